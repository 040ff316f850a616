/* Brush model entities (doors, lifts, buttons, secret walls) in the world's
 * edge list.  Each polygon the camera can see is moved to the entity's place,
 * then clipped down the world BSP into the leaves it occupies: fragments in
 * solid leaves vanish (so it cannot poke through walls), and the rest take
 * the BSP key of their leaf, so they sort against the world in BSP order
 * and, within one leaf, against each other by 1/z (see hsr/edge_scan.c). */
#include "renderer.h"
#include "scene/scene.h"

#include <math.h>
#include <stdlib.h>

#define ON_EPSILON 0.01f
/* Each level of split() holds two polygons on the stack (about 7 KB), so
 * its depth is capped well inside a thread's stack; real trees are under
 * 200 deep.  A fragment deeper than this is dropped (and counted). */
#define MAX_SPLIT_DEPTH 512

typedef struct split_ctx {
    ew_renderer   *r;
    const ew_view *view;    /* camera in the model's own space */
    int            face;
    float          normal[3]; /* the face's outward normal in world space */
    int            handed;    /* fragments handed to the hidden-surface method */
    int            kind;      /* EW_SEE_*: where its fragments go */
    float          alpha;
} split_ctx;

static void split(split_ctx *c, float (*p)[3], int n, int node, int depth) {
    ew_renderer *r = c->r;
    const ew_world *w = r->world;
    if (depth > MAX_SPLIT_DEPTH) {
        r->stats.dropped++;
        return;
    }
    if (node < 0) {
        int li = -1 - node;
        if (r->marks.leaf_keyframe[li] == r->marks.framecount && w->leaves[li].contents != EW_CONTENTS_SOLID) {
            if (ew_see_to_hsr(r, c->kind))
                r->cfg.hsr->poly(r, p, n, c->face, c->view, r->marks.leaf_key[li]);
            else
                ew_see_add(r, p, n, c->face, c->view, r->marks.leaf_key[li], c->kind, c->alpha);
            c->handed++;
        }
        return;
    }
    /* No leaf of this frame's PVS below (ew_pvs_mark marks every node above
     * one): no leaf here was visited, so no fragment could be handed. */
    if (r->marks.node_frame[node] != r->marks.framecount) return;
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

/* A face is drawn if any fragment of it lands in a visited leaf. */
static int split_face(ew_renderer *r, int fi, const ew_view *mv, const float normal[3], float (*p)[3], int n,
                      float entity_alpha) {
    split_ctx c = {r, mv, fi, {normal[0], normal[1], normal[2]}, 0, 0, 1};
    c.kind = ew_see_kind(r, &r->world->faces[fi], entity_alpha, &c.alpha);
    split(&c, p, n, r->world->models[0].headnode, 0);
    return c.handed > 0;
}

/* Every camera-facing face of every brush entity in the frustum, moved into
 * world space and split down the world BSP. */
void ew_walk_brush_models(ew_renderer *r) {
    const struct ew_scene *sc = r->ents.scene;
    if (!sc) return;
    const ew_world *w = r->world;
    int used = 0;
    for (int ei = 0; ei < sc->nents; ei++) {
        const ew_scene_entity *e = &sc->ents[ei];
        int sub = -1 - e->model;
        if (e->model >= 0 || sub <= 0 || sub >= w->nummodels || used >= r->ents.max_ent_views) continue;
        const ew_model *m = &w->models[sub];
        float ax[3][3];
        ew_entity_axes(e->angles, ax);

        float lo[3], hi[3];
        ew_moved_box(ax, e->origin, m->mins, m->maxs, lo, hi);
        if (ew_cull_box(&r->view, lo, hi, 15) < 0) {
            r->stats.entities_culled++;
            continue;
        }
        ew_view *mv = &r->ents.ent_views[used++];
        ew_view_to_model(&r->view, ax, e->origin, mv);
        int drawn = 0;
        for (int i = 0; i < m->numfaces; i++) {
            int fi = m->firstface + i;
            const ew_face *f = &w->faces[fi];
            const ew_plane *pl = &w->planes[f->plane];
            float dist = mv->origin[0] * pl->normal[0] + mv->origin[1] * pl->normal[1] +
                         mv->origin[2] * pl->normal[2] - pl->dist;
            int back = (f->flags & EW_SURF_PLANEBACK) != 0;
            if ((back && dist >= 0) || (!back && dist <= 0)) continue;  /* faces away */
            if (f->numedges > EW_MAX_POLY - 16) continue;
            float sign = back ? -1.0f : 1.0f, normal[3];
            for (int k = 0; k < 3; k++)
                normal[k] = sign * (ax[k][0] * pl->normal[0] + ax[k][1] * pl->normal[1] + ax[k][2] * pl->normal[2]);
            float p[EW_MAX_POLY][3];
            for (int v = 0; v < f->numedges; v++) {
                const float *q = w->verts[ew_face_vertex(w, f, v)];
                for (int k = 0; k < 3; k++)
                    p[v][k] = e->origin[k] + ax[k][0] * q[0] + ax[k][1] * q[1] + ax[k][2] * q[2];
            }
            drawn += split_face(r, fi, mv, normal, p, f->numedges, e->alpha);
        }
        if (drawn) r->stats.entities_drawn++;
        else r->stats.entities_culled++;
    }
}


