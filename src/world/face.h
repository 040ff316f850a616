/* The front end's per-face rules (internal), written once: the clip, the
 * budgets, the occlusion test's inputs, the verdict on a face and the
 * edges' setup and linking.  One thread runs them face by face as the walk
 * hands faces over (world/edges.c, ew_front_face); the parallel front end
 * (world/front_par.c) runs the same functions in its phases: the clip,
 * the points and the edges' setup in "prepare", the occlusion test on
 * strips, the verdict and the links in "merge" (or, when everything fits,
 * by prefix sums).  The edge cache (world/edge_math.h) shares an edge
 * between the two faces on a world edge: the first in BSP order adds it,
 * the second takes its free side. */
#ifndef EW_WORLD_FACE_H
#define EW_WORLD_FACE_H

#include "world/edge_math.h"
#include "world/occlude.h"

#include <stdint.h>

#define EW_FACE_CLIP_EDGE INT32_MIN  /* an edge the clip made: on no world edge */

/* A face of more edges than this is dropped (counted). */
static inline int ew_face_too_big(int n) { return n > EW_MAX_POLY - 8; }

/* The list has no room for a face of n edges: its surface, its edges and
 * four the clip may add. */
static inline int ew_face_list_full(const ew_edge_list *el, int n) {
    return el->nsurfs >= el->max_surfs || el->nedges + n + 4 > el->max_edges;
}

/* Face f clipped to the frustum planes in clipflags: its points in cl and
 * per edge the face's own edge it lies on (tout, -1 for one the clip made);
 * the point count (below 3: clipped away).  clipflags 0: no clip, the
 * face's n vertices are its points (cl, tout untouched). */
static inline int ew_face_clip(const ew_view *v, const ew_world *w, const ew_face *f, int clipflags, float (*cl)[3],
                               int *tout) {
    int n = f->numedges;
    if (!clipflags) return n;
    float in[EW_MAX_POLY][3];
    int tin[EW_MAX_POLY];
    ew_face_points(w, f, in);
    for (int i = 0; i < n; i++) tin[i] = i;
    return ew_clip_poly(v, clipflags, in, n, cl, tin, tout);
}

/* Point i of the clipped face: its vertex, or the clip's point. */
static inline const float *ew_face_point(const ew_world *w, const ew_face *f, float (*cl)[3], int clipflags, int i) {
    return clipflags ? cl[i] : w->verts[ew_face_vertex(w, f, i)];
}

/* The world edge (signed surfedge) under edge i of the clipped face, or
 * EW_FACE_CLIP_EDGE. */
static inline int32_t ew_face_world_edge(const ew_world *w, const ew_face *f, int clipflags, const int *tout, int i) {
    return clipflags == 0 ? w->surfedges[f->firstedge + i]
           : tout[i] >= 0 ? w->surfedges[f->firstedge + tout[i]]
                          : EW_FACE_CLIP_EDGE;
}

/* What becomes of a face: dropped (too big, or the list is full: counted),
 * clipped away, hidden by nearer faces (counted), or added.  The coverage
 * map counts every face with points, even one the budgets then refuse. */
enum { EW_FACE_DROPPED, EW_FACE_CLIPPED, EW_FACE_OCCLUDED, EW_FACE_ADDED };
static inline int ew_face_verdict(int too_big, int full, int m, int hidden) {
    if (too_big || full) return EW_FACE_DROPPED;
    if (m < 3) return EW_FACE_CLIPPED;
    if (hidden) return EW_FACE_OCCLUDED;
    return EW_FACE_ADDED;
}
/* The verdict counted; 1 if the face is added. */
static inline int ew_face_counted(ew_stats *st, int verdict) {
    if (verdict == EW_FACE_ADDED) return 1;
    if (verdict == EW_FACE_DROPPED) st->dropped++;
    else if (verdict == EW_FACE_OCCLUDED) st->faces_occluded++;
    return 0;
}

/* The edge a->b set up (position and nearer 1/z); 0 if it crosses no
 * scanline centre and so never bounds a span. */
static inline int ew_face_setup_edge(const ew_proj *a, const ew_proj *b, ew_edge *e) {
    if (!ew_edge_setup(a, b, e)) return 0;
    e->nearzi = a->zi > b->zi ? a->zi : b->zi;
    return 1;
}

/* The set-up edge at el->edges[el->nedges] joins the list for surface s;
 * its index, or -1 if the list had no room for it (full: counted as
 * dropped, the edge was set up elsewhere). */
static inline int ew_face_link_edge(ew_front *fr, int full, int down, int s) {
    if (full) {
        fr->f->stats.dropped++;
        return -1;
    }
    return ew_edge_link(fr->el, down, s);
}

/* Where to set up the list's next edge: its own slot, or *spill if the
 * list is full (ew_face_add_edge then counts it dropped). */
static inline ew_edge *ew_face_edge_slot(ew_front *fr, ew_edge *spill) {
    ew_edge_list *el = fr->el;
    return el->nedges < el->max_edges ? &el->edges[el->nedges] : spill;
}

/* Edge e of surface s (set up; crosses: it crosses a scanline centre;
 * down: it goes down the screen), on world edge se or made by the clip
 * (EW_FACE_CLIP_EDGE), into the list if it crosses one, and a world edge
 * noted in the edge cache for the face on its other side (which then takes
 * its free side, ew_edge_cache_take).  Its index, or -1. */
static inline int ew_face_add_edge(ew_front *fr, int32_t se, const ew_edge *e, int crosses, int down, int s) {
    ew_edge_list *el = fr->el;
    int idx = -1;
    if (crosses) {
        int full = el->nedges >= el->max_edges;
        if (!full && e != &el->edges[el->nedges]) el->edges[el->nedges] = *e;
        idx = ew_face_link_edge(fr, full, down, s);
    }
    if (se != EW_FACE_CLIP_EDGE) ew_edge_cache_note(fr, se, idx, down);
    return idx;
}

#endif
