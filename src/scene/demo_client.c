/*
 * A demo's client (ew_demo_client in edgewise.h): the scene and camera the
 * game's client would draw at a time between the two latest messages of a
 * demo read by asset/demo.c.  Entities are interpolated between their two
 * latest updates; effects (temp entities, particle bursts, trails) are
 * functions of their age drawn from a seeded hash, so a frame depends only
 * on the blocks read and the time asked for.
 */
#include "asset/scene.h"
#include "asset/mdl.h"
#include "ew_util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* An alias model's flags (the MDL header's). */
#define MF_ROCKET  1
#define MF_GRENADE 2
#define MF_GIB     4
#define MF_ROTATE  8
#define MF_TRACER  16
#define MF_ZOMGIB  32
#define MF_TRACER2 64
#define MF_TRACER3 128
#define MF_TRAILS (MF_ROCKET | MF_GRENADE | MF_GIB | MF_TRACER | MF_ZOMGIB | MF_TRACER2 | MF_TRACER3)

/* Entity effects (the update's byte). */
#define EF_BRIGHTFIELD 1
#define EF_MUZZLEFLASH 2
#define EF_BRIGHTLIGHT 4
#define EF_DIMLIGHT    8

#define MAX_EFFECTS 256
#define TRAIL_POINTS 32
#define BEAM_LIFE 0.2
#define PI 3.14159265358979323846

typedef struct effect {
    ew_demo_event ev;
    double   t0;     /* client time it appeared */
    uint32_t seed;
} effect;

typedef struct trail {
    int    n, head;  /* points in the ring, the newest's slot */
    double t[TRAIL_POINTS];
    float  org[TRAIL_POINTS][3];
    int    kind;     /* MF_* of the model that left it */
} trail;

enum { BEAM_BOLT, BEAM_BOLT2, BEAM_BOLT3, BEAM_BEAM, BEAM_KINDS };

struct ew_demo_client {
    ew_demo        *d;
    const ew_world *w;
    ew_fs          *fs;
    ew_scene       *scene;
    int             model_of[EW_DEMO_MAX_MODELS];  /* scene model; <= -2: brush submodel -2 - m; -1 none */
    int             flags_of[EW_DEMO_MAX_MODELS];  /* alias model flags (MF_*) */
    int             loaded;                        /* precaches taken in (1..loaded) */
    char            level_models[64];              /* models[1] when they were taken in */
    int             missing;
    int             beam[BEAM_KINDS];              /* scene models of the beams, -1 missing */
    effect          effects[MAX_EFFECTS];
    int             neffects;
    uint32_t        seed;
    trail          *trails;
    int             ntrails;
};

/* ---- a hash for the effects' randomness ---------------------------------- */

static uint32_t mix(uint32_t a, uint32_t b) {
    uint32_t h = a * 0x9E3779B1u ^ (b + 0x7F4A7C15u) * 0x85EBCA77u;
    h ^= h >> 15, h *= 0x2C1B3C6Du, h ^= h >> 12, h *= 0x297A2D39u, h ^= h >> 15;
    return h;
}
/* rand() & mask and uniform -1..1, by particle and draw. */
static int rnd(uint32_t seed, int i, int k, int mask) { return (int)(mix(seed, (uint32_t)i * 8u + (uint32_t)k) & (uint32_t)mask); }
static float sfrand(uint32_t seed, int i, int k) {
    return (float)(mix(seed, (uint32_t)i * 8u + (uint32_t)k) & 0xffff) / 32767.5f - 1.0f;
}

/* ---- models --------------------------------------------------------------- */

static int load_model(ew_demo_client *c, const char *name) {
    if (!c->fs) return -1;
    uint8_t *data = NULL;
    size_t size = 0;
    ew_error err;
    if (ew_fs_load(c->fs, name, &data, &size, &err) != 0) return -1;
    int m = ew_scene_load_model(c->scene, name, data, size, &err);
    free(data);
    return m;
}

/* Takes in precaches load..nmodels (a new server info starts again). */
static void take_models(ew_demo_client *c) {
    const ew_demo_state *st = ew_demo_get_state(c->d);
    if (st->nmodels >= 1 && strcmp(c->level_models, st->models[1]) != 0) {
        c->loaded = 0;  /* another level's list */
        snprintf(c->level_models, sizeof c->level_models, "%s", st->models[1]);
    }
    for (int i = c->loaded + 1; i <= st->nmodels; i++) {
        const char *name = st->models[i];
        c->model_of[i] = -1, c->flags_of[i] = 0;
        if (i == 1) continue;  /* the world */
        if (name[0] == '*') {
            long sub = strtol(name + 1, NULL, 10);
            if (sub >= 1 && sub < c->w->nummodels) c->model_of[i] = -2 - (int)sub;
            else c->missing++;
            continue;
        }
        int m = load_model(c, name);
        if (m < 0) {
            c->missing++;
            continue;
        }
        c->model_of[i] = m;
        const ew_scene_model *sm = &c->scene->models[m];
        if (sm->kind == EW_MODEL_ALIAS) c->flags_of[i] = ((const ew_mdl *)sm->data)->flags;
    }
    if (st->nmodels > c->loaded) c->loaded = st->nmodels;
}

ew_demo_client *ew_demo_client_create(ew_demo *d, const ew_world *w, const char *data_dir, ew_error *err) {
    if (!d || !w) {
        ew_fail(err, "demo client: no demo or no world");
        return NULL;
    }
    ew_demo_client *c = calloc(1, sizeof *c);
    if (!c) {
        ew_fail(err, "demo client: out of memory");
        return NULL;
    }
    c->d = d, c->w = w;
    if (!(c->scene = ew_scene_create(w, err))) {
        free(c);
        return NULL;
    }
    if (data_dir && *data_dir && !(c->fs = ew_fs_create(data_dir, err))) {
        ew_demo_client_destroy(c);
        return NULL;
    }
    static const char *const beams[BEAM_KINDS] = {"progs/bolt.mdl", "progs/bolt2.mdl", "progs/bolt3.mdl",
                                                  "progs/beam.mdl"};
    for (int k = 0; k < BEAM_KINDS; k++) c->beam[k] = load_model(c, beams[k]);
    for (int i = 0; i < EW_DEMO_MAX_MODELS; i++) c->model_of[i] = -1;
    c->seed = 0x5eed;
    take_models(c);
    return c;
}

void ew_demo_client_destroy(ew_demo_client *c) {
    if (!c) return;
    ew_scene_destroy(c->scene);
    ew_fs_destroy(c->fs);
    free(c->trails);
    free(c);
}

ew_scene *ew_demo_client_scene(ew_demo_client *c) { return c ? c->scene : NULL; }
int ew_demo_client_missing(const ew_demo_client *c) { return c ? c->missing : 0; }
const char *ew_demo_client_map(const ew_demo_client *c) {
    const ew_demo_state *st = c ? ew_demo_get_state(c->d) : NULL;
    return st && st->nmodels >= 1 ? st->models[1] : "";
}

/* ---- reading ---------------------------------------------------------------- */

static void add_trail_point(ew_demo_client *c, int i, const ew_demo_entity *e, int kind, double t) {
    if (i >= c->ntrails) {
        int n = c->ntrails ? c->ntrails : 64;
        while (n <= i) n *= 2;
        trail *tr = realloc(c->trails, sizeof *tr * (size_t)n);
        if (!tr) return;
        memset(tr + c->ntrails, 0, sizeof *tr * (size_t)(n - c->ntrails));
        c->trails = tr, c->ntrails = n;
    }
    trail *tr = &c->trails[i];
    /* a new entity (not interpolated from the one before) starts a new trail */
    if (tr->kind != kind || memcmp(e->prev_origin, e->origin, sizeof e->origin) == 0) tr->n = 0;
    tr->kind = kind;
    tr->head = (tr->head + 1) % TRAIL_POINTS;
    tr->t[tr->head] = t;
    memcpy(tr->org[tr->head], e->origin, sizeof e->origin);
    if (tr->n < TRAIL_POINTS) tr->n++;
}

int ew_demo_client_read(ew_demo_client *c, ew_error *err) {
    int rc = ew_demo_read_block(c->d, err);
    if (rc <= 0) return rc;
    const ew_demo_state *st = ew_demo_get_state(c->d);
    if (st->nmodels != c->loaded || (st->nmodels >= 1 && strcmp(c->level_models, st->models[1]) != 0))
        take_models(c);
    double t0 = st->prev_time < st->time ? st->prev_time : st->time;
    if (st->time - t0 > 0.1) t0 = st->time - 0.1;
    for (int i = 0; i < st->nevents; i++) {
        if (c->neffects == MAX_EFFECTS) {  /* the oldest goes */
            memmove(c->effects, c->effects + 1, sizeof c->effects[0] * (MAX_EFFECTS - 1));
            c->neffects--;
        }
        effect *f = &c->effects[c->neffects++];
        f->ev = st->events[i];
        f->t0 = t0;
        f->seed = mix(c->seed, (uint32_t)(st->block * 131 + i));
    }
    /* effects long over */
    int k = 0;
    for (int i = 0; i < c->neffects; i++)
        if (c->effects[i].t0 > st->time - 3.0) c->effects[k++] = c->effects[i];
    c->neffects = k;
    /* trails: where the trailing entities were at each message */
    for (int i = 1; i < st->nentities; i++) {
        const ew_demo_entity *e = &st->entities[i];
        if (e->msgtime != st->time || e->model <= 0 || e->model > st->nmodels) continue;
        int kind = c->flags_of[e->model] & MF_TRAILS;
        if (kind) add_trail_point(c, i, e, kind, st->time);
    }
    return 1;
}

int ew_demo_client_advance(ew_demo_client *c, double t, ew_error *err) {
    for (;;) {
        const ew_demo_state *st = ew_demo_get_state(c->d);
        if (st->protocol && st->time >= t && st->block > 0) return 1;
        int rc = ew_demo_client_read(c, err);
        if (rc <= 0) return rc;
    }
}

/* ---- the frame ---------------------------------------------------------------- */

static float lerp_angle(float a, float b, float f) {
    float d = b - a;
    while (d > 180) d -= 360;
    while (d < -180) d += 360;
    return a + d * f;
}

static void angle_vectors(const float ang[3], float fwd[3]) {
    double p = ang[0] * PI / 180, y = ang[1] * PI / 180;
    fwd[0] = (float)(cos(p) * cos(y)), fwd[1] = (float)(cos(p) * sin(y)), fwd[2] = (float)-sin(p);
}

static void particle(ew_scene *s, float x, float y, float z, int color) {
    float p[3] = {x, y, z};
    ew_scene_add_particle(s, p, color);
}

static const uint8_t ramp1[8] = {0x6f, 0x6d, 0x6b, 0x69, 0x67, 0x65, 0x63, 0x61};
static const uint8_t ramp2[8] = {0x6f, 0x6e, 0x6d, 0x6c, 0x6b, 0x6a, 0x68, 0x66};
static const uint8_t ramp3[8] = {0x6d, 0x6b, 6, 5, 4, 3, 3, 3};
#define GRAV 40.0f  /* the particles' fall: sv_gravity * 0.05 units/s^2 */

/* An explosion's particles at age a: half pushed out faster and faster,
 * half slowing, both falling, their colours down the fire ramps. */
static void explosion(ew_scene *s, const float o[3], double a, uint32_t seed, int n, int cstart, int clen) {
    for (int i = 0; i < n; i++) {
        float v[3] = {sfrand(seed, i, 0) * 256, sfrand(seed, i, 1) * 256, sfrand(seed, i, 2) * 256};
        float jit[3] = {sfrand(seed, i, 3) * 16, sfrand(seed, i, 4) * 16, sfrand(seed, i, 5) * 16};
        int r0 = rnd(seed, i, 6, 3);
        float k;
        int color;
        if (clen > 0) {  /* EXPLOSION2: its own colours, a short burst */
            if (a > 0.3) continue;
            k = (float)(1 - exp(-a));
            color = cstart + i % clen;
        } else if (i & 1) {
            double ramp = r0 + a * 10;
            if (ramp >= 8) continue;
            k = (float)((exp(4 * a) - 1) / 4);
            color = ramp1[(int)ramp];
        } else {
            double ramp = r0 + a * 15;
            if (ramp >= 8) continue;
            k = (float)(1 - exp(-a));
            color = ramp2[(int)ramp];
        }
        particle(s, o[0] + jit[0] + v[0] * k, o[1] + jit[1] + v[1] * k,
                 o[2] + jit[2] + v[2] * k - 0.5f * GRAV * (float)(a * a), color & 255);
    }
}

/* svc_particle's burst (R_RunParticleEffect): count particles spread 8
 * units about org, moving dir * 15, falling, each living 0..0.4 s. */
static void burst(ew_scene *s, const float o[3], const float dir[3], int count, int color, double a, uint32_t seed) {
    if (count >= 1024) {
        explosion(s, o, a, seed, 1024, 0, 0);
        return;
    }
    for (int i = 0; i < count; i++) {
        double life = 0.1 * rnd(seed, i, 0, 3);
        if (a > life + 0.05) continue;
        float x = o[0] + (float)(rnd(seed, i, 1, 15) - 8) + dir[0] * 15 * (float)a;
        float y = o[1] + (float)(rnd(seed, i, 2, 15) - 8) + dir[1] * 15 * (float)a;
        float z = o[2] + (float)(rnd(seed, i, 3, 15) - 8) + dir[2] * 15 * (float)a - 0.5f * GRAV * (float)(a * a);
        particle(s, x, y, z, ((color & ~7) + rnd(seed, i, 4, 7)) & 255);
    }
}

static void beam(ew_demo_client *c, int model, const float start[3], const float end[3], uint32_t seed) {
    if (model < 0) return;
    float d[3] = {end[0] - start[0], end[1] - start[1], end[2] - start[2]};
    float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(len > 0) || len > 8192) return;
    float yaw = (float)(atan2(d[1], d[0]) * 180 / PI);
    float pitch = (float)(atan2(d[2], sqrtf(d[0] * d[0] + d[1] * d[1])) * 180 / PI);
    for (int i = 0; len > 0 && i < 300; i++, len -= 30) {
        float f = (float)i * 30 / sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        float o[3] = {start[0] + d[0] * f, start[1] + d[1] * f, start[2] + d[2] * f};
        float ang[3] = {pitch, yaw, (float)rnd(seed, i, 0, 255) * 360.0f / 256};
        ew_scene_add_entity(c->scene, model, o, ang, 0, 0);
    }
}

static void draw_effect(ew_demo_client *c, const ew_demo_state *st, const effect *f, double t) {
    double a = t - f->t0;
    if (a < 0) return;
    const ew_demo_event *ev = &f->ev;
    ew_scene *s = c->scene;
    static const float zero[3] = {0, 0, 0};
    switch (ev->type) {
    case EW_TE_EXPLOSION:
    case EW_TE_EXPLOSION2:
        explosion(s, ev->start, a, f->seed, ev->type == EW_TE_EXPLOSION ? 1024 : 512, ev->color,
                  ev->type == EW_TE_EXPLOSION2 ? (ev->count ? ev->count : 1) : 0);
        if (a < 0.5) ew_scene_add_dlight(s, ev->start, (float)(350 - 300 * a));
        break;
    case EW_TE_TAREXPLOSION:
        for (int i = 0; i < 1024; i++) {
            double life = 1 + (rnd(f->seed, i, 0, 8) & 7) * 0.05;
            if (a > life) continue;
            float v[3] = {sfrand(f->seed, i, 1) * 256, sfrand(f->seed, i, 2) * 256, sfrand(f->seed, i, 3) * 256};
            float k = (float)(1 - exp(-a));
            int color = (i & 1) ? 66 + rnd(f->seed, i, 4, 7) % 6 : 150 + rnd(f->seed, i, 4, 7) % 6;
            particle(s, ev->start[0] + v[0] * k, ev->start[1] + v[1] * k,
                     ev->start[2] + v[2] * k - 0.5f * GRAV * (float)(a * a), color);
        }
        break;
    case EW_TE_GUNSHOT: burst(s, ev->start, zero, 20, 0, a, f->seed); break;
    case EW_TE_SPIKE: burst(s, ev->start, zero, 10, 0, a, f->seed); break;
    case EW_TE_SUPERSPIKE: burst(s, ev->start, zero, 20, 0, a, f->seed); break;
    case EW_TE_WIZSPIKE: burst(s, ev->start, zero, 30, 20, a, f->seed); break;
    case EW_TE_KNIGHTSPIKE: burst(s, ev->start, zero, 20, 226, a, f->seed); break;
    case EW_DEMO_EV_PARTICLES: burst(s, ev->start, ev->dir, ev->count, ev->color, a, f->seed); break;
    case EW_TE_LAVASPLASH:
        for (int i = -16, n = 0; i < 16; i++)
            for (int j = -16; j < 16; j++, n++) {
                double life = 2 + rnd(f->seed, n, 0, 31) * 0.02;
                if (a > life) continue;
                float dx = (float)(j * 8 + rnd(f->seed, n, 1, 7)), dy = (float)(i * 8 + rnd(f->seed, n, 2, 7));
                float dz = 256;
                float l = sqrtf(dx * dx + dy * dy + dz * dz);
                float vel = (float)(50 + rnd(f->seed, n, 3, 63));
                float k = vel * (float)a / l;
                particle(s, ev->start[0] + dx + dx * k, ev->start[1] + dy + dy * k,
                         ev->start[2] + (float)rnd(f->seed, n, 4, 63) + dz * k - 0.5f * GRAV * (float)(a * a),
                         224 + rnd(f->seed, n, 5, 7));
            }
        break;
    case EW_TE_TELEPORT:
        for (int i = -16, n = 0; i < 16; i += 4)
            for (int j = -16; j < 16; j += 4)
                for (int k = -24; k < 32; k += 4, n++) {
                    double life = 0.2 + rnd(f->seed, n, 0, 7) * 0.02;
                    if (a > life) continue;
                    float dx = (float)(j * 8), dy = (float)(i * 8), dz = (float)(k * 8);
                    float l = sqrtf(dx * dx + dy * dy + dz * dz);
                    float vel = (float)(50 + rnd(f->seed, n, 1, 63));
                    float m = l > 0 ? vel * (float)a / l : 0;
                    particle(s, ev->start[0] + (float)(i + rnd(f->seed, n, 2, 3)) + dx * m,
                             ev->start[1] + (float)(j + rnd(f->seed, n, 3, 3)) + dy * m,
                             ev->start[2] + (float)(k + rnd(f->seed, n, 4, 3)) + dz * m - 0.5f * GRAV * (float)(a * a),
                             7 + rnd(f->seed, n, 5, 7));
                }
        break;
    case EW_TE_LIGHTNING1: case EW_TE_LIGHTNING2: case EW_TE_LIGHTNING3: case EW_TE_BEAM: {
        if (a > BEAM_LIFE) break;
        int kind = ev->type == EW_TE_LIGHTNING1 ? BEAM_BOLT : ev->type == EW_TE_LIGHTNING2 ? BEAM_BOLT2
                 : ev->type == EW_TE_LIGHTNING3 ? BEAM_BOLT3 : BEAM_BEAM;
        float start[3] = {ev->start[0], ev->start[1], ev->start[2]};
        /* the player's own beam leaves from where the player is now */
        if (ev->entity == st->view_entity && ev->entity > 0 && ev->entity < st->nentities)
            memcpy(start, st->entities[ev->entity].origin, sizeof start);
        beam(c, c->beam[kind], start, ev->end, mix(f->seed, (uint32_t)(t * 20)));
        break;
    }
    default: break;
    }
}

/* Trail particles along where entity i has been (R_RocketTrail's kinds). */
static void draw_trail(ew_demo_client *c, const trail *tr, const float now[3], double t, uint32_t seed) {
    ew_scene *s = c->scene;
    double life = (tr->kind & (MF_ROCKET | MF_GRENADE)) ? 1.2 : (tr->kind & (MF_GIB | MF_ZOMGIB)) ? 2.0 : 0.5;
    int n = 0;
    for (int k = tr->n - 1; k >= 0; k--) {
        int i0 = (tr->head - k + TRAIL_POINTS) % TRAIL_POINTS;
        int i1 = k ? (i0 + 1) % TRAIL_POINTS : -1;
        const float *a = tr->org[i0], *b = i1 >= 0 ? tr->org[i1] : now;
        double ta = tr->t[i0], tb = i1 >= 0 ? tr->t[i1] : t;
        if (tb < t - life || ta > t) continue;
        float d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (!(len < 1000)) continue;
        for (float x = 0; x < len; x += 3, n++) {
            float f = x / len;
            double born = ta + (tb - ta) * f, age = t - born;
            if (age < 0 || age > life) continue;
            float p[3] = {a[0] + d[0] * f, a[1] + d[1] * f, a[2] + d[2] * f};
            int color;
            if (tr->kind & MF_ROCKET) {
                double ramp = rnd(seed, n, 0, 3) + age * 5;
                if (ramp >= 6) continue;
                color = ramp3[(int)ramp];
                p[2] += (float)(age * 20);  /* fire rises */
            } else if (tr->kind & MF_GRENADE) {
                double ramp = rnd(seed, n, 0, 3) + 2 + age * 5;
                if (ramp >= 6) continue;
                color = ramp3[(int)ramp];
                p[2] += (float)(age * 20);
            } else if (tr->kind & (MF_GIB | MF_ZOMGIB)) {
                color = 67 + rnd(seed, n, 0, 3);
                p[2] -= 0.5f * GRAV * (float)(age * age);
            } else if (tr->kind & MF_TRACER) {
                color = 52 + ((n & 4) << 1);
            } else if (tr->kind & MF_TRACER2) {
                color = 230 + ((n & 4) << 1);
            } else {
                color = 9 * 16 + 8 + rnd(seed, n, 0, 3);
            }
            for (int j = 0; j < 3; j++) p[j] += sfrand(seed, n, 1 + j) * 3;
            ew_scene_add_particle(s, p, color);
        }
    }
}

int ew_demo_client_frame(ew_demo_client *c, double t, ew_camera *cam) {
    const ew_demo_state *st = ew_demo_get_state(c->d);
    if (!st->protocol) return -1;
    double t1 = st->time, t0 = st->prev_time < t1 ? st->prev_time : t1;
    if (t1 - t0 > 0.1) t0 = t1 - 0.1;
    if (!(t <= t1)) t = t1;  /* NaN too */
    if (t < t0) t = t0;
    float frac = t1 > t0 ? (float)((t - t0) / (t1 - t0)) : 1.0f;
    ew_scene *s = c->scene;
    ew_scene_clear(s);

    for (int i = 0; i < st->nstatics; i++) {
        const ew_demo_baseline *b = &st->statics[i];
        if (b->model <= 0 || b->model > st->nmodels) continue;
        int m = c->model_of[b->model];
        if (m <= -2) ew_scene_add_brush(s, -2 - m, b->origin, b->angles);
        else if (m >= 0) ew_scene_add_entity(s, m, b->origin, b->angles, b->frame, b->skin);
    }
    for (int i = 1; i < st->nentities; i++) {
        const ew_demo_entity *e = &st->entities[i];
        if (e->msgtime != st->time || e->model <= 0 || e->model > st->nmodels) continue;
        float org[3], ang[3];
        for (int k = 0; k < 3; k++) {
            org[k] = e->prev_origin[k] + (e->origin[k] - e->prev_origin[k]) * frac;
            ang[k] = lerp_angle(e->prev_angles[k], e->angles[k], frac);
        }
        int flags = c->flags_of[e->model];
        /* lights the entity carries */
        if (e->effects & EF_MUZZLEFLASH) {
            float fwd[3], p[3];
            angle_vectors(e->angles, fwd);
            for (int k = 0; k < 3; k++) p[k] = org[k] + fwd[k] * 18;
            p[2] += 16;
            ew_scene_add_dlight(s, p, 200.0f + (float)rnd(c->seed, i, (int)st->block & 7, 31));
        }
        if (e->effects & EF_BRIGHTLIGHT) {
            float p[3] = {org[0], org[1], org[2] + 16};
            ew_scene_add_dlight(s, p, 400.0f + (float)rnd(c->seed, i, 1, 31));
        }
        if (e->effects & EF_DIMLIGHT) ew_scene_add_dlight(s, org, 200.0f + (float)rnd(c->seed, i, 2, 31));
        if (flags & MF_ROCKET) ew_scene_add_dlight(s, org, 200);
        if ((flags & MF_TRAILS) && i < c->ntrails && c->trails[i].n) draw_trail(c, &c->trails[i], org, t, mix(c->seed, (uint32_t)i));
        if (i == st->view_entity) continue;  /* the player's own body is not drawn */
        if (flags & MF_ROTATE) ang[1] = (float)fmod(t * 100, 360);
        int m = c->model_of[e->model];
        int ent = -1;
        if (m <= -2) ent = ew_scene_add_brush(s, -2 - m, org, ang);
        else if (m >= 0) ent = ew_scene_add_entity(s, m, org, ang, e->frame, e->skin);
        if (ent >= 0 && m <= -2 && e->alpha < 1 && e->alpha > 0) ew_scene_set_alpha(s, ent, e->alpha);
    }
    for (int i = 0; i < c->neffects; i++) draw_effect(c, st, &c->effects[i], t);

    /* the camera */
    memset(cam, 0, sizeof *cam);
    cam->fov = 90, cam->time = t;
    int ve = st->view_entity;
    if (ve > 0 && ve < st->nentities) {
        const ew_demo_entity *e = &st->entities[ve];
        for (int k = 0; k < 3; k++) {
            cam->origin[k] = e->prev_origin[k] + (e->origin[k] - e->prev_origin[k]) * frac;
            cam->angles[k] = st->intermission ? lerp_angle(e->prev_angles[k], e->angles[k], frac)
                                              : lerp_angle(st->prev_view_angles[k], st->view_angles[k], frac);
        }
    }
    if (!st->intermission) {
        cam->origin[2] += (float)st->view_height;
        /* the weapon, in front of the view */
        int wm = st->weapon_model;
        if (wm > 0 && wm <= st->nmodels && c->model_of[wm] >= 0 && st->weapon_alpha > 0) {
            float ang[3] = {-cam->angles[0], cam->angles[1], cam->angles[2]};
            ew_scene_add_entity(s, c->model_of[wm], cam->origin, ang, st->weapon_frame, 0);
        }
    }
    return 0;
}
