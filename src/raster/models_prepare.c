/* The models' pass prepared, once per frame before the bands draw (serial):
 * the entities the front end let through (world/entities.c, tested there
 * in its phases or here) posed room for, the item boxes' surfaces made
 * current, so the bands only draw. */
#include "renderer.h"
#include "raster/alias.h"
#include "scene/scene.h"

#include <stdlib.h>

int ew_reserve_entities(ew_renderer *r) {
    const struct ew_scene *sc = r->ents.scene;
    if (!sc) return 0;
    if (sc->nents > r->ents.max_ent_frame) {
        ew_ent_frame *f = realloc(r->ents.ent_frame, sizeof *f * (size_t)sc->nents);
        if (!f) return -1;
        r->ents.ent_frame = f, r->ents.max_ent_frame = sc->nents;
    }
    return 0;
}

int ew_prepare_entities(ew_renderer *r) {
    const struct ew_scene *sc = r->ents.scene;
    r->ents.nent_frame = 0;
    if (!sc) return 0;
    if (r->front.tested_frame != r->marks.framecount) {
        if (ew_reserve_entities(r) < 0) {
            r->f.stats.dropped++;
            return 0;
        }
        r->front.ent_frame = r->ents.ent_frame;
        ew_test_entities(&r->front, 0, sc->nents);
    }
    ew_ents *en = &r->ents;
    en->nalias = 0;
    if (sc->nents > en->max_xf) {
        ew_alias_xf *xf = realloc(en->xf, sizeof *xf * (size_t)sc->nents);
        int *list = realloc(en->alias_list, sizeof *list * (size_t)sc->nents);
        if (xf) en->xf = xf;
        if (list) en->alias_list = list;
        if (!xf || !list) {
            r->f.stats.dropped++;
            return 0;
        }
        en->max_xf = sc->nents;
        uint32_t *tr = realloc(en->tint_rgba, sizeof *tr * 256 * (size_t)sc->nents);
        uint8_t *tm = realloc(en->tint_remap, 256 * (size_t)sc->nents);
        if (tr) en->tint_rgba = tr;
        if (tm) en->tint_remap = tm;
        if (!tr || !tm) {
            en->max_xf = 0;
            r->f.stats.dropped++;
            return 0;
        }
    }
    size_t nxverts = 0;
    int nbox_faces = 0, boxes = ew_boxes_reserve(r, sc->nents, 0) == 0;
    en->nbox = 0;
    if (!boxes) r->f.stats.dropped++;  /* no item box drawn */
    for (int i = 0; i < sc->nents; i++) {
        const ew_scene_entity *e = &sc->ents[i];
        const ew_ent_frame *ef = &r->ents.ent_frame[i];
        en->xf[i].visible = en->xf[i].hidden = 0;
        r->f.stats.entities_culled += ef->culled;
        if (!ef->visible) continue;
        const ew_scene_model *m = &sc->models[e->model];
        if (m->kind == EW_MODEL_ALIAS) {
            r->ents.ent_frame[i].xvert0 = nxverts;
            nxverts += (size_t)((const ew_mdl *)m->data)->numverts;
            en->alias_list[en->nalias++] = i;
        }
        if (m->kind == EW_MODEL_BOX) {
            if (ew_prepare_box(r, e->model, m->data) < 0) r->f.stats.dropped++;
            if (boxes) {
                en->box_frame[i].face0 = nbox_faces;
                nbox_faces += ((const ew_world *)m->data)->models[0].numfaces;
                en->box_list[en->nbox++] = i;
            }
        }
    }
    if (boxes && ew_boxes_reserve(r, sc->nents, nbox_faces) < 0) {
        r->f.stats.dropped++;
        en->nbox = 0;
    }
    r->ents.nent_frame = sc->nents;
    if (ew_sprite_cache_reserve(r, sc->nents) < 0) r->f.stats.dropped++;  /* models drawn exactly then */
    if (nxverts > en->max_xverts) {
        ew_xvert *xv = realloc(en->xverts, sizeof *xv * nxverts);
        if (!xv) {  /* each piece poses its own then */
            r->f.stats.dropped++;
            en->nalias = 0;
            return en->nbox;
        }
        en->xverts = xv, en->max_xverts = nxverts;
    }
    return en->nalias + en->nbox;
}
