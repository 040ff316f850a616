/* Debug modes (internal): the pipeline made visible (ew_set_debug,
 * ew_set_pvs_lock; raster/debug.c).  The hooks elsewhere are a branch per
 * band, surface or frame, never per pixel:
 *   renderer.c   job_draw: spans drawn by ew_debug_spans;
 *                prepare_surfaces: built surfaces become EW_DRAW_DEBUG
 *   scene/passes.c  the passes drawn the mode's way (overdraw counts,
 *                edges drawn over); no underwater warp in the structure modes
 *   light/surface.c  ew_build_surface: flat grey texture, mip tints;
 *                gather: normal light everywhere
 *   renderer.c   ew_frame_begin: the locked leaf's PVS (ew_pvs_mark) */
#ifndef EW_RASTER_DEBUG_H
#define EW_RASTER_DEBUG_H

#include "light/light.h"
#include "raster/raster.h"

#include <stdint.h>

typedef struct ew_band ew_band;

/* The modes' colours for the frame's target and palette. */
void ew_debug_init(ew_debug *d, const ew_frame *f, const ew_lightcurve *lc);
void ew_debug_free(ew_debug *d);
/* ew_set_debug: mode m (unknown: none); -1 without memory for it, else 1
 * when surfaces built in the old mode must be rebuilt, 0 when not. */
int  ew_debug_set(ew_debug *d, const ew_target *t, int m);
void ew_debug_pvs_lock(ew_debug *d, int on);
/* A band's spans (band: its number), each in its own colour (instead of
 * ew_draw_spans). */
void ew_debug_spans(const ew_span_ctx *draw, const ew_band *b, int band);
/* What the modes draw over a band's world, by the pass list
 * (scene/passes.c): the edges drawn over its rows; overdraw: the band's
 * spans counted, a pass's rows kept before it draws and the pixels it
 * changed counted after, then the counts painted. */
/* Every edge of the global edge list crossing rows, a pixel a row where the
 * scan puts its span's first pixel (shows_edges: the method scans that list,
 * EW_HSR_SHOWS_EDGES). */
void ew_debug_edges(const ew_debug *dbg, const ew_frame *f, const ew_edge_list *el, int shows_edges,
                    const ew_rows *rows);
void ew_debug_count_spans(ew_debug *d, const ew_target *t, const ew_band *b, const ew_rows *rows);
void ew_debug_snap(ew_debug *d, const ew_target *t, const ew_rows *rows);
void ew_debug_count_changes(ew_debug *d, const ew_target *t, const ew_rows *rows);
void ew_debug_paint_heat(const ew_debug *d, const ew_target *t, const ew_rows *rows);
/* A span of one colour (EW_DRAW_DEBUG surfaces: colour in d->flat). */
void ew_debug_fill_span(const ew_span_ctx *c, const ew_span *sp, uint32_t color);

#endif
