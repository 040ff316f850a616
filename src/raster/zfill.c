/* Deferred z-fill (raster/zfill.h): each row remembers the interval of
 * the world's 1/z already filled this frame; requests widen it.  The values
 * are those of ew_zfill_span (the same formula), so bit for bit. */
#include "raster/zfill.h"

void ew_zfill_span(const ew_target *t, const ew_span *sp, const ew_gradients *g) {
    float *z = ew_target_z(t, sp->u, sp->v);
    /* Each value from the start, not accumulated: exact and vectorizable. */
    float zi = g->zi_u * sp->u + g->zi_v * sp->v + g->zi_0, dz = g->zi_u;
    for (int i = 0; i < sp->count; i++) z[i] = zi + (float)i * dz;
}

int ew_zfill_row_spans(const ew_zfill *z, int y, int lo, const ew_span **first, int *sorted) {
    int n = z->row_nspans[y];
    if (n == 0) return 0;  /* no spans (yet, or their bands are gone) */
    const ew_band *b = &z->bands[z->row_band[y]];
    const ew_span *sp = b->spans + z->row_span0[y];
    *sorted = !b->unsorted;
    if (*sorted && n > 8) {
        /* Disjoint and in order, they end in order too: skip to the first
         * that ends past lo by halving (a model's box is a few of a row's
         * many spans). */
        int l = 0, h = n;
        while (l < h) {
            int mid = (l + h) / 2;
            if (sp[mid].u + sp[mid].count > lo) h = mid;
            else l = mid + 1;
        }
        sp += l, n -= l;
    }
    *first = sp;
    return n;
}

/* World 1/z over [lo, hi) of row y from the spans that cover it. */
static void zfill_row(ew_zfill *z, int y, int lo, int hi) {
    const ew_span *sp;
    int sorted, n = ew_zfill_row_spans(z, y, lo, &sp, &sorted);
    float *zr = z->target->zbuf + (size_t)y * z->target->width;
    for (int i = 0; i < n; i++, sp++) {
        if (sp->u >= hi && sorted) break;
        int a = sp->u > lo ? sp->u : lo, e = sp->u + sp->count < hi ? sp->u + sp->count : hi;
        if (a >= e) continue;
        const ew_gradients *g = &z->draw[sp->surf].g;
        float zi = g->zi_u * sp->u + g->zi_v * sp->v + g->zi_0, dz = g->zi_u;
        for (int x = a; x < e; x++) zr[x] = zi + (float)(x - sp->u) * dz;
    }
}

void ew_zfill_rect(ew_zfill *z, int x0, int y0, int x1, int y1) {
    if (z->all) return;
    if (x0 < 0) x0 = 0;
    if (y0 < 0) y0 = 0;
    if (x1 > z->target->width) x1 = z->target->width;
    if (y1 > z->target->height) y1 = z->target->height;
    if (x0 >= x1) return;
    for (int y = y0; y < y1; y++) {
        int lo = z->zlo[y], hi = z->zhi[y];
        if (lo >= hi) {
            zfill_row(z, y, x0, x1);
            z->zlo[y] = x0, z->zhi[y] = x1;
            continue;
        }
        if (x0 < lo) zfill_row(z, y, x0, lo), z->zlo[y] = x0;
        if (x1 > hi) zfill_row(z, y, hi, x1), z->zhi[y] = x1;
    }
}

void ew_zfill_index_band(ew_zfill *z, const ew_band *b, int band) {
    for (int y = b->y0; y < b->y1; y++) {
        z->row_band[y] = band, z->row_nspans[y] = 0, z->row_span0[y] = 0;
        z->zlo[y] = z->zhi[y] = 0;
    }
    /* A row's spans come together (hsr/hsr.h), so each run of one row is
     * counted at once rather than span by span; the same counts and first
     * spans, however the rows come. */
    const ew_span *sp = b->spans;
    for (int i = 0, n = b->nspans; i < n;) {
        int y = sp[i].v, j = i + 1;
        while (j < n && sp[j].v == y) j++;
        if (y >= b->y0 && y < b->y1) {
            if (z->row_nspans[y] == 0) z->row_span0[y] = i;
            z->row_nspans[y] += j - i;
        }
        i = j;
    }
}

void ew_zfill_mark_all(ew_zfill *z) {
    for (int y = 0; y < z->target->height; y++) z->zlo[y] = 0, z->zhi[y] = z->target->width;
}
