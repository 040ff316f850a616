/* The built-in scene's moving things. */
#include "edgewise.h"

ew_scene *ew_scene_builtin(const ew_world *w, ew_error *err) {
    return ew_scene_from_map(w, NULL, NULL, err);
}
