/*
 * edgewise timedemo, on LibreQuake's demo3.dem over lqdm3 (--game
 * ../shared/data/demos --data ../shared/data/librequake):
 *   - it plays through at 320x200: 1238 frames, the classic line and the
 *     JSON line (median, p99, worst frame and its demo time), every model
 *     found, the camera never in solid;
 *   - a frame of the demo without its moving things is byte for byte
 *     `edgewise render` of the same camera and time (what does not move
 *     is drawn the same); with them, most of the frame agrees;
 *   - drawing options of render (--classic, --color true) are taken;
 *   - fly --demo: y4m and PNG frames at a fixed rate between --from and --to;
 *   - damaged demos (cut short, random bytes in a message, an absurd
 *     length, not a demo): the frames before the damage, then one error
 *     line naming the block and the byte, exit status 1, never a crash.
 */
#define _GNU_SOURCE
#include "util.h"
#include "edgewise_lab.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char tmp[64], demos[1024], lq[1024], demo3[1100];

static void run(ew_t_run *r, const char *const *args) { ew_t_run_cli(r, tmp, args); }

static int count_lines(const char *s) { return ew_t_count_lines(s); }

static void play_through(void) {
    ew_t_run r;
    const char *a[] = {"timedemo", demo3, "--game", demos, "--data", lq, "--size", "320x200", "--threads", "1",
                       "--quiet", NULL};
    run(&r, a);
    CHECK(r.status == 0, "timedemo demo3: status %d: %s", r.status, r.err);
    int frames = 0;
    double secs = 0, fps = 0;
    CHECK(sscanf(r.out, "%d frames %lf seconds %lf fps\n", &frames, &secs, &fps) == 3 && frames == 1235 && secs > 0 &&
          fps > 0, "the classic line: %.80s", r.out);
    const char *json = strchr(r.out, '{');
    CHECK(json != NULL, "a JSON line");
    if (!json) return;
    CHECK(ew_t_json_num(json, "frames") == 1235, "1235 frames (the blocks after the view entity's first update)");
    CHECK(ew_t_json_num(json, "camera_in_solid") == 0, "the camera is never in solid (%g frames)",
          ew_t_json_num(json, "camera_in_solid"));
    CHECK(ew_t_json_num(json, "models_missing") == 0, "every model found (%g missing)", ew_t_json_num(json, "models_missing"));
    CHECK(ew_t_json_num(json, "complete") == 1, "played to the end");
    double med = ew_t_json_num(json, "median_ms"), p99 = ew_t_json_num(json, "p99_ms"), worst = ew_t_json_num(json, "worst_ms");
    CHECK(med > 0 && p99 >= med && worst >= p99, "median %g <= p99 %g <= worst %g", med, p99, worst);
    double wt = ew_t_json_num(json, "worst_time");
    CHECK(wt >= 416 && wt <= 447, "the worst frame's demo time %g lies in the demo", wt);
    CHECK(count_lines(r.out) == 2, "two lines on stdout");
}

static uint8_t *read_png(const char *path, int *w, int *h) {
    uint8_t *rgb = NULL;
    ew_error err;
    if (ew_read_png_rgb(path, &rgb, w, h, &err) != 0) {
        CHECK(0, "%s", err.msg);
        return NULL;
    }
    return rgb;
}

/* A demo frame at time t against render of its camera; returns the share
 * of equal pixels. */
static double against_render(double t, int entities) {
    ew_t_run r;
    char at[32];
    snprintf(at, sizeof at, "%g", t);
    char to[32];
    snprintf(to, sizeof to, "%g", t + 0.5);
    const char *a[] = {"timedemo", demo3, "--game", demos, "--data", lq, "--size", "320x200", "--quiet", "--threads",
                       "1", "--out", "demo.png", "--at", at, "--to", to, entities ? "--quiet" : "--no-entities", NULL};
    run(&r, a);
    CHECK(r.status == 0, "timedemo --out --at %s: %s", at, r.err);
    const char *json = strchr(r.out, '{');
    const char *cam = json ? strstr(json, "\"out_camera\":[") : NULL;
    double c[6];
    CHECK(cam && sscanf(cam, "\"out_camera\":[%lf,%lf,%lf,%lf,%lf,%lf]", &c[0], &c[1], &c[2], &c[3], &c[4], &c[5]) == 6,
          "the frame's camera in the JSON");
    if (!cam) return 0;
    double ot = ew_t_json_num(json, "out_time");
    CHECK(ot >= t, "the frame written is at or after --at (%g >= %g)", ot, t);
    char pos[128], ang[128], time[64];
    snprintf(pos, sizeof pos, "%.9g,%.9g,%.9g", c[0], c[1], c[2]);
    snprintf(ang, sizeof ang, "%.9g,%.9g,%.9g", c[3], c[4], c[5]);
    snprintf(time, sizeof time, "%.9g", ot);
    const char *b[] = {"render", "lqdm3", "--game", demos, "--data", lq, "--size", "320x200", "--pos", pos,
                       "--angles", ang, "--time", time, "--out", "render.png", entities ? "--size" : "--no-entities",
                       entities ? "320x200" : NULL, NULL};
    run(&r, b);
    CHECK(r.status == 0, "render --pos %s --angles %s: %s", pos, ang, r.err);
    int w1, h1, w2, h2;
    uint8_t *p1 = read_png(ew_t_in_dir(tmp, "demo.png"), &w1, &h1), *p2 = read_png(ew_t_in_dir(tmp, "render.png"), &w2, &h2);
    double same = 0;
    if (p1 && p2 && w1 == w2 && h1 == h2) {
        long eq = 0;
        for (int i = 0; i < w1 * h1; i++) eq += memcmp(p1 + 3 * i, p2 + 3 * i, 3) == 0;
        same = (double)eq / (w1 * h1);
    }
    free(p1), free(p2);
    return same;
}

static void still_frames(void) {
    double ts[] = {417.5, 426, 433, 444};
    for (int i = EW_T_SANITIZED ? 2 : 0; i < 4; i += EW_T_SANITIZED ? 2 : 1) {  /* sanitized: 433 only */
        double s = against_render(ts[i], 0);
        CHECK(s == 1.0, "t %g without moving things: the demo's frame is render's (%.4f of the pixels)", ts[i], s);
    }
    double s = against_render(426, 1);
    CHECK(s > 0.8, "t 426 with the moving things: %.4f of the pixels agree with render's map entities", s);
}

static void options(void) {
    ew_t_run r;
    const char *a[] = {"timedemo", demo3, "--game", demos, "--data", lq, "--size", "320x200", "--classic",
                       "--to", "420", "--quiet", NULL};
    run(&r, a);
    const char *json = strchr(r.out, '{');
    CHECK(r.status == 0 && json && strstr(json, "\"classic\":true") && strstr(json, "\"complete\":false"),
          "--classic --to 420: %s %s", r.err, json ? json : "");
    const char *t[] = {"timedemo", demo3, "--game", demos, "--data", lq, "--size", "320x200", "--color", "true",
                       "--to", "420", "--quiet", NULL};
    run(&r, t);
    json = strchr(r.out, '{');
    CHECK(r.status == 0 && json && strstr(json, "\"color\":\"true\""), "--color true: %s %s", r.err, json ? json : "");
    const char *early[] = {"timedemo", demo3, "--game", demos, "--data", lq, "--size", "320x200", "--to", "5", NULL};
    run(&r, early);
    CHECK(r.status == 2 && count_lines(r.err) == 1 && strstr(r.err, "before the demo's first frame"),
          "--to before the first frame: %s", r.err);
    const char *nodata[] = {"timedemo", demo3, NULL};
    run(&r, nodata);
    CHECK(r.status == 1 && count_lines(r.err) == 1 && strstr(r.err, "--data"), "without --data: %s", r.err);
    const char *help[] = {"timedemo", "--help", NULL};
    run(&r, help);
    CHECK(r.status == 0 && strstr(r.out, "--classic") && strstr(r.out, "--game"), "--help lists the drawing options");
}

static void damaged(const uint8_t *d, size_t n, const char *what, int want_frames_some) {
    const char *path = ew_t_in_dir(tmp, "bad.dem");
    ew_t_write_file(path, d, n);
    ew_t_run r;
    const char *a[] = {"timedemo", "bad.dem", "--game", demos, "--data", lq, "--size", "320x200", "--quiet",
                       "--threads", "1", NULL};
    run(&r, a);
    CHECK(r.signal == 0, "%s: no crash (signal %d)", what, r.signal);
    CHECK(r.status == 1, "%s: exit status 1 (%d)", what, r.status);
    CHECK(count_lines(r.err) == 1 && strncmp(r.err, "edgewise: ", 10) == 0, "%s: one error line: %s", what, r.err);
    if (want_frames_some) {
        int frames = -1;
        CHECK(sscanf(r.out, "%d frames", &frames) == 1 && frames > 0, "%s: the frames before the damage are played: %.60s",
              what, r.out);
        CHECK(strstr(r.err, "block ") && strstr(r.err, " at byte "), "%s: names the block and the byte: %s", what, r.err);
    }
}

static void corrupt(void) {
    uint8_t *data = NULL;
    size_t size = 0;
    ew_error err;
    if (ew_read_file(demo3, &data, &size, &err) != 0) {
        CHECK(0, "%s", err.msg);
        return;
    }
    size_t offs[1300];
    int nb = 0;
    for (size_t p = 3; p + 16 <= size && nb < 1300; p += 16 + ew_t_le32(data + p)) offs[nb++] = p;
    damaged(data, offs[200] + 9, "cut short", 1);
    uint8_t *c = malloc(size);
    memcpy(c, data, size);
    ew_t_put_le32(c + offs[100], 0x40000000u);
    damaged(c, size, "absurd length", 1);
    memcpy(c, data, size);
    c[offs[150] + 16] = 77;  /* no such message */
    damaged(c, size, "an unknown message", 1);
    /* random bytes in messages: no crash, exit 0 or one error line */
    uint32_t seed = 99;
    for (int k = 0; k < (EW_T_SANITIZED ? 1 : 3); k++) {
        memcpy(c, data, size);
        for (int f = 0; f < 6; f++) {
            seed = seed * 1664525u + 1013904223u;
            int b = 4 + (int)((seed >> 8) % (uint32_t)(nb - 4));
            uint32_t len = ew_t_le32(data + offs[b]);
            seed = seed * 1664525u + 1013904223u;
            if (len) c[offs[b] + 16 + (seed >> 8) % len] = (uint8_t)(seed >> 24);
        }
        const char *path = ew_t_in_dir(tmp, "bad.dem");
        ew_t_write_file(path, c, size);
        ew_t_run r;
        const char *a[] = {"timedemo", "bad.dem", "--game", demos, "--data", lq, "--size", "320x200", "--quiet", NULL};
        run(&r, a);
        CHECK(r.signal == 0 && (r.status == 0 || (r.status == 1 && count_lines(r.err) == 1)),
              "random bytes %d: status %d signal %d: %s", k, r.status, r.signal, r.err);
    }
    damaged((const uint8_t *)"not a demo at all\n", 18, "not a demo", 0);
    free(c);
    free(data);
}

/* fly --demo: a fixed frame rate, --from/--to, y4m and PNG frames. */
static void fly_demo(void) {
    ew_t_run r;
    const char *a[] = {"fly", "--demo", demo3, "--game", demos, "--data", lq, "--size", "320x200", "--from", "1",
                       "--to", "2", "--fps", "10", "--out", "v.y4m", "--quiet", NULL};
    run(&r, a);
    CHECK(r.status == 0, "fly --demo to y4m: %s", r.err);
    FILE *f = fopen(ew_t_in_dir(tmp, "v.y4m"), "rb");
    long size = -1;
    char head[64] = "";
    if (f) {
        if (!fgets(head, sizeof head, f)) head[0] = 0;
        fseek(f, 0, SEEK_END);
        size = ftell(f);
        fclose(f);
    }
    long frame = 6 + 320 * 200 * 3 / 2;
    CHECK(strncmp(head, "YUV4MPEG2 W320 H200 F10:1", 25) == 0, "y4m header: %s", head);
    CHECK(size == (long)strlen(head) + 11 * frame, "11 frames from 1 s to 2 s at 10 fps (%ld bytes)", size);
    remove(ew_t_in_dir(tmp, "v.y4m"));
    const char *p[] = {"fly", "--demo", demo3, "--game", demos, "--data", lq, "--size", "320x200", "--from", "10",
                       "--to", "10.5", "--fps", "4", "--out", "f%02d.png", "--quiet", "--threads", "2", NULL};
    run(&r, p);
    int n = 0;
    for (int k = 0; k < 4; k++) {
        char name[16];
        snprintf(name, sizeof name, "f%02d.png", k);
        FILE *g = fopen(ew_t_in_dir(tmp, name), "rb");
        if (g) n++, fclose(g), remove(ew_t_in_dir(tmp, name));
    }
    CHECK(r.status == 0 && n == 3, "fly --demo to PNG frames: 3 frames (%d): %s", n, r.err);
    const char *both[] = {"fly", "lqdm3", "--demo", demo3, "--out", "x.y4m", NULL};
    run(&r, both);
    CHECK(r.status == 2 && count_lines(r.err) == 1, "MAP and --demo: one usage line: %s", r.err);
    const char *late[] = {"fly", "--demo", demo3, "--game", demos, "--data", lq, "--from", "500", "--out", "x.y4m", NULL};
    run(&r, late);
    CHECK(r.status == 1 && count_lines(r.err) == 1 && strstr(r.err, "past the demo"), "--from past the end: %s", r.err);
}

int main(void) {
    if (!ew_t_need_shared("data/demos/demo3.dem") || !ew_t_need_shared("data/librequake/progs/player.mdl"))
        return ew_t_finish();
    snprintf(tmp, sizeof tmp, "/tmp/ew_timedemo_XXXXXX");
    if (!mkdtemp(tmp)) {
        CHECK(0, "mkdtemp");
        return ew_t_finish();
    }
    snprintf(demos, sizeof demos, "%s", ew_t_shared_abs("data/demos"));
    snprintf(lq, sizeof lq, "%s", ew_t_shared_abs("data/librequake"));
    snprintf(demo3, sizeof demo3, "%s/demo3.dem", demos);
    play_through();
    still_frames();
    options();
    corrupt();
    fly_demo();
    return ew_t_finish();
}
