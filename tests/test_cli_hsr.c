/*
 * `edgewise hsr`, the hidden-surface lab (issue 13), through the command
 * (path in EW_CLI): a table row and a JSON line per map x size x method
 * with sane numbers (the edge list never overdraws and agrees with the
 * reference path; the reference path agrees with itself), a heat map per
 * method and view (decoded: the edge list's is one colour), an SVG whose
 * tags balance and whose bars carry the JSON's values, stress halls whose
 * polygons in view grow with their detail, and bad arguments refused with
 * one line.  Times are printed, never asserted on.
 */
#define _POSIX_C_SOURCE 200809L
#include "util.h"
#include "edgewise_lab.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define ARGS(...) ((const char *const[]){ __VA_ARGS__, NULL })

static char tmpdir[256];

static ew_t_run *run(const char *const *args) {
    static ew_t_run r;
    ew_t_run_cli(&r, tmpdir, args);
    return &r;
}

static char *path_in(char out[600], const char *rel) {
    snprintf(out, 600, "%s/%s", tmpdir, rel);
    return out;
}

/* ---- JSON lines ----------------------------------------------------------- */

typedef struct jrow {
    char   map[64], method[32];
    int    w, h, views;
    double median, worst, od_mean, od_max, agree_mean, agree_min, in_view, dropped, stress;
} jrow;

/* The string after "key":" in a JSON line ("" if absent). */
static void json_str(const char *line, const char *key, char *out, size_t size) {
    char pat[64];
    snprintf(pat, sizeof pat, "\"%s\":\"", key);
    const char *p = strstr(line, pat);
    out[0] = '\0';
    if (!p) return;
    p += strlen(pat);
    size_t n = strcspn(p, "\"");
    snprintf(out, size, "%.*s", (int)(n < size ? n : size - 1), p);
}

/* Parses the JSON lines of text into rows; the count. */
static int parse_rows(const char *text, jrow *rows, int cap) {
    int n = 0;
    for (const char *p = text; *p && n < cap;) {
        const char *e = strchr(p, '\n');
        size_t len = e ? (size_t)(e - p) : strlen(p);
        char line[4096];
        snprintf(line, sizeof line, "%.*s", (int)(len < sizeof line ? len : sizeof line - 1), p);
        if (line[0] == '{') {
            jrow *r = &rows[n++];
            json_str(line, "map", r->map, sizeof r->map);
            json_str(line, "method", r->method, sizeof r->method);
            r->w = (int)ew_t_json_num(line, "width");
            r->h = (int)ew_t_json_num(line, "height");
            r->views = (int)ew_t_json_num(line, "views");
            r->median = ew_t_json_num(line, "median_ms");
            r->worst = ew_t_json_num(line, "worst_ms");
            r->od_mean = ew_t_json_num(line, "overdraw_mean");
            r->od_max = ew_t_json_num(line, "overdraw_max");
            r->agree_mean = ew_t_json_num(line, "agreement_mean_pct");
            r->agree_min = ew_t_json_num(line, "agreement_min_pct");
            r->in_view = ew_t_json_num(line, "polygons_in_view");
            r->dropped = ew_t_json_num(line, "dropped");
            r->stress = ew_t_json_num(line, "stress");
        }
        p += len + (e != NULL);
    }
    return n;
}

static const jrow *find_row(const jrow *rows, int n, const char *map, int w, const char *method) {
    for (int i = 0; i < n; i++)
        if (strcmp(rows[i].map, map) == 0 && rows[i].w == w && strcmp(rows[i].method, method) == 0)
            return &rows[i];
    return NULL;
}

/* ---- SVG: the tags edgewise writes --------------------------------------- */

/* The value of attr="..." inside one tag's text ("" if absent). */
static void attr(const char *tag, size_t len, const char *name, char *out, size_t size) {
    char pat[64];
    snprintf(pat, sizeof pat, " %s=\"", name);
    out[0] = '\0';
    for (const char *p = tag; p + strlen(pat) <= tag + len; p++)
        if (strncmp(p, pat, strlen(pat)) == 0) {
            p += strlen(pat);
            size_t n = strcspn(p, "\"");
            snprintf(out, size, "%.*s", (int)(n < size ? n : size - 1), p);
            return;
        }
}

typedef struct svg_mark {
    char kind[16], map[64], size[16], method[32];
    double value, polygons;
} svg_mark;

/* Checks that the tags balance (a stack of names, one root <svg>) and
 * collects the marks: <rect class="bar"> or <circle class="point">.
 * Returns the number of marks, or -1 if the tags do not balance. */
static int parse_svg(const char *text, svg_mark *marks, int cap, const char *mark_tag, const char *mark_class) {
    char stack[64][16];
    int depth = 0, roots = 0, n = 0;
    for (const char *p = strchr(text, '<'); p; p = strchr(p, '<')) {
        const char *e = strchr(p, '>');
        if (!e) return -1;
        size_t len = (size_t)(e - p) + 1;
        if (p[1] == '?' || p[1] == '!') {   /* the XML declaration */
            p = e;
            continue;
        }
        int closing = p[1] == '/', selfclosing = e[-1] == '/';
        const char *nm = p + 1 + closing;
        size_t nl = strcspn(nm, " />\n");
        char name[16];
        snprintf(name, sizeof name, "%.*s", (int)(nl < sizeof name ? nl : sizeof name - 1), nm);
        if (closing) {
            if (depth == 0 || strcmp(stack[depth - 1], name) != 0) return -1;
            depth--;
        } else {
            if (depth == 0) roots++;
            if (depth == 0 && strcmp(name, "svg") != 0) return -1;
            char cls[32];
            attr(p, len, "class", cls, sizeof cls);
            if (strcmp(name, mark_tag) == 0 && strcmp(cls, mark_class) == 0 && n < cap) {
                svg_mark *m = &marks[n++];
                char v[64];
                attr(p, len, "data-kind", m->kind, sizeof m->kind);
                attr(p, len, "data-map", m->map, sizeof m->map);
                attr(p, len, "data-size", m->size, sizeof m->size);
                attr(p, len, "data-method", m->method, sizeof m->method);
                attr(p, len, "data-value", v, sizeof v);
                m->value = v[0] ? atof(v) : NAN;
                attr(p, len, "data-polygons", v, sizeof v);
                m->polygons = v[0] ? atof(v) : NAN;
            }
            if (!selfclosing) {
                if (depth == 64) return -1;
                snprintf(stack[depth++], sizeof stack[0], "%s", name);
            }
        }
        p = e;
    }
    return depth == 0 && roots == 1 ? n : -1;
}

static int close_to(double a, double b) { return fabs(a - b) <= 1e-5 * fmax(1.0, fabs(b)); }

/* ---- the lab on real maps -------------------------------------------------- */

static void test_lab(const char *data) {
    char json[600], hm[600], svg[600];
    path_in(json, "lab.jsonl");
    path_in(hm, "heat");
    path_in(svg, "lab.svg");
    ew_t_run *r = run(ARGS("hsr", "e1m1", "start", "--data", data, "--methods", "edge,reference", "--size", "320x200",
                           "--size", "640x480", "--repeat", "1", "--no-entities", "--classic", "--json", json, "--heatmap", hm,
                           "--svg", svg));
    CHECK(r->status == 0, "exit %d: %s", r->status, r->err);
    /* the table: a header and a row per map x size x method */
    CHECK(ew_t_count_lines(r->out) == 1 + 8, "table lines %d:\n%s", ew_t_count_lines(r->out), r->out);
    CHECK(strncmp(r->out, "map ", 4) == 0, "table header: %.80s", r->out);
    const char *maps[2] = { "e1m1", "start" }, *methods[2] = { "edge", "reference" };
    const int sizes[2][2] = { { 320, 200 }, { 640, 480 } };
    for (int m = 0; m < 2; m++)
        for (int s = 0; s < 2; s++)
            for (int k = 0; k < 2; k++) {
                char want[64], size[16];
                snprintf(size, sizeof size, "%dx%d", sizes[s][0], sizes[s][1]);
                snprintf(want, sizeof want, "\n%-20s %9s %-10s ", maps[m], size, methods[k]);
                CHECK(strstr(r->out, want) != NULL, "no table row '%s'", want + 1);
            }

    static char text[65536];
    ew_t_slurp(json, text, sizeof text);
    jrow rows[16];
    int n = parse_rows(text, rows, 16);
    CHECK(n == 8, "%d JSON lines, want 8", n);
    for (int m = 0; m < 2; m++)
        for (int s = 0; s < 2; s++)
            for (int k = 0; k < 2; k++) {
                const jrow *j = find_row(rows, n, maps[m], sizes[s][0], methods[k]);
                CHECK(j != NULL, "no JSON row %s %d %s", maps[m], sizes[s][0], methods[k]);
                if (!j) continue;
                CHECK(j->h == sizes[s][1] && j->views > 0 && j->views <= EW_MAX_VIEWS, "%s %s: %dx%d, %d views",
                      maps[m], methods[k], j->w, j->h, j->views);
                CHECK(j->median > 0 && j->worst >= j->median && isfinite(j->worst), "%s %s: median %g worst %g",
                      maps[m], methods[k], j->median, j->worst);
                CHECK(j->agree_min >= 0 && j->agree_min <= j->agree_mean && j->agree_mean <= 100,
                      "%s %s: agreement %g min %g", maps[m], methods[k], j->agree_mean, j->agree_min);
                CHECK(j->in_view > 0 && j->dropped == 0, "%s: polygons in view %g, dropped %g", maps[m], j->in_view,
                      j->dropped);
                if (k == 0) {
                    /* the edge list writes every pixel once */
                    CHECK(j->od_mean == 1.0 && j->od_max == 1.0, "%s %dx%d edge: overdraw %g max %g", maps[m],
                          j->w, j->h, j->od_mean, j->od_max);
                    CHECK(j->agree_mean >= 99.0 && j->agree_min >= 95.0, "%s %dx%d edge: agreement %g%% min %g%%",
                          maps[m], j->w, j->h, j->agree_mean, j->agree_min);
                } else {
                    CHECK(j->agree_mean == 100.0 && j->agree_min == 100.0, "%s %dx%d reference: agreement %g%%",
                          maps[m], j->w, j->h, j->agree_mean);
                }
            }
    /* the drawing options reach every row, as in bench */
    CHECK(strstr(text, "\"classic\":false") == NULL && strstr(text, "\"entities\":true") == NULL,
          "JSON rows without --classic or --no-entities");
    const jrow *e = find_row(rows, n, "e1m1", 320, "edge");
    if (e) fprintf(stderr, "e1m1 320x200 edge: median %.3f ms, agreement %.3f%%\n", e->median, e->agree_mean);

    /* the heat maps: one PNG per method and view, the frame's size; the
     * edge list's one colour wherever it drew (no entities, and --classic:
     * no translucent liquid or fence drawn over the world) */
    int files = 0, expected = 0;
    for (int i = 0; i < n; i++) {
        expected += rows[i].views;
        for (int v = 0; v < rows[i].views; v++) {
            char p[4096];
            snprintf(p, sizeof p, "%s/%s_%dx%d_v%d_%s.png", hm, rows[i].map, rows[i].w, rows[i].h, v, rows[i].method);
            uint8_t *rgb = NULL;
            int w = 0, h = 0;
            ew_error err;
            if (ew_read_png_rgb(p, &rgb, &w, &h, &err) != 0) {
                CHECK(0, "%s: %s", p, err.msg);
                continue;
            }
            files++;
            CHECK(w == rows[i].w && h == rows[i].h, "%s: %dx%d", p, w, h);
            if (strcmp(rows[i].method, "edge") == 0) {
                long world = 0, other = 0;
                uint8_t c[3] = { 0, 0, 0 };
                for (long k = 0; k < (long)w * h; k++) {
                    const uint8_t *px = rgb + 3 * k;
                    if (!px[0] && !px[1] && !px[2]) continue;  /* nothing drawn */
                    if (!world++) memcpy(c, px, 3);
                    else other += memcmp(c, px, 3) != 0;
                }
                CHECK(world > (long)w * h / 2 && other == 0, "%s: %ld world pixels, %ld of another colour", p, world,
                      other);
            }
            free(rgb);
        }
    }
    CHECK(files == expected && files > 0, "%d heat maps of %d", files, expected);
    /* and nothing else in the folder */
    char cmd[700];
    snprintf(cmd, sizeof cmd, "ls '%s' | wc -l", hm);
    FILE *ls = popen(cmd, "r");
    int listed = -1;
    if (ls) {
        if (fscanf(ls, "%d", &listed) != 1) listed = -1;
        pclose(ls);
    }
    CHECK(listed == expected, "%d files in the heat map folder, want %d", listed, expected);

    /* the SVG: balanced tags, a time bar and an overdraw bar per row with
     * the JSON's values */
    static char svgtext[1 << 18];
    ew_t_slurp(svg, svgtext, sizeof svgtext);
    svg_mark marks[64];
    int nm = parse_svg(svgtext, marks, 64, "rect", "bar");
    CHECK(nm == 2 * n, "SVG: %d bars (want %d), or unbalanced tags", nm, 2 * n);
    for (int i = 0; i < nm; i++) {
        int w = 0, h = 0;
        sscanf(marks[i].size, "%dx%d", &w, &h);
        const jrow *j = find_row(rows, n, marks[i].map, w, marks[i].method);
        CHECK(j != NULL, "SVG bar %s %s %s has no JSON row", marks[i].map, marks[i].size, marks[i].method);
        if (!j) continue;
        int is_time = strcmp(marks[i].kind, "time") == 0;
        CHECK(is_time || strcmp(marks[i].kind, "overdraw") == 0, "SVG bar kind '%s'", marks[i].kind);
        double want = is_time ? j->median : j->od_mean;
        CHECK(close_to(marks[i].value, want), "SVG %s bar %s %s %s: %g, JSON %g", marks[i].kind, marks[i].map,
              marks[i].size, marks[i].method, marks[i].value, want);
    }
    for (int i = 0; i < nm; i++)
        for (int k = i + 1; k < nm; k++)
            CHECK(!(strcmp(marks[i].kind, marks[k].kind) == 0 && strcmp(marks[i].map, marks[k].map) == 0 &&
                    strcmp(marks[i].size, marks[k].size) == 0 && strcmp(marks[i].method, marks[k].method) == 0),
                  "SVG: two %s bars for %s %s %s", marks[i].kind, marks[i].map, marks[i].size, marks[i].method);
    CHECK(strstr(svgtext, "class=\"legend\"") && strstr(svgtext, ">edge</text>") &&
              strstr(svgtext, ">reference</text>"), "SVG: no legend naming the methods");

    /* --json - : the JSON lines on stdout instead of the table */
    r = run(ARGS("hsr", "start", "--data", data, "--methods", "edge", "--size", "320x200", "--repeat", "1",
                 "--json", "-"));
    CHECK(r->status == 0 && ew_t_count_lines(r->out) == 1 && r->out[0] == '{', "--json -: exit %d, stdout %.200s",
          r->status, r->out);
}

/* ---- the stress halls ---------------------------------------------------- */

static void test_stress(void) {
    char json[600], svg[600];
    path_in(json, "stress.jsonl");
    path_in(svg, "stress.svg");
    ew_t_run *r = run(ARGS("hsr", "--stress", "0,2000,20000", "--methods", "edge", "--size", "320x200", "--repeat",
                           "1", "--json", json, "--svg", svg));
    CHECK(r->status == 0, "exit %d: %s", r->status, r->err);
    CHECK(strstr(r->out, "stress 320x200") != NULL, "no stress table:\n%s", r->out);
    static char text[65536];
    ew_t_slurp(json, text, sizeof text);
    jrow rows[8];
    int n = parse_rows(text, rows, 8);
    CHECK(n == 3, "%d stress rows", n);
    if (n == 3) {
        for (int i = 0; i < 3; i++) {
            CHECK(rows[i].stress == (i == 0 ? 0 : i == 1 ? 2000 : 20000), "row %d: stress %g", i, rows[i].stress);
            CHECK(rows[i].dropped == 0 && rows[i].od_mean == 1.0 && rows[i].agree_mean >= 99.0,
                  "detail %g: dropped %g, overdraw %g, agreement %g", rows[i].stress, rows[i].dropped, rows[i].od_mean,
                  rows[i].agree_mean);
            fprintf(stderr, "stress detail %g: %.0f polygons in view, edge %.3f ms\n", rows[i].stress, rows[i].in_view,
                    rows[i].median);
        }
        /* about one polygon in view per detail cell, over a few hundred of the hall's own */
        CHECK(rows[0].in_view > 100 && rows[0].in_view < 2000, "detail 0: %g polygons", rows[0].in_view);
        CHECK(rows[1].in_view > rows[0].in_view + 1500, "detail 2000: %g polygons (detail 0: %g)", rows[1].in_view,
              rows[0].in_view);
        CHECK(rows[2].in_view > 18000 && rows[2].in_view > rows[1].in_view + 15000, "detail 20000: %g polygons",
              rows[2].in_view);
    }
    static char svgtext[1 << 16];
    ew_t_slurp(svg, svgtext, sizeof svgtext);
    svg_mark pts[16];
    int np = parse_svg(svgtext, pts, 16, "circle", "point");
    CHECK(np == 3, "stress SVG: %d points (want 3), or unbalanced tags", np);
    for (int i = 0; i < np && i < n; i++)
        CHECK(close_to(pts[i].polygons, rows[i].in_view) && close_to(pts[i].value, rows[i].median),
              "point %d: %g polygons %g ms, JSON %g %g", i, pts[i].polygons, pts[i].value, rows[i].in_view,
              rows[i].median);
    CHECK(strstr(svgtext, "<polyline class=\"series\" data-method=\"edge\"") != NULL, "stress SVG: no line for edge");

    /* the same hall as a MAP of other commands */
    char png[600];
    r = run(ARGS("render", "builtin:detail=500", "--out", path_in(png, "stress.png")));
    CHECK(r->status == 0, "render builtin:detail=500: exit %d: %s", r->status, r->err);
}

/* ---- bad arguments: one line, non-zero exit ------------------------------ */

static void expect_line_(int line, const char *const *args, int status, const char *want) {
    ew_t_run *r = run(args);
    char full[1024];
    snprintf(full, sizeof full, "edgewise: %s\n", want);
    CHECK(r->signal == 0 && r->status == status, "line %d: exit %d (want %d), stderr: %s", line, r->status, status,
          r->err);
    CHECK(strcmp(r->err, full) == 0, "line %d: stderr\n  %s want\n  %s", line, r->err, full);
}
#define expect_line(args, status, want) expect_line_(__LINE__, args, status, want)

/* One "edgewise: " line containing want, and a non-zero exit. */
static void expect_one_line_(int line, const char *const *args, const char *want) {
    ew_t_run *r = run(args);
    CHECK(r->signal == 0 && r->status != 0, "line %d: exit %d, stderr: %s", line, r->status, r->err);
    CHECK(ew_t_count_lines(r->err) == 1 && strncmp(r->err, "edgewise: ", 10) == 0 && strstr(r->err, want),
          "line %d: stderr '%s' (want one line with '%s')", line, r->err, want);
}
#define expect_one_line(args, want) expect_one_line_(__LINE__, args, want)

static void test_errors(const char *data) {
    /* the methods this build has, as the error lists them */
    char have[256] = "", want_m[512];
    for (int m = 0; m < EW_HSR_COUNT; m++)
        if (ew_hsr_available((ew_hsr_method)m))
            snprintf(have + strlen(have), sizeof have - strlen(have), "%s%s", *have ? ", " : "",
                     ew_hsr_name((ew_hsr_method)m));
    snprintf(want_m, sizeof want_m, "hsr: --methods edge,nosuch: unknown method 'nosuch' (this build has %s)", have);
    expect_line(ARGS("hsr", "builtin", "--methods", "edge,nosuch"), 2, want_m);
    expect_line(ARGS("hsr", "builtin", "--methods", "edge,edge"), 2, "hsr: --methods edge,edge: 'edge' given twice");
    expect_line(ARGS("hsr", "builtin", "--size", "10x10"), 2,
                "--size 10x10: out of range (from 320x200 up to 7680x4320)");
    expect_line(ARGS("hsr", "builtin", "--size", "big"), 2, "--size big: expected WIDTHxHEIGHT, e.g. 640x480");
    expect_line(ARGS("hsr", "builtin", "--repeat", "0"), 2, "hsr: --repeat 0: expected 1 to 1000");
    expect_line(ARGS("hsr"), 2,
                "hsr: missing MAP (a .bsp path, a map name with --data, 'builtin' or builtin:detail=N)");
    expect_line(ARGS("hsr", "builtin", "--stress", "500"), 2,
                "hsr: --stress takes no MAP (it makes its own: builtin:detail=N)");
    expect_line(ARGS("hsr", "--stress", "500,x"), 2,
                "hsr: --stress 500,x: expected a comma list of details from 0 to 26000");
    expect_line(ARGS("hsr", "builtin:detail=26001"), 2,
                "builtin:detail=26001: the detail must be a whole number from 0 to 26000");
    expect_line(ARGS("hsr", "builtin", "--hsr", "edge"), 2, "hsr: --hsr: the lab runs every method of --methods LIST");
    expect_line(ARGS("hsr", "builtin", "--frobnicate"), 2, "hsr: unknown option '--frobnicate' (see edgewise hsr --help)");
    /* a drawing option's error is the same line as in bench */
    ew_t_run *rb = run(ARGS("bench", "builtin", "--fog", "x"));
    static char bench_err[sizeof rb->err];
    snprintf(bench_err, sizeof bench_err, "%s", rb->err);
    ew_t_run *rh = run(ARGS("hsr", "builtin", "--fog", "x"));
    CHECK(rh->status == 2 && strcmp(rh->err, bench_err) == 0 && ew_t_count_lines(bench_err) == 1,
          "hsr --fog x: '%s', bench: '%s'", rh->err, bench_err);
    /* a heat map folder that is a file, or under one */
    char file[600], sub[700];
    path_in(file, "plain_file");
    FILE *f = fopen(file, "w");
    if (f) fclose(f);
    snprintf(sub, sizeof sub, "%s/sub", file);
    char want[900];
    snprintf(want, sizeof want, "hsr: --heatmap %s: not a directory", file);
    expect_line(ARGS("hsr", "builtin", "--heatmap", file), 1, want);
    snprintf(want, sizeof want, "hsr: --heatmap %s: Not a directory", sub);
    expect_line(ARGS("hsr", "builtin", "--heatmap", sub), 1, want);
    /* an unwritable folder: only when permissions bind (not as root) */
    char ro[600];
    path_in(ro, "readonly");
    mkdir(ro, 0555);
    chmod(ro, 0555);
    if (access(ro, W_OK) != 0) {
        snprintf(want, sizeof want, "hsr: --heatmap %s: Permission denied", ro);
        expect_line(ARGS("hsr", "builtin", "--heatmap", ro), 1, want);
    }
    chmod(ro, 0755);
    /* a missing map */
    expect_one_line(ARGS("hsr", "no_such_map.bsp"), "no_such_map.bsp");
    if (data) expect_one_line(ARGS("hsr", "no_such_map", "--data", data), "no_such_map");
}

int main(void) {
    snprintf(tmpdir, sizeof tmpdir, "/tmp/ew_cli_hsr_XXXXXX");
    if (!mkdtemp(tmpdir)) {
        fprintf(stderr, "mkdtemp failed\n");
        return 1;
    }
    const char *data = ew_t_have_shared("data/librequake/maps/e1m1.bsp") ? ew_t_shared_abs("data/librequake") : NULL;
    static char data_buf[600];
    if (data) {
        snprintf(data_buf, sizeof data_buf, "%s", data);
        data = data_buf;
    }
    test_errors(data);
    test_stress();
    if (data)
        test_lab(data);
    else
        ew_t_skip("the lab on real maps: %s not found (set EW_SHARED)", ew_t_shared("data/librequake"));
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmpdir);
    return ew_t_finish();
}
