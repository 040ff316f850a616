/*
 * edgewise soak MAP [--data DIR] --frames N [--size WxH] [--seed S] [--threads N]
 *               [--quiet] [drawing options, as render's]
 *
 * Renders N frames, alternating between the view set and deterministic
 * random cameras (a random open leaf of the world, the camera at the
 * centre of its bounds nudged clear of every plane, random yaw and
 * pitch), and checks every frame's
 * counters against what the renderer promises:
 *   - overdraw exactly 1 (no pixel written twice);
 *   - every pixel written, unless the camera is in solid (or sky) or a
 *     budget dropped something; a pixel left unwritten is an anomaly when
 *     the reference path covers it (a crack in the edge list), else the
 *     map leaves that view open and the frame is listed under open_views;
 *   - nothing dropped unless a budget (surfaces, edges, spans) is full:
 *     drops with a full budget are reported separately, not as anomalies;
 *   - no more fogged pixels than the frame has (each pixel fogged once),
 *     for every method.
 * The counters are the edge list's world spans: see-through surfaces
 * (fences, translucent liquids and brush entities) are drawn after them and
 * counted apart, so with them on a pixel seen only through one can be left
 * unwritten by the spans; the crack test then compares with the reference
 * path, which diverts the same surfaces.  With --hsr reference there are no
 * spans, and painter, zbuffer and raycast do not promise one write per
 * pixel: only the pixel count, the fog count and the drops are checked ("checks" in the
 * JSON line says which ran).
 * Prints one JSON line at the end: frames per second, anomalies (frame,
 * camera, what), budget drops, open views and peak memory (ru_maxrss).  Exit 1 if any
 * anomaly, 2 for bad arguments.
 */
#define _POSIX_C_SOURCE 200809L
#include "cli.h"
#include "edgewise.h"
#include "edgewise_lab.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#define MAX_FRAMES 1000000000L
#define MAX_LISTED 20  /* anomalies and drops listed in full in the JSON */

static const char soak_usage[] =
    "usage: edgewise soak MAP [--data DIR] --frames N [--size WxH] [--seed S] [--threads N]\n"
    "                         [--quiet] [what is drawn]\n"
    "\n"
    "Renders N frames cycling through the view set and random cameras in open\n"
    "leaves of the map, checks each frame's counters (overdraw exactly 1, every\n"
    "pixel written unless the camera is in solid, nothing dropped unless a\n"
    "budget is full) and prints one JSON line: frames/s, anomalies, budget\n"
    "drops, peak memory.  Exit status 1 if any frame broke a promise.\n"
    "\n"
    CLI_OPTIONS_HERE
    "\n"
    "what is drawn (as in edgewise render):\n";

typedef struct soak_opts {
    const char *map, *data;
    long        frames;
    int         width, height, threads;
    uint64_t    seed;
    int         quiet;
    draw_opts   draw;   /* what is drawn (cli/draw_options.c) */
} soak_opts;

/* Returns 0, 1 after --help, or -1 (error printed). */
static int parse(int argc, char **argv, soak_opts *o) {
    int have_frames = 0;
    const char *map[1];
    cli_args args;
    cli_args_init(&args, CLI_SOAK, argc, argv, map, 1, &o->draw, soak_usage, NULL);
    while (cli_next_arg(&args)) {
        const cli_option *opt = args.opt;
        const char *v = args.value;
        const char *names[] = {"--data", "--frames", "--size", "--seed", "--threads"};
        int which = 0;
        for (int k = 0; k < 5; k++)
            if (cli_is(opt, names[k])) which = k;
        long l;
        switch (which) {
        case 0:
            if (!*v) {
                error_line("--data: empty directory name");
                return -1;
            }
            o->data = v;
            break;
        case 1:
            if (parse_long(v, &l) < 0 || l < 1 || l > MAX_FRAMES) {
                error_line("--frames %s: expected a whole number from 1 to %ld", v, MAX_FRAMES);
                return -1;
            }
            o->frames = l;
            have_frames = 1;
            break;
        case 2:
            if (parse_size(v, &o->width, &o->height) < 0) return -1;
            break;
        case 3: {
            char *end;
            errno = 0;
            unsigned long long s = strtoull(v, &end, 10);
            if (!*v || *v < '0' || *v > '9' || *end || errno == ERANGE) {  /* no sign, no blank */
                error_line("--seed %s: expected a whole number from 0 to %llu", v, ULLONG_MAX);
                return -1;
            }
            o->seed = (uint64_t)s;
            break;
        }
        case 4:
            if (parse_threads(v, &o->threads) < 0)
                return -1;
            break;
        }
    }
    if (args.stop)
        return args.stop;
    o->map = args.nmaps ? map[0] : NULL, o->quiet = args.quiet;
    if (!o->map) {
        error_line("soak: missing MAP (a .bsp path, a map name with --data, or 'builtin')");
        return -1;
    }
    if (!have_frames) {
        error_line("soak: missing --frames N");
        return -1;
    }
    return 0;
}

/* splitmix64: small, and the same sequence on every platform. */
static uint64_t next_u64(uint64_t *s) {
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}
static double next_unit(uint64_t *s) { return (double)(next_u64(s) >> 11) / 9007199254740992.0; }

/* A camera there sees the inside of the world: open contents (sky
 * volumes are closed to the player as solid is). */
static int open_contents(int c) { return c != EW_CONTENTS_SOLID && c != EW_CONTENTS_SKY; }

/* Open leaves of the world tree (model 0), not of brush models. */
static int *world_open_leaves(const ew_world *w, int *n) {
    *n = ew_world_open_leaves(w, NULL);
    int *list = malloc(sizeof(int) * (size_t)(*n > 0 ? *n : 1));
    if (!list) return NULL;
    ew_world_open_leaves(w, list);
    return list;
}

/* Where the eye may go.  Leaf bounds sit on the map grid, so their centres
 * often lie exactly in some face's plane or right against a wall.  An eye
 * in a face's plane sees it edge-on: rays along a wall's plane start in
 * the solid behind it, and the faces either side of an edge-on face meet
 * on one screen line computed from two different edges, which float
 * rounding can leave a pixel apart.  An eye a hair from a wall is in the
 * same trouble (the player's eye never comes within 16 units of one).
 * So the centre is nudged by up to JITTER units, and the eye must be at
 * least WALL_CLEARANCE inside its leaf (from every plane above it in the
 * tree, which are the planes of every face that bounds it) and clear of
 * every other plane by far more than float error. */
#define WALL_CLEARANCE 1.0f
#define PLANE_CLEARANCE (1.0f / 256)
#define JITTER 0.5
#define PLACE_TRIES 64

static int eye_clear(const ew_world *w, int leaf, const float p[3]) {
    return ew_world_leaf_clearance(w, leaf, p) >= WALL_CLEARANCE &&
           ew_world_plane_clearance(w, p) >= PLANE_CLEARANCE;
}

/* An eye near the centre of a random open leaf, in that leaf and clear of
 * its walls and of every plane; 0, or -1 if PLACE_TRIES leaves all failed. */
static int random_eye(const ew_world *w, const int *open_leaves, int nopen, uint64_t *rng,
                      float eye[3]) {
    for (int t = 0; t < PLACE_TRIES; t++) {
        int li = open_leaves[next_u64(rng) % (uint64_t)nopen];
        float mins[3], maxs[3];
        ew_world_leaf_bounds(w, li, mins, maxs);
        for (int k = 0; k < 3; k++)
            eye[k] = (mins[k] + maxs[k]) * 0.5f + (float)((next_unit(rng) * 2 - 1) * JITTER);
        if (ew_world_point_leaf(w, eye) == li && eye_clear(w, li, eye)) return 0;
    }
    return -1;
}

/* Pixels the edge list left unwritten although the reference path (the
 * same visible faces, filled by brute force with a z-buffer) covers them:
 * a crack in the edge list.  Pixels neither writes are a view the map
 * itself leaves open (a void pocket, a leak, a PVS that hides the walls).
 * Re-renders the frame; -1 when out of memory. */
static long cracks(ew_renderer *r, const ew_camera *cam, long *open_px) {
    size_t n = (size_t)ew_frame_width(r) * (size_t)ew_frame_height(r);
    int *edge_ids = malloc(sizeof(int) * n), *ref_ids = malloc(sizeof(int) * n);
    long missed = -1;
    ew_error err;
    ew_stats st;
    if (edge_ids && ref_ids) {
        ew_enable_face_ids(r, 1);
        if (ew_render(r, cam, &st) == 0 && ew_frame_face_ids(r)) {
            memcpy(edge_ids, ew_frame_face_ids(r), sizeof(int) * n);
            if (ew_render_reference(r, cam, NULL, ref_ids, &err) == 0) {
                missed = *open_px = 0;
                for (size_t i = 0; i < n; i++) {
                    missed += edge_ids[i] < 0 && ref_ids[i] >= 0;
                    *open_px += edge_ids[i] < 0 && ref_ids[i] < 0;
                }
            }
        }
        ew_enable_face_ids(r, 0);
    }
    free(edge_ids), free(ref_ids);
    return missed;
}

typedef struct finding {
    long      frame;
    ew_camera cam;
    char      what[160];
} finding;

typedef struct findings {
    finding list[MAX_LISTED];
    long    count;
} findings;

static void add_finding(findings *f, long frame, const ew_camera *cam, const char *fmt, ...)
    EW_CLI_PRINTF(4, 5);
static void add_finding(findings *f, long frame, const ew_camera *cam, const char *fmt, ...) {
    if (f->count < MAX_LISTED) {
        finding *x = &f->list[f->count];
        x->frame = frame;
        x->cam = *cam;
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(x->what, sizeof x->what, fmt, ap);
        va_end(ap);
    }
    f->count++;
}

/* Cameras in full float precision, so a reported frame can be rendered
 * again exactly (edgewise render --pos/--angles/--time). */
static void print_camera(FILE *out, const ew_camera *c) {
    fputs("{\"origin\":[", out);
    for (int k = 0; k < 3; k++) fprintf(out, "%.9g%s", c->origin[k], k < 2 ? "," : "],\"angles\":[");
    for (int k = 0; k < 3; k++) fprintf(out, "%.9g%s", c->angles[k], k < 2 ? "," : "],\"time\":");
    fprintf(out, "%.17g}", c->time);
}

static void print_findings(FILE *out, const char *key, const findings *f) {
    fprintf(out, ",\"%s\":%ld,\"%s_list\":[", key, f->count, key);
    long shown = f->count < MAX_LISTED ? f->count : MAX_LISTED;
    for (long i = 0; i < shown; i++) {
        fprintf(out, "%s{\"frame\":%ld,\"camera\":", i ? "," : "", f->list[i].frame);
        print_camera(out, &f->list[i].cam);
        fputs(",\"what\":", out);
        json_string(out, f->list[i].what);
        fputc('}', out);
    }
    fputc(']', out);
}


int cmd_soak(int argc, char **argv) {
    soak_opts o = {.width = 320, .height = 200, .threads = 1, .seed = 1};
    draw_opts_init(&o.draw);
    int pr = parse(argc, argv, &o);
    if (pr != 0) return pr > 0 ? 0 : 2;

    ew_error err = {""};
    ew_assets *a = load_map(o.map, o.data, o.quiet);
    int rc = 0;
    if (!a)
        return 1;
    o.draw.map_rgb = ew_world_has_rgb_light(a->world);  /* "lit": coloured light actually drawn */
    ew_scene *scene = NULL;
    if (draw_opts_scene(&o.draw, a, o.map, o.data, 0, o.quiet, &scene) < 0) {
        ew_assets_destroy(a);
        return 1;
    }
    const ew_world *w = a->world;
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){ .world = w, .palette = a->palette,
            .colormap = a->colormap, .width = o.width, .height = o.height, .threads = 1,
            .color = (ew_color_mode)o.draw.color }, &err);
    int nopen = 0, *open_leaves = world_open_leaves(w, &nopen);
    if (!r || !open_leaves || ew_set_threads(r, o.threads) < 0) {
        error_line("%s", r ? "soak: out of memory" : err.msg);
        ew_renderer_destroy(r);
        ew_scene_destroy(scene);
        free(open_leaves);
        ew_assets_destroy(a);
        return 1;
    }
    draw_opts_apply(&o.draw, r, scene);
    /* The methods that write every world pixel exactly once are held to it
     * (the raycast too: it approximates which surface, not how often); the
     * reference draws no spans, painter's order and the z-buffer overdraw
     * by design (docs/hsr.md). */
    int spans_checked = o.draw.hsr == EW_HSR_EDGE || o.draw.hsr == EW_HSR_EDGE_Z || o.draw.hsr == EW_HSR_SPANS ||
                        o.draw.hsr == EW_HSR_DRAWBUFFER || o.draw.hsr == EW_HSR_BEAMTREE ||
                        o.draw.hsr == EW_HSR_RAYCAST;
    ew_camera views[EW_MAX_VIEWS];
    int nviews = ew_benchmark_views(w, views);
    long seethrough_frames = 0, underwater_frames = 0, fog_frames = 0;
    double fence_px = 0, translucent_px = 0, fog_px = 0;

    findings anomalies = {.count = 0}, drops = {.count = 0}, open_views = {.count = 0};
    long in_solid = 0, random_frames = 0, view_frames = 0;
    uint64_t rng = o.seed;
    double total_ms = 0, t_start = ew_clock_ms();
    for (long i = 0; i < o.frames; i++) {
        ew_camera cam;
        memset(&cam, 0, sizeof cam);
        /* Even frames walk the view set, odd ones (all, without views) are random. */
        if (nviews > 0 && (i % 2 == 0 || nopen == 0)) {
            cam = views[(i / 2) % nviews];
            view_frames++;
        } else if (nopen > 0 && random_eye(w, open_leaves, nopen, &rng, cam.origin) == 0) {
            cam.angles[0] = (float)(next_unit(&rng) * 170.0 - 85.0);
            cam.angles[1] = (float)(next_unit(&rng) * 360.0);
            cam.fov = 90;
            random_frames++;
        } else {
            error_line("%s: no views, and no open leaf to place a camera in", o.map);
            rc = 1;
            break;
        }
        cam.time = i / 30.0;  /* animations, sky and liquids keep moving */

        ew_stats st;
        if (ew_render(r, &cam, &st) != 0) {
            add_finding(&anomalies, i, &cam, "ew_render refused the camera");
            continue;
        }
        total_ms += st.ms_total;
        seethrough_frames += st.seethrough_surfaces > 0;
        underwater_frames += st.underwater != 0;
        fog_frames += st.fog_pixels > 0;
        fence_px += (double)st.fence_pixels, translucent_px += (double)st.translucent_pixels;
        fog_px += (double)st.fog_pixels;
        int leaf = ew_world_point_leaf(w, cam.origin);
        int solid = leaf == 0 || !open_contents(ew_world_leaf_contents(w, leaf));
        in_solid += solid;
        if (st.pixels != (long)o.width * o.height)
            add_finding(&anomalies, i, &cam, "pixels %ld, frame has %ld", st.pixels, (long)o.width * o.height);
        /* Fog is laid once on each pixel, whatever the method: more fogged
         * pixels than the frame has is a pixel fogged twice. */
        if (st.fog_pixels > st.pixels)
            add_finding(&anomalies, i, &cam, "fog_pixels %ld, frame has %ld (a pixel fogged twice)",
                        (long)st.fog_pixels, st.pixels);
        if (spans_checked && st.pixels_written != st.pixels_covered)
            add_finding(&anomalies, i, &cam, "overdraw %.9g (%ld written, %ld covered)", st.overdraw,
                        st.pixels_written, st.pixels_covered);
        if (st.dropped > 0) {
            if (ew_frame_budget_full(r))
                add_finding(&drops, i, &cam, "dropped %d with a full budget (%d surfaces, %d edges)",
                            st.dropped, st.surfaces, st.edges);
            else
                add_finding(&anomalies, i, &cam, "dropped %d with no budget full (%d surfaces, %d edges)",
                            st.dropped, st.surfaces, st.edges);
        } else if (spans_checked && !solid && st.pixels_covered != st.pixels) {
            long open_px = 0, missed = cracks(r, &cam, &open_px);
            if (missed != 0)
                add_finding(&anomalies, i, &cam,
                            "%ld of %ld pixels written, %ld of the others covered by the reference path (leaf %d)",
                            st.pixels_covered, st.pixels, missed, leaf);
            else
                add_finding(&open_views, i, &cam, "%ld pixels see no face, in the reference path too (leaf %d)",
                            open_px, leaf);
        }
    }
    double wall_ms = ew_clock_ms() - t_start;
    struct rusage ru;
    memset(&ru, 0, sizeof ru);
    getrusage(RUSAGE_SELF, &ru);

    char name[256];
    map_basename(o.map, name, sizeof name);
    FILE *out = stdout;
    fputs("{\"map\":", out);
    json_string(out, name);
    fprintf(out, ",\"width\":%d,\"height\":%d,\"threads\":%d,\"seed\":%llu,\"frames\":%ld",
            o.width, o.height, ew_get_threads(r), (unsigned long long)o.seed, o.frames);
    fprintf(out, ",\"view_frames\":%ld,\"random_frames\":%ld,\"in_solid\":%ld,\"open_leaves\":%d",
            view_frames, random_frames, in_solid, nopen);
    draw_opts_json(out, &o.draw);
    fprintf(out, ",\"checks\":\"%s\"", spans_checked ? "pixels,overdraw,coverage,drops,fog" : "pixels,drops,fog");
    fprintf(out, ",\"seethrough_frames\":%ld,\"underwater_frames\":%ld,\"fog_frames\":%ld",
            seethrough_frames, underwater_frames, fog_frames);
    fputs(",\"fence_pixels\":", out);
    fprintf(out, "%.0f", fence_px);
    fputs(",\"translucent_pixels\":", out);
    fprintf(out, "%.0f", translucent_px);
    fputs(",\"fog_pixels\":", out);
    fprintf(out, "%.0f", fog_px);
    fputs(",\"seconds\":", out);
    json_number(out, wall_ms / 1000);
    fputs(",\"fps\":", out);
    json_number(out, wall_ms > 0 ? o.frames * 1000.0 / wall_ms : 0);
    fputs(",\"ms_per_frame\":", out);
    json_number(out, total_ms / o.frames);
    print_findings(out, "anomalies", &anomalies);
    print_findings(out, "budget_drops", &drops);
    print_findings(out, "open_views", &open_views);
    fprintf(out, ",\"peak_rss_kb\":%ld}\n", (long)ru.ru_maxrss);

    for (long i = 0; i < anomalies.count && i < MAX_LISTED; i++)
        error_line("soak: frame %ld: %s", anomalies.list[i].frame, anomalies.list[i].what);
    ew_renderer_destroy(r);
    ew_scene_destroy(scene);
    free(open_leaves);
    ew_assets_destroy(a);
    if (fflush(stdout) != 0) {
        error_line("stdout: %s", strerror(errno));
        return 1;
    }
    return rc || anomalies.count ? 1 : 0;
}
