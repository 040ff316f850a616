/* 8-bit frames to 32-bit pixels for a display: R, G, B, A bytes in memory. */
#include "edgewise.h"

#include <string.h>

void ew_palette_rgba(const uint8_t palette[768], uint32_t out[256]) {
    for (int i = 0; i < 256; i++) {
        const uint8_t px[4] = { palette[i * 3], palette[i * 3 + 1], palette[i * 3 + 2], 255 };
        memcpy(&out[i], px, 4);  /* memory order, whatever the byte order */
    }
}

void ew_pixels_to_rgba(const uint8_t *pixels, size_t n, const uint32_t table[256], uint32_t *out) {
    for (size_t i = 0; i < n; i++) out[i] = table[pixels[i]];
}
