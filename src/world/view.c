/* View setup: camera basis from Quake angles, projection, frustum planes. */
#include "ew_render.h"

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

void ew_view_setup(ew_view *v, const ew_camera *cam, int width, int height) {
    const double d2r = 3.14159265358979323846 / 180.0;
    double sp = sin(cam->angles[0] * d2r), cp = cos(cam->angles[0] * d2r);
    double sy = sin(cam->angles[1] * d2r), cy = cos(cam->angles[1] * d2r);
    double sr = sin(cam->angles[2] * d2r), cr = cos(cam->angles[2] * d2r);

    for (int i = 0; i < 3; i++) v->origin[i] = cam->origin[i];
    /* Quake: positive pitch looks down, yaw turns left, x forward, y left, z up. */
    v->forward[0] = (float)(cp * cy);
    v->forward[1] = (float)(cp * sy);
    v->forward[2] = (float)(-sp);
    v->right[0] = (float)(-sr * sp * cy + cr * sy);
    v->right[1] = (float)(-sr * sp * sy - cr * cy);
    v->right[2] = (float)(-sr * cp);
    v->up[0] = (float)(cr * sp * cy + sr * sy);
    v->up[1] = (float)(cr * sp * sy - sr * cy);
    v->up[2] = (float)(cr * cp);

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
