/* Front end, last step: clip a face to the frustum, project it and add its
 * edges to the global edge list.  Faces share edges: an unclipped world
 * edge emitted for one face is cached for the frame, and the face on its
 * other side reuses it (filling the edge's other surface slot) instead of
 * clipping and projecting it again. */
#include "renderer.h"
#include "world/edge_math.h"
#include "world/occlude.h"

typedef ew_proj proj;

static void project(const ew_renderer *r, const float p[3], proj *out) { ew_project(&r->f.view, p, out); }

/* Adds the edge a->b for surface s; returns its index, or -1 if it crosses
 * no scanline centre (horizontal or too short) and so never bounds a span. */
static inline int add_edge(ew_renderer *r, const proj *a, const proj *b, int s) {
    ew_edge spill, *e = r->el.nedges < r->el.max_edges ? &r->el.edges[r->el.nedges] : &spill;
    if (!ew_edge_setup(a, b, e)) return -1;
    if (e == &spill) {
        r->f.stats.dropped++;
        return -1;
    }
    e->nearzi = a->zi > b->zi ? a->zi : b->zi;
    return ew_edge_link(&r->el, b->v > a->v, s);
}

/* World vertex vi projected, once a frame: most are corners of three or
 * four faces. */
static inline void project_vertex(ew_renderer *r, int vi, proj *out) {
    if (r->marks.vert_frame[vi] != r->marks.framecount) {
        project(r, r->f.world->verts[vi], &r->marks.vert_proj[vi]);
        r->marks.vert_frame[vi] = r->marks.framecount;
    }
    *out = r->marks.vert_proj[vi];
}

/* Emits (or reuses) world edge `se` (a signed surfedge) between a and b,
 * projecting the ends on demand: world vertices va_i, vb_i (>= 0) through
 * the frame's cache, else the points pa, pb.  Returns the nearest 1/z it
 * saw. */
static inline float emit_world_edge(ew_renderer *r, int se, const float *pa, const float *pb, int va_i, int vb_i,
                                    proj *ja, int *va, proj *jb, int *vb, int s) {
    float zi;
    if (ew_edge_cache_take(r, se, s, &zi)) return zi;
    if (!*va) (va_i >= 0 ? project_vertex(r, va_i, ja) : project(r, pa, ja)), *va = 1;
    if (!*vb) (vb_i >= 0 ? project_vertex(r, vb_i, jb) : project(r, pb, jb)), *vb = 1;
    ew_edge_cache_note(r, se, add_edge(r, ja, jb, s), jb->v > ja->v);
    return ja->zi > jb->zi ? ja->zi : jb->zi;
}

void ew_emit_face(ew_renderer *r, int fi, int clipflags, int key) {
    const ew_world *w = r->f.world;
    const ew_face *f = &w->faces[fi];
    int n = f->numedges;
    int full = r->el.nsurfs >= r->el.max_surfs || r->el.nedges + n + 4 > r->el.max_edges;
    if (n > EW_MAX_POLY - 8 || (full && !r->occ.on)) {
        r->f.stats.dropped++;
        return;
    }
    int s = r->el.nsurfs;
    float nearzi = 0;
    proj pj[EW_MAX_POLY];
    int valid[EW_MAX_POLY];  /* cleared for the face's (clipped) vertices only, not all 256 */
    float in[EW_MAX_POLY][3], out[EW_MAX_POLY][3];
    int tin[EW_MAX_POLY], tout[EW_MAX_POLY];
    int m = n;
    if (clipflags) {
        ew_face_points(w, f, in);
        for (int i = 0; i < n; i++) tin[i] = i;
        m = ew_clip_poly(&r->f.view, clipflags, in, n, out, tin, tout);
    }
    if (r->occ.on) {
        /* Every point projected first, for the coverage map (world/occlude.c),
         * which every face with points counts in, even one the budgets then
         * refuse, as the parallel front end decides them all before it
         * numbers any. */
        int hidden = 1;
        if (m >= 3) {
            for (int i = 0; i < m; i++) {
                if (clipflags) project(r, out[i], &pj[i]);
                else project_vertex(r, ew_face_vertex(w, f, i), &pj[i]);
                valid[i] = 1;
            }
            ew_occ_box b = ew_occ_box_of(&r->occ, pj, m, r->f.target.width, r->f.target.height);
            hidden = ew_occ_face(&r->occ, &r->occ.whole, pj, m, b, key);
        }
        if (full) {
            r->f.stats.dropped++;
            return;
        }
        if (m < 3) return;
        if (hidden) {
            r->f.stats.faces_occluded++;
            return;
        }
    } else {
        if (m < 3) return;
        for (int i = 0; i < m; i++) valid[i] = 0;
    }

    if (clipflags == 0) {
        /* Wholly inside the frustum: every edge is a whole world edge. */
        for (int i = 0; i < n; i++) {
            int j = i + 1 == n ? 0 : i + 1;
            float zi = emit_world_edge(r, w->surfedges[f->firstedge + i], NULL, NULL, ew_face_vertex(w, f, i),
                                       ew_face_vertex(w, f, j), &pj[i], &valid[i], &pj[j], &valid[j], s);
            if (zi > nearzi) nearzi = zi;
        }
    } else {
        for (int i = 0; i < m; i++) {
            int j = i + 1 == m ? 0 : i + 1;
            float zi;
            if (tout[i] >= 0) {
                zi = emit_world_edge(r, w->surfedges[f->firstedge + tout[i]], out[i], out[j], -1, -1,
                                     &pj[i], &valid[i], &pj[j], &valid[j], s);
            } else {
                if (!valid[i]) project(r, out[i], &pj[i]), valid[i] = 1;
                if (!valid[j]) project(r, out[j], &pj[j]), valid[j] = 1;
                add_edge(r, &pj[i], &pj[j], s);
                zi = pj[i].zi > pj[j].zi ? pj[i].zi : pj[j].zi;
            }
            if (zi > nearzi) nearzi = zi;
        }
    }
    ew_surf_add_world(r, fi, key, nearzi);
}

void ew_emit_poly(ew_renderer *r, float (*verts)[3], int n, int fi, const ew_view *v, int key) {
    if (r->el.nsurfs >= r->el.max_surfs || n > EW_MAX_POLY - 8 || r->el.nedges + n + 4 > r->el.max_edges) {
        r->f.stats.dropped++;
        return;
    }
    proj pj[EW_MAX_POLY];
    float nearzi;
    int m = ew_poly_project(&r->f.view, verts, n, pj, &nearzi);
    if (m < 3) return;
    int s = r->el.nsurfs;
    for (int i = 0; i < m; i++) add_edge(r, &pj[i], &pj[i + 1 == m ? 0 : i + 1], s);
    ew_surf_set_fragment(r->f.world, &r->el.surfs[s], fi, key, nearzi, v);
    r->el.nsurfs++;
}
