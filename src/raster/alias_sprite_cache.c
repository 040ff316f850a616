/* Sprite-cache: the idea Black Book chapter 69 tells of trying and giving
 * up ("caching a model's image from one frame and reusing it in the next
 * frame as a sprite").  A small model is drawn exactly (affine, Gouraud)
 * into an image of its own with its 1/z; while the key holds (alias.h,
 * ew_sc_tol) later frames draw that image as a z-tested sprite.  The
 * model is still posed every frame (ew_alias_transform: its vertices, the
 * screen box and the key come from it), but no triangle is drawn.
 *
 * Threads: the slots are one per scene entity, grown in the models pass's
 * prepare (serial); slot i is written only by the pose work of entity i and
 * read by the bands after that, so no slot is written by two threads and
 * nothing is written while bands draw. */
#include "raster/alias.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct ew_sprite_cache {
    ew_sc_slot *slots;
    int         n;
    ew_sc_tol   tol;
};

#define MAX_IMAGE_PIXELS (256 * 256)

ew_sc_tol ew_sprite_cache_tol_default(void) {
    /* The book reused an image for "the next two or three frames"; its
     * angle and size are what a model 40 pixels tall can change before an
     * edge moves by about a pixel (2 degrees: 40 * sin 2 = 1.4 px). */
    return (ew_sc_tol){2.0f, 0.03f, 8, 3};
}

void ew_sprite_cache_slot_free(ew_sc_slot *slot) {
    free(slot->pix), free(slot->zi);
    memset(slot, 0, sizeof *slot);
}

void ew_sprite_cache_free(struct ew_sprite_cache *c) {
    if (!c) return;
    for (int i = 0; i < c->n; i++) ew_sprite_cache_slot_free(&c->slots[i]);
    free(c->slots);
    free(c);
}

static struct ew_sprite_cache *cache_of(struct ew_sprite_cache **cp) {
    struct ew_sprite_cache *c = *cp;
    if (!c) {
        c = calloc(1, sizeof *c);
        if (!c) return NULL;
        c->tol = ew_sprite_cache_tol_default();
        *cp = c;
    }
    return c;
}

int ew_sprite_cache_set_tol(struct ew_sprite_cache **cp, const ew_sc_tol *tol) {
    struct ew_sprite_cache *c = cache_of(cp);
    if (!c) return -1;
    c->tol = *tol;
    for (int i = 0; i < c->n; i++) c->slots[i].valid = 0;  /* images made under other rules */
    return 0;
}

const ew_sc_tol *ew_sprite_cache_tol(const struct ew_sprite_cache *c) {
    static const ew_sc_tol none = {0, 0, 0, 0};
    return c ? &c->tol : &none;
}

int ew_sprite_cache_grow(struct ew_sprite_cache **cp, const ew_frame *f, int n) {
    if (f->cfg.alias_raster != EW_ALIAS_SPRITE_CACHE) return 0;
    struct ew_sprite_cache *c = cache_of(cp);
    if (!c) return -1;
    if (n <= c->n) return 0;
    ew_sc_slot *s = realloc(c->slots, sizeof *s * (size_t)n);
    if (!s) return -1;
    memset(s + c->n, 0, sizeof *s * (size_t)(n - c->n));
    c->slots = s, c->n = n;
    return 0;
}

ew_sc_slot *ew_sprite_cache_slot(const struct ew_sprite_cache *c, const ew_frame *f, int i) {
    if (f->cfg.alias_raster != EW_ALIAS_SPRITE_CACHE || !c || i < 0 || i >= c->n) return NULL;
    return &c->slots[i];
}

static uint32_t hash_tint(const uint32_t *rgba, const uint8_t *remap) {
    uint32_t h = 2166136261u;
    if (rgba)
        for (int i = 0; i < 256; i++) h = (h ^ rgba[i]) * 16777619u;
    if (remap)
        for (int i = 0; i < 256; i++) h = (h ^ remap[i]) * 16777619u;
    return h;
}

/* Does the key still hold?  Angles by the largest change of an axis or the
 * eye direction (unit vectors: |a - b| = 2 sin(angle / 2)). */
static int key_holds(const ew_sc_slot *s, const ew_mdl *m, const ew_alias_xf *xf, const ew_model_pose *p,
                     uint32_t tint, const float dir[3], float dist, const ew_sc_tol *tol) {
    if (!s->valid || s->model != m || s->pose != xf->pose || s->image != xf->image || s->tint != tint) return 0;
    if (s->reused >= tol->max_reuse) return 0;
    if (abs(s->ambient - p->ambient) > tol->light || abs(s->shade - p->shade) > tol->light) return 0;
    if (!(fabsf(dist / s->dist - 1.0f) <= tol->scale)) return 0;
    float chord = 2.0f * sinf(tol->angle_deg * 0.0087266463f /* pi / 360 */);
    float lim = chord * chord, d2 = 0;
    for (int j = 0; j < 3; j++) {
        float a = 0;
        for (int i = 0; i < 3; i++) a += (xf->rot[i][j] - s->rot[i][j]) * (xf->rot[i][j] - s->rot[i][j]);
        if (!(a <= lim)) return 0;
    }
    for (int i = 0; i < 3; i++) d2 += (dir[i] - s->dir[i]) * (dir[i] - s->dir[i]);
    return d2 <= lim;
}

/* The origin on screen (unsnapped). */
static void origin_on_screen(const ew_view *v, const float o[3], float *x, float *y) {
    *x = v->xcenter + v->xscale * o[0] / o[2];
    *y = v->ycenter - v->yscale * o[1] / o[2];
}

/* Draws the model into the slot's image: the affine filler over a target
 * the size of its projected box. */
static int redraw(const ew_frame *f, ew_sc_slot *s, const ew_mdl *m, const ew_alias_xf *xf) {
    int w = xf->maxx - xf->minx + 1, h = xf->maxy - xf->miny + 1, bpp = f->target.bpp;
    if (w <= 0 || h <= 0 || (long)w * h > MAX_IMAGE_PIXELS) return 0;
    size_t n = (size_t)w * h;
    if (n > s->cap || bpp != s->bpp) {
        uint8_t *pix = realloc(s->pix, n * (size_t)bpp);
        if (pix) s->pix = pix;
        float *zi = realloc(s->zi, n * sizeof *zi);
        if (zi) s->zi = zi;
        if (!pix || !zi) {
            s->cap = 0;
            return 0;
        }
        s->cap = n;
    }
    s->x0 = xf->minx, s->y0 = xf->miny, s->w = w, s->h = h, s->bpp = bpp;
    memset(s->zi, 0, n * sizeof *s->zi);
    ew_target t = {s->pix, s->zi, w, h, w * bpp, bpp, f->target.rgba};
    ew_araster ra;
    memset(&ra, 0, sizeof ra);
    ra.target = &t;
    ra.rgba = xf->rgba ? xf->rgba : f->target.rgba;
    ra.remap = bpp == 1 ? xf->remap : NULL;
    ra.x0 = 0, ra.y0 = 0, ra.x1 = w, ra.y1 = h;
    ra.skin = m->skinpixels + (size_t)xf->image * m->skinwidth * m->skinheight;
    ra.skinw = m->skinwidth, ra.skinh = m->skinheight;
    ra.colormap = f->colormap;
    int ntris = 0;
    for (int ti = 0; ti < m->numtris; ti++) {
        const ew_mdl_tri *tri = &m->tris[ti];
        const ew_xvert *x0 = &xf->xv[tri->v[0]], *x1 = &xf->xv[tri->v[1]], *x2 = &xf->xv[tri->v[2]];
        if (!ew_alias_tri_visible(&x0->sv, &x1->sv, &x2->sv)) continue;  /* culled before the copies */
        ew_avert a = x0->sv, b = x1->sv, c = x2->sv;
        if (!tri->facesfront) a.s = x0->sback, b.s = x1->sback, c.s = x2->sback;
        a.x -= s->x0, b.x -= s->x0, c.x -= s->x0;
        a.y -= s->y0, b.y -= s->y0, c.y -= s->y0;
        ew_alias_affine_tri(&ra, &a, &b, &c);
        ntris++;
    }
    s->ntris = ntris;
    return 1;
}

/* Small models wholly in view (their image is their whole box). */
static int cacheable(const ew_frame *f, const ew_alias_xf *xf) {
    return xf->visible && xf->accept && xf->vmax - xf->vmin < f->cfg.alias_threshold && xf->org[2] > 0;
}

int ew_sprite_cache_reuse(const ew_frame *f, ew_sc_slot *s, const ew_mdl *m, const ew_alias_xf *xf,
                          const ew_model_pose *p, const ew_sc_tol *tol) {
    s->use = 0, s->hit = 0;
    if (!cacheable(f, xf)) return 0;
    float dist = sqrtf(xf->org[0] * xf->org[0] + xf->org[1] * xf->org[1] + xf->org[2] * xf->org[2]);
    float dir[3] = {xf->org[0] / dist, xf->org[1] / dist, xf->org[2] / dist};
    uint32_t tint = hash_tint(xf->rgba, f->target.bpp == 1 ? xf->remap : NULL);
    if (!key_holds(s, m, xf, p, tint, dir, dist, tol)) return 0;
    float ox, oy;
    origin_on_screen(&f->view, xf->org, &ox, &oy);
    s->reused++;
    s->use = 1, s->hit = 1;
    s->dx = (int)lrintf(ox - s->ox), s->dy = (int)lrintf(oy - s->oy);
    s->dz = xf->org[2] - s->oz;  /* how much deeper the origin is now */
    return 1;
}

void ew_sprite_cache_redraw(const ew_frame *f, ew_sc_slot *s, const ew_mdl *m, const ew_alias_xf *xf,
                            const ew_model_pose *p) {
    s->use = 0, s->hit = 0, s->valid = 0;
    if (!cacheable(f, xf) || xf->maxx < xf->minx || !redraw(f, s, m, xf)) return;
    float dist = sqrtf(xf->org[0] * xf->org[0] + xf->org[1] * xf->org[1] + xf->org[2] * xf->org[2]);
    float dir[3] = {xf->org[0] / dist, xf->org[1] / dist, xf->org[2] / dist};
    uint32_t tint = hash_tint(xf->rgba, f->target.bpp == 1 ? xf->remap : NULL);
    float ox, oy;
    origin_on_screen(&f->view, xf->org, &ox, &oy);
    s->valid = 1, s->model = m, s->pose = xf->pose, s->image = xf->image, s->tint = tint;
    s->ambient = p->ambient, s->shade = p->shade, s->reused = 0;
    memcpy(s->rot, xf->rot, sizeof s->rot);
    memcpy(s->dir, dir, sizeof dir);
    s->dist = dist, s->ox = ox, s->oy = oy, s->oz = xf->org[2];
    s->use = 1, s->dx = s->dy = 0, s->dz = 0;
}

void ew_sprite_cache_draw(const ew_frame *f, ew_zfill *zf, const ew_sc_slot *s, const ew_rows *rows) {
    if (!s->use) return;
    if (rows->first) {
        if (s->hit) rows->stats->alias_sprite_hits++;
        else rows->stats->alias_sprite_misses++, rows->stats->alias_tris += s->ntris;
    }
    const ew_target *t = &f->target;
    int x0 = s->x0 + s->dx, y0 = s->y0 + s->dy;
    int xa = x0 < 0 ? 0 : x0, xb = x0 + s->w > t->width ? t->width : x0 + s->w;
    int ya = y0 > rows->y0 ? y0 : rows->y0, yb = y0 + s->h < rows->y1 ? y0 + s->h : rows->y1;
    if (xa >= xb || ya >= yb) return;
    ew_zfill_rect(zf, xa, ya, xb, yb);
    const int bpp = t->bpp;
    const float dz = s->dz;
    long n = 0;
    for (int y = ya; y < yb; y++) {
        const float *zs = s->zi + (size_t)(y - y0) * s->w - x0;
        const uint8_t *ps = s->pix + ((size_t)(y - y0) * s->w - x0) * bpp;
        float *zd = ew_target_z(t, 0, y);
        uint8_t *pd = ew_target_at(t, 0, y);
        for (int x = xa; x < xb; x++) {
            float zi = zs[x];
            if (!(zi > 0)) continue;
            if (dz != 0) {
                float z = 1.0f / zi + dz;  /* the whole image moved dz deeper */
                if (!(z > 0)) continue;
                zi = 1.0f / z;
            }
            if (zi >= zd[x]) {
                zd[x] = zi;
                memcpy(pd + (size_t)x * bpp, ps + (size_t)x * bpp, (size_t)bpp);
                n++;
            }
        }
    }
    rows->stats->alias_pixels += n;
}
