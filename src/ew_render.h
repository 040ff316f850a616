/*
 * Renderer state (internal).  Everything a frame needs lives in an
 * ew_renderer (per-world marks, the edge list, surfaces, surface cache) or
 * in an ew_band (one horizontal band's scan state and spans), never in
 * globals, so bands of one frame can later be scanned and drawn on several
 * threads from the shared per-frame edge setup.
 *
 * Frame pipeline, one file per stage:
 *   world/view.c      camera basis, projection, frustum planes
 *   world/pvs.c       view leaf, PVS decompression, visible-leaf marks
 *   world/bsp_walk.c  front-to-back walk, box culling, backface culling
 *   world/edges.c     polygon clipping, projection, shared edge emission
 *   hsr/edge_scan.c   active edge list + surface stack -> spans
 *   raster/span.c     perspective-correct spans (divide per 16 px) + z-fill
 *   raster/sky.c      two-layer scrolling sky;  raster/turb.c  liquids
 *   light/surface.c   lit surface building;     light/cache.c  surface cache
 *   hsr/reference.c   brute-force z-buffer reference path (for tests)
 */
#ifndef EW_RENDER_H
#define EW_RENDER_H

#include "ew_world.h"

/* ---- view ---- */
typedef struct ew_view {
    float origin[3];
    float forward[3], right[3], up[3];
    float xcenter, ycenter;   /* pixel centres are integers */
    float xscale, yscale;     /* pixels per unit of x/z, y/z */
    ew_plane frustum[4];      /* world space, normals point inward */
    int   width, height;
    double time;
} ew_view;

void ew_view_setup(ew_view *v, const ew_camera *cam, int width, int height);
/* Forward, right and up of Quake angles (pitch yaw roll, degrees). */
void ew_angle_vectors(const float angles[3], float fwd[3], float right[3], float up[3]);
/* Moved models (ax: the model's axes as columns, from ew_entity_axes):
 * the world box around its moved bounds, and the camera in its own space
 * (p_model = ax^T (p_world - origin)). */
void ew_moved_box(const float ax[3][3], const float origin[3], const float mins[3],
                  const float maxs[3], float lo[3], float hi[3]);
void ew_view_to_model(const ew_view *v, const float ax[3][3], const float origin[3], ew_view *out);
/* World point -> view space (x right, y up, z forward). */
static inline void ew_view_transform(const ew_view *v, const float p[3], float out[3]) {
    float d0 = p[0] - v->origin[0], d1 = p[1] - v->origin[1], d2 = p[2] - v->origin[2];
    out[0] = d0 * v->right[0] + d1 * v->right[1] + d2 * v->right[2];
    out[1] = d0 * v->up[0] + d1 * v->up[1] + d2 * v->up[2];
    out[2] = d0 * v->forward[0] + d1 * v->forward[1] + d2 * v->forward[2];
}

/* ---- edge list (built by the front end, read by the scan) ---- */
typedef struct ew_edge {
    int32_t  u;          /* 16.16 screen x at the first scanline */
    int32_t  u_step;     /* 16.16 per scanline */
    int32_t  v_first;    /* first scanline crossed */
    int32_t  v_last;     /* last scanline crossed */
    uint16_t surfs[2];   /* [0]: surface it trails (right side), [1]: leads */
    int32_t  next_new;   /* next edge starting on the same line, -1 end */
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

/* Spans are kept in the order the scan makes them: row by row, left to
 * right within a row (the drawing, the z-fill index and the accounting all
 * rely on it). */
typedef struct ew_span {
    int32_t u, v, count;
    int32_t surf;        /* the surface it belongs to */
} ew_span;

/* One horizontal band [y0, y1): its scan state and its spans. */
typedef struct ew_active {
    int32_t  u, u_step, v_last;
    uint16_t surfs[2];
} ew_active;

typedef struct ew_band {
    int y0, y1;
    /* surface stack, indexed by surface number; 0 is the background */
    int32_t *st_next, *st_prev, *st_state, *st_lastu;
    uint8_t *has_spans;             /* per surface: won a span in this band */
    ew_span *spans;  int nspans, cap_spans, max_spans;
    ew_active *aet;  int naet, cap_aet, max_aet;
    int dropped;
    ew_stats model_stats;           /* this band's share of the moving things' counters */
    long written, covered;          /* world pixels its spans wrote, and covered at least once */
    double model_ms;                /* time it spent on them */
} ew_band;

/* ---- surface cache ---- */
typedef struct ew_cached_surf {
    struct ew_cached_surf *lru_prev, *lru_next;
    int      face, mip, texture;
    int      light[4];   /* style values it was lit with */
    unsigned dlights;    /* dynamic lights it was built with */
    int      width, height;
    int      last_frame;
    uint8_t *pixels;
} ew_cached_surf;

typedef struct ew_surf_cache {
    ew_cached_surf **slot;        /* numfaces * 4 (per mip) */
    ew_cached_surf  *lru_head, *lru_tail;
    size_t bytes, budget;
} ew_surf_cache;

/* ---- worker pool (pool.c) ---- */
#define EW_MAX_THREADS 16
#define EW_BANDS_PER_THREAD 4
#define EW_MAX_BANDS (EW_MAX_THREADS * EW_BANDS_PER_THREAD)
typedef struct ew_pool ew_pool;
ew_pool *ew_pool_create(int threads);
void     ew_pool_free(ew_pool *p);
int      ew_pool_threads(const ew_pool *p);
/* Runs job(ctx, i) for every thread index i, 0 on the caller; waits for all. */
void     ew_pool_run(ew_pool *p, void (*job)(void *ctx, int index), void *ctx);
/* Gets sleeping workers polling for a while (a frame's serial front end is
 * starting), so the first parallel phase does not wait on a kernel wake-up. */
void     ew_pool_wake(ew_pool *p);

/* ---- the renderer ---- */
struct ew_renderer {
    const ew_world *world;
    const uint8_t  *palette, *colormap;
    int width, height;
    uint8_t *frame;
    float   *zbuf;
    /* Deferred z-fill: the world's 1/z is written only where a moving
     * thing is about to test it (ew_zfill_rect), or everywhere when
     * zfill_all is set.  Per row: the band and spans that cover it, and
     * the interval [zlo, zhi) already filled this frame. */
    int      zfill_all;
    int32_t *row_band, *row_span0, *row_nspans, *zlo, *zhi;
    int     *face_ids;
    int      face_ids_on;
    int      subdiv_shift;                   /* perspective divide every 1 << shift px */
    int      alias_raster;                   /* ew_alias_raster */
    float    alias_threshold;                /* auto: subdivide below this screen height */
    int      hsr;                            /* ew_hsr_method (EW_HSR_REFERENCE: not wired yet) */
    int      lightstyle[64];

    /* per-world marks, compared against framecount */
    int  framecount;
    int *leaf_frame, *node_frame, *face_frame;
    int *leaf_key, *leaf_keyframe;            /* BSP key of each visited leaf */
    int *face_dlframe; unsigned *face_dlbits; /* dynamic lights on each face */
    int *edge_cache_frame, *edge_cache_index; /* per world edge */
    int8_t *edge_cache_down;                  /* +1: +sign traversal goes down */

    ew_view view;
    int     currentkey;

    ew_edge *edges;   int nedges, max_edges;
    int      max_spans;                       /* per band */
    int32_t *new_edges;                       /* per scanline: first edge, -1 */
    ew_surf *surfs;   int nsurfs, max_surfs;

    /* bands of the frame: several per thread, taken in turn by whichever
     * thread is free, with boundaries that follow the last frame's cost */
    ew_pool *pool;
    int      nthreads;
    int      nbands;
    ew_band *bands;
    double   band_ms[EW_MAX_BANDS];               /* last frame's cost per band */
    _Atomic int next_band, next_build;            /* work handed out in a phase */
    float   *row_cost;                            /* per scanline, from band_ms */
    int      bands_sized_for;                     /* row_cost valid for this many bands */

    ew_surf_cache cache;
    /* per surface of this frame: its lit surface (normal surfaces only),
     * and how its spans are drawn (ew_surf_draw, set before the bands draw) */
    ew_cached_surf **surf_cache;
    struct ew_surf_draw *surf_draw;
    ew_cached_surf **to_build;  int nbuild;
    int     *grad_list;  int ngrad;              /* surfaces whose ew_surf_draw needs gradients */
    _Atomic int next_grad;
    float    sky_scroll;                         /* sky layers' offset for this frame's time */
    int      maxlm;                               /* largest light map, in samples */

    const struct ew_scene *scene;             /* entities to draw, or NULL */
    ew_view *ent_views;  int max_ent_views;   /* camera in each brush entity's space */
    struct ew_ent_frame *ent_frame;           /* per entity, this frame (ew_prepare_entities) */
    int      nent_frame, max_ent_frame;
    struct ew_box_surfs **box_surfs;          /* per scene model: item box lit surfaces, or NULL */
    int      nbox_surfs;

    ew_stats stats;
    int32_t  turb[128];                      /* liquid warp for this frame's time */
    int     *blocklights;                    /* surface building scratch, maxlm per thread */
    /* reference path: when set, the walk hands visible faces to it */
    void (*face_hook)(ew_renderer *r, int face, int clipflags, void *ctx);
    void *face_hook_ctx;
};

/* renderer.c: new frame number, view, turbulence, empty edge list, PVS marks. */
int  ew_frame_begin(ew_renderer *r, const ew_camera *cam);

/* world/pvs.c: marks the leaves (and their ancestors) visible from the
 * camera's leaf for this frame; returns the view leaf. */
int  ew_pvs_mark(ew_renderer *r);
int  ew_point_leaf(const ew_world *w, int headnode, const float p[3]);

/* world/bsp_walk.c: front-to-back walk emitting every visible face. */
void ew_walk_world(ew_renderer *r);
/* -1 if the box is outside a frustum plane in clipflags, else the planes it still crosses. */
int  ew_cull_box(const ew_view *v, const float mins[3], const float maxs[3], int clipflags);
/* 1 if a world-space box touches a leaf in this frame's PVS. */
int  ew_box_in_pvs(const ew_renderer *r, const float lo[3], const float hi[3]);

/* world/edges.c: clip, project and emit one face into the edge list. */
void ew_emit_face(ew_renderer *r, int face, int clipflags);
/* Emits a loose world-space polygon (a brush model fragment) for face fi
 * seen through view v, with BSP key `key`; clipped to the whole frustum. */
void ew_emit_poly(ew_renderer *r, float (*verts)[3], int n, int fi, const ew_view *v, int key);
/* world/bmodel.c: brush model entities into the edge list. */
void ew_emit_brush_models(ew_renderer *r);
/* Calls fn for every camera-facing face of every brush entity in the
 * frustum, with the polygon moved into world space, the face's world
 * normal and the camera in model space; fn returns 1 if it drew anything. */
typedef int (*ew_brush_face_fn)(ew_renderer *r, void *ctx, int face, const ew_view *model_view,
                                const float normal[3], float (*poly)[3], int n);
void ew_for_brush_faces(ew_renderer *r, ew_brush_face_fn fn, void *ctx);
/* Entity rotation from Quake angles: columns are the model's x, y, z axes. */
void ew_entity_axes(const float angles[3], float ax[3][3]);

/* light/dlight.c: mark faces in reach of the scene's dynamic lights; the
 * lights on a face this frame (bit i = light i); add them to a light map. */
void     ew_mark_dlights(ew_renderer *r);
unsigned ew_face_dlights(const ew_renderer *r, int face);
void     ew_add_dlights(const ew_renderer *r, const ew_face *f, unsigned bits, int *blocklights);
/* Clips a polygon (view-independent world coords) against the frustum
 * planes in clipflags; returns the vertex count (0 if all clipped).
 * orig[i] = index of the original edge leaving vertex i, or -1. */
#define EW_MAX_POLY 256
int  ew_clip_poly(const ew_view *v, int clipflags, float (*in)[3], int nin,
                  float (*out)[3], int *edge_tag_in, int *edge_tag_out);

/* hsr/edge_scan.c */
int  ew_band_init(ew_band *b, int max_surfs, int max_spans, int max_aet);
void ew_band_free(ew_band *b);
void ew_scan_band(ew_renderer *r, ew_band *b);

/* raster */
typedef struct ew_gradients {
    float zi_u, zi_v, zi_0;       /* 1/z = zi_u*u + zi_v*v + zi_0 */
    float s_u, s_v, s_0;          /* s/z likewise, seen from the eye */
    float t_u, t_v, t_0;
    int32_t s_adjust, t_adjust;   /* 16.16: s = (s/z) * z + s_adjust */
    int32_t s_max, t_max;         /* 16.16 clamp limits */
} ew_gradients;
/* Screen gradients of face f of world w seen through v (the camera in the
 * face's own space) at a mip level. */
void ew_face_gradients(const ew_world *w, const ew_view *v, const ew_face *f, int mip,
                       ew_gradients *g);
/* How one surface's spans are drawn this frame. */
enum { EW_DRAW_BACKGROUND, EW_DRAW_LIT, EW_DRAW_SKY, EW_DRAW_TURB, EW_DRAW_FLAT };
typedef struct ew_surf_draw {
    ew_gradients g;           /* screen gradients (mip of its lit surface; 0 for sky and liquids) */
    const uint8_t *pixels;    /* EW_DRAW_LIT: the lit surface, pitch bytes a row */
    int pitch;
    int kind;                 /* EW_DRAW_*; FLAT: no memory for its lit surface */
    const ew_texture *tex;    /* sky and liquids */
} ew_surf_draw;
/* One span of each kind.  A band draws its spans in the order the scan
 * made them (row by row), so the frame is written front to back in memory
 * and the span list is read straight through. */
void ew_draw_lit_span(ew_renderer *r, const ew_span *sp, const ew_surf_draw *d);
void ew_draw_sky_span(ew_renderer *r, const ew_span *sp, const ew_texture *t);
void ew_draw_turb_span(ew_renderer *r, const ew_span *sp, const ew_gradients *g, const ew_texture *t);
/* The world's 1/z under one span (full z-fill, ew_set_full_zfill). */
void ew_zfill_span(ew_renderer *r, const ew_span *sp, const ew_gradients *g);
/* Makes r->zbuf hold the world's 1/z over [x0, x1) x [y0, y1) (clipped to
 * the frame), filling from this frame's spans only what is not filled yet.
 * Every moving thing calls it for its screen box before its z test; a
 * caller drawing in a band passes rows inside that band. */
void ew_zfill_rect(ew_renderer *r, int x0, int y0, int x1, int y1);
/* Indexes a scanned band's spans by row and marks its rows unfilled. */
void ew_zfill_index_band(ew_renderer *r, const ew_band *b, int band);
/* Declares every row filled (the reference path's own z, a caller's). */
void ew_zfill_mark_all(ew_renderer *r);
void ew_draw_band(ew_renderer *r, ew_band *b);
/* Sky colour of one pixel (shared with the reference path). */
uint8_t ew_sky_pixel(const ew_view *v, const ew_texture *t, float u, float y);
/* The sky layers' offset in texels at a time (the back layer's; the front
 * one moves twice as far). */
float   ew_sky_scroll(double time);
void    ew_turb_table(int32_t table[128], double time);
uint8_t ew_turb_texel(const int32_t table[128], const ew_texture *t, int32_t s, int32_t tt);

/* Rows of the frame a drawing call may touch, and where its counters go:
 * moving things are drawn band by band, each band only in its own rows. */
typedef struct ew_rows {
    int       y0, y1;      /* [y0, y1) */
    ew_stats *stats;
    int       first;       /* the band that counts per-model figures (triangles, entities) */
} ew_rows;

/* raster/zpoly.c: the z-buffered polygon fill (reference path, item boxes) */
typedef struct ew_zpoly {
    int    n;
    float  u[EW_MAX_POLY], v[EW_MAX_POLY];
    float  nearzi;
    double sign;
    int    x0, y0, x1, y1;
} ew_zpoly;
typedef struct ew_zpoly_look {
    const ew_world   *world;
    const ew_face    *face;
    const ew_view    *view;         /* the camera in the face's own space */
    const ew_texture *tex;          /* sky and liquids */
    const uint8_t    *surf;         /* lit surface (others) */
    int               surf_width, mip;
    int               stepped;      /* lit surfaces: a divide every 16 pixels as world
                                       spans (ew_stepper), not at every pixel */
} ew_zpoly_look;
/* Clips (whole frustum) and projects a world-space polygon; 0 if nothing is left. */
int  ew_zpoly_project(const ew_renderer *r, float (*in)[3], int n, ew_zpoly *p);
/* Fills it into r->frame and r->zbuf where nearer; ids[pixel] = id where it
 * wins (ids may be NULL).  Returns the pixels won. */
long ew_zpoly_fill(ew_renderer *r, const ew_zpoly *p, const ew_zpoly_look *look, int *ids, int id,
                  int y0, int y1);

/* raster/entities.c: alias models, sprites, item boxes and particles of the
 * scene, z-buffered over the frame. */
void ew_draw_entities(ew_renderer *r, const ew_rows *rows);
/* Once per frame before the bands draw (serial): which entities the PVS and
 * the frustum let through, and the light on each, so that the bands do not
 * each trace it again.  -1 when out of memory (no entities then). */
typedef struct ew_ent_frame {
    int visible;
    int ambient, shade;
} ew_ent_frame;
int  ew_prepare_entities(ew_renderer *r);
/* Frees the item boxes' lit surfaces (a new scene, the renderer's end). */
void ew_free_box_surfs(ew_renderer *r);

/* light */
int  ew_face_mip(const ew_view *v, const ew_world *w, const ew_face *f, float nearzi);
const ew_texture *ew_face_texture(const ew_world *w, const ew_face *f, double time);
/* Finds (or makes room for) the lit surface of a face at a mip level and
 * marks it used this frame; *build is set when its pixels must be built
 * (ew_cache_build, which may run on any thread: entries are distinct).
 * Serial: lookups allocate and evict.  NULL when out of memory. */
ew_cached_surf *ew_cache_lookup(ew_renderer *r, int face, int mip, int *build);
void ew_cache_build(const ew_renderer *r, ew_cached_surf *e, int *scratch);
/* Builds face f of world w lit by style values light[] (and, for the
 * renderer's own world, the dynamic lights in bits dlights) into out. */
void ew_build_surface(const ew_renderer *r, const ew_world *w, const ew_face *f,
                      const ew_texture *tex, int mip, const int light[4], unsigned dlights,
                      uint8_t *out, int *scratch);
int  ew_cache_init(ew_surf_cache *c, int numfaces, size_t budget);
void ew_cache_free(ew_surf_cache *c);

#endif
