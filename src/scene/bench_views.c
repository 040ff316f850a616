/* The view set of ../shared/BENCHMARK.md: the cameras every benchmark
 * figure (and every golden frame) uses.  A policy of the benchmark, read
 * from the entity lump; the renderer itself knows nothing of it. */
#include "bench_views.h"
#include "asset/entity_lump.h"

#include <string.h>

int ew_benchmark_views(const ew_world *w, ew_camera views[EW_MAX_VIEWS]) {
    if (!w || !views)
        return 0;
    return ew_benchmark_views_from_entities(ew_world_entities(w), views, EW_MAX_VIEWS);
}

/* Each player start (info_player_*) gives four views, its eye 22 units over
 * the origin, turned by 0, 90, 180 and 270 degrees from its "angle"; each
 * info_intermission one, from its "mangle". */
int ew_benchmark_views_from_entities(const char *text, ew_camera *views, int max) {
    if (!text || !views || max <= 0)
        return 0;
    ew_entities ents;
    ew_entities_parse(text, strlen(text), &ents, NULL);  /* keep what parsed */
    int n = 0;
    for (int i = 0; i < ents.count && n < max; i++) {
        const ew_entity *e = &ents.ents[i];
        const char *cls = ew_entity_get(e, "classname");
        if (!cls)
            continue;
        float origin[3], a[3];
        if (strncmp(cls, "info_player", 11) == 0) {
            ew_entity_floats(e, "origin", origin, 3);
            ew_entity_floats(e, "angle", a, 1);
            for (int k = 0; k < 4 && n < max; k++) {
                ew_camera *c = &views[n++];
                memset(c, 0, sizeof *c);
                c->origin[0] = origin[0];
                c->origin[1] = origin[1];
                c->origin[2] = origin[2] + 22.0f;   /* eye height */
                c->angles[1] = a[0] + 90.0f * (float)k;
                c->fov = 90.0f;
            }
        } else if (strcmp(cls, "info_intermission") == 0) {
            ew_entity_floats(e, "origin", origin, 3);
            ew_entity_floats(e, "mangle", a, 3);
            ew_camera *c = &views[n++];
            memset(c, 0, sizeof *c);
            memcpy(c->origin, origin, sizeof origin);
            memcpy(c->angles, a, sizeof a);
            c->fov = 90.0f;
        }
    }
    ew_entities_free(&ents);
    return n;
}
