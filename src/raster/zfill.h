/* Deferred z-fill (internal, raster/zfill.c).  Only moving things read the
 * z-buffer, and they usually cover a small part of the frame, so the
 * world's 1/z is written where they are about to be drawn instead of under
 * every span: the same values, a fraction of the memory traffic. */
#ifndef EW_RASTER_ZFILL_H
#define EW_RASTER_ZFILL_H

#include "raster/raster.h"

typedef struct ew_zfill {
    int all;                          /* 1: z-filled under every span as drawn (ew_set_full_zfill) */
    const ew_target    *target;
    const ew_band      *bands;        /* this frame's spans ... */
    const ew_surf_draw *draw;         /* ... and their gradients */
    /* per row: the band and spans that cover it, and [zlo, zhi) already filled */
    int32_t *row_band, *row_span0, *row_nspans, *zlo, *zhi;
} ew_zfill;

/* The world's 1/z under one span (full z-fill). */
void ew_zfill_span(const ew_target *t, const ew_span *sp, const ew_gradients *g);
/* Makes the z-buffer hold the world's 1/z over [x0, x1) x [y0, y1)
 * (clipped to the frame), filling from this frame's spans only what is not
 * filled yet.  Every moving thing calls it for its screen box before its z
 * test; a caller drawing in a band passes rows inside that band. */
void ew_zfill_rect(ew_zfill *z, int x0, int y0, int x1, int y1);
/* Row y's spans from the first that may reach past column lo: *first, and
 * the count returned (0: no spans indexed for the row).  *sorted: they run
 * left to right, disjoint, so a caller stops at the first past its
 * interval; else (an overdrawing method's) every one must be looked at. */
int ew_zfill_row_spans(const ew_zfill *z, int y, int lo, const ew_span **first, int *sorted);
/* Indexes a scanned band's spans by row and marks its rows unfilled. */
void ew_zfill_index_band(ew_zfill *z, const ew_band *b, int band);
/* Declares every row filled (the reference path's own z, a caller's). */
void ew_zfill_mark_all(ew_zfill *z);

#endif
