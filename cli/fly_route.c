/*
 * fly_route.c - fly's default camera path through open space (fly_route.h).
 *
 * Open: a point whose contents (rendering hull) are neither solid nor sky
 * (the sky's leaves are the outside of the map; traces pass through them,
 * so they are looked for along every segment too).  A segment is clear
 * when the point trace along it hits nothing, the same trace shifted by the
 * eye's margin along each axis hits nothing where it starts and ends in the
 * open, and no point sampled along it is in the sky.
 */
#include "fly_route.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define GRID        32.0    /* the search grid's step, units */
#define MARGIN      16.0    /* room kept around the eye, units */
#define MAX_NODES   200000  /* grid points looked at for one leg */
#define SKY_STEP    16.0    /* sky samples along a segment, units apart */
#define ARC_SAMPLES 32      /* arc-length table entries per spline piece */
#define CHECK_STEP  4.0     /* spline samples checked, units apart */

struct fly_route {
    int      nw, *view_at, nkept;
    double (*w)[3];         /* waypoints */
    unsigned char *linear;  /* per piece: drawn straight */
    double  *cum;           /* per piece: ARC_SAMPLES + 1 arc lengths from its start */
};

/* ---- open space ------------------------------------------------------------ */

static int open_at(const ew_world *w, const double p[3]) {
    float f[3] = { (float)p[0], (float)p[1], (float)p[2] };
    int c = ew_point_contents(w, EW_HULL_POINT, f);
    return c != EW_CONTENTS_SOLID && c != EW_CONTENTS_SKY;
}

/* The point and the points MARGIN from it along each axis are open. */
static int roomy_at(const ew_world *w, const double p[3]) {
    if (!open_at(w, p)) return 0;
    for (int k = 0; k < 3; k++)
        for (int s = -1; s <= 1; s += 2) {
            double q[3] = { p[0], p[1], p[2] };
            q[k] += s * MARGIN;
            if (!open_at(w, q)) return 0;
        }
    return 1;
}

static int trace_clear(const ew_world *w, const double a[3], const double b[3]) {
    float fa[3] = { (float)a[0], (float)a[1], (float)a[2] }, fb[3] = { (float)b[0], (float)b[1], (float)b[2] };
    ew_trace_result tr;
    return ew_trace(w, EW_HULL_POINT, fa, fb, &tr) == 0 && tr.fraction >= 1 && !tr.startsolid;
}

static double dist(const double a[3], const double b[3]) {
    double x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
    return sqrt(x * x + y * y + z * z);
}

static int clear(const ew_world *w, const double a[3], const double b[3]) {
    if (!trace_clear(w, a, b)) return 0;
    for (int k = 0; k < 3; k++)
        for (int s = -1; s <= 1; s += 2) {
            double a2[3] = { a[0], a[1], a[2] }, b2[3] = { b[0], b[1], b[2] };
            a2[k] += s * MARGIN, b2[k] += s * MARGIN;
            if (open_at(w, a2) && open_at(w, b2) && !trace_clear(w, a2, b2)) return 0;
        }
    int n = (int)(dist(a, b) / SKY_STEP);
    for (int i = 1; i <= n; i++) {
        double f = (double)i / (n + 1), p[3];
        for (int k = 0; k < 3; k++) p[k] = a[k] + (b[k] - a[k]) * f;
        if (!open_at(w, p)) return 0;
    }
    return 1;
}

/* ---- A* over the grid ------------------------------------------------------ */

typedef struct node {
    int    ijk[3], parent, state;  /* state: 0 not looked at, 1 open, 2 blocked */
    double g;
    int    closed;
} node;

typedef struct search {
    node  *n;
    int    nn, cap;
    int   *hash;     /* node index + 1, 0 empty */
    size_t hcap;
    struct hent { double f; int i; } *heap;
    int    nh, heapcap;
} search;

static size_t hash_ijk(const int ijk[3]) {
    unsigned h = (unsigned)ijk[0] * 73856093u ^ (unsigned)ijk[1] * 19349663u ^ (unsigned)ijk[2] * 83492791u;
    return h;
}

/* The node at ijk, made if new; -1 when out of memory or over MAX_NODES. */
static int node_at(search *s, const int ijk[3]) {
    size_t m = s->hcap - 1, h = hash_ijk(ijk) & m;
    while (s->hash[h]) {
        node *e = &s->n[s->hash[h] - 1];
        if (e->ijk[0] == ijk[0] && e->ijk[1] == ijk[1] && e->ijk[2] == ijk[2]) return s->hash[h] - 1;
        h = (h + 1) & m;
    }
    if (s->nn >= MAX_NODES) return -1;
    if (s->nn == s->cap) {
        int cap = s->cap ? s->cap * 2 : 4096;
        node *q = realloc(s->n, sizeof *q * (size_t)cap);
        if (!q) return -1;
        s->n = q, s->cap = cap;
    }
    node *e = &s->n[s->nn];
    memset(e, 0, sizeof *e);
    memcpy(e->ijk, ijk, sizeof e->ijk);
    e->parent = -1;
    e->g = INFINITY;
    s->hash[h] = ++s->nn;
    return s->nn - 1;
}

static int heap_push(search *s, double f, int i) {
    if (s->nh == s->heapcap) {
        int cap = s->heapcap ? s->heapcap * 2 : 4096;
        struct hent *q = realloc(s->heap, sizeof *q * (size_t)cap);
        if (!q) return -1;
        s->heap = q, s->heapcap = cap;
    }
    int k = s->nh++;
    while (k > 0 && s->heap[(k - 1) / 2].f > f) {
        s->heap[k] = s->heap[(k - 1) / 2];
        k = (k - 1) / 2;
    }
    s->heap[k].f = f, s->heap[k].i = i;
    return 0;
}

static int heap_pop(search *s) {
    int top = s->heap[0].i;
    struct hent last = s->heap[--s->nh];
    int k = 0;
    for (;;) {
        int c = 2 * k + 1;
        if (c >= s->nh) break;
        if (c + 1 < s->nh && s->heap[c + 1].f < s->heap[c].f) c++;
        if (s->heap[c].f >= last.f) break;
        s->heap[k] = s->heap[c];
        k = c;
    }
    if (s->nh) s->heap[k] = last;
    return top;
}

static void grid_pos(const double a[3], const int ijk[3], double p[3]) {
    for (int k = 0; k < 3; k++) p[k] = a[k] + GRID * ijk[k];
}

/* Grid points from a to b (a first, b not included) in *out; their count,
 * 0 when none reaches b, -1 out of memory. */
static int grid_path(const ew_world *w, const double a[3], const double b[3], double (**out)[3]) {
    search s;
    memset(&s, 0, sizeof s);
    s.hcap = 1u << 19;  /* > 2 * MAX_NODES */
    s.hash = calloc(s.hcap, sizeof *s.hash);
    int found = -1, rc = -1;
    if (!s.hash) goto done;
    int zero[3] = { 0, 0, 0 };
    int start = node_at(&s, zero);
    if (start < 0) goto done;
    s.n[start].g = 0, s.n[start].state = 1;
    if (heap_push(&s, dist(a, b), start) < 0) goto done;
    static const int dirs[6][3] = { { 1, 0, 0 }, { -1, 0, 0 }, { 0, 1, 0 }, { 0, -1, 0 }, { 0, 0, 1 }, { 0, 0, -1 } };
    int full = 0;
    while (s.nh && found < 0) {
        int i = heap_pop(&s);
        if (s.n[i].closed) continue;
        s.n[i].closed = 1;
        double p[3];
        grid_pos(a, s.n[i].ijk, p);
        if (fabs(p[0] - b[0]) <= GRID && fabs(p[1] - b[1]) <= GRID && fabs(p[2] - b[2]) <= GRID && clear(w, p, b)) {
            found = i;
            break;
        }
        for (int d = 0; d < 6 && !full; d++) {
            int q[3] = { s.n[i].ijk[0] + dirs[d][0], s.n[i].ijk[1] + dirs[d][1], s.n[i].ijk[2] + dirs[d][2] };
            int j = node_at(&s, q);
            if (j < 0) {
                full = 1;  /* the budget is spent: finish what is queued */
                break;
            }
            node *e = &s.n[j];
            double qp[3];
            grid_pos(a, q, qp);
            if (!e->state) e->state = roomy_at(w, qp) ? 1 : 2;
            if (e->state != 1 || e->closed) continue;
            double g = s.n[i].g + GRID;
            if (g >= e->g) continue;
            if (!trace_clear(w, p, qp)) continue;
            e->g = g, e->parent = i;
            /* weighted: fewer points looked at for a path a little longer */
            if (heap_push(&s, g + 1.5 * dist(qp, b), j) < 0) goto done;
        }
    }
    rc = 0;
    if (found >= 0) {
        int len = 0;
        for (int i = found; i >= 0; i = s.n[i].parent) len++;
        double (*pts)[3] = malloc(sizeof *pts * (size_t)len);
        if (!pts) {
            rc = -1;
            goto done;
        }
        int k = len;
        for (int i = found; i >= 0; i = s.n[i].parent) grid_pos(a, s.n[i].ijk, pts[--k]);
        *out = pts;
        rc = len;
    }
done:
    free(s.n);
    free(s.hash);
    free(s.heap);
    return rc;
}

/* ---- the route --------------------------------------------------------------- */

static int push_point(fly_route *r, int *cap, const double p[3]) {
    if (r->nw == *cap) {
        int c = *cap ? *cap * 2 : 64;
        double (*q)[3] = realloc(r->w, sizeof *q * (size_t)c);
        if (!q) return -1;
        r->w = q, *cap = c;
    }
    memcpy(r->w[r->nw++], p, sizeof r->w[0]);
    return 0;
}

/* Centripetal Catmull-Rom through p1..p2 (p0, p3 its neighbours) at u 0..1. */
static void centripetal(const double *p0, const double *p1, const double *p2, const double *p3, double u,
                        double out[3]) {
    double t0 = 0, t1 = t0 + fmax(sqrt(dist(p0, p1)), 1e-3), t2 = t1 + fmax(sqrt(dist(p1, p2)), 1e-3),
           t3 = t2 + fmax(sqrt(dist(p2, p3)), 1e-3);
    double t = t1 + (t2 - t1) * u;
    for (int k = 0; k < 3; k++) {
        double a1 = ((t1 - t) * p0[k] + (t - t0) * p1[k]) / (t1 - t0);
        double a2 = ((t2 - t) * p1[k] + (t - t1) * p2[k]) / (t2 - t1);
        double a3 = ((t3 - t) * p2[k] + (t - t2) * p3[k]) / (t3 - t2);
        double b1 = ((t2 - t) * a1 + (t - t0) * a2) / (t2 - t0);
        double b2 = ((t3 - t) * a2 + (t - t1) * a3) / (t3 - t1);
        out[k] = ((t2 - t) * b1 + (t - t1) * b2) / (t2 - t1);
    }
}

/* Piece q (waypoint q to q + 1) at u. */
static void piece_at(const fly_route *r, int q, double u, double out[3]) {
    const double *p1 = r->w[q], *p2 = r->w[q + 1];
    if (r->linear[q]) {
        for (int k = 0; k < 3; k++) out[k] = p1[k] + (p2[k] - p1[k]) * u;
        return;
    }
    double p0[3], p3[3];
    for (int k = 0; k < 3; k++) {
        p0[k] = q > 0 ? r->w[q - 1][k] : 2 * p1[k] - p2[k];
        p3[k] = q + 2 < r->nw ? r->w[q + 2][k] : 2 * p2[k] - p1[k];
    }
    centripetal(p0, p1, p2, p3, u, out);
}

/* The spline piece stays in the open: samples CHECK_STEP apart, each open,
 * each joined to the one before by a clear point trace. */
static int piece_open(const ew_world *w, const fly_route *r, int q) {
    int n = (int)ceil(dist(r->w[q], r->w[q + 1]) * 1.5 / CHECK_STEP);
    if (n < 8) n = 8;
    if (n > 4096) n = 4096;
    double prev[3];
    memcpy(prev, r->w[q], sizeof prev);
    for (int i = 1; i <= n; i++) {
        double p[3];
        piece_at(r, q, (double)i / n, p);
        if (!open_at(w, p) || !trace_clear(w, prev, p)) return 0;
        memcpy(prev, p, sizeof prev);
    }
    return 1;
}

fly_route *fly_route_build(const ew_world *w, const double (*pos)[3], int n, int *kept, int *nkept) {
    *nkept = 0;
    fly_route *r = calloc(1, sizeof *r);
    if (!r || !(r->view_at = malloc(sizeof *r->view_at * (size_t)(n > 0 ? n : 1)))) goto fail;
    int cap = 0, cur = -1;
    for (int v = 0; v < n; v++) {
        if (!open_at(w, pos[v])) continue;  /* its eye is in solid or the sky */
        if (cur < 0) {
            if (push_point(r, &cap, pos[v]) < 0) goto fail;
        } else if (clear(w, pos[cur], pos[v])) {
            if (push_point(r, &cap, pos[v]) < 0) goto fail;
        } else {
            double (*g)[3] = NULL;
            int len = grid_path(w, pos[cur], pos[v], &g);
            if (len < 0) goto fail;
            if (len == 0) continue;  /* no open path reaches it */
            /* g[0] is the view before; b after g[len - 1].  Cut corners:
             * from each point, on to the farthest one in clear sight. */
            double (*pts)[3] = malloc(sizeof *pts * (size_t)(len + 1));
            if (!pts) {
                free(g);
                goto fail;
            }
            memcpy(pts, g, sizeof *pts * (size_t)len);
            memcpy(pts[len], pos[v], sizeof pts[0]);
            free(g);
            int i = 0;
            while (i < len) {
                int j = len;
                while (j > i + 1 && !clear(w, pts[i], pts[j])) j--;
                if (push_point(r, &cap, pts[j]) < 0) {
                    free(pts);
                    goto fail;
                }
                i = j;
            }
            free(pts);
        }
        r->view_at[*nkept] = r->nw - 1;
        kept[(*nkept)++] = v;
        cur = v;
    }
    r->nkept = *nkept;
    if (!r->nw) goto fail;
    int pieces = r->nw - 1;
    r->linear = calloc((size_t)(pieces > 0 ? pieces : 1), 1);
    r->cum = malloc(sizeof *r->cum * (size_t)(pieces > 0 ? pieces : 1) * (ARC_SAMPLES + 1));
    if (!r->linear || !r->cum) goto fail;
    for (int q = 0; q < pieces; q++) {
        if (!piece_open(w, r, q)) r->linear[q] = 1;
        double *c = r->cum + (size_t)q * (ARC_SAMPLES + 1), prev[3];
        memcpy(prev, r->w[q], sizeof prev);
        c[0] = 0;
        for (int s = 1; s <= ARC_SAMPLES; s++) {
            double p[3];
            piece_at(r, q, (double)s / ARC_SAMPLES, p);
            c[s] = c[s - 1] + dist(prev, p);
            memcpy(prev, p, sizeof prev);
        }
    }
    return r;
fail:
    *nkept = 0;
    fly_route_destroy(r);
    return NULL;
}

void fly_route_eye(const fly_route *r, int leg, double u, double out[3]) {
    if (leg < 0) leg = 0, u = 0;
    if (leg >= r->nkept - 1) {
        memcpy(out, r->w[r->view_at[r->nkept - 1]], sizeof r->w[0]);
        return;
    }
    int q0 = r->view_at[leg], q1 = r->view_at[leg + 1];
    double total = 0;
    for (int q = q0; q < q1; q++) total += r->cum[(size_t)q * (ARC_SAMPLES + 1) + ARC_SAMPLES];
    double s = (u < 0 ? 0 : u > 1 ? 1 : u) * total;
    for (int q = q0; q < q1; q++) {
        const double *c = r->cum + (size_t)q * (ARC_SAMPLES + 1);
        if (s > c[ARC_SAMPLES] && q + 1 < q1) {
            s -= c[ARC_SAMPLES];
            continue;
        }
        int k = 0;
        while (k < ARC_SAMPLES - 1 && c[k + 1] < s) k++;
        double span = c[k + 1] - c[k], f = span > 0 ? (s - c[k]) / span : 0;
        if (f < 0) f = 0;
        if (f > 1) f = 1;
        piece_at(r, q, (k + f) / ARC_SAMPLES, out);
        return;
    }
    memcpy(out, r->w[q1], sizeof r->w[0]);
}

void fly_route_destroy(fly_route *r) {
    if (!r) return;
    free(r->w);
    free(r->view_at);
    free(r->linear);
    free(r->cum);
    free(r);
}
