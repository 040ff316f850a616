/*
 * edgewise bench: the benchmark protocol of ../shared/BENCHMARK.md.
 *
 *   edgewise bench MAP... [--data DIR] [--size WxH]... [--threads N]...
 *                  [--passes P] [--gap MS] [--bands N]... [--cold] [--simd LEVEL] [drawing options] [--table]
 *                  [--out FILE.jsonl]
 *   edgewise bench --floor [--size WxH]... [--table] [--out FILE.jsonl]
 *
 * Per map, size and thread count: load the map, render the whole view set
 * once (warm-up), then P more times, timing each ew_render call with the
 * monotonic clock.  One JSON object per row (docs/performance.md lists every
 * field).  Each row also carries this machine's "fill floor" for its size:
 * the time to texture every pixel once with the cheapest loop there is, so
 * a figure can be read as "N times the cost of touching every pixel".
 * Each row reports the frame's serial time (outside the parallel sections)
 * and, with --bands N, the imbalance of N bands cut from the one-thread
 * frame's per-row costs and the speed-up Amdahl's law then predicts on N
 * cores (docs/performance.md, "Threads").
 *
 * A benchmark is read, never asserted on: nothing here fails on a time.
 */
#define _POSIX_C_SOURCE 200809L
#include "cli.h"
#include "edgewise.h"
#include "edgewise_lab.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

enum {
    BENCH_EXIT_USAGE = 2,
    MAX_SIZES = 16,
    MAX_THREAD_COUNTS = 8,
    MAX_BAND_COUNTS = 8,
    MAX_BANDS = 256,          /* as many as the renderer makes (64 threads, 4 each) */
    PROFILE_PASSES = 3,       /* the row profile: per strip, the least of these */
    MAX_MAPS = 64,
    MAX_PASSES = 1000,
    MAX_THREADS = EW_MAX_THREADS,
    DEFAULT_PASSES = 5,
};

static const char bench_usage[] =
    "usage: edgewise bench MAP... [options]\n"
    "       edgewise bench --floor [--size WxH]... [--table] [--out FILE]\n"
    "\n"
    "Runs the benchmark protocol of BENCHMARK.md: per map, size and thread\n"
    "count, one warm-up pass over the view set, then P timed passes.  Prints\n"
    "one JSON object per row (fields: docs/performance.md).\n"
    "\n"
    "options:\n"
    CLI_OPTIONS_HERE
    "\n"
    "what is drawn (as in edgewise render):\n";
static const char bench_usage_tail[] =
    "\n"
    "MAP is a .bsp path, a map name in --data, or 'builtin'.\n"
    "example:\n"
    "  edgewise bench e1m1 start --data ../shared/data/librequake --size 1920x1080 --table\n";

typedef struct bench_opts {
    const char *maps[MAX_MAPS];
    int         nmaps;
    const char *data, *out;
    int         sizes[MAX_SIZES][2];
    int         nsizes;
    int         threads[MAX_THREAD_COUNTS];
    int         nthreads;
    int         bands[MAX_BAND_COUNTS];
    int         nbands;
    int         passes;
    int         gap_ms;         /* --gap: pause before each frame */
    int         table, floor_only, quiet, per_view;
    int         cold;           /* --cold: the surface cache emptied before each frame */
    int         simd;           /* --simd: an ew_simd_level */
    draw_opts   draw;           /* what is drawn (cli/draw_options.c) */
} bench_opts;

/* ---- arguments ------------------------------------------------------------- */

/* Returns 0, 1 for --help (usage printed), -1 (error printed). */
static int bench_parse(int argc, char **argv, bench_opts *o) {
    int passes_given = 0, gap_given = 0, simd_given = 0;
    cli_args args;
    cli_args_init(&args, CLI_BENCH, argc, argv, o->maps, MAX_MAPS, &o->draw, bench_usage, bench_usage_tail);
    while (cli_next_arg(&args)) {
        const cli_option *opt = args.opt;
        const char *v = args.value;
        const char *name = opt->name;
        if (!v) {
            if (strcmp(name, "--table") == 0)
                o->table = 1;
            else if (strcmp(name, "--per-view") == 0)
                o->per_view = 1;
            else if (strcmp(name, "--cold") == 0)
                o->cold = 1;
            else
                o->floor_only = 1;
            continue;
        }
        long l;
        if (strcmp(name, "--data") == 0 || strcmp(name, "--out") == 0) {
            if (cli_set_once("bench", name, v, name[2] == 'd' ? &o->data : &o->out) < 0)
                return -1;
        } else if (strcmp(name, "--size") == 0) {
            if (cli_add_size("bench", v, o->sizes, &o->nsizes, MAX_SIZES) < 0)
                return -1;
        } else if (strcmp(name, "--threads") == 0) {
            if (o->nthreads == MAX_THREAD_COUNTS) {
                error_line("bench: more than %d --threads values", MAX_THREAD_COUNTS);
                return -1;
            }
            if (parse_threads(v, &o->threads[o->nthreads]) < 0)
                return -1;
            o->nthreads++;
        } else if (strcmp(name, "--bands") == 0) {
            if (o->nbands == MAX_BAND_COUNTS) {
                error_line("bench: more than %d --bands values", MAX_BAND_COUNTS);
                return -1;
            }
            if (parse_long(v, &l) < 0 || l < 1 || l > MAX_BANDS) {
                error_line("bench: --bands %s: expected 1 to %d", v, MAX_BANDS);
                return -1;
            }
            o->bands[o->nbands++] = (int)l;
        } else if (strcmp(name, "--simd") == 0) {
            if (simd_given) {
                error_line("bench: --simd given twice");
                return -1;
            }
            int k = ew_simd_from_name(v);
            if (k < 0) {
                error_line("bench: --simd %s: expected best, sse2, avx2 or avx512", v);
                return -1;
            }
            o->simd = k;
            simd_given = 1;
        } else if (strcmp(name, "--gap") == 0) {
            if (cli_int_once("bench", name, v, 0, 1000, &gap_given, &o->gap_ms) < 0)
                return -1;
        } else if (cli_int_once("bench", name, v, 1, MAX_PASSES, &passes_given, &o->passes) < 0) { /* --passes */
            return -1;
        }
    }
    if (args.stop)
        return args.stop;
    o->nmaps = args.nmaps, o->quiet = args.quiet;
    if (o->floor_only && o->nmaps) {
        error_line("bench: --floor takes no MAP (it measures the machine, not a map)");
        return -1;
    }
    if (!o->floor_only && !o->nmaps) {
        error_line("bench: missing MAP (a .bsp path, a map name with --data, or 'builtin')");
        return -1;
    }
    if (o->floor_only && (o->data || o->nthreads || passes_given || o->draw.given || o->quiet || o->nbands || gap_given ||
                          o->cold || simd_given)) {
        error_line("bench: --floor takes only --size, --table and --out");
        return -1;
    }
    if (!o->nsizes) {
        o->sizes[0][0] = 640;
        o->sizes[0][1] = 480;
        o->nsizes = 1;
    }
    for (int b = 0; b < o->nbands; b++)
        for (int i = 0; i < o->nsizes; i++)
            if (o->bands[b] * 8 > o->sizes[i][1]) {
                error_line("bench: --bands %d: a band has at least 8 rows, %dx%d has %d rows", o->bands[b],
                           o->sizes[i][0], o->sizes[i][1], o->sizes[i][1]);
                return -1;
            }
    if (!o->nthreads)
        o->threads[o->nthreads++] = 1;
    if (!passes_given)
        o->passes = DEFAULT_PASSES;
    return 0;
}

/* ---- timing and statistics ------------------------------------------------- */

static double now_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Sorts v in place. */
static double median_of(double *v, int n) {
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* Nearest rank on a sorted array: the smallest value >= 99% of them. */
static double p99_of_sorted(const double *v, int n) {
    int k = (int)ceil(0.99 * n);
    return v[k < 1 ? 0 : k - 1];
}

static int online_cores(void) {
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > MAX_THREADS ? MAX_THREADS : (int)n;
}

/* ---- the fill floor -------------------------------------------------------- */

/* The cheapest textured frame: every pixel written once from a 64x64 texture
 * with affine 16.16 u,v steps; no perspective, no lighting, no z.  seed moves
 * the texture per repetition so no pass can be skipped as a repeat. */
static void floor_fill(uint8_t *dst, int w, int h, const uint8_t tex[64 * 64], uint32_t seed) {
    for (int y = 0; y < h; y++) {
        uint32_t u = seed + (uint32_t)y * 0x5A3u, v = seed + (uint32_t)y * 0x4000u;
        uint8_t *row = dst + (size_t)y * (size_t)w;
        for (int x = 0; x < w; x++) {
            row[x] = tex[((v >> 10) & (63u << 6)) | ((u >> 16) & 63u)];
            u += 0xC000u;
            v += 0x1800u;
        }
    }
}

/* The lookup floor: one table lookup a pixel, p[x] = row[p[x]] with the
 * row (of 64, 256 bytes each) changing every 32 pixels, as an 8-bit fog
 * level's run looks its pixels up (four loads, then four stores), on
 * pixels in the cache as the fog finds them right after the span draw: a
 * 32 KB strip gone over until w x h pixels are done.  Without a
 * 256-entry byte permute (AVX-512 VBMI) no 8-bit fog can cost less than
 * this on top of the frame, however its levels are found. */
enum { LOOKUP_STRIP = 32 << 10, LOOKUP_RUN = 32 };
static void lookup_floor(uint8_t *strip, size_t npx, const uint8_t lut[64 * 256], uint32_t seed) {
    for (size_t done = 0; done < npx; done += LOOKUP_STRIP) {
        size_t n = npx - done < LOOKUP_STRIP ? npx - done : LOOKUP_STRIP;
        for (size_t x0 = 0; x0 < n; x0 += LOOKUP_RUN) {
            const uint8_t *row = lut + ((seed + done / LOOKUP_RUN + x0 / LOOKUP_RUN) & 63) * 256;
            uint8_t *p = strip + x0;
            size_t m = n - x0 < LOOKUP_RUN ? n - x0 : LOOKUP_RUN, x = 0;
            for (; x + 4 <= m; x += 4) {
                uint8_t a = row[p[x]], b = row[p[x + 1]], c = row[p[x + 2]], d = row[p[x + 3]];
                p[x] = a, p[x + 1] = b, p[x + 2] = c, p[x + 3] = d;
            }
            for (; x < m; x++) p[x] = row[p[x]];
        }
    }
}

/* Floor fills of one frame size, timed one at a time, each followed by a
 * lookup floor timed on its own. */
typedef struct floor_sampler {
    int      w, h;
    uint8_t  tex[64 * 64];
    uint8_t  lut[64 * 256];
    uint8_t  strip[LOOKUP_STRIP];
    uint8_t *frame;
    double  *t, *lt;
    int      n, cap;
} floor_sampler;

static int floor_begin(floor_sampler *f, int w, int h, int cap) {
    memset(f, 0, sizeof *f);
    f->w = w, f->h = h, f->cap = cap;
    for (int i = 0; i < 64 * 64; i++)
        f->tex[i] = (uint8_t)((i * 37) ^ (i >> 6) * 11);
    for (int i = 0; i < 64 * 256; i++)
        f->lut[i] = (uint8_t)(i * 7 + (i >> 8) * 13);
    for (int i = 0; i < LOOKUP_STRIP; i++)
        f->strip[i] = (uint8_t)((uint32_t)i * 2654435761u >> 13);
    f->frame = malloc((size_t)w * (size_t)h);
    f->t = malloc((size_t)cap * sizeof *f->t);
    f->lt = malloc((size_t)cap * sizeof *f->lt);
    if (!f->frame || !f->t || !f->lt)
        return -1;
    floor_fill(f->frame, w, h, f->tex, 0);   /* warm-up: page in the frame */
    lookup_floor(f->strip, LOOKUP_STRIP, f->lut, 0);
    return 0;
}

static void floor_rep(floor_sampler *f) {
    static volatile uint8_t sink;   /* keeps every frame observable */
    if (f->n >= f->cap)
        return;
    double t0 = now_ms();
    floor_fill(f->frame, f->w, f->h, f->tex, (uint32_t)f->n * 0x9E3779B9u);
    double t1 = now_ms();
    lookup_floor(f->strip, (size_t)f->w * (size_t)f->h, f->lut, (uint32_t)f->n);
    f->lt[f->n] = now_ms() - t1;
    f->t[f->n++] = t1 - t0;
    sink = (uint8_t)(sink + f->frame[(size_t)(f->n * 7919) % ((size_t)f->w * (size_t)f->h)] +
                     f->strip[(size_t)(f->n * 7919) % LOOKUP_STRIP]);
}

/* The fill floor's median (-1: no samples); *lookup_ms the lookup floor's. */
static double floor_end(floor_sampler *f, double *lookup_ms) {
    double m = f->n && f->t ? median_of(f->t, f->n) : -1;
    if (lookup_ms)
        *lookup_ms = f->n && f->lt ? median_of(f->lt, f->n) : -1;
    free(f->frame);
    free(f->t);
    free(f->lt);
    f->frame = NULL, f->t = NULL, f->lt = NULL, f->n = 0;
    return m;
}

/* Median ms of many floor fills of a w x h frame (-1 if out of memory),
 * and in *lookup_ms the lookup floor's.  Runs for about a quarter second
 * so small sizes get many samples. */
static double measure_floor(int w, int h, int *reps_out, double *lookup_ms) {
    enum { MIN_REPS = 15, MAX_REPS = 1000 };
    const double budget_ms = 250;
    floor_sampler f;
    if (floor_begin(&f, w, h, MAX_REPS) < 0) {
        floor_end(&f, NULL);
        return -1;
    }
    double start = now_ms();
    while (f.n < MAX_REPS && (f.n < MIN_REPS || now_ms() - start < budget_ms))
        floor_rep(&f);
    if (reps_out)
        *reps_out = f.n;
    return floor_end(&f, lookup_ms);
}

typedef struct floor_cache {
    int    w[MAX_SIZES], h[MAX_SIZES], reps[MAX_SIZES];
    double ms[MAX_SIZES], lookup_ms[MAX_SIZES];
    int    n;
} floor_cache;

static double floor_for(floor_cache *c, int w, int h, double *lookup_ms) {
    for (int i = 0; i < c->n; i++)
        if (c->w[i] == w && c->h[i] == h) {
            *lookup_ms = c->lookup_ms[i];
            return c->ms[i];
        }
    if (c->n == MAX_SIZES)
        return measure_floor(w, h, NULL, lookup_ms);
    c->w[c->n] = w;
    c->h[c->n] = h;
    c->ms[c->n] = measure_floor(w, h, &c->reps[c->n], &c->lookup_ms[c->n]);
    *lookup_ms = c->lookup_ms[c->n];
    return c->ms[c->n++];
}

/* ---- one row --------------------------------------------------------------- */

/* The integer counters of ew_stats reported per row, as a mean per frame. */
#define COUNTER(f) { #f, offsetof(ew_stats, f), _Generic(((ew_stats *)0)->f, long: 1, default: 0) }
static const struct counter_def {
    const char *name;
    size_t      offset;
    int         is_long;
} counter_defs[] = {
    COUNTER(pixels_written), COUNTER(pixels_covered), COUNTER(edges),
    COUNTER(edges_cached), COUNTER(surfaces), COUNTER(surfaces_shown), COUNTER(faces_occluded), COUNTER(spans),
    COUNTER(surfaces_built), COUNTER(surfaces_cached), COUNTER(visible_leaves),
    COUNTER(dropped), COUNTER(entities_drawn), COUNTER(entities_culled), COUNTER(entities_hidden),
    COUNTER(entities_unknown), COUNTER(models_missing), COUNTER(alias_tris),
    COUNTER(alias_tris_subdiv), COUNTER(alias_pixels), COUNTER(particles),
    COUNTER(surfaces_rebuilt_by_dlights), COUNTER(seethrough_surfaces), COUNTER(fence_pixels),
    COUNTER(translucent_pixels), COUNTER(fog_pixels), COUNTER(underwater), COUNTER(hsr_bytes),
};
#undef COUNTER
enum { NCOUNTERS = sizeof counter_defs / sizeof counter_defs[0] };

/* The counter of an ew_stats field, by its offset (found, not numbered by
 * hand: the list grows in the middle). */
static int counter_of(size_t offset) {
    for (int i = 0; i < NCOUNTERS; i++)
        if (counter_defs[i].offset == offset) return i;
    return 0;
}

static double counter_value(const ew_stats *s, const struct counter_def *d) {
    const char *p = (const char *)s + d->offset;
    return d->is_long ? (double)*(const long *)(const void *)p
                      : (double)*(const int *)(const void *)p;
}

enum { ST_FRONT, ST_SCAN, ST_DRAW, ST_MODELS, ST_TOTAL, NSTAGES };
/* ew_stats' parts of ms_serial, and what is left of it. */
enum { PH_BEGIN, PH_WALK, PH_BRUSH, PH_PREPARE, PH_PASSES, PH_OTHER, NPHASES };
static const char *const phase_names[NPHASES] = { "begin_ms", "walk_ms", "brush_ms", "prepare_ms",
                                                  "passes_ms", "other_ms" };
/* The parts are the lab's probes (ew_frame_lab_stats), ms_serial the frame's. */
static double phase_of(const ew_stats *st, const ew_lab_stats *lab, int ph) {
#ifdef EW_BENCH_NO_SERIAL  /* a library from before ms_serial (compare.sh) */
    (void)st, (void)lab, (void)ph;
    return NAN;
#else
    switch (ph) {
    case PH_BEGIN: return lab->ms_serial_begin;
    case PH_WALK: return lab->ms_serial_walk;
    case PH_BRUSH: return lab->ms_serial_brush;
    case PH_PREPARE: return lab->ms_serial_prepare;
    case PH_PASSES: return lab->ms_serial_passes;
    default:
        return st->ms_serial - lab->ms_serial_begin - lab->ms_serial_walk - lab->ms_serial_brush -
               lab->ms_serial_prepare - lab->ms_serial_passes;
    }
#endif
}
static const char *const stage_names[NSTAGES] = { "front", "scan", "draw", "models", "total" };

/* Parts of a frame whose own view_level bench reports (view_level_<part>): the
 * geometry (walk, clipping, edges, scan), the world's spans, and all the
 * pixel work, which is what would be left if the geometry took no time. */
enum { PART_FRONT_SCAN, PART_DRAW, PART_DRAW_MODELS, NPARTS };
static const char *const part_names[NPARTS] = { "front_scan", "draw", "draw_models" };
static const unsigned part_stages[NPARTS] = { 1u << ST_FRONT | 1u << ST_SCAN, 1u << ST_DRAW,
                                              1u << ST_DRAW | 1u << ST_MODELS };

/* --per-view: one view's medians over the passes, and its counts. */
typedef struct view_row {
    double stages[NSTAGES];
    long   surfaces, edges, spans, entities_drawn, alias_tris;
} view_row;

typedef struct row {
    char   map[256];
    int    w, h, threads, threads_requested, threads_applied, views, passes, entities, max_view;
    int    gap_ms;        /* --gap: the pause before each frame */
    int    cold;          /* --cold: each frame after the surface cache was emptied */
    int    simd;          /* the ew_simd_level in use (--simd, capped by the processor) */
    int    slow_view;     /* the view with the highest median over the passes */
    draw_opts draw;       /* what was drawn */
    double median, mean, p99, max, level, ns_per_pixel, floor_ms, floor_ratio;
    double lookup_floor_ms;  /* the lookup floor at this size (lookup_floor) */
    double view_level;    /* slow_view's median / median: level without one-off spikes */
    double part_levels[NPARTS];  /* view_level of a frame of only these stages (part_names) */
    double stages[NSTAGES];        /* median per frame */
    double counters[NCOUNTERS];    /* mean per frame */
    double serial;                 /* median ms_serial per frame */
    double serial_mean;            /* its mean */
    double serial_phase[NPHASES];  /* mean of each part, and of the rest */
    double serial_share;           /* serial / a one-thread median (serial_base) */
    double predict_share;          /* the one-thread row's share with front_items, at most 1: the predictions' */
    double front_items;            /* --bands: the front end's largest items per frame (ms_front_items), or NaN */
    int    serial_base_own;        /* 1: this row's median (no one-thread row before it) */
    int    nbands;                 /* --bands: */
    int    bands[MAX_BAND_COUNTS];
    double imbalance[MAX_BAND_COUNTS], imbalance_max[MAX_BAND_COUNTS];  /* over views: median, worst */
    double speedup[MAX_BAND_COUNTS];                                    /* predicted on that many cores */
    double sched_imbalance[MAX_BAND_COUNTS], sched_speedup[MAX_BAND_COUNTS];  /* the renderer's own bands */
    double cpu_per_frame, work_per_frame;  /* --gap: process CPU ms per frame, the frame's own work (ms_work) */
    double phases_share;           /* the one-thread frame with the front end's phases over its median: the predictions' whole */
    view_row *per_view;            /* --per-view: views entries (freed by the caller), else NULL */
} row;

/* The one-thread figures of a map and size, for the rows after it. */
typedef struct size_ctx {
    int    have_one;               /* a one-thread row was measured */
    double one_median;
    double one_share;              /* that row's serial share: what the predictions use */
    double loop_share;             /* its serial share with the one-loop front end (NaN: unknown) */
    double phases_ratio;           /* --bands: the one-thread frame with the front end's phases over without, 0 unknown */
    int    have_profile;           /* the band imbalances were measured */
    double imbalance[MAX_BAND_COUNTS], imbalance_max[MAX_BAND_COUNTS], sched_imbalance[MAX_BAND_COUNTS];
    double front_items;            /* median over the views of each one's least ms_front_items */
} size_ctx;

static double stage_of(const ew_stats *st, int s) {
    return s == ST_FRONT ? st->ms_front : s == ST_SCAN ? st->ms_scan : s == ST_DRAW ? st->ms_draw
         : s == ST_MODELS ? st->ms_models : st->ms_total;
}

/* n frames' serial times into scratch. */
static void serial_times(const ew_stats *stats, const ew_lab_stats *labs, int n, double *scratch) {
    for (int i = 0; i < n; i++) scratch[i] = phase_of(&stats[i], &labs[i], PH_OTHER) + phase_of(&stats[i], &labs[i], PH_BEGIN) +
                                             phase_of(&stats[i], &labs[i], PH_WALK) + phase_of(&stats[i], &labs[i], PH_BRUSH) +
                                             phase_of(&stats[i], &labs[i], PH_PREPARE) + phase_of(&stats[i], &labs[i], PH_PASSES);
}

/* The serial time of n frames' stats: its median, mean and parts. */
static void summarize_serial(row *r, const ew_stats *stats, const ew_lab_stats *labs, int n,
                             double *scratch) {
    serial_times(stats, labs, n, scratch);
    r->serial_mean = 0;
    for (int i = 0; i < n; i++) r->serial_mean += scratch[i] / n;
    r->serial = median_of(scratch, n);
    /* The parts as means, so they add up to serial_mean (medians of a
     * skewed view set would not). */
    for (int ph = 0; ph < NPHASES; ph++) {
        r->serial_phase[ph] = 0;
        for (int i = 0; i < n; i++) r->serial_phase[ph] += phase_of(&stats[i], &labs[i], ph) / n;
    }
}

/* View v's median over the passes of x[pass * views + v] (tmp: passes). */
static double view_median(const double *x, int views, int passes, int v, double *tmp) {
    for (int p = 0; p < passes; p++) tmp[p] = x[(size_t)p * views + v];
    return median_of(tmp, passes);
}

/* The highest of the views' medians over the passes, and its view: the
 * numerator of view_level.  A frame the machine interrupted once raises
 * max_ms but not this, a view that is always slow raises both. */
static double slowest_view(const double *x, int views, int passes, double *tmp, int *which) {
    double slowest = -1;
    for (int v = 0; v < views; v++) {
        double m = view_median(x, views, passes, v, tmp);
        if (m > slowest) slowest = m, *which = v;
    }
    return slowest;
}

static double part_of(const ew_stats *st, int part) {
    double t = 0;
    for (int s = 0; s < ST_TOTAL; s++)
        if (part_stages[part] >> s & 1u) t += stage_of(st, s);
    return t;
}

/* The view_level of each part: its slowest view over its median over every
 * frame, as view_level is the whole frame's. */
static void summarize_parts(row *r, const ew_stats *stats, double *scratch) {
    const int n = r->views * r->passes;
    double tmp[MAX_PASSES];
    for (int k = 0; k < NPARTS; k++) {
        int v;
        for (int i = 0; i < n; i++) scratch[i] = part_of(&stats[i], k);
        const double slowest = slowest_view(scratch, r->views, r->passes, tmp, &v);
        const double med = median_of(scratch, n);  /* sorts scratch: after the views' medians */
        r->part_levels[k] = med > 0 ? slowest / med : NAN;
    }
}

/* Fills r from frames[views * passes] and their stats. */
static void summarize(row *r, double *frames, const ew_stats *stats, const ew_lab_stats *labs,
                      double *scratch) {
    int n = r->views * r->passes;
    double sum = 0;
    r->max = -1;
    for (int i = 0; i < n; i++) {
        sum += frames[i];
        if (frames[i] > r->max) {
            r->max = frames[i];
            r->max_view = i % r->views;
        }
    }
    r->mean = sum / n;
    const double slowest = slowest_view(frames, r->views, r->passes, scratch, &r->slow_view);
    for (int v = 0; r->per_view && v < r->views; v++) {
        view_row *pv = &r->per_view[v];
        for (int s = 0; s < NSTAGES; s++) {
            for (int p = 0; p < r->passes; p++) scratch[p] = stage_of(&stats[(size_t)p * r->views + v], s);
            pv->stages[s] = median_of(scratch, r->passes);
        }
        /* the frame as timed around ew_render, like the row's median */
        pv->stages[ST_TOTAL] = view_median(frames, r->views, r->passes, v, scratch);
        const ew_stats *st = &stats[v];  /* the counts are the same every pass */
        pv->surfaces = st->surfaces, pv->edges = st->edges, pv->spans = st->spans;
        pv->entities_drawn = st->entities_drawn, pv->alias_tris = st->alias_tris;
    }
    r->median = median_of(frames, n);   /* sorts frames: max_view is found first */
    r->p99 = p99_of_sorted(frames, n);
    r->level = r->median > 0 ? r->max / r->median : NAN;
    r->view_level = r->median > 0 ? slowest / r->median : NAN;
    r->ns_per_pixel = r->median * 1e6 / ((double)r->w * r->h);
    r->floor_ratio = r->floor_ms > 0 ? r->median / r->floor_ms : NAN;
    for (int s = 0; s < NSTAGES; s++) {
        for (int i = 0; i < n; i++) {
            scratch[i] = stage_of(&stats[i], s);
        }
        r->stages[s] = median_of(scratch, n);
    }
    summarize_serial(r, stats, labs, n, scratch);
    summarize_parts(r, stats, scratch);
    for (int c = 0; c < NCOUNTERS; c++) {
        double total = 0;
        for (int i = 0; i < n; i++)
            total += counter_value(&stats[i], &counter_defs[c]);
        r->counters[c] = total / n;
    }
}

/* Like json_number, but keeps up to 10 digits so large counts stay exact. */
static void json_count(FILE *f, double v) {
    if (isfinite(v))
        fprintf(f, "%.10g", v);
    else
        fputs("null", f);
}

static void print_row_json(FILE *f, const row *r) {
    fputs("{\"map\":", f);
    json_string(f, r->map);
    fprintf(f, ",\"width\":%d,\"height\":%d,\"threads\":%d,\"threads_requested\":%d,"
               "\"threads_applied\":%s,\"views\":%d,\"passes\":%d,\"gap_ms\":%d",
            r->w, r->h, r->threads, r->threads_requested, r->threads_applied ? "true" : "false",
            r->views, r->passes, r->gap_ms);
    /* what was drawn: "entities", "alias_raster", "zfill", "classic", ... */
    draw_opts_json(f, &r->draw);
    const char *names[] = { "median_ms", "mean_ms", "p99_ms", "max_ms" };
    const double vals[] = { r->median, r->mean, r->p99, r->max };
    for (int i = 0; i < 4; i++) {
        fprintf(f, ",\"%s\":", names[i]);
        json_number(f, vals[i]);
    }
    fprintf(f, ",\"cold\":%s,\"simd\":\"%s\",\"max_view\":%d,\"level\":", r->cold ? "true" : "false",
            ew_simd_name((ew_simd_level)r->simd), r->max_view);
    json_number(f, r->level);
    fprintf(f, ",\"slow_view\":%d", r->slow_view);
    const char *more[] = { "view_level", "ns_per_pixel", "floor_ms", "floor_ratio", "lookup_floor_ms", "serial_ms",
                           "serial_share", "predict_share", "front_items_ms", "phases_share" };
    const double morev[] = { r->view_level, r->ns_per_pixel, r->floor_ms, r->floor_ratio, r->lookup_floor_ms,
                             r->serial, r->serial_share, r->predict_share, r->front_items, r->phases_share };
    for (size_t i = 0; i < sizeof more / sizeof *more; i++) {
        fprintf(f, ",\"%s\":", more[i]);
        json_number(f, morev[i]);
    }
    fprintf(f, ",\"serial_share_base\":\"%s\",\"serial_mean_ms\":", r->serial_base_own ? "own" : "threads1");
    json_number(f, r->serial_mean);
    fputs(",\"serial_phases\":{", f);
    for (int ph = 0; ph < NPHASES; ph++) {
        fprintf(f, "%s\"%s\":", ph ? "," : "", phase_names[ph]);
        json_number(f, r->serial_phase[ph]);
    }
    fputc('}', f);
    for (int k = 0; k < NPARTS; k++) {
        fprintf(f, ",\"view_level_%s\":", part_names[k]);
        json_number(f, r->part_levels[k]);
    }
    if (r->gap_ms > 0) {
        const char *cn[] = { "cpu_ms_per_frame", "work_ms_per_frame", "cpu_over_work" };
        const double cv[] = { r->cpu_per_frame, r->work_per_frame,
                              r->work_per_frame > 0 ? r->cpu_per_frame / r->work_per_frame : NAN };
        for (int i = 0; i < 3; i++) {
            fprintf(f, ",\"%s\":", cn[i]);
            json_number(f, cv[i]);
        }
    }
    for (int b = 0; b < r->nbands; b++) {
        const char *bn[] = { "imbalance", "imbalance_max", "predicted_speedup", "sched_imbalance", "sched_speedup" };
        const double bv[] = { r->imbalance[b], r->imbalance_max[b], r->speedup[b], r->sched_imbalance[b],
                              r->sched_speedup[b] };
        for (int i = 0; i < 5; i++) {
            fprintf(f, ",\"%s_%d\":", bn[i], r->bands[b]);
            json_number(f, bv[i]);
        }
    }
    fputs(",\"stages\":{", f);
    for (int s = 0; s < NSTAGES; s++) {
        fprintf(f, "%s\"%s\":", s ? "," : "", stage_names[s]);
        json_number(f, r->stages[s]);
    }
    fprintf(f, "},\"counters\":{\"pixels\":%ld", (long)r->w * r->h);
    for (int c = 0; c < NCOUNTERS; c++) {
        fprintf(f, ",\"%s\":", counter_defs[c].name);
        json_count(f, r->counters[c]);
    }
    fputc('}', f);
    if (r->per_view) {
        fputs(",\"per_view\":[", f);
        for (int v = 0; v < r->views; v++) {
            const view_row *pv = &r->per_view[v];
            fprintf(f, "%s{\"view\":%d,\"median_ms\":", v ? "," : "", v);
            json_number(f, pv->stages[ST_TOTAL]);
            fputs(",\"stages\":{", f);
            for (int s = 0; s < ST_TOTAL; s++) {
                fprintf(f, "%s\"%s\":", s ? "," : "", stage_names[s]);
                json_number(f, pv->stages[s]);
            }
            fprintf(f, "},\"surfaces\":%ld,\"edges\":%ld,\"spans\":%ld,\"entities_drawn\":%ld,\"alias_tris\":%ld}",
                    pv->surfaces, pv->edges, pv->spans, pv->entities_drawn, pv->alias_tris);
        }
        fputc(']', f);
    }
    fputs("}\n", f);
}

static void print_table_header(const bench_opts *o) {
    printf("%-10s %9s %3s %5s %4s %8s %8s %8s %8s %4s %5s %5s %6s %7s %6s %7s %7s %7s %7s %6s %7s %6s", "map",
           "size", "thr", "views", "cold", "median", "mean", "p99", "max", "@", "level", "vlev", "ns/px",
           "floor", "xfloor", "front", "scan", "draw", "models", "seethr", "serial", "ser%");
    for (int b = 0; b < o->nbands; b++) {
        char imb[16], x[16], xs[16];
        snprintf(imb, sizeof imb, "imb%d", o->bands[b]);
        snprintf(x, sizeof x, "x%d", o->bands[b]);
        snprintf(xs, sizeof xs, "xs%d", o->bands[b]);
        printf(" %6s %6s %6s", imb, x, xs);
    }
    putchar('\n');
}

static void print_table_row(const row *r) {
    char size[24];
    snprintf(size, sizeof size, "%dx%d", r->w, r->h);
    printf("%-10.10s %9s %3d %5d %4s %8.3f %8.3f %8.3f %8.3f %4d %5.2f %5.2f %6.2f %7.3f %6.2f %7.3f "
           "%7.3f %7.3f %7.3f %6.1f",
           r->map, size, r->threads, r->views, r->cold ? "yes" : "no", r->median, r->mean, r->p99, r->max, r->max_view,
           r->level, r->view_level, r->ns_per_pixel, r->floor_ms, r->floor_ratio, r->stages[ST_FRONT],
           r->stages[ST_SCAN], r->stages[ST_DRAW], r->stages[ST_MODELS],
           r->counters[counter_of(offsetof(ew_stats, seethrough_surfaces))]);
    printf(" %7.3f %6.2f", r->serial, 100 * r->serial_share);
    for (int b = 0; b < r->nbands; b++)
        printf(" %6.3f %6.2f %6.2f", r->imbalance[b], r->speedup[b], r->sched_speedup[b]);
    putchar('\n');
    if (!r->per_view) return;
    printf("  view_level of the parts alone:");
    for (int k = 0; k < NPARTS; k++) printf(" %s %.2f", part_names[k], r->part_levels[k]);
    putchar('\n');
    printf("  %4s %8s %6s %7s %7s %7s %7s %6s %6s %7s %5s %6s\n", "view", "median", "x med", "front", "scan",
           "draw", "models", "surfs", "edges", "spans", "ents", "tris");
    for (int v = 0; v < r->views; v++) {
        const view_row *pv = &r->per_view[v];
        printf("  %4d %8.3f %6.2f %7.3f %7.3f %7.3f %7.3f %6ld %6ld %7ld %5ld %6ld\n", v, pv->stages[ST_TOTAL],
               r->median > 0 ? pv->stages[ST_TOTAL] / r->median : NAN, pv->stages[ST_FRONT], pv->stages[ST_SCAN],
               pv->stages[ST_DRAW], pv->stages[ST_MODELS], pv->surfaces, pv->edges, pv->spans, pv->entities_drawn,
               pv->alias_tris);
    }
}

/* A progress line on stderr, only for a person watching a terminal. */
static int     progress_on;
static double  progress_last;
static void progress(const char *map, int w, int h, int threads, int pass, int passes, int view,
                     int views) {
    if (!progress_on)
        return;
    double t = now_ms();
    if (t - progress_last < 100 && view != 0)
        return;
    progress_last = t;
    char line[160];
    snprintf(line, sizeof line, "bench: %.40s %dx%d threads %d %s %d/%d view %d/%d", map, w, h,
             threads, pass ? "pass" : "warm-up", pass, passes, view + 1, views);
    fprintf(stderr, "\r%-78.78s", line);
    fflush(stderr);
}
static void progress_clear(void) {
    if (progress_on)
        fprintf(stderr, "\r%78s\r", "");
}

/* ---- the command ----------------------------------------------------------- */

static int bench_floor(const bench_opts *o, FILE *json) {
    if (o->table)
        printf("%9s %9s %6s %9s %6s %6s\n", "size", "floor_ms", "ns/px", "lookup_ms", "ns/px", "reps");
    for (int i = 0; i < o->nsizes; i++) {
        int w = o->sizes[i][0], h = o->sizes[i][1], reps = 0;
        double lookup = -1, ms = measure_floor(w, h, &reps, &lookup);
        if (ms < 0) {
            error_line("bench: out of memory for a %dx%d frame", w, h);
            return 1;
        }
        double nspp = ms * 1e6 / ((double)w * h);
        if (json) {
            fprintf(json, "{\"floor\":true,\"width\":%d,\"height\":%d,\"floor_ms\":", w, h);
            json_number(json, ms);
            fputs(",\"ns_per_pixel\":", json);
            json_number(json, nspp);
            fputs(",\"lookup_floor_ms\":", json);
            json_number(json, lookup);
            fprintf(json, ",\"reps\":%d}\n", reps);
            fflush(json);
        }
        if (o->table) {
            char size[24];
            snprintf(size, sizeof size, "%dx%d", w, h);
            printf("%9s %9.4f %6.3f %9.4f %6.3f %6d\n", size, ms, nspp, lookup, lookup * 1e6 / ((double)w * h), reps);
            fflush(stdout);
        }
    }
    return 0;
}

/* Loads one map, or NULL with the error printed. */
static ew_assets *bench_load(const bench_opts *o, const char *map) { return load_map(map, o->data, o->quiet); }

/* The protocol itself, shared with `edgewise hsr` (cli.h). */
int bench_run_views(ew_renderer *rd, const ew_camera *views, int nviews, int passes, double *frames,
                    ew_stats *stats, ew_lab_stats *labs, const bench_hooks *hooks) {
    for (int pass = 0; pass <= passes; pass++) {
        for (int v = 0; v < nviews; v++) {
            if (hooks && hooks->before)
                hooks->before(hooks->ctx, pass, v);
            ew_stats st;
            /* Pass 0 is the warm-up: page in the frame and fill the surface cache. */
            ew_stats *sp = pass && stats ? &stats[(size_t)(pass - 1) * nviews + v] : &st;
            double t0 = now_ms();
            int ok = ew_render(rd, &views[v], sp);
            double t1 = now_ms();
            if (ok < 0)
                return -1 - v;
            if (pass && labs) ew_frame_lab_stats(rd, &labs[(size_t)(pass - 1) * nviews + v]);
            if (pass) {
                frames[(size_t)(pass - 1) * nviews + v] = t1 - t0;
                if (hooks && hooks->after)
                    hooks->after(hooks->ctx, pass, v);
            }
        }
    }
    return 0;
}

double bench_median(double *v, int n) { return median_of(v, n); }

/* bench_row's progress line before each frame, a floor sample after every
 * other timed one; with --gap the pause before each frame and the process's
 * processor time over the timed passes. */
typedef struct bench_row_hooks_ctx {
    const row     *r;
    ew_renderer   *rd;      /* --cold: its surface cache emptied before each frame */
    int            passes, nviews;
    floor_sampler *fl;
    double         cpu0, cpu1;  /* --gap: process CPU ms, after the first timed frame's gap, after the last's */
} bench_row_hooks_ctx;

static double process_cpu_ms(void) {
    struct timespec t;
    if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t) != 0)
        return NAN;
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec / 1e6;
}

static void gap_sleep(int ms) {
    struct timespec ts = { ms / 1000, (long)(ms % 1000) * 1000000L };
    nanosleep(&ts, NULL);
}

static void row_before(void *ctx, int pass, int v) {
    bench_row_hooks_ctx *c = ctx;
    if (c->r)
        progress(c->r->map, c->r->w, c->r->h, c->r->threads, pass, c->passes, v, c->nviews);
    if (c->r && c->r->gap_ms > 0) {
        gap_sleep(c->r->gap_ms);
        /* From here every timed frame and the gap after it: what the
         * workers do between frames (poll or sleep) is in the count. */
        if (pass == 1 && v == 0)
            c->cpu0 = process_cpu_ms();
    }
    /* Outside the timed call: the frame then pays for its surface builds,
     * not for the eviction. */
    if (c->rd)
        ew_flush_surfaces(c->rd);
}

static void row_after(void *ctx, int pass, int v) {
    bench_row_hooks_ctx *c = ctx;
    if (c->r->gap_ms > 0 && pass == c->passes && v == c->nviews - 1) {
        gap_sleep(c->r->gap_ms);  /* the last frame's gap, which the next frame would follow */
        c->cpu1 = process_cpu_ms();
    }
    if (!c->fl) return;
    /* On more threads the samples of a pass wait for its end: a fill on the
     * calling thread outlasts the pool's polling, so taken between frames it
     * would put the workers to sleep before every other frame, which a
     * renderer drawing frame after frame never does (a 2-3% slower median
     * at 1080p on two threads; --gap measures frames spaced out). */
    if (c->r->threads == 1) {
        if (v % 2) floor_rep(c->fl);
    } else if (v == c->nviews - 1) {
        for (int k = 0; k < c->nviews / 2; k++) floor_rep(c->fl);
    }
}

/* Rows [0, h) of per-row costs cost cut into n pieces placed by placed_by
 * (ew_place_bands, or with guided ew_place_pieces as the draw's), handed
 * out in order to whichever of threads threads is free first; returns when
 * the last finishes and adds the work to *total.  With as many pieces as
 * threads, the slowest piece. */
static double phase_end(const float *placed_by, const float *cost, int h, int n, int threads, int guided,
                        double *total) {
    int bounds[MAX_BANDS * EW_DRAW_ITEMS_PER_THREAD + 1];
    double busy[MAX_BANDS] = { 0 }, end = 0;
    if (guided)
        ew_place_pieces(placed_by, h, n, threads, bounds);
    else
        ew_place_bands(placed_by, h, n, bounds);
    for (int b = 0; b < n; b++) {
        double c = 0;
        for (int v = bounds[b]; v < bounds[b + 1]; v++) c += cost[v];
        int t = 0;
        for (int k = 1; k < threads; k++)
            if (busy[k] < busy[t])
                t = k;
        busy[t] += c;
        *total += c;
        if (busy[t] > end)
            end = busy[t];
    }
    return end;
}

/* The frame's two phases, which wait for each other, each cut into n bands
 * by its own row costs (scan, draw): their slowest bands over the mean. */
static double band_imbalance(const float *scan, const float *draw, int h, int n) {
    double total = 0, end = phase_end(scan, scan, h, n, n, 0, &total) + phase_end(draw, draw, h, n, n, 0, &total);
    return total > 0 ? end / (total / n) : NAN;
}

/* The renderer itself on n threads: the scan's bands placed by the last
 * frame's scan costs (prev_scan), the draw's guided pieces by this frame's
 * draw costs (which the renderer estimates from its spans and models; here
 * the measured ones), each phase handed out to whichever thread is free first;
 * the two finishing times over a perfect share, total / n. */
static double sched_imbalance(const float *prev_scan, const float *scan, const float *draw, int h, int n) {
    int nb, ni;
    ew_frame_cuts(n, h, &nb, &ni);
    double total = 0,
           end = phase_end(prev_scan, scan, h, nb, n, 0, &total) + phase_end(draw, draw, h, ni, n, 1, &total);
    return total > 0 ? end / (total / n) : NAN;
}

static float min3(float a, float b, float c) {
    float m = a < b ? a : b;
    return c < m ? c : m;
}

/* --bands: the one-thread frame's cost per row in its scan and in its
 * draw (strips of 8 rows, the view set rendered PROFILE_PASSES times and
 * each strip's least time kept: a time slice lost to another process, 4 ms
 * here, hits a strip of one pass in a hundred, so its median of three
 * still caught one view a map on this shared machine), each phase cut
 * into each N bands; per N the median over the views of the slowest bands
 * over the mean band, and the worst view's.  rd is left on one thread, without
 * the profile.  0, or -1 when out of memory or a camera fails. */
static int profile_bands(const bench_opts *o, ew_renderer *rd, const ew_camera *views, int nviews, int h,
                         size_ctx *sx) {
#ifdef EW_BENCH_NO_SERIAL
    (void)rd, (void)views, (void)nviews, (void)h;
    for (int b = 0; b < o->nbands; b++) sx->imbalance[b] = sx->imbalance_max[b] = sx->sched_imbalance[b] = NAN;
    sx->front_items = NAN;
    sx->have_profile = 1;
    return 0;
#else
    /* per pass and view, each row's time in the scan and in the draw; then
     * per view each strip's least */
    size_t hv = (size_t)h * (size_t)nviews;
    float *scan = malloc(sizeof(float) * hv * (PROFILE_PASSES + 1) * 2), *draw = scan + hv * (PROFILE_PASSES + 1);
    double *imb = malloc(sizeof(double) * (size_t)nviews * (size_t)o->nbands * 2);
    double *items = malloc(sizeof(double) * (size_t)nviews);
    int rc = -1;
    if (!scan || !imb || !items || ew_set_threads(rd, 1) < 0 || ew_set_row_profile(rd, 1) < 0)
        goto out;
    ew_set_front_mode(rd, EW_FRONT_PHASES);  /* the front end's items as many threads run them */
    double *simb = imb + (size_t)nviews * o->nbands;
    /* Pass after pass over the view set, so one stall of the machine hits
     * a view's strip in one pass, not in all three. */
    for (int p = 0; p < PROFILE_PASSES; p++)
        for (int v = 0; v < nviews; v++) {
            ew_stats st;
            if (o->cold)
                ew_flush_surfaces(rd);
            if (ew_render(rd, &views[v], &st) < 0)
                goto out;
            ew_frame_row_ms(rd, scan + hv * p + (size_t)h * v, draw + hv * p + (size_t)h * v, h);
            /* the front end's largest items: the least of the passes too */
            ew_lab_stats lab;
            ew_frame_lab_stats(rd, &lab);
            if (p == 0 || lab.ms_front_items < items[v]) items[v] = lab.ms_front_items;
        }
    sx->front_items = median_of(items, nviews);
    for (int v = 0; v < nviews; v++) {
        float *ph[2] = { scan, draw };
        for (int k = 0; k < 2; k++) {
            const float *r0 = ph[k] + (size_t)h * v, *r1 = r0 + hv, *r2 = r1 + hv;
            float *best = ph[k] + hv * PROFILE_PASSES + (size_t)h * v;
            for (int y = 0; y < h; y++)
                best[y] = min3(r0[y], r1[y], r2[y]);
        }
        const float *bs = scan + hv * PROFILE_PASSES + (size_t)h * v, *bd = draw + hv * PROFILE_PASSES + (size_t)h * v;
        for (int b = 0; b < o->nbands; b++)
            imb[(size_t)b * nviews + v] = band_imbalance(bs, bd, h, o->bands[b]);
    }
    /* The bench's frames follow each other view after view, the first after
     * the last: each one's scan is cut by the one before. */
    for (int v = 0; v < nviews; v++) {
        const float *cur = scan + hv * PROFILE_PASSES + (size_t)h * v;
        const float *prev = scan + hv * PROFILE_PASSES + (size_t)h * ((v + nviews - 1) % nviews);
        const float *dr = draw + hv * PROFILE_PASSES + (size_t)h * v;
        for (int b = 0; b < o->nbands; b++)
            simb[(size_t)b * nviews + v] = sched_imbalance(prev, cur, dr, h, o->bands[b]);
    }
    for (int b = 0; b < o->nbands; b++) {
        double *col = imb + (size_t)b * nviews;
        sx->imbalance[b] = median_of(col, nviews);  /* sorts col */
        sx->imbalance_max[b] = col[nviews - 1];
        sx->sched_imbalance[b] = median_of(simb + (size_t)b * nviews, nviews);
    }
    sx->have_profile = 1;
    rc = 0;
out:
    ew_set_front_mode(rd, EW_FRONT_AUTO);
    if (ew_set_row_profile(rd, 0) < 0)
        rc = -1;
    free(scan);
    free(imb);
    free(items);
    return rc;
#endif
}
_Static_assert(PROFILE_PASSES == 3, "min3 takes three");

/* --bands: what the front end's phases, which many threads run, cost the
 * one-thread frame: each view rendered with and without them, the order
 * swapped from frame to frame (so the machine's drift cancels), each
 * view's least of PROFILE_PASSES; the sum with over the sum without.  rd
 * on one thread, left in EW_FRONT_AUTO.  The ratio, or 0 if a camera fails. */
static double phases_ratio(ew_renderer *rd, const ew_camera *views, int nviews) {
    double sum[2] = { 0, 0 };
    for (int v = 0; v < nviews; v++) {
        double best[2] = { INFINITY, INFINITY };
        for (int p = 0; p < PROFILE_PASSES; p++)
            for (int k = 0; k < 2; k++) {
                int phases = k ^ ((v + p) & 1);
                ew_set_front_mode(rd, phases ? EW_FRONT_PHASES : EW_FRONT_AUTO);
                double t0 = now_ms();
                int bad = ew_render(rd, &views[v], NULL) < 0;
                double ms = now_ms() - t0;
                if (bad) {
                    ew_set_front_mode(rd, EW_FRONT_AUTO);
                    return 0;
                }
                if (ms < best[phases])
                    best[phases] = ms;
            }
        sum[0] += best[0], sum[1] += best[1];
    }
    ew_set_front_mode(rd, EW_FRONT_AUTO);
    return sum[0] > 0 ? sum[1] / sum[0] : 0;
}

/* One map at one size and thread count; returns 0 or 1 (error printed).
 * scene is an ew_scene or NULL (world only). */
static int bench_row(const bench_opts *o, const char *map, const ew_assets *a,
                     const ew_scene *scene, const ew_camera *views, int nviews, int w, int h,
                     int threads, floor_cache *fc, size_ctx *sx, row *r) {
    memset(r, 0, sizeof *r);
    map_basename(map, r->map, sizeof r->map);
    r->w = w;
    r->h = h;
    r->threads_requested = threads;
    r->threads = threads ? threads : online_cores();
    r->entities = scene != NULL;
    r->views = nviews;
    r->passes = o->passes;
    r->gap_ms = o->gap_ms;
    r->cold = o->cold;

    ew_error err = { "" };
    ew_renderer *rd = ew_renderer_create(&(ew_renderer_desc){
            .world = a->world, .palette = a->palette,
            .colormap = a->colormap, .width = w, .height = h, .threads = 1,
            .color = (ew_color_mode)o->draw.color }, &err);
    if (!rd) {
        error_line("%s", err.msg[0] ? err.msg : "cannot create the renderer");
        return 1;
    }
#ifndef EW_BENCH_NO_THREADS
    /* The renderer may use fewer threads than asked (bands of >= 8 rows, a
     * cap): rows report the count in use. */
    int used = ew_set_threads(rd, threads);
    if (used < 0) {
        error_line("bench: out of memory for %d threads at %dx%d", r->threads, w, h);
        ew_renderer_destroy(rd);
        return 1;
    }
    r->threads = used;
    r->threads_applied = 1;
#endif
    r->draw = o->draw;
    r->draw.map_rgb = ew_world_has_rgb_light(a->world);  /* "lit": coloured light actually drawn */
    r->draw.no_entities = scene == NULL;
    draw_opts_apply(&o->draw, rd, scene);
    r->simd = (int)ew_set_simd(rd, (ew_simd_level)o->simd);
    size_t n = (size_t)nviews * (size_t)o->passes;
    double *frames = malloc(n * sizeof *frames), *scratch = malloc(n * sizeof *scratch);
    ew_stats *stats = calloc(n, sizeof *stats);
    ew_lab_stats *labs = calloc(n, sizeof *labs);
    if (o->per_view && nviews > 0) r->per_view = calloc((size_t)nviews, sizeof *r->per_view);
    /* The floor is sampled between the frames (after every other one), so
     * both see the machine in the same state: on a shared machine the
     * floor alone moves by a quarter from one minute to the next. */
    floor_sampler fl;
    int fl_ok = floor_begin(&fl, w, h, nviews * o->passes) == 0;
    int rc = 1;
    if (!frames || !scratch || !stats || !labs || (o->per_view && nviews > 0 && !r->per_view)) {
        error_line("bench: out of memory");
        goto done;
    }
    /* --gap counts the process's processor time: no floor samples among
     * the frames then (the floor is measured on its own). */
    if (o->gap_ms > 0)
        fl_ok = 0;
    bench_row_hooks_ctx hc = { r, o->cold ? rd : NULL, o->passes, nviews, fl_ok ? &fl : NULL, NAN, NAN };
    bench_hooks hooks = { row_before, row_after, &hc };
    int bad = bench_run_views(rd, views, nviews, o->passes, frames, stats, labs, &hooks);
    if (o->gap_ms > 0 && n > 0) {
        double work = 0;
        for (size_t i = 0; i < n; i++)
            work += labs[i].ms_work;
        r->cpu_per_frame = (hc.cpu1 - hc.cpu0) / (double)n;
        r->work_per_frame = work / (double)n;
    }
    if (bad) {
        progress_clear();
        error_line("%s: view %d: cannot render this camera", r->map, -bad - 1);
        goto done;
    }
    if (fl_ok)
        r->floor_ms = floor_end(&fl, &r->lookup_floor_ms);
    else  /* no memory for the interleaved samples: measured on its own */
        r->floor_ms = floor_for(fc, w, h, &r->lookup_floor_ms);
    summarize(r, frames, stats, labs, scratch);
    /* The one-loop frame's serial time (a one-thread row): its walk is
     * serial on up to EW_FRONT_LOOP_THREADS threads too (their prediction). */
    double loop_serial = NAN;
#ifndef EW_BENCH_NO_SERIAL
    if (r->threads == 1) {
        serial_times(stats, labs, r->views * r->passes, scratch);
        loop_serial = median_of(scratch, r->views * r->passes);
    }
    /* One thread walks the front end in one loop, outside the pool: its
     * serial time would not be a many-thread frame's.  That comes from one
     * more pass (after a warm-up) with the phases many threads run
     * (ew_set_front_mode), over this row's faster median below. */
    if (r->threads == 1) {
        ew_set_front_mode(rd, EW_FRONT_PHASES);
        bench_row_hooks_ctx cc = { NULL, rd, 1, nviews, NULL, NAN, NAN };  /* --cold: that pass cold too */
        bad = bench_run_views(rd, views, nviews, 1, frames, stats, labs,
                              o->cold ? &(bench_hooks){ row_before, NULL, &cc } : NULL);
        ew_set_front_mode(rd, EW_FRONT_AUTO);
        if (bad) {
            progress_clear();
            error_line("%s: view %d: cannot render this camera", r->map, -bad - 1);
            goto done;
        }
        summarize_serial(r, stats, labs, nviews, scratch);
    }
#endif
    /* The serial share is of the one-thread frame: this row's if it is
     * one, else the one-thread row of this map and size measured before
     * it, else (none) of this row's own median. */
    int first_one = r->threads == 1 && !sx->have_one;
    if (first_one)
        sx->have_one = 1, sx->one_median = r->median;
    r->serial_base_own = !sx->have_one;
    r->serial_share = r->serial / (sx->have_one ? sx->one_median : r->median);
    if (first_one)
        sx->one_share = r->serial_share, sx->loop_share = loop_serial / r->median;
    /* The predictions model the work of one frame, so they take the
     * one-thread row's share: a row on more threads measures its serial
     * part with the pool's wake-ups in it, and on a busy machine that part
     * can outgrow the one-thread frame (a share above 1). */
    r->predict_share = sx->have_one ? sx->one_share : r->serial_share;
    if (r->predict_share > 1)
        r->predict_share = 1;
#ifdef EW_BENCH_NO_SERIAL
    r->serial = r->serial_share = r->serial_mean = NAN;
    for (int ph = 0; ph < NPHASES; ph++) r->serial_phase[ph] = NAN;
#endif
    if (o->nbands && !sx->have_profile) {
        if (profile_bands(o, rd, views, nviews, h, sx) < 0) {
            progress_clear();
            error_line("bench: %s at %dx%d: the row profile failed (out of memory?)", r->map, w, h);
            goto done;
        }
#ifndef EW_BENCH_NO_SERIAL
        sx->phases_ratio = phases_ratio(rd, views, nviews);  /* rd is on one thread now */
#endif
    }
    /* The front end's largest items wait on one thread however many there
     * are: counted with the serial share. */
    r->front_items = o->nbands ? sx->front_items : NAN;
    if (o->nbands && isfinite(sx->front_items)) {
        r->predict_share += sx->front_items / (sx->have_one ? sx->one_median : r->median);
        if (r->predict_share > 1)
            r->predict_share = 1;
    }
    /* Many threads run the front end's phases, which cost more than the
     * one-thread loop (10-20% of the front end): the work they share is
     * the phases frame's, less the serial part (as a share of the loop's
     * frame, so the speed-up is over the one-thread frame as it runs). */
    r->phases_share = o->nbands && sx->phases_ratio > 1 ? sx->phases_ratio : 1;
    r->nbands = o->nbands;
    for (int b = 0; b < o->nbands; b++) {
        int n = o->bands[b];
        double s = r->predict_share, ps = r->phases_share, imb = sx->imbalance[b];
        r->bands[b] = n;
        r->imbalance[b] = imb;
        r->imbalance_max[b] = sx->imbalance_max[b];
        /* On few threads the frame is the one-loop frame, its walk serial. */
        if (n <= EW_FRONT_LOOP_THREADS && isfinite(sx->loop_share))
            s = sx->loop_share < 1 ? sx->loop_share : 1, ps = 1;
        /* Amdahl with imbalance: the serial share stays, the rest of the
         * phases frame is cut into n bands on n cores and waits for the slowest. */
        r->speedup[b] = 1 / (s + (ps - s) * imb / n);
        r->sched_imbalance[b] = sx->sched_imbalance[b];
        r->sched_speedup[b] = 1 / (s + (ps - s) * r->sched_imbalance[b] / n);
    }
    rc = 0;
done:
    floor_end(&fl, NULL);
    free(frames);
    free(scratch);
    free(stats);
    free(labs);
    ew_renderer_destroy(rd);
    return rc;
}

int cmd_bench(int argc, char **argv) {
    bench_opts o;
    memset(&o, 0, sizeof o);
    draw_opts_init(&o.draw);
    int pr = bench_parse(argc, argv, &o);
    if (pr)
        return pr < 0 ? BENCH_EXIT_USAGE : 0;

    FILE *json = NULL;
    if (o.out) {
        json = fopen(o.out, "w");
        if (!json) {
            error_line("%s: %s", o.out, strerror(errno));
            return 1;
        }
    } else if (!o.table) {
        json = stdout;
    }
    progress_on = isatty(STDERR_FILENO);

    int rc = 0;
    if (o.floor_only) {
        rc = bench_floor(&o, json);
    } else {
        floor_cache fc;
        memset(&fc, 0, sizeof fc);
        if (o.table)
            print_table_header(&o);
        for (int m = 0; m < o.nmaps && !rc; m++) {
            ew_assets *a = bench_load(&o, o.maps[m]);
            if (!a) {
                rc = 1;
                break;
            }
            ew_camera views[EW_MAX_VIEWS];
            int nviews = ew_benchmark_views(a->world, views);
            /* The map's entities, as the game shows it; the built-in scene's
             * own moving things for `builtin`. */
            ew_scene *sc = NULL;
            if (nviews > 0 && draw_opts_scene(&o.draw, a, o.maps[m], o.data, 0, o.quiet, &sc) < 0)
                rc = 1;
            const ew_scene *scene = sc;
            if (nviews == 0) {
                error_line("%s: no views (no info_player* or info_intermission entity)",
                           o.maps[m]);
                rc = 1;
            }
            for (int s = 0; s < o.nsizes && !rc; s++) {
                size_ctx sx;
                memset(&sx, 0, sizeof sx);
                sx.loop_share = NAN;
                for (int t = 0; t < o.nthreads && !rc; t++) {
                    row r;
                    rc = bench_row(&o, o.maps[m], a, scene, views, nviews, o.sizes[s][0],
                                   o.sizes[s][1], o.threads[t], &fc, &sx, &r);
                    if (!rc) {
                        progress_clear();
                        if (json) {
                            print_row_json(json, &r);
                            fflush(json);
                        }
                        if (o.table) {
                            print_table_row(&r);
                            fflush(stdout);
                        }
                    }
                    free(r.per_view);
                }
            }
            ew_scene_destroy(sc);
            ew_assets_destroy(a);
        }
    }
    progress_clear();
    if (json && json != stdout && fclose(json) != 0 && rc == 0) {
        error_line("%s: %s", o.out, strerror(errno));
        rc = 1;
    }
    if (fflush(stdout) != 0 && rc == 0) {
        error_line("stdout: %s", strerror(errno));
        rc = 1;
    }
    return rc;
}
