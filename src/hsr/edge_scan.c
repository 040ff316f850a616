/* Hidden-surface removal: scan the global edge list top to bottom.  Each
 * scanline keeps an active edge list sorted by x and a surface stack sorted
 * by BSP key (smaller = nearer).  A leading edge pushes its surface; if it
 * lands on top, the old top's span ends there.  A trailing edge pops its
 * surface; if it was on top, its span ends and the next one down resumes.
 * So every pixel of the band is emitted exactly once, for the nearest
 * surface, and surface 0 (the background, farthest of all) fills any gap. */
#include "hsr/active.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

/* The active edges start small and grow on demand up to the budget, so
 * many bands cost little memory. */
#define FIRST_AET 1024

void ew_edge_scan_free(void *own) {
    ew_edge_scan *s = own;
    if (!s) return;
    free(s->stack), free(s->aet), free(s->aet_tmp), free(s->st_neg), free(s->st_fix);
    free(s);
}

static void scan_reset(void *own) { ((ew_edge_scan *)own)->naet = 0; }
static int scan_full(const void *own) {
    const ew_edge_scan *s = own;
    return s->naet >= s->max_aet;
}
static const ew_band_own_ops scan_ops = {ew_edge_scan_free, scan_reset, scan_full};

ew_edge_scan *ew_edge_scan_of(ew_band *b, const ew_edge_list *el) {
    if (b->own_ops == &scan_ops) return b->own;
    if (b->own_ops) b->own_ops->free(b->own);  /* another method's */
    b->own = NULL, b->own_ops = NULL;
    ew_edge_scan *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    s->max_aet = el->max_edges;
    s->cap_aet = s->max_aet < FIRST_AET ? s->max_aet : FIRST_AET;
    s->stack = calloc((size_t)el->max_surfs, sizeof *s->stack);
    s->aet = malloc(sizeof(ew_active) * (size_t)s->cap_aet);
    s->st_neg = malloc(sizeof(int32_t) * (size_t)s->cap_aet);
    s->st_fix = malloc(sizeof(int32_t) * (size_t)s->cap_aet);
    s->cap_neg = s->st_neg && s->st_fix ? s->cap_aet : 0;
    if (!s->stack || !s->aet || !s->st_neg || !s->st_fix) {
        ew_edge_scan_free(s);
        return NULL;
    }
    b->own = s, b->own_ops = &scan_ops;
    return s;
}

/* Doubles an array of *cap elements, at most to max; 0 if it could. */
static int grow(void **arr, int *cap, int max, size_t elem) {
    if (*cap >= max) return -1;
    int n = *cap * 2 > max ? max : *cap * 2;
    void *p = realloc(*arr, elem * (size_t)n);
    if (!p) return -1;
    *arr = p, *cap = n;
    return 0;
}

/* Is surface a in front of surface b at pixel (u, v)?  BSP order decides,
 * except between brush model fragments in the same leaf (same key): there
 * 1/z at the pixel decides, and where they abut (equal 1/z) the one whose
 * 1/z grows faster to the right is in front from here on (chapter 51).
 * ka and kb: their keys, read from the stack's entries (ew_stack_entry.key). */
static inline int nearer(int32_t ka, int32_t kb, const ew_surf *a, const ew_surf *b, int u, int v) {
    if (ka < kb) return 1;  /* two branches: cheaper than a flag made and tested */
    if (ka > kb) return 0;
    if (!a->insubmodel || !b->insubmodel) return 0;
    float za = a->zi_u * u + a->zi_v * v + a->zi_0, zb = b->zi_u * u + b->zi_v * v + b->zi_0;
    if (za != zb) return za > zb;
    return a->zi_u > b->zi_u;
}

/* st_neg and st_fix hold at least cap_aet entries, since a line has at most
 * as many counts going below zero, or edges out of order, as it has edges.
 * Another method may have grown aet on the same band (hsr/edge_z.c); if
 * they cannot follow, cap_aet comes down to them (aet itself stays as large
 * as it is).  realloc keeps st_fix's entries: they live from one line's
 * stepping to the next line's sort, and new edges may grow aet between. */
static void fit_neg(ew_edge_scan *s) {
    if (s->cap_neg >= s->cap_aet) return;
    int32_t *neg = realloc(s->st_neg, sizeof(int32_t) * (size_t)s->cap_aet), *fix = NULL;
    if (neg) s->st_neg = neg, fix = realloc(s->st_fix, sizeof(int32_t) * (size_t)s->cap_aet);
    if (fix) s->st_fix = fix, s->cap_neg = s->cap_aet;
    else s->cap_aet = s->cap_neg;
}

static void add_active(ew_edge_scan *s, ew_band *b, const ew_edge *e, int v) {
    if (s->naet >= s->cap_aet) {
        if (grow((void **)&s->aet, &s->cap_aet, s->max_aet, sizeof(ew_active)) == 0) fit_neg(s);
        if (s->naet >= s->cap_aet) {
            b->dropped++;
            return;
        }
    }
    ew_active_set(&s->aet[s->naet++], e, v);
}

void ew_edge_scan_start(const ew_edge_list *el, ew_edge_scan *s, ew_band *b) {
    /* Only the rows above are visited, and the edges are sorted at once,
     * since the insertion sort of the first row would take time quadratic
     * in their number. */
    s->naet = 0;
    for (int k = 0, end = el->row_first[b->y0]; k < end; k++)
        if (el->by_row_last[k] >= b->y0) add_active(s, b, &el->edges[el->by_row[k]], b->y0);
    if (s->naet <= 1) return;
    if (s->cap_tmp < s->naet) {
        ew_active *t = realloc(s->aet_tmp, sizeof *t * (size_t)s->naet);
        if (t) s->aet_tmp = t, s->cap_tmp = s->naet;
    }
    if (s->cap_tmp >= s->naet)
        ew_active_sort_any(s->aet, s->naet, s->aet_tmp);
    else  /* no memory for the merge: the same order, slower */
        ew_active_sort(s->aet, s->naet);
}

static inline void add_row(const ew_edge_list *el, ew_edge_scan *s, ew_band *b, int v) {
    for (int k = el->row_first[v], end = el->row_first[v + 1]; k < end; k++)
        add_active(s, b, &el->edges[el->by_row[k]], v);
}
void ew_edge_scan_add_row(const ew_edge_list *el, ew_edge_scan *s, ew_band *b, int v) { add_row(el, s, b, v); }

/* The line's edges in order: a[0..nold) are last line's, stepped, nearly in
 * order already; a[nold..n) start on this line, in the order they were
 * added.  The result is the insertion sort's of the whole array, which is a
 * stable sort (ew_active_after() compares the keys u, u_step and "has a trailing
 * side" in turn): the old part sorted in place, the new ones sorted among
 * themselves, then merged from the back, an old edge staying before a new
 * one it ties with.  The new edges would otherwise each travel from the end
 * of the list to their place.
 *
 * The old part's insertion sort visits only fix[0..nfix), ascending: the
 * stepping listed every edge whose u was not above all the u before it.
 * Any other edge is after all of them (a larger u), so the insertion sort
 * would leave it where it is, having compared it once. */
#define MERGE_MAX 64
static void sort_edges(ew_active *a, int nold, int n, const int32_t *fix, int nfix) {
    for (int f = 0; f < nfix; f++)
        if (fix[f] > 0) ew_active_insert(a, fix[f]);
    int k = n - nold;
    if (k <= 0) return;
    if (k > MERGE_MAX || nold == 0) {
        ew_active_sort(a, n);
        return;
    }
    ew_active x[MERGE_MAX];
    memcpy(x, a + nold, sizeof(ew_active) * (size_t)k);
    ew_active_sort(x, k);
    int i = nold - 1, d = n - 1;
    for (int j = k - 1; j >= 0; j--) {
        const ew_active xj = x[j];  /* held while the old edges after it move up */
        while (i >= 0 && ew_active_after(&a[i], &xj)) a[d--] = a[i--];
        a[d--] = xj;
    }
}

void ew_scan_band(const ew_edge_list *el, int width, ew_band *b) {
    const ew_surf *surfs = el->surfs;
    b->nspans = 0;
    memset(b->has_spans, 0, (size_t)el->nsurfs);
    ew_edge_scan *es = ew_edge_scan_of(b, el);
    if (!es) {  /* out of memory: the band stays background */
        b->dropped++;
        for (int v = b->y0; v < b->y1; v++) ew_band_span(b, 0, 0, width, v);
        return;
    }
    ew_stack_entry *st = es->stack;

    /* The stack's counts are all zero here: calloc'd, and each line ends by
     * clearing every count it left above or below zero. */
    fit_neg(es);
    ew_edge_scan_start(el, es, b);
    for (int s = 0; s < el->nsurfs; s++) st[s].key = surfs[s].key;

    int nfix = 0;  /* sorted */
    ew_span_sink out = {b->spans, 0, b->cap_spans, b->has_spans};
    for (int v = b->y0; v < b->y1; v++) {
        const int nold = es->naet;  /* last line's edges, stepped: nearly in order */
        add_row(el, es, b, v);
        /* Read once per line: a span's stores could alias them, so
         * the compiler would reload both at every edge. */
        ew_active *aet = es->aet;
        const int naet = es->naet;
        int32_t *fix = es->st_fix;
        sort_edges(aet, nold, naet, fix, nfix);

        int top = 0;  /* the background, always at the bottom of the stack */
        st[0].next = -1, st[0].prev = -1, st[0].lastu = 0;
        /* Surfaces whose count went below zero on this line: cap_neg >=
         * cap_aet >= naet entries, at most one per edge. */
        int32_t *neg = es->st_neg;
        int nneg = 0;
        for (int i = 0; i < naet; i++) {
            const ew_active a = aet[i];
            /* The first pixel centre right of the edge: in [0, width] with no
             * clamp, since every edge runs between projected points on the
             * screen, [-0.5, width - 0.5] (world/edge_math.h), and its 16.16
             * steps drift by under 1/16 pixel over 4320 lines. */
            int iu = (a.u + 0xFFFF) >> 16;  /* no overflow: u < 7681 << 16 */
            int s = a.surfs[0];
            /* A trailing edge met before its leading edge (crossed by rounding,
             * or a zero-width sliver) drives the count negative, and the
             * late leading edge then brings it back to zero without a push. */
            if (s) {                                             /* trailing edge */
                int c = --st[s].state;
                if (c == 0) {
                    if (s == top) {
                        ew_sink_span(b, &out, s, st[s].lastu, iu, v);
                        top = st[s].next;
                        st[top].prev = -1;
                        st[top].lastu = iu;
                    } else {
                        st[st[s].prev].next = st[s].next;
                        st[st[s].next].prev = st[s].prev;  /* s is not the bottom: the background is */
                    }
                } else if (c < 0) {
                    neg[nneg++] = s;
                }
            }
            s = a.surfs[1];
            if (s && ++st[s].state == 1) {                          /* leading edge */
                if (nearer(st[s].key, st[top].key, &surfs[s], &surfs[top], iu, v)) {
                    ew_sink_span(b, &out, top, st[top].lastu, iu, v);
                    st[s].next = top, st[s].prev = -1;
                    st[top].prev = s;
                    top = s;
                    st[s].lastu = iu;
                } else {
                    /* Down the stack: each step's key from the stack's own
                     * entry (one cache line), the surface only on a tie. */
                    int p = top;
                    const int32_t ks = st[s].key;
                    for (int n = st[p].next; !nearer(ks, st[n].key, &surfs[s], &surfs[n], iu, v); n = st[p].next)
                        p = n;
                    st[s].next = st[p].next, st[s].prev = p;
                    st[st[p].next].prev = s;
                    st[p].next = s;
                }
            }
        }
        ew_sink_span(b, &out, top, st[top].lastu, width, v);

        /* Stepped to the next line, in a pass of its own: the scan above
         * then keeps its state in registers.  No branch on an edge's u
         * or its end: which edges fall out of order or end follows no
         * pattern, so every such branch would be a coin toss. */
        int32_t max_u = INT32_MIN;
        nfix = 0;
        int i = 0;
        for (; i < naet && aet[i].v_last > v; i++) {  /* up to the first edge that ends: in place */
            int32_t u = aet[i].u += aet[i].u_step;
            fix[nfix] = i;  /* never 0 with a real u; sort_edges checks */
            nfix += u <= max_u;
            max_u = u > max_u ? u : max_u;
        }
        int n = i;
        for (; i < naet; i++) {  /* then moved down over the ended ones */
            const int alive = aet[i].v_last > v;
            aet[n] = aet[i];  /* copied whole, then stepped: one 16-byte move; an ended one is overwritten next */
            int32_t u = aet[n].u += aet[n].u_step;
            fix[nfix] = n;
            nfix += alive & (u <= max_u);
            const int32_t lead = alive ? u : INT32_MIN;
            max_u = lead > max_u ? lead : max_u;
            n += alive;
        }

        /* Every count back to zero for the next line.  A count above zero is
         * a surface still on the stack (pushed at 0 -> 1, taken off at
         * 1 -> 0), one below zero is in neg; when the line's edges balanced,
         * the stack is just the background and neg is empty. */
        for (int s = top; s > 0; s = st[s].next) st[s].state = 0;
        for (int k = 0; k < nneg; k++) st[neg[k]].state = 0;
        es->naet = n;
    }
    b->nspans = out.n;
}

/* ---- the edge list as a hidden-surface method ---- */

void ew_edge_begin(ew_hsr_ctx *c) {
    ew_edge_list *el = c->el;
    el->nedges = 0;
    el->nsurfs = 1;  /* surface 0: the background, behind everything */
    el->surfs[0] = (ew_surf){.key = INT32_MAX, .face = -1, .view = &c->f->view};
}

/* A counting sort by first scanline.  Within a row the later edge comes
 * first, the order the per-row lists this replaced had (and the scans'
 * ties depend on). */
void ew_edge_sort_rows(ew_hsr_ctx *c) {
    ew_edge_list *el = c->el;
    const int h = c->f->target.height;
    int32_t *first = el->row_first;
    memset(first, 0, sizeof(int32_t) * (size_t)(h + 2));
    for (int i = 0; i < el->nedges; i++) first[el->edges[i].v_first + 2]++;
    for (int v = 2; v <= h + 1; v++) first[v] += first[v - 1];
    /* first[v + 1] is where row v starts; placing moves it to row v's end,
     * which is row v + 1's start. */
    for (int i = el->nedges - 1; i >= 0; i--) {
        const ew_edge *e = &el->edges[i];
        int k = first[e->v_first + 1]++;
        el->by_row[k] = i, el->by_row_last[k] = e->v_last;
    }
}

/* The front end's own face and polygon (world/edges.c), through the context. */
void ew_edge_face(ew_hsr_ctx *c, int face, int clipflags, int key) { c->emit_face(c->owner, face, clipflags, key); }
void ew_edge_poly(ew_hsr_ctx *c, float (*verts)[3], int n, int fi, const ew_view *v, int key) {
    c->emit_poly(c->owner, verts, n, fi, v, key);
}

static void edge_resolve(const ew_hsr_ctx *c, ew_band *b) { ew_scan_band(c->el, c->f->target.width, b); }

const ew_hsr ew_hsr_edge = {
    "edge",
    EW_HSR_EDGE_LIST | EW_HSR_OCCLUSION | EW_HSR_MAKES_SPANS | EW_HSR_EXACT_ONCE | EW_HSR_SHOWS_EDGES,
    ew_edge_begin, ew_edge_face, ew_edge_poly, ew_edge_sort_rows, edge_resolve, NULL, {NULL}};
