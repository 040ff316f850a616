/* Text and the statistics overlay (internal): the built-in bitmap font
 * (font.c) and its drawer into a frame target (text.c).  The public calls
 * are ew_draw_text, ew_text_size, ew_format_stats_overlay and
 * ew_draw_stats_overlay in edgewise.h. */
#ifndef EW_OVERLAY_H
#define EW_OVERLAY_H

#include <stdint.h>

#include "edgewise.h"
#include "raster/target.h"

/* The font: fixed width, a 5x7 glyph in a 6x8 cell (one column and one row
 * of spacing to the right and below).  A block of text also has a margin
 * of one font pixel on each side (see ew_text_size). */
#define EW_FONT_GLYPH_W 5
#define EW_FONT_GLYPH_H 7
#define EW_FONT_CELL_W  6
#define EW_FONT_CELL_H  8
#define EW_FONT_FIRST   32   /* ' ' */
#define EW_FONT_LAST    126  /* '~' */

/* The glyph of character c: rows[0] is the top row, bit 4 of a row the
 * leftmost column (bit 0 the fifth).  Characters outside 32..126 get the
 * box glyph (a hollow 5x7 rectangle) and the call returns 0; 1 otherwise. */
int ew_font_glyph(int c, uint8_t rows[EW_FONT_GLYPH_H]);

/* What to draw with, resolved for one target (text.c). */
typedef struct ew_text_ink {
    uint8_t  fg, dark;           /* 8-bit: text and shadow/outline indices */
    uint32_t fg_rgba, dark_rgba; /* true colour: the same as 4-byte pixels */
    int      flags;              /* EW_TEXT_SHADOW | EW_TEXT_OUTLINE | EW_TEXT_BOX */
    const uint8_t *palette;      /* 768 bytes: the 8-bit box's darkened colours */
} ew_text_ink;

/* Draws text with its block's top-left corner at (x, y), each font pixel
 * scale x scale frame pixels, clipped to the target.  0, or -1 for a bad
 * scale (1..EW_TEXT_MAX_SCALE) or NULL text. */
int ew_target_text(const ew_target *t, int x, int y, int scale, const char *text, const ew_text_ink *ink);

/* ew_draw_text and ew_draw_stats_overlay into a target whose 8-bit colours
 * are indices of pal (the renderer's public calls, renderer.c). */
int ew_text_draw(const ew_target *t, const uint8_t *pal, int x, int y, int scale, const char *text,
                 const ew_text_style *style);
int ew_stats_overlay_draw(const ew_target *t, const uint8_t *pal, const ew_stats *st, const ew_overlay_info *extra);

#endif
