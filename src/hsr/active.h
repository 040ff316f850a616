/* The edge list's scans' band state (hsr/edge_scan.c, hsr/edge_z.c), and
 * the active edge table's order they share: by u; at equal u the edge heading left first, then edges
 * that only lead before edges that trail, so a sliver's leading edge comes
 * before its trailing edge. */
#ifndef EW_HSR_ACTIVE_H
#define EW_HSR_ACTIVE_H

#include "hsr/hsr.h"

#include <string.h>

/* An edge alive on the current line of a scan. */
typedef struct ew_active {
    int32_t  u, u_step, v_last;
    uint16_t surfs[2];
} ew_active;

/* One surface's place in a band's surface stack (the edge list's scans):
 * its neighbours, its count of edges entered less left, and where its
 * current span began.  Together, so that one cache line and one base
 * register serve all four. */
typedef struct ew_stack_entry {
    int32_t next, prev, state, lastu;
    int32_t key;  /* the surface's key (the edge list's scan copies it at the band's start) */
} ew_stack_entry;

/* The edge list's scans' own state in a band (ew_band.own): the surface
 * stack and the active edge table, which start small and grow on demand
 * up to the budget. */
typedef struct ew_edge_scan {
    ew_stack_entry *stack;          /* indexed by surface number; 0 is the background (max_surfs) */
    ew_active *aet;  int naet, cap_aet, max_aet;
    ew_active *aet_tmp;  int cap_tmp;  /* the band start's merge sort */
    int32_t *st_neg;  int cap_neg;  /* >= cap_aet entries (the edge list's scan): counts gone below zero on a line */
    int32_t *st_fix;                /* as many: the stepped edges that may be out of order for the next line */
} ew_edge_scan;

/* The band's edge scan state, made on first use for el's budgets (the
 * stack's counts all zero), or NULL when memory runs out. */
ew_edge_scan *ew_edge_scan_of(ew_band *b, const ew_edge_list *el);
/* Frees one (the band's own_ops, when its own is an edge scan). */
void ew_edge_scan_free(void *own);
/* The band's active edges made those alive at its top row, sorted; then
 * each row's new edges added, unsorted.  Edges past the table's capacity
 * are counted in b->dropped. */
void ew_edge_scan_start(const ew_edge_list *el, ew_edge_scan *s, ew_band *b);
void ew_edge_scan_add_row(const ew_edge_list *el, ew_edge_scan *s, ew_band *b, int v);

/* The spans a scan makes, held in locals (after inlining, registers) by
 * its inner loop, since the stores of a span and its has_spans byte could
 * alias the band's fields. */
typedef struct ew_span_sink {
    ew_span *spans;
    int      n, cap;
    uint8_t *has;
} ew_span_sink;


/* A span of surf on row v from u0 to u1 (none if empty) into the band. */
static inline void ew_sink_span(ew_band *b, ew_span_sink *o, int surf, int u0, int u1, int v) {
    if (u1 <= u0) return;
    if (o->n >= o->cap) {
        b->nspans = o->n;
        if (ew_band_grow_spans(b) < 0) {
            b->dropped++;
            return;
        }
        o->spans = b->spans, o->cap = b->cap_spans;
    }
    ew_span *sp = &o->spans[o->n++];
    sp->u = u0, sp->v = v, sp->count = u1 - u0, sp->surf = surf;
    o->has[surf] = 1;
}

/* Edge e entering the active table on line v. */
static inline void ew_active_set(ew_active *a, const ew_edge *e, int v) {
    a->u = e->u + (v - e->v_first) * e->u_step;
    a->u_step = e->u_step;
    a->v_last = e->v_last;
    a->surfs[0] = e->surfs[0];
    a->surfs[1] = e->surfs[1];
}

static inline int ew_active_after(const ew_active *a, const ew_active *b) {
    if (a->u > b->u) return 1;  /* branches: cheaper than a flag made and tested */
    if (a->u < b->u) return 0;
    if (a->u_step != b->u_step) return a->u_step > b->u_step;
    return a->surfs[0] != 0 && b->surfs[0] == 0;
}

/* One step of the insertion sort, a[0..i) sorted: a[i] moved down past
 * the edges after it (i > 0). */
static inline void ew_active_insert(ew_active *a, int i) {
    if (!ew_active_after(&a[i - 1], &a[i])) return;  /* in place already: most edges, most lines */
    ew_active x = a[i];
    int j = i - 1;
    do {
        a[j + 1] = a[j];
        j--;
    } while (j >= 0 && ew_active_after(&a[j], &x));
    a[j + 1] = x;
}

/* Insertion sort (stable): the list is nearly sorted every line. */
static inline void ew_active_sort(ew_active *a, int n) {
    for (int i = 1; i < n; i++) ew_active_insert(a, i);
}

/* A stable merge sort for a list in no order (a band's first line), with
 * tmp room for n: runs of 8 sorted by insertion, then merged pairwise, the
 * comparisons inlined.  Stable, as the insertion sort is, so ties keep the
 * order they were added in and either gives the same list. */
static inline void ew_active_sort_any(ew_active *a, int n, ew_active *tmp) {
    enum { RUN = 8 };
    for (int i = 0; i < n; i += RUN) ew_active_sort(a + i, n - i < RUN ? n - i : RUN);
    ew_active *src = a, *dst = tmp;
    for (int w = RUN; w < n; w *= 2) {
        for (int lo = 0; lo < n; lo += 2 * w) {
            int mid = lo + w < n ? lo + w : n, hi = lo + 2 * w < n ? lo + 2 * w : n;
            int i = lo, j = mid, k = lo;
            while (i < mid && j < hi) dst[k++] = ew_active_after(&src[i], &src[j]) ? src[j++] : src[i++];
            while (i < mid) dst[k++] = src[i++];
            while (j < hi) dst[k++] = src[j++];
        }
        ew_active *t = src;
        src = dst, dst = t;
    }
    if (src != a) memcpy(a, src, sizeof *a * (size_t)n);
}

#endif
