/*
 * What the command reports is true (issue 33, item 6), on maps made here
 * from the built-in level (no shared data):
 *   - "lit" in the JSON of render --stats and soak is true only when the
 *     map's coloured light is drawn: a .lit beside it or a BSPX RGBLIGHTING
 *     lump, and neither --no-lit nor --classic; false for a map with neither;
 *   - a picture's name must end in .png (any case): render/demo --out,
 *     render builtin:polyhedra --out, shots --contact-sheet refuse x.jpg in
 *     one line (exit 2) and write nothing; X.PNG is taken;
 *   - options that would do nothing are refused as --classic --color true
 *     is, in every command that takes drawing options: --color true with
 *     --dither, --classic with --dither, --no-lit with --dither (either
 *     order);
 *   - --debug builds: help says a single render builds every surface (and
 *     one render is indeed all magenta), the rebuilds show between frames;
 *   - views prints yaws from 0 to under 360.
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
#define IN_TMP(rel) ew_t_in_dir(tmpdir, rel)
static ew_t_run *run_r;

static ew_t_run *run(const char *const *args) {
    ew_t_run_cli(run_r, tmpdir, args);
    return run_r;
}
#define ARGS(...) ((const char *const[]){__VA_ARGS__, NULL})

/* A map of the built-in level: plain, with a .lit beside it, or with BSPX RGBLIGHTING. */
static void make_maps(void) {
    mkdir(IN_TMP("g"), 0777);
    mkdir(IN_TMP("g/maps"), 0777);
    mkdir(IN_TMP("g/gfx"), 0777);
    uint8_t pal[768], cmap[EW_COLORMAP_SIZE];
    const char *names[] = {"plain", "withlit", "rgbx"};
    for (int k = 0; k < 3; k++) {
        ew_mapgen_options o;
        memset(&o, 0, sizeof o);
        o.lit = k == 1, o.rgblighting = k == 2;
        uint8_t *bsp = NULL, *lit = NULL;
        size_t n = 0, nl = 0;
        ew_error err = {""};
        CHECK(ew_builtin_generate_ex(&o, &bsp, &n, pal, cmap, &lit, &nl, &err) == 0, "generate: %s", err.msg);
        char rel[64];
        snprintf(rel, sizeof rel, "g/maps/%s.bsp", names[k]);
        CHECK(bsp && ew_t_write_file(IN_TMP(rel), bsp, n) == 0, "write %s", rel);
        if (lit) {
            snprintf(rel, sizeof rel, "g/maps/%s.lit", names[k]);
            CHECK(ew_t_write_file(IN_TMP(rel), lit, nl) == 0, "write %s", rel);
        }
        free(bsp), free(lit);
    }
    CHECK(ew_t_write_file(IN_TMP("g/gfx/palette.lmp"), pal, sizeof pal) == 0, "palette");
    CHECK(ew_t_write_file(IN_TMP("g/gfx/colormap.lmp"), cmap, sizeof cmap) == 0, "colormap");
}

static void lit_field(void) {
    static const struct {
        const char *map, *opt;
        int lit;
    } cases[] = {
        {"plain", NULL, 0}, {"withlit", NULL, 1}, {"rgbx", NULL, 1}, {"withlit", "--no-lit", 0},
        {"rgbx", "--classic", 0}, {"plain", "--color", 0},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        char map[300];
        snprintf(map, sizeof map, "g/maps/%s.bsp", cases[i].map);
        const char *opt = cases[i].opt;
        ew_t_run *r = !opt ? run(ARGS("render", map, "--size", "320x200", "--stats", "--out", "l.png"))
                      : !strcmp(opt, "--color")
                          ? run(ARGS("render", map, "--size", "320x200", "--stats", "--out", "l.png", "--color", "true"))
                          : run(ARGS("render", map, "--size", "320x200", "--stats", "--out", "l.png", opt));
        double lit = ew_t_json_num(r->out, "lit");
        CHECK(r->status == 0 && lit == cases[i].lit, "render %s %s --stats: \"lit\" %g, want %d (exit %d: %s)",
              cases[i].map, opt ? opt : "", lit, cases[i].lit, r->status, r->err);
    }
    ew_t_run *r = run(ARGS("soak", "g/maps/plain.bsp", "--frames", "2"));
    CHECK(r->status == 0 && ew_t_json_num(r->out, "lit") == 0, "soak plain: \"lit\" %g: %.300s",
          ew_t_json_num(r->out, "lit"), r->out);
    r = run(ARGS("soak", "g/maps/withlit.bsp", "--frames", "2"));
    CHECK(r->status == 0 && ew_t_json_num(r->out, "lit") == 1, "soak withlit: \"lit\" %g",
          ew_t_json_num(r->out, "lit"));
}

/* Exit 2, one line on stderr saying needle, nothing on stdout. */
static void refused(const char *what, ew_t_run *r, const char *needle) {
    CHECK(r->status == 2 && ew_t_count_lines(r->err) == 1 && strstr(r->err, needle) && !r->out[0],
          "%s: want exit 2 and one line with '%s', got %d: %s", what, needle, r->status, r->err);
}

static void png_names(void) {
    refused("render --out x.jpg", run(ARGS("render", "g/maps/plain.bsp", "--out", "x.jpg")), "must end in .png");
    CHECK(access(IN_TMP("x.jpg"), F_OK) != 0, "render --out x.jpg wrote x.jpg");
    refused("demo --out a.JPG", run(ARGS("demo", "--out", "a.JPG")), "--out a.JPG: edgewise writes PNG");
    refused("demo --out png", run(ARGS("demo", "--out", "png")), "must end in .png");
    refused("polyhedra --out p.gif", run(ARGS("render", "builtin:polyhedra", "--out", "p.gif")), "must end in .png");
    refused("shots --contact-sheet s.jpg",
            run(ARGS("shots", "g/maps/plain.bsp", "--out", "sh", "--contact-sheet", "s.jpg")), "must end in .png");
    ew_t_run *r = run(ARGS("render", "g/maps/plain.bsp", "--size", "320x200", "--out", "Upper.PNG"));
    CHECK(r->status == 0 && access(IN_TMP("Upper.PNG"), F_OK) == 0, "render --out Upper.PNG: %d %s", r->status,
          r->err);
}

static void do_nothing_options(void) {
    const char *pairs[][3] = {
        {"--color", "true", "--dither"}, {"--dither", "--color", "true"}, {"--classic", "--dither", NULL},
        {"--dither", "--classic", NULL}, {"--no-lit", "--dither", NULL}, {"--dither", "--no-lit", NULL},
    };
    const char *cmds[][8] = {
        {"render", "g/maps/plain.bsp", "--size", "320x200", "--out", "o.png", NULL},
        {"demo", "--size", "320x200", "--out", "o.png", NULL},
        {"bench", "g/maps/plain.bsp", "--size", "320x200", "--passes", "1", NULL},
        {"soak", "g/maps/plain.bsp", "--frames", "2", NULL},
        {"shots", "g/maps/plain.bsp", "--out", "dn", "--size", "320x200", NULL},
        {"fly", "g/maps/plain.bsp", "--seconds", "0.5", "--size", "320x200", "--out", "f.y4m"},
        {"hsr", "g/maps/plain.bsp", "--size", "320x200", "--repeat", "1", NULL},
        {"view", "g/maps/plain.bsp", NULL},
    };
    for (size_t c = 0; c < sizeof cmds / sizeof *cmds; c++)
        for (size_t p = 0; p < sizeof pairs / sizeof *pairs; p++) {
            const char *args[16];
            int n = 0;
            for (int k = 0; k < 8 && cmds[c][k]; k++) args[n++] = cmds[c][k];
            for (int k = 0; k < 3 && pairs[p][k]; k++) args[n++] = pairs[p][k];
            args[n] = NULL;
            char what[200];
            snprintf(what, sizeof what, "%s %s %s %s", cmds[c][0], pairs[p][0], pairs[p][1],
                     pairs[p][2] ? pairs[p][2] : "");
            ew_t_run *r = run(args);
            if (!strcmp(cmds[c][0], "view") && strstr(r->err, "without SDL2")) {
                ew_t_skip("edgewise view was built without SDL2: %s not checked", what);
                continue;
            }
            refused(what, r, "--dither");
        }
    /* Each alone is taken. */
    ew_t_run *r = run(ARGS("render", "g/maps/withlit.bsp", "--size", "320x200", "--out", "o.png", "--dither"));
    CHECK(r->status == 0, "render --dither: %d %s", r->status, r->err);
}

static void debug_builds(void) {
    ew_t_run *r = run(ARGS("render", "--help"));
    CHECK(r->status == 0 && strstr(r->out, "builds (surfaces the frame built, magenta: a single render builds every "
                                           "one, so all is magenta; view and fly show the rebuilds between frames)"),
          "render --help does not say what builds shows in one render");
    r = run(ARGS("render", "g/maps/plain.bsp", "--size", "320x200", "--color", "true", "--debug", "builds", "--out",
                 "b.png"));
    uint8_t *rgb = NULL;
    int w = 0, h = 0;
    ew_error err;
    long magenta = 0;
    if (r->status == 0 && ew_read_png_rgb(IN_TMP("b.png"), &rgb, &w, &h, &err) == 0) {
        for (long i = 0; i < (long)w * h; i++)
            magenta += rgb[3 * i] > 200 && rgb[3 * i + 1] < 60 && rgb[3 * i + 2] > 200;
        free(rgb);
    }
    printf("--debug builds, one render: %.1f%% of the pixels magenta\n", w * h > 0 ? 100.0 * magenta / (w * h) : 0);
    CHECK(w * h > 0 && magenta * 2 > (long)w * h, "one render of --debug builds: %ld of %d pixels magenta", magenta,
          w * h);
}

static void view_yaws(void) {
    ew_t_run *r = run(ARGS("views", "g/maps/plain.bsp"));
    int lines = 0, bad = 0;
    for (const char *p = r->out; *p;) {
        double v[7];
        if (sscanf(p, "%lf %lf %lf %lf %lf %lf %lf", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5], &v[6]) == 7) {
            lines++;
            bad += !(v[5] >= 0 && v[5] < 360);
        }
        const char *nl = strchr(p, '\n');
        p = nl ? nl + 1 : p + strlen(p);
    }
    CHECK(r->status == 0 && lines == 5 && bad == 0, "views: %d lines, %d yaws outside 0..359:\n%s", lines, bad,
          r->out);
}

int main(void) {
    if (!getenv("EW_CLI")) {
        fprintf(stderr, "EW_CLI not set\n");
        return 1;
    }
    snprintf(tmpdir, sizeof tmpdir, "/tmp/ew_true_XXXXXX");
    run_r = malloc(sizeof *run_r);
    if (!run_r || !mkdtemp(tmpdir)) {
        fprintf(stderr, "cannot make a scratch folder\n");
        return 1;
    }
    make_maps();
    lit_field();
    png_names();
    do_nothing_options();
    debug_builds();
    view_yaws();
    free(run_r);
    char cmd[400];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmpdir);
    return ew_t_finish();
}
