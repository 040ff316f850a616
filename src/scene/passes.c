/* What is drawn over the opaque world, in this order.  The edge list has
 * given every pixel exactly one world surface; each pass adds what can be
 * seen in front of (or through) it, z-tested against what is there. */
#include "renderer.h"

static const ew_pass passes[] = {
    /* alias models, sprites, item boxes, particles */
    {"models", ew_prepare_entities, ew_models_work, ew_draw_models},
    /* fence textures: holes show the world and the models behind */
    {"fences", ew_see_prepare, NULL, ew_draw_fences},
    /* fog over everything opaque, by its depth */
    {"fog", ew_fog_prepare, NULL, ew_draw_fog},
    /* translucent surfaces, far to near, each fogged at its own depth */
    {"translucent", NULL, NULL, ew_draw_translucent},
};
/* A method that composites for itself (EW_HSR_OWN_COMPOSE: the reference)
 * runs the models, then its own fences, translucent surfaces and fog,
 * per pixel (hsr/ref_compose.c), and none of the shared passes above: it
 * is what they are checked against. */
static int compose_prepare(ew_renderer *r) { return ew_ref_compose_prepare(&r->hsr); }
static void compose_draw(ew_renderer *r, const ew_rows *rows) { ew_ref_compose_draw(&r->hsr, rows); }
static const ew_pass own_passes[] = {
    {"models", ew_prepare_entities, ew_models_work, ew_draw_models},
    {"compose", compose_prepare, NULL, compose_draw},
};
/* After the bands: the underwater warp and tint (raster/warp.c, ew_render). */
enum { NPASSES = sizeof passes / sizeof *passes, NOWN = sizeof own_passes / sizeof *own_passes };
_Static_assert(NPASSES <= sizeof ((ew_sched *)0)->pass_items / sizeof(int), "room for every pass's work");
_Static_assert(NOWN <= NPASSES, "room for every pass's work");

/* The frame's list: its method's choice. */
static const ew_pass *pass_list(const ew_renderer *r, int *n) {
    if (r->f.cfg.hsr && (r->f.cfg.hsr->flags & EW_HSR_OWN_COMPOSE)) {
        *n = NOWN;
        return own_passes;
    }
    *n = NPASSES;
    return passes;
}

void ew_passes_prepare(ew_renderer *r) {
    ew_sched *s = &r->sched;
    int np;
    const ew_pass *passes = pass_list(r, &np);
    s->npass_items = 0;
    for (int i = 0; i < np; i++) {
        int n = passes[i].prepare ? passes[i].prepare(r) : 0;
        s->pass_items[i] = passes[i].work && n > 0 ? n : 0;
        s->npass_items += s->pass_items[i];
    }
    atomic_store(&s->next_item, 0);
}

void ew_passes_work(ew_renderer *r) {
    ew_sched *s = &r->sched;
    int np;
    const ew_pass *passes = pass_list(r, &np);
    (void)np;
    for (int k; (k = atomic_fetch_add(&s->next_item, 1)) < s->npass_items;) {
        int i = 0;
        while (k >= s->pass_items[i]) k -= s->pass_items[i++];
        passes[i].work(r, k);
    }
}

int ew_pass_count(const ew_renderer *r) {
    int np;
    pass_list(r, &np);
    return np;
}
const char *ew_pass_name(const ew_renderer *r, int i) {
    int np;
    return pass_list(r, &np)[i].name;
}
void ew_pass_draw(ew_renderer *r, const ew_rows *rows, int i) {
    int np;
    pass_list(r, &np)[i].draw(r, rows);
}

void ew_passes_draw(ew_renderer *r, const ew_rows *rows) {
    int np;
    const ew_pass *passes = pass_list(r, &np);
    for (int i = 0; i < np; i++) passes[i].draw(r, rows);
}
