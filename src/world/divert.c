/* What is not opaque does not go to the hidden-surface method: fence
 * textures (holes) and translucent surfaces (liquids the map makes
 * translucent, brush entities with an "alpha") would hide what is behind
 * them there, and the edge list gives each pixel exactly one surface.  They
 * are handed up (ew_front_out.see) for the see-through pass
 * (raster/seethrough.c) drawn over the world and the models. */
#include "world/front.h"

int ew_see_kind(const ew_front *fr, const ew_face *f, float entity_alpha, float *alpha) {
    *alpha = 1;
    if (fr->f->cfg.classic || (f->flags & EW_SURF_SKY)) return EW_SEE_OPAQUE;
    /* An entity's own alpha replaces its liquids' (as the ports do). */
    float a = entity_alpha;
    if ((f->flags & EW_SURF_TURB) && entity_alpha >= 1) {
        const ew_world *w = fr->f->world;
        const ew_texture *tex = &w->textures[w->texinfo[f->texinfo].texture];
        a = fr->f->cfg.liquid_alpha >= 0 ? fr->f->cfg.liquid_alpha : w->worldspawn.liquid_alpha[tex->liquid];
    }
    if (a < 1) {
        *alpha = a;
        return EW_SEE_BLEND;
    }
    return f->flags & EW_SURF_FENCE ? EW_SEE_FENCE : EW_SEE_OPAQUE;
}

