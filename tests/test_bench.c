/*
 * `edgewise bench` (path in EW_CLI, set by CMake): every field of the JSON
 * line is there and consistent, and bad arguments fail with one line.
 * Times are checked only for order and sign, never for size: the machines
 * running the tests are shared and noisy.
 */
#define _POSIX_C_SOURCE 200809L
#include "util.h"

#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static const char *cli;
static char tmpdir[256];

typedef ew_t_run run_result;

static char *tmp_path(char out[512], const char *name) {
    snprintf(out, 512, "%s/%s", tmpdir, name);
    return out;
}

/* Runs EW_CLI with args (NULL-terminated), no shell, in tmpdir; stderr goes
 * to a file, so the progress line (terminals only) stays off. */
static void run(run_result *r, const char *const *args) { ew_t_run_cli(r, tmpdir, args); }

static int count_lines(const char *s) { return ew_t_count_lines(s); }

#define ARGS(...) ((const char *const[]){ __VA_ARGS__, NULL })

/* The number after "key": in the JSON line (keys are unique in a row, the
 * nested stage and counter names included); NAN if absent. */
static double field(const char *json, const char *key) { return ew_t_json_num(json, key); }

static void expect_ok(run_result *r, const char *what, const char *const *args) {
    run(r, args);
    CHECK(r->signal == 0 && r->status == 0 && !r->err[0], "%s: exit %d signal %d, stderr: %s",
          what, r->status, r->signal, r->err);
}

/* One row of the protocol: every field present, and the order statistics
 * consistent with each other. */
static void check_row(const char *what, const char *line, int w, int h, int views, int passes) {
    static const char *const keys[] = {
        "width", "height", "threads", "threads_applied", "entities", "views", "passes", "gap_ms",
        "median_ms", "mean_ms", "p99_ms", "max_ms", "max_view", "level", "ns_per_pixel",
        "floor_ms", "floor_ratio", "lookup_floor_ms", "front", "scan", "draw", "models", "total", "pixels",
        "pixels_written", "pixels_covered", "edges", "edges_cached", "surfaces", "surfaces_shown", "spans",
        "surfaces_built", "surfaces_cached", "visible_leaves", "dropped", "entities_drawn", "entities_hidden",
        "alias_tris", "particles", "serial_ms", "serial_share", "begin_ms", "walk_ms", "brush_ms",
        "prepare_ms", "passes_ms", "serial_mean_ms", "view_level_front_scan", "view_level_draw",
        "view_level_draw_models",
    };
    CHECK(line[0] == '{' && strstr(line, "\"map\":\"") && strstr(line, "\"stages\":{") &&
              strstr(line, "\"counters\":{"), "%s: %s", what, line);
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++) {
        double v = field(line, keys[i]);
        CHECK(isfinite(v) && v >= 0, "%s: %s = %g in %s", what, keys[i], v, line);
    }
    CHECK(field(line, "width") == w && field(line, "height") == h, "%s: size in %s", what, line);
    CHECK(field(line, "pixels") == (double)w * h, "%s: pixels in %s", what, line);
    if (views > 0)
        CHECK(field(line, "views") == views, "%s: views in %s", what, line);
    CHECK(field(line, "passes") == passes && field(line, "threads") >= 1, "%s: %s", what, line);
    double med = field(line, "median_ms"), p99 = field(line, "p99_ms"),
           max = field(line, "max_ms"), mean = field(line, "mean_ms");
    CHECK(med <= p99 && p99 <= max && mean <= max, "%s: median %g p99 %g max %g mean %g", what,
          med, p99, max, mean);
    CHECK(field(line, "level") >= 1, "%s: level in %s", what, line);
    CHECK(field(line, "max_view") < field(line, "views"), "%s: max_view in %s", what, line);
    CHECK(field(line, "pixels_written") > 0 && field(line, "spans") > 0, "%s: counters: %s",
          what, line);
    /* The serial time: a part of the frame, and its parts of it (medians of
     * different frames, so with some slack). */
    double ser = field(line, "serial_ms"), share = field(line, "serial_share");
    CHECK(ser > 0 && share > 0, "%s: serial %g share %g in %s", what, ser, share, line);
    /* Each frame's serial time is part of it, so the medians are ordered
     * too; a row on more threads is compared with another row's frames. */
    if (field(line, "threads") == 1)
        CHECK(ser <= med && share < 1 && strstr(line, "\"serial_share_base\":\"threads1\""),
              "%s: serial %g share %g median %g: %s", what, ser, share, med, line);
    double parts = field(line, "begin_ms") + field(line, "walk_ms") + field(line, "brush_ms") +
                   field(line, "prepare_ms") + field(line, "passes_ms");
    double smean = field(line, "serial_mean_ms");
    CHECK(fabs(parts + field(line, "other_ms") - smean) <= 1e-3 * smean + 1e-5, "%s: serial parts %g of %g: %s",
          what, parts, smean, line);
}

/* --bands: per N, the imbalance (>= 1, at most N: the slowest band holds at
 * most all the work) and Amdahl's speed-up on N cores (1 to N). */
static void check_bands(const char *what, const char *line, const int *bands, int n) {
    for (int i = 0; i < n; i++) {
        char k1[32], k2[32], k3[48];
        snprintf(k1, sizeof k1, "imbalance_%d", bands[i]);
        snprintf(k2, sizeof k2, "imbalance_max_%d", bands[i]);
        snprintf(k3, sizeof k3, "predicted_speedup_%d", bands[i]);
        double imb = field(line, k1), worst = field(line, k2), x = field(line, k3);
        CHECK(imb >= 1 && imb <= bands[i] && worst >= imb && worst <= bands[i], "%s: %s %g, %s %g in %s", what,
              k1, imb, k2, worst, line);
        CHECK(x >= 1 && x <= bands[i], "%s: %s %g in %s", what, k3, x, line);
        snprintf(k1, sizeof k1, "sched_imbalance_%d", bands[i]);
        snprintf(k3, sizeof k3, "sched_speedup_%d", bands[i]);
        double simb = field(line, k1), sx = field(line, k3);
        CHECK(simb >= 1 && simb <= bands[i] && sx >= 1 && sx <= bands[i], "%s: %s %g, %s %g in %s", what, k1, simb,
              k3, sx, line);
        double s = field(line, "predict_share");
        CHECK(s > 0 && s <= 1, "%s: predict_share %g in %s", what, s, line);
        /* the parallel front end's largest items, timed in the row profile */
        double fi = field(line, "front_items_ms");
        CHECK(fi > 0 && fi < field(line, "median_ms"), "%s: front_items_ms %g in %s", what, fi, line);
        /* the work many threads share: the frame with the front end's phases */
        double ps = field(line, "phases_share");
        CHECK(ps >= 1 && ps < 2, "%s: phases_share %g in %s", what, ps, line);
        CHECK(fabs(x - 1 / (s + (ps - s) * imb / bands[i])) < 1e-3 * x, "%s: predicted_speedup_%d %g is not Amdahl's: %s",
              what, bands[i], x, line);
    }
}

static void test_start(void) {
    const char *rel = "data/librequake/maps/start.bsp";
    if (!ew_t_need_shared(rel)) return;
    /* The CLI runs in tmpdir: make the data path absolute. */
    char data[2048], cwd[512] = "";
    const char *shared = ew_t_shared("data/librequake");
    if (shared[0] != '/' && !getcwd(cwd, sizeof cwd))
        cwd[0] = '\0';
    snprintf(data, sizeof data, "%s%s%s", cwd, cwd[0] ? "/" : "", shared);

    run_result *r = malloc(sizeof *r);
    expect_ok(r, "start", ARGS("bench", "start", "--data", data, "--size", "320x200",
                               "--passes", "1"));
    CHECK(count_lines(r->out) == 1, "start: want one line: %s", r->out);
    CHECK(strstr(r->out, "\"map\":\"start\""), "start: %s", r->out);
    check_row("start", r->out, 320, 200, 20, 1);
    CHECK(field(r->out, "entities") == 1, "start: entities: %s", r->out);

    /* World only: no entity drawn, and the row says so. */
    expect_ok(r, "start --no-entities", ARGS("bench", "start", "--data", data, "--size",
                                             "320x200", "--passes", "1", "--no-entities"));
    check_row("start --no-entities", r->out, 320, 200, 20, 1);
    CHECK(field(r->out, "entities") == 0 && field(r->out, "entities_drawn") == 0 &&
              field(r->out, "alias_tris") == 0, "--no-entities: %s", r->out);

    /* --gap: frames spaced out, the two-thread pool asleep between them;
     * the pauses (20 views, a warm-up and one pass, 5 ms each) show in the
     * run's time and the row says so. */
    struct timespec g0, g1;
    clock_gettime(CLOCK_MONOTONIC, &g0);
    expect_ok(r, "start --gap", ARGS("bench", "start", "--data", data, "--size", "320x200", "--passes", "1",
                                     "--threads", "2", "--gap", "5"));
    clock_gettime(CLOCK_MONOTONIC, &g1);
    double gap_s = (double)(g1.tv_sec - g0.tv_sec) + (double)(g1.tv_nsec - g0.tv_nsec) * 1e-9;
    check_row("start --gap", r->out, 320, 200, 20, 1);
    CHECK(field(r->out, "gap_ms") == 5 && gap_s >= 0.2, "--gap 5: gap_ms %g, %.3f s for 40 frames: %s",
          field(r->out, "gap_ms"), gap_s, r->out);
    /* The process's processor time per frame and the frames' own work: the
     * work is inside the process's time (the pauses add a little), and the
     * ratio is theirs.  No bound on it: that is a measurement. */
    double cpu = field(r->out, "cpu_ms_per_frame"), work = field(r->out, "work_ms_per_frame");
    double ratio = field(r->out, "cpu_over_work");
    CHECK(work > 0 && cpu >= 0.9 * work && fabs(ratio - cpu / work) < 1e-3 * ratio,
          "--gap: cpu_ms_per_frame %g, work_ms_per_frame %g, cpu_over_work %g: %s", cpu, work, ratio, r->out);

    /* --per-view: an entry per view; the slow view's median over the
     * row's median is view_level, and every view drew something. */
    expect_ok(r, "start --per-view", ARGS("bench", "start", "--data", data, "--size", "320x200", "--passes", "2",
                                          "--per-view"));
    check_row("start --per-view", r->out, 320, 200, 20, 2);
    int entries = 0, drawn = 0;
    for (const char *p = r->out; (p = strstr(p, "{\"view\":")); p++) {
        entries++;
        drawn += ew_t_json_num(p, "surfaces") > 0 && ew_t_json_num(p, "spans") > 0 && ew_t_json_num(p, "median_ms") > 0;
    }
    CHECK(entries == 20 && drawn == 20, "--per-view: %d entries, %d drew: %s", entries, drawn, r->out);
    char key[64];
    snprintf(key, sizeof key, "{\"view\":%d,", (int)field(r->out, "slow_view"));
    const char *slow = strstr(r->out, key);
    CHECK(slow && fabs(ew_t_json_num(slow, "median_ms") / field(r->out, "median_ms") - field(r->out, "view_level")) <
                      1e-3 * field(r->out, "view_level"),
          "--per-view: the slow view's entry (%s) does not give view_level: %s", key, r->out);
    /* The parts' levels: the draw's is its slowest view's draw over the
     * row's median draw (a median of two passes is their mean, as each
     * entry's is); each part is finite and positive. */
    double slow_draw = 0;
    for (const char *p = r->out; (p = strstr(p, "{\"view\":")); p++) {
        double d = ew_t_json_num(p, "draw");
        if (d > slow_draw) slow_draw = d;
    }
    const char *stages = strstr(r->out, "\"stages\":{");
    double draw_level = field(r->out, "view_level_draw");
    CHECK(stages && fabs(slow_draw / ew_t_json_num(stages, "draw") - draw_level) < 1e-3 * draw_level,
          "--per-view: view_level_draw %g, slowest view's draw %g: %s", draw_level, slow_draw, r->out);
    CHECK(field(r->out, "view_level_front_scan") > 0 && field(r->out, "view_level_draw_models") > 0,
          "--per-view: the parts' levels: %s", r->out);

    /* --bands, on one thread and then two: the same imbalances (one
     * profile per map and size), the two-thread row's serial share of the
     * one-thread row's frame. */
    expect_ok(r, "start --bands", ARGS("bench", "start", "--data", data, "--size", "320x200", "--passes", "1",
                                       "--threads", "1", "--threads", "2", "--bands", "4", "--bands=25"));
    static const int bands[] = {4, 25};
    CHECK(count_lines(r->out) == 2, "--bands: want two lines: %s", r->out);
    char *second = strchr(r->out, '\n');
    if (second) {
        *second++ = '\0';
        check_row("start --bands, 1 thread", r->out, 320, 200, 20, 1);
        check_row("start --bands, 2 threads", second, 320, 200, 20, 1);
        check_bands("start --bands, 1 thread", r->out, bands, 2);
        check_bands("start --bands, 2 threads", second, bands, 2);
        CHECK(field(r->out, "imbalance_25") == field(second, "imbalance_25") &&
                  strstr(second, "\"serial_share_base\":\"threads1\""),
              "--bands: rows differ: %s / %s", r->out, second);
    }
    free(r);
}

/* The built-in scene needs no files: several sizes, --table with --out. */
static void test_builtin(void) {
    run_result *r = malloc(sizeof *r);
    char out[512], json[65536];
    tmp_path(out, "bench.jsonl");
    expect_ok(r, "builtin", ARGS("bench", "builtin", "--size", "320x200", "--size=400x300",
                                 "--passes=2", "--table", "--out", out));
    ew_t_slurp(out, json, sizeof json);
    CHECK(count_lines(json) == 2, "builtin: want two JSON lines: %s", json);
    char *second = strchr(json, '\n');
    if (second) {
        *second++ = '\0';
        check_row("builtin 320x200", json, 320, 200, 0, 2);
        check_row("builtin 400x300", second, 400, 300, 0, 2);
    }
    /* The table: a header and one row per size, no JSON. */
    CHECK(count_lines(r->out) == 3 && strncmp(r->out, "map", 3) == 0 && !strchr(r->out, '{'),
          "table: %s", r->out);
    remove(out);

    expect_ok(r, "floor", ARGS("bench", "--floor", "--size", "320x200"));
    CHECK(count_lines(r->out) == 1 && strstr(r->out, "\"floor\":true"), "floor: %s", r->out);
    CHECK(field(r->out, "width") == 320 && field(r->out, "floor_ms") >= 0 &&
              field(r->out, "reps") >= 1, "floor: %s", r->out);
    /* The lookup floor: measured (a time above 0), not a placeholder. */
    CHECK(field(r->out, "lookup_floor_ms") > 0, "floor: lookup_floor_ms: %s", r->out);

    run(r, ARGS("bench", "--help"));
    CHECK(r->status == 0 && strstr(r->out, "--passes"), "bench --help: %d", r->status);
    run(r, ARGS("--help"));
    CHECK(r->status == 0 && strstr(r->out, "bench MAP"), "--help lists bench: %s", r->out);
    free(r);
}

/* --cold: every timed frame builds all the lit surfaces it shows (none
 * from the cache), where a warm row's frames build almost none; the rows
 * say which they are, in the JSON and in the table. */
static void test_cold(void) {
    run_result *r = malloc(sizeof *r);
    expect_ok(r, "builtin warm", ARGS("bench", "builtin", "--size", "320x200", "--passes", "2"));
    char *warm = strdup(r->out);
    if (!warm) {
        free(r);
        return;
    }
    expect_ok(r, "builtin --cold", ARGS("bench", "builtin", "--size", "320x200", "--passes", "2", "--cold"));
    check_row("builtin --cold", r->out, 320, 200, 0, 2);
    CHECK(strstr(r->out, "\"cold\":true") && strstr(warm, "\"cold\":false"), "cold field: %s / %s", r->out, warm);
    double built = field(r->out, "surfaces_built"), cached = field(r->out, "surfaces_cached");
    CHECK(built > 0 && cached == 0, "--cold: built %g cached %g a frame: %s", built, cached, r->out);
    CHECK(built == field(warm, "surfaces_built") + field(warm, "surfaces_cached"),
          "--cold builds %g a frame, the warm row shows %g + %g", built, field(warm, "surfaces_built"),
          field(warm, "surfaces_cached"));
    /* with another drawing option, in the table */
    expect_ok(r, "builtin --cold --color true --table",
              ARGS("bench", "builtin", "--size", "320x200", "--passes", "1", "--cold", "--color", "true", "--table"));
    CHECK(count_lines(r->out) == 2 && strstr(r->out, " cold ") && strstr(r->out, " yes "), "--cold table: %s",
          r->out);
    free(warm);
    free(r);
}

/* --simd: the row names the loops in use (sse2 on any x86-64 processor),
 * and a fogged frame at sse2 counts the same fogged pixels as at the
 * processor's widest (tests/test_fog_simd.c compares the frames). */
static void test_simd(void) {
    run_result *r = malloc(sizeof *r);
    expect_ok(r, "builtin --simd sse2",
              ARGS("bench", "builtin", "--size", "320x200", "--passes", "1", "--simd", "sse2", "--fog", "0.5,0.5,0.5,0.5"));
    CHECK(strstr(r->out, "\"simd\":\"sse2\"") != NULL, "--simd sse2 row: %s", r->out);
    double narrow = field(r->out, "fog_pixels");
    expect_ok(r, "builtin (best)", ARGS("bench", "builtin", "--size", "320x200", "--passes", "1", "--fog", "0.5,0.5,0.5,0.5"));
    CHECK(strstr(r->out, "\"simd\":\"") != NULL && strstr(r->out, "\"simd\":\"best\"") == NULL,
          "the default row names the loops it ran: %s", r->out);
    CHECK(narrow > 0 && field(r->out, "fog_pixels") == narrow, "fog_pixels %g at sse2, %g at best", narrow,
          field(r->out, "fog_pixels"));
    free(r);
}

/* A normal non-zero exit and exactly one "edgewise: ..." line on stderr. */
static void expect_fail(const char *const *args, const char *needle) {
    run_result *r = malloc(sizeof *r);
    run(r, args);
    CHECK(r->signal == 0 && r->status > 0 && r->status < 126, "%s: exit %d signal %d", needle,
          r->status, r->signal);
    CHECK(count_lines(r->err) == 1 && strncmp(r->err, "edgewise: ", 10) == 0,
          "%s: want one error line, got: %s", needle, r->err);
    CHECK(strstr(r->err, needle) != NULL, "'%s' not in: %s", needle, r->err);
    CHECK(!r->out[0], "%s: stdout: %s", needle, r->out);
    free(r);
}

static void test_bad_args(void) {
    char path[512];
    expect_fail(ARGS("bench", "builtin", "--simd", "avx3"), "--simd avx3: expected best, sse2, avx2 or avx512");
    expect_fail(ARGS("bench", "--floor", "--simd", "sse2"), "--floor takes only");
    expect_fail(ARGS("bench", "builtin", "--simd", "sse2", "--simd", "avx2"), "--simd given twice");
    expect_fail(ARGS("bench"), "missing MAP");
    expect_fail(ARGS("bench", "builtin", "--passes", "0"), "--passes");
    expect_fail(ARGS("bench", "builtin", "--passes", "x"), "--passes");
    expect_fail(ARGS("bench", "builtin", "--passes", "1", "--passes", "2"), "twice");
    expect_fail(ARGS("bench", "builtin", "--passes"), "needs a value");
    expect_fail(ARGS("bench", "builtin", "--threads", "-1"), "--threads");
    expect_fail(ARGS("bench", "builtin", "--bands", "0"), "--bands 0: expected 1 to 256");
    expect_fail(ARGS("bench", "builtin", "--bands", "257"), "--bands 257: expected 1 to 256");
    expect_fail(ARGS("bench", "builtin", "--bands", "x"), "--bands x: expected 1 to 256");
    expect_fail(ARGS("bench", "builtin", "--bands", "4.5"), "--bands 4.5");
    expect_fail(ARGS("bench", "builtin", "--bands"), "needs a value");
    expect_fail(ARGS("bench", "builtin", "--size", "320x200", "--bands", "26"),
                "--bands 26: a band has at least 8 rows, 320x200 has 200 rows");
    expect_fail(ARGS("bench", "--floor", "--bands", "4"), "--floor");
    expect_fail(ARGS("bench", "builtin", "--size", "10x10"), "10x10");
    expect_fail(ARGS("bench", "builtin", "--size", "abc"), "abc");
    expect_fail(ARGS("bench", "builtin", "--wibble"), "--wibble");
    expect_fail(ARGS("bench", "builtin", "--table=yes"), "--table");
    expect_fail(ARGS("bench", "builtin", "--floor"), "--floor");
    expect_fail(ARGS("bench", "--floor", "--passes", "2"), "--floor");
    expect_fail(ARGS("bench", "builtin", "--gap", "-1"), "--gap -1: expected 0 to 1000");
    expect_fail(ARGS("bench", "builtin", "--gap", "1001"), "--gap 1001: expected 0 to 1000");
    expect_fail(ARGS("bench", "builtin", "--gap", "x"), "--gap x");
    expect_fail(ARGS("bench", "--floor", "--gap", "3"), "--floor");
    expect_fail(ARGS("bench", "--floor", "--cold"), "--floor");
    expect_fail(ARGS("bench", "builtin", "--cold=yes"), "--cold");
    expect_fail(ARGS("bench", "nosuchmap", "--data", tmpdir), "nosuchmap");
    expect_fail(ARGS("bench", tmp_path(path, "no-such.bsp")), "no-such.bsp");
    expect_fail(ARGS("bench", "builtin", "--out", tmp_path(path, "nodir/x.jsonl")), "nodir");
}

int main(void) {
    cli = getenv("EW_CLI");
    if (!cli || !*cli || access(cli, X_OK) != 0) {
        fprintf(stderr, "EW_CLI is not set to the edgewise binary (run through ctest)\n");
        return 1;
    }
    const char *t = getenv("TMPDIR");
    snprintf(tmpdir, sizeof tmpdir, "%s/ew_bench_XXXXXX", t && *t ? t : "/tmp");
    if (!mkdtemp(tmpdir)) {
        perror("mkdtemp");
        return 1;
    }
    test_start();
    test_builtin();
    test_cold();
    test_simd();
    test_bad_args();
    char path[512];
    remove(tmp_path(path, "stdout.txt"));
    remove(tmp_path(path, "stderr.txt"));
    rmdir(tmpdir);
    return ew_t_finish();
}
