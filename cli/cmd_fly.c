/*
 * edgewise fly MAP [--data DIR] [--path views|straight|FILE] [--seconds S] [--fps F]
 *                  [--size WxH] [--cameras FILE] [--quiet] [what is drawn]
 *                  --out FILE.y4m|FILE.mp4|PATTERN.png
 *
 * A flythrough video: a camera path sampled at 1/fps, each frame rendered
 * with the camera's time = frame / fps (skies, liquids, animated textures and
 * light styles move) and written as YUV4MPEG2 (.y4m), piped as y4m to ffmpeg
 * (.mp4), or as one PNG per frame (a printf pattern with one %d).
 */
#define _DEFAULT_SOURCE
#include "cli.h"
#include "edgewise.h"
#include "fly_route.h"
#include "edgewise_lab.h"  /* ew_clock_ms */

#include <errno.h>
#include <pthread.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#define MAX_FPS 240
#define MAX_SECONDS 3600.0
#define SECONDS_PER_SEGMENT 2.0
#define TURN_SECONDS 8.0      /* one origin: a full turn in place */

static const char fly_usage[] =
    "usage: edgewise fly MAP [--data DIR] [--path views|straight|FILE] [--seconds S]\n"
    "                    [--fps F] [--size WxH] [--cameras FILE] [--quiet] [what is drawn]\n"
    "                    --out FILE.y4m|FILE.mp4|DIR/%05d.png\n"
    "       edgewise fly --demo DEMO [--game DIR] [--data DIR] [--from S] [--to S] [--fps F]\n"
    "                    [--size WxH] [--threads N] [...] --out FILE.y4m|FILE.mp4|DIR/%05d.png\n"
    "\n"
    "Renders a flythrough video.  Frame k shows the path at k/F seconds, with the\n"
    "camera's time also k/F, so skies, liquids, animated textures and light\n"
    "styles move.  With --demo: a recorded game at F frames a second (default\n"
    "60), frame k at demo time first + --from + k/F, the entities interpolated\n"
    "between the demo's messages as the game's client does.\n"
    "\n"
    CLI_OPTIONS_HERE
    "\n"
    "Progress goes to stderr on a terminal, else one summary line.  The output is\n"
    "written as FILE.PID.part and renamed when complete: a failed or interrupted\n"
    "run leaves no partial file (a PNG sequence's frames are removed).\n"
    "\n"
    "what is drawn (as in edgewise render):\n";

enum { OUT_Y4M, OUT_MP4, OUT_PNG };

typedef struct fly_opts {
    const char *map, *data, *path, *out, *cameras, *demo;
    double      seconds;   /* 0: the default */
    double      from, to;  /* --demo: seconds after its first frame (to < 0: its end) */
    int         fps, width, height, quiet, kind, threads, path_given, seconds_given;
    draw_opts   draw;
} fly_opts;

/* A path key: position and angles (yaw unwrapped), at a time. */
typedef struct key {
    double t, pos[3], ang[3];
} key;

static int ends_with(const char *s, const char *suffix) {
    size_t n = strlen(s), m = strlen(suffix);
    return n > m && !strcmp(s + n - m, suffix);
}

/* A printf pattern with exactly one %d-style conversion (flags 0 and -,
 * a width) and any number of %%. */
static int png_pattern_ok(const char *s) {
    int conv = 0;
    for (const char *p = s; *p; p++) {
        if (*p != '%') continue;
        if (p[1] == '%') {
            p++;
            continue;
        }
        p++;
        while (*p == '0' || *p == '-') p++;
        int digits = 0;
        while (*p >= '0' && *p <= '9') p++, digits++;
        if (digits > 2 || (*p != 'd' && *p != 'i' && *p != 'u')) return 0;
        conv++;
    }
    return conv == 1;
}

static int parse_number(const char *s, double *out) {
    const char *end;
    return parse_decimal(s, &end, out) == 0 && !*end ? 0 : -1;
}

/* 0, 1 after --help, -1 (error printed). */
static int parse(int argc, char **argv, fly_opts *o) {
    const char *map[1];
    cli_args args;
    cli_args_init(&args, CLI_FLY, argc, argv, map, 1, &o->draw, fly_usage, NULL);
    while (cli_next_arg(&args)) {
        const cli_option *opt = args.opt;
        const char *v = args.value;
        const char *names[] = {"--data", "--path", "--seconds", "--fps", "--size", "--out", "--cameras",
                               "--demo", "--from", "--to", "--threads"};
        int which = 0;
        for (int k = 0; k < 11; k++)
            if (cli_is(opt, names[k])) which = k;
        if (!*v) {
            error_line("%s: empty value", names[which]);
            return -1;
        }
        long l;
        double d;
        switch (which) {
        case 0: o->data = v; break;
        case 1: o->path = v, o->path_given = 1; break;
        case 2:
            if (parse_number(v, &d) < 0 || !(d > 0) || d > MAX_SECONDS) {
                error_line("--seconds %s: must be a number more than 0 up to %g", v, MAX_SECONDS);
                return -1;
            }
            o->seconds = d, o->seconds_given = 1;
            break;
        case 3:
            if (parse_long(v, &l) < 0 || l < 1 || l > MAX_FPS) {
                error_line("--fps %s: must be a whole number from 1 to %d", v, MAX_FPS);
                return -1;
            }
            o->fps = (int)l;
            break;
        case 4:
            if (parse_size(v, &o->width, &o->height) < 0) return -1;
            if (o->width % 2 || o->height % 2) {
                error_line("--size %s: width and height must be even (4:2:0 video)", v);
                return -1;
            }
            break;
        case 5: o->out = v; break;
        case 6: o->cameras = v; break;
        case 7: o->demo = v; break;
        case 8: case 9:
            if (parse_number(v, &d) < 0 || !(d >= 0) || d > MAX_SECONDS) {
                error_line("%s %s: must be a number of seconds from 0 to %g", names[which], v, MAX_SECONDS);
                return -1;
            }
            if (which == 8) o->from = d;
            else o->to = d;
            break;
        case 10:
            if (parse_threads(v, &o->threads) < 0) return -1;
            break;
        }
    }
    if (args.stop)
        return args.stop;
    o->map = args.nmaps ? map[0] : NULL, o->quiet = args.quiet;
    if (o->demo && (o->map || o->path_given || o->seconds_given)) {
        error_line("fly: --demo plays the demo's own map and camera: no MAP, --path or --seconds with it");
        return -1;
    }
    if (!o->demo && (o->from > 0 || o->to >= 0)) {
        error_line("fly: --from and --to are for --demo");
        return -1;
    }
    if (o->demo && o->to >= 0 && o->to <= o->from) {
        error_line("fly: --to %g must come after --from %g", o->to, o->from);
        return -1;
    }
    if (!o->map && !o->demo) {
        error_line("fly: no map given (see edgewise fly --help)");
        return -1;
    }
    if (!o->out) {
        error_line("fly: --out FILE.y4m|FILE.mp4|PATTERN.png is required");
        return -1;
    }
    if (strchr(o->out, '%')) {
        if (!png_pattern_ok(o->out) || !ends_with(o->out, ".png")) {
            error_line("--out %s: a frame pattern needs exactly one %%d conversion (e.g. %%05d) and ends "
                       "in .png", o->out);
            return -1;
        }
        o->kind = OUT_PNG;
    } else if (ends_with(o->out, ".y4m")) {
        o->kind = OUT_Y4M;
    } else if (ends_with(o->out, ".mp4")) {
        o->kind = OUT_MP4;
    } else {
        error_line("--out %s: unknown kind of output (expected .y4m, .mp4, or a pattern like %%05d.png)",
                   o->out);
        return -1;
    }
    return 0;
}

/* 1 if an executable NAME is in a directory of PATH. */
static int on_path(const char *name) {
    const char *path = getenv("PATH");
    if (!path) return 0;
    while (*path) {
        size_t n = strcspn(path, ":");
        char file[4096];
        snprintf(file, sizeof file, "%.*s/%s", (int)(n ? n : 1), n ? path : ".", name);
        struct stat st;
        if (stat(file, &st) == 0 && S_ISREG(st.st_mode) && access(file, X_OK) == 0) return 1;
        path += n;
        if (*path == ':') path++;
    }
    return 0;
}

/* ---- the path ---------------------------------------------------------------- */

/* Makes each angle the nearest equivalent of the previous key's (no flips). */
static void unwrap_angles(key *k, int n) {
    for (int i = 1; i < n; i++)
        for (int c = 0; c < 3; c++) {
            double d = fmod(k[i].ang[c] - k[i - 1].ang[c], 360.0);
            if (d > 180) d -= 360;
            if (d < -180) d += 360;
            k[i].ang[c] = k[i - 1].ang[c] + d;
        }
}

static double wrap180(double a) {
    a = fmod(a, 360.0);
    if (a > 180) a -= 360;
    if (a <= -180) a += 360;
    return a;
}

/* The distinct view origins as keys; their count. */
static int view_keys(const ew_world *w, key *k) {
    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(w, views), n = 0;
    for (int i = 0; i < nv; i++) {
        int seen = 0;
        for (int j = 0; j < n && !seen; j++)
            seen = k[j].pos[0] == views[i].origin[0] && k[j].pos[1] == views[i].origin[1] &&
                   k[j].pos[2] == views[i].origin[2];
        if (seen) continue;
        for (int c = 0; c < 3; c++) k[n].pos[c] = views[i].origin[c], k[n].ang[c] = views[i].angles[c];
        n++;
    }
    unwrap_angles(k, n);
    return n;
}

static double catmull_rom(double p0, double p1, double p2, double p3, double t) {
    return 0.5 * (2 * p1 + (p2 - p0) * t + (2 * p0 - 5 * p1 + 4 * p2 - p3) * t * t +
                  (3 * p1 - p0 - 3 * p2 + p3) * t * t * t);
}

/* The default path (fly_route.c): the views whose eyes are in the open and
 * that a path through open space reaches, kept in k (in order, their count
 * returned), the path between them in *route.  A skipped view is named in
 * a warning.  -1 with the error printed. */
static int open_route(const ew_world *w, const char *map, int quiet, key *k, int n, fly_route **route) {
    double (*pos)[3] = malloc(sizeof *pos * (size_t)n);
    int *kept = malloc(sizeof *kept * (size_t)n), nkept = 0;
    if (!pos || !kept) {
        free(pos);
        free(kept);
        error_line("out of memory");
        return -1;
    }
    for (int i = 0; i < n; i++) memcpy(pos[i], k[i].pos, sizeof pos[i]);
    *route = fly_route_build(w, (const double(*)[3])pos, n, kept, &nkept);
    if (*route) {
        for (int i = 0, j = 0; i < n; i++) {
            if (j < nkept && kept[j] == i) {
                k[j++] = k[i];
                continue;
            }
            if (!quiet)
                fprintf(stderr, "edgewise: warning: %s: fly: skipped the view at %g,%g,%g: its eye is in solid or "
                        "the sky, or no path through open space reaches it\n", map, pos[i][0], pos[i][1],
                        pos[i][2]);
        }
        unwrap_angles(k, nkept);
    }
    free(pos);
    free(kept);
    return *route ? nkept : 0;
}

/* The camera at fraction f (0..1) of the view path: the views' own
 * Catmull-Rom spline (route NULL, --path straight) or the route. */
static void views_camera(const key *k, int n, const fly_route *route, double f, ew_camera *cam) {
    if (n == 1) {
        for (int c = 0; c < 3; c++) cam->origin[c] = (float)k[0].pos[c];
        cam->angles[0] = 0;
        cam->angles[1] = (float)wrap180(k[0].ang[1] + 360 * f);
        cam->angles[2] = 0;
        return;
    }
    double u = f * (n - 1);
    int s = (int)floor(u);
    if (s > n - 2) s = n - 2;
    if (s < 0) s = 0;
    double t = u - s;
    const key *p0 = &k[s > 0 ? s - 1 : 0], *p1 = &k[s], *p2 = &k[s + 1], *p3 = &k[s + 2 < n ? s + 2 : n - 1];
    double eye[3];
    if (route) fly_route_eye(route, s, t, eye);
    for (int c = 0; c < 3; c++) {
        cam->origin[c] = (float)(route ? eye[c] : catmull_rom(p0->pos[c], p1->pos[c], p2->pos[c], p3->pos[c], t));
        /* Smoothstep between the two views' angles: no overshoot, no flip. */
        double e = t * t * (3 - 2 * t);
        cam->angles[c] = (float)wrap180(p1->ang[c] + (p2->ang[c] - p1->ang[c]) * e);
    }
}

/* Lines longer than this are refused as such (comments of any length are
 * skipped); a camera line is seven numbers. */
#define PATH_LINE_MAX 4096
/* The camera values --pos and --angles accept (the renderer's limit). */
#define PATH_COORD_MAX 1e6

static int is_blank(int c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

/* One line of f, of any length, without its '\n': the first size - 1 bytes
 * in buf, the rest read and dropped (*longer set).  *nul: it holds a NUL
 * byte.  0 at the end of the file, 1, or -1 on a read error. */
static int read_line(FILE *f, char *buf, size_t size, int *longer, int *nul) {
    size_t n = 0;
    int c, any = 0;
    *longer = *nul = 0;
    while ((c = getc(f)) != EOF) {
        any = 1;
        if (c == '\n') break;
        if (c == '\0') *nul = 1;
        if (n + 1 < size) buf[n++] = (char)c;
        else *longer = 1;
    }
    buf[n] = '\0';
    if (ferror(f)) return -1;
    return any;
}

/* A recorded path: keys with times from the first line's (0) and unwrapped
 * angles; the times span at most MAX_SECONDS, like --seconds.  The count,
 * or -1 (one error line naming the file and the line). */
static int read_path(const char *file, key **out) {
    FILE *f = fopen(file, "r");
    if (!f) {
        error_line("--path %s: %s", file, strerror(errno));
        return -1;
    }
    key *k = NULL;
    int n = 0, cap = 0, lineno = 0, got, longer, nul;
    double t0 = 0;
    char *line = malloc(PATH_LINE_MAX);
    if (!line) {
        error_line("--path %s: out of memory", file);
        fclose(f);
        return -1;
    }
    while ((got = read_line(f, line, PATH_LINE_MAX, &longer, &nul)) > 0) {
        lineno++;
        if (nul) {
            error_line("--path %s:%d: a NUL byte (not a text file)", file, lineno);
            goto fail;
        }
        const char *p = line;
        while (is_blank(*p)) p++;
        if (*p == '#') continue;  /* a comment, however long */
        if (longer) {
            error_line("--path %s:%d: line longer than %d bytes", file, lineno, PATH_LINE_MAX - 1);
            goto fail;
        }
        if (*p == '\0') continue;
        double v[7];
        int fields = 0;
        const char *end = p;
        while (fields < 7 && parse_decimal(p, &end, &v[fields]) == 0 && (is_blank(*end) || !*end)) {
            fields++;
            for (p = end; is_blank(*p); p++) {}
        }
        if (fields < 7 || *p) {
            error_line("--path %s:%d: expected 'time x y z pitch yaw roll', seven decimal numbers", file, lineno);
            goto fail;
        }
        key kk = {v[0], {v[1], v[2], v[3]}, {v[4], v[5], v[6]}};
        if (kk.t < 0) {
            error_line("--path %s:%d: time %g is negative", file, lineno, kk.t);
            goto fail;
        }
        if (!n) t0 = kk.t;
        if (n && kk.t < t0 + k[n - 1].t) {
            error_line("--path %s:%d: time %g goes back (the line before has %g)", file, lineno, kk.t,
                       t0 + k[n - 1].t);
            goto fail;
        }
        /* As long as --seconds allows: a later time would ask for more
         * frames than any video fly writes (or overflow their count). */
        if (kk.t - t0 > MAX_SECONDS) {
            error_line("--path %s:%d: time %g is %g s after the first line's; a path spans at most %g s (as "
                       "--seconds)", file, lineno, kk.t, kk.t - t0, MAX_SECONDS);
            goto fail;
        }
        for (int c = 0; c < 3; c++)
            if (fabs(kk.pos[c]) > PATH_COORD_MAX || fabs(kk.ang[c]) > PATH_COORD_MAX) {
                error_line("--path %s:%d: position and angles must be from -%.0f to %.0f (as --pos and --angles)",
                           file, lineno, PATH_COORD_MAX, PATH_COORD_MAX);
                goto fail;
            }
        kk.t -= t0;  /* times from 0: no precision lost adding small steps to a large t0 */
        if (n == cap) {
            cap = cap ? cap * 2 : 64;
            key *q = realloc(k, sizeof *q * (size_t)cap);
            if (!q) {
                error_line("--path %s: out of memory", file);
                goto fail;
            }
            k = q;
        }
        k[n++] = kk;
    }
    if (got < 0) {
        error_line("--path %s: %s", file, strerror(errno));
        goto fail;
    }
    free(line);
    fclose(f);
    if (!n) {
        error_line("--path %s: no camera lines", file);
        free(k);
        return -1;
    }
    unwrap_angles(k, n);
    *out = k;
    return n;
fail:
    free(line);
    free(k);
    fclose(f);
    return -1;
}

/* The recorded path's camera at time t (linear between lines; the last
 * line of a run of equal times). */
static void file_camera(const key *k, int n, double t, ew_camera *cam) {
    int i = 0;
    while (i + 1 < n && k[i + 1].t <= t) i++;
    const key *a = &k[i], *b = &k[i + 1 < n ? i + 1 : i];
    double f = b->t > a->t ? (t - a->t) / (b->t - a->t) : 0;
    if (f < 0) f = 0;
    if (f > 1) f = 1;
    for (int c = 0; c < 3; c++) {
        cam->origin[c] = (float)(a->pos[c] + (b->pos[c] - a->pos[c]) * f);
        cam->angles[c] = (float)wrap180(a->ang[c] + (b->ang[c] - a->ang[c]) * f);
    }
}

/* ---- output ---------------------------------------------------------------- */

/* The frame as RGB bytes. */
static void frame_rgb(const ew_renderer *r, uint8_t *rgb, size_t n) {
    const uint8_t *px = ew_frame_pixels(r);
    if (px) {
        const uint8_t *pal = ew_frame_palette(r);
        for (size_t i = 0; i < n; i++) memcpy(rgb + 3 * i, pal + 3 * px[i], 3);
    } else {
        const uint8_t *c = (const uint8_t *)ew_frame_rgba(r);
        for (size_t i = 0; i < n; i++) memcpy(rgb + 3 * i, c + 4 * i, 3);
    }
}

static uint8_t clamp8(double v) { return (uint8_t)(v < 0 ? 0 : v > 255 ? 255 : lround(v)); }

/* BT.601 full range (JPEG): Y plane, then Cb and Cr averaged over 2x2. */
static void rgb_to_yuv420(const uint8_t *rgb, int w, int h, uint8_t *yuv) {
    uint8_t *Y = yuv, *U = yuv + (size_t)w * h, *V = U + (size_t)(w / 2) * (h / 2);
    for (size_t i = 0; i < (size_t)w * h; i++) {
        const uint8_t *p = rgb + 3 * i;
        Y[i] = clamp8(0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2]);
    }
    for (int y = 0; y < h / 2; y++)
        for (int x = 0; x < w / 2; x++) {
            double cb = 0, cr = 0;
            for (int dy = 0; dy < 2; dy++)
                for (int dx = 0; dx < 2; dx++) {
                    const uint8_t *p = rgb + 3 * ((size_t)(2 * y + dy) * w + 2 * x + dx);
                    cb += 128 - 0.168736 * p[0] - 0.331264 * p[1] + 0.5 * p[2];
                    cr += 128 + 0.5 * p[0] - 0.418688 * p[1] - 0.081312 * p[2];
                }
            U[(size_t)y * (w / 2) + x] = clamp8(cb / 4);
            V[(size_t)y * (w / 2) + x] = clamp8(cr / 4);
        }
}

/* The same conversion of an 8-bit frame through tables by palette index:
 * each pixel's Y, and its Cb and Cr terms, are the doubles rgb_to_yuv420
 * computes from that colour, summed in the same order, so the bytes are
 * the same; a table lookup instead of the arithmetic per pixel. */
static void indexed_to_yuv420(const uint8_t *px, const uint8_t pal[768], int w, int h, uint8_t *yuv) {
    uint8_t ylut[256];
    double cbt[256], crt[256];
    for (int i = 0; i < 256; i++) {
        const uint8_t *p = pal + 3 * i;
        ylut[i] = clamp8(0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2]);
        cbt[i] = 128 - 0.168736 * p[0] - 0.331264 * p[1] + 0.5 * p[2];
        crt[i] = 128 + 0.5 * p[0] - 0.418688 * p[1] - 0.081312 * p[2];
    }
    uint8_t *Y = yuv, *U = yuv + (size_t)w * h, *V = U + (size_t)(w / 2) * (h / 2);
    for (size_t i = 0; i < (size_t)w * h; i++) Y[i] = ylut[px[i]];
    for (int y = 0; y < h / 2; y++) {
        const uint8_t *r0 = px + (size_t)(2 * y) * w, *r1 = r0 + w;
        for (int x = 0; x < w / 2; x++) {
            double cb = 0, cr = 0;
            cb += cbt[r0[2 * x]], cr += crt[r0[2 * x]];
            cb += cbt[r0[2 * x + 1]], cr += crt[r0[2 * x + 1]];
            cb += cbt[r1[2 * x]], cr += crt[r1[2 * x]];
            cb += cbt[r1[2 * x + 1]], cr += crt[r1[2 * x + 1]];
            U[(size_t)y * (w / 2) + x] = clamp8(cb / 4);
            V[(size_t)y * (w / 2) + x] = clamp8(cr / 4);
        }
    }
}

/* The y4m frames are written by a thread of their own while the next frame
 * is drawn and converted: two buffers, the one being written and the one
 * being filled.  ok 0 once a write failed (errno_ the error). */
typedef struct frame_writer {
    pthread_t       thread;
    pthread_mutex_t m;
    pthread_cond_t  cv;
    FILE           *f;
    const uint8_t  *buf;   /* the frame to write, NULL when none waits */
    size_t          n;
    int             quit, ok, err_no, started;
} frame_writer;

static void *writer_main(void *arg) {
    frame_writer *w = arg;
    pthread_mutex_lock(&w->m);
    for (;;) {
        while (!w->buf && !w->quit) pthread_cond_wait(&w->cv, &w->m);
        if (!w->buf) break;
        const uint8_t *buf = w->buf;
        size_t n = w->n;
        pthread_mutex_unlock(&w->m);
        errno = 0;
        int ok = fputs("FRAME\n", w->f) >= 0 && fwrite(buf, 1, n, w->f) == n;
        int e = errno;
        pthread_mutex_lock(&w->m);
        if (!ok && w->ok) w->ok = 0, w->err_no = e;
        w->buf = NULL;
        pthread_cond_broadcast(&w->cv);
    }
    pthread_mutex_unlock(&w->m);
    return NULL;
}

static int writer_start(frame_writer *w, FILE *f) {
    memset(w, 0, sizeof *w);
    w->f = f, w->ok = 1;
    pthread_mutex_init(&w->m, NULL);
    pthread_cond_init(&w->cv, NULL);
    if (pthread_create(&w->thread, NULL, writer_main, w) != 0) {
        pthread_mutex_destroy(&w->m);
        pthread_cond_destroy(&w->cv);
        return -1;
    }
    w->started = 1;
    return 0;
}

/* Waits until the writer is idle: 0, or -1 if a write failed. */
static int writer_wait(frame_writer *w) {
    pthread_mutex_lock(&w->m);
    while (w->buf) pthread_cond_wait(&w->cv, &w->m);
    int ok = w->ok;
    pthread_mutex_unlock(&w->m);
    return ok ? 0 : -1;
}

/* Hands buf (n bytes, left alone until the next call) to the writer after
 * the frame before it is written: 0, or -1 if a write failed. */
static int writer_put(frame_writer *w, const uint8_t *buf, size_t n) {
    pthread_mutex_lock(&w->m);
    while (w->buf) pthread_cond_wait(&w->cv, &w->m);
    int ok = w->ok;
    if (ok) {
        w->buf = buf, w->n = n;
        pthread_cond_broadcast(&w->cv);
    }
    pthread_mutex_unlock(&w->m);
    return ok ? 0 : -1;
}

static void writer_stop(frame_writer *w) {
    if (!w->started) return;
    pthread_mutex_lock(&w->m);
    while (w->buf) pthread_cond_wait(&w->cv, &w->m);
    w->quit = 1;
    pthread_cond_broadcast(&w->cv);
    pthread_mutex_unlock(&w->m);
    pthread_join(w->thread, NULL);
    pthread_mutex_destroy(&w->m);
    pthread_cond_destroy(&w->cv);
    w->started = 0;
}

/* ffmpeg reading y4m on its stdin; the pipe's write end, or NULL. */
static FILE *start_ffmpeg(const char *out, pid_t *pid) {
    int fds[2];
    if (pipe(fds) < 0) return NULL;
    fflush(NULL);
    *pid = fork();
    if (*pid < 0) {
        close(fds[0]), close(fds[1]);
        return NULL;
    }
    if (*pid == 0) {
        dup2(fds[0], 0);
        close(fds[0]), close(fds[1]);
        execlp("ffmpeg", "ffmpeg", "-y", "-loglevel", "error", "-f", "yuv4mpegpipe", "-i", "-", "-c:v",
               "libx264", "-pix_fmt", "yuv420p", "-f", "mp4", out, (char *)NULL);  /* out: a temporary name */
        _exit(127);
    }
    close(fds[0]);
    FILE *f = fdopen(fds[1], "wb");
    if (!f) close(fds[1]);
    return f;
}

static void fmt_time(char *out, size_t size, double s) {
    if (!(s >= 0) || s > 1e7) snprintf(out, size, "--:--");
    else snprintf(out, size, "%d:%02d", (int)s / 60, (int)s % 60);
}

/* ---- the command -------------------------------------------------------------- */

/* Every file fly writes goes first under a temporary name beside its own
 * (FILE.PID.part) and is renamed into place once the whole video is
 * written: a failed or interrupted run leaves no partial file and keeps an
 * older one intact.  A PNG sequence is written in place, and the frames of
 * a failed run are removed. */
static void part_name(char *out, size_t size, const char *file) {
    snprintf(out, size, "%s.%ld.part", file, (long)getpid());
}

static volatile sig_atomic_t stop_signal;
static void on_stop(int sig) { stop_signal = sig; }

int cmd_fly(int argc, char **argv) {
    fly_opts o;
    memset(&o, 0, sizeof o);
    o.fps = 0, o.width = 640, o.height = 360, o.path = "views", o.threads = 1, o.to = -1;
    draw_opts_init(&o.draw);
    int pr = parse(argc, argv, &o);
    if (pr) return pr > 0 ? 0 : 2;
    if (!o.fps) o.fps = o.demo ? 60 : 30;
    if (o.kind == OUT_MP4 && !on_path("ffmpeg")) {
        error_line("--out %s: writing .mp4 needs ffmpeg, which is not on PATH (write .y4m instead)", o.out);
        return 1;
    }
    /* Said now, not after the whole video went to a temporary file. */
    struct stat st;
    if (o.kind != OUT_PNG && stat(o.out, &st) == 0 && S_ISDIR(st.st_mode)) {
        error_line("--out %s: is a directory", o.out);
        return 1;
    }
    if (o.cameras && stat(o.cameras, &st) == 0 && S_ISDIR(st.st_mode)) {
        error_line("--cameras %s: is a directory", o.cameras);
        return 1;
    }
    key *keys = NULL;
    int nkeys = 0, straight = !strcmp(o.path, "straight"), from_file = !straight && strcmp(o.path, "views") != 0;
    fly_route *route = NULL;
    if (from_file && (nkeys = read_path(o.path, &keys)) < 0) return 1;

    int rc = 1;
    ew_assets *a = NULL;
    ew_demo *demo = NULL;
    ew_demo_client *dc = NULL;
    double demo_t0 = 0, demo_t1 = 0;
    ew_scene *scene = NULL;
    ew_renderer *r = NULL;
    FILE *video = NULL, *cams = NULL;
    pid_t ff = -1;
    uint8_t *rgb = NULL, *yuv = NULL, *yuv_bufs[2] = {NULL, NULL};
    frame_writer writer;
    memset(&writer, 0, sizeof writer);
    ew_error err = {""};
    char out_part[4200] = "", cams_part[4200] = "";
    long written = 0;  /* PNG frames written */
    if (o.demo) {
        if (demo_open_with_map(o.demo, o.data, o.quiet, &demo, &a) < 0) goto done;
        /* its span: from the view entity's first update to the last message */
        const ew_demo_state *ds = ew_demo_get_state(demo);
        int rd, seen = 0;
        while ((rd = ew_demo_read_block(demo, &err)) == 1) {
            if (!seen && ds->view_entity > 0 && ds->view_entity < ds->nentities &&
                ds->entities[ds->view_entity].msgtime >= 0)
                seen = 1, demo_t0 = ds->time;
            demo_t1 = ds->time;
        }
        if (rd < 0) {
            error_line("%s", err.msg);
            goto done;
        }
        if (!seen) {
            error_line("%s: the demo never shows its view entity: nothing to draw", o.demo);
            goto done;
        }
        ew_demo_rewind(demo);
        if (!(dc = ew_demo_client_create(demo, a->world, cli_search_path(o.data), &err))) {
            error_line("%s", err.msg);
            goto done;
        }
        if (ew_demo_client_missing(dc) && !o.quiet)
            error_line("warning: %s: %d model files missing (not drawn)", o.demo, ew_demo_client_missing(dc));
    } else {
        a = load_map(o.map, o.data, o.quiet);
    }
    if (!a) goto done;
    double seconds;
    if (o.demo) {
        double end = o.to >= 0 && o.to < demo_t1 - demo_t0 ? o.to : demo_t1 - demo_t0;
        if (!(end > o.from)) {
            error_line("%s: --from %g is past the demo's end (%.3f s)", o.demo, o.from, demo_t1 - demo_t0);
            goto done;
        }
        seconds = end - o.from + 1.0 / o.fps;  /* the last frame at end */
    } else if (!from_file) {
        keys = malloc(sizeof *keys * EW_MAX_VIEWS);
        if (!keys) goto done;
        nkeys = view_keys(a->world, keys);
        if (!nkeys) {
            error_line("%s: no views (no info_player* or info_intermission entity); use --path FILE", o.map);
            goto done;
        }
        if (!straight && (nkeys = open_route(a->world, o.map, o.quiet, keys, nkeys, &route)) <= 0) {
            if (nkeys == 0)
                error_line("%s: no view has its eye in the open (all in solid or the sky); use --path straight "
                           "or --path FILE", o.map);
            goto done;
        }
        seconds = o.seconds > 0 ? o.seconds : nkeys == 1 ? TURN_SECONDS : SECONDS_PER_SEGMENT * (nkeys - 1);
    } else {
        seconds = o.seconds > 0 ? o.seconds : keys[nkeys - 1].t + 1.0 / o.fps;
    }
    /* At most MAX_SECONDS (a path: its span, checked by read_path, and one
     * frame more) at MAX_FPS: checked before lround can overflow. */
    double nframes = seconds * o.fps;
    if (!(nframes <= MAX_SECONDS * MAX_FPS + 1.5)) {
        error_line("fly: %.6g frames asked for; at most %g s at %d fps", nframes, MAX_SECONDS, MAX_FPS);
        goto done;
    }
    long frames = lround(nframes);
    if (frames < 1) frames = 1;

    if (!dc && draw_opts_scene(&o.draw, a, o.map, o.data, 0, o.quiet, &scene) < 0) goto done;
    ew_scene *draw_scene = dc ? (o.draw.no_entities ? NULL : ew_demo_client_scene(dc)) : scene;
    r = ew_renderer_create(&(ew_renderer_desc){ .world = a->world, .palette = a->palette,
            .colormap = a->colormap, .width = o.width, .height = o.height, .threads = o.threads,
            .color = (ew_color_mode)o.draw.color }, &err);
    if (!r || draw_opts_apply(&o.draw, r, draw_scene) < 0) {
        error_line("%s", err.msg[0] ? err.msg : "cannot create the renderer");
        goto done;
    }
    size_t npx = (size_t)o.width * o.height;
    rgb = malloc(npx * 3);
    yuv_bufs[0] = malloc(npx * 3 / 2);
    yuv_bufs[1] = malloc(npx * 3 / 2);
    yuv = yuv_bufs[0];
    if (!rgb || !yuv_bufs[0] || !yuv_bufs[1]) {
        error_line("out of memory");
        goto done;
    }
    /* Ctrl-C or a kill: the loop stops and the partial files are removed. */
    signal(SIGINT, on_stop);
    signal(SIGTERM, on_stop);
    signal(SIGHUP, on_stop);
    if (o.cameras) {
        part_name(cams_part, sizeof cams_part, o.cameras);
        if (!(cams = fopen(cams_part, "w"))) {
            cams_part[0] = '\0';
            error_line("--cameras %s: %s", o.cameras, strerror(errno));
            goto done;
        }
    }
    if (o.kind != OUT_PNG) part_name(out_part, sizeof out_part, o.out);
    if (o.kind == OUT_Y4M && !(video = fopen(out_part, "wb"))) {
        out_part[0] = '\0';
        error_line("--out %s: %s", o.out, strerror(errno));
        goto done;
    }
    if (o.kind == OUT_MP4) {
        signal(SIGPIPE, SIG_IGN);
        if (!(video = start_ffmpeg(out_part, &ff))) {
            error_line("--out %s: cannot start ffmpeg: %s", o.out, strerror(errno));
            goto done;
        }
    }
    if (video) fprintf(video, "YUV4MPEG2 W%d H%d F%d:1 Ip A1:1 C420jpeg\n", o.width, o.height, o.fps);
    if (video && writer_start(&writer, video) < 0) {
        error_line("--out %s: cannot start the writer thread", o.out);
        goto done;
    }

    int tty = isatty(2);
    double start = ew_clock_ms(), last = 0;
    long dark_frames = 0, first_dark = -1;
    char dark_why[400] = "";
    for (long k = 0; k < frames; k++) {
        if (stop_signal) {
            error_line("fly: stopped by signal %d after %ld of %ld frames; nothing written", (int)stop_signal, k,
                       frames);
            goto done;
        }
        ew_camera cam;
        memset(&cam, 0, sizeof cam);
        double t = (double)k / o.fps;
        if (dc) {
            t = demo_t0 + o.from + t;
            if (ew_demo_client_advance(dc, t, &err) < 0) {
                error_line("%s", err.msg);
                goto done;
            }
            ew_demo_client_frame(dc, t, &cam);  /* the camera, fov 90, time t */
            demo_apply_lightstyles(r, ew_demo_get_state(demo), &o.draw);
            if (draw_scene) ew_set_scene(r, draw_scene);
        } else {
            if (from_file) file_camera(keys, nkeys, t, &cam);
            else views_camera(keys, nkeys, route, t / seconds, &cam);
            cam.fov = 90;
            cam.time = t;
        }
        if (cams)
            fprintf(cams, "%ld %.17g %.9g %.9g %.9g %.9g %.9g %.9g\n", k, cam.time, cam.origin[0], cam.origin[1],
                    cam.origin[2], cam.angles[0], cam.angles[1], cam.angles[2]);
        if (ew_render(r, &cam, NULL) < 0 || !(ew_frame_pixels(r) || ew_frame_rgba(r))) {
            error_line("frame %ld: cannot render this camera (origin %g,%g,%g angles %g,%g,%g)", k, cam.origin[0],
                       cam.origin[1], cam.origin[2], cam.angles[0], cam.angles[1], cam.angles[2]);
            goto done;
        }
        /* Nearly black frames: counted, one warning a run (below) with the first one's cause. */
        double luma = frame_mean_luma(r);
        if (luma < DARK_LUMA && dark_frames++ == 0) {
            first_dark = k;
            dark_cause(r, a->world, &cam, dark_why, sizeof dark_why);
        }
        if (o.kind == OUT_PNG) {
            char file[4200];
            snprintf(file, sizeof file, o.out, (int)k);
            if (ew_write_frame_png(r, file, &err) < 0) {
                error_line("%s", err.msg);
                goto done;
            }
            written = k + 1;
        } else {
            if (ew_frame_pixels(r)) {
                indexed_to_yuv420(ew_frame_pixels(r), ew_frame_palette(r), o.width, o.height, yuv);
            } else {
                frame_rgb(r, rgb, npx);
                rgb_to_yuv420(rgb, o.width, o.height, yuv);
            }
            if (writer_put(&writer, yuv, npx * 3 / 2) < 0) {
                error_line("--out %s: %s", o.out, o.kind == OUT_MP4 ? "ffmpeg stopped reading" : strerror(writer.err_no));
                goto done;
            }
            yuv = yuv == yuv_bufs[0] ? yuv_bufs[1] : yuv_bufs[0];  /* the next frame goes into the other */
        }
        double now = ew_clock_ms();
        if (tty && (now - last > 100 || k + 1 == frames)) {
            last = now;
            double el = (now - start) / 1000;
            char e[32], left[32];
            fmt_time(e, sizeof e, el);
            fmt_time(left, sizeof left, el / (double)(k + 1) * (double)(frames - k - 1));
            fprintf(stderr, "\r\033[Kfly: %ld/%ld frames, %s elapsed, %s left", k + 1, frames, e, left);
            fflush(stderr);
        }
    }
    if (tty) fputc('\n', stderr);
    if (writer.started) {
        int wr = writer_wait(&writer);
        writer_stop(&writer);
        if (wr < 0) {
            error_line("--out %s: %s", o.out, o.kind == OUT_MP4 ? "ffmpeg stopped reading" : strerror(writer.err_no));
            goto done;
        }
    }
    if (dark_frames && !o.quiet)
        error_line("warning: fly: %ld of %ld frames are nearly black (mean brightness under %.1f%% of full scale); "
                   "the first, frame %ld: %s", dark_frames, frames, DARK_LUMA / 2.55, first_dark, dark_why);
    if (video) {
        FILE *v = video;
        video = NULL;
        if (fclose(v) != 0) {
            error_line("--out %s: %s", o.out, strerror(errno));
            goto done;
        }
    }
    if (ff > 0) {
        int status = 0;
        waitpid(ff, &status, 0);
        ff = -1;
        if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
            error_line("--out %s: ffmpeg failed (exit status %d)", o.out, WIFEXITED(status) ? WEXITSTATUS(status) : -1);
            goto done;
        }
    }
    if (cams) {
        FILE *c = cams;
        cams = NULL;
        if (fclose(c) != 0) {
            error_line("--cameras %s: %s", o.cameras, strerror(errno));
            goto done;
        }
    }
    /* Everything is written: into place. */
    if (out_part[0]) {
        if (rename(out_part, o.out) != 0) {
            error_line("--out %s: %s", o.out, strerror(errno));
            goto done;
        }
        out_part[0] = '\0';
    }
    if (cams_part[0]) {
        if (rename(cams_part, o.cameras) != 0) {
            error_line("--cameras %s: %s", o.cameras, strerror(errno));
            goto done;
        }
        cams_part[0] = '\0';
    }
    rc = 0;
    written = 0;
    double secs = (ew_clock_ms() - start) / 1000;
    fprintf(stderr, "fly: %ld frames %dx%d at %d fps (%.2f s of video) written to %s in %.1f s (%.1f frames/s)\n",
            frames, o.width, o.height, o.fps, (double)frames / o.fps, o.out, secs,
            secs > 0 ? (double)frames / secs : 0);
done:
    writer_stop(&writer);  /* before its file is closed */
    if (video) fclose(video);
    if (ff > 0) waitpid(ff, NULL, 0);
    if (cams) fclose(cams);
    /* A failed run: what it wrote goes. */
    if (out_part[0]) unlink(out_part);
    if (cams_part[0]) unlink(cams_part);
    for (long k = 0; k < written; k++) {
        char file[4200];
        snprintf(file, sizeof file, o.out, (int)k);
        unlink(file);
    }
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
    signal(SIGHUP, SIG_DFL);
    free(rgb);
    free(yuv_bufs[0]);
    free(yuv_bufs[1]);
    free(keys);
    fly_route_destroy(route);
    ew_renderer_destroy(r);
    ew_scene_destroy(scene);
    ew_demo_client_destroy(dc);
    ew_demo_close(demo);
    ew_assets_destroy(a);
    return rc;
}
