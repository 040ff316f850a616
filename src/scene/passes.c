/* What is drawn over the opaque world, in this order.  The edge list has
 * given every pixel exactly one world surface; each pass adds what can be
 * seen in front of (or through) it, z-tested against what is there.  Then
 * the whole-frame passes, once every band is drawn.  Each entry hands its
 * stage the parts it reads (ew_pass_ctx). */
#include "scene/passes.h"
#include "hsr/hsr.h"
#include "output/gamma.h"
#include "world/front.h"  /* ew_prepare_entities */

#include <string.h>

/* ---- the entries: each stage given its parts ---- */

static int models_prepare(const ew_pass_ctx *c) { return ew_prepare_entities(c->models, c->lit, c->f, c->front); }
static void models_work(const ew_pass_ctx *c, int item) { ew_models_work(c->models, c->f, item); }
static void models_draw(const ew_pass_ctx *c, const ew_rows *rows) { ew_draw_models(c->models, c->f, rows); }

static int see_prepare(const ew_pass_ctx *c) {
    ew_see_prepare(c->see, c->f, c->lit);
    return 0;
}
static void fences_draw(const ew_pass_ctx *c, const ew_rows *rows) {
    ew_draw_fences(c->see, c->f, c->draw, c->zf, rows);
}
static void translucent_draw(const ew_pass_ctx *c, const ew_rows *rows) {
    ew_draw_translucent(c->see, c->f, c->draw, c->zf, rows);
}

/* The span draw may leave out what fog covers whole, but not in the debug
 * views (they show what is drawn) nor with the full z-fill (the drawers
 * write its z). */
static int fog_prepare(const ew_pass_ctx *c) {
    ew_fog_prepare(c->draw, c->f, c->blend, c->dbg->mode == EW_DEBUG_NONE && !c->zf->all);
    return 0;
}
static void fog_draw(const ew_pass_ctx *c, const ew_rows *rows) {
    ew_draw_fog(&c->draw->fog, &c->f->target, c->zf, c->lit->surf_draw, rows);
}

static int compose_prepare(const ew_pass_ctx *c) {
    c->draw->fog.fill = 0;  /* its fog is its own: the spans drawn whole */
    return ew_ref_compose_prepare(c->hsr);
}
static void compose_draw(const ew_pass_ctx *c, const ew_rows *rows) { ew_ref_compose_draw(c->hsr, rows); }

/* The underwater view reads rows of other bands; none in the modes that
 * show the frame's structure. */
static int warp_prepare(const ew_pass_ctx *c) {
    return !ew_debug_structure(c->dbg) && ew_warp_begin(c->warp, c->f, c->blend);
}
static void warp_draw(const ew_pass_ctx *c, const ew_rows *rows) {
    ew_warp_rows(c->warp, &c->f->target, rows->y0, rows->y1);
}

/* True colour: the output gamma, last. */
static int gamma_prepare(const ew_pass_ctx *c) { return c->f->target.bpp == 4 && c->f->cfg.gamma != 1; }
static void gamma_draw(const ew_pass_ctx *c, const ew_rows *rows) {
    const ew_target *t = &c->f->target;
    size_t w = (size_t)t->width;
    ew_gamma_pixels((uint32_t *)(void *)t->pixels + (size_t)rows->y0 * w, (size_t)(rows->y1 - rows->y0) * w,
                    c->f->cfg.gamma_lut);
}

/* ---- the lists ---- */

static const ew_pass passes[] = {
    /* alias models, sprites, item boxes, particles */
    {"models", models_prepare, models_work, models_draw, 0},
    /* fence textures: holes show the world and the models behind */
    {"fences", see_prepare, NULL, fences_draw, 0},
    /* fog over everything opaque, by its depth */
    {"fog", fog_prepare, NULL, fog_draw, 0},
    /* translucent surfaces, far to near, each fogged at its own depth */
    {"translucent", NULL, NULL, translucent_draw, 0},
    /* after every band: the underwater warp and tint, then the gamma */
    {"warp", warp_prepare, NULL, warp_draw, 1},
    {"gamma", gamma_prepare, NULL, gamma_draw, 1},
};
/* A method that composites for itself (EW_HSR_OWN_COMPOSE: the reference)
 * runs the models, then its own fences, translucent surfaces and fog,
 * per pixel (hsr/ref_compose.c), and none of the shared passes above: it
 * is what they are checked against. */
static const ew_pass own_passes[] = {
    {"models", models_prepare, models_work, models_draw, 0},
    {"compose", compose_prepare, NULL, compose_draw, 0},
    {"warp", warp_prepare, NULL, warp_draw, 1},
    {"gamma", gamma_prepare, NULL, gamma_draw, 1},
};
enum { NPASSES = sizeof passes / sizeof *passes, NOWN = sizeof own_passes / sizeof *own_passes };
_Static_assert((int)NPASSES <= (int)EW_MAX_PASSES && (int)NOWN <= (int)EW_MAX_PASSES, "room for every pass's work");

/* The frame's list: its method's choice. */
static const ew_pass *pass_list(const ew_passes *p, int *n) {
    const ew_config *cfg = &p->ctx.f->cfg;
    if (cfg->hsr && (cfg->hsr->flags & EW_HSR_OWN_COMPOSE)) {
        *n = NOWN;
        return own_passes;
    }
    *n = NPASSES;
    return passes;
}

int ew_pass_count(const ew_passes *p) {
    int n;
    pass_list(p, &n);
    return n;
}

const char *ew_pass_name(const ew_passes *p, int i) {
    int n;
    const ew_pass *list = pass_list(p, &n);
    return i >= 0 && i < n ? list[i].name : NULL;
}

void ew_passes_prepare(ew_passes *p) {
    int np;
    const ew_pass *list = pass_list(p, &np);
    p->nitems = 0;
    for (int i = 0; i < np; i++) {
        int n = !list[i].whole_frame && list[i].prepare ? list[i].prepare(&p->ctx) : 0;
        p->items[i] = list[i].work && n > 0 ? n : 0;
        p->nitems += p->items[i];
    }
    atomic_store(&p->next_item, 0);
}

void ew_passes_work(ew_passes *p) {
    int np;
    const ew_pass *list = pass_list(p, &np);
    (void)np;
    for (int k; (k = atomic_fetch_add(&p->next_item, 1)) < p->nitems;) {
        int i = 0;
        while (k >= p->items[i]) k -= p->items[i++];
        list[i].work(&p->ctx, k);
    }
}

/* Overdraw: each pass over the world (fog aside) counted where it changed
 * a pixel. */
static void draw_counted(const ew_passes *p, const ew_pass *list, int np, const ew_band *b, const ew_rows *rows) {
    const ew_pass_ctx *c = &p->ctx;
    const ew_target *t = &c->f->target;
    ew_debug_count_spans(c->dbg, t, b, rows);
    for (int i = 0; i < np; i++) {
        if (list[i].whole_frame || strcmp(list[i].name, "fog") == 0) continue;
        ew_debug_snap(c->dbg, t, rows);
        list[i].draw(c, rows);
        ew_debug_count_changes(c->dbg, t, rows);
    }
    ew_debug_paint_heat(c->dbg, t, rows);
}

void ew_passes_draw(const ew_passes *p, const ew_band *b, const ew_rows *rows) {
    int np;
    const ew_pass *list = pass_list(p, &np);
    switch (p->ctx.dbg->mode) {
    case EW_DEBUG_SPANS:
        return;  /* the spans alone */
    case EW_DEBUG_OVERDRAW:
        draw_counted(p, list, np, b, rows);
        return;
    default:
        break;
    }
    for (int i = 0; i < np; i++)
        if (!list[i].whole_frame) list[i].draw(&p->ctx, rows);
    if (p->ctx.dbg->mode == EW_DEBUG_EDGES) ew_debug_edges(p->ctx.dbg, p->ctx.f, p->ctx.el, (p->ctx.f->cfg.hsr->flags & EW_HSR_SHOWS_EDGES) != 0, rows);
}

int ew_passes_after_begin(ew_passes *p) {
    int np;
    const ew_pass *list = pass_list(p, &np);
    p->nafter = 0;
    for (int i = 0; i < np; i++)
        if (list[i].whole_frame && list[i].prepare(&p->ctx)) p->after[p->nafter++] = i;
    return p->nafter;
}

void ew_passes_after(const ew_passes *p, const ew_rows *rows) {
    int np;
    const ew_pass *list = pass_list(p, &np);
    (void)np;
    for (int k = 0; k < p->nafter; k++) list[p->after[k]].draw(&p->ctx, rows);
}
