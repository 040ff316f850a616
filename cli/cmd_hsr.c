/*
 * edgewise hsr: the hidden-surface lab (issue 13).
 *
 *   edgewise hsr MAP... [--data DIR] [--methods LIST] [--size WxH]...
 *                [--threads N] [--repeat N] [--json FILE|-] [--heatmap DIR]
 *                [--svg FILE] [drawing options]
 *   edgewise hsr --stress LIST [the same options]
 *
 * Per map, size and method: the view set timed by the benchmark protocol
 * (cmd_bench.c's bench_run_views: a warm-up, then N timed passes), then one
 * untimed pass per view that compares the face of every pixel with the
 * reference path's (ew_render_reference, once per view and size) and, with
 * --heatmap, draws the overdraw heat map.  One row per map x size x method:
 * median and worst frame, overdraw, agreement, the method's memory and its
 * own counters, as a table and as JSON lines; --svg draws them as a bar
 * chart (or, with --stress, time against the polygons in view).
 *
 * Like bench, this is read, never asserted on for its times.
 */
#define _POSIX_C_SOURCE 200809L
#include "cli.h"
#include "edgewise.h"
#include "edgewise_lab.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

enum {
    HSR_EXIT_USAGE = 2,
    MAX_MAPS = 64,
    MAX_SIZES = 8,
    MAX_STRESS = 16,
    MAX_REPEAT = 1000,
    DEFAULT_REPEAT = 5,
};

/* The map form that names a stress level (also what --stress makes). */
#define STRESS_PREFIX STRESS_MAP_PREFIX

static const char hsr_usage[] =
    "usage: edgewise hsr MAP... [options]\n"
    "       edgewise hsr --stress LIST [options]\n"
    "\n"
    "The hidden-surface lab: every method on the view set of each MAP at each\n"
    "size, timed by the benchmark protocol (a warm-up, then N timed passes).\n"
    "One row per map x size x method: median and worst frame, overdraw (pixels\n"
    "written per pixel covered), agreement with the reference path (pixels whose\n"
    "face matches), the method's memory and its own counters.\n"
    "\n"
    "options:\n"
    CLI_OPTIONS_HERE
    "\n"
    "what is drawn (as in edgewise render; --hsr is --methods here):\n";
static const char hsr_usage_tail[] =
    "\n"
    "MAP is a .bsp path, a map name in --data, 'builtin' or builtin:detail=N.\n"
    "example:\n"
    "  edgewise hsr e1m1 lqdm7 --data ../shared/data/librequake --size 320x200 --svg hsr.svg\n"
    "  edgewise hsr --stress 500,2000,5000,20000 --svg stress.svg\n";

typedef struct hsr_opts {
    const char *maps[MAX_MAPS];
    char        stress_names[MAX_STRESS][32];
    int         stress[MAX_STRESS], nstress;
    int         nmaps;
    const char *data, *json, *heatmap, *svg;
    int         sizes[MAX_SIZES][2], nsizes;
    int         methods[EW_HSR_COUNT], nmethods;
    int         threads, repeat, quiet;
    draw_opts   draw;
} hsr_opts;

/* One row: a map at a size drawn by a method. */
typedef struct hsr_row {
    char   map[256];
    int    w, h, method, views, passes, threads, stress;  /* stress: detail, or -1 */
    int    entities;      /* drawn with a scene */
    double median, mean, worst;
    int    worst_view;
    double overdraw_mean, overdraw_max;
    double agree_mean, agree_min;   /* percent of the frame's pixels */
    int    agree_min_view;
    double polygons, polygons_max, dropped;   /* ew_stats.surfaces (+ faces_occluded), .dropped per frame */
    double in_view;        /* polygons in view: the edge list's surfaces, mean per view */
    double mem_mean, mem_max;       /* ew_stats.hsr_bytes */
    double counters[EW_HSR_COUNTERS];  /* mean per frame */
} hsr_row;

/* ---- arguments --------------------------------------------------------------- */

static int parse_methods(const char *v, hsr_opts *o) {
    char buf[256];
    if (!*v || strlen(v) >= sizeof buf) {
        error_line("hsr: --methods %s: expected a comma list of method names", v);
        return -1;
    }
    strcpy(buf, v);
    char have[160] = "";
    for (int m = 0; m < EW_HSR_COUNT; m++)
        if (ew_hsr_available((ew_hsr_method)m))
            snprintf(have + strlen(have), sizeof have - strlen(have), "%s%s", *have ? ", " : "",
                     ew_hsr_name((ew_hsr_method)m));
    o->nmethods = 0;
    for (char *p = buf, *next; p; p = next) {
        next = strchr(p, ',');
        if (next) *next++ = '\0';
        int m = ew_hsr_from_name(p);
        if (m < 0 || !ew_hsr_available((ew_hsr_method)m)) {
            error_line("hsr: --methods %s: %s method '%s' (this build has %s)", v,
                       m < 0 ? "unknown" : "unavailable", p, have);
            return -1;
        }
        for (int i = 0; i < o->nmethods; i++)
            if (o->methods[i] == m) {
                error_line("hsr: --methods %s: '%s' given twice", v, p);
                return -1;
            }
        o->methods[o->nmethods++] = m;
    }
    return 0;
}

/* "N" within the stress level's detail range; 0 or -1 (nothing printed). */
static int parse_detail(const char *s, int *out) {
    long l;
    if (parse_long(s, &l) < 0 || l < 0 || l > EW_STRESS_MAX_DETAIL)
        return -1;
    *out = (int)l;
    return 0;
}

static int parse_stress(const char *v, hsr_opts *o) {
    char buf[256];
    if (!*v || strlen(v) >= sizeof buf)
        goto bad;
    strcpy(buf, v);
    for (char *p = buf, *next; p; p = next) {
        next = strchr(p, ',');
        if (next) *next++ = '\0';
        if (o->nstress == MAX_STRESS) {
            error_line("hsr: --stress %s: more than %d details", v, MAX_STRESS);
            return -1;
        }
        if (parse_detail(p, &o->stress[o->nstress]) < 0)
            goto bad;
        o->nstress++;
    }
    return 0;
bad:
    error_line("hsr: --stress %s: expected a comma list of details from 0 to %d", v, EW_STRESS_MAX_DETAIL);
    return -1;
}

/* Returns 0, 1 for --help (usage printed), -1 (error printed). */
static int hsr_parse(int argc, char **argv, hsr_opts *o) {
    int repeat_given = 0, threads_given = 0, methods_given = 0;
    cli_args args;
    cli_args_init(&args, CLI_HSR, argc, argv, o->maps, MAX_MAPS, &o->draw, hsr_usage, hsr_usage_tail);
    /* --hsr is a drawing option of the table, but the lab runs every method */
    for (int i = 2; i < argc && strcmp(argv[i], "--") != 0; i++)
        if (strcmp(argv[i], "--hsr") == 0 || strncmp(argv[i], "--hsr=", 6) == 0) {
            error_line("hsr: --hsr: the lab runs every method of --methods LIST");
            return -1;
        }
    while (cli_next_arg(&args)) {
        const cli_option *opt = args.opt;
        const char *v = args.value;
        const char *name = opt->name;
        if (strcmp(name, "--data") == 0 || strcmp(name, "--json") == 0 || strcmp(name, "--heatmap") == 0 ||
            strcmp(name, "--svg") == 0) {
            const char **slot = name[2] == 'd' ? &o->data : name[2] == 'j' ? &o->json
                                : name[2] == 'h' ? &o->heatmap : &o->svg;
            if (cli_set_once("hsr", name, v, slot) < 0)
                return -1;
        } else if (strcmp(name, "--methods") == 0) {
            if (methods_given++) {
                error_line("hsr: --methods given twice");
                return -1;
            }
            if (parse_methods(v, o) < 0)
                return -1;
        } else if (strcmp(name, "--size") == 0) {
            if (cli_add_size("hsr", v, o->sizes, &o->nsizes, MAX_SIZES) < 0)
                return -1;
        } else if (strcmp(name, "--threads") == 0) {
            if (threads_given++) {
                error_line("hsr: --threads given twice");
                return -1;
            }
            if (parse_threads(v, &o->threads) < 0)
                return -1;
        } else if (strcmp(name, "--repeat") == 0) {
            if (cli_int_once("hsr", name, v, 1, MAX_REPEAT, &repeat_given, &o->repeat) < 0)
                return -1;
        } else { /* --stress */
            if (o->nstress) {
                error_line("hsr: --stress given twice");
                return -1;
            }
            if (parse_stress(v, o) < 0)
                return -1;
        }
    }
    if (args.stop)
        return args.stop;
    o->nmaps = args.nmaps, o->quiet = args.quiet;
    if (o->nstress && o->nmaps) {
        error_line("hsr: --stress takes no MAP (it makes its own: builtin:detail=N)");
        return -1;
    }
    if (!o->nstress && !o->nmaps) {
        error_line("hsr: missing MAP (a .bsp path, a map name with --data, 'builtin' or builtin:detail=N)");
        return -1;
    }
    for (int i = 0; i < o->nmaps; i++) {
        if (stress_detail(o->maps[i]) == -2) {
            error_line("%s: the detail must be a whole number from 0 to %d", o->maps[i], EW_STRESS_MAX_DETAIL);
            return -1;
        }
    }
    for (int i = 0; i < o->nstress; i++) {
        snprintf(o->stress_names[i], sizeof o->stress_names[i], STRESS_PREFIX "%d", o->stress[i]);
        o->maps[o->nmaps++] = o->stress_names[i];
    }
    if (!o->nsizes) {
        static const int lab[3][2] = { { 320, 200 }, { 640, 480 }, { 1920, 1080 } };
        int n = o->nstress ? 1 : 3;
        for (int i = 0; i < n; i++) {
            o->sizes[i][0] = o->nstress ? 640 : lab[i][0];
            o->sizes[i][1] = o->nstress ? 480 : lab[i][1];
        }
        o->nsizes = n;
    }
    if (!methods_given)
        for (int m = 0; m < EW_HSR_COUNT; m++)
            if (ew_hsr_available((ew_hsr_method)m)) o->methods[o->nmethods++] = m;
    if (!repeat_given)
        o->repeat = DEFAULT_REPEAT;
    if (!threads_given)
        o->threads = 1;
    return 0;
}

/* --heatmap DIR: made if missing (one level), and it must take files. */
static int check_heatmap_dir(const char *dir) {
    struct stat st;
    if (stat(dir, &st) != 0) {
        if (errno != ENOENT || mkdir(dir, 0777) != 0) {
            error_line("hsr: --heatmap %s: %s", dir, strerror(errno));
            return -1;
        }
        return 0;
    }
    if (!S_ISDIR(st.st_mode)) {
        error_line("hsr: --heatmap %s: not a directory", dir);
        return -1;
    }
    if (access(dir, W_OK | X_OK) != 0) {
        error_line("hsr: --heatmap %s: %s", dir, strerror(errno));
        return -1;
    }
    return 0;
}

/* ---- maps --------------------------------------------------------------------- */

/* MAP as assets, or NULL with the error printed; *stress the detail or -1. */
static ew_assets *hsr_load(const hsr_opts *o, const char *map, int *stress) {
    *stress = stress_detail(map) >= 0 ? stress_detail(map) : -1;
    return load_map(map, o->data, o->quiet);
}

/* A name for files: the map's base name, every character outside
 * [A-Za-z0-9_-] as '_' (builtin:detail=500 -> builtin_detail_500). */
static void file_label(const char *map, char *out, size_t size) {
    map_basename(map, out, size);
    for (char *p = out; *p; p++)
        if (!((*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') || *p == '-'))
            *p = '_';
}

/* ---- progress ------------------------------------------------------------------ */

static int progress_on;

static double now_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

typedef struct progress_ctx {
    const char *map, *what;
    int         w, h, passes, nviews;
    double      last;
} progress_ctx;

static void progress_before(void *ctx, int pass, int v) {
    progress_ctx *p = ctx;
    double t = now_ms();
    if (!progress_on || (t - p->last < 100 && v != 0))
        return;
    p->last = t;
    char line[160];
    snprintf(line, sizeof line, "hsr: %.32s %dx%d %s %s %d/%d view %d/%d", p->map, p->w, p->h, p->what,
             pass ? "pass" : "warm-up", pass, p->passes, v + 1, p->nviews);
    fprintf(stderr, "\r%-78.78s", line);
    fflush(stderr);
}

static void progress_clear(void) {
    if (progress_on)
        fprintf(stderr, "\r%78s\r", "");
}

/* ---- one map at one size --------------------------------------------------------- */

/* Fills the timing half of row from frames and stats[passes * nviews]. */
static void summarize_timing(hsr_row *r, double *frames, const ew_stats *stats) {
    int n = r->views * r->passes;
    double sum = 0;
    r->worst = -1;
    r->overdraw_mean = 0, r->overdraw_max = 0;
    r->polygons = r->polygons_max = r->dropped = r->mem_mean = r->mem_max = 0;
    for (int c = 0; c < EW_HSR_COUNTERS; c++) r->counters[c] = 0;
    for (int i = 0; i < n; i++) {
        const ew_stats *s = &stats[i];
        sum += frames[i];
        if (frames[i] > r->worst) r->worst = frames[i], r->worst_view = i % r->views;
        /* the faces handed to the method, also those the edge method found
         * hidden before it set up their edges */
        int polys = s->surfaces + s->faces_occluded;
        r->polygons += polys;
        if (polys > r->polygons_max) r->polygons_max = polys;
        r->dropped += s->dropped;
        r->mem_mean += (double)s->hsr_bytes;
        if ((double)s->hsr_bytes > r->mem_max) r->mem_max = (double)s->hsr_bytes;
        for (int c = 0; c < EW_HSR_COUNTERS; c++) r->counters[c] += (double)s->hsr_counters[c];
    }
    r->mean = sum / n;
    r->polygons /= n, r->dropped /= n, r->mem_mean /= n;
    for (int c = 0; c < EW_HSR_COUNTERS; c++) r->counters[c] /= n;
    /* overdraw per view (the mean of its passes: every pass draws the same) */
    for (int v = 0; v < r->views; v++) {
        double od = 0;
        for (int p = 0; p < r->passes; p++) od += stats[(size_t)p * r->views + v].overdraw;
        od /= r->passes;
        r->overdraw_mean += od / r->views;
        if (od > r->overdraw_max) r->overdraw_max = od;
    }
    r->median = bench_median(frames, n);
}

typedef struct lab_ctx {
    const hsr_opts *o;
    const char     *map;
    const ew_assets *a;
    const ew_scene *scene;
    const ew_camera *views;
    int             nviews, stress;
} lab_ctx;

/* Writes the heat map of the renderer's current method for view v. */
static int write_heatmap(const lab_ctx *c, ew_renderer *rd, int w, int h, int v, int method) {
    char label[200], path[1024];
    ew_error err = { "" };
    file_label(c->map, label, sizeof label);
    snprintf(path, sizeof path, "%s/%s_%dx%d_v%d_%s.png", c->o->heatmap, label, w, h, v,
             ew_hsr_name((ew_hsr_method)method));
    if (ew_set_debug(rd, EW_DEBUG_OVERDRAW) < 0) {
        error_line("hsr: out of memory for the overdraw heat map at %dx%d", w, h);
        return -1;
    }
    int rc = ew_render(rd, &c->views[v], NULL);
    ew_set_debug(rd, (ew_debug_mode)c->o->draw.debug);
    if (rc < 0) {
        error_line("%s: view %d: cannot render this camera", c->map, v);
        return -1;
    }
    if (ew_write_frame_png(rd, path, &err) < 0) {
        error_line("%s", err.msg[0] ? err.msg : "cannot write the heat map");
        return -1;
    }
    return 0;
}

/* Every method at w x h into rows[o->nmethods]; 0 or 1 (error printed). */
static int lab_size(const lab_ctx *c, int w, int h, hsr_row *rows) {
    const hsr_opts *o = c->o;
    ew_error err = { "" };
    ew_renderer *rd = ew_renderer_create(&(ew_renderer_desc){
            .world = c->a->world, .palette = c->a->palette, .colormap = c->a->colormap,
            .width = w, .height = h, .threads = 1, .color = (ew_color_mode)o->draw.color }, &err);
    if (!rd) {
        error_line("%s", err.msg[0] ? err.msg : "cannot create the renderer");
        return 1;
    }
    int threads = ew_set_threads(rd, o->threads);
    size_t n = (size_t)c->nviews * (size_t)o->repeat, px = (size_t)w * (size_t)h;
    double *frames = malloc(n * sizeof *frames);
    ew_stats *stats = calloc(n, sizeof *stats);
    int *ref_ids = malloc(px * sizeof *ref_ids);
    int rc = 1;
    if (threads < 0 || !frames || !stats || !ref_ids) {
        error_line("hsr: out of memory at %dx%d", w, h);
        goto done;
    }
    draw_opts_apply(&o->draw, rd, c->scene);

    /* the timing: each method in turn through the benchmark protocol */
    for (int m = 0; m < o->nmethods; m++) {
        hsr_row *r = &rows[m];
        memset(r, 0, sizeof *r);
        map_basename(c->map, r->map, sizeof r->map);
        r->w = w, r->h = h, r->method = o->methods[m], r->views = c->nviews, r->passes = o->repeat;
        r->threads = threads, r->stress = c->stress, r->entities = c->scene != NULL && c->stress < 0;
        if (ew_set_hsr(rd, (ew_hsr_method)r->method) < 0) {
            error_line("hsr: method %s not available", ew_hsr_name((ew_hsr_method)r->method));
            goto done;
        }
        progress_ctx pc = { r->map, ew_hsr_name((ew_hsr_method)r->method), w, h, o->repeat, c->nviews, 0 };
        bench_hooks hooks = { progress_before, NULL, &pc };
        int bad = bench_run_views(rd, c->views, c->nviews, o->repeat, frames, stats, NULL, &hooks);
        if (bad) {
            progress_clear();
            error_line("%s: view %d: cannot render this camera", c->map, -bad - 1);
            goto done;
        }
        summarize_timing(r, frames, stats);
        r->agree_mean = 0, r->agree_min = 101;
    }

    /* agreement (and heat maps), untimed: the reference path's faces once per
     * view, then each method's */
    for (int v = 0; v < c->nviews; v++) {
        progress_ctx pc = { c->map, "agreement", w, h, 1, c->nviews, 0 };
        progress_before(&pc, 1, v);
        /* the polygons in view, as the front end hands them to the edge list
         * (whatever each method itself counts) */
        ew_stats st;
        ew_set_hsr(rd, EW_HSR_EDGE);
        if (ew_render(rd, &c->views[v], &st) == 0)
            for (int m = 0; m < o->nmethods; m++)
                rows[m].in_view += (double)(st.surfaces + st.faces_occluded) / c->nviews;
        if (ew_render_reference(rd, &c->views[v], NULL, ref_ids, &err) < 0) {
            progress_clear();
            error_line("%s: view %d: %s", c->map, v, err.msg[0] ? err.msg : "cannot render the reference");
            goto done;
        }
        for (int m = 0; m < o->nmethods; m++) {
            hsr_row *r = &rows[m];
            ew_set_hsr(rd, (ew_hsr_method)r->method);
            ew_enable_face_ids(rd, 1);
            int ok = ew_render(rd, &c->views[v], NULL);
            const int *ids = ew_frame_face_ids(rd);
            ew_enable_face_ids(rd, 0);
            if (ok < 0 || !ids) {
                progress_clear();
                error_line("%s: view %d: cannot render this camera", c->map, v);
                goto done;
            }
            size_t same = 0;
            for (size_t i = 0; i < px; i++) same += ids[i] == ref_ids[i];
            double pct = 100.0 * (double)same / (double)px;
            r->agree_mean += pct / c->nviews;
            if (pct < r->agree_min) r->agree_min = pct, r->agree_min_view = v;
            if (o->heatmap && write_heatmap(c, rd, w, h, v, r->method) < 0) {
                progress_clear();
                goto done;
            }
        }
    }
    progress_clear();
    rc = 0;
done:
    free(frames);
    free(stats);
    free(ref_ids);
    ew_renderer_destroy(rd);
    return rc;
}

/* ---- output: JSON lines and the table ------------------------------------------ */

static void print_row_json(FILE *f, const hsr_row *r, const draw_opts *d) {
    draw_opts dm = *d;
    dm.hsr = r->method;
    dm.no_entities = !r->entities;
    fputs("{\"map\":", f);
    json_string(f, r->map);
    fprintf(f, ",\"width\":%d,\"height\":%d,\"method\":", r->w, r->h);
    json_string(f, ew_hsr_name((ew_hsr_method)r->method));
    if (r->stress >= 0) fprintf(f, ",\"stress\":%d", r->stress);
    fprintf(f, ",\"threads\":%d,\"views\":%d,\"passes\":%d", r->threads, r->views, r->passes);
    draw_opts_json(f, &dm);
    const char *names[] = { "median_ms", "mean_ms", "worst_ms" };
    const double vals[] = { r->median, r->mean, r->worst };
    for (int i = 0; i < 3; i++) {
        fprintf(f, ",\"%s\":", names[i]);
        json_number(f, vals[i]);
    }
    fprintf(f, ",\"worst_view\":%d,\"overdraw_mean\":", r->worst_view);
    json_number(f, r->overdraw_mean);
    fputs(",\"overdraw_max\":", f);
    json_number(f, r->overdraw_max);
    fputs(",\"agreement_mean_pct\":", f);
    json_number(f, r->agree_mean);
    fputs(",\"agreement_min_pct\":", f);
    json_number(f, r->agree_min);
    fprintf(f, ",\"agreement_min_view\":%d,\"polygons\":", r->agree_min_view);
    json_number(f, r->polygons);
    fprintf(f, ",\"polygons_max\":%.0f,\"polygons_in_view\":", r->polygons_max);
    json_number(f, r->in_view);
    fputs(",\"dropped\":", f);
    json_number(f, r->dropped);
    fprintf(f, ",\"hsr_bytes_max\":%.0f,\"hsr_bytes_mean\":", r->mem_max);
    json_number(f, r->mem_mean);
    fputs(",\"counters\":{", f);
    int first = 1;
    for (int c = 0; c < EW_HSR_COUNTERS; c++) {
        const char *name = ew_hsr_counter_name((ew_hsr_method)r->method, c);
        if (!name) continue;
        fputs(first ? "" : ",", f);
        first = 0;
        json_string(f, name);
        fputc(':', f);
        json_number(f, r->counters[c]);
    }
    fputs("}}\n", f);
}

static void print_table_header(void) {
    printf("%-20s %9s %-10s %5s %9s %9s %4s %8s %8s %7s %7s %8s %9s  %s\n", "map", "size", "method", "views",
           "median", "worst", "@", "overdraw", "od_max", "agree%", "min%", "polygons", "memory", "counters");
}

static void print_table_row(const hsr_row *r) {
    char size[24], mem[32];
    snprintf(size, sizeof size, "%dx%d", r->w, r->h);
    if (r->mem_max < 1024 * 1024)
        snprintf(mem, sizeof mem, "%.1fK", r->mem_max / 1024);
    else
        snprintf(mem, sizeof mem, "%.1fM", r->mem_max / (1024 * 1024));
    printf("%-20.20s %9s %-10s %5d %9.3f %9.3f %4d %8.3f %8.3f %7.2f %7.2f %8.0f %9s ", r->map, size,
           ew_hsr_name((ew_hsr_method)r->method), r->views, r->median, r->worst, r->worst_view,
           r->overdraw_mean, r->overdraw_max, r->agree_mean, r->agree_min, r->in_view, mem);
    for (int c = 0; c < EW_HSR_COUNTERS; c++) {
        const char *name = ew_hsr_counter_name((ew_hsr_method)r->method, c);
        if (name) printf(" %s=%.0f", name, r->counters[c]);
    }
    putchar('\n');
}

/* --stress: time per method against the polygons in view, per size. */
static void print_stress_table(const hsr_opts *o, const hsr_row *rows, int nrows) {
    for (int s = 0; s < o->nsizes; s++) {
        printf("\nstress %dx%d: median ms per method against the polygons in view\n", o->sizes[s][0],
               o->sizes[s][1]);
        printf("%8s %9s", "detail", "polygons");
        for (int m = 0; m < o->nmethods; m++) printf(" %12s", ew_hsr_name((ew_hsr_method)o->methods[m]));
        for (int m = 0; m < o->nmethods; m++) {
            char head[32];
            snprintf(head, sizeof head, "%s us/poly", ew_hsr_name((ew_hsr_method)o->methods[m]));
            printf(" %16s", head);
        }
        putchar('\n');
        for (int d = 0; d < o->nstress; d++) {
            const hsr_row *first = NULL;
            double ms[EW_HSR_COUNT];
            for (int i = 0; i < nrows; i++) {
                const hsr_row *r = &rows[i];
                if (r->stress != o->stress[d] || r->w != o->sizes[s][0] || r->h != o->sizes[s][1]) continue;
                if (!first) first = r;
                for (int m = 0; m < o->nmethods; m++)
                    if (o->methods[m] == r->method) ms[m] = r->median;
            }
            if (!first) continue;
            printf("%8d %9.0f", o->stress[d], first->in_view);
            for (int m = 0; m < o->nmethods; m++) printf(" %12.3f", ms[m]);
            for (int m = 0; m < o->nmethods; m++)
                printf(" %16.3f", first->in_view > 0 ? ms[m] * 1e3 / first->in_view : 0.0);
            putchar('\n');
        }
    }
}

/* ---- the SVG charts, drawn here as text ----------------------------------------- */

static void xml_text(FILE *f, const char *s) {
    for (; *s; s++) {
        if (*s == '&') fputs("&amp;", f);
        else if (*s == '<') fputs("&lt;", f);
        else if (*s == '>') fputs("&gt;", f);
        else if (*s == '"') fputs("&quot;", f);
        else if ((unsigned char)*s >= ' ') fputc(*s, f);
    }
}

/* A colour per method (by its enum value, so a method keeps its colour
 * whatever --methods picks). */
static const char *method_colour(int m) {
    static const char *const colours[] = { "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                           "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f" };
    return colours[m % (int)(sizeof colours / sizeof *colours)];
}

/* Ticks for a linear axis from 0 to about top: the step (1, 2 or 5 x 10^k)
 * giving 4 to 10 ticks; *top rounded up to a whole step. */
static double nice_step(double *top) {
    if (!(*top > 0)) *top = 1;
    double e = pow(10, floor(log10(*top / 5))), step = e;
    static const double mult[] = { 1, 2, 5, 10 };
    for (int i = 0; i < 4; i++) {
        step = e * mult[i];
        if (*top / step <= 8) break;
    }
    *top = ceil(*top / step - 1e-9) * step;
    return step;
}

static void svg_legend(FILE *f, const hsr_opts *o, double x, double y) {
    fprintf(f, "<g class=\"legend\">\n");
    for (int m = 0; m < o->nmethods; m++) {
        int id = o->methods[m];
        fprintf(f, "<rect class=\"swatch\" x=\"%.1f\" y=\"%.1f\" width=\"12\" height=\"12\" fill=\"%s\"/>\n", x,
                y + m * 18.0, method_colour(id));
        fprintf(f, "<text x=\"%.1f\" y=\"%.1f\">", x + 18, y + m * 18.0 + 10);
        xml_text(f, ew_hsr_name((ew_hsr_method)id));
        fputs("</text>\n", f);
    }
    fputs("</g>\n", f);
}

/* Bars: per map x size a group, per method a bar of the median time (log
 * scale, a tick at the worst frame) and a bar of the mean overdraw. */
static int write_bar_svg(FILE *f, const hsr_opts *o, const hsr_row *rows, int nrows) {
    const double barw = 14, gap = 24, left = 70, top = 40, ph = 220, pgap = 90, legendw = 150;
    int ngroups = o->nmethods ? nrows / o->nmethods : 0;
    double groupw = o->nmethods * barw + gap;
    double width = left + ngroups * groupw + legendw, height = top + 2 * ph + pgap + 80;
    if (width < 640) width = 640;  /* room for the title */
    /* time axis: decades covering every median and worst frame */
    double lo = INFINITY, hi = 0, odtop = 1;
    for (int i = 0; i < nrows; i++) {
        if (rows[i].median > 0 && rows[i].median < lo) lo = rows[i].median;
        if (rows[i].worst > hi) hi = rows[i].worst;
        if (rows[i].overdraw_mean > odtop) odtop = rows[i].overdraw_mean;
    }
    if (!(lo < INFINITY)) lo = 0.1;
    if (!(hi > lo)) hi = lo * 10;
    int d0 = (int)floor(log10(lo)), d1 = (int)ceil(log10(hi));
    if (d1 <= d0) d1 = d0 + 1;
    double odstep = nice_step(&odtop);
    double y_time0 = top + ph, y_od0 = top + 2 * ph + pgap;

    fprintf(f, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
               "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" "
               "viewBox=\"0 0 %.0f %.0f\" font-family=\"sans-serif\" font-size=\"11\">\n",
            width, height, width, height);
    fprintf(f, "<rect x=\"0\" y=\"0\" width=\"%.0f\" height=\"%.0f\" fill=\"white\"/>\n", width, height);
    fprintf(f, "<text x=\"%.1f\" y=\"20\" font-size=\"14\">edgewise hsr: median frame time (worst as a tick) "
               "and overdraw per method</text>\n", left);
    /* axes, grid and labels */
    fprintf(f, "<g class=\"axes\" stroke=\"#000\">\n");
    fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n", left, top, left, y_time0);
    fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n", left, y_time0, left + ngroups * groupw, y_time0);
    fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n", left, y_od0 - ph, left, y_od0);
    fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n", left, y_od0, left + ngroups * groupw, y_od0);
    fputs("</g>\n<g class=\"ticks\">\n", f);
    for (int d = d0; d <= d1; d++) {
        double y = y_time0 - ph * (d - d0) / (d1 - d0);
        fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ccc\"/>\n", left, y,
                left + ngroups * groupw, y);
        fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">%g</text>\n", left - 4, y + 4, pow(10, d));
    }
    for (double v = 0; v <= odtop + 1e-9; v += odstep) {
        double y = y_od0 - ph * v / odtop;
        fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ccc\"/>\n", left, y,
                left + ngroups * groupw, y);
        fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">%g</text>\n", left - 4, y + 4, v);
    }
    fputs("</g>\n", f);
    fprintf(f, "<text x=\"16\" y=\"%.1f\" transform=\"rotate(-90 16 %.1f)\" text-anchor=\"middle\">median ms "
               "(log scale)</text>\n", top + ph / 2, top + ph / 2);
    fprintf(f, "<text x=\"16\" y=\"%.1f\" transform=\"rotate(-90 16 %.1f)\" text-anchor=\"middle\">overdraw "
               "(writes per pixel)</text>\n", y_od0 - ph / 2, y_od0 - ph / 2);
    /* the bars */
    fputs("<g class=\"bars\">\n", f);
    for (int g = 0; g < ngroups; g++) {
        const hsr_row *r0 = &rows[g * o->nmethods];
        double gx = left + gap / 2 + g * groupw;
        char size[24];
        snprintf(size, sizeof size, "%dx%d", r0->w, r0->h);
        for (int panel = 0; panel < 2; panel++) {
            fprintf(f, "<text class=\"group\" x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">",
                    gx + o->nmethods * barw / 2, (panel ? y_od0 : y_time0) + 14);
            xml_text(f, r0->map);
            fprintf(f, "</text>\n<text class=\"group\" x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%s</text>\n",
                    gx + o->nmethods * barw / 2, (panel ? y_od0 : y_time0) + 27, size);
        }
        for (int m = 0; m < o->nmethods; m++) {
            const hsr_row *r = &rows[g * o->nmethods + m];
            const char *name = ew_hsr_name((ew_hsr_method)r->method);
            double x = gx + m * barw;
            double lt = r->median > 0 ? (log10(r->median) - d0) / (d1 - d0) : 0;
            double bh = ph * (lt < 0 ? 0 : lt > 1 ? 1 : lt);
            fprintf(f, "<rect class=\"bar\" data-kind=\"time\" data-map=\"");
            xml_text(f, r->map);
            fprintf(f, "\" data-size=\"%s\" data-method=\"%s\" data-value=\"%.6g\" x=\"%.1f\" y=\"%.1f\" "
                       "width=\"%.1f\" height=\"%.1f\" fill=\"%s\"><title>%s %s %s: median %.3f ms</title></rect>\n",
                    size, name, r->median, x, y_time0 - bh, barw - 2, bh, method_colour(r->method), r->map, size,
                    name, r->median);
            double lw = r->worst > 0 ? (log10(r->worst) - d0) / (d1 - d0) : 0;
            double wy = y_time0 - ph * (lw < 0 ? 0 : lw > 1 ? 1 : lw);
            fprintf(f, "<line class=\"worst\" data-value=\"%.6g\" x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" "
                       "stroke=\"#000\" stroke-width=\"2\"/>\n", r->worst, x, wy, x + barw - 2, wy);
            double oh = ph * r->overdraw_mean / odtop;
            fprintf(f, "<rect class=\"bar\" data-kind=\"overdraw\" data-map=\"");
            xml_text(f, r->map);
            fprintf(f, "\" data-size=\"%s\" data-method=\"%s\" data-value=\"%.6g\" x=\"%.1f\" y=\"%.1f\" "
                       "width=\"%.1f\" height=\"%.1f\" fill=\"%s\"><title>%s %s %s: overdraw %.3f</title></rect>\n",
                    size, name, r->overdraw_mean, x, y_od0 - oh, barw - 2, oh, method_colour(r->method), r->map,
                    size, name, r->overdraw_mean);
        }
    }
    fputs("</g>\n", f);
    svg_legend(f, o, left + ngroups * groupw + 20, top);
    fputs("</svg>\n", f);
    return 0;
}

/* --stress: per size a panel of median ms against polygons, a line per method. */
static int write_stress_svg(FILE *f, const hsr_opts *o, const hsr_row *rows, int nrows) {
    const double left = 70, top = 52, pw = 520, ph = 260, pgap = 80, legendw = 150;
    double width = left + pw + legendw, height = top + o->nsizes * (ph + pgap) + 20;
    fprintf(f, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
               "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" "
               "viewBox=\"0 0 %.0f %.0f\" font-family=\"sans-serif\" font-size=\"11\">\n",
            width, height, width, height);
    fprintf(f, "<rect x=\"0\" y=\"0\" width=\"%.0f\" height=\"%.0f\" fill=\"white\"/>\n", width, height);
    fprintf(f, "<text x=\"%.1f\" y=\"20\" font-size=\"14\">edgewise hsr --stress: median frame time against "
               "polygons in view</text>\n", left);
    for (int s = 0; s < o->nsizes; s++) {
        int w = o->sizes[s][0], h = o->sizes[s][1];
        double y0 = top + s * (ph + pgap) + ph, xtop = 1, ytop = 0;
        for (int i = 0; i < nrows; i++)
            if (rows[i].w == w && rows[i].h == h) {
                if (rows[i].in_view > xtop) xtop = rows[i].in_view;
                if (rows[i].median > ytop) ytop = rows[i].median;
            }
        double xstep = nice_step(&xtop), ystep = nice_step(&ytop);
        fprintf(f, "<g class=\"panel\" data-size=\"%dx%d\">\n", w, h);
        fprintf(f, "<text x=\"%.1f\" y=\"%.1f\">%dx%d</text>\n", left + 4, y0 - ph - 6, w, h);
        fprintf(f, "<g class=\"axes\" stroke=\"#000\">\n<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n"
                   "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n</g>\n",
                left, y0 - ph, left, y0, left, y0, left + pw, y0);
        fputs("<g class=\"ticks\">\n", f);
        for (double v = 0; v <= xtop + 1e-9; v += xstep) {
            double x = left + pw * v / xtop;
            fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ccc\"/>\n", x, y0 - ph, x, y0);
            fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%g</text>\n", x, y0 + 14, v);
        }
        for (double v = 0; v <= ytop + 1e-9; v += ystep) {
            double y = y0 - ph * v / ytop;
            fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ccc\"/>\n", left, y, left + pw, y);
            fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">%g</text>\n", left - 4, y + 4, v);
        }
        fputs("</g>\n", f);
        fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">polygons in view (mean surfaces a frame)</text>\n",
                left + pw / 2, y0 + 32);
        fprintf(f, "<text x=\"16\" y=\"%.1f\" transform=\"rotate(-90 16 %.1f)\" text-anchor=\"middle\">median ms"
                   "</text>\n", y0 - ph / 2, y0 - ph / 2);
        /* the points left to right, whatever order --stress listed them in */
        int order[MAX_STRESS * MAX_SIZES * EW_HSR_COUNT], npts = 0;
        for (int i = 0; i < nrows && npts < (int)(sizeof order / sizeof *order); i++)
            if (rows[i].w == w && rows[i].h == h) order[npts++] = i;
        for (int i = 1; i < npts; i++)
            for (int k = i; k > 0 && rows[order[k]].in_view < rows[order[k - 1]].in_view; k--) {
                int t = order[k];
                order[k] = order[k - 1], order[k - 1] = t;
            }
        for (int m = 0; m < o->nmethods; m++) {
            const char *name = ew_hsr_name((ew_hsr_method)o->methods[m]);
            fprintf(f, "<polyline class=\"series\" data-method=\"%s\" data-size=\"%dx%d\" fill=\"none\" "
                       "stroke=\"%s\" stroke-width=\"2\" points=\"", name, w, h, method_colour(o->methods[m]));
            for (int i = 0; i < npts; i++) {
                const hsr_row *r = &rows[order[i]];
                if (r->method == o->methods[m])
                    fprintf(f, "%.1f,%.1f ", left + pw * r->in_view / xtop, y0 - ph * r->median / ytop);
            }
            fputs("\"/>\n", f);
            for (int i = 0; i < nrows; i++) {
                const hsr_row *r = &rows[i];
                if (r->w != w || r->h != h || r->method != o->methods[m]) continue;
                fprintf(f, "<circle class=\"point\" data-method=\"%s\" data-size=\"%dx%d\" data-detail=\"%d\" "
                           "data-polygons=\"%.6g\" data-value=\"%.6g\" cx=\"%.1f\" cy=\"%.1f\" r=\"3\" fill=\"%s\">"
                           "<title>%s: %.0f polygons, %.3f ms</title></circle>\n",
                        name, w, h, r->stress, r->in_view, r->median, left + pw * r->in_view / xtop,
                        y0 - ph * r->median / ytop, method_colour(r->method), name, r->in_view, r->median);
            }
        }
        fputs("</g>\n", f);
    }
    svg_legend(f, o, left + pw + 20, top);
    fputs("</svg>\n", f);
    return 0;
}

static int write_svg(const hsr_opts *o, const hsr_row *rows, int nrows) {
    FILE *f = fopen(o->svg, "w");
    if (!f) {
        error_line("%s: %s", o->svg, strerror(errno));
        return 1;
    }
    if (o->nstress)
        write_stress_svg(f, o, rows, nrows);
    else
        write_bar_svg(f, o, rows, nrows);
    if (ferror(f) | (fclose(f) != 0)) {
        error_line("%s: %s", o->svg, strerror(errno));
        return 1;
    }
    return 0;
}

/* ---- the command ------------------------------------------------------------------ */

int cmd_hsr(int argc, char **argv) {
    hsr_opts o;
    memset(&o, 0, sizeof o);
    draw_opts_init(&o.draw);
    int pr = hsr_parse(argc, argv, &o);
    if (pr)
        return pr < 0 ? HSR_EXIT_USAGE : 0;
    if (o.heatmap && check_heatmap_dir(o.heatmap) < 0)
        return 1;

    int to_stdout = o.json && strcmp(o.json, "-") == 0;
    FILE *json = NULL;
    if (to_stdout) {
        json = stdout;
    } else if (o.json && !(json = fopen(o.json, "w"))) {
        error_line("%s: %s", o.json, strerror(errno));
        return 1;
    }
    progress_on = isatty(STDERR_FILENO);
    size_t cap = (size_t)o.nmaps * (size_t)o.nsizes * (size_t)o.nmethods;
    hsr_row *rows = calloc(cap ? cap : 1, sizeof *rows);
    int nrows = 0, rc = rows ? 0 : 1;
    if (!rows)
        error_line("hsr: out of memory");
    if (!rc && !to_stdout)
        print_table_header();
    for (int m = 0; m < o.nmaps && !rc; m++) {
        int stress;
        ew_assets *a = hsr_load(&o, o.maps[m], &stress);
        if (!a) {
            rc = 1;
            break;
        }
        ew_camera views[EW_MAX_VIEWS];
        int nviews = ew_benchmark_views(a->world, views);
        ew_scene *sc = NULL;
        if (nviews == 0) {
            error_line("%s: no views (no info_player* or info_intermission entity)", o.maps[m]);
            rc = 1;
        } else if (draw_opts_scene(&o.draw, a, o.maps[m], o.data, 0, o.quiet, &sc) < 0) {
            rc = 1;
        }
        o.draw.map_rgb = a ? ew_world_has_rgb_light(a->world) : -1;  /* "lit": coloured light actually drawn */
        lab_ctx c = { &o, o.maps[m], a, sc, views, nviews, stress };
        for (int s = 0; s < o.nsizes && !rc; s++) {
            hsr_row *r = &rows[nrows];
            rc = lab_size(&c, o.sizes[s][0], o.sizes[s][1], r);
            if (rc) break;
            for (int k = 0; k < o.nmethods; k++) {
                if (json) print_row_json(json, &r[k], &o.draw);
                if (!to_stdout) print_table_row(&r[k]);
            }
            if (json) fflush(json);
            fflush(stdout);
            nrows += o.nmethods;
        }
        ew_scene_destroy(sc);
        ew_assets_destroy(a);
    }
    if (!rc && o.nstress && !to_stdout)
        print_stress_table(&o, rows, nrows);
    if (!rc && o.svg)
        rc = write_svg(&o, rows, nrows);
    free(rows);
    if (json && json != stdout && fclose(json) != 0 && rc == 0) {
        error_line("%s: %s", o.json, strerror(errno));
        rc = 1;
    }
    if (fflush(stdout) != 0 && rc == 0) {
        error_line("stdout: %s", strerror(errno));
        rc = 1;
    }
    return rc;
}
