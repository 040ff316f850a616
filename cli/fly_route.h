/*
 * fly_route.h - fly's default camera path through open space (fly_route.c).
 *
 * The views are joined in order by paths that keep the eye in the open:
 * a straight segment where it is clear (point traces of the rendering hull
 * with a margin around the eye, ew_trace), else a path found by an A*
 * search over a coarse grid of open points and shortened by cutting every
 * corner it can see past.  A smooth spline runs through the waypoints; a
 * piece of it that would touch solid or the sky is drawn straight instead.
 * A view whose eye is in solid or that no open path reaches is skipped.
 * Only the public API (ew_trace, ew_point_contents) is used.
 */
#ifndef EW_FLY_ROUTE_H
#define EW_FLY_ROUTE_H

#include "edgewise.h"

typedef struct fly_route fly_route;

/* The route through n view eyes (pos[i]) in order.  kept[] (n entries)
 * receives the indices of the views on the route, *nkept their count (at
 * least 1 when the first view's eye is open, else 0 and NULL is
 * returned).  NULL on failure (out of memory or no open view). */
fly_route *fly_route_build(const ew_world *w, const double (*pos)[3], int n, int *kept, int *nkept);
/* The eye at fraction u (0..1) of leg i (from kept view i to kept view
 * i + 1), moving at an even speed along the leg. */
void fly_route_eye(const fly_route *r, int leg, double u, double out[3]);
void fly_route_destroy(fly_route *r);

#endif
