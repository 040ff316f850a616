/*
 * `edgewise shots` (path in EW_CLI): a batch of shared maps and the
 * built-in scene gives valid PNGs and one manifest line each; a truncated
 * map is recorded with its error and exit 1 while the rest render; item
 * boxes are noted, not failures; a second run skips what is there and
 * --force redoes it; --jobs 2 writes the same PNGs as --jobs 1; a pak's
 * maps are found; bad arguments exit 2 with one line; stderr that is not a
 * terminal gets one summary line; and a batch split into one `edgewise
 * shots` per map under GNU parallel, manifests merged with cat, gives the
 * same pictures (skipped, saying why, without `parallel`).
 */
#define _POSIX_C_SOURCE 200809L
#include "util.h"
#include "edgewise_lab.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char tmpdir[256];
static ew_t_run *run_r;

static ew_t_run *run(const char *const *args) {
    ew_t_run_cli(run_r, tmpdir, args);
    return run_r;
}

static int count_str(const char *s, const char *needle) {
    int n = 0;
    for (const char *p = s; (p = strstr(p, needle)) != NULL; p += strlen(needle)) n++;
    return n;
}

static char *slurp_big(const char *path) {
    static char buf[1 << 20];
    ew_t_slurp(path, buf, sizeof buf);
    return buf;
}

/* A PNG of the size asked for that is not one flat colour. */
static int png_ok(const char *path, int w, int h) {
    uint8_t *rgb = NULL;
    int pw = 0, ph = 0;
    ew_error err;
    if (ew_read_png_rgb(path, &rgb, &pw, &ph, &err) < 0) return 0;
    int varied = 0;
    for (long i = 1; i < (long)pw * ph && !varied; i++) varied = memcmp(rgb, rgb + 3 * i, 3) != 0;
    free(rgb);
    return pw == w && ph == h && varied;
}

static int same_file(const char *a, const char *b) {
    uint8_t *da = NULL, *db = NULL;
    size_t na = 0, nb = 0;
    ew_error err;
    int same = ew_read_file(a, &da, &na, &err) == 0 && ew_read_file(b, &db, &nb, &err) == 0 && na == nb &&
               memcmp(da, db, na) == 0;
    free(da), free(db);
    return same;
}

static void path_in(char *out, size_t size, const char *rel) { snprintf(out, size, "%s/%s", tmpdir, rel); }

/* Bad arguments: exit 2, one line on stderr, nothing on stdout. */
static void bad_args(void) {
    const char *const cases[][6] = {
        {"shots", NULL},
        {"shots", "builtin", "--jobs", "0", NULL},
        {"shots", "builtin", "--jobs", "x", NULL},
        {"shots", "builtin", "--views", "1,,2", NULL},
        {"shots", "builtin", "--views", "worst", NULL},
        {"shots", "builtin", "--size", "10x10", NULL},
        {"shots", "builtin", "--bogus", NULL},
        {"shots", "builtin", "--force=1", NULL},
        {"shots", "builtin", "--out", NULL},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        ew_t_run *r = run(cases[i]);
        CHECK(r->status == 2 && ew_t_count_lines(r->err) == 1 && !r->out[0],
              "%s %s: want exit 2 and one line, got %d: %s", cases[i][1] ? cases[i][1] : "",
              cases[i][2] ? cases[i][2] : "", r->status, r->err);
    }
    const char *const help[] = {"shots", "--help", NULL};
    ew_t_run *r = run(help);
    CHECK(r->status == 0 && strstr(r->out, "--views") && strstr(r->out, "most open"), "shots --help: %d", r->status);
}

/* A batch of three shared maps and the built-in scene. */
static void batch(const char *maps) {
    char s_start[512], s_e1m1[512], s_lqdm1[512], out[300], man[300], p[400];
    snprintf(s_start, sizeof s_start, "%.400s/start.bsp", maps);
    snprintf(s_e1m1, sizeof s_e1m1, "%.400s/e1m1.bsp", maps);
    snprintf(s_lqdm1, sizeof s_lqdm1, "%.400s/lqdm1.bsp", maps);
    path_in(out, sizeof out, "batch");
    path_in(man, sizeof man, "batch/manifest.jsonl");
    const char *const args[] = {"shots", s_start, s_e1m1, s_lqdm1, "builtin", "--out", out, "--size", "320x200", NULL};
    ew_t_run *r = run(args);
    CHECK(r->status == 0, "batch: exit %d: %s", r->status, r->err);
    CHECK(ew_t_count_lines(r->err) == 1 && strstr(r->err, "4 maps, 4 pictures written") &&
              strstr(r->err, "0 failed") && !strchr(r->err, '\r'),
          "batch: want one summary line on a non-terminal, got: %s", r->err);
    const char *names[] = {"start", "e1m1", "lqdm1", "builtin"};
    for (int i = 0; i < 4; i++) {
        snprintf(p, sizeof p, "%s/%s_best.png", out, names[i]);
        CHECK(png_ok(p, 320, 200), "batch: %s is not a 320x200 picture", p);
    }
    char *m = slurp_big(man);
    CHECK(ew_t_count_lines(m) == 4 && count_str(m, "\"status\":\"ok\"") == 4, "batch: manifest: %s", m);
    CHECK(count_str(m, "\"width\":320,\"height\":200") == 4 && count_str(m, "\"ms_render\":") == 4 &&
              count_str(m, "\"origin\":[") == 4 && count_str(m, "\"dark\":false") == 4 &&
              count_str(m, "\"pixels_written\":64000") == 4,
          "batch: manifest lines lack camera, size, times or stats: %s", m);
    CHECK(strstr(m, "\"map\":\"e1m1\"") && strstr(m, "\"source\":\"") && strstr(m, "\"view\":\"best\""),
          "batch: manifest names: %s", m);
    /* start has no intermission: its best view is level, from the first player start. */
    const char *ls = strstr(m, "\"map\":\"start\"");
    CHECK(ls && strstr(ls, "\"angles\":[0,"), "batch: start's best view should be level: %s", ls ? ls : m);

    /* Again: everything skipped, nothing rewritten. */
    struct stat before, after;
    snprintf(p, sizeof p, "%s/e1m1_best.png", out);
    stat(p, &before);
    r = run(args);
    m = slurp_big(man);
    CHECK(r->status == 0 && strstr(r->err, "0 pictures written, 4 skipped"), "resume: %d %s", r->status, r->err);
    CHECK(ew_t_count_lines(m) == 8 && count_str(m, "\"status\":\"skipped\"") == 4, "resume: manifest: %s", m);
    stat(p, &after);
    CHECK(before.st_mtim.tv_sec == after.st_mtim.tv_sec && before.st_mtim.tv_nsec == after.st_mtim.tv_nsec,
          "resume rewrote %s", p);
    /* A picture removed is the only one redone. */
    snprintf(p, sizeof p, "%s/lqdm1_best.png", out);
    unlink(p);
    r = run(args);
    CHECK(r->status == 0 && strstr(r->err, "1 picture written, 3 skipped") && png_ok(p, 320, 200),
          "resume after removing one: %s", r->err);
    const char *const forced[] = {"shots", s_start, s_e1m1, s_lqdm1, "builtin", "--out", out, "--size", "320x200",
                                  "--force", NULL};
    r = run(forced);
    m = slurp_big(man);
    CHECK(r->status == 0 && strstr(r->err, "4 pictures written, 0 skipped"), "--force: %s", r->err);
    CHECK(ew_t_count_lines(m) == 16 && count_str(m, "\"status\":\"ok\"") == 9, "--force: manifest: %s", m);
}

/* A truncated map among good ones, and an item box. */
static void broken(const char *maps) {
    char src[512], cut[300], out[300], man[300], box[512];
    snprintf(src, sizeof src, "%.400s/start.bsp", maps);
    snprintf(box, sizeof box, "%.400s/b_batt0.bsp", maps);
    path_in(cut, sizeof cut, "cut.bsp");
    path_in(out, sizeof out, "broken");
    path_in(man, sizeof man, "broken.jsonl");
    uint8_t *d = NULL;
    size_t n = 0;
    ew_error err;
    if (ew_read_file(src, &d, &n, &err) < 0) {
        CHECK(0, "%s", err.msg);
        return;
    }
    FILE *f = fopen(cut, "wb");
    if (f) fwrite(d, 1, n / 3, f), fclose(f);
    free(d);
    const char *const args[] = {"shots", "builtin", cut, box, "--out", out, "--manifest", man, "--size", "320x200", NULL};
    ew_t_run *r = run(args);
    CHECK(r->status == 1 && strstr(r->err, "1 failed") && strstr(r->err, "1 without views") &&
              ew_t_count_lines(r->err) == 2 && strstr(r->err, "shots: failed: cut: ") && strstr(r->err, "cut.bsp: "),
          "broken: want exit 1, one summary line saying 1 failed and a line naming cut with its error, got %d: %s",
          r->status, r->err);
    char *m = slurp_big(man);
    const char *e = strstr(m, "\"map\":\"cut\"");
    CHECK(e && strstr(e, "\"status\":\"error\",\"error\":\"") && strstr(e, "cut.bsp:"),
          "broken: manifest lacks the error: %s", m);
    CHECK(strstr(m, "\"map\":\"b_batt0\"") && strstr(m, "\"status\":\"no_views\""), "item box: %s", m);
    char p[400];
    snprintf(p, sizeof p, "%s/builtin_best.png", out);
    CHECK(png_ok(p, 320, 200) && count_str(m, "\"status\":\"ok\"") == 1, "broken: the batch did not go on");
}

/* --jobs 2 and --jobs 1: the same files, byte for byte. */
static void jobs(const char *maps) {
    char start[512], lq[512], a[300], b[300], pa[400], pb[400];
    snprintf(start, sizeof start, "%.400s/start.bsp", maps);
    snprintf(lq, sizeof lq, "%.400s/lqdm1.bsp", maps);
    path_in(a, sizeof a, "jobs1");
    path_in(b, sizeof b, "jobs2");
    const char *const one[] = {"shots", start, lq, "builtin", "--views", "all", "--out", a, "--size", "320x200", NULL};
    const char *const two[] = {"shots", start, lq, "builtin", "--views", "all", "--out", b, "--size", "320x200",
                               "--jobs", "2", NULL};
    ew_t_run *r = run(one);
    CHECK(r->status == 0, "jobs 1: %s", r->err);
    char *m = slurp_big(strcat(strcpy(pa, a), "/manifest.jsonl"));
    int lines1 = ew_t_count_lines(m);
    r = run(two);
    CHECK(r->status == 0 && ew_t_count_lines(r->err) == 1, "jobs 2: %s", r->err);
    m = slurp_big(strcat(strcpy(pb, b), "/manifest.jsonl"));
    CHECK(lines1 > 8 && ew_t_count_lines(m) == lines1 && count_str(m, "\"status\":\"ok\"") == lines1,
          "jobs 2: %d manifest lines, jobs 1: %d", ew_t_count_lines(m), lines1);
    int compared = 0;
    const char *names[] = {"start", "lqdm1", "builtin"};
    for (int k = 0; k < 3; k++)
        for (int v = 0; v < EW_MAX_VIEWS; v++) {
            snprintf(pa, sizeof pa, "%s/%s_v%d.png", a, names[k], v);
            snprintf(pb, sizeof pb, "%s/%s_v%d.png", b, names[k], v);
            if (access(pa, F_OK) != 0) {
                CHECK(access(pb, F_OK) != 0, "jobs 2 wrote %s, jobs 1 did not", pb);
                continue;
            }
            CHECK(same_file(pa, pb), "jobs: %s and %s differ", pa, pb);
            compared++;
        }
    CHECK(compared == lines1, "jobs: compared %d pictures, manifest has %d", compared, lines1);
}

static void put32(uint8_t *p, uint32_t v) {
    for (int i = 0; i < 4; i++) p[i] = (uint8_t)(v >> (8 * i));
}

/* A pak holding maps/start.bsp and a text file: its map is found and drawn. */
static void pak(const char *maps, const char *data) {
    char src[512], pk[300], out[300], man[300];
    snprintf(src, sizeof src, "%.400s/start.bsp", maps);
    path_in(pk, sizeof pk, "test.pak");
    path_in(out, sizeof out, "pak");
    path_in(man, sizeof man, "pak/manifest.jsonl");
    uint8_t *d = NULL;
    size_t n = 0;
    ew_error err;
    if (ew_read_file(src, &d, &n, &err) < 0) {
        CHECK(0, "%s", err.msg);
        return;
    }
    const char note[] = "hello";
    uint8_t hdr[12], dir[128];
    memset(dir, 0, sizeof dir);
    memcpy(hdr, "PACK", 4);
    put32(hdr + 4, (uint32_t)(12 + n + sizeof note));
    put32(hdr + 8, sizeof dir);
    strcpy((char *)dir, "maps/start.bsp");
    put32(dir + 56, 12), put32(dir + 60, (uint32_t)n);
    strcpy((char *)dir + 64, "readme.txt");
    put32(dir + 120, (uint32_t)(12 + n)), put32(dir + 124, sizeof note);
    FILE *f = fopen(pk, "wb");
    if (f) {
        fwrite(hdr, 1, 12, f), fwrite(d, 1, n, f), fwrite(note, 1, sizeof note, f), fwrite(dir, 1, sizeof dir, f);
        fclose(f);
    }
    free(d);
    const char *const args[] = {"shots", pk, "--data", data, "--out", out, "--size", "320x200", NULL};
    ew_t_run *r = run(args);
    char *m = slurp_big(man);
    char p[400];
    snprintf(p, sizeof p, "%s/start_best.png", out);
    CHECK(r->status == 0 && png_ok(p, 320, 200), "pak: %d %s", r->status, r->err);
    CHECK(ew_t_count_lines(m) == 1 && strstr(m, "\"entry\":\"maps/start.bsp\"") && strstr(m, "test.pak\""),
          "pak: manifest: %s", m);
}

/* One `edgewise shots` per map under GNU parallel, manifests merged with cat. */
static void gnu_parallel(const char *maps) {
    if (system("parallel --version >/dev/null 2>&1") != 0) {
        ew_t_skip("GNU parallel is not installed (Debian package 'parallel'), the split batch is not tested");
        return;
    }
    const char *cli = getenv("EW_CLI");
    char cmd[4096];
    snprintf(cmd, sizeof cmd,
             "cd '%s' && printf '%%s\\n' '%s/start.bsp' '%s/lqdm1.bsp' '%s/e2m1.bsp' > list.txt && "
             "parallel --will-cite --jobs 2 '%s' shots {} --out par --size 320x200 --manifest par/part.{#}.jsonl "
             ":::: list.txt 2>/dev/null && cat par/part.*.jsonl > par/all.jsonl",
             tmpdir, maps, maps, maps, cli);
    int rc = system(cmd);
    char p[400];
    path_in(p, sizeof p, "par/all.jsonl");
    char *m = slurp_big(p);
    CHECK(rc == 0 && ew_t_count_lines(m) == 3 && count_str(m, "\"status\":\"ok\"") == 3, "parallel: %d %s", rc, m);
    const char *names[] = {"start", "lqdm1", "e2m1"};
    for (int i = 0; i < 3; i++) {
        char q[400];
        snprintf(q, sizeof q, "%s/par/%s_best.png", tmpdir, names[i]);
        CHECK(png_ok(q, 320, 200), "parallel: %s", q);
        snprintf(p, sizeof p, "%s/batch/%s_best.png", tmpdir, names[i]);
        if (access(p, F_OK) == 0) CHECK(same_file(p, q), "parallel: %s differs from the batch's", q);
    }
}

int main(void) {
    if (!getenv("EW_CLI")) {
        fprintf(stderr, "EW_CLI not set\n");
        return 1;
    }
    snprintf(tmpdir, sizeof tmpdir, "/tmp/ew_shots_XXXXXX");
    run_r = malloc(sizeof *run_r);
    if (!run_r || !mkdtemp(tmpdir)) {
        fprintf(stderr, "cannot make a scratch folder\n");
        return 1;
    }
    bad_args();
    if (ew_t_need_shared("data/librequake/maps/start.bsp")) {
        char maps[512], data[512];
        snprintf(maps, sizeof maps, "%s", ew_t_shared_abs("data/librequake/maps"));
        snprintf(data, sizeof data, "%s", ew_t_shared_abs("data/librequake"));
        batch(maps);
        broken(maps);
        jobs(maps);
        pak(maps, data);
        gnu_parallel(maps);
    }
    free(run_r);
    char cmd[400];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmpdir);
    return ew_t_finish();
}
