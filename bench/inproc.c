/* bench/inproc.c: two builds of the library timed frame by frame in one
 * process (bench/compare.sh with INPROC=1 builds and runs it).
 *
 * Side A is the library linked as is (ew_*), side B a second library whose
 * symbols compare.sh renamed to b_ew_* (objcopy --redefine-syms).  Each side
 * loads its own world and scene, so the two revisions' internal structures
 * may differ; only the public calls below must be the same.  Every view of
 * the view set is rendered by A and by B in turn, the order swapped from
 * frame to frame, so both sides see the machine in the same state to within
 * a frame: on a shared machine whose speed drifts by 10-20% from one run to
 * the next, the ratio of the two then holds to about 1%, where separate
 * bench runs needed many rounds to resolve 5%.
 *
 * One warm-up pass, whose frames are also compared byte for byte (a change
 * meant to keep the pixels must show 0 frames differing), then P timed
 * passes.  Per map and size: each side's mean over the views of the
 * view's median frame time, B/A of those, B/A of the two sides' median
 * frames (bench's median_ms), and the median and range of the per-view
 * ratios.
 *
 * What is drawn: --fog D,R,G,B, --no-fog, --color 8bit|true, --hsr METHOD, --no-lit
 * and --classic go to both sides, and so does --simd best|sse2|avx2|avx512
 * (ew_set_simd: how wide the fog's loops may be, to time on this machine
 * what a processor without AVX-512 or AVX2 runs) and --occlusion
 * off|auto|always (ew_set_occlusion_cull); --a-args "OPTS" and --b-args
 * "OPTS" (those options,
 * split at spaces) to one side after them.  With the same revision on
 * both sides (bench/compare.sh WORKTREE WORKTREE) that times one library
 * against itself under two option sets: e.g. --b-args "--fog 1,0.3,0.3,0.35"
 * gives the cost of fog as B/A, each view with and without fog in turn.
 * Frames are compared as RGB (8-bit ones through the palette): the last
 * columns are the pixels that differ over the warm-up pass's views and
 * the largest difference of a channel.
 *
 * --stage front|scan|draw|models times one stage of the frame instead (the
 * renderer's own ew_stats times), so a change to that stage alone is not
 * lost in the frame's noise; --per-view prints each view's two medians.
 *
 * --color true renders both sides in true colour (frames compared as 4-byte
 * pixels), --no-lit without the maps' coloured light (ew_set_lit), --cold
 * each frame after the side's surface cache was emptied (ew_flush_surfaces,
 * untimed), so a frame pays for every surface it builds, as the first frame
 * of a new view does.  --vs-color draws side A in 8-bit and side B in true
 * colour (frames not compared): B/A is then what true colour costs over
 * 8-bit; run it with the same revision on both sides.  slow_B/A is B's
 * slowest view (its median) over A's slowest view: the worst frame's ratio
 * without one-off spikes.
 *
 * Built with EW_INPROC_OLD, side A is instead a revision from before these
 * public calls (cde885f, the many-core work's baseline), reached through
 * bench/inproc_old.c built against that revision's header; --classic then
 * goes to side B only (the old revision's one look was the classic one).
 *
 * --threads-vs A,N times the same library on A threads and on N threads
 * instead, alternating frame by frame as above (so the machine's drift
 * cancels), and prints per map and size the speed-up of N over A (ratio
 * of the means, of the median frames, the per-view ratios' median and
 * range) beside the speed-up bench's model predicts (`edgewise bench
 * --threads 1 --bands N`, run after the timing: its predicted_speedup_N
 * and sched_speedup_N; --bench PATH names the command, by default the
 * `edgewise` beside this program; --no-model skips it).  Built with
 * EW_INPROC_SELF (the `inproc` target of CMake), both sides are this
 * library and no second one is linked; then `work` is the N-thread
 * frames' processor time over the A-thread frames' (ew_lab_stats.ms_work:
 * the caller's and the workers' time in jobs), the extra work the threads
 * do, which the load of other processes does not change as it changes
 * wall time (NaN otherwise).
 *
 * --per-cpu (with --threads-vs 1,N; Linux) also renders each view on side
 * A pinned to each processor the process may run on, in turn with the
 * other frames: each processor's own one-thread speed (cpus, the mean
 * frame on each).  Where the processors differ (a virtual machine whose
 * vCPUs another tenant slows unequally; a processor with fast and slow
 * cores) N threads cannot give N times one: what they can give is
 * the capacity of the N fastest processors together, 1 / (sum of 1 /
 * their mean frames).  eff is that capacity over the N-thread mean frame
 * (1: every processor busy with nothing lost), and x_eq = N x eff, the
 * speed-up N equal processors would show at that efficiency (on equal
 * processors it is x_mean itself).  Each pinned frame is timed the second
 * time it is drawn, with its caches warm on that processor: the capacity
 * is if anything overstated, and eff understated.
 *
 * --runs (with --threads-vs) adds a line per row on the frame's parallel
 * runs by kind (ew_lab_stats.ms_run_*: the scan, the builds, the draw, the
 * rest): each one's speed-up (A's wall time over N's) and its work (N's
 * busy time, every thread's time inside the run's job, over A's), then
 * each side's wall time a frame: which part of the frame the threads
 * share out well and which one they do not.
 *
 *   inproc MAP... --data DIR [--size WxH]... [--passes P] [--threads N]
 *          [--classic] [--no-entities] [--stage S] [--per-view]
 *          [--color 8bit|true] [--vs-color] [--no-lit] [--cold]
 *          [--fog D,R,G,B | --no-fog] [--hsr METHOD] [--simd LEVEL] [--occlusion MODE] [--a-args OPTS] [--b-args OPTS]
 *   inproc --threads-vs A,N MAP... [the same options] [--bench PATH] [--no-model] [--per-cpu] [--runs] */
#define _GNU_SOURCE  /* clock_gettime; sched_setaffinity for --per-cpu */
#include "edgewise_lab.h"  /* ew_flush_surfaces */
/* Calls an older revision on side A may lack: weak, so a missing one is
 * NULL there and the option that needs it is refused (need() in main). */
#pragma weak ew_frame_rgba
#pragma weak ew_set_lit
#pragma weak ew_flush_surfaces
#pragma weak ew_frame_palette
#pragma weak ew_set_fog
#pragma weak ew_set_hsr
#pragma weak ew_set_simd
#pragma weak ew_set_occlusion_cull
#ifdef EW_INPROC_OLD
#include "inproc_old.h"
#endif
#ifdef EW_INPROC_SELF
#include "edgewise_lab.h"  /* ew_lab_stats.ms_work: one library, so its own probes */
#endif

#include <math.h>
#ifdef __linux__
#include <sched.h>
#endif
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* Side B: the same functions under the names compare.sh gave them (or,
 * built with EW_INPROC_SELF, this library's again). */
#ifdef EW_INPROC_SELF
#define B_SIDE(fn)
#else
#define B_SIDE(fn) extern __typeof__(fn) b_##fn;
#endif
B_SIDE(ew_assets_create)
B_SIDE(ew_assets_destroy)
B_SIDE(ew_scene_create_from_map)
B_SIDE(ew_scene_destroy)
B_SIDE(ew_benchmark_views)
B_SIDE(ew_renderer_create)
B_SIDE(ew_renderer_destroy)
B_SIDE(ew_set_classic)
B_SIDE(ew_set_scene)
B_SIDE(ew_render)
B_SIDE(ew_frame_pixels)
B_SIDE(ew_frame_rgba)
B_SIDE(ew_set_lit)
B_SIDE(ew_flush_surfaces)
B_SIDE(ew_frame_palette)
B_SIDE(ew_set_fog)
B_SIDE(ew_set_hsr)
B_SIDE(ew_set_simd)
B_SIDE(ew_set_occlusion_cull)
#ifndef EW_INPROC_SELF
#pragma weak b_ew_set_simd
#pragma weak b_ew_set_occlusion_cull
#endif

typedef struct side {
    __typeof__(ew_assets_create) *assets_create;
    __typeof__(ew_assets_destroy) *assets_destroy;
    __typeof__(ew_scene_create_from_map) *scene_create;
    __typeof__(ew_scene_destroy) *scene_destroy;
    __typeof__(ew_benchmark_views) *views;
    __typeof__(ew_renderer_create) *renderer_create;
    __typeof__(ew_renderer_destroy) *renderer_destroy;
    __typeof__(ew_set_classic) *set_classic;
    __typeof__(ew_set_scene) *set_scene;
    __typeof__(ew_render) *render;
    __typeof__(ew_frame_pixels) *pixels;
    __typeof__(ew_frame_rgba) *rgba;
    __typeof__(ew_set_lit) *set_lit;
    __typeof__(ew_flush_surfaces) *flush;
    __typeof__(ew_frame_palette) *palette;
    __typeof__(ew_set_fog) *set_fog;
    __typeof__(ew_set_hsr) *set_hsr;
    __typeof__(ew_set_simd) *set_simd;
    __typeof__(ew_set_occlusion_cull) *set_occlusion;
    /* per map and size */
    ew_assets   *assets;
    ew_scene    *scene;
    ew_renderer *r;
} side;

static side sides[2] = {
#ifdef EW_INPROC_OLD
    {0},  /* side A: inproc_old_* */
#else
    {ew_assets_create, ew_assets_destroy, ew_scene_create_from_map, ew_scene_destroy, ew_benchmark_views,
     ew_renderer_create, ew_renderer_destroy, ew_set_classic, ew_set_scene, ew_render, ew_frame_pixels,
     ew_frame_rgba, ew_set_lit, ew_flush_surfaces, ew_frame_palette, ew_set_fog, ew_set_hsr, ew_set_simd, ew_set_occlusion_cull, NULL, NULL, NULL},
#endif
#ifdef EW_INPROC_SELF
    {ew_assets_create, ew_assets_destroy, ew_scene_create_from_map, ew_scene_destroy, ew_benchmark_views,
     ew_renderer_create, ew_renderer_destroy, ew_set_classic, ew_set_scene, ew_render, ew_frame_pixels,
     ew_frame_rgba, ew_set_lit, ew_flush_surfaces, ew_frame_palette, ew_set_fog, ew_set_hsr, ew_set_simd, ew_set_occlusion_cull, NULL, NULL, NULL},
#else
    {b_ew_assets_create, b_ew_assets_destroy, b_ew_scene_create_from_map, b_ew_scene_destroy,
     b_ew_benchmark_views, b_ew_renderer_create, b_ew_renderer_destroy, b_ew_set_classic, b_ew_set_scene,
     b_ew_render, b_ew_frame_pixels, b_ew_frame_rgba, b_ew_set_lit, b_ew_flush_surfaces, b_ew_frame_palette,
     b_ew_set_fog, b_ew_set_hsr, b_ew_set_simd, b_ew_set_occlusion_cull, NULL, NULL, NULL},
#endif
};

/* What a side draws: the options for both, then its own. */
typedef struct side_opts {
    int   classic, color, no_lit;
    int   hsr;          /* ew_hsr_method + 1 (0: the default) */
    int   simd;         /* ew_simd_level (0: the widest the processor has) */
    int   occlusion;    /* ew_occlusion_mode + 1 (0: the default) */
    int   fog_set;      /* 0: the map's fog; else fog[] (density 0: none) */
    float fog[4];
} side_opts;
static side_opts opts[2];

/* Spelled here, not asked of either library: an older side A lacks
 * ew_simd_name (bench --simd spells them the same). */
static const char *const simd_words[] = {"best", "sse2", "avx2", "avx512"};
static const char *const occlusion_words[] = {"off", "auto", "always"};
/* The index of v among n words, or -1. */
static int word(const char *v, const char *const *words, int n) {
    for (int k = 0; k < n; k++)
        if (!strcmp(v, words[k])) return k;
    return -1;
}

/* One option of what is drawn at argv[*i] (taking its value), into o:
 * 1 if it was one, 0 if not, -1 if its value is wrong. */
static int draw_opt(int argc, char **argv, int *i, side_opts *o) {
    const char *a = argv[*i];
    if (!strcmp(a, "--classic")) return o->classic = 1;
    if (!strcmp(a, "--no-lit")) return o->no_lit = 1;
    if (!strcmp(a, "--no-fog")) {
        o->fog_set = 1, o->fog[0] = 0;
        return 1;
    }
    if (!strcmp(a, "--fog")) {
        if (*i + 1 >= argc) return -1;
        float *f = o->fog;
        if (sscanf(argv[++*i], "%f,%f,%f,%f", &f[0], &f[1], &f[2], &f[3]) != 4 || !(f[0] >= 0)) return -1;
        return o->fog_set = 1;
    }
    if (!strcmp(a, "--hsr")) {
        if (*i + 1 >= argc) return -1;
        int m = ew_hsr_from_name(argv[++*i]);
        if (m < 0) return -1;
        o->hsr = m + 1;
        return 1;
    }
    if (!strcmp(a, "--occlusion")) {  /* ew_occlusion_mode + 1 */
        if (*i + 1 >= argc || (o->occlusion = word(argv[++*i], occlusion_words, 3) + 1) == 0) return -1;
        return 1;
    }
    if (!strcmp(a, "--simd")) {  /* ew_simd_level */
        if (*i + 1 >= argc || (o->simd = word(argv[++*i], simd_words, 4)) < 0) return -1;
        return 1;
    }
    if (!strcmp(a, "--color")) {
        if (*i + 1 >= argc) return -1;
        const char *m = argv[++*i];
        if (!strcmp(m, "true")) o->color = EW_COLOR_TRUE;
        else if (!strcmp(m, "8bit")) o->color = EW_COLOR_8BIT;
        else return -1;
        return 1;
    }
    return 0;
}

/* --a-args/--b-args: the options in one string, split at spaces. */
static int side_args(const char *s, side_opts *o) {
    char buf[512], *argv[32];
    int argc = 0;
    if (strlen(s) >= sizeof buf) return -1;
    strcpy(buf, s);
    for (char *t = strtok(buf, " "); t; t = strtok(NULL, " "))
        if (argc < 32) argv[argc++] = t;
        else return -1;
    for (int i = 0; i < argc; i++)
        if (draw_opt(argc, argv, &i, o) != 1) return -1;
    return 0;
}

/* --threads-vs A,N: side A on vs[0] threads, side B (this library too) on vs[1]. */
static int vs[2] = {0, 0}, model = 1;
/* Each side's processor time inside its frames (ew_lab_stats.ms_work, built
 * with EW_INPROC_SELF), summed over the timed ones: the work the N threads
 * do over the one thread's, what they lose beside the wall time. */
static double work_ms[2];
/* --runs: each side's parallel runs by kind (ew_lab_stats.ms_run_*), wall
 * and busy time summed over the timed frames. */
static int runs = 0;
static double run_wall[2][EW_RUNS], run_busy[2][EW_RUNS];
static const char *bench_cmd = NULL;

/* --per-cpu: the processors the process may run on (at most MAX_CPUS). */
enum { MAX_CPUS = 64 };
static int per_cpu = 0, ncpu = 0, cpu_ids[MAX_CPUS];
#ifdef __linux__
static cpu_set_t cpus_all;
#endif

/* The calling thread onto processor j of cpu_ids, or (j < 0) back onto all
 * of them. */
static void pin(int j) {
#ifdef __linux__
    cpu_set_t one;
    CPU_ZERO(&one);
    if (j >= 0) CPU_SET(cpu_ids[j], &one);
    (void)sched_setaffinity(0, sizeof one, j >= 0 ? &one : &cpus_all);  /* a failure: the frame runs where it may */
#else
    (void)j;
#endif
}

/* Lists the processors for --per-cpu: 0, or -1 where they cannot be known. */
static int list_cpus(void) {
#ifdef __linux__
    if (sched_getaffinity(0, sizeof cpus_all, &cpus_all) != 0) return -1;
    for (int c = 0; c < CPU_SETSIZE && ncpu < MAX_CPUS; c++)
        if (CPU_ISSET(c, &cpus_all)) cpu_ids[ncpu++] = c;
    return ncpu > 0 ? 0 : -1;
#else
    return -1;
#endif
}

static double now_ms(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec / 1e6;
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n) {
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

static int usage(const char *why) {
    fprintf(stderr, "inproc: %s\nusage: inproc MAP... --data DIR [--size WxH]... [--passes P] [--threads N] "
                    "[--classic] [--no-entities] [--stage front|scan|draw|models] [--per-view]\n"
                    "       [--color 8bit|true] [--vs-color] [--no-lit] [--cold] [--fog D,R,G,B | --no-fog] [--hsr METHOD] [--simd LEVEL] [--occlusion MODE]\n"
                    "       [--a-args OPTS] [--b-args OPTS]\n"
                    "       inproc --threads-vs A,N MAP... [the same options] [--bench PATH] [--no-model] [--per-cpu] [--runs]\n", why);
    return 2;
}

/* What is timed: the whole ew_render call, or one stage's time in its stats. */
enum { STAGE_FRAME, STAGE_FRONT, STAGE_SCAN, STAGE_DRAW, STAGE_MODELS };
static const char *const stage_names[] = {"frame", "front", "scan", "draw", "models"};
static int stage = STAGE_FRAME, per_view = 0;
/* --cold: each frame after its side's surface cache was emptied */
static int cold = 0;

static double stage_ms(const ew_stats *st, double wall) {
    switch (stage) {
    case STAGE_FRONT: return st->ms_front;
    case STAGE_SCAN: return st->ms_scan;
    case STAGE_DRAW: return st->ms_draw;
    case STAGE_MODELS: return st->ms_models;
    default: return wall;
    }
}

#ifdef EW_INPROC_OLD
static inproc_old *old;  /* side A */
#endif

/* Side s renders view v; what is timed. */
static double side_frame(int s, const ew_camera *views, int v) {
    /* Room for either revision's ew_stats: the old library writes its own
     * (the probes that left it for ew_lab_stats made it shorter).  --stage
     * reads fields this header places, so it wants two revisions whose
     * ew_stats agree up to them. */
    union { ew_stats st; char room[8192]; } u;
#ifdef EW_INPROC_OLD
    if (s == 0) {
        double ms[4];
        double t0 = now_ms();
        inproc_old_render(old, v, ms);
        double wall = now_ms() - t0;
        return stage == STAGE_FRAME ? wall : ms[stage - STAGE_FRONT];
    }
#endif
    if (cold) sides[s].flush(sides[s].r);  /* untimed: the frame pays for its builds only */
    double t0 = now_ms();
    sides[s].render(sides[s].r, &views[v], &u.st);
    double wall = now_ms() - t0;
#ifdef EW_INPROC_SELF
    ew_lab_stats lab;
    ew_frame_lab_stats(sides[s].r, &lab);
    work_ms[s] += lab.ms_work;
    for (int k = 0; k < EW_RUNS; k++) run_wall[s][k] += lab.ms_run_wall[k], run_busy[s][k] += lab.ms_run_busy[k];
#endif
    return stage_ms(&u.st, wall);
}

/* Pixel i of side s's frame as RGB. */
static void side_rgb(int s, int n, uint8_t *rgb) {
#ifdef EW_INPROC_OLD
    if (s == 0) {
        const uint8_t *px = inproc_old_pixels(old);
        for (int i = 0; i < n; i++) rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = px[i];  /* indices: equal or not */
        return;
    }
#endif
    if (opts[s].color == EW_COLOR_TRUE) {
        const uint8_t *px = (const uint8_t *)sides[s].rgba(sides[s].r);
        for (int i = 0; i < n; i++) memcpy(rgb + 3 * i, px + 4 * i, 3);
        return;
    }
    const uint8_t *px = sides[s].pixels(sides[s].r);
    /* Through the palette where both sides have it, else the indices. */
    const uint8_t *pal = sides[0].palette && sides[1].palette ? sides[s].palette(sides[s].r) : NULL;
#ifdef EW_INPROC_OLD
    pal = NULL;  /* side A gives indices: so must B */
#endif
    for (int i = 0; i < n; i++) {
        if (pal) memcpy(rgb + 3 * i, pal + 3 * px[i], 3);
        else rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = px[i];
    }
}

/* The value of "key": in a line of JSON, or NAN. */
static double json_field(const char *line, const char *key) {
    char pat[80];
    snprintf(pat, sizeof pat, "\"%s\":", key);
    const char *at = strstr(line, pat);
    return at && strncmp(at + strlen(pat), "null", 4) ? strtod(at + strlen(pat), NULL) : NAN;
}

/* bench's model of the speed-up of vs[1] threads over vs[0] on this map
 * and size (cli/cmd_bench.c, docs/performance.md "Threads"): one
 * one-thread row with --bands, whose predicted_speedup_N (Amdahl with the
 * serial share and the band imbalance) and sched_speedup_N (the renderer's
 * own schedule replayed) are read from its JSON; over A threads, the ratio
 * of the two predictions.  NAN where bench cannot be run. */
static void model_speedup(const char *map, const char *size, const char *data, int classic, int entities,
                          double *pred, double *sched) {
    char cmd[2048], line[1 << 16];
    snprintf(cmd, sizeof cmd, "'%s' bench '%s' --data '%s' --size %s --threads 1 --bands %d --bands %d "
             "--passes 3 --quiet%s%s 2>/dev/null", bench_cmd, map, data ? data : ".", size, vs[0] > 1 ? vs[0] : 1,
             vs[1], classic ? " --classic" : "", entities ? "" : " --no-entities");
    FILE *f = popen(cmd, "r");
    if (!f) return;
    if (fgets(line, sizeof line, f)) {
        char k[64];
        double p[2], q[2];
        for (int i = 0; i < 2; i++) {
            int n = i == 0 ? (vs[0] > 1 ? vs[0] : 1) : vs[1];
            snprintf(k, sizeof k, "predicted_speedup_%d", n), p[i] = json_field(line, k);
            snprintf(k, sizeof k, "sched_speedup_%d", n), q[i] = json_field(line, k);
        }
        if (vs[0] <= 1) p[0] = q[0] = 1;  /* one thread: the base itself */
        *pred = p[1] / p[0], *sched = q[1] / q[0];
    }
    pclose(f);
}

/* One map at one size: 0, or -1 with a line on stderr. */
static int run(const char *map, const char *size, const char *data, int w, int h, int passes, int threads,
               int entities) {
    ew_error err;
    ew_camera views[EW_MAX_VIEWS];
    int nv = 0, k0 = 0;
#ifdef EW_INPROC_OLD
    char msg[512];
    if (!(old = inproc_old_open(map, data, w, h, threads, entities, msg, (int)sizeof msg))) {
        fprintf(stderr, "inproc: side A: %s\n", msg);
        return -1;
    }
    k0 = 1;
#endif
    for (int k = k0; k < 2; k++) {
        side *s = &sides[k];
        if (!(s->assets = s->assets_create(map, data, &err))) {
            fprintf(stderr, "inproc: side %c: %s\n", "AB"[k], err.msg);
            return -1;
        }
        if (entities && !(s->scene = s->scene_create(s->assets->world, map, data, &err))) {
            fprintf(stderr, "inproc: side %c: %s\n", "AB"[k], err.msg);
            return -1;
        }
        ew_renderer_desc d = {.world = s->assets->world, .palette = s->assets->palette,
                              .colormap = s->assets->colormap, .width = w, .height = h,
                              .threads = vs[1] ? vs[k] : threads,
                              .color = (ew_color_mode)opts[k].color};
        if (!(s->r = s->renderer_create(&d, &err))) {
            fprintf(stderr, "inproc: side %c: %s\n", "AB"[k], err.msg);
            return -1;
        }
        s->set_classic(s->r, opts[k].classic);
        if (opts[k].no_lit) s->set_lit(s->r, 0);
        if (opts[k].hsr && s->set_hsr(s->r, (ew_hsr_method)(opts[k].hsr - 1)) != 0) {
            fprintf(stderr, "inproc: side %c: no such method in this build\n", "AB"[k]);
            return -1;
        }
        if (opts[k].fog_set) s->set_fog(s->r, opts[k].fog[0], opts[k].fog[1], opts[k].fog[2], opts[k].fog[3]);
        if (opts[k].occlusion) s->set_occlusion(s->r, (ew_occlusion_mode)(opts[k].occlusion - 1));
        if (opts[k].simd) {
            ew_simd_level got = s->set_simd(s->r, (ew_simd_level)opts[k].simd);
            if (got != (ew_simd_level)opts[k].simd)
                printf("side %c: --simd %s: this processor runs %s\n", "AB"[k], simd_words[opts[k].simd],
                       simd_words[got]);
        }
        if (s->scene) s->set_scene(s->r, s->scene);
        nv = s->views(s->assets->world, views);  /* the same cameras from either side */
    }
    if (nv <= 0) {
        fprintf(stderr, "inproc: %s: no views\n", map);
        return -1;
    }
#ifdef EW_INPROC_OLD
    if (inproc_old_views(old) != nv) {
        fprintf(stderr, "inproc: %s: side A has %d views, side B %d\n", map, inproc_old_views(old), nv);
        return -1;
    }
#endif
    /* Frame times: side s (0, 1, then 2 + j: side A pinned to processor j),
     * pass p, view v at t[(s * passes + p) * nv + v]. */
    const int nsides = 2 + (per_cpu ? ncpu : 0);
    double *t = malloc(sizeof(double) * (size_t)nsides * (size_t)nv * (size_t)passes),
           *col = malloc(sizeof(double) * (size_t)passes);
    double *ratio = malloc(sizeof(double) * (size_t)nv);
    uint8_t *rgb[2] = {malloc((size_t)w * h * 3), malloc((size_t)w * h * 3)};
    if (!t || !col || !ratio || !rgb[0] || !rgb[1]) {
        fprintf(stderr, "inproc: out of memory\n");
        free(t), free(col), free(ratio), free(rgb[0]), free(rgb[1]);
        return -1;
    }
    /* Two pixel formats draw different pictures: their frames are not compared. */
    const int compare = opts[0].color == opts[1].color;
    int differ = 0, maxdiff = 0;
    long pxdiff = 0;
    for (int p = -1; p < passes; p++)
        for (int v = 0; v < nv; v++) {
            int first = (p + v) & 1;  /* which side goes first swaps every frame */
            if (p == 0 && v == 0) {  /* the timed frames' only */
                work_ms[0] = work_ms[1] = 0;
                memset(run_wall, 0, sizeof run_wall), memset(run_busy, 0, sizeof run_busy);
            }
            for (int k = 0; k < nsides; k++) {
                /* two sides: A B, B A, ...; with the pinned ones each goes
                 * first in turn */
                int s = nsides == 2 ? k ^ first : (k + p + 1 + v) % nsides;
                double ms;
                if (s < 2) {
                    ms = side_frame(s, views, v);
                } else {  /* side A on one processor; its work is not A's */
                    double w0 = work_ms[0], rw[EW_RUNS], rb[EW_RUNS];
                    memcpy(rw, run_wall[0], sizeof rw), memcpy(rb, run_busy[0], sizeof rb);
                    pin(s - 2);
                    /* Timed the second time: a thread moved to another
                     * processor finds its caches cold there (1.79 against
                     * 1.57 ms a frame at 1080p timed the first time). */
                    side_frame(0, views, v);
                    ms = side_frame(0, views, v);
                    pin(-1);
                    work_ms[0] = w0;
                    memcpy(run_wall[0], rw, sizeof rw), memcpy(run_busy[0], rb, sizeof rb);
                }
                if (p >= 0) t[((size_t)s * passes + (size_t)p) * nv + v] = ms;
            }
            if (p < 0 && compare) {
                side_rgb(0, w * h, rgb[0]), side_rgb(1, w * h, rgb[1]);
                if (memcmp(rgb[0], rgb[1], (size_t)w * h * 3)) {
                    differ++;
                    for (long i = 0; i < (long)w * h; i++) {
                        int d = 0;
                        for (int c = 0; c < 3; c++) {
                            int e = abs(rgb[0][3 * i + c] - rgb[1][3 * i + c]);
                            d = e > d ? e : d;
                        }
                        pxdiff += d > 0;
                        maxdiff = d > maxdiff ? d : maxdiff;
                    }
                }
            }
        }
    double sum[2] = {0, 0}, slow[2] = {0, 0};
    for (int v = 0; v < nv; v++) {
        double m[2];
        for (int s = 0; s < 2; s++) {
            for (int p = 0; p < passes; p++) col[p] = t[((size_t)s * passes + (size_t)p) * nv + v];
            m[s] = median(col, passes);
            sum[s] += m[s];
            if (m[s] > slow[s]) slow[s] = m[s];
        }
        ratio[v] = m[0] > 0 ? m[1] / m[0] : 1;
        if (per_view) printf("  view %2d %9.4f %9.4f %8.4f\n", v, m[0], m[1], ratio[v]);
    }
    qsort(ratio, (size_t)nv, sizeof *ratio, cmp_double);
    /* Each side's median frame of all views and passes, as bench's median_ms
     * (it sorts that side's block of t in place; the per-view medians above
     * are done with it). */
    double med[2];
    for (int s = 0; s < 2; s++) med[s] = median(t + (size_t)s * passes * nv, passes * nv);
    if (vs[1]) {
        /* speed-ups: A over B; the per-view ratios above are B/A, so their
         * order reverses */
        double view_med = nv % 2 ? ratio[nv / 2] : (ratio[nv / 2 - 1] + ratio[nv / 2]) / 2;
        double pred = NAN, sched = NAN;
        if (model) model_speedup(map, size, data, opts[1].classic, entities, &pred, &sched);
        double x = sum[0] / sum[1];
        printf("%-10s %9s %2d,%-2d %9.4f %9.4f %7.3f %7.3f %7.3f  %.3f-%.3f %7.3f %7.3f %7.3f %6.3f  %d of %d", map,
               size, vs[0], vs[1], sum[0] / nv, sum[1] / nv, x, med[1] > 0 ? med[0] / med[1] : 1, 1 / view_med,
               1 / ratio[nv - 1], 1 / ratio[0], pred, sched, x / pred,
               work_ms[0] > 0 ? work_ms[1] / work_ms[0] : NAN, differ, nv);
        if (per_cpu) {
            /* each processor's mean frame (the mean over the views of their
             * medians, as A_ms), then the N fastest ones' capacity */
            double fast[MAX_CPUS];
            printf("  cpus ");
            for (int j = 0; j < ncpu; j++) {
                double c = 0;
                for (int v = 0; v < nv; v++) {
                    for (int p = 0; p < passes; p++) col[p] = t[((size_t)(2 + j) * passes + (size_t)p) * nv + v];
                    c += median(col, passes);
                }
                fast[j] = c / nv;
                printf("%s%.3f", j ? "," : "", fast[j]);
            }
            qsort(fast, (size_t)ncpu, sizeof *fast, cmp_double);
            const int m = vs[1] < ncpu ? vs[1] : ncpu;
            double rate = 0;
            for (int j = 0; j < m; j++) rate += 1 / fast[j];
            const double eff = sum[1] > 0 ? (1 / rate) / (sum[1] / nv) : NAN;
            printf("  eff %.3f  x_eq %.3f", eff, m * eff);
        }
        printf("\n");
        if (runs) {
            /* each kind of run: A's wall time over N's (its speed-up), and
             * N's busy time over A's (its extra work) */
            static const char *kind[EW_RUNS] = {"scan", "build", "draw", "other"};
            printf("  runs (speed-up, work):");
            for (int k = 0; k < EW_RUNS; k++)
                printf("  %s %.3f %.3f", kind[k], run_wall[1][k] > 0 ? run_wall[0][k] / run_wall[1][k] : NAN,
                       run_busy[0][k] > 0 ? run_busy[1][k] / run_busy[0][k] : NAN);
            printf("  (ms a frame, A wall, N wall:");
            for (int k = 0; k < EW_RUNS; k++) printf(" %.3f %.3f", run_wall[0][k] / (nv * passes), run_wall[1][k] / (nv * passes));
            printf(")\n");
        }
        free(t), free(col), free(ratio), free(rgb[0]), free(rgb[1]);
        return 0;
    }
    char differing[64];
    if (!compare) snprintf(differing, sizeof differing, "- of %d", nv);
    else snprintf(differing, sizeof differing, "%d of %d  %ld %d", differ, nv, pxdiff, maxdiff);
    printf("%-10s %9s %3d %9.4f %9.4f %8.4f %8.4f %8.4f %8.4f  %.3f-%.3f  %s\n", map, size, threads, sum[0] / nv,
           sum[1] / nv, sum[1] / sum[0], med[0] > 0 ? med[1] / med[0] : 1, slow[0] > 0 ? slow[1] / slow[0] : 1,
           nv % 2 ? ratio[nv / 2] : (ratio[nv / 2 - 1] + ratio[nv / 2]) / 2, ratio[0], ratio[nv - 1], differing);
    free(t), free(col), free(ratio), free(rgb[0]), free(rgb[1]);
    return 0;
}

int main(int argc, char **argv) {
    const char *maps[64], *data = NULL;
    int nmaps = 0, sizes[16][2], nsizes = 0, passes = 10, threads = 1, entities = 1, vs_color = 0;
    const char *own[2] = {NULL, NULL};  /* --a-args, --b-args */
    side_opts both = {0};
    for (int i = 1, k; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--data") && i + 1 < argc) data = argv[++i];
        else if (!strcmp(a, "--size") && i + 1 < argc) {
            if (nsizes == 16 || sscanf(argv[++i], "%dx%d", &sizes[nsizes][0], &sizes[nsizes][1]) != 2)
                return usage("--size must be WxH, at most 16 of them");
            nsizes++;
        } else if (!strcmp(a, "--passes") && i + 1 < argc) {
            passes = atoi(argv[++i]);
            if (passes < 1 || passes > 1000) return usage("--passes must be 1 to 1000");
        } else if (!strcmp(a, "--threads") && i + 1 < argc) {
            threads = atoi(argv[++i]);
            if (threads < 0 || threads > EW_MAX_THREADS) return usage("--threads out of range");
        } else if (!strcmp(a, "--a-args") && i + 1 < argc) own[0] = argv[++i];
        else if (!strcmp(a, "--b-args") && i + 1 < argc) own[1] = argv[++i];
        else if (!strcmp(a, "--no-entities")) entities = 0;
        else if (!strcmp(a, "--per-view")) per_view = 1;
        else if (!strcmp(a, "--threads-vs") && i + 1 < argc) {
            if (sscanf(argv[++i], "%d,%d", &vs[0], &vs[1]) != 2 || vs[0] < 1 || vs[1] < 1 ||
                vs[0] > EW_MAX_THREADS || vs[1] > EW_MAX_THREADS)
                return usage("--threads-vs must be A,N: two thread counts, 1 and up");
        } else if (!strcmp(a, "--bench") && i + 1 < argc) bench_cmd = argv[++i];
        else if (!strcmp(a, "--no-model")) model = 0;
        else if (!strcmp(a, "--per-cpu")) per_cpu = 1;
        else if (!strcmp(a, "--runs")) runs = 1;
        else if (!strcmp(a, "--vs-color")) vs_color = 1;
        else if (!strcmp(a, "--cold")) cold = 1;
        else if (!strcmp(a, "--stage") && i + 1 < argc) {
            const char *n = argv[++i];
            stage = -1;
            for (int k = 0; k < (int)(sizeof stage_names / sizeof *stage_names); k++)
                if (!strcmp(n, stage_names[k])) stage = k;
            if (stage < 0) return usage("--stage must be frame, front, scan, draw or models");
        } else if (!strcmp(a, "--quiet")) continue;  /* what compare.sh passes to bench too */
        else if ((k = draw_opt(argc, argv, &i, &both)) != 0) {
            if (k < 0) return usage("--fog must be D,R,G,B (D at least 0), --color 8bit or true, --hsr a method");
        }
        else if (a[0] == '-') return usage("unknown option");
        else if (nmaps < 64) maps[nmaps++] = a;
        else return usage("at most 64 maps");
    }
    if (!nmaps) return usage("no map");
    if (vs[1] && vs_color) return usage("--threads-vs and --vs-color: one comparison at a time");
    if (per_cpu && (!vs[1] || vs[0] != 1)) return usage("--per-cpu goes with --threads-vs 1,N");
    if (runs && !vs[1]) return usage("--runs goes with --threads-vs A,N");
    if (per_cpu && list_cpus() < 0) return usage("--per-cpu: this system does not say which processors there are");
    char beside[4096];
    if (vs[1]) {
#ifdef EW_INPROC_OLD
        return usage("--threads-vs times this revision's library alone: not with side A from before its calls");
#endif
        sides[1] = sides[0];  /* one library, two thread counts */
        if (!bench_cmd) {  /* the edgewise beside this program */
            const char *slash = strrchr(argv[0], '/');
            snprintf(beside, sizeof beside, "%.*sedgewise", slash ? (int)(slash - argv[0] + 1) : 0, argv[0]);
            bench_cmd = beside;
        }
    }
    if (vs_color && both.color) return usage("--vs-color draws A in 8-bit and B in true colour: no --color");
    for (int k = 0; k < 2; k++) {
        opts[k] = both;
        if (vs_color) opts[k].color = k ? EW_COLOR_TRUE : EW_COLOR_8BIT;
        if (own[k] && side_args(own[k], &opts[k]) < 0)
            return usage("--a-args/--b-args take --fog, --no-fog, --color, --hsr, --simd, --occlusion, --classic, --no-lit");
    }
    for (int k = 0; k < 2; k++) {
        const side *sd = &sides[k];
        const char *miss = opts[k].color && !sd->rgba ? "--color true (ew_frame_rgba)"
                         : opts[k].no_lit && !sd->set_lit ? "--no-lit (ew_set_lit)"
                         : cold && !sd->flush ? "--cold (ew_flush_surfaces)"
                         : opts[k].fog_set && !sd->set_fog ? "--fog (ew_set_fog)"
                         : opts[k].hsr && !sd->set_hsr ? "--hsr (ew_set_hsr)"
                         : opts[k].simd && !sd->set_simd ? "--simd (ew_set_simd)"
                         : opts[k].occlusion && !sd->set_occlusion ? "--occlusion (ew_set_occlusion_cull)" : NULL;
        if (miss) {
            fprintf(stderr, "inproc: side %c's library has no %s\n", "AB"[k], miss);
            return 2;
        }
    }
#ifdef EW_INPROC_OLD
    if (own[0] || own[1] || both.color || both.hsr || both.fog_set || both.no_lit || both.simd || both.occlusion || vs_color ||
        cold)
        return usage("side A is an old revision: only --classic of what is drawn (to B)");
    opts[0].classic = 0;  /* its one look was the classic one */
#endif
    for (int k = 0; k < 2; k++)
        if (memcmp(&opts[k], &(side_opts){0}, sizeof opts[k]))
            printf("side %c: %s%s%s%s%s\n", "AB"[k], opts[k].classic ? "classic " : "", opts[k].no_lit ? "white light " : "",
                   opts[k].color ? "true colour " : "8-bit ",
                   !opts[k].fog_set ? "the map's fog" : opts[k].fog[0] > 0 ? "fog" : "no fog",
                   (const char *[]){"", ", loops up to the processor's widest", ", loops in SSE2",
                                    ", loops up to AVX2", ", loops up to AVX-512"}[opts[k].simd + 1]);
    if (cold) printf("cold: each frame after its side's surface cache was emptied\n");
    if (!nsizes) sizes[0][0] = 640, sizes[0][1] = 480, nsizes = 1;
    if (stage != STAGE_FRAME) printf("timed: the %s stage (ew_stats.ms_%s)\n", stage_names[stage], stage_names[stage]);
    if (vs[1])
        printf("%-10s %9s %5s %9s %9s %7s %7s %7s  %-11s %7s %7s %7s %6s  %s\n", "map", "size", "thr", "A_ms", "N_ms",
               "x_mean", "x_med", "x_view", "view range", "x_pred", "x_sched", "x/pred", "work",
               per_cpu ? "frames differing  [cpus: each processor's A_ms; eff: the N fastest ones' capacity over N_ms; x_eq: N eff]"
                       : "frames differing");
    else printf("%-10s %9s %3s %9s %9s %8s %8s %8s %8s  %s  %s\n", "map", "size", "thr", "A_ms", "B_ms", "B/A", "med_B/A",
           "slow_B/A", "view_med", "view range", "frames differing, px differing, max");
    for (int m = 0; m < nmaps; m++)
        for (int s = 0; s < nsizes; s++) {
            char size[24];
            snprintf(size, sizeof size, "%dx%d", sizes[s][0], sizes[s][1]);
            int rc = run(maps[m], size, data, sizes[s][0], sizes[s][1], passes, threads, entities);
#ifdef EW_INPROC_OLD
            inproc_old_close(old);
            old = NULL;
#endif
            for (int k = 0; k < 2; k++) {
                if (sides[k].r) sides[k].renderer_destroy(sides[k].r);
                if (sides[k].scene) sides[k].scene_destroy(sides[k].scene);
                if (sides[k].assets) sides[k].assets_destroy(sides[k].assets);
                sides[k].r = NULL, sides[k].scene = NULL, sides[k].assets = NULL;
            }
            if (rc < 0) return 1;
        }
    return 0;
}
