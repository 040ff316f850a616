/* View setup: camera basis from Quake angles, projection, frustum planes. */
#include "world/view.h"

#include <math.h>

static void set_plane(ew_plane *p, const ew_view *v, float x, float y, float z) {
    /* (x, y, z) is an inward normal in view space; the plane passes through the eye. */
    float len = sqrtf(x * x + y * y + z * z);
    x /= len, y /= len, z /= len;
    for (int i = 0; i < 3; i++)
        p->normal[i] = x * v->right[i] + y * v->up[i] + z * v->forward[i];
    p->dist = p->normal[0] * v->origin[0] + p->normal[1] * v->origin[1] + p->normal[2] * v->origin[2];
    p->type = 3;
}

void ew_angle_vectors(const float angles[3], float fwd[3], float right[3], float up[3]) {
    /* +0 only: -0 would turn the sign of some zeros below. */
    if (angles[0] == 0 && angles[1] == 0 && angles[2] == 0 && !signbit(angles[0]) && !signbit(angles[1]) &&
        !signbit(angles[2])) {
        /* Most entities: what the formulas below give for sin 0 = 0 and
         * cos 0 = 1, signed zeros included, without the six calls. */
        fwd[0] = 1, fwd[1] = 0, fwd[2] = -0.0f;
        right[0] = 0, right[1] = -1, right[2] = -0.0f;
        up[0] = 0, up[1] = 0, up[2] = 1;
        return;
    }
    const double d2r = 3.14159265358979323846 / 180.0;
    double sp = sin(angles[0] * d2r), cp = cos(angles[0] * d2r);
    double sy = sin(angles[1] * d2r), cy = cos(angles[1] * d2r);
    double sr = sin(angles[2] * d2r), cr = cos(angles[2] * d2r);
    /* Quake: positive pitch looks down, yaw turns left, x forward, y left, z up. */
    fwd[0] = (float)(cp * cy), fwd[1] = (float)(cp * sy), fwd[2] = (float)(-sp);
    right[0] = (float)(-sr * sp * cy + cr * sy);
    right[1] = (float)(-sr * sp * sy - cr * cy);
    right[2] = (float)(-sr * cp);
    up[0] = (float)(cr * sp * cy + sr * sy);
    up[1] = (float)(cr * sp * sy - sr * cy);
    up[2] = (float)(cr * cp);
}

void ew_view_setup(ew_view *v, const ew_camera *cam, int width, int height) {
    const double d2r = 3.14159265358979323846 / 180.0;
    for (int i = 0; i < 3; i++) v->origin[i] = cam->origin[i];
    ew_angle_vectors(cam->angles, v->forward, v->right, v->up);

    float fov = cam->fov > 0 ? cam->fov : 90.0f;
    v->width = width;
    v->height = height;
    /* Integers are pixel centres, so the screen spans [-0.5, width - 0.5]. */
    v->xcenter = width * 0.5f - 0.5f;
    v->ycenter = height * 0.5f - 0.5f;
    v->xscale = (float)(width * 0.5 / tan(fov * 0.5 * d2r));
    v->yscale = v->xscale;  /* square pixels */
    v->time = cam->time;

    float tx = width * 0.5f / v->xscale, ty = height * 0.5f / v->yscale;
    set_plane(&v->frustum[0], v, 1, 0, tx);   /* left:   x/z >= -tx */
    set_plane(&v->frustum[1], v, -1, 0, tx);  /* right:  x/z <=  tx */
    set_plane(&v->frustum[2], v, 0, -1, ty);  /* top:    y/z <=  ty */
    set_plane(&v->frustum[3], v, 0, 1, ty);   /* bottom: y/z >= -ty */
}

void ew_moved_box(const float ax[3][3], const float origin[3], const float mins[3],
                  const float maxs[3], float lo[3], float hi[3]) {
    /* Each coordinate of a moved corner is ((origin + a0) + a1) + a2, one
     * term per axis, and rounding never reverses an order, so the least
     * corner takes the least term of each axis in that order: the same value
     * as the least of the eight corners, without forming them. */
    for (int k = 0; k < 3; k++) {
        float l = origin[k], h = origin[k];
        for (int j = 0; j < 3; j++) {
            float a = ax[k][j] * mins[j], b = ax[k][j] * maxs[j];
            l += a < b ? a : b;
            h += a > b ? a : b;
        }
        lo[k] = l, hi[k] = h;
    }
}

void ew_view_to_model(const ew_view *v, const float ax[3][3], const float origin[3], ew_view *out) {
    *out = *v;
    const float *src[4] = {v->origin, v->forward, v->right, v->up};
    float *dst[4] = {out->origin, out->forward, out->right, out->up};
    for (int q = 0; q < 4; q++) {
        float d[3] = {src[q][0], src[q][1], src[q][2]};
        if (q == 0)  /* a point moves with the model; directions only turn */
            for (int k = 0; k < 3; k++) d[k] -= origin[k];
        for (int k = 0; k < 3; k++) dst[q][k] = ax[0][k] * d[0] + ax[1][k] * d[1] + ax[2][k] * d[2];
    }
}

/* Entity rotation: columns are the model's x (forward), y (left), z (up). */
void ew_entity_axes(const float angles[3], float ax[3][3]) {
    float fwd[3], right[3], up[3];
    ew_angle_vectors(angles, fwd, right, up);
    for (int k = 0; k < 3; k++) ax[k][0] = fwd[k], ax[k][1] = -right[k], ax[k][2] = up[k];
}

/* Returns -1 if the box is outside a plane, else the reduced clipflags. */
int ew_cull_box(const ew_view *v, const float mins[3], const float maxs[3], int clipflags) {
    for (int i = 0; i < 4; i++) {
        if (!(clipflags & (1 << i))) continue;
        const ew_plane *p = &v->frustum[i];
        float far_pt, near_pt;  /* corners most / least along the normal */
        ew_box_reach(p, mins, maxs, &far_pt, &near_pt);
        if (far_pt <= p->dist) return -1;                 /* wholly outside */
        if (near_pt >= p->dist) clipflags &= ~(1 << i);   /* wholly inside */
    }
    return clipflags;
}

void ew_face_zplane(const ew_world *w, const ew_view *v, const ew_face *f, float out[3]) {
    const ew_plane *pl = &w->planes[f->plane];
    float nx = 0, ny = 0, nz = 0, od = 0;
    for (int k = 0; k < 3; k++) {
        nx += pl->normal[k] * v->right[k];
        ny += pl->normal[k] * v->up[k];
        nz += pl->normal[k] * v->forward[k];
        od += pl->normal[k] * v->origin[k];
    }
    float dist = pl->dist - od;  /* plane in view space: n.p = dist */
    if (fabsf(dist) < 1e-3f) dist = dist < 0 ? -1e-3f : 1e-3f;
    out[0] = nx / (v->xscale * dist);
    out[1] = -ny / (v->yscale * dist);
    out[2] = nz / dist - v->xcenter * out[0] - v->ycenter * out[1];
}
