/* The models' pass prepared, once per frame before the bands draw (serial):
 * the entities the front end let through (world/entities.c, tested there
 * in its phases or here) posed room for, the item boxes' surfaces made
 * current, so the bands only draw. */
#include "raster/alias.h"
#include "light/light.h"
#include "world/front.h"
#include "asset/scene.h"

#include <stdlib.h>

int ew_reserve_entities(ew_ents *en) {
    const struct ew_scene *sc = en->scene;
    if (!sc) return 0;
    if (sc->nents > en->max_ent_frame) {
        ew_ent_frame *f = realloc(en->ent_frame, sizeof *f * (size_t)sc->nents);
        if (!f) return -1;
        en->ent_frame = f, en->max_ent_frame = sc->nents;
    }
    return 0;
}

int ew_prepare_entities(const ew_models *md, ew_lit *lit, ew_frame *f, ew_front *fr) {
    ew_ents *en = md->ents;
    const struct ew_scene *sc = en->scene;
    ew_stats *st = &f->stats;
    en->nent_frame = 0;
    if (!sc) return 0;
    if (fr->tested_frame != md->marks->framecount) {
        if (ew_reserve_entities(en) < 0) {
            st->dropped++;
            return 0;
        }
        fr->ent_frame = en->ent_frame;
        ew_test_entities(fr, 0, sc->nents);
    }
    en->nalias = 0;
    if (sc->nents > en->max_xf) {
        ew_alias_xf *xf = realloc(en->xf, sizeof *xf * (size_t)sc->nents);
        int *list = realloc(en->alias_list, sizeof *list * (size_t)sc->nents);
        if (xf) en->xf = xf;
        if (list) en->alias_list = list;
        if (!xf || !list) {
            st->dropped++;
            return 0;
        }
        en->max_xf = sc->nents;
        uint32_t *tr = realloc(en->tint_rgba, sizeof *tr * 256 * (size_t)sc->nents);
        uint8_t *tm = realloc(en->tint_remap, 256 * (size_t)sc->nents);
        if (tr) en->tint_rgba = tr;
        if (tm) en->tint_remap = tm;
        if (!tr || !tm) {
            en->max_xf = 0;
            st->dropped++;
            return 0;
        }
    }
    size_t nxverts = 0;
    int nbox_faces = 0, boxes = ew_boxes_grow(en, sc->nents, 0) == 0;
    en->nbox = 0;
    if (!boxes) st->dropped++;  /* no item box drawn */
    for (int i = 0; i < sc->nents; i++) {
        const ew_scene_entity *e = &sc->ents[i];
        const ew_ent_frame *ef = &en->ent_frame[i];
        en->xf[i].visible = en->xf[i].hidden = 0;
        st->entities_culled += ef->culled;
        if (!ef->visible) continue;
        const ew_scene_model *m = &sc->models[e->model];
        if (m->kind == EW_MODEL_ALIAS) {
            en->ent_frame[i].xvert0 = nxverts;
            nxverts += (size_t)((const ew_mdl *)m->data)->numverts;
            en->alias_list[en->nalias++] = i;
        }
        if (m->kind == EW_MODEL_BOX) {
            if (ew_box_surfs_prepare(&en->box_surfs, &en->nbox_surfs, lit, f, e->model, m->data) < 0) st->dropped++;
            if (boxes) {
                en->box_frame[i].face0 = nbox_faces;
                nbox_faces += ((const ew_world *)m->data)->models[0].numfaces;
                en->box_list[en->nbox++] = i;
            }
        }
    }
    if (boxes && ew_boxes_grow(en, sc->nents, nbox_faces) < 0) {
        st->dropped++;
        en->nbox = 0;
    }
    en->nent_frame = sc->nents;
    if (ew_sprite_cache_grow(&en->sprite_cache, f, sc->nents) < 0) st->dropped++;  /* models drawn exactly then */
    if (nxverts > en->max_xverts) {
        ew_xvert *xv = realloc(en->xverts, sizeof *xv * nxverts);
        if (!xv) {  /* each piece poses its own then */
            st->dropped++;
            en->nalias = 0;
            return en->nbox;
        }
        en->xverts = xv, en->max_xverts = nxverts;
    }
    return en->nalias + en->nbox;
}
