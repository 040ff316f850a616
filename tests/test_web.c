/*
 * test_web.c - the web page (app/web/, docs/web.md) in a real browser:
 * Debian's chromium, headless, driven by tests/web/drive.mjs (puppeteer-core
 * from npm, pointed at the system chromium).
 *
 *   - the page's canvas equals `edgewise render` of the same camera at the
 *     same size byte for byte: the built-in scene and the shared map lqdm7,
 *     8-bit and true colour, one thread (a page that is not cross-origin
 *     isolated) and threaded (isolated: Web Workers), the map from the
 *     page's URL (?map=, gfx/ beside maps/) and from files given to the page
 *     (a map with its .lit, palette, colormap and models), a view of the
 *     view set and a --pos/--angles camera; start's view with its sky
 *     (the sky drawers), fog given in the URL (fog=, as --fog), and
 *     ericw-tools' BSP2 start with BSPX coloured light;
 *   - keyboard and mouse events move the camera; a corrupt file gives a
 *     message on the page and the page keeps working; ?bench=1 prints
 *     bench's JSON (drive.mjs checks these).
 *
 * Needs the built page (make web: build-web/web, EW_WEB_DIR), node, chromium
 * and tests/web/node_modules (npm ci); without one of them it is skipped
 * (77), as CI does not allow (.ci/run installs them all).
 */
#define _POSIX_C_SOURCE 200809L
#include "edgewise_lab.h"
#include "util.h"

#include <glob.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

static char tmp[256];

static int exists(const char *p) {
    struct stat st;
    return stat(p, &st) == 0;
}

/* A pak file at path holding the files srcs (absolute) under the names
 * names: "PACK", the directory's offset and length, the data, then one
 * 64-byte entry (56-byte name, offset, size) a file.  0 or -1. */
static int write_pak(const char *path, const char *const *names, const char *const *srcs, int n) {
    FILE *f = fopen(path, "wb");
    if (!f) return -1;
    uint8_t *dir = calloc((size_t)n, 64), head[12] = "PACK";
    uint32_t at = 12;
    int rc = dir ? 0 : -1;
    if (fwrite(head, 1, 12, f) != 12) rc = -1;
    for (int i = 0; i < n && rc == 0; i++) {
        uint8_t *d = NULL;
        size_t size = 0;
        ew_error err;
        if (ew_read_file(srcs[i], &d, &size, &err) != 0 || fwrite(d, 1, size, f) != size) rc = -1;
        snprintf((char *)dir + 64 * i, 56, "%s", names[i]);
        ew_t_put_le32(dir + 64 * i + 56, at);
        ew_t_put_le32(dir + 64 * i + 60, (uint32_t)size);
        at += (uint32_t)size;
        free(d);
    }
    if (rc == 0 && fwrite(dir, 64, (size_t)n, f) != (size_t)n) rc = -1;
    ew_t_put_le32(head + 4, at);
    ew_t_put_le32(head + 8, (uint32_t)(64 * n));
    if (rc == 0 && (fseek(f, 0, SEEK_SET) != 0 || fwrite(head, 1, 12, f) != 12)) rc = -1;
    if (fclose(f) != 0) rc = -1;
    free(dir);
    return rc;
}

typedef struct web_case {
    const char *name;
    int         isolated;
    const char *query;
    int         files;     /* 1: lqdm7's files given to the page's file input; 2: the pak and a loose e1m1.bsp */
    int         w, h;
    const char *native[16];  /* the edgewise render arguments after "render" (out and size added) */
    int         compare;
} web_case;

static int compare_case(const web_case *c) {
    char png[512], rgba[512];
    snprintf(png, sizeof png, "%s/%s_native.png", tmp, c->name);
    snprintf(rgba, sizeof rgba, "%s/%s.rgba", tmp, c->name);
    uint8_t *rgb = NULL, *web = NULL;
    size_t wsize = 0;
    int w = 0, h = 0;
    ew_error err = { "" };
    if (ew_read_png_rgb(png, &rgb, &w, &h, &err) != 0) {
        CHECK(0, "%s: %s", c->name, err.msg);
        return -1;
    }
    if (ew_read_file(rgba, &web, &wsize, &err) != 0) {
        CHECK(0, "%s: the page's frame: %s", c->name, err.msg);
        free(rgb);
        return -1;
    }
    CHECK(w == c->w && h == c->h, "%s: native frame %dx%d, asked %dx%d", c->name, w, h, c->w, c->h);
    CHECK(wsize == (size_t)w * h * 4, "%s: the canvas has %zu bytes, %dx%d RGBA is %zu", c->name, wsize, w, h,
          (size_t)w * h * 4);
    if (wsize == (size_t)w * h * 4) {
        long diff = 0, first = -1, alpha = 0;
        for (long i = 0; i < (long)w * h; i++) {
            if (web[4 * i + 3] != 255) alpha++;
            if (memcmp(web + 4 * i, rgb + 3 * i, 3) != 0) {
                if (first < 0) first = i;
                diff++;
            }
        }
        CHECK(diff == 0, "%s: %ld of %d pixels differ from edgewise render's; the first at x %ld y %ld: page "
              "%d,%d,%d, native %d,%d,%d", c->name, diff, w * h, first % w, first / w,
              first >= 0 ? web[4 * first] : 0, first >= 0 ? web[4 * first + 1] : 0,
              first >= 0 ? web[4 * first + 2] : 0, first >= 0 ? rgb[3 * first] : 0,
              first >= 0 ? rgb[3 * first + 1] : 0, first >= 0 ? rgb[3 * first + 2] : 0);
        CHECK(alpha == 0, "%s: %ld canvas pixels not opaque", c->name, alpha);
        /* a picture, not a blank frame that any two renderers agree on */
        long lit = 0, changes = 0;
        for (long i = 0; i < (long)w * h; i++) {
            lit += rgb[3 * i] + rgb[3 * i + 1] + rgb[3 * i + 2] > 60;
            changes += i > 0 && memcmp(rgb + 3 * i, rgb + 3 * (i - 1), 3) != 0;
        }
        CHECK(lit > (long)w * h / 10 && changes > (long)w * h / 16, "%s: the frame is nearly blank (%ld of %d "
              "pixels lit, %ld changes)", c->name, lit, w * h, changes);
        if (diff == 0) printf("%s: %dx%d, byte-identical to edgewise render\n", c->name, w, h);
    }
    free(rgb);
    free(web);
    return 0;
}

int main(void) {
    const char *webdir = getenv("EW_WEB_DIR"), *src = getenv("EW_SOURCE");
    char node[1024], chromium[1024], nm[1200], wasm[1200], drive[1200];
    if (!ew_t_need_shared("data/librequake/maps/lqdm7.bsp")) return ew_t_finish();
    if (!ew_t_need_shared("data/ericw/maps/start_bsp2_bspxlit.bsp")) return ew_t_finish();
    if (!src) {
        ew_t_skip("EW_SOURCE not set (run through ctest)");
        return ew_t_finish();
    }
    snprintf(wasm, sizeof wasm, "%s/edgewise.wasm", webdir ? webdir : "");
    snprintf(nm, sizeof nm, "%s/tests/web/node_modules/puppeteer-core/package.json", src);
    snprintf(drive, sizeof drive, "%s/tests/web/drive.mjs", src);
    const char *chrome_env = getenv("EW_CHROMIUM");
    if (!webdir || !exists(wasm) || !exists(webdir)) {
        ew_t_skip("the web page is not built (%s missing: make web, which needs emscripten)", wasm);
        return ew_t_finish();
    }
    if (!ew_t_find_exe("node", node, sizeof node)) {
        ew_t_skip("node not found (apt-get install nodejs)");
        return ew_t_finish();
    }
    if (!ew_t_find_exe(chrome_env && *chrome_env ? chrome_env : "chromium", chromium, sizeof chromium)) {
        ew_t_skip("chromium not found (apt-get install chromium)");
        return ew_t_finish();
    }
    if (!exists(nm)) {
        ew_t_skip("%s missing (cd tests/web && npm ci)", nm);
        return ew_t_finish();
    }
    snprintf(tmp, sizeof tmp, "/tmp/ew_web_XXXXXX");
    if (!mkdtemp(tmp)) {
        CHECK(0, "mkdtemp failed");
        return ew_t_finish();
    }

    /* A map archive's folder: maps/lqdm7.bsp, its .lit, gfx/ beside maps/. */
    char site[300], buf[1300];
    snprintf(site, sizeof site, "%s/site", tmp);
    static const char *const links[][2] = { { "maps/lqdm7.bsp", "maps/lqdm7.bsp" },
                                            { "maps/lqdm7.lit", "maps/lqdm7.lit" },
                                            { "gfx/palette.lmp", "gfx/palette.lmp" },
                                            { "gfx/colormap.lmp", "gfx/colormap.lmp" },
                                            { "maps/start.bsp", "maps/start.bsp" },
                                            { "maps/start.lit", "maps/start.lit" } };
    mkdir(site, 0755);
    snprintf(buf, sizeof buf, "%s/maps", site);
    mkdir(buf, 0755);
    snprintf(buf, sizeof buf, "%s/gfx", site);
    mkdir(buf, 0755);
    /* its models too: progs/ and the item boxes maps/b_*.bsp, which the page fetches as it needs them */
    {
        char from[1200], to[700];
        snprintf(from, sizeof from, "%s/progs", ew_t_shared_abs("data/librequake"));
        snprintf(to, sizeof to, "%s/progs", site);
        CHECK(symlink(from, to) == 0, "symlink %s", to);
        snprintf(from, sizeof from, "%s/maps/b_*.bsp", ew_t_shared_abs("data/librequake"));
        glob_t g;
        if (glob(from, 0, NULL, &g) == 0) {
            for (size_t i = 0; i < g.gl_pathc; i++) {
                const char *base = strrchr(g.gl_pathv[i], '/');
                snprintf(to, sizeof to, "%s/maps%s", site, base);
                CHECK(symlink(g.gl_pathv[i], to) == 0, "symlink %s", to);
            }
            globfree(&g);
        }
    }
    for (size_t i = 0; i < sizeof links / sizeof *links; i++) {
        char from[2400], to[700];
        snprintf(from, sizeof from, "%s", ew_t_shared_abs("data/librequake"));
        strncat(from, "/", sizeof from - strlen(from) - 1);
        strncat(from, links[i][0], sizeof from - strlen(from) - 1);
        snprintf(to, sizeof to, "%s/%s", site, links[i][1]);
        CHECK(symlink(from, to) == 0, "symlink %s", to);
    }
    /* A map from ericw-tools (BSP2, BSPX RGBLIGHTING) on the same site: its
     * gfx/ is LibreQuake's, the site's. */
    {
        static const char *const ericw[] = { "start_bsp2_bspxlit.bsp", "start_bsp2_bspxlit.lit" };
        for (size_t i = 0; i < sizeof ericw / sizeof *ericw; i++) {
            char from[1200], to[700];
            snprintf(from, sizeof from, "%s/maps/%s", ew_t_shared_abs("data/ericw"), ericw[i]);
            snprintf(to, sizeof to, "%s/maps/%s", site, ericw[i]);
            CHECK(symlink(from, to) == 0, "symlink %s", to);
        }
    }
    char sitemap[400], lq[1100], startmap[400], ericwmap[400];
    snprintf(startmap, sizeof startmap, "%s/maps/start.bsp", site);
    snprintf(ericwmap, sizeof ericwmap, "%s/maps/start_bsp2_bspxlit.bsp", site);
    snprintf(sitemap, sizeof sitemap, "%s/maps/lqdm7.bsp", site);
    snprintf(lq, sizeof lq, "%s", ew_t_shared_abs("data/librequake"));

    /* A game directory with a pak (lqdm7, its .lit, gfx, every model) and a
     * loose map beside it (maps/e1m1.bsp); the pak also on the site. */
    char pakgame[300], pak[400], sitepak[400], e1m1[400];
    snprintf(pakgame, sizeof pakgame, "%s/pakgame", tmp);
    snprintf(pak, sizeof pak, "%s/pak0.pak", pakgame);
    snprintf(sitepak, sizeof sitepak, "%s/pak0.pak", site);
    snprintf(e1m1, sizeof e1m1, "%s/maps/e1m1.bsp", pakgame);
    {
        static char names[256][64], srcs[256][1200];
        const char *np[256], *sp[256];
        int n = 0;
        const char *fixed[] = { "maps/lqdm7.bsp", "maps/lqdm7.lit", "gfx/palette.lmp", "gfx/colormap.lmp" };
        for (int i = 0; i < 4; i++, n++) {
            snprintf(names[n], 64, "%s", fixed[i]);
            snprintf(srcs[n], sizeof srcs[n], "%s/%s", lq, fixed[i]);
        }
        char pattern[1200];
        for (int k = 0; k < 2; k++) {
            snprintf(pattern, sizeof pattern, k ? "%s/maps/b_*.bsp" : "%s/progs/*.mdl", lq);
            glob_t g;
            if (glob(pattern, 0, NULL, &g) != 0) continue;
            for (size_t i = 0; i < g.gl_pathc && n < 256; i++, n++) {
                snprintf(srcs[n], sizeof srcs[n], "%s", g.gl_pathv[i]);
                snprintf(names[n], 64, "%s/%s", k ? "maps" : "progs", strrchr(g.gl_pathv[i], '/') + 1);
            }
            globfree(&g);
        }
        for (int i = 0; i < n; i++) np[i] = names[i], sp[i] = srcs[i];
        mkdir(pakgame, 0755);
        snprintf(buf, sizeof buf, "%s/maps", pakgame);
        mkdir(buf, 0755);
        char from[1200];
        snprintf(from, sizeof from, "%s/maps/e1m1.bsp", lq);
        CHECK(write_pak(pak, np, sp, n) == 0, "cannot write %s", pak);
        CHECK(symlink(from, e1m1) == 0 && symlink(pak, sitepak) == 0, "symlinks for the pak");
    }

    /* in lqdm7's first room, a camera of its own (render --pos/--angles), a health box in view */
    const web_case cases[] = {
        { "builtin_8bit_1thread", 0, "view=0&time=0", 0, 640, 480,
          { "builtin", "--view", "0", "--time", "0", "--threads", "1", NULL }, 1 },
        { "lqdm7_true_threads", 1, "map=site/maps/lqdm7.bsp&view=0&time=0&color=true", 0, 640, 480,
          { sitemap, "--view", "0", "--time", "0", "--color", "true", "--threads", "0", NULL }, 1 },
        { "lqdm7_8bit_1thread_pos", 0, "map=site/maps/lqdm7.bsp&pos=60,0,-10&angles=8,40,0&time=0", 0, 800, 600,
          { sitemap, "--pos", "60,0,-10", "--angles", "8,40,0", "--time", "0", "--threads", "1", NULL }, 1 },
        { "lqdm7_files_8bit_threads", 1, "overlay=0&time=0&threads=2", 1, 640, 480,
          { "lqdm7", "--data", lq, "--view", "0", "--time", "0", "--threads", "2", NULL }, 1 },
        { "lqdm7_files_true_1thread", 0, "overlay=0&time=0&color=true", 1, 1024, 640,
          { "lqdm7", "--data", lq, "--view", "3", "--time", "0", "--color", "true", "--threads", "1", NULL }, 0 },
        { "pak_lqdm7_true_threads", 1, "map=site/pak0.pak&view=1&time=0&color=true", 0, 640, 480,
          { "lqdm7", "--data", pakgame, "--view", "1", "--time", "0", "--color", "true", "--threads", "0", NULL }, 1 },
        { "pak_and_loose_e1m1_1thread", 0, "overlay=0&time=0", 2, 640, 480,
          { "e1m1", "--data", pakgame, "--view", "0", "--time", "0", "--threads", "1", NULL }, 1 },
        { "lqdm7_classic_threads", 1, "map=site/maps/lqdm7.bsp&view=0&time=0&classic=1", 0, 640, 480,
          { sitemap, "--view", "0", "--time", "0", "--classic", "--threads", "0", NULL }, 1 },
        /* start's view 11: its floor is sky (the sky drawers), monsters over it */
        { "start_sky_true_threads", 1, "map=site/maps/start.bsp&view=11&time=1.5&color=true", 0, 640, 480,
          { startmap, "--view", "11", "--time", "1.5", "--color", "true", "--threads", "0", NULL }, 1 },
        { "start_sky_8bit_1thread", 0, "map=site/maps/start.bsp&view=11&time=1.5", 0, 800, 600,
          { startmap, "--view", "11", "--time", "1.5", "--threads", "1", NULL }, 1 },
        /* fog from the URL, as render's --fog (the fog drawers) */
        { "lqdm7_fog_true_threads", 1, "map=site/maps/lqdm7.bsp&view=0&time=0&color=true&fog=0.08,0.45,0.42,0.38", 0,
          640, 480,
          { sitemap, "--view", "0", "--time", "0", "--color", "true", "--fog", "0.08,0.45,0.42,0.38", "--threads", "0",
            NULL }, 1 },
        { "lqdm7_fog_8bit_1thread", 0, "map=site/maps/lqdm7.bsp&view=0&time=0&fog=0.08,0.45,0.42,0.38", 0, 640, 480,
          { sitemap, "--view", "0", "--time", "0", "--fog", "0.08,0.45,0.42,0.38", "--threads", "1", NULL }, 1 },
        /* ericw-tools' BSP2 with BSPX coloured light: the blue cube (ericw/README.md) */
        { "ericw_bsp2_bspxlit_true", 1, "map=site/maps/start_bsp2_bspxlit.bsp&pos=-48,-600,80&angles=30,270,0&time=0&color=true",
          0, 640, 480,
          { ericwmap, "--pos", "-48,-600,80", "--angles", "30,270,0", "--time", "0", "--color", "true", "--threads", "0",
            NULL }, 1 },
    };
    const int ncases = (int)(sizeof cases / sizeof *cases);

    /* the native frames */
    for (int i = 0; i < ncases; i++) {
        const web_case *c = &cases[i];
        if (!c->compare) continue;
        const char *args[24];
        char out[512], size[32];
        int n = 0;
        args[n++] = "render";
        for (int k = 0; c->native[k]; k++) args[n++] = c->native[k];
        snprintf(out, sizeof out, "%s/%s_native.png", tmp, c->name);
        snprintf(size, sizeof size, "%dx%d", c->w, c->h);
        args[n++] = "--size", args[n++] = size, args[n++] = "--out", args[n++] = out, args[n++] = "--quiet";
        args[n] = NULL;
        ew_t_run r;
        ew_t_run_cli(&r, tmp, args);
        CHECK(r.status == 0, "%s: edgewise render: %s", c->name, r.err);
    }

    /* the spec for drive.mjs: the files the page is given for lqdm7 */
    char spec[600];
    snprintf(spec, sizeof spec, "%s/spec.json", tmp);
    FILE *f = fopen(spec, "w");
    if (!f) {
        CHECK(0, "cannot write %s", spec);
        return ew_t_finish();
    }
    fprintf(f, "{\"web\":\"%s\",\"site\":\"%s\",\"chromium\":\"%s\",\"out\":\"%s\",\"checks\":true,"
            "\"lonemap\":\"%s\",\"cases\":[", webdir, site, chromium, tmp, e1m1);
    for (int i = 0; i < ncases; i++) {
        const web_case *c = &cases[i];
        fprintf(f, "%s{\"name\":\"%s\",\"isolated\":%s,\"query\":\"%s\",\"width\":%d,\"height\":%d", i ? "," : "",
                c->name, c->isolated ? "true" : "false", c->query, c->w, c->h);
        if (c->files == 2) fprintf(f, ",\"files\":[\"%s\",\"%s\"]", pak, e1m1);
        if (c->files == 1) {
            fprintf(f, ",\"files\":[\"%s/maps/lqdm7.bsp\",\"%s/maps/lqdm7.lit\",\"%s/gfx/palette.lmp\","
                    "\"%s/gfx/colormap.lmp\"", lq, lq, lq, lq);
            /* the models its entities use: every .mdl of progs/ and the item boxes maps/b_NAME.bsp */
            char cmd[2400];
            snprintf(cmd, sizeof cmd, "ls %s/progs/*.mdl %s/maps/b_*.bsp 2>/dev/null", lq, lq);
            FILE *ls = popen(cmd, "r");
            char line[1200];
            while (ls && fgets(line, sizeof line, ls)) {
                line[strcspn(line, "\n")] = '\0';
                fprintf(f, ",\"%s\"", line);
            }
            if (ls) pclose(ls);
            fputc(']', f);
        }
        if (!c->compare) fputs(",\"screenshot\":true", f);
        fputc('}', f);
    }
    fputs("]}\n", f);
    fclose(f);

    char cmd[4096], log[700];
    snprintf(log, sizeof log, "%s/drive.log", tmp);
    snprintf(cmd, sizeof cmd, "'%s' '%s' '%s' > '%s' 2>&1", node, drive, spec, log);
    int rc = system(cmd);
    static char out[65536];
    ew_t_slurp(log, out, sizeof out);
    fputs(out, stdout);
    CHECK(rc == 0 && WIFEXITED(rc) && WEXITSTATUS(rc) == 0, "drive.mjs failed (exit %d): see its lines above",
          WIFEXITED(rc) ? WEXITSTATUS(rc) : -1);
    CHECK(strstr(out, "FAIL") == NULL, "drive.mjs reported a failure");

    for (int i = 0; i < ncases; i++) {
        const web_case *c = &cases[i];
        char json[600], text[4096];
        snprintf(json, sizeof json, "%s/%s.json", tmp, c->name);
        ew_t_slurp(json, text, sizeof text);
        CHECK(text[0] == '{', "%s: no state from the page", c->name);
        /* isolated: threads on Web Workers, all cores; not: one thread */
        double threads = ew_t_json_num(text, "threads"), isolated = ew_t_json_num(text, "isolated");
        CHECK(isolated == c->isolated, "%s: crossOriginIsolated %g, expected %d", c->name, isolated, c->isolated);
        if (!c->isolated) CHECK(threads == 1, "%s: %g threads on a page that is not isolated", c->name, threads);
        else CHECK(threads >= 1, "%s: %g threads", c->name, threads);
        if (c->compare) compare_case(c);
    }
    if (ew_t_failed == 0) {
        snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmp);
        if (system(cmd) != 0) { /* left behind */ }
    } else {
        printf("files kept in %s\n", tmp);
    }
    return ew_t_finish();
}
