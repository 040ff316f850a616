/* The front end on the pool's threads (world/front_par.c: subtrees walked
 * in parallel, shared edges settled by prefix sums) makes exactly the edge
 * list the serial walk makes with ew_emit_face one face at a time: for
 * every view of e1m1, lqdm7, e4m1 and start (with their entities, so brush
 * models follow the parallel faces) and of the built-in scene, at 640x480
 * and 1920x1080, on 1, 2, 3 and 8 threads, the edges (position, surfaces,
 * per-scanline lists), the surfaces, the counters, every span and every
 * pixel equal the serial front end's: one thread in the default mode,
 * which walks the tree in one loop.  The renderers under test run the
 * phases on one thread too (EW_FRONT_PHASES, as bench does); in the
 * default mode two threads walk in one loop and three take the phases.
 * The methods that share the edge list's front end (spans, painter,
 * drawbuffer) are checked the same way at 640x480. */
#include "renderer.h"
#include "util.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static const char *const maps[] = {"e1m1", "lqdm7", "e4m1", "start", "builtin"};
static const int sizes[][2] = {{640, 480}, {1920, 1080}};
static const int thread_counts[] = {1, 2, 3, 8};
#define NT ((int)(sizeof thread_counts / sizeof *thread_counts))
/* Under the sanitizers (ten times slower) the other methods are checked on
 * the first map and the built-in scene only. */
#define SANITIZED EW_T_SANITIZED

typedef struct fnv { uint64_t h; } fnv;
static void mix(fnv *f, const void *p, size_t n) {
    const uint8_t *b = p;
    for (size_t i = 0; i < n; i++) f->h = (f->h ^ b[i]) * 1099511628211ull;
}
static void mix_int(fnv *f, long v) { mix(f, &v, sizeof v); }

/* What one frame made: its edge list, its spans (bands in row order: the
 * whole frame's, whatever the banding), its counters and its pixels. */
typedef struct frame_sig {
    uint64_t edges, surfs, spans, pixels;
    long nedges, edges_cached, nsurfs, nspans, dropped;
} frame_sig;

static frame_sig sign_frame(const ew_renderer *r, const ew_stats *st) {
    frame_sig s = {0};
    fnv f = {1469598103934665603ull};
    const ew_edge_list *el = &r->el;
    for (int i = 0; i < el->nedges; i++) {
        const ew_edge *e = &el->edges[i];
        mix_int(&f, e->u), mix_int(&f, e->u_step), mix_int(&f, e->v_first), mix_int(&f, e->v_last);
        mix_int(&f, e->surfs[0]), mix_int(&f, e->surfs[1]);
        mix(&f, &e->nearzi, sizeof e->nearzi);
    }
    if (r->f.cfg.hsr->finish) {  /* the scans' order by row: made for the edge list's methods only */
        for (int v = 0; v <= r->f.target.height + 1; v++) mix_int(&f, el->row_first[v]);
        for (int i = 0; i < el->nedges; i++) mix_int(&f, el->by_row[i]), mix_int(&f, el->by_row_last[i]);
    }
    s.edges = f.h;
    f.h = 1469598103934665603ull;
    for (int i = 0; i < el->nsurfs; i++) {
        const ew_surf *sf = &el->surfs[i];
        mix_int(&f, sf->key), mix_int(&f, sf->face), mix_int(&f, sf->flags), mix_int(&f, sf->insubmodel);
        mix(&f, &sf->nearzi, sizeof sf->nearzi);
        /* which camera: the frame's, or the n-th moved brush model's */
        mix_int(&f, sf->view == &r->f.view ? -1 : (long)(sf->view - r->ents.ent_views));
        if (sf->insubmodel) mix(&f, &sf->zi_u, sizeof sf->zi_u * 3);
    }
    s.surfs = f.h;
    f.h = 1469598103934665603ull;
    for (int b = 0; b < r->sched.nbands; b++) {
        const ew_band *bd = &r->sched.bands[b];
        for (int i = 0; i < bd->nspans; i++) {
            const ew_span *sp = &bd->spans[i];
            mix_int(&f, sp->u), mix_int(&f, sp->v), mix_int(&f, sp->count), mix_int(&f, sp->surf);
        }
    }
    s.spans = f.h;
    f.h = 1469598103934665603ull;
    mix(&f, r->f.target.pixels, (size_t)r->f.target.width * r->f.target.height * r->f.target.bpp);
    s.pixels = f.h;
    s.nedges = st->edges, s.edges_cached = st->edges_cached, s.nsurfs = st->surfaces;
    s.nspans = st->spans, s.dropped = st->dropped;
    return s;
}

static ew_renderer *make(const ew_assets *a, ew_scene *sc, int w, int h, int threads, ew_hsr_method hsr) {
    ew_error err;
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                             .colormap = a->colormap, .width = w, .height = h,
                                                             .threads = 1, .hsr = hsr}, &err);
    CHECK(r != NULL, "%s", err.msg);
    if (!r) return NULL;
    CHECK(ew_set_threads(r, threads) == threads, "%d threads", threads);
    ew_set_front_mode(r, EW_FRONT_PHASES);
    ew_set_scene(r, sc);
    return r;
}

static long frames, parallel_faces, fallback_frames;
/* Renders every view on one thread and on each thread count; compares. */
/* max_surfs > 0: every renderer's lists are cut to that many surfaces (and
 * six edges each), so that big views overflow them: the parallel front end
 * then merges one face at a time, and must drop what the serial one drops. */
static void check_limited(const char *map, const ew_assets *a, ew_scene *sc, const ew_camera *views, int nv, int w,
                          int h, ew_hsr_method hsr, int max_surfs) {
    ew_renderer *one = make(a, sc, w, h, 1, hsr);
    if (one) ew_set_front_mode(one, EW_FRONT_AUTO);  /* the default: one thread's own walk */
    ew_renderer *many[NT];
    for (int t = 0; t < NT; t++) many[t] = make(a, sc, w, h, thread_counts[t], hsr);
    if (max_surfs > 0) {
        if (one) one->el.max_surfs = max_surfs, one->el.max_edges = 6 * max_surfs;
        for (int t = 0; t < NT; t++)
            if (many[t]) many[t]->el.max_surfs = max_surfs, many[t]->el.max_edges = 6 * max_surfs;
    }
    for (int v = 0; v < nv && one; v++) {
        ew_stats st;
        CHECK(ew_render(one, &views[v], &st) == 0, "%s view %d", map, v);
        frame_sig want = sign_frame(one, &st);
        CHECK(one->front.par == NULL, "one thread walks in one loop by default");
        for (int t = 0; t < NT; t++) {
            ew_renderer *r = many[t];
            if (!r) continue;
            CHECK(ew_render(r, &views[v], &st) == 0, "%s view %d", map, v);
            frame_sig got = sign_frame(r, &st);
            frames++;
            CHECK(r->front.par != NULL, "%d threads take the parallel front end", thread_counts[t]);
            if (want.nsurfs > 64) parallel_faces++;
            if (want.dropped > 0) fallback_frames++;
            const char *m = ew_hsr_name(hsr);
            CHECK(got.nedges == want.nedges && got.edges_cached == want.edges_cached && got.nsurfs == want.nsurfs &&
                      got.dropped == want.dropped,
                  "%s %s %dx%d view %d, %d threads: edges %ld/%ld cached %ld/%ld surfaces %ld/%ld dropped %ld/%ld",
                  map, m, w, h, v, thread_counts[t], got.nedges, want.nedges, got.edges_cached, want.edges_cached,
                  got.nsurfs, want.nsurfs, got.dropped, want.dropped);
            CHECK(got.edges == want.edges, "%s %s %dx%d view %d, %d threads: edge list differs", map, m, w, h, v,
                  thread_counts[t]);
            CHECK(got.surfs == want.surfs, "%s %s %dx%d view %d, %d threads: surfaces differ", map, m, w, h, v,
                  thread_counts[t]);
            CHECK(got.spans == want.spans && got.nspans == want.nspans,
                  "%s %s %dx%d view %d, %d threads: spans differ", map, m, w, h, v, thread_counts[t]);
            CHECK(got.pixels == want.pixels, "%s %s %dx%d view %d, %d threads: pixels differ", map, m, w, h, v,
                  thread_counts[t]);
        }
    }
    ew_renderer_destroy(one);
    for (int t = 0; t < NT; t++) ew_renderer_destroy(many[t]);
}

static void check(const char *map, const ew_assets *a, ew_scene *sc, const ew_camera *views, int nv, int w, int h,
                  ew_hsr_method hsr) {
    check_limited(map, a, sc, views, nv, w, h, hsr, 0);
}

/* A tree the parallel front end cannot split (an edge on two faces the
 * same way round, as no compiler writes it): its plan fails and every
 * thread count walks serially, with the serial frames. */
static void check_irregular(ew_assets *a, ew_scene *sc, const ew_camera *views, int nv) {
    ew_world *w = (ew_world *)a->world;
    int f0 = -1, f1 = -1;
    for (int i = 0; i < w->numfaces && f1 < 0; i++)
        if (w->faces[i].numedges >= 3) f0 < 0 ? (f0 = i) : (f1 = i);
    if (f1 < 0) return;
    int *se = &w->surfedges[w->faces[f1].firstedge], saved = *se;
    int *sv = &w->surfverts[w->faces[f1].firstedge], saved_v = *sv;  /* its start vertex with it */
    *se = w->surfedges[w->faces[f0].firstedge];
    *sv = w->surfverts[w->faces[f0].firstedge];
    ew_renderer *one = make(a, sc, 640, 480, 1, EW_HSR_EDGE), *two = make(a, sc, 640, 480, 2, EW_HSR_EDGE);
    if (one) ew_set_front_mode(one, EW_FRONT_AUTO);
    for (int v = 0; v < nv && one && two; v++) {
        ew_stats st;
        CHECK(ew_render(one, &views[v], &st) == 0, "view %d", v);
        frame_sig want = sign_frame(one, &st);
        CHECK(ew_render(two, &views[v], &st) == 0, "view %d", v);
        frame_sig got = sign_frame(two, &st);
        CHECK(two->front.par == NULL && two->front.par_bad, "an irregular tree takes the serial front end");
        CHECK(got.edges == want.edges && got.pixels == want.pixels, "irregular tree, view %d: frames differ", v);
    }
    ew_renderer_destroy(one);
    ew_renderer_destroy(two);
    *se = saved, *sv = saved_v;
}

/* The default mode on several threads: up to EW_FRONT_LOOP_THREADS the
 * calling thread walks in one loop, above it the phases; the same frames. */
static void check_default_mode(const ew_assets *a, ew_scene *sc, const ew_camera *views, int nv) {
    ew_renderer *one = make(a, sc, 640, 480, 1, EW_HSR_EDGE);
    if (one) ew_set_front_mode(one, EW_FRONT_AUTO);
    for (int n = 2; n <= EW_FRONT_LOOP_THREADS + 1; n++) {
        ew_renderer *r = make(a, sc, 640, 480, n, EW_HSR_EDGE);
        if (r) ew_set_front_mode(r, EW_FRONT_AUTO);
        for (int v = 0; v < nv && one && r; v++) {
            ew_stats st;
            CHECK(ew_render(one, &views[v], &st) == 0, "view %d", v);
            frame_sig want = sign_frame(one, &st);
            CHECK(ew_render(r, &views[v], &st) == 0, "view %d", v);
            frame_sig got = sign_frame(r, &st);
            CHECK((r->front.par == NULL) == (n <= EW_FRONT_LOOP_THREADS),
                  "%d threads by default: %s", n, n <= EW_FRONT_LOOP_THREADS ? "one loop" : "the phases");
            CHECK(got.edges == want.edges && got.spans == want.spans && got.pixels == want.pixels,
                  "%d threads by default, view %d: the frame differs from one thread's", n, v);
        }
        ew_renderer_destroy(r);
    }
    ew_renderer_destroy(one);
}

int main(void) {
    for (size_t m = 0; m < sizeof maps / sizeof *maps; m++) {
        ew_scene *sc;
        ew_camera views[EW_MAX_VIEWS];
        int nv;
        ew_assets *a = ew_t_load_map_scene(maps[m], &sc, views, &nv);
        if (!a) continue;
        /* Under the sanitizers (ten times slower) the large size on e1m1 only. */
        for (size_t s = 0; s < sizeof sizes / sizeof *sizes; s++)
            if (!SANITIZED || s == 0 || m == 0) check(maps[m], a, sc, views, nv, sizes[s][0], sizes[s][1], EW_HSR_EDGE);
        if (m == 0) {
            check_limited(maps[m], a, sc, views, nv, 640, 480, EW_HSR_EDGE, 150);
            check_irregular(a, sc, views, nv);
            check_default_mode(a, sc, views, nv);
        }
        const ew_hsr_method shared_front[] = {EW_HSR_SPANS, EW_HSR_PAINTER, EW_HSR_DRAWBUFFER};
        for (size_t k = 0; k < sizeof shared_front / sizeof *shared_front; k++)
            if (ew_hsr_available(shared_front[k]) && (!SANITIZED || m == 0 || !strcmp(maps[m], "builtin")))
                check(maps[m], a, sc, views, nv, 640, 480, shared_front[k]);
        ew_scene_destroy(sc);
        ew_assets_destroy(a);
    }
    printf("%ld frames of the parallel front end compared with the serial one's (%ld with over 64 surfaces)\n", frames,
           parallel_faces);
    CHECK(parallel_faces > 100, "%ld frames of any size", parallel_faces);
    printf("%ld frames overflowed the lists (the parallel front end merged one face at a time)\n", fallback_frames);
    CHECK(fallback_frames > 5, "%ld frames overflowed the lists", fallback_frames);
    return ew_t_finish();
}
