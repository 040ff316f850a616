/* How a frame's rows are cut into bands and draw pieces (internal,
 * src/bands.c; the public cuts are in edgewise_lab.h). */
#ifndef EW_BANDS_H
#define EW_BANDS_H

#include "raster/alias.h"  /* ew_ents */
#include "raster/zfill.h"

/* The frame's cost to draw per row (cost[0..height-1]; cost[height] is
 * scratch), from the scan's spans (zf's per-row counts) and the posed
 * models, for placing the draw's pieces. */
void ew_estimate_draw_costs(const ew_target *t, const ew_ents *en, const ew_zfill *zf, float *cost);

#endif
