/* Precalculated drawing masks for small triangles: the idea Black Book
 * chapter 69 puts forward and leaves untried ("precalculate drawing masks
 * ... for all possible small triangles (say, up to 4x4 or 5x5)").
 *
 * Vertices are snapped to whole pixels (pixel centres are integers), so a
 * triangle whose x and y extents are at most 4 is, moved to its box's
 * top-left corner, one of 25^3 vertex triples on a 5x5 grid.  For each
 * triple the table holds the pixels covered under the affine filler's rule
 * (a pixel centre inside the triangle, or on a top or left edge) as a
 * 25-bit mask, bit y * 5 + x.  Drawing a small triangle is then one lookup;
 * each covered row is a run of bits (a row meets a convex triangle in one
 * interval) drawn by the affine filler's own span code, so the pixels and
 * their colours and depths are those of the affine filler.  The table is
 * 25^3 * 4 = 62500 bytes, made once per process (pthread_once) and only
 * read after that. */
#include "raster/alias_tri.h"

#include <pthread.h>

#define BOX EW_MASK_BOX
#define GRID (BOX * BOX)

static uint32_t mask_table[GRID * GRID * GRID];
static pthread_once_t mask_once = PTHREAD_ONCE_INIT;

static int top_left(int px, int py, int qx, int qy) { return qy < py || (qy == py && qx > px); }

/* Edge p -> q against centre (x, y): > 0 inside for a positive cross. */
static int64_t edge_fn(int px, int py, int qx, int qy, int x, int y) {
    return (int64_t)(qx - px) * (y - py) - (int64_t)(qy - py) * (x - px);
}

static uint32_t coverage(int ax, int ay, int bx, int by, int cx, int cy) {
    if ((int64_t)(bx - ax) * (cy - ay) - (int64_t)(by - ay) * (cx - ax) <= 0) return 0;  /* back or flat */
    uint32_t m = 0;
    for (int y = 0; y < BOX; y++)
        for (int x = 0; x < BOX; x++) {
            int64_t e0 = edge_fn(ax, ay, bx, by, x, y), e1 = edge_fn(bx, by, cx, cy, x, y),
                    e2 = edge_fn(cx, cy, ax, ay, x, y);
            if ((e0 > 0 || (e0 == 0 && top_left(ax, ay, bx, by))) &&
                (e1 > 0 || (e1 == 0 && top_left(bx, by, cx, cy))) &&
                (e2 > 0 || (e2 == 0 && top_left(cx, cy, ax, ay))))
                m |= 1u << (y * BOX + x);
        }
    return m;
}

static void build_table(void) {
    for (int a = 0; a < GRID; a++)
        for (int b = 0; b < GRID; b++)
            for (int c = 0; c < GRID; c++)
                mask_table[(a * GRID + b) * GRID + c] =
                    coverage(a % BOX, a / BOX, b % BOX, b / BOX, c % BOX, c / BOX);
}

const uint32_t *ew_alias_mask_table(size_t *bytes) {
    pthread_once(&mask_once, build_table);
    if (bytes) *bytes = sizeof mask_table;
    return mask_table;
}

int ew_alias_masks_tri(ew_araster *ra, const ew_avert *a, const ew_avert *b, const ew_avert *c) {
    int32_t x0 = a->x, x1 = a->x, y0 = a->y, y1 = a->y;
    if (b->x < x0) x0 = b->x;
    if (b->x > x1) x1 = b->x;
    if (c->x < x0) x0 = c->x;
    if (c->x > x1) x1 = c->x;
    if (b->y < y0) y0 = b->y;
    if (b->y > y1) y1 = b->y;
    if (c->y < y0) y0 = c->y;
    if (c->y > y1) y1 = c->y;
    if (x1 - x0 >= BOX || y1 - y0 >= BOX) {
        ew_alias_affine_tri(ra, a, b, c);
        return 0;
    }
    pthread_once(&mask_once, build_table);
    int ia = (a->y - y0) * BOX + (a->x - x0), ib = (b->y - y0) * BOX + (b->x - x0),
        ic = (c->y - y0) * BOX + (c->x - x0);
    uint32_t m = mask_table[(ia * GRID + ib) * GRID + ic];
    if (!m) return 1;  /* back-facing, flat, or no pixel centre inside */
    /* Clip: the columns of the box inside [ra->x0, ra->x1), the rows inside
     * [ra->y0, ra->y1). */
    uint32_t cols = 0;
    for (int x = 0; x < BOX; x++)
        if (x0 + x >= ra->x0 && x0 + x < ra->x1) cols |= 1u << x;
    ew_atri tri;
    int setup = 0;
    for (int y = 0; y < BOX; y++, m >>= BOX) {
        uint32_t row = m & cols & ((1u << BOX) - 1);
        if (!row || y0 + y < ra->y0 || y0 + y >= ra->y1) continue;
        if (!setup) ew_alias_tri_setup(&tri, a, b, c), setup = 1;
        int xs = __builtin_ctz(row), xe = 32 - __builtin_clz(row);
        ew_alias_span(ra, &tri, y0 + y, x0 + xs, x0 + xe);
    }
    return 1;
}
