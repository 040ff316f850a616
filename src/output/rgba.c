/* 8-bit frames to 32-bit pixels for a display: R, G, B, A bytes in memory. */
#include "edgewise.h"

#include <string.h>

void ew_palette_rgba(const uint8_t palette[768], uint32_t out[256]) {
    for (int i = 0; i < 256; i++) {
        const uint8_t px[4] = { palette[i * 3], palette[i * 3 + 1], palette[i * 3 + 2], 255 };
        memcpy(&out[i], px, 4);  /* memory order, whatever the byte order */
    }
}

/* Eight pixels a step, all eight looked up before any is stored: at -O3
 * gcc turns the plain loop into emulated vector gathers, two to three
 * times slower than this (the viewer's present converts a frame a frame). */
void ew_pixels_to_rgba(const uint8_t *pixels, size_t n, const uint32_t table[256], uint32_t *out) {
    size_t blocks = n / 8;
    for (size_t b = 0; b < blocks; b++, pixels += 8, out += 8) {
        uint32_t p0 = table[pixels[0]], p1 = table[pixels[1]], p2 = table[pixels[2]], p3 = table[pixels[3]];
        uint32_t p4 = table[pixels[4]], p5 = table[pixels[5]], p6 = table[pixels[6]], p7 = table[pixels[7]];
        out[0] = p0, out[1] = p1, out[2] = p2, out[3] = p3, out[4] = p4, out[5] = p5, out[6] = p6, out[7] = p7;
    }
    for (size_t i = 0; i < n % 8; i++) out[i] = table[pixels[i]];
}
