/*
 * Movement and collision: box traces through the BSP's clip hulls and a
 * player that walks a map (edgewise.h, "movement and collision").
 *
 * The trace.  A map compiler grows every solid brush by the player's box
 * before building a clip hull, so moving the box is moving one point
 * through that hull's tree.  The segment is followed down the tree: where
 * both ends lie on one side of a node's plane it goes to that child; where
 * it crosses, it is cut at the crossing (pulled 1/32 unit back towards the
 * start, so a stop never lies on a plane), the near piece is followed first,
 * and the far piece only if the point just past the cut is not solid on
 * the far side.  The first solid met is the hit, and its plane, seen from
 * the start, is the normal.  Everything is done in double precision.
 *
 * The mover.  Fixed sub-steps of at most 1/72 s; in each: friction and
 * acceleration (on the ground) or air control and gravity (in the air),
 * then a slide (move, stop at a plane, cut the velocity's component into
 * it, move on with the time that is left, up to four planes), and where the
 * slide was blocked on the ground, the same slide started 18 units higher
 * and dropped back down, kept when it got further (stairs).
 */
#include "ew_util.h"
#include "ew_world.h"

#include <math.h>

#define DIST_EPSILON (1.0 / 32.0)
#define MAX_DEPTH 1024         /* deeper than any real tree; a bound for bad files */
#define MAX_VISITS (1 << 16)   /* nodes one trace may visit (the hulls may share subtrees) */
#define FLOOR_Z 0.7            /* a plane whose normal z is at least this is a floor */
#define MAX_DT 1.0             /* longest dt simulated by one call */
#define MAX_COORD 1.0e6        /* origins beyond this are not moved */
#define MAX_BUMPS 4
#define RISING 180.0          /* rising faster than this (a jump) is not standing */
#define DEG2RAD 0.017453292519943295

/* ---- hulls ---------------------------------------------------------------- */

/* A hull is read through these: node refs >= 0 are nodes (hull 0) or
 * clipnodes (hulls 1, 2); refs < 0 are contents. */
typedef struct hull {
    const ew_world *w;
    int             kind;  /* 0: the rendering tree, 1 or 2: clip hull */
    int             head;
} hull;

static int leaf_contents(const ew_world *w, int leaf) {
    int c = w->leaves[leaf].contents;
    return c < 0 && c >= -15 ? c : EW_CONTENTS_EMPTY;  /* leaf contents are not checked by the loader */
}

static int hull_child(const hull *h, int node, int side) {
    if (h->kind == 0) {
        int ch = h->w->nodes[node].children[side];
        return ch >= 0 ? ch : leaf_contents(h->w, -1 - ch);
    }
    return h->w->clipnodes[node].children[side];
}

static const ew_plane *hull_plane(const hull *h, int node) {
    return &h->w->planes[h->kind == 0 ? h->w->nodes[node].plane : h->w->clipnodes[node].plane];
}

static double plane_dist(const ew_plane *pl, const double p[3]) {
    return pl->normal[0] * p[0] + pl->normal[1] * p[1] + pl->normal[2] * p[2] - pl->dist;
}

/* 0 if the world has the hull, -1 if not. */
static int hull_open(const ew_world *w, int kind, hull *h) {
    if (!w || kind < 0 || kind > 2 || w->nummodels < 1) return -1;
    h->w = w;
    h->kind = kind;
    if (kind == 0) {
        h->head = w->models[0].headnode;
        return 0;
    }
    if (!w->clip_ok) return -1;
    h->head = w->models[0].cliphead[kind - 1];
    return 0;
}

static int contents_from(const hull *h, int node, const double p[3]) {
    for (int steps = 0; node >= 0; steps++) {
        if (steps > MAX_DEPTH) return EW_CONTENTS_SOLID;
        node = hull_child(h, node, plane_dist(hull_plane(h, node), p) < 0);
    }
    return node;
}

/* ---- the trace ------------------------------------------------------------ */

typedef struct trace {
    hull   h;
    int    visits;
    int    aborted;
    int    startsolid, allsolid;
    double frac;
    double end[3], normal[3];
} trace;

static void lerp3(const double a[3], const double b[3], double f, double out[3]) {
    for (int k = 0; k < 3; k++) out[k] = a[k] + f * (b[k] - a[k]);
}

/* Follows the piece p1 (at fraction t1 of the whole move) .. p2 (t2)
 * through the subtree node; 1 when the move ends here (hit or abort). */
static int trace_node(trace *tr, int node, double t1, double t2, const double p1[3], const double p2[3],
                      int depth) {
    if (++tr->visits > MAX_VISITS || depth > MAX_DEPTH) {
        tr->aborted = 1;
        return 1;
    }
    if (node < 0) {
        if (node == EW_CONTENTS_SOLID)
            tr->startsolid = 1;  /* only a piece that starts inside solid gets here */
        else
            tr->allsolid = 0;
        return 0;
    }
    const ew_plane *pl = hull_plane(&tr->h, node);
    double d1 = plane_dist(pl, p1), d2 = plane_dist(pl, p2);
    if (d1 >= 0 && d2 >= 0) return trace_node(tr, hull_child(&tr->h, node, 0), t1, t2, p1, p2, depth + 1);
    if (d1 < 0 && d2 < 0) return trace_node(tr, hull_child(&tr->h, node, 1), t1, t2, p1, p2, depth + 1);

    int near = d1 < 0;  /* the child holding p1 */
    double f = near ? (d1 + DIST_EPSILON) / (d1 - d2) : (d1 - DIST_EPSILON) / (d1 - d2);
    if (f < 0) f = 0;
    if (f > 1) f = 1;
    double mid[3], tm = t1 + (t2 - t1) * f;
    lerp3(p1, p2, f, mid);
    if (trace_node(tr, hull_child(&tr->h, node, near), t1, tm, p1, mid, depth + 1)) return 1;
    int far = hull_child(&tr->h, node, !near);
    if (contents_from(&tr->h, far, mid) != EW_CONTENTS_SOLID)
        return trace_node(tr, far, tm, t2, mid, p2, depth + 1);
    if (tr->allsolid) return 0;  /* never out of solid: no plane to stop at */

    /* The hit.  mid lies on the near side; make sure the whole hull agrees
     * (another plane may pass within the epsilon), backing off towards p1. */
    for (int i = 0; i < 10 && contents_from(&tr->h, tr->h.head, mid) == EW_CONTENTS_SOLID; i++) {
        f -= 0.1;
        if (f < 0) f = 0;
        tm = t1 + (t2 - t1) * f;
        lerp3(p1, p2, f, mid);
    }
    tr->frac = tm;
    for (int k = 0; k < 3; k++) {
        tr->end[k] = mid[k];
        tr->normal[k] = near ? -pl->normal[k] : pl->normal[k];
    }
    return 1;
}

/* The trace in doubles (the mover's own precision). */
static void trace_hull(const hull *h, const double start[3], const double end[3], trace *tr) {
    tr->h = *h;
    tr->visits = tr->aborted = tr->startsolid = 0;
    tr->allsolid = 1;
    tr->frac = 1;
    for (int k = 0; k < 3; k++) tr->end[k] = end[k], tr->normal[k] = 0;
    trace_node(tr, h->head, 0, 1, start, end, 0);
    if (tr->aborted || tr->allsolid) {
        /* an unusable tree blocks rather than lets through */
        tr->allsolid = tr->startsolid = 1;
        tr->frac = 0;
        for (int k = 0; k < 3; k++) tr->end[k] = start[k], tr->normal[k] = 0;
    }
}

static int finite3f(const float v[3]) { return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]); }

int ew_trace(const ew_world *w, int hull_kind, const float start[3], const float end[3], ew_trace_result *r) {
    if (!r) return -1;
    memset(r, 0, sizeof *r);
    r->fraction = 1;
    if (end && finite3f(end))
        for (int k = 0; k < 3; k++) r->end[k] = end[k];
    hull h;
    if (hull_open(w, hull_kind, &h) || !start || !end || !finite3f(start) || !finite3f(end)) return -1;
    double s[3] = {start[0], start[1], start[2]}, e[3] = {end[0], end[1], end[2]};
    trace tr;
    trace_hull(&h, s, e, &tr);
    r->fraction = (float)tr.frac;
    for (int k = 0; k < 3; k++) r->end[k] = (float)tr.end[k], r->normal[k] = (float)tr.normal[k];
    r->startsolid = tr.startsolid;
    r->allsolid = tr.allsolid;
    return 0;
}

int ew_point_contents(const ew_world *w, int hull_kind, const float p[3]) {
    hull h;
    if (hull_open(w, hull_kind, &h) || !p || !finite3f(p)) return EW_CONTENTS_EMPTY;
    double d[3] = {p[0], p[1], p[2]};
    return contents_from(&h, h.head, d);
}

/* ---- the player ------------------------------------------------------------ */

void ew_player_eye(const ew_player *p, float eye[3]) {
    eye[0] = p->origin[0];
    eye[1] = p->origin[1];
    eye[2] = p->origin[2] + EW_EYE_HEIGHT;
}

void ew_player_set_eye(ew_player *p, const float eye[3], ew_move_mode mode) {
    memset(p, 0, sizeof *p);
    p->origin[0] = eye[0];
    p->origin[1] = eye[1];
    p->origin[2] = eye[2] - EW_EYE_HEIGHT;
    p->mode = mode;
}

/* The mover's state in doubles for one call. */
typedef struct mover {
    hull   h;
    double org[3], vel[3];
    int    on_ground;
} mover;

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* Removes the part of v going into the plane n, and a hair more so the
 * next move leaves it rather than grazing it. */
static void clip_velocity(double v[3], const double n[3]) {
    double into = dot3(v, n);
    if (into >= 0) return;
    for (int k = 0; k < 3; k++) {
        v[k] -= n[k] * into * 1.001;
        if (fabs(v[k]) < 1e-6) v[k] = 0;
    }
}

/* Moves org by vel over time h, sliding along what it hits.  Returns the
 * number of planes met; *floor set when one of them was a floor. */
static int slide_move(const hull *hl, double org[3], double vel[3], double h, int *floor) {
    double planes[MAX_BUMPS][3], orig_vel[3];
    int nplanes = 0;
    double left = h;
    *floor = 0;
    for (int k = 0; k < 3; k++) orig_vel[k] = vel[k];
    for (int bump = 0; bump < MAX_BUMPS && left > 0; bump++) {
        double end[3];
        for (int k = 0; k < 3; k++) end[k] = org[k] + vel[k] * left;
        trace tr;
        trace_hull(hl, org, end, &tr);
        if (tr.allsolid) {
            for (int k = 0; k < 3; k++) vel[k] = 0;
            return nplanes;
        }
        if (tr.frac > 0)
            for (int k = 0; k < 3; k++) org[k] = tr.end[k];
        if (tr.frac >= 1) break;
        left *= 1 - tr.frac;
        if (tr.normal[2] >= FLOOR_Z) *floor = 1;
        if (nplanes == MAX_BUMPS) break;
        for (int k = 0; k < 3; k++) planes[nplanes][k] = tr.normal[k];
        nplanes++;

        /* a velocity that leaves every plane met so far: clip by each in
         * turn; if none works alone, follow the crease of two; else stop */
        int ok = 0;
        for (int i = 0; i < nplanes && !ok; i++) {
            double v[3] = {vel[0], vel[1], vel[2]};
            clip_velocity(v, planes[i]);
            ok = 1;
            for (int j = 0; j < nplanes; j++)
                if (j != i && dot3(v, planes[j]) < 0) ok = 0;
            if (ok)
                for (int k = 0; k < 3; k++) vel[k] = v[k];
        }
        if (!ok) {
            if (nplanes != 2) {
                for (int k = 0; k < 3; k++) vel[k] = 0;
                break;
            }
            const double *a = planes[0], *b = planes[1];
            double dir[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
            double len = sqrt(dot3(dir, dir));
            if (len < 1e-9) {
                for (int k = 0; k < 3; k++) vel[k] = 0;
                break;
            }
            double s = dot3(dir, vel) / (len * len);
            for (int k = 0; k < 3; k++) vel[k] = dir[k] * s;
        }
        /* turned back against where it was going: stop (no jitter in corners) */
        if (dot3(vel, orig_vel) <= 0) {
            for (int k = 0; k < 3; k++) vel[k] = 0;
            break;
        }
    }
    return nplanes;
}

/* Standing on a floor: the box 1/4 unit lower hits a floor plane. */
static int ground_check(const hull *hl, const double org[3]) {
    double down[3] = {org[0], org[1], org[2] - 0.25};
    trace tr;
    trace_hull(hl, org, down, &tr);
    return !tr.allsolid && tr.frac < 1 && tr.normal[2] >= FLOOR_Z;
}

/* A player inside solid (a start point in a floor, a moved wall): the
 * nearest free spot within EW_MOVE_STEP, up first.  0 when found. */
static int unstick(const hull *hl, double org[3]) {
    if (contents_from(hl, hl->head, org) != EW_CONTENTS_SOLID) return 0;
    static const int dirs[6][3] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
    for (int d = 1; d <= (int)EW_MOVE_STEP; d++)
        for (int i = 0; i < 6; i++) {
            double p[3];
            for (int k = 0; k < 3; k++) p[k] = org[k] + dirs[i][k] * d;
            if (contents_from(hl, hl->head, p) != EW_CONTENTS_SOLID) {
                for (int k = 0; k < 3; k++) org[k] = p[k];
                return 0;
            }
        }
    return -1;
}

static double hdist2(const double a[3], const double b[3]) {
    return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]);
}

/* The slide, and where it was blocked on the ground, the step: up by
 * EW_MOVE_STEP, the same slide, down again; kept when it went further and
 * ended on a floor (or over one lower than the step). */
static void walk_move(mover *m, double h) {
    double org0[3], vel0[3];
    for (int k = 0; k < 3; k++) org0[k] = m->org[k], vel0[k] = m->vel[k];
    int floor = 0;
    int planes = slide_move(&m->h, m->org, m->vel, h, &floor);
    if (!m->on_ground || planes == 0 || (planes == 1 && floor)) return;

    double sorg[3] = {org0[0], org0[1], org0[2]}, svel[3] = {vel0[0], vel0[1], vel0[2]};
    double up[3] = {sorg[0], sorg[1], sorg[2] + EW_MOVE_STEP};
    trace tr;
    trace_hull(&m->h, sorg, up, &tr);
    if (tr.allsolid) return;
    for (int k = 0; k < 3; k++) sorg[k] = tr.end[k];
    svel[2] = 0;
    int sfloor;
    slide_move(&m->h, sorg, svel, h, &sfloor);
    double down[3] = {sorg[0], sorg[1], sorg[2] - (tr.end[2] - org0[2])};
    trace_hull(&m->h, sorg, down, &tr);
    if (tr.allsolid || (tr.frac < 1 && tr.normal[2] < FLOOR_Z)) return;
    if (hdist2(tr.end, org0) <= hdist2(m->org, org0) + 1e-6) return;
    for (int k = 0; k < 3; k++) m->org[k] = tr.end[k], m->vel[k] = svel[k];
    m->vel[2] = 0;  /* walked up: on the step, not flying off it */
}

static float clampf(float v, float lo, float hi) { return !(v >= lo) ? (v != v ? 0 : lo) : v > hi ? hi : v; }

static void walk_step(mover *m, const ew_move_input *in, double h, int jump_now) {
    m->on_ground = m->vel[2] <= RISING && ground_check(&m->h, m->org);
    if (m->on_ground) m->vel[2] = 0;
    if (jump_now && m->on_ground) {
        m->vel[2] = EW_MOVE_JUMP;
        m->on_ground = 0;
    }

    if (m->on_ground) {  /* friction */
        double speed = sqrt(m->vel[0] * m->vel[0] + m->vel[1] * m->vel[1]);
        if (speed > 0) {
            double drop = (speed < EW_MOVE_STOP_SPEED ? EW_MOVE_STOP_SPEED : speed) * EW_MOVE_FRICTION * h;
            double ns = speed - drop < 0 ? 0 : speed - drop;
            m->vel[0] *= ns / speed;
            m->vel[1] *= ns / speed;
        }
    }

    /* wish: the keys along the yaw, level */
    double yaw = (double)in->angles[1] * DEG2RAD;
    double fwd[2] = {cos(yaw), sin(yaw)}, right[2] = {sin(yaw), -cos(yaw)};
    double wish[3] = {in->forward * fwd[0] + in->right * right[0], in->forward * fwd[1] + in->right * right[1], 0};
    double wlen = sqrt(wish[0] * wish[0] + wish[1] * wish[1]);
    if (wlen > 0) {
        double base = in->speed > 0 ? in->speed : EW_MOVE_SPEED;
        double wishspeed = base * (in->run ? 2 : 1) * wlen;
        if (wishspeed > EW_MOVE_MAX_SPEED) wishspeed = EW_MOVE_MAX_SPEED;
        for (int k = 0; k < 2; k++) wish[k] /= wlen;
        double cap = m->on_ground ? wishspeed : (wishspeed < EW_MOVE_AIR_SPEED ? wishspeed : EW_MOVE_AIR_SPEED);
        double add = cap - dot3(m->vel, wish);
        if (add > 0) {
            double acc = EW_MOVE_ACCEL * wishspeed * h;
            if (acc > add) acc = add;
            for (int k = 0; k < 2; k++) m->vel[k] += acc * wish[k];
        }
    }
    if (!m->on_ground) m->vel[2] -= EW_MOVE_GRAVITY * h;
    for (int k = 0; k < 3; k++) m->vel[k] = clampf((float)m->vel[k], -EW_MOVE_MAX_FALL, EW_MOVE_MAX_FALL);

    walk_move(m, h);
    m->on_ground = m->vel[2] <= RISING && ground_check(&m->h, m->org);
    if (m->on_ground && m->vel[2] < 0) m->vel[2] = 0;
}

void ew_player_move(const ew_world *w, ew_player *p, const ew_move_input *in_raw, double dt) {
    if (!p) return;
    for (int k = 0; k < 3; k++)
        if (!isfinite(p->velocity[k])) p->velocity[k] = 0;
    if (!finite3f(p->origin) || fabsf(p->origin[0]) > MAX_COORD || fabsf(p->origin[1]) > MAX_COORD ||
        fabsf(p->origin[2]) > MAX_COORD) {
        for (int k = 0; k < 3; k++) p->velocity[k] = 0;
        return;
    }
    if (!(dt > 0)) return;  /* NaN too */
    if (dt > MAX_DT) dt = MAX_DT;

    ew_move_input in = {{0, 0, 0}, 0, 0, 0, 0, 0, 0};
    if (in_raw) {
        for (int k = 0; k < 3; k++) in.angles[k] = isfinite(in_raw->angles[k]) ? fmodf(in_raw->angles[k], 360.0f) : 0;
        in.forward = clampf(in_raw->forward, -1, 1);
        in.right = clampf(in_raw->right, -1, 1);
        in.up = clampf(in_raw->up, -1, 1);
        in.speed = clampf(in_raw->speed, 0, 100000);
        in.run = in_raw->run != 0;
        in.jump = in_raw->jump != 0;
    }

    int steps = (int)ceil(dt / EW_MOVE_SUBSTEP - 1e-9);
    if (steps < 1) steps = 1;
    double h = dt / steps;

    mover m;
    int walk = p->mode == EW_MOVE_WALK && hull_open(w, EW_HULL_PLAYER, &m.h) == 0;
    for (int k = 0; k < 3; k++) m.org[k] = p->origin[k], m.vel[k] = p->velocity[k];

    if (!walk) {
        /* fly: the keys along the view, no inertia and no collision */
        double pitch = in.angles[0] * DEG2RAD, yaw = in.angles[1] * DEG2RAD;
        double f[3] = {cos(pitch) * cos(yaw), cos(pitch) * sin(yaw), -sin(pitch)};
        double r[3] = {sin(yaw), -cos(yaw), 0};
        double speed = (in.speed > 0 ? in.speed : EW_MOVE_SPEED) * (in.run ? 2 : 1);
        for (int k = 0; k < 3; k++) m.vel[k] = (in.forward * f[k] + in.right * r[k] + (k == 2 ? in.up : 0)) * speed;
        for (int s = 0; s < steps; s++)
            for (int k = 0; k < 3; k++) m.org[k] += m.vel[k] * h;
        for (int k = 0; k < 3; k++) p->origin[k] = (float)m.org[k], p->velocity[k] = (float)m.vel[k];
        p->on_ground = 0;
        p->jump_held = in.jump;
        return;
    }

    if (unstick(&m.h, m.org)) {  /* buried: stay put */
        for (int k = 0; k < 3; k++) p->velocity[k] = 0;
        p->on_ground = 0;
        return;
    }
    /* a press jumps once: at once on the ground, else on landing */
    int jump_now = in.jump && !p->jump_held, jumped = 0;
    for (int s = 0; s < steps; s++) {
        int was_ground = m.vel[2] <= RISING && ground_check(&m.h, m.org);
        walk_step(&m, &in, h, jump_now && !jumped);
        if (jump_now && was_ground) jumped = 1;
    }
    for (int k = 0; k < 3; k++) p->origin[k] = (float)m.org[k], p->velocity[k] = (float)m.vel[k];
    p->on_ground = m.on_ground;
    p->jump_held = in.jump && (jumped || p->jump_held);
}
