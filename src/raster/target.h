/* The frame target (internal): where a frame's pixels and 1/z go.
 *
 * Every drawer writes through an ew_target: a row starts at
 * pixels + y * pitch, a pixel is bpp bytes: 1 for 8-bit palette indices,
 * 4 for true colour.  Only the per-pixel store below and the lit-surface
 * texel differ by depth (see docs/architecture.md). */
#ifndef EW_RASTER_TARGET_H
#define EW_RASTER_TARGET_H

#include "frame.h"

#include <stddef.h>
#include <stdint.h>
#include <string.h>


/* First pixel of row y, column x. */
static inline uint8_t *ew_target_at(const ew_target *t, int x, int y) {
    return t->pixels + (size_t)y * (size_t)t->pitch + (size_t)x * (size_t)t->bpp;
}
/* The z value under pixel (x, y). */
static inline float *ew_target_z(const ew_target *t, int x, int y) {
    return t->zbuf + (size_t)y * (size_t)t->width + (size_t)x;
}
/* The two pixel writers: palette index c into pixel x of a row, through a
 * table of 4-byte pixels in true colour (the target's, or a model's tinted one). */
static inline void ew_put_via(int bpp, const uint32_t *rgba, uint8_t *row, int x, uint8_t c) {
    if (bpp == 1)
        row[x] = c;
    else
        memcpy(row + (size_t)x * 4, &rgba[c], 4);
}
static inline void ew_put_index(const ew_target *t, uint8_t *row, int x, uint8_t c) {
    ew_put_via(t->bpp, t->rgba, row, x, c);
}
static inline uint32_t ew_get32(const uint8_t *row, int x) {
    uint32_t v;
    memcpy(&v, row + (size_t)x * 4, 4);
    return v;
}
static inline void ew_set32(uint8_t *row, int x, uint32_t v) { memcpy(row + (size_t)x * 4, &v, 4); }
/* Alpha 0: a fence texture's hole in a true-colour lit surface. */
static inline int ew_rgba_clear(uint32_t v) {
    uint8_t px[4];
    memcpy(px, &v, 4);
    return px[3] == 0;
}
/* Texel i of a lit surface (1 or 4 bytes a texel, as the target) into pixel x. */
static inline void ew_put_texel(const ew_target *t, uint8_t *row, int x, const uint8_t *surf, size_t i) {
    if (t->bpp == 1)
        row[x] = surf[i];
    else
        memcpy(row + (size_t)x * 4, surf + i * 4, 4);
}
/* A true-colour pixel: the bytes R, G, B, A (255) in memory, as
 * ew_palette_rgba (so a frame goes to a display or a PNG as it is). */
static inline uint32_t ew_rgba(int r, int g, int b) {
    uint8_t px[4] = {(uint8_t)r, (uint8_t)g, (uint8_t)b, 255};
    uint32_t v;
    memcpy(&v, px, 4);
    return v;
}
static inline void ew_rgba_split(uint32_t v, int rgb[3]) {
    uint8_t px[4];
    memcpy(px, &v, 4);
    rgb[0] = px[0], rgb[1] = px[1], rgb[2] = px[2];
}

#endif
