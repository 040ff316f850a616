/*
 * Map generator: light map samples (with shadows found by walking the
 * cells a light ray crosses, so they match the geometry exactly) and the
 * potentially visible set (a conservative portal flow over the leaves).
 */
#include "mapgen_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int bi_trace(const bi_grid *g, const float a[3], const float b[3]) {
    double p[3], d[3], tmax[3], tdelta[3];
    int c[3], step[3];
    for (int k = 0; k < 3; k++) {
        p[k] = a[k];
        d[k] = (double)b[k] - a[k];
        c[k] = (int)floor(p[k] / BI_CELL);
        if (d[k] > 0) {
            step[k] = 1;
            tmax[k] = ((c[k] + 1) * (double)BI_CELL - p[k]) / d[k];
            tdelta[k] = BI_CELL / d[k];
        } else if (d[k] < 0) {
            step[k] = -1;
            tmax[k] = (c[k] * (double)BI_CELL - p[k]) / d[k];
            tdelta[k] = -BI_CELL / d[k];
        } else {
            step[k] = 0;
            tmax[k] = tdelta[k] = HUGE_VAL;
        }
    }
    for (;;) {
        int kind = bi_kind(g, c[0], c[1], c[2]);
        if (kind == BI_SOLID || kind == BI_SKY) return kind;
        int ax = tmax[0] < tmax[1] ? (tmax[0] < tmax[2] ? 0 : 2) : (tmax[1] < tmax[2] ? 1 : 2);
        if (tmax[ax] > 1.0) return -1;
        c[ax] += step[ax];
        tmax[ax] += tdelta[ax];
    }
}

/* What light l adds at point p of a surface facing n: linear falloff to
 * its reach, by the cosine, nothing if the grid blocks it. */
static double light_reach(const bi_scene *s, const bi_light *l, const float p[3], const float n[3]) {
    double d[3] = {l->origin[0] - p[0], l->origin[1] - p[1], l->origin[2] - p[2]};
    double dist = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (dist >= l->intensity) return 0;
    double c = dist < 1 ? 1 : (d[0] * n[0] + d[1] * n[1] + d[2] * n[2]) / dist;
    if (c <= 0 || bi_trace(&s->grid, p, l->origin) >= 0) return 0;
    return (l->intensity - dist) * c;
}

int bi_light_point(const bi_scene *s, const float p[3], const float n[3]) {
    double total = s->ambient;
    for (int i = 0; i < s->nlights; i++) total += light_reach(s, &s->lights[i], p, n);
    /* sunlight: the surface sees the sky looking back along the sun's rays */
    double c = -(s->sun_dir[0] * n[0] + s->sun_dir[1] * n[1] + s->sun_dir[2] * n[2]);
    if (s->sun_intensity > 0 && c > 0) {
        float far[3];
        for (int k = 0; k < 3; k++) far[k] = p[k] - s->sun_dir[k] * 8192.0f;
        if (bi_trace(&s->grid, p, far) == BI_SKY) total += s->sun_intensity * c;
    }
    return total < 0 ? 0 : total > 255 ? 255 : (int)lrint(total);
}

int bi_light_point_rgb(const bi_scene *s, const float p[3], const float n[3], uint8_t rgb[3]) {
    int mono = bi_light_point(s, p, n);
    const float *tint = s->opt ? s->opt->light_tint : NULL;
    if (!tint) {
        rgb[0] = rgb[1] = rgb[2] = (uint8_t)mono;
        return mono;
    }
    double total[3] = {s->ambient, s->ambient, s->ambient};
    for (int i = 0; i < s->nlights && i < EW_MAPGEN_MAX_LIGHTS; i++) {
        double add = light_reach(s, &s->lights[i], p, n);
        for (int k = 0; k < 3; k++) total[k] += add * tint[3 * i + k];
    }
    double c = -(s->sun_dir[0] * n[0] + s->sun_dir[1] * n[1] + s->sun_dir[2] * n[2]);
    if (s->sun_intensity > 0 && c > 0) {
        float far[3];
        for (int k = 0; k < 3; k++) far[k] = p[k] - s->sun_dir[k] * 8192.0f;
        if (bi_trace(&s->grid, p, far) == BI_SKY)
            for (int k = 0; k < 3; k++) total[k] += s->sun_intensity * c;
    }
    for (int k = 0; k < 3; k++) rgb[k] = (uint8_t)(total[k] < 0 ? 0 : total[k] > 255 ? 255 : lrint(total[k]));
    return mono;
}

/* ---- PVS ------------------------------------------------------------------- */

/* Portal flow over the leaf boxes.  Open leaves that share a face area are
 * joined by a portal (one each way).  A line of sight from leaf S crosses
 * a chain of portals; for each portal P out of S we follow chains while
 * some line can still pass through all of them.  The test keeps, on every
 * step, only the part of the next portal that lies beyond the planes
 * separating the source portal from the last one passed (the region lit
 * by an area light shining through a window), so the result is a
 * superset of the truly visible leaves: a leaf may be kept that is not
 * visible, but never dropped when it is.  Each portal is first given a
 * cheap "might see" set by flooding through portals that face away from
 * it; chains stop once they can add nothing new to the portal's set. */

#define WMAX 48
#define PEPS 0.01

typedef struct winding {
    int    n;
    double p[WMAX][3];
} winding;

typedef struct vportal {
    int      from, to;
    double   normal[3], dist;  /* normal points into 'to' */
    winding  w;
    uint8_t *might, *vis;      /* per leaf */
    int      nmight, done;
} vportal;

typedef struct vctx {
    int       nleaves, nportals;
    vportal  *portals;
    int      *first, *count, *list;  /* portals leaving each leaf */
    uint8_t  *onpath;
} vctx;

static double wdist(const double n[3], double d, const double p[3]) {
    return n[0] * p[0] + n[1] * p[1] + n[2] * p[2] - d;
}

/* Keeps the part of w with distance >= -PEPS (conservative). */
static void clip(winding *w, const double n[3], double d) {
    double dist[WMAX];
    int front = 0, back = 0;
    for (int i = 0; i < w->n; i++) {
        dist[i] = wdist(n, d, w->p[i]);
        front += dist[i] >= -PEPS;
        back += dist[i] < -PEPS;
    }
    if (!back) return;
    if (!front) { w->n = 0; return; }
    winding out;
    out.n = 0;
    for (int i = 0; i < w->n && out.n < WMAX - 1; i++) {
        int j = (i + 1) % w->n;
        if (dist[i] >= -PEPS) memcpy(out.p[out.n++], w->p[i], sizeof out.p[0]);
        if ((dist[i] >= -PEPS) != (dist[j] >= -PEPS)) {
            double t = (dist[i] + PEPS) / (dist[i] - dist[j]);
            for (int k = 0; k < 3; k++) out.p[out.n][k] = w->p[i][k] + t * (w->p[j][k] - w->p[i][k]);
            out.n++;
        }
    }
    if (out.n >= WMAX - 1) return;  /* too complex: keep it whole */
    /* drop repeated points (cuts through a vertex make them) */
    w->n = 0;
    for (int i = 0; i < out.n; i++) {
        const double *p = out.p[i], *q = w->n ? w->p[w->n - 1] : out.p[out.n - 1];
        if (fabs(p[0] - q[0]) + fabs(p[1] - q[1]) + fabs(p[2] - q[2]) < 1e-3 && !(i == 0 && out.n == 1)) continue;
        memcpy(w->p[w->n++], p, sizeof w->p[0]);
    }
}

/* The planes that separate a from b (a behind, b in front) and hold an
 * edge of one and a vertex of the other: a line through a and then b can
 * only continue in front of all of them.  planes needs room for
 * 2 * a->n * b->n entries of (normal, dist); returns the count. */
static int separators(const winding *a, const winding *b, double (*planes)[4]) {
    int count = 0;
    for (int pass = 0; pass < 2; pass++) {
        const winding *e = pass ? b : a, *v = pass ? a : b;
        for (int i = 0; i < e->n; i++) {
            const double *p0 = e->p[i], *p1 = e->p[(i + 1) % e->n];
            for (int j = 0; j < v->n; j++) {
                const double *q = v->p[j];
                double u[3], w[3], n[3];
                for (int k = 0; k < 3; k++) u[k] = p1[k] - p0[k], w[k] = q[k] - p0[k];
                n[0] = u[1] * w[2] - u[2] * w[1];
                n[1] = u[2] * w[0] - u[0] * w[2];
                n[2] = u[0] * w[1] - u[1] * w[0];
                double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
                if (len < 1e-6) continue;
                for (int k = 0; k < 3; k++) n[k] /= len;
                double d = n[0] * p0[0] + n[1] * p0[1] + n[2] * p0[2];
                /* which sides each winding reaches; stop as soon as it is both */
                int apos = 0, aneg = 0, bpos = 0, bneg = 0;
                for (int k = 0; k < a->n && !(apos && aneg); k++) {
                    double t = n[0] * a->p[k][0] + n[1] * a->p[k][1] + n[2] * a->p[k][2] - d;
                    apos |= t > PEPS, aneg |= t < -PEPS;
                }
                if (apos && aneg) continue;
                for (int k = 0; k < b->n && !(bpos && bneg); k++) {
                    double t = n[0] * b->p[k][0] + n[1] * b->p[k][1] + n[2] * b->p[k][2] - d;
                    bpos |= t > PEPS, bneg |= t < -PEPS;
                }
                double sign;
                if (!apos && !bneg && bpos) sign = 1;
                else if (!aneg && !bpos && bneg) sign = -1;
                else continue;
                for (int k = 0; k < 3; k++) planes[count][k] = sign * n[k];
                planes[count][3] = sign * d;
                count++;
            }
        }
    }
    return count;
}

static void clip_planes(winding *w, double (*planes)[4], int count) {
    for (int i = 0; i < count && w->n; i++) clip(w, planes[i], planes[i][3]);
}

/* Largest distance of w in front of a portal's plane. */
static double front_extent(const vportal *p, const winding *w) {
    double m = -HUGE_VAL;
    for (int i = 0; i < w->n; i++) {
        double t = wdist(p->normal, p->dist, w->p[i]);
        m = t > m ? t : m;
    }
    return m;
}

static void base_flood(vctx *v, vportal *p, int leaf) {
    if (p->might[leaf]) return;
    p->might[leaf] = 1;
    p->nmight++;
    for (int i = 0; i < v->count[leaf]; i++) {
        const vportal *q = &v->portals[v->list[v->first[leaf] + i]];
        /* q must reach in front of p, and p must lie partly behind q */
        if (front_extent(p, &q->w) <= PEPS) continue;
        double behind = HUGE_VAL;
        for (int k = 0; k < p->w.n; k++) {
            double t = wdist(q->normal, q->dist, p->w.p[k]);
            behind = t < behind ? t : behind;
        }
        if (behind >= -PEPS) continue;
        base_flood(v, p, q->to);
    }
}

static int flow(vctx *v, vportal *src_portal, int leaf, const winding *src, const winding *pass,
                const uint8_t *might) {
    int n = v->nleaves;
    src_portal->vis[leaf] = 1;
    uint8_t *next = malloc((size_t)n);
    winding *target = malloc(sizeof *target);
    /* the separators of (src, pass) serve every portal out of this leaf */
    double (*sep)[4] = pass ? malloc(sizeof *sep * 2 * (size_t)src->n * pass->n) : NULL;
    int rc = -1;
    if (!next || !target || (pass && !sep)) goto done;
    int nsep = pass ? separators(src, pass, sep) : 0;
    rc = 0;
    for (int i = 0; i < v->count[leaf] && rc == 0; i++) {
        vportal *q = &v->portals[v->list[v->first[leaf] + i]];
        int m = q->to;
        if (!might[m] || v->onpath[m]) continue;
        const uint8_t *qs = q->done ? q->vis : q->might;
        int more = 0;
        for (int k = 0; k < n; k++) {
            next[k] = might[k] & qs[k];
            more |= next[k] & !src_portal->vis[k];
        }
        if (!more && src_portal->vis[m]) continue;  /* nothing new down this way */
        *target = q->w;
        clip(target, src_portal->normal, src_portal->dist);
        if (!target->n || front_extent(src_portal, target) <= PEPS) continue;
        clip_planes(target, sep, nsep);
        if (!target->n) continue;
        v->onpath[m] = 1;
        rc = flow(v, src_portal, m, src, target, next);
        v->onpath[m] = 0;
    }
done:
    free(next), free(target), free(sep);
    return rc;
}

int bi_compute_pvs(int n, const int (*lo)[3], const int (*hi)[3], const uint8_t *open, uint8_t *vis) {
    vctx v;
    memset(&v, 0, sizeof v);
    v.nleaves = n;
    int cap = 0, rc = -1;
    int *order = NULL;
    v.first = calloc((size_t)n, sizeof *v.first);
    v.count = calloc((size_t)n, sizeof *v.count);
    v.onpath = calloc((size_t)n, 1);
    if (!v.first || !v.count || !v.onpath) goto done;
    /* portals: shared face areas of open leaf boxes */
    for (int a = 0; a < n; a++)
        for (int b = 0; b < n; b++) {
            if (a == b || !open[a] || !open[b]) continue;
            for (int k = 0; k < 3; k++) {
                int s = hi[a][k] == lo[b][k] ? 1 : hi[b][k] == lo[a][k] ? -1 : 0;
                int u = (k + 1) % 3, w = (k + 2) % 3;
                int u0 = lo[a][u] > lo[b][u] ? lo[a][u] : lo[b][u], u1 = hi[a][u] < hi[b][u] ? hi[a][u] : hi[b][u];
                int w0 = lo[a][w] > lo[b][w] ? lo[a][w] : lo[b][w], w1 = hi[a][w] < hi[b][w] ? hi[a][w] : hi[b][w];
                if (!s || u0 >= u1 || w0 >= w1) continue;
                if (v.nportals == cap) {
                    cap = cap ? cap * 2 : 256;
                    vportal *np = realloc(v.portals, sizeof *np * (size_t)cap);
                    if (!np) goto done;
                    v.portals = np;
                }
                vportal *p = &v.portals[v.nportals++];
                memset(p, 0, sizeof *p);
                p->to = b;
                p->normal[k] = s;
                p->dist = s * (double)(s > 0 ? hi[a][k] : lo[a][k]);
                const int cu[4] = {u0, u1, u1, u0}, cw[4] = {w0, w0, w1, w1};
                p->w.n = 4;
                for (int c = 0; c < 4; c++) {
                    p->w.p[c][k] = s > 0 ? hi[a][k] : lo[a][k];
                    p->w.p[c][u] = cu[c], p->w.p[c][w] = cw[c];
                }
                p->from = a;
                v.count[a]++;
            }
        }
    v.list = malloc(sizeof *v.list * ((size_t)v.nportals + 1));
    order = malloc(sizeof *order * ((size_t)v.nportals + 1));
    if (!v.list || !order) goto done;
    for (int a = 1; a < n; a++) v.first[a] = v.first[a - 1] + v.count[a - 1];
    memset(v.count, 0, sizeof *v.count * (size_t)n);
    for (int i = 0; i < v.nportals; i++) {
        int a = v.portals[i].from;
        v.list[v.first[a] + v.count[a]++] = i;
    }
    for (int i = 0; i < v.nportals; i++) {
        vportal *p = &v.portals[i];
        p->might = calloc((size_t)n, 1);
        p->vis = calloc((size_t)n, 1);
        if (!p->might || !p->vis) goto done;
        base_flood(&v, p, p->to);
        order[i] = i;
    }
    /* portals that might see least first: their results then prune the rest */
    for (int i = 1; i < v.nportals; i++)
        for (int j = i; j > 0 && v.portals[order[j]].nmight < v.portals[order[j - 1]].nmight; j--) {
            int t = order[j];
            order[j] = order[j - 1], order[j - 1] = t;
        }
    for (int i = 0; i < v.nportals; i++) {
        vportal *p = &v.portals[order[i]];
        v.onpath[p->to] = 1;
        int frc = flow(&v, p, p->to, &p->w, NULL, p->might);
        v.onpath[p->to] = 0;
        if (frc) goto done;
        p->done = 1;
    }
    memset(vis, 0, (size_t)n * n);
    for (int a = 0; a < n; a++) {
        if (!open[a]) continue;
        vis[(size_t)a * n + a] = 1;
        for (int i = 0; i < v.count[a]; i++) {
            const vportal *p = &v.portals[v.list[v.first[a] + i]];
            for (int b = 0; b < n; b++)
                if (p->vis[b]) vis[(size_t)a * n + b] = vis[(size_t)b * n + a] = 1;
        }
    }
    rc = 0;
done:
    for (int i = 0; i < v.nportals; i++) free(v.portals[i].might), free(v.portals[i].vis);
    free(v.portals), free(v.first), free(v.count), free(v.list), free(v.onpath), free(order);
    return rc;
}
