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
#if EW_SIMD4
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

#if EW_SIMD4
/* The lit span walk is inlined into each caller: gcc otherwise keeps one
 * shared copy and calls it for every span. */
#if defined(__GNUC__)
#define EW_SPAN_INLINE inline __attribute__((always_inline))
#else
#define EW_SPAN_INLINE inline
#endif

/* A lit span's row, everything in the lanes (1/z, s/z, t/z, -) of one
 * vector: the planes' column term and the rest, and for s and t (lanes 1
 * and 2) the eye's coordinate and the clamp limits less it. */
typedef struct lit_row {
    ew_v4f u, c;
    ew_v4i adj, lo0, lo16, hi;
    ew_v4i mul;  /* texel_lanes' (1, pitch) pairs */
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
    r.u = ew_v4f_loadu(&g->zi_u);
    r.c = ew_v4f_add(ew_v4f_mul(ew_v4f_loadu(&g->zi_v), ew_v4f_set1((float)v)), ew_v4f_loadu(&g->zi_0));
    ew_v4i lim = ew_v4i_loadu(&g->s_adjust);  /* s_adjust t_adjust s_max t_max */
    r.adj = EW_V4I_SHUF(lim, 0, 0, 1, 1);
    r.hi = ew_v4i_sub(EW_V4I_SHUF(lim, 2, 2, 3, 3), r.adj);
    r.lo0 = ew_v4i_sub(ew_v4i_zero(), r.adj);
    r.lo16 = ew_v4i_sub(ew_v4i_set1(16), r.adj);
    r.mul = ew_v4i_set1((int32_t)((pitch << 16) | 1u));
    return r;
}

/* The true s and t (lanes 1 and 2) at column fu, as ew_step_begin and
 * ew_step_next compute them (lo: lo0 or lo16 of the row, their low clamp):
 * lane by lane the same single-precision multiplies and adds, the float
 * clamps of ew_tex_fix as SSE's max and min, its integer ones as above. */
static inline ew_v4i lit_point(const lit_row *r, float fu, ew_v4i lo) {
    ew_v4f p = ew_v4f_add(ew_v4f_mul(r->u, ew_v4f_set1(fu)), r->c);
    ew_v4f z = ew_v4f_div0(65536.0f, p);
    p = ew_v4f_mul(p, EW_V4F_SPLAT(z, 0));
    ew_v4i x = ew_v4f_trunc(ew_v4f_min(ew_v4f_max(p, ew_v4f_set1(-1e9f)), ew_v4f_set1(1e9f)));
    return ew_v4i_add(ew_v4i_min(ew_v4i_max(x, lo), r->hi), r->adj);
}

/* 16 texels from st (s, t, s, t) with steps d (ds, dt, ds, dt). */
static inline void texel_run16(uint8_t *dst, const uint8_t *pixels, ew_v4i st, ew_v4i d, ew_v4i mul,
                               int bytes, int narrow) {
    texel_lanes l;
    l.a = ew_v4i_add(st, ew_v4i_and(d, ew_v4i_setr(0, 0, -1, -1)));
    d = ew_v4i_add(d, d);
    l.b = ew_v4i_add(l.a, d);
    l.step = ew_v4i_add(d, d);
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
 * with the low clamp lo16 (each lane of a four-lane divide is the one-lane
 * divide's result), so four points cost one divide. */
static inline void lit_points4(const lit_row *r, float fu, ew_v4f off, ew_v4i *S, ew_v4i *T) {
    const ew_v4f f = ew_v4f_add(ew_v4f_set1(fu), off);
    const ew_v4f zi = ew_v4f_add(ew_v4f_mul(EW_V4F_SPLAT(r->u, 0), f), EW_V4F_SPLAT(r->c, 0));
    const ew_v4f z = ew_v4f_div(ew_v4f_set1(65536.0f), zi);
    ew_v4f ps = ew_v4f_mul(ew_v4f_add(ew_v4f_mul(EW_V4F_SPLAT(r->u, 1), f), EW_V4F_SPLAT(r->c, 1)), z);
    ew_v4f pt = ew_v4f_mul(ew_v4f_add(ew_v4f_mul(EW_V4F_SPLAT(r->u, 2), f), EW_V4F_SPLAT(r->c, 2)), z);
    const ew_v4f lo = ew_v4f_set1(-1e9f), hi = ew_v4f_set1(1e9f);
    ew_v4i xs = ew_v4f_trunc(ew_v4f_min(ew_v4f_max(ps, lo), hi));
    ew_v4i xt = ew_v4f_trunc(ew_v4f_min(ew_v4f_max(pt, lo), hi));
    *S = ew_v4i_add(ew_v4i_min(ew_v4i_max(xs, EW_V4I_SHUF(r->lo16, 1, 1, 1, 1)), EW_V4I_SHUF(r->hi, 1, 1, 1, 1)),
                    EW_V4I_SHUF(r->adj, 1, 1, 1, 1));
    *T = ew_v4i_add(ew_v4i_min(ew_v4i_max(xt, EW_V4I_SHUF(r->lo16, 2, 2, 2, 2)), EW_V4I_SHUF(r->hi, 2, 2, 2, 2)),
                    EW_V4I_SHUF(r->adj, 2, 2, 2, 2));
}

/* Four 16-pixel segments in a row, from the first one's start st (s, t in
 * lanes 1 and 2) and each one's end (lane k of S and T): start and step
 * of segments 0 and 1 in a and da, of 2 and 3 in b and db, as (s, t, s, t)
 * pairs. */
typedef struct seg4 { ew_v4i a, b, da, db; } seg4;
static inline seg4 segments4(ew_v4i st, ew_v4i S, ew_v4i T) {
    const ew_v4i lane0 = ew_v4i_setr(-1, 0, 0, 0);
    /* The starts: the carried point, then the first three ends. */
    const ew_v4i PS = ew_v4i_or(ew_v4i_up1(S), ew_v4i_and(EW_V4I_SHUF(st, 1, 1, 1, 1), lane0));
    const ew_v4i PT = ew_v4i_or(ew_v4i_up1(T), ew_v4i_and(EW_V4I_SHUF(st, 2, 2, 2, 2), lane0));
    const ew_v4i DS = EW_V4I_SRA(ew_v4i_sub(S, PS), 4), DT = EW_V4I_SRA(ew_v4i_sub(T, PT), 4);
    return (seg4){ew_v4i_zip_lo(PS, PT), ew_v4i_zip_hi(PS, PT), ew_v4i_zip_lo(DS, DT), ew_v4i_zip_hi(DS, DT)};
}

/* Segment k (0 to 3, a constant after inlining) of q: 16 texels. */
static inline void seg4_run(uint8_t *dst, const uint8_t *pixels, const seg4 *q, int k, ew_v4i mul, int bytes,
                            int narrow) {
    const ew_v4i p = k < 2 ? q->a : q->b, d = k < 2 ? q->da : q->db;
    if (k % 2 == 0)
        texel_run16(dst + 16 * k * bytes, pixels, EW_V4I_SHUF(p, 0, 1, 0, 1), EW_V4I_SHUF(d, 0, 1, 0, 1), mul, bytes,
                    narrow);
    else
        texel_run16(dst + 16 * k * bytes, pixels, EW_V4I_SHUF(p, 2, 3, 2, 3), EW_V4I_SHUF(d, 2, 3, 2, 3), mul, bytes,
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
    ew_v4i st = lit_point(&r, fu, r.lo0);
    /* The points of the next four segments, or of the rest (up to three
     * whole segments and the last one's end, on the span's last pixel), are
     * computed before the four before them are drawn: their divide's
     * latency then hides behind 64 pixels of drawing. */
    const ew_v4f ends = ew_v4f_setr(16.0f, 32.0f, 48.0f, 64.0f);
    ew_v4i S, T;
    lit_points4(&r, fu, count > 64 ? ends : ew_v4f_min(ends, ew_v4f_set1((float)(count - 1))), &S, &T);
    for (; count > 64; count -= 64) {  /* four whole segments a divide */
        const seg4 q = segments4(st, S, T);
        st = ew_v4i_up1(ew_v4i_zip_hi(EW_V4I_SHUF(S, 3, 3, 3, 3), EW_V4I_SHUF(T, 3, 3, 3, 3)));
        fu += 64.0f;
        const int left = count - 64;
        lit_points4(&r, fu, left > 64 ? ends : ew_v4f_min(ends, ew_v4f_set1((float)(left - 1))), &S, &T);
        seg4_run(dst, pixels, &q, 0, r.mul, bytes, narrow);  /* not a loop: gcc would not unroll it */
        seg4_run(dst, pixels, &q, 1, r.mul, bytes, narrow);
        seg4_run(dst, pixels, &q, 2, r.mul, bytes, narrow);
        seg4_run(dst, pixels, &q, 3, r.mul, bytes, narrow);
        dst += 64 * bytes;
    }
    int32_t s = EW_V4I_LANE(st, 1), t = EW_V4I_LANE(st, 2);
    int32_t ds = 0, dt = 0;
    if (count > 1) {
        const int last = count - 1, nfull = last >> 4;
        int32_t sa[4], ta[4];
        ew_v4i_storeu(sa, S);
        ew_v4i_storeu(ta, T);
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
#if EW_SIMD4
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
#if EW_SIMD4
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

#if EW_SIMD4
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
#if EW_SIMD4
    d->lit16 = lit_tame(&d->g) ? (lit_narrow(d) ? 2 : 1) : 0;
#else
    d->lit16 = 0;
#endif
}

void ew_draw_spans(const ew_span_ctx *c, const ew_span *spans, int n, const ew_surf_draw *draw, int full_z) {
#if EW_SIMD4
    const int lit8 = c->target->bpp == 1 && c->subdiv_shift == 4;
#endif
    for (int i = 0; i < n; i++) {
        const ew_span *sp = &spans[i];
        const ew_surf_draw *d = &draw[sp->surf];
        switch (d->kind) {
        case EW_DRAW_LIT:
#if EW_SIMD4
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
