/* The edge list's polygons one row at a time, for the methods that resolve
 * visibility polygon by polygon (spans, zbuffer, painter, drawbuffer).
 *
 * Those methods share the edge list's front end (ew_edge_begin,
 * ew_edge_face, ew_edge_poly), so their surfaces and edges are the edge
 * method's.  Here a band finds each surface's edges, orders the surfaces
 * front to back by BSP key and, row by row, hands out every polygon
 * crossing the row with its pixel extent [xl, xr): the pixels the edge
 * scan would give the polygon if it were alone (the same 16.16 u, the same
 * rounding), so abutting polygons tile a row with no gap and no pixel
 * twice.  Brush-model fragments sharing a key (one leaf) are ordered on
 * each row by 1/z where they overlap, as the edge scan decides between
 * them.  So a method that keeps the nearest polygon at each pixel gives
 * the edge list's frame exactly.
 *
 * Everything lives in the band's scratch (ew_band_scratch): bands resolve
 * on several threads at once. */
#ifndef EW_HSR_POLY_ROWS_H
#define EW_HSR_POLY_ROWS_H

#include "hsr/hsr.h"

typedef struct ew_row_poly {
    int32_t surf, xl, xr;  /* surface, pixels [xl, xr) of the current row */
} ew_row_poly;

typedef struct ew_poly_rows {
    const ew_edge_list *el;
    ew_band *b;
    int width, v;              /* v: the current row */
    int nband;                 /* surfaces with an edge in the band */
    int32_t *first, *ent;      /* per surface: its band edges ent[first[s] .. first[s + 1]), edge << 1 | leads */
    int32_t *order;            /* the band's surfaces, front to back */
    int32_t *top, *bot;        /* per surface: its rows in the band [top, bot] */
    int32_t *vmin;             /* per surface: its first row in the frame */
    int32_t *head, *next;      /* surfaces by first row in the band, front to back */
    int32_t *act, *act2;       /* ranks of the surfaces crossing the row, ascending */
    int32_t *rank;             /* per surface: its place in order */
    int nact;
    ew_row_poly *row;          /* this row's polygons, front to back */
    int nrow, cap_row;
} ew_poly_rows;

/* Starts band b: indexes the frame's edges and orders its surfaces, and
 * returns extra bytes of the band's scratch for the method (contents left
 * over: the method clears what it needs), or NULL when out of memory (the
 * caller then fills the band with the background: ew_poly_rows_background).
 * Also clears b's spans and has_spans. */
void *ew_poly_rows_begin(ew_poly_rows *pr, const ew_hsr_ctx *c, ew_band *b, size_t extra);
/* Every row of b the background alone (a band that could not resolve). */
void ew_poly_rows_background(ew_band *b, int width);

/* Moves to the next row of the band and lists its polygons front to back
 * in pr->row; 0 when the band is done. */
int ew_poly_rows_next(ew_poly_rows *pr);

/* 1 if surface s's top row (over the whole frame) lies in this band: a
 * polygon is counted once however many bands it crosses. */
int ew_poly_rows_starts_here(const ew_poly_rows *pr, int s);

/* Emits a row's disjoint pieces sorted left to right (sorting p in place)
 * with the background (surface 0) in every gap, so the row is complete. */
void ew_poly_rows_emit_sorted(ew_poly_rows *pr, ew_row_poly *p, int n);

/* The method's memory: what it used of the bands' scratch this frame. */
size_t ew_poly_rows_memory(const ew_hsr_ctx *c);

#endif
