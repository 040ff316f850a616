/* Back end: a band's spans, each drawn by its surface's kind; lit surfaces
 * from the surface cache with perspective-correct texture mapping (a divide
 * every 16 pixels, affine in between). */
#include "raster/span_step.h"
#include "raster/debug.h"
#include "raster/zfill.h"
#include "light/twopass.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

/* True colour: n texels of a 4-byte lit surface along the same line, the
 * indices made four at a time as ew_texel_run does. */
static inline void texel_run32(uint8_t *dst, const uint8_t *pixels, uint32_t pitch, int32_t s, int32_t t,
                               int32_t ds, int32_t dt, int n) {
    const uint32_t *src = (const uint32_t *)(const void *)pixels;
    int i = 0;
#if defined(__SSE2__)
    if (n >= 4) {
        texel_lanes l = texel_lanes_at(s, t, ds, dt, pitch);
        for (; i + 4 <= n; i += 4) {
            uint32_t k[4];
            texel_lanes_next(&l, k, 0);
            uint8_t *d = dst + (size_t)i * 4;  /* a load and a store a pixel, as texel_run16 */
            memcpy(d, &src[k[0]], 4);
            memcpy(d + 4, &src[k[1]], 4);
            memcpy(d + 8, &src[k[2]], 4);
            memcpy(d + 12, &src[k[3]], 4);
        }
        if (i < n) {  /* the last 1 to 3, as ew_texel_run */
            uint32_t k[4];
            texel_lanes_next(&l, k, 0);
            for (int j = 0; i + j < n; j++) memcpy(dst + (size_t)(i + j) * 4, &src[k[j]], 4);
        }
        return;
    }
#endif
    for (; i < n; i++) {
        uint32_t v = src[((uint32_t)t >> 16) * pitch + ((uint32_t)s >> 16)];
        memcpy(dst + (size_t)i * 4, &v, 4);
        s += ds;
        t += dt;
    }
}

#if defined(__SSE2__)
/* The lit span walk is inlined into each caller: gcc otherwise keeps one
 * shared copy and calls it for every span. */
#if defined(__GNUC__)
#define EW_SPAN_INLINE inline __attribute__((always_inline))
#else
#define EW_SPAN_INLINE inline
#endif

/* Greatest and least of signed 32-bit lanes (SSE2 has them for 16 bits). */
static inline __m128i max32(__m128i a, __m128i b) {
    __m128i m = _mm_cmpgt_epi32(b, a);
    return _mm_or_si128(_mm_and_si128(m, b), _mm_andnot_si128(m, a));
}
static inline __m128i min32(__m128i a, __m128i b) {
    __m128i m = _mm_cmpgt_epi32(a, b);
    return _mm_or_si128(_mm_and_si128(m, b), _mm_andnot_si128(m, a));
}

/* A lit span's row, everything in the lanes (1/z, s/z, t/z, -) of one
 * vector: the planes' column term and the rest, and for s and t (lanes 1
 * and 2) the eye's coordinate and the clamp limits less it. */
typedef struct lit_row {
    __m128 u, c;
    __m128i adj, lo0, lo16, hi;
    __m128i mul;  /* texel_lanes' (1, pitch) pairs */
} lit_row;

/* Whether ew_tex_clamp's int64 sum and clamps can be done in 32-bit lanes
 * as clamp(x, lo - adjust, hi - adjust) + adjust (the same value for
 * integers): with |adjust| within 2^30 and limits under 2^27 (EW_MAX_EXTENT)
 * nothing there overflows.  Others, only from absurd texture vectors, take
 * the stepper. */
_Static_assert(EW_MAX_EXTENT <= 2048, "lit_tame's bounds assume s_max and t_max under 2^27");
static inline int lit_tame(const ew_gradients *g) {
    /* Both in [-2^30, 2^30), tested at once (a little stricter than needed). */
    return (((uint32_t)g->s_adjust + (1u << 30)) | ((uint32_t)g->t_adjust + (1u << 30))) < (1u << 31);
}

/* lit_row_at loads the gradients four members at a time. */
_Static_assert(offsetof(ew_gradients, pad_u) == offsetof(ew_gradients, zi_u) + 12 &&
                   offsetof(ew_gradients, zi_v) == offsetof(ew_gradients, zi_u) + 16 &&
                   offsetof(ew_gradients, zi_0) == offsetof(ew_gradients, zi_u) + 32 &&
                   offsetof(ew_gradients, pad_0) == offsetof(ew_gradients, zi_0) + 12 &&
                   offsetof(ew_gradients, t_max) == offsetof(ew_gradients, s_adjust) + 12,
               "ew_gradients' terms and limits must lie four to a vector");
static inline lit_row lit_row_at(const ew_gradients *g, int v, uint32_t pitch) {
    lit_row r;
    r.u = _mm_loadu_ps(&g->zi_u);
    r.c = _mm_add_ps(_mm_mul_ps(_mm_loadu_ps(&g->zi_v), _mm_set1_ps((float)v)), _mm_loadu_ps(&g->zi_0));
    __m128i lim = _mm_loadu_si128((const __m128i *)(const void *)&g->s_adjust);  /* s_adjust t_adjust s_max t_max */
    r.adj = _mm_shuffle_epi32(lim, _MM_SHUFFLE(1, 1, 0, 0));
    r.hi = _mm_sub_epi32(_mm_shuffle_epi32(lim, _MM_SHUFFLE(3, 3, 2, 2)), r.adj);
    r.lo0 = _mm_sub_epi32(_mm_setzero_si128(), r.adj);
    r.lo16 = _mm_sub_epi32(_mm_set1_epi32(16), r.adj);
    r.mul = _mm_set1_epi32((int)((pitch << 16) | 1u));
    return r;
}

/* The true s and t (lanes 1 and 2) at column fu, as ew_step_begin and
 * ew_step_next compute them (lo: lo0 or lo16 of the row, their low clamp):
 * lane by lane the same single-precision multiplies and adds, the float
 * clamps of ew_tex_fix as maxps/minps, its integer ones as above. */
static inline __m128i lit_point(const lit_row *r, float fu, __m128i lo) {
    __m128 p = _mm_add_ps(_mm_mul_ps(r->u, _mm_set1_ps(fu)), r->c);
    __m128 z = _mm_div_ss(_mm_set_ss(65536.0f), p);
    p = _mm_mul_ps(p, _mm_shuffle_ps(z, z, 0));
    __m128i x = _mm_cvttps_epi32(_mm_min_ps(_mm_max_ps(p, _mm_set1_ps(-1e9f)), _mm_set1_ps(1e9f)));
    return _mm_add_epi32(min32(max32(x, lo), r->hi), r->adj);
}

/* 16 texels from st (s, t, s, t) with steps d (ds, dt, ds, dt). */
static inline void texel_run16(uint8_t *dst, const uint8_t *pixels, __m128i st, __m128i d, __m128i mul,
                               int bytes, int narrow) {
    texel_lanes l;
    l.a = _mm_add_epi32(st, _mm_and_si128(d, _mm_setr_epi32(0, 0, -1, -1)));
    d = _mm_add_epi32(d, d);
    l.b = _mm_add_epi32(l.a, d);
    l.step = _mm_add_epi32(d, d);
    l.mul = mul;
    for (int i = 0; i < 16; i += 4) {
        uint32_t k[4];
        texel_lanes_next(&l, k, narrow);
        if (bytes == 1) {
            dst[i] = pixels[k[0]];
            dst[i + 1] = pixels[k[1]];
            dst[i + 2] = pixels[k[2]];
            dst[i + 3] = pixels[k[3]];
        } else {
            /* A load and a store a pixel, as the bytes above: building the
             * vector of four took three shuffles more. */
            const uint32_t *src = (const uint32_t *)(const void *)pixels;
            uint8_t *d = dst + (size_t)i * 4;
            memcpy(d, &src[k[0]], 4);
            memcpy(d + 4, &src[k[1]], 4);
            memcpy(d + 8, &src[k[2]], 4);
            memcpy(d + 12, &src[k[3]], 4);
        }
    }
}

/* The end points of four segments at fu + off (off: each lane's distance
 * in columns), s in *S and t in *T: lit_point's arithmetic lane by lane
 * with the low clamp lo16 (each lane of divps is divss's result), so four
 * points cost one divide. */
static inline void lit_points4(const lit_row *r, float fu, __m128 off, __m128i *S, __m128i *T) {
    const __m128 f = _mm_add_ps(_mm_set1_ps(fu), off);
    const __m128 zi = _mm_add_ps(_mm_mul_ps(_mm_shuffle_ps(r->u, r->u, 0x00), f), _mm_shuffle_ps(r->c, r->c, 0x00));
    const __m128 z = _mm_div_ps(_mm_set1_ps(65536.0f), zi);
    __m128 ps = _mm_mul_ps(_mm_add_ps(_mm_mul_ps(_mm_shuffle_ps(r->u, r->u, 0x55), f), _mm_shuffle_ps(r->c, r->c, 0x55)), z);
    __m128 pt = _mm_mul_ps(_mm_add_ps(_mm_mul_ps(_mm_shuffle_ps(r->u, r->u, 0xAA), f), _mm_shuffle_ps(r->c, r->c, 0xAA)), z);
    const __m128 lo = _mm_set1_ps(-1e9f), hi = _mm_set1_ps(1e9f);
    __m128i xs = _mm_cvttps_epi32(_mm_min_ps(_mm_max_ps(ps, lo), hi));
    __m128i xt = _mm_cvttps_epi32(_mm_min_ps(_mm_max_ps(pt, lo), hi));
    *S = _mm_add_epi32(min32(max32(xs, _mm_shuffle_epi32(r->lo16, 0x55)), _mm_shuffle_epi32(r->hi, 0x55)),
                       _mm_shuffle_epi32(r->adj, 0x55));
    *T = _mm_add_epi32(min32(max32(xt, _mm_shuffle_epi32(r->lo16, 0xAA)), _mm_shuffle_epi32(r->hi, 0xAA)),
                       _mm_shuffle_epi32(r->adj, 0xAA));
}

/* Four 16-pixel segments in a row, from the first one's start st (s, t in
 * lanes 1 and 2) and each one's end (lane k of S and T): start and step
 * of segments 0 and 1 in a and da, of 2 and 3 in b and db, as (s, t, s, t)
 * pairs. */
typedef struct seg4 { __m128i a, b, da, db; } seg4;
static inline seg4 segments4(__m128i st, __m128i S, __m128i T) {
    const __m128i lane0 = _mm_setr_epi32(-1, 0, 0, 0);
    /* The starts: the carried point, then the first three ends. */
    const __m128i PS = _mm_or_si128(_mm_slli_si128(S, 4), _mm_and_si128(_mm_shuffle_epi32(st, 0x55), lane0));
    const __m128i PT = _mm_or_si128(_mm_slli_si128(T, 4), _mm_and_si128(_mm_shuffle_epi32(st, 0xAA), lane0));
    const __m128i DS = _mm_srai_epi32(_mm_sub_epi32(S, PS), 4), DT = _mm_srai_epi32(_mm_sub_epi32(T, PT), 4);
    return (seg4){_mm_unpacklo_epi32(PS, PT), _mm_unpackhi_epi32(PS, PT), _mm_unpacklo_epi32(DS, DT),
                  _mm_unpackhi_epi32(DS, DT)};
}

/* Segment k (0 to 3, a constant after inlining) of q: 16 texels. */
static inline void seg4_run(uint8_t *dst, const uint8_t *pixels, const seg4 *q, int k, __m128i mul, int bytes,
                            int narrow) {
    const __m128i p = k < 2 ? q->a : q->b, d = k < 2 ? q->da : q->db;
    if (k % 2 == 0)
        texel_run16(dst + 16 * k * bytes, pixels, _mm_shuffle_epi32(p, 0x44), _mm_shuffle_epi32(d, 0x44), mul, bytes,
                    narrow);
    else
        texel_run16(dst + 16 * k * bytes, pixels, _mm_shuffle_epi32(p, 0xEE), _mm_shuffle_epi32(d, 0xEE), mul, bytes,
                    narrow);
}

/* A lit span with the default divide every 16 pixels (bytes: 1 for 8-bit
 * frames, 4 for true colour; a tame surface, lit_tame): the stepper's
 * arithmetic with the surface's gradients and limits held in registers,
 * whole segments first, then the last one of 1 to 16 pixels, which ends on
 * its own last pixel.  The segments' end points are computed four at a
 * time: one divide instruction for four, where the divide's latency, one
 * segment after another, had been what the span waited on (the pixels are
 * the same).  Columns are whole numbers far below 2^24, so fu stepped in
 * floats is exactly (float)u. */
static EW_SPAN_INLINE void lit_span16(uint8_t *dst, const ew_surf_draw *d, int u, int v, int count, int bytes,
                                      int narrow) {
    if (count <= 0) return;
    const uint8_t *pixels = d->pixels;
    const uint32_t pitch = (uint32_t)d->pitch;
    const lit_row r = lit_row_at(&d->g, v, pitch);
    float fu = (float)u;
    __m128i st = lit_point(&r, fu, r.lo0);
    /* The points of the next four segments, or of the rest (up to three
     * whole segments and the last one's end, on the span's last pixel), are
     * computed before the four before them are drawn: their divide's
     * latency then hides behind 64 pixels of drawing. */
    const __m128 ends = _mm_setr_ps(16.0f, 32.0f, 48.0f, 64.0f);
    __m128i S, T;
    lit_points4(&r, fu, count > 64 ? ends : _mm_min_ps(ends, _mm_set1_ps((float)(count - 1))), &S, &T);
    for (; count > 64; count -= 64) {  /* four whole segments a divide */
        const seg4 q = segments4(st, S, T);
        st = _mm_slli_si128(_mm_unpackhi_epi32(_mm_shuffle_epi32(S, 0xFF), _mm_shuffle_epi32(T, 0xFF)), 4);
        fu += 64.0f;
        const int left = count - 64;
        lit_points4(&r, fu, left > 64 ? ends : _mm_min_ps(ends, _mm_set1_ps((float)(left - 1))), &S, &T);
        seg4_run(dst, pixels, &q, 0, r.mul, bytes, narrow);  /* not a loop: gcc would not unroll it */
        seg4_run(dst, pixels, &q, 1, r.mul, bytes, narrow);
        seg4_run(dst, pixels, &q, 2, r.mul, bytes, narrow);
        seg4_run(dst, pixels, &q, 3, r.mul, bytes, narrow);
        dst += 64 * bytes;
    }
    int32_t s = _mm_cvtsi128_si32(_mm_srli_si128(st, 4)), t = _mm_cvtsi128_si32(_mm_srli_si128(st, 8));
    int32_t ds = 0, dt = 0;
    if (count > 1) {
        const int last = count - 1, nfull = last >> 4;
        int32_t sa[4], ta[4];
        _mm_storeu_si128((__m128i *)(void *)sa, S);
        _mm_storeu_si128((__m128i *)(void *)ta, T);
        if (nfull > 0) {
            const seg4 q = segments4(st, S, T);
            seg4_run(dst, pixels, &q, 0, r.mul, bytes, narrow);
            if (nfull > 1) seg4_run(dst, pixels, &q, 1, r.mul, bytes, narrow);
            if (nfull > 2) seg4_run(dst, pixels, &q, 2, r.mul, bytes, narrow);
            s = sa[nfull - 1], t = ta[nfull - 1];
            dst += 16 * nfull * bytes;
            count -= 16 * nfull;
        }
        if (count > 1) {
            ds = ew_step_div(sa[nfull] - s, count - 1);
            dt = ew_step_div(ta[nfull] - t, count - 1);
        }
    }
    if (bytes == 1)
        ew_texel_run(dst, pixels, pitch, s, t, ds, dt, count, narrow);
    else
        texel_run32(dst, pixels, pitch, s, t, ds, dt, count);
}
#endif

void ew_draw_lit_span(const ew_span_ctx *c, const ew_span *sp, const ew_surf_draw *d) {
    uint8_t *dst = ew_target_at(c->target, sp->u, sp->v);
#if defined(__SSE2__)
    if (c->subdiv_shift == 4 && lit_tame(&d->g)) {
        lit_span16(dst, d, sp->u, sp->v, sp->count, 1, 0);
        return;
    }
#endif
    ew_stepper st;
    int32_t s, t, ds, dt;
    int n;
    ew_step_begin(&st, &d->g, c->subdiv_shift, sp->u, sp->v, sp->count);
    if (st.shift == 4) {
        /* Whole 16-pixel segments first: with their length known the
         * stepper's branches fold away and the texel loop unrolls. */
        while (st.left > 16) {
            ew_step_next(&st, &s, &t, &ds, &dt);
            ew_texel_run(dst, d->pixels, (uint32_t)d->pitch, s, t, ds, dt, 16, 0);
            dst += 16;
        }
    }
    while ((n = ew_step_next(&st, &s, &t, &ds, &dt)) > 0) {
        ew_texel_run(dst, d->pixels, (uint32_t)d->pitch, s, t, ds, dt, n, 0);
        dst += n;
    }
}

void ew_draw_flat_span(const ew_span_ctx *c, const ew_span *sp) {
    uint8_t *dst = ew_target_at(c->target, sp->u, sp->v);
    if (c->target->bpp == 1) {
        memset(dst, 0, (size_t)sp->count);
        return;
    }
    for (int x = 0; x < sp->count; x++) ew_put_index(c->target, dst, x, 0);
}

static void draw_lit_span32(const ew_span_ctx *c, const ew_span *sp, const ew_surf_draw *d) {
    uint8_t *dst = ew_target_at(c->target, sp->u, sp->v);
#if defined(__SSE2__)
    if (c->subdiv_shift == 4 && lit_tame(&d->g)) {
        lit_span16(dst, d, sp->u, sp->v, sp->count, 4, 0);
        return;
    }
#endif
    ew_stepper st;
    int32_t s, t, ds, dt;
    int n;
    ew_step_begin(&st, &d->g, c->subdiv_shift, sp->u, sp->v, sp->count);
    if (st.shift == 4) {  /* whole 16-pixel segments first, as the 8-bit drawer */
        while (st.left > 16) {
            ew_step_next(&st, &s, &t, &ds, &dt);
            texel_run32(dst, d->pixels, (uint32_t)d->pitch, s, t, ds, dt, 16);
            dst += 16 * 4;
        }
    }
    while ((n = ew_step_next(&st, &s, &t, &ds, &dt)) > 0) {
        texel_run32(dst, d->pixels, (uint32_t)d->pitch, s, t, ds, dt, n);
        dst += (size_t)n * 4;
    }
}

#if defined(__SSE2__)
/* A lit surface of at most 65536 texels (t_max holds its height less one,
 * in 16.16): its texel indices fit in 16 bits. */
static inline int lit_narrow(const ew_surf_draw *d) {
    return (int64_t)d->pitch * ((d->g.t_max >> 16) + 1) <= 65536;
}
#endif

/* The band's spans in the order the scan made them, row by row: the frame
 * is written straight through and so is the span list, where a surface's
 * own spans lie scattered.  Lit surfaces were looked up and built, and
 * every surface's gradients computed once, before the bands started. */
void ew_span_prepare(ew_surf_draw *d) {
#if defined(__SSE2__)
    d->lit16 = lit_tame(&d->g) ? (lit_narrow(d) ? 2 : 1) : 0;
#else
    d->lit16 = 0;
#endif
}

void ew_draw_spans(const ew_span_ctx *c, const ew_span *spans, int n, const ew_surf_draw *draw, int full_z) {
#if defined(__SSE2__)
    const int lit8 = c->target->bpp == 1 && c->subdiv_shift == 4;
#endif
    for (int i = 0; i < n; i++) {
        const ew_span *sp = &spans[i];
        const ew_surf_draw *d = &draw[sp->surf];
        switch (d->kind) {
        case EW_DRAW_LIT:
#if defined(__SSE2__)
            if (lit8 && d->lit16) {  /* the common cases inline: no call a span */
                uint8_t *dst = ew_target_at(c->target, sp->u, sp->v);
                if (d->lit16 == 2)
                    lit_span16(dst, d, sp->u, sp->v, sp->count, 1, 1);
                else
                    lit_span16(dst, d, sp->u, sp->v, sp->count, 1, 0);
            } else
#endif
            if (c->target->bpp == 1)
                ew_draw_lit_span(c, sp, d);
            else
                draw_lit_span32(c, sp, d);
            break;
        case EW_DRAW_SKY:
            ew_draw_sky_span(c, sp, d->tex);
            break;
        case EW_DRAW_TURB:
            ew_draw_turb_span(c, sp, &d->g, d->tex);
            break;
        case EW_DRAW_DEBUG:
            ew_debug_fill_span(c, sp, d->flat);
            break;
        case EW_DRAW_TWOPASS:
            ew_tp_span(c->tp, &c->tp_faces[sp->surf], ew_target_at(c->target, 0, sp->v), sp->v, sp->u,
                      sp->u + sp->count);
            break;
        default:  /* gaps (nothing covers them), or no memory for the surface: black */
            ew_draw_flat_span(c, sp);
            break;
        }
        if (full_z) ew_zfill_span(c->target, sp, &d->g);  /* the background's g is 0: far */
    }
}
