/* John Carmack's recursive subdivision rasterizer for small triangles
 * (Black Book chapter 69), with a fill rule of our own.
 *
 * Snapped vertices are integers, so a triangle is split at the rounded
 * midpoint of its longest edge (screen position, texel, light and 1/z all
 * halved with shifts; a screen half x.5 rounds to the even neighbour, so
 * repeated halving along an edge does not drift to one side) until no edge is longer than one pixel in x or y.
 * Such a triangle has no pixel centre but its three corners, and each corner
 * pixel is drawn by the one triangle around it that the top-left rule picks
 * there: the corner is drawn if both edges meeting at it are top or left
 * edges.  A shared edge splits the same way from both sides (a midpoint
 * depends only on the two endpoints), so in a mesh of triangles meeting
 * edge to edge every pixel inside is drawn, and drawn once where the split
 * triangles tile the plane.  Rounding can fold a split point across a
 * neighbouring edge (thin triangles); the few pixels a fold gives twice are
 * absorbed by the model's tile: the model is z-buffered into a small
 * buffer over its screen bounds and composited once, so every frame and
 * z-buffer pixel is written at most once per model. */
#include "raster/alias_tri.h"

#include <float.h>
#include <string.h>

/* 1 if the edge p -> q is a top or left edge of a triangle with positive
 * cross (interior on the right of the edge in y-down screen space). */
static inline int top_left(const ew_avert *p, const ew_avert *q) {
    return q->y < p->y || (q->y == p->y && q->x > p->x);
}

/* The texel of p through its light (looked up only for pixels that win:
 * most corners lose to a nearer one of the same model). */
static inline uint8_t texel(const ew_araster *ra, const ew_avert *p) {
    return ra->colormap[(p->l & 0x3F00) + ra->skin[(p->t >> 16) * ra->skinw + (p->s >> 16)]];
}

static inline void plot(ew_araster *ra, const ew_avert *p) {
    if (ra->tile_z) {
        size_t o = (size_t)(p->y - ra->ty0) * ra->tw + (p->x - ra->tx0);
        if (p->zi >= ra->tile_z[o]) {
            ra->tile_z[o] = p->zi;
            ra->tile_c[o] = texel(ra, p);
            ra->tile_f[o] = 1;
        }
        return;
    }
    float *z = ew_target_z(ra->target, p->x, p->y);
    if (p->zi >= *z) {
        uint8_t c = texel(ra, p);
        *z = p->zi;
        ew_put_via(ra->target->bpp, ra->rgba, ew_target_at(ra->target, 0, p->y), p->x, ra->remap ? ra->remap[c] : c);
        ra->pixels++;
    }
}

static void subdivide(ew_araster *ra, const ew_avert *a, const ew_avert *b, const ew_avert *c, int depth) {
    int32_t abx = b->x - a->x, aby = b->y - a->y;
    int32_t bcx = c->x - b->x, bcy = c->y - b->y;
    int32_t cax = a->x - c->x, cay = a->y - c->y;
    /* Every edge at most one pixel long in x and y (unsigned trick: -1..1). */
    if ((uint32_t)(abx + 1) <= 2 && (uint32_t)(aby + 1) <= 2 && (uint32_t)(bcx + 1) <= 2 &&
        (uint32_t)(bcy + 1) <= 2 && (uint32_t)(cax + 1) <= 2 && (uint32_t)(cay + 1) <= 2) {
        /* No pixel centres but the corners; area 1/2 (cross 1) or none. */
        if (abx * (c->y - a->y) - aby * (c->x - a->x) <= 0) return;
        int tab = top_left(a, b), tbc = top_left(b, c), tca = top_left(c, a);
        if (tca && tab) plot(ra, a);
        if (tab && tbc) plot(ra, b);
        if (tbc && tca) plot(ra, c);
        return;
    }
    if (depth > 48) return;  /* cannot happen for on-screen sizes; a guard */
    /* Rotate so that a -> b is the longest edge. */
    int32_t lab = abx * abx + aby * aby, lbc = bcx * bcx + bcy * bcy, lca = cax * cax + cay * cay;
    const ew_avert *t;
    if (lbc > lab && lbc >= lca) {
        t = a, a = b, b = c, c = t;
    } else if (lca > lab && lca > lbc) {
        t = a, a = c, c = b, b = t;
    }
    ew_avert m;
    int32_t sx = a->x + b->x, sy = a->y + b->y;  /* halves rounded to even: no drift */
    m.x = sx >> 1;
    m.y = sy >> 1;
    if (sx & 1) m.x += m.x & 1;
    if (sy & 1) m.y += m.y & 1;
    m.s = (a->s + b->s) >> 1;
    m.t = (a->t + b->t) >> 1;
    m.l = (a->l + b->l) >> 1;
    m.zi = (a->zi + b->zi) * 0.5f;
    subdivide(ra, c, a, &m, depth + 1);
    subdivide(ra, c, &m, b, depth + 1);
}

void ew_alias_subdiv_tri(ew_araster *ra, const ew_avert *a, const ew_avert *b, const ew_avert *c) {
    if (ew_alias_cross(a, b, c) <= 0) return;
    /* Every split point is within its corners' rows, and the tile's rows
     * outside [y0, y1) take nothing (ew_alias_tile_begin): a triangle of
     * another band's rows would only be split for naught. */
    if (ra->tile_cut) {
        int32_t ytop, ybot;
        ew_alias_tri_rows(a, b, c, &ytop, &ybot);
        if (ybot < ra->y0 || ytop >= ra->y1) return;
    }
    subdivide(ra, a, b, c, 0);
}

size_t ew_alias_tile_bytes(int w, int h) { return (size_t)w * h * (sizeof(float) + 2); }

void ew_alias_tile_begin(ew_araster *ra, int x0, int y0, int w, int h, void *mem) {
    uint8_t *p = mem;
    ra->tile_z = (float *)(void *)p;
    ra->tile_c = p + sizeof(float) * (size_t)w * h;
    ra->tile_f = ra->tile_c + (size_t)w * h;
    ra->tx0 = x0, ra->ty0 = y0, ra->tw = w, ra->th = h;
    ra->tile_cut = y0 < ra->y0 || y0 + h > ra->y1;
    for (int y = 0; y < h; y++) {
        float *tz = ra->tile_z + (size_t)y * w;
        if (y0 + y >= ra->y0 && y0 + y < ra->y1)
            memcpy(tz, ew_target_z(ra->target, x0, y0 + y), sizeof(float) * (size_t)w);
        else
            for (int x = 0; x < w; x++) tz[x] = FLT_MAX;
    }
    memset(ra->tile_f, 0, (size_t)w * h);
}

void ew_alias_tile_end(ew_araster *ra) {
    if (!ra->tile_z) return;
    long n = 0;
    for (int y = 0; y < ra->th; y++) {
        const uint8_t *f = ra->tile_f + (size_t)y * ra->tw, *c = ra->tile_c + (size_t)y * ra->tw;
        const float *z = ra->tile_z + (size_t)y * ra->tw;
        float *zr = ew_target_z(ra->target, ra->tx0, ra->ty0 + y);
        uint8_t *fr = ew_target_at(ra->target, ra->tx0, ra->ty0 + y);  /* column tx0 */
        for (int x = 0; x < ra->tw; x++)
            if (f[x]) {
                zr[x] = z[x];
                ew_put_via(ra->target->bpp, ra->rgba, fr, x, ra->remap ? ra->remap[c[x]] : c[x]);
                n++;
            }
    }
    ra->pixels += n;
    ra->tile_z = NULL, ra->tile_c = ra->tile_f = NULL;
    ra->tile_cut = 0;
}
