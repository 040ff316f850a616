/* The front end (internal): what can be seen this frame.  The PVS marks
 * the leaves visible from the camera's leaf, the walk visits the BSP front
 * to back culling nodes by the frustum and hands every visible face to the
 * frame's hidden-surface method, brush models are split into the leaves
 * they occupy, and entities are culled by the PVS and the frustum.
 *
 * Its state is an ew_front (below): the frame it reads (frame.h), the
 * marks and the edge list it writes, its own occlusion map and parallel
 * lists, and an ew_front_out through which it hands everything else up
 * (the method's faces, the see-through polygons, an entity's light).  It
 * includes nothing above itself.  The per-face rules (clip, occlusion,
 * budgets, edge sharing) are written once, in world/face.h, and run on one
 * thread (world/edges.c) or in phases on many (world/front_par.c). */
#ifndef EW_WORLD_FRONT_H
#define EW_WORLD_FRONT_H

#include "pool.h"
#include "world/view.h"

#include <stdint.h>

struct ew_scene;

/* Per-world marks, compared against framecount (so nothing is cleared
 * between frames). */
typedef struct ew_marks {
    int  framecount;
    int *leaf_frame, *node_frame, *face_frame;
    int *leaf_up, *node_up;                   /* the world's parent links, packed: PVS marking climbs them */
    int *leaf_key, *leaf_keyframe;            /* BSP key of each visited leaf */
    int *face_dlframe; unsigned *face_dlbits; /* dynamic lights on each face */
    int *edge_cache_frame, *edge_cache_index; /* per world edge: shared edges */
    int *vert_frame; struct ew_proj *vert_proj; /* per world vertex: projected this frame (serial emission) */
    int8_t *edge_cache_down;                  /* +1: +sign traversal goes down */
    int    *vis, nvis, vis_pending;            /* this frame's PVS leaves, not yet marked */
} ew_marks;

/* world/occlude.c: world faces that nearer world faces hide, found on a
 * coarse coverage map of the screen and left out of the edge list (the
 * edge method only; the other methods' figures count every face).  A
 * strip of tile rows [ty0, ty1] notes the tiles of the faces of the
 * current key as pending until a larger key comes. */
struct ew_proj;
typedef struct ew_occ_range { int16_t ty, tx0, tx1; } ew_occ_range;
typedef struct ew_occ_strip {
    int           ty0, ty1, key;
    int           npend, cap;
    ew_occ_range *pend;
    int           any;     /* a tile of the strip is set */
    int           failed;  /* out of memory: nothing more is hidden in the strip */
} ew_occ_strip;
typedef struct ew_occlusion {
    int           mode, on;           /* the setting (ew_occlusion_mode); in use this frame */
    int           shift, tw, th, words;  /* tiles of 1 << shift pixels; tw x th of them; words a row */
    uint64_t     *bits;               /* th rows of words: tile covered */
    ew_occ_strip  whole;              /* every row: the one-thread emission's */
    ew_occ_strip *strips; int nstrips;/* the parallel front end's */
} ew_occlusion;
/* The tiles a face's pixels may fall in, its points' vertical extent, and
 * the tile rows it may cover (ra > rb: it is too small to note). */
typedef struct ew_occ_box { int tx0, tx1, ty0, ty1; float vmin, vmax; int ra, rb; } ew_occ_box;
int        ew_occ_init(ew_occlusion *o, int width, int height);
void       ew_occ_free(ew_occlusion *o);
/* n strips (at most one a tile row) for the parallel front end; the count. */
int        ew_occ_strips(ew_occlusion *o, int n);
/* auto uses the map only where the frame's PVS has at least this many
 * leaves (measured: below it, the faces the PVS and the frustum let
 * through are mostly seen, and the test costs more than it saves). */
#define EW_OCC_AUTO_LEAVES 500
/* A frame starts: the map cleared, in use if on (and the mode is not off). */
void       ew_occ_begin(ew_occlusion *o, int on);
ew_occ_box ew_occ_box_of(const ew_occlusion *o, const struct ew_proj *p, int n, int width, int height);
/* The test of a face itself, ew_occ_face, is in world/occlude.h. */

/* world/entities.c's answer per entity of the scene (the models' prepare,
 * raster/models_prepare.c, sizes the array): visible, culled, and the
 * light on each (alias models). */
typedef struct ew_ent_frame {
    int    visible, culled;  /* culled: a model entity the frustum or the PVS hides */
    int    ambient, shade;
    size_t xvert0;      /* alias models: where their posed vertices start in ents.xverts */
    int    tinted, tint[3];  /* alias models under coloured light: its colour (ew_light_tint) */
} ew_ent_frame;

/* How the front end hands its results up, filled by the renderer: the
 * front end calls nothing above itself. */
typedef struct ew_front_out {
    void *ctx;
    /* The method takes its faces and polygons as the edge list does
     * (ew_front_face, ew_front_poly): the walk makes them itself, and the
     * parallel phases may run.  0: every face goes to face(), every
     * fragment to poly(), on the calling thread. */
    int   edge_list;
    int   fences;      /* fence faces go to the method (else to the see-through pass) */
    void (*face)(void *ctx, int fi, int clipflags, int key);
    void (*poly)(void *ctx, float (*verts)[3], int n, int fi, const ew_view *v, int key);
    /* A face or fragment that is not opaque (world/divert.c), for the see-through pass. */
    void (*see)(void *ctx, float (*verts)[3], int n, int fi, const ew_view *v, int key, int kind, float alpha);
    /* The light on an alias model entity at origin: ef->ambient, shade, tinted and tint. */
    void (*entity_light)(void *ctx, const float origin[3], ew_ent_frame *ef);
} ew_front_out;

/* The front end's state.  f, marks and el are the renderer's (set once by
 * ew_front_init); the inputs below them are set before each frame's front
 * end runs. */
typedef struct ew_front {
    ew_frame     *f;
    ew_marks     *marks;
    ew_edge_list *el;
    ew_front_out  out;
    ew_occlusion  occ;                          /* faces nearer faces hide (world/occlude.c) */
    struct ew_front_par *par;                   /* the parallel front end's lists (world/front_par.c), or NULL */
    int           par_bad;                      /* its plan failed (an irregular tree): the serial front end */
    /* this frame's inputs */
    ew_pool      *pool;
    int           nthreads, profile_rows;
    const struct ew_scene *scene;               /* or NULL */
    ew_view      *ent_views;  int max_ent_views; /* room for a camera per brush entity */
    ew_ent_frame *ent_frame;                    /* per entity of the scene, or NULL (no room) */
    int           tested_frame;                 /* frame whose entities were tested (ew_test_entities) */
    double        ms_front_items;               /* probe: the parallel phases' longest items this frame (ew_lab_stats) */
} ew_front;

int  ew_front_init(ew_front *fr, ew_frame *f, ew_marks *marks, ew_edge_list *el, int width, int height);
void ew_front_free(ew_front *fr);

/* world/pvs.c: lists the leaves visible from `leaf` (the camera's, or a
 * locked one) for this frame (marks.vis, pending); ew_pvs_apply marks
 * listed leaves [from, to) and every node above them (any thread, shares
 * of the list at once), ew_pvs_finish all that are pending (serial). */
void ew_pvs_mark(ew_front *fr, int leaf);
void ew_pvs_apply(ew_front *fr, int from, int to);
void ew_pvs_finish(ew_front *fr);
int  ew_point_leaf(const ew_world *w, int headnode, const float p[3]);

/* world/edges.c: a world face (clip flags, BSP key) and a brush model's
 * fragment (world-space points seen through v) into the edge list, with
 * the rules of world/face.h. */
void ew_front_face(ew_front *fr, int fi, int clipflags, int key);
void ew_front_poly(ew_front *fr, float (*verts)[3], int n, int fi, const ew_view *v, int key);

/* world/bsp_walk.c: front-to-back walk handing every visible face to the
 * frame's hidden-surface method. */
void ew_walk_world(ew_front *fr);

/* The walk's pieces, for walking subtrees on several threads
 * (world/front_par.c).  A walker carries the BSP key (grows front to back,
 * one per visible leaf and one per visited node) and its own counters;
 * leaf(wk, li) marks a visible leaf's faces (its key and keyframe already
 * set), face() takes every marked face facing the camera with its kind
 * (EW_SEE_*). */
#define EW_MAX_WALK_DEPTH 4096
typedef struct ew_walker ew_walker;
struct ew_walker {
    ew_front    *fr;
    int          key, visible_leaves, dropped;
    void       (*leaf)(ew_walker *wk, int li);
    void       (*face)(ew_walker *wk, int fi, int clipflags, int kind, float alpha);
};
/* Walks node (or leaf, n < 0) n and everything below it. */
void ew_walk_node(ew_walker *wk, int n, int clipflags, int depth);
/* Node n's PVS and frustum test: -1 culled, else the camera's side of its
 * plane (0 front; *d the distance) and *clipflags narrowed. */
int  ew_walk_enter(ew_walker *wk, int n, int *clipflags, float *d);
/* Node n's marked faces on the camera's side to wk->face, then key + 1. */
void ew_walk_faces(ew_walker *wk, int n, int clipflags, int side, float d);
/* Face fi to the see-through pass with BSP key `key`. */
void ew_walk_see_add(ew_front *fr, int fi, int key, int kind, float alpha);

/* world/front_par.c: the walk with ew_front_face of its faces, then the
 * brush models with ew_front_poly of their fragments, on every thread of
 * the pool, making exactly the edge list ew_walk_world and
 * ew_walk_brush_models make: subtrees of the BSP walked in parallel, faces
 * and brush entities clipped, projected and set up in parallel, the edges
 * shared between faces settled and everything numbered by prefix sums;
 * then, on the calling thread, tail(arg), and then then(then_ctx, thread)
 * on every thread of the pool (one pool run for all).  -1 (nothing done)
 * if the method does not take the edge list's faces (out.edge_list), the
 * pool has at most EW_FRONT_LOOP_THREADS threads and phases is 0
 * (ew_front_walks_alone), the tree is irregular (an edge on
 * more than two faces, a face on two nodes...) or memory runs out: then
 * the serial walk and brush models as before.  serial_ms: the time the
 * calling thread spent in the run's serial steps (not the tail): [0] the
 * walk's, [1] the brush entities' culling. */
/* Whether a frame of nthreads threads walks the front end in one loop on
 * the calling thread (the rule ew_walk_world_parallel and the pool's wake
 * both follow). */
static inline int ew_front_walks_alone(int nthreads, int phases) {
    return nthreads <= EW_FRONT_LOOP_THREADS && !phases;
}
int  ew_walk_world_parallel(ew_front *fr, int phases, void (*tail)(void *arg), void *arg,
                            void (*then)(void *ctx, int thread), void *then_ctx, double serial_ms[2]);
struct ew_front_par;
void ew_front_par_free(struct ew_front_par *fp);
/* 1 if a world-space box touches a leaf in this frame's PVS. */
int  ew_box_in_pvs(const ew_front *fr, const float lo[3], const float hi[3]);

/* world/bmodel.c: brush model entities, split into the world's leaves and
 * handed to the hidden-surface method with their leaf's BSP key. */
void ew_walk_brush_models(ew_front *fr);
/* Its pieces, for the parallel front end: the brush entities in the
 * frustum (camera in its own space, axes), and one entity's fragments
 * handed to a sink. */
typedef struct ew_brush_item {
    int      ent;
    ew_view *mv;
    float    ax[3][3];
} ew_brush_item;
typedef void (*ew_frag_sink)(void *ctx, float (*p)[3], int n, int face, const ew_view *v, int key, int kind,
                             float alpha);
int  ew_brush_items(ew_front *fr, ew_brush_item *items, int *culled);
int  ew_brush_split(const ew_front *fr, const ew_brush_item *it, ew_frag_sink sink, void *sink_ctx, int *dropped);

/* world/divert.c: faces that are not opaque (fence textures, translucent
 * liquids and brush entities) go to the see-through pass instead of the
 * hidden-surface method (the kinds EW_SEE_*: frame.h).
 * EW_SEE_OPAQUE, _FENCE or _BLEND (with *alpha) for face f of the world
 * (entity_alpha 1 for the world itself). */
int  ew_see_kind(const ew_front *fr, const ew_face *f, float entity_alpha, float *alpha);
/* 1 if a face of that kind goes to the hidden-surface method. */
static inline int ew_see_to_hsr(const ew_front *fr, int kind) {
    return kind == EW_SEE_OPAQUE || (kind == EW_SEE_FENCE && fr->out.fences);
}

/* world/entities.c: which entities the PVS and the frustum let through,
 * and the light on each (out.entity_light), for entities [from, to) of
 * fr->scene into fr->ent_frame (sized for them): any thread, each on its
 * own entities. */
void ew_test_entities(ew_front *fr, int from, int to);

#endif
