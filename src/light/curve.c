/* The light curve of true colour, taken from the colormap itself: row k of
 * the colormap holds, for each palette colour, the colour the original drew
 * it with under light level k.  In RGB those rows are the curve: a light
 * level between two rows takes the straight line between their colours, so
 * white light in true colour looks like the 8-bit frame, only smoother
 * (the colormap's own quirks, such as bright rows moving a colour to
 * another ramp, are kept), and coloured light reads each channel from its
 * own level. */
#include "light/light.h"

void ew_lightcurve_fit(ew_lightcurve *lc, const uint8_t palette[768], const uint8_t *colormap) {
    lc->palette = palette;
    for (int c = 0; c < 256; c++) {
        int same = 1;
        for (int k = 0; k < 64 && same; k++) same = colormap[k * 256 + c] == c;
        lc->fullbright[c] = (uint8_t)same;
        lc->rgba[c] = ew_rgba(palette[c * 3], palette[c * 3 + 1], palette[c * 3 + 2]);
    }
    for (int k = 0; k < 64; k++)
        for (int c = 0; c < 256; c++) {
            int lit = colormap[k * 256 + c], next = colormap[(k < 63 ? k + 1 : 63) * 256 + c];
            for (int ch = 0; ch < 3; ch++) {
                lc->pair[k][c][ch] = palette[lit * 3 + ch];
                lc->pair[k][c][4 + ch] = (int16_t)(2 * (palette[next * 3 + ch] - palette[lit * 3 + ch]));
            }
            lc->pair[k][c][3] = lc->pair[k][c][7] = 0;
        }
}
