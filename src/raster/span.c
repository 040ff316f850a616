/* Back end: draw a surface's spans from its cached, lit surface with
 * perspective-correct texture mapping, and z-fill the world's 1/z. */
#include "span_step.h"

#include <math.h>
#include <string.h>

void ew_face_gradients(const ew_world *w, const ew_view *v, const ew_face *f, int mip,
                       ew_gradients *g) {
    const ew_plane *pl = &w->planes[f->plane];
    const ew_texinfo *ti = &w->texinfo[f->texinfo];
    float nx = 0, ny = 0, nz = 0, od = 0;
    for (int k = 0; k < 3; k++) {
        nx += pl->normal[k] * v->right[k];
        ny += pl->normal[k] * v->up[k];
        nz += pl->normal[k] * v->forward[k];
        od += pl->normal[k] * v->origin[k];
    }
    float dist = pl->dist - od;  /* plane in view space: n.p = dist */
    if (fabsf(dist) < 1e-3f) dist = dist < 0 ? -1e-3f : 1e-3f;
    float xs = v->xscale, ys = v->yscale, xc = v->xcenter, yc = v->ycenter;
    g->zi_u = nx / (xs * dist);
    g->zi_v = -ny / (ys * dist);
    g->zi_0 = nz / dist - xc * g->zi_u - yc * g->zi_v;

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


/* n texels along a straight line through the surface: the affine stretch
 * between two perspective-correct points.  s and t stay within the surface
 * all along (the stepper guarantees it), so unsigned maths is exact.  (A
 * four-at-a-time SSE2 version, and one that z-filled in the same loop,
 * bought no time: bench/README.md.) */
static inline void texel_run(uint8_t *dst, const uint8_t *pixels, uint32_t pitch, int32_t s,
                             int32_t t, int32_t ds, int32_t dt, int n) {
    for (int i = 0; i < n; i++) {
        dst[i] = pixels[((uint32_t)t >> 16) * pitch + ((uint32_t)s >> 16)];
        s += ds;
        t += dt;
    }
}

void ew_draw_spans(ew_renderer *r, const ew_band *b, int surf, const ew_gradients *g,
                   const uint8_t *pixels, int pitch) {
    int w = r->width;
    for (int si = b->span_head[surf]; si >= 0; si = b->spans[si].next) {
        const ew_span *sp = &b->spans[si];
        uint8_t *dst = r->frame + (size_t)sp->v * w + sp->u;
        ew_stepper st;
        int32_t s, t, ds, dt;
        int n;
        ew_step_begin(&st, g, r->subdiv_shift, sp->u, sp->v, sp->count);
        while ((n = ew_step_next(&st, &s, &t, &ds, &dt)) > 0) {
            texel_run(dst, pixels, (uint32_t)pitch, s, t, ds, dt, n);
            dst += n;
        }
    }
}

void ew_zfill_spans(ew_renderer *r, const ew_band *b, int surf, const ew_gradients *g) {
    int w = r->width;
    for (int si = b->span_head[surf]; si >= 0; si = b->spans[si].next) {
        const ew_span *sp = &b->spans[si];
        float *z = r->zbuf + (size_t)sp->v * w + sp->u;
        /* Each value from the start, not accumulated: exact and vectorizable. */
        float zi = g->zi_u * sp->u + g->zi_v * sp->v + g->zi_0, dz = g->zi_u;
        for (int i = 0; i < sp->count; i++) z[i] = zi + (float)i * dz;
    }
}
