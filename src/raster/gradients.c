/* Screen gradients of a face: 1/z, s/z and t/z as planes over the screen,
 * computed once per surface and frame (in parallel with the surface
 * builds), read by the span drawers, the z-fill and the edge scan's 1/z
 * ties between brush-model fragments. */
#include "raster/raster.h"
#include "world/view.h"

#include <math.h>

void ew_face_gradients(const ew_world *w, const ew_view *v, const ew_face *f, int mip,
                       ew_gradients *g) {
    const ew_texinfo *ti = &w->texinfo[f->texinfo];
    float zp[3];
    ew_face_zplane(w, v, f, zp);
    g->zi_u = zp[0], g->zi_v = zp[1], g->zi_0 = zp[2];
    g->pad_u = g->pad_v = g->pad_0 = 0;
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
    g->s_max = (int32_t)(((int64_t)ew_face_surf_size(f, 0, mip) << 16) - 1);
    g->t_max = (int32_t)(((int64_t)ew_face_surf_size(f, 1, mip) << 16) - 1);
}
