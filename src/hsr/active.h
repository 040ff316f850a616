/* The active edge table's order, shared by the edge list's scans (hsr/edge_scan.c,
 * hsr/edge_z.c): by u; at equal u the edge heading left first, then edges
 * that only lead before edges that trail, so a sliver's leading edge comes
 * before its trailing edge. */
#ifndef EW_HSR_ACTIVE_H
#define EW_HSR_ACTIVE_H

#include "hsr/hsr.h"

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

/* For qsort. */
static inline int ew_active_cmp(const void *pa, const void *pb) {
    const ew_active *a = pa, *b = pb;
    return ew_active_after(a, b) ? 1 : ew_active_after(b, a) ? -1 : 0;
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

#endif
