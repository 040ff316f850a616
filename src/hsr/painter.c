/* The painter's algorithm: polygons back to front in BSP order, every one
 * drawn whole over what is behind it, the background first.  Nothing is
 * tested, and every hidden pixel is drawn anyway: the overdraw the Black
 * Book warns of (ew_stats.overdraw).  The polygons, their order and their
 * pixels are the edge list's (hsr/poly_rows.h). */
#include "hsr/poly_rows.h"
#include "renderer.h"

enum { C_POLYS, C_SPANS, C_PIXELS };

static void painter_resolve(ew_renderer *r, ew_band *b) {
    const int width = r->f.target.width;
    ew_poly_rows pr;
    if (!ew_poly_rows_begin(&pr, r, b, 0)) {
        ew_poly_rows_background(b, width);
        return;
    }
    b->unsorted = 1;
    long *c = b->counters;
    for (int i = 0; i < pr.nband; i++) c[C_POLYS] += ew_poly_rows_starts_here(&pr, pr.order[i]);
    while (ew_poly_rows_next(&pr)) {
        ew_band_span(b, 0, 0, width, pr.v);
        for (int i = pr.nrow - 1; i >= 0; i--) {
            const ew_row_poly *rp = &pr.row[i];
            ew_band_span(b, rp->surf, rp->xl, rp->xr, pr.v);
            c[C_SPANS]++, c[C_PIXELS] += rp->xr - rp->xl;
        }
    }
}

static size_t painter_memory(const ew_renderer *r) { return ew_poly_rows_memory(r); }

const ew_hsr ew_hsr_painter = {"painter", ew_edge_begin, ew_emit_face, ew_emit_poly, painter_resolve, 0,
                               {"polygons drawn", "spans drawn", "pixels drawn"}, 0, painter_memory, NULL, 0};
