/* The alias models' triangle rasterizers (internal, Black Book chapter
 * 69): the affine filler with Gouraud shading (raster/alias_tri.c), the
 * mask rasterizer (alias_masks.c) and John Carmack's recursive subdivision
 * (alias_subdiv.c).  Below the model pipeline (raster/alias.c), which
 * poses, projects and culls a model's triangles and hands them here. */
#ifndef EW_ALIAS_TRI_H
#define EW_ALIAS_TRI_H

#include "raster/target.h"  /* the frame target and its pixel writers */

#include <stddef.h>
#include <stdint.h>

/* ---- rasterizer internals (exposed for the tests) ------------------------ */

/* The colormap row of a light level: 128 -> row 32 (the texture's own
 * colours), 255 -> row 0 (brightest), 0 -> row 63 (black), in 8.8. */
static inline int32_t ew_alias_light_row(int light) {
    if (light < 0) light = 0;
    if (light > 255) light = 255;
    int32_t row = (256 - light) * 64;
    return row > (63 << 8) + 255 ? (63 << 8) + 255 : row;
}

/* A projected vertex: integer pixel (pixel centres are integers), texel
 * coordinates in 16.16, light as a colormap row in 8.8, and 1/z. */
typedef struct ew_avert {
    int32_t x, y;
    int32_t s, t;
    int32_t l;
    float   zi;
} ew_avert;

/* What a triangle is drawn into and with. */
typedef struct ew_araster {
    const ew_target *target;            /* the frame and its z-buffer */
    const uint32_t  *rgba;              /* true colour: palette index -> pixel (tinted by the model's light) */
    const uint8_t   *remap;             /* 8-bit: palette index -> the tinted one, or NULL */
    int            x0, y0, x1, y1;      /* clip rectangle [x0, x1) x [y0, y1) */
    const uint8_t *skin;                /* skinw * skinh palette indices */
    int            skinw, skinh;
    const uint8_t *colormap;            /* 64 rows of 256 */
    long           pixels;              /* pixels that passed the z test */
    /* Subdivision only: when tile_z is set, pixels go to the model's tile
     * over [tx0, tx0 + tw) x [ty0, ty0 + th) (1/z, colour, written flag)
     * and reach the frame once, in ew_alias_tile_end. */
    float            *tile_z;
    uint8_t          *tile_c, *tile_f;
    int               tx0, ty0, tw, th;
    int               tile_cut;     /* the tile has rows outside [y0, y1) (another band's) */
} ew_araster;

/* Twice the signed area of the snapped triangle, y down.  Positive for a
 * front-facing triangle (the models wind front faces this way on screen);
 * zero for a degenerate one, so this one product culls both. */
static inline int64_t ew_alias_cross(const ew_avert *a, const ew_avert *b, const ew_avert *c) {
    return (int64_t)(b->x - a->x) * (c->y - a->y) - (int64_t)(b->y - a->y) * (c->x - a->x);
}
static inline int ew_alias_tri_visible(const ew_avert *a, const ew_avert *b, const ew_avert *c) {
    return ew_alias_cross(a, b, c) > 0;
}
/* The rows of the triangle's snapped corners, [*top, *bot]: no rasterizer
 * writes a row outside them. */
static inline void ew_alias_tri_rows(const ew_avert *a, const ew_avert *b, const ew_avert *c, int32_t *top,
                                     int32_t *bot) {
    int32_t t = a->y < b->y ? a->y : b->y, m = a->y > b->y ? a->y : b->y;
    *top = c->y < t ? c->y : t, *bot = c->y > m ? c->y : m;
}

/* Affine texture mapping with Gouraud shading and the top-left fill rule on
 * pixel centres: a pixel is drawn if its centre is inside the triangle, or
 * on a top or left edge.  Clipped to the rectangle; culls by the cross. */
void ew_alias_affine_tri(ew_araster *ra, const ew_avert *a, const ew_avert *b, const ew_avert *c);

/* A triangle set up for spans: its vertices sorted by y (v0 top) and the
 * screen gradients of texel, light and 1/z from v0.  ew_alias_span draws
 * row y over [xs, xe) with them exactly as the affine filler does (z-tested,
 * counted in ra->pixels); the caller clips xs, xe and y. */
typedef struct ew_agrad {
    float dx, dy, v0;  /* value at the triangle's first (top) vertex */
} ew_agrad;
typedef struct ew_atri {
    const ew_avert *v0, *v1, *v2;
    ew_agrad gs, gt, gl, gz;
} ew_atri;
void ew_alias_tri_setup(ew_atri *t, const ew_avert *a, const ew_avert *b, const ew_avert *c);
void ew_alias_span(ew_araster *ra, const ew_atri *t, int y, int xs, int xe);

/* Precalculated drawing masks (alias_masks.c, Black Book chapter 69's
 * suggestion): a triangle whose snapped vertices fit a 5x5-pixel box
 * (x and y extents at most EW_MASK_BOX - 1) looks its covered pixels up in
 * a table made once (the same top-left rule on pixel centres as the affine
 * filler, so the same pixels), and draws each covered row with
 * ew_alias_span; larger triangles go to the affine filler.  Returns 1 if
 * the table drew it. */
#define EW_MASK_BOX 5
int    ew_alias_masks_tri(ew_araster *ra, const ew_avert *a, const ew_avert *b, const ew_avert *c);
/* The table: 25^3 entries of a 25-bit mask (bit y * 5 + x); its bytes. */
const uint32_t *ew_alias_mask_table(size_t *bytes);

/* Recursive subdivision: the longest edge is split at its (rounded)
 * midpoint while it is longer than one pixel in x or y; the split vertex
 * takes the average of the endpoints' texel, light and 1/z.  Shared edges
 * split the same way from either side (a midpoint depends only on the two
 * endpoints).  At the bottom every triangle is a lattice triangle with no
 * pixel centres but its corners, and each corner is drawn by the one
 * triangle around it whose two edges there are top or left edges, so
 * triangles that tile the plane neither both draw a pixel nor leave one
 * out.  Every vertex must lie inside the clip rectangle (and the tile). */
void ew_alias_subdiv_tri(ew_araster *ra, const ew_avert *a, const ew_avert *b, const ew_avert *c);

/* The model's tile for the subdivision rasterizer: ew_alias_tile_bytes(w, h)
 * of memory at mem; begin loads the z-buffer under it, end writes back the
 * pixels the model won (each once) and counts them in ra->pixels. */
size_t ew_alias_tile_bytes(int w, int h);
/* Rows of the tile outside [ra->y0, ra->y1) start nearer than anything, so
 * nothing is drawn or written back there (another band owns them). */
void   ew_alias_tile_begin(ew_araster *ra, int x0, int y0, int w, int h, void *mem);
void   ew_alias_tile_end(ew_araster *ra);

#endif
