/* Blend, fog and tint tables for 8-bit frames (light/blend.h). */
#include "light/blend.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define CHOICES 224  /* 224..255: fullbrights and the key colour, never a result */

static int nearest_exact(const uint8_t *pal, int r, int g, int b) {
    int best = 0, bestd = 1 << 30;
    for (int i = 0; i < CHOICES; i++) {
        int dr = pal[i * 3] - r, dg = pal[i * 3 + 1] - g, db = pal[i * 3 + 2] - b;
        int d = dr * dr + dg * dg + db * db;
        if (d < bestd) bestd = d, best = i;
    }
    return best;
}

int ew_blend_init(ew_blend *b, const uint8_t palette[768]) {
    memset(b, 0, sizeof *b);
    b->palette = palette;
    b->fog_rgb[0] = -1;  /* no fog table yet */
    b->tint_amount = -1; /* nor a tint */
    return 0;
}

void ew_blend_free(ew_blend *b) {
    free(b->build_c);
    free(b->build_h);
    free(b->nearest);
    free(b->hue);
    for (int i = 0; i <= EW_BLEND_LEVELS; i++) free(b->alpha[i]);
    free(b->fog);
    memset(b, 0, sizeof *b);
}

/* The RGB cubes (64 steps a channel), filled from the exact search at each
 * cell's centre: blends then cost three shifts and one lookup to map back.
 * with_hue also fills the cube for coloured light (EW_HUE_DIST); without
 * memory for it, that one stays NULL and the plain cube serves.  Built a
 * red step at a time (ew_blend_cube_slice), so a pool can share it out. */
int ew_blend_cube_begin(ew_blend *b, int with_hue) {
    int need_c = !b->nearest, need_h = with_hue && !b->hue;
    if (!need_c && !need_h) return 0;
    uint8_t *c = need_c ? malloc(64 * 64 * 64) : NULL, *h = need_h ? malloc(64 * 64 * 64) : NULL;
    if (need_c && !c) {
        free(h);
        return -1;
    }
    if (!c && !h) return 0;
    for (int v = 0; v < 256; v++) b->q[v] = (uint8_t)lrint(63.0 * sqrt(v / 255.0));
    b->build_c = c, b->build_h = h;
    return 1;
}

void ew_blend_cube_end(ew_blend *b) {
    if (b->build_c) b->nearest = b->build_c;
    if (b->build_h) b->hue = b->build_h;
    b->build_c = b->build_h = NULL;
}

/* Each cell's choice is the least, over the choices i, of a distance that
 * along the blue axis (x, the cell's blue centre) is A x^2 + m_i x + c_i
 * with the same A for every choice: the plain distance drg + (pb - x)^2
 * (m = -2 pb, c = pb^2 + drg; drg and srg the red-green part of the
 * squared distance and of the sum of differences, pb the choice's blue),
 * and EW_HUE_DIST, 3W (drg + u^2) - (W - 1) (srg + u)^2 with u = pb - x,
 * (2W + 1) x^2 + (2 (W - 1) srg - 2 (2W + 1) pb) x + 3W drg - (W - 1)
 * srg^2 + (2W + 1) pb^2 - 2 (W - 1) srg pb.  So the least at every x is
 * the least of the lines m_i x + c_i: their lower envelope, built once for
 * each (r, g) and swept along the 64 blue centres.  As keys 256 (m x + c)
 * + i no two choices are equal at a whole x (their difference would be a
 * multiple of 256 and a difference of indices), so the envelope's choice
 * is the first index at the least distance, what a loop over all the
 * choices picks, and the hull can drop ties freely.  All in 64 bits. */
typedef struct line { int64_t m, b; } line;

/* From the lines in order of falling slope (of equal slopes the least b
 * kept), each of the 64 blue centres' choice, out[bl]; hull: room for the
 * envelope. */
static void envelope(const line *l, const uint8_t *order, const int *centre, uint8_t *out, line *hull) {
    int h = 0;
    for (int j = 0; j < CHOICES; j++) {
        const line n = l[order[j]];
        if (h && hull[h - 1].m == n.m) {
            if (hull[h - 1].b <= n.b) continue;
            h--;
        }
        /* The top is needed only if the new line crosses the one below it
         * after the top does. */
        while (h >= 2 && (n.b - hull[h - 2].b) * (hull[h - 2].m - hull[h - 1].m) <=
                             (hull[h - 1].b - hull[h - 2].b) * (hull[h - 2].m - n.m))
            h--;
        hull[h++] = n;
    }
    for (int bl = 0, p = 0; bl < 64; bl++) {
        const int64_t x = centre[bl];
        while (p + 1 < h && hull[p + 1].m * x + hull[p + 1].b < hull[p].m * x + hull[p].b) p++;
        out[bl] = (uint8_t)(hull[p].b & 255);
    }
}

/* The choices by falling slope: an insertion sort from the last order,
 * which changes little from one g to the next. */
static void sort_falling(uint8_t *order, const line *l) {
    for (int j = 1; j < CHOICES; j++) {
        const uint8_t o = order[j];
        int k = j;
        for (; k > 0 && l[order[k - 1]].m < l[o].m; k--) order[k] = order[k - 1];
        order[k] = o;
    }
}

/* Red step r of the cubes ew_blend_cube_begin allocated.  (A loop over all
 * 224 choices a cell took about 130 ms for the two cubes, on the first
 * frame of every 8-bit map with coloured light.) */
void ew_blend_cube_slice(const ew_blend *b, int r) {
    uint8_t *c = b->build_c, *h = b->build_h;
    int centre[64];
    for (int k = 0; k < 64; k++) centre[k] = (int)lrint(255.0 * (k / 63.0) * (k / 63.0));
    const uint8_t *p = b->palette;
    enum { W = EW_HUE_WEIGHT };
    line lc[CHOICES], lh[CHOICES], hull[CHOICES];
    uint8_t oc[CHOICES], oh[CHOICES];
    for (int i = 0; i < CHOICES; i++) oc[i] = oh[i] = (uint8_t)i;
    for (int g = 0; g < 64; g++) {
        for (int i = 0; i < CHOICES; i++) {
            const int64_t dr = p[i * 3] - centre[r], dg = p[i * 3 + 1] - centre[g], pb = p[i * 3 + 2];
            const int64_t drg = dr * dr + dg * dg, srg = dr + dg;
            if (c) lc[i] = (line){256 * (-2 * pb), 256 * (pb * pb + drg) + i};
            if (h)
                lh[i] = (line){256 * (2 * (W - 1) * srg - 2 * (2 * W + 1) * pb),
                               256 * (3 * W * drg - (W - 1) * srg * srg + (2 * W + 1) * pb * pb - 2 * (W - 1) * srg * pb) +
                                   i};
        }
        if (c) {
            sort_falling(oc, lc);
            envelope(lc, oc, centre, c + (r << 12) + (g << 6), hull);
        }
        if (h) {
            sort_falling(oh, lh);
            envelope(lh, oh, centre, h + (r << 12) + (g << 6), hull);
        }
    }
}

static int build_cube(ew_blend *b, int with_hue) {
    int k = ew_blend_cube_begin(b, with_hue);
    if (k <= 0) return k;
    for (int r = 0; r < 64; r++) ew_blend_cube_slice(b, r);
    ew_blend_cube_end(b);
    return 0;
}

const uint8_t *ew_blend_cube(ew_blend *b) { return build_cube(b, 1) < 0 ? NULL : b->nearest; }

int ew_blend_level(float alpha) {
    int l = (int)lrintf(alpha * EW_BLEND_LEVELS);
    return l < 1 ? 1 : l > EW_BLEND_LEVELS ? EW_BLEND_LEVELS : l;
}

const uint8_t *ew_blend_alpha(ew_blend *b, int level) {
    if (level < 1) level = 1;
    if (level > EW_BLEND_LEVELS) level = EW_BLEND_LEVELS;
    if (b->alpha[level]) return b->alpha[level];
    if (build_cube(b, 0) < 0) return NULL;
    uint8_t *t = malloc(256 * 256);
    if (!t) return NULL;
    const uint8_t *p = b->palette;
    int a = level, na = EW_BLEND_LEVELS - level;
    for (int s = 0; s < 256; s++)
        for (int d = 0; d < 256; d++) {
            int r = (p[s * 3] * a + p[d * 3] * na) / EW_BLEND_LEVELS;
            int g = (p[s * 3 + 1] * a + p[d * 3 + 1] * na) / EW_BLEND_LEVELS;
            int bl = (p[s * 3 + 2] * a + p[d * 3 + 2] * na) / EW_BLEND_LEVELS;
            t[s * 256 + d] = b->nearest[ew_blend_at(b, r, g, bl)];
        }
    /* Opaque is exact: no colour changes at level 16. */
    if (level == EW_BLEND_LEVELS)
        for (int s = 0; s < 256; s++) memset(t + s * 256, s, 256);
    b->alpha[level] = t;
    return t;
}

const uint8_t *ew_blend_fog(ew_blend *b, const float rgb[3]) {
    if (b->fog && memcmp(rgb, b->fog_rgb, sizeof b->fog_rgb) == 0) return b->fog;
    uint8_t *t = b->fog ? b->fog : calloc(EW_FOG_LEVELS * 256 + 4, 1);  /* + 4: raster/fog.c's four-byte gathers */
    if (!t) return NULL;
    const uint8_t *p = b->palette;
    float fr = rgb[0] * 255, fg = rgb[1] * 255, fb = rgb[2] * 255;
    for (int k = 0; k < EW_FOG_LEVELS; k++) {
        float f = (float)k / (EW_FOG_LEVELS - 1);
        for (int c = 0; c < 256; c++) {
            if (k == 0) {  /* no fog: the colour itself, fullbrights included */
                t[c] = (uint8_t)c;
                continue;
            }
            int r = (int)lrintf(p[c * 3] + (fr - p[c * 3]) * f);
            int g = (int)lrintf(p[c * 3 + 1] + (fg - p[c * 3 + 1]) * f);
            int bl = (int)lrintf(p[c * 3 + 2] + (fb - p[c * 3 + 2]) * f);
            t[k * 256 + c] = (uint8_t)nearest_exact(p, r, g, bl);
        }
    }
    /* The last rows are often one colour: the nearest to the fog's. */
    int full = EW_FOG_LEVELS;
    for (int k = EW_FOG_LEVELS - 1; k > 0; k--) {
        const uint8_t *row = t + k * 256;
        int one = row[0] == t[(EW_FOG_LEVELS - 1) * 256];
        for (int c = 1; c < 256 && one; c++) one = row[c] == row[0];
        if (!one) break;
        full = k;
    }
    b->fog_full = full;
    b->fog_full_colour = t[(EW_FOG_LEVELS - 1) * 256];
    memcpy(b->fog_rgb, rgb, sizeof b->fog_rgb);
    b->fog = t;
    return t;
}

const uint8_t *ew_blend_tint(ew_blend *b, const int rgb[3], int amount) {
    if (b->tint_amount == amount && memcmp(rgb, b->tint_rgb, sizeof b->tint_rgb) == 0) return b->tint;
    const uint8_t *p = b->palette;
    for (int c = 0; c < 256; c++) {
        int r = p[c * 3] + (rgb[0] - p[c * 3]) * amount / 256;
        int g = p[c * 3 + 1] + (rgb[1] - p[c * 3 + 1]) * amount / 256;
        int bl = p[c * 3 + 2] + (rgb[2] - p[c * 3 + 2]) * amount / 256;
        b->tint[c] = amount ? (uint8_t)nearest_exact(p, r, g, bl) : (uint8_t)c;
    }
    memcpy(b->tint_rgb, rgb, sizeof b->tint_rgb);
    b->tint_amount = amount;
    return b->tint;
}
