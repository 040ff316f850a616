/* The edge list sorted by 1/z instead of BSP order: the experiment of
 * chapter 51 that id tried for Quake and dropped.  The front end and the
 * edge list are the edge method's (world/edges.c); every surface, world
 * faces too, carries its 1/z plane over the screen, and the scan of each
 * row keeps the set of surfaces the scan position is inside and, as the
 * top, the one nearest there:
 *
 *  - a leading edge at pixel u: the new surface's 1/z at u against the
 *    top's; the nearer becomes the top;
 *  - abutting (the two 1/z within a hair of each other at u, as where a
 *    door starts on a wall): the one whose 1/z grows faster to the right
 *    is in front from there on, as the book describes;
 *  - intersecting: between two edge events the top can only be overtaken
 *    by a surface whose 1/z grows faster to the right; each such one is
 *    tested at the last pixel before the next event, and where one wins
 *    there, the pixel where their planes cross is computed and the span
 *    is split there (the book's two-point test and split);
 *  - a trailing edge of the top: the nearest of the rest at u becomes the
 *    top (a search of the set, not the next one down a stack: without BSP
 *    order nothing keeps the ones below sorted once planes cross).
 *
 * No BSP key is read.  Every pixel of a row is emitted once, left to right,
 * for the surface nearest at its centre (1/z evaluated as the reference
 * path evaluates it), or the background where none is. */
#include "hsr/active.h"
#include "raster/raster.h"  /* ew_face_gradients */

#include <limits.h>
#include <string.h>

enum { C_COMPARES, C_SPLITS, C_TIES };

/* Relative width of a 1/z tie: float error of evaluating two planes at a
 * pixel, where surfaces that meet along an edge are equal in exact math. */
#define TIE_EPS (1.0f / (1 << 20))

/* One row's scan state: the set of surfaces (doubly linked, head 0) and
 * the top. */
typedef struct zscan {
    const ew_surf *surfs;
    ew_stack_entry *st;   /* next and prev */
    float *zrow;          /* per surface: zi_v * v + zi_0 for this row */
    float v;
    long compares, splits, ties;
} zscan;

static inline float zi_at(const zscan *z, int s, int u) { return z->surfs[s].zi_u * (float)u + z->zrow[s]; }

/* Is surface a in front of surface b at pixel u of this row (and so from
 * u on to the right, unless they cross)? */
static inline int front(zscan *z, int a, int b, int u) {
    float za = zi_at(z, a, u), zb = zi_at(z, b, u), tol = TIE_EPS * (za + zb);
    z->compares++;
    if (za - zb > tol) return 1;
    if (zb - za > tol) return 0;
    z->ties++;
    return z->surfs[a].zi_u > z->surfs[b].zi_u;
}

/* The first pixel of [a, last] where s is in front of t, given that it is
 * at last and its 1/z grows faster: where the planes cross, adjusted to
 * the comparison itself. */
static int crossing(zscan *z, int s, int t, int a, int last) {
    const ew_surf *ss = &z->surfs[s], *st = &z->surfs[t];
    double x = -((double)z->zrow[s] - z->zrow[t]) / ((double)ss->zi_u - st->zi_u);
    if (!(x >= a)) x = a;  /* NaN too */
    if (x > last) x = last;
    int u = (int)x;
    while (u > a && front(z, s, t, u - 1)) u--;
    while (u < last && !front(z, s, t, u)) u++;
    return u;
}

/* The nearest surface of the set at pixel u; 0 (the background) if the
 * set is empty. */
static int nearest(zscan *z, int u) {
    int best = z->st[0].next;
    if (best <= 0) return 0;
    for (int s = z->st[best].next; s > 0; s = z->st[s].next)
        if (front(z, s, best, u)) best = s;
    return best;
}

/* Pixels [a, b) of the row, with *top nearest at a: wherever another
 * surface overtakes it, the top's span ends and the other's starts. */
static void advance(zscan *z, ew_band *b, int *top, int *start, int a, int end, int v) {
    int t = *top;
    while (t > 0 && a < end) {
        float tu = z->surfs[t].zi_u;
        int best = 0, bu = end;
        for (int s = z->st[0].next; s > 0; s = z->st[s].next) {
            if (s == t || z->surfs[s].zi_u <= tu || !front(z, s, t, end - 1)) continue;
            int u = crossing(z, s, t, a, end - 1);
            if (u < bu || (u == bu && front(z, s, best, u))) best = s, bu = u;
        }
        if (!best) break;
        ew_band_span(b, t, *start, bu, v);
        z->splits++;
        t = best, *start = bu, a = bu;
    }
    *top = t;
}

static void scan_band_z(const ew_edge_list *el, int width, ew_band *b) {
    b->nspans = 0;
    memset(b->has_spans, 0, (size_t)el->nsurfs);
    ew_edge_scan *es = ew_edge_scan_of(b, el);  /* the edge method's band state (hsr/edge_scan.c) */
    float *zrow = es ? ew_band_scratch(b, sizeof(float) * (size_t)el->nsurfs) : NULL;
    if (!zrow) {  /* out of memory: the band stays background */
        b->dropped++;
        for (int v = b->y0; v < b->y1; v++) ew_band_span(b, 0, 0, width, v);
        return;
    }
    ew_stack_entry *st = es->stack;
    zscan z = {el->surfs, st, zrow, 0, 0, 0, 0};

    ew_edge_scan_start(el, es, b);  /* the edge method's active edges */

    for (int v = b->y0; v < b->y1; v++) {
        ew_edge_scan_add_row(el, es, b, v);
        ew_active *aet = es->aet;
        const int naet = es->naet;
        ew_active_sort(aet, naet);

        z.v = (float)v;
        z.st[0].next = -1, z.st[0].prev = -1;
        int top = 0, start = 0, at = 0;  /* the top is nearest over [start, at) */
        for (int i = 0; i < naet; i++) {
            const ew_active *a = &aet[i];
            int iu = (int)(((int64_t)a->u + 0xFFFF) >> 16);  /* first pixel centre right of the edge */
            iu = iu < 0 ? 0 : iu > width ? width : iu;
            if (iu > at) {
                advance(&z, b, &top, &start, at, iu, v);
                at = iu;
            }
            int s = a->surfs[0];
            if (s && --st[s].state == 0) {  /* trailing edge: out of the set */
                int p = z.st[s].prev, n = z.st[s].next;
                z.st[p].next = n;
                if (n > 0) z.st[n].prev = p;
                if (s == top) {
                    ew_band_span(b, s, start, iu, v);
                    top = nearest(&z, iu);
                    start = iu;
                }
            }
            s = a->surfs[1];
            if (s && ++st[s].state == 1) {  /* leading edge: into the set */
                const ew_surf *sf = &z.surfs[s];
                z.zrow[s] = sf->zi_v * z.v + sf->zi_0;  /* the reference's order of operations */
                int n = z.st[0].next;
                z.st[s].next = n, z.st[s].prev = 0;
                if (n > 0) z.st[n].prev = s;
                z.st[0].next = s;
                if (top == 0 || front(&z, s, top, iu)) {
                    ew_band_span(b, top, start, iu, v);
                    top = s;
                    start = iu;
                }
            }
        }
        advance(&z, b, &top, &start, at, width, v);
        ew_band_span(b, top, start, width, v);

        int n = 0;
        for (int i = 0; i < naet; i++) {
            ew_active a = aet[i];
            st[a.surfs[0]].state = st[a.surfs[1]].state = 0;
            if (a.v_last <= v) continue;
            a.u += a.u_step;
            aet[n++] = a;
        }
        es->naet = n;
    }
    b->counters[C_COMPARES] += z.compares;
    b->counters[C_SPLITS] += z.splits;
    b->counters[C_TIES] += z.ties;
}

/* ---- the method: the edge method's front end, planes for every surface ---- */

/* ew_emit_face gives only brush-model fragments a plane; here world faces
 * get theirs, seen from the camera. */
static void z_face(ew_hsr_ctx *c, int fi, int clipflags, int key) {
    int s = c->el->nsurfs;
    ew_edge_face(c, fi, clipflags, key);
    if (c->el->nsurfs == s) return;
    ew_gradients g;
    ew_face_gradients(c->f->world, &c->f->view, &c->f->world->faces[fi], 0, &g);
    ew_surf *sf = &c->el->surfs[s];
    sf->zi_u = g.zi_u, sf->zi_v = g.zi_v, sf->zi_0 = g.zi_0;
}

static void z_resolve(const ew_hsr_ctx *c, ew_band *b) { scan_band_z(c->el, c->f->target.width, b); }

static size_t z_memory(const ew_hsr_ctx *c) {
    size_t n = 0;
    for (int i = 0; i < c->nbands; i++) n += c->bands[i].scratch_bytes;
    return n;
}

const ew_hsr ew_hsr_edge_z = {
    "edge-z", EW_HSR_MAKES_SPANS | EW_HSR_EXACT_ONCE, ew_edge_begin, z_face, ew_edge_poly, ew_edge_sort_rows,
    z_resolve, z_memory,
    {[C_COMPARES] = "1/z comparisons", [C_SPLITS] = "intersections split", [C_TIES] = "abutting ties"}};
