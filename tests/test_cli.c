/*
 * The `edgewise` command (path in EW_CLI, set by CMake): bad arguments and
 * bad files must fail with one line on stderr that names the problem, never
 * crash.  Success cases go through expect_ok (see test_success).
 */
#define _POSIX_C_SOURCE 200809L
#include "edgewise_lab.h"
#include "util.h"

#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

static const char *cli;
static char tmpdir[256];

typedef ew_t_run run_result;

/* Path of name in tmpdir, in the caller's buffer (512 bytes). */
static char *tmp_path(char out[512], const char *name) {
    snprintf(out, 512, "%s/%s", tmpdir, name);
    return out;
}

/* Runs EW_CLI with args (NULL-terminated), no shell, in tmpdir. */
static void run(run_result *r, const char *const *args) { ew_t_run_cli(r, tmpdir, args); }

static int count_lines(const char *s) { return ew_t_count_lines(s); }

static void describe(char *buf, size_t size, const char *const *args) {
    size_t used = 0;
    buf[0] = '\0';
    for (; *args && used < size; args++)
        used += (size_t)snprintf(buf + used, size - used, " %s", *args);
}

/* The command fails cleanly: a normal non-zero exit, exactly one line
 * "edgewise: ..." on stderr containing every string in needles. */
static void expect_fail_(int line, const char *const *args, const char *const *needles,
                         run_result *r) {
    char cmd[1024];
    describe(cmd, sizeof cmd, args);
    run(r, args);
    CHECK(r->signal == 0, "line %d:%s: killed by signal %d", line, cmd, r->signal);
    CHECK(r->status > 0 && r->status < 126, "line %d:%s: exit %d", line, cmd, r->status);
    CHECK(count_lines(r->err) == 1 && r->err[strlen(r->err) - 1] == '\n',
          "line %d:%s: want one stderr line, got:\n%s", line, cmd, r->err);
    CHECK(strncmp(r->err, "edgewise: ", 10) == 0 && strlen(r->err) > 12,
          "line %d:%s: stderr '%s'", line, cmd, r->err);
    for (; needles && *needles; needles++)
        CHECK(strstr(r->err, *needles) != NULL, "line %d:%s: '%s' not in: %s", line, cmd,
              *needles, r->err);
}

#define ARGS(...) ((const char *const[]){ __VA_ARGS__, NULL })
#define NEEDS(...) ((const char *const[]){ __VA_ARGS__, NULL })
#define expect_fail(args, needles)                                                   \
    do {                                                                             \
        run_result *r_ = malloc(sizeof *r_);                                         \
        expect_fail_(__LINE__, args, needles, r_);                                   \
        free(r_);                                                                    \
    } while (0)

/* The command succeeds: exit 0, nothing on stderr but "wrote ..." lines
 * (and the map's "edgewise: warning: ..." lines).
 * Returns the result (caller frees) for further checks on r->out. */
static run_result *expect_ok_(int line, const char *const *args) {
    char cmd[1024];
    describe(cmd, sizeof cmd, args);
    run_result *r = malloc(sizeof *r);
    run(r, args);
    CHECK(r->signal == 0 && r->status == 0, "line %d:%s: exit %d signal %d, stderr: %s", line,
          cmd, r->status, r->signal, r->err);
    for (const char *p = r->err; *p; p = strchr(p, '\n') ? strchr(p, '\n') + 1 : p + strlen(p))
        CHECK(strncmp(p, "wrote ", 6) == 0 || strncmp(p, "edgewise: warning: ", 19) == 0,
              "line %d:%s: stderr: %s", line, cmd, r->err);
    return r;
}
#define expect_ok(args) expect_ok_(__LINE__, args)

static void write_file(const char *path, const void *data, size_t size) {
    FILE *f = fopen(path, "wb");
    if (f) {
        fwrite(data, 1, size, f);
        fclose(f);
    }
}

static void test_usage(void) {
    run_result *r = malloc(sizeof *r);
    run(r, ARGS("--help"));
    CHECK(r->status == 0 && strstr(r->out, "usage: edgewise") && !r->err[0], "--help: %d %s",
          r->status, r->err);
    run(r, ARGS("help"));
    CHECK(r->status == 0 && strstr(r->out, "render MAP"), "help: %d", r->status);
    run(r, ARGS("render", "--help"));
    CHECK(r->status == 0 && strstr(r->out, "--size"), "render --help: %d", r->status);
    run(r, ARGS("--version"));
    CHECK(r->status == 0 && strncmp(r->out, "edgewise ", 9) == 0, "--version: %s", r->out);
    free(r);

    r = malloc(sizeof *r);
    expect_fail_(__LINE__, (const char *const[]){ NULL }, NEEDS("missing command"), r);
    free(r);
    expect_fail(ARGS("frobnicate"), NEEDS("frobnicate", "unknown command"));
    expect_fail(ARGS("render"), NEEDS("missing MAP"));
    expect_fail(ARGS("render", "builtin", "--size", "10x10"), NEEDS("--size", "10x10", "range"));
    expect_fail(ARGS("render", "builtin", "--size", "7681x480"), NEEDS("7681x480"));
    expect_fail(ARGS("render", "builtin", "--size", "640x4321"), NEEDS("640x4321"));
    expect_fail(ARGS("render", "builtin", "--size", "abc"), NEEDS("--size", "abc"));
    expect_fail(ARGS("render", "builtin", "--size", "640x"), NEEDS("640x"));
    expect_fail(ARGS("render", "builtin", "--size", "640x480x3"), NEEDS("640x480x3"));
    expect_fail(ARGS("render", "builtin", "--size", "99999999999999999999x480"), NEEDS("--size"));
    expect_fail(ARGS("render", "builtin", "--size"), NEEDS("--size", "needs a value"));
    expect_fail(ARGS("render", "builtin", "--view", "-1"), NEEDS("--view", "-1"));
    expect_fail(ARGS("render", "builtin", "--view", "1.5"), NEEDS("--view", "1.5"));
    expect_fail(ARGS("render", "builtin", "--view", ""), NEEDS("--view"));
    expect_fail(ARGS("render", "builtin", "--fov", "179"), NEEDS("--fov", "179"));
    expect_fail(ARGS("render", "builtin", "--fov", "1"), NEEDS("--fov"));
    expect_fail(ARGS("render", "builtin", "--fov", "nan"), NEEDS("--fov", "nan"));
    expect_fail(ARGS("render", "builtin", "--fov", "90deg"), NEEDS("--fov", "90deg"));
    expect_fail(ARGS("render", "builtin", "--time", "inf"), NEEDS("--time", "inf"));
    expect_fail(ARGS("render", "builtin", "--time", "-1"), NEEDS("--time"));
    expect_fail(ARGS("render", "builtin", "--pos", "1,2,3"), NEEDS("--angles"));
    expect_fail(ARGS("render", "builtin", "--angles", "1,2,3"), NEEDS("--pos"));
    expect_fail(ARGS("render", "builtin", "--pos", "1,2", "--angles", "0,0,0"), NEEDS("1,2"));
    expect_fail(ARGS("render", "builtin", "--pos", "1,2,3,4", "--angles", "0,0,0"),
                NEEDS("1,2,3,4"));
    expect_fail(ARGS("render", "builtin", "--pos", "1,x,3", "--angles", "0,0,0"), NEEDS("1,x,3"));
    expect_fail(ARGS("render", "builtin", "--pos", "1,2,3", "--angles", "0,1e300,0"),
                NEEDS("--angles"));
    expect_fail(ARGS("render", "builtin", "--pos", "0,0,0", "--angles", "0,0,0", "--view", "1"),
                NEEDS("--view"));
    expect_fail(ARGS("render", "builtin", "--wibble"), NEEDS("--wibble"));
    expect_fail(ARGS("render", "builtin", "--stats=yes"), NEEDS("--stats"));
    expect_fail(ARGS("render", "builtin", "extra"), NEEDS("extra"));
    expect_fail(ARGS("views", "builtin", "--size", "640x480"), NEEDS("--size"));
    expect_fail(ARGS("info"), NEEDS("missing MAP"));
    expect_fail(ARGS("demo", "builtin"), NEEDS("builtin"));
    /* Control characters in an argument cannot break the one-line rule. */
    expect_fail(ARGS("render", "builtin", "--size", "64\n0x480"), NEEDS("--size"));
}

static void test_bad_files(void) {
    char missing[512], trunc[512], text[512];
    tmp_path(missing, "no-such-map.bsp");
    tmp_path(trunc, "truncated.bsp");
    tmp_path(text, "notabsp.bsp");
    expect_fail(ARGS("render", missing), NEEDS(missing));
    expect_fail(ARGS("info", missing), NEEDS(missing));
    expect_fail(ARGS("views", missing), NEEDS(missing));
    expect_fail(ARGS("render", "nosuchmap", "--data", tmpdir), NEEDS("nosuchmap"));

    /* A BSP29 header that promises lumps far beyond the file's end. */
    unsigned char head[4 + 15 * 8 + 20];
    memset(head, 0, sizeof head);
    head[0] = 29;
    for (int i = 0; i < 15; i++) {
        head[4 + 8 * i + 0] = 0x00;
        head[4 + 8 * i + 1] = 0x10;   /* offset 4096 */
        head[4 + 8 * i + 5] = 0x01;   /* length 256 */
    }
    write_file(trunc, head, sizeof head);
    expect_fail(ARGS("render", trunc), NEEDS("truncated.bsp"));
    expect_fail(ARGS("info", trunc), NEEDS("truncated.bsp"));
    expect_fail(ARGS("views", trunc), NEEDS("truncated.bsp"));

    /* Only half a header. */
    write_file(trunc, head, 30);
    expect_fail(ARGS("info", trunc), NEEDS("truncated.bsp"));

    const char msg[] = "this is a text file, not a BSP\n";
    write_file(text, msg, sizeof msg - 1);
    expect_fail(ARGS("render", text), NEEDS("notabsp.bsp"));
    expect_fail(ARGS("info", text), NEEDS("notabsp.bsp"));

    write_file(text, "", 0);
    expect_fail(ARGS("info", text), NEEDS("notabsp.bsp"));

    /* A directory where a map should be. */
    expect_fail(ARGS("info", tmpdir), NEEDS(tmpdir));

    remove(trunc);
    remove(text);
}

/* The shared e1m1 as an absolute path (the CLI runs in tmpdir); 0, or -1
 * after a failed CHECK when ../shared lacks it. */
static int shared_e1m1(char map[2048]) {
    const char *rel = "data/librequake/maps/e1m1.bsp";
    if (!ew_t_need_shared(rel)) return -1;
    snprintf(map, 2048, "%s", ew_t_shared_abs(rel));
    return 0;
}

/* View numbers beyond the map's view set, and outputs that cannot be
 * written, need a loadable map: the shared e1m1 (29 views). */
static void test_with_map(void) {
    char map[2048];
    if (shared_e1m1(map) < 0) return;
    run_result *r = malloc(sizeof *r);
    expect_fail_(__LINE__, ARGS("render", map, "--view", "999"), NULL, r);
    CHECK(strstr(r->err, "999") && strstr(r->err, "29 views"), "view 999: %s", r->err);
    expect_fail_(__LINE__, ARGS("render", map, "--view", "29"), NULL, r);
    CHECK(strstr(r->err, "29") && strstr(r->err, "29 views"), "view 29: %s", r->err);
    free(r);
}

/* Every ew_stats field and the frame's description are in the JSON. */
static void check_stats_json(const char *what, const char *out) {
    static const char *const keys[] = {
        "map", "width", "height", "view", "pixels", "pixels_written", "pixels_covered",
        "overdraw", "edges", "edges_cached", "surfaces", "surfaces_shown", "spans", "surfaces_built",
        "surfaces_cached", "visible_leaves", "dropped", "entities_hidden", "ms_front", "ms_scan", "ms_draw",
        "ms_total", "ms_serial",
    };
    CHECK(out[0] == '{' && count_lines(out) == 1 && strstr(out, "}\n"), "%s: stdout: %s", what,
          out);
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++) {
        char key[64];
        snprintf(key, sizeof key, "\"%s\":", keys[i]);
        CHECK(strstr(out, key) != NULL, "%s: %s missing from %s", what, key, out);
    }
}

static void check_png(const char *what, const char *path, int w, int h) {
    uint8_t *rgb = NULL;
    int rw = 0, rh = 0;
    ew_error err = { "" };
    CHECK(ew_read_png_rgb(path, &rgb, &rw, &rh, &err) == 0, "%s: %s", what, err.msg);
    CHECK(rw == w && rh == h, "%s: %dx%d, want %dx%d", what, rw, rh, w, h);
    free(rgb);
    remove(path);
}

/* Commands that succeed, on the shared e1m1 and the built-in scene. */
static void test_success(void) {
    char map[2048];
    if (shared_e1m1(map) < 0) return;

    run_result *r = expect_ok(ARGS("views", map));
    CHECK(count_lines(r->out) == 29 && strncmp(r->out, "0 ", 2) == 0, "views: %s", r->out);
    free(r);
    r = expect_ok(ARGS("info", map));
    CHECK(strstr(r->out, "version   29") && strstr(r->out, "entities") &&
              strstr(r->out, "models") && strstr(r->out, "missing"), "info: %s", r->out);
    free(r);

    char png[512], path[512];
    tmp_path(png, "e1m1.png");
    {
        r = expect_ok(ARGS("render", map, "--view=28", "--size=320x200", "--out", png, "--stats"));
        check_stats_json("render --stats", r->out);
        CHECK(strstr(r->out, "\"view\":28,") && strstr(r->out, "\"pixels\":64000,") &&
                  strstr(r->out, "\"map\":\"e1m1\""), "stats: %s", r->out);
        CHECK(strstr(r->err, "wrote ") != NULL, "no 'wrote' line: %s", r->err);
        free(r);
        check_png("render", png, 320, 200);

        /* Default names, in the working directory (tmpdir). */
        r = expect_ok(ARGS("render", map, "--view", "2", "--size", "320x200"));
        CHECK(!r->out[0], "stdout without --stats: %s", r->out);
        free(r);
        check_png("default name", tmp_path(path, "e1m1_v2.png"), 320, 200);
        r = expect_ok(ARGS("render", map, "--pos", "464,2048,-178", "--angles", "10,45,0",
                           "--fov", "100", "--time", "1.5", "--size", "400x300", "--stats"));
        check_stats_json("free camera", r->out);
        CHECK(strstr(r->out, "\"view\":null") && strstr(r->out, "\"fov\":100"), "free: %s",
              r->out);
        free(r);
        check_png("free camera", tmp_path(path, "e1m1_free.png"), 400, 300);

        tmp_path(png, "demo.png");
        r = malloc(sizeof *r);
        run(r, ARGS("demo", "--out", png, "--size", "320x200", "--stats"));
        CHECK(r->status == 0, "demo: exit %d: %s", r->status, r->err);
        check_stats_json("demo", r->out);
        check_png("demo", png, 320, 200);
        free(r);
    }
}

int main(void) {
    cli = getenv("EW_CLI");
    if (!cli || !*cli || access(cli, X_OK) != 0) {
        fprintf(stderr, "EW_CLI is not set to the edgewise binary (run through ctest)\n");
        return 1;
    }
    const char *t = getenv("TMPDIR");
    snprintf(tmpdir, sizeof tmpdir, "%s/ew_cli_XXXXXX", t && *t ? t : "/tmp");
    if (!mkdtemp(tmpdir)) {
        perror("mkdtemp");
        return 1;
    }
    test_usage();
    test_bad_files();
    test_with_map();
    test_success();
    char path[512];
    remove(tmp_path(path, "stdout.txt"));
    remove(tmp_path(path, "stderr.txt"));
    rmdir(tmpdir);
    return ew_t_finish();
}
