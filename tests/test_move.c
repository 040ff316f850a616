/* Movement and collision (world/move.c) on real maps: gravity lands the
 * player on the floor, walls stop it, stairs are climbed, fly mode passes
 * walls, the same inputs give the same path, bad input and corrupt clip
 * hulls are survived. */
#include "ew_world.h"
#include "util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define DT (1.0 / 60.0)
#define EPS (1.0f / 32.0f)
#define RANGE 640.0f

static ew_move_input still(void) {
    ew_move_input in;
    memset(&in, 0, sizeof in);
    return in;
}

static void run(const ew_world *w, ew_player *p, const ew_move_input *in, double seconds) {
    for (int i = 0; i < (int)(seconds * 60 + 0.5); i++) ew_player_move(w, p, in, DT);
}

/* The player at view v's start, settled on its floor. */
static ew_player settled(const ew_world *w, const ew_camera *v) {
    ew_player p;
    ew_player_set_eye(&p, v->origin, EW_MOVE_WALK);
    ew_move_input in = still();
    run(w, &p, &in, 2);
    return p;
}

static void dir_of(float yaw, float d[3]) {
    d[0] = cosf(yaw * 0.017453293f);
    d[1] = sinf(yaw * 0.017453293f);
    d[2] = 0;
}

/* (a) from above its floor, the player falls and rests with its origin 24
 * over the floor (the box's mins), the floor found by a point trace down. */
static void test_gravity(const ew_world *w, const char *name, const ew_camera *v) {
    ew_player p;
    ew_player_set_eye(&p, v->origin, EW_MOVE_WALK);
    /* lift it by up to 40 units of free space, so there is a fall */
    float up[3] = {p.origin[0], p.origin[1], p.origin[2] + 40};
    ew_trace_result t;
    CHECK(ew_trace(w, EW_HULL_PLAYER, p.origin, up, &t) == 0 && !t.startsolid, "%s: start in solid", name);
    memcpy(p.origin, t.end, sizeof p.origin);
    float start_z = p.origin[2];
    float down[3] = {p.origin[0], p.origin[1], p.origin[2] - 4096};
    CHECK(ew_trace(w, EW_HULL_POINT, p.origin, down, &t) == 0 && t.fraction < 1 && t.normal[2] > 0.99f,
          "%s: no floor below the start (fraction %g)", name, t.fraction);
    float floor_z = t.end[2] - EPS;  /* a point trace stops 1/32 above the plane */
    ew_trace_result t1;
    ew_trace(w, EW_HULL_PLAYER, p.origin, down, &t1);
    CHECK(fabsf(t1.end[2] - (floor_z + 24 + EPS)) < 0.01f, "%s: hull 1 floor %g, point floor %g", name,
          t1.end[2], floor_z);

    ew_move_input in = still();
    float x0 = p.origin[0], y0 = p.origin[1];
    run(w, &p, &in, 3);
    CHECK(p.on_ground, "%s: not on the ground after 3 s", name);
    CHECK(fabsf(p.origin[2] - (floor_z + 24)) < 0.1f, "%s: settled at z %.3f, floor %.3f + 24", name, p.origin[2],
          floor_z);
    CHECK(p.origin[0] == x0 && p.origin[1] == y0, "%s: drifted to %g %g", name, p.origin[0], p.origin[1]);
    CHECK(p.velocity[0] == 0 && p.velocity[1] == 0 && p.velocity[2] == 0, "%s: still moving", name);
    CHECK(start_z - p.origin[2] > 30, "%s: fell only %g units", name, start_z - p.origin[2]);
    printf("%s: fell from z %.3f to %.3f (floor %.3f + 24)\n", name, start_z, p.origin[2], floor_z);

    /* a jump rises 270^2 / (2 * 800) = 45.6 units and lands again */
    float rest = p.origin[2], top = rest;
    in.jump = 1;
    ew_player_move(w, &p, &in, DT);
    CHECK(!p.on_ground && p.velocity[2] > 250, "%s: jump: velocity %g", name, p.velocity[2]);
    for (int i = 0; i < 120; i++) {  /* jump held: no second jump */
        ew_player_move(w, &p, &in, DT);
        if (p.origin[2] > top) top = p.origin[2];
    }
    CHECK(top - rest > 42 && top - rest < 47, "%s: jump peak %.2f over the floor", name, top - rest);
    CHECK(p.on_ground && fabsf(p.origin[2] - rest) < 0.01f, "%s: after the jump at %.3f (was %.3f)", name,
          p.origin[2], rest);
    printf("%s: jump peak %.2f units\n", name, top - rest);
}

/* (b) walking into a wall for seconds never passes it; at an angle the
 * player slides along it.  (d) fly mode goes through it. */
static void test_wall(const ew_world *w, const char *name, const ew_camera *v) {
    ew_player p0 = settled(w, v);
    /* the first direction with a wall face-on within 100..800 units */
    float d[3], yaw = -1, dist = 0;
    ew_trace_result t;
    for (int a = 0; a < 360 && yaw < 0; a += 15) {
        dir_of((float)a, d);
        float end[3];
        for (int k = 0; k < 3; k++) end[k] = p0.origin[k] + 1000 * d[k];
        ew_trace(w, EW_HULL_PLAYER, p0.origin, end, &t);
        float face = t.normal[0] * d[0] + t.normal[1] * d[1] + t.normal[2] * d[2];
        if (t.fraction < 1 && face < -0.99f && t.fraction * 1000 > 100 && t.fraction * 1000 < 800)
            yaw = (float)a, dist = t.fraction * 1000;
    }
    CHECK(yaw >= 0, "%s: no wall ahead in any direction", name);
    if (yaw < 0) return;
    float n[3] = {t.normal[0], t.normal[1], t.normal[2]};
    float plane = n[0] * t.end[0] + n[1] * t.end[1] + n[2] * t.end[2] - EPS;  /* the hull's wall */

    ew_player p = p0;
    ew_move_input in = still();
    in.angles[1] = yaw;
    in.forward = 1;
    in.run = 1;
    float worst = 1e9f;
    for (int i = 0; i < 4 * 60; i++) {
        ew_player_move(w, &p, &in, DT);
        float side = n[0] * p.origin[0] + n[1] * p.origin[1] + n[2] * p.origin[2] - plane;
        if (side < worst) worst = side;
    }
    CHECK(worst >= 0, "%s: passed the wall by %g units", name, -worst);
    float side = n[0] * p.origin[0] + n[1] * p.origin[1] + n[2] * p.origin[2] - plane;
    CHECK(side < 0.5f, "%s: stopped %g units short of the wall", name, side);
    /* the visible wall is the box's half width away */
    float far[3];
    for (int k = 0; k < 3; k++) far[k] = p.origin[k] + 64 * d[k];
    ew_trace_result tp;
    ew_trace(w, EW_HULL_POINT, p.origin, far, &tp);
    CHECK(tp.fraction < 1 && fabsf(tp.fraction * 64 - 16) < 0.1f, "%s: eye-level wall %g units away (want 16)",
          name, tp.fraction * 64);
    printf("%s: walked %.1f units at yaw %.0f into a wall: stopped %.3f from its hull plane, %.3f from the face\n",
           name, dist, yaw, side, tp.fraction * 64);

    /* at 30 degrees to the wall's normal: slides along it */
    ew_player s = p;
    in.angles[1] = yaw + 30;
    float before[3];
    memcpy(before, s.origin, sizeof before);
    worst = 1e9f;
    for (int i = 0; i < 30; i++) {
        ew_player_move(w, &s, &in, DT);
        float sd = n[0] * s.origin[0] + n[1] * s.origin[1] + n[2] * s.origin[2] - plane;
        if (sd < worst) worst = sd;
    }
    float moved = hypotf(s.origin[0] - before[0], s.origin[1] - before[1]);
    CHECK(worst >= 0 && moved > 20, "%s: slide: %g units along, %g past the wall", name, moved, -worst);
    printf("%s: slid %.1f units along the wall in 0.5 s\n", name, moved);

    /* (d) fly: straight through, exactly speed x time */
    ew_player f = p;
    f.mode = EW_MOVE_FLY;
    in.angles[1] = yaw;
    in.speed = 100;
    in.run = 0;
    float o[3];
    memcpy(o, f.origin, sizeof o);
    run(w, &f, &in, 1);
    float gone = (f.origin[0] - o[0]) * d[0] + (f.origin[1] - o[1]) * d[1];
    CHECK(fabsf(gone - 100) < 0.01f && fabsf(f.origin[2] - o[2]) < 1e-3f, "%s: fly went %g (want 100)", name, gone);
    side = n[0] * f.origin[0] + n[1] * f.origin[1] + n[2] * f.origin[2] - plane;
    CHECK(side < -80, "%s: fly did not pass the wall (%g)", name, side);
    /* looking 90 degrees down, forward is down */
    in.angles[0] = 90;
    memcpy(o, f.origin, sizeof o);
    run(w, &f, &in, 0.5);
    CHECK(fabsf(f.origin[2] - (o[2] - 50)) < 0.01f && fabsf(f.origin[0] - o[0]) < 0.01f,
          "%s: fly down: %g %g", name, f.origin[0] - o[0], f.origin[2] - o[2]);
}

/* (c) a step of at most 18 units ahead of a view: walking into it climbs it. */
static int test_stairs(const ew_world *w, const char *name, const ew_camera *v) {
    ew_player p0 = settled(w, v);
    int climbed = 0;
    for (int a = 0; a < 360; a += 15) {
        float d[3], end[3], s2[3], e2[3];
        dir_of((float)a, d);
        ew_trace_result low, high;
        for (int k = 0; k < 3; k++) end[k] = p0.origin[k] + RANGE * d[k];
        ew_trace(w, EW_HULL_PLAYER, p0.origin, end, &low);
        if (low.fraction >= 1 || fabsf(low.normal[2]) > 0.01f || low.fraction * RANGE < 32) continue;
        for (int k = 0; k < 3; k++) s2[k] = p0.origin[k] + (k == 2 ? 18 : 0), e2[k] = s2[k] + RANGE * d[k];
        ew_trace(w, EW_HULL_PLAYER, s2, e2, &high);
        if (high.startsolid || high.fraction * RANGE < low.fraction * RANGE + 24) continue;
        /* level floor from here to the riser (a step down first is another test) */
        int level = 1;
        for (float s = 8; s < low.fraction * RANGE && level; s += 8) {
            float at[3], dn[3];
            ew_trace_result fl;
            for (int k = 0; k < 3; k++) at[k] = p0.origin[k] + s * d[k];
            memcpy(dn, at, sizeof dn);
            dn[2] -= 2;
            ew_trace(w, EW_HULL_PLAYER, at, dn, &fl);
            level = fl.fraction < 0.1f;
        }
        if (!level) continue;
        /* the step's top: down from just past the riser */
        float over[3], below[3];
        for (int k = 0; k < 3; k++) over[k] = s2[k] + (low.fraction * RANGE + 8) * d[k];
        memcpy(below, over, sizeof below);
        below[2] -= 18;
        ew_trace_result top;
        ew_trace(w, EW_HULL_PLAYER, over, below, &top);
        if (top.fraction >= 1 || top.normal[2] < 0.99f) continue;
        float step = top.end[2] - p0.origin[2];
        if (step < 2) continue;

        ew_player p = p0;
        ew_move_input in = still();
        in.angles[1] = (float)a;
        in.forward = 1;
        float max_rise = 0, z = p.origin[2];
        int i;
        for (i = 0; i < 240; i++) {
            ew_player_move(w, &p, &in, DT);
            if (p.origin[2] - z > max_rise) max_rise = p.origin[2] - z;
            z = p.origin[2];
            float along = (p.origin[0] - p0.origin[0]) * d[0] + (p.origin[1] - p0.origin[1]) * d[1];
            if (along > low.fraction * RANGE + 24) break;
        }
        float along = (p.origin[0] - p0.origin[0]) * d[0] + (p.origin[1] - p0.origin[1]) * d[1];
        CHECK(along > low.fraction * RANGE + 24, "%s yaw %d: stuck at the step (%g of %g units)", name, a, along,
              low.fraction * RANGE);
        CHECK(p.origin[2] - p0.origin[2] >= step - 0.05f && p.on_ground,
              "%s yaw %d: rose %g for a %g step", name, a, p.origin[2] - p0.origin[2], step);
        CHECK(max_rise <= 2 * 18 + 0.1f, "%s yaw %d: rose %g in one frame", name, a, max_rise);
        printf("%s: step of %.3f units %.1f ahead at yaw %d climbed: z %.3f -> %.3f in %.2f s\n", name, step,
               low.fraction * RANGE, a, p0.origin[2], p.origin[2], (i + 1) * DT);
        climbed++;
    }
    return climbed;
}

/* (e) the same inputs, the same path, bit for bit. */
static void test_determinism(const ew_world *w, const ew_camera *v) {
    ew_player a[2];
    for (int r = 0; r < 2; r++) {
        ew_player_set_eye(&a[r], v->origin, EW_MOVE_WALK);
        for (int i = 0; i < 300; i++) {
            ew_move_input in = still();
            in.angles[1] = (float)(i * 7 % 360);
            in.forward = (i / 40) % 2 ? 1.0f : -0.5f;
            in.right = (i / 25) % 3 - 1.0f;
            in.jump = (i / 50) % 2;
            in.run = (i / 60) % 2;
            double dt = (i % 5 + 1) / 120.0;  /* uneven frames */
            ew_player_move(w, &a[r], &in, dt);
        }
    }
    CHECK(!memcmp(a[0].origin, a[1].origin, sizeof a[0].origin) &&
              !memcmp(a[0].velocity, a[1].velocity, sizeof a[0].velocity),
          "two runs differ: %g %g %g / %g %g %g", a[0].origin[0], a[0].origin[1], a[0].origin[2], a[1].origin[0],
          a[1].origin[1], a[1].origin[2]);
    CHECK(ew_point_contents(w, EW_HULL_PLAYER, a[0].origin) != EW_CONTENTS_SOLID, "the path ended in solid");
    printf("determinism: after 300 uneven frames at %.3f %.3f %.3f in both runs\n", a[0].origin[0], a[0].origin[1],
           a[0].origin[2]);
}

/* (f) bad input: nothing NaN comes out, nothing crashes. */
static void test_bad_input(const ew_world *w, const ew_camera *v) {
    ew_player p = settled(w, v), q;
    ew_move_input in = still();
    q = p;
    ew_player_move(w, &q, &in, NAN);
    ew_player_move(w, &q, &in, -1);
    ew_player_move(w, &q, &in, 0);
    CHECK(!memcmp(&q, &p, sizeof q), "NaN / negative / zero dt moved the player");
    q.velocity[0] = NAN;
    q.velocity[2] = INFINITY;
    ew_player_move(w, &q, &in, DT);
    CHECK(isfinite(q.origin[0]) && isfinite(q.origin[2]) && q.velocity[0] == 0 && isfinite(q.velocity[2]),
          "NaN velocity: %g %g", q.origin[0], q.velocity[0]);
    in.forward = NAN;
    in.angles[1] = INFINITY;
    in.speed = NAN;
    ew_player_move(w, &q, &in, DT);
    CHECK(isfinite(q.origin[0]) && isfinite(q.origin[1]), "NaN input gave %g %g", q.origin[0], q.origin[1]);
    /* a huge dt is one second at most */
    in = still();
    in.forward = 1;
    in.run = 1;
    q = p;
    ew_player_move(w, &q, &in, 1e30);
    float moved = hypotf(q.origin[0] - p.origin[0], q.origin[1] - p.origin[1]);
    CHECK(moved <= EW_MOVE_MAX_SPEED + 1 && isfinite(q.origin[2]), "1e30 s moved %g units", moved);
    q.mode = EW_MOVE_FLY;
    ew_player_move(w, &q, &in, INFINITY);
    CHECK(isfinite(q.origin[0]), "infinite dt in fly mode: %g", q.origin[0]);
    q.origin[1] = NAN;
    ew_player_move(w, &q, &in, DT);
    CHECK(q.velocity[0] == 0 && q.velocity[1] == 0, "NaN origin kept moving");
    q.origin[1] = 1e30f;
    q.mode = EW_MOVE_WALK;
    ew_player_move(w, &q, &in, DT);
    CHECK(q.origin[1] == 1e30f, "far origin moved");
    /* no input at all, no world */
    q = p;
    ew_player_move(w, &q, NULL, DT);
    ew_player_move(NULL, &q, &in, DT);  /* no world: walks as it flies */
    CHECK(isfinite(q.origin[0]), "NULL world");
    ew_player_move(w, NULL, &in, DT);

    ew_trace_result t;
    float a[3] = {0, 0, 0}, b[3] = {NAN, 0, 0};
    CHECK(ew_trace(w, EW_HULL_PLAYER, a, b, &t) == -1 && t.fraction == 1, "NaN end traced");
    CHECK(ew_trace(w, 3, a, a, &t) == -1 && ew_trace(w, -1, a, a, &t) == -1, "hull 3 traced");
    CHECK(ew_trace(NULL, 1, a, a, &t) == -1, "NULL world traced");
    CHECK(ew_point_contents(w, 7, a) == EW_CONTENTS_EMPTY, "hull 7 contents");
}

/* Patched copies of a map's clip hulls: a cycle, a child out of range, a
 * plane out of range, a bad head: the map loads (it renders without them)
 * with one warning, and nothing collides. */
static void test_corrupt(const char *name) {
    char rel[128];
    snprintf(rel, sizeof rel, "data/librequake/maps/%s.bsp", name);
    uint8_t *data;
    size_t size;
    ew_error err;
    if (ew_read_file(ew_t_shared(rel), &data, &size, &err)) {
        CHECK(0, "%s", err.msg);
        return;
    }
    CHECK(data[0] == 29, "%s is not BSP29", name);
    uint32_t cofs = (uint32_t)data[4 + 9 * 8] | (uint32_t)data[5 + 9 * 8] << 8 | (uint32_t)data[6 + 9 * 8] << 16 |
                    (uint32_t)data[7 + 9 * 8] << 24;
    uint32_t mofs = (uint32_t)data[4 + 14 * 8] | (uint32_t)data[5 + 14 * 8] << 8 | (uint32_t)data[6 + 14 * 8] << 16 |
                    (uint32_t)data[7 + 14 * 8] << 24;
    struct {
        const char *what, *want;
        size_t at;
        uint8_t bytes[4];
        int n;
    } cases[] = {
        {"self loop", "cycle", cofs + 8 * 5 + 4, {5, 0}, 2},     /* clipnode 5's front child: itself */
        {"child range", "child", cofs + 8 * 3 + 6, {0x00, 0x7f}, 2},  /* 32512 */
        {"plane range", "plane", cofs + 8 * 7, {0xff, 0xff, 0xff, 0x7f}, 4},
        {"contents", "child", cofs + 8 * 2 + 4, {0xe0, 0xff}, 2},    /* contents -32 */
        {"head", "head", mofs + 40, {0xff, 0xff, 0x00, 0x00}, 4},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        uint8_t *copy = malloc(size);
        memcpy(copy, data, size);
        memcpy(copy + cases[c].at, cases[c].bytes, (size_t)cases[c].n);
        ew_world *w = ew_world_create(copy, size, rel, &err);
        CHECK(w != NULL, "%s: %s refused: %s", name, cases[c].what, err.msg);
        if (w) {
            const char *msg = ew_world_warning(w, 0);
            CHECK(msg && strstr(msg, cases[c].want) && strstr(msg, "no collision") && !ew_world_warning(w, 1),
                  "%s: %s: warning %s", name, cases[c].what, msg ? msg : "none");
            if (c == 0 && msg) printf("corrupt clip hull: %s\n", msg);
            ew_trace_result t;
            float a[3] = {0, 0, 0}, b[3] = {100, 0, 0};
            CHECK(!w->clip_ok && ew_trace(w, EW_HULL_PLAYER, a, b, &t) == -1 && t.fraction == 1,
                  "%s: %s: still traced", name, cases[c].what);
            CHECK(ew_trace(w, EW_HULL_POINT, a, b, &t) == 0, "%s: %s: hull 0 lost", name, cases[c].what);
            ew_player p;
            ew_player_set_eye(&p, a, EW_MOVE_WALK);
            ew_move_input in = still();
            in.forward = 1;
            ew_player_move(w, &p, &in, 0.5);
            CHECK(fabsf(p.origin[0] - 100) < 0.01f, "%s: %s: walk without a hull moved %g", name, cases[c].what,
                  p.origin[0]);
            ew_world_destroy(w);
        }
        free(copy);
    }
    /* a shared subtree (both children of clipnode 0 the same) is no cycle */
    uint8_t *copy = malloc(size);
    memcpy(copy, data, size);
    memcpy(copy + cofs + 6, copy + cofs + 4, 2);
    ew_world *w = ew_world_create(copy, size, rel, &err);
    CHECK(w && w->clip_ok && !ew_world_warning(w, 0), "%s: shared subtree refused", name);
    ew_world_destroy(w);
    free(copy);
    free(data);
}

/* The point-hull floor under (x, y) from z, and the first wall from p
 * along yaw (point traces: the map's faces themselves). */
static float floor_under(const ew_world *w, float x, float y, float z) {
    float a[3] = {x, y, z}, b[3] = {x, y, z - 1000};
    ew_trace_result t;
    ew_trace(w, EW_HULL_POINT, a, b, &t);
    return t.fraction < 1 ? t.end[2] - EPS : -1e9f;
}

/* The built-in map's own player hulls (src/mapgen/clip_hull.c: the level's
 * solid boxes grown by the hull's box): dropped over the courtyard floor
 * the player rests 24 over it; walking into the hall's east wall it stops
 * 16 from it (hull 2: 32); walking north up the hall's wooden stairs it
 * climbs their three 16-unit steps into the stone room. */
static void test_builtin(void) {
    ew_error err = {""};
    ew_assets *a = ew_assets_create_builtin(&err);
    CHECK(a != NULL, "builtin: %s", err.msg);
    if (!a) return;
    const ew_world *w = a->world;
    CHECK(w->clip_ok && !ew_world_warning(w, 0), "builtin: clip hulls refused");
    CHECK(w->models[0].cliphead[0] > 0 && w->models[0].cliphead[1] > w->models[0].cliphead[0],
          "builtin: hull heads %d %d", w->models[0].cliphead[0], w->models[0].cliphead[1]);
    printf("builtin: %d clipnodes, hull 1 at %d, hull 2 at %d\n", w->numclipnodes, w->models[0].cliphead[0],
           w->models[0].cliphead[1]);

    /* gravity: from 150 over the courtyard (the player start's x, y) */
    float fz = floor_under(w, 230, 290, 150);
    CHECK(fabsf(fz - 64) < 0.01f, "builtin: courtyard floor at %g (the grid says 64)", fz);
    ew_player p;
    float eye[3] = {230, 290, 150 + EW_EYE_HEIGHT};
    ew_player_set_eye(&p, eye, EW_MOVE_WALK);
    ew_move_input in = still();
    run(w, &p, &in, 2);
    CHECK(p.on_ground && fabsf(p.origin[2] - (fz + 24)) < 0.05f, "builtin: landed at z %.3f, floor %.3f + 24",
          p.origin[2], fz);
    CHECK(p.origin[0] == 230 && p.origin[1] == 290, "builtin: drifted to %g %g", p.origin[0], p.origin[1]);
    printf("builtin: dropped from z 150, landed at z %.3f (floor %.3f + 24)\n", p.origin[2], fz);
    ew_trace_result t;
    float from[3] = {230, 290, 150}, to[3] = {230, 290, 0};
    ew_trace(w, EW_HULL_LARGE, from, to, &t);
    CHECK(fabsf(t.end[2] - (fz + 24)) < 0.05f, "builtin: hull 2 rests at %g", t.end[2]);

    /* a wall: the hall's east wall, walking east from (800, 100) */
    float hz = floor_under(w, 800, 100, 150), wall;
    {
        float s[3] = {800, 100, hz + 24}, e[3] = {1800, 100, hz + 24};
        ew_trace(w, EW_HULL_POINT, s, e, &t);
        wall = t.end[0] + EPS;
        CHECK(t.fraction < 1 && fabsf(wall - 896) < 0.01f && t.normal[0] < -0.99f, "builtin: hall wall at %g", wall);
        ew_trace(w, EW_HULL_LARGE, s, e, &t);
        CHECK(fabsf(t.end[0] - (wall - 32)) < 0.05f, "builtin: hull 2 stops at %g (wall %g - 32)", t.end[0], wall);
    }
    eye[0] = 800, eye[1] = 100, eye[2] = hz + 24 + EW_EYE_HEIGHT;
    ew_player_set_eye(&p, eye, EW_MOVE_WALK);
    in.angles[1] = 0;
    in.forward = 1;
    in.run = 1;
    float most = 0;
    for (int i = 0; i < 3 * 60; i++) {
        ew_player_move(w, &p, &in, DT);
        if (p.origin[0] > most) most = p.origin[0];
    }
    CHECK(most <= wall - 16 && fabsf(p.origin[0] - (wall - 16)) < 0.05f && fabsf(p.origin[2] - (hz + 24)) < 0.05f,
          "builtin: walked east to x %.3f (furthest %.3f), wall at %.3f", p.origin[0], most, wall);
    printf("builtin: walked into the hall's east wall (x %.3f): stopped at x %.3f, %.3f from it\n", wall,
           p.origin[0], wall - p.origin[0]);

    /* stairs: north from (736, 300) up the three steps into the stone room */
    float tops[4] = {hz, floor_under(w, 736, 400, 150), floor_under(w, 736, 432, 150),
                   floor_under(w, 736, 500, 150)};
    CHECK(fabsf(tops[1] - tops[0] - 16) < 0.01f && fabsf(tops[2] - tops[1] - 16) < 0.01f &&
              fabsf(tops[3] - tops[2] - 16) < 0.01f,
          "builtin: stair tops %g %g %g %g", tops[0], tops[1], tops[2], tops[3]);
    eye[0] = 736, eye[1] = 300, eye[2] = hz + 24 + EW_EYE_HEIGHT;
    ew_player_set_eye(&p, eye, EW_MOVE_WALK);
    in = still();
    in.angles[1] = 90;
    in.forward = 1;
    int stood[4] = {0, 0, 0, 0};
    for (int i = 0; i < 180 && p.origin[1] < 512; i++) {  /* (a dais further on) */
        ew_player_move(w, &p, &in, DT);
        for (int k = 0; k < 4; k++)
            if (p.on_ground && fabsf(p.origin[2] - (tops[k] + 24)) < 0.05f) stood[k]++;
    }
    CHECK(stood[0] && stood[1] && stood[2] && stood[3], "builtin: stood on the levels %d %d %d %d", stood[0],
          stood[1], stood[2], stood[3]);
    CHECK(p.origin[1] > 480 + 16 && fabsf(p.origin[2] - (tops[3] + 24)) < 0.05f && fabsf(p.origin[0] - 736) < 0.01f,
          "builtin: after the stairs at %g %g %g", p.origin[0], p.origin[1], p.origin[2]);
    printf("builtin: climbed steps %.0f -> %.0f -> %.0f -> %.0f: at y %.3f, z %.3f (room floor %.3f + 24)\n",
           tops[0], tops[1], tops[2], tops[3], p.origin[1], p.origin[2], tops[3]);

    /* the generic gravity and jump check at its start (not test_wall: the
     * courtyard's walls stand on a plinth, a step) */
    ew_camera v[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(w, v);
    CHECK(nv > 0, "builtin: no views");
    if (nv > 0) test_gravity(w, "builtin view 0", &v[0]);
    ew_assets_destroy(a);
}

int main(void) {
    test_builtin();
    ew_assets *e1 = ew_t_load_map("e1m1"), *st = ew_t_load_map("start");
    if (!e1 || !st) {
        ew_assets_destroy(e1);
        ew_assets_destroy(st);
        return ew_t_finish();
    }
    ew_camera ve[EW_MAX_VIEWS], vs[EW_MAX_VIEWS];
    int ne = ew_benchmark_views(e1->world, ve), ns = ew_benchmark_views(st->world, vs);
    CHECK(ne > 28 && ns > 0, "views: e1m1 %d, start %d", ne, ns);
    CHECK(e1->world->clip_ok && st->world->clip_ok && e1->world->numclipnodes > 0, "clip hulls not loaded");
    CHECK(!ew_world_warning(e1->world, 0) && !ew_world_warning(st->world, 0), "warnings on good maps");
    printf("clipnodes: e1m1 %d (hull 1 head %d), start %d\n", e1->world->numclipnodes,
           e1->world->models[0].cliphead[0], st->world->numclipnodes);

    /* the view set's eye is the player's origin + 22 */
    ew_player p;
    ew_player_set_eye(&p, ve[0].origin, EW_MOVE_WALK);
    float eye[3];
    ew_player_eye(&p, eye);
    CHECK(!memcmp(eye, ve[0].origin, sizeof eye) && p.origin[2] == ve[0].origin[2] - 22, "eye offset");

    test_gravity(st->world, "start view 0", &vs[0]);
    test_gravity(e1->world, "e1m1 view 0", &ve[0]);
    test_wall(e1->world, "e1m1 view 0", &ve[0]);
    test_wall(st->world, "start view 0", &vs[0]);
    int found = 0;
    for (int i = 0; i < ne; i += 4) found += test_stairs(e1->world, "e1m1", &ve[i]);
    for (int i = 0; i < ns; i += 4) found += test_stairs(st->world, "start", &vs[i]);
    CHECK(found > 0, "no step found in the views of e1m1 and start");
    printf("%d steps climbed\n", found);
    test_determinism(e1->world, &ve[0]);
    test_bad_input(e1->world, &ve[0]);
    test_corrupt("e1m1");

    ew_assets_destroy(e1);
    ew_assets_destroy(st);
    return ew_t_finish();
}
