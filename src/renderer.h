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

#include "hsr/hsr.h"
#include "light/light.h"
#include "light/twopass.h"
#include "pool.h"
#include "raster/blend.h"
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
    _Alignas(64) _Atomic int next_item;           /* the passes' parallel preparation */
    int      pass_items[8], npass_items;          /* per pass, its work items this frame */
    _Alignas(64) char end;
} ew_sched;

/* This frame's lit surfaces: per surface of the edge list, its cache entry
 * (normal surfaces only) and how its spans are drawn. */
typedef struct ew_lit {
    ew_surf_cache    cache;
    ew_cached_surf **surf_cache;
    ew_surf_draw    *surf_draw;
    ew_cached_surf **to_build;  int nbuild;
    int             *grad_list; int ngrad;       /* surfaces whose gradients are needed */
    uint8_t         *surf_state, *surf_mip;      /* per surface: prepare_surfaces' read-only findings */
    int              maxlm;                      /* largest light map, in samples */
    int             *blocklights;                /* building scratch, maxlm * 3 per thread */
    ew_lightcurve    curve;                      /* palette colour x light (light/curve.c) */
    const uint8_t   *nearest;                    /* 8-bit coloured light: RGB cube -> index */
    ew_twopass       tp;                         /* two-pass lighting: this frame's inputs */
    ew_tp_face      *tp_faces;                   /* two-pass lighting: per surface (max_surfs) */
} ew_lit;

/* The scene drawn with the world, and what this frame knows of it. */
typedef struct ew_ents {
    const struct ew_scene *scene;               /* or NULL */
    ew_view      *ent_views;  int max_ent_views; /* camera in each brush entity's space */
    ew_ent_frame *ent_frame;  int nent_frame, max_ent_frame;
    int           tested_frame;                 /* frame whose entities were tested in the front end */
    ew_box_surfs **box_surfs; int nbox_surfs;   /* per scene model: item box surfaces, or NULL */
    /* item boxes projected once a frame for every piece of the draw
     * (raster/models.c): per entity its frame, the faces to fill of all of
     * them, and the visible boxes, the parallel work after the alias models */
    struct ew_box_frame *box_frame; int max_box_frame;
    struct ew_box_face  *box_faces; int max_box_faces;
    int          *box_list;   int nbox;
    /* alias models posed once a frame for every band (raster/alias.h) */
    struct ew_alias_xf *xf;   int max_xf;       /* per entity */
    struct ew_xvert *xverts;  size_t max_xverts; /* their vertices, one run per visible model */
    int          *alias_list; int nalias;       /* visible alias entities, the parallel work first */
    uint32_t     *tint_rgba;                    /* per entity, 256: the palette in its light's colour */
    uint8_t      *tint_remap;                   /* per entity, 256: 8-bit, the nearest colours of that */
    /* EW_ALIAS_SPRITE_CACHE: per entity, its image kept across frames
     * (raster/alias_sprite_cache.c; sized in the prepare, slot i written only
     * by the pose work of entity i, read by the bands) */
    struct ew_sprite_cache *sprite_cache;
} ew_ents;
void ew_sprite_cache_free(struct ew_sprite_cache *c);

/* See-through polygons of this frame (world/divert.c collects them from the
 * front end, raster/seethrough.c draws them): fences first, then the
 * translucent ones back to front. */
enum { EW_SEE_OPAQUE, EW_SEE_FENCE, EW_SEE_BLEND };
typedef struct ew_see_poly {
    ew_zpoly       p;           /* clipped and projected */
    ew_zpoly_look  look;        /* its texels and how it is drawn */
    int            face, key, kind;
    float          alpha;
} ew_see_poly;
typedef struct ew_see {
    ew_see_poly *polys; int n, cap;
    int         *order;  int cap_order;  /* fences, then translucent far to near */
    int          n_drawn, nfences;       /* in order[]: all, and the fences among them */
} ew_see;

/* The reference method's frame: the polygons it fills band by band. */
typedef struct ew_ref_poly ew_ref_poly;
typedef struct ew_ref {
    ew_ref_poly *polys; int npolys, cap;
    int         *ids;                            /* ew_render_reference's face ids, or NULL */
    int         *poly_of;  size_t npoly_of;      /* two-pass lighting: each pixel's polygon */
    struct ew_ref_compose *compose;              /* its own compositing (hsr/ref_compose.c) */
} ew_ref;

struct ew_renderer {
    ew_frame    f;                               /* the frame's shared state (frame.h) */
    ew_marks    marks;
    ew_edge_list el;
    ew_span_ctx draw;
    ew_zfill    zf;
    ew_lit      lit;
    ew_ents     ents;
    ew_ref      ref;
    struct ew_spolys *spolys;                    /* beamtree, raycast: surfaces' screen polygons (hsr/surf_poly.c) */
    ew_see      see;
    ew_blend    blend;                           /* 8-bit blend, fog and tint tables */
    uint8_t    *warp_copy;                       /* the underwater warp's source frame and shifts */
    const uint8_t *warp_tint;                    /* and its tint table this frame */
    int         warp_rgb[3], warp_amount;        /* true colour: the tint itself */
    ew_sched    sched;
    ew_debug    dbg;                             /* debug modes (raster/debug.c) */
    struct ew_front_par *fpar;                   /* the parallel front end's lists (world/front_par.c), or NULL */
    int         fpar_bad;                        /* its plan failed (an irregular tree): the serial front end */
    ew_occlusion occ;                            /* faces nearer faces hide (world/occlude.c) */
    ew_lab_stats lab;                            /* this frame's probes (ew_frame_lab_stats) */
};

/* output/gamma.c: the table of a channel through gamma g (out = 255 *
 * (in / 255) ^ (1 / g)); the gamma applied to n 32-bit pixels in place
 * (R, G, B through lut, A kept). */
void ew_gamma_table(float g, uint8_t lut[256]);
void ew_gamma_pixels(uint32_t *px, size_t n, const uint8_t lut[256]);

/* bands.c: the frame's cost to draw per row (cost[0..height-1]; cost[height]
 * is scratch), from the scan's spans and the posed models, for placing the
 * draw's items. */
void ew_estimate_draw_costs(const ew_renderer *r, float *cost);

/* renderer.c: new frame number, view, per-frame tables, PVS marks, and the
 * hidden-surface method's begin. */
int  ew_frame_begin(ew_renderer *r, const ew_camera *cam);

#endif
