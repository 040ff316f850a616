/* The moving polyhedra of Listing 51.1's idea (ew_polyhedra_*): 200 frames
 * whose objects pass through and touch each other, each drawn by the
 * 1/z-sorted edge list and by a per-pixel z-buffer of the same polygons.
 * Per frame: at least 99.9% of the pixels agree, the spans tile the frame
 * (every pixel written exactly once: overdraw 1.0), both cover the same
 * pixels.  Over the run: planes really cross (intersections resolved > 0)
 * and resolving them matters (without, the frames disagree more); glued
 * pairs abut (ties of 1/z settled by the slope > 0); the
 * near plane cuts faces; the same time gives the same frame; a palette
 * given is used; bad arguments are refused with a message, in the library
 * and in `edgewise render builtin:polyhedra` (EW_CLI). */
#define _POSIX_C_SOURCE 200809L
#include "util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define W 640
#define H 480
#define FRAMES 200

static double now_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

static double agreement_n(const uint8_t *a, const uint8_t *b, int n) {
    long same = 0;
    for (int i = 0; i < n; i++)
        same += a[i] == b[i];
    return (double)same / n;
}
#define agreement(a, b) agreement_n(a, b, W * H)

static void bad_arguments(void) {
    ew_error err;
    static const int bad[][3] = { { 0, W, H }, { EW_POLYHEDRA_MAX + 1, W, H }, { -3, W, H },
                                  { 4, 15, H }, { 4, W, 0 }, { 4, 20000, H }, { 4, W, -480 } };
    for (int i = 0; i < (int)(sizeof bad / sizeof *bad); i++) {
        err.msg[0] = 0;
        ew_polyhedra *p = ew_polyhedra_create(bad[i][0], bad[i][1], bad[i][2], NULL, &err);
        CHECK(!p && err.msg[0], "create(%d, %d, %d) accepted", bad[i][0], bad[i][1], bad[i][2]);
        ew_polyhedra_destroy(p);
    }
    ew_polyhedra *p = ew_polyhedra_create(3, 64, 48, NULL, &err);
    CHECK(p != NULL, "create(3, 64, 48): %s", err.msg);
    if (!p)
        return;
    uint8_t px[64 * 48];
    const double times[] = { NAN, INFINITY, -INFINITY, 2e6, -1e7 };
    for (int i = 0; i < 5; i++) {
        err.msg[0] = 0;
        CHECK(ew_polyhedra_render(p, times[i], px, NULL, &err) < 0 && err.msg[0],
              "render at time %g accepted", times[i]);
        err.msg[0] = 0;
        CHECK(ew_polyhedra_render_zbuffer(p, times[i], px, NULL, &err) < 0 && err.msg[0],
              "z-buffer at time %g accepted", times[i]);
    }
    CHECK(ew_polyhedra_render(p, 1, NULL, NULL, &err) < 0, "NULL frame accepted");
    CHECK(ew_polyhedra_render(NULL, 1, px, NULL, &err) < 0, "NULL scene accepted");
    CHECK(ew_polyhedra_render(p, 1e6, px, NULL, &err) == 0, "time 1e6 refused: %s", err.msg);
    ew_polyhedra_destroy(p);
    ew_polyhedra_destroy(NULL);
}

/* Checks the spans of the last frame tile it: row by row, left to right,
 * no gap, no overlap, each painting its colour.  Returns the writes. */
static long check_spans_wh(const ew_polyhedra *p, const uint8_t *frame, int *bad_frames, int f,
                           int w, int h) {
    static uint8_t writes[640 * 480];
    memset(writes, 0, sizeof writes);
    int n, ok = 1;
    const ew_polyhedra_span *sp = ew_polyhedra_spans(p, &n);
    long total = 0;
    int y = 0, x = 0;
    for (int i = 0; i < n; i++) {
        const ew_polyhedra_span *s = &sp[i];
        if (s->y < 0 || s->y >= h || s->x < 0 || s->count <= 0 || s->x + s->count > w) {
            ok = 0;
            break;
        }
        if (s->y != y) { /* a new row: the last one must have ended at w */
            if (x != w || s->y != y + 1)
                ok = 0;
            y = s->y, x = 0;
        }
        if (s->x != x)
            ok = 0;
        x = s->x + s->count;
        for (int k = s->x; k < x; k++) {
            writes[s->y * w + k]++;
            if (frame[s->y * w + k] != s->color)
                ok = 0;
        }
        total += s->count;
    }
    if (y != h - 1 || x != w)
        ok = 0;
    for (int i = 0; i < w * h && ok; i++)
        ok = writes[i] == 1;
    if (!ok && (*bad_frames)++ < 3)
        CHECK(0, "frame %d (%dx%d): the spans do not write every pixel exactly once", f, w, h);
    return total;
}
#define check_spans(p, frame, bad, f) check_spans_wh(p, frame, bad, f, W, H)

/* Other scenes and sizes: the most objects (crowded, everything crossing)
 * and the smallest frame; the same checks, fewer frames. */
static void other_scenes(void) {
    static const int cases[][4] = { { EW_POLYHEDRA_MAX, 320, 240, 60 }, { 1, 64, 48, 30 },
                                    { EW_POLYHEDRA_DEFAULT, 16, 16, 60 }, { 30, 640, 37, 30 } };
    static uint8_t a[640 * 480], b[640 * 480];
    for (int c = 0; c < 4; c++) {
        int n = cases[c][0], w = cases[c][1], h = cases[c][2], frames = cases[c][3];
        ew_error err;
        ew_polyhedra *p = ew_polyhedra_create(n, w, h, NULL, &err);
        CHECK(p != NULL, "create(%d, %d, %d): %s", n, w, h, err.msg);
        if (!p)
            continue;
        double worst = 1;
        int bad = 0;
        long long crossings = 0, writes = 0;
        for (int f = 0; f < frames; f++) {
            ew_polyhedra_stats st;
            double t = f * 0.31;
            CHECK(ew_polyhedra_render(p, t, a, &st, &err) == 0 &&
                      ew_polyhedra_render_zbuffer(p, t, b, NULL, &err) == 0, "%s", err.msg);
            writes += check_spans_wh(p, a, &bad, f, w, h);
            crossings += st.crossings;
            double ag = agreement_n(a, b, w * h);
            worst = ag < worst ? ag : worst;
        }
        printf("%d polyhedra %dx%d, %d frames: agreement min %.5f%%, overdraw %.6f, crossings %lld\n",
               n, w, h, frames, worst * 100, (double)writes / ((double)w * h * frames), crossings);
        CHECK(worst >= 0.999 && bad == 0 && writes == (long long)w * h * frames,
              "%d polyhedra %dx%d: agreement %.5f%%, %d frames badly tiled", n, w, h, worst * 100, bad);
        if (n == EW_POLYHEDRA_MAX)
            CHECK(crossings > 0, "64 polyhedra and no crossing");
        ew_polyhedra_destroy(p);
    }
}

#define ARGS(...) ((const char *const[]){ __VA_ARGS__, NULL })

/* The command: one frame with --stats, then bad arguments (one line, exit 2). */
static void command_line(void) {
    char dir[] = "/tmp/ew_polyhedra_XXXXXX";
    if (!getenv("EW_CLI") || !mkdtemp(dir)) {
        CHECK(0, "no EW_CLI or no temporary folder");
        return;
    }
    static ew_t_run r;
    ew_t_run_cli(&r, dir, ARGS("render", "builtin:polyhedra", "--time", "14", "--size", "400x300",
                               "--out", "p.png", "--stats"));
    CHECK(r.status == 0, "render builtin:polyhedra: exit %d: %s", r.status, r.err);
    CHECK(ew_t_json_num(r.out, "overdraw") == 1 && ew_t_json_num(r.out, "agreement") >= 0.999 &&
              ew_t_json_num(r.out, "width") == 400 && ew_t_json_num(r.out, "polygons") > 0,
          "stats: %s", r.out);
    char png[64];
    snprintf(png, sizeof png, "%s/p.png", dir);
    CHECK(access(png, R_OK) == 0, "no %s", png);
    remove(png);
    /* The word may come after the options. */
    ew_t_run_cli(&r, dir, ARGS("render", "--out", "q.png", "--objects", "3", "builtin:polyhedra"));
    snprintf(png, sizeof png, "%s/q.png", dir);
    CHECK(r.status == 0 && access(png, R_OK) == 0, "options first: exit %d: %s", r.status, r.err);
    remove(png);
    const char *const *bad[] = {
        ARGS("render", "builtin:polyhedra", "--time", "-1"),
        ARGS("render", "builtin:polyhedra", "--time", "nan"),
        ARGS("render", "builtin:polyhedra", "--time", "1e7"),
        ARGS("render", "builtin:polyhedra", "--objects", "0"),
        ARGS("render", "builtin:polyhedra", "--objects", "65"),
        ARGS("render", "builtin:polyhedra", "--size", "10x10"),
        ARGS("render", "builtin:polyhedra", "--out"),
        ARGS("render", "builtin:polyhedra", "--bogus"),
        ARGS("view", "builtin:polyhedra", "--scale", "9"),
        ARGS("render", "builtin:polyhedra", "e1m1"),
        ARGS("render", "builtin:polyhedra", "builtin:polyhedra"),
    };
    for (int i = 0; i < (int)(sizeof bad / sizeof *bad); i++) {
        ew_t_run_cli(&r, dir, bad[i]);
        CHECK(r.status == 2 && ew_t_count_lines(r.err) == 1 && strncmp(r.err, "edgewise: ", 10) == 0,
              "%s %s: exit %d, stderr: %s", bad[i][2], bad[i][3] ? bad[i][3] : "", r.status, r.err);
    }
    rmdir(dir);
}

int main(void) {
    bad_arguments();
    command_line();
    other_scenes();

    ew_error err;
    ew_polyhedra *p = ew_polyhedra_create(EW_POLYHEDRA_DEFAULT, W, H, NULL, &err);
    CHECK(p != NULL, "create: %s", err.msg);
    if (!p)
        return ew_t_finish();
    uint8_t *edge = malloc(W * H), *zb = malloc(W * H), *indep = malloc(W * H);
    if (!edge || !zb || !indep)
        return 1;

    double agree_min = 1, agree_sum = 0, indep_min = 1, indep_sum = 0, ms_edge = 0, ms_z = 0;
    long long writes = 0, crossings = 0, ties = 0;
    int frames_crossing = 0, frames_clipped = 0, bad_spans = 0, below = 0, indep_below = 0;
    int covered_differs = 0, min_frame = 0;
    double zod_min = 1e9, zod_max = 0;
    for (int f = 0; f < FRAMES; f++) {
        /* 0.137 s apart: 27 s, more than a turn of the slowest orbits. */
        double t = f * 0.137;
        ew_polyhedra_stats se, sz, si;
        ew_polyhedra_set_crossings(p, 1);
        double t0 = now_ms();
        int rc = ew_polyhedra_render(p, t, edge, &se, &err);
        double t1 = now_ms();
        CHECK(rc == 0, "frame %d: %s", f, err.msg);
        writes += check_spans(p, edge, &bad_spans, f);
        double t2 = now_ms();
        rc = ew_polyhedra_render_zbuffer(p, t, zb, &sz, &err);
        double t3 = now_ms();
        CHECK(rc == 0, "frame %d z-buffer: %s", f, err.msg);
        ms_edge += t1 - t0, ms_z += t3 - t2;
        double zod = (double)sz.pixels / (W * H);
        zod_min = zod < zod_min ? zod : zod_min, zod_max = zod > zod_max ? zod : zod_max;
        double a = agreement(edge, zb);
        if (a < agree_min)
            agree_min = a, min_frame = f;
        agree_sum += a;
        below += a < 0.999;
        CHECK(se.pixels == (long long)W * H, "frame %d: %lld pixels written", f, se.pixels);
        covered_differs += se.covered != sz.covered;
        crossings += se.crossings, ties += se.ties;
        frames_crossing += se.crossings > 0;
        frames_clipped += se.clipped > 0;
        CHECK(se.polygons > 0 && se.edges >= 2 * se.polygons && se.spans >= H,
              "frame %d: %d polygons %d edges %d spans", f, se.polygons, se.edges, se.spans);

        /* Independent sorting alone: right only where nothing touches. */
        ew_polyhedra_set_crossings(p, 0);
        CHECK(ew_polyhedra_render(p, t, indep, &si, &err) == 0, "frame %d: %s", f, err.msg);
        CHECK(si.crossings == 0, "frame %d: crossings with resolution off", f);
        double ai = agreement(indep, zb);
        indep_min = ai < indep_min ? ai : indep_min;
        indep_sum += ai;
        indep_below += ai < 0.999;
    }
    double overdraw = (double)writes / ((double)W * H * FRAMES);
    printf("%d frames %dx%d, %d polyhedra\n", FRAMES, W, H, EW_POLYHEDRA_DEFAULT);
    printf("agreement with the z-buffer: min %.5f%% (frame %d) mean %.5f%%, frames under 99.9%%: %d\n",
           agree_min * 100, min_frame, agree_sum / FRAMES * 100, below);
    printf("without intersection resolution: min %.5f%% mean %.5f%%, frames under 99.9%%: %d\n",
           indep_min * 100, indep_sum / FRAMES * 100, indep_below);
    printf("overdraw %.6f; crossings resolved %lld on %d frames; ties %lld; near/screen clipping on %d frames\n",
           overdraw, crossings, frames_crossing, ties, frames_clipped);
    printf("z-buffer overdraw (clear included) %.3f to %.3f\n", zod_min, zod_max);
    printf("ms per frame: edge list %.3f, z-buffer %.3f\n", ms_edge / FRAMES, ms_z / FRAMES);

    CHECK(agree_min >= 0.999, "agreement %.5f%% on frame %d", agree_min * 100, min_frame);
    CHECK(overdraw == 1.0, "overdraw %.6f", overdraw);
    CHECK(bad_spans == 0, "%d frames with spans that do not tile", bad_spans);
    CHECK(covered_differs == 0, "%d frames where the two cover different pixels", covered_differs);
    /* The scene must really interpenetrate, and resolving it must matter. */
    CHECK(crossings > 0 && frames_crossing >= FRAMES / 10, "crossings %lld on %d frames", crossings,
          frames_crossing);
    CHECK(indep_below > 0 && indep_sum < agree_sum,
          "independent sorting alone is as good (%d frames under 99.9%%)", indep_below);
    CHECK(frames_clipped > 0, "nothing clipped on any frame");
    /* The glued pairs abut: equal 1/z met and settled by the slope. */
    CHECK(ties > 0, "no abutting surfaces met in %d frames", FRAMES);

    /* The same time, the same frame (and the z-buffer's too). */
    uint8_t *again = malloc(W * H);
    ew_polyhedra_set_crossings(p, 1);
    CHECK(again && ew_polyhedra_render(p, 3.5, edge, NULL, &err) == 0 &&
              ew_polyhedra_render(p, 3.5, again, NULL, &err) == 0 && memcmp(edge, again, W * H) == 0,
          "two renders of t = 3.5 differ");
    ew_polyhedra *q = ew_polyhedra_create(EW_POLYHEDRA_DEFAULT, W, H, NULL, &err);
    CHECK(q && ew_polyhedra_render(q, 3.5, again, NULL, &err) == 0 && memcmp(edge, again, W * H) == 0,
          "a second scene of the same count draws t = 3.5 differently");
    ew_polyhedra_destroy(q);

    /* A palette given is used: the built-in one reversed gives index 255 - i. */
    const uint8_t *pal = ew_polyhedra_palette(p);
    uint8_t rev[768];
    for (int i = 0; i < 256; i++)
        memcpy(rev + 3 * (255 - i), pal + 3 * i, 3);
    q = ew_polyhedra_create(EW_POLYHEDRA_DEFAULT, W, H, rev, &err);
    int reversed = q && ew_polyhedra_render(q, 3.5, again, NULL, &err) == 0 &&
                   memcmp(ew_polyhedra_palette(q), rev, 768) == 0;
    for (int i = 0; i < W * H && reversed; i++)
        reversed = again[i] == 255 - edge[i];
    CHECK(reversed, "a reversed palette is not used as given");
    ew_polyhedra_destroy(q);

    free(again), free(edge), free(zb), free(indep);
    ew_polyhedra_destroy(p);
    return ew_t_finish();
}
