/*
 * The built-in map's clip hulls 1 and 2: the space where the centre of a
 * player-sized box may be.
 *
 * A box with extents mins..maxs about its origin p touches a solid box
 * lo..hi exactly when lo - maxs < p < hi - mins, so the solid space of a
 * hull is the union of the solid boxes each grown by the hull's extents
 * (a Minkowski sum, which distributes over the union).  The level is made
 * of cells, so it is cut into a few boxes (runs of solid cells merged
 * along x, then y, then z; sky counts as solid, water does not, as in
 * Quake's clip hulls), plus six slabs for the solid outside the grid;
 * each is grown, and a BSP is built over the grown boxes:
 *
 *   - a region holding no box is empty, one a box covers whole is solid;
 *   - otherwise it is split on a box side inside it: the side that cuts
 *     the fewest other boxes, then the one that splits the boxes most
 *     evenly; each half keeps its boxes clipped to it.
 *
 * The split planes are axial; the front child is the side where the
 * coordinate is at least the plane's distance, as in the BSP's nodes.
 * Every box side is on a whole unit (cells of 16, extents whole), so the
 * hull is exact.  No bevel planes are needed: every solid is a box.
 */
#include "mapgen_internal.h"
#include "ew_util.h"
#include "ew_world.h"

#include <stdlib.h>
#include <string.h>

#define OUTSIDE (1 << 24)  /* the hull is built this far beyond the grid (every slab reaches it) */

typedef struct cbox {
    int lo[3], hi[3];
} cbox;

typedef struct cbuild {
    bi_clipnode *nodes;
    int          n, cap, oom;
} cbuild;

/* The solid cells (and sky) cut into boxes, grown; *n boxes in a new array. */
static cbox *grown_boxes(const bi_grid *g, const int mins[3], const int maxs[3], int *count) {
    size_t cells = (size_t)g->n[0] * g->n[1] * g->n[2];
    uint8_t *done = calloc(cells, 1);
    int cap = 256, n = 0;
    cbox *b = malloc(sizeof *b * (size_t)cap);
    if (!done || !b) { free(done), free(b); return NULL; }
#define CELL(x, y, z) (((size_t)(z) * g->n[1] + (y)) * g->n[0] + (x))
#define SOLID(x, y, z) (!done[CELL(x, y, z)] && (bi_kind(g, x, y, z) == BI_SOLID || bi_kind(g, x, y, z) == BI_SKY))
    for (int z = 0; z < g->n[2]; z++)
        for (int y = 0; y < g->n[1]; y++)
            for (int x = 0; x < g->n[0]; x++) {
                if (!SOLID(x, y, z)) continue;
                int x1 = x + 1, y1 = y + 1, z1 = z + 1;
                while (x1 < g->n[0] && SOLID(x1, y, z)) x1++;
                for (;; y1++) {
                    int ok = y1 < g->n[1];
                    for (int xx = x; xx < x1 && ok; xx++) ok = SOLID(xx, y1, z);
                    if (!ok) break;
                }
                for (;; z1++) {
                    int ok = z1 < g->n[2];
                    for (int yy = y; yy < y1 && ok; yy++)
                        for (int xx = x; xx < x1 && ok; xx++) ok = SOLID(xx, yy, z1);
                    if (!ok) break;
                }
                for (int zz = z; zz < z1; zz++)
                    for (int yy = y; yy < y1; yy++) memset(done + CELL(x, yy, zz), 1, (size_t)(x1 - x));
                if (n + 6 >= cap) {
                    cbox *nb = realloc(b, sizeof *b * (size_t)(cap *= 2));
                    if (!nb) { free(done), free(b); return NULL; }
                    b = nb;
                }
                const int lo[3] = {x, y, z}, hi[3] = {x1, y1, z1};
                for (int k = 0; k < 3; k++) b[n].lo[k] = lo[k] * BI_CELL, b[n].hi[k] = hi[k] * BI_CELL;
                n++;
            }
#undef SOLID
#undef CELL
    free(done);
    /* the outside: a slab beyond each side of the grid */
    for (int k = 0; k < 3; k++)
        for (int side = 0; side < 2; side++) {
            cbox *s = &b[n++];
            for (int j = 0; j < 3; j++) s->lo[j] = -2 * OUTSIDE, s->hi[j] = g->n[j] * BI_CELL + 2 * OUTSIDE;
            if (side) s->lo[k] = g->n[k] * BI_CELL;
            else s->hi[k] = 0;
        }
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) b[i].lo[k] -= maxs[k], b[i].hi[k] -= mins[k];
    *count = n;
    return b;
}

static int covers(const cbox *b, const int lo[3], const int hi[3]) {
    for (int k = 0; k < 3; k++)
        if (b->lo[k] > lo[k] || b->hi[k] < hi[k]) return 0;
    return 1;
}

/* The node for region lo..hi holding boxes b[0..n) (already clipped to
 * it; the array is the caller's scratch): a node index or a contents. */
static int build(cbuild *c, const int lo[3], const int hi[3], cbox *b, int n, int depth) {
    if (c->oom) return EW_CONTENTS_SOLID;
    if (n == 0) return EW_CONTENTS_EMPTY;
    for (int i = 0; i < n; i++)
        if (covers(&b[i], lo, hi)) return EW_CONTENTS_SOLID;
    /* the split: fewest boxes cut, then the most even count either side */
    long best = -1;
    int ba = -1, bd = 0;
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 3; k++)
            for (int s = 0; s < 2; s++) {
                int d = s ? b[i].hi[k] : b[i].lo[k];
                if (d <= lo[k] || d >= hi[k]) continue;
                int cut = 0, front = 0, back = 0;
                for (int j = 0; j < n; j++) {
                    if (b[j].lo[k] >= d) front++;
                    else if (b[j].hi[k] <= d) back++;
                    else cut++;
                }
                long score = (long)cut * 1000000L + labs((long)front - back);
                if (best < 0 || score < best) best = score, ba = k, bd = d;
            }
    if (ba < 0 || depth > 200) return EW_CONTENTS_SOLID;  /* cannot happen: a box not covering has a side inside */
    cbox *fb = malloc(sizeof *fb * (size_t)n * 2);
    if (!fb) { c->oom = 1; return EW_CONTENTS_SOLID; }
    cbox *bb = fb + n;
    int nf = 0, nb = 0;
    for (int j = 0; j < n; j++) {
        if (b[j].hi[ba] > bd) {
            fb[nf] = b[j];
            if (fb[nf].lo[ba] < bd) fb[nf].lo[ba] = bd;
            nf++;
        }
        if (b[j].lo[ba] < bd) {
            bb[nb] = b[j];
            if (bb[nb].hi[ba] > bd) bb[nb].hi[ba] = bd;
            nb++;
        }
    }
    if (c->n == c->cap) {
        int nc = c->cap ? c->cap * 2 : 256;
        bi_clipnode *q = realloc(c->nodes, sizeof *q * (size_t)nc);
        if (!q) { free(fb); c->oom = 1; return EW_CONTENTS_SOLID; }
        c->nodes = q, c->cap = nc;
    }
    int idx = c->n++;
    c->nodes[idx].axis = ba, c->nodes[idx].dist = bd;
    int flo[3], bhi[3];
    memcpy(flo, lo, sizeof flo), memcpy(bhi, hi, sizeof bhi);
    flo[ba] = bd, bhi[ba] = bd;
    int front = build(c, flo, hi, fb, nf, depth + 1);
    int back = build(c, lo, bhi, bb, nb, depth + 1);
    free(fb);
    c->nodes[idx].child[0] = front, c->nodes[idx].child[1] = back;
    return idx;
}

int bi_build_clip_hull(const bi_grid *g, const int mins[3], const int maxs[3], bi_clipnode **nodes, int *count) {
    *nodes = NULL, *count = 0;
    int n;
    cbox *b = grown_boxes(g, mins, maxs, &n);
    if (!b) return -1;
    cbuild c = {NULL, 0, 0, 0};
    int lo[3], hi[3];
    for (int k = 0; k < 3; k++) lo[k] = -OUTSIDE, hi[k] = g->n[k] * BI_CELL + OUTSIDE;
    int root = build(&c, lo, hi, b, n, 0);
    free(b);
    if (c.oom || root != 0) {  /* the grid's shell makes the root a node */
        free(c.nodes);
        return -1;
    }
    *nodes = c.nodes, *count = c.n;
    return 0;
}
