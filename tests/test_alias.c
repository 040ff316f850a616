/* The alias model rasterizers and pipeline, on data built here:
 *   - the affine filler covers exactly the pixels a reference top-left
 *     rule on pixel centres covers, for thousands of random triangles (also
 *     clipped to a rectangle), and tiles a mesh with no double writes/gaps;
 *   - the one cross product rejects back-facing and zero-area triangles;
 *   - the subdivision rasterizer: on a planar mesh and on a closed sphere
 *     drawn small, every pixel is written at most once and none inside the
 *     silhouette is missed;
 *   - z-buffering against a "wall", near-plane and screen clipping, the
 *     automatic choice of rasterizer, sprites and particles. */
#include "util.h"
#include "renderer.h"
#include "raster/alias.h"
#include "model_fixtures.h"

#include <stdlib.h>
#include <string.h>

#define BW 96
#define BH 96
#ifndef SPHERE_POSES
#define SPHERE_POSES 150
#endif

static uint32_t rng_state = 12345;
static uint32_t rnd(void) {
    rng_state = rng_state * 1664525u + 1013904223u;
    return rng_state >> 8;
}
static int rndi(int lo, int hi) { return lo + (int)(rnd() % (uint32_t)(hi - lo + 1)); }

static uint8_t test_skin[16 * 16];
static uint8_t test_cmap[64 * 256];

static ew_target test_target;

static void init_araster(ew_araster *ra, uint8_t *frame, float *zbuf) {
    memset(ra, 0, sizeof *ra);
    test_target = (ew_target){frame, zbuf, BW, BH, BW, 1, NULL};
    ra->target = &test_target;
    ra->x0 = 0, ra->y0 = 0, ra->x1 = BW, ra->y1 = BH;
    ra->skin = test_skin, ra->skinw = 16, ra->skinh = 16;
    ra->colormap = test_cmap;
}

static ew_avert vert(int x, int y) {
    ew_avert v = {x, y, (x & 15) << 16, (y & 15) << 16, 32 << 8, 1.0f};
    return v;
}

static int tl(const ew_avert *p, const ew_avert *q) {
    return q->y < p->y || (q->y == p->y && q->x > p->x);
}
static long edge(const ew_avert *a, const ew_avert *b, int x, int y) {
    return (long)(b->x - a->x) * (y - a->y) - (long)(b->y - a->y) * (x - a->x);
}
/* The reference: centre inside, or on a top/left edge. */
static int ref_inside(const ew_avert *a, const ew_avert *b, const ew_avert *c, int x, int y) {
    if (ew_alias_cross(a, b, c) <= 0) return 0;
    long e0 = edge(a, b, x, y), e1 = edge(b, c, x, y), e2 = edge(c, a, x, y);
    return (e0 > 0 || (e0 == 0 && tl(a, b))) && (e1 > 0 || (e1 == 0 && tl(b, c))) &&
           (e2 > 0 || (e2 == 0 && tl(c, a)));
}

static void test_affine_reference(void) {
    uint8_t *frame = calloc(BW * BH, 1);
    float *zbuf = calloc(BW * BH, sizeof(float));
    ew_araster ra;
    int tris = 0, front = 0, mismatched = 0, pixels = 0;
    for (int i = 0; i < 6000; i++) {
        init_araster(&ra, frame, zbuf);
        if (i % 3 == 2) ra.x0 = 20, ra.y0 = 24, ra.x1 = 70, ra.y1 = 61;  /* clipped */
        int cx = rndi(-4, BW + 3), cy = rndi(-4, BH + 3), sz = i % 4 == 0 ? 30 : 10;
        ew_avert a = vert(cx + rndi(-sz, sz), cy + rndi(-sz, sz));
        ew_avert b = vert(cx + rndi(-sz, sz), cy + rndi(-sz, sz));
        ew_avert c = vert(cx + rndi(-sz, sz), cy + rndi(-sz, sz));
        memset(zbuf, 0, sizeof(float) * BW * BH);
        ew_alias_affine_tri(&ra, &a, &b, &c);
        tris++;
        front += ew_alias_tri_visible(&a, &b, &c);
        long covered = 0;
        int bad = 0;
        for (int y = 0; y < BH; y++)
            for (int x = 0; x < BW; x++) {
                int got = zbuf[y * BW + x] != 0;
                int in_rect = x >= ra.x0 && x < ra.x1 && y >= ra.y0 && y < ra.y1;
                int want = in_rect && ref_inside(&a, &b, &c, x, y);
                covered += got;
                if (got != want) bad++;
            }
        pixels += (int)covered;
        if (bad) {
            if (mismatched < 3)
                fprintf(stderr, "triangle (%d,%d) (%d,%d) (%d,%d): %d pixels differ\n", a.x, a.y, b.x,
                        b.y, c.x, c.y, bad);
            mismatched++;
        }
        CHECK(covered == ra.pixels, "pixel count %ld vs coverage %ld", ra.pixels, covered);
    }
    CHECK(mismatched == 0, "%d of %d triangles differ from the reference fill", mismatched, tris);
    CHECK(front > 1000 && pixels > 50000, "too few drawn (%d front, %d pixels)", front, pixels);
    printf("affine vs reference: %d triangles (%d front-facing), %d pixels, %d differ\n", tris, front,
           pixels, mismatched);
    free(frame);
    free(zbuf);
}

static void test_cross_culls(void) {
    ew_avert a = vert(10, 10), b = vert(20, 10), c = vert(10, 20);
    /* Positive cross: front-facing. */
    int64_t front = ew_alias_cross(&a, &c, &b), back = ew_alias_cross(&a, &b, &c);
    CHECK(front != 0 && back == -front, "cross %lld / %lld", (long long)front, (long long)back);
    const ew_avert *f0 = front > 0 ? &c : &b, *f1 = front > 0 ? &b : &c;
    CHECK(ew_alias_tri_visible(&a, f0, f1), "front-facing triangle rejected");
    CHECK(!ew_alias_tri_visible(&a, f1, f0), "back-facing triangle accepted");
    ew_avert d = vert(15, 15), e = vert(20, 20), g = vert(12, 12);
    CHECK(ew_alias_cross(&a, &d, &e) == 0 && !ew_alias_tri_visible(&a, &d, &e) &&
              !ew_alias_tri_visible(&a, &e, &d),
          "collinear triangle accepted");
    CHECK(!ew_alias_tri_visible(&a, &a, &g), "two equal vertices accepted");
    /* Neither rasterizer draws what the cross rejects. */
    uint8_t frame[BW * BH];
    float zbuf[BW * BH];
    memset(zbuf, 0, sizeof zbuf);
    ew_araster ra;
    init_araster(&ra, frame, zbuf);
    ew_alias_affine_tri(&ra, &a, f1, f0);
    ew_alias_affine_tri(&ra, &a, &d, &e);
    ew_alias_subdiv_tri(&ra, &a, f1, f0);
    ew_alias_subdiv_tri(&ra, &a, &d, &e);
    CHECK(ra.pixels == 0, "rejected triangles drew %ld pixels", ra.pixels);
    ew_alias_affine_tri(&ra, &a, f0, f1);
    CHECK(ra.pixels > 0, "front triangle drew nothing");
}

/* A planar mesh: a jittered grid, two triangles a cell, all front-facing. */
typedef struct grid {
    int n, npts;
    ew_avert *v;
    ew_mdl_tri *tris;
    int ntris;
} grid;

static int make_grid(grid *g, int cells, int spacing, int jitter) {
    g->n = cells;
    g->npts = (cells + 1) * (cells + 1);
    g->v = malloc(sizeof *g->v * (size_t)g->npts);
    g->tris = malloc(sizeof *g->tris * (size_t)cells * cells * 2);
    g->ntris = 0;
    for (int j = 0; j <= cells; j++)
        for (int i = 0; i <= cells; i++) {
            int jx = i > 0 && i < cells ? rndi(-jitter, jitter) : 0;
            int jy = j > 0 && j < cells ? rndi(-jitter, jitter) : 0;
            g->v[j * (cells + 1) + i] = vert(4 + i * spacing + jx, 4 + j * spacing + jy);
        }
    int ok = 1;
    for (int j = 0; j < cells; j++)
        for (int i = 0; i < cells; i++) {
            int a = j * (cells + 1) + i, b = a + 1, c = a + cells + 2, d = a + cells + 1;
            /* y down: a b c clockwise on screen is a positive cross */
            ew_mdl_tri t1 = {1, {a, b, c}}, t2 = {1, {a, c, d}};
            g->tris[g->ntris++] = t1;
            g->tris[g->ntris++] = t2;
            if (ew_alias_cross(&g->v[a], &g->v[b], &g->v[c]) <= 0 ||
                ew_alias_cross(&g->v[a], &g->v[c], &g->v[d]) <= 0)
                ok = 0;
        }
    return ok;
}

/* Draws the grid; counts[] gets the writes per pixel (a pixel is written
 * when its z changes: every triangle is at the same depth, so a second
 * write is detected by drawing each triangle into a cleared marker). */
static void draw_grid(const grid *g, int subdiv, int *counts, long *pixels) {
    uint8_t *frame = calloc(BW * BH, 1);
    float *zbuf = calloc(BW * BH, sizeof(float));
    ew_araster ra;
    init_araster(&ra, frame, zbuf);
    memset(counts, 0, sizeof(int) * BW * BH);
    *pixels = 0;
    for (int t = 0; t < g->ntris; t++) {
        const ew_mdl_tri *tr = &g->tris[t];
        /* Same depth everywhere: z-test passes always (>=), so every write
         * lands; mark it by a z value unique to the triangle. */
        ew_avert a = g->v[tr->v[0]], b = g->v[tr->v[1]], c = g->v[tr->v[2]];
        a.zi = b.zi = c.zi = 1.0f + t;
        long before = ra.pixels;
        float *snap = malloc(sizeof(float) * BW * BH);
        memcpy(snap, zbuf, sizeof(float) * BW * BH);
        if (subdiv)
            ew_alias_subdiv_tri(&ra, &a, &b, &c);
        else
            ew_alias_affine_tri(&ra, &a, &b, &c);
        for (int i = 0; i < BW * BH; i++)
            if (zbuf[i] != snap[i]) counts[i]++;
        free(snap);
        *pixels += ra.pixels - before;
    }
    free(frame);
    free(zbuf);
}

static void test_mesh_fill(void) {
    int *counts = malloc(sizeof(int) * BW * BH);
    int seeds = 0, raw_dups = 0, raw_pixels = 0;
    for (int trial = 0; trial < 40; trial++) {
        grid g;
        int spacing = 3 + trial % 8, cells = 80 / spacing, ok = 0;
        for (int attempt = 0; attempt < 50 && !ok; attempt++) {
            ok = make_grid(&g, cells, spacing, (spacing - 1) / 2);
            if (!ok) free(g.v), free(g.tris);
        }
        if (!ok) continue;
        seeds++;
        int lo = 4, hi = 4 + cells * spacing;  /* the mesh covers [lo, hi] x [lo, hi] */
        for (int mode = 0; mode < 2; mode++) {  /* affine, subdivision (straight to the frame) */
            long pixels;
            draw_grid(&g, mode, counts, &pixels);
            int dup = 0, gap = 0;
            for (int y = lo + 1; y < hi; y++)
                for (int x = lo + 1; x < hi; x++) {
                    dup += counts[y * BW + x] > 1;
                    gap += counts[y * BW + x] == 0;
                }
            if (mode == 1) {
                raw_dups += dup;
                raw_pixels += (hi - lo - 1) * (hi - lo - 1);
                CHECK(gap == 0, "subdivision left %d gaps, spacing %d", gap, spacing);
            } else {
                CHECK(dup == 0 && gap == 0, "affine: %d pixels twice, %d gaps (spacing %d)", dup, gap, spacing);
            }
        }
        free(g.v), free(g.tris);
    }
    CHECK(seeds >= 20, "only %d valid meshes", seeds);
    /* Folds of rounded split points over a neighbour's edge: rare. */
    CHECK(raw_dups * 1000 < raw_pixels, "subdivision wrote %d of %d pixels twice", raw_dups, raw_pixels);
    printf("planar meshes: %d; the subdivision fill rule alone (no tile) writes %d of %d inner pixels "
           "twice (rounded split points folding over a neighbour), leaves none out\n",
           seeds, raw_dups, raw_pixels);
    free(counts);
}

/* ---- through the pipeline ------------------------------------------------ */

typedef struct scene {
    ew_assets *a;
    ew_renderer *r;
} scene;

static void view_at(ew_renderer *r, float yaw) {
    ew_camera cam = {{0, 0, 0}, {0, yaw, 0}, 90, 0};
    ew_view_setup(&r->f.view, &cam, r->f.target.width, r->f.target.height);
    memset(r->f.target.pixels, 0, (size_t)r->f.target.width * r->f.target.height);
    for (int i = 0; i < r->f.target.width * r->f.target.height; i++) r->f.target.zbuf[i] = 0;
    memset(&r->f.stats, 0, sizeof r->f.stats);
}

static long count_written(const ew_renderer *r) {
    long n = 0;
    for (int i = 0; i < r->f.target.width * r->f.target.height; i++) n += r->f.target.zbuf[i] != 0;
    return n;
}

static ew_mdl *sphere_model(int level, float radius, int frame_group) {
    fx_mesh mesh = fx_icosphere(level);
    fx_mdl_opts o = {32, 32, 0, frame_group, radius};
    size_t size;
    uint8_t *data = fx_mdl(&mesh, &o, &size);
    ew_error err;
    ew_mdl *m = ew_mdl_load(data, size, "sphere.mdl", &err);
    CHECK(m != NULL, "%s", err.msg);
    /* The fixture winds like the game's files: negative signed volume. */
    double vol = 0;
    for (int i = 0; i < mesh.ntris; i++) {
        const float *p0 = mesh.pos[mesh.tri[i][0]], *p1 = mesh.pos[mesh.tri[i][1]], *p2 = mesh.pos[mesh.tri[i][2]];
        vol += p0[0] * (p1[1] * p2[2] - p1[2] * p2[1]) - p0[1] * (p1[0] * p2[2] - p1[2] * p2[0]) +
               p0[2] * (p1[0] * p2[1] - p1[1] * p2[0]);
    }
    CHECK(vol < 0, "fixture winding: volume %g", vol);
    free(data);
    free(mesh.pos), free(mesh.tri);
    return m;
}

static void test_subdiv_sphere(ew_renderer *r) {
    ew_mdl *m = sphere_model(3, 16, 0);
    if (!m) return;
    int W = r->f.target.width, H = r->f.target.height;
    uint8_t *aff = malloc((size_t)W * H);
    int runs = 0, total_missing = 0, total_twice = 0;
    long aff_overlap = 0, missing1 = 0;
    long sum_aff = 0, sum_sub = 0;
    for (int i = 0; i < SPHERE_POSES; i++) {
        ew_model_pose p = {{0}, {0}, 0, 0, 0, 96, 128};
        float dist = 90 + 12 * (i % 15);  /* about 57..20 px across, all on screen */
        p.origin[0] = dist;
        p.origin[1] = (float)rndi(-8, 8);
        p.origin[2] = (float)rndi(-4, 4);
        for (int k = 0; k < 3; k++) p.angles[k] = (float)rndi(0, 359);

        view_at(r, 0);
        r->f.cfg.alias_raster = EW_ALIAS_AFFINE;
        CHECK(ew_draw_alias(r, m, &p) == 1, "sphere culled");
        for (int k = 0; k < W * H; k++) aff[k] = r->f.target.zbuf[k] != 0;
        long naff = count_written(r);
        /* Snapping can fold a nearly edge-on face over its neighbours at the
         * silhouette: the exact fill writes those few pixels twice too. */
        aff_overlap += r->f.stats.alias_pixels - naff;

        view_at(r, 0);
        r->f.cfg.alias_raster = EW_ALIAS_SUBDIV;
        CHECK(ew_draw_alias(r, m, &p) == 1, "sphere culled");
        long nsub = count_written(r);
        int twice = (int)(r->f.stats.alias_pixels - nsub);
        CHECK(r->f.stats.alias_tris_subdiv == r->f.stats.alias_tris && r->f.stats.alias_tris > 100,
              "subdivision drew %d of %d triangles", r->f.stats.alias_tris_subdiv, r->f.stats.alias_tris);
        /* Inside the silhouette: the pixel and its neighbours within 2 pixels
         * are all inside the exact (affine, top-left) coverage.  (Split
         * points of silhouette edges are rounded, so subdivision's outline
         * may differ from the exact one by a pixel; 1-pixel margins are
         * counted for the report.) */
        int missing = 0;
        for (int y = 2; y < H - 2; y++)
            for (int x = 2; x < W - 2; x++) {
                if (r->f.target.zbuf[y * W + x] != 0) continue;
                int in1 = 1, in2 = 1;
                for (int dy = -2; dy <= 2; dy++)
                    for (int dx = -2; dx <= 2; dx++)
                        if (!aff[(y + dy) * W + x + dx]) {
                            in2 = 0;
                            if (dx >= -1 && dx <= 1 && dy >= -1 && dy <= 1) in1 = 0;
                        }
                missing += in2;
                missing1 += in1;
            }
        total_missing += missing;
        total_twice += twice;
        sum_aff += naff, sum_sub += nsub;
        runs++;
    }
    CHECK(total_twice == 0, "subdivision wrote %d pixels more than once", total_twice);
    CHECK(total_missing == 0, "subdivision missed %d pixels inside the silhouette", total_missing);
    double ratio = (double)sum_sub / (double)sum_aff;
    CHECK(ratio > 0.95 && ratio < 1.05, "subdivision covers %.3f of the affine area", ratio);
    printf("sphere (1280 triangles) x %d poses: affine %ld px (%ld written twice where snapped faces "
           "overlap), subdivision %ld px (%.3f), %d written twice, %d missed 2+ px inside the "
           "silhouette (%ld 1 px inside)\n",
           runs, sum_aff, aff_overlap, sum_sub, ratio, total_twice, total_missing, missing1);
    free(aff);
    ew_mdl_free(m);
}

static void test_zbuffer(ew_renderer *r) {
    ew_mdl *m = sphere_model(2, 24, 2);
    if (!m) return;
    int W = r->f.target.width, H = r->f.target.height;
    for (int mode = EW_ALIAS_AFFINE; mode <= EW_ALIAS_SUBDIV; mode++) {
        ew_model_pose p = {{100, 0, 0}, {0, 30, 0}, 0, 0, 0.15, 128, 64};
        /* A wall nearer than the model (at 50 units) everywhere. */
        view_at(r, 0);
        r->f.cfg.alias_raster = mode;
        for (int i = 0; i < W * H; i++) r->f.target.zbuf[i] = 1.0f / 50;
        memset(r->f.target.pixels, 7, (size_t)W * H);
        CHECK(ew_draw_alias(r, m, &p) == 1, "not in view");
        int changed = 0;
        for (int i = 0; i < W * H; i++) changed += r->f.target.pixels[i] != 7 || r->f.target.zbuf[i] != 1.0f / 50;
        CHECK(changed == 0 && r->f.stats.alias_pixels == 0, "mode %d: %d pixels through the wall", mode, changed);
        CHECK(r->f.stats.alias_tris > 0, "mode %d: no triangles", mode);

        /* A wall far behind: the model shows. */
        view_at(r, 0);
        r->f.cfg.alias_raster = mode;
        for (int i = 0; i < W * H; i++) r->f.target.zbuf[i] = 1.0f / 1000;
        memset(r->f.target.pixels, 7, (size_t)W * H);
        ew_draw_alias(r, m, &p);
        long full = r->f.stats.alias_pixels;
        CHECK(full > 500, "mode %d: only %ld pixels in front of a far wall", mode, full);

        /* Near wall on the left half only: only the right half is drawn. */
        view_at(r, 0);
        r->f.cfg.alias_raster = mode;
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) r->f.target.zbuf[y * W + x] = x < W / 2 ? 1.0f / 50 : 1.0f / 1000;
        memset(r->f.target.pixels, 7, (size_t)W * H);
        ew_draw_alias(r, m, &p);
        int left = 0, right = 0;
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                int ch = r->f.target.zbuf[y * W + x] != (x < W / 2 ? 1.0f / 50 : 1.0f / 1000);
                if (x < W / 2) left += ch; else right += ch;
            }
        CHECK(left == 0 && right > full / 4 && right < full, "mode %d: half wall: %d left, %d right of %ld",
              mode, left, right, full);
        CHECK(r->f.stats.alias_pixels == right, "mode %d: %ld counted, %d written", mode, r->f.stats.alias_pixels, right);
    }
    ew_mdl_free(m);
}

static void test_clipping_and_auto(ew_renderer *r) {
    ew_mdl *m = sphere_model(2, 40, 0);
    if (!m) return;
    int W = r->f.target.width, H = r->f.target.height;
    /* Straddling the near plane and every screen edge; off to each side. */
    float spots[][3] = {{30, 45, 0}, {30, 0, 45}, {30, -30, -30}, {60, 70, 0}, {60, -70, 0}, {60, 0, 50},
                        {60, 0, -50}, {5, 0, 0}, {-100, 0, 0}, {300, 0, 0}};
    for (int i = 0; i < (int)(sizeof spots / sizeof spots[0]); i++) {
        for (int mode = EW_ALIAS_AUTO; mode <= EW_ALIAS_SUBDIV; mode++) {
            ew_model_pose p = {{spots[i][0], spots[i][1], spots[i][2]}, {10, 20, 30}, 0, 0, 0, 200, 50};
            view_at(r, 0);
            r->f.cfg.alias_raster = mode;
            int drawn = ew_draw_alias(r, m, &p);
            long n = count_written(r);
            if (spots[i][0] < 0) {
                CHECK(drawn == 0 && n == 0, "behind the eye: drawn %d, %ld px", drawn, n);
            } else if (spots[i][0] >= 20) {
                CHECK(drawn == 1 && n > 0 && r->f.stats.alias_pixels == n,
                      "spot %d mode %d: drawn %d, %ld px, %ld counted", i, mode, drawn, n, r->f.stats.alias_pixels);
            }
        }
    }
    /* Automatic choice by projected height (threshold 40 px at 320 wide). */
    r->f.cfg.alias_threshold = 40;
    ew_model_pose far = {{600, 0, 0}, {0, 0, 0}, 0, 0, 0, 128, 64};
    ew_model_pose close = {{120, 0, 0}, {0, 0, 0}, 0, 0, 0, 128, 64};
    view_at(r, 0);
    r->f.cfg.alias_raster = EW_ALIAS_AUTO;
    ew_draw_alias(r, m, &far);
    CHECK(r->f.stats.alias_tris > 0 && r->f.stats.alias_tris_subdiv == r->f.stats.alias_tris,
          "far model: %d of %d subdivided", r->f.stats.alias_tris_subdiv, r->f.stats.alias_tris);
    view_at(r, 0);
    ew_draw_alias(r, m, &close);
    CHECK(r->f.stats.alias_tris > 0 && r->f.stats.alias_tris_subdiv == 0, "near model: %d of %d subdivided",
          r->f.stats.alias_tris_subdiv, r->f.stats.alias_tris);
    /* Forced subdivision of a model that needs clipping falls back to the
     * affine clip path (subdivision needs every vertex on screen). */
    view_at(r, 0);
    r->f.cfg.alias_raster = EW_ALIAS_SUBDIV;
    ew_model_pose edge = {{60, 70, 0}, {0, 0, 0}, 0, 0, 0, 128, 64};
    ew_draw_alias(r, m, &edge);
    CHECK(r->f.stats.alias_tris > 0 && r->f.stats.alias_tris_subdiv == 0, "clipped model subdivided");
    /* Bad poses are refused, not drawn. */
    ew_model_pose bad = {{NAN, 0, 0}, {0, 0, 0}, 0, 0, 0, 128, 64};
    CHECK(ew_draw_alias(r, m, &bad) == 0, "NaN origin drawn");
    ew_model_pose wild = {{100, 0, 0}, {0, 0, 0}, 99999, -5, -1e300, 128, 64};
    view_at(r, 0);
    CHECK(ew_draw_alias(r, m, &wild) == 1 && count_written(r) > 0, "out-of-range frame/skin not clamped");
    (void)W, (void)H;
    ew_mdl_free(m);
}

/* Culling through the pipeline: a front triangle, the same one reversed,
 * and one with zero area; only the first is drawn. */
static void test_cull_counts(ew_renderer *r) {
    fx_mesh mesh;
    float pos[6][3] = {{0, 0.5f, -0.5f}, {0, 0, 0.5f}, {0, -0.5f, -0.5f},  /* across the view */
                       {0, 0, -0.5f}, {0, 0, 0}, {0, 0, 0.5f}};            /* collinear, vertical */
    int tri[3][3] = {{0, 2, 1}, {0, 1, 2}, {3, 4, 5}};
    mesh.nverts = 6, mesh.ntris = 3, mesh.pos = pos, mesh.tri = tri;
    fx_mdl_opts o = {8, 8, 0, 0, 30};
    size_t size;
    uint8_t *data = fx_mdl(&mesh, &o, &size);
    ew_error err;
    ew_mdl *m = ew_mdl_load(data, size, "cull.mdl", &err);
    CHECK(m != NULL, "%s", err.msg);
    free(data);
    if (!m) return;
    for (int mode = EW_ALIAS_AFFINE; mode <= EW_ALIAS_SUBDIV; mode++) {
        view_at(r, 0);
        r->f.cfg.alias_raster = mode;
        ew_model_pose p = {{100, 0, 0}, {0, 0, 0}, 0, 0, 0, 128, 0};
        ew_draw_alias(r, m, &p);
        CHECK(r->f.stats.alias_tris == 1 && r->f.stats.alias_pixels > 20,
              "mode %d: %d triangles drawn (%ld px), want 1", mode, r->f.stats.alias_tris, r->f.stats.alias_pixels);
        /* Turned around, the other one faces the eye. */
        view_at(r, 0);
        p.angles[1] = 180;
        ew_draw_alias(r, m, &p);
        CHECK(r->f.stats.alias_tris == 1, "mode %d turned: %d triangles drawn", mode, r->f.stats.alias_tris);
    }
    ew_mdl_free(m);
}

static void test_sprites_particles(ew_renderer *r) {
    int W = r->f.target.width, H = r->f.target.height;
    for (int type = 0; type <= 4; type++) {
        size_t size;
        uint8_t *data = fx_spr(type, 32, 24, 2, 3, &size);
        ew_error err;
        ew_spr *s = ew_spr_load(data, size, "t.spr", &err);
        CHECK(s != NULL, "%s", err.msg);
        free(data);
        if (!s) continue;
        ew_model_pose p = {{100, 0, 0}, {0, 180, 0}, 0, 0, 0, 0, 0};
        view_at(r, 0);
        CHECK(ew_draw_sprite(r, s, &p) == 1, "type %d sprite not drawn", type);
        long n = count_written(r);
        /* 32x24 units at 100 units on a 320-wide 90-degree view: 160 px per
         * 100 units, so about 51x38 pixels less the transparent column. */
        CHECK(n > 1200 && n < 2400 && r->f.stats.alias_pixels == n, "type %d: %ld pixels", type, n);
        int has255 = 0;
        for (int i = 0; i < W * H; i++) has255 |= r->f.target.zbuf[i] != 0 && r->f.target.pixels[i] == 255;
        CHECK(!has255, "transparent index drawn");
        /* The group animates by time: a different picture at t = 0.07. */
        p.frame = 2;
        p.time = 0.01;
        view_at(r, 0);
        ew_draw_sprite(r, s, &p);
        int c0 = r->f.target.pixels[(H / 2) * W + W / 2];
        p.time = 0.07;
        view_at(r, 0);
        ew_draw_sprite(r, s, &p);
        int c1 = r->f.target.pixels[(H / 2) * W + W / 2];
        CHECK(c0 == 102 && c1 == 103, "group pictures %d %d", c0, c1);
        /* Behind a near wall: nothing. */
        view_at(r, 0);
        for (int i = 0; i < W * H; i++) r->f.target.zbuf[i] = 1.0f / 50;
        ew_draw_sprite(r, s, &p);
        CHECK(r->f.stats.alias_pixels == 0, "sprite through a wall");
        /* Behind the eye: culled. */
        ew_model_pose back = {{-100, 0, 0}, {0, 0, 0}, 0, 0, 0, 0, 0};
        view_at(r, 0);
        CHECK(ew_draw_sprite(r, s, &back) == 0 && count_written(r) == 0, "sprite behind the eye drawn");
        /* Straddling the eye: clipped, no crash. */
        ew_model_pose close = {{0.5f, 0, 0}, {0, 90, 0}, 0, 0, 0, 0, 0};
        view_at(r, 0);
        ew_draw_sprite(r, s, &close);
        ew_spr_free(s);
    }
    /* Particles: deterministic field, sizes shrink with distance. */
    ew_particle a[500], b[500];
    float c[3] = {150, 0, 0};
    CHECK(ew_particle_field(a, 500, c, 40, 7) == 500 && ew_particle_field(b, 500, c, 40, 7) == 500,
          "particle field");
    int same = 1;
    for (int i = 0; i < 500; i++)
        same &= !memcmp(a[i].org, b[i].org, sizeof a[i].org) && a[i].color == b[i].color;
    CHECK(same, "same seed, different field");
    ew_particle_field(b, 500, c, 40, 8);
    same = 1;
    for (int i = 0; i < 500; i++) same &= !memcmp(a[i].org, b[i].org, sizeof a[i].org);
    CHECK(!same, "different seeds, same field");
    int inside = 1;
    for (int i = 0; i < 500; i++) {
        float d = 0;
        for (int k = 0; k < 3; k++) d += (a[i].org[k] - c[k]) * (a[i].org[k] - c[k]);
        inside &= d <= 40.01f * 40.01f;
    }
    CHECK(inside, "particle outside the ball");
    view_at(r, 0);
    ew_draw_particles(r, a, 500);
    CHECK(r->f.stats.particles == 500 && r->f.stats.alias_pixels > 400 && count_written(r) > 400, "%d particles, %ld px",
          r->f.stats.particles, r->f.stats.alias_pixels);
    ew_particle one[2] = {{{30, 0, 0}, 5}, {{400, 0, 0}, 6}};
    view_at(r, 0);
    ew_draw_particles(r, one, 1);
    long near_px = count_written(r);
    view_at(r, 0);
    ew_draw_particles(r, one + 1, 1);
    long far_px = count_written(r);
    /* 320 wide: 100 / z pixels (2 at 100 units on a 640-wide view): 3x3 at 30 units, 1 at 400 */
    CHECK(near_px == 9 && far_px == 1, "particle sizes %ld near, %ld far", near_px, far_px);
    view_at(r, 0);
    for (int i = 0; i < W * H; i++) r->f.target.zbuf[i] = 1.0f / 50;
    ew_draw_particles(r, a, 500);
    CHECK(r->f.stats.alias_pixels == 0, "particles through a wall");
}

int main(void) {
    for (int i = 0; i < 256; i++) test_skin[i] = (uint8_t)(i * 7 + 1);
    for (int i = 0; i < 64 * 256; i++) test_cmap[i] = (uint8_t)(i & 255);
    test_affine_reference();
    test_cross_culls();
    test_mesh_fill();

    scene sc = { NULL, NULL };
    ew_error err;
    CHECK((sc.a = ew_assets_create_builtin(&err)) != NULL, "%s", err.msg);
    if (sc.a) sc.r = ew_renderer_create(&(ew_renderer_desc){ .world = sc.a->world, .palette = sc.a->palette,
            .colormap = sc.a->colormap, .width = 320, .height = 200, .threads = 1 }, &err);
    CHECK(sc.r != NULL, "%s", err.msg);
    if (sc.r) {
        test_subdiv_sphere(sc.r);
        test_zbuffer(sc.r);
        test_clipping_and_auto(sc.r);
        test_cull_counts(sc.r);
        test_sprites_particles(sc.r);
        ew_renderer_destroy(sc.r);
    }
    ew_assets_destroy(sc.a);
    return ew_t_finish();
}
