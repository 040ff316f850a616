/* Potentially visible set: find the camera's leaf, decompress its row of
 * the PVS into a list, then mark those leaves (and every node above them)
 * for this frame: the calling thread, or every thread of the parallel
 * front end (world/front_par.c), a share of the list each.  Marks are
 * relaxed atomic stores: threads marking the same ancestor store the same
 * value. */
#include "world/front.h"

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

static void mark_leaf(ew_marks *mk, int leaf, int frame) {
    if (__atomic_load_n(&mk->leaf_frame[leaf], __ATOMIC_RELAXED) == frame) return;
    __atomic_store_n(&mk->leaf_frame[leaf], frame, __ATOMIC_RELAXED);
    const int *up = mk->node_up;
    for (int n = mk->leaf_up[leaf]; n >= 0; n = up[n]) {
        if (__atomic_load_n(&mk->node_frame[n], __ATOMIC_RELAXED) == frame) break;
        __atomic_store_n(&mk->node_frame[n], frame, __ATOMIC_RELAXED);
    }
}

void ew_pvs_apply(ew_front *fr, int from, int to) {
    ew_marks *mk = fr->marks;
    for (int i = from; i < to; i++) mark_leaf(mk, mk->vis[i], mk->framecount);
}

void ew_pvs_finish(ew_front *fr) {
    if (!fr->marks->vis_pending) return;
    ew_pvs_apply(fr, 0, fr->marks->nvis);
    fr->marks->vis_pending = 0;
}

static void list_leaf(ew_marks *mk, int leaf) { mk->vis[mk->nvis++] = leaf; }

void ew_pvs_mark(ew_front *fr, int leaf) {
    const ew_world *w = fr->f->world;
    ew_marks *mk = fr->marks;
    const ew_model *m = &w->models[0];
    const ew_leaf *l = &w->leaves[leaf];
    int nleaves = m->visleafs;
    if (nleaves > w->numleaves - 1) nleaves = w->numleaves - 1;

    mk->nvis = 0;
    mk->vis_pending = 1;
    if (leaf == 0 || l->visofs < 0 || !w->visdata) {
        /* Outside the map or no vis data: everything is potentially visible. */
        for (int i = 1; i <= nleaves; i++) list_leaf(mk, i);
        return;
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
            if (b & (1 << k)) list_leaf(mk, bit + k + 1);
        bit += 8;
    }
    list_leaf(mk, leaf);  /* the view leaf is always visible (marking twice is harmless) */
}
