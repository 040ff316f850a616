/* The screen polygons of the frame's surfaces (see surf_poly.h): recorded
 * serially as the walk hands faces over, read by the bands in parallel. */
#include "hsr/surf_poly.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int ew_line_norm(double a, double b, double c, ew_line *out) {
    double len = sqrt(a * a + b * b);
    if (!(len > 0)) return 0;
    out->a = a, out->b = b, out->c = c, out->inv = 1 / len, out->grid = 0;
    return 1;
}

int ew_line_through(double x0, double y0, double x1, double y1, ew_line *out) {
    /* Each term changes sign exactly when the ends swap. */
    if (!ew_line_norm(y0 - y1, x1 - x0, x0 * y1 - x1 * y0, out)) return 0;
    out->grid = 1;
    return 1;
}

/* Doubles *cap (from first) until it holds need elements; 0 if it could. */
static int reserve(void **arr, int *cap, int need, size_t elem, int first) {
    if (need <= *cap) return 0;
    int n = *cap ? *cap : first;
    while (n < need) n *= 2;
    void *p = realloc(*arr, elem * (size_t)n);
    if (!p) return -1;
    *arr = p, *cap = n;
    return 0;
}

ew_spolys *ew_spolys_begin(ew_hsr_ctx *c) {
    ew_edge_begin(c);
    ew_spolys *sp = c->spolys;
    if (!sp) {
        sp = c->spolys = calloc(1, sizeof *sp);
        if (!sp) return NULL;
    }
    int nf = c->f->world->numfaces;
    if (sp->nfaces != nf) {
        free(sp->face_surf), free(sp->face_frame);
        sp->face_surf = malloc(sizeof(int) * (size_t)nf);
        sp->face_frame = calloc((size_t)nf, sizeof(int));
        sp->nfaces = sp->face_surf && sp->face_frame ? nf : 0;
        sp->frame = 0;
    }
    sp->frame++;
    sp->nverts = 0;
    sp->norder = 0;
    sp->neplanes = 0;
    sp->failed = sp->nfaces != nf;
    if (reserve((void **)&sp->polys, &sp->cap_polys, c->el->max_surfs, sizeof *sp->polys, 256) < 0) sp->failed = 1;
    else sp->polys[0] = (ew_spoly){0, 0, 0, 0, 0, 0, 0, 0};  /* the background has no polygon */
    return sp;
}

/* Surface s (just made) gets its polygon from the world-space points p
 * (already clipped), and its place in the BSP order. */
static void record(ew_hsr_ctx *c, int s, float (*p)[3], int n) {
    ew_spolys *sp = c->spolys;
    if (!sp || sp->failed) return;
    ew_spoly *pl = &sp->polys[s];
    pl->first = sp->nverts, pl->n = 0;
    pl->x0 = pl->y0 = 1e30f, pl->x1 = pl->y1 = -1e30f;
    if (reserve((void **)&sp->verts, &sp->cap_verts, sp->nverts + n, sizeof *sp->verts, 4096) < 0 ||
        reserve((void **)&sp->order, &sp->cap_order, sp->norder + 1, sizeof(int), 1024) < 0) {
        sp->failed = 1;
        return;
    }
    const ew_view *v = &c->f->view;
    ew_spoly_vert *out = sp->verts + sp->nverts;
    double area = 0;
    for (int i = 0; i < n; i++) {
        float t[3];
        ew_view_transform(v, p[i], t);
        double zi = 1.0 / (t[2] < 0.01f ? 0.01 : (double)t[2]);
        /* on a 1/1024 pixel grid: exact lines (surf_poly.h) */
        out[i].x = nearbyint((v->xcenter + v->xscale * t[0] * zi) * 1024) / 1024;
        out[i].y = nearbyint((v->ycenter - v->yscale * t[1] * zi) * 1024) / 1024;
    }
    for (int i = 0; i < n; i++) {
        int j = i + 1 == n ? 0 : i + 1;
        area += out[i].x * out[j].y - out[j].x * out[i].y;
    }
    if (!(area != 0)) return;  /* edge on: no pixels */
    if (area < 0)
        for (int i = 0, j = n - 1; i < j; i++, j--) {
            ew_spoly_vert t = out[i];
            out[i] = out[j], out[j] = t;
        }
    /* A face's vertices in a row along one world edge (T-junctions) are
     * not quite in a row on the screen: where one makes the polygon bend
     * in, it goes, or the pixel centres just inside the bend would belong
     * to no polygon.  (Exact on the grid: every product fits a double.) */
    for (int again = 1; again && n >= 3;) {
        again = 0;
        for (int i = 0; i < n && n >= 3; i++) {
            const ew_spoly_vert *a = &out[i == 0 ? n - 1 : i - 1], *c = &out[i + 1 == n ? 0 : i + 1];
            double cross = (out[i].x - a->x) * (c->y - out[i].y) - (out[i].y - a->y) * (c->x - out[i].x);
            if (cross > 0) continue;
            memmove(out + i, out + i + 1, sizeof *out * (size_t)(n - i - 1));
            n--, again = 1;
        }
    }
    /* Edges too short for a line are dropped: their neighbours meet anyway. */
    int m = 0;
    for (int i = 0; i < n; i++) {
        int j = i + 1 == n ? 0 : i + 1;
        ew_spoly_vert q = out[i];
        if (!ew_line_through(q.x, q.y, out[j].x, out[j].y, &q.l)) continue;
        out[m++] = q;
        pl->x0 = (float)fmin(pl->x0, q.x), pl->x1 = (float)fmax(pl->x1, q.x);
        pl->y0 = (float)fmin(pl->y0, q.y), pl->y1 = (float)fmax(pl->y1, q.y);
    }
    if (m < 3) return;
    pl->n = m;
    sp->nverts += m;
    /* World faces arrive in key order; brush model fragments come later
     * with their leaves' keys, and are inserted after equal keys. */
    const ew_surf *surfs = c->el->surfs;
    int key = surfs[s].key, at = sp->norder;
    if (at > 0 && surfs[sp->order[at - 1]].key > key) {
        int lo = 0, hi = at;
        while (lo < hi) {
            int mid = (lo + hi) / 2;
            if (surfs[sp->order[mid]].key <= key) lo = mid + 1;
            else hi = mid;
        }
        at = lo;
        memmove(sp->order + at + 1, sp->order + at, sizeof(int) * (size_t)(sp->norder - at));
    }
    sp->order[at] = s;
    sp->norder++;
}

/* Face fi's edge planes for surface s. */
static void edge_planes(ew_hsr_ctx *c, int s, int fi) {
    ew_spolys *sp = c->spolys;
    const ew_world *w = c->f->world;
    const ew_face *f = &w->faces[fi];
    int n = f->numedges;
    if (reserve((void **)&sp->eplanes, &sp->cap_eplanes, sp->neplanes + n, sizeof *sp->eplanes, 4096) < 0) {
        sp->failed = 1;
        return;
    }
    const float *nm = w->planes[f->plane].normal;
    double wind = 0;
    for (int i = 0; i < n; i++) {
        const float *a = w->verts[ew_face_vertex(w, f, i)], *b = w->verts[ew_face_vertex(w, f, i + 1 == n ? 0 : i + 1)];
        wind += nm[0] * ((double)a[1] * b[2] - (double)a[2] * b[1]) + nm[1] * ((double)a[2] * b[0] - (double)a[0] * b[2]) +
                nm[2] * ((double)a[0] * b[1] - (double)a[1] * b[0]);
    }
    double sign = wind >= 0 ? 1 : -1;
    float (*ep)[4] = sp->eplanes + sp->neplanes;
    int m = 0;
    for (int i = 0; i < n; i++) {
        const float *a = w->verts[ew_face_vertex(w, f, i)], *b = w->verts[ew_face_vertex(w, f, i + 1 == n ? 0 : i + 1)];
        double e[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        /* inward: normal x edge, for a polygon wound counter-clockwise about the normal */
        double q[3] = {nm[1] * e[2] - nm[2] * e[1], nm[2] * e[0] - nm[0] * e[2], nm[0] * e[1] - nm[1] * e[0]};
        double len = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
        if (!(len > 0)) continue;
        for (int k = 0; k < 3; k++) ep[m][k] = (float)(sign * q[k] / len);
        ep[m][3] = ep[m][0] * a[0] + ep[m][1] * a[1] + ep[m][2] * a[2];
        m++;
    }
    sp->polys[s].eplane0 = sp->neplanes, sp->polys[s].neplanes = m;
    sp->neplanes += m;
}

void ew_spolys_face(ew_hsr_ctx *c, int fi, int clipflags, int key) {
    int s = c->el->nsurfs;
    ew_edge_face(c, fi, clipflags, key);
    if (c->el->nsurfs == s || !c->spolys || c->spolys->failed) return;
    ew_spolys *sp = c->spolys;
    sp->face_surf[fi] = s, sp->face_frame[fi] = sp->frame;
    sp->polys[s] = (ew_spoly){0, 0, 0, 0, 0, 0, 0, 0};
    edge_planes(c, s, fi);
    const ew_world *w = c->f->world;
    const ew_face *f = &w->faces[fi];
    float in[EW_MAX_POLY][3], out[EW_MAX_POLY][3];
    int tin[EW_MAX_POLY], tout[EW_MAX_POLY];
    ew_face_points(w, f, in);
    for (int i = 0; i < f->numedges; i++) tin[i] = i;
    /* The same clip as the edge list's, so shared clipped points match. */
    int m = clipflags ? ew_clip_poly(&c->f->view, clipflags, in, f->numedges, out, tin, tout) : f->numedges;
    if (m < 3) {
        sp->polys[s].n = 0;
        return;
    }
    record(c, s, clipflags ? out : in, m);
}

void ew_spolys_poly(ew_hsr_ctx *c, float (*verts)[3], int n, int fi, const ew_view *v, int key) {
    int s = c->el->nsurfs;
    ew_edge_poly(c, verts, n, fi, v, key);
    if (c->el->nsurfs == s || !c->spolys || c->spolys->failed) return;
    c->spolys->polys[s] = (ew_spoly){0, 0, 0, 0, 0, 0, 0, 0};
    float out[EW_MAX_POLY][3];
    int tin[EW_MAX_POLY], tout[EW_MAX_POLY];
    for (int i = 0; i < n; i++) tin[i] = -1;
    int m = ew_clip_poly(&c->f->view, 15, verts, n, out, tin, tout);
    if (m < 3) {
        c->spolys->polys[s].n = 0;
        return;
    }
    record(c, s, out, m);
}

size_t ew_spolys_memory(const ew_hsr_ctx *c) {
    const ew_spolys *sp = c->spolys;
    if (!sp) return 0;
    return sizeof *sp->polys * (size_t)sp->cap_polys + sizeof *sp->verts * (size_t)sp->cap_verts +
           sizeof(int) * ((size_t)sp->cap_order + 2 * (size_t)sp->nfaces) + sizeof *sp->eplanes * (size_t)sp->cap_eplanes;
}

void ew_spolys_free(ew_spolys *sp) {
    if (!sp) return;
    free(sp->polys), free(sp->verts), free(sp->order), free(sp->face_surf), free(sp->face_frame), free(sp->eplanes);
    free(sp);
}
