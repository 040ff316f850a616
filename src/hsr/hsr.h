/* Hidden-surface removal (internal): one interface, one file per method.
 *
 * The front end (world/) walks the BSP front to back and hands every
 * visible, camera-facing world face and every brush-model polygon to the
 * frame's method; each band of the frame is then resolved into spans for
 * the back end to draw (hsr/edge_scan.c: Quake's global edge list) or
 * straight into pixels (hsr/reference.c: a per-pixel z-buffer the tests
 * trust).  Each method is one file here with its own ew_hsr, listed in
 * hsr/methods.c under its ew_hsr_method.  A method sees the frame through
 * an ew_hsr_ctx, never the renderer; what sets it apart is in its flags.
 *
 * What resolve may hand the back end: spans grouped by row, rows in
 * ascending order.  A method whose spans in a row are disjoint and left to
 * right (the edge list's) leaves b->unsorted 0; one that draws a pixel more
 * than once (painter's order, a z-buffer) sets it, and then the spans are
 * drawn in the order given, later over earlier, and the accounting counts
 * the distinct pixels for itself. */
#ifndef EW_HSR_H
#define EW_HSR_H

#include "world/view.h"  /* the frame's types (frame.h), clipping, EW_MAX_POLY */

struct ew_span_ctx;
struct ew_twopass;
struct ew_see;
struct ew_rows;

/* What a method needs of the frame, and nothing of the renderer: filled
 * once a frame by renderer.c (hsr_ctx_setup) before begin.  The front end
 * and the surface cache are reached through the callbacks, with owner. */
typedef struct ew_hsr_ctx {
    ew_frame     *f;                     /* the world, settings, target, camera, counters */
    ew_edge_list *el;                    /* the front end's edge list (and the surfaces the back end draws) */
    ew_band      *bands;  int nbands;    /* this frame's bands (a method's memory over them) */
    const struct ew_span_ctx *draw;      /* the span drawers' tables (the reference fills through them) */
    const struct ew_twopass  *tp;        /* two-pass lighting's inputs this frame */
    const struct ew_see      *see;       /* the see-through polygons (world/divert.c): the reference's compose */
    int           debug;                 /* a debug view is on (raster/debug.c) */
    void         *owner;                 /* the callbacks' first argument */
    /* the front end's face / brush-model polygon into the edge list (world/edges.c) */
    void (*emit_face)(void *owner, int face, int clipflags, int key);
    void (*emit_poly)(void *owner, float (*verts)[3], int n, int fi, const ew_view *v, int key);
    /* face's lit surface at mip, built if it is new (serial); NULL when the
     * cache has no room.  *width: its texels a row. */
    const uint8_t *(*lit_surface)(void *owner, int face, int mip, int *width);
    /* the methods' own state kept from frame to frame (ew_hsr_ctx_free) */
    struct ew_spolys *spolys;            /* beamtree, raycast: surfaces' screen polygons (hsr/surf_poly.c) */
    struct ew_ref    *ref;               /* the reference's polygons and compositing (hsr/reference.c) */
    int          *ref_ids;               /* ew_render_reference's face ids, or NULL */
} ew_hsr_ctx;

/* What a method is and does, for the stages that treat methods apart
 * (ew_hsr.flags). */
enum {
    /* face and poly are the front end's own (ctx emit_face / emit_poly):
     * the edge list as world/edges.c builds it, so world/front_par.c may
     * build it in parallel phases instead of calling them. */
    EW_HSR_EDGE_LIST   = 1 << 0,
    /* Its frame is the same when faces nearer faces hide are left out of
     * the edge list (world/occlude.c): it scans the list in BSP order. */
    EW_HSR_OCCLUSION   = 1 << 1,
    /* resolve tiles every row of its band with spans for the back end; 0:
     * it writes the pixels itself and leaves no span (the reference). */
    EW_HSR_MAKES_SPANS = 1 << 2,
    /* Every world pixel is written exactly once (overdraw 1.0 is an
     * invariant the soak checks). */
    EW_HSR_EXACT_ONCE  = 1 << 3,
    /* Fence faces go to face/poly too and their holes are the method's
     * business; 0: they go to the see-through pass. */
    EW_HSR_FENCES      = 1 << 4,
    /* It composites fences, translucent surfaces and fog over its opaque
     * pixels itself (the reference: hsr/ref_compose.c), and the pass list
     * runs its compose instead of the shared passes (scene/passes.c). */
    EW_HSR_OWN_COMPOSE = 1 << 5,
    /* The debug span view marks the edge list's edges where its scan
     * starts their spans (raster/debug.c). */
    EW_HSR_SHOWS_EDGES = 1 << 6,
};

typedef struct ew_hsr {
    const char *name;
    unsigned    flags;                   /* EW_HSR_EDGE_LIST ... */
    /* A frame starts (serial, after the view and the PVS are set). */
    void (*begin)(ew_hsr_ctx *c);
    /* A visible world face facing the camera, in BSP order front to back;
     * key grows from front to back (serial, from the walk). */
    void (*face)(ew_hsr_ctx *c, int face, int clipflags, int key);
    /* A brush-model polygon in world space: face fi of a moved model seen
     * through v (the camera in the model's space), sorting at BSP key key
     * (serial). */
    void (*poly)(ew_hsr_ctx *c, float (*verts)[3], int n, int fi, const ew_view *v, int key);
    /* The front end is done, no band resolved yet (serial); NULL: nothing
     * to do.  The edge list's scans sort its edges by row here. */
    void (*finish)(ew_hsr_ctx *c);
    /* Resolves rows [b->y0, b->y1): spans into b, or pixels into the frame
     * (parallel: one band per call, bands never share rows). */
    void (*resolve)(const ew_hsr_ctx *c, ew_band *b);
    /* Bytes the method holds for the frame beyond the edge list and the
     * bands' spans (ew_stats.hsr_bytes); NULL: none. */
    size_t (*memory)(const ew_hsr_ctx *c);
    /* What each of the band counters (ew_band.counters, summed into
     * ew_stats.hsr_counters) counts; NULL: unused. */
    const char *counters[EW_HSR_COUNTERS];
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

/* hsr/methods.c: the method for an ew_hsr_method, NULL if not built. */
const ew_hsr *ew_hsr_get(int method);
/* The methods' own state in c (spolys, ref) freed. */
void ew_hsr_ctx_free(ew_hsr_ctx *c);

/* hsr/ref_compose.c: the reference's own compositing, its pass (serial
 * prepare, then draw per piece of rows). */
typedef struct ew_ref_compose ew_ref_compose;
int  ew_ref_compose_prepare(ew_hsr_ctx *c);
void ew_ref_compose_draw(const ew_hsr_ctx *c, const struct ew_rows *rows);

/* ---- bands (hsr/band.c) ---- */
int  ew_band_init(ew_band *b, int max_surfs, int max_spans);
void ew_band_free(ew_band *b);
/* Before a band resolves: its counts zeroed (dropped, unsorted, counters,
 * and the edge scan's active edges). */
void ew_band_reset(ew_band *b);
/* 1 if one of the band's budgets is full: its spans, or its edge scan's
 * active edges (a soak's refusal test). */
int  ew_band_budget_full(const ew_band *b);
/* The band's scratch of at least bytes (grown, contents kept up to the old
 * size; zeroed when first made), or NULL when memory runs out.  Freed with
 * the band.  A method keeps its per-band state here: bands resolve on
 * several threads at once. */
void *ew_band_scratch(ew_band *b, size_t bytes);
/* The band's spans doubled, at most to its budget; 0 if they were. */
int  ew_band_grow_spans(ew_band *b);
/* Appends a span [u0, u1) of row v to the band (nothing if empty; counted
 * as dropped when the span budget is full) and marks its surface used. */
void ew_band_span(ew_band *b, int surf, int u0, int u1, int v);

/* ---- the edge method (hsr/edge_scan.c) ---- */
/* The edge list's scan of one band into spans. */
void ew_scan_band(const ew_edge_list *el, int width, ew_band *b);
/* The edge list emptied for a frame (the edge method's begin); its edges
 * sorted by first scanline (the scans' finish); the front end's face and
 * poly (through c). */
void ew_edge_begin(ew_hsr_ctx *c);
void ew_edge_sort_rows(ew_hsr_ctx *c);
void ew_edge_face(ew_hsr_ctx *c, int face, int clipflags, int key);
void ew_edge_poly(ew_hsr_ctx *c, float (*verts)[3], int n, int fi, const ew_view *v, int key);

#endif
