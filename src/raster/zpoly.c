/* The z-buffered polygon fill: a world-space polygon of any world's face is
 * clipped, projected and filled pixel by pixel (pixel centres inside it),
 * with 1/z from the face's plane tested against the z-buffer and a true
 * divide per pixel for the texture.  Slow and simple: the reference path
 * draws every face with it.  Item boxes (faces of other, tiny worlds) are
 * drawn with it over the z-filled world too, but with the world spans'
 * texturing, a divide every 16 pixels: near the eye a box covers a tenth
 * of the frame, and a divide per pixel there cost a fifth of the frame. */
#include "raster/span_step.h"
#include "ew_util.h"

#include <math.h>

void ew_zpoly_vertex(const ew_view *v, const float pt[3], float *u, float *vv, float *zi) {
    float t[3];
    ew_view_transform(v, pt, t);
    float z = 1.0f / (t[2] < 0.01f ? 0.01f : t[2]);
    *u = v->xcenter + v->xscale * t[0] * z;
    *vv = v->ycenter - v->yscale * t[1] * z;
    *zi = z;
}

/* ew_zpoly_rect of the polygon's own corners. */
static int zpoly_bounds(const ew_view *v, ew_zpoly *p, int m) {
    float umin = 1e30f, umax = -1e30f, vmin = 1e30f, vmax = -1e30f;
    for (int i = 0; i < m; i++) {
        if (p->u[i] < umin) umin = p->u[i];
        if (p->u[i] > umax) umax = p->u[i];
        if (p->v[i] < vmin) vmin = p->v[i];
        if (p->v[i] > vmax) vmax = p->v[i];
    }
    return ew_zpoly_rect(v, p, m, umin, umax, vmin, vmax);
}

int ew_zpoly_rect(const ew_view *v, ew_zpoly *p, int m, float umin, float umax, float vmin, float vmax) {
    p->n = m;
    p->x0 = ew_ceilf_int(umin), p->x1 = ew_ceilf_int(umax) - 1;
    p->y0 = ew_ceilf_int(vmin), p->y1 = ew_ceilf_int(vmax) - 1;
    if (p->x0 < 0) p->x0 = 0;
    if (p->y0 < 0) p->y0 = 0;
    if (p->x1 > v->width - 1) p->x1 = v->width - 1;
    if (p->y1 > v->height - 1) p->y1 = v->height - 1;
    return p->x0 <= p->x1 && p->y0 <= p->y1;
}

int ew_zpoly_orient(ew_zpoly *p) {
    /* Orientation of the projected polygon, so "inside" has one sign. */
    double area = 0;
    for (int i = 0, m = p->n; i < m; i++) {
        int j = i + 1 == m ? 0 : i + 1;
        area += (double)p->u[i] * p->v[j] - (double)p->u[j] * p->v[i];
    }
    if (area == 0) return 0;
    p->sign = area > 0 ? 1 : -1;
    return 1;
}

int ew_zpoly_close(const ew_view *v, ew_zpoly *p, int m) {
    zpoly_bounds(v, p, m);
    return ew_zpoly_orient(p);
}

int ew_zpoly_project(const ew_view *v, float (*in)[3], int n, ew_zpoly *p) {
    float out[EW_MAX_POLY][3];
    int tin[EW_MAX_POLY], tout[EW_MAX_POLY];
    if (n > EW_MAX_POLY - 8) return 0;
    for (int i = 0; i < n; i++) tin[i] = -1;
    int m = ew_clip_poly(v, 15, in, n, out, tin, tout);
    if (m < 3) return 0;
    p->nearzi = 0;
    for (int i = 0; i < m; i++) {
        float zi;
        ew_zpoly_vertex(v, out[i], &p->u[i], &p->v[i], &zi);
        if (zi > p->nearzi) p->nearzi = zi;
    }
    return ew_zpoly_close(v, p, m);
}

/* Pixels xa..xb of row y of a lit surface, z-tested, textured like a world
 * span; returns the pixels won. */
static long stepped_row(const ew_span_ctx *c, const ew_gradients *g, const ew_zpoly_look *look, int *ids,
                        int id, int xa, int xb, int y) {
    ew_stepper st;
    int32_t s, t, ds, dt;
    int n, x = xa;
    long won = 0;
    /* Locals, not fields: a byte stored to the frame could alias any of them. */
    const float zrow = g->zi_v * (float)y + g->zi_0, dz = g->zi_u;
    const ew_target *tg = c->target;
    float *zr = ew_target_z(tg, 0, y);
    uint8_t *dst = ew_target_at(tg, 0, y);
    const uint8_t *surf = look->surf;
    const uint32_t sw = (uint32_t)look->surf_width;
    const int fast = tg->bpp == 1 && !ids;  /* an item box in an 8-bit frame */
    int *idr = ids ? ids + (size_t)y * (size_t)tg->width : NULL;
    ew_step_begin(&st, g, c->subdiv_shift, xa, y, xb - xa + 1);
    while ((n = ew_step_next(&st, &s, &t, &ds, &dt)) > 0) {
        if (fast) {
            /* The z test of the segment first: where it wins whole (most
             * of a box's rows), its texels go as a world span's do. */
            uint32_t wins = 0;
            int k = 0;
#if EW_SIMD4
            /* Four at a time, the scalar test's exact values: (float)x,
             * one multiply, one add; !(zi <= z) as the scalar continue. */
            const ew_v4f vdz = ew_v4f_set1(dz), vrow = ew_v4f_set1(zrow);
            for (; k + 4 <= n; k += 4) {
                ew_v4i xi = ew_v4i_add(ew_v4i_set1(x + k), ew_v4i_setr(0, 1, 2, 3));
                ew_v4f zi = ew_v4f_add(ew_v4f_mul(vdz, ew_v4i_to_f(xi)), vrow);
                ew_v4f old = ew_v4f_loadu(zr + x + k);
                ew_v4f win = ew_v4f_not_le(zi, old);
                ew_v4f_storeu(zr + x + k, ew_v4f_select(win, zi, old));
                wins |= (uint32_t)ew_v4f_mask(win) << k;
            }
#endif
            for (; k < n; k++) {
                float zi = dz * (float)(x + k) + zrow;
                if (zi <= zr[x + k]) continue;
                zr[x + k] = zi;
                wins |= 1u << k;
            }
            if (wins == (n == 32 ? ~0u : (1u << n) - 1)) {
                ew_texel_run(dst + x, surf, sw, s, t, ds, dt, n, 0);
                won += n;
            } else {
                for (int k = 0; k < n; k++, s += ds, t += dt)
                    if (wins >> k & 1) dst[x + k] = surf[((uint32_t)t >> 16) * sw + ((uint32_t)s >> 16)], won++;
            }
            x += n;
            continue;
        }
        for (int k = 0; k < n; k++, x++, s += ds, t += dt) {
            float zi = dz * (float)x + zrow;
            if (zi <= zr[x]) continue;
            zr[x] = zi;
            won++;
            if (idr) idr[x] = id;
            ew_put_texel(tg, dst, x, surf, ((uint32_t)t >> 16) * sw + ((uint32_t)s >> 16));
        }
    }
    return won;
}

/* Pixels xa..xb of row y of a see-through polygon (fence or blend), its
 * texels fetched like the opaque paths' (stepped or exact); returns the
 * pixels written. */
static long see_row(const ew_span_ctx *c, const ew_gradients *g, const ew_zpoly_look *look, int *ids,
                    int id, int xa, int xb, int y) {
    const ew_target *tg = c->target;
    const ew_face *f = look->face;
    int turb = (f->flags & EW_SURF_TURB) != 0, fence = (f->flags & EW_SURF_FENCE) != 0;
    if (!turb && !look->surf) return 0;
    float zrow = g->zi_v * (float)y + g->zi_0;
    float *zr = ew_target_z(tg, 0, y);
    uint8_t *dst = ew_target_at(tg, 0, y);
    const ew_fog *fog = look->mode == EW_ZP_BLEND && c->fog.table ? &c->fog : NULL;
    const int bpp = tg->bpp;  /* read once: the stores could alias the target */
    long won = 0;
    ew_stepper st = {0};
    int32_t s = 0, t = 0, ds = 0, dt = 0;
    int left = 0;
    if (look->stepped) ew_step_begin(&st, g, c->subdiv_shift, xa, y, xb - xa + 1);
    for (int x = xa; x <= xb; x++, s += ds, t += dt, left--) {
        if (look->stepped) {
            if (left == 0) left = ew_step_next(&st, &s, &t, &ds, &dt);
        } else {
            float z = 65536.0f / (g->zi_u * (float)x + zrow), fx = (float)x, fy = (float)y;
            s = ew_tex_fix((g->s_u * fx + (g->s_v * fy + g->s_0)) * z, g->s_adjust, 0, g->s_max);
            t = ew_tex_fix((g->t_u * fx + (g->t_v * fy + g->t_0)) * z, g->t_adjust, 0, g->t_max);
        }
        float zi = g->zi_u * (float)x + zrow;
        if (zi <= zr[x]) continue;
        size_t ti = ((uint32_t)t >> 16) * (uint32_t)look->surf_width + ((uint32_t)s >> 16);
        if (bpp == 1) {
            uint8_t px = turb ? ew_turb_texel(c->turb, look->tex, s, t) : look->surf[ti];
            if (px == 255 && fence) continue;  /* a hole */
            if (look->mode == EW_ZP_FENCE) {
                zr[x] = zi;
                if (ids) ids[(size_t)y * tg->width + x] = id;
                dst[x] = px;
            } else {
                if (fog) px = fog->table[ew_fog_level(fog, zi) * 256 + px];
                dst[x] = look->blend[px * 256 + dst[x]];
            }
        } else {
            uint32_t px = turb ? tg->rgba[ew_turb_texel(c->turb, look->tex, s, t)] : ew_get32(look->surf, (int)ti);
            if (fence && ew_rgba_clear(px)) continue;  /* a hole */
            if (look->mode == EW_ZP_FENCE) {
                zr[x] = zi;
                if (ids) ids[(size_t)y * tg->width + x] = id;
                ew_set32(dst, x, px);
            } else {
                if (fog) px = ew_fog_rgba(fog, ew_fog_level(fog, zi), px);
                ew_set32(dst, x, ew_blend_rgba(px, ew_get32(dst, x), look->alpha256));
            }
        }
        won++;
    }
    return won;
}

long ew_zpoly_fill(const ew_span_ctx *c, const ew_zpoly *p, const ew_zpoly_look *look, int *ids, int id,
                   int y0, int y1) {
    const ew_face *f = look->face;
    const ew_target *tg = c->target;
    ew_gradients g;
    int have_g = 0;  /* set up at the first pixel: most faces of a small box have none */
    long won = 0;
    int m = p->n;
    int ya = p->y0 > y0 ? p->y0 : y0, yb = p->y1 < y1 - 1 ? p->y1 : y1 - 1;
    if (ya > yb) return 0;
    /* A pixel centre is inside when it is on the inner side of every edge,
     * with a hair of tolerance so centres exactly on a shared edge are
     * covered by both sides (the z test picks one).  Along a row each edge's
     * test is linear in x, so it bounds x from one side: the row's pixels are
     * the interval all of them leave.  Edge i's test,
     *   sign * (du * (y - v_i) - dv * (x - u_i)) >= -tol,  i.e.  a - b x >= -tol,
     * has du, dv, tol, b and the dv * u_i of a the same on every row. */
    double e_du[EW_MAX_POLY], e_dvu[EW_MAX_POLY], e_tol[EW_MAX_POLY], e_b[EW_MAX_POLY];
    float e_v[EW_MAX_POLY];
    for (int i = 0; i < m; i++) {
        int j = i + 1 == m ? 0 : i + 1;
        double du = (double)p->u[j] - p->u[i], dv = (double)p->v[j] - p->v[i];
        e_du[i] = du, e_dvu[i] = dv * p->u[i], e_v[i] = p->v[i];
        e_tol[i] = 1e-6 * (fabs(du) + fabs(dv));
        e_b[i] = p->sign * dv;
    }
    for (int y = ya; y <= yb; y++) {
        double xlo = p->x0, xhi = p->x1;
        for (int i = 0; i < m && xlo <= xhi; i++) {
            double a = p->sign * (e_du[i] * ((double)y - e_v[i]) + e_dvu[i]), b = e_b[i], tol = e_tol[i];
            if (b > 0) {
                double lim = (a + tol) / b;
                if (lim < xhi) xhi = lim;
            } else if (b < 0) {
                double lim = (a + tol) / b;
                if (lim > xlo) xlo = lim;
            } else if (a < -tol) {
                xhi = xlo - 1;  /* parallel to the row and outside */
            }
        }
        int xa = ew_ceil_int(xlo), xb = ew_floor_int(xhi);
        if (xa < p->x0) xa = p->x0;
        if (xb > p->x1) xb = p->x1;
        if (xb < xa) continue;
        if (!have_g) ew_face_gradients(look->world, look->view, f, look->mip, &g), have_g = 1;
        if (look->mode != EW_ZP_OPAQUE) {
            won += see_row(c, &g, look, ids, id, xa, xb, y);
            continue;
        }
        if (look->stepped && look->surf && !(f->flags & (EW_SURF_SKY | EW_SURF_TURB))) {
            won += stepped_row(c, &g, look, ids, id, xa, xb, y);
            continue;
        }
        for (int x = xa; x <= xb; x++) {
            size_t o = (size_t)y * (size_t)tg->width + (size_t)x;
            float zi = g.zi_u * (float)x + (g.zi_v * (float)y + g.zi_0);
            if (zi <= tg->zbuf[o]) continue;
            tg->zbuf[o] = zi;
            won++;
            if (ids) ids[o] = id;
            uint8_t *row = ew_target_at(tg, 0, y);
            if (f->flags & EW_SURF_SKY) {
                ew_put_index(tg, row, x, ew_sky_pixel(c->view, look->tex, (float)x, (float)y));
            } else {
                float z = 65536.0f / zi;
                float fx = (float)x, fy = (float)y;
                int32_t s = ew_tex_fix((g.s_u * fx + (g.s_v * fy + g.s_0)) * z, g.s_adjust, 0, g.s_max);
                int32_t t = ew_tex_fix((g.t_u * fx + (g.t_v * fy + g.t_0)) * z, g.t_adjust, 0, g.t_max);
                if (f->flags & EW_SURF_TURB)
                    ew_put_index(tg, row, x, ew_turb_texel(c->turb, look->tex, s, t));
                else if (look->surf)
                    ew_put_texel(tg, row, x, look->surf, (size_t)((t >> 16) * look->surf_width + (s >> 16)));
                else
                    ew_put_index(tg, row, x, 0);
            }
        }
    }
    return won;
}
