/* The scene's z-buffered moving things, drawn after the world's spans have
 * z-filled the frame: alias models, sprites, item boxes, then particles.
 * Brush model entities are not here: they went into the edge list. */
#include "ew_render.h"
#include "raster/alias.h"
#include "scene/scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Light on a model: the floor under it, plus dynamic lights in reach, held
 * to a floor of 24 and a ceiling so shading keeps some contrast. */
static void model_light(const ew_renderer *r, const float origin[3], int *ambient, int *shade) {
    const struct ew_scene *sc = r->scene;
    int l = ew_light_point(r, origin);
    for (int i = 0; i < sc->ndlights; i++) {
        const ew_dlight *d = &sc->dlights[i];
        float dx = origin[0] - d->origin[0], dy = origin[1] - d->origin[1], dz = origin[2] - d->origin[2];
        float add = d->radius - sqrtf(dx * dx + dy * dy + dz * dz);
        if (add > 0) l += (int)add;
    }
    int a = l < 24 ? 24 : l > 128 ? 128 : l, s = l < 24 ? 24 : l;
    if (a + s > 192) s = 192 - a;
    *ambient = a, *shade = s;
}

/* An item box's lit surfaces, every face at every mip: boxes are small, so
 * all four are kept, built in the serial per-frame pass and rebuilt only
 * when a light style on the face or its texture frame changes; the bands
 * only read them. */
typedef struct ew_box_surf {
    uint8_t *pixels[4];
    int      width[4];
    int      light[4];   /* style values they were lit with */
    const ew_texture *tex;  /* and the texture frame (animated textures) */
    int      built;
} ew_box_surf;
struct ew_box_surfs {
    int         nfaces;
    ew_box_surf face[];  /* model 0's faces */
};

void ew_free_box_surfs(ew_renderer *r) {
    for (int i = 0; i < r->nbox_surfs; i++) {
        struct ew_box_surfs *b = r->box_surfs[i];
        for (int f = 0; b && f < b->nfaces; f++)
            for (int m = 0; m < 4; m++) free(b->face[f].pixels[m]);
        free(b);
    }
    free(r->box_surfs);
    r->box_surfs = NULL;
    r->nbox_surfs = 0;
}

static void box_light(const ew_renderer *r, const ew_face *f, int light[4]) {
    for (int k = 0; k < 4; k++) light[k] = f->styles[k] == 255 ? 0 : r->lightstyle[f->styles[k] & 63];
}

/* Makes scene model mi's box surfaces current; -1 when out of memory. */
static int prepare_box(ew_renderer *r, int mi, const ew_world *bw) {
    if (mi >= r->nbox_surfs) {
        struct ew_box_surfs **p = realloc(r->box_surfs, sizeof *p * (size_t)(mi + 1));
        if (!p) return -1;
        for (int i = r->nbox_surfs; i <= mi; i++) p[i] = NULL;
        r->box_surfs = p, r->nbox_surfs = mi + 1;
    }
    const ew_model *m = &bw->models[0];
    struct ew_box_surfs *b = r->box_surfs[mi];
    if (!b) {
        b = calloc(1, sizeof *b + sizeof(ew_box_surf) * (size_t)m->numfaces);
        if (!b) return -1;
        b->nfaces = m->numfaces;
        r->box_surfs[mi] = b;
    }
    int rc = 0;
    for (int i = 0; i < b->nfaces; i++) {
        const ew_face *f = &bw->faces[m->firstface + i];
        ew_box_surf *bs = &b->face[i];
        if (f->flags & (EW_SURF_SKY | EW_SURF_TURB)) continue;
        int light[4];
        box_light(r, f, light);
        const ew_texture *tex = ew_face_texture(bw, f, r->view.time);
        if (bs->built && bs->tex == tex && memcmp(light, bs->light, sizeof light) == 0) continue;
        bs->built = 0;
        int samples = ((f->extents[0] >> 4) + 1) * ((f->extents[1] >> 4) + 1);
        int *scratch = malloc(sizeof(int) * (size_t)samples);
        int ok = scratch != NULL;
        for (int mip = 0; mip < 4 && ok; mip++) {
            int w = f->extents[0] >> mip, h = f->extents[1] >> mip;
            if (!bs->pixels[mip]) bs->pixels[mip] = malloc((size_t)w * h);
            ok = bs->pixels[mip] != NULL;
            if (ok) ew_build_surface(r, bw, f, tex, mip, light, 0, bs->pixels[mip], scratch);
            bs->width[mip] = w;
        }
        free(scratch);
        if (!ok) {
            rc = -1;
            continue;
        }
        memcpy(bs->light, light, sizeof light);
        bs->tex = tex;
        bs->built = 1;
    }
    return rc;
}

/* An item box: faces of a small world of its own, z-buffered. */
static int draw_box(ew_renderer *r, const ew_world *bw, const struct ew_box_surfs *surfs,
                    const ew_scene_entity *e, const ew_rows *rows) {
    const ew_model *m = &bw->models[0];
    float ax[3][3];
    ew_entity_axes(e->angles, ax);
    float lo[3], hi[3];
    ew_moved_box(ax, e->origin, m->mins, m->maxs, lo, hi);
    if (ew_cull_box(&r->view, lo, hi, 15) < 0) return 0;
    ew_view mv;  /* the camera in the box's space */
    ew_view_to_model(&r->view, ax, e->origin, &mv);
    long won = 0;
    int in_view = 0;
    for (int i = 0; i < m->numfaces; i++) {
        const ew_face *f = &bw->faces[m->firstface + i];
        const ew_plane *pl = &bw->planes[f->plane];
        float dist = mv.origin[0] * pl->normal[0] + mv.origin[1] * pl->normal[1] + mv.origin[2] * pl->normal[2] - pl->dist;
        int back = (f->flags & EW_SURF_PLANEBACK) != 0;
        if ((back && dist >= 0) || (!back && dist <= 0) || f->numedges > EW_MAX_POLY - 8) continue;
        float p[EW_MAX_POLY][3];
        for (int v = 0; v < f->numedges; v++) {
            const float *q = bw->verts[ew_face_vertex(bw, f, v)];
            for (int k = 0; k < 3; k++) p[v][k] = e->origin[k] + ax[k][0] * q[0] + ax[k][1] * q[1] + ax[k][2] * q[2];
        }
        ew_zpoly zp;
        if (!ew_zpoly_project(r, p, f->numedges, &zp)) continue;
        in_view = 1;
        if (zp.y1 < rows->y0 || zp.y0 >= rows->y1) continue;  /* another band's rows */
        ew_zpoly_look look = {bw, f, &mv, ew_face_texture(bw, f, r->view.time), NULL, 0, 0, 1};
        if (!(f->flags & (EW_SURF_SKY | EW_SURF_TURB))) {
            const ew_box_surf *bs = surfs && i < surfs->nfaces ? &surfs->face[i] : NULL;
            if (!bs || !bs->built) {  /* no memory for it */
                rows->stats->dropped++;
                continue;
            }
            look.mip = ew_face_mip(&r->view, bw, f, zp.nearzi);
            look.surf = bs->pixels[look.mip], look.surf_width = bs->width[look.mip];
        }
        ew_zfill_rect(r, zp.x0, zp.y0 > rows->y0 ? zp.y0 : rows->y0, zp.x1 + 1,
                      zp.y1 + 1 < rows->y1 ? zp.y1 + 1 : rows->y1);
        won += ew_zpoly_fill(r, &zp, &look, NULL, 0, rows->y0, rows->y1);
    }
    rows->stats->alias_pixels += won;
    return in_view;
}

/* How far a model reaches from its origin, for the PVS and frustum tests. */
static float model_reach(const ew_scene_model *m) {
    return m->kind == EW_MODEL_ALIAS  ? ((const ew_mdl *)m->data)->radius
           : m->kind == EW_MODEL_BOX ? 64.0f
                                      : ((const ew_spr *)m->data)->radius;
}

int ew_prepare_entities(ew_renderer *r) {
    const struct ew_scene *sc = r->scene;
    r->nent_frame = 0;
    if (!sc) return 0;
    if (sc->nents > r->max_ent_frame) {
        ew_ent_frame *f = realloc(r->ent_frame, sizeof *f * (size_t)sc->nents);
        if (!f) {
            r->stats.dropped++;
            return -1;
        }
        r->ent_frame = f, r->max_ent_frame = sc->nents;
    }
    for (int i = 0; i < sc->nents; i++) {
        const ew_scene_entity *e = &sc->ents[i];
        ew_ent_frame *ef = &r->ent_frame[i];
        ef->visible = 0;
        if (e->model < 0) continue;  /* brush entities are in the edge list */
        const ew_scene_model *m = &sc->models[e->model];
        /* Potentially visible at all?  A box around the model against the
         * PVS and the frustum. */
        float reach = model_reach(m), lo[3], hi[3];
        for (int k = 0; k < 3; k++) lo[k] = e->origin[k] - reach, hi[k] = e->origin[k] + reach;
        if (ew_cull_box(&r->view, lo, hi, 15) < 0 || !ew_box_in_pvs(r, lo, hi)) {  /* the cheap test first */
            r->stats.entities_culled++;
            continue;
        }
        ef->visible = 1;
        if (m->kind == EW_MODEL_ALIAS) model_light(r, e->origin, &ef->ambient, &ef->shade);
        if (m->kind == EW_MODEL_BOX && prepare_box(r, e->model, m->data) < 0) r->stats.dropped++;
    }
    r->nent_frame = sc->nents;
    return 0;
}

void ew_draw_entities(ew_renderer *r, const ew_rows *rows) {
    const struct ew_scene *sc = r->scene;
    if (!sc) return;
    for (int i = 0; i < r->nent_frame && i < sc->nents; i++) {
        const ew_scene_entity *e = &sc->ents[i];
        const ew_ent_frame *ef = &r->ent_frame[i];
        if (!ef->visible) continue;
        const ew_scene_model *m = &sc->models[e->model];
        ew_model_pose pose = {{e->origin[0], e->origin[1], e->origin[2]},
                              {e->angles[0], e->angles[1], e->angles[2]},
                              e->frame, e->skin, r->view.time, ef->ambient, ef->shade};
        int drawn = 0;
        if (m->kind == EW_MODEL_ALIAS) {
            /* Time walks a model through its frames at the game's 10 a
             * second (frame groups animate by their own intervals too). */
            const ew_mdl *mdl = m->data;
            if (r->view.time > 0 && mdl->numframes > 1)
                pose.frame = (int)(((long long)(r->view.time * 10) + e->frame) % mdl->numframes);
            drawn = ew_draw_alias_rows(r, m->data, &pose, rows);
        } else if (m->kind == EW_MODEL_SPRITE) {
            drawn = ew_draw_sprite_rows(r, m->data, &pose, rows);
        } else if (m->kind == EW_MODEL_BOX) {
            drawn = draw_box(r, m->data, e->model < r->nbox_surfs ? r->box_surfs[e->model] : NULL, e, rows);
        }
        if (rows->first) {
            if (drawn) rows->stats->entities_drawn++;
            else rows->stats->entities_culled++;
        }
    }
    if (sc->nparticles) ew_draw_particles_rows(r, sc->particles, sc->nparticles, rows);
}
