/* Potentially visible set: find the camera's leaf, decompress its row of
 * the PVS and mark those leaves (and every node above them) for this frame. */
#include "renderer.h"

int ew_point_leaf(const ew_world *w, int headnode, const float p[3]) {
    int n = headnode;
    /* The loader rejected cycles, so the walk ends within numnodes steps. */
    for (int steps = 0; n >= 0 && steps <= w->numnodes; steps++) {
        const ew_node *node = &w->nodes[n];
        const ew_plane *pl = &w->planes[node->plane];
        float d = p[0] * pl->normal[0] + p[1] * pl->normal[1] + p[2] * pl->normal[2] - pl->dist;
        n = node->children[d >= 0 ? 0 : 1];
    }
    return n < 0 ? -1 - n : 0;
}

static void mark_leaf(ew_renderer *r, int leaf) {
    const ew_world *w = r->world;
    if (r->marks.leaf_frame[leaf] == r->marks.framecount) return;
    r->marks.leaf_frame[leaf] = r->marks.framecount;
    for (int n = w->leaves[leaf].parent; n >= 0; n = w->nodes[n].parent) {
        if (r->marks.node_frame[n] == r->marks.framecount) break;
        r->marks.node_frame[n] = r->marks.framecount;
    }
}

int ew_pvs_mark(ew_renderer *r) {
    const ew_world *w = r->world;
    const ew_model *m = &w->models[0];
    int leaf = ew_point_leaf(w, m->headnode, r->view.origin);
    /* Locked (ew_set_pvs_lock): the PVS of the leaf the lock kept. */
    int eye = leaf;
    r->dbg.last_leaf = eye;
    if (r->dbg.pvs_lock) {
        if (r->dbg.pvs_leaf < 0) r->dbg.pvs_leaf = eye;
        leaf = r->dbg.pvs_leaf;
    }
    const ew_leaf *l = &w->leaves[leaf];
    int nleaves = m->visleafs;
    if (nleaves > w->numleaves - 1) nleaves = w->numleaves - 1;

    if (leaf == 0 || l->visofs < 0 || !w->visdata) {
        /* Outside the map or no vis data: everything is potentially visible. */
        for (int i = 1; i <= nleaves; i++) mark_leaf(r, i);
        return eye;
    }
    /* Run-length decoding: a zero byte is followed by a count of zero bytes.
     * Bounded by the leaf count and by the end of the lump. */
    const uint8_t *p = w->visdata + l->visofs, *end = w->visdata + w->vissize;
    int bit = 0;
    while (bit < nleaves && p < end) {
        uint8_t b = *p++;
        if (b == 0) {
            if (p >= end) break;
            bit += 8 * *p++;
            continue;
        }
        for (int k = 0; k < 8 && bit + k < nleaves; k++)
            if (b & (1 << k)) mark_leaf(r, bit + k + 1);
        bit += 8;
    }
    mark_leaf(r, leaf);  /* the view leaf is always visible */
    return eye;
}
