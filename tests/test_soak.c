/*
 * `edgewise soak` (path in EW_CLI): a short soak of the built-in scene and
 * of start and e1m1 (when ../shared is there) must find no anomaly and
 * report what it rendered in its JSON line, and so must start in painter's
 * order under fog (each pixel fogged once); bad arguments exit 2 with one
 * error line.  Under `make test-asan` this is also the sanitizers' soak.
 */
#define _POSIX_C_SOURCE 200809L
#include "util.h"

#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#define FRAMES 200

typedef ew_t_run run_result;
static char tmpdir[256];

/* Runs EW_CLI with args (NULL-terminated), no shell, in a scratch folder. */
static void run(run_result *r, const char *const *args) { ew_t_run_cli(r, tmpdir, args); }

/* The number after "key": in the JSON line, NAN if absent. */
static double json_num(const char *json, const char *key) { return ew_t_json_num(json, key); }

static void soak_ok(const char *map, const char *data) {
    char frames[16];
    snprintf(frames, sizeof frames, "%d", FRAMES);
    run_result *r = malloc(sizeof *r);
    const char *const with_data[] = {"soak", map, "--data", data, "--frames", frames, "--size", "320x200", NULL};
    const char *const without[] = {"soak", map, "--frames", frames, "--seed", "7", NULL};
    run(r, data ? with_data : without);
    CHECK(r->status == 0, "soak %s: exit %d, stderr: %s, stdout: %s", map, r->status, r->err, r->out);
    CHECK(r->out[0] == '{' && strchr(r->out, '\n') == strrchr(r->out, '\n') &&
              r->out[strlen(r->out) - 1] == '\n',
          "soak %s: want one JSON line, got: %s", map, r->out);
    double n = json_num(r->out, "frames"), views = json_num(r->out, "view_frames"),
           rnd = json_num(r->out, "random_frames");
    CHECK(n == FRAMES, "soak %s: frames %g", map, n);
    CHECK(views + rnd == FRAMES && rnd >= FRAMES / 2, "soak %s: %g view + %g random frames", map, views, rnd);
    CHECK(json_num(r->out, "anomalies") == 0, "soak %s: anomalies in %s", map, r->out);
    CHECK(json_num(r->out, "in_solid") >= 0, "soak %s: no in_solid count", map);
    CHECK(json_num(r->out, "fps") > 0, "soak %s: fps %g", map, json_num(r->out, "fps"));
    CHECK(json_num(r->out, "peak_rss_kb") > 0, "soak %s: no peak memory", map);
    CHECK(json_num(r->out, "width") == 320 && json_num(r->out, "height") == 200, "soak %s: size", map);
    printf("%s\n", r->out);
    free(r);
}

/* Painter's order with fog: each pixel fogged once (soak's fog check; the
 * fog pass once fogged a pixel again under each polygon drawn over it). */
static void soak_painter_fog(const char *data) {
    run_result *r = malloc(sizeof *r);
    const char *const args[] = {"soak", "start", "--data", data, "--frames", "40", "--size", "320x200",
                                "--hsr", "painter", "--fog", "0.1,0.3,0.3,0.35", NULL};
    run(r, args);
    CHECK(r->status == 0, "soak start --hsr painter --fog: exit %d, stderr: %s", r->status, r->err);
    CHECK(json_num(r->out, "anomalies") == 0, "soak painter fog: anomalies in %s", r->out);
    CHECK(json_num(r->out, "fog_frames") == 40, "soak painter fog: fog_frames %g", json_num(r->out, "fog_frames"));
    CHECK(strstr(r->out, "\"checks\":\"pixels,drops,fog\"") != NULL, "soak painter fog: checks in %s", r->out);
    free(r);
}

static void soak_fails(const char *const *args, int status, const char *needle) {
    run_result *r = malloc(sizeof *r);
    run(r, args);
    CHECK(r->status == status, "soak %s: exit %d (want %d), stderr: %s", args[1], r->status, status, r->err);
    CHECK(strncmp(r->err, "edgewise: ", 10) == 0 && strchr(r->err, '\n') == strrchr(r->err, '\n'),
          "want one error line, got: %s", r->err);
    CHECK(strstr(r->err, needle) != NULL, "'%s' not in: %s", needle, r->err);
    CHECK(r->out[0] == '\0', "stdout should be empty: %s", r->out);
    free(r);
}

int main(void) {
    if (!getenv("EW_CLI")) {
        fprintf(stderr, "EW_CLI not set\n");
        return 1;
    }
    snprintf(tmpdir, sizeof tmpdir, "/tmp/ew_soak_XXXXXX");
    if (!mkdtemp(tmpdir)) {
        fprintf(stderr, "cannot make a scratch folder\n");
        return 1;
    }
    soak_ok("builtin", NULL);
    const char *data = ew_t_shared("data/librequake");
    if (ew_t_need_shared("data/librequake/maps/start.bsp")) {
        soak_ok("start", data);
        soak_ok("e1m1", data);
        soak_painter_fog(data);
    }

    soak_fails((const char *const[]){"soak", "builtin", NULL}, 2, "--frames");
    soak_fails((const char *const[]){"soak", "builtin", "--frames", "0", NULL}, 2, "--frames");
    soak_fails((const char *const[]){"soak", "builtin", "--frames", "10", "--size", "10x10", NULL}, 2, "--size");
    soak_fails((const char *const[]){"soak", "builtin", "--frames", "10", "--seed", "-1", NULL}, 2, "--seed");
    soak_fails((const char *const[]){"soak", "builtin", "--frames", "10", "--bogus", NULL}, 2, "--bogus");
    soak_fails((const char *const[]){"soak", "--frames", "10", NULL}, 2, "MAP");
    soak_fails((const char *const[]){"soak", "/nonexistent/x.bsp", "--frames", "10", NULL}, 1, "x.bsp");
    char path[300];
    snprintf(path, sizeof path, "%s/stdout.txt", tmpdir), unlink(path);
    snprintf(path, sizeof path, "%s/stderr.txt", tmpdir), unlink(path);
    rmdir(tmpdir);
    return ew_t_finish();
}
