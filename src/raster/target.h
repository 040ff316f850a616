/* The frame target (internal): where a frame's pixels and 1/z go.
 *
 * Every drawer writes through an ew_target: a row starts at
 * pixels + y * pitch, a pixel is bpp bytes.  Only the per-pixel store below
 * and the lit-surface texel differ by depth: 8-bit palette indices or
 * 32-bit pixels (the pixel helpers every stage uses are in frame.h). */
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
/* The per-pixel store of the 8-bit writer. */
static inline void ew_put8(uint8_t *dst, uint8_t index) { *dst = index; }
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
/* Texel i of a lit surface (1 or 4 bytes a texel, as the target) into pixel x. */
static inline void ew_put_texel(const ew_target *t, uint8_t *row, int x, const uint8_t *surf, size_t i) {
    if (t->bpp == 1)
        row[x] = surf[i];
    else
        memcpy(row + (size_t)x * 4, surf + i * 4, 4);
}
#endif
