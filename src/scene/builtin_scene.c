/*
 * The built-in scene's moving things, made in memory like its world:
 *   - the door: the entity lump's func_door (submodel *1), spawned by
 *     ew_scene_create_from_map like any map's brush entities;
 *   - lantern bearers (src/mapgen/mdl_writer.c's MDL): two floating by the
 *     courtyard's east wall on either side of the corridor, where the demo
 *     view (view 0) looks, turned towards the player start (the right one
 *     in the wall's shadow); a third on the platform for the other views;
 *   - a dynamic light at each of the two lanterns, lighting the floor, the
 *     wall behind them and the door;
 *   - a fountain in the pool: particles on the arcs of water thrown up
 *     from it, with a spray where they fall back.
 * Everything is fixed, so every call makes the same scene.
 */
#include "mapgen/mapgen.h"
#include "asset/scene.h"
#include "raster/alias.h"
#include "ew_util.h"

#include <math.h>
#include <stdlib.h>

#define PI 3.14159265358979323846

typedef struct placed {
    float origin[3];
    float yaw;
} placed;

/* By the east wall left and right of the corridor (their lanterns are the
 * dynamic lights); on the platform. */
static const placed bearers[] = {
    {{395, 300, 64}, 200},
    {{415, 128, 64}, 150},
    {{72, 470, 112}, 315},
};

/* The fountain: where the jet leaves the water, how high it rises and how
 * far out its arcs fall. */
static const float fountain_base[3] = {326, 116, 50};
#define FOUNTAIN_HEIGHT 80.0
#define FOUNTAIN_REACH 26.0
#define FOUNTAIN_JET 520
#define FOUNTAIN_SPRAY 160
#define LIT_BEARERS 2
#define LANTERN_LIGHT 150.0f

static uint32_t next(uint32_t *s) {
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}
static double uniform(uint32_t *s) { return next(s) / 16777216.0; }

/* Reshapes n particles (made by ew_scene_add_particles) into the fountain's
 * jet: each is a drop at a random moment of its flight along one of the
 * arcs, so they crowd where the drops are slow, at the top. */
static void shape_jet(ew_particle *p, int n, uint32_t seed) {
    const double g = 800, vz = sqrt(2 * g * FOUNTAIN_HEIGHT), flight = 2 * vz / g;
    for (int i = 0; i < n; i++) {
        double a = 2 * PI * uniform(&seed), reach = FOUNTAIN_REACH * (0.75 + 0.4 * uniform(&seed));
        double t = flight * uniform(&seed), vh = reach / flight;
        double h = vz * t - 0.5 * g * t * t;
        double jitter = 1.2 * (uniform(&seed) - 0.5);
        p[i].org[0] = fountain_base[0] + (float)(cos(a) * (vh * t + jitter));
        p[i].org[1] = fountain_base[1] + (float)(sin(a) * (vh * t + jitter));
        p[i].org[2] = fountain_base[2] + (float)h;
        /* white and pale blue, lit by nothing */
        uint32_t c = next(&seed) % 4;
        p[i].color = (uint8_t)(c == 0 ? BI_FB_WHITE : BI_FB_BLUE + (int)c - 1);
    }
}

/* The spray: the ball ew_scene_add_particles made, flattened onto the
 * ring where the arcs meet the water. */
static void shape_spray(ew_particle *p, int n, uint32_t seed) {
    for (int i = 0; i < n; i++) {
        double a = 2 * PI * uniform(&seed), r = FOUNTAIN_REACH * (0.7 + 0.55 * uniform(&seed));
        p[i].org[0] = fountain_base[0] + (float)(cos(a) * r);
        p[i].org[1] = fountain_base[1] + (float)(sin(a) * r);
        p[i].org[2] = fountain_base[2] - 1 + (float)(7 * uniform(&seed) * uniform(&seed));
        p[i].color = (uint8_t)(next(&seed) % 3 ? BI_FB_BLUE + 1 : bi_px(BI_R_TEAL, 14));
    }
}

/* The lantern of a bearer in the world (pose 0). */
static void lantern_at(const placed *b, float out[3]) {
    double y = b->yaw * PI / 180;
    const float *l = bi_model_lantern;
    out[0] = b->origin[0] + (float)(cos(y) * l[0] - sin(y) * l[1]);
    out[1] = b->origin[1] + (float)(sin(y) * l[0] + cos(y) * l[1]);
    out[2] = b->origin[2] + l[2];
}

ew_scene *ew_scene_create_builtin(const ew_world *w, ew_error *err) {
    ew_scene *s = ew_scene_create_from_map(w, NULL, NULL, err);
    if (!s) return NULL;
    uint8_t *mdl;
    size_t size;
    if (bi_model_generate(&mdl, &size, err)) goto fail;
    int model = ew_scene_load_model(s, "builtin/bearer.mdl", mdl, size, err);
    free(mdl);
    if (model < 0) goto fail;
    for (size_t i = 0; i < sizeof bearers / sizeof bearers[0]; i++) {
        const float angles[3] = {0, bearers[i].yaw, 0};
        if (ew_scene_add_entity(s, model, bearers[i].origin, angles, 0, 0) < 0) goto oom;
    }
    for (int i = 0; i < LIT_BEARERS; i++) {
        float light[3];
        lantern_at(&bearers[i], light);
        if (ew_scene_add_dlight(s, light, LANTERN_LIGHT) < 0) goto oom;
    }

    int first = s->nparticles;
    if (ew_scene_add_particles(s, FOUNTAIN_JET, fountain_base, (float)FOUNTAIN_REACH, 1996) < 0 ||
        ew_scene_add_particles(s, FOUNTAIN_SPRAY, fountain_base, (float)FOUNTAIN_REACH, 1997) < 0)
        goto oom;
    shape_jet(s->particles + first, FOUNTAIN_JET, 1996);
    shape_spray(s->particles + first + FOUNTAIN_JET, FOUNTAIN_SPRAY, 1997);
    return s;
oom:
    ew_fail(err, "builtin scene: out of memory");
fail:
    ew_scene_destroy(s);
    return NULL;
}
