/* Front end: walk the world BSP front to back.  A node's bounding box is
 * tested against the frustum planes it is not already known to be inside
 * of (clipflags bit i = plane i still needs testing); leaves in the PVS and
 * the frustum mark their surfaces; each node then emits its marked faces
 * that face the camera, all with one BSP-order key. */
#include "ew_render.h"

#define EW_MAX_WALK_DEPTH 4096

/* Returns -1 if the box is outside a plane, else the reduced clipflags. */
int ew_cull_box(const ew_view *v, const float mins[3], const float maxs[3], int clipflags) {
    for (int i = 0; i < 4; i++) {
        if (!(clipflags & (1 << i))) continue;
        const ew_plane *p = &v->frustum[i];
        float far_pt = 0, near_pt = 0;  /* corners most / least along the normal */
        for (int k = 0; k < 3; k++) {
            if (p->normal[k] >= 0) {
                far_pt += p->normal[k] * maxs[k];
                near_pt += p->normal[k] * mins[k];
            } else {
                far_pt += p->normal[k] * mins[k];
                near_pt += p->normal[k] * maxs[k];
            }
        }
        if (far_pt <= p->dist) return -1;                 /* wholly outside */
        if (near_pt >= p->dist) clipflags &= ~(1 << i);   /* wholly inside */
    }
    return clipflags;
}

static void walk(ew_renderer *r, int n, int clipflags, int depth) {
    const ew_world *w = r->world;
    if (depth > EW_MAX_WALK_DEPTH) {
        r->stats.dropped++;
        return;
    }
    if (n < 0) {
        int li = -1 - n;
        const ew_leaf *leaf = &w->leaves[li];
        if (r->leaf_frame[li] != r->framecount || leaf->contents == EW_CONTENTS_SOLID) return;
        if (clipflags && ew_cull_box(&r->view, leaf->mins, leaf->maxs, clipflags) < 0) return;
        r->stats.visible_leaves++;
        /* Brush model fragments in this leaf sort here in BSP order. */
        r->leaf_key[li] = r->currentkey++;
        r->leaf_keyframe[li] = r->framecount;
        for (int i = 0; i < leaf->nummarks; i++)
            r->face_frame[w->marksurfaces[leaf->firstmark + i]] = r->framecount;
        return;
    }
    const ew_node *node = &w->nodes[n];
    if (r->node_frame[n] != r->framecount) return;
    if (clipflags) {
        clipflags = ew_cull_box(&r->view, node->mins, node->maxs, clipflags);
        if (clipflags < 0) return;
    }
    const ew_plane *pl = &w->planes[node->plane];
    const float *o = r->view.origin;
    float d = o[0] * pl->normal[0] + o[1] * pl->normal[1] + o[2] * pl->normal[2] - pl->dist;
    int side = d >= 0 ? 0 : 1;

    walk(r, node->children[side], clipflags, depth + 1);

    /* Faces on this node: only those facing the camera can be seen. */
    int want_back = side;  /* camera behind the plane sees PLANEBACK faces */
    for (int i = 0; i < node->numfaces; i++) {
        int fi = node->firstface + i;
        const ew_face *f = &w->faces[fi];
        if (r->face_frame[fi] != r->framecount) continue;
        if (((f->flags & EW_SURF_PLANEBACK) != 0) != want_back) continue;
        if (d == 0) continue;  /* edge-on */
        if (r->face_hook)
            r->face_hook(r, fi, clipflags, r->face_hook_ctx);
        else
            ew_emit_face(r, fi, clipflags);
    }
    r->currentkey++;

    walk(r, node->children[!side], clipflags, depth + 1);
}

void ew_walk_world(ew_renderer *r) {
    walk(r, r->world->models[0].headnode, 15, 0);
}

/* Does a world-space box touch any leaf of this frame's PVS?  (Entities in
 * no visible leaf are hidden however near they are.) */
static int box_visible(const ew_renderer *r, int n, const float lo[3], const float hi[3], int depth) {
    const ew_world *w = r->world;
    while (n >= 0) {
        if (depth++ > EW_MAX_WALK_DEPTH) return 1;
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
    return r->leaf_frame[leaf] == r->framecount && w->leaves[leaf].contents != EW_CONTENTS_SOLID;
}

int ew_box_in_pvs(const ew_renderer *r, const float lo[3], const float hi[3]) {
    return box_visible(r, r->world->models[0].headnode, lo, hi, 0);
}
