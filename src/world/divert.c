/* What is not opaque does not go to the hidden-surface method: fence
 * textures (holes) and translucent surfaces (liquids the map makes
 * translucent, brush entities with an "alpha") would hide what is behind
 * them there, and the edge list gives each pixel exactly one surface.  They
 * are collected here, clipped and projected, for the see-through pass
 * (raster/seethrough.c) drawn over the world and the models. */
#include "renderer.h"

#include <stdlib.h>

int ew_see_kind(const ew_renderer *r, const ew_face *f, float entity_alpha, float *alpha) {
    *alpha = 1;
    if (r->f.cfg.classic || (f->flags & EW_SURF_SKY)) return EW_SEE_OPAQUE;
    /* An entity's own alpha replaces its liquids' (as the ports do). */
    float a = entity_alpha;
    if ((f->flags & EW_SURF_TURB) && entity_alpha >= 1) {
        const ew_world *w = r->f.world;
        const ew_texture *tex = &w->textures[w->texinfo[f->texinfo].texture];
        a = r->f.cfg.liquid_alpha >= 0 ? r->f.cfg.liquid_alpha : w->worldspawn.liquid_alpha[tex->liquid];
    }
    if (a < 1) {
        *alpha = a;
        return EW_SEE_BLEND;
    }
    return f->flags & EW_SURF_FENCE ? EW_SEE_FENCE : EW_SEE_OPAQUE;
}

int ew_see_to_hsr(const ew_renderer *r, int kind) {
    return kind == EW_SEE_OPAQUE || (kind == EW_SEE_FENCE && (r->f.cfg.hsr->flags & EW_HSR_FENCES));
}

void ew_see_add(ew_renderer *r, float (*verts)[3], int n, int fi, const ew_view *v, int key, int kind,
                float alpha) {
    ew_see *see = &r->see;
    if (see->n == see->cap) {
        int cap = see->cap ? see->cap * 2 : 64;
        if (cap > r->el.max_surfs) {  /* the same budget as the edge list's */
            r->f.stats.dropped++;
            return;
        }
        ew_see_poly *p = realloc(see->polys, sizeof *p * (size_t)cap);
        if (!p) {
            r->f.stats.dropped++;
            return;
        }
        see->polys = p, see->cap = cap;
    }
    ew_see_poly *sp = &see->polys[see->n];
    if (!ew_zpoly_project(&r->f.view, verts, n, &sp->p)) return;  /* outside the frustum */
    sp->face = fi, sp->key = key, sp->kind = kind, sp->alpha = alpha;
    sp->look = (ew_zpoly_look){r->f.world, &r->f.world->faces[fi], v, NULL, NULL, 0, 0, 1, EW_ZP_OPAQUE, NULL, 256};
    see->n++;
}
