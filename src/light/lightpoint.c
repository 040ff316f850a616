/* The light level under a point, for lighting models: trace straight down
 * through the world's BSP to the first face the segment crosses and read
 * that face's light map at the crossing, the way the game lit its models
 * from the floor they stood on. */
#include "light/light.h"

#include <math.h>

/* The light of face f at texture point (fs, ft), styles applied: mono
 * returned, rgb filled (the mono level three times without coloured
 * light).  Quake's 16-texel grid, or the face's own layout (facelm). */
static int face_light(const ew_frame *fr, const ew_face *f, int fi, float fs, float ft, int rgb[3]) {
    const ew_world *w = fr->world;
    long at, step;
    if (w->facelm) {
        const ew_facelm *lm = &w->facelm[fi];
        if (lm->lightofs < 0) return rgb[0] = rgb[1] = rgb[2] = 0;
        float u = lm->st_to_lm[0][0] * fs + lm->st_to_lm[0][1] * ft + lm->st_to_lm[0][2];
        float v = lm->st_to_lm[1][0] * fs + lm->st_to_lm[1][1] * ft + lm->st_to_lm[1][2];
        /* the face's edge may sit a little outside its samples: clamp */
        int iu = u > 0 ? (u < (float)(lm->width - 1) ? (int)u : lm->width - 1) : 0;
        int iv = v > 0 ? (v < (float)(lm->height - 1) ? (int)v : lm->height - 1) : 0;
        at = (long)lm->lightofs + (long)iv * lm->width + iu;
        step = (long)lm->width * lm->height;
    } else {
        if (f->lightofs < 0) return rgb[0] = rgb[1] = rgb[2] = 0;
        int ds = (int)fs - f->texturemins[0], dt = (int)ft - f->texturemins[1];
        int smax = (f->extents[0] >> 4) + 1, tmax = (f->extents[1] >> 4) + 1;
        at = (long)f->lightofs + (long)(dt >> 4) * smax + (ds >> 4);
        step = (long)smax * tmax;
    }
    long sum = 0, c[3] = {0, 0, 0};
    for (int k = 0; k < 4 && f->styles[k] != 255; k++, at += step) {
        if (at < 0 || at >= w->lightsize) break;
        int style = f->styles[k];
        int scale = style < 64 ? fr->cfg.lightstyle[style] : 256;
        sum += (long)w->lighting[at] * scale;
        if (w->rgblight)
            for (int j = 0; j < 3; j++) c[j] += (long)w->rgblight[3 * at + j] * scale;
    }
    sum >>= 8;
    int mono = sum > 255 ? 255 : (int)sum;
    for (int j = 0; j < 3; j++) {
        long v = w->rgblight ? c[j] >> 8 : mono;
        rgb[j] = v > 255 ? 255 : (int)v;
    }
    return mono;
}

/* -1: nothing hit on this part of the segment. */
static int trace(const ew_frame *fr, int node, const float start[3], const float end[3], int depth,
                 int rgb[3]) {
    const ew_world *w = fr->world;
    float a[3] = {start[0], start[1], start[2]};
    while (node >= 0) {
        if (depth++ > w->numnodes + 1) return -1;  /* the loader rejected cycles; a guard */
        const ew_node *nd = &w->nodes[node];
        const ew_plane *pl = &w->planes[nd->plane];
        float front = a[0] * pl->normal[0] + a[1] * pl->normal[1] + a[2] * pl->normal[2] - pl->dist;
        float back = end[0] * pl->normal[0] + end[1] * pl->normal[1] + end[2] * pl->normal[2] - pl->dist;
        int side = front < 0;
        if ((back < 0) == side) {
            node = nd->children[side];
            continue;
        }
        float frac = front / (front - back);
        float mid[3];
        for (int i = 0; i < 3; i++) mid[i] = a[i] + frac * (end[i] - a[i]);
        int lit = trace(fr, nd->children[side], a, mid, depth, rgb);
        if (lit >= 0) return lit;

        /* The crossing point on this node's plane: a face of the node there? */
        for (int fi = 0; fi < nd->numfaces; fi++) {
            const ew_face *f = &w->faces[nd->firstface + fi];
            if (f->flags & (EW_SURF_SKY | EW_SURF_TURB)) continue;
            const ew_texinfo *ti = &w->texinfo[f->texinfo];
            float fs = mid[0] * ti->vecs[0][0] + mid[1] * ti->vecs[0][1] + mid[2] * ti->vecs[0][2] + ti->vecs[0][3];
            float ft = mid[0] * ti->vecs[1][0] + mid[1] * ti->vecs[1][1] + mid[2] * ti->vecs[1][2] + ti->vecs[1][3];
            if (!(fs > -1e8f && fs < 1e8f && ft > -1e8f && ft < 1e8f)) continue;
            int ds = (int)fs - f->texturemins[0], dt = (int)ft - f->texturemins[1];
            if (ds < 0 || dt < 0 || ds > f->extents[0] || dt > f->extents[1]) continue;
            if (!w->lighting) return rgb[0] = rgb[1] = rgb[2] = 255;
            return face_light(fr, f, nd->firstface + fi, fs, ft, rgb);
        }
        /* Go on down the far side. */
        for (int i = 0; i < 3; i++) a[i] = mid[i];
        node = nd->children[!side];
    }
    return -1;
}

int ew_light_point_rgb(const ew_frame *fr, const float p[3], int rgb[3]) {
    int scratch[3];
    if (!rgb) rgb = scratch;
    rgb[0] = rgb[1] = rgb[2] = 0;
    if (!fr || !fr->world || !p || fr->world->nummodels < 1) return 0;
    if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) return 0;
    float end[3] = {p[0], p[1], p[2] - 2048.0f};
    int lit = trace(fr, fr->world->models[0].headnode, p, end, 0, rgb);
    if (lit < 0) rgb[0] = rgb[1] = rgb[2] = 0;
    return lit < 0 ? 0 : lit;
}

int ew_light_point(const ew_frame *fr, const float p[3]) { return ew_light_point_rgb(fr, p, NULL); }
