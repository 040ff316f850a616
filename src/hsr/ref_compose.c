/* The reference method's own compositing of what lies over its opaque
 * pixels: fences, translucent surfaces and fog, done the slow way so the
 * tests can check the shared passes (raster/seethrough.c, fog.c, blend.c)
 * against it.  None of those is called here.
 *
 * Per pixel: every see-through polygon (world/divert.c's list) is tested
 * for the pixel by brute force (its bounding box, then an inside test on
 * its projected corners), its 1/z taken from its face's plane; those in
 * front of the opaque pixel (world and models, with their z) that are not a
 * fence's hole are its fragments.  They are sorted by depth and composited
 * far to near over the opaque colour, in RGB: the opaque colour fogged at
 * its own depth (the sky half way, whatever its depth), each fragment
 * fogged at its own depth and laid over with its opacity (a fence's: 1).
 * An 8-bit frame takes the nearest palette colour of the result, found by
 * searching the palette (fullbrights and the key colour never chosen). */
#include "hsr/ref_compose.h"
#include "light/light.h"      /* ew_face_mip, ew_face_texture */
#include "light/twopass.h"
#include "raster/span_step.h"  /* ew_tex_fix; raster/raster.h: ew_see */

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct rc_poly {
    const ew_zpoly *p;        /* clipped and projected (world/divert.c) */
    ew_gradients    g;        /* 1/z, s/z, t/z of its face at its mip */
    const ew_face  *f;
    const ew_texture *tex;    /* liquids */
    const uint8_t  *surf;     /* lit faces: the cached lit surface */
    int             surf_width, face, fence;
    float           alpha;    /* 1 for a fence */
    double          sign;     /* orientation of the projected corners */
    int             two_pass; /* lit faces in two-pass lighting: tp, no surface */
    ew_tp_face      tp;
} rc_poly;

struct ew_ref_compose {
    int     *faces;           /* per pixel: the world face the reference drew, or -1 */
    size_t   cap_faces;
    rc_poly *polys;  int npolys, cap_polys;
    int      fog_on;
    double   fog_w;           /* (density / 64)^2 */
    double   fog_rgb[3];      /* 0..255 */
};

void ew_ref_compose_free(ew_ref_compose *c) {
    if (!c) return;
    free(c->faces), free(c->polys), free(c);
}

int *ew_ref_compose_begin(ew_hsr_ctx *hc) {
    if (!hc->ref) return NULL;
    ew_ref_compose *c = hc->ref->compose;
    if (!c && !(c = hc->ref->compose = calloc(1, sizeof *c))) return NULL;
    size_t n = (size_t)hc->f->target.width * (size_t)hc->f->target.height;
    if (n > c->cap_faces) {
        free(c->faces);
        c->cap_faces = 0;
        if (!(c->faces = malloc(sizeof *c->faces * n))) return NULL;  /* no sky found: fogged by depth */
        c->cap_faces = n;
    }
    return c->faces;
}

static ew_ref_compose *compose_of(const ew_hsr_ctx *hc) { return hc->ref ? hc->ref->compose : NULL; }

int *ew_ref_compose_faces(const ew_hsr_ctx *hc) { return compose_of(hc) ? compose_of(hc)->faces : NULL; }

void ew_ref_compose_ids_out(const ew_hsr_ctx *hc, int *ids, int y0, int y1) {
    const ew_ref_compose *c = compose_of(hc);
    size_t w = (size_t)hc->f->target.width;
    if (ids && c && c->faces && c->faces != ids)
        memcpy(ids + (size_t)y0 * w, c->faces + (size_t)y0 * w, sizeof *ids * w * (size_t)(y1 - y0));
}

/* The fog amount at 1/z zi, 1 - exp(-(density z / 64)^2). */
static double fog_amount(const ew_ref_compose *c, double zi) { return 1.0 - exp(-c->fog_w / (zi * zi)); }

int ew_ref_compose_prepare(ew_hsr_ctx *hc) {
    ew_ref_compose *c = compose_of(hc);
    if (!c) return 0;
    ew_frame *fr = hc->f;
    const ew_see *see = hc->see;
    const ew_world *w = fr->world;
    c->npolys = 0;
    c->fog_on = 0;
    double d = fr->cfg.fog_density >= 0 ? fr->cfg.fog_density : fr->world->worldspawn.fog_density;
    const float *rgb = fr->cfg.fog_density >= 0 ? fr->cfg.fog_rgb : fr->world->worldspawn.fog_rgb;
    if (!fr->cfg.classic && d > 0) {
        c->fog_on = 1;
        c->fog_w = (d / 64) * (d / 64);
        for (int k = 0; k < 3; k++) c->fog_rgb[k] = rgb[k] * 255.0;
    }
    fr->stats.seethrough_surfaces = 0;
    if (see->n > c->cap_polys) {
        rc_poly *p = realloc(c->polys, sizeof *p * (size_t)see->n);
        if (!p) {
            fr->stats.dropped += see->n;
            return 0;
        }
        c->polys = p, c->cap_polys = see->n;
    }
    for (int i = 0; i < see->n; i++) {
        const ew_see_poly *sp = &see->polys[i];
        const ew_face *f = &w->faces[sp->face];
        rc_poly *q = &c->polys[c->npolys];
        *q = (rc_poly){.p = &sp->p, .f = f, .face = sp->face, .fence = (f->flags & EW_SURF_FENCE) != 0,
                       .alpha = sp->kind == EW_SEE_FENCE ? 1.0f : sp->alpha};
        q->tex = ew_face_texture(w, f, fr->view.time);
        int mip = 0;
        if (!(f->flags & EW_SURF_TURB) && fr->cfg.lighting == EW_LIGHTING_TWO_PASS && !hc->debug) {
            mip = ew_face_mip(&fr->view, w, f, sp->p.nearzi);
            q->two_pass = 1;
            ew_tp_face_setup(hc->tp, sp->look.view, sp->face, mip, q->tex, &q->tp);
        } else if (!(f->flags & EW_SURF_TURB)) {
            mip = ew_face_mip(&fr->view, w, f, sp->p.nearzi);
            int width;
            const uint8_t *surf = hc->lit_surface(hc->owner, sp->face, mip, &width);
            if (!surf) {
                fr->stats.dropped++;
                continue;
            }
            q->surf = surf, q->surf_width = width;
        }
        ew_face_gradients(w, sp->look.view, f, mip, &q->g);
        double area = 0;
        for (int k = 0, n = sp->p.n; k < n; k++) {
            int j = k + 1 == n ? 0 : k + 1;
            area += (double)sp->p.u[k] * sp->p.v[j] - (double)sp->p.u[j] * sp->p.v[k];
        }
        if (area == 0) continue;
        q->sign = area > 0 ? 1 : -1;
        c->npolys++;
    }
    fr->stats.seethrough_surfaces = c->npolys;
    return 0;
}

/* Whether pixel (x, y) is inside the projected polygon: on the inner side
 * of every edge, with a hair of tolerance so a pixel on an edge two
 * polygons share is in both. */
static int inside(const rc_poly *q, double x, double y) {
    const ew_zpoly *p = q->p;
    for (int i = 0, n = p->n; i < n; i++) {
        int j = i + 1 == n ? 0 : i + 1;
        double du = (double)p->u[j] - p->u[i], dv = (double)p->v[j] - p->v[i];
        double cross = q->sign * (du * (y - p->v[i]) - dv * (x - p->u[i]));
        if (cross < -1e-6 * (fabs(du) + fabs(dv))) return 0;
    }
    return 1;
}

/* A fragment's colour (0xRRGGBB) at pixel (x, y) of 1/z zi, or -1 for a
 * fence's hole.  The one place a see-through face's texel is read: lit
 * faces from their cached lit surface (or, in two-pass lighting, from the
 * light oracle per pixel), liquids from their warped texture. */
static int32_t frag_texel(const ew_hsr_ctx *hc, const rc_poly *q, int x, int y, float zi) {
    const ew_frame *fr = hc->f;
    if (q->two_pass) {
        int X, Y, light[3];
        uint8_t c = ew_tp_texel(&q->tp, x, y, &X, &Y);
        if (q->fence && c == 255) return -1;
        ew_tp_light(hc->tp, &q->tp, X, Y, light);
        uint32_t v = ew_tp_shade(hc->tp, &q->tp, c, light);
        int rgb[3];
        if (fr->target.bpp == 4)
            ew_rgba_split(v, rgb);
        else
            for (int k = 0; k < 3; k++) rgb[k] = fr->palette[v * 3 + k];
        return rgb[0] << 16 | rgb[1] << 8 | rgb[2];
    }
    const ew_gradients *g = &q->g;
    float z = 65536.0f / zi, fx = (float)x, fy = (float)y;
    int32_t s = ew_tex_fix((g->s_u * fx + (g->s_v * fy + g->s_0)) * z, g->s_adjust, 0, g->s_max);
    int32_t t = ew_tex_fix((g->t_u * fx + (g->t_v * fy + g->t_0)) * z, g->t_adjust, 0, g->t_max);
    const uint8_t *pal = fr->palette;
    int idx;
    if (q->f->flags & EW_SURF_TURB) {
        idx = ew_turb_texel(hc->draw->turb, q->tex, s, t);
    } else if (fr->target.bpp == 4) {
        uint8_t px[4];
        memcpy(px, q->surf + (((size_t)((uint32_t)t >> 16) * (size_t)q->surf_width + ((uint32_t)s >> 16)) * 4), 4);
        if (q->fence && px[3] == 0) return -1;
        return px[0] << 16 | px[1] << 8 | px[2];
    } else {
        idx = q->surf[(size_t)((uint32_t)t >> 16) * (size_t)q->surf_width + ((uint32_t)s >> 16)];
    }
    if (q->fence && idx == 255) return -1;
    if (fr->target.bpp == 4) {  /* liquids in true colour: the palette as the frame shows it */
        int c[3];
        ew_rgba_split(fr->target.rgba[idx], c);
        return c[0] << 16 | c[1] << 8 | c[2];
    }
    return pal[idx * 3] << 16 | pal[idx * 3 + 1] << 8 | pal[idx * 3 + 2];
}

/* The nearest palette colour, by search; fullbrights (224..254) and the
 * key colour 255 are never chosen.  A small cache keyed by the colour. */
typedef struct nearest_cache {
    uint32_t key[4096];
    uint8_t  idx[4096];
} nearest_cache;
static uint8_t nearest(const uint8_t *pal, nearest_cache *nc, int r, int g, int b) {
    uint32_t key = (uint32_t)(r << 16 | g << 8 | b), h = (key * 2654435761u) >> 20;
    if (nc->key[h] == key) return nc->idx[h];
    int best = 0, bestd = 1 << 30;
    for (int i = 0; i < 224; i++) {
        int dr = pal[i * 3] - r, dg = pal[i * 3 + 1] - g, db = pal[i * 3 + 2] - b;
        int d = dr * dr + dg * dg + db * db;
        if (d < bestd) bestd = d, best = i;
    }
    nc->key[h] = key, nc->idx[h] = (uint8_t)best;
    return (uint8_t)best;
}

typedef struct frag {
    float zi;
    int32_t rgb;
    float alpha;
    int face;
} frag;
enum { MAX_FRAGS = 64 };

void ew_ref_compose_draw(const ew_hsr_ctx *hc, const ew_rows *rows) {
    const ew_ref_compose *c = compose_of(hc);
    if (!c || (!c->fog_on && c->npolys == 0)) return;
    const ew_frame *fm = hc->f;
    const ew_target *t = &fm->target;
    const ew_world *w = fm->world;
    int *ids = hc->ref_ids ? hc->ref_ids : fm->cfg.face_ids_on ? fm->face_ids : NULL;
    nearest_cache *nc = NULL;
    if (t->bpp == 1) {
        if (!(nc = malloc(sizeof *nc))) {
            rows->stats->dropped++;
            return;
        }
        memset(nc->key, 0xff, sizeof nc->key);  /* no colour has all 32 bits set */
    }
    int *row_polys = malloc(sizeof *row_polys * (size_t)(c->npolys + 1));
    if (!row_polys) {
        free(nc);
        rows->stats->dropped++;
        return;
    }
    long fogged = 0, fence_px = 0, blend_px = 0;
    frag fr[MAX_FRAGS];
    for (int y = rows->y0; y < rows->y1; y++) {
        int nrow = 0;
        for (int i = 0; i < c->npolys; i++)
            if (c->polys[i].p->y0 <= y && y <= c->polys[i].p->y1) row_polys[nrow++] = i;
        if (nrow == 0 && !c->fog_on) continue;
        float *zr = ew_target_z(t, 0, y);
        uint8_t *row = ew_target_at(t, 0, y);
        for (int x = 0; x < t->width; x++) {
            size_t o = (size_t)y * (size_t)t->width + (size_t)x;
            int n = 0;
            for (int k = 0; k < nrow; k++) {
                const rc_poly *q = &c->polys[row_polys[k]];
                if (x < q->p->x0 || x > q->p->x1 || !inside(q, x, y)) continue;
                float zi = q->g.zi_u * (float)x + q->g.zi_v * (float)y + q->g.zi_0;
                if (!(zi > zr[x])) continue;  /* behind the opaque pixel */
                int32_t rgb = frag_texel(hc, q, x, y, zi);
                if (rgb < 0) continue;  /* a fence's hole */
                if (n == MAX_FRAGS) {
                    rows->stats->dropped++;
                    break;
                }
                fr[n++] = (frag){zi, rgb, q->alpha, q->face};
            }
            if (n == 0 && !(c->fog_on && zr[x] > 0)) continue;
            /* far to near: by 1/z, smaller first */
            for (int i = 1; i < n; i++)
                for (int j = i; j > 0 && fr[j - 1].zi > fr[j].zi; j--) {
                    frag tmp = fr[j];
                    fr[j] = fr[j - 1], fr[j - 1] = tmp;
                }
            double col[3];
            int was = -1;
            if (t->bpp == 1) {
                was = row[x];
                for (int k = 0; k < 3; k++) col[k] = fm->palette[was * 3 + k];
            } else {
                int v[3];
                ew_rgba_split(ew_get32(row, x), v);
                for (int k = 0; k < 3; k++) col[k] = v[k];
            }
            if (c->fog_on && zr[x] > 0) {
                /* The sky: the reference drew a sky face here and nothing
                 * nearer (a model) was drawn over it since. */
                int face = c->faces ? c->faces[o] : -1;
                double amount = -1;
                if (face >= 0 && (w->faces[face].flags & EW_SURF_SKY)) {
                    float plane[3];
                    ew_face_zplane(w, &fm->view, &w->faces[face], plane);
                    double sky = (double)plane[0] * x + (double)plane[1] * y + plane[2];
                    if (zr[x] <= sky * (1 + 1e-4)) amount = 0.5;
                }
                if (amount < 0) amount = fog_amount(c, zr[x]);
                for (int k = 0; k < 3; k++) col[k] += (c->fog_rgb[k] - col[k]) * amount;
                fogged++;
            }
            for (int i = 0; i < n; i++) {
                double fc[3] = {fr[i].rgb >> 16 & 255, fr[i].rgb >> 8 & 255, fr[i].rgb & 255};
                if (c->fog_on) {
                    double amount = fog_amount(c, fr[i].zi);
                    for (int k = 0; k < 3; k++) fc[k] += (c->fog_rgb[k] - fc[k]) * amount;
                }
                for (int k = 0; k < 3; k++) col[k] += (fc[k] - col[k]) * fr[i].alpha;
                if (fr[i].alpha >= 1) {  /* a fence's texel: opaque, in the z-buffer and the face ids */
                    zr[x] = fr[i].zi;
                    if (ids) ids[o] = fr[i].face;
                    fence_px++;
                } else {
                    blend_px++;
                }
            }
            int v[3];
            for (int k = 0; k < 3; k++) {
                long l = lrint(col[k]);
                v[k] = l < 0 ? 0 : l > 255 ? 255 : (int)l;
            }
            if (t->bpp == 4) {
                ew_set32(row, x, ew_rgba(v[0], v[1], v[2]));
            } else {
                const uint8_t *p = &fm->palette[was * 3];
                if (v[0] != p[0] || v[1] != p[1] || v[2] != p[2])  /* unchanged colours keep their index */
                    row[x] = nearest(fm->palette, nc, v[0], v[1], v[2]);
            }
        }
    }
    rows->stats->fog_pixels += fogged;
    rows->stats->fence_pixels += fence_px;
    rows->stats->translucent_pixels += blend_px;
    free(row_polys);
    free(nc);
}
