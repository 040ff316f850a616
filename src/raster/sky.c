/* Sky: Quake's two scrolling layers seen as a flattened dome.  The ray
 * through the pixel, with its height stretched 3x, is normalized and its
 * x, y pick texels; the front layer (left half, colour 0 = clear) scrolls
 * twice as fast as the back layer (right half).  Unlit.  Spans compute the
 * exact coordinates every 32 pixels and step linearly between, as the
 * original did; the reference path computes every pixel. */
#include "raster/raster.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#define SKY_STEP 32

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

#if defined(__SSE2__)
/* (x, y, x + dx, y + dy) */
static inline __m128i pair_lanes(int32_t x, int32_t y, __m128i d) {
    __m128i xy = _mm_unpacklo_epi32(_mm_cvtsi32_si128(x), _mm_cvtsi32_si128(y));
    return _mm_add_epi32(_mm_unpacklo_epi64(xy, xy), _mm_slli_si128(d, 8));
}

/* The texel indices of four pixels from (s, t) pairs a and b (two pixels
 * each): the wrapped integer parts packed as 16-bit pairs, then one
 * multiply-add with (1, width). */
static inline __m128i sky_index4(__m128i a, __m128i b, __m128i mask, __m128i mul) {
    a = _mm_and_si128(_mm_srli_epi32(a, 16), mask);
    b = _mm_and_si128(_mm_srli_epi32(b, 16), mask);
    return _mm_madd_epi16(_mm_packs_epi32(a, b), mul);
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
        const __m128i mask = _mm_setr_epi32((int)hm, (int)rm, (int)hm, (int)rm);
        const __m128i mul = _mm_set1_epi32((int)((width << 16) | 1u)), off = _mm_set1_epi32((int)half);
        __m128i d = _mm_unpacklo_epi32(_mm_cvtsi32_si128(ds), _mm_cvtsi32_si128(dt));
        __m128i fa = pair_lanes(fs, ft, d), ba = pair_lanes(bs, bt, d);
        d = _mm_add_epi32(d, d);
        d = _mm_unpacklo_epi64(d, d);
        __m128i fb = _mm_add_epi32(fa, d), bb = _mm_add_epi32(ba, d);
        const __m128i step = _mm_add_epi32(d, d);
        for (; k + 4 <= n; k += 4) {
            __m128i fi = sky_index4(fa, fb, mask, mul);
            __m128i bi = _mm_add_epi32(sky_index4(ba, bb, mask, mul), off);
            uint32_t f = (uint32_t)px[_mm_extract_epi16(fi, 0)] | (uint32_t)px[_mm_extract_epi16(fi, 2)] << 8 |
                         (uint32_t)px[_mm_extract_epi16(fi, 4)] << 16 | (uint32_t)px[_mm_extract_epi16(fi, 6)] << 24;
            uint32_t b = (uint32_t)px[_mm_extract_epi16(bi, 0)] | (uint32_t)px[_mm_extract_epi16(bi, 2)] << 8 |
                         (uint32_t)px[_mm_extract_epi16(bi, 4)] << 16 | (uint32_t)px[_mm_extract_epi16(bi, 6)] << 24;
            const __m128i fv = _mm_cvtsi32_si128((int)f), clear = _mm_cmpeq_epi8(fv, _mm_setzero_si128());
            const uint32_t four =
                (uint32_t)_mm_cvtsi128_si32(_mm_or_si128(fv, _mm_and_si128(clear, _mm_cvtsi32_si128((int)b))));
            memcpy(dst + k, &four, 4);
            fa = _mm_add_epi32(fa, step), fb = _mm_add_epi32(fb, step);
            ba = _mm_add_epi32(ba, step), bb = _mm_add_epi32(bb, step);
        }
        /* Where the lanes are now, in the scalar loop's wrapping 32-bit sums. */
        fs = _mm_cvtsi128_si32(fa), ft = _mm_cvtsi128_si32(_mm_srli_si128(fa, 4));
        bs = _mm_cvtsi128_si32(ba), bt = _mm_cvtsi128_si32(_mm_srli_si128(ba, 4));
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
static inline void sky_st4(const ew_view *v, const ew_texture *t, __m128 u, float y, __m128 *s, __m128 *tt) {
    const __m128 a = _mm_div_ps(_mm_sub_ps(u, _mm_set1_ps(v->width * 0.5f)), _mm_set1_ps(v->xscale));
    const float b = (v->height * 0.5f - y) / v->yscale;
    __m128 d[3];
    for (int k = 0; k < 3; k++)
        d[k] = _mm_add_ps(_mm_add_ps(_mm_set1_ps(v->forward[k]), _mm_mul_ps(a, _mm_set1_ps(v->right[k]))),
                          _mm_set1_ps(b * v->up[k]));
    d[2] = _mm_mul_ps(d[2], _mm_set1_ps(3.0f));
    const __m128 len = _mm_sqrt_ps(
        _mm_add_ps(_mm_add_ps(_mm_mul_ps(d[0], d[0]), _mm_mul_ps(d[1], d[1])), _mm_mul_ps(d[2], d[2])));
    const __m128 pos = _mm_cmpgt_ps(len, _mm_setzero_ps());  /* len > 0 ? len : 1, NaN too */
    const __m128 div = _mm_or_ps(_mm_and_ps(pos, len), _mm_andnot_ps(pos, _mm_set1_ps(1.0f)));
    const __m128 reach = _mm_div_ps(_mm_set1_ps(6.0f * (t->height / 2 - 1)), div);
    *s = _mm_mul_ps(reach, d[0]);
    *tt = _mm_mul_ps(reach, d[1]);
}

/* (int32_t)floorf(x) lane by lane without SSE4.1: the truncation, one less
 * where it lies above x; where the conversion fails (INT32_MIN: NaN or out
 * of range) it stays INT32_MIN, as cvttss2si leaves it. */
static inline __m128i floor4(__m128 x) {
    const __m128i i = _mm_cvttps_epi32(x);
    const __m128i above = _mm_castps_si128(_mm_cmpgt_ps(_mm_cvtepi32_ps(i), x));
    const __m128i bad = _mm_cmpeq_epi32(i, _mm_set1_epi32(INT32_MIN));
    return _mm_add_epi32(i, _mm_andnot_si128(bad, above));
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
        const __m128i mask = _mm_setr_epi32((int)hm, (int)rm, (int)hm, (int)rm);
        const __m128i mul = _mm_set1_epi32((int)((width << 16) | 1u)), off = _mm_set1_epi32((int)half);
        __m128i d = _mm_unpacklo_epi32(_mm_cvtsi32_si128(ds), _mm_cvtsi32_si128(dt));
        __m128i fa = pair_lanes(fs, ft, d), ba = pair_lanes(bs, bt, d);
        d = _mm_add_epi32(d, d);
        d = _mm_unpacklo_epi64(d, d);
        __m128i fb = _mm_add_epi32(fa, d), bb = _mm_add_epi32(ba, d);
        const __m128i step = _mm_add_epi32(d, d);
        for (; k + 4 <= n; k += 4) {
            __m128i fi = sky_index4(fa, fb, mask, mul);
            __m128i bi = _mm_add_epi32(sky_index4(ba, bb, mask, mul), off);
            uint8_t f0 = px[_mm_extract_epi16(fi, 0)], f1 = px[_mm_extract_epi16(fi, 2)];
            uint8_t f2 = px[_mm_extract_epi16(fi, 4)], f3 = px[_mm_extract_epi16(fi, 6)];
            uint8_t *o = dst + (size_t)k * 4;
            memcpy(o, &rgba[f0 ? f0 : px[_mm_extract_epi16(bi, 0)]], 4);
            memcpy(o + 4, &rgba[f1 ? f1 : px[_mm_extract_epi16(bi, 2)]], 4);
            memcpy(o + 8, &rgba[f2 ? f2 : px[_mm_extract_epi16(bi, 4)]], 4);
            memcpy(o + 12, &rgba[f3 ? f3 : px[_mm_extract_epi16(bi, 6)]], 4);
            fa = _mm_add_epi32(fa, step), fb = _mm_add_epi32(fb, step);
            ba = _mm_add_epi32(ba, step), bb = _mm_add_epi32(bb, step);
        }
        fs = _mm_cvtsi128_si32(fa), ft = _mm_cvtsi128_si32(_mm_srli_si128(fa, 4));
        bs = _mm_cvtsi128_si32(ba), bt = _mm_cvtsi128_si32(_mm_srli_si128(ba, 4));
    }
    for (; k < n; k++) {
        uint8_t f = px[(((unsigned)ft >> 16) & rm) * width + (((unsigned)fs >> 16) & hm)];
        memcpy(dst + (size_t)k * 4, &rgba[f ? f : px[(((unsigned)bt >> 16) & rm) * width + half + (((unsigned)bs >> 16) & hm)]], 4);
        fs += ds, ft += dt, bs += ds, bt += dt;
    }
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
    const float y = (float)sp->v;
    float s0, t0;
    sky_st(v, t, (float)sp->u, y, &s0, &t0);
    __m128 ps = _mm_set1_ps(s0), pt = _mm_set1_ps(t0);  /* lane 3: the last end point */
    const __m128i ends = _mm_setr_epi32(SKY_STEP, 2 * SKY_STEP, 3 * SKY_STEP, 4 * SKY_STEP);
    for (int i = 0; i < sp->count; i += 4 * SKY_STEP) {
        __m128 S, T;
        sky_st4(v, t, _mm_cvtepi32_ps(_mm_add_epi32(_mm_set1_epi32(sp->u + i), ends)), y, &S, &T);
        /* Each segment's start: the carried point, then the first three ends. */
        const __m128 S0 = _mm_shuffle_ps(_mm_shuffle_ps(ps, S, _MM_SHUFFLE(0, 0, 3, 3)), S, _MM_SHUFFLE(2, 1, 2, 0));
        const __m128 T0 = _mm_shuffle_ps(_mm_shuffle_ps(pt, T, _MM_SHUFFLE(0, 0, 3, 3)), T, _MM_SHUFFLE(2, 1, 2, 0));
        const __m128 k16 = _mm_set1_ps(65536.0f), fstep = _mm_set1_ps((float)SKY_STEP);
        int32_t fs[4], ft[4], bs[4], bt[4], ds[4], dt[4];
        _mm_storeu_si128((__m128i *)(void *)fs, floor4(_mm_mul_ps(_mm_add_ps(S0, _mm_set1_ps(scroll2)), k16)));
        _mm_storeu_si128((__m128i *)(void *)ft, floor4(_mm_mul_ps(_mm_add_ps(T0, _mm_set1_ps(scroll2)), k16)));
        _mm_storeu_si128((__m128i *)(void *)bs, floor4(_mm_mul_ps(_mm_add_ps(S0, _mm_set1_ps(scroll)), k16)));
        _mm_storeu_si128((__m128i *)(void *)bt, floor4(_mm_mul_ps(_mm_add_ps(T0, _mm_set1_ps(scroll)), k16)));
        _mm_storeu_si128((__m128i *)(void *)ds, _mm_cvttps_epi32(_mm_div_ps(_mm_mul_ps(_mm_sub_ps(S, S0), k16), fstep)));
        _mm_storeu_si128((__m128i *)(void *)dt, _mm_cvttps_epi32(_mm_div_ps(_mm_mul_ps(_mm_sub_ps(T, T0), k16), fstep)));
        for (int j = 0; j < 4 && i + j * SKY_STEP < sp->count; j++) {
            const int at = i + j * SKY_STEP, n = sp->count - at < SKY_STEP ? sp->count - at : SKY_STEP;
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
    int pow2 = half > 0 && (half & (half - 1)) == 0 && rows > 0 && (rows & (rows - 1)) == 0;
    float scroll = c->sky_scroll;
    const uint8_t *px = t->mip[0];
    uint8_t *dst = ew_target_at(c->target, sp->u, sp->v);
    /* Read once: the pixel stores could alias the target struct. */
    const int bpp = c->target->bpp;
    const uint32_t *rgba = c->target->rgba;
    float s0, t0, s1, t1;
    int step = c->subdiv_shift ? SKY_STEP : 1;  /* exact mode: every pixel */
#if defined(__SSE2__)
    if (pow2 && step == SKY_STEP && t->width < 32768 && (unsigned)t->width * (unsigned)rows <= 65536u) {
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
#if defined(__SSE2__)
            if (t->width < 32768 && (unsigned)t->width * (unsigned)rows <= 65536u) {
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
