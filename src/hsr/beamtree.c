/* Hidden-surface removal with a beam tree (the Black Book's lab): polygons
 * front to back, each clipped against a tree of wedges from the eye and
 * drawn only where the tree is still empty, then added to it as solid;
 * when no empty region is left, the rest are skipped.
 *
 * A plane through the eye is a line on the screen, so the tree is a 2D BSP
 * of screen lines, one per band with the band's rectangle as its root
 * region.  An internal node is a line (its inside child takes the pixel
 * centres ew_line_in gives it); a leaf is empty or a surface.  A polygon
 * fragment reaching an empty leaf turns it into a chain of the fragment's
 * own edges ending in a solid leaf: its outside pieces stay empty.
 *
 * The pixels come from the tree alone: each row is walked down the tree
 * with an interval of x, each node's line cutting the interval where its
 * pixel test changes, so every pixel of the band reaches exactly one leaf:
 * written once, by construction, in spans left to right.  Polygon geometry
 * (clipped in doubles, a vertex near a line going both ways) only decides
 * which leaves a fragment reaches; the lines themselves are exact
 * (surf_poly.h), so a frame does not depend on how it is cut into bands.
 *
 * Brush model fragments in one leaf share a BSP key and may overlap; the
 * edge list orders them by 1/z at each pixel.  Here each one first loses
 * the parts where another of its leaf is nearer (that other's polygon cut
 * by the line where the two 1/z planes are equal), then goes in. */
#include "hsr/surf_poly.h"

#include <math.h>
#include <string.h>

#define EPS 1e-9      /* pixels: a vertex this near a line is on it */
#define MIN_AREA 1e-6 /* square pixels: a fragment less than this is no fragment */
#define EMPTY (-1)    /* leaves: EMPTY, or SOLID(s) = -2 - s */
#define SOLID(s) (-2 - (s))

typedef struct bt_node {
    ew_line l;
    int     child[2];  /* [0]: inside of l, [1]: outside */
} bt_node;

/* A fragment's vertex and its edge to the next; add: the edge is a line
 * of the polygon (or of what hides it), not one the tree already has. */
typedef struct bt_vert {
    double  x, y;
    ew_line l;
    int     add;
} bt_vert;

typedef struct bt_item { int v0, n, slot; } bt_item;  /* a fragment bound for a slot */
typedef struct bt_row { int node, x0, x1; } bt_row;   /* the row walk's pending intervals */

/* The band's scratch: a header, then growable arrays. */
enum { A_NODES, A_VERTS, A_ITEMS, A_PIECES, A_ROWS, A_N };
static const size_t elem[A_N] = {sizeof(bt_node), sizeof(bt_vert), sizeof(bt_item), sizeof(bt_item), sizeof(bt_row)};
#define MAGIC 0x6265616d74726565ULL  /* "beamtree": the scratch is laid out as below */

typedef struct bt_hdr {
    unsigned long long magic;
    size_t off[A_N], cap[A_N];
    int    root, nnodes, nverts, empties, oom;
} bt_hdr;

static size_t round16(size_t n) { return (n + 15) & ~(size_t)15; }

static bt_hdr *layout(ew_band *b, const size_t cap[A_N]) {
    size_t off[A_N], at = round16(sizeof(bt_hdr));
    for (int k = 0; k < A_N; k++) off[k] = at, at = round16(at + cap[k] * elem[k]);
    bt_hdr *h = ew_band_scratch(b, at);
    if (!h) return NULL;
    /* Offsets only grow: moving the last array first never overwrites one not yet moved. */
    if (h->magic == MAGIC)
        for (int k = A_N - 1; k >= 0; k--) memmove((char *)h + off[k], (char *)h + h->off[k], h->cap[k] * elem[k]);
    h->magic = MAGIC;
    for (int k = 0; k < A_N; k++) h->off[k] = off[k], h->cap[k] = cap[k];
    return h;
}

static bt_hdr *arena(ew_band *b) {
    bt_hdr *h = b->scratch_bytes >= sizeof(bt_hdr) ? b->scratch : NULL;
    if (h && h->magic == MAGIC) return h;
    if (h) h->magic = 0;  /* another method's bytes */
    static const size_t first[A_N] = {1024, 4096, 256, 256, 256};
    return layout(b, first);
}

/* Array k holds at least n; 0 when out of memory.  Moves the arrays. */
static int need(ew_band *b, int k, size_t n) {
    bt_hdr *h = b->scratch;
    if (n <= h->cap[k]) return 1;
    size_t cap[A_N];
    memcpy(cap, h->cap, sizeof cap);
    while (cap[k] < n) cap[k] *= 2;
    if (!layout(b, cap)) {
        ((bt_hdr *)b->scratch)->oom = 1;
        return 0;
    }
    return 1;
}

#define ARR(b, k, T) ((T *)((char *)(b)->scratch + ((bt_hdr *)(b)->scratch)->off[k]))
#define HDR(b) ((bt_hdr *)(b)->scratch)

static int *slot_at(ew_band *b, int slot) {
    return slot < 0 ? &HDR(b)->root : &ARR(b, A_NODES, bt_node)[slot >> 1].child[slot & 1];
}

/* x * y == z * w exactly (fma gives each product's rounding error). */
static int prod_eq(double x, double y, double z, double w) {
    double p = x * y, q = z * w;
    return p == q && fma(x, y, -p) == fma(z, w, -q);
}

/* 1 if m is the line l, -1 if its negation, 0 if another line (exact for
 * grid lines; others only when bitwise equal). */
static int same_line(const ew_line *l, const ew_line *m) {
    if (l->a == m->a && l->b == m->b && l->c == m->c) return 1;
    if (l->a == -m->a && l->b == -m->b && l->c == -m->c) return -1;
    if (!l->grid || !m->grid) return 0;
    if (!prod_eq(l->a, m->b, m->a, l->b) || !prod_eq(l->a, m->c, m->a, l->c) || !prod_eq(l->b, m->c, m->b, l->c))
        return 0;
    return l->a * m->a + l->b * m->b > 0 ? 1 : -1;
}

static double frag_area(const bt_vert *v, int n) {
    double area = 0;
    for (int i = 0; i < n; i++) {
        int j = i + 1 == n ? 0 : i + 1;
        area += v[i].x * v[j].y - v[j].x * v[i].y;
    }
    return area * 0.5;
}

/* Appends the part of fragment (v0, n) on one side of l (keep 1: inside,
 * 0: outside) to the pool; the edge the cut makes lies on l and gets add.
 * Returns its vertex count (0: nothing there), its first vertex in *out. */
static int clip(ew_band *b, int v0, int n, const ew_line *l, int keep, int add, int *out) {
    if (!need(b, A_VERTS, (size_t)HDR(b)->nverts + (size_t)n * 2 + 2)) return 0;
    bt_vert *pool = ARR(b, A_VERTS, bt_vert);
    const bt_vert *src = pool + v0;
    bt_vert *dst = pool + HDR(b)->nverts;
    double d[EW_MAX_POLY * 2];
    if (n > EW_MAX_POLY * 2 - 2) return 0;
    ew_line cut = keep ? *l : ew_line_neg(*l);
    for (int i = 0; i < n; i++) d[i] = ew_line_dist(&cut, src[i].x, src[i].y);
    int m = 0;
    for (int i = 0; i < n; i++) {
        int j = i + 1 == n ? 0 : i + 1;
        if (d[i] >= -EPS) {
            bt_vert q = src[i];
            if (d[j] < -EPS || (d[i] <= EPS && d[j] <= EPS)) {
                if (d[i] > EPS) {  /* leaves: this vertex, then the crossing */
                    dst[m++] = q;
                    double t = d[i] / (d[i] - d[j]);
                    q.x = src[i].x + t * (src[j].x - src[i].x), q.y = src[i].y + t * (src[j].y - src[i].y);
                }
                q.l = cut, q.add = add;  /* along the cut */
            }
            dst[m++] = q;
        } else if (d[j] > EPS) {  /* enters: the crossing, on this edge */
            bt_vert q = src[i];
            double t = d[i] / (d[i] - d[j]);
            q.x = src[i].x + t * (src[j].x - src[i].x), q.y = src[i].y + t * (src[j].y - src[i].y);
            dst[m++] = q;
        }
    }
    if (m < 3 || !(frag_area(dst, m) > 0)) return 0;
    *out = HDR(b)->nverts;
    HDR(b)->nverts += m;
    return m;
}

/* Every pixel centre of the band is inside l: its outside would be an
 * empty leaf no polygon can fill, and the tree would never be solid. */
static int covers_band(const ew_line *l, const ew_band *b, int w) {
    double top = ew_line_row(l, b->y0), bottom = ew_line_row(l, b->y1 - 1);
    return ew_line_in(l, 0, top) && ew_line_in(l, w - 1, top) && ew_line_in(l, 0, bottom) &&
           ew_line_in(l, w - 1, bottom);
}

/* Fragment (v0, n) of surface s filtered down the tree from the root:
 * drawn into every empty leaf it reaches; returns how many. */
static int insert(ew_band *b, int w, int s, int v0, int n) {
    int drawn = 0, nitems = 0;
    if (!need(b, A_ITEMS, 1)) return 0;
    ARR(b, A_ITEMS, bt_item)[nitems++] = (bt_item){v0, n, -1};
    while (nitems > 0) {
        bt_item it = ARR(b, A_ITEMS, bt_item)[--nitems];
        int at = *slot_at(b, it.slot);
        if (at >= 0) {
            ew_line l = ARR(b, A_NODES, bt_node)[at].l;
            bt_vert *f = ARR(b, A_VERTS, bt_vert) + it.v0;
            /* The pixel tests are exact and the clipping is not: a vertex
             * near the line counts on both sides, so the fragment reaches
             * every leaf it might own a pixel centre of (the leaf's pixels
             * are then settled by the fragment's exact lines).  Only the
             * ends of an edge lying on the line itself are known to be on it. */
            int in = 0, out = 0;
            uint8_t on[EW_MAX_POLY * 2];
            for (int i = 0; i < it.n; i++) on[i] = 0;
            for (int i = 0; i < it.n; i++)
                if (same_line(&l, &f[i].l)) on[i] = on[i + 1 == it.n ? 0 : i + 1] = 1;
            for (int i = 0; i < it.n; i++) {
                if (on[i]) continue;
                double d = ew_line_dist(&l, f[i].x, f[i].y);
                in |= d > -EPS, out |= d < EPS;
            }
            if (in && out) {
                int fv = 0, bv = 0, fn = clip(b, it.v0, it.n, &l, 1, 0, &fv), bn = clip(b, it.v0, it.n, &l, 0, 0, &bv);
                if (!need(b, A_ITEMS, (size_t)nitems + 2)) break;  /* (both move the arrays) */
                bt_item *items = ARR(b, A_ITEMS, bt_item);
                if (fn) items[nitems++] = (bt_item){fv, fn, at * 2};
                if (bn) items[nitems++] = (bt_item){bv, bn, at * 2 + 1};
            } else if (in || out) {
                /* Wholly on one side: its edges on the line need no node of their own. */
                for (int i = 0; i < it.n; i++)
                    if (on[i] && on[i + 1 == it.n ? 0 : i + 1] && same_line(&l, &f[i].l)) f[i].add = 0;
                ARR(b, A_ITEMS, bt_item)[nitems++] = (bt_item){it.v0, it.n, at * 2 + (in ? 0 : 1)};
            }
            continue;
        }
        if (at != EMPTY) continue;  /* solid: hidden */
        /* A sliver (the near-miss of two lines) would take the whole leaf
         * if none of its edges were lines to add: none of its area is real. */
        if (frag_area(ARR(b, A_VERTS, bt_vert) + it.v0, it.n) < MIN_AREA) continue;
        /* Visible: the leaf becomes the fragment's edges, ending solid. */
        drawn++;
        int slot = it.slot;
        for (int i = 0; i < it.n; i++) {
            const bt_vert *v = ARR(b, A_VERTS, bt_vert) + it.v0 + i;
            if (!v->add || covers_band(&v->l, b, w)) continue;
            if (!need(b, A_NODES, (size_t)HDR(b)->nnodes + 1)) return drawn;
            int k = HDR(b)->nnodes++;
            ARR(b, A_NODES, bt_node)[k] = (bt_node){ARR(b, A_VERTS, bt_vert)[it.v0 + i].l, {EMPTY, EMPTY}};
            *slot_at(b, slot) = k;
            slot = k * 2;
            HDR(b)->empties++;  /* its outside */
        }
        *slot_at(b, slot) = SOLID(s);
        HDR(b)->empties--;
    }
    return drawn;
}

/* Surface p's pieces [0, *npieces) made into the pieces not hidden by
 * surface q of the same leaf (emptied pieces keep n 0; new ones appended). */
static void subtract(ew_band *b, const ew_spolys *sp, const ew_surf *surfs, int p, int q, int *npieces) {
    const ew_surf *P = &surfs[p], *Q = &surfs[q];
    ew_line hl[EW_MAX_POLY + 1];
    int nh = 0;
    /* Where q is nearer than p: inside q, and where its 1/z is larger
     * (ties as the edge list breaks them: the faster growing to the right). */
    ew_line g;
    if (ew_line_norm(Q->zi_u - P->zi_u, Q->zi_v - P->zi_v, Q->zi_0 - P->zi_0, &g)) hl[nh++] = g;
    else if (!(Q->zi_0 > P->zi_0 || (Q->zi_0 == P->zi_0 && q < p))) return;
    const ew_spoly *qp = &sp->polys[q];
    for (int i = 0; i < qp->n && nh <= EW_MAX_POLY; i++) hl[nh++] = sp->verts[qp->first + i].l;
    int end = *npieces;
    for (int k = 0; k < end; k++) {
        bt_item x = ARR(b, A_PIECES, bt_item)[k];
        ARR(b, A_PIECES, bt_item)[k].n = 0;  /* replaced by what is left of it */
        int rv = x.v0, rn = x.n;
        for (int h = 0; h < nh && rn; h++) {
            int ov, on = clip(b, rv, rn, &hl[h], 0, 1, &ov);
            if (on) {
                if (!need(b, A_PIECES, (size_t)*npieces + 1)) return;
                ARR(b, A_PIECES, bt_item)[(*npieces)++] = (bt_item){ov, on, 0};
            }
            /* The cut bounds the outside pieces made after this one too:
             * without it one could reach past p's edges clipped off here. */
            int iv, in = clip(b, rv, rn, &hl[h], 1, 1, &iv);
            rv = iv, rn = in;
        }
    }
}

/* The band's rectangle of pixel areas, as lines with their insides in. */
static void band_rect(const ew_band *b, double w, ew_line rect[4]) {
    ew_line_norm(1, 0, 0.5, &rect[0]);          /* x > -0.5 */
    ew_line_norm(-1, 0, w - 0.5, &rect[1]);     /* x < w - 0.5 */
    ew_line_norm(0, 1, 0.5 - b->y0, &rect[2]);  /* y > y0 - 0.5 */
    ew_line_norm(0, -1, b->y1 - 0.5, &rect[3]); /* y < y1 - 0.5 */
    for (int k = 0; k < 4; k++) rect[k].grid = 1;
}

/* Surface s's polygon clipped to the band: the first of the pieces. */
static int start_piece(ew_band *b, const ew_spolys *sp, int s, const ew_line rect[4]) {
    const ew_spoly *pl = &sp->polys[s];
    if (!need(b, A_VERTS, (size_t)HDR(b)->nverts + (size_t)pl->n)) return 0;
    bt_vert *v = ARR(b, A_VERTS, bt_vert) + HDR(b)->nverts;
    for (int i = 0; i < pl->n; i++) {
        const ew_spoly_vert *q = &sp->verts[pl->first + i];
        v[i] = (bt_vert){q->x, q->y, q->l, 1};
    }
    int v0 = HDR(b)->nverts, n = pl->n;
    HDR(b)->nverts += n;
    for (int k = 0; k < 4 && n; k++) n = clip(b, v0, n, &rect[k], 1, 0, &v0);
    if (!n) return 0;
    if (!need(b, A_PIECES, 1)) return 0;
    ARR(b, A_PIECES, bt_item)[0] = (bt_item){v0, n, 0};
    return 1;
}

/* Row y walked down the tree: each leaf's share of it becomes a span. */
static void raster_row(ew_band *b, int w, int y) {
    int nrows = 0, cur = -1, cu0 = 0, cu1 = 0;
    ARR(b, A_ROWS, bt_row)[nrows++] = (bt_row){HDR(b)->root, 0, w};
    while (nrows > 0) {
        bt_row it = ARR(b, A_ROWS, bt_row)[--nrows];
        if (it.node < 0) {
            int s = it.node == EMPTY ? 0 : -2 - it.node;
            if (s == cur && it.x0 == cu1) {
                cu1 = it.x1;
            } else {
                if (cur >= 0) ew_band_span(b, cur, cu0, cu1, y);
                cur = s, cu0 = it.x0, cu1 = it.x1;
            }
            continue;
        }
        const bt_node *nd = &ARR(b, A_NODES, bt_node)[it.node];
        const ew_line *l = &nd->l;
        double rowc = ew_line_row(l, y);
        int lo = it.x0, hi = it.x1, xs;
        int left, right;  /* the children taking [x0, xs) and [xs, x1) */
        if (l->a == 0) {
            xs = hi;
            left = nd->child[ew_line_in(l, lo, rowc) ? 0 : 1], right = left;
        } else {
            /* The test is monotonic along the row: estimate where it flips, then settle it by the test itself. */
            double e = ceil(-rowc / l->a);
            xs = e > lo ? (e < hi ? (int)e : hi) : lo;
            int inside_right = l->a > 0;
            while (xs > lo && ew_line_in(l, xs - 1, rowc) == inside_right) xs--;
            while (xs < hi && ew_line_in(l, xs, rowc) != inside_right) xs++;
            left = nd->child[inside_right ? 1 : 0], right = nd->child[inside_right ? 0 : 1];
        }
        if (!need(b, A_ROWS, (size_t)nrows + 2)) break;
        bt_row *rows = ARR(b, A_ROWS, bt_row);
        if (xs < hi) rows[nrows++] = (bt_row){right, xs, hi};  /* the left part pops first */
        if (lo < xs) rows[nrows++] = (bt_row){left, lo, xs};
    }
    if (cur >= 0) ew_band_span(b, cur, cu0, cu1, y);
}

static void beam_begin(ew_hsr_ctx *c) { ew_spolys_begin(c); }

static void beam_resolve(const ew_hsr_ctx *c, ew_band *b) {
    const int w = c->f->target.width;
    const ew_spolys *sp = c->spolys;
    const ew_surf *surfs = c->el->surfs;
    b->nspans = 0;
    memset(b->has_spans, 0, (size_t)c->el->nsurfs);
    bt_hdr *h = arena(b);
    if (!h || !sp || sp->failed) {  /* out of memory: the background alone, counted */
        b->dropped++;
        for (int y = b->y0; y < b->y1; y++) ew_band_span(b, 0, 0, w, y);
        return;
    }
    h->root = EMPTY, h->nnodes = 0, h->empties = 1, h->oom = 0;
    ew_line rect[4];
    band_rect(b, w, rect);
    long drawn = 0, rejected = 0, skipped = 0;
    for (int i = 0; i < sp->norder;) {
        /* A run of brush model fragments in one leaf: one group. */
        int j = i + 1;
        if (surfs[sp->order[i]].insubmodel)
            while (j < sp->norder && surfs[sp->order[j]].key == surfs[sp->order[i]].key &&
                   surfs[sp->order[j]].insubmodel)
                j++;
        for (int k = i; k < j; k++) {
            int s = sp->order[k];
            const ew_spoly *pl = &sp->polys[s];
            if (pl->y1 < b->y0 - 0.5f || pl->y0 > b->y1 - 0.5f) continue;  /* another band's */
            if (HDR(b)->empties == 0) {  /* the band is solid: nothing more can show */
                skipped++;
                continue;
            }
            HDR(b)->nverts = 0;
            if (!start_piece(b, sp, s, rect)) continue;
            int npieces = 1;
            for (int q = i; q < j; q++) {
                int qs = sp->order[q];
                const ew_spoly *qp = &sp->polys[qs];
                if (qs == s || qp->x1 < pl->x0 || qp->x0 > pl->x1 || qp->y1 < pl->y0 || qp->y0 > pl->y1) continue;
                subtract(b, sp, surfs, s, qs, &npieces);
            }
            int shown = 0;
            for (int p = 0; p < npieces; p++) {
                bt_item x = ARR(b, A_PIECES, bt_item)[p];
                if (x.n) shown += insert(b, w, s, x.v0, x.n);
            }
            drawn += shown;
            rejected += shown == 0;
        }
        i = j;
    }
    for (int y = b->y0; y < b->y1; y++) raster_row(b, w, y);
    if (HDR(b)->oom) b->dropped++;
    b->counters[0] = HDR(b)->nnodes;
    b->counters[1] = drawn;
    b->counters[2] = rejected;
    b->counters[3] = skipped;
}

/* The polygons, and what the bands' trees use of their scratch (another
 * method may have grown it further). */
static size_t beam_memory(const ew_hsr_ctx *c) {
    size_t n = ew_spolys_memory(c);
    for (int i = 0; i < c->nbands; i++) {
        const ew_band *b = &c->bands[i];
        const bt_hdr *h = b->scratch_bytes >= sizeof(bt_hdr) ? b->scratch : NULL;
        if (h && h->magic == MAGIC) n += h->off[A_N - 1] + h->cap[A_N - 1] * elem[A_N - 1];
    }
    return n;
}

const ew_hsr ew_hsr_beamtree = {
    "beamtree", EW_HSR_MAKES_SPANS | EW_HSR_EXACT_ONCE, beam_begin, ew_spolys_face, ew_spolys_poly, NULL,
    beam_resolve, beam_memory,
    {"beam tree nodes", "fragments drawn", "polygons rejected", "polygons skipped by early out"}};
