/* Walking a span with perspective correction every 16 pixels (internal).
 * s/z, t/z and 1/z are linear in screen space; at each 16-pixel point the
 * true s and t come from one divide, and the pixels between are stepped
 * affinely.  The segment length is 1 << shift (4 by default; 0 divides at
 * every pixel, for measuring what the approximation costs and changes).
 * Used by the textured and the liquid span drawers; then the texel run
 * between two such points (ew_texel_run), shared with the item boxes'
 * rows (raster/zpoly.c). */
#ifndef EW_SPAN_STEP_H
#define EW_SPAN_STEP_H

#include "raster/raster.h"

#include "ew_simd.h"

typedef struct ew_stepper {
    const ew_gradients *g;
    float zi, sz, tz;      /* at the current segment start */
    float zi_row, s_row, t_row; /* the v and constant terms of this row */
    int u;                 /* current segment start */
    int32_t s, t;          /* 16.16 at the current segment start */
    int left;              /* pixels left in the span */
    int shift;             /* log2 of the segment length */
} ew_stepper;

/* x, the truncated (s/z) * z, plus the eye's coordinate, clamped to the
 * surface. */
static inline int32_t ew_tex_clamp(int32_t x, int32_t adjust, int32_t lo, int32_t hi) {
    int64_t s = (int64_t)x + adjust;
    s = s < lo ? lo : s;
    s = s > hi ? hi : s;
    return (int32_t)s;
}

/* (s/z) * z plus the eye's coordinate, clamped to the surface. */
static inline int32_t ew_tex_fix(float x, int32_t adjust, int32_t lo, int32_t hi) {
#if defined(__SSE2__)
    /* maxss and minss are exactly the selects below (NaN becomes -1e9: the
     * second operand wins); written out, gcc made branches of them. */
    __m128 v = _mm_min_ss(_mm_max_ss(_mm_set_ss(x), _mm_set_ss(-1e9f)), _mm_set_ss(1e9f));
    return ew_tex_clamp(_mm_cvttss_si32(v), adjust, lo, hi);  /* |v| <= 1e9: truncation as a cast */
#else
    x = x > -1e9f ? x : -1e9f;  /* also turns NaN into -1e9 */
    x = x < 1e9f ? x : 1e9f;
    return ew_tex_clamp((int32_t)x, adjust, lo, hi);
#endif
}

/* 65536 / n for the last, shorter segment of a span: a multiply instead of
 * two integer divides.  Rounds the step towards zero, so the pixels stay
 * between the two true end points. */
static inline int32_t ew_step_div(int32_t diff, int n) {
    static const int32_t recip[33] = {
        0, 65536, 32768, 21845, 16384, 13107, 10922, 9362, 8192, 7281, 6553, 5957,
        5461, 5041, 4681, 4369, 4096, 3855, 3640, 3449, 3276, 3120, 2978, 2849,
        2730, 2621, 2520, 2427, 2340, 2259, 2184, 2114, 2048};
    int64_t q = (int64_t)diff * recip[n];
    return (int32_t)(q / 65536);  /* truncates; a shift and an add, no branch */
}

static inline void ew_step_begin(ew_stepper *st, const ew_gradients *g, int shift, int u, int v,
                                 int count) {
    st->g = g;
    st->shift = shift;
    st->u = u;
    st->zi_row = g->zi_v * v + g->zi_0;
    st->s_row = g->s_v * v + g->s_0;
    st->t_row = g->t_v * v + g->t_0;
    st->zi = g->zi_u * u + st->zi_row;
    st->sz = g->s_u * u + st->s_row;
    st->tz = g->t_u * u + st->t_row;
    float z = 65536.0f / st->zi;
    st->s = ew_tex_fix(st->sz * z, g->s_adjust, 0, g->s_max);
    st->t = ew_tex_fix(st->tz * z, g->t_adjust, 0, g->t_max);
    st->left = count;
}

/* Next segment of up to 16 pixels: start point, per-pixel steps, length. */
static inline int ew_step_next(ew_stepper *st, int32_t *s, int32_t *t, int32_t *ds, int32_t *dt) {
    int seg = 1 << st->shift;
    int n = st->left < seg ? st->left : seg;
    if (n <= 0) return 0;
    st->left -= n;
    *s = st->s, *t = st->t;
    const ew_gradients *g = st->g;
    /* A full segment aims at the next segment's first pixel; the last one
     * at its own last pixel, so the span ends exactly on the true s, t. */
    int adv = st->left > 0 ? seg : n - 1;
    if (adv == 0) {
        *ds = *dt = 0;
        return n;
    }
    /* Evaluated afresh at each point rather than accumulated, so long spans
     * do not drift. */
    st->u += adv;
    float fu = (float)st->u;
    st->zi = g->zi_u * fu + st->zi_row;
    st->sz = g->s_u * fu + st->s_row;
    st->tz = g->t_u * fu + st->t_row;
    float z = 65536.0f / st->zi;
    /* Not quite 0 at the low end: floored steps may undershoot by up to seg - 1. */
    int32_t sn = ew_tex_fix(st->sz * z, g->s_adjust, seg, g->s_max);
    int32_t tn = ew_tex_fix(st->tz * z, g->t_adjust, seg, g->t_max);
    if (adv == seg) {
        *ds = (sn - *s) >> st->shift;
        *dt = (tn - *t) >> st->shift;
    } else {
        *ds = ew_step_div(sn - *s, adv);
        *dt = ew_step_div(tn - *t, adv);
    }
    st->s = sn, st->t = tn;
    return n;
}

#if EW_SIMD4
/* Four texels' s and t a step apart, walked four steps at a time by both
 * texel runs (8-bit and true colour): a holds (s, t) of the first two
 * pixels, b of the next two, so one s, t pair is set up and stepped in
 * one register instead of s and t each spread over four lanes. */
typedef struct texel_lanes { ew_v4i a, b, step, mul; } texel_lanes;

static inline texel_lanes texel_lanes_at(int32_t s, int32_t t, int32_t ds, int32_t dt, uint32_t pitch) {
    texel_lanes l;
    ew_v4i st = ew_v4i_zip_lo(ew_v4i_first(s), ew_v4i_first(t));
    st = ew_v4i_lo_lo(st, st);                              /* s, t, s, t */
    ew_v4i d = ew_v4i_zip_lo(ew_v4i_first(ds), ew_v4i_first(dt));
    l.a = ew_v4i_add(st, ew_v4i_up2(d));                    /* s, t, s + ds, t + dt */
    ew_v4i d2 = ew_v4i_add(d, d);
    d2 = ew_v4i_lo_lo(d2, d2);                              /* 2 ds, 2 dt, 2 ds, 2 dt */
    l.b = ew_v4i_add(l.a, d2);
    l.step = ew_v4i_add(d2, d2);
    l.mul = ew_v4i_set1((int32_t)((pitch << 16) | 1u));  /* (1, pitch) pairs */
    return l;
}

/* The surface indices t * pitch + s of the lanes' four texels, then the
 * lanes step on: the integer parts of s and t packed as 16-bit pairs (no
 * saturation: both are under 32768), one multiply-add with mul's
 * (1, pitch) pairs. */
static inline void texel_lanes_next(texel_lanes *l, uint32_t k[4], int narrow) {
    ew_v4i idx = ew_v4i_madd16(ew_v4i_pack16(EW_V4I_SRL(l->a, 16), EW_V4I_SRL(l->b, 16)), l->mul);
    if (narrow) {  /* every index under 65536: one pextrw each instead of a shuffle and a move */
        k[0] = EW_V4I_U16(idx, 0);
        k[1] = EW_V4I_U16(idx, 2);
        k[2] = EW_V4I_U16(idx, 4);
        k[3] = EW_V4I_U16(idx, 6);
    } else {
        k[0] = (uint32_t)EW_V4I_LANE(idx, 0);
        k[1] = (uint32_t)EW_V4I_LANE(idx, 1);
        k[2] = (uint32_t)EW_V4I_LANE(idx, 2);
        k[3] = (uint32_t)EW_V4I_LANE(idx, 3);
    }
    l->a = ew_v4i_add(l->a, l->step);
    l->b = ew_v4i_add(l->b, l->step);
}
#endif

/* n texels along a straight line through the surface: the affine stretch
 * between two perspective-correct points.  s and t stay within the
 * surface all along (the stepper guarantees it), so unsigned maths is exact.
 * With four-lane vectors (ew_simd.h), four at a time: the integer parts of s and t are paired as
 * 16-bit halves and one multiply-add gives s + t * pitch for four pixels;
 * surfaces are far smaller than 32768 texels a side, as that needs (the
 * static assertion below ties it to the largest face extent the loader
 * accepts).  narrow: the surface has at most 65536 texels, so every index
 * fits in 16 bits. */
_Static_assert(EW_MAX_EXTENT < 32768, "ew_texel_run's 16-bit pairs need surfaces under 32768 texels a side");
static inline void ew_texel_run(uint8_t *dst, const uint8_t *pixels, uint32_t pitch, int32_t s, int32_t t,
                                int32_t ds, int32_t dt, int n, int narrow) {
    int i = 0;
#if !EW_SIMD4
    (void)narrow;
#else
    if (n >= 4) {
        texel_lanes l = texel_lanes_at(s, t, ds, dt, pitch);
        uint32_t k[4];
        for (; i + 4 < n; i += 4) {  /* all but the last 1 to 4 */
            texel_lanes_next(&l, k, narrow);
            /* Byte stores: a load and a store a pixel, where packing four
             * into one word took two more instructions a pixel. */
            dst[i] = pixels[k[0]];
            dst[i + 1] = pixels[k[1]];
            dst[i + 2] = pixels[k[2]];
            dst[i + 3] = pixels[k[3]];
        }
        /* Then the last four pixels, n - 4 to n - 1, those the loop drew
         * among them drawn again with the same texels (the lanes' sums
         * wrap as s + j * ds does): no branch on the remainder, which
         * follows no pattern from one span to the next. */
        const uint32_t back = (uint32_t)(n - 4);
        l = texel_lanes_at((int32_t)((uint32_t)s + back * (uint32_t)ds), (int32_t)((uint32_t)t + back * (uint32_t)dt),
                           ds, dt, pitch);
        texel_lanes_next(&l, k, narrow);
        dst[n - 4] = pixels[k[0]];
        dst[n - 3] = pixels[k[1]];
        dst[n - 2] = pixels[k[2]];
        dst[n - 1] = pixels[k[3]];
        return;
    }
#endif
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC unroll 4
#endif
    for (; i < n; i++) {
        dst[i] = pixels[((uint32_t)t >> 16) * pitch + ((uint32_t)s >> 16)];
        s += ds;
        t += dt;
    }
}

#endif
