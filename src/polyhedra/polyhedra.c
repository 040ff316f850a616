/* Moving convex polyhedra drawn by a 1/z-sorted global edge list, with no
 * BSP tree at all (the Black Book, chapter 51; edgewise.h documents the
 * API).  Per frame:
 *
 *   1. every object is placed at the frame's time; its front faces are
 *      clipped in view space to the near plane and the four screen planes,
 *      projected, and given the 1/z plane equation 1/z = a*x + b*y + c in
 *      screen pixels (x + 0.5, y + 0.5 is a pixel's centre);
 *   2. each face's non-horizontal edges go into the global edge list,
 *      bucketed by first scanline, marked leading or trailing;
 *   3. every scanline sorts its active edges by x and walks them: a surface
 *      stack sorted by 1/z at the current pixel decides which surface is
 *      nearest, and a span is emitted whenever that changes.  Between two
 *      edges the nearest surface can still change where two planes cross
 *      (objects that pass through each other): the first pixel where another
 *      surface's 1/z passes the top one's is computed and the stack re-sorted
 *      there;
 *   4. the spans are drawn: every pixel exactly once.
 *
 * The z-buffer of the same polygons (steps 1 and 2 shared, then 1/z tested
 * per pixel) is the check.  All state lives in the ew_polyhedra context. */
#include "ew_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_FACES 8         /* faces of the largest shape (octahedron, prism) */
#define MAX_FACE_VERTS 6
#define MAX_CLIP_VERTS 16   /* a face's vertices after five clip planes */
#define MAX_SHAPE_VERTS 12
#define NEAR_Z 1.0
#define BACKGROUND 0        /* surface 0: at 1/z = -1, behind everything */
#define BG_COLOR 2          /* built-in palette: ramp 0 (grey), shade 2 */
/* 1/z values this close (relative) count as equal: abutting surfaces. */
#define TIE_EPS 1e-10

typedef struct shape {
    int    nverts, nfaces;
    double v[MAX_SHAPE_VERTS][3];
    int    nfv[MAX_FACES];
    int    f[MAX_FACES][MAX_FACE_VERTS];
} shape;

/* One polyhedron: its shape scaled, and how it spins and flies. */
typedef struct object {
    double v[MAX_SHAPE_VERTS][3];      /* object space, outward winding */
    double n[MAX_FACES][3];            /* outward unit normals */
    int    nverts, nfaces;
    int    nfv[MAX_FACES];
    int    f[MAX_FACES][MAX_FACE_VERTS];
    int    ramp;                       /* palette ramp 1..15 */
    double axis[3], spin, spin0;       /* rotation axis, rad/s, phase */
    double center[3], u[3], w[3];      /* orbit: centre + r(cos u + sin w) */
    double radius, speed, phase, bob;  /* orbit radius, rad/s, phase, bob amplitude */
} object;

/* A drawn face: the surface the edge list sorts. */
typedef struct surf {
    double  a, b, c;   /* 1/z at pixel (x, y) = a(x+.5) + (b(y+.5) + c) */
    int     first_edge, nedges;
    int     state;     /* leading minus trailing edges passed on this row */
    uint8_t color;
} surf;

typedef struct edge {
    double xt, yt, dxdy;  /* top end and x step per row */
    int    ytop, ybot;    /* rows [ytop, ybot) whose centres it crosses */
    int    surf, lead;    /* lead: +1 leading (starts its surface), -1 trailing */
    int    next;          /* next edge starting on the same row, -1 */
} edge;

struct ew_polyhedra {
    int      nobj, width, height;
    object   obj[EW_POLYHEDRA_MAX];
    uint8_t  palette[768];
    uint8_t  shade[256];     /* built-in ramp colour -> palette index */
    int      crossings_on;
    surf    *surfs;          /* [0] is the background */
    edge    *edges;
    int      nsurfs, nedges, max_surfs, max_edges;
    int     *bucket;         /* first edge starting on each row, -1 */
    int     *ael;            /* active edges of the row */
    int     *ael_px;         /* their first pixel on the row */
    int     *stack;          /* surface stack, nearest first, background last */
    double  *key;            /* scratch for re-sorting the stack */
    ew_polyhedra_span *spans;
    int      nspans, cap_spans;
    double  *zbuf;           /* the check only; made on first use */
    ew_polyhedra_stats st;
};

/* ---- the scene -------------------------------------------------------------- */

static void make_shape(int kind, shape *s) {
    memset(s, 0, sizeof *s);
    switch (kind) {
    case 0: /* cube */
        s->nverts = 8;
        for (int i = 0; i < 8; i++) {
            s->v[i][0] = (i & 1) ? 1 : -1;
            s->v[i][1] = (i & 2) ? 1 : -1;
            s->v[i][2] = (i & 4) ? 1 : -1;
        }
        {
            static const int f[6][4] = { { 0, 2, 6, 4 }, { 1, 3, 7, 5 }, { 0, 1, 5, 4 },
                                         { 2, 3, 7, 6 }, { 0, 1, 3, 2 }, { 4, 5, 7, 6 } };
            s->nfaces = 6;
            for (int i = 0; i < 6; i++) {
                s->nfv[i] = 4;
                memcpy(s->f[i], f[i], sizeof f[i]);
            }
        }
        break;
    case 1: { /* tetrahedron */
        static const double v[4][3] = { { 1, 1, 1 }, { 1, -1, -1 }, { -1, 1, -1 }, { -1, -1, 1 } };
        static const int f[4][3] = { { 0, 1, 2 }, { 0, 1, 3 }, { 0, 2, 3 }, { 1, 2, 3 } };
        s->nverts = 4;
        memcpy(s->v, v, sizeof v);
        s->nfaces = 4;
        for (int i = 0; i < 4; i++) {
            s->nfv[i] = 3;
            memcpy(s->f[i], f[i], sizeof f[i]);
        }
        break;
    }
    case 2: /* octahedron */
        s->nverts = 6;
        for (int i = 0; i < 6; i++)
            s->v[i][i / 2] = (i & 1) ? -1.3 : 1.3;
        s->nfaces = 8;
        for (int i = 0; i < 8; i++) {
            s->nfv[i] = 3;
            s->f[i][0] = i & 1, s->f[i][1] = 2 + (i >> 1 & 1), s->f[i][2] = 4 + (i >> 2 & 1);
        }
        break;
    case 3: /* hexagonal prism */
        s->nverts = 12;
        for (int i = 0; i < 6; i++) {
            double t = i * 3.14159265358979 / 3;
            s->v[i][0] = s->v[i + 6][0] = cos(t);
            s->v[i][1] = s->v[i + 6][1] = sin(t);
            s->v[i][2] = -1, s->v[i + 6][2] = 1;
        }
        s->nfaces = 8;
        for (int i = 0; i < 6; i++) {
            s->nfv[i] = 4;
            s->f[i][0] = i, s->f[i][1] = (i + 1) % 6, s->f[i][2] = (i + 1) % 6 + 6, s->f[i][3] = i + 6;
        }
        s->nfv[6] = s->nfv[7] = 6;
        for (int i = 0; i < 6; i++)
            s->f[6][i] = i, s->f[7][i] = i + 6;
        break;
    default: { /* square pyramid */
        static const double v[5][3] = { { -1, -1, -1 }, { 1, -1, -1 }, { 1, -1, 1 }, { -1, -1, 1 },
                                        { 0, 1.4, 0 } };
        s->nverts = 5;
        memcpy(s->v, v, sizeof v);
        s->nfaces = 5;
        s->nfv[0] = 4;
        for (int i = 0; i < 4; i++)
            s->f[0][i] = i;
        for (int i = 0; i < 4; i++) {
            s->nfv[1 + i] = 3;
            s->f[1 + i][0] = i, s->f[1 + i][1] = (i + 1) % 4, s->f[1 + i][2] = 4;
        }
        break;
    }
    }
}

static void cross3(const double a[3], const double b[3], double o[3]) {
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}
static double dot3(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
static void normalize3(double v[3]) {
    double l = sqrt(dot3(v, v));
    if (l > 0)
        v[0] /= l, v[1] /= l, v[2] /= l;
}

/* A small deterministic generator: the same count gives the same scene. */
static double rnd(uint32_t *s) {
    *s = *s * 1664525u + 1013904223u;
    uint32_t x = *s ^ (*s >> 15);
    x *= 0x2c1b3c6du;
    x ^= x >> 12;
    return (x >> 8) / 16777216.0;
}

/* Scales the shape and turns every face so its winding agrees with the
 * outward normal (the shapes are written without caring). */
static void make_object(object *o, int i) {
    uint32_t seed = 0x51u + (uint32_t)i * 7919u;
    shape s;
    make_shape(i % 5, &s);
    double scale[3];
    double size = 10 + 12 * rnd(&seed);
    for (int k = 0; k < 3; k++)
        scale[k] = size * (0.7 + 0.6 * rnd(&seed));
    if (i % 5 == 0 && (i / 5) % 2 == 1)  /* every other cube a slab */
        scale[1] *= 0.25, scale[0] *= 1.6;
    o->nverts = s.nverts;
    o->nfaces = s.nfaces;
    double mid[3] = { 0, 0, 0 };
    for (int v = 0; v < s.nverts; v++)
        for (int k = 0; k < 3; k++) {
            o->v[v][k] = s.v[v][k] * scale[k];
            mid[k] += o->v[v][k] / s.nverts;
        }
    for (int f = 0; f < s.nfaces; f++) {
        int n = s.nfv[f];
        double nrm[3] = { 0, 0, 0 }, fc[3] = { 0, 0, 0 };
        for (int j = 0; j < n; j++) { /* Newell's normal */
            const double *p = o->v[s.f[f][j]], *q = o->v[s.f[f][(j + 1) % n]];
            nrm[0] += (p[1] - q[1]) * (p[2] + q[2]);
            nrm[1] += (p[2] - q[2]) * (p[0] + q[0]);
            nrm[2] += (p[0] - q[0]) * (p[1] + q[1]);
            for (int k = 0; k < 3; k++)
                fc[k] += p[k] / n;
        }
        double out[3] = { fc[0] - mid[0], fc[1] - mid[1], fc[2] - mid[2] };
        int flip = dot3(nrm, out) < 0;
        o->nfv[f] = n;
        for (int j = 0; j < n; j++)
            o->f[f][j] = s.f[f][flip ? n - 1 - j : j];
        if (flip)
            nrm[0] = -nrm[0], nrm[1] = -nrm[1], nrm[2] = -nrm[2];
        normalize3(nrm);
        memcpy(o->n[f], nrm, sizeof nrm);
    }
    o->ramp = 1 + i * 7 % 15;  /* neighbours far apart on the wheel */
    for (int k = 0; k < 3; k++)
        o->axis[k] = rnd(&seed) - 0.5;
    normalize3(o->axis);
    o->spin = (0.4 + 1.2 * rnd(&seed)) * (rnd(&seed) < 0.5 ? -1 : 1);
    o->spin0 = 6.283 * rnd(&seed);
    /* Orbits about one point in front of the camera, in tilted planes, so
     * the objects keep passing through each other. */
    o->center[0] = 80 * (rnd(&seed) - 0.5);
    o->center[1] = 30 * (rnd(&seed) - 0.5);
    o->center[2] = 180 + 40 * (rnd(&seed) - 0.5);
    double tilt = 3.14159 * rnd(&seed), yaw = 6.283 * rnd(&seed);
    o->u[0] = cos(yaw), o->u[1] = 0, o->u[2] = sin(yaw);
    double up[3] = { -sin(yaw) * sin(tilt), cos(tilt), cos(yaw) * sin(tilt) };
    double c[3];
    cross3(o->u, up, c);
    cross3(c, o->u, o->w);
    normalize3(o->w);
    o->radius = 30 + 60 * rnd(&seed);
    o->speed = (0.25 + 0.5 * rnd(&seed)) * (rnd(&seed) < 0.5 ? -1 : 1);
    o->phase = 6.283 * rnd(&seed);
    o->bob = 20 * rnd(&seed);
    if (i == 0) {
        /* The first one's orbit passes beside and behind the camera, so the
         * near plane cuts it now and then. */
        o->center[0] = -40, o->center[1] = 10, o->center[2] = 150;
        o->u[0] = 0.3, o->u[1] = 0, o->u[2] = 0.954;
        o->w[0] = 0.954, o->w[1] = 0, o->w[2] = -0.3;
        o->radius = 158;
        o->speed = 0.35;
    }
}

/* The built-in palette: 16 ramps of 16 shades, ramp 0 grey. */
static void builtin_palette(uint8_t pal[768]) {
    for (int r = 0; r < 16; r++) {
        double rgb[3] = { 1, 1, 1 };
        if (r > 0) { /* hues around the wheel, fully saturated-ish */
            double h = (r - 1) / 15.0 * 6;
            int k = (int)h;
            double f = h - k;
            double t[6][3] = { { 1, f, 0 }, { 1 - f, 1, 0 }, { 0, 1, f },
                               { 0, 1 - f, 1 }, { f, 0, 1 }, { 1, 0, 1 - f } };
            for (int c = 0; c < 3; c++)
                rgb[c] = 0.25 + 0.75 * t[k % 6][c];
        }
        for (int s = 0; s < 16; s++) {
            double l = 0.08 + 0.92 * s / 15.0;
            for (int c = 0; c < 3; c++)
                pal[(r * 16 + s) * 3 + c] = (uint8_t)lrint(255 * l * rgb[c]);
        }
    }
}

ew_polyhedra *ew_polyhedra_create(int objects, int width, int height, const uint8_t palette[768],
                                  ew_error *err) {
    if (objects < 1 || objects > EW_POLYHEDRA_MAX) {
        ew_fail(err, "polyhedra: %d objects (must be 1 to %d)", objects, EW_POLYHEDRA_MAX);
        return NULL;
    }
    if (width < 16 || width > 16384 || height < 16 || height > 16384) {
        ew_fail(err, "polyhedra: frame %dx%d (each side must be 16 to 16384)", width, height);
        return NULL;
    }
    ew_polyhedra *p = calloc(1, sizeof *p);
    if (!p) {
        ew_fail(err, "polyhedra: out of memory");
        return NULL;
    }
    p->nobj = objects, p->width = width, p->height = height, p->crossings_on = 1;
    for (int i = 0; i < objects; i++) {
        make_object(&p->obj[i], i);
        if (i % 6 == 5) {
            /* A twin glued to the one before: the same shape moved by its
             * width along its own x, the same motion, so the two touch
             * along a face (boxes: coplanar faces side by side) or an edge
             * and abut all the time (the chapter's abutting case). */
            object *o = &p->obj[i];
            int ramp = o->ramp;
            *o = p->obj[i - 1];
            o->ramp = ramp;
            double lo = o->v[0][0], hi = lo;
            for (int v = 1; v < o->nverts; v++) {
                lo = o->v[v][0] < lo ? o->v[v][0] : lo;
                hi = o->v[v][0] > hi ? o->v[v][0] : hi;
            }
            for (int v = 0; v < o->nverts; v++)
                o->v[v][0] += hi - lo;
        }
    }
    uint8_t ramp[768];
    builtin_palette(ramp);
    memcpy(p->palette, palette ? palette : ramp, 768);
    for (int i = 0; i < 256; i++) {
        int best = 0;
        long bestd = -1;
        for (int j = 0; j < 256 && palette; j++) {
            long d = 0;
            for (int c = 0; c < 3; c++) {
                long e = (long)ramp[i * 3 + c] - palette[j * 3 + c];
                d += e * e;
            }
            if (bestd < 0 || d < bestd)
                bestd = d, best = j;
        }
        p->shade[i] = (uint8_t)(palette ? best : i);
    }
    p->max_surfs = objects * MAX_FACES + 1;
    p->max_edges = p->max_surfs * MAX_CLIP_VERTS;
    p->surfs = malloc(sizeof *p->surfs * (size_t)p->max_surfs);
    p->edges = malloc(sizeof *p->edges * (size_t)p->max_edges);
    p->bucket = malloc(sizeof *p->bucket * (size_t)height);
    p->ael = malloc(sizeof *p->ael * (size_t)p->max_edges);
    p->ael_px = malloc(sizeof *p->ael_px * (size_t)p->max_edges);
    p->stack = malloc(sizeof *p->stack * (size_t)p->max_surfs);
    p->key = malloc(sizeof *p->key * (size_t)p->max_surfs);
    p->cap_spans = 4 * height;
    p->spans = malloc(sizeof *p->spans * (size_t)p->cap_spans);
    if (!p->surfs || !p->edges || !p->bucket || !p->ael || !p->ael_px || !p->stack || !p->key ||
        !p->spans) {
        ew_polyhedra_destroy(p);
        ew_fail(err, "polyhedra: out of memory");
        return NULL;
    }
    return p;
}

void ew_polyhedra_destroy(ew_polyhedra *p) {
    if (!p)
        return;
    free(p->surfs), free(p->edges), free(p->bucket), free(p->ael), free(p->ael_px);
    free(p->stack), free(p->key), free(p->spans), free(p->zbuf);
    free(p);
}

void ew_polyhedra_set_crossings(ew_polyhedra *p, int on) {
    if (p)
        p->crossings_on = !!on;
}

const uint8_t *ew_polyhedra_palette(const ew_polyhedra *p) { return p ? p->palette : NULL; }

const ew_polyhedra_span *ew_polyhedra_spans(const ew_polyhedra *p, int *count) {
    if (count)
        *count = p ? p->nspans : 0;
    return p ? p->spans : NULL;
}

/* ---- steps 1 and 2: faces to surfaces and edges ------------------------------ */

typedef struct view {
    double scale, cx, cy;  /* projection: x' = cx + x scale / z */
} view;

/* Signed distance of p to clip plane k (>= 0 inside): near, left, right,
 * top, bottom. */
static double plane_dist(const ew_polyhedra *p, const view *vw, int k, const double *v) {
    switch (k) {
    case 0: return v[2] - NEAR_Z;
    case 1: return v[0] * vw->scale + vw->cx * v[2];
    case 2: return -v[0] * vw->scale + (p->width - vw->cx) * v[2];
    case 3: return vw->cy * v[2] - v[1] * vw->scale;
    default: return v[1] * vw->scale + (p->height - vw->cy) * v[2];
    }
}

/* Lexicographic order of points, so an edge two faces share is cut at
 * exactly the same point whichever face clips it (no cracks). */
static int before(const double *a, const double *b) {
    for (int k = 0; k < 3; k++)
        if (a[k] != b[k])
            return a[k] < b[k];
    return 0;
}

/* Clips a convex polygon to one plane; the new vertex count. */
static int clip_poly(const ew_polyhedra *p, const view *vw, int k, double (*in)[3], int n,
                     double (*out)[3]) {
    int m = 0;
    for (int i = 0; i < n; i++) {
        const double *a = in[i], *b = in[(i + 1) % n];
        double da = plane_dist(p, vw, k, a), db = plane_dist(p, vw, k, b);
        if (da >= 0)
            memcpy(out[m++], a, sizeof out[0]);
        if ((da >= 0) != (db >= 0)) {
            const double *s = a, *e = b;
            double ds = da, de = db;
            if (before(b, a))
                s = b, e = a, ds = db, de = da;
            double t = ds / (ds - de);
            for (int c = 0; c < 3; c++)
                out[m][c] = s[c] + t * (e[c] - s[c]);
            m++;
        }
    }
    return m;
}

/* Where the object is at time t: R (rows) and position. */
static void place(const object *o, double t, double R[3][3], double pos[3]) {
    double ang = o->spin0 + o->spin * t, c = cos(ang), s = sin(ang), C = 1 - c;
    const double *a = o->axis;
    R[0][0] = c + a[0] * a[0] * C, R[0][1] = a[0] * a[1] * C - a[2] * s, R[0][2] = a[0] * a[2] * C + a[1] * s;
    R[1][0] = a[1] * a[0] * C + a[2] * s, R[1][1] = c + a[1] * a[1] * C, R[1][2] = a[1] * a[2] * C - a[0] * s;
    R[2][0] = a[2] * a[0] * C - a[1] * s, R[2][1] = a[2] * a[1] * C + a[0] * s, R[2][2] = c + a[2] * a[2] * C;
    double th = o->phase + o->speed * t, ct = cos(th), st = sin(th);
    for (int k = 0; k < 3; k++)
        pos[k] = o->center[k] + o->radius * (ct * o->u[k] + st * o->w[k]);
    pos[1] += o->bob * sin(1.7 * th + o->phase);
}

/* The light's direction (towards it) in view space: up, left, behind the eye. */
static const double light_dir[3] = { -0.45, 0.75, -0.48 };

/* Adds the face's edges (screen vertices sx, sy, n of them) for surface s. */
static void add_edges(ew_polyhedra *p, int s, const double *sx, const double *sy, int n) {
    double area = 0;
    for (int i = 0; i < n; i++) {
        int j = (i + 1) % n;
        area += sx[i] * sy[j] - sx[j] * sy[i];
    }
    surf *S = &p->surfs[s];
    S->first_edge = p->nedges;
    S->nedges = 0;
    if (!(fabs(area) > 1e-9))
        return;
    for (int i = 0; i < n; i++) {
        int j = (i + 1) % n;
        if (sy[i] == sy[j])
            continue;  /* horizontal: covers no row centre */
        int down = sy[j] > sy[i];
        int t = down ? i : j, b = down ? j : i;
        int ytop = (int)ceil(sy[t] - 0.5), ybot = (int)ceil(sy[b] - 0.5);
        if (ytop < 0) ytop = 0;
        if (ybot > p->height) ybot = p->height;
        if (ytop >= ybot)
            continue;
        edge *e = &p->edges[p->nedges++];
        e->xt = sx[t], e->yt = sy[t];
        e->dxdy = (sx[b] - sx[t]) / (sy[b] - sy[t]);
        e->ytop = ytop, e->ybot = ybot;
        e->surf = s;
        /* Screen y grows downwards: with a positive area the interior lies
         * left of a downward edge (a trailing edge), right of an upward one. */
        e->lead = (area > 0) == !down ? 1 : -1;
        e->next = -1;
        S->nedges++;
    }
}

/* Step 1 and 2: places the objects at time t, builds surfaces and edges. */
static void build(ew_polyhedra *p, double t) {
    view vw;
    vw.cx = p->width / 2.0, vw.cy = p->height / 2.0;
    vw.scale = vw.cx;  /* tan(45 degrees) = 1: 90 degrees across */
    memset(&p->st, 0, sizeof p->st);
    p->nsurfs = 1, p->nedges = 0;
    surf *bg = &p->surfs[BACKGROUND];
    bg->a = 0, bg->b = 0, bg->c = -1, bg->nedges = 0, bg->first_edge = 0;
    bg->color = p->shade[BG_COLOR];
    for (int i = 0; i < p->nobj; i++) {
        const object *o = &p->obj[i];
        double R[3][3], pos[3], vv[MAX_SHAPE_VERTS][3];
        place(o, t, R, pos);
        for (int v = 0; v < o->nverts; v++)
            for (int k = 0; k < 3; k++)
                vv[v][k] = pos[k] + R[k][0] * o->v[v][0] + R[k][1] * o->v[v][1] + R[k][2] * o->v[v][2];
        for (int f = 0; f < o->nfaces; f++) {
            double n[3];
            for (int k = 0; k < 3; k++)
                n[k] = R[k][0] * o->n[f][0] + R[k][1] * o->n[f][1] + R[k][2] * o->n[f][2];
            /* Plane n.x = d; the eye (the origin) sees the front when d < 0.
             * Faces nearly edge-on are culled: their screen gradients blow up. */
            const double *v0 = vv[o->f[f][0]];
            double d = dot3(n, v0);
            if (!(d < -1e-6 * sqrt(dot3(v0, v0)) - 1e-9))
                continue;
            double buf[2][MAX_CLIP_VERTS][3];
            int m = o->nfv[f], cur = 0, cut = 0;
            for (int j = 0; j < m; j++)
                memcpy(buf[0][j], vv[o->f[f][j]], sizeof buf[0][0]);
            for (int k = 0; k < 5 && m >= 3; k++) {
                int inside = 1;
                for (int j = 0; j < m && inside; j++)
                    inside = plane_dist(p, &vw, k, buf[cur][j]) >= 0;
                if (inside)
                    continue;
                m = clip_poly(p, &vw, k, buf[cur], m, buf[cur ^ 1]);
                cur ^= 1, cut = 1;
            }
            if (m < 3)
                continue;
            double sx[MAX_CLIP_VERTS], sy[MAX_CLIP_VERTS];
            for (int j = 0; j < m; j++) {
                const double *v = buf[cur][j];
                sx[j] = vw.cx + v[0] * vw.scale / v[2];
                sy[j] = vw.cy - v[1] * vw.scale / v[2];
                /* Clipping leaves them on the screen up to rounding; make sure. */
                sx[j] = sx[j] < 0 ? 0 : sx[j] > p->width ? p->width : sx[j];
                sy[j] = sy[j] < 0 ? 0 : sy[j] > p->height ? p->height : sy[j];
            }
            int s = p->nsurfs;
            surf *S = &p->surfs[s];
            /* 1/z = (n.x * (x'-cx)/scale - n.y * (y'-cy)/scale + n.z) / d. */
            S->a = n[0] / (vw.scale * d);
            S->b = -n[1] / (vw.scale * d);
            S->c = (n[2] - n[0] * vw.cx / vw.scale + n[1] * vw.cy / vw.scale) / d;
            S->state = 0;
            double lit = dot3(n, light_dir) / sqrt(dot3(light_dir, light_dir));
            int shade = (int)lrint(3 + 12 * (lit > 0 ? lit : 0));
            S->color = p->shade[o->ramp * 16 + (shade > 15 ? 15 : shade)];
            add_edges(p, s, sx, sy, m);
            if (S->nedges == 0)
                continue;  /* covers no pixel centre row */
            p->nsurfs++;
            p->st.polygons++;
            p->st.clipped += cut;
        }
    }
    p->st.edges = p->nedges;
}

/* 1/z of surface s at the centre of pixel (x, y); the scan and the z-buffer
 * both evaluate it exactly so. */
static inline double zinv(const surf *s, int x, int y) {
    return s->a * (x + 0.5) + (s->b * (y + 0.5) + s->c);
}

/* First pixel of an edge on row y: the first centre at or right of it. */
static inline int edge_px(const ew_polyhedra *p, const edge *e, int y) {
    double x = e->xt + ((y + 0.5) - e->yt) * e->dxdy;
    double c = ceil(x - 0.5);
    return c <= 0 ? 0 : c >= p->width ? p->width : (int)c;
}

/* ---- step 3: the scan ------------------------------------------------------- */

/* Is a nearer than b at pixel (x, y)?  Equal 1/z (abutting surfaces, or
 * coplanar ones) goes to the larger 1/z slope in x: the one heading
 * towards the eye fastest is in front to the right of the meeting point. */
static int nearer(ew_polyhedra *p, int a, int b, int x, int y) {
    const surf *sa = &p->surfs[a], *sb = &p->surfs[b];
    double za = zinv(sa, x, y), zb = zinv(sb, x, y);
    if (fabs(za - zb) <= TIE_EPS * (fabs(za) + fabs(zb))) {
        p->st.ties++;
        return sa->a > sb->a;
    }
    return za > zb;
}

static int push_span(ew_polyhedra *p, int y, int x0, int x1, int s) {
    if (x1 <= x0)
        return 0;
    if (p->nspans == p->cap_spans) {
        int cap = p->cap_spans * 2;
        ew_polyhedra_span *n = realloc(p->spans, sizeof *n * (size_t)cap);
        if (!n)
            return -1;
        p->spans = n, p->cap_spans = cap;
    }
    ew_polyhedra_span *sp = &p->spans[p->nspans++];
    sp->y = y, sp->x = x0, sp->count = x1 - x0, sp->color = p->surfs[s].color;
    if (s != BACKGROUND)
        p->st.covered += x1 - x0;
    return 0;
}

/* Re-sorts the stack (n surfaces, background last) by 1/z at pixel (x, y):
 * insertion sort, nearly free as the stack is nearly in order. */
static void resort(ew_polyhedra *p, int n, int x, int y) {
    int *st = p->stack;
    for (int i = 0; i < n - 1; i++)
        p->key[i] = zinv(&p->surfs[st[i]], x, y);
    for (int i = 1; i < n - 1; i++) {
        int s = st[i];
        double k = p->key[i];
        int j = i;
        while (j > 0) {
            double kj = p->key[j - 1];
            int tie = fabs(k - kj) <= TIE_EPS * (fabs(k) + fabs(kj));
            if (tie)
                p->st.ties++;
            if (!(tie ? p->surfs[s].a > p->surfs[st[j - 1]].a : k > kj))
                break;
            st[j] = st[j - 1], p->key[j] = kj;
            j--;
        }
        st[j] = s, p->key[j] = k;
    }
}

/* The first pixel in (x, end) at whose centre surface s is nearer than the
 * top surface t on row y; end if none.  1/z is linear along the row, so the
 * difference crosses zero once: computed, then checked at the pixels
 * themselves so the answer is exactly the z-buffer's. */
static int crossing(const ew_polyhedra *p, int s, int t, int x, int end, int y) {
    const surf *ss = &p->surfs[s], *st = &p->surfs[t];
    double da = ss->a - st->a;
    if (!(da > 0))
        return end;  /* s falls further behind to the right */
    double d0 = zinv(ss, x, y) - zinv(st, x, y);  /* <= 0: t is on top at x */
    double xc = x - d0 / da;                      /* where they are equal */
    if (!(xc < end))
        return end;
    int q = xc < x + 1 ? x + 1 : (int)floor(xc) + 1;
    while (q < end && !(zinv(ss, q, y) > zinv(st, q, y)))
        q++;
    while (q - 1 > x && zinv(ss, q - 1, y) > zinv(st, q - 1, y))
        q--;
    return q;
}

static int scan(ew_polyhedra *p) {
    int W = p->width, H = p->height;
    for (int y = 0; y < H; y++)
        p->bucket[y] = -1;
    /* Bucket by first row, kept in creation order within a row. */
    for (int e = p->nedges - 1; e >= 0; e--) {
        edge *E = &p->edges[e];
        E->next = p->bucket[E->ytop];
        p->bucket[E->ytop] = e;
    }
    p->nspans = 0;
    int nael = 0;
    for (int y = 0; y < H; y++) {
        /* The active edges: newcomers in, finished ones out, x for this row,
         * then an insertion sort by x (last row's order is nearly right). */
        for (int e = p->bucket[y]; e >= 0; e = p->edges[e].next)
            p->ael[nael++] = e;
        int k = 0;
        for (int i = 0; i < nael; i++) {
            int e = p->ael[i];
            if (p->edges[e].ybot <= y)
                continue;
            int px = edge_px(p, &p->edges[e], y), j = k;
            while (j > 0 && p->ael_px[j - 1] > px) {
                p->ael[j] = p->ael[j - 1], p->ael_px[j] = p->ael_px[j - 1];
                j--;
            }
            p->ael[j] = e, p->ael_px[j] = px;
            k++;
        }
        nael = k;

        /* The walk: the stack holds the active surfaces nearest first, the
         * background always last; top is the surface whose span is open. */
        int n = 1, top = BACKGROUND, start = 0, x = 0;
        p->stack[0] = BACKGROUND;
        for (int i = 0; i <= nael; i++) {
            int nx = i < nael ? p->ael_px[i] : W;
            /* Between edges planes that cross switch the top surface; up
             * to and including the next edge's own pixel, so the top is
             * right there before that edge's surface is sorted in. */
            int lim = nx < W ? nx + 1 : W;
            while (p->crossings_on && n > 2 && x + 1 < lim) {
                int best = lim, who = -1;
                for (int j = 1; j < n - 1; j++) {
                    int q = crossing(p, p->stack[j], p->stack[0], x, best, y);
                    if (q < best)
                        best = q, who = p->stack[j];
                }
                if (who < 0)
                    break;
                resort(p, n, best, y);
                if (p->stack[0] != top) {
                    if (push_span(p, y, start, best, top) < 0)
                        return -1;
                    top = p->stack[0], start = best;
                    p->st.crossings++;
                }
                x = best;
            }
            if (i == nael)
                break;
            x = nx;
            /* Every edge on this pixel, then the span decision: the
             * outcome does not depend on the order within the pixel. */
            for (; i < nael && p->ael_px[i] == x; i++) {
                const edge *E = &p->edges[p->ael[i]];
                int s = E->surf;
                surf *S = &p->surfs[s];
                S->state += E->lead;
                if (E->lead > 0 && S->state == 1) {
                    /* Sort the surface in by 1/z at this pixel. */
                    int j = 0;
                    while (j < n - 1 && !nearer(p, s, p->stack[j], x, y))
                        j++;
                    memmove(&p->stack[j + 1], &p->stack[j], sizeof(int) * (size_t)(n - j));
                    p->stack[j] = s;
                    n++;
                } else if (E->lead < 0 && S->state == 0) {
                    int j = 0;
                    while (j < n - 1 && p->stack[j] != s)
                        j++;
                    if (j == n - 1)
                        continue;  /* not in the stack (its leading edge is later) */
                    memmove(&p->stack[j], &p->stack[j + 1], sizeof(int) * (size_t)(n - j - 1));
                    n--;
                    /* The next one down was sorted at its own start; planes
                     * may have crossed since.  Independent sorting trusts it. */
                    if (j == 0 && p->crossings_on)
                        resort(p, n, x, y);
                }
            }
            i--;  /* the for loop steps past the last edge of the pixel */
            if (p->stack[0] != top) {
                if (push_span(p, y, start, x, top) < 0)
                    return -1;
                top = p->stack[0], start = x;
            }
        }
        if (push_span(p, y, start, W, top) < 0)
            return -1;
        /* Surfaces left half-open by rounding start the next row clean. */
        for (int i = 0; i < nael; i++)
            p->surfs[p->edges[p->ael[i]].surf].state = 0;
    }
    p->st.spans = p->nspans;
    return 0;
}

static int check_args(const ew_polyhedra *p, double t, const uint8_t *pixels, ew_error *err) {
    if (!p || !pixels)
        return ew_fail(err, "polyhedra: no %s", p ? "frame buffer" : "scene");
    if (!isfinite(t) || fabs(t) > 1e6)
        return ew_fail(err, "polyhedra: time %g (must be a finite number of seconds, at most 1e6 either way)", t);
    return 0;
}

int ew_polyhedra_render(ew_polyhedra *p, double time, uint8_t *pixels, ew_polyhedra_stats *st,
                        ew_error *err) {
    if (check_args(p, time, pixels, err) < 0)
        return -1;
    build(p, time);
    if (scan(p) < 0)
        return ew_fail(err, "polyhedra: out of memory for spans");
    /* Step 4: every span once, every pixel once. */
    for (int i = 0; i < p->nspans; i++) {
        const ew_polyhedra_span *s = &p->spans[i];
        memset(pixels + (size_t)s->y * p->width + s->x, s->color, (size_t)s->count);
        p->st.pixels += s->count;
    }
    if (st)
        *st = p->st;
    return 0;
}

/* ---- the check: a z-buffer of the same polygons ------------------------------ */

int ew_polyhedra_render_zbuffer(ew_polyhedra *p, double time, uint8_t *pixels,
                                ew_polyhedra_stats *st, ew_error *err) {
    if (check_args(p, time, pixels, err) < 0)
        return -1;
    size_t npix = (size_t)p->width * p->height;
    if (!p->zbuf && !(p->zbuf = malloc(sizeof *p->zbuf * npix)))
        return ew_fail(err, "polyhedra: out of memory for the z-buffer");
    build(p, time);
    memset(pixels, p->surfs[BACKGROUND].color, npix);
    for (size_t i = 0; i < npix; i++)
        p->zbuf[i] = p->surfs[BACKGROUND].c;
    p->st.pixels = (long long)npix;
    for (int s = 1; s < p->nsurfs; s++) {
        const surf *S = &p->surfs[s];
        const edge *E = &p->edges[S->first_edge];
        int y0 = p->height, y1 = 0;
        for (int i = 0; i < S->nedges; i++) {
            if (E[i].ytop < y0) y0 = E[i].ytop;
            if (E[i].ybot > y1) y1 = E[i].ybot;
        }
        for (int y = y0; y < y1; y++) {
            /* The row's edges of this polygon, sorted by first pixel; a pixel
             * is inside where more leading than trailing edges start at or
             * left of it: the rule the scan's surface states follow. */
            int px[MAX_CLIP_VERTS], lead[MAX_CLIP_VERTS], m = 0;
            for (int i = 0; i < S->nedges; i++) {
                if (y < E[i].ytop || y >= E[i].ybot)
                    continue;
                int x = edge_px(p, &E[i], y), j = m++;
                while (j > 0 && px[j - 1] > x) {
                    px[j] = px[j - 1], lead[j] = lead[j - 1];
                    j--;
                }
                px[j] = x, lead[j] = E[i].lead;
            }
            int state = 0;
            for (int i = 0; i < m; i++) {
                state += lead[i];
                int x1 = i + 1 < m ? px[i + 1] : p->width;
                if (state < 1)
                    continue;
                for (int x = px[i]; x < x1; x++) {
                    double z = zinv(S, x, y);
                    size_t o = (size_t)y * p->width + x;
                    if (z > p->zbuf[o]) {
                        p->zbuf[o] = z;
                        pixels[o] = S->color;
                        p->st.pixels++;
                    }
                }
            }
        }
    }
    for (size_t i = 0; i < npix; i++)
        p->st.covered += p->zbuf[i] > p->surfs[BACKGROUND].c;
    if (st)
        *st = p->st;
    return 0;
}
