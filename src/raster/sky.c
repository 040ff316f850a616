/* Sky: Quake's two scrolling layers seen as a flattened dome.  The ray
 * through the pixel, with its height stretched 3x, is normalized and its
 * x, y pick texels; the front layer (left half, colour 0 = clear) scrolls
 * twice as fast as the back layer (right half).  Unlit.  Spans compute the
 * exact coordinates every 32 pixels and step linearly between, as the
 * original did; the reference path computes every pixel. */
#include "raster/raster.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "ew_simd.h"

#define SKY_STEP 32

/* Power-of-two layers (Quake's are 128x128) wrap with a mask; the spans'
 * lanes take those whose wrapped integer parts fit 16-bit lanes. */
static int sky_pow2(const ew_texture *t) {
    int half = t->width / 2, rows = t->height;
    return half > 0 && (half & (half - 1)) == 0 && rows > 0 && (rows & (rows - 1)) == 0;
}
static int sky_in_lanes(const ew_texture *t) {
    return sky_pow2(t) && t->width < 32768 && (unsigned)t->width * (unsigned)t->height <= 65536u;
}

int ew_sky_comp_make(ew_sky_comp *sc, const ew_texture *t, float scroll) {
    if (!EW_SIMD4 || !sky_in_lanes(t) || !(scroll >= 0 && scroll < 8192)) return -1;  /* the lanes' spans read them */
    /* A segment's back layer lies Ds = fs - bs behind the front one in 16.16
     * (sky_span: fs = floor((S0 + 2 scroll) 65536), bs = floor((S0 + scroll)
     * 65536), |S0| at most 6 (rows / 2 - 1): 378 texels for Quake's 128
     * rows).  Then the two sums round by at most 2^-11 each, so Ds is within
     * 65 of scroll * 65536: its integer part is round(scroll) - 1 or
     * round(scroll), and a borrow adds one.  (A taller sky's segment that
     * falls outside the planes is drawn layer by layer: sky_comp_run.) */
    const int w0 = (int)floorf(scroll + 0.5f) - 1;
    if (sc->tex == t && sc->w0 == w0) return 0;
    const unsigned half = (unsigned)t->width / 2, rows = (unsigned)t->height, width = (unsigned)t->width;
    const unsigned hm = half - 1, rm = rows - 1;
    const size_t plane = (size_t)half * rows;
    if (sc->cap < 9 * plane) {
        uint8_t *p = realloc(sc->planes, 9 * plane);
        if (!p) {
            sc->tex = NULL;
            return -1;
        }
        sc->planes = p, sc->cap = 9 * plane;
    }
    const uint8_t *px = t->mip[0];
    uint8_t row[16384];  /* half < 16384 (sky_in_lanes) */
    for (int b = 0; b < 3; b++)
        for (int a = 0; a < 3; a++) {
            uint8_t *out = sc->planes + (size_t)(a + 3 * b) * plane;
            const unsigned sx = (unsigned)(w0 + a) & hm;
            for (unsigned y = 0; y < rows; y++) {
                const uint8_t *front = px + (size_t)y * width;
                const uint8_t *back = px + (size_t)((y - (unsigned)(w0 + b)) & rm) * width + half;
                /* row[x] = back[(x - sx) & hm]: the back row turned by sx */
                memcpy(row, back + half - sx, sx);
                memcpy(row + sx, back, half - sx);
                uint8_t *o = out + (size_t)y * half;
                for (unsigned x = 0; x < half; x++) o[x] = front[x] ? front[x] : row[x];
            }
        }
    sc->tex = t, sc->w0 = w0;
    return 0;
}

void ew_sky_comp_free(ew_sky_comp *sc) {
    free(sc->planes);
    *sc = (ew_sky_comp){0};
}

static int wrap(int x, int n) {
    x %= n;
    return x < 0 ? x + n : x;
}

/* Layer coordinates (texels, before scrolling) of the ray through (u, y). */
static void sky_st(const ew_view *v, const ew_texture *t, float u, float y, float *s, float *tt) {
    float a = (u - v->width * 0.5f) / v->xscale, b = (v->height * 0.5f - y) / v->yscale;
    float d[3];
    for (int k = 0; k < 3; k++) d[k] = v->forward[k] + a * v->right[k] + b * v->up[k];
    d[2] *= 3.0f;
    float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    float reach = 6.0f * (t->height / 2 - 1) / (len > 0 ? len : 1);
    *s = reach * d[0];
    *tt = reach * d[1];
}

float ew_sky_scroll(double time) { return (float)fmod(time * 8.0, 4096.0); }

static uint8_t sky_texel(const ew_view *v, const ew_texture *t, float s, float tt) {
    int half = t->width / 2 > 0 ? t->width / 2 : 1, rows = t->height;
    float scroll = ew_sky_scroll(v->time);
    const uint8_t *px = t->mip[0];
    uint8_t front = px[wrap((int)floorf(tt + 2 * scroll), rows) * t->width +
                       wrap((int)floorf(s + 2 * scroll), half)];
    if (front) return front;
    return px[wrap((int)floorf(tt + scroll), rows) * t->width + half +
              wrap((int)floorf(s + scroll), half)];
}

uint8_t ew_sky_pixel(const ew_view *v, const ew_texture *t, float u, float y) {
    float s, tt;
    sky_st(v, t, u, y, &s, &tt);
    return sky_texel(v, t, s, tt);
}

#if EW_SIMD4
/* (x, y, x + dx, y + dy) */
static inline ew_v4i pair_lanes(int32_t x, int32_t y, ew_v4i d) {
    ew_v4i xy = ew_v4i_zip_lo(ew_v4i_first(x), ew_v4i_first(y));
    return ew_v4i_add(ew_v4i_lo_lo(xy, xy), ew_v4i_up2(d));
}

/* The texel indices of four pixels from (s, t) pairs a and b (two pixels
 * each): the wrapped integer parts packed as 16-bit pairs, then one
 * multiply-add with (1, width). */
static inline ew_v4i sky_index4(ew_v4i a, ew_v4i b, ew_v4i mask, ew_v4i mul) {
    a = ew_v4i_and(EW_V4I_SRL(a, 16), mask);
    b = ew_v4i_and(EW_V4I_SRL(b, 16), mask);
    return ew_v4i_madd16(ew_v4i_pack16(a, b), mul);
}

/* Both layers four pixels at a time: the front layer's (s, t) pairs in fa
 * and fb, the back one's in ba and bb (two pixels each), all stepped by
 * step; mask wraps them, mul and off make the texel indices. */
typedef struct sky_lanes { ew_v4i mask, mul, off, fa, fb, ba, bb, step; } sky_lanes;

static inline sky_lanes sky_lanes_at(int32_t fs, int32_t ft, int32_t bs, int32_t bt, int32_t ds, int32_t dt,
                                     unsigned hm, unsigned rm, unsigned width, unsigned half) {
    sky_lanes l;
    l.mask = ew_v4i_setr((int32_t)hm, (int32_t)rm, (int32_t)hm, (int32_t)rm);
    l.mul = ew_v4i_set1((int32_t)((width << 16) | 1u)), l.off = ew_v4i_set1((int32_t)half);
    ew_v4i d = ew_v4i_zip_lo(ew_v4i_first(ds), ew_v4i_first(dt));
    l.fa = pair_lanes(fs, ft, d), l.ba = pair_lanes(bs, bt, d);
    d = ew_v4i_add(d, d);
    d = ew_v4i_lo_lo(d, d);
    l.fb = ew_v4i_add(l.fa, d), l.bb = ew_v4i_add(l.ba, d);
    l.step = ew_v4i_add(d, d);
    return l;
}

/* The four pixels' texel indices in the front layer (fi) and the back one
 * (bi, in 16-bit lanes 0, 2, 4, 6), then the lanes step on. */
static inline void sky_lanes_next(sky_lanes *l, ew_v4i *fi, ew_v4i *bi) {
    *fi = sky_index4(l->fa, l->fb, l->mask, l->mul);
    *bi = ew_v4i_add(sky_index4(l->ba, l->bb, l->mask, l->mul), l->off);
    l->fa = ew_v4i_add(l->fa, l->step), l->fb = ew_v4i_add(l->fb, l->step);
    l->ba = ew_v4i_add(l->ba, l->step), l->bb = ew_v4i_add(l->bb, l->step);
}

/* The power-of-two sky's inner loop for an 8-bit frame, both layers' texel
 * indices made four pixels at a time as the lit spans make theirs (the
 * layer of at most 65536 texels, so the wrapped integer parts are under
 * 32768 and each index fits in 16 bits); then the scalar loop's
 * arithmetic for the last pixels.  Both layers' texels are read for every
 * pixel and the back one kept where the front one is clear, with no
 * branch: the front layer's holes follow no pattern a predictor learns. */
static void sky_run8(uint8_t *dst, const uint8_t *px, int32_t fs, int32_t ft, int32_t bs, int32_t bt,
                     int32_t ds, int32_t dt, unsigned hm, unsigned rm, unsigned width, unsigned half, int n) {
    int k = 0;
    if (n >= 4) {
        sky_lanes l = sky_lanes_at(fs, ft, bs, bt, ds, dt, hm, rm, width, half);
        for (; k + 4 <= n; k += 4) {
            ew_v4i fi, bi;
            sky_lanes_next(&l, &fi, &bi);
            uint32_t f = (uint32_t)px[EW_V4I_U16(fi, 0)] | (uint32_t)px[EW_V4I_U16(fi, 2)] << 8 |
                         (uint32_t)px[EW_V4I_U16(fi, 4)] << 16 | (uint32_t)px[EW_V4I_U16(fi, 6)] << 24;
            uint32_t b = (uint32_t)px[EW_V4I_U16(bi, 0)] | (uint32_t)px[EW_V4I_U16(bi, 2)] << 8 |
                         (uint32_t)px[EW_V4I_U16(bi, 4)] << 16 | (uint32_t)px[EW_V4I_U16(bi, 6)] << 24;
            const ew_v4i fv = ew_v4i_first((int32_t)f), clear = ew_v4i_eq8(fv, ew_v4i_zero());
            const uint32_t four = (uint32_t)EW_V4I_LANE(ew_v4i_or(fv, ew_v4i_and(clear, ew_v4i_first((int32_t)b))), 0);
            memcpy(dst + k, &four, 4);
        }
        /* Where the lanes are now, in the scalar loop's wrapping 32-bit sums. */
        fs = EW_V4I_LANE(l.fa, 0), ft = EW_V4I_LANE(l.fa, 1);
        bs = EW_V4I_LANE(l.ba, 0), bt = EW_V4I_LANE(l.ba, 1);
    }
    for (; k < n; k++) {
        uint8_t f = px[(((unsigned)ft >> 16) & rm) * width + (((unsigned)fs >> 16) & hm)];
        dst[k] = f ? f : px[(((unsigned)bt >> 16) & rm) * width + half + (((unsigned)bs >> 16) & hm)];
        fs += ds, ft += dt, bs += ds, bt += dt;
    }
}

/* sky_st for four columns u of row y: the same single-precision operations
 * in the same order, lane by lane (sqrtps and divps round as sqrtss and
 * divss do), so the points are the scalar ones. */
static inline void sky_st4(const ew_view *v, const ew_texture *t, ew_v4f u, float y, ew_v4f *s, ew_v4f *tt) {
    const ew_v4f a = ew_v4f_div(ew_v4f_sub(u, ew_v4f_set1(v->width * 0.5f)), ew_v4f_set1(v->xscale));
    const float b = (v->height * 0.5f - y) / v->yscale;
    ew_v4f d[3];
    for (int k = 0; k < 3; k++)
        d[k] = ew_v4f_add(ew_v4f_add(ew_v4f_set1(v->forward[k]), ew_v4f_mul(a, ew_v4f_set1(v->right[k]))),
                          ew_v4f_set1(b * v->up[k]));
    d[2] = ew_v4f_mul(d[2], ew_v4f_set1(3.0f));
    const ew_v4f len = ew_v4f_sqrt(
        ew_v4f_add(ew_v4f_add(ew_v4f_mul(d[0], d[0]), ew_v4f_mul(d[1], d[1])), ew_v4f_mul(d[2], d[2])));
    const ew_v4f pos = ew_v4f_gt(len, ew_v4f_set1(0.0f));  /* len > 0 ? len : 1, NaN too */
    const ew_v4f div = ew_v4f_select(pos, len, ew_v4f_set1(1.0f));
    const ew_v4f reach = ew_v4f_div(ew_v4f_set1(6.0f * (t->height / 2 - 1)), div);
    *s = ew_v4f_mul(reach, d[0]);
    *tt = ew_v4f_mul(reach, d[1]);
}

/* (int32_t)floorf(x) lane by lane without a floor instruction (SSE2 has
 * none): the truncation, one less where it lies above x; where the
 * conversion fails (INT32_MIN: NaN or out of range) it stays INT32_MIN, as
 * cvttss2si leaves it. */
static inline ew_v4i floor4(ew_v4f x) {
    const ew_v4i i = ew_v4f_trunc(x);
    const ew_v4i above = ew_v4f_bits(ew_v4f_gt(ew_v4i_to_f(i), x));
    const ew_v4i bad = ew_v4i_eq(i, ew_v4i_set1(INT32_MIN));
    return ew_v4i_add(i, ew_v4i_andnot(bad, above));
}

/* The same for a true-colour frame: each pixel the palette's rgba[] of
 * the texel (sky_run8 kept apart, so the 8-bit loop stays as it was). */
#if defined(__GNUC__)
__attribute__((noinline))  /* inlined, it cost the 8-bit caller registers */
#endif
static void sky_run32(uint8_t *dst, const uint8_t *px, int32_t fs, int32_t ft, int32_t bs, int32_t bt, int32_t ds,
                      int32_t dt, unsigned hm, unsigned rm, unsigned width, unsigned half, int n, const uint32_t *rgba) {
    int k = 0;
    if (n >= 4) {
        sky_lanes l = sky_lanes_at(fs, ft, bs, bt, ds, dt, hm, rm, width, half);
        for (; k + 4 <= n; k += 4) {
            ew_v4i fi, bi;
            sky_lanes_next(&l, &fi, &bi);
            uint8_t f0 = px[EW_V4I_U16(fi, 0)], f1 = px[EW_V4I_U16(fi, 2)];
            uint8_t f2 = px[EW_V4I_U16(fi, 4)], f3 = px[EW_V4I_U16(fi, 6)];
            uint8_t *o = dst + (size_t)k * 4;
            memcpy(o, &rgba[f0 ? f0 : px[EW_V4I_U16(bi, 0)]], 4);
            memcpy(o + 4, &rgba[f1 ? f1 : px[EW_V4I_U16(bi, 2)]], 4);
            memcpy(o + 8, &rgba[f2 ? f2 : px[EW_V4I_U16(bi, 4)]], 4);
            memcpy(o + 12, &rgba[f3 ? f3 : px[EW_V4I_U16(bi, 6)]], 4);
        }
        fs = EW_V4I_LANE(l.fa, 0), ft = EW_V4I_LANE(l.fa, 1);
        bs = EW_V4I_LANE(l.ba, 0), bt = EW_V4I_LANE(l.ba, 1);
    }
    for (; k < n; k++) {
        uint8_t f = px[(((unsigned)ft >> 16) & rm) * width + (((unsigned)fs >> 16) & hm)];
        memcpy(dst + (size_t)k * 4, &rgba[f ? f : px[(((unsigned)bt >> 16) & rm) * width + half + (((unsigned)bs >> 16) & hm)]], 4);
        fs += ds, ft += dt, bs += ds, bt += dt;
    }
}

/* One segment through the composited planes: the front layer's 16.16
 * (fs, ft) stepped by (ds, dt), the back layer Ds, Dt behind it (the
 * starts' differences, constant along the segment since both layers step
 * alike).  Where a pixel's fraction is below the difference's, the back
 * layer's integer part is one further behind: the next plane.  0 (nothing
 * drawn) if the segment's shifts lie outside the planes' (a view whose
 * numbers are not finite), for the layer-by-layer loop. */
static int sky_comp_run(uint8_t *dst, int bpp, const uint32_t *rgba, const ew_sky_comp *sc, unsigned half,
                        unsigned rows, int32_t fs, int32_t ft, int32_t ds, int32_t dt, int32_t Ds, int32_t Dt, int n) {
    const int a0 = (int)((Ds - (Ds & 0xFFFF)) / 65536) - sc->w0, b0 = (int)((Dt - (Dt & 0xFFFF)) / 65536) - sc->w0;
    if (a0 < 0 || a0 > 1 || b0 < 0 || b0 > 1) return 0;
    const unsigned P = half * rows, hm = half - 1, rm = rows - 1;
    const int32_t dsf = Ds & 0xFFFF, dtf = Dt & 0xFFFF;
    const uint8_t *base = sc->planes + (size_t)(a0 + 3 * b0) * P;
    int k = 0;
    if (n >= 4) {
        ew_v4i S = ew_v4i_setr(fs, (int32_t)((uint32_t)fs + (uint32_t)ds), (int32_t)((uint32_t)fs + 2u * (uint32_t)ds),
                               (int32_t)((uint32_t)fs + 3u * (uint32_t)ds));
        ew_v4i T = ew_v4i_setr(ft, (int32_t)((uint32_t)ft + (uint32_t)dt), (int32_t)((uint32_t)ft + 2u * (uint32_t)dt),
                               (int32_t)((uint32_t)ft + 3u * (uint32_t)dt));
        const ew_v4i sstep = ew_v4i_set1((int32_t)(4u * (uint32_t)ds)), tstep = ew_v4i_set1((int32_t)(4u * (uint32_t)dt));
        const ew_v4i hmv = ew_v4i_set1((int32_t)hm), rmhi = ew_v4i_set1((int32_t)(rm << 16)), lo = ew_v4i_set1(0xFFFF);
        const ew_v4i mul = ew_v4i_set1((int32_t)((half << 16) | 1u)), dsv = ew_v4i_set1(dsf), dtv = ew_v4i_set1(dtf);
        const ew_v4i pv = ew_v4i_set1((int32_t)P), p3v = ew_v4i_set1((int32_t)(3 * P));
        for (; k + 4 <= n; k += 4) {
            /* x | y << 16 as 16-bit pairs (x <= hm < 16384, y <= rm < 32768), then x + y * half */
            ew_v4i idx = ew_v4i_madd16(ew_v4i_or(ew_v4i_and(EW_V4I_SRL(S, 16), hmv), ew_v4i_and(T, rmhi)), mul);
            idx = ew_v4i_add(idx, ew_v4i_and(ew_v4i_gt(dsv, ew_v4i_and(S, lo)), pv));
            idx = ew_v4i_add(idx, ew_v4i_and(ew_v4i_gt(dtv, ew_v4i_and(T, lo)), p3v));
            uint32_t i4[4];
            ew_v4i_storeu(i4, idx);
            if (bpp == 1) {
                const uint32_t four = (uint32_t)base[i4[0]] | (uint32_t)base[i4[1]] << 8 | (uint32_t)base[i4[2]] << 16 |
                                      (uint32_t)base[i4[3]] << 24;
                memcpy(dst + k, &four, 4);
            } else {
                uint8_t *o = dst + (size_t)k * 4;
                memcpy(o, &rgba[base[i4[0]]], 4);
                memcpy(o + 4, &rgba[base[i4[1]]], 4);
                memcpy(o + 8, &rgba[base[i4[2]]], 4);
                memcpy(o + 12, &rgba[base[i4[3]]], 4);
            }
            S = ew_v4i_add(S, sstep), T = ew_v4i_add(T, tstep);
        }
        fs = EW_V4I_LANE(S, 0), ft = EW_V4I_LANE(T, 0);
    }
    for (; k < n; k++) {
        const unsigned i = (((unsigned)ft >> 16) & rm) * half + (((unsigned)fs >> 16) & hm) +
                           ((fs & 0xFFFF) < dsf ? P : 0) + ((ft & 0xFFFF) < dtf ? 3 * P : 0);
        if (bpp == 1)
            dst[k] = base[i];
        else
            memcpy(dst + (size_t)k * 4, &rgba[base[i]], 4);
        fs = (int32_t)((uint32_t)fs + (uint32_t)ds), ft = (int32_t)((uint32_t)ft + (uint32_t)dt);
    }
    return 1;
}

/* A power-of-two sky's span with the default 32-pixel segments, in either
 * pixel format: ew_draw_sky_span's arithmetic, each four segments' end points,
 * 16.16 starts and steps made in the lanes of one vector (one square root
 * and two divides for four segments, and no floorf calls). */
static void sky_span(const ew_span_ctx *c, const ew_span *sp, const ew_texture *t, uint8_t *dst, int bpp,
                     const uint32_t *rgba) {
    const ew_view *v = c->view;
    const unsigned half = (unsigned)t->width / 2, rows = (unsigned)t->height, width = (unsigned)t->width;
    const float scroll = c->sky_scroll, scroll2 = 2 * scroll;
    const uint8_t *px = t->mip[0];
    const ew_sky_comp *comp = c->sky_comp && c->sky_comp->tex == t ? c->sky_comp : NULL;
    const float y = (float)sp->v;
    float s0, t0;
    sky_st(v, t, (float)sp->u, y, &s0, &t0);
    ew_v4f ps = ew_v4f_set1(s0), pt = ew_v4f_set1(t0);  /* lane 3: the last end point */
    const ew_v4i ends = ew_v4i_setr(SKY_STEP, 2 * SKY_STEP, 3 * SKY_STEP, 4 * SKY_STEP);
    for (int i = 0; i < sp->count; i += 4 * SKY_STEP) {
        ew_v4f S, T;
        sky_st4(v, t, ew_v4i_to_f(ew_v4i_add(ew_v4i_set1(sp->u + i), ends)), y, &S, &T);
        /* Each segment's start: the carried point, then the first three ends. */
        const ew_v4f S0 = ew_v4f_carry(ps, S), T0 = ew_v4f_carry(pt, T);
        const ew_v4f k16 = ew_v4f_set1(65536.0f), fstep = ew_v4f_set1((float)SKY_STEP);
        int32_t fs[4], ft[4], bs[4], bt[4], ds[4], dt[4];
        ew_v4i_storeu(fs, floor4(ew_v4f_mul(ew_v4f_add(S0, ew_v4f_set1(scroll2)), k16)));
        ew_v4i_storeu(ft, floor4(ew_v4f_mul(ew_v4f_add(T0, ew_v4f_set1(scroll2)), k16)));
        ew_v4i_storeu(bs, floor4(ew_v4f_mul(ew_v4f_add(S0, ew_v4f_set1(scroll)), k16)));
        ew_v4i_storeu(bt, floor4(ew_v4f_mul(ew_v4f_add(T0, ew_v4f_set1(scroll)), k16)));
        ew_v4i_storeu(ds, ew_v4f_trunc(ew_v4f_div(ew_v4f_mul(ew_v4f_sub(S, S0), k16), fstep)));
        ew_v4i_storeu(dt, ew_v4f_trunc(ew_v4f_div(ew_v4f_mul(ew_v4f_sub(T, T0), k16), fstep)));
        for (int j = 0; j < 4 && i + j * SKY_STEP < sp->count; j++) {
            const int at = i + j * SKY_STEP, n = sp->count - at < SKY_STEP ? sp->count - at : SKY_STEP;
            if (comp && sky_comp_run(dst + (size_t)at * (size_t)bpp, bpp, rgba, comp, half, rows, fs[j], ft[j], ds[j],
                                     dt[j], (int32_t)((uint32_t)fs[j] - (uint32_t)bs[j]),
                                     (int32_t)((uint32_t)ft[j] - (uint32_t)bt[j]), n))
                continue;
            if (bpp == 1)
                sky_run8(dst + at, px, fs[j], ft[j], bs[j], bt[j], ds[j], dt[j], half - 1, rows - 1, width, half, n);
            else
                sky_run32(dst + (size_t)at * 4, px, fs[j], ft[j], bs[j], bt[j], ds[j], dt[j], half - 1, rows - 1, width,
                          half, n, rgba);
        }
        ps = S, pt = T;
    }
}
#endif

void ew_draw_sky_span(const ew_span_ctx *c, const ew_span *sp, const ew_texture *t) {
    const ew_view *v = c->view;
    int half = t->width / 2, rows = t->height;
    /* Power-of-two layers (Quake's are 128x128) wrap with a mask; others
     * take the exact path per pixel. */
    int pow2 = sky_pow2(t);
    float scroll = c->sky_scroll;
    const uint8_t *px = t->mip[0];
    uint8_t *dst = ew_target_at(c->target, sp->u, sp->v);
    /* Read once: the pixel stores could alias the target struct. */
    const int bpp = c->target->bpp;
    const uint32_t *rgba = c->target->rgba;
    float s0, t0, s1, t1;
    int step = c->subdiv_shift ? SKY_STEP : 1;  /* exact mode: every pixel */
#if EW_SIMD4
    if (step == SKY_STEP && sky_in_lanes(t)) {
        sky_span(c, sp, t, dst, bpp, rgba);
        return;
    }
#endif
    sky_st(v, t, (float)sp->u, (float)sp->v, &s0, &t0);
    for (int i = 0; i < sp->count; i += step) {
        int n = sp->count - i < step ? sp->count - i : step;
        sky_st(v, t, (float)(sp->u + i + step), (float)sp->v, &s1, &t1);
        if (!pow2) {
            float ds = (s1 - s0) / step, dt = (t1 - t0) / step;
            for (int k = 0; k < n; k++) ew_put_via(bpp, rgba, dst, i + k, sky_texel(v, t, s0 + ds * k, t0 + dt * k));
        } else {
            /* 16.16 fixed point from the same floored start, two layers. */
            int32_t fs = (int32_t)floorf((s0 + 2 * scroll) * 65536.0f), ft = (int32_t)floorf((t0 + 2 * scroll) * 65536.0f);
            int32_t bs = (int32_t)floorf((s0 + scroll) * 65536.0f), bt = (int32_t)floorf((t0 + scroll) * 65536.0f);
            int32_t ds = (int32_t)((s1 - s0) * 65536.0f / step), dt = (int32_t)((t1 - t0) * 65536.0f / step);
            unsigned hm = (unsigned)half - 1, rm = (unsigned)rows - 1;
#if EW_SIMD4
            if (sky_in_lanes(t)) {
                if (bpp == 1)
                    sky_run8(dst + i, px, fs, ft, bs, bt, ds, dt, hm, rm, (unsigned)t->width, (unsigned)half, n);
                else
                    sky_run32(dst + (size_t)i * 4, px, fs, ft, bs, bt, ds, dt, hm, rm, (unsigned)t->width,
                              (unsigned)half, n, rgba);
                s0 = s1, t0 = t1;
                continue;
            }
#endif
            for (int k = 0; k < n; k++) {
                uint8_t px_front = px[(((unsigned)ft >> 16) & rm) * (unsigned)t->width + (((unsigned)fs >> 16) & hm)];
                ew_put_via(bpp, rgba, dst, i + k,
                             px_front ? px_front
                                      : px[(((unsigned)bt >> 16) & rm) * (unsigned)t->width + (unsigned)half +
                                           (((unsigned)bs >> 16) & hm)]);
                fs += ds, ft += dt, bs += ds, bt += dt;
            }
        }
        s0 = s1, t0 = t1;
    }
}
