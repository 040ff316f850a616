/* The view set of ../shared/BENCHMARK.md: the cameras every figure uses. */
#include "entities.h"

int ew_view_set(const ew_world *w, ew_camera views[EW_MAX_VIEWS]) {
    if (!w || !views)
        return 0;
    return ew_view_set_from_entities(ew_world_entities(w), views, EW_MAX_VIEWS);
}
