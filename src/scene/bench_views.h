/* The view set of ../shared/BENCHMARK.md (internal; ew_benchmark_views is
 * the public way in). */
#ifndef EW_BENCH_VIEWS_H
#define EW_BENCH_VIEWS_H

#include "edgewise.h"

/* The view set from entity lump text: at most max cameras (fov 90, time 0)
 * written to views; returns the count. */
int ew_benchmark_views_from_entities(const char *text, ew_camera *views, int max);

#endif
