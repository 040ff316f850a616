/* The front end (internal): what can be seen this frame.  The PVS marks
 * the leaves visible from the camera's leaf, the walk visits the BSP front
 * to back culling nodes by the frustum and hands every visible face to the
 * frame's hidden-surface method, brush models are split into the leaves
 * they occupy, and entities are culled by the PVS and the frustum. */
#ifndef EW_WORLD_FRONT_H
#define EW_WORLD_FRONT_H

#include "world/view.h"

typedef struct ew_renderer ew_renderer;

/* Per-world marks, compared against framecount (so nothing is cleared
 * between frames). */
typedef struct ew_marks {
    int  framecount;
    int *leaf_frame, *node_frame, *face_frame;
    int *leaf_key, *leaf_keyframe;            /* BSP key of each visited leaf */
    int *face_dlframe; unsigned *face_dlbits; /* dynamic lights on each face */
    int *edge_cache_frame, *edge_cache_index; /* per world edge: shared edges */
    int8_t *edge_cache_down;                  /* +1: +sign traversal goes down */
} ew_marks;

/* world/pvs.c: marks the leaves (and their ancestors) visible from the
 * camera's leaf for this frame; returns the view leaf. */
int  ew_pvs_mark(ew_renderer *r);
int  ew_point_leaf(const ew_world *w, int headnode, const float p[3]);

/* world/bsp_walk.c: front-to-back walk handing every visible face to the
 * frame's hidden-surface method. */
void ew_walk_world(ew_renderer *r);
/* 1 if a world-space box touches a leaf in this frame's PVS. */
int  ew_box_in_pvs(const ew_renderer *r, const float lo[3], const float hi[3]);

/* world/bmodel.c: brush model entities, split into the world's leaves and
 * handed to the hidden-surface method with their leaf's BSP key. */
void ew_walk_brush_models(ew_renderer *r);
/* Calls fn for every camera-facing face of every brush entity in the
 * frustum, with the polygon moved into world space, the face's world
 * normal and the camera in model space; fn returns 1 if it drew anything. */
typedef int (*ew_brush_face_fn)(ew_renderer *r, void *ctx, int face, const ew_view *model_view,
                                const float normal[3], float (*poly)[3], int n);
void ew_for_brush_faces(ew_renderer *r, ew_brush_face_fn fn, void *ctx);

/* world/entities.c: once per frame before the bands draw (serial): which
 * entities the PVS and the frustum let through, and the light on each, so
 * that the bands do not each work it out again; returns how many alias
 * models are left to pose (ew_pose_alias).  Out of memory: no entities
 * (counted in dropped). */
typedef struct ew_ent_frame {
    int    visible;
    int    ambient, shade;
    size_t xvert0;      /* alias models: where their posed vertices start in ents.xverts */
} ew_ent_frame;
int  ew_prepare_entities(ew_renderer *r);

#endif
