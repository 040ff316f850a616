/* The output gamma (internal, output/gamma.c). */
#ifndef EW_OUTPUT_GAMMA_H
#define EW_OUTPUT_GAMMA_H

#include <stddef.h>
#include <stdint.h>

/* The table of a channel through gamma g (out = 255 * (in / 255) ^ (1 /
 * g)); the gamma applied to n 32-bit pixels in place (R, G, B through lut,
 * A kept). */
void ew_gamma_table(float g, uint8_t lut[256]);
void ew_gamma_pixels(uint32_t *px, size_t n, const uint8_t lut[256]);

#endif
