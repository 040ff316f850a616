/* Z-buffered hidden-surface removal: polygons front to back, each pixel's
 * 1/z (from the polygon's plane) tested against a depth buffer and written
 * where nearer.  Row by row, each row's polygons in turn (the rows do not
 * depend on each other, so this is the polygon-by-polygon result).  Runs of passing pixels become spans, drawn in
 * the order made (later over earlier: a later pass is nearer), so pixels
 * may be written more than once where the order is not the depth order.
 * The polygons, their order and their pixels are the edge list's
 * (hsr/poly_rows.h); ties in 1/z go to the one drawn first, the nearer in
 * BSP order. */
#include "hsr/poly_rows.h"
#include "raster/raster.h"  /* ew_face_gradients */

#include <string.h>

enum { C_TESTS, C_PASSES, C_SPANS };

/* The edge list's face, with its 1/z plane kept on the surface (the edge
 * list fills it for brush-model fragments only). */
static void zb_face(ew_hsr_ctx *c, int face, int clipflags, int key) {
    int s = c->el->nsurfs;
    ew_edge_face(c, face, clipflags, key);
    if (c->el->nsurfs == s) return;  /* clipped away, or no room */
    ew_surf *sf = &c->el->surfs[s];
    ew_gradients g;
    ew_face_gradients(c->f->world, sf->view, &c->f->world->faces[face], 0, &g);
    sf->zi_u = g.zi_u, sf->zi_v = g.zi_v, sf->zi_0 = g.zi_0;
}

static void zb_resolve(const ew_hsr_ctx *ctx, ew_band *b) {
    const int width = ctx->f->target.width;
    ew_poly_rows pr;
    /* The rows are resolved one after another: one row of depth is all
     * the buffer ever needs. */
    float *zr = ew_poly_rows_begin(&pr, ctx, b, sizeof(float) * (size_t)width);
    if (!zr) {
        ew_poly_rows_background(b, width);
        return;
    }
    b->unsorted = 1;
    long *c = b->counters;
    while (ew_poly_rows_next(&pr)) {
        const int v = pr.v;
        memset(zr, 0, sizeof(float) * (size_t)width);  /* 0: nothing drawn, farther than any polygon */
        for (int i = 0; i < pr.nrow; i++) {
            const ew_row_poly *rp = &pr.row[i];
            const ew_surf *sf = &ctx->el->surfs[rp->surf];
            const float zv = sf->zi_v * v + sf->zi_0, du = sf->zi_u;
            c[C_TESTS] += rp->xr - rp->xl;
            int run = -1;
            for (int x = rp->xl; x < rp->xr; x++) {
                float zi = du * x + zv;  /* from the plane at every pixel, as the z-fill has it */
                if (zi > zr[x]) {
                    zr[x] = zi;
                    c[C_PASSES]++;
                    if (run < 0) run = x;
                } else if (run >= 0) {
                    ew_band_span(b, rp->surf, run, x, v), c[C_SPANS]++;
                    run = -1;
                }
            }
            if (run >= 0) ew_band_span(b, rp->surf, run, rp->xr, v), c[C_SPANS]++;
        }
        /* What no polygon covered: the background. */
        for (int x = 0; x < width;) {
            if (zr[x] != 0) {
                x++;
                continue;
            }
            int x0 = x;
            while (x < width && zr[x] == 0) x++;
            ew_band_span(b, 0, x0, x, v);
        }
    }
}

const ew_hsr ew_hsr_zbuffer = {"zbuffer", EW_HSR_MAKES_SPANS, ew_edge_begin, zb_face, ew_edge_poly, NULL, zb_resolve,
                               ew_poly_rows_memory, {"depth tests", "depth passes", "spans made"}};
