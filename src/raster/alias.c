/* Triangle (alias) models: per-frame vertex transform, projection and
 * integer snapping; frustum accept/reject/clip by the frame's bounds;
 * backface + degenerate culling in one cross product; Gouraud shading from
 * a fixed light direction; the triangles go to the rasterizers
 * (raster/alias_tri.h). */
#include "raster/alias.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define NEAR_Z 4.0f          /* view-space near plane for models */
#define STACK_VERTS 1024     /* vertices handled without malloc */
#define STACK_TILE 49152     /* bytes of subdivision tile without malloc */
#define MAX_TILE_PIXELS (1 << 20)
#define MAX_CLIPPED 12

/* ---- the model pipeline --------------------------------------------------- */

typedef ew_xvert xvert;

void ew_view_planes(const ew_view *v, float near_z, ew_view_planes_t *cp) {
    float w = (float)v->width, h = (float)v->height;
    float pl[5][4] = {
        {0, 0, 1, -near_z},
        {v->xscale, 0, v->xcenter + 0.5f, 0},
        {-v->xscale, 0, w - 0.5f - v->xcenter, 0},
        {0, -v->yscale, v->ycenter + 0.5f, 0},
        {0, v->yscale, h - 0.5f - v->ycenter, 0},
    };
    for (int k = 0; k < 5; k++) {
        for (int i = 0; i < 3; i++) cp->n[k][i] = pl[k][i];
        cp->d[k] = pl[k][3];
    }
}

typedef ew_view_planes_t clip_planes;

static inline float plane_dist(const clip_planes *cp, int k, const float p[3]) {
    return cp->n[k][0] * p[0] + cp->n[k][1] * p[1] + cp->n[k][2] * p[2] + cp->d[k];
}

static inline int clip_flags(const clip_planes *cp, const float p[3]) {
    int f = 0;
    for (int k = 0; k < 5; k++)
        if (plane_dist(cp, k, p) < 0) f |= 1 << k;
    return f;
}

static inline int32_t snap(float f, int32_t lo, int32_t hi) {
    /* Clamped first (lo >= 0), so truncating f + 0.5 rounds; no floorf call. */
    float x = f > (float)lo ? f : (float)lo;  /* also turns NaN into lo */
    x = x < (float)hi ? x : (float)hi;
    return (int32_t)(x + 0.5f);
}

static void project(const ew_view *v, const float p[3], ew_avert *out) {
    float zi = 1.0f / p[2];
    out->x = snap(v->xcenter + v->xscale * p[0] * zi, 0, v->width - 1);
    out->y = snap(v->ycenter - v->yscale * p[1] * zi, 0, v->height - 1);
    out->zi = zi;
}

/* project() with the view's numbers and the clamps' limits as floats read
 * once for a model's vertices (the loop reloaded and converted them). */
typedef struct proj_k {
    float xc, yc, xs, ys, xhi, yhi;
} proj_k;
static inline void project_k(const proj_k *k, const float p[3], ew_avert *out) {
    float zi = 1.0f / p[2];
    float x = k->xc + k->xs * p[0] * zi, y = k->yc - k->ys * p[1] * zi;
    /* snap(f, 0, hi): the same selects, lo being 0 */
    x = x > 0.0f ? x : 0.0f;
    x = x < k->xhi ? x : k->xhi;
    y = y > 0.0f ? y : 0.0f;
    y = y < k->yhi ? y : k->yhi;
    out->x = (int32_t)(x + 0.5f);
    out->y = (int32_t)(y + 0.5f);
    out->zi = zi;
}

static inline int32_t fix16(float f, int32_t max) {
    float x = f * 65536.0f;
    if (!(x >= 0)) return 0;
    if (x > (float)max) return max;
    return (int32_t)x;
}

/* fix16((float)s, max) for an integer s: (float)s * 65536 is exact while
 * that fits a float's 24 bits (and past them far above max), so the
 * float's two tests are the integer's against lim = fix16_lim(max), the
 * largest s whose product does not pass (float)max. */
static inline int32_t fix16_lim(int32_t max) { return (int32_t)((float)max / 65536.0f); }
static inline int32_t fix16_int(int64_t s, int32_t max, int32_t lim) {
    return s < 0 ? 0 : s > lim ? max : (int32_t)(s << 16);
}

/* The light comes from this fixed world direction (towards the light),
 * whatever the scene: from the front-above along +x, as the game's fixed
 * light vector did. */
static const float light_towards[3] = {0.8944272f, 0.0f, 0.4472136f};

/* Sutherland-Hodgman against the planes in mask; attributes linear along
 * edges.  Intersections are computed from the inside vertex, so an edge
 * shared by two triangles clips to the same point from either side. */
typedef struct cvert {
    float p[3], s, t, l;
} cvert;

static int clip_poly(const clip_planes *cp, int mask, cvert *in, int n, cvert *scratch) {
    cvert *src = in, *dst = scratch;
    for (int k = 0; k < 5 && n > 0; k++) {
        if (!(mask & (1 << k))) continue;
        int m = 0;
        for (int i = 0; i < n; i++) {
            const cvert *a = &src[i], *b = &src[(i + 1) % n];
            float da = plane_dist(cp, k, a->p), db = plane_dist(cp, k, b->p);
            if (da >= 0) dst[m++] = *a;
            if ((da >= 0) != (db >= 0) && m < MAX_CLIPPED) {
                const cvert *pin = da >= 0 ? a : b, *pout = da >= 0 ? b : a;
                float di = da >= 0 ? da : db, dout = da >= 0 ? db : da;
                float f = di / (di - dout);
                cvert *o = &dst[m++];
                for (int j = 0; j < 3; j++) o->p[j] = pin->p[j] + f * (pout->p[j] - pin->p[j]);
                o->s = pin->s + f * (pout->s - pin->s);
                o->t = pin->t + f * (pout->t - pin->t);
                o->l = pin->l + f * (pout->l - pin->l);
            }
            if (m >= MAX_CLIPPED) break;
        }
        n = m;
        cvert *t = src;
        src = dst, dst = t;
    }
    if (src != in)
        for (int i = 0; i < n; i++) in[i] = src[i];
    return n;
}

int ew_alias_place(const ew_frame *fr, const ew_mdl *m, const ew_model_pose *p, ew_alias_xf *xf) {
    xf->visible = xf->hidden = 0;
    xf->rgba = NULL, xf->remap = NULL;
    for (int k = 0; k < 3; k++)
        if (!isfinite(p->origin[k]) || !isfinite(p->angles[k]) || fabsf(p->origin[k]) > 1e6f) return 0;
    const ew_view *v = &fr->view;

    int frame = p->frame < 0 || p->frame >= m->numframes ? 0 : p->frame;
    int skin = p->skin < 0 || p->skin >= m->numskins ? 0 : p->skin;
    const ew_mdl_pose *pose = &m->poses[ew_mdl_anim_pick(&m->frames[frame], p->time)];
    int image = ew_mdl_anim_pick(&m->skins[skin], p->time);

    /* Model axes in the world (the game negated an alias model's pitch). */
    float ang[3] = {-p->angles[0], p->angles[1], p->angles[2]};
    float fwd[3], right[3], up[3];
    ew_angle_vectors(ang, fwd, right, up);
    float axis[3][3];  /* model x, y, z in world space */
    for (int i = 0; i < 3; i++) axis[0][i] = fwd[i], axis[1][i] = -right[i], axis[2][i] = up[i];
    const float *vrow[3] = {v->right, v->up, v->forward};
    /* model space -> view space: view = mm * model + mt */
    float mm[3][3], mt[3], d[3];
    for (int i = 0; i < 3; i++) d[i] = p->origin[i] - v->origin[i];
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            mm[i][j] = vrow[i][0] * axis[j][0] + vrow[i][1] * axis[j][1] + vrow[i][2] * axis[j][2];
        mt[i] = vrow[i][0] * d[0] + vrow[i][1] * d[1] + vrow[i][2] * d[2];
    }

    /* Trivial accept / reject by the frame's bounds. */
    clip_planes cp;
    ew_view_planes(v, NEAR_Z, &cp);
    xf->cp = cp;
    int and_flags = 0x1F, or_flags = 0, behind = 0;
    float vmin = 1e30f, vmax = -1e30f, umin = 1e30f, umax = -1e30f, znear = 1e30f;
    for (int c = 0; c < 8; c++) {
        float mp[3] = {c & 1 ? pose->maxs[0] : pose->mins[0], c & 2 ? pose->maxs[1] : pose->mins[1],
                       c & 4 ? pose->maxs[2] : pose->mins[2]};
        float vp[3];
        for (int i = 0; i < 3; i++) vp[i] = mm[i][0] * mp[0] + mm[i][1] * mp[1] + mm[i][2] * mp[2] + mt[i];
        int f = clip_flags(&cp, vp);
        and_flags &= f, or_flags |= f;
        if (vp[2] < znear) znear = vp[2];
        if (vp[2] > 0) {
            float sx = v->xcenter + v->xscale * vp[0] / vp[2];
            float sy = v->ycenter - v->yscale * vp[1] / vp[2];
            if (sx < umin) umin = sx;
            if (sx > umax) umax = sx;
            if (sy < vmin) vmin = sy;
            if (sy > vmax) vmax = sy;
        } else {
            behind = 1;
        }
    }
    if (and_flags) return 0;
    int accept = or_flags == 0;
    int subdiv = accept && (fr->cfg.alias_raster == EW_ALIAS_SUBDIV ||
                            (fr->cfg.alias_raster == EW_ALIAS_AUTO && vmax - vmin < fr->cfg.alias_threshold));

    /* Byte vertex -> view space. */
    for (int i = 0; i < 3; i++) {
        xf->bt[i] = mt[i];
        for (int j = 0; j < 3; j++) {
            xf->bm[i][j] = mm[i][j] * m->scale[j];
            xf->bt[i] += mm[i][j] * m->translate[j];
        }
    }
    /* The light direction in model space. */
    for (int j = 0; j < 3; j++)
        xf->lm[j] = light_towards[0] * axis[j][0] + light_towards[1] * axis[j][1] + light_towards[2] * axis[j][2];
    xf->visible = 1, xf->accept = accept, xf->behind = behind, xf->subdiv = subdiv;
    xf->umin = umin, xf->umax = umax, xf->vmin = vmin, xf->vmax = vmax;
    xf->zi_near = behind ? INFINITY : 1.0f / znear;
    xf->image = image, xf->pose = (int)(pose - m->poses);
    memcpy(xf->rot, mm, sizeof mm), memcpy(xf->org, mt, sizeof mt);
    xf->xv = NULL;
    return 1;
}

void ew_alias_pose_verts(const ew_frame *fr, const ew_mdl *m, const ew_model_pose *p, ew_alias_xf *xf,
                         ew_xvert *xv) {
    const ew_view *v = &fr->view;
    const ew_mdl_pose *pose = &m->poses[xf->pose];
    const clip_planes cp = xf->cp;
    int accept = xf->accept;
    /* Copied, and each vertex's bytes read once: the stores to xv could alias
     * them (uint8_t aliases anything), so the loop reloaded and converted
     * them for every coordinate.  The arithmetic is unchanged. */
    float bm[3][3], bt[3], lm[3];
    memcpy(bm, xf->bm, sizeof bm), memcpy(bt, xf->bt, sizeof bt), memcpy(lm, xf->lm, sizeof lm);
    int ambient = p->ambient, shade = p->shade;

    int32_t smax = (m->skinwidth << 16) - 1, tmax = (m->skinheight << 16) - 1;
    int minx = v->width, miny = v->height, maxx = -1, maxy = -1;
    /* Two passes, texel and light, then position: one loop holding both
     * spilled half its values to the stack. */
    int32_t slim = fix16_lim(smax), tlim = fix16_lim(tmax), half = m->skinwidth / 2;
    const proj_k pk = {v->xcenter, v->ycenter, v->xscale, v->yscale, (float)(v->width - 1), (float)(v->height - 1)};
    for (int i = 0; i < m->numverts; i++) {
        xvert *x = &xv[i];
        const float *n = pose->normals[i];
        float dot = n[0] * lm[0] + n[1] * lm[1] + n[2] * lm[2];
        int light = ambient + (dot > 0 ? (int)(shade * dot) : 0);
        int32_t row = ew_alias_light_row(light);
        const ew_mdl_st *st = &m->st[i];
        x->sv.s = fix16_int(st->s, smax, slim);
        x->sv.t = fix16_int(st->t, tmax, tlim);
        x->sv.l = row;
        x->sback = st->onseam ? fix16_int((int64_t)st->s + half, smax, slim) : x->sv.s;
        /* the clip path's (ew_alias_draw): no vertex of a model wholly in view takes it */
        if (!accept) x->s = (float)st->s, x->t = (float)st->t, x->l = (float)row;
    }
    for (int i = 0; i < m->numverts; i++) {
        xvert *x = &xv[i];
        const uint8_t *bv = pose->verts[i].v;
        const float b0 = bv[0], b1 = bv[1], b2 = bv[2];
        float q[3];
        for (int k = 0; k < 3; k++) q[k] = bm[k][0] * b0 + bm[k][1] * b1 + bm[k][2] * b2 + bt[k];
        x->clip = 0;
        if (!accept) {
            x->p[0] = q[0], x->p[1] = q[1], x->p[2] = q[2];
            x->clip = clip_flags(&cp, q);
        }
        if (!x->clip) {
            project_k(&pk, q, &x->sv);
            if (x->sv.x < minx) minx = x->sv.x;
            if (x->sv.x > maxx) maxx = x->sv.x;
            if (x->sv.y < miny) miny = x->sv.y;
            if (x->sv.y > maxy) maxy = x->sv.y;
        }
    }

    xf->minx = minx, xf->miny = miny, xf->maxx = maxx, xf->maxy = maxy;
    xf->smax = smax, xf->tmax = tmax;
    xf->xv = xv;
}

int ew_alias_transform(const ew_frame *fr, const ew_mdl *m, const ew_model_pose *p, ew_alias_xf *xf,
                       ew_xvert *xv) {
    if (!ew_alias_place(fr, m, p, xf)) return 0;
    ew_alias_pose_verts(fr, m, p, xf, xv);
    return 1;
}

int ew_alias_draw(const ew_frame *fr, ew_zfill *zf, const ew_mdl *m, const ew_alias_xf *xf, const ew_rows *rows) {
    if (!xf->visible) return 0;
    const ew_view *v = &fr->view;
    const clip_planes cp = xf->cp;
    const xvert *xv = xf->xv;
    int accept = xf->accept, behind = xf->behind, subdiv = xf->subdiv, image = xf->image;
    int masks = fr->cfg.alias_raster == EW_ALIAS_MASKS;
    float umin = xf->umin, umax = xf->umax, vmin = xf->vmin, vmax = xf->vmax;
    int minx = xf->minx, miny = xf->miny, maxx = xf->maxx, maxy = xf->maxy;
    int32_t smax = xf->smax, tmax = xf->tmax;
    /* Wholly in view but not in this band's rows: nothing to do here.  The
     * band holding the model's top row counts its triangles (any band
     * would count the same); a model crossing the frustum, band 0. */
    if (accept && (vmax < rows->y0 - 1 || vmin > rows->y1 + 1)) return 1;
    /* The world's 1/z under the model's screen box (a pixel of margin for
     * snapping), or under all these rows if the box reaches behind the eye. */
    if (accept && minx <= maxx) {
        /* Wholly in view, every pixel it draws is within its snapped
         * vertices' box, often a good deal smaller than its bounds'. */
        ew_zfill_rect(zf, minx, miny > rows->y0 ? miny : rows->y0, maxx + 1, maxy + 1 < rows->y1 ? maxy + 1 : rows->y1);
    } else if (behind || !(umin <= umax && vmin <= vmax)) {
        ew_zfill_rect(zf, 0, rows->y0, fr->target.width, rows->y1);
    } else {
        /* Clamped first: a corner just in front of the eye projects far out. */
        float w = (float)fr->target.width, h = (float)fr->target.height;
        int zx0 = (int)floorf(fminf(fmaxf(umin, -2), w)) - 1, zx1 = (int)ceilf(fminf(fmaxf(umax, -2), w)) + 2;
        int zy0 = (int)floorf(fminf(fmaxf(vmin, -2), h)) - 1, zy1 = (int)ceilf(fminf(fmaxf(vmax, -2), h)) + 2;
        ew_zfill_rect(zf, zx0, zy0 > rows->y0 ? zy0 : rows->y0, zx1, zy1 < rows->y1 ? zy1 : rows->y1);
    }
    int top = vmin < 0 ? 0 : vmin >= fr->target.height ? fr->target.height - 1 : (int)vmin;
    int counts = accept ? (top >= rows->y0 && top < rows->y1) : rows->first;

    ew_araster ra;
    memset(&ra, 0, sizeof ra);
    ra.target = &fr->target;
    ra.rgba = xf->rgba ? xf->rgba : fr->target.rgba;
    ra.remap = fr->target.bpp == 1 ? xf->remap : NULL;
    ra.x0 = 0, ra.y0 = rows->y0, ra.x1 = fr->target.width, ra.y1 = rows->y1;
    ra.skin = m->skinpixels + (size_t)image * m->skinwidth * m->skinheight;
    ra.skinw = m->skinwidth, ra.skinh = m->skinheight;
    ra.colormap = fr->colormap;
    /* Subdivision draws into a tile over the model's screen bounds. */
    _Alignas(float) uint8_t stack_tile[STACK_TILE];
    void *tile = NULL;
    if (subdiv && maxx >= minx) {
        int tw = maxx - minx + 1, th = maxy - miny + 1;
        size_t bytes = ew_alias_tile_bytes(tw, th);
        if (bytes <= sizeof stack_tile)
            tile = stack_tile;
        else if ((size_t)tw * th <= MAX_TILE_PIXELS)
            tile = malloc(bytes);
        if (tile) ew_alias_tile_begin(&ra, minx, miny, tw, th, tile);
    }

    int drawn = 0, drawn_subdiv = 0;
    for (int ti = 0; ti < m->numtris; ti++) {
        const ew_mdl_tri *tri = &m->tris[ti];
        const xvert *x0 = &xv[tri->v[0]], *x1 = &xv[tri->v[1]], *x2 = &xv[tri->v[2]];
        /* A model wholly in view has no vertex outside: no flag to read. */
        if (!accept && (x0->clip & x1->clip & x2->clip)) continue;
        int back = !tri->facesfront;
        if (accept || !(x0->clip | x1->clip | x2->clip)) {
            /* Rows first where nothing is counted: a model crossing several
             * of the draw's pieces sends each all its triangles. */
            if (!counts) {
                int32_t ytop, ybot;
                ew_alias_tri_rows(&x0->sv, &x1->sv, &x2->sv, &ytop, &ybot);
                if (ybot < rows->y0 || ytop >= rows->y1) continue;
            }
            /* Culled before the copies: about half of them are back faces. */
            if (!ew_alias_tri_visible(&x0->sv, &x1->sv, &x2->sv)) continue;  /* back face or degenerate */
            ew_avert a = x0->sv, b = x1->sv, c = x2->sv;
            if (back) a.s = x0->sback, b.s = x1->sback, c.s = x2->sback;
            drawn++;
            if (subdiv) {
                ew_alias_subdiv_tri(&ra, &a, &b, &c);
                drawn_subdiv++;
            } else if (masks) {
                ew_alias_masks_tri(&ra, &a, &b, &c);
            } else {
                ew_alias_affine_tri(&ra, &a, &b, &c);
            }
            continue;
        }
        /* The clip path: facing from the view-space triangle (the same sign
         * as the screen cross for vertices in front of the eye). */
        const float *p0 = x0->p, *p1 = x1->p, *p2 = x2->p;
        float det = p0[0] * (p1[1] * p2[2] - p1[2] * p2[1]) - p0[1] * (p1[0] * p2[2] - p1[2] * p2[0]) +
                    p0[2] * (p1[0] * p2[1] - p1[1] * p2[0]);
        if (!(det < 0)) continue;
        cvert poly[MAX_CLIPPED], scratch[MAX_CLIPPED];
        const xvert *src[3] = {x0, x1, x2};
        for (int k = 0; k < 3; k++) {
            for (int j = 0; j < 3; j++) poly[k].p[j] = src[k]->p[j];
            poly[k].s = back ? (float)src[k]->sback / 65536.0f : src[k]->s;
            poly[k].t = src[k]->t;
            poly[k].l = src[k]->l;
        }
        int n = clip_poly(&cp, x0->clip | x1->clip | x2->clip, poly, 3, scratch);
        if (n < 3) continue;
        ew_avert sv[MAX_CLIPPED];
        for (int k = 0; k < n; k++) {
            project(v, poly[k].p, &sv[k]);
            sv[k].s = fix16(poly[k].s, smax);
            sv[k].t = fix16(poly[k].t, tmax);
            sv[k].l = (int32_t)poly[k].l;
        }
        drawn++;
        for (int k = 1; k + 1 < n; k++) ew_alias_affine_tri(&ra, &sv[0], &sv[k], &sv[k + 1]);
    }
    ew_alias_tile_end(&ra);
    if (tile && tile != stack_tile) free(tile);
    if (counts) {
        rows->stats->alias_tris += drawn;
        rows->stats->alias_tris_subdiv += drawn_subdiv;
    }
    rows->stats->alias_pixels += ra.pixels;
    return 1;
}

int ew_draw_alias_rows(const ew_frame *fr, ew_zfill *zf, const ew_mdl *m, const ew_model_pose *p,
                       const ew_rows *rows) {
    if (!fr || !m || !p) return 0;
    xvert stack_verts[STACK_VERTS];
    xvert *xv = m->numverts <= STACK_VERTS ? stack_verts : malloc(sizeof(xvert) * (size_t)m->numverts);
    if (!xv) return 0;
    ew_alias_xf xf;
    int drawn = ew_alias_transform(fr, m, p, &xf, xv) ? ew_alias_draw(fr, zf, m, &xf, rows) : 0;
    if (xv != stack_verts) free(xv);
    return drawn;
}
