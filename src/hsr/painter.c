/* The painter's algorithm: polygons back to front in BSP order, every one
 * drawn whole over what is behind it, the background first.  Nothing is
 * tested, and every hidden pixel is drawn anyway: the overdraw the Black
 * Book warns of (ew_stats.overdraw).  The polygons, their order and their
 * pixels are the edge list's (hsr/poly_rows.h). */
#include "hsr/poly_rows.h"

enum { C_POLYS, C_SPANS, C_PIXELS };

static void painter_resolve(const ew_hsr_ctx *c, ew_band *b) {
    const int width = c->f->target.width;
    ew_poly_rows pr;
    if (!ew_poly_rows_begin(&pr, c, b, 0)) {
        ew_poly_rows_background(b, width);
        return;
    }
    b->unsorted = 1;
    long *n = b->counters;
    for (int i = 0; i < pr.nband; i++) n[C_POLYS] += ew_poly_rows_starts_here(&pr, pr.order[i]);
    while (ew_poly_rows_next(&pr)) {
        ew_band_span(b, 0, 0, width, pr.v);
        for (int i = pr.nrow - 1; i >= 0; i--) {
            const ew_row_poly *rp = &pr.row[i];
            ew_band_span(b, rp->surf, rp->xl, rp->xr, pr.v);
            n[C_SPANS]++, n[C_PIXELS] += rp->xr - rp->xl;
        }
    }
}

const ew_hsr ew_hsr_painter = {"painter", EW_HSR_EDGE_LIST | EW_HSR_MAKES_SPANS, ew_edge_begin, ew_edge_face,
                               ew_edge_poly, NULL, painter_resolve, ew_poly_rows_memory,
                               {"polygons drawn", "spans drawn", "pixels drawn"}};
