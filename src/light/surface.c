/* Surface building: tile the face's texture (at the chosen mip level) into a
 * buffer the size of the face, lighting each texel from the face's light
 * map.  Light samples sit every 16 texels (or where the map's BSPX layout
 * puts them) and are interpolated bilinearly between them; up to four light
 * styles add up.  One light value per texel and channel, in colormap rows
 * (8.8), becomes the texel in one of three ways:
 *   - 8-bit, white light: through the colormap, as the original;
 *   - 8-bit, coloured light: the palette colour times the light curve per
 *     channel, mapped to the nearest palette colour (ordered dither optional);
 *   - true colour: the palette colour times the light curve per channel.
 * The light curve is fitted to the colormap itself (light/curve.c), so white
 * light in true colour looks like the 8-bit frame, only smoother. */
#include "light/light.h"
#include "ew_util.h"  /* ew_debug_mode, ew_light_fault */

#include <string.h>

#include "ew_simd.h"

int ew_face_mip(const ew_view *v, const ew_world *w, const ew_face *f, float nearzi) {
    float scale = nearzi * (v->xscale > v->yscale ? v->xscale : v->yscale) * w->texinfo[f->texinfo].mipadjust;
    /* Coarser mips once a texel covers less than a pixel (0.8 leaves a little
     * sharpness margin, as the original did). */
    if (scale >= 1.0f) return 0;
    if (scale >= 0.4f) return 1;
    if (scale >= 0.2f) return 2;
    return 3;
}

const ew_texture *ew_face_texture(const ew_world *w, const ew_face *f, double time) {
    const ew_texture *t = &w->textures[w->texinfo[f->texinfo].texture];
    if (t->anim_total <= 0 || time <= 0) return t;
    int frame = (int)(time * 5.0) % t->anim_total;  /* five frames a second */
    for (int guard = 0; guard < 20 && !(frame >= t->anim_min && frame < t->anim_max); guard++) {
        if (t->anim_next < 0) break;
        t = &w->textures[t->anim_next];
    }
    return t;
}

static int wrap(int x, int n) {
    x %= n;
    return x < 0 ? x + n : x;
}

/* Where a face's light samples are: Quake's grid (every 16 texels from
 * texturemins), or a BSPX layout (facelm). */
typedef struct lm_layout {
    int smax, tmax, lightofs;
    int standard;                 /* Quake's grid: the exact fixed-point stepping */
    const float (*st_to_lm)[3];   /* otherwise: texture point -> sample */
} lm_layout;

static lm_layout face_layout(const ew_world *w, const ew_face *f) {
    lm_layout L = {(f->extents[0] >> 4) + 1, (f->extents[1] >> 4) + 1, f->lightofs, 1, NULL};
    if (!w->facelm) return L;
    const ew_facelm *lm = &w->facelm[f - w->faces];
    /* No light map (or no samples): Quake's grid, unlit, so the face is
     * dark as in the same map without BSPX and every sample index is in
     * the buffer gather fills. */
    if (lm->lightofs < 0 || lm->width < 1 || lm->height < 1) {
        L.lightofs = -1;
        return L;
    }
    /* A layout equal to Quake's (LMSHIFT 4) takes Quake's path, exactly. */
    const float std[2][3] = {{1.0f / 16, 0, -(float)f->texturemins[0] / 16},
                             {0, 1.0f / 16, -(float)f->texturemins[1] / 16}};
    if (lm->width == L.smax && lm->height == L.tmax && memcmp(lm->st_to_lm, std, sizeof std) == 0) {
        L.lightofs = lm->lightofs;
        return L;
    }
    L.smax = lm->width, L.tmax = lm->height, L.lightofs = lm->lightofs;
    L.standard = 0, L.st_to_lm = lm->st_to_lm;
    return L;
}

int ew_face_samples(const ew_world *w, const ew_face *f) {
    lm_layout L = face_layout(w, f);
    return L.smax * L.tmax;
}

/* Light 0..255*256 (per sample, styles summed) becomes a colormap row in
 * 8.8: bright maps to low rows; the top is held just short of the
 * overbright end. */
static inline int light_row(int bl) {
    int t = (255 * 256 - bl) >> 2;
    return t < (1 << 6) ? (1 << 6) : t;
}

/* The samples of a face, nc channels interleaved (1: white, 3: RGB), as
 * colormap rows; with nc 3 and rgbsrc 0 the white light in all three (for
 * coloured dynamic lights on it).  Returns 1 if every sample is grey (r = g = b). */
static int gather(const ew_lit *lit, const ew_frame *fr, const ew_world *w, const ew_face *f, const lm_layout *L,
                  const int light[4], unsigned dlights, int nc, int rgbsrc, int *bl) {
    int size = L->smax * L->tmax, n = size * nc, grey = 1;
    if (!w->lighting || lit->dbg->mode == EW_DEBUG_TEXTURES) {
        for (int i = 0; i < n; i++) bl[i] = 32 << 8;  /* unlit map (or textures only): colours as they are */
        return 1;
    }
    /* Start dark; a face without a light map stays dark, as in Quake. */
    for (int i = 0; i < n; i++) bl[i] = 0;
    if (L->lightofs >= 0) {
        if (nc == 1) {
            const uint8_t *lm = w->lighting + L->lightofs;
            for (int k = 0; k < 4 && f->styles[k] != 255; k++, lm += size)
                for (int i = 0; i < size; i++) bl[i] += lm[i] * light[k];
        } else if (!rgbsrc) {
            const uint8_t *lm = w->lighting + L->lightofs;
            for (int k = 0; k < 4 && f->styles[k] != 255; k++, lm += size)
                for (int i = 0; i < n; i++) bl[i] += lm[i / 3] * light[k];
        } else {
            const uint8_t *lm = w->rgblight + (size_t)L->lightofs * 3;
            for (int k = 0; k < 4 && f->styles[k] != 255; k++, lm += (size_t)size * 3)
                for (int i = 0; i < n; i++) bl[i] += lm[i] * light[k];
        }
    }
    if (w == fr->world) ew_add_dlights(fr, lit->scene, f, dlights, bl, nc, L->smax, L->tmax, L->st_to_lm);
    if (nc == 3)
        for (int i = 0; i < size && grey; i++) grey = bl[i * 3] == bl[i * 3 + 1] && bl[i * 3] == bl[i * 3 + 2];
    for (int i = 0; i < n; i++) bl[i] = light_row(bl[i]);
    return grey;
}

/* The light oracle's controls (ew_set_light_fault): the samples moved one
 * to the left (each texel lit by its right-hand neighbour's light), or read
 * with s and t swapped (held to the map's size). */
static void light_fault(int fault, int *bl, int smax, int tmax, int nc) {
    if (smax <= 0 || tmax <= 0) return;
    if (fault == EW_LIGHT_FAULT_SHIFT) {
        for (int j = 0; j < tmax; j++)
            for (int i = 0; i + 1 < smax; i++)
                for (int k = 0; k < nc; k++) bl[(j * smax + i) * nc + k] = bl[(j * smax + i + 1) * nc + k];
        return;
    }
    /* swap: sample (i, j) takes (j, i); a copy first, in the scratch's spare room (3 channels a sample) */
    int n = smax * tmax * nc, *old = bl + n;
    if (nc == 3) return;  /* no spare room: the white light is enough of a control */
    for (int i = 0; i < n; i++) old[i] = bl[i];
    for (int j = 0; j < tmax; j++)
        for (int i = 0; i < smax; i++) {
            int si = j < smax ? j : smax - 1, sj = i < tmax ? i : tmax - 1;
            bl[j * smax + i] = old[sj * smax + si];
        }
}

/* How texels are made from the palette index and the light. */
enum { OUT_CMAP, OUT_NEAREST, OUT_RGBA };

typedef struct emitter {
    int mode, nc;
    int fence;                 /* true colour: index 255 is a hole (alpha 0) */
    const uint8_t *cmap;
    const ew_lightcurve *lc;
    const ew_blend *cube;      /* OUT_NEAREST: the cubes' steps */
    const uint8_t *hue;        /* OUT_NEAREST: the cube of nearest colours for coloured light */
    int dither;
} emitter;

/* Coloured light tinted less than 1/NEAR_GREY of its level (the channels'
 * spread over their mean) keeps the colormap's ramps in 8-bit frames: a
 * mild tint moved to the palette's few pinks and greens shows as blotches
 * on grey walls, not as the soft glow true colour draws. */
#define NEAR_GREY 4
/* Colours mixed by the ordered dither (over the 16 places of its pattern). */
#define DITHER_N 2

/* 4x4 ordered dither offsets, in 1/16. */
static const int8_t bayer[4][4] = {{0, 8, 2, 10}, {12, 4, 14, 6}, {3, 11, 1, 9}, {15, 7, 13, 5}};

/* OUT_NEAREST: the texel's ramp (the colormap's own colour at the
 * channels' mean light, the 8-bit look), and in *grey whether the light is
 * tinted less than 1/NEAR_GREY of its level (rows are 64 a light level,
 * level 0 at row 255), so the ramp is drawn as white light would draw it. */
static inline uint8_t ramp_of(const emitter *e, uint8_t c, const int *l, int *grey) {
    int mean = (l[0] + l[1] + l[2]) / 3;
    int lo = l[0] < l[1] ? l[0] : l[1], hi = l[0] < l[1] ? l[1] : l[0];
    lo = lo < l[2] ? lo : l[2], hi = hi > l[2] ? hi : l[2];
    *grey = (hi - lo) * NEAR_GREY <= 255 * 64 - mean;
    return e->cmap[(mean & 0xFF00) + c];
}

/* OUT_NEAREST for a tint: the palette colour nearest the RGB by a distance
 * that counts chroma twice (EW_HUE_DIST: a colour of the light's hue over
 * a grey one a little nearer in brightness, so the blue cube reads blue,
 * not grey-blue), or the ramp's where it is as near. */
static inline uint8_t hue_pick(const emitter *e, uint8_t ramp, const int *rgb) {
    const uint8_t *pal = e->lc->palette;
    uint8_t near = e->hue[ew_blend_at(e->cube, rgb[0], rgb[1], rgb[2])];
    int da = 0, dn = 0, sa = 0, sn = 0;
    for (int k = 0; k < 3; k++) {
        int a = pal[ramp * 3 + k] - rgb[k], n = pal[near * 3 + k] - rgb[k];
        da += a * a, dn += n * n, sa += a, sn += n;
    }
    return EW_HUE_DIST(da, sa) <= EW_HUE_DIST(dn, sn) ? ramp : near;
}

/* Texel x of a row: palette index c, light rows l[0..nc-1]. */
static inline void emit(const emitter *e, uint8_t *out8, uint32_t *out32, int x, int dx, int dy, uint8_t c,
                        const int *l) {
    const ew_lightcurve *lc = e->lc;
    if (e->mode == OUT_CMAP) {
        out8[x] = e->cmap[(l[0] & 0xFF00) + c];
        return;
    }
    int rgb[3];
    for (int k = 0; k < 3; k++) rgb[k] = ew_lightcurve_at(lc, c, l[e->nc == 3 ? k : 0], k);
    if (e->mode == OUT_RGBA) {
        out32[x] = c == 255 && e->fence ? 0 : ew_rgba(rgb[0], rgb[1], rgb[2]);
        return;
    }
    if (lc->fullbright[c]) {
        out8[x] = c;
        return;
    }
    int grey;
    const uint8_t ramp = ramp_of(e, c, l, &grey);
    if (grey) {
        out8[x] = ramp;
        return;
    }
    if (!e->dither) {
        out8[x] = hue_pick(e, ramp, rgb);
        return;
    }
    /* Pattern dither: DITHER_N palette colours whose mean comes near the
     * RGB (each the nearest colour of the RGB plus the error the ones
     * before it left), taken in order of lightness by the texel's place in
     * the 4x4 pattern: a mix reaches colours between the palette's (more of
     * the tint, the lightness kept) and a gradient that falls between two
     * colours shows no contour rings. */
    const uint8_t *pal = lc->palette;
    const ew_blend *cb = e->cube;
    int err[3] = {0, 0, 0}, cand[DITHER_N], lum[DITHER_N];
    for (int i = 0; i < DITHER_N; i++) {
        int q[3];
        for (int k = 0; k < 3; k++) {
            int v = rgb[k] + err[k];
            q[k] = v < 0 ? 0 : v > 255 ? 255 : v;
        }
        int p = cb->nearest[ew_blend_at(cb, q[0], q[1], q[2])];
        for (int k = 0; k < 3; k++) err[k] += rgb[k] - pal[p * 3 + k];
        /* insertion by lightness (ties keep their order) */
        int lp = pal[p * 3] * 2 + pal[p * 3 + 1] * 3 + pal[p * 3 + 2], j = i;
        for (; j > 0 && lum[j - 1] > lp; j--) cand[j] = cand[j - 1], lum[j] = lum[j - 1];
        cand[j] = p, lum[j] = lp;
    }
    out8[x] = (uint8_t)cand[bayer[dy & 3][dx & 3] * DITHER_N / 16];
}

#if EW_SIMD4
/* One row of a block of bs (8 or 16) texels whose texture columns are
 * consecutive: dst[x] = cmap[(l & 0xFF00) + src[x]] with l = right +
 * (bs - 1 - x) * step, the light the scalar loop reaches at x stepping
 * leftwards from right.  The light in 16-bit lanes: bits 8 to 15 of l are
 * those of l taken modulo 2^16, so the indices are the same. */
static inline void cmap_row(uint8_t *dst, const uint8_t *src, const uint8_t *cmap, int right, int step, int bs) {
    const ew_v4i hi8 = ew_v4i_set1_16(0xFF00);
    const ew_v4i vr = ew_v4i_set1_16(right), vs = ew_v4i_set1_16(step);
    for (int x0 = 0; x0 < bs; x0 += 8) {
        ew_v4i k = ew_v4i_add16(ew_v4i_setr16(7, 6, 5, 4, 3, 2, 1, 0), ew_v4i_set1_16(bs - 8 - x0));
        ew_v4i l = ew_v4i_add16(vr, ew_v4i_mullo16(vs, k));
        ew_v4i tex = ew_v4i_bytes_lo(ew_v4i_load8(src + x0));
        ew_v4i idx = ew_v4i_add16(ew_v4i_and(l, hi8), tex);
        uint8_t *d = dst + x0;
        d[0] = cmap[EW_V4I_U16(idx, 0)];
        d[1] = cmap[EW_V4I_U16(idx, 1)];
        d[2] = cmap[EW_V4I_U16(idx, 2)];
        d[3] = cmap[EW_V4I_U16(idx, 3)];
        d[4] = cmap[EW_V4I_U16(idx, 4)];
        d[5] = cmap[EW_V4I_U16(idx, 5)];
        d[6] = cmap[EW_V4I_U16(idx, 6)];
        d[7] = cmap[EW_V4I_U16(idx, 7)];
    }
}
#endif

/* The colormap path of ew_build_surface: each block of bs x bs texels
 * between four light samples, stepped in fixed point from the right-hand
 * sample leftwards, as the original did (the same rounding gives the same
 * light rings). */
#if defined(__GNUC__)
__attribute__((always_inline))
#endif
static inline void cmap_blocks(uint8_t *out, int width, const int *bl, int smax, int tmax, const uint8_t *tp,
                               int tw, int th, int s0, int t0, const uint8_t *cmap, int bs, int shift) {
    for (int j = 0; j < tmax - 1; j++) {
        for (int i = 0; i < smax - 1; i++) {
            int l00 = bl[j * smax + i], l10 = bl[j * smax + i + 1];
            int l01 = bl[(j + 1) * smax + i], l11 = bl[(j + 1) * smax + i + 1];
            int lstep = (l01 - l00) >> shift, rstep = (l11 - l10) >> shift;
            int left = l00, right = l10;
            /* The block's last texture column and first texture row; when
             * its columns do not run past the texture's left edge they are
             * consecutive, and the texel loop needs no wrap. */
            int sx0 = (s0 + i * bs + bs - 1) % tw, ty = (t0 + j * bs) % th;
            for (int y = 0; y < bs; y++, left += lstep, right += rstep) {
                const uint8_t *row = tp + ty * tw;
                if (++ty == th) ty = 0;
                uint8_t *dst = out + (size_t)(j * bs + y) * width + i * bs;
                int step = (left - right) >> shift, l = right;
                if (sx0 >= bs - 1) {
                    const uint8_t *src = row + sx0 - (bs - 1);
#if EW_SIMD4
                    if (bs >= 8) {
                        cmap_row(dst, src, cmap, right, step, bs);
                        continue;
                    }
#endif
                    for (int x = bs - 1; x >= 0; x--, l += step) dst[x] = cmap[(l & 0xFF00) + src[x]];
                    continue;
                }
                int sx = sx0;
                for (int x = bs - 1; x >= 0; x--, l += step) {
                    dst[x] = cmap[(l & 0xFF00) + row[sx]];
                    if (--sx < 0) sx = tw - 1;
                }
            }
        }
    }
}

typedef void cmap_block_fn(uint8_t *, int, const int *, int, int, const uint8_t *, int, int, int, int,
                           const uint8_t *);
#define CMAP_BLOCKS(bs, shift)                                                                          \
    static void cmap_blocks##bs(uint8_t *out, int width, const int *bl, int smax, int tmax,             \
                                const uint8_t *tp, int tw, int th, int s0, int t0, const uint8_t *cmap) { \
        cmap_blocks(out, width, bl, smax, tmax, tp, tw, th, s0, t0, cmap, bs, shift);                   \
    }
CMAP_BLOCKS(16, 4)
CMAP_BLOCKS(8, 3)
CMAP_BLOCKS(4, 2)
CMAP_BLOCKS(2, 1)

/* Block (i, j)'s light at its left and right edges and their steps down a
 * row, per channel, from the four samples at its corners. */
static inline void block_edges(const int *bl, int nc, int smax, int i, int j, int shift, int *left, int *right,
                               int *lstep, int *rstep) {
    for (int k = 0; k < nc; k++) {
        int l00 = bl[(j * smax + i) * nc + k], l10 = bl[(j * smax + i + 1) * nc + k];
        int l01 = bl[((j + 1) * smax + i) * nc + k], l11 = bl[((j + 1) * smax + i + 1) * nc + k];
        lstep[k] = (l01 - l00) >> shift, rstep[k] = (l11 - l10) >> shift;
        left[k] = l00, right[k] = l10;
    }
}

#if EW_SIMD4
/* True colour, two texels at once: p0 and p1 each one's light curve pair
 * (lightcurve.pair: a, the colour at its light row, and 2 (b - a), b the
 * colour at the next row), f128 each one's fraction of the way from a to
 * b times 128, per channel (texel 0 in lanes 0-3, texel 1 in 4-7).  The
 * high half of 2 (b - a) * 128 f is (b - a) * f >> 8, rounded down as the
 * shift does, both factors fit a signed 16-bit lane: exactly
 * ew_lightcurve_at. */
static inline ew_v4i curve2(ew_v4i p0, ew_v4i p1, ew_v4i f128) {
    return ew_v4i_add16(ew_v4i_lo_lo(p0, p1), ew_v4i_mulhi16(ew_v4i_hi_hi(p0, p1), f128));
}

/* One row of a true-colour block of bs (4, 8 or 16) texels, src its bs texel
 * indices: dst[x] the colour of src[x] under light l = right + (bs - 1 - x)
 * * step per channel (nc 1: white, the same light in all three; 3: RGB),
 * the light the scalar loop reaches at x stepping leftwards from right, as
 * cmap_row's.  The light in 16-bit lanes: below 1 << 14 (light_row's range,
 * and stepping between samples stays between them), so exact.  Alpha 255,
 * or 0 for colour 255 of a fence texture (a hole). */
static inline void rgba_row(uint32_t *dst, const uint8_t *src, const int16_t *pairs, const int *right,
                            const int *step, int nc, int fence, int bs) {
    const ew_v4i zero = ew_v4i_zero(), hi8 = ew_v4i_set1_16(0xFF00), lo8 = ew_v4i_set1_16(0xFF);
    const ew_v4i alpha = ew_v4i_set1((int32_t)0xFF000000u);
    for (int x0 = 0; x0 < bs; x0 += 8) {
        const ew_v4i k = ew_v4i_add16(ew_v4i_setr16(7, 6, 5, 4, 3, 2, 1, 0), ew_v4i_set1_16(bs - 8 - x0));
        uint8_t four[8] = {0};  /* bs 4: its four texels, not a read past them */
        if (bs < 8) memcpy(four, src, 4);
        const ew_v4i tex = ew_v4i_bytes_lo(ew_v4i_load8(bs < 8 ? four : src + x0));
        uint16_t idx[3][8];
        ew_v4i f[3];
        for (int ch = 0; ch < nc; ch++) {
            const ew_v4i l = ew_v4i_add16(ew_v4i_set1_16(right[ch]), ew_v4i_mullo16(ew_v4i_set1_16(step[ch]), k));
            ew_v4i_storeu(idx[ch], ew_v4i_add16(ew_v4i_and(l, hi8), tex));
            f[ch] = EW_V4I_SLL16(ew_v4i_and(l, lo8), 7);
        }
        ew_v4i t[4];  /* the fractions of texels (0, 1), (2, 3), (4, 5), (6, 7), per channel */
        if (nc == 1) {
            const ew_v4i lo = ew_v4i_zip16_lo(f[0], f[0]), hi = ew_v4i_zip16_hi(f[0], f[0]);
            t[0] = ew_v4i_zip_lo(lo, lo), t[1] = ew_v4i_zip_hi(lo, lo);
            t[2] = ew_v4i_zip_lo(hi, hi), t[3] = ew_v4i_zip_hi(hi, hi);
        } else {
            const ew_v4i rg_lo = ew_v4i_zip16_lo(f[0], f[1]), rg_hi = ew_v4i_zip16_hi(f[0], f[1]);
            const ew_v4i b_lo = ew_v4i_zip16_lo(f[2], zero), b_hi = ew_v4i_zip16_hi(f[2], zero);
            t[0] = ew_v4i_zip_lo(rg_lo, b_lo), t[1] = ew_v4i_zip_hi(rg_lo, b_lo);
            t[2] = ew_v4i_zip_lo(rg_hi, b_hi), t[3] = ew_v4i_zip_hi(rg_hi, b_hi);
        }
        ew_v4i hole = zero;
        if (fence) hole = ew_v4i_eq16(tex, lo8);
        const ew_v4i *pp = (const ew_v4i *)(const void *)pairs;  /* a pair a vector, 16-byte aligned */
        for (int h = 0; h < (bs < 8 ? 1 : 2); h++) {  /* texels 0-3, then 4-7 (bs 4: the lanes past its
                                                        * texels are computed, never looked up) */
            ew_v4i c[2];
            for (int q = 0; q < 2; q++) {
                const int i = h * 4 + q * 2;
                ew_v4i p0, p1;
                if (nc == 1) {
                    p0 = ew_v4i_load(pp + idx[0][i]), p1 = ew_v4i_load(pp + idx[0][i + 1]);
                } else {  /* each channel from the pair of its own light */
                    const ew_v4i mr = ew_v4i_setr16(-1, 0, 0, 0, -1, 0, 0, 0),
                                 mg = ew_v4i_setr16(0, -1, 0, 0, 0, -1, 0, 0),
                                 mb = ew_v4i_setr16(0, 0, -1, 0, 0, 0, -1, 0);
                    p0 = ew_v4i_or(ew_v4i_or(ew_v4i_and(ew_v4i_load(pp + idx[0][i]), mr),
                                             ew_v4i_and(ew_v4i_load(pp + idx[1][i]), mg)),
                                   ew_v4i_and(ew_v4i_load(pp + idx[2][i]), mb));
                    p1 = ew_v4i_or(ew_v4i_or(ew_v4i_and(ew_v4i_load(pp + idx[0][i + 1]), mr),
                                             ew_v4i_and(ew_v4i_load(pp + idx[1][i + 1]), mg)),
                                   ew_v4i_and(ew_v4i_load(pp + idx[2][i + 1]), mb));
                }
                c[q] = curve2(p0, p1, t[h * 2 + q]);
            }
            ew_v4i px = ew_v4i_or(ew_v4i_packus8(c[0], c[1]), alpha);
            if (fence) {
                const ew_v4i m = h ? ew_v4i_zip16_hi(hole, hole) : ew_v4i_zip16_lo(hole, hole);
                px = ew_v4i_andnot(m, px);
            }
            ew_v4i_storeu(dst + x0 + h * 4, px);
        }
    }
}

/* One row of an 8-bit coloured-light block (OUT_NEAREST, no dither): each
 * texel decided as emit decides it, from its RGB (rgb8, from rgba_row:
 * exactly ew_lightcurve_at) and its light, four at a time: each texel's
 * ramp (or itself, if fullbright) written and the cube's choice looked up
 * one by one, then, where any of the four is tinted, hue_pick's comparison
 * of the two for all four in the lanes (a texel that needs no pick has
 * its choice set to what was written, which the comparison keeps).  The
 * lanes took slope's cold frames, nearly every texel tinted, to 0.71x. */
_Static_assert(EW_HUE_WEIGHT == 2, "nearest_row's lanes compute EW_HUE_DIST as 6 d - s^2");
static inline void nearest_row(uint8_t *d8, const uint8_t *src, const uint8_t *rgb8, const int *right,
                               const int *step, const emitter *e, int bs) {
    const ew_v4i neg = ew_v4i_set1_16(-1), one = ew_v4i_set1_16(1), lo16 = ew_v4i_set1(0xFFFF);
    for (int x0 = 0; x0 < bs; x0 += 4) {
        uint8_t other[4];
        int pick = 0;
        for (int j = 0; j < 4; j++) {
            const int x = x0 + j;
            const uint8_t c = src[x];
            if (e->lc->fullbright[c]) {
                d8[x] = other[j] = c;
                continue;
            }
            const int l[3] = {right[0] + (bs - 1 - x) * step[0], right[1] + (bs - 1 - x) * step[1],
                              right[2] + (bs - 1 - x) * step[2]};
            int grey;
            d8[x] = other[j] = ramp_of(e, c, l, &grey);
            if (!grey) {
                other[j] = e->hue[ew_blend_at(e->cube, rgb8[x * 4], rgb8[x * 4 + 1], rgb8[x * 4 + 2])];
                pick = 1;
            }
        }
        if (pick) {
            /* EW_HUE_DIST of each choice from the texel's RGB: the bytes'
             * differences as 16-bit lanes (alpha 255 on both sides: 0), their
             * squares and sums by pairs, then each texel's two pairs added. */
            const uint8_t *keep = d8 + x0;  /* each texel's ramp (or itself), written above */
            const uint32_t kc[4] = {e->lc->rgba[keep[0]], e->lc->rgba[keep[1]], e->lc->rgba[keep[2]],
                                    e->lc->rgba[keep[3]]};
            const uint32_t oc[4] = {e->lc->rgba[other[0]], e->lc->rgba[other[1]], e->lc->rgba[other[2]],
                                    e->lc->rgba[other[3]]};
            const ew_v4i t = ew_v4i_loadu(rgb8 + x0 * 4);
            const ew_v4i tlo = ew_v4i_mullo16(ew_v4i_bytes_lo(t), neg), thi = ew_v4i_mullo16(ew_v4i_bytes_hi(t), neg);
            ew_v4i dist[2];
            for (int k = 0; k < 2; k++) {
                const ew_v4i v = ew_v4i_loadu(k ? oc : kc);
                const ew_v4i dlo = ew_v4i_add16(ew_v4i_bytes_lo(v), tlo), dhi = ew_v4i_add16(ew_v4i_bytes_hi(v), thi);
                ew_v4i qlo = ew_v4i_madd16(dlo, dlo), qhi = ew_v4i_madd16(dhi, dhi);
                ew_v4i slo = ew_v4i_madd16(dlo, one), shi = ew_v4i_madd16(dhi, one);
                qlo = ew_v4i_add(qlo, EW_V4I_SHUF(qlo, 1, 0, 3, 2)), qhi = ew_v4i_add(qhi, EW_V4I_SHUF(qhi, 1, 0, 3, 2));
                slo = ew_v4i_add(slo, EW_V4I_SHUF(slo, 1, 0, 3, 2)), shi = ew_v4i_add(shi, EW_V4I_SHUF(shi, 1, 0, 3, 2));
                const ew_v4i d = ew_v4i_lo_lo(EW_V4I_SHUF(qlo, 0, 2, 1, 3), EW_V4I_SHUF(qhi, 0, 2, 1, 3));
                const ew_v4i sum = ew_v4i_lo_lo(EW_V4I_SHUF(slo, 0, 2, 1, 3), EW_V4I_SHUF(shi, 0, 2, 1, 3));
                const ew_v4i d2 = ew_v4i_add(d, d);
                /* sum^2 by one multiply-add of its low half (|sum| <= 765) with itself */
                dist[k] = ew_v4i_sub(ew_v4i_add(d2, ew_v4i_add(d2, d2)), ew_v4i_madd16(sum, ew_v4i_and(sum, lo16)));
            }
            /* the ramp where it is as near: EW_HUE_DIST(keep) <= EW_HUE_DIST(other) */
            uint32_t kept[4];
            ew_v4i_storeu(kept, ew_v4i_eq(ew_v4i_min(dist[0], dist[1]), dist[0]));
            for (int j = 0; j < 4; j++)
                if (!kept[j]) d8[x0 + j] = other[j];
        }
    }
}

/* The vector paths of ew_build_surface for blocks of bs >= 4 texels:
 * cmap_blocks' stepping per channel, each row of a block by rgba_row, into
 * true colour (near NULL), or through nearest_row into 8-bit texels for
 * coloured light (near: the emitter, nc 3). */
#if defined(__GNUC__)
__attribute__((always_inline))
#endif
static inline void rgba_blocks(void *out, int width, const int *bl, int nc, int smax, int tmax, const uint8_t *tp,
                               int tw, int th, int s0, int t0, const int16_t *pairs, int fence, const emitter *near,
                               int bs, int shift) {
    uint8_t wrapped[16];
    _Alignas(16) uint8_t rgb8[16 * 4];
    for (int j = 0; j < tmax - 1; j++) {
        for (int i = 0; i < smax - 1; i++) {
            int left[3], right[3], lstep[3], rstep[3];
            block_edges(bl, nc, smax, i, j, shift, left, right, lstep, rstep);
            int sx0 = (s0 + i * bs + bs - 1) % tw, ty = (t0 + j * bs) % th;
            for (int y = 0; y < bs; y++) {
                const uint8_t *row = tp + ty * tw, *src = row + sx0 - (bs - 1);
                if (++ty == th) ty = 0;
                if (sx0 < bs - 1) {  /* the block runs past the texture's left edge: its columns, wrapped */
                    for (int x = bs - 1, sx = sx0; x >= 0; x--) {
                        wrapped[x] = row[sx];
                        if (--sx < 0) sx = tw - 1;
                    }
                    src = wrapped;
                }
                int step[3];
                for (int k = 0; k < nc; k++) step[k] = (left[k] - right[k]) >> shift;
                const size_t at = (size_t)(j * bs + y) * width + i * bs;
                if (near) {
                    rgba_row((uint32_t *)(void *)rgb8, src, pairs, right, step, nc, 0, bs);
                    nearest_row((uint8_t *)out + at, src, rgb8, right, step, near, bs);
                } else {
                    rgba_row((uint32_t *)out + at, src, pairs, right, step, nc, fence, bs);
                }
                for (int k = 0; k < nc; k++) left[k] += lstep[k], right[k] += rstep[k];
            }
        }
    }
}

typedef void rgba_block_fn(uint32_t *, int, const int *, int, int, const uint8_t *, int, int, int, int,
                           const int16_t *, int);
#define RGBA_BLOCKS(bs, shift, nc)                                                                          \
    static void rgba_blocks##bs##_##nc(uint32_t *out, int width, const int *bl, int smax, int tmax,         \
                                       const uint8_t *tp, int tw, int th, int s0, int t0, const int16_t *pairs, \
                                       int fence) {                                                         \
        rgba_blocks(out, width, bl, nc, smax, tmax, tp, tw, th, s0, t0, pairs, fence, NULL, bs, shift);     \
    }
RGBA_BLOCKS(16, 4, 1)
RGBA_BLOCKS(16, 4, 3)
RGBA_BLOCKS(8, 3, 1)
RGBA_BLOCKS(8, 3, 3)
RGBA_BLOCKS(4, 2, 1)
RGBA_BLOCKS(4, 2, 3)

/* The 8-bit coloured-light path (OUT_NEAREST, no dither), bs a constant
 * in each copy as above. */
#define NEAREST_BLOCKS(bs, shift)                                                                              \
    static void nearest_blocks##bs(uint8_t *out, int width, const int *bl, int smax, int tmax, const uint8_t *tp, \
                                   int tw, int th, int s0, int t0, const emitter *e) {                          \
        rgba_blocks(out, width, bl, 3, smax, tmax, tp, tw, th, s0, t0, &e->lc->pair[0][0][0], 0, e, bs, shift); \
    }
NEAREST_BLOCKS(16, 4)
NEAREST_BLOCKS(8, 3)
NEAREST_BLOCKS(4, 2)
#endif

/* A lit surface of width x height texels in mip's colour (the mips debug mode). */
static void mip_surface(const ew_debug *dbg, int bpp, int mip, uint8_t *out, int width, int height) {
    size_t n = (size_t)width * (size_t)height;
    if (bpp == 1) {
        memset(out, (int)(uint8_t)dbg->mip[mip & 3], n);
        return;
    }
    for (size_t i = 0; i < n; i++) ew_set32(out, (int)i, dbg->mip[mip & 3]);
}

int ew_use_rgb_light(const ew_frame *f, const ew_world *w) {
    return w == f->world && w->rgblight && f->cfg.use_lit && !f->cfg.classic;
}

void ew_build_surface(const ew_lit *lit, const ew_frame *fr, const ew_world *w, const ew_face *f,
                      const ew_texture *tex, int mip, const int light[4], unsigned dlights,
                      uint8_t *out, int *scratch) {
    if (lit->dbg->mode == EW_DEBUG_MIPS) {  /* one colour per mip level */
        mip_surface(lit->dbg, fr->target.bpp, mip, out, ew_face_surf_size(f, 0, mip), ew_face_surf_size(f, 1, mip));
        return;
    }
    lm_layout L = face_layout(w, f);
    int truecolor = fr->target.bpp == 4;
    int rgbsrc = ew_use_rgb_light(fr, w);
    /* True colour lights in RGB where dynamic lights reach, even under
     * white light: they may be coloured. */
    /* Dynamic lights may be coloured: RGB where they reach (a white one
     * leaves the samples grey, and grey takes the white path below). */
    int rgb = rgbsrc || (dlights && w == fr->world && !fr->cfg.classic && (truecolor || lit->nearest));
    int *bl = scratch;
    int grey = gather(lit, fr, w, f, &L, light, dlights, rgb ? 3 : 1, rgbsrc, bl);
    int nc = rgb ? 3 : 1;
    if (fr->cfg.light_fault) light_fault(fr->cfg.light_fault, bl, L.smax, L.tmax, nc);
    if (rgb && grey) {  /* white after all: one channel, so 8-bit takes the colormap path exactly */
        for (int i = 0, n = L.smax * L.tmax; i < n; i++) bl[i] = bl[i * 3];
        nc = 1;
    }
    emitter e = {truecolor ? OUT_RGBA : nc == 3 ? OUT_NEAREST : OUT_CMAP, nc,
                 (tex->flags & EW_SURF_FENCE) && !fr->cfg.classic, fr->colormap, &lit->curve, NULL, NULL,
                 fr->cfg.dither};
    if (e.mode == OUT_NEAREST && !lit->nearest) e.mode = OUT_CMAP;  /* no table: white */
    e.cube = lit->blend;
    e.hue = lit->blend->hue ? lit->blend->hue : lit->nearest;  /* no memory for the hue cube: plain nearest */

    int tw = tex->width >> mip, th = tex->height >> mip;
    const uint8_t *tp = tex->mip[mip];
    if (lit->dbg->mode == EW_DEBUG_LIGHTING) tp = &lit->dbg->grey, tw = th = 1;  /* light maps only: a flat grey texture */
    int width = ew_face_surf_size(f, 0, mip), height = ew_face_surf_size(f, 1, mip);
    int s0 = wrap(f->texturemins[0] >> mip, tw), t0 = wrap(f->texturemins[1] >> mip, th);
    uint32_t *out32 = (uint32_t *)(void *)out;

    if (!L.standard || !f->extents[0] || !f->extents[1]) {
        /* A BSPX layout: each texel's sample position through the face's
         * own mapping, light interpolated bilinearly there.  Also Quake's
         * grid on a face of extent 0 along an axis (one row or column of
         * samples, a surface one texel thick), which the blocks below,
         * 16 texels between two samples, would leave unwritten. */
        static const float grid[2][3] = {{1.0f / 16, 0, 0}, {0, 1.0f / 16, 0}};
        const float (*m)[3] = L.st_to_lm ? L.st_to_lm : grid;
        float off[2] = {L.st_to_lm ? 0 : -(float)f->texturemins[0] / 16,
                        L.st_to_lm ? 0 : -(float)f->texturemins[1] / 16};
        float step = (float)(1 << mip);
        for (int y = 0; y < height; y++) {
            const uint8_t *row = tp + ((t0 + y) % th) * tw;
            uint8_t *d8 = out + (size_t)y * width;
            uint32_t *d32 = out32 + (size_t)y * width;
            float tt = (float)f->texturemins[1] + (float)y * step;
            for (int x = 0; x < width; x++) {
                float ss = (float)f->texturemins[0] + (float)x * step;
                float u = m[0][0] * ss + m[0][1] * tt + m[0][2] + off[0];
                float v = m[1][0] * ss + m[1][1] * tt + m[1][2] + off[1];
                /* clamped into the samples (smax, tmax >= 1: face_layout); NaN to 0 */
                u = u > 0 ? (u < (float)(L.smax - 1) ? u : (float)(L.smax - 1)) : 0;
                v = v > 0 ? (v < (float)(L.tmax - 1) ? v : (float)(L.tmax - 1)) : 0;
                int iu = (int)u, iv = (int)v;
                int iu1 = iu + 1 < L.smax ? iu + 1 : iu, iv1 = iv + 1 < L.tmax ? iv + 1 : iv;
                float fu = u - (float)iu, fv = v - (float)iv;
                int l[3];
                for (int k = 0; k < nc; k++) {
                    float a = (float)bl[(iv * L.smax + iu) * nc + k], b = (float)bl[(iv * L.smax + iu1) * nc + k];
                    float c = (float)bl[(iv1 * L.smax + iu) * nc + k], d = (float)bl[(iv1 * L.smax + iu1) * nc + k];
                    l[k] = (int)((a + (b - a) * fu) * (1 - fv) + (c + (d - c) * fu) * fv);
                }
                emit(&e, d8, d32, x, x, y, row[(s0 + x) % tw], l);
            }
        }
        return;
    }

    int bs = 16 >> mip, shift = 4 - mip, smax = L.smax, tmax = L.tmax;
    if (e.mode == OUT_CMAP) {  /* the original's path, kept tight */
        /* The block size as a constant in each copy, so the texel loops unroll. */
        cmap_block_fn *fn = mip == 0 ? cmap_blocks16 : mip == 1 ? cmap_blocks8 : mip == 2 ? cmap_blocks4 : cmap_blocks2;
        fn(out, width, bl, smax, tmax, tp, tw, th, s0, t0, fr->colormap);
        return;
    }
#if EW_SIMD4
    if (e.mode == OUT_NEAREST && bs >= 4 && !e.dither) {
        (bs == 16 ? nearest_blocks16 : bs == 8 ? nearest_blocks8 : nearest_blocks4)(out, width, bl, smax, tmax, tp, tw,
                                                                                  th, s0, t0, &e);
        return;
    }
    if (e.mode == OUT_RGBA && bs >= 4) {
        rgba_block_fn *fn = bs == 16 ? (nc == 3 ? rgba_blocks16_3 : rgba_blocks16_1)
                          : bs == 8  ? (nc == 3 ? rgba_blocks8_3 : rgba_blocks8_1)
                                     : (nc == 3 ? rgba_blocks4_3 : rgba_blocks4_1);
        fn(out32, width, bl, smax, tmax, tp, tw, th, s0, t0, &lit->curve.pair[0][0][0], e.fence);
        return;
    }
#endif
    /* The same stepping per channel, each texel through the emitter. */
    for (int j = 0; j < tmax - 1; j++) {
        for (int i = 0; i < smax - 1; i++) {
            int left[3], right[3], lstep[3], rstep[3];
            block_edges(bl, nc, smax, i, j, shift, left, right, lstep, rstep);
            for (int y = 0; y < bs; y++) {
                int yy = j * bs + y;
                const uint8_t *row = tp + ((t0 + yy) % th) * tw;
                uint8_t *d8 = out + (size_t)yy * width + i * bs;
                uint32_t *d32 = out32 + (size_t)yy * width + i * bs;
                int l[3], step[3];
                for (int k = 0; k < nc; k++) step[k] = (left[k] - right[k]) >> shift, l[k] = right[k];
                int sx = (s0 + i * bs + bs - 1) % tw;
                for (int x = bs - 1; x >= 0; x--) {
                    emit(&e, d8, d32, x, i * bs + x, yy, row[sx], l);
                    for (int k = 0; k < nc; k++) l[k] += step[k];
                    if (--sx < 0) sx = tw - 1;
                }
                for (int k = 0; k < nc; k++) left[k] += lstep[k], right[k] += rstep[k];
            }
        }
    }
}
