/* The hidden-surface lab: every method this build has (so methods merged
 * later are covered without touching this file), on every view of the view
 * set of e1m1, lqdm7 and start at 320x200, against the reference path:
 *   - the face that wins each pixel agrees with the reference's on at least
 *     99% of pixels (raycast: 90%, it approximates between its rays);
 *   - overdraw exactly 1.0 for the methods that write each pixel once
 *     (edge, edge-z, spans, beamtree, drawbuffer), and their ew_hsr says so;
 *     painter's order overdraws on most views; the z-buffer tests depth at
 *     least once per pixel it writes;
 *   - frames (pixels and faces) identical for 1 and 2 threads;
 *   - the names round-trip, ew_set_hsr refuses unknown and unavailable
 *     methods, and `--hsr` in the CLI refuses an unknown name.
 * One table line per method and map: agreement, overdraw, counters. */
#define _POSIX_C_SOURCE 200809L
#include "edgewise_lab.h"
#include "renderer.h"
#include "util.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define W 320
#define H 200

static int exact_once_expected(int m) {
    /* (the raycast approximates which surface, but still writes each pixel once) */
    return m == EW_HSR_EDGE || m == EW_HSR_EDGE_Z || m == EW_HSR_SPANS || m == EW_HSR_BEAMTREE ||
           m == EW_HSR_DRAWBUFFER || m == EW_HSR_RAYCAST;
}

static double floor_for(int m) { return m == EW_HSR_RAYCAST ? 0.90 : 0.99; }

static int counter_index(int m, const char *name) {
    for (int i = 0; i < EW_HSR_COUNTERS; i++) {
        const char *c = ew_hsr_counter_name((ew_hsr_method)m, i);
        if (c && strcmp(c, name) == 0) return i;
    }
    return -1;
}

static void names(void) {
    for (int m = 0; m < EW_HSR_COUNT; m++) {
        const char *n = ew_hsr_name((ew_hsr_method)m);
        CHECK(n != NULL && *n, "method %d has no name", m);
        if (n) CHECK(ew_hsr_from_name(n) == m, "%s: from_name gives %d, not %d", n, ew_hsr_from_name(n), m);
        for (int k = 0; n && k < m; k++) CHECK(strcmp(n, ew_hsr_name((ew_hsr_method)k)) != 0, "%s twice", n);
    }
    CHECK(ew_hsr_name(EW_HSR_COUNT) == NULL && ew_hsr_name((ew_hsr_method)-1) == NULL, "names out of range");
    CHECK(ew_hsr_from_name("bogus") == -1 && ew_hsr_from_name("") == -1 && ew_hsr_from_name(NULL) == -1 &&
              ew_hsr_from_name("Edge") == -1 && ew_hsr_from_name("edge ") == -1,
          "from_name accepts a name that is none");
    CHECK(ew_hsr_available(EW_HSR_EDGE) && ew_hsr_available(EW_HSR_REFERENCE), "edge and reference always built");
    CHECK(!ew_hsr_available(EW_HSR_COUNT) && !ew_hsr_available((ew_hsr_method)-1), "available out of range");
    CHECK(ew_hsr_counter_name(EW_HSR_EDGE, -1) == NULL && ew_hsr_counter_name(EW_HSR_EDGE, EW_HSR_COUNTERS) == NULL &&
              ew_hsr_counter_name(EW_HSR_COUNT, 0) == NULL,
          "counter names out of range");
}

/* ew_set_hsr: -1 for what is unknown or not built, and then the method in
 * use stays (the frame still matches the one before). */
static void set_hsr(ew_renderer *r, const ew_camera *cam) {
    CHECK(ew_set_hsr(r, EW_HSR_EDGE) == 0, "set edge");
    CHECK(ew_render(r, cam, NULL) == 0, "render");
    int *before = malloc(sizeof(int) * W * H);
    memcpy(before, ew_frame_face_ids(r), sizeof(int) * W * H);
    int unavailable = 0;
    for (int m = 0; m < EW_HSR_COUNT; m++)
        if (!ew_hsr_available((ew_hsr_method)m)) {
            unavailable++;
            CHECK(ew_set_hsr(r, (ew_hsr_method)m) == -1, "%s is not built, yet ew_set_hsr takes it",
                  ew_hsr_name((ew_hsr_method)m));
        }
    CHECK(ew_set_hsr(r, EW_HSR_COUNT) == -1 && ew_set_hsr(r, (ew_hsr_method)-1) == -1 &&
              ew_set_hsr(r, (ew_hsr_method)1000) == -1,
          "ew_set_hsr takes an unknown method");
    CHECK(r->f.cfg.hsr == ew_hsr_get(EW_HSR_EDGE), "a refused ew_set_hsr changed the method");
    CHECK(ew_render(r, cam, NULL) == 0, "render");
    CHECK(memcmp(before, ew_frame_face_ids(r), sizeof(int) * W * H) == 0, "a refused ew_set_hsr changed the frame");
    printf("methods: %d of %d built, %d refused by ew_set_hsr as not built\n", EW_HSR_COUNT - unavailable,
           EW_HSR_COUNT, unavailable);
    free(before);
}

typedef struct row {
    double ag_sum, ag_min, od_sum, od_max;
    int views, overdrawn;
    long counters[EW_HSR_COUNTERS];
    double ms;
} row;

static void check_map(const char *map) {
    ew_assets *a = ew_t_load_map(map);
    if (!a) return;
    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(a->world, views);
    CHECK(nv > 0, "%s has no views", map);
    ew_error err;
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                            .colormap = a->colormap, .width = W, .height = H,
                                                            .threads = 1},
                                        &err);
    CHECK(r != NULL, "%s: %s", map, err.msg);
    if (!r || nv <= 0) {
        ew_renderer_destroy(r);
        ew_assets_destroy(a);
        return;
    }
    ew_enable_face_ids(r, 1);
    if (strcmp(map, "e1m1") == 0) set_hsr(r, &views[0]);

    int *ref = malloc(sizeof(int) * W * H);
    row rows[EW_HSR_COUNT];
    memset(rows, 0, sizeof rows);
    for (int m = 0; m < EW_HSR_COUNT; m++) rows[m].ag_min = 1;

    for (int v = 0; v < nv; v++) {
        CHECK(ew_render_reference(r, &views[v], NULL, ref, &err) == 0, "%s view %d: %s", map, v, err.msg);
        for (int m = 0; m < EW_HSR_COUNT; m++) {
            if (!ew_hsr_available((ew_hsr_method)m)) continue;
            const char *name = ew_hsr_name((ew_hsr_method)m);
            CHECK(ew_set_hsr(r, (ew_hsr_method)m) == 0, "set %s", name);
            ew_stats st;
            CHECK(ew_render(r, &views[v], &st) == 0, "%s view %d %s: render", map, v, name);
            const int *ids = ew_frame_face_ids(r);
            long same = 0;
            for (int i = 0; i < W * H; i++) same += ids[i] == ref[i];
            double ag = (double)same / (W * H);
            CHECK(ag >= floor_for(m), "%s view %d %s: %.3f%% of pixels agree with the reference", map, v, name,
                  100 * ag);
            CHECK(st.dropped == 0, "%s view %d %s: %d dropped", map, v, name, st.dropped);
            if (m == EW_HSR_REFERENCE)
                CHECK(same == W * H, "%s view %d: the reference differs from itself at %ld pixels", map, v,
                      W * H - same);
            if (exact_once_expected(m))
                CHECK(st.overdraw == 1.0 && st.pixels_written == st.pixels_covered && st.pixels_covered > W * H / 2,
                      "%s view %d %s: overdraw %.4f, %ld written, %ld covered", map, v, name, st.overdraw,
                      st.pixels_written, st.pixels_covered);
            if (m == EW_HSR_ZBUFFER) {
                int k = counter_index(m, "depth tests");
                CHECK(k >= 0, "zbuffer has no counter named \"depth tests\"");
                if (k >= 0)
                    CHECK(st.hsr_counters[k] >= st.pixels_written && st.pixels_written >= st.pixels_covered &&
                              st.pixels_covered > 0,
                          "%s view %d zbuffer: %ld depth tests, %ld written, %ld covered", map, v,
                          st.hsr_counters[k], st.pixels_written, st.pixels_covered);
            }
            if (m == EW_HSR_PAINTER)
                printf("%s view %2d painter: overdraw %.3f (%ld written, %ld covered)\n", map, v, st.overdraw,
                       st.pixels_written, st.pixels_covered);
            row *rw = &rows[m];
            rw->views++;
            rw->ag_sum += ag;
            if (ag < rw->ag_min) rw->ag_min = ag;
            rw->od_sum += st.overdraw;
            if (st.overdraw > rw->od_max) rw->od_max = st.overdraw;
            rw->overdrawn += st.overdraw > 1.0;
            rw->ms += st.ms_total;
            for (int k = 0; k < EW_HSR_COUNTERS; k++) rw->counters[k] += st.hsr_counters[k];
        }
    }
    for (int m = 0; m < EW_HSR_COUNT; m++) {
        const row *rw = &rows[m];
        if (!rw->views) continue;
        const ew_hsr *h = ew_hsr_get(m);
        CHECK(!!(h->flags & EW_HSR_EXACT_ONCE) == exact_once_expected(m), "%s: EW_HSR_EXACT_ONCE %d", h->name,
              !!(h->flags & EW_HSR_EXACT_ONCE));
        if (m == EW_HSR_EDGE_Z) {
            int k = counter_index(m, "1/z comparisons");
            CHECK(k >= 0 && rw->counters[k] >= rw->views, "%s edge-z: %ld 1/z comparisons over %d views", map,
                  k >= 0 ? rw->counters[k] : -1L, rw->views);
        }
        if (m == EW_HSR_PAINTER)
            CHECK(2 * rw->overdrawn > rw->views, "%s painter: overdraw above 1 on only %d of %d views", map,
                  rw->overdrawn, rw->views);
        char counters[512] = "";
        size_t len = 0;
        for (int k = 0; k < EW_HSR_COUNTERS && len < sizeof counters; k++) {
            const char *c = ew_hsr_counter_name((ew_hsr_method)m, k);
            if (c) len += (size_t)snprintf(counters + len, sizeof counters - len, "  %s %ld", c, rw->counters[k]);
        }
        printf("hsr %-10s %-6s views %2d  agreement mean %7.3f%% min %7.3f%%  overdraw mean %.3f max %.3f  "
               "%.1f ms/view%s\n",
               h->name, map, rw->views, 100 * rw->ag_sum / rw->views, 100 * rw->ag_min, rw->od_sum / rw->views,
               rw->od_max, rw->ms / rw->views, counters);
    }
    free(ref);
    ew_renderer_destroy(r);
    ew_assets_destroy(a);
}

/* Every method's frame, pixels and faces, the same on 1 and 2 threads
 * (bands resolve on several threads at once). */
static void threads(void) {
    ew_assets *a = ew_t_load_map("e1m1");
    if (!a) return;
    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(a->world, views);
    ew_error err;
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                            .colormap = a->colormap, .width = W, .height = H,
                                                            .threads = 1},
                                        &err);
    CHECK(r != NULL, "%s", err.msg);
    if (!r || nv <= 0) {
        ew_renderer_destroy(r);
        ew_assets_destroy(a);
        return;
    }
    ew_enable_face_ids(r, 1);
    const int pick[] = {0, nv / 2, nv - 1};
    uint8_t *px = malloc(W * H);
    int *ids = malloc(sizeof(int) * W * H);
    for (int m = 0; m < EW_HSR_COUNT; m++) {
        if (!ew_hsr_available((ew_hsr_method)m)) continue;
        CHECK(ew_set_hsr(r, (ew_hsr_method)m) == 0, "set %s", ew_hsr_name((ew_hsr_method)m));
        int same = 0;
        for (int i = 0; i < 3; i++) {
            ew_set_threads(r, 1);
            CHECK(ew_render(r, &views[pick[i]], NULL) == 0, "render");
            memcpy(px, ew_frame_pixels(r), W * H);
            memcpy(ids, ew_frame_face_ids(r), sizeof(int) * W * H);
            CHECK(ew_set_threads(r, 2) == 2, "2 threads");
            CHECK(ew_render(r, &views[pick[i]], NULL) == 0, "render");
            int ok = memcmp(px, ew_frame_pixels(r), W * H) == 0 &&
                     memcmp(ids, ew_frame_face_ids(r), sizeof(int) * W * H) == 0;
            CHECK(ok, "%s e1m1 view %d: 1 and 2 threads differ", ew_hsr_name((ew_hsr_method)m), pick[i]);
            same += ok;
        }
        printf("threads %-10s e1m1 views %d %d %d: %d of 3 identical on 1 and 2 threads\n",
               ew_hsr_name((ew_hsr_method)m), pick[0], pick[1], pick[2], same);
    }
    free(px), free(ids);
    ew_renderer_destroy(r);
    ew_assets_destroy(a);
}

/* --hsr through the command: an unknown name is one error line and a
 * failing exit; every built method renders. */
static void cli(void) {
    if (!getenv("EW_CLI")) {
        CHECK(0, "EW_CLI not set");
        return;
    }
    char dir[] = "/tmp/ew_hsr_XXXXXX";
    if (!mkdtemp(dir)) {
        CHECK(0, "no scratch folder");
        return;
    }
    static ew_t_run run;
    ew_t_run_cli(&run, dir, (const char *const[]){"demo", "--hsr", "bogus", "--out", "x.png", NULL});
    CHECK(run.signal == 0 && run.status != 0, "--hsr bogus: exit %d", run.status);
    CHECK(ew_t_count_lines(run.err) == 1 && strncmp(run.err, "edgewise: --hsr bogus", 21) == 0,
          "--hsr bogus: stderr %s", run.err);
    CHECK(run.out[0] == 0, "--hsr bogus: stdout %s", run.out);
    for (int m = 0; m < EW_HSR_COUNT; m++) {
        const char *n = ew_hsr_name((ew_hsr_method)m);
        ew_t_run_cli(&run, dir, (const char *const[]){"demo", "--hsr", n, "--size", "320x200", "--out", "x.png", NULL});
        if (ew_hsr_available((ew_hsr_method)m))
            CHECK(run.signal == 0 && run.status == 0, "--hsr %s: exit %d, stderr %s", n, run.status, run.err);
        else
            CHECK(run.signal == 0 && run.status != 0 && ew_t_count_lines(run.err) == 1,
                  "--hsr %s (not built): exit %d, stderr %s", n, run.status, run.err);
    }
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    CHECK(system(cmd) == 0, "%s", cmd);
}

/* ---- edge-z on hand-made edge lists: planes that cross and abut ---- */

/* An edge from (u0, v0) to (u1, v1) for surface s, as world/edges.c makes
 * them: 16.16 u at the first scanline centre crossed; going down on the
 * screen it bounds the surface's right side (trails), going up its left. */
static void synth_edge(ew_edge_list *el, float u0, float v0, float u1, float v1, int s) {
    int down = v1 > v0;
    float tu = down ? u0 : u1, tv = down ? v0 : v1, bu = down ? u1 : u0, bv = down ? v1 : v0;
    int first = (int)ceilf(tv), last = (int)ceilf(bv) - 1;
    if (first > last) return;
    ew_edge *e = &el->edges[el->nedges];
    double slope = ((double)bu - tu) / ((double)bv - tv);
    e->u = (int32_t)floor((tu + (first - tv) * slope) * 65536.0 + 0.5);
    e->u_step = first == last ? 0 : (int32_t)floor(slope * 65536.0 + 0.5);
    e->v_first = first, e->v_last = last;
    e->surfs[0] = down ? (uint16_t)s : 0;
    e->surfs[1] = down ? 0 : (uint16_t)s;
    e->nearzi = 0;
    el->nedges++;
}

/* A convex polygon, clockwise on the screen, with the 1/z plane given. */
static void synth_poly(ew_edge_list *el, const float (*p)[2], int n, float zu, float zv, float z0) {
    int s = el->nsurfs++;
    el->surfs[s] = (ew_surf){.key = s, .face = s, .zi_u = zu, .zi_v = zv, .zi_0 = z0};
    for (int i = 0; i < n; i++) synth_edge(el, p[i][0], p[i][1], p[(i + 1) % n][0], p[(i + 1) % n][1], s);
}

static void synth_begin(ew_edge_list *el) {
    el->nedges = 0;
    el->nsurfs = 1;
    el->surfs[0] = (ew_surf){.key = INT32_MAX, .face = -1};
}

/* Where each edge's u lands on row y: the first pixel centre right of it. */
static int edge_pixel(const ew_edge *e, int y, int w) {
    int64_t u = (int64_t)e->u + (int64_t)(y - e->v_first) * e->u_step;
    int iu = (int)((u + 0xFFFF) >> 16);
    return iu < 0 ? 0 : iu > w ? w : iu;
}

/* The surface nearest at each pixel, one pixel at a time: coverage from
 * each surface's own edges, 1/z as the reference evaluates it, ties within
 * the method's hair to the faster-growing 1/z. */
static void synth_expect(const ew_edge_list *el, int w, int h, int *want) {
    for (int i = 0; i < w * h; i++) want[i] = 0;
    int *lo = malloc(sizeof(int) * (size_t)el->nsurfs), *hi = malloc(sizeof(int) * (size_t)el->nsurfs);
    for (int y = 0; y < h; y++) {
        for (int s = 0; s < el->nsurfs; s++) lo[s] = w, hi[s] = 0;
        for (int i = 0; i < el->nedges; i++) {
            const ew_edge *e = &el->edges[i];
            if (y < e->v_first || y > e->v_last) continue;
            int iu = edge_pixel(e, y, w);
            if (e->surfs[1]) lo[e->surfs[1]] = iu;
            if (e->surfs[0]) hi[e->surfs[0]] = iu;
        }
        for (int x = 0; x < w; x++) {
            int best = 0;
            float bz = 0;
            for (int s = 1; s < el->nsurfs; s++) {
                if (x < lo[s] || x >= hi[s]) continue;
                const ew_surf *sf = &el->surfs[s];
                float z = sf->zi_u * (float)x + (sf->zi_v * (float)y + sf->zi_0);
                float tol = (z + bz) / (1 << 20);
                if (!best || z - bz > tol || (!(bz - z > tol) && sf->zi_u > el->surfs[best].zi_u)) best = s, bz = z;
            }
            want[y * w + x] = best;
        }
    }
    free(lo), free(hi);
}

/* Resolves the hand-made list with edge-z; spans must tile every row once,
 * left to right.  Returns the pixels that differ from want. */
static long synth_resolve(ew_renderer *r, int h, const int *want, long counters[EW_HSR_COUNTERS], const char *what) {
    const int w = r->f.target.width;
    ew_band b;
    memset(&b, 0, sizeof b);
    long bad = -1;
    if (ew_band_init(&b, r->el.max_surfs, r->el.max_spans) == 0) {
        b.y0 = 0, b.y1 = h;
        ew_hsr_get(EW_HSR_EDGE_Z)->finish(&r->hsr);
        ew_hsr_get(EW_HSR_EDGE_Z)->resolve(&r->hsr, &b);
        memcpy(counters, b.counters, sizeof b.counters);
        bad = 0;
        int row = -1, end = 0, tiled = 1;
        for (int i = 0; i < b.nspans; i++) {
            const ew_span *sp = &b.spans[i];
            if (sp->v != row) tiled = tiled && (row < 0 || end == w) && sp->v == row + 1, row = sp->v, end = 0;
            tiled = tiled && sp->u == end && sp->count > 0;
            end = sp->u + sp->count;
            for (int k = 0; k < sp->count && sp->u + k < w; k++) bad += want[sp->v * w + sp->u + k] != sp->surf;
        }
        tiled = tiled && row == h - 1 && end == w;
        CHECK(tiled && b.dropped == 0, "%s: the spans do not tile the rows once (%d spans, %d dropped)", what,
              b.nspans, b.dropped);
    }
    CHECK(bad >= 0, "%s: no band", what);
    ew_band_free(&b);
    return bad;
}

static float rnd(unsigned *seed) {
    *seed = *seed * 1103515245u + 12345u;
    return (float)(*seed >> 8 & 0xFFFF) / 65536.0f;
}

static void edge_z_synthetic(void) {
    ew_error err;
    ew_assets *a = ew_assets_create_builtin(&err);
    CHECK(a != NULL, "builtin: %s", err.msg);
    if (!a) return;
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                            .colormap = a->colormap, .width = W, .height = H,
                                                            .threads = 1},
                                        &err);
    CHECK(r != NULL, "%s", err.msg);
    int *want = malloc(sizeof(int) * W * H);
    long c[EW_HSR_COUNTERS];
    const int cmp = counter_index(EW_HSR_EDGE_Z, "1/z comparisons"), split = counter_index(EW_HSR_EDGE_Z, "intersections split"),
              tie = counter_index(EW_HSR_EDGE_Z, "abutting ties");
    CHECK(cmp >= 0 && split >= 0 && tie >= 0, "edge-z counters %d %d %d", cmp, split, tie);
    if (!r || cmp < 0 || split < 0 || tie < 0) goto done;
    ew_edge_list *el = &r->el;

    /* Two rectangles over rows 10..19, planes crossing at x = 100.5: the
     * first is nearer left of it, the second from pixel 101 on.  In BSP
     * order one would hide the other whole. */
    static const float box[4][2] = {{40, 10}, {200, 10}, {200, 20}, {40, 20}};
    synth_begin(el);
    synth_poly(el, box, 4, -1e-5f, 0, 0.01f + 100.5f * 1e-5f);
    synth_poly(el, box, 4, 1e-5f, 0, 0.01f - 100.5f * 1e-5f);
    synth_expect(el, W, H, want);
    long bad = synth_resolve(r, H, want, c, "crossing planes");
    CHECK(bad == 0 && want[15 * W + 100] == 1 && want[15 * W + 101] == 2, "crossing planes: %ld pixels wrong", bad);
    CHECK(c[split] == 10, "crossing planes: %ld splits, want one per row (10)", c[split]);

    /* Abutting: a wall over [40, 200) and a door starting on it at x = 120
     * with the same 1/z there, leaning towards the eye to the right.  At
     * its first pixel the two are equal: the faster-growing 1/z wins. */
    static const float wall[4][2] = {{40, 30}, {200, 30}, {200, 40}, {40, 40}};
    static const float door[4][2] = {{119.5f, 30}, {180, 30}, {180, 40}, {119.5f, 40}};
    synth_begin(el);
    synth_poly(el, wall, 4, 0, 0, 0.01f);
    synth_poly(el, door, 4, 1e-5f, 0, 0.01f - 120 * 1e-5f);
    synth_expect(el, W, H, want);
    bad = synth_resolve(r, H, want, c, "abutting");
    CHECK(bad == 0 && want[35 * W + 119] == 1 && want[35 * W + 120] == 2, "abutting: %ld pixels wrong", bad);
    CHECK(c[tie] >= 10 && c[split] == 0, "abutting: %ld ties, %ld splits", c[tie], c[split]);

    /* Many random quadrilaterals with random planes, crossing each other
     * everywhere: against the per-pixel answer. */
    unsigned seed = 12345;
    long splits = 0, total_bad = 0;
    for (int scene = 0; scene < 20; scene++) {
        synth_begin(el);
        for (int k = 0; k < 24; k++) {
            /* one corner on each side of a box inside the screen: convex */
            float f[10];
            for (int i = 0; i < 10; i++) f[i] = rnd(&seed);
            float rx = 10 + f[0] * 120, ry = 5 + f[1] * 80, cx = rx + f[2] * (W - 1 - 2 * rx),
                  cy = ry + f[3] * (H - 1 - 2 * ry);
            const float q[4][2] = {{cx - rx * f[4], cy - ry}, {cx + rx, cy - ry * f[5]},
                                   {cx + rx * f[6], cy + ry}, {cx - rx, cy + ry * f[7]}};
            float zc = 0.01f + 0.01f * f[8], zu = (f[9] - 0.5f) * 6e-5f, zv = (rnd(&seed) - 0.5f) * 6e-5f;
            synth_poly(el, q, 4, zu, zv, zc - zu * W / 2 - zv * H / 2);
        }
        synth_expect(el, W, H, want);
        total_bad += synth_resolve(r, H, want, c, "random planes");
        splits += c[split];
    }
    /* Only where three planes tie within the hair may the order of the
     * comparisons pick another one: a handful of pixels at most. */
    CHECK(total_bad <= 8, "random planes: %ld pixels of %d differ from the per-pixel answer",
          total_bad, 20 * W * H);
    CHECK(splits > 1000, "random planes: only %ld splits", splits);
    printf("edge-z hand-made lists: crossing, abutting exact; 20 random scenes of 24 planes: %ld pixels differ, "
           "%ld intersections split\n", total_bad, splits);
done:
    free(want);
    ew_renderer_destroy(r);
    ew_assets_destroy(a);
}

int main(void) {
    names();
    if (ew_hsr_available(EW_HSR_EDGE_Z)) edge_z_synthetic();
    cli();
    if (!ew_t_need_shared("data/librequake/maps/e1m1.bsp")) return ew_t_finish();
    const char *maps[] = {"e1m1", "lqdm7", "start"};
    for (int i = 0; i < 3; i++) check_map(maps[i]);
    threads();
    return ew_t_finish();
}
