/* Scenes: the entities of a map (or of a program) drawn over its world. */
#include "scene.h"
#include "entities.h"
#include "ew_render.h"
#include "ew_util.h"

#include <stdlib.h>
#include <string.h>

ew_scene *ew_scene_create(const ew_world *w, ew_error *err) {
    ew_scene *s = calloc(1, sizeof *s);
    if (!s) {
        ew_fail(err, "scene: out of memory");
        return NULL;
    }
    s->world = w;
    return s;
}

void ew_scene_free(ew_scene *s) {
    if (!s) return;
    free(s->ents);
    free(s->models);
    free(s->particles);
    free(s);
}

int ew_scene_add_entity(ew_scene *s, int model, const float origin[3], const float angles[3],
                        int frame, int skin) {
    if (model >= s->nmodels || (model < 0 && -1 - model >= s->world->nummodels)) return -1;
    if (s->nents == s->cap_ents) {
        int cap = s->cap_ents ? s->cap_ents * 2 : 64;
        ew_scene_entity *e = realloc(s->ents, sizeof *e * (size_t)cap);
        if (!e) return -1;
        s->ents = e, s->cap_ents = cap;
    }
    ew_scene_entity *e = &s->ents[s->nents];
    memset(e, 0, sizeof *e);
    e->model = model;
    for (int k = 0; k < 3; k++) {
        e->origin[k] = origin ? origin[k] : 0;
        e->angles[k] = angles ? angles[k] : 0;
    }
    e->frame = frame, e->skin = skin;
    return s->nents++;
}

int ew_scene_add_brush(ew_scene *s, int submodel, const float origin[3], const float angles[3]) {
    if (submodel <= 0 || submodel >= s->world->nummodels) return -1;
    return ew_scene_add_entity(s, -1 - submodel, origin, angles, 0, 0);
}

int ew_scene_add_dlight(ew_scene *s, const float origin[3], float radius) {
    if (s->ndlights >= EW_MAX_DLIGHTS || !(radius > 0) || radius > 1e5f) return -1;
    ew_dlight *d = &s->dlights[s->ndlights];
    for (int k = 0; k < 3; k++) d->origin[k] = origin[k];
    d->radius = radius;
    return s->ndlights++;
}

void ew_scene_counts(const ew_scene *s, int *entities, int *unknown, int *missing) {
    if (entities) *entities = s->nents;
    if (unknown) *unknown = s->unknown;
    if (missing) *missing = s->missing;
}

ew_scene *ew_scene_from_map(const ew_world *w, const char *map, const char *data_dir, ew_error *err) {
    (void)map, (void)data_dir;
    ew_scene *s = ew_scene_create(w, err);
    if (!s) return NULL;
    const char *text = ew_world_entities(w);
    ew_entities ents;
    ew_error perr;
    ew_entities_parse(text, strlen(text), &ents, &perr);  /* keeps what parsed */
    for (int i = 0; i < ents.count; i++) {
        const ew_entity *e = &ents.ents[i];
        const char *cls = ew_entity_get(e, "classname");
        const char *model = ew_entity_get(e, "model");
        if (!cls || strcmp(cls, "worldspawn") == 0) continue;
        float origin[3] = {0, 0, 0}, angles[3] = {0, 0, 0};
        ew_entity_floats(e, "origin", origin, 3);
        if (model && model[0] == '*') {
            /* A brush entity's "angle" is its direction of travel, not a turn. */
            char *end;
            long sub = strtol(model + 1, &end, 10);
            if (*end || sub <= 0 || sub >= w->nummodels || ew_scene_add_brush(s, (int)sub, origin, angles) < 0)
                s->missing++;
            continue;
        }
    }
    ew_entities_free(&ents);
    return s;
}

void ew_set_scene(ew_renderer *r, const ew_scene *s) {
    r->scene = s;
    int need = s ? s->nents : 0;
    if (need > r->max_ent_views) {
        ew_view *v = realloc(r->ent_views, sizeof *v * (size_t)need);
        if (v) r->ent_views = v, r->max_ent_views = need;
    }
}
