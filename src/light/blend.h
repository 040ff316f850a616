/* Colour arithmetic in 8-bit frames (internal, light/blend.c).  A paletted
 * frame cannot hold a blend or a fogged colour, so each is mapped back to
 * the nearest palette colour through tables built once per palette (and per
 * alpha or fog colour), the way the software renderers of the time did
 * translucency: a lookup per pixel, no dithering noise, and the frame keeps
 * its palette.  Fullbright colours (224..254) and the key colour 255 are
 * never chosen as results: a blend must not glow or punch a hole. */
#ifndef EW_RASTER_BLEND_H
#define EW_RASTER_BLEND_H

#include <stdint.h>

#define EW_BLEND_LEVELS 16   /* alpha quantized to 1/16 */
#define EW_FOG_LEVELS   64   /* fog amount quantized to 1/64 */

typedef struct ew_blend {
    const uint8_t *palette;                  /* the palette the tables are for */
    uint8_t  *nearest;                       /* 64x64x64 RGB cube -> palette index */
    uint8_t  *hue;                           /* the same cube, nearest by ew_blend_hue_dist */
    uint8_t   q[256];                        /* channel value -> cube step: finer in the darks */
    uint8_t  *alpha[EW_BLEND_LEVELS + 1];    /* [level][src * 256 + dst], built on first use */
    uint8_t  *fog;                           /* [level * 256 + colour] for fog_rgb */
    float     fog_rgb[3];
    int       fog_full;                      /* the rows from this level on map every colour to fog_full_colour */
    uint8_t   fog_full_colour;
    uint8_t   tint[256];                     /* the underwater tint for tint_rgb/tint_amount */
    int       tint_rgb[3], tint_amount;      /* tint[] is valid for these (amount 0: none built) */
    uint8_t  *build_c, *build_h;             /* the cubes being built (ew_blend_cube_begin) */
} ew_blend;

/* Starts empty (tables are built on first use); 0, or -1 out of memory. */
int  ew_blend_init(ew_blend *b, const uint8_t palette[768]);
void ew_blend_free(ew_blend *b);
/* The 64x64x64 cube of nearest colours, and beside it (b->hue) the cube of
 * the colours nearest by EW_HUE_DIST, for coloured light: built on first
 * use (serial); NULL out of memory (b->hue may be NULL alone).  Their steps
 * follow the square root of the value (fine in the darks, where the palette
 * is sparse and a coarse step shows as colour specks): the colour (r, g, b)
 * is at ew_blend_at(b, r, g, b). */
const uint8_t *ew_blend_cube(ew_blend *b);
/* The same in 64 slices that may run at once on any threads: begin
 * allocates what is missing (1: then ew_blend_cube_slice for every red
 * step r of 0..63, then ew_blend_cube_end; 0: nothing to build; -1: out of
 * memory), end makes them b->nearest and b->hue. */
int  ew_blend_cube_begin(ew_blend *b, int with_hue);
void ew_blend_cube_slice(const ew_blend *b, int r);
void ew_blend_cube_end(ew_blend *b);
static inline int ew_blend_at(const ew_blend *b, int r, int g, int bl) {
    return (b->q[r] << 12) | (b->q[g] << 6) | b->q[bl];
}
/* The distance of coloured light's texels: the squared RGB difference with
 * its chroma part (the difference less its grey part) counted
 * EW_HUE_WEIGHT times, its grey part once.  A tinted light then picks a
 * palette colour of its hue and chroma over a grey one a little nearer in
 * brightness.  (More weight buys more chroma from this palette, whose dark
 * blues and greens are greyish, at the price of lightness and of texture
 * detail: neighbouring texels fall on one colour.)  Arguments: the squared
 * RGB distance and the sum of the three differences; the result is three
 * times the weighted distance, in integers. */
#define EW_HUE_WEIGHT 2
#define EW_HUE_DIST(d2, sum) (3 * EW_HUE_WEIGHT * (d2) - (EW_HUE_WEIGHT - 1) * (sum) * (sum))
/* The alpha level of an opacity in (0, 1]: 1..EW_BLEND_LEVELS. */
int  ew_blend_level(float alpha);
/* The table of level (src over dst at level / EW_BLEND_LEVELS): built if
 * needed (serial: before the bands draw); NULL out of memory. */
const uint8_t *ew_blend_alpha(ew_blend *b, int level);
/* Fog tables for colour rgb (0..1): [k * 256 + c] is colour c fogged by
 * k / (EW_FOG_LEVELS - 1).  Rebuilt when the colour changes; NULL out of memory.
 * With them b->fog_full: the first level from which every row is one colour,
 * b->fog_full_colour (EW_FOG_LEVELS if even the last row is not), where a
 * pixel fogged that much need not be drawn first. */
const uint8_t *ew_blend_fog(ew_blend *b, const float rgb[3]);
/* tint[c]: colour c moved amount/256 of the way to rgb (0..255). */
const uint8_t *ew_blend_tint(ew_blend *b, const int rgb[3], int amount);

#endif
