/* Span-based hidden-surface removal (the Black Book's "sorted spans" by
 * polygon): polygons are walked front to back and rasterized into spans;
 * each row keeps the list of spans already drawn, sorted by x, and a new
 * span is clipped against it, so only the pixels no nearer polygon took
 * are written.  Every pixel is written exactly once.  Row by row, each
 * row's polygons in turn (the rows do not depend on each other, so this is
 * the polygon-by-polygon result, with one row's list at a time).  The
 * polygons, their order and their pixels are the edge list's
 * (hsr/poly_rows.h). */
#include "hsr/poly_rows.h"

#include <string.h>

typedef struct drawn { int32_t u0, u1; } drawn;

enum { C_POLY, C_CLIPPED, C_HIDDEN, C_ENTRIES };

/* Clips [xl, xr) of surface s against the row's drawn list d (sorted,
 * disjoint, never touching), appends what is left to p, and merges the
 * span into d.  Returns the pieces appended. */
static int clip_span(drawn *d, int *nd, int s, int xl, int xr, ew_row_poly *p, long *visited) {
    int i = 0, n = *nd;
    /* the first drawn span that reaches xl (touching counts: it merges) */
    while (i < n && d[i].u1 < xl) i++;
    int j = i, cur = xl, np = 0;
    for (; j < n && d[j].u0 <= xr; j++) {
        if (d[j].u0 > cur) p[np++] = (ew_row_poly){s, cur, d[j].u0 < xr ? d[j].u0 : xr};
        if (d[j].u1 > cur) cur = d[j].u1;
    }
    *visited += j + (j < n);  /* every entry looked at, the one that stopped the walk too */
    if (cur < xr) p[np++] = (ew_row_poly){s, cur, xr};
    /* d[i, j) and the new span become one drawn span */
    drawn m = {xl, xr};
    if (j > i) {
        if (d[i].u0 < m.u0) m.u0 = d[i].u0;
        if (d[j - 1].u1 > m.u1) m.u1 = d[j - 1].u1;
    }
    int removed = j - i;
    if (removed == 0) {
        memmove(d + i + 1, d + i, sizeof *d * (size_t)(n - i));
        n++;
    } else if (removed > 1) {
        memmove(d + i + 1, d + j, sizeof *d * (size_t)(n - j));
        n -= removed - 1;
    }
    d[i] = m;
    *nd = n;
    return np;
}

static void spans_resolve(const ew_hsr_ctx *ctx, ew_band *b) {
    const int width = ctx->f->target.width;
    const int maxd = width / 2 + 2;
    ew_poly_rows pr;
    char *m = ew_poly_rows_begin(&pr, ctx, b, sizeof(drawn) * (size_t)maxd + sizeof(ew_row_poly) * (size_t)(width + 1));
    if (!m) {
        ew_poly_rows_background(b, width);
        return;
    }
    drawn *d = (drawn *)(void *)m;
    ew_row_poly *pieces = (ew_row_poly *)(void *)(m + sizeof(drawn) * (size_t)maxd);
    long *c = b->counters;
    while (ew_poly_rows_next(&pr)) {
        int nd = 0, np = 0;
        for (int i = 0; i < pr.nrow; i++) {
            const ew_row_poly *rp = &pr.row[i];
            c[C_POLY]++;
            int got = clip_span(d, &nd, rp->surf, rp->xl, rp->xr, pieces + np, &c[C_ENTRIES]);
            if (got != 1 || pieces[np].xl != rp->xl || pieces[np].xr != rp->xr) c[C_CLIPPED]++;
            if (got == 0) c[C_HIDDEN]++;
            np += got;
            if (nd == 1 && d[0].u0 == 0 && d[0].u1 == width) break;  /* the row is full */
        }
        ew_poly_rows_emit_sorted(&pr, pieces, np);
    }
}

const ew_hsr ew_hsr_spans = {"spans", EW_HSR_EDGE_LIST | EW_HSR_MAKES_SPANS | EW_HSR_EXACT_ONCE, ew_edge_begin,
                             ew_edge_face, ew_edge_poly, NULL, spans_resolve, ew_poly_rows_memory,
                             {"polygon spans", "spans clipped", "spans hidden", "span list entries"}};
