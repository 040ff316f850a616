/* The frame target (internal): where a frame's pixels and 1/z go.
 *
 * Every drawer writes through an ew_target: a row starts at
 * pixels + y * pitch, a pixel is bpp bytes.  Only the per-pixel store below
 * and the lit-surface texel differ by depth; 8-bit palette indices are the
 * only format today, a 32-bit writer is the second one the colour work adds
 * here (see docs/architecture.md). */
#ifndef EW_RASTER_TARGET_H
#define EW_RASTER_TARGET_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

typedef struct ew_target {
    uint8_t *pixels;        /* height rows of pitch bytes */
    float   *zbuf;          /* width * height 1/z values (larger is nearer, 0 is far) */
    int      width, height;
    int      pitch;         /* bytes from one row to the next */
    int      bpp;           /* bytes per pixel: 1 (palette indices) */
} ew_target;

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
