/* Front end: walk the world BSP front to back.  A node's bounding box is
 * tested against the frustum planes it is not already known to be inside
 * of (clipflags bit i = plane i still needs testing); leaves in the PVS and
 * the frustum mark their surfaces; each node then hands its marked faces
 * that face the camera to the frame's hidden-surface method (or to another
 * sink: world/front_par.c lists them), all with one BSP-order key. */
#include "renderer.h"

#define EW_MAX_WALK_DEPTH 4096

typedef void (*face_sink)(ew_renderer *r, int face, int clipflags, int key);

static void walk(ew_renderer *r, face_sink sink, int n, int clipflags, int depth, int *key) {
    const ew_world *w = r->world;
    if (depth > EW_MAX_WALK_DEPTH) {
        r->stats.dropped++;
        return;
    }
    if (n < 0) {
        int li = -1 - n;
        const ew_leaf *leaf = &w->leaves[li];
        if (r->marks.leaf_frame[li] != r->marks.framecount || leaf->contents == EW_CONTENTS_SOLID) return;
        if (clipflags && ew_cull_box(&r->view, leaf->mins, leaf->maxs, clipflags) < 0) return;
        r->stats.visible_leaves++;
        /* Brush model fragments in this leaf sort here in BSP order. */
        r->marks.leaf_key[li] = (*key)++;
        r->marks.leaf_keyframe[li] = r->marks.framecount;
        for (int i = 0; i < leaf->nummarks; i++)
            r->marks.face_frame[w->marksurfaces[leaf->firstmark + i]] = r->marks.framecount;
        return;
    }
    const ew_node *node = &w->nodes[n];
    if (r->marks.node_frame[n] != r->marks.framecount) return;
    if (clipflags) {
        clipflags = ew_cull_box(&r->view, node->mins, node->maxs, clipflags);
        if (clipflags < 0) return;
    }
    const ew_plane *pl = &w->planes[node->plane];
    const float *o = r->view.origin;
    float d = o[0] * pl->normal[0] + o[1] * pl->normal[1] + o[2] * pl->normal[2] - pl->dist;
    int side = d >= 0 ? 0 : 1;

    walk(r, sink, node->children[side], clipflags, depth + 1, key);

    /* Faces on this node: only those facing the camera can be seen. */
    int want_back = side;  /* camera behind the plane sees PLANEBACK faces */
    for (int i = 0; i < node->numfaces; i++) {
        int fi = node->firstface + i;
        const ew_face *f = &w->faces[fi];
        if (r->marks.face_frame[fi] != r->marks.framecount) continue;
        if (((f->flags & EW_SURF_PLANEBACK) != 0) != want_back) continue;
        if (d == 0) continue;  /* edge-on */
        float alpha;
        int kind = ew_see_kind(r, f, 1, &alpha);
        if (ew_see_to_hsr(r, kind)) {
            sink(r, fi, clipflags, *key);
        } else if (f->numedges <= EW_MAX_POLY - 8) {
            float p[EW_MAX_POLY][3];
            for (int k = 0; k < f->numedges; k++) {
                const float *q = w->verts[ew_face_vertex(w, f, k)];
                p[k][0] = q[0], p[k][1] = q[1], p[k][2] = q[2];
            }
            ew_see_add(r, p, f->numedges, fi, &r->view, *key, kind, alpha);
        }
    }
    (*key)++;

    walk(r, sink, node->children[!side], clipflags, depth + 1, key);
}

void ew_walk_world_to(ew_renderer *r, void (*face)(ew_renderer *r, int face, int clipflags, int key)) {
    int key = 0;  /* BSP order: grows front to back */
    walk(r, face, r->world->models[0].headnode, 15, 0, &key);
}

void ew_walk_world(ew_renderer *r) { ew_walk_world_to(r, r->cfg.hsr->face); }

/* Does a world-space box touch any leaf of this frame's PVS?  (Entities in
 * no visible leaf are hidden however near they are.) */
static int box_visible(const ew_renderer *r, int n, const float lo[3], const float hi[3], int depth) {
    const ew_world *w = r->world;
    while (n >= 0) {
        if (depth++ > EW_MAX_WALK_DEPTH) return 1;
        /* No leaf of this frame's PVS below (ew_pvs_mark marks every node
         * above one): none to find here. */
        if (r->marks.node_frame[n] != r->marks.framecount) return 0;
        const ew_node *node = &w->nodes[n];
        const ew_plane *p = &w->planes[node->plane];
        float dmax = 0, dmin = 0;
        for (int k = 0; k < 3; k++) {
            dmax += p->normal[k] * (p->normal[k] >= 0 ? hi[k] : lo[k]);
            dmin += p->normal[k] * (p->normal[k] >= 0 ? lo[k] : hi[k]);
        }
        if (dmin >= p->dist) {
            n = node->children[0];
        } else if (dmax < p->dist) {
            n = node->children[1];
        } else {
            if (box_visible(r, node->children[0], lo, hi, depth)) return 1;
            n = node->children[1];
        }
    }
    int leaf = -1 - n;
    return r->marks.leaf_frame[leaf] == r->marks.framecount && w->leaves[leaf].contents != EW_CONTENTS_SOLID;
}

int ew_box_in_pvs(const ew_renderer *r, const float lo[3], const float hi[3]) {
    return box_visible(r, r->world->models[0].headnode, lo, hi, 0);
}
