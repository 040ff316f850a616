/* Sprites: one flat, z-buffered picture per entity, oriented by the
 * sprite's type.  Each pixel of the quad's screen bounds casts its ray onto
 * the sprite's plane: 1/z is linear over the screen (so the z test is
 * exact) and the texel comes from one divide per pixel (sprites are few
 * and small).  Index 255 is transparent; sprites are not lit. */
#include "raster/alias.h"

#include <math.h>

#define SPRITE_NEAR 1.0f

static float norm3(float v[3]) {
    float l = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 1e-6f)
        for (int i = 0; i < 3; i++) v[i] /= l;
    return l;
}

static void sprite_axes(const ew_view *v, const ew_spr *s, const ew_model_pose *p, float right[3],
                        float up[3]) {
    const double d2r = 3.14159265358979323846 / 180.0;
    for (int i = 0; i < 3; i++) right[i] = v->right[i], up[i] = v->up[i];
    switch (s->type) {
    case EW_SPR_VP_PARALLEL_UPRIGHT: {
        float r[3] = {v->forward[1], -v->forward[0], 0};
        if (norm3(r) > 1e-6f) {
            for (int i = 0; i < 3; i++) right[i] = r[i];
            up[0] = up[1] = 0, up[2] = 1;
        }
        break;
    }
    case EW_SPR_FACING_UPRIGHT: {
        float r[3] = {p->origin[1] - v->origin[1], -(p->origin[0] - v->origin[0]), 0};
        if (norm3(r) > 1e-6f) {
            for (int i = 0; i < 3; i++) right[i] = r[i];
            up[0] = up[1] = 0, up[2] = 1;
        }
        break;
    }
    case EW_SPR_ORIENTED: {
        float fwd[3];
        ew_angle_vectors(p->angles, fwd, right, up);
        break;
    }
    case EW_SPR_VP_PARALLEL_ORIENTED: {
        float sr = (float)sin(p->angles[2] * d2r), cr = (float)cos(p->angles[2] * d2r);
        for (int i = 0; i < 3; i++) {
            right[i] = v->right[i] * cr + v->up[i] * sr;
            up[i] = -v->right[i] * sr + v->up[i] * cr;
        }
        break;
    }
    default: /* EW_SPR_VP_PARALLEL */
        break;
    }
}

static inline float dot3(const float a[3], const float b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

int ew_draw_sprite_rows(const ew_frame *f, ew_zfill *zf, const ew_spr *s, const ew_model_pose *p,
                        const ew_rows *rows) {
    if (!f || !s || !p) return 0;
    for (int k = 0; k < 3; k++)
        if (!isfinite(p->origin[k]) || !isfinite(p->angles[k]) || fabsf(p->origin[k]) > 1e6f) return 0;
    const ew_view *v = &f->view;
    const ew_spr_pic *pic = ew_spr_pick(s, p->frame, p->time);
    float wr[3], wu[3];
    sprite_axes(v, s, p, wr, wu);

    /* Everything in view space: origin O, axes R and U, normal N. */
    float O[3], R[3], U[3], N[3];
    ew_view_transform(v, p->origin, O);
    const float *vrow[3] = {v->right, v->up, v->forward};
    for (int i = 0; i < 3; i++) R[i] = dot3(vrow[i], wr), U[i] = dot3(vrow[i], wu);
    N[0] = R[1] * U[2] - R[2] * U[1];
    N[1] = R[2] * U[0] - R[0] * U[2];
    N[2] = R[0] * U[1] - R[1] * U[0];
    float no = dot3(N, O);
    if (fabsf(no) < 1e-4f) return 0;  /* seen edge-on */

    /* The quad, clipped to the near plane and the screen's side planes. */
    float left = (float)pic->origin[0], top = (float)pic->origin[1];
    float rgt = left + pic->width, bot = top - pic->height;
    float quad[4][2] = {{left, top}, {rgt, top}, {rgt, bot}, {left, bot}};
    float poly[2][16][3];
    int n = 4;
    for (int c = 0; c < 4; c++)
        for (int i = 0; i < 3; i++) poly[0][c][i] = O[i] + R[i] * quad[c][0] + U[i] * quad[c][1];
    ew_view_planes_t pl;
    ew_view_planes(v, SPRITE_NEAR, &pl);
    int cur = 0;
    for (int k = 0; k < 5 && n > 0; k++) {
        int m = 0;
        float(*src)[3] = poly[cur], (*dst)[3] = poly[cur ^ 1];
        for (int i = 0; i < n && m < 15; i++) {
            const float *a = src[i], *b = src[(i + 1) % n];
            float da = dot3(pl.n[k], a) + pl.d[k], db = dot3(pl.n[k], b) + pl.d[k];
            if (da >= 0) {
                for (int j = 0; j < 3; j++) dst[m][j] = a[j];
                m++;
            }
            if ((da >= 0) != (db >= 0)) {
                float f = da / (da - db);
                for (int j = 0; j < 3; j++) dst[m][j] = a[j] + f * (b[j] - a[j]);
                m++;
            }
        }
        n = m;
        cur ^= 1;
    }
    if (n < 3) return 0;
    float umin = 1e30f, umax = -1e30f, vmin = 1e30f, vmax = -1e30f;
    for (int i = 0; i < n; i++) {
        const float *q = poly[cur][i];
        float u = v->xcenter + v->xscale * q[0] / q[2], vv = v->ycenter - v->yscale * q[1] / q[2];
        if (u < umin) umin = u;
        if (u > umax) umax = u;
        if (vv < vmin) vmin = vv;
        if (vv > vmax) vmax = vv;
    }
    int x0 = (int)floorf(umin), x1 = (int)ceilf(umax) + 1;
    int y0 = (int)floorf(vmin), y1 = (int)ceilf(vmax) + 1;
    if (x0 < 0) x0 = 0;
    if (y0 < rows->y0) y0 = rows->y0;
    if (x1 > v->width) x1 = v->width;
    if (y1 > rows->y1) y1 = rows->y1;
    if (x0 >= x1) return 0;
    if (y0 >= y1) return 1;  /* in view, but not in these rows */
    ew_zfill_rect(zf, x0, y0, x1, y1);

    /* Per pixel: d = ((u - xc) / xs, -(v - yc) / ys, 1);  1/z = N.d / N.O;
     * a = (R.d) z - R.O, b = (U.d) z - U.O. */
    float ixs = 1.0f / v->xscale, iys = 1.0f / v->yscale;
    float du[3] = {ixs, 0, 0}, dv[3] = {0, -iys, 0};
    float d0[3] = {-v->xcenter * ixs, v->ycenter * iys, 1};
    float inv_no = 1.0f / no;
    float zu = dot3(N, du) * inv_no, zv = dot3(N, dv) * inv_no, z0 = dot3(N, d0) * inv_no;
    float ru = dot3(R, du), rv = dot3(R, dv), r0 = dot3(R, d0), ro = dot3(R, O);
    float uu = dot3(U, du), uv = dot3(U, dv), u0 = dot3(U, d0), uo = dot3(U, O);
    int pw = pic->width, ph = pic->height;
    long count = 0;
    const int bpp = f->target.bpp;  /* read once: the stores could alias the renderer */
    const uint32_t *rgba = f->target.rgba;
    for (int y = y0; y < y1; y++) {
        float *zr = ew_target_z(&f->target, 0, y);
        uint8_t *fr = ew_target_at(&f->target, 0, y);
        float fy = (float)y;
        for (int x = x0; x < x1; x++) {
            float fx = (float)x;
            float zi = zu * fx + zv * fy + z0;
            if (!(zi > 0) || zi < zr[x]) continue;
            float z = 1.0f / zi;
            float a = (ru * fx + rv * fy + r0) * z - ro - left;
            float b = top - ((uu * fx + uv * fy + u0) * z - uo);
            if (!(a >= 0 && b >= 0 && a < (float)pw && b < (float)ph)) continue;
            uint8_t c = pic->pixels[(int)b * pw + (int)a];
            if (c == 255) continue;
            zr[x] = zi;
            ew_put_via(bpp, rgba, fr, x, c);
            count++;
        }
    }
    rows->stats->alias_pixels += count;
    return 1;
}
