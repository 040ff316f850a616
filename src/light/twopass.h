/* Two-pass lighting (internal, light/twopass.c): the alternative to the
 * surface cache that chapter 69 of the Black Book weighs.  Pass one draws
 * a face's unlit texture; pass two lights every pixel it drew from the
 * face's light map, sampled bilinearly at that pixel.  No lit surface is
 * built and nothing is cached: every pixel is worked on twice.
 *
 * It is also the tests' light oracle, so it shares no code with
 * light/surface.c, the cache or the span drawers: each pixel's texture
 * point comes from its own ray-plane intersection, the light sample
 * position from the face's texture axes (or its BSPX layout), the styles
 * are summed and the light applied here.  It reads only the loaded world
 * (texinfo, faces, light lumps, textures), the palette and the colormap.
 *
 * Semantics (the ones the cache implements its own way): a pixel shows
 * texel (X, Y) of mip m, X = floor(s / 2^m) - texturemins / 2^m held to the
 * face's extents; that texel is lit by the light at its corner, texture
 * point (texturemins + X 2^m, ...): sample u = that point's offset / 16 on
 * Quake's grid, or the BSPX layout's st_to_lm of it.  Light per channel is
 * sum(sample * style value), 255 * 256 full; colormap row (8.8) =
 * (255 * 256 - light) / 4, at least 64 (one row short of overbright). */
#ifndef EW_LIGHT_TWOPASS_H
#define EW_LIGHT_TWOPASS_H

#include "world/view.h"

#include <stdint.h>

/* What every pixel of a frame needs: set once a frame (serial). */
typedef struct ew_twopass {
    const ew_world *world;
    const uint8_t  *palette;   /* 768 */
    const uint8_t  *colormap;  /* 64 rows of 256 */
    const int      *style;     /* 64 style values this frame (256: as compiled) */
    int             rgb;       /* light from the world's RGB light */
    int             bpp;       /* 1 or 4 */
    int             classic;   /* fences drawn with their key colour */
    const uint8_t  *fullbright_of;      /* the colormap fullbright[] was made for */
    uint8_t         fullbright[256];    /* 1: a colour every row leaves as it is */
} ew_twopass;

/* Sets the frame's inputs (the fullbright colours found again only when
 * the colormap changes). */
void ew_tp_begin(ew_twopass *tp, const ew_world *w, const uint8_t *palette, const uint8_t *colormap,
                 const int *style, int rgb, int bpp, int classic);

/* One face seen by one camera (the camera in the face's own space). */
typedef struct ew_tp_face {
    const ew_face    *f;
    const ew_texture *tex;
    int     mip, tw, th;       /* texture size at mip */
    int     mins[2], size[2];  /* texturemins and extents at mip, in texels */
    int     fence;             /* index 255 is a hole (alpha 0 in true colour) */
    /* the pixel (x, y)'s ray hits the plane at parameter k / den(x, y):
     * den = d0 + dx x + dy y; s = so + (s0 + sx x + sy y) k / den */
    double  k, d0, dx, dy;
    double  so[2], s0[2], sx[2], sy[2];
    /* light: samples a side, first sample, texture point -> sample */
    int     smax, tmax, lightofs;
    double  lm[2][3];
} ew_tp_face;

/* Sets pf for face index fi of tp's world at mip, seen through view v,
 * with the texture frame tex (animated textures: the caller's choice). */
void ew_tp_face_setup(const ew_twopass *tp, const ew_view *v, int fi, int mip, const ew_texture *tex,
                      ew_tp_face *pf);
/* Pass one: the texel (palette index) the pixel (x, y) shows, and its
 * coordinates X, Y (texels of the mip from texturemins). */
uint8_t ew_tp_texel(const ew_tp_face *pf, int x, int y, int *X, int *Y);
/* Pass two's light at texel (X, Y): per channel (three, equal in white
 * light), 0 .. 255 * 256 and more where styles add up. */
void ew_tp_light(const ew_twopass *tp, const ew_tp_face *pf, int X, int Y, int light[3]);
/* Texel index c under that light: a palette index (bpp 1) or an RGBA pixel
 * (bpp 4, alpha 0 for a fence's hole). */
uint32_t ew_tp_shade(const ew_twopass *tp, const ew_tp_face *pf, uint8_t c, const int light[3]);
/* Pixels [x0, x1) of row y (row: the target's row) in the two passes: the
 * unlit texels first, then each lit.  Fence holes are left as they were.
 * Exact: every pixel's own ray and the light in floating point (the
 * reference's, the oracle). */
void ew_tp_run(const ew_twopass *tp, const ew_tp_face *pf, uint8_t *row, int y, int x0, int x1);
/* The same as a software renderer would draw it (the renderer's
 * --lighting two-pass): a pixel's ray every 16 pixels and the texture
 * point stepped in between, the light map's samples interpolated in fixed
 * point (faces on Quake's grid; other layouts take ew_tp_light). */
void ew_tp_span(const ew_twopass *tp, const ew_tp_face *pf, uint8_t *row, int y, int x0, int x1);

#endif
