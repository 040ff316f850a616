/* The frame's shared types (internal): what every stage of a frame reads or
 * writes and no stage owns, below every stage header.  A stage's header
 * includes this one (and lower ones: ew_world.h, edgewise.h), never the
 * renderer's (src/renderer.h), which assembles the stages.
 *
 *   ew_view        this frame's camera           (set up by world/view.c)
 *   ew_target      the pixels and 1/z            (written through raster/target.h)
 *   ew_edge_list   the global edge list          (built by world/edges.c, scanned by hsr/)
 *   ew_span, ew_band, ew_rows   a band's spans and rows (hsr/ resolves, raster/ draws)
 *   ew_config      the settings every stage reads
 *   ew_frame       all of the above for one frame, with the world and its tables
 */
#ifndef EW_FRAME_H
#define EW_FRAME_H

#include "ew_world.h"

#include <stddef.h>
#include <stdint.h>
#include <string.h>

typedef struct ew_hsr ew_hsr;
/* What a band's own state (ew_band.own) does besides holding it. */
typedef struct ew_band_own_ops {
    void (*free)(void *own);
    void (*reset)(void *own);        /* a new frame (NULL: nothing) */
    int  (*full)(const void *own);   /* its budget is full: the soak's check (NULL: never) */
} ew_band_own_ops;

typedef struct ew_band ew_band;

typedef struct ew_view {
    float origin[3];
    float forward[3], right[3], up[3];
    float xcenter, ycenter;   /* pixel centres are integers */
    float xscale, yscale;     /* pixels per unit of x/z, y/z */
    ew_plane frustum[4];      /* world space, normals point inward */
    int   width, height;
    double time;
} ew_view;

typedef struct ew_target {
    uint8_t *pixels;        /* height rows of pitch bytes */
    float   *zbuf;          /* width * height 1/z values (larger is nearer, 0 is far) */
    int      width, height;
    int      pitch;         /* bytes from one row to the next */
    int      bpp;           /* bytes per pixel: 1 (palette indices) or 4 (R, G, B, A bytes) */
    const uint32_t *rgba;   /* the palette as 4-byte pixels (ew_rgba), for bpp 4 */
} ew_target;

/* A band of rows being drawn, and the counters its drawing adds to. */
typedef struct ew_rows {
    int       y0, y1;      /* [y0, y1) */
    ew_stats *stats;
    int       first;       /* the rows that count per-model figures (triangles, entities) */
} ew_rows;

/* ---- light styles (light/styles.c sets them each frame) ---- */
#define EW_STYLE_PATTERN_MAX 64       /* letters in a pattern, at most */
enum { EW_STYLE_DEFAULT = 0, EW_STYLE_FIXED, EW_STYLE_PATTERN };
typedef struct ew_style_setting {
    int  mode;                        /* EW_STYLE_* (0: the default) */
    int  value;                       /* EW_STYLE_FIXED */
    char pattern[EW_STYLE_PATTERN_MAX + 1];  /* EW_STYLE_PATTERN: letters a..z */
} ew_style_setting;

/* ---- the global edge list (built by world/edges.c, scanned by hsr/) ---- */
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

/* One horizontal band [y0, y1): its spans, the method's state, and what
 * its draw job counted.  Aligned so neighbouring bands' counters, written by
 * different threads, never share a cache line. */
struct ew_band {
    _Alignas(64) int y0, y1;
    uint8_t *has_spans;             /* per surface: won a span in this band */
    ew_span *spans;  int nspans, cap_spans, max_spans;
    int unsorted;                   /* a row's spans may overlap or run out of order (see above) */
    long counters[EW_HSR_COUNTERS]; /* the method's own counts in this band (zeroed before resolve) */
    uint8_t *rowmark;               /* width bytes of scratch (accounting unsorted rows), or NULL */
    void *scratch;  size_t scratch_bytes;  /* the method's own per-band memory (ew_band_scratch) */
    /* The method's own band state (the edge scan's: hsr/active.h), made by
     * the method on first use; own_ops (the method's, which also says whose
     * it is) frees it with the band, resets it each frame and says whether
     * its budget is full. */
    void *own;  const struct ew_band_own_ops *own_ops;
    int dropped;
    long written, covered;          /* world pixels its spans wrote, and covered at least once */
    double ms;                      /* its scan's time this frame */
};

/* Settings: changed between frames, read by every stage. */
typedef struct ew_config {
    int   subdiv_shift;              /* perspective divide every 1 << shift px */
    int   alias_raster;              /* ew_alias_raster */
    float alias_threshold;           /* auto: subdivide below this screen height */
    int   lightstyle[64];            /* this frame's style values (light/styles.c) */
    ew_style_setting style_set[64];  /* how each is chosen (ew_set_lightstyle ...) */
    float gamma;                     /* output gamma (ew_set_gamma): 1 = none */
    uint8_t gamma_lut[256];          /* channel value through the gamma */
    uint8_t gamma_palette[768];      /* the palette through it (ew_frame_palette) */
    int   face_ids_on;               /* test hook: record the face of each pixel */
    /* see-through surfaces, fog, underwater view (ew_set_classic ...) */
    int   classic;                   /* 1: all of them off, the 1996 look */
    float liquid_alpha;              /* < 0: the map's */
    float fog_density, fog_rgb[3];   /* density < 0: the map's */
    int   waterwarp;
    int   use_lit, dither;           /* coloured light on; 8-bit coloured light dithered */
    int   lighting;                  /* ew_lighting_mode: the surface cache or two passes */
    int   light_fault;               /* test hook (ew_set_light_fault): a wrong cache, for controls */
    const ew_hsr *hsr;          /* hidden-surface method */
    int   hide_occluded;             /* moving things the world hides are left out (raster/models.c) */
    int   front_phases;              /* one thread too runs the front end's phases (ew_set_front_mode) */
} ew_config;

/* One frame's shared state: the world and its tables, the settings, the
 * target, the camera and the counters.  Every stage reads it; the serial
 * stages write stats, bands count into their own. */
typedef struct ew_frame {
    const ew_world *world;
    const uint8_t  *palette, *colormap;
    ew_config       cfg;
    ew_target       target;
    ew_view         view;            /* this frame's camera */
    ew_stats        stats;           /* this frame's counters (serial stages) */
    int            *face_ids;        /* test hook: per pixel, or NULL */
    int             eye_contents;    /* EW_CONTENTS_* of the eye's leaf this frame */
} ew_frame;

enum { EW_DBG_HEAT = 6 };  /* overdraw colours: 0, 1, ... 5 or more writes */

/* Debug modes (ew_set_debug, ew_set_pvs_lock; raster/debug.c): set
 * between frames, read by the stages they change (light, world/pvs.c,
 * raster, the pass list). */
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

/* ---- 32-bit pixels (true colour), for every stage that writes them ---- */
static inline uint32_t ew_get32(const uint8_t *row, int x) {
    uint32_t v;
    memcpy(&v, row + (size_t)x * 4, 4);
    return v;
}
static inline void ew_set32(uint8_t *row, int x, uint32_t v) { memcpy(row + (size_t)x * 4, &v, 4); }
/* Alpha 0: a fence texture's hole in a true-colour lit surface. */
static inline int ew_rgba_clear(uint32_t v) {
    uint8_t px[4];
    memcpy(px, &v, 4);
    return px[3] == 0;
}
/* A true-colour pixel: the bytes R, G, B, A (255) in memory, as
 * ew_palette_rgba (so a frame goes to a display or a PNG as it is). */
static inline uint32_t ew_rgba(int r, int g, int b) {
    uint8_t px[4] = {(uint8_t)r, (uint8_t)g, (uint8_t)b, 255};
    uint32_t v;
    memcpy(&v, px, 4);
    return v;
}
static inline void ew_rgba_split(uint32_t v, int rgb[3]) {
    uint8_t px[4];
    memcpy(px, &v, 4);
    rgb[0] = px[0], rgb[1] = px[1], rgb[2] = px[2];
}

/* What the front end makes of a face that is not plain opaque wall: the
 * hidden-surface method's (opaque), a fence (alpha-tested) or blended
 * (translucent); world/divert.c decides, raster/seethrough.c draws. */
enum { EW_SEE_OPAQUE, EW_SEE_FENCE, EW_SEE_BLEND };

#endif
