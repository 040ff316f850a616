/* Back end: draw a surface's spans from its cached, lit surface with
 * perspective-correct texture mapping, and z-fill the world's 1/z. */
#include "span_step.h"

#include <math.h>
#include <string.h>

/* The 1/z plane of face f seen through v. */
static void face_zplane(const ew_world *w, const ew_view *v, const ew_face *f, float out[3]) {
    const ew_plane *pl = &w->planes[f->plane];
    float nx = 0, ny = 0, nz = 0, od = 0;
    for (int k = 0; k < 3; k++) {
        nx += pl->normal[k] * v->right[k];
        ny += pl->normal[k] * v->up[k];
        nz += pl->normal[k] * v->forward[k];
        od += pl->normal[k] * v->origin[k];
    }
    float dist = pl->dist - od;  /* plane in view space: n.p = dist */
    if (fabsf(dist) < 1e-3f) dist = dist < 0 ? -1e-3f : 1e-3f;
    out[0] = nx / (v->xscale * dist);
    out[1] = -ny / (v->yscale * dist);
    out[2] = nz / dist - v->xcenter * out[0] - v->ycenter * out[1];
}

void ew_face_gradients(const ew_world *w, const ew_view *v, const ew_face *f, int mip,
                       ew_gradients *g) {
    const ew_texinfo *ti = &w->texinfo[f->texinfo];
    float zp[3];
    face_zplane(w, v, f, zp);
    g->zi_u = zp[0], g->zi_v = zp[1], g->zi_0 = zp[2];
    float xs = v->xscale, ys = v->yscale, xc = v->xcenter, yc = v->ycenter;

    /* s/z and t/z of the direction from the eye; the eye's own texture
     * coordinate is added after the divide, in fixed point, as the
     * original did (it keeps the big offset out of the float gradients). */
    float scale = 1.0f / (float)(1 << mip);
    int mins[2] = {f->texturemins[0], f->texturemins[1]};
    float *out[2][3] = {{&g->s_u, &g->s_v, &g->s_0}, {&g->t_u, &g->t_v, &g->t_0}};
    int32_t *adj[2] = {&g->s_adjust, &g->t_adjust};
    for (int a = 0; a < 2; a++) {
        const float *vec = ti->vecs[a];
        float sr = 0, su = 0, sf = 0, so = 0;
        for (int k = 0; k < 3; k++) {
            sr += vec[k] * v->right[k];
            su += vec[k] * v->up[k];
            sf += vec[k] * v->forward[k];
            so += vec[k] * v->origin[k];
        }
        sr *= scale, su *= scale, sf *= scale;
        *out[a][0] = sr / xs;
        *out[a][1] = -su / ys;
        *out[a][2] = sf - xc * sr / xs + yc * su / ys;
        /* Clamped (NaN too) before any conversion, summed in 64 bits:
         * a file's huge vectors or offsets only misplace the texture,
         * whose coordinates are clamped to the surface anyway. */
        double c = (double)so * scale * 65536.0 + 0.5;
        if (!(c > -1e9)) c = -1e9;
        if (c > 1e9) c = 1e9;
        double ofs = (double)vec[3] * 65536.0 * scale;
        if (!(ofs > -1e9)) ofs = -1e9;
        if (ofs > 1e9) ofs = 1e9;
        int64_t sum = (int64_t)(int32_t)c - (((int64_t)mins[a] * 65536) >> mip) + (int32_t)ofs;
        *adj[a] = (int32_t)(sum < INT32_MIN ? INT32_MIN : sum > INT32_MAX ? INT32_MAX : sum);
    }
    g->s_max = (int32_t)(((int64_t)(f->extents[0] >> mip) << 16) - 1);
    g->t_max = (int32_t)(((int64_t)(f->extents[1] >> mip) << 16) - 1);
}


#if defined(__SSE2__)
#include <emmintrin.h>
#endif

/* n texels along a straight line through the surface: the affine stretch
 * between two perspective-correct points.  s and t stay within the
 * surface all along (the stepper guarantees it), so unsigned maths is exact.
 * With SSE2, four at a time: the integer parts of s and t are paired as
 * 16-bit halves and one multiply-add gives s + t * pitch for four pixels;
 * surfaces are far smaller than 32768 texels a side, as that needs. */
static inline void texel_run(uint8_t *dst, const uint8_t *pixels, uint32_t pitch, int32_t s,
                             int32_t t, int32_t ds, int32_t dt, int n) {
    int i = 0;
#if defined(__SSE2__)
    if (n >= 4) {
        __m128i vs = _mm_setr_epi32(s, s + ds, s + 2 * ds, s + 3 * ds);
        __m128i vt = _mm_setr_epi32(t, t + dt, t + 2 * dt, t + 3 * dt);
        const __m128i step_s = _mm_set1_epi32(4 * ds), step_t = _mm_set1_epi32(4 * dt);
        const __m128i hi16 = _mm_set1_epi32((int)0xFFFF0000u);
        const __m128i mul = _mm_set1_epi32((int)((pitch << 16) | 1u));  /* (1, pitch) pairs */
        for (; i + 4 <= n; i += 4) {
            __m128i pair = _mm_or_si128(_mm_srli_epi32(vs, 16), _mm_and_si128(vt, hi16));
            __m128i idx = _mm_madd_epi16(pair, mul);
            uint32_t k0 = (uint32_t)_mm_cvtsi128_si32(idx);
            uint32_t k1 = (uint32_t)_mm_cvtsi128_si32(_mm_shuffle_epi32(idx, 0x55));
            uint32_t k2 = (uint32_t)_mm_cvtsi128_si32(_mm_shuffle_epi32(idx, 0xAA));
            uint32_t k3 = (uint32_t)_mm_cvtsi128_si32(_mm_shuffle_epi32(idx, 0xFF));
            uint32_t four = (uint32_t)pixels[k0] | (uint32_t)pixels[k1] << 8 |
                            (uint32_t)pixels[k2] << 16 | (uint32_t)pixels[k3] << 24;
            memcpy(dst + i, &four, 4);  /* little-endian: pixel i first */
            vs = _mm_add_epi32(vs, step_s);
            vt = _mm_add_epi32(vt, step_t);
        }
        s += i * ds;
        t += i * dt;
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

void ew_draw_lit_span(ew_renderer *r, const ew_span *sp, const ew_surf_draw *d) {
    uint8_t *dst = r->frame + (size_t)sp->v * r->width + sp->u;
    ew_stepper st;
    int32_t s, t, ds, dt;
    int n;
    ew_step_begin(&st, &d->g, r->subdiv_shift, sp->u, sp->v, sp->count);
    if (st.shift == 4) {
        /* Whole 16-pixel segments first: with their length known the
         * stepper's branches fold away and the texel loop unrolls. */
        while (st.left > 16) {
            ew_step_next(&st, &s, &t, &ds, &dt);
            texel_run(dst, d->pixels, (uint32_t)d->pitch, s, t, ds, dt, 16);
            dst += 16;
        }
    }
    while ((n = ew_step_next(&st, &s, &t, &ds, &dt)) > 0) {
        texel_run(dst, d->pixels, (uint32_t)d->pitch, s, t, ds, dt, n);
        dst += n;
    }
}

void ew_zfill_span(ew_renderer *r, const ew_span *sp, const ew_gradients *g) {
    float *z = r->zbuf + (size_t)sp->v * r->width + sp->u;
    /* Each value from the start, not accumulated: exact and vectorizable. */
    float zi = g->zi_u * sp->u + g->zi_v * sp->v + g->zi_0, dz = g->zi_u;
    for (int i = 0; i < sp->count; i++) z[i] = zi + (float)i * dz;
}

/* ---- deferred z-fill ----
 * Only moving things read the z-buffer, and they usually cover a small part
 * of the frame, so the world's 1/z is written where they are about to be
 * drawn instead of under every span: the same values (the same formula as
 * ew_zfill_span, so bit for bit), a fraction of the memory traffic.  Each
 * row remembers the interval already filled; requests widen it. */

/* World 1/z over [lo, hi) of row y from the spans that cover it. */
static void zfill_row(ew_renderer *r, int y, int lo, int hi) {
    if (r->row_nspans[y] == 0) return;  /* no spans (yet, or their bands are gone) */
    const ew_band *b = &r->bands[r->row_band[y]];
    const ew_span *sp = b->spans + r->row_span0[y];
    float *zr = r->zbuf + (size_t)y * r->width;
    for (int i = 0, n = r->row_nspans[y]; i < n; i++, sp++) {
        if (sp->u >= hi) break;  /* a row's spans run left to right */
        int a = sp->u > lo ? sp->u : lo, e = sp->u + sp->count < hi ? sp->u + sp->count : hi;
        if (a >= e) continue;
        const ew_gradients *g = &r->surf_draw[sp->surf].g;
        float zi = g->zi_u * sp->u + g->zi_v * sp->v + g->zi_0, dz = g->zi_u;
        for (int x = a; x < e; x++) zr[x] = zi + (float)(x - sp->u) * dz;
    }
}

void ew_zfill_rect(ew_renderer *r, int x0, int y0, int x1, int y1) {
    if (r->zfill_all) return;
    if (x0 < 0) x0 = 0;
    if (y0 < 0) y0 = 0;
    if (x1 > r->width) x1 = r->width;
    if (y1 > r->height) y1 = r->height;
    if (x0 >= x1) return;
    for (int y = y0; y < y1; y++) {
        int lo = r->zlo[y], hi = r->zhi[y];
        if (lo >= hi) {
            zfill_row(r, y, x0, x1);
            r->zlo[y] = x0, r->zhi[y] = x1;
            continue;
        }
        if (x0 < lo) zfill_row(r, y, x0, lo), r->zlo[y] = x0;
        if (x1 > hi) zfill_row(r, y, hi, x1), r->zhi[y] = x1;
    }
}

void ew_zfill_index_band(ew_renderer *r, const ew_band *b, int band) {
    for (int y = b->y0; y < b->y1; y++) {
        r->row_band[y] = band, r->row_nspans[y] = 0, r->row_span0[y] = 0;
        r->zlo[y] = r->zhi[y] = 0;
    }
    for (int i = 0; i < b->nspans; i++) {
        int y = b->spans[i].v;
        if (y < b->y0 || y >= b->y1) continue;
        if (r->row_nspans[y]++ == 0) r->row_span0[y] = i;
    }
}

void ew_zfill_mark_all(ew_renderer *r) {
    for (int y = 0; y < r->height; y++) r->zlo[y] = 0, r->zhi[y] = r->width;
}
