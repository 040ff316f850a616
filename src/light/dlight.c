/* Dynamic lights: each frame, every light walks the BSP and marks the faces
 * within its radius (a node whose plane is farther than the radius from the
 * light sends it down one side only).  Marked faces get their lit surface
 * rebuilt with the light added; a surface built with a light is rebuilt once
 * more when the light has gone.  Faces the light does not reach keep their
 * cached surfaces. */
#include "light/light.h"
#include "ew_util.h"
#include "asset/scene.h"

#include <math.h>

/* One light's most at a sample: a radius of 1e5 (ew_scene_add_dlight's
 * limit) times 256, so 32 lights on a sample stay inside int. */
#define EW_DLIGHT_MAX_ADD 25600000

static void mark(ew_marks *m, const ew_world *w, const float p[3], float radius, int bit, int node, int depth) {
    while (node >= 0 && depth++ < 4096) {
        const ew_node *n = &w->nodes[node];
        const ew_plane *pl = &w->planes[n->plane];
        float d = p[0] * pl->normal[0] + p[1] * pl->normal[1] + p[2] * pl->normal[2] - pl->dist;
        if (d > radius) {
            node = n->children[0];
            continue;
        }
        if (d < -radius) {
            node = n->children[1];
            continue;
        }
        for (int i = 0; i < n->numfaces; i++) {
            int fi = n->firstface + i;
            if (m->face_dlframe[fi] != m->framecount) {
                m->face_dlframe[fi] = m->framecount;
                m->face_dlbits[fi] = 0;
            }
            m->face_dlbits[fi] |= 1u << bit;
        }
        mark(m, w, p, radius, bit, n->children[0], depth);
        node = n->children[1];
    }
}

void ew_mark_dlights(ew_marks *m, const ew_frame *f, const struct ew_scene *sc) {
    if (!sc) return;
    const ew_world *w = f->world;
    for (int i = 0; i < sc->ndlights; i++) {
        const ew_dlight *dl = &sc->dlights[i];
        mark(m, w, dl->origin, dl->radius, i, w->models[0].headnode, 0);
        /* Brush entities: the light in each one's own space. */
        for (int e = 0; e < sc->nents; e++) {
            const ew_scene_entity *en = &sc->ents[e];
            int sub = -1 - en->model;
            if (en->model >= 0 || sub <= 0 || sub >= w->nummodels) continue;
            float ax[3][3], d[3], p[3];
            ew_entity_axes(en->angles, ax);
            for (int k = 0; k < 3; k++) d[k] = dl->origin[k] - en->origin[k];
            for (int k = 0; k < 3; k++) p[k] = ax[0][k] * d[0] + ax[1][k] * d[1] + ax[2][k] * d[2];
            mark(m, w, p, dl->radius, i, w->models[sub].headnode, 0);
        }
    }
}

unsigned ew_face_dlights(const ew_marks *m, int face) {
    return m->face_dlframe[face] == m->framecount ? m->face_dlbits[face] : 0;
}

void ew_add_dlights(const ew_frame *fr, const struct ew_scene *sc, const ew_face *f, unsigned bits, int *bl, int nc,
                    int smax, int tmax, const float (*st_to_lm)[3]) {
    const ew_world *w = fr->world;
    if (!sc || !bits) return;
    const ew_plane *pl = &w->planes[f->plane];
    const ew_texinfo *ti = &w->texinfo[f->texinfo];
    /* Texture position of sample (s, t), from texturemins: 16 s, 16 t on
     * Quake's grid, else through the inverse of the layout's mapping. */
    float inv[2][3] = {{16, 0, 0}, {0, 16, 0}};
    if (st_to_lm) {
        float a = st_to_lm[0][0], b = st_to_lm[0][1], c = st_to_lm[1][0], d = st_to_lm[1][1];
        float det = a * d - b * c;
        if (!(det > 1e-12f || det < -1e-12f)) return;
        /* (S, T) = A^-1 ((u, v) - offset), made relative to texturemins */
        inv[0][0] = d / det, inv[0][1] = -b / det;
        inv[1][0] = -c / det, inv[1][1] = a / det;
        inv[0][2] = -(inv[0][0] * st_to_lm[0][2] + inv[0][1] * st_to_lm[1][2]) - (float)f->texturemins[0];
        inv[1][2] = -(inv[1][0] * st_to_lm[0][2] + inv[1][1] * st_to_lm[1][2]) - (float)f->texturemins[1];
    }
    /* Texture axes are not unit length: measure distances in world units. */
    float ls = sqrtf(ti->vecs[0][0] * ti->vecs[0][0] + ti->vecs[0][1] * ti->vecs[0][1] + ti->vecs[0][2] * ti->vecs[0][2]);
    float lt = sqrtf(ti->vecs[1][0] * ti->vecs[1][0] + ti->vecs[1][1] * ti->vecs[1][1] + ti->vecs[1][2] * ti->vecs[1][2]);
    if (ls < 1e-6f || lt < 1e-6f) return;
    for (int i = 0; i < sc->ndlights && i < 32; i++) {
        if (!(bits & (1u << i))) continue;
        const ew_dlight *dl = &sc->dlights[i];
        float o[3] = {dl->origin[0], dl->origin[1], dl->origin[2]};
        /* Lit with the light in world space: exact for brush entities at
         * their rest position (no offset, no turn), which is how maps
         * place them. */
        float dist = o[0] * pl->normal[0] + o[1] * pl->normal[1] + o[2] * pl->normal[2] - pl->dist;
        float rad = dl->radius - fabsf(dist);
        if (!(rad > 0)) continue;  /* NaN too */
        float imp[3];
        for (int k = 0; k < 3; k++) imp[k] = o[k] - pl->normal[k] * dist;
        float is = imp[0] * ti->vecs[0][0] + imp[1] * ti->vecs[0][1] + imp[2] * ti->vecs[0][2] + ti->vecs[0][3] - f->texturemins[0];
        float it = imp[0] * ti->vecs[1][0] + imp[1] * ti->vecs[1][1] + imp[2] * ti->vecs[1][2] + ti->vecs[1][3] - f->texturemins[1];
        const float *col = dl->color;
        for (int t = 0; t < tmax; t++) {
            for (int s = 0; s < smax; s++) {
                float ds, dt;
                if (!st_to_lm) {
                    dt = (it - (float)(t * 16)) / lt, ds = (is - (float)(s * 16)) / ls;
                } else {
                    ds = (is - (inv[0][0] * (float)s + inv[0][1] * (float)t + inv[0][2])) / ls;
                    dt = (it - (inv[1][0] * (float)s + inv[1][1] * (float)t + inv[1][2])) / lt;
                }
                float d = sqrtf(ds * ds + dt * dt);
                if (d >= rad) continue;
                /* d is NaN where the face's numbers overflow (a plane or
                 * texture axis of 1e37 is finite): no light, not UB */
                int add = ew_int_checked((rad - d) * 256, 0, EW_DLIGHT_MAX_ADD, 0);
                if (nc == 1) {
                    bl[t * smax + s] += add;
                } else {
                    int *p = &bl[(t * smax + s) * 3];
                    for (int k = 0; k < 3; k++) p[k] += ew_int_checked((float)add * col[k], 0, add, 0);
                }
            }
        }
    }
}
