/* The reference path: hidden surfaces removed by brute force, independent
 * of the edge list.  The same front end picks the visible faces; each is
 * clipped, projected and filled pixel by pixel (pixel centres inside the
 * polygon), with 1/z from its plane equation tested against a z-buffer.
 * Texels come from the same lit surfaces, sampled with a true divide per
 * pixel.  Slow and simple on purpose: it is what the tests trust. */
#include "../raster/span_step.h"
#include "ew_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct ref_ctx {
    uint8_t *pixels;
    int     *ids;
    float   *z;
} ref_ctx;

/* Fills one world-space polygon of face fi; v is the camera in the face's
 * own space (for texture gradients).  Returns 1 if it won any pixel. */
static int ref_poly(ew_renderer *r, ref_ctx *c, int fi, const ew_view *v, float (*in)[3], int n) {
    const ew_world *w = r->world;
    const ew_face *f = &w->faces[fi];
    float out[EW_MAX_POLY][3];
    int tin[EW_MAX_POLY], tout[EW_MAX_POLY];
    for (int i = 0; i < n; i++) tin[i] = -1;
    /* Clip against all four planes, whatever the walk knew. */
    int m = ew_clip_poly(&r->view, 15, in, n, out, tin, tout);
    if (m < 3) return 0;
    float pu[EW_MAX_POLY], pv[EW_MAX_POLY], nearzi = 0;
    float umin = 1e30f, umax = -1e30f, vmin = 1e30f, vmax = -1e30f;
    for (int i = 0; i < m; i++) {
        float t[3];
        ew_view_transform(&r->view, out[i], t);
        float zi = 1.0f / (t[2] < 0.01f ? 0.01f : t[2]);
        pu[i] = r->view.xcenter + r->view.xscale * t[0] * zi;
        pv[i] = r->view.ycenter - r->view.yscale * t[1] * zi;
        if (zi > nearzi) nearzi = zi;
        if (pu[i] < umin) umin = pu[i];
        if (pu[i] > umax) umax = pu[i];
        if (pv[i] < vmin) vmin = pv[i];
        if (pv[i] > vmax) vmax = pv[i];
    }
    /* Orientation of the projected polygon, so "inside" has one sign. */
    double area = 0;
    for (int i = 0; i < m; i++) {
        int j = i + 1 == m ? 0 : i + 1;
        area += (double)pu[i] * pv[j] - (double)pu[j] * pv[i];
    }
    if (area == 0) return 0;
    double sign = area > 0 ? 1 : -1;

    int x0 = (int)ceilf(umin), x1 = (int)ceilf(umax) - 1;
    int y0 = (int)ceilf(vmin), y1 = (int)ceilf(vmax) - 1;
    if (x0 < 0) x0 = 0;
    if (y0 < 0) y0 = 0;
    if (x1 > r->width - 1) x1 = r->width - 1;
    if (y1 > r->height - 1) y1 = r->height - 1;

    int mip = 0;
    const ew_texture *tex = ew_face_texture(w, f, v->time);
    int won = 0;
    const ew_cached_surf *cs = NULL;
    ew_gradients g;
    if (f->flags & (EW_SURF_SKY | EW_SURF_TURB)) {
        ew_face_gradients(r, v, f, 0, &g);
    } else {
        mip = ew_face_mip(r, f, nearzi);
        int build;
        ew_cached_surf *e = ew_cache_lookup(r, fi, mip, &build);
        if (e && build) ew_cache_build(r, e, r->blocklights);
        cs = e;
        ew_face_gradients(r, v, f, mip, &g);
    }
    for (int y = y0; y <= y1; y++) {
        for (int x = x0; x <= x1; x++) {
            int inside = 1;
            for (int i = 0; i < m && inside; i++) {
                int j = i + 1 == m ? 0 : i + 1;
                double e = ((double)pu[j] - pu[i]) * ((double)y - pv[i]) -
                           ((double)pv[j] - pv[i]) * ((double)x - pu[i]);
                /* A hair of tolerance so pixel centres exactly on a shared
                 * edge are covered by both sides (the z test picks one). */
                if (e * sign < -1e-6 * (fabs(pu[j] - pu[i]) + fabs(pv[j] - pv[i]))) inside = 0;
            }
            if (!inside) continue;
            size_t o = (size_t)y * r->width + x;
            float zi = g.zi_u * (float)x + (g.zi_v * (float)y + g.zi_0);
            if (zi <= c->z[o]) continue;
            c->z[o] = zi;
            won = 1;
            if (c->ids) c->ids[o] = fi;
            uint8_t px;
            if (f->flags & EW_SURF_SKY) {
                px = ew_sky_pixel(&r->view, tex, (float)x, (float)y);
            } else {
                float z = 65536.0f / zi;
                float fx = (float)x, fy = (float)y;
                int32_t s = ew_tex_fix((g.s_u * fx + (g.s_v * fy + g.s_0)) * z, g.s_adjust, 0, g.s_max);
                int32_t t = ew_tex_fix((g.t_u * fx + (g.t_v * fy + g.t_0)) * z, g.t_adjust, 0, g.t_max);
                if (f->flags & EW_SURF_TURB)
                    px = ew_turb_texel(r->turb, tex, s, t);
                else
                    px = cs ? cs->pixels[(t >> 16) * cs->width + (s >> 16)] : 0;
            }
            c->pixels[o] = px;
        }
    }
    return won;
}

static void ref_face(ew_renderer *r, int fi, int clipflags, void *vctx) {
    (void)clipflags;  /* clipped against every plane regardless */
    const ew_world *w = r->world;
    const ew_face *f = &w->faces[fi];
    if (f->numedges > EW_MAX_POLY - 8) return;
    float in[EW_MAX_POLY][3];
    for (int i = 0; i < f->numedges; i++) {
        const float *p = w->verts[ew_face_vertex(w, f, i)];
        in[i][0] = p[0], in[i][1] = p[1], in[i][2] = p[2];
    }
    ref_poly(r, vctx, fi, &r->view, in, f->numedges);
}

static int ref_brush_face(ew_renderer *r, void *ctx, int fi, const ew_view *mv,
                          const float normal[3], float (*p)[3], int n) {
    (void)normal;
    return ref_poly(r, ctx, fi, mv, p, n);
}

/* Renders into the renderer's own frame and z-buffer (so the moving
 * things drawn after it meet the same z-buffer test), then copies out. */
int ew_render_reference(ew_renderer *r, const ew_camera *cam, uint8_t *pixels, int *face_ids,
                        ew_error *err) {
    size_t px = (size_t)r->width * r->height;
    ref_ctx c = {r->frame, face_ids, r->zbuf};
    if (ew_frame_begin(r, cam) < 0) return ew_fail(err, "reference: bad camera");
    for (size_t i = 0; i < px; i++) {
        c.z[i] = 0;
        c.pixels[i] = 0;
        if (face_ids) face_ids[i] = -1;
    }
    r->face_hook = ref_face;
    r->face_hook_ctx = &c;
    ew_walk_world(r);
    r->face_hook = NULL;
    r->face_hook_ctx = NULL;
    ew_for_brush_faces(r, ref_brush_face, &c);
    if (pixels) memcpy(pixels, r->frame, px);
    return 0;
}
