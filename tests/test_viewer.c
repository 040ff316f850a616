/*
 * test_viewer.c - edgewise view under a real X server.
 *
 * Starts its own Xvfb on a free display (from :90 up) and kills it at the
 * end (an alarm bounds the whole test and kills what it started):
 *   - a script visiting views and taking screenshots gives PNGs equal pixel
 *     for pixel to `edgewise render` of the same cameras, size and time;
 *   - the overlay changes the frame in its corner only; a debug key changes it;
 *   - walk mode (script-held keys): walking into a wall stops short of it,
 *     gravity lands the player on the floor (checked with ew_trace);
 *   - real input: xdotool key and mouse events move and turn the camera
 *     (from the --record file);
 *   - real input in walk mode on the built-in map: F drops the player onto
 *     the floor, W stops at a wall 16 units short and climbs stairs step
 *     by step (the recorded path against point traces of the map);
 *   - H cycles the available hidden-surface methods;
 *   - without a display, view says so in one line and fails; so it does
 *     with DISPLAY naming no X server (issue 33: SDL fell back to its
 *     offscreen driver and the viewer rendered to nothing until killed);
 *     a bad --present value is refused;
 *   - view --demo: the demo's camera at the script's time (a screenshot
 *     equal to render of its camera), [ and ] seek, G frees the camera;
 *   - T cycles the threads 1, 2, all cores (issue 33: stuck at 1 after
 *     --threads 1); keys 0-9 go to views 0-9, counted from 0 as --view.
 * In a build without SDL2, only that `view` says it was built without it.
 */
#define _POSIX_C_SOURCE 200809L
#include "edgewise.h"
#include "edgewise_lab.h"
#include "util.h"

#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#ifdef EW_HAVE_SDL2
static const char *cli(void) { return getenv("EW_CLI") ? getenv("EW_CLI") : "./edgewise"; }

static volatile pid_t xvfb_pid = -1, viewer_pid = -1;

static void kill_started(void) {
    if (viewer_pid > 0) kill(viewer_pid, SIGKILL);
    if (xvfb_pid > 0) kill(xvfb_pid, SIGTERM);
}

static void on_alarm(int sig) {
    (void)sig;
    static const char msg[] = "FAIL test_viewer: time limit, killing Xvfb and the viewer\n";
    if (write(2, msg, sizeof msg - 1) < 0) { /* nothing to do */ }
    kill_started();
    _exit(1);
}

static int file_exists(const char *p) {
    struct stat s;
    return stat(p, &s) == 0;
}

static int have_tool(const char *name) {
    char p[256];
    const char *dirs[] = { "/usr/bin", "/usr/local/bin", "/bin" };
    for (int i = 0; i < 3; i++) {
        snprintf(p, sizeof p, "%s/%s", dirs[i], name);
        if (access(p, X_OK) == 0) return 1;
    }
    return 0;
}

static void sleep_ms(int ms) {
    struct timespec ts = { ms / 1000, (long)(ms % 1000) * 1000000L };
    nanosleep(&ts, NULL);
}

/* Xvfb on the first free display from :90; the display number or -1. */
static int start_xvfb(void) {
    for (int d = 90; d < 130; d++) {
        char lock[64], sock[64], disp[16];
        snprintf(lock, sizeof lock, "/tmp/.X%d-lock", d);
        snprintf(sock, sizeof sock, "/tmp/.X11-unix/X%d", d);
        if (file_exists(lock) || file_exists(sock)) continue;
        snprintf(disp, sizeof disp, ":%d", d);
        pid_t pid = fork();
        if (pid == 0) {
            freopen("/dev/null", "w", stdout);
            freopen("/dev/null", "w", stderr);
            execlp("Xvfb", "Xvfb", disp, "-screen", "0", "1280x1024x24", "-nolisten", "tcp", (char *)NULL);
            _exit(127);
        }
        if (pid < 0) return -1;
        xvfb_pid = pid;
        for (int i = 0; i < 100; i++) {
            int st;
            if (waitpid(pid, &st, WNOHANG) == pid) { xvfb_pid = -1; break; }
            if (file_exists(sock)) {
                sleep_ms(200);
                return d;
            }
            sleep_ms(50);
        }
        if (xvfb_pid > 0) { kill(pid, SIGTERM); waitpid(pid, NULL, 0); xvfb_pid = -1; }
    }
    return -1;
}

static void stop_xvfb(void) {
    if (xvfb_pid > 0) {
        kill(xvfb_pid, SIGTERM);
        waitpid(xvfb_pid, NULL, 0);
        xvfb_pid = -1;
    }
}

static int run_tool(const char *const *args) {
    fflush(stdout);  /* not twice: a child's freopen would flush the copy */
    pid_t pid = fork();
    if (pid == 0) {
        freopen("/dev/null", "w", stdout);
        execvp(args[0], (char *const *)args);
        _exit(127);
    }
    int st = 0;
    waitpid(pid, &st, 0);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static void write_text(const char *path, const char *text) {
    FILE *f = fopen(path, "w");
    if (f) { fputs(text, f); fclose(f); }
}

/* PNG as RGB; 0 or -1. */
static uint8_t *read_png(const char *path, int *w, int *h) {
    uint8_t *rgb = NULL;
    ew_error err;
    if (ew_read_png_rgb(path, &rgb, w, h, &err) < 0) {
        fprintf(stderr, "%s\n", err.msg);
        return NULL;
    }
    return rgb;
}

/* Last line of a record file: time x y z pitch yaw roll; lines read or 0. */
static int record_lines(const char *path, double first[7], double last[7]) {
    FILE *f = fopen(path, "r");
    if (!f) return 0;
    int n = 0;
    double v[7];
    while (fscanf(f, "%lf %lf %lf %lf %lf %lf %lf", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5], &v[6]) == 7) {
        if (n == 0) memcpy(first, v, sizeof v);
        memcpy(last, v, sizeof v);
        n++;
    }
    fclose(f);
    return n;
}

static char tmpdir[256];
static const char *tpath(const char *name) {
    static char buf[4][512];
    static int k;
    k = (k + 1) % 4;
    snprintf(buf[k], sizeof buf[k], "%s/%s", tmpdir, name);
    return buf[k];
}

/* view --demo: a screenshot 10 s into demo3 without its moving things is
 * `edgewise render` of the camera it printed; ] moves the demo 5 s on, [
 * back (read again from the start), G frees the camera. */
static void test_demo(void) {
    if (!ew_t_need_shared("data/demos/demo3.dem") || !ew_t_need_shared("data/librequake/progs/player.mdl")) return;
    char demos[512], lq[512], dem[600];
    snprintf(demos, sizeof demos, "%s", ew_t_shared_abs("data/demos"));
    snprintf(lq, sizeof lq, "%s", ew_t_shared_abs("data/librequake"));
    snprintf(dem, sizeof dem, "%s/demo3.dem", demos);
    char script[1024];
    snprintf(script, sizeof script,
             "at 10 screenshot %s\nat 10.1 key ]\nat 10.2 screenshot %s\nat 10.3 key [\nat 10.3 key [\n"
             "at 10.4 screenshot %s\nat 10.5 key G\nat 10.6 quit\n", tpath("d0.png"), tpath("d1.png"), tpath("d2.png"));
    write_text(tpath("d.script"), script);
    ew_t_run r;
    const char *args[] = { "view", "--demo", dem, "--game", demos, "--data", lq, "--size", "320x240", "--no-entities",
                           "--threads", "1", "--script", tpath("d.script"), NULL };
    ew_t_run_cli(&r, tmpdir, args);
    CHECK(r.status == 0 && ew_t_count_lines(r.out) == 3, "view --demo: status %d: %s %s", r.status, r.out, r.err);
    CHECK(strstr(r.err, "demo: 15.1 s") && strstr(r.err, "demo: 10.3 s") && strstr(r.err, "demo: 5.3 s") &&
          strstr(r.err, "camera: free"),
          "] and [ move the demo, G frees the camera: %s", r.err);
    const char *line = r.out;
    double times[3] = {0, 0, 0};
    for (int idx = 0; idx < 3 && *line; idx++) {
        char path[512], pos[128], ang[128], tm[64], size[32];
        if (sscanf(line, "%511s --pos %127s --angles %127s --time %63s --size %31s", path, pos, ang, tm, size) != 5) {
            CHECK(0, "screenshot line: %s", line);
            break;
        }
        times[idx] = atof(tm);
        char out[600];
        snprintf(out, sizeof out, "%s/drender%d.png", tmpdir, idx);
        ew_t_run rr;
        const char *rargs[] = { "render", "lqdm3", "--game", demos, "--data", lq, "--pos", pos, "--angles", ang,
                                "--time", tm, "--size", size, "--no-entities", "--threads", "1", "--out", out, NULL };
        ew_t_run_cli(&rr, tmpdir, rargs);
        CHECK(rr.status == 0, "render: %s", rr.err);
        int w1, h1, w2, h2;
        uint8_t *p1 = read_png(path, &w1, &h1), *p2 = read_png(out, &w2, &h2);
        if (p1 && p2 && w1 == w2 && h1 == h2) {
            long diff = 0;
            for (long i = 0; i < (long)w1 * h1 * 3; i++) diff += p1[i] != p2[i];
            CHECK(diff == 0, "demo screenshot %d differs from render of its camera in %ld bytes", idx, diff);
        } else {
            CHECK(0, "demo screenshot %d: %s and %s", idx, path, out);
        }
        free(p1);
        free(p2);
        const char *nl = strchr(line, '\n');
        line = nl ? nl + 1 : line + strlen(line);
    }
    CHECK(fabs(times[0] - 426.466) < 0.01 && fabs(times[1] - 431.666) < 0.01 && fabs(times[2] - 421.866) < 0.01,
          "the demo's times: 10 s in, 5 s on, 10 s back (%.3f %.3f %.3f)", times[0], times[1], times[2]);
}

static void test_script_matches_render(const char *data) {
    ew_assets *a = ew_t_load_map("e1m1");
    if (!a) return;
    ew_camera views[EW_MAX_VIEWS];
    int n = ew_benchmark_views(a->world, views);
    CHECK(n >= 3, "e1m1 has %d views", n);
    char script[2048];
    snprintf(script, sizeof script,
             "# visit views, take screenshots\n"
             "at 0 view 0\nat 0.5 screenshot %s\n"
             "at 1 camera %g,%g,%g %g,%g,%g\nat 1 screenshot %s\n"
             "at 1.5 view 2\nat 1.5 screenshot %s\nat 1.6 quit\n",
             tpath("s0.png"), views[1].origin[0], views[1].origin[1], views[1].origin[2], views[1].angles[0],
             views[1].angles[1], views[1].angles[2], tpath("s1.png"), tpath("s2.png"));
    write_text(tpath("a.script"), script);
    ew_t_run r;
    const char *args[] = { "view", "e1m1", "--data", data, "--size", "640x480", "--threads", "0",
                           "--script", tpath("a.script"), NULL };
    ew_t_run_cli(&r, tmpdir, args);
    CHECK(r.status == 0, "view script: status %d: %s", r.status, r.err);
    CHECK(ew_t_count_lines(r.out) == 3, "three screenshot lines: %s", r.out);
    /* Each line: PATH --pos X,Y,Z --angles P,Y,R --time T --size WxH: render it again. */
    const char *line = r.out;
    int idx = 0;
    while (*line && idx < 3) {
        char path[512], pos[128], ang[128], tm[64], size[32];
        if (sscanf(line, "%511s --pos %127s --angles %127s --time %63s --size %31s", path, pos, ang, tm, size) != 5) {
            CHECK(0, "screenshot line: %s", line);
            break;
        }
        char out[600];
        snprintf(out, sizeof out, "%s/render%d.png", tmpdir, idx);
        ew_t_run rr;
        const char *rargs[] = { "render", "e1m1", "--data", data, "--pos", pos, "--angles", ang,
                                "--time", tm, "--size", size, "--threads", "1", "--out", out, NULL };
        ew_t_run_cli(&rr, tmpdir, rargs);
        CHECK(rr.status == 0, "render: %s", rr.err);
        int w1, h1, w2, h2;
        uint8_t *p1 = read_png(path, &w1, &h1), *p2 = read_png(out, &w2, &h2);
        CHECK(p1 && p2 && w1 == 640 && h1 == 480 && w2 == w1 && h2 == h1, "screenshot %d sizes", idx);
        if (p1 && p2 && w1 == w2 && h1 == h2) {
            long diff = 0;
            for (long i = 0; i < (long)w1 * h1 * 3; i++) diff += p1[i] != p2[i];
            CHECK(diff == 0, "screenshot %d (%s) differs from render in %ld bytes", idx, path, diff);
        }
        free(p1);
        free(p2);
        const char *nl = strchr(line, '\n');
        line = nl ? nl + 1 : line + strlen(line);
        idx++;
    }
    /* The second shot used the script's camera exactly. */
    CHECK(strstr(r.out, "--time 1 ") != NULL, "screenshot at time 1: %s", r.out);
    ew_assets_destroy(a);
}

static void test_overlay_and_debug(const char *data) {
    char script[2048];
    snprintf(script, sizeof script,
             "at 0 key P\nat 0.1 screenshot %s\nat 0.15 key Tab\nat 0.2 screenshot %s\nat 0.25 key Tab\n"
             "at 0.25 key F3\nat 0.3 screenshot %s\nat 0.35 key F3\nat 0.4 screenshot %s\nat 0.5 quit\n",
             tpath("o0.png"), tpath("o1.png"), tpath("d1.png"), tpath("d0.png"));
    write_text(tpath("o.script"), script);
    ew_t_run r;
    const char *args[] = { "view", "e1m1", "--data", data, "--size", "640x480", "--script",
                           tpath("o.script"), NULL };
    ew_t_run_cli(&r, tmpdir, args);
    CHECK(r.status == 0, "overlay script: %s", r.err);
    int w, h, w1, h1, w2, h2, w3, h3;
    uint8_t *o0 = read_png(tpath("o0.png"), &w, &h), *o1 = read_png(tpath("o1.png"), &w1, &h1);
    uint8_t *d1 = read_png(tpath("d1.png"), &w2, &h2), *d0 = read_png(tpath("d0.png"), &w3, &h3);
    if (o0 && o1 && d0 && d1 && w == 640 && w1 == 640 && w2 == 640 && w3 == 640) {
        long inside = 0, outside = 0, dbg = 0;
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                long i = ((long)y * w + x) * 3;
                int d = memcmp(o0 + i, o1 + i, 3) != 0;
                if (x < w / 2 && y < h / 2) inside += d;
                else outside += d;
                dbg += memcmp(d0 + i, d1 + i, 3) != 0;
            }
        CHECK(inside > 1000, "overlay drew %ld pixels in the top-left corner", inside);
        CHECK(outside == 0, "overlay changed %ld pixels outside its corner", outside);
        CHECK(dbg > (long)w * h / 4, "F3 (overdraw) changed only %ld pixels", dbg);
        CHECK(memcmp(o0, d0, (size_t)w * h * 3) == 0, "F3 again gives the normal frame back");
    } else {
        CHECK(0, "overlay/debug screenshots missing");
    }
    free(o0); free(o1); free(d0); free(d1);
}

/* T from --threads 1: 1, 2, all cores, round again (issue 33); keys 0-9
 * are views 0-9 (counted from 0 as --view and `edgewise views`). */
static void test_threads_and_view_keys(void) {
    ew_error err = { "" };
    ew_assets *a = ew_assets_create_builtin(&err);
    CHECK(a != NULL, "builtin: %s", err.msg);
    if (!a) return;
    ew_renderer *rd = ew_renderer_create(&(ew_renderer_desc){ .world = a->world, .palette = a->palette,
            .colormap = a->colormap, .width = 320, .height = 200, .threads = 0 }, &err);
    int cores = rd ? ew_get_threads(rd) : 1;
    ew_renderer_destroy(rd);
    char want[256];
    if (cores > 2)
        snprintf(want, sizeof want, "threads: 2\nthreads: %d (all cores)\nthreads: 1\nthreads: 2\n", cores);
    else if (cores == 2)
        snprintf(want, sizeof want, "threads: 2 (all cores)\nthreads: 1\nthreads: 2 (all cores)\nthreads: 1\n");
    else
        snprintf(want, sizeof want, "threads: 1 (all cores)\nthreads: 1 (all cores)\nthreads: 1 (all cores)\n");
    write_text(tpath("t.script"), "at 0 key T\nat 0.1 key T\nat 0.2 key T\nat 0.3 key T\nat 0.4 quit\n");
    ew_t_run r;
    const char *args[] = { "view", "builtin", "--size", "320x240", "--threads", "1", "--script", tpath("t.script"),
                           NULL };
    ew_t_run_cli(&r, tmpdir, args);
    CHECK(r.status == 0 && strstr(r.err, want), "T four times from --threads 1 (%d cores): want '%s': %s", cores,
          want, r.err);

    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(a->world, views);
    CHECK(nv >= 5, "builtin has %d views", nv);
    char script[1024];
    snprintf(script, sizeof script,
             "at 0 key 4\nat 0.1 screenshot %s\nat 0.2 key 0\nat 0.3 screenshot %s\nat 0.35 key 1\n"
             "at 0.4 screenshot %s\nat 0.5 quit\n", tpath("k4.png"), tpath("k0.png"), tpath("k1.png"));
    write_text(tpath("k.script"), script);
    const char *argsk[] = { "view", "builtin", "--size", "320x240", "--view", "2", "--script", tpath("k.script"),
                            NULL };
    ew_t_run_cli(&r, tmpdir, argsk);
    CHECK(r.status == 0 && ew_t_count_lines(r.out) == 3, "keys 4, 0, 1: %d %s %s", r.status, r.out, r.err);
    const char *line = r.out;
    static const int want_view[3] = { 4, 0, 1 };
    for (int i = 0; i < 3 && nv >= 5; i++) {
        char path[512];
        float p[3], g[3];
        int ok = sscanf(line, "%511s --pos %f,%f,%f --angles %f,%f,%f", path, &p[0], &p[1], &p[2], &g[0], &g[1],
                        &g[2]) == 7;
        const ew_camera *v = &views[want_view[i]];
        float dy = fmodf(fabsf(g[1] - v->angles[1]), 360.0f);
        CHECK(ok && fabsf(p[0] - v->origin[0]) < 0.01f && fabsf(p[1] - v->origin[1]) < 0.01f &&
              fabsf(p[2] - v->origin[2]) < 0.01f && fabsf(g[0] - v->angles[0]) < 0.01f &&
              (dy < 0.01f || dy > 359.99f), "key %d: view %d (%g,%g,%g yaw %g), got: %.*s", want_view[i],
              want_view[i], v->origin[0], v->origin[1], v->origin[2], v->angles[1],
              (int)strcspn(line, "\n"), line);
        const char *nl = strchr(line, '\n');
        line = nl ? nl + 1 : line + strlen(line);
    }
    ew_assets_destroy(a);
}

/* Walk mode: gravity lands the player, a wall stops it. */
static void test_walk(const char *data) {
    ew_assets *a = ew_t_load_map("e1m1");
    if (!a) return;
    ew_camera views[EW_MAX_VIEWS];
    ew_benchmark_views(a->world, views);
    float org[3] = { views[0].origin[0], views[0].origin[1], views[0].origin[2] - EW_EYE_HEIGHT };
    /* Find a yaw with a wall 64..400 units ahead. */
    float yaw = -1, wall = 0;
    for (int k = 0; k < 72 && yaw < 0; k++) {
        float y = k * 5.0f, rad = y * 3.14159265f / 180;
        float end[3] = { org[0] + 1000 * cosf(rad), org[1] + 1000 * sinf(rad), org[2] };
        ew_trace_result tr;
        ew_trace(a->world, EW_HULL_PLAYER, org, end, &tr);
        if (tr.fraction < 1 && tr.fraction * 1000 > 64 && tr.fraction * 1000 < 400 && fabsf(tr.normal[2]) < 0.1f &&
            fabsf(tr.normal[0] * cosf(rad) + tr.normal[1] * sinf(rad)) > 0.95f)
            yaw = y, wall = tr.fraction * 1000;
    }
    CHECK(yaw >= 0, "a wall ahead of e1m1's start");
    /* Start 40 units above (room checked), in walk mode, hold W 4 s. */
    float up[3] = { org[0], org[1], org[2] + 40 };
    ew_trace_result tu;
    ew_trace(a->world, EW_HULL_PLAYER, org, up, &tu);
    float lift = tu.fraction * 40 - 1;
    char script[1024];
    snprintf(script, sizeof script,
             "at 0 camera %.4f,%.4f,%.4f 0,%.1f,0\nat 0 key F\nat 0.0 down W\nat 4 quit\n", org[0], org[1],
             org[2] + lift + EW_EYE_HEIGHT, yaw);
    write_text(tpath("w.script"), script);
    ew_t_run r;
    const char *args[] = { "view", "e1m1", "--data", data, "--size", "320x240", "--script",
                           tpath("w.script"), "--record", tpath("w.rec"), NULL };
    ew_t_run_cli(&r, tmpdir, args);
    CHECK(r.status == 0, "walk script: %s", r.err);
    double first[7], last[7];
    int n = record_lines(tpath("w.rec"), first, last);
    CHECK(n >= 200, "record lines %d", n);
    if (n > 0 && yaw >= 0) {
        float rad = yaw * 3.14159265f / 180;
        double along = (last[1] - org[0]) * cos(rad) + (last[2] - org[1]) * sin(rad);
        CHECK(along > wall - 40 && along < wall + 1e-3, "walked %.2f units towards a wall %.2f away", along, wall);
        float o[3] = { (float)last[1], (float)last[2], (float)(last[3] - EW_EYE_HEIGHT) };
        float below[3] = { o[0], o[1], o[2] - 2 };
        ew_trace_result tr;
        ew_trace(a->world, EW_HULL_PLAYER, o, below, &tr);
        CHECK(tr.fraction < 1 && !tr.startsolid, "landed on the floor (trace down %.3f)", tr.fraction);
        CHECK(first[3] - last[3] > lift - 2, "fell from %.2f to %.2f", first[3], last[3]);
        CHECK(ew_point_contents(a->world, EW_HULL_PLAYER, o) != -2, "not in solid");
    }
    ew_assets_destroy(a);
}

/* Esc quits (the mouse is not grabbed); waits up to 5 s for the viewer to
 * exit (then kills it); 1 when it exited by itself with status 0. */
static int stop_viewer(pid_t pid, const char *errfile) {
    const char *esc[] = { "xdotool", "key", "Escape", NULL };
    run_tool(esc);
    int st = 0, done = 0;
    for (int i = 0; i < 100 && !done; i++) {
        if (waitpid(pid, &st, WNOHANG) == pid) done = 1;
        else sleep_ms(50);
    }
    if (!done) {
        kill(pid, SIGKILL);
        waitpid(pid, &st, 0);
    }
    viewer_pid = -1;
    int ok = done && WIFEXITED(st) && WEXITSTATUS(st) == 0;
    if (!ok) {
        char err[4096];
        ew_t_slurp(errfile, err, sizeof err);
        fprintf(stderr, "viewer stderr: %s\n", err);
    }
    return ok;
}

/* Real input through xdotool. */
static void test_xdotool(const char *data) {
    char script[128];
    snprintf(script, sizeof script, "at 0 view 0\n");
    const char *rec = tpath("x.rec");
    pid_t pid = fork();
    if (pid == 0) {
        freopen("/dev/null", "w", stdout);
        freopen(tpath("x.err"), "w", stderr);
        execl(cli(), cli(), "view", "e1m1", "--data", data, "--size", "320x240", "--scale", "2", "--threads", "0",
              "--record", rec, (char *)NULL);
        _exit(127);
    }
    viewer_pid = pid;
    const char *search[] = { "xdotool", "search", "--sync", "--onlyvisible", "--name", "edgewise", NULL };
    CHECK(run_tool(search) == 0, "xdotool found the window");
    const char *act[] = { "xdotool", "search", "--name", "edgewise", "windowfocus", "--sync", NULL };
    run_tool(act);
    /* Until the viewer has drawn and recorded a frame (a loaded machine or
     * the sanitizers make that slow): the keys must come after it. */
    double s0[7] = {0}, l0[7] = {0};
    int n0 = 0;
    for (int i = 0; i < 100 && n0 == 0; i++) {
        sleep_ms(100);
        n0 = record_lines(rec, s0, l0);
    }
    const char *kd[] = { "xdotool", "keydown", "w", NULL }, *ku[] = { "xdotool", "keyup", "w", NULL };
    run_tool(kd);
    sleep_ms(1000);
    run_tool(ku);
    sleep_ms(300);
    double s1[7], l1[7];
    int n1 = record_lines(rec, s1, l1);
    const char *click[] = { "xdotool", "search", "--name", "edgewise", "mousemove", "--window", "%1", "320", "240",
                            "click", "1", NULL };
    run_tool(click);
    sleep_ms(300);
    double s2[7], l2[7];
    record_lines(rec, s2, l2);
    const char *rel[] = { "xdotool", "mousemove_relative", "--", "100", "0", NULL };
    /* Until the turn shows in the recorded path (or 6 s): a slow build (the
     * sanitizers) may take the grab later than the first moves arrive, so
     * click again now and then. */
    double s3[7], l3[7];
    int n3 = 0;
    for (int i = 0; i < 40; i++) {
        if (i > 0 && i % 8 == 0) run_tool(click), sleep_ms(200);
        run_tool(rel);
        sleep_ms(150);
        n3 = record_lines(rec, s3, l3);
        if (n3 > 0 && l3[5] < l2[5] - 10) break;
    }
    const char *esc[] = { "xdotool", "key", "Escape", NULL };
    run_tool(esc);
    sleep_ms(200);
    CHECK(stop_viewer(pid, tpath("x.err")), "Esc, Esc quit the viewer");
    CHECK(n0 > 0 && n1 > n0 && n3 > n1, "frames recorded %d %d %d", n0, n1, n3);
    if (n0 > 0 && n1 > n0) {
        double yaw = l0[5] * 3.14159265358979 / 180;
        double dx = l1[1] - l0[1], dy = l1[2] - l0[2];
        double fwd = dx * cos(yaw) + dy * sin(yaw), side = -dx * sin(yaw) + dy * cos(yaw);
        CHECK(fwd > 50 && fabs(side) < 1 && fabs(l1[3] - l0[3]) < 1,
              "W moved forward %.2f (side %.2f, up %.2f)", fwd, side, l1[3] - l0[3]);
        CHECK(l1[5] == l0[5], "W did not turn");
    }
    if (n3 > 0) {
        CHECK(l3[5] < l2[5] - 10, "mouse right turned right: yaw %.2f -> %.2f", l2[5], l3[5]);
        CHECK(fabs(l3[4] - l2[4]) < 1, "pitch kept %.2f -> %.2f", l2[4], l3[4]);
    }
}

/* ---- real input in walk mode on the built-in map ---------------------------- */

/* Every line of a record file (at most max): time x y z pitch yaw roll. */
static int record_all(const char *path, double (*v)[7], int max) {
    FILE *f = fopen(path, "r");
    if (!f) return 0;
    int n = 0;
    double l[7];
    while (n < max && fscanf(f, "%lf %lf %lf %lf %lf %lf %lf", &l[0], &l[1], &l[2], &l[3], &l[4], &l[5], &l[6]) == 7)
        memcpy(v[n++], l, sizeof l);
    fclose(f);
    return n;
}

/* The viewer on the built-in map with a script that only places the
 * camera, its window found and focused, its first frame recorded; the
 * pid, or -1. */
static pid_t start_builtin_viewer(const char *script, const char *rec, const char *errfile) {
    remove(rec);
    fflush(stdout);
    pid_t pid = fork();
    if (pid == 0) {
        freopen("/dev/null", "w", stdout);
        freopen(errfile, "w", stderr);
        execl(cli(), cli(), "view", "builtin", "--size", "320x240", "--threads", "0", "--script", script,
              "--record", rec, (char *)NULL);
        _exit(127);
    }
    if (pid < 0) return -1;
    viewer_pid = pid;
    const char *search[] = { "xdotool", "search", "--sync", "--onlyvisible", "--name", "edgewise - builtin", NULL };
    CHECK(run_tool(search) == 0, "xdotool found the builtin window");
    const char *act[] = { "xdotool", "search", "--onlyvisible", "--name", "edgewise - builtin", "windowfocus",
                          "--sync", NULL };
    run_tool(act);
    double a[7], b[7];
    for (int i = 0; i < 100 && record_lines(rec, a, b) == 0; i++) sleep_ms(100);
    return pid;
}


/* Polls the record until the last line satisfies done(line, arg) or
 * seconds pass; the number of lines then. */
static int wait_record(const char *rec, int (*done)(const double *, const double *), const double *arg,
                       double seconds) {
    double a[7], b[7];
    int n = 0;
    for (int i = 0; i < (int)(seconds * 10); i++) {
        sleep_ms(100);
        n = record_lines(rec, a, b);
        if (n > 0 && done(b, arg)) break;
    }
    return n;
}
static int at_z(const double *l, const double *z) { return fabs(l[3] - z[0]) < 0.05; }
static int at_x_least(const double *l, const double *x) { return l[1] >= x[0]; }
static int at_y_least(const double *l, const double *y) { return l[2] >= y[0]; }

/* The map's geometry by point traces: the floor under (x, y) below z,
 * the first wall from p along +x or +y. */
static float floor_at(const ew_world *w, float x, float y, float z) {
    float a[3] = { x, y, z }, b[3] = { x, y, z - 1000 };
    ew_trace_result t;
    ew_trace(w, EW_HULL_POINT, a, b, &t);
    return t.fraction < 1 ? t.end[2] - 1.0f / 32 : -1e9f;
}
static float wall_at(const ew_world *w, const float p[3], int axis) {
    float b[3] = { p[0], p[1], p[2] };
    b[axis] += 2000;
    ew_trace_result t;
    ew_trace(w, EW_HULL_POINT, p, b, &t);
    return t.fraction < 1 ? t.end[axis] + 1.0f / 32 : 1e9f;
}

/* xdotool keys in walk mode on the built-in map (its player hulls:
 * src/mapgen/clip_hull.c), checked on the recorded path against the
 * map's faces: F drops the player from 50 units up onto the hall's floor
 * (eye = floor + 24 + 22); W held walks it into the hall's east wall,
 * which stops it 16 units short; W held at the foot of the wooden stairs
 * climbs their three 16-unit steps one by one into the stone room. */
static void test_xdotool_walk(void) {
    ew_error err = { "" };
    ew_assets *a = ew_assets_create_builtin(&err);
    CHECK(a != NULL, "builtin: %s", err.msg);
    if (!a) return;
    const ew_world *w = a->world;
    const double eye = 24 + EW_EYE_HEIGHT;  /* the eye over the floor when standing */
    static double path[20000][7];

    /* gravity and a wall: the hall, 50 units over its floor, facing east */
    float fz = floor_at(w, 800, 100, 150);
    float p0[3] = { 800, 100, fz + 8 };
    float wall = wall_at(w, p0, 0);
    CHECK(fabsf(fz - 64) < 0.01f && fabsf(wall - 896) < 0.01f, "hall floor %g, east wall %g", fz, wall);
    char script[256];
    snprintf(script, sizeof script, "at 0 camera 800,100,%.1f 0,0,0\n", fz + eye + 50);
    write_text(tpath("wa.script"), script);
    pid_t pid = start_builtin_viewer(tpath("wa.script"), tpath("wa.rec"), tpath("wa.err"));
    if (pid < 0) { ew_assets_destroy(a); return; }
    int n0 = wait_record(tpath("wa.rec"), at_z, (double[]){ fz + eye + 50 }, 5);
    const char *kf[] = { "xdotool", "key", "f", NULL };
    run_tool(kf);
    int n1 = wait_record(tpath("wa.rec"), at_z, (double[]){ fz + eye }, 10);
    const char *wd[] = { "xdotool", "keydown", "w", NULL }, *wu[] = { "xdotool", "keyup", "w", NULL };
    run_tool(wd);
    int n2 = wait_record(tpath("wa.rec"), at_x_least, (double[]){ wall - 16 - 0.05 }, 10);
    sleep_ms(300);  /* pushing on the wall a while */
    run_tool(wu);
    sleep_ms(200);
    CHECK(stop_viewer(pid, tpath("wa.err")), "Esc quit the viewer (fall and wall)");
    int n = record_all(tpath("wa.rec"), path, 20000);
    CHECK(n0 > 0 && n1 > n0 && n2 > n1 && n > n2, "frames recorded %d %d %d %d", n0, n1, n2, n);
    if (n > n2 && n0 > 0) {
        double top = path[0][3], low = 1e9, most_x = -1e9;
        int falling = 0;
        for (int i = 0; i < n; i++) {
            if (path[i][3] < low) low = path[i][3];
            if (path[i][1] > most_x) most_x = path[i][1];
            if (i > 0 && path[i][3] < path[i - 1][3] - 0.5) falling++;
        }
        const double *l = path[n - 1];
        CHECK(fabs(top - (fz + eye + 50)) < 0.01 && falling >= 3, "a fall from %.3f (%d falling frames)", top,
              falling);
        CHECK(low >= fz + eye - 0.05 && fabs(l[3] - (fz + eye)) < 0.05, "landed at eye z %.3f (lowest %.3f), floor %g",
              l[3], low, fz);
        CHECK(most_x <= wall - 16 + 1e-3 && fabs(l[1] - (wall - 16)) < 0.05 && fabs(l[2] - 100) < 1e-3,
              "stopped at x %.3f (furthest %.3f), the wall at %g", l[1], most_x, wall);
        printf("xdotool walk: fell from eye z %.3f to %.3f (floor %.3f + 46) in %d frames; W: stopped at x %.3f, "
               "%.3f from the wall at %.3f\n", top, l[3], fz, falling, l[1], wall - l[1], wall);
    }

    /* stairs: at their foot in the hall, facing north */
    float riser[3], tops[4] = { fz, 0, 0, 0 };
    for (int k = 0; k < 3; k++) {
        float q[3] = { 736, 300 + 32.0f * k, tops[k] + 8 };
        riser[k] = wall_at(w, q, 1);
        tops[k + 1] = floor_at(w, 736, riser[k] + 8, tops[k] + 60);
    }
    CHECK(fabsf(riser[0] - 384) < 0.01f && fabsf(riser[1] - 416) < 0.01f && fabsf(riser[2] - 448) < 0.01f &&
              fabsf(tops[1] - 80) < 0.01f && fabsf(tops[2] - 96) < 0.01f && fabsf(tops[3] - 112) < 0.01f,
          "stairs: risers %g %g %g, tops %g %g %g", riser[0], riser[1], riser[2], tops[1], tops[2], tops[3]);
    snprintf(script, sizeof script, "at 0 camera 736,300,%.1f 0,90,0\n", fz + eye);
    write_text(tpath("wb.script"), script);
    pid = start_builtin_viewer(tpath("wb.script"), tpath("wb.rec"), tpath("wb.err"));
    if (pid < 0) { ew_assets_destroy(a); return; }
    run_tool(kf);
    sleep_ms(200);
    run_tool(wd);
    int m1 = wait_record(tpath("wb.rec"), at_y_least, (double[]){ riser[2] + 40 }, 10);
    run_tool(wu);
    sleep_ms(200);
    CHECK(stop_viewer(pid, tpath("wb.err")), "Esc quit the viewer (stairs)");
    n = record_all(tpath("wb.rec"), path, 20000);
    CHECK(m1 > 0 && n >= m1, "stairs: frames recorded %d %d", m1, n);
    int seen[4] = { 0, 0, 0, 0 }, early = 0, back = 0, drift = 0;
    double first_y[4] = { 0, 0, 0, 0 };
    for (int i = 0; i < n; i++) {
        for (int k = 0; k < 4; k++)
            if (fabs(path[i][3] - (tops[k] + eye)) < 0.05) {
                if (!seen[k]++) first_y[k] = path[i][2];
                /* on a step only once the box is over it: origin past the riser - 16 */
                if (k > 0 && path[i][2] < riser[k - 1] - 16 - 0.05) early++;
            }
        /* up the stairs, never down (further on, a dais in the room is stepped up and off) */
        if (i > 0 && path[i][2] < riser[2] + 32 && path[i][3] < path[i - 1][3] - 0.05) back++;
        if (fabs(path[i][1] - 736) >= 1e-3) drift++;
    }
    CHECK(drift == 0, "stairs: x left 736 in %d frames", drift);
    CHECK(seen[0] && seen[1] && seen[2] && seen[3], "stairs: frames on each level %d %d %d %d", seen[0], seen[1],
          seen[2], seen[3]);
    CHECK(early == 0 && back == 0, "stairs: %d frames up a step before its riser, %d going down", early, back);
    CHECK(n > 0 && path[n - 1][2] > riser[2] && path[n - 1][3] >= tops[3] + eye - 0.05, "stairs: ended at y %.3f z %.3f",
          n > 0 ? path[n - 1][2] : 0, n > 0 ? path[n - 1][3] : 0);
    printf("xdotool walk: stairs climbed, eye z %.0f/%.0f/%.0f/%.0f first reached at y %.3f/%.3f/%.3f/%.3f (risers "
           "at y %.0f/%.0f/%.0f), %d frames\n", tops[0] + eye, tops[1] + eye, tops[2] + eye, tops[3] + eye,
           first_y[0], first_y[1], first_y[2], first_y[3], riser[0], riser[1], riser[2], n);
    ew_assets_destroy(a);
}

#endif /* EW_HAVE_SDL2 */

int main(void) {
    ew_t_run r;
#ifndef EW_HAVE_SDL2
    const char *args0[] = { "view", "builtin", NULL };
    ew_t_run_cli(&r, ".", args0);
    CHECK(r.status != 0 && strstr(r.err, "without SDL2"), "view without SDL2: %s", r.err);
    return ew_t_finish();
#else
    snprintf(tmpdir, sizeof tmpdir, "/tmp/ew_viewer_XXXXXX");
    if (!mkdtemp(tmpdir)) { perror("mkdtemp"); return 1; }
    /* No display: one line, non-zero. */
    unsetenv("DISPLAY");
    unsetenv("WAYLAND_DISPLAY");
    const char *args0[] = { "view", "builtin", NULL };
    ew_t_run_cli(&r, tmpdir, args0);
    CHECK(r.status != 0 && strstr(r.err, "no display") && ew_t_count_lines(r.err) == 1, "no display: %d %s",
          r.status, r.err);

    /* DISPLAY naming no X server: one line, exit 1 (not a window-less run;
     * the script quits a run that wrongly goes on). */
    {
        int free_d = -1;
        for (int d = 150; d < 250 && free_d < 0; d++) {
            char lock[64], sock[64];
            snprintf(lock, sizeof lock, "/tmp/.X%d-lock", d);
            snprintf(sock, sizeof sock, "/tmp/.X11-unix/X%d", d);
            if (!file_exists(lock) && !file_exists(sock)) free_d = d;
        }
        char disp[16];
        snprintf(disp, sizeof disp, ":%d", free_d);
        setenv("DISPLAY", disp, 1);
        write_text(tpath("q.script"), "at 1 quit\n");
        const char *argsx[] = { "view", "builtin", "--script", tpath("q.script"), NULL };
        ew_t_run_cli(&r, tmpdir, argsx);
        CHECK(r.status == 1 && strstr(r.err, "cannot open the display") && strstr(r.err, disp) &&
              ew_t_count_lines(r.err) == 1, "DISPLAY=%s (no X server): exit %d, want 1 and one line: %s", disp,
              r.status, r.err);
        unsetenv("DISPLAY");
    }

    const char *argsp[] = { "view", "builtin", "--present", "bogus", NULL };
    ew_t_run_cli(&r, tmpdir, argsp);
    CHECK(r.status == 2 && strstr(r.err, "--present bogus") && ew_t_count_lines(r.err) == 1, "--present bogus: %d %s",
          r.status, r.err);

    /* Numbers are decimal, as everywhere in the command (issue 36). */
    const char *argsf[] = { "view", "builtin", "--fov", "0x10", NULL };
    ew_t_run_cli(&r, tmpdir, argsf);
    CHECK(r.status == 2 && strstr(r.err, "--fov 0x10") && ew_t_count_lines(r.err) == 1, "--fov 0x10: %d %s",
          r.status, r.err);

    if (!have_tool("Xvfb")) {
        ew_t_skip("no Xvfb (Debian package 'xvfb'): the viewer is not driven");
        return ew_t_finish();
    }
    signal(SIGALRM, on_alarm);
    alarm(400);
    int d = start_xvfb();
    CHECK(d >= 0, "Xvfb started");
    if (d >= 0) {
        char disp[16];
        snprintf(disp, sizeof disp, ":%d", d);
        setenv("DISPLAY", disp, 1);
        /* The built-in scene opens and quits. */
        write_text(tpath("b.script"), "at 0.2 quit\n");
        const char *args1[] = { "view", "builtin", "--script", tpath("b.script"), NULL };
        ew_t_run_cli(&r, tmpdir, args1);
        CHECK(r.status == 0 && strstr(r.err, "frames"), "view builtin: %d %s", r.status, r.err);
        /* H: the next available hidden-surface method, twice */
        {
            int m1 = EW_HSR_EDGE, m2;
            for (int i = 1; i <= EW_HSR_COUNT; i++)
                if (ew_hsr_available((ew_hsr_method)((EW_HSR_EDGE + i) % EW_HSR_COUNT))) {
                    m1 = (EW_HSR_EDGE + i) % EW_HSR_COUNT;
                    break;
                }
            m2 = m1;
            for (int i = 1; i <= EW_HSR_COUNT; i++)
                if (ew_hsr_available((ew_hsr_method)((m1 + i) % EW_HSR_COUNT))) {
                    m2 = (m1 + i) % EW_HSR_COUNT;
                    break;
                }
            char want[128];
            snprintf(want, sizeof want, "hsr: %s\nhsr: %s\n", ew_hsr_name((ew_hsr_method)m1),
                     ew_hsr_name((ew_hsr_method)m2));
            write_text(tpath("h.script"), "at 0 key H\nat 0.1 key H\nat 0.2 quit\n");
            const char *argsh[] = { "view", "builtin", "--size", "320x240", "--script", tpath("h.script"), NULL };
            ew_t_run_cli(&r, tmpdir, argsh);
            CHECK(r.status == 0 && strstr(r.err, want), "H twice: want '%s': %s", want, r.err);
        }
        test_threads_and_view_keys();
        if (have_tool("xdotool")) test_xdotool_walk();
        else ew_t_skip("no xdotool (Debian package 'xdotool'): no keys sent through X");
        if (ew_t_need_shared("data/librequake/maps/e1m1.bsp")) {
            const char *data = ew_t_shared_abs("data/librequake");
            char databuf[512];
            snprintf(databuf, sizeof databuf, "%s", data);
            test_script_matches_render(databuf);
            test_demo();
            test_overlay_and_debug(databuf);
            test_walk(databuf);
            if (have_tool("xdotool")) test_xdotool(databuf);
        }
    }
    stop_xvfb();
    alarm(0);
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    if (system(cmd) != 0) { /* left behind */ }
    return ew_t_finish();
#endif
}
