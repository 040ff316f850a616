/* The affine triangle filler of alias models: texture stepped linearly
 * across each span, Gouraud light, z-tested against the world's 1/z
 * (raster/alias_tri.h). */
#include "raster/alias_tri.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- the affine filler ---------------------------------------------------- */

/* ceil(n / d) for d > 0 */
static inline int32_t ceil_div(int64_t n, int64_t d) {
    int64_t q = n / d;
    if (q * d < n) q++;
    return (int32_t)q;
}

/* Walks x = ceil(x0 + (y - y0) * dx / dy) down the scanlines (dy > 0):
 * the first pixel centre on or right of the edge. */
typedef struct edge_walk {
    int32_t x, err, step, rstep, dy;
} edge_walk;

static void edge_start(edge_walk *e, const ew_avert *p, const ew_avert *q, int32_t y) {
    int32_t dx = q->x - p->x, dy = q->y - p->y;
    int64_t n = (int64_t)(y - p->y) * dx;
    int32_t c = ceil_div(n, dy);
    e->x = p->x + c;
    e->err = (int32_t)((int64_t)c * dy - n);  /* in [0, dy) */
    e->dy = dy;
    /* dx = step * dy + rstep, 0 <= rstep < dy */
    int32_t step = dx / dy;
    if (step * dy > dx) step--;
    e->step = step;
    e->rstep = dx - step * dy;
}

static inline void edge_next(edge_walk *e) {
    e->x += e->step;
    e->err -= e->rstep;
    if (e->err < 0) {
        e->x++;
        e->err += e->dy;
    }
}

typedef ew_agrad grad;

static inline grad make_grad(float a0, float a1, float a2, float x1, float y1, float x2, float y2,
                             float inv) {
    float d1 = a1 - a0, d2 = a2 - a0;
    return (grad){(d1 * y2 - d2 * y1) * inv, (d2 * x1 - d1 * x2) * inv, a0};
}

/* Clamps a 16.16/8.8 run to [0, max] by its ends: the run is linear, so if
 * both ends are inside, every value between is. */
static inline void fix_run(int32_t *start, int32_t *step, int n, int32_t max) {
    int64_t end = (int64_t)*start + (int64_t)*step * (n - 1);
    if (*start >= 0 && *start <= max && end >= 0 && end <= max) return;
    int64_t s = *start < 0 ? 0 : *start > max ? max : *start;
    int64_t e = end < 0 ? 0 : end > max ? max : end;
    *start = (int32_t)s;
    *step = n > 1 ? (int32_t)((e - s) / (n - 1)) : 0;
}

/* float -> int32 without undefined behaviour for wild values (slivers). */
static inline int32_t f2i(float f) {
    if (!(f > -1073741824.0f)) return -1073741824;
    if (f > 1073741824.0f) return 1073741824;
    return (int32_t)f;
}

void ew_alias_span(ew_araster *ra, const ew_atri *tri, int y, int xs, int xe) {
    const ew_avert *top = tri->v0;
    const grad *gs = &tri->gs, *gt = &tri->gt, *gl = &tri->gl, *gz = &tri->gz;
    int n = xe - xs;
    float fx = (float)(xs - top->x), fy = (float)(y - top->y);
    int32_t s = f2i(gs->v0 + gs->dx * fx + gs->dy * fy);
    int32_t t = f2i(gt->v0 + gt->dx * fx + gt->dy * fy);
    int32_t l = f2i(gl->v0 + gl->dx * fx + gl->dy * fy);
    float zi = gz->v0 + gz->dx * fx + gz->dy * fy, dzi = gz->dx;
    int32_t ds = f2i(gs->dx), dt = f2i(gt->dx), dl = f2i(gl->dx);
    fix_run(&s, &ds, n, (ra->skinw << 16) - 1);
    fix_run(&t, &dt, n, (ra->skinh << 16) - 1);
    fix_run(&l, &dl, n, (63 << 8) + 255);

    float *zr = ew_target_z(ra->target, 0, y);
    uint8_t *fr = ew_target_at(ra->target, 0, y);
    const uint8_t *skin = ra->skin, *cmap = ra->colormap;
    const int bpp = ra->target->bpp;
    const uint32_t *rgba = ra->rgba;
    const uint8_t *remap = ra->remap;
    int sw = ra->skinw;
    long count = 0;
    for (int x = xs; x < xe; x++) {
        if (zi >= zr[x]) {
            zr[x] = zi;
            uint8_t px = cmap[(l & 0x3F00) + skin[(t >> 16) * sw + (s >> 16)]];
            ew_put_via(bpp, rgba, fr, x, remap ? remap[px] : px);
            count++;
        }
        zi += dzi;
        s += ds;
        t += dt;
        l += dl;
    }
    ra->pixels += count;
}

void ew_alias_tri_setup(ew_atri *t, const ew_avert *a, const ew_avert *b, const ew_avert *c) {
    /* Sort by y: top, mid, bottom. */
    const ew_avert *v0 = a, *v1 = b, *v2 = c, *tmp;
    if (v1->y < v0->y) tmp = v0, v0 = v1, v1 = tmp;
    if (v2->y < v1->y) tmp = v1, v1 = v2, v2 = tmp;
    if (v1->y < v0->y) tmp = v0, v0 = v1, v1 = tmp;
    t->v0 = v0, t->v1 = v1, t->v2 = v2;
    /* Gradients over the screen from the top vertex (the cross is their
     * common denominator). */
    float x1 = (float)(v1->x - v0->x), y1 = (float)(v1->y - v0->y);
    float x2 = (float)(v2->x - v0->x), y2 = (float)(v2->y - v0->y);
    float det = x1 * y2 - x2 * y1;  /* +-cross: sorting may have swapped the order */
    float inv = 1.0f / det;
    t->gs = make_grad((float)v0->s, (float)v1->s, (float)v2->s, x1, y1, x2, y2, inv);
    t->gt = make_grad((float)v0->t, (float)v1->t, (float)v2->t, x1, y1, x2, y2, inv);
    t->gl = make_grad((float)v0->l, (float)v1->l, (float)v2->l, x1, y1, x2, y2, inv);
    t->gz = make_grad(v0->zi, v1->zi, v2->zi, x1, y1, x2, y2, inv);
}

void ew_alias_affine_tri(ew_araster *ra, const ew_avert *a, const ew_avert *b, const ew_avert *c) {
    int64_t cross = ew_alias_cross(a, b, c);
    if (cross <= 0) return;
    /* Rows first: a model crossing several bands sends every band all its
     * triangles, and the setup's divides are most of a small one's cost. */
    int32_t ytop, ybot;
    ew_alias_tri_rows(a, b, c, &ytop, &ybot);
    int32_t ya = ytop > ra->y0 ? ytop : ra->y0;
    int32_t yb = ybot < ra->y1 ? ybot : ra->y1;
    if (ya >= yb) return;
    ew_atri tri;
    ew_alias_tri_setup(&tri, a, b, c);
    const ew_avert *v0 = tri.v0, *v1 = tri.v1, *v2 = tri.v2;
    int32_t ymid = v1->y;

    /* Is the middle vertex right of the long edge (then the long edge is the
     * left one)?  The x range of a scanline is [ceil(xl), ceil(xr)): left
     * edges include centres on them, right edges exclude them, a top
     * horizontal edge is drawn and a bottom one is not. */
    int mid_right = (int64_t)(v1->x - v0->x) * (ybot - ytop) > (int64_t)(v2->x - v0->x) * (ymid - ytop);
    edge_walk lng, sh;
    edge_start(&lng, v0, v2, ya);
    int32_t y = ya;
    if (y < ymid) {
        edge_start(&sh, v0, v1, y);
        int32_t yend = ymid < yb ? ymid : yb;
        for (; y < yend; y++, edge_next(&lng), edge_next(&sh)) {
            int32_t xl = mid_right ? lng.x : sh.x, xr = mid_right ? sh.x : lng.x;
            if (xl < ra->x0) xl = ra->x0;
            if (xr > ra->x1) xr = ra->x1;
            if (xl < xr) ew_alias_span(ra, &tri, y, xl, xr);
        }
    }
    if (y < yb) {
        edge_start(&sh, v1, v2, y);
        for (; y < yb; y++, edge_next(&lng), edge_next(&sh)) {
            int32_t xl = mid_right ? lng.x : sh.x, xr = mid_right ? sh.x : lng.x;
            if (xl < ra->x0) xl = ra->x0;
            if (xr > ra->x1) xr = ra->x1;
            if (xl < xr) ew_alias_span(ra, &tri, y, xl, xr);
        }
    }
}

