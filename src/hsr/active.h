/* The active edge table's order, shared by the edge list's scans (hsr/edge_scan.c,
 * hsr/edge_z.c): by u; at equal u the edge heading left first, then edges
 * that only lead before edges that trail, so a sliver's leading edge comes
 * before its trailing edge. */
#ifndef EW_HSR_ACTIVE_H
#define EW_HSR_ACTIVE_H

#include "hsr/hsr.h"

#include <string.h>

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
