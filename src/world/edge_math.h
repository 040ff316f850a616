/* The edge list's per-edge arithmetic (internal), shared by the serial
 * emission (world/edges.c) and the parallel one (world/front_par.c), which
 * must compute bit-identical edges: a point projected to the screen, and
 * an edge's first scanline, 16.16 start and step between two projected
 * points. */
#ifndef EW_WORLD_EDGE_MATH_H
#define EW_WORLD_EDGE_MATH_H

#include "hsr/hsr.h"
#include "world/view.h"

#include <math.h>

#define EW_NEAR_Z 0.01f

typedef struct ew_proj { float u, v, zi; } ew_proj;

static inline void ew_project(const ew_view *v, const float p[3], ew_proj *out) {
    float t[3];
    ew_view_transform(v, p, t);
    float z = t[2] < EW_NEAR_Z ? EW_NEAR_Z : t[2];
    float zi = 1.0f / z;
    float u = v->xcenter + v->xscale * t[0] * zi;
    float y = v->ycenter - v->yscale * t[1] * zi;
    /* Frustum clipping leaves points on the screen's borders; float error
     * must not push them past, or spans would leave the frame. */
    float umax = v->width - 0.5f, vmax = v->height - 0.5f;
    out->u = u < -0.5f ? -0.5f : u > umax ? umax : u;
    out->v = y < -0.5f ? -0.5f : y > vmax ? vmax : y;
    out->zi = zi;
}

/* The edge a->b's position (u, u_step, v_first, v_last; not its surfaces
 * or list link) into e; 0 if it crosses no scanline centre (horizontal or
 * too short) and so never bounds a span. */
static inline int ew_edge_setup(const ew_proj *a, const ew_proj *b, ew_edge *e) {
    int down = b->v > a->v;
    const ew_proj *top = down ? a : b, *bot = down ? b : a;
    int first = (int)ceilf(top->v), last = (int)ceilf(bot->v) - 1;
    if (first > last) return 0;
    double slope = (double)(bot->u - top->u) / (double)(bot->v - top->v);
    double u = top->u + (first - top->v) * slope;
    e->u = (int32_t)floor(u * 65536.0 + 0.5);
    e->u_step = first == last ? 0 : (int32_t)floor(slope * 65536.0 + 0.5);
    e->v_first = first;
    e->v_last = last;
    return 1;
}

#endif
