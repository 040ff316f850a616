/* What is drawn over the opaque world, in order (internal, scene/passes.c).
 * The world's spans come first and own every pixel once; each pass then
 * draws, band by band, only in its band's rows, z-tested against what is
 * there.  The list is in scene/passes.c: models, fences, fog, translucent
 * surfaces; or, for a method with its own compositing (the reference),
 * models then its compose. */
#ifndef EW_SCENE_PASSES_H
#define EW_SCENE_PASSES_H

#include "raster/raster.h"

typedef struct ew_pass {
    const char *name;
    /* Once a frame, serial, after the scan and before the bands draw;
     * returns how many work items it leaves for work() (NULL: nothing). */
    int  (*prepare)(ew_renderer *r);
    /* One item of the frame's preparation, in parallel with the surface
     * builds, before any band draws (NULL: none). */
    void (*work)(ew_renderer *r, int item);
    /* In one band's rows, after that band's world spans (parallel across bands). */
    void (*draw)(ew_renderer *r, const ew_rows *rows);
} ew_pass;

/* Every pass's prepare, in order; the work items they leave are then taken
 * by ew_passes_work on every thread until none is left. */
void ew_passes_prepare(ew_renderer *r);
void ew_passes_work(ew_renderer *r);
void ew_passes_draw(ew_renderer *r, const ew_rows *rows);
/* The passes one at a time (the overdraw debug mode counts each). */
int         ew_pass_count(const ew_renderer *r);
const char *ew_pass_name(const ew_renderer *r, int i);
void        ew_pass_draw(ew_renderer *r, const ew_rows *rows, int i);

/* raster/models.c: alias models, sprites, item boxes, then particles,
 * z-buffered over the z-filled world.  (Brush models are in the world.)
 * ew_models_work does the frame's item-th piece of the work
 * ew_prepare_entities leaves: the visible alias models posed, then the item
 * boxes projected, once for every piece of the draw. */
void ew_draw_models(ew_renderer *r, const ew_rows *rows);
void ew_models_work(ew_renderer *r, int item);
/* raster/models_prepare.c: the models' pass prepared (serial): the
 * entities the front end let through (tested here unless its phases did,
 * world/entities.c), their poses' and item boxes' room; returns how many
 * alias models are left to pose and item boxes to project (ew_models_work).
 * Out of memory: no entities (counted in dropped).  ew_reserve_entities
 * sizes ents.ent_frame for the scene (-1 out of memory). */
int  ew_prepare_entities(ew_renderer *r);
int  ew_reserve_entities(ew_renderer *r);

/* raster/seethrough.c: fence textures (alpha-tested, z-written), then
 * translucent surfaces (blended far to near, no z), as the front end
 * collected them (world/divert.c). */
int  ew_see_prepare(ew_renderer *r);
void ew_draw_fences(ew_renderer *r, const ew_rows *rows);
void ew_draw_translucent(ew_renderer *r, const ew_rows *rows);
/* Adds face fi's world-space polygon (seen through v, the camera in the
 * face's space) to the see-through list with its BSP key (the front end's
 * ew_front_out.see). */
void ew_see_add(ew_renderer *r, float (*verts)[3], int n, int fi, const ew_view *v, int key, int kind, float alpha);

/* raster/fog.c: fog over what is opaque by its depth (the translucent
 * surfaces fog their own texels as they blend). */
int  ew_fog_prepare(ew_renderer *r);
void ew_draw_fog(ew_renderer *r, const ew_rows *rows);

/* raster/warp.c: the underwater view, after every band is drawn (it reads
 * rows of other bands): the frame warped and tinted by the liquid the eye
 * is in.  ew_warp_begin (serial) returns 0 when there is nothing to do. */
int  ew_warp_begin(ew_renderer *r);
void ew_warp_rows(ew_renderer *r, int y0, int y1);

#endif
