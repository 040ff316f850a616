/* Hidden-surface removal by subdividing raycast (the Black Book's lab):
 * rays through the pixel centres of an 8x8 grid are traced into the world
 * BSP to the first face that has a surface this frame, and tested against
 * the brush model fragments the front end handed over (their screen
 * polygons and 1/z planes).  A block whose four corner rays hit the same
 * surface is filled with it without more rays; otherwise it is cut in four
 * and the new corners traced, down to single pixels.  Thin things between
 * agreeing corners are missed: the method's approximation, which the
 * counters (pixels filled from corners) and the tests (agreement with the
 * reference) measure.
 *
 * The grid is the frame's, not the band's (blocks start at multiples of 8
 * from the top), and a block's rays do not depend on the band, so a frame
 * is the same for any number of threads; a band traces the corner rays it
 * needs below its last row itself. */
#include "hsr/surf_poly.h"

#include <math.h>
#include <string.h>

#define GRID 8
#define UNKNOWN (-3)
#define MAX_DEPTH 4096
#define MAGIC 0x72617963617374ULL  /* "raycast": this method's scratch layout */

typedef struct ray_ctx {
    const ew_hsr_ctx  *c;
    const ew_world    *w;
    const ew_spolys   *sp;
    double o[3], d[3];     /* eye, and direction with a forward part of 1 (t is the view depth) */
    int    last_node;      /* the last plane the ray crossed, and where */
    double last_t;
    int    faceless;       /* it went into solid without meeting a face */
    int    solid_node;     /* the first time: the plane it crossed, and where */
    double solid_t;
} ray_ctx;

/* Signed distance of p (on the face's plane) from surface s's face
 * outline, in world units, positive inside; below floor it stops early. */
static double inside_dist(const ew_spolys *sp, int s, const double p[3], double floor) {
    const ew_spoly *pl = &sp->polys[s];
    double worst = 1e30;
    for (int i = 0; i < pl->neplanes; i++) {
        const float *e = sp->eplanes[pl->eplane0 + i];
        double d = e[0] * p[0] + e[1] * p[1] + e[2] * p[2] - e[3];
        if (d < worst && (worst = d) < floor) break;
    }
    return worst;
}

/* The surface of the camera-facing face of node n the ray meets at t (the
 * one it is most inside of, within tol), or -1. */
static int face_at(const ray_ctx *c, int n, double t, double tol) {
    const ew_world *w = c->w;
    const ew_node *nd = &w->nodes[n];
    const ew_plane *pl = &w->planes[nd->plane];
    double dO = c->o[0] * pl->normal[0] + c->o[1] * pl->normal[1] + c->o[2] * pl->normal[2] - pl->dist;
    int back = dO < 0;
    double p[3] = {c->o[0] + t * c->d[0], c->o[1] + t * c->d[1], c->o[2] + t * c->d[2]};
    int best = -1;
    double best_d = -tol;
    for (int i = 0; i < nd->numfaces; i++) {
        int fi = nd->firstface + i;
        const ew_face *f = &w->faces[fi];
        if (c->sp->face_frame[fi] != c->sp->frame) continue;  /* no surface: not drawn by any method */
        if (((f->flags & EW_SURF_PLANEBACK) != 0) != back) continue;
        double d = inside_dist(c->sp, c->sp->face_surf[fi], p, best_d);
        if (d >= best_d) best_d = d, best = c->sp->face_surf[fi];
    }
    return best;
}

/* The first surface met in [t0, t1] below node n: its index, or -1.  A
 * ray that goes into solid without meeting a face either slipped between
 * two faces (a crack: the nearest face on the plane it crossed, if one is
 * close, is the one) or went into solid that has no faces here (brushes a
 * map leaves unseen): it goes on through, as every other method sees
 * through it. */
static int trace(ray_ctx *c, int n, double t0, double t1, int depth, double *thit) {
    const ew_world *w = c->w;
    while (n >= 0) {
        if (depth > MAX_DEPTH) return -1;
        const ew_node *nd = &w->nodes[n];
        const ew_plane *pl = &w->planes[nd->plane];
        double dO = c->o[0] * pl->normal[0] + c->o[1] * pl->normal[1] + c->o[2] * pl->normal[2] - pl->dist;
        double dD = c->d[0] * pl->normal[0] + c->d[1] * pl->normal[1] + c->d[2] * pl->normal[2];
        double d0 = dO + t0 * dD, d1 = dO + t1 * dD;
        if (d0 >= 0 && d1 >= 0) {
            n = nd->children[0];
        } else if (d0 < 0 && d1 < 0) {
            n = nd->children[1];
        } else {
            int nearside = d0 >= 0 ? 0 : 1;
            double tm = -dO / dD;
            int s = trace(c, nd->children[nearside], t0, tm, depth + 1, thit);
            if (s != -1) return s;
            c->last_node = n, c->last_t = tm;
            s = face_at(c, n, tm, 1e-3);
            if (s >= 0) {
                *thit = tm;
                return s;
            }
            n = nd->children[!nearside];
            t0 = tm;
        }
        depth++;
    }
    if (w->leaves[-1 - n].contents != EW_CONTENTS_SOLID) return -1;
    if (!c->faceless++) c->solid_node = c->last_node, c->solid_t = c->last_t;
    if (c->last_node < 0) return -1;
    int s = face_at(c, c->last_node, c->last_t, 1.0);
    if (s >= 0) *thit = c->last_t;
    return s;
}

/* The surface seen through pixel centre (x, y); *lost counts rays that
 * found none where the world is solid. */
static int cast(const ew_hsr_ctx *hc, const int *brush, int nbrush, int x, int y, long *lost) {
    const ew_view *v = &hc->f->view;
    ray_ctx c = {hc, hc->f->world, hc->spolys, {v->origin[0], v->origin[1], v->origin[2]}, {0, 0, 0}, -1, 0, 0, -1, 0};
    double dx = (x - v->xcenter) / (double)v->xscale, dy = (v->ycenter - y) / (double)v->yscale;
    for (int k = 0; k < 3; k++) c.d[k] = v->forward[k] + dx * v->right[k] + dy * v->up[k];
    double thit = 0;
    int s = trace(&c, hc->f->world->models[0].headnode, 0, 1e6, 0, &thit);
    *lost += c.faceless > 0;
    /* Through solid and out into nothing: a crack after all, wider than
     * the tolerance; the nearest face where it first went in. */
    if (s < 0 && c.solid_node >= 0) {
        s = face_at(&c, c.solid_node, c.solid_t, 1e30);
        thit = c.solid_t;
    }
    if (s < 0) s = 0, thit = 0;
    /* Brush model fragments: the nearest one whose polygon holds the pixel, if nearer than the world. */
    double best = thit > 0 ? 1.0 / thit * (1 - 1e-6) : 0;
    const ew_surf *surfs = hc->el->surfs;
    for (int i = 0; i < nbrush; i++) {
        int bs = brush[i];
        const ew_spoly *pl = &c.sp->polys[bs];
        if (x < pl->x0 || x > pl->x1 || y < pl->y0 || y > pl->y1) continue;
        int in = 1;
        for (int k = 0; k < pl->n && in; k++) {
            const ew_line *l = &c.sp->verts[pl->first + k].l;
            in = ew_line_in(l, x, ew_line_row(l, y));
        }
        if (!in) continue;
        const ew_surf *sf = &surfs[bs];
        double zi = sf->zi_u * (double)x + sf->zi_v * (double)y + sf->zi_0;
        if (zi > best || (zi == best && s > 0 && surfs[s].insubmodel && sf->zi_u > surfs[s].zi_u)) best = zi, s = bs;
    }
    return s;
}

typedef struct rc_band {
    const ew_hsr_ctx *c;
    ew_band *b;
    int     *rays;     /* per pixel of rows [ry0, ry1]: the surface, or UNKNOWN */
    int     *out;      /* per pixel of the band */
    int     *brush;    int nbrush;
    int      ry0, ry1, w, h;
    long     cast, filled, filled_px, lost;
} rc_band;

static int ray(rc_band *k, int x, int y) {
    int *slot = &k->rays[(size_t)(y - k->ry0) * k->w + x];
    if (*slot == UNKNOWN) *slot = cast(k->c, k->brush, k->nbrush, x, y, &k->lost), k->cast++;
    return *slot;
}

/* The block of size s at (x, y): filled if its corners agree, else cut in four. */
static void block(rc_band *k, int x, int y, int s) {
    const ew_band *b = k->b;
    if (y >= b->y1 || y + s <= b->y0 || x >= k->w) return;
    if (s == 1) {
        k->out[(size_t)(y - b->y0) * k->w + x] = ray(k, x, y);
        return;
    }
    int xb = x + s < k->w ? x + s : k->w - 1, yb = y + s < k->h ? y + s : k->h - 1;
    int c0 = ray(k, x, y);
    if (ray(k, xb, y) == c0 && ray(k, x, yb) == c0 && ray(k, xb, yb) == c0) {
        int ya = y > b->y0 ? y : b->y0, ye = y + s < b->y1 ? y + s : b->y1, xe = x + s < k->w ? x + s : k->w;
        for (int yy = ya; yy < ye; yy++)
            for (int xx = x; xx < xe; xx++) k->out[(size_t)(yy - b->y0) * k->w + xx] = c0;
        k->filled++;
        k->filled_px += (long)(ye - ya) * (xe - x);
        return;
    }
    int h = s / 2;
    block(k, x, y, h), block(k, x + h, y, h), block(k, x, y + h, h), block(k, x + h, y + h, h);
}

static void ray_begin(ew_hsr_ctx *c) { ew_spolys_begin(c); }

static void ray_resolve(const ew_hsr_ctx *c, ew_band *b) {
    const int w = c->f->target.width, h = c->f->target.height;
    const ew_spolys *sp = c->spolys;
    b->nspans = 0;
    memset(b->has_spans, 0, (size_t)c->el->nsurfs);
    rc_band k = {c, b, NULL, NULL, NULL, 0, 0, 0, w, h, 0, 0, 0, 0};
    k.ry0 = b->y0 / GRID * GRID;
    k.ry1 = (b->y1 - 1) / GRID * GRID + GRID;
    if (k.ry1 > h - 1) k.ry1 = h - 1;
    size_t nrays = (size_t)(k.ry1 - k.ry0 + 1) * w, nout = (size_t)(b->y1 - b->y0) * w;
    size_t nbrush = sp ? (size_t)sp->norder : 0;
    size_t bytes = sizeof(unsigned long long) * 2 + sizeof(int) * (nrays + nout + nbrush);
    unsigned long long *hdr = (!sp || sp->failed) ? NULL : ew_band_scratch(b, bytes);
    if (!hdr) {  /* out of memory: the background alone, counted */
        b->dropped++;
        for (int y = b->y0; y < b->y1; y++) ew_band_span(b, 0, 0, w, y);
        return;
    }
    hdr[0] = MAGIC, hdr[1] = bytes;  /* whose scratch, and how much of it this frame used */
    k.rays = (int *)(hdr + 2), k.out = k.rays + nrays, k.brush = k.out + nout;
    for (size_t i = 0; i < nrays; i++) k.rays[i] = UNKNOWN;
    /* The brush model fragments that can reach the rows this band traces. */
    for (int i = 0; i < sp->norder; i++) {
        int s = sp->order[i];
        const ew_spoly *pl = &sp->polys[s];
        if (c->el->surfs[s].insubmodel && pl->y1 >= k.ry0 && pl->y0 <= k.ry1) k.brush[k.nbrush++] = s;
    }
    for (int y = k.ry0; y < b->y1; y += GRID)
        for (int x = 0; x < w; x += GRID) block(&k, x, y, GRID);
    for (int y = b->y0; y < b->y1; y++) {
        const int *row = k.out + (size_t)(y - b->y0) * w;
        int x0 = 0;
        for (int x = 1; x <= w; x++)
            if (x == w || row[x] != row[x0]) ew_band_span(b, row[x0], x0, x, y), x0 = x;
    }
    b->counters[0] = k.cast;
    b->counters[1] = k.filled;
    b->counters[2] = k.filled_px;
    b->counters[3] = k.lost;
}

/* The polygons, and what the bands used of their scratch this frame. */
static size_t ray_memory(const ew_hsr_ctx *c) {
    size_t n = ew_spolys_memory(c);
    for (int i = 0; i < c->nbands; i++) {
        const ew_band *b = &c->bands[i];
        const unsigned long long *h = b->scratch_bytes >= 16 ? b->scratch : NULL;
        if (h && h[0] == MAGIC) n += (size_t)h[1];
    }
    return n;
}

const ew_hsr ew_hsr_raycast = {
    "raycast", EW_HSR_MAKES_SPANS | EW_HSR_EXACT_ONCE, ray_begin, ew_spolys_face, ew_spolys_poly, NULL, ray_resolve,
    ray_memory, {"rays cast", "blocks filled", "pixels filled from corners", "rays into solid with no face"}};
