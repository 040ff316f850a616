/* Entities of the scene, once per frame before the bands draw: which ones
 * the frustum and the PVS let through, with the light on each (alias
 * models, through ew_front_out.entity_light), so the bands only draw.
 * Brush entities are not here: they went into the world.  The models'
 * prepare (raster/models_prepare.c) sizes the answers and makes the rest
 * of what the bands read. */
#include "world/front.h"
#include "asset/mdl.h"
#include "asset/spr.h"
#include "asset/scene.h"

/* How far a model reaches from its origin, for the PVS and frustum tests. */
static float model_reach(const ew_scene_model *m) {
    return m->kind == EW_MODEL_ALIAS  ? ((const ew_mdl *)m->data)->radius
           : m->kind == EW_MODEL_BOX ? 64.0f
                                      : ((const ew_spr *)m->data)->radius;
}

void ew_test_entities(ew_front *fr, int from, int to) {
    const struct ew_scene *sc = fr->scene;
    for (int i = from; i < to; i++) {
        const ew_scene_entity *e = &sc->ents[i];
        ew_ent_frame *ef = &fr->ent_frame[i];
        ef->visible = ef->culled = 0;
        if (e->model < 0) continue;  /* brush entities are in the edge list */
        const ew_scene_model *m = &sc->models[e->model];
        /* Potentially visible at all?  A box around the model against the
         * PVS and the frustum. */
        float reach = model_reach(m), lo[3], hi[3];
        for (int k = 0; k < 3; k++) lo[k] = e->origin[k] - reach, hi[k] = e->origin[k] + reach;
        if (ew_cull_box(&fr->f->view, lo, hi, 15) < 0 || !ew_box_in_pvs(fr, lo, hi)) {  /* the cheap test first */
            ef->culled = 1;
            continue;
        }
        ef->visible = 1;
        if (m->kind == EW_MODEL_ALIAS) fr->out.entity_light(fr->out.ctx, e->origin, ef);
    }
}
