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

int ew_entity_camera(const ew_entity *e, ew_camera *c, int *intermission) {
    const char *cls = ew_entity_get(e, "classname");
    if (!cls) return 0;
    int inter = strcmp(cls, "info_intermission") == 0;
    if (!inter && strncmp(cls, "info_player", 11) != 0) return 0;
    float a[3] = {0, 0, 0};
    memset(c, 0, sizeof *c);
    ew_entity_floats(e, "origin", c->origin, 3);
    if (inter) {
        ew_entity_floats(e, "mangle", a, 3);
        memcpy(c->angles, a, sizeof a);
    } else {
        ew_entity_floats(e, "angle", a, 1);
        c->origin[2] += EW_EYE_HEIGHT;
        c->angles[1] = a[0];
    }
    c->fov = 90.0f;
    if (intermission) *intermission = inter;
    return 1;
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
        ew_camera c;
        int inter;
        if (!ew_entity_camera(&ents.ents[i], &c, &inter))
            continue;
        for (int k = 0; k < (inter ? 1 : 4) && n < max; k++) {
            views[n] = c;
            views[n++].angles[1] = c.angles[1] + 90.0f * (float)k;
        }
    }
    ew_entities_free(&ents);
    return n;
}
