/* The light curve of true colour, fitted to the colormap: row k of the
 * colormap holds, for each palette colour, the colour the original drew it
 * with under light level k.  A least-squares multiplier per row (over the
 * colours light changes) turns that into "palette colour times brightness",
 * which true colour then applies exactly, and per channel for coloured
 * light.  With white light the result tracks the 8-bit frame, minus the
 * palette's quantization. */
#include "renderer.h"

void ew_lightcurve_fit(ew_lightcurve *lc, const uint8_t palette[768], const uint8_t *colormap) {
    lc->palette = palette;
    for (int c = 0; c < 256; c++) {
        int same = 1;
        for (int k = 0; k < 64 && same; k++) same = colormap[k * 256 + c] == c;
        lc->fullbright[c] = (uint8_t)same;
        lc->rgba[c] = ew_rgba(palette[c * 3], palette[c * 3 + 1], palette[c * 3 + 2]);
    }
    double m[65];
    for (int k = 0; k < 64; k++) {
        double num = 0, den = 0;
        for (int c = 0; c < 256; c++) {
            if (lc->fullbright[c]) continue;
            int lit = colormap[k * 256 + c];
            for (int ch = 0; ch < 3; ch++) {
                num += (double)palette[c * 3 + ch] * palette[lit * 3 + ch];
                den += (double)palette[c * 3 + ch] * palette[c * 3 + ch];
            }
        }
        m[k] = den > 0 ? num / den : 1.0;
    }
    m[64] = m[63];
    /* Index l >> 4 of a light row l (8.8): row (l >> 4) / 16, between rows. */
    for (int i = 0; i < 1024; i++) {
        int k = i >> 4;
        double f = (i & 15) / 16.0, v = m[k] + (m[k + 1] - m[k]) * f;
        int q = (int)(v * 256 + 0.5);
        lc->curve[i] = (uint16_t)(q < 0 ? 0 : q > 65535 ? 65535 : q);
    }
}
