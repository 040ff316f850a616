/*
 * `edgewise shots --views best` (issue 33, item 1), on maps made here from
 * the built-in level with their entity lump replaced (no shared data):
 *   - ten player starts out in the void fill the view set's 32 views and
 *     the lit info_intermission comes after them: best finds it in the
 *     entity lump and its picture is lit;
 *   - the intermission camera is in the void (dark) and a player start is
 *     lit: best takes the player start, never the black intermission;
 *   - every camera in the void: a picture is still written (marked dark).
 */
#define _POSIX_C_SOURCE 200809L
#include "util.h"
#include "edgewise_lab.h"
#include "mapgen.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char tmpdir[256];
static ew_t_run *run_r;
static uint8_t *base_bsp;
static size_t base_size;

/* The built-in map with its entity lump replaced by text: the new lump
 * appended at the end (4-byte aligned), lump 0's offset and length set. */
static void write_map(const char *name, const char *text) {
    size_t len = strlen(text) + 1, at = (base_size + 3) & ~(size_t)3;
    uint8_t *b = calloc(1, at + len);
    if (!b) return;
    memcpy(b, base_bsp, base_size);
    memcpy(b + at, text, len);
    ew_t_put_le32(b + 4, (uint32_t)at), ew_t_put_le32(b + 8, (uint32_t)len);
    char path[400];
    snprintf(path, sizeof path, "%s/g/maps/%s.bsp", tmpdir, name);
    CHECK(ew_t_write_file(path, b, at + len) == 0, "write %s", path);
    free(b);
}

/* The base map's entity text (NUL-terminated copy), split after its worldspawn. */
static char *base_entities(size_t *world_end) {
    uint32_t ofs = ew_t_le32(base_bsp + 4), len = ew_t_le32(base_bsp + 8);
    char *t = malloc(len + 1);
    if (!t) return NULL;
    memcpy(t, base_bsp + ofs, len);
    t[len] = '\0';
    char *close = strstr(t, "}\n");
    *world_end = close ? (size_t)(close + 2 - t) : 0;
    return t;
}

/* Mean luma of a PNG (0..255), -1 if unreadable. */
static double png_luma(const char *path) {
    uint8_t *rgb = NULL;
    int w = 0, h = 0;
    ew_error err;
    if (ew_read_png_rgb(path, &rgb, &w, &h, &err) < 0) return -1;
    double sum = 0;
    for (long i = 0; i < (long)w * h; i++)
        sum += 0.299 * rgb[3 * i] + 0.587 * rgb[3 * i + 1] + 0.114 * rgb[3 * i + 2];
    free(rgb);
    return w > 0 && h > 0 ? sum / ((double)w * h) : -1;
}

static void slurp(const char *path, char *buf, size_t size) { ew_t_slurp(path, buf, size); }

/* shots MAP --views best; the manifest line in man, the picture's luma returned. */
static double shoot(const char *name, char *man, size_t size) {
    char map[400], out[400], png[500], mf[500];
    snprintf(map, sizeof map, "%s/g/maps/%s.bsp", tmpdir, name);
    snprintf(out, sizeof out, "%s/out_%s", tmpdir, name);
    const char *const args[] = {"shots", map, "--out", out, "--size", "320x200", "--force", NULL};
    ew_t_run_cli(run_r, tmpdir, args);
    CHECK(run_r->status == 0, "%s: exit %d: %s", name, run_r->status, run_r->err);
    snprintf(mf, sizeof mf, "%s/manifest.jsonl", out);
    slurp(mf, man, size);
    snprintf(png, sizeof png, "%s/%s_best.png", out, name);
    double l = png_luma(png);
    printf("%s: best picture luma %.1f; manifest %.300s\n", name, l, man);
    return l;
}

int main(void) {
    if (!getenv("EW_CLI")) {
        fprintf(stderr, "EW_CLI not set\n");
        return 1;
    }
    snprintf(tmpdir, sizeof tmpdir, "/tmp/ew_best_XXXXXX");
    run_r = malloc(sizeof *run_r);
    if (!run_r || !mkdtemp(tmpdir)) {
        fprintf(stderr, "cannot make a scratch folder\n");
        return 1;
    }
    uint8_t pal[768], cmap[EW_COLORMAP_SIZE];
    ew_error err = {""};
    CHECK(ew_builtin_generate(&base_bsp, &base_size, pal, cmap, &err) == 0, "generate: %s", err.msg);
    char p[400];
    snprintf(p, sizeof p, "%s/g", tmpdir);
    mkdir(p, 0777);
    snprintf(p, sizeof p, "%s/g/maps", tmpdir);
    mkdir(p, 0777);
    snprintf(p, sizeof p, "%s/g/gfx", tmpdir);
    mkdir(p, 0777);
    snprintf(p, sizeof p, "%s/g/gfx/palette.lmp", tmpdir);
    CHECK(ew_t_write_file(p, pal, sizeof pal) == 0, "palette");
    snprintf(p, sizeof p, "%s/g/gfx/colormap.lmp", tmpdir);
    CHECK(ew_t_write_file(p, cmap, sizeof cmap) == 0, "colormap");

    size_t wend = 0;
    char *ents = base_entities(&wend);
    CHECK(ents && wend > 0 && strstr(ents, "info_intermission") && strstr(ents, "info_player_start"),
          "the built-in map's entities: %s", ents ? ents : "(none)");
    if (ents && wend > 0) {
        const char *rest = ents + wend;
        /* Ten player starts out in the void, facing away from the map. */
        char voids[4096];
        size_t n = 0;
        for (int i = 0; i < 10; i++)
            n += (size_t)snprintf(voids + n, sizeof voids - n,
                                  "{\n\"classname\" \"info_player_deathmatch\"\n\"origin\" \"%d 20000 20000\"\n"
                                  "\"angle\" \"45\"\n}\n", 20000 + 64 * i);
        size_t cap = strlen(ents) + sizeof voids + 512;
        char *text = malloc(cap);
        char man[8192];

        /* 1: the lit intermission after 40 void views. */
        snprintf(text, cap, "%.*s%s%s", (int)wend, ents, voids, rest);
        write_map("late", text);
        double l = shoot("late", man, sizeof man);
        CHECK(l >= 8, "late: the best picture is nearly black (luma %.1f): the intermission camera after the "
                      "view set's 32 views was not found", l);
        CHECK(strstr(man, "\"dark\":false") && strstr(man, "\"best_from\":\"intermission\""),
              "late: manifest: %s", man);

        /* 2: the intermission in the void, the player starts lit: a player start. */
        char *renamed = malloc(strlen(rest) + 64);
        snprintf(renamed, strlen(rest) + 64, "%s", rest);
        char *at = strstr(renamed, "info_intermission");
        if (at) memcpy(at, "info_notnull_zzzz", 17);  /* the same length: no longer a camera */
        snprintf(text, cap, "%.*s{\n\"classname\" \"info_intermission\"\n\"origin\" \"20000 20000 20000\"\n"
                 "\"mangle\" \"0 45 0\"\n}\n%s", (int)wend, ents, renamed);
        write_map("darkinter", text);
        l = shoot("darkinter", man, sizeof man);
        CHECK(l >= 8, "darkinter: the best picture is nearly black (luma %.1f) though a player start is lit", l);
        CHECK(strstr(man, "\"dark\":false") && strstr(man, "\"best_from\":\"player_start\""),
              "darkinter: manifest: %s", man);

        /* 3: every camera in the void: still one picture, marked dark. */
        snprintf(text, cap, "%.*s%s", (int)wend, ents, voids);
        write_map("allvoid", text);
        l = shoot("allvoid", man, sizeof man);
        CHECK(l >= 0 && l < 8 && strstr(man, "\"status\":\"ok\"") && strstr(man, "\"dark\":true"),
              "allvoid: want a dark picture written, luma %.1f, manifest %s", l, man);
        free(renamed);
        free(text);
    }
    free(ents);
    free(base_bsp);
    free(run_r);
    char cmd[400];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmpdir);
    return ew_t_finish();
}
