/* Front end: walk the world BSP front to back.  A node's bounding box is
 * tested against the frustum planes it is not already known to be inside
 * of (clipflags bit i = plane i still needs testing); leaves in the PVS and
 * the frustum mark their surfaces; each node then hands its marked faces
 * that face the camera to the walker's face sink (the hidden-surface
 * method's, or world/front_par.c's lists), all with one BSP-order key.
 * world/front_par.c walks subtrees of one frame on several threads with
 * the same code, each with a walker of its own. */
#include "world/front.h"

/* The serial walker's leaf: its faces marked for the nodes above. */
static void mark_leaf(ew_walker *wk, int li) {
    ew_marks *mk = wk->fr->marks;
    const ew_world *w = wk->fr->f->world;
    const ew_leaf *leaf = &w->leaves[li];
    for (int i = 0; i < leaf->nummarks; i++) mk->face_frame[w->marksurfaces[leaf->firstmark + i]] = mk->framecount;
}

void ew_walk_faces(ew_walker *wk, int n, int clipflags, int side, float d) {
    const ew_front *fr = wk->fr;
    const ew_world *w = fr->f->world;
    const ew_marks *mk = fr->marks;
    const ew_node *node = &w->nodes[n];
    /* Only faces facing the camera can be seen: behind the plane, the
     * PLANEBACK ones. */
    if (d == 0) {  /* edge-on */
        wk->key++;
        return;
    }
    /* The faces that pass first, their corners' vertex numbers fetched
     * meanwhile; then each handed over. */
    enum { BATCH = 32 };
    int list[BATCH], cfs[BATCH];
    for (int i0 = 0; i0 < node->numfaces; i0 += BATCH) {
        int np = 0;
        for (int i = i0; i < node->numfaces && i < i0 + BATCH; i++) {
            int fi = node->firstface + i;
            const ew_face *f = &w->faces[fi];
            if (mk->face_frame[fi] != mk->framecount) continue;
            if (((f->flags & EW_SURF_PLANEBACK) != 0) != side) continue;
            /* The node's box crosses a plane; the face itself often does not,
             * and then skips the clip (or is not seen at all). */
            int cf = clipflags ? ew_cull_face(&fr->f->view, w->face_box[fi], clipflags) : 0;
            if (cf < 0) continue;
            __builtin_prefetch(&w->surfverts[f->firstedge]);
            list[np] = fi, cfs[np++] = cf;
        }
        for (int k = 0; k < np; k++) {
            float alpha;
            int kind = ew_see_kind(fr, &w->faces[list[k]], 1, &alpha);
            wk->face(wk, list[k], cfs[k], kind, alpha);
        }
    }
    wk->key++;
}

/* Which side of node n's plane the camera is on (0 front), and how far. */
static inline int node_side(const ew_front *fr, const ew_node *node, float *d) {
    const ew_plane *pl = &fr->f->world->planes[node->plane];
    const float *o = fr->f->view.origin;
    *d = o[0] * pl->normal[0] + o[1] * pl->normal[1] + o[2] * pl->normal[2] - pl->dist;
    return *d >= 0 ? 0 : 1;
}

int ew_walk_enter(ew_walker *wk, int n, int *clipflags, float *d) {
    const ew_front *fr = wk->fr;
    const ew_node *node = &fr->f->world->nodes[n];
    if (fr->marks->node_frame[n] != fr->marks->framecount) return -1;
    if (*clipflags) {
        *clipflags = ew_cull_box(&fr->f->view, node->mins, node->maxs, *clipflags);
        if (*clipflags < 0) return -1;
    }
    return node_side(fr, node, d);
}

void ew_walk_node(ew_walker *wk, int n, int clipflags, int depth) {
    ew_front *fr = wk->fr;
    ew_marks *mk = fr->marks;
    const ew_world *w = fr->f->world;
    if (depth > EW_MAX_WALK_DEPTH) {
        wk->dropped++;
        return;
    }
    if (n < 0) {
        int li = -1 - n;
        const ew_leaf *leaf = &w->leaves[li];
        if (mk->leaf_frame[li] != mk->framecount || leaf->contents == EW_CONTENTS_SOLID) return;
        if (clipflags && ew_cull_box(&fr->f->view, leaf->mins, leaf->maxs, clipflags) < 0) return;
        wk->visible_leaves++;
        /* Brush model fragments in this leaf sort here in BSP order. */
        mk->leaf_key[li] = wk->key++;
        mk->leaf_keyframe[li] = mk->framecount;
        wk->leaf(wk, li);
        return;
    }
    float d;
    int side = ew_walk_enter(wk, n, &clipflags, &d);
    if (side < 0) return;
    {
        /* Asked for as the node is entered: its children (walked next) and
         * its faces, their boxes and marks (after the near child).  A new
         * view finds most of the map out of the cache: front end 0.93-0.95x. */
        const ew_node *nd = &w->nodes[n];
        for (int k = 0; k < 2; k++) {
            int ch = nd->children[k];
            if (ch >= 0) __builtin_prefetch(&w->nodes[ch]);
            else __builtin_prefetch(&w->leaves[-1 - ch]);
        }
        for (int i = 0; i < nd->numfaces; i += 2) __builtin_prefetch(&w->faces[nd->firstface + i]);
        for (int i = 0; i < nd->numfaces; i += 4) __builtin_prefetch(&w->face_box[nd->firstface + i]);
        if (nd->numfaces) __builtin_prefetch(&wk->fr->marks->face_frame[nd->firstface]);
    }
    ew_walk_node(wk, w->nodes[n].children[side], clipflags, depth + 1);
    ew_walk_faces(wk, n, clipflags, side, d);
    ew_walk_node(wk, w->nodes[n].children[!side], clipflags, depth + 1);
}

void ew_walk_see_add(ew_front *fr, int fi, int key, int kind, float alpha) {
    const ew_world *w = fr->f->world;
    const ew_face *f = &w->faces[fi];
    if (f->numedges > EW_MAX_POLY - 8) return;
    float p[EW_MAX_POLY][3];
    ew_face_points(w, f, p);
    fr->out.see(fr->out.ctx, p, f->numedges, fi, &fr->f->view, key, kind, alpha);
}

/* The serial walker's face: into the edge list (the edge list's own
 * methods), to the method, or to the see-through pass. */
static void list_face(ew_walker *wk, int fi, int clipflags, int kind, float alpha) {
    if (ew_see_to_hsr(wk->fr, kind))
        ew_front_face(wk->fr, fi, clipflags, wk->key);
    else
        ew_walk_see_add(wk->fr, fi, wk->key, kind, alpha);
}
static void method_face(ew_walker *wk, int fi, int clipflags, int kind, float alpha) {
    if (ew_see_to_hsr(wk->fr, kind))
        wk->fr->out.face(wk->fr->out.ctx, fi, clipflags, wk->key);
    else
        ew_walk_see_add(wk->fr, fi, wk->key, kind, alpha);
}

void ew_walk_world(ew_front *fr) {
    ew_walker wk = {.fr = fr, .leaf = mark_leaf, .face = fr->out.edge_list ? list_face : method_face};
    ew_walk_node(&wk, fr->f->world->models[0].headnode, 15, 0);
    fr->f->stats.visible_leaves += wk.visible_leaves;
    fr->f->stats.dropped += wk.dropped;
}
/* Does a world-space box touch any leaf of this frame's PVS?  (Entities in
 * no visible leaf are hidden however near they are.) */
static int box_visible(const ew_front *fr, int n, const float lo[3], const float hi[3], int depth) {
    const ew_world *w = fr->f->world;
    const ew_marks *mk = fr->marks;
    while (n >= 0) {
        if (depth++ > EW_MAX_WALK_DEPTH) return 1;
        /* No leaf of this frame's PVS below (ew_pvs_mark marks every node
         * above one): none to find here. */
        if (mk->node_frame[n] != mk->framecount) return 0;
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
            if (box_visible(fr, node->children[0], lo, hi, depth)) return 1;
            n = node->children[1];
        }
    }
    int leaf = -1 - n;
    return mk->leaf_frame[leaf] == mk->framecount && w->leaves[leaf].contents != EW_CONTENTS_SOLID;
}

int ew_box_in_pvs(const ew_front *fr, const float lo[3], const float hi[3]) {
    return box_visible(fr, fr->f->world->models[0].headnode, lo, hi, 0);
}
