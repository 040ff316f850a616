/* Debug modes (internal): the pipeline made visible (ew_set_debug,
 * ew_set_pvs_lock; raster/debug.c).  The hooks elsewhere are a branch per
 * band, surface or frame, never per pixel:
 *   renderer.c   job_draw: spans drawn by ew_debug_spans, the passes by
 *                ew_debug_passes (overdraw counts, edges drawn over);
 *                prepare_surfaces: built surfaces become EW_DRAW_DEBUG;
 *                ew_render: no underwater warp in the structure modes;
 *                ew_frame_begin: the locked leaf's PVS (ew_pvs_mark)
 *   light/surface.c  ew_build_surface: flat grey texture, mip tints;
 *                gather: normal light everywhere */
#ifndef EW_RASTER_DEBUG_H
#define EW_RASTER_DEBUG_H

#include "raster/raster.h"

#include <stdint.h>

typedef struct ew_renderer ew_renderer;
typedef struct ew_band ew_band;

enum { EW_DBG_HEAT = 6 };  /* overdraw colours: 0, 1, ... 5 or more writes */

typedef struct ew_debug {
    int      mode;                 /* ew_debug_mode */
    int      pvs_lock, pvs_leaf;   /* locked: the leaf whose PVS is marked (-1: the next frame's) */
    int      last_leaf;            /* the eye's leaf at the last frame, -1 before one */
    uint8_t  grey;                 /* lighting: the flat texture's palette index */
    /* colours as the target stores them: a palette index (8-bit) or ew_rgba */
    uint32_t mip[4], build, edge, heat[EW_DBG_HEAT];
    uint8_t *count;                /* overdraw: writes per pixel */
    uint8_t *snap;                 /* overdraw: a band's pixels before a pass */
} ew_debug;

/* Modes that show the structure of the frame: no underwater warp. */
static inline int ew_debug_structure(const ew_debug *d) {
    return d->mode >= 1 && d->mode <= 3;  /* spans, edges, overdraw */
}

void ew_debug_init(ew_renderer *r);
void ew_debug_free(ew_renderer *r);
/* A band's spans, each in its own colour (instead of ew_draw_spans). */
void ew_debug_spans(ew_renderer *r, const ew_band *b);
/* What a mode draws over a band's world instead of ew_passes_draw. */
void ew_debug_passes(ew_renderer *r, const ew_band *b, const ew_rows *rows);
/* A span of one colour (EW_DRAW_DEBUG surfaces: colour in d->flat). */
void ew_debug_fill_span(const ew_span_ctx *c, const ew_span *sp, uint32_t color);
/* A lit surface of width x height texels in mip's colour. */
void ew_debug_mip_surface(const ew_renderer *r, int mip, uint8_t *out, int width, int height);

#endif
