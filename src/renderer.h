/*
 * The renderer context (internal).  Everything a frame needs lives in an
 * ew_renderer, in one part per stage, or in an ew_band (one horizontal
 * band's scan state and spans), never in globals, so bands of one frame
 * are scanned and drawn on several threads.  docs/architecture.md draws
 * the pipeline; each stage's interface is its own header:
 *
 *   world/view.h    camera, frustum, clipping          (world/view.c, clip.c)
 *   world/front.h   PVS, BSP walk, brush models, entity culling
 *   hsr/hsr.h       hidden-surface methods: edge list (edge_scan.c), reference
 *   light/light.h   surface cache, lit surfaces, dynamic lights, model light
 *   raster/raster.h span drawers, sky, liquids, z-buffered polygons
 *   raster/zfill.h  deferred z-fill;  raster/target.h  the frame target
 *   scene/passes.h  what is drawn over the world, in order
 */
#ifndef EW_RENDERER_H
#define EW_RENDERER_H

#include "bands.h"
#include "hsr/hsr.h"
#include "light/light.h"
#include "light/twopass.h"
#include "output/gamma.h"
#include "pool.h"
#include "raster/alias.h"
#include "light/blend.h"
#include "raster/debug.h"
#include "raster/raster.h"
#include "raster/zfill.h"
#include "scene/passes.h"
#include "world/front.h"
#include "edgewise_lab.h"  /* ew_lab_stats */

#include <stdatomic.h>


/* The draw's own cut of the rows, placed after the scan by what each row
 * then holds (its spans, the models over it), since a row's cost to scan
 * and its cost to draw differ. */
typedef struct ew_draw_item {
    _Alignas(64) int y0, y1;
    ew_stats stats;      /* the moving things' counters in its rows */
    double   model_ms;   /* time it spent on them */
    double   ms;         /* its whole time */
} ew_draw_item;

/* Bands of the frame: several per thread, taken in turn by whichever
 * thread is free, with boundaries that follow the last frame's cost.  The
 * counters threads take work from sit on cache lines of their own. */
typedef struct ew_sched {
    ew_pool *pool;
    int      nthreads, nbands;
    ew_band *bands;
    ew_draw_item *items;                          /* nitems this frame, of max_items */
    int      nitems, max_items;
    float   *row_cost;                            /* per scanline and one more: what bands, items are placed by */
    int      bands_sized_for;                     /* row_cost valid for this many bands */
    int      profile_rows;                        /* ew_set_row_profile: strips of 8 rows */
    _Alignas(64) _Atomic int next_band;           /* work handed out in a phase */
    _Alignas(64) _Atomic int next_build;
    _Alignas(64) _Atomic int next_grad;
    _Alignas(64) _Atomic int next_cube;   /* the nearest-colour cubes' red steps (job_cube) */
    _Alignas(64) _Atomic int next_item;           /* the surfaces' lookup */
    _Alignas(64) char end;
} ew_sched;


struct ew_renderer {
    ew_frame    f;                               /* the frame's shared state (frame.h) */
    ew_marks    marks;
    ew_edge_list el;
    ew_span_ctx draw;
    ew_sky_comp sky;                             /* the sky's layers made one (draw.sky_comp) */
    ew_zfill    zf;
    ew_lit      lit;
    ew_ents     ents;                            /* the scene's entities this frame (raster/alias.h) */
    ew_models   models;                          /* the models pass's parts (raster/models.c) */
    ew_hsr_ctx  hsr;                             /* what the hidden-surface method sees of the frame (hsr/hsr.h) */
    ew_see      see;
    ew_blend    blend;                           /* 8-bit blend, fog and tint tables */
    ew_warp     warp;                            /* the underwater warp (raster/warp.c) */
    ew_passes   passes;                          /* what is drawn over the world, and after (scene/passes.c) */
    ew_sched    sched;
    ew_debug    dbg;                             /* debug modes (raster/debug.c) */
    ew_front    front;                           /* the front end (world/front.h) */
    ew_lab_stats lab;                            /* this frame's probes (ew_frame_lab_stats) */
};


/* The whole frame's rows (the tests' calls; raster/alias.h draws a band's). */
int  ew_draw_alias(ew_renderer *r, const ew_mdl *m, const ew_model_pose *p);
int  ew_draw_sprite(ew_renderer *r, const ew_spr *s, const ew_model_pose *p);
void ew_draw_particles(ew_renderer *r, const ew_particle *p, int n);

/* renderer.c: new frame number, view, per-frame tables, PVS marks, and the
 * hidden-surface method's begin. */
int  ew_frame_begin(ew_renderer *r, const ew_camera *cam);

#endif
