/* The edge list's polygons row by row, front to back (hsr/poly_rows.h). */
#include "hsr/poly_rows.h"

#include <stdlib.h>
#include <string.h>

/* Front-to-back order: BSP key, smaller nearer; brush-model fragments that
 * share a key (one leaf) after the world's faces, by their nearest 1/z
 * for a start (each row sorts them again: order_run); then the surface
 * number, so the order is total and the same in every band. */
typedef struct sort_item {
    int   key, sub;
    float zi;
    int   s;
} sort_item;

static int cmp_item(const void *pa, const void *pb) {
    const sort_item *a = pa, *b = pb;
    if (a->key != b->key) return a->key < b->key ? -1 : 1;
    if (a->sub != b->sub) return a->sub < b->sub ? -1 : 1;
    if (a->zi != b->zi) return a->zi > b->zi ? -1 : 1;
    return (a->s > b->s) - (a->s < b->s);
}

static size_t align16(size_t n) { return (n + 15) & ~(size_t)15; }

void *ew_poly_rows_begin(ew_poly_rows *pr, const ew_hsr_ctx *c, ew_band *b, size_t extra) {
    const ew_edge_list *el = c->el;
    const int ns = el->nsurfs, ne = el->nedges, rows = b->y1 - b->y0;
    memset(pr, 0, sizeof *pr);
    pr->el = el, pr->b = b, pr->width = c->f->target.width, pr->v = b->y0 - 1;
    b->nspans = 0;
    memset(b->has_spans, 0, (size_t)ns);

    /* One block: the index, the order and the row list, then the method's
     * part; all of it rebuilt every frame. */
    const size_t i32 = sizeof(int32_t);
    size_t off[12], at = 16;  /* first the bytes used this frame (ew_poly_rows_memory) */
    const size_t len[12] = {i32 * (size_t)(ns + 1), i32 * 2 * (size_t)ne, i32 * (size_t)ns, i32 * (size_t)ns,
                            i32 * (size_t)ns,       i32 * (size_t)ns,     i32 * (size_t)(rows + 1), i32 * (size_t)ns,
                            i32 * (size_t)ns,       i32 * (size_t)ns,     i32 * (size_t)ns,
                            sizeof(ew_row_poly) * (size_t)(2 * ns + 64)};
    for (int k = 0; k < 12; k++) off[k] = at, at += align16(len[k]);
    size_t method_at = at;
    size_t total = at + align16(extra);
    char *m = ew_band_scratch(b, total);
    if (!m) {
        b->dropped++;
        return NULL;
    }
    *(size_t *)(void *)m = total;
    pr->first = (int32_t *)(void *)(m + off[0]);
    pr->ent = (int32_t *)(void *)(m + off[1]);
    pr->order = (int32_t *)(void *)(m + off[2]);
    pr->top = (int32_t *)(void *)(m + off[3]);
    pr->bot = (int32_t *)(void *)(m + off[4]);
    pr->vmin = (int32_t *)(void *)(m + off[5]);
    pr->head = (int32_t *)(void *)(m + off[6]);
    pr->next = (int32_t *)(void *)(m + off[7]);
    pr->act = (int32_t *)(void *)(m + off[8]);
    pr->act2 = (int32_t *)(void *)(m + off[9]);
    pr->rank = (int32_t *)(void *)(m + off[10]);
    pr->row = (ew_row_poly *)(void *)(m + off[11]);
    pr->cap_row = 2 * ns + 64;

    /* Each surface's edges that cross the band (counting sort by surface). */
    int32_t *first = pr->first;
    memset(first, 0, i32 * (size_t)(ns + 1));
    for (int s = 0; s < ns; s++) pr->top[s] = INT32_MAX, pr->bot[s] = -1, pr->vmin[s] = INT32_MAX;
    const ew_edge *edges = el->edges;
    for (int i = 0; i < ne; i++) {
        const ew_edge *e = &edges[i];
        /* the surface's first row over the whole frame: edges can end and
         * begin at a band's first row on both sides at once */
        for (int k = 0; k < 2; k++)
            if (e->v_first < pr->vmin[e->surfs[k]]) pr->vmin[e->surfs[k]] = e->v_first;
        if (e->v_last < b->y0 || e->v_first >= b->y1) continue;
        for (int k = 0; k < 2; k++) {
            int s = e->surfs[k];
            if (!s) continue;
            first[s + 1]++;
            int t = e->v_first > b->y0 ? e->v_first : b->y0, u = e->v_last < b->y1 - 1 ? e->v_last : b->y1 - 1;
            if (t < pr->top[s]) pr->top[s] = t;
            if (u > pr->bot[s]) pr->bot[s] = u;
        }
    }
    for (int s = 0; s < ns; s++) first[s + 1] += first[s];
    /* Fill with next[] as the cursor (it is rebuilt below). */
    int32_t *cur = pr->next;
    memcpy(cur, first, i32 * (size_t)ns);
    for (int i = 0; i < ne; i++) {
        const ew_edge *e = &edges[i];
        if (e->v_last < b->y0 || e->v_first >= b->y1) continue;
        for (int k = 0; k < 2; k++)
            if (e->surfs[k]) pr->ent[cur[e->surfs[k]]++] = i << 1 | k;
    }

    /* The band's surfaces front to back.  The sort items borrow the row
     * list's room (at least 2 * ns items of 12 bytes: enough for ns of 16). */
    sort_item *items = (sort_item *)(void *)pr->row;
    int n = 0;
    for (int s = 1; s < ns; s++) {
        if (first[s + 1] == first[s]) continue;
        const ew_surf *sf = &el->surfs[s];
        items[n++] = (sort_item){sf->key, sf->insubmodel, sf->insubmodel ? sf->nearzi : 0, s};
    }
    qsort(items, (size_t)n, sizeof *items, cmp_item);
    for (int i = 0; i < n; i++) pr->order[i] = items[i].s, pr->rank[items[i].s] = i;
    pr->nband = n;

    /* Surfaces by first row, each list front to back (pushed back to front). */
    for (int y = 0; y <= rows; y++) pr->head[y] = -1;
    for (int i = n - 1; i >= 0; i--) {
        int s = pr->order[i];
        int y = pr->top[s] - b->y0;
        pr->next[s] = pr->head[y];
        pr->head[y] = s;
    }
    return m + method_at;
}

void ew_poly_rows_background(ew_band *b, int width) {
    for (int v = b->y0; v < b->y1; v++) ew_band_span(b, 0, 0, width, v);
}

int ew_poly_rows_starts_here(const ew_poly_rows *pr, int s) { return pr->vmin[s] >= pr->b->y0; }

/* Surface s on row v: the pixels the edge scan gives it when alone.  The
 * scan counts a surface's leading edges up and its trailing edges down, at
 * the first pixel centre right of each edge; the surface is present where
 * the count is at least 1.  A convex polygon has one of each (the common
 * case); inconsistent edges may give any number, handled the same way. */
static int surf_row(const ew_poly_rows *pr, int s, int v, ew_row_poly *out, int max) {
    const ew_edge *edges = pr->el->edges;
    int xs[EW_MAX_POLY], ds[EW_MAX_POLY], n = 0;
    const int width = pr->width;
    for (int k = pr->first[s]; k < pr->first[s + 1] && n < EW_MAX_POLY; k++) {
        const ew_edge *e = &edges[pr->ent[k] >> 1];
        if (v < e->v_first || v > e->v_last) continue;
        int64_t u = (int64_t)e->u + (int64_t)(v - e->v_first) * e->u_step;
        int iu = (int)((u + 0xFFFF) >> 16);
        xs[n] = iu < 0 ? 0 : iu > width ? width : iu;
        ds[n++] = (pr->ent[k] & 1) ? 1 : -1;
    }
    if (n == 2 && ds[0] != ds[1]) {
        int xl = ds[0] > 0 ? xs[0] : xs[1], xr = ds[0] > 0 ? xs[1] : xs[0];
        if (xr <= xl || max < 1) return 0;
        out[0] = (ew_row_poly){s, xl, xr};
        return 1;
    }
    /* By pixel; at equal pixels the order of the steps does not change
     * which pixels have a count of 1 or more. */
    for (int i = 1; i < n; i++) {
        int x = xs[i], d = ds[i], j = i - 1;
        while (j >= 0 && xs[j] > x) xs[j + 1] = xs[j], ds[j + 1] = ds[j], j--;
        xs[j + 1] = x, ds[j + 1] = d;
    }
    int cnt = 0, m = 0, open = -1;
    for (int i = 0; i < n;) {
        int x = xs[i];
        for (; i < n && xs[i] == x; i++) cnt += ds[i];
        if (cnt >= 1 && open < 0)
            open = x;
        else if (cnt < 1 && open >= 0) {
            if (x > open && m < max) out[m++] = (ew_row_poly){s, open, x};
            open = -1;
        }
    }
    return m;
}

/* Must interval a come before interval b on row v?  Only brush-model
 * fragments of one leaf (one key) need it: where they overlap, the one
 * nearer at the first pixel both cover, as the edge scan decides when the
 * later one enters its surface stack (edge_scan.c nearer(): 1/z there;
 * equal, the one whose 1/z grows faster to the right). */
static int goes_before(const ew_surf *surfs, const ew_row_poly *a, const ew_row_poly *b, int v) {
    int u = a->xl > b->xl ? a->xl : b->xl, end = a->xr < b->xr ? a->xr : b->xr;
    if (u >= end) return 0;
    const ew_surf *sa = &surfs[a->surf], *sb = &surfs[b->surf];
    float za = sa->zi_u * u + sa->zi_v * v + sa->zi_0, zb = sb->zi_u * u + sb->zi_v * v + sb->zi_0;
    if (za != zb) return za > zb;
    return sa->zi_u > sb->zi_u;
}

/* Orders a run of same-key fragments on this row: repeatedly the first
 * one that no other remaining one must precede (a cycle, from
 * interpenetrating fragments, takes the first as it stands). */
static void order_run(const ew_surf *surfs, ew_row_poly *p, int n, int v) {
    for (int i = 0; i < n - 1; i++) {
        int pick = i;
        for (int k = i; k < n; k++) {
            int free = 1;
            for (int m = i; m < n && free; m++) free = m == k || !goes_before(surfs, &p[m], &p[k], v);
            if (free) {
                pick = k;
                break;
            }
        }
        ew_row_poly x = p[pick];
        memmove(p + i + 1, p + i, sizeof *p * (size_t)(pick - i));
        p[i] = x;
    }
}

int ew_poly_rows_next(ew_poly_rows *pr) {
    ew_band *b = pr->b;
    if (++pr->v >= b->y1) return 0;
    const int v = pr->v;
    /* Drop the surfaces that ended above, merge in the ones starting here
     * (both lists ascending by rank). */
    int n = 0;
    for (int i = 0; i < pr->nact; i++)
        if (pr->bot[pr->order[pr->act[i]]] >= v) pr->act[n++] = pr->act[i];
    int m = 0, i = 0;
    for (int s = pr->head[v - b->y0]; s >= 0; s = pr->next[s]) {
        int rk = pr->rank[s];
        while (i < n && pr->act[i] < rk) pr->act2[m++] = pr->act[i++];
        pr->act2[m++] = rk;
    }
    while (i < n) pr->act2[m++] = pr->act[i++];
    int32_t *t = pr->act;
    pr->act = pr->act2, pr->act2 = t;
    pr->nact = m;

    pr->nrow = 0;
    for (int k = 0; k < pr->nact; k++) {
        int s = pr->order[pr->act[k]];
        int room = pr->cap_row - pr->nrow;
        if (room <= 0) {
            b->dropped++;
            break;
        }
        pr->nrow += surf_row(pr, s, v, pr->row + pr->nrow, room);
    }
    /* Same-key brush-model fragments sit together in the order; sort each
     * such run for this row by 1/z where its members overlap. */
    const ew_surf *surfs = pr->el->surfs;
    for (int i = 0; i < pr->nrow;) {
        const ew_surf *a = &surfs[pr->row[i].surf];
        int j = i + 1;
        while (j < pr->nrow && a->insubmodel && surfs[pr->row[j].surf].insubmodel && surfs[pr->row[j].surf].key == a->key)
            j++;
        if (j - i > 1) order_run(surfs, pr->row + i, j - i, v);
        i = j;
    }
    return 1;
}

static int cmp_xl(const void *pa, const void *pb) {
    const ew_row_poly *a = pa, *b = pb;
    return (a->xl > b->xl) - (a->xl < b->xl);
}

void ew_poly_rows_emit_sorted(ew_poly_rows *pr, ew_row_poly *p, int n) {
    if (n > 24) {
        qsort(p, (size_t)n, sizeof *p, cmp_xl);
    } else {
        for (int i = 1; i < n; i++) {
            ew_row_poly x = p[i];
            int j = i - 1;
            while (j >= 0 && p[j].xl > x.xl) p[j + 1] = p[j], j--;
            p[j + 1] = x;
        }
    }
    int x = 0;
    for (int i = 0; i < n; i++) {
        if (p[i].xl > x) ew_band_span(pr->b, 0, x, p[i].xl, pr->v);
        ew_band_span(pr->b, p[i].surf, p[i].xl, p[i].xr, pr->v);
        x = p[i].xr;
    }
    ew_band_span(pr->b, 0, x, pr->width, pr->v);
}

/* What this frame used of each band's scratch: another method may have
 * grown it further, and the scratch is kept. */
size_t ew_poly_rows_memory(const ew_hsr_ctx *c) {
    size_t n = 0;
    for (int i = 0; i < c->nbands; i++) {
        const ew_band *b = &c->bands[i];
        if (b->scratch_bytes >= 16) n += *(const size_t *)b->scratch;
    }
    return n;
}
