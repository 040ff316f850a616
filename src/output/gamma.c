/* Output gamma: a table per channel value, for the palette of 8-bit frames
 * and the pixels of true-colour frames (output/gamma.h). */
#include "output/gamma.h"

#include <math.h>
#include <string.h>

void ew_gamma_table(float g, uint8_t lut[256]) {
    for (int i = 0; i < 256; i++) {
        double v = g == 1 ? i : 255.0 * pow(i / 255.0, 1.0 / g) + 0.5;
        lut[i] = (uint8_t)(v > 255 ? 255 : v);
    }
}

/* Byte by byte in memory order (R, G, B, A), whatever the machine's. */
void ew_gamma_pixels(uint32_t *px, size_t n, const uint8_t lut[256]) {
    uint8_t *b = (uint8_t *)px;
    for (size_t i = 0; i < n; i++, b += 4) {
        b[0] = lut[b[0]];
        b[1] = lut[b[1]];
        b[2] = lut[b[2]];
    }
}
