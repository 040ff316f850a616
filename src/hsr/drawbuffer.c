/* The draw-buffer: like a z-buffer with one bit per pixel, set when the
 * pixel is drawn.  Polygons go front to back, so a pixel already drawn is
 * nearer and a set bit means skip; a new polygon's span is walked bit by
 * bit, except that on a whole byte of the buffer it is tested a byte at a
 * time: 8 drawn pixels skipped at once, 8 free ones taken at once (the
 * variation the Black Book mentions).  Every pixel is written exactly once.
 * Row by row, each row's polygons in turn (the rows do not depend on each
 * other, so this is the polygon-by-polygon result).
 * The polygons, their order and their pixels are the edge list's
 * (hsr/poly_rows.h). */
#include "hsr/poly_rows.h"

#include <string.h>

enum { C_BITS, C_SKIPPED, C_FILLED, C_SPANS };

static void db_resolve(const ew_hsr_ctx *ctx, ew_band *b) {
    const int width = ctx->f->target.width, stride = (width + 7) / 8;
    ew_poly_rows pr;
    /* The rows are resolved one after another: one row of bits is all the
     * buffer ever needs. */
    size_t pieces_at = ((size_t)stride + 15) & ~(size_t)15;
    uint8_t *row = ew_poly_rows_begin(&pr, ctx, b, pieces_at + sizeof(ew_row_poly) * (size_t)(width + 1));
    if (!row) {
        ew_poly_rows_background(b, width);
        return;
    }
    ew_row_poly *pieces = (ew_row_poly *)(void *)(row + pieces_at);
    long *c = b->counters;
    while (ew_poly_rows_next(&pr)) {
        memset(row, 0, (size_t)stride);
        int np = 0;
        for (int i = 0; i < pr.nrow; i++) {
            const ew_row_poly *rp = &pr.row[i];
            const int s = rp->surf, xr = rp->xr;
            int run = -1;
            c[C_SPANS]++;
            for (int x = rp->xl; x < xr;) {
                uint8_t *by = &row[x >> 3];
                if ((x & 7) == 0 && x + 8 <= xr && (*by == 0xFF || *by == 0)) {
                    if (*by == 0xFF) {  /* 8 drawn: skipped */
                        if (run >= 0) pieces[np++] = (ew_row_poly){s, run, x}, run = -1;
                        c[C_SKIPPED]++;
                    } else {            /* 8 free: taken */
                        *by = 0xFF;
                        if (run < 0) run = x;
                        c[C_FILLED]++;
                    }
                    x += 8;
                    continue;
                }
                const uint8_t bit = (uint8_t)(1u << (x & 7));
                c[C_BITS]++;
                if (*by & bit) {
                    if (run >= 0) pieces[np++] = (ew_row_poly){s, run, x}, run = -1;
                } else {
                    *by |= bit;
                    if (run < 0) run = x;
                }
                x++;
            }
            if (run >= 0) pieces[np++] = (ew_row_poly){s, run, xr};
        }
        ew_poly_rows_emit_sorted(&pr, pieces, np);
    }
}

const ew_hsr ew_hsr_drawbuffer = {"drawbuffer", EW_HSR_EDGE_LIST | EW_HSR_MAKES_SPANS | EW_HSR_EXACT_ONCE,
                                  ew_edge_begin, ew_edge_face, ew_edge_poly, NULL, db_resolve, ew_poly_rows_memory,
                                  {"bits tested", "bytes skipped", "bytes filled", "polygon spans"}};
