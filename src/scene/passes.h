/* What is drawn over the opaque world, in order (internal, scene/passes.c).
 * The world's spans come first and own every pixel once; each pass then
 * draws, band by band, only in its band's rows, z-tested against what is
 * there.  The list is in scene/passes.c: models, fences, fog, translucent
 * surfaces; or, for a method with its own compositing (the reference),
 * models then its compose.  Then the whole-frame passes (the underwater
 * warp, the output gamma), which read or change rows of other bands: they
 * run after every band is drawn, band by band again.
 *
 * A pass is given the stages' parts it reads (ew_pass_ctx), set up once by
 * the renderer (renderer.c), not the renderer. */
#ifndef EW_SCENE_PASSES_H
#define EW_SCENE_PASSES_H

#include "frame.h"
#include "light/light.h"
#include "raster/alias.h"
#include "raster/debug.h"
#include "raster/raster.h"
#include "raster/zfill.h"

#include <stdatomic.h>


/* The parts of the frame the passes read and write. */
typedef struct ew_pass_ctx {
    ew_frame          *f;
    ew_span_ctx       *draw;   /* the span drawers' tables (fog) */
    ew_zfill          *zf;
    ew_blend          *blend;
    ew_see            *see;
    ew_warp           *warp;
    ew_debug          *dbg;
    const ew_edge_list *el;    /* the edge debug view */
    ew_lit            *lit;    /* the lit surfaces (see-through ones join the world's builds) */
    const ew_models   *models; /* the models pass's parts */
    struct ew_hsr_ctx *hsr;    /* the method's own compositing (the reference) */
    struct ew_front   *front;  /* the entities' listing (world/entities.c) */
} ew_pass_ctx;

typedef struct ew_pass {
    const char *name;
    /* Once a frame, serial, after the scan and before the bands draw;
     * returns how many work items it leaves for work() (NULL: nothing).
     * A whole-frame pass: after every band is drawn; 0 when it has
     * nothing to do this frame. */
    int  (*prepare)(const ew_pass_ctx *c);
    /* One item of the frame's preparation, in parallel with the surface
     * builds, before any band draws (NULL: none). */
    void (*work)(const ew_pass_ctx *c, int item);
    /* In one band's rows, after that band's world spans (parallel across
     * bands); a whole-frame pass: after every band is drawn. */
    void (*draw)(const ew_pass_ctx *c, const ew_rows *rows);
    int  whole_frame;
} ew_pass;

enum { EW_MAX_PASSES = 8 };

/* The frame's pass list and its work in progress. */
typedef struct ew_passes {
    ew_pass_ctx ctx;
    int items[EW_MAX_PASSES], nitems;  /* per pass, its work items this frame */
    int after[EW_MAX_PASSES], nafter;  /* the whole-frame passes with work this frame */
    _Alignas(64) _Atomic int next_item;
    _Alignas(64) char end;
} ew_passes;

/* The frame's list as its method chooses it (the whole-frame passes last):
 * how many, and the name of the i-th. */
int         ew_pass_count(const ew_passes *p);
const char *ew_pass_name(const ew_passes *p, int i);

/* Every band pass's prepare, in order; the work items they leave are then
 * taken by ew_passes_work on every thread until none is left. */
void ew_passes_prepare(ew_passes *p);
void ew_passes_work(ew_passes *p);
/* The band passes in one band's rows (b: its scan's band, for the debug
 * views, which draw the passes their own way). */
void ew_passes_draw(const ew_passes *p, const ew_band *b, const ew_rows *rows);
/* The whole-frame passes: which have work this frame (serial, once every
 * band is drawn; returns how many), then those in one band's rows. */
int  ew_passes_after_begin(ew_passes *p);
void ew_passes_after(const ew_passes *p, const ew_rows *rows);

#endif
