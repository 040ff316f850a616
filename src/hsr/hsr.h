/* Hidden-surface removal (internal): one interface, one file per method.
 *
 * The front end (world/) walks the BSP front to back and hands every
 * visible, camera-facing world face and every brush-model polygon to the
 * frame's method; each band of the frame is then resolved into spans for
 * the back end to draw (hsr/edge_scan.c: Quake's global edge list) or
 * straight into pixels (hsr/reference.c: a per-pixel z-buffer the tests
 * trust).  Each method is one file here with its own ew_hsr, listed in
 * hsr/methods.c under its ew_hsr_method.
 *
 * What resolve may hand the back end: spans grouped by row, rows in
 * ascending order.  A method whose spans in a row are disjoint and left to
 * right (the edge list's) leaves b->unsorted 0; one that draws a pixel more
 * than once (painter's order, a z-buffer) sets it, and then the spans are
 * drawn in the order given, later over earlier, and the accounting counts
 * the distinct pixels for itself. */
#ifndef EW_HSR_H
#define EW_HSR_H

#include "world/view.h"

typedef struct ew_renderer ew_renderer;
typedef struct ew_band ew_band;

typedef struct ew_hsr {
    const char *name;
    /* A frame starts (serial, after the view and the PVS are set). */
    void (*begin)(ew_renderer *r);
    /* A visible world face facing the camera, in BSP order front to back;
     * key grows from front to back (serial, from the walk).  With several
     * threads, a method whose face is ew_emit_face gets the same edge list
     * from world/front_par.c instead, which does not call it. */
    void (*face)(ew_renderer *r, int face, int clipflags, int key);
    /* A brush-model polygon in world space: face fi of a moved model seen
     * through v (the camera in the model's space), sorting at BSP key key
     * (serial). */
    void (*poly)(ew_renderer *r, float (*verts)[3], int n, int fi, const ew_view *v, int key);
    /* Resolves rows [b->y0, b->y1): spans into b, or pixels into the frame
     * (parallel: one band per call, bands never share rows). */
    void (*resolve)(ew_renderer *r, ew_band *b);
    /* 1: fence faces go to face/poly too and their holes are the method's
     * business (the reference); 0: they go to the see-through pass. */
    int fences;
    /* What each of the band counters (ew_band.counters, summed into
     * ew_stats.hsr_counters) counts; NULL: unused. */
    const char *counters[EW_HSR_COUNTERS];
    /* 1: every world pixel is written exactly once (overdraw 1.0 is an
     * invariant the soak checks); 0: the method may overdraw or writes no
     * spans (the reference). */
    int exact_once;
    /* Bytes the method holds for the frame beyond the edge list and the
     * bands' spans (ew_stats.hsr_bytes); NULL: none. */
    size_t (*memory)(const ew_renderer *r);
    /* The front end is done, no band resolved yet (serial); NULL: nothing
     * to do.  The edge list's scans sort its edges by row here. */
    void (*finish)(ew_renderer *r);
    /* 1: the method composites fences, translucent surfaces and fog over
     * its opaque pixels itself (the reference: hsr/ref_compose.c), and the
     * pass list runs its compose instead of the shared passes
     * (scene/passes.c); 0: the shared fences, fog and translucent passes. */
    int own_compose;
} ew_hsr;

extern const ew_hsr ew_hsr_edge;       /* hsr/edge_scan.c + world/edges.c */
extern const ew_hsr ew_hsr_reference;  /* hsr/reference.c */
extern const ew_hsr ew_hsr_edge_z;     /* hsr/edge_z.c: the edge list sorted by 1/z */
/* Polygon by polygon over the edge list's polygons (hsr/poly_rows.h). */
extern const ew_hsr ew_hsr_spans;      /* hsr/spans.c */
extern const ew_hsr ew_hsr_zbuffer;    /* hsr/zbuffer.c */
extern const ew_hsr ew_hsr_painter;    /* hsr/painter.c */
extern const ew_hsr ew_hsr_drawbuffer; /* hsr/drawbuffer.c */
extern const ew_hsr ew_hsr_beamtree;   /* hsr/beamtree.c (+ surf_poly.c) */
extern const ew_hsr ew_hsr_raycast;    /* hsr/raycast.c (+ surf_poly.c) */

/* hsr/ref_compose.c: the reference's own compositing.  begin (serial, a
 * frame's start) returns the per-pixel buffer of world faces the reference
 * fills (NULL out of memory: no sky is found); ids_out copies rows [y0, y1) of it to the
 * caller's face ids; prepare and draw are its pass. */
typedef struct ew_ref_compose ew_ref_compose;
struct ew_rows;
int *ew_ref_compose_begin(ew_renderer *r);
int *ew_ref_compose_faces(const ew_renderer *r);  /* that buffer, or NULL */
void ew_ref_compose_ids_out(const ew_renderer *r, int *ids, int y0, int y1);
int  ew_ref_compose_prepare(ew_renderer *r);
void ew_ref_compose_draw(ew_renderer *r, const struct ew_rows *rows);
void ew_ref_compose_free(ew_ref_compose *c);

/* hsr/methods.c: the method for an ew_hsr_method, NULL if not built. */
const ew_hsr *ew_hsr_get(int method);

/* ---- the global edge list (built by world/edges.c, scanned by edge_scan.c) ---- */



int  ew_band_init(ew_band *b, int max_surfs, int max_spans, int max_aet);
void ew_band_free(ew_band *b);
/* The edge list's scan of one band into spans. */
void ew_scan_band(const ew_edge_list *el, int width, ew_band *b);
/* The edge list's scans (edge_scan.c, edge_z.c): a band's active edges made
 * those alive at its top row, sorted; then each row's new edges added,
 * unsorted.  Edges past the band's capacity are counted in dropped. */
void ew_band_start(const ew_edge_list *el, ew_band *b);
void ew_band_add_row(const ew_edge_list *el, ew_band *b, int v);
/* The band's scratch of at least bytes (grown, contents kept up to the old
 * size; zeroed when first made), or NULL when memory runs out.  Freed with
 * the band.  A method keeps its per-band state here: bands resolve on
 * several threads at once. */
void *ew_band_scratch(ew_band *b, size_t bytes);
/* Appends a span [u0, u1) of row v to the band (nothing if empty; counted
 * as dropped when the span budget is full) and marks its surface used. */
void ew_band_span(ew_band *b, int surf, int u0, int u1, int v);

/* world/edges.c: clip, project and emit one face (or a loose polygon) into
 * the edge list: the edge method's face and poly. */
void ew_emit_face(ew_renderer *r, int face, int clipflags, int key);
void ew_emit_poly(ew_renderer *r, float (*verts)[3], int n, int fi, const ew_view *v, int key);
/* hsr/edge_scan.c: the edge list emptied for a frame (the edge method's
 * begin); its edges sorted by first scanline (the scans' finish). */
void ew_edge_begin(ew_renderer *r);
void ew_edge_sort_rows(ew_renderer *r);
/* hsr/surf_poly.c: frees r->spolys, the screen polygons of beamtree and raycast. */
struct ew_spolys;
void ew_spolys_free(struct ew_spolys *sp);

#endif
