/* The camera of a frame (internal, world/view.c): basis, projection and
 * frustum planes, and the moves between world and model space. */
#ifndef EW_WORLD_VIEW_H
#define EW_WORLD_VIEW_H

#include "frame.h"


void ew_view_setup(ew_view *v, const ew_camera *cam, int width, int height);
/* Forward, right and up of Quake angles (pitch yaw roll, degrees). */
void ew_angle_vectors(const float angles[3], float fwd[3], float right[3], float up[3]);
/* Entity rotation from Quake angles: columns are the model's x, y, z axes. */
void ew_entity_axes(const float angles[3], float ax[3][3]);
/* Moved models (ax: the model's axes as columns, from ew_entity_axes):
 * the world box around its moved bounds, and the camera in its own space
 * (p_model = ax^T (p_world - origin)). */
void ew_moved_box(const float ax[3][3], const float origin[3], const float mins[3],
                  const float maxs[3], float lo[3], float hi[3]);
void ew_view_to_model(const ew_view *v, const float ax[3][3], const float origin[3], ew_view *out);
/* Face f's 1/z plane seen through v (the camera in the face's own space):
 * 1/z = out[0] u + out[1] v + out[2] (the gradients' zi_u, zi_v, zi_0,
 * raster/gradients.c). */
void ew_face_zplane(const ew_world *w, const ew_view *v, const ew_face *f, float out[3]);
/* World point -> view space (x right, y up, z forward). */
static inline void ew_view_transform(const ew_view *v, const float p[3], float out[3]) {
    float d0 = p[0] - v->origin[0], d1 = p[1] - v->origin[1], d2 = p[2] - v->origin[2];
    out[0] = d0 * v->right[0] + d1 * v->right[1] + d2 * v->right[2];
    out[1] = d0 * v->up[0] + d1 * v->up[1] + d2 * v->up[2];
    out[2] = d0 * v->forward[0] + d1 * v->forward[1] + d2 * v->forward[2];
}
/* The box [lo, hi]'s distances along plane p's normal: *far_pt of its corner
 * furthest along it, *near_pt of the least (the plane's dist not taken). */
static inline void ew_box_reach(const ew_plane *p, const float lo[3], const float hi[3], float *far_pt,
                                float *near_pt) {
    float f = 0, n = 0;
    for (int k = 0; k < 3; k++) {
        int pos = p->normal[k] >= 0;
        f += p->normal[k] * (pos ? hi[k] : lo[k]);
        n += p->normal[k] * (pos ? lo[k] : hi[k]);
    }
    *far_pt = f, *near_pt = n;
}
/* -1 if the box is outside a frustum plane in clipflags, else the planes it still crosses. */
int  ew_cull_box(const ew_view *v, const float mins[3], const float maxs[3], int clipflags);
/* A face's box (ew_world.face_box) against the planes in clipflags: -1 if
 * it is wholly outside one, else the planes it may cross.  Decides only
 * what ew_clip_poly would decide the same way for every corner (a margin
 * keeps a box touching a plane in the flags), so a face keeps its clip. */
static inline int ew_cull_face(const ew_view *v, const float box[2][3], int clipflags) {
    const float margin = 1.0f / 16;  /* far above the sums' rounding at map sizes */
    for (int i = 0; i < 4; i++) {
        if (!(clipflags & (1 << i))) continue;
        const ew_plane *p = &v->frustum[i];
        float far_pt, near_pt;
        ew_box_reach(p, box[0], box[1], &far_pt, &near_pt);
        if (far_pt < p->dist - margin) return -1;
        if (near_pt > p->dist + margin) clipflags &= ~(1 << i);
    }
    return clipflags;
}

/* world/clip.c: clips a polygon (world coords) against the frustum planes
 * in clipflags; returns the vertex count (0 if all clipped).  tag_out[i] =
 * tag_in of the original edge leaving vertex i, or -1 for a new edge. */
#define EW_MAX_POLY 256
int  ew_clip_poly(const ew_view *v, int clipflags, float (*in)[3], int nin,
                  float (*out)[3], int *edge_tag_in, int *edge_tag_out);

#endif
