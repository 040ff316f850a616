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
typedef struct ew_edge {
    int32_t  u;          /* 16.16 screen x at the first scanline */
    int32_t  u_step;     /* 16.16 per scanline */
    int32_t  v_first;    /* first scanline crossed */
    int32_t  v_last;     /* last scanline crossed */
    uint16_t surfs[2];   /* [0]: surface it trails (right side), [1]: leads */
    float    nearzi;     /* larger 1/z of its two ends */
} ew_edge;

/* A polygon in the edge list. */
typedef struct ew_surf {
    int   key;           /* BSP order: smaller is nearer */
    int   face;          /* world face, -1 for the background */
    int   flags;         /* EW_SURF_* */
    float nearzi;        /* largest 1/z of its clipped vertices (mip choice) */
    const ew_view *view; /* the camera in the face's own space (moved brush models) */
    int   insubmodel;    /* brush model fragment: ties in key sort by 1/z */
    float zi_u, zi_v, zi_0;  /* 1/z plane (brush model fragments only) */
} ew_surf;

typedef struct ew_edge_list {
    ew_edge *edges;      int nedges, max_edges;
    /* The edges by first scanline (ew_edge_sort_rows, once the front end is
     * done): row v's are by_row[row_first[v] .. row_first[v + 1]), the
     * later edge first; by_row_last holds their last scanlines, so a band
     * finds the edges alive at its top row in one pass over two arrays. */
    int32_t *row_first;  /* height + 2 */
    int32_t *by_row, *by_row_last;  /* max_edges each */
    ew_surf *surfs;      int nsurfs, max_surfs;  /* surface 0 is the background */
    int      max_spans;  /* per band */
} ew_edge_list;

/* Spans are kept in the order the scan makes them: row by row, left to
 * right within a row (the drawing, the z-fill index and the accounting all
 * rely on it). */
typedef struct ew_span {
    int32_t u, v, count;
    int32_t surf;        /* the surface it belongs to */
} ew_span;

typedef struct ew_active {
    int32_t  u, u_step, v_last;
    uint16_t surfs[2];
} ew_active;

/* One surface's place in a band's surface stack (the edge list's scans):
 * its neighbours, its count of edges entered less left, and where its
 * current span began.  Together, so that one cache line and one base
 * register serve all four. */
typedef struct ew_stack_entry {
    int32_t next, prev, state, lastu;
} ew_stack_entry;

/* One horizontal band [y0, y1): its scan state, its spans, and what its
 * draw job counted.  Aligned so neighbouring bands' counters, written by
 * different threads, never share a cache line. */
struct ew_band {
    _Alignas(64) int y0, y1;
    ew_stack_entry *stack;          /* indexed by surface number; 0 is the background */
    uint8_t *has_spans;             /* per surface: won a span in this band */
    ew_span *spans;  int nspans, cap_spans, max_spans;
    int unsorted;                   /* a row's spans may overlap or run out of order (see above) */
    long counters[EW_HSR_COUNTERS]; /* the method's own counts in this band (zeroed before resolve) */
    uint8_t *rowmark;               /* width bytes of scratch (accounting unsorted rows), or NULL */
    void *scratch;  size_t scratch_bytes;  /* the method's own per-band memory (ew_band_scratch) */
    ew_active *aet;  int naet, cap_aet, max_aet;
    ew_active *aet_tmp;  int cap_tmp;  /* the band start's merge sort */
    int32_t *st_neg;  int cap_neg;  /* >= cap_aet entries (the edge list's scan): counts gone below zero on a line */
    int32_t *st_fix;                /* as many: the stepped edges that may be out of order for the next line */
    int dropped;
    long written, covered;          /* world pixels its spans wrote, and covered at least once */
    double ms;                      /* its scan's time this frame */
};

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
