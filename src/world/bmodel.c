/* Brush model entities (doors, lifts, buttons, secret walls) in the world's
 * edge list.  Each polygon the camera can see is moved to the entity's place,
 * then clipped down the world BSP into the leaves it occupies: fragments in
 * solid leaves vanish (so it cannot poke through walls), and the rest take
 * the BSP key of their leaf, so they sort against the world in BSP order
 * and, within one leaf, against each other by 1/z (see hsr/edge_scan.c). */
#include "world/front.h"
#include "asset/scene.h"

#include <math.h>
#include <stdlib.h>

#define ON_EPSILON 0.01f
/* Each level of split() holds two polygons on the stack (about 7 KB), so
 * its depth is capped well inside a thread's stack; real trees are under
 * 200 deep.  A fragment deeper than this is dropped (and counted). */
#define MAX_SPLIT_DEPTH 512

typedef struct split_ctx {
    const ew_front *fr;
    const ew_view *view;    /* camera in the model's own space */
    int            face;
    float          normal[3]; /* the face's outward normal in world space */
    int            handed;    /* fragments handed to the sink */
    int            kind;      /* EW_SEE_*: where its fragments go */
    float          alpha;
    int            dropped;
    ew_frag_sink   sink;
    void          *sink_ctx;
} split_ctx;

static void split(split_ctx *c, float (*p)[3], int n, int node, int depth) {
    const ew_marks *mk = c->fr->marks;
    const ew_world *w = c->fr->f->world;
    if (depth > MAX_SPLIT_DEPTH) {
        c->dropped++;
        return;
    }
    if (node < 0) {
        int li = -1 - node;
        if (mk->leaf_keyframe[li] == mk->framecount && w->leaves[li].contents != EW_CONTENTS_SOLID) {
            c->sink(c->sink_ctx, p, n, c->face, c->view, mk->leaf_key[li], c->kind, c->alpha);
            c->handed++;
        }
        return;
    }
    /* No leaf of this frame's PVS below (ew_pvs_mark marks every node above
     * one): no leaf here was visited, so no fragment could be handed. */
    if (mk->node_frame[node] != mk->framecount) return;
    const ew_node *nd = &w->nodes[node];
    const ew_plane *pl = &w->planes[nd->plane];
    float d[EW_MAX_POLY];
    int front = 0, back = 0;
    for (int i = 0; i < n; i++) {
        d[i] = p[i][0] * pl->normal[0] + p[i][1] * pl->normal[1] + p[i][2] * pl->normal[2] - pl->dist;
        if (d[i] > ON_EPSILON) front = 1;
        else if (d[i] < -ON_EPSILON) back = 1;
    }
    if (!front && !back) {  /* on the plane: goes the way it faces */
        float dot = c->normal[0] * pl->normal[0] + c->normal[1] * pl->normal[1] + c->normal[2] * pl->normal[2];
        split(c, p, n, nd->children[dot >= 0 ? 0 : 1], depth + 1);
        return;
    }
    if (!back) {
        split(c, p, n, nd->children[0], depth + 1);
        return;
    }
    if (!front) {
        split(c, p, n, nd->children[1], depth + 1);
        return;
    }
    float f[EW_MAX_POLY][3], b[EW_MAX_POLY][3];
    int nf = 0, nb = 0;
    for (int i = 0; i < n && nf < EW_MAX_POLY - 9 && nb < EW_MAX_POLY - 9; i++) {
        int j = i + 1 == n ? 0 : i + 1;
        if (d[i] >= -ON_EPSILON) f[nf][0] = p[i][0], f[nf][1] = p[i][1], f[nf][2] = p[i][2], nf++;
        if (d[i] <= ON_EPSILON) b[nb][0] = p[i][0], b[nb][1] = p[i][1], b[nb][2] = p[i][2], nb++;
        if ((d[i] > ON_EPSILON && d[j] < -ON_EPSILON) || (d[i] < -ON_EPSILON && d[j] > ON_EPSILON)) {
            float t = d[i] / (d[i] - d[j]);
            for (int k = 0; k < 3; k++) f[nf][k] = b[nb][k] = p[i][k] + t * (p[j][k] - p[i][k]);
            nf++, nb++;
        }
    }
    if (nf >= 3) split(c, f, nf, nd->children[0], depth + 1);
    if (nb >= 3) split(c, b, nb, nd->children[1], depth + 1);
}

/* Which brush entities are in the frustum, each with its camera (in
 * fr->ent_views) and axes; the others are counted in *culled. */
int ew_brush_items(ew_front *fr, ew_brush_item *items, int *culled) {
    const struct ew_scene *sc = fr->scene;
    *culled = 0;
    if (!sc) return 0;
    const ew_world *w = fr->f->world;
    int used = 0;
    for (int ei = 0; ei < sc->nents; ei++) {
        const ew_scene_entity *e = &sc->ents[ei];
        int sub = -1 - e->model;
        if (e->model >= 0 || sub <= 0 || sub >= w->nummodels || used >= fr->max_ent_views) continue;
        const ew_model *m = &w->models[sub];
        ew_brush_item *it = &items[used];
        ew_entity_axes(e->angles, it->ax);
        float lo[3], hi[3];
        ew_moved_box(it->ax, e->origin, m->mins, m->maxs, lo, hi);
        if (ew_cull_box(&fr->f->view, lo, hi, 15) < 0) {
            (*culled)++;
            continue;
        }
        it->ent = ei;
        it->mv = &fr->ent_views[used++];
        ew_view_to_model(&fr->f->view, it->ax, e->origin, it->mv);
    }
    return used;
}

/* Where the faces of brush entity `it` can start their way down the world
 * BSP: the deepest node above which the box around all of its moved
 * vertices lies wholly on one side of every plane, by more than the
 * split's margin (with room for rounding), so that every face would have
 * gone the same way at each of those nodes; *depth is how deep.  A node
 * with no leaf of the PVS below has none below its children either, so
 * skipping its test changes nothing. */
static int start_node(const ew_world *w, const ew_model *m, const ew_scene_entity *e, const float ax[3][3],
                      int *depth) {
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < m->numfaces; i++) {
        const ew_face *f = &w->faces[m->firstface + i];
        for (int v = 0; v < f->numedges; v++) {
            const float *q = w->verts[ew_face_vertex(w, f, v)];
            for (int k = 0; k < 3; k++) {
                float x = e->origin[k] + ax[k][0] * q[0] + ax[k][1] * q[1] + ax[k][2] * q[2];
                lo[k] = x < lo[k] ? x : lo[k], hi[k] = x > hi[k] ? x : hi[k];
            }
        }
    }
    const float margin = ON_EPSILON + 0.125f;
    int n = w->models[0].headnode;
    *depth = 0;
    while (n >= 0 && *depth < MAX_SPLIT_DEPTH) {
        const ew_node *nd = &w->nodes[n];
        const ew_plane *pl = &w->planes[nd->plane];
        float dmin = -pl->dist, dmax = -pl->dist;
        for (int k = 0; k < 3; k++) {
            dmin += pl->normal[k] * (pl->normal[k] >= 0 ? lo[k] : hi[k]);
            dmax += pl->normal[k] * (pl->normal[k] >= 0 ? hi[k] : lo[k]);
        }
        if (dmin > margin) n = nd->children[0];
        else if (dmax < -margin) n = nd->children[1];
        else break;
        ++*depth;
    }
    return n;
}

/* Every camera-facing face of one brush entity, moved into world space and
 * split down the world BSP; its fragments in visited leaves go to sink.
 * 1 if any did (the entity is drawn); *dropped counts what was lost. */
int ew_brush_split(const ew_front *fr, const ew_brush_item *it, ew_frag_sink sink, void *sink_ctx, int *dropped) {
    const ew_world *w = fr->f->world;
    const ew_scene_entity *e = &fr->scene->ents[it->ent];
    const ew_model *m = &w->models[-1 - e->model];
    const ew_view *mv = it->mv;
    int drawn = 0, depth0, node0 = start_node(w, m, e, it->ax, &depth0);
    *dropped = 0;
    for (int i = 0; i < m->numfaces; i++) {
        int fi = m->firstface + i;
        const ew_face *f = &w->faces[fi];
        const ew_plane *pl = &w->planes[f->plane];
        float dist = mv->origin[0] * pl->normal[0] + mv->origin[1] * pl->normal[1] + mv->origin[2] * pl->normal[2] -
                     pl->dist;
        int back = (f->flags & EW_SURF_PLANEBACK) != 0;
        if ((back && dist >= 0) || (!back && dist <= 0)) continue;  /* faces away */
        if (f->numedges > EW_MAX_POLY - 16) continue;
        float sign = back ? -1.0f : 1.0f;
        split_ctx c = {fr, mv, fi, {0, 0, 0}, 0, 0, 1, 0, sink, sink_ctx};
        for (int k = 0; k < 3; k++)
            c.normal[k] = sign * (it->ax[k][0] * pl->normal[0] + it->ax[k][1] * pl->normal[1] +
                                  it->ax[k][2] * pl->normal[2]);
        float p[EW_MAX_POLY][3];
        for (int v = 0; v < f->numedges; v++) {
            const float *q = w->verts[ew_face_vertex(w, f, v)];
            for (int k = 0; k < 3; k++)
                p[v][k] = e->origin[k] + it->ax[k][0] * q[0] + it->ax[k][1] * q[1] + it->ax[k][2] * q[2];
        }
        /* A face is drawn if any fragment of it lands in a visited leaf. */
        c.kind = ew_see_kind(fr, f, e->alpha, &c.alpha);
        split(&c, p, f->numedges, node0, depth0);
        drawn |= c.handed > 0;
        *dropped += c.dropped;
    }
    return drawn;
}

/* The serial sink: into the edge list (the edge list's own methods), the
 * method's polygons, or the see-through pass. */
static void frag_direct(void *ctx, float (*p)[3], int n, int face, const ew_view *v, int key, int kind, float alpha) {
    ew_front *fr = ctx;
    if (!ew_see_to_hsr(fr, kind))
        fr->out.see(fr->out.ctx, p, n, face, v, key, kind, alpha);
    else if (fr->out.edge_list)
        ew_front_poly(fr, p, n, face, v, key);
    else
        fr->out.poly(fr->out.ctx, p, n, face, v, key);
}

void ew_walk_brush_models(ew_front *fr) {
    if (!fr->scene) return;
    ew_stats *st = &fr->f->stats;
    ew_brush_item *items = malloc(sizeof *items * (size_t)(fr->max_ent_views + 1));
    if (!items) {
        st->dropped++;
        return;
    }
    int culled, n = ew_brush_items(fr, items, &culled);
    st->entities_culled += culled;
    for (int i = 0; i < n; i++) {
        int dropped, drawn = ew_brush_split(fr, &items[i], frag_direct, fr, &dropped);
        st->dropped += dropped;
        if (drawn) st->entities_drawn++;
        else st->entities_culled++;
    }
    free(items);
}
