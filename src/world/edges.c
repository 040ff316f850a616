/* Front end, last step, on one thread: clip a face to the frustum, project
 * it and add its edges to the global edge list, by the rules of
 * world/face.h.  Faces share edges: an unclipped world edge emitted for one
 * face is cached for the frame, and the face on its other side reuses it
 * (filling the edge's other surface slot) instead of clipping and
 * projecting it again. */
#include "world/face.h"

typedef ew_proj proj;

/* Adds the edge a->b of surface s on world edge se (or EW_FACE_CLIP_EDGE),
 * set up in its slot of the list. */
static inline void add_edge(ew_front *fr, int32_t se, const proj *a, const proj *b, int s) {
    ew_edge spill, *e = ew_face_edge_slot(fr, &spill);
    ew_face_add_edge(fr, se, e, ew_face_setup_edge(a, b, e), b->v > a->v, s);
}

/* World vertex vi projected, once a frame: most are corners of three or
 * four faces. */
static inline void project_vertex(ew_front *fr, int vi, proj *out) {
    ew_marks *mk = fr->marks;
    if (mk->vert_frame[vi] != mk->framecount) {
        ew_project(&fr->f->view, fr->f->world->verts[vi], &mk->vert_proj[vi]);
        mk->vert_frame[vi] = mk->framecount;
    }
    *out = mk->vert_proj[vi];
}

/* Point i of the clipped face projected: its vertex through the frame's
 * cache, or the clip's point. */
static inline void project_point(ew_front *fr, const ew_face *f, float (*cl)[3], int clipflags, int i, proj *out) {
    if (clipflags) ew_project(&fr->f->view, cl[i], out);
    else project_vertex(fr, ew_face_vertex(fr->f->world, f, i), out);
}

/* Edge i -> j of the clipped face for surface s, on world edge se (or
 * EW_FACE_CLIP_EDGE): taken from the face on its other side if that one
 * added it, else its ends projected (as far as not yet) and the edge
 * added.  Its nearer 1/z. */
__attribute__((always_inline))  /* in both loops of ew_front_face, the first with no clip */
static inline float emit_edge(ew_front *fr, const ew_face *f, float (*cl)[3], int clipflags, int32_t se, int i, int j,
                              proj *pj, int *valid, int s) {
    float zi;
    if (se != EW_FACE_CLIP_EDGE && ew_edge_cache_take(fr, se, s, &zi)) return zi;
    if (!valid[i]) project_point(fr, f, cl, clipflags, i, &pj[i]), valid[i] = 1;
    if (!valid[j]) project_point(fr, f, cl, clipflags, j, &pj[j]), valid[j] = 1;
    add_edge(fr, se, &pj[i], &pj[j], s);
    return pj[i].zi > pj[j].zi ? pj[i].zi : pj[j].zi;
}

void ew_front_face(ew_front *fr, int fi, int clipflags, int key) {
    const ew_world *w = fr->f->world;
    const ew_face *f = &w->faces[fi];
    int n = f->numedges, occ = fr->occ.on;
    int too_big = ew_face_too_big(n), full = ew_face_list_full(fr->el, n);
    /* Dropped either way: without the coverage map to count it in, not clipped. */
    if (too_big || (full && !occ)) {
        fr->f->stats.dropped++;
        return;
    }
    int s = fr->el->nsurfs;
    float nearzi = 0;
    proj pj[EW_MAX_POLY];
    int valid[EW_MAX_POLY];  /* cleared for the face's (clipped) vertices only, not all 256 */
    float cl[EW_MAX_POLY][3];
    int tout[EW_MAX_POLY];
    int m = ew_face_clip(&fr->f->view, w, f, clipflags, cl, tout), hidden = 0;
    if (occ) {
        /* Every point projected first, for the coverage map (world/occlude.c). */
        hidden = 1;
        if (m >= 3) {
            for (int i = 0; i < m; i++) project_point(fr, f, cl, clipflags, i, &pj[i]), valid[i] = 1;
            ew_occ_box b = ew_occ_box_of(&fr->occ, pj, m, fr->f->target.width, fr->f->target.height);
            hidden = ew_occ_face(&fr->occ, &fr->occ.whole, pj, m, b, key);
        }
    } else {
        for (int i = 0; i < m; i++) valid[i] = 0;
    }
    if (!ew_face_counted(&fr->f->stats, ew_face_verdict(0, full, m, hidden))) return;

    if (clipflags == 0) {
        /* Wholly inside the frustum (most faces): every edge is a whole world edge. */
        for (int i = 0; i < n; i++) {
            float zi = emit_edge(fr, f, NULL, 0, w->surfedges[f->firstedge + i], i, i + 1 == n ? 0 : i + 1, pj, valid, s);
            if (zi > nearzi) nearzi = zi;
        }
    } else {
        for (int i = 0; i < m; i++) {
            float zi = emit_edge(fr, f, cl, clipflags, ew_face_world_edge(w, f, clipflags, tout, i), i,
                                 i + 1 == m ? 0 : i + 1, pj, valid, s);
            if (zi > nearzi) nearzi = zi;
        }
    }
    ew_surf_add_world(fr, fi, key, nearzi);
}

void ew_front_poly(ew_front *fr, float (*verts)[3], int n, int fi, const ew_view *v, int key) {
    if (ew_face_too_big(n) || ew_face_list_full(fr->el, n)) {
        fr->f->stats.dropped++;
        return;
    }
    proj pj[EW_MAX_POLY];
    float nearzi;
    int m = ew_poly_project(&fr->f->view, verts, n, pj, &nearzi);
    if (m < 3) return;
    int s = fr->el->nsurfs;
    for (int i = 0; i < m; i++) add_edge(fr, EW_FACE_CLIP_EDGE, &pj[i], &pj[i + 1 == m ? 0 : i + 1], s);
    ew_surf_set_fragment(fr->f->world, &fr->el->surfs[s], fi, key, nearzi, v);
    fr->el->nsurfs++;
}
