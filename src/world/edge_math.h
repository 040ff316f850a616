/* The edge list's per-edge work (internal), shared by the serial emission
 * (world/edges.c) and the parallel one (world/front_par.c), which must make
 * bit-identical edge lists: a point projected to the screen, an edge's
 * first scanline, 16.16 start and step between two projected points, its
 * place in the list, the edge cache that lets the faces on both sides of a
 * world edge share one edge, and a world face's surface record. */
#ifndef EW_WORLD_EDGE_MATH_H
#define EW_WORLD_EDGE_MATH_H

#include "frame.h"
#include "ew_util.h"
#include "world/front.h"

#include <math.h>

#define EW_NEAR_Z 0.01f

typedef struct ew_proj { float u, v, zi; } ew_proj;

static inline void ew_project(const ew_view *v, const float p[3], ew_proj *out) {
    float t[3];
    ew_view_transform(v, p, t);
    float z = t[2] < EW_NEAR_Z ? EW_NEAR_Z : t[2];
    float zi = 1.0f / z;
    float u = v->xcenter + v->xscale * t[0] * zi;
    float y = v->ycenter - v->yscale * t[1] * zi;
    /* Frustum clipping leaves points on the screen's borders; float error
     * must not push them past, or spans would leave the frame.  Written so
     * that a NaN lands on the low border too: the edge scan relies on every
     * edge's u lying on the screen (hsr/edge_scan.c). */
    float umax = v->width - 0.5f, vmax = v->height - 0.5f;
    out->u = u > -0.5f ? (u < umax ? u : umax) : -0.5f;
    out->v = y > -0.5f ? (y < vmax ? y : vmax) : -0.5f;
    out->zi = zi;
}

/* The edge a->b's position (u, u_step, v_first, v_last; not its surfaces
 * or list link) into e; 0 if it crosses no scanline centre (horizontal or
 * too short) and so never bounds a span. */
static inline int ew_edge_setup(const ew_proj *a, const ew_proj *b, ew_edge *e) {
    int down = b->v > a->v;
    const ew_proj *top = down ? a : b, *bot = down ? b : a;
    int first = ew_ceilf_int(top->v), last = ew_ceilf_int(bot->v) - 1;
    if (first > last) return 0;
    double slope = (double)(bot->u - top->u) / (double)(bot->v - top->v);
    double u = top->u + (first - top->v) * slope;
    e->u = ew_floor_int(u * 65536.0 + 0.5);
    e->u_step = first == last ? 0 : ew_floor_int(slope * 65536.0 + 0.5);
    e->v_first = first;
    e->v_last = last;
    return 1;
}

/* The edge el->edges[el->nedges] (its position set) joins the list for
 * surface s: on its right side if it goes down the screen, else its left.
 * Its index. */
static inline int ew_edge_link(ew_edge_list *el, int down, int s) {
    ew_edge *e = &el->edges[el->nedges];
    e->surfs[0] = down ? (uint16_t)s : 0;
    e->surfs[1] = down ? 0 : (uint16_t)s;
    return el->nedges++;
}

/* The edge cache (marks->edge_cache_*).  World edge se (a signed
 * surfedge) may be in this frame's list already, from the face on its
 * other side.  1: it is settled for surface s, *zi its nearer 1/z (its free
 * side now takes s), or 0 if it crosses no scanline.  0: the caller adds an
 * edge and notes it with ew_edge_cache_note (also when both faces use it
 * the same way round, so its free side is taken). */
static inline int ew_edge_cache_take(ew_front *fr, int se, int s, float *zi) {
    const ew_marks *mk = fr->marks;
    int e = se >= 0 ? se : -se, sign = se >= 0 ? 1 : -1;
    if (mk->edge_cache_frame[e] != mk->framecount) return 0;
    int idx = mk->edge_cache_index[e];
    if (idx < 0) {
        *zi = 0;
        return 1;
    }
    ew_edge *ed = &fr->el->edges[idx];
    int slot = sign * mk->edge_cache_down[e] > 0 ? 0 : 1;
    if (ed->surfs[slot] != 0) return 0;
    ed->surfs[slot] = (uint16_t)s;
    fr->f->stats.edges_cached++;
    *zi = ed->nearzi;
    return 1;
}

/* World edge se is edge idx of the list (-1: crosses no scanline), added
 * going down the screen or not. */
static inline void ew_edge_cache_note(ew_front *fr, int se, int idx, int down) {
    ew_marks *mk = fr->marks;
    int e = se >= 0 ? se : -se, sign = se >= 0 ? 1 : -1;
    mk->edge_cache_frame[e] = mk->framecount;
    mk->edge_cache_index[e] = idx;
    mk->edge_cache_down[e] = (int8_t)(down ? sign : -sign);
}

/* Surface sf for world face fi, seen from the frame's camera. */
static inline void ew_surf_set_world(const ew_frame *f, ew_surf *sf, int fi, int key, float nearzi) {
    sf->key = key;
    sf->face = fi;
    sf->flags = f->world->faces[fi].flags;
    sf->nearzi = nearzi;
    sf->view = &f->view;
    sf->insubmodel = 0;
}

/* That surface added as el.nsurfs. */
static inline void ew_surf_add_world(ew_front *fr, int fi, int key, float nearzi) {
    ew_surf_set_world(fr->f, &fr->el->surfs[fr->el->nsurfs++], fi, key, nearzi);
}

/* A polygon with no world edges (a brush model's fragment) clipped to the
 * whole frustum and projected into pj: its point count (below 3: clipped
 * away) and *nearzi, the largest 1/z of its points. */
static inline int ew_poly_project(const ew_view *view, float (*verts)[3], int n, ew_proj *pj, float *nearzi) {
    float out[EW_MAX_POLY][3];
    int tin[EW_MAX_POLY], tout[EW_MAX_POLY];
    for (int i = 0; i < n; i++) tin[i] = -1;
    int m = ew_clip_poly(view, 15, verts, n, out, tin, tout);
    *nearzi = 0;
    for (int i = 0; i < m; i++) {
        ew_project(view, out[i], &pj[i]);
        if (pj[i].zi > *nearzi) *nearzi = pj[i].zi;
    }
    return m;
}

/* Surface sf for a fragment of face fi seen through v (a moved brush
 * model's camera), with the face's 1/z plane for ties within a leaf. */
static inline void ew_surf_set_fragment(const ew_world *w, ew_surf *sf, int fi, int key, float nearzi,
                                        const ew_view *v) {
    const ew_face *f = &w->faces[fi];
    sf->key = key;
    sf->face = fi;
    sf->flags = f->flags;
    sf->nearzi = nearzi;
    sf->view = v;
    sf->insubmodel = 1;
    float zp[3];
    ew_face_zplane(w, v, f, zp);
    sf->zi_u = zp[0], sf->zi_v = zp[1], sf->zi_0 = zp[2];
}

#endif
