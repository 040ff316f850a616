/* The view set of ../shared/BENCHMARK.md (internal; ew_benchmark_views is
 * the public way in). */
#ifndef EW_BENCH_VIEWS_H
#define EW_BENCH_VIEWS_H

#include "edgewise.h"
#include "asset/entity_lump.h"

/* The view set from entity lump text: at most max cameras (fov 90, time 0)
 * written to views; returns the count. */
int ew_benchmark_views_from_entities(const char *text, ew_camera *views, int max);
/* The camera of one entity, as the view set reads it: a player start's eye
 * turned by its "angle", an intermission's "mangle"; 0 if the entity is
 * neither.  *intermission (may be NULL) says which. */
int ew_entity_camera(const ew_entity *e, ew_camera *c, int *intermission);

#endif
