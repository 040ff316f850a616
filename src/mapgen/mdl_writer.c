/*
 * Map generator: the built-in scene's triangle model, made in memory and
 * written as an MDL version 6 image (the format src/asset/mdl.c reads).
 *
 * A hooded lantern bearer floating over the floor: a robed body revolved
 * from a profile (16 segments round, closed by a vertex at each pole), two
 * arms (six-sided tubes through shoulder, elbow and wrist, closed at both
 * ends) and a crystal lantern (a six-sided bipyramid) held in front.
 * Every part is a closed surface wound clockwise seen from outside, the
 * way the format's files are (the test checks each edge is used once each
 * way and the enclosed volume is positive).
 *
 * Skin (128x64, palette indices of the built-in palette): the body is
 * mapped by projecting it onto the y-z plane, the format's way: the left
 * half of the skin is the front (x > 0) seen from in front, the right half
 * the back, and the vertices on the seam between them (the silhouette at
 * y = +-r, and the two poles) are flagged onseam so triangles of the back
 * use s + 64.  Rows 48..55 are the sleeves (s along the arm), rows 56..63
 * the lantern's glass in fullbright colours that light does not dim.
 *
 * Animation: one frame, a group of BI_MODEL_POSES poses, so the renderer
 * picks a pose by time: the figure bobs, the chest breathes, the hem
 * ripples round, the hood's tip sways and the lantern turns.
 */
#include "mapgen_internal.h"
#include "ew_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846
#define NSEG 16       /* body segments round */
#define ASEG 6        /* arm tube sides */
#define MAXV 400
#define MAXT 800
#define SKIN_W BI_MODEL_SKIN_W
#define SKIN_H BI_MODEL_SKIN_H
#define BODY_ROWS 48  /* skin rows of the body */
#define ZTOP 69.0     /* the hood's tip, before bobbing */
#define ZBOT 7.0      /* the hem */
#define SKIN_K (31.0 / 13.5)  /* skin texels per unit of y on the body */

const float bi_model_lantern[3] = {17.0f, 0.0f, 39.3f};

/* The body's profile, bottom to top: radius, height.  The first and last
 * points are the poles. */
static const double profile[][2] = {
    {0, 9.5},    {12.5, 7},  {11.6, 12}, {9.6, 20},  {7.9, 28},  {7.2, 32},
    {8.2, 37},   {9.4, 42},  {8.8, 45.5}, {5.6, 47.6}, {3.7, 49.2}, {5.3, 51.5},
    {6.7, 55},   {6.7, 59},  {5.3, 62.5}, {2.9, 65.6}, {0, ZTOP},
};
#define NPROF ((int)(sizeof profile / sizeof profile[0]))

typedef struct mesh {
    int   topology;  /* pose 0: also record texture coordinates and triangles */
    int   nverts, ntris;
    int   overflow;  /* more than MAXV vertices or MAXT triangles were made */
    float pos[MAXV][3];
    int   st[MAXV][3];   /* onseam, s, t */
    int   tri[MAXT][4];  /* facesfront, v0, v1, v2 */
} mesh;

static int clampi(int v, int lo, int hi) { return v < lo ? lo : v > hi ? hi : v; }

static int add_vert(mesh *m, const double p[3], int onseam, double s, double t) {
    int i = m->nverts++;
    if (i >= MAXV) {
        m->overflow = 1;
        return 0;
    }
    for (int k = 0; k < 3; k++) m->pos[i][k] = (float)p[k];
    if (m->topology) {
        m->st[i][0] = onseam;
        m->st[i][1] = clampi((int)lrint(s), 0, SKIN_W);
        m->st[i][2] = clampi((int)lrint(t), 0, SKIN_H);
    }
    return i;
}

/* A triangle wound clockwise seen from outside: the outward normal of
 * (a, b, c) is (c - a) x (b - a); it is turned round if that points
 * against `out` (a direction known to point outwards there). */
static void add_tri(mesh *m, int front, int a, int b, int c, const double out[3]) {
    if (!m->topology) return;
    if (m->ntris >= MAXT) {
        m->overflow = 1;
        return;
    }
    double e1[3], e2[3];
    for (int k = 0; k < 3; k++) e1[k] = m->pos[b][k] - m->pos[a][k], e2[k] = m->pos[c][k] - m->pos[a][k];
    double n[3] = {e2[1] * e1[2] - e2[2] * e1[1], e2[2] * e1[0] - e2[0] * e1[2], e2[0] * e1[1] - e2[1] * e1[0]};
    int *t = m->tri[m->ntris++];
    t[0] = front, t[1] = a;
    if (n[0] * out[0] + n[1] * out[1] + n[2] * out[2] >= 0) t[2] = b, t[3] = c;
    else t[2] = c, t[3] = b;
}

/* ---- the parts ---------------------------------------------------------------- */

static double smooth01(double x) {
    x = x < 0 ? 0 : x > 1 ? 1 : x;
    return x * x * (3 - 2 * x);
}

/* Body vertex of profile point i (not a pole) at segment j, pose phase ph. */
static void body_point(int i, int j, double ph, double bob, double p[3]) {
    double th = 2 * PI * j / NSEG, r = profile[i][0], z = profile[i][1];
    if (z > 33 && z < 48) r *= 1 + 0.04 * sin(ph) * smooth01((48 - z) / 6) * smooth01((z - 33) / 4);
    r *= 1 + 0.07 * smooth01((20 - z) / 13) * sin(3 * th - ph);
    double x = r * cos(th), y = r * sin(th);
    /* the face: pressed into the front of the hood */
    if (z > 52 && z < 61.5 && cos(th) > 0.5) x -= 2.2 * (cos(th) - 0.5) / 0.5;
    /* the hood's tip leans back and sways */
    double lean = smooth01((z - 57) / (ZTOP - 57));
    x -= lean * lean * (3.0 + 0.8 * sin(ph));
    y += lean * lean * 0.6 * cos(ph);
    p[0] = x, p[1] = y, p[2] = z + bob;
}

static void body(mesh *m, double ph, double bob) {
    int base = m->nverts;
    /* poles: onseam, at the centre of the front half (the back adds 64) */
    double lo[3] = {0, 0, profile[0][1] + bob};
    add_vert(m, lo, 1, SKIN_W / 4.0, (ZTOP - profile[0][1]) * (BODY_ROWS - 1) / (ZTOP - ZBOT));
    for (int i = 1; i < NPROF - 1; i++)
        for (int j = 0; j < NSEG; j++) {
            double p[3];
            body_point(i, j, ph, bob, p);
            double th = 2 * PI * j / NSEG, y0 = profile[i][0] * sin(th);
            int seam = j == NSEG / 4 || j == 3 * NSEG / 4, back = cos(th) < -1e-9;
            double s = SKIN_W / 4.0 + y0 * SKIN_K + (back ? SKIN_W / 2.0 : 0);
            double t = (ZTOP - profile[i][1]) * (BODY_ROWS - 1) / (ZTOP - ZBOT);
            add_vert(m, p, seam, s, t);
        }
    double hi[3];
    body_point(NPROF - 1, 0, ph, bob, hi);
    int top = add_vert(m, hi, 1, SKIN_W / 4.0, 0);
    if (!m->topology) return;
    int rings = NPROF - 2;
#define RV(i, j) (base + 1 + (i) * NSEG + ((j) % NSEG))
    for (int i = 0; i <= rings; i++)
        for (int j = 0; j < NSEG; j++) {
            double th0 = 2 * PI * j / NSEG, th1 = 2 * PI * (j + 1) / NSEG, thm = (th0 + th1) / 2;
            int front = cos(th0) > -1e-9 && cos(th1) > -1e-9;
            /* outward normal of the profile segment below point i + 1 */
            double dr = profile[i + 1][0] - profile[i][0], dz = profile[i + 1][1] - profile[i][1];
            double out[3] = {dz * cos(thm), dz * sin(thm), -dr};
            if (i == 0) add_tri(m, front, base, RV(0, j), RV(0, j + 1), out);
            else if (i == rings) add_tri(m, front, top, RV(rings - 1, j), RV(rings - 1, j + 1), out);
            else {
                add_tri(m, front, RV(i - 1, j), RV(i, j), RV(i, j + 1), out);
                add_tri(m, front, RV(i - 1, j), RV(i, j + 1), RV(i - 1, j + 1), out);
            }
        }
#undef RV
}

static void normalize(double v[3]) {
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 1e-12)
        for (int k = 0; k < 3; k++) v[k] /= l;
}

/* An arm on side sg (+1 left, -1 right): a tube through four centres from
 * inside the shoulder to the wrist, capped by a pole at each end (the hand
 * is the cap at the wrist).  Sleeve texture along the arm in rows 49..55. */
static void arm(mesh *m, int sg, double ph, double bob) {
    double lift = 0.9 * sin(ph + 0.6);
    double c[4][3] = {{0.5, sg * 6.0, 43.5}, {2.0, sg * 9.6, 42.6}, {8.0, sg * 10.2, 35.5 + 0.5 * lift},
                      {13.6, sg * 4.6, 37.0 + lift}};
    const double rad[4] = {2.4, 2.9, 2.3, 1.9};
    for (int i = 0; i < 4; i++) c[i][2] += bob;
    int base = m->nverts;
    double dir[4][3];
    for (int i = 0; i < 4; i++) {
        const double *a = c[i > 0 ? i - 1 : 0], *b = c[i < 3 ? i + 1 : 3];
        for (int k = 0; k < 3; k++) dir[i][k] = b[k] - a[k];
        normalize(dir[i]);
    }
    double p[3];
    for (int k = 0; k < 3; k++) p[k] = c[0][k] - dir[0][k] * 1.5;
    add_vert(m, p, 0, 2, 52);
    for (int i = 0; i < 4; i++) {
        /* ring frame: u level and across the arm, w = u x dir */
        double u[3] = {dir[i][1], -dir[i][0], 0}, w[3];
        normalize(u);
        w[0] = u[1] * dir[i][2] - u[2] * dir[i][1];
        w[1] = u[2] * dir[i][0] - u[0] * dir[i][2];
        w[2] = u[0] * dir[i][1] - u[1] * dir[i][0];
        for (int k = 0; k < ASEG; k++) {
            double f = 2 * PI * k / ASEG;
            for (int q = 0; q < 3; q++) p[q] = c[i][q] + rad[i] * (cos(f) * u[q] + sin(f) * w[q]);
            add_vert(m, p, 0, 6 + 118.0 * i / 3, 49 + 6.0 * fabs(k - ASEG / 2.0) / (ASEG / 2.0));
        }
    }
    for (int k = 0; k < 3; k++) p[k] = c[3][k] + dir[3][k] * 2.6;
    int hand = add_vert(m, p, 0, 126, 52);
    if (!m->topology) return;
#define AV(i, k) (base + 1 + (i) * ASEG + ((k) % ASEG))
    for (int i = 0; i <= 4; i++)
        for (int k = 0; k < ASEG; k++) {
            double out[3];
            if (i == 0 || i == 4) {
                for (int q = 0; q < 3; q++) out[q] = i == 0 ? -dir[0][q] : dir[3][q];
                add_tri(m, 1, i == 0 ? base : hand, AV(i == 0 ? 0 : 3, k), AV(i == 0 ? 0 : 3, k + 1), out);
                continue;
            }
            /* from the axis to the quad's middle */
            for (int q = 0; q < 3; q++)
                out[q] = (m->pos[AV(i - 1, k)][q] + m->pos[AV(i, k + 1)][q]) / 2 - (c[i - 1][q] + c[i][q]) / 2;
            add_tri(m, 1, AV(i - 1, k), AV(i, k), AV(i, k + 1), out);
            add_tri(m, 1, AV(i - 1, k), AV(i, k + 1), AV(i - 1, k + 1), out);
        }
#undef AV
}

/* The lantern: a six-sided bipyramid of glass turning about z. */
static void lantern(mesh *m, double ph, double bob) {
    double c[3] = {bi_model_lantern[0], bi_model_lantern[1], bi_model_lantern[2] + bob + 0.9 * sin(ph + 0.6)};
    double turn = ph / 6;  /* a sixth of a turn per cycle: the shape repeats */
    int base = m->nverts;
    double p[3] = {c[0], c[1], c[2] + 5.2};
    add_vert(m, p, 0, 64, 56);
    for (int k = 0; k < 6; k++) {
        double a = 2 * PI * k / 6 + turn;
        p[0] = c[0] + 3.3 * cos(a), p[1] = c[1] + 3.3 * sin(a), p[2] = c[2];
        add_vert(m, p, 0, 10 + 21 * k, 60);
    }
    p[0] = c[0], p[1] = c[1], p[2] = c[2] - 5.2;
    add_vert(m, p, 0, 64, 63);
    if (!m->topology) return;
    for (int k = 0; k < 6; k++) {
        int a = base + 1 + k, b = base + 1 + (k + 1) % 6;
        for (int e = 0; e < 2; e++) {
            int pole = e ? base + 7 : base;
            double out[3];
            for (int q = 0; q < 3; q++) out[q] = (m->pos[a][q] + m->pos[b][q] + m->pos[pole][q]) / 3 - c[q];
            add_tri(m, 1, pole, a, b, out);
        }
    }
}

static void build_pose(mesh *m, int pose) {
    double ph = 2 * PI * pose / BI_MODEL_POSES, bob = 1.8 + 1.8 * sin(ph);
    m->nverts = 0;
    if (m->topology) m->ntris = 0;
    body(m, ph, bob);
    arm(m, 1, ph, bob);
    arm(m, -1, ph, bob);
    lantern(m, ph, bob);
}

/* ---- the skin --------------------------------------------------------------------- */

static uint8_t body_texel(int x, int row) {
    int front = x < SKIN_W / 2;
    double sx = x % (SKIN_W / 2) + 0.5;
    double y = (sx - SKIN_W / 4.0) / SKIN_K;  /* model y under the texel */
    double z = ZTOP - (row + 0.5) * (ZTOP - ZBOT) / (BODY_ROWS - 1);
    double u = (double)x / SKIN_W, v = (double)row / SKIN_H;
    double n = bi_fbm(u, v, 8, 3, 211);
    double fold = z < 44 ? 1.4 * sin(y * 0.85 + (front ? 0 : 1.3)) : 0;
    double shade = 6.5 + fold + 2.5 * (n - 0.5);
    if (z < 10.8) {  /* the hem: a gold band with a zigzag */
        double zig = 8.9 + 0.9 * (fabs(fmod(sx, 6.0) - 3.0) - 1.5);
        if (z > 10.2) return bi_px(BI_R_GOLD, 3);
        return bi_px(BI_R_GOLD, fabs(z - zig) < 0.55 ? 3.5 : 8.5 + 2 * (n - 0.5));
    }
    if (z > 30.5 && z < 33.5) {  /* the belt and its buckle */
        if (front && fabs(y) < 1.8) return bi_px(BI_R_GOLD, fabs(y) < 0.9 && fabs(z - 32) < 0.7 ? 4 : 11);
        return bi_px(BI_R_BROWN, 4.5 + 2 * (n - 0.5));
    }
    if (z > 45 && z < 48) return bi_px(BI_R_GOLD, 7.5 + 3 * (n - 0.5) + (z > 47.3 ? 2 : 0));  /* collar */
    if (z >= 33.5 && z <= 45) {
        double dy = y, dz = z - 39.5, d = sqrt(dy * dy + dz * dz);
        if (front && d < 0.9) return BI_FB_RED + 1;  /* the amulet's gem */
        if (front && d < 2.0) return bi_px(BI_R_GOLD, 12 - d * 2);
        if (!front && fabs(d - 2.6) < 0.6) return bi_px(BI_R_GOLD, 9);  /* an emblem on the back */
        if (front && fabs(y) < 3.2) shade += 2;  /* the front panel */
    }
    if (z > 50.8) {  /* the hood; in front, the face in its shadow */
        double ey = y / 4.1, ez = (z - 56.6) / 4.8, e = ey * ey + ez * ez;
        if (front && e < 1) {
            for (int side = -1; side <= 1; side += 2) {
                double dy = (y - side * 1.75) / 1.1, dz = (z - 57.4) / 0.75;
                if (dy * dy + dz * dz < 1) return BI_FB_BLUE + (dy * dy + dz * dz < 0.35 ? 0 : 1);
            }
            return bi_px(BI_R_GREY, 1 + 1.5 * n + (z < 53 ? 1 : 0));
        }
        if (front && e < 1.35) return bi_px(BI_R_PURPLE, 3);
        shade = 7 + 2.5 * (n - 0.5) - (z > 64 ? 1 : 0);
    } else if (z > 47.9) {
        shade = 5.5 + 2 * (n - 0.5);  /* the mantle over the shoulders */
    }
    if (z < 30.5 && front && fabs(y) < 2.2) shade -= 1.5;  /* the robe's front opening */
    return bi_px(BI_R_PURPLE, shade);
}

static void paint_skin(uint8_t *skin) {
    for (int row = 0; row < SKIN_H; row++)
        for (int x = 0; x < SKIN_W; x++) {
            uint8_t c;
            double n = bi_fbm((double)x / SKIN_W, (double)row / SKIN_H, 8, 2, 223);
            if (row < BODY_ROWS) {
                c = body_texel(x, row);
            } else if (row < 56) {  /* sleeves: shoulder at s 6, wrist at s 124 */
                if (x >= 122) c = bi_px(BI_R_OLIVE, 6 + 3 * (n - 0.5) - (row == 55 ? 2 : 0));   /* hand */
                else if (x >= 102) c = bi_px(BI_R_GOLD, 8 + 3 * (n - 0.5) + (x < 104 ? -3 : 0));  /* cuff */
                else c = bi_px(BI_R_PURPLE, 6.5 + 2.5 * (n - 0.5) + 1.2 * sin(x * 0.5));
            } else {  /* the lantern's glass: hot core rows, facets alternate */
                int facet = (x - 10 + 21) / 21, dr = abs(2 * row - 119);
                int level = dr / 2 + (facet & 1);
                c = level <= 0 ? BI_FB_WHITE : (uint8_t)(BI_FB_YELLOW + clampi(level, 0, 6));
            }
            skin[row * SKIN_W + x] = c;
        }
}

/* ---- the file ------------------------------------------------------------------------ */

int bi_model_generate(uint8_t **mdl, size_t *size, ew_error *err) {
    *mdl = NULL, *size = 0;
    mesh *m = calloc(1, sizeof *m);
    float(*pos)[MAXV][3] = malloc(sizeof *pos * BI_MODEL_POSES);
    uint8_t *skin = malloc((size_t)SKIN_W * SKIN_H);
    bi_buf b = {0};
    if (!m || !pos || !skin) {
        free(m), free(pos), free(skin);
        return ew_fail(err, "builtin model: out of memory");
    }
    m->topology = 1;
    build_pose(m, 0);
    int nverts = m->nverts;
    m->topology = 0;
    memcpy(pos[0], m->pos, sizeof pos[0]);
    for (int p = 1; p < BI_MODEL_POSES; p++) {
        build_pose(m, p);
        memcpy(pos[p], m->pos, sizeof pos[p]);
    }
    if (m->overflow || m->nverts != nverts) {
        int nt = m->ntris;
        free(m), free(pos), free(skin);
        return ew_fail(err, "builtin model: %d vertices, %d triangles (at most %d, %d)", nverts, nt, MAXV,
                       MAXT);
    }
    /* one scale and translation packing every pose into bytes */
    float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f}, radius = 0;
    for (int p = 0; p < BI_MODEL_POSES; p++)
        for (int i = 0; i < nverts; i++) {
            const float *q = pos[p][i];
            for (int k = 0; k < 3; k++) lo[k] = q[k] < lo[k] ? q[k] : lo[k], hi[k] = q[k] > hi[k] ? q[k] : hi[k];
            float r = sqrtf(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
            radius = r > radius ? r : radius;
        }
    float scale[3];
    for (int k = 0; k < 3; k++) scale[k] = (hi[k] - lo[k]) / 255.0f;
    paint_skin(skin);

    bi_put(&b, "IDPO", 4);
    bi_put_i32(&b, 6);
    for (int k = 0; k < 3; k++) bi_put_f32(&b, scale[k]);
    for (int k = 0; k < 3; k++) bi_put_f32(&b, lo[k]);
    bi_put_f32(&b, radius);
    const float eye[3] = {0, 0, 56};
    for (int k = 0; k < 3; k++) bi_put_f32(&b, eye[k]);
    bi_put_i32(&b, 1);  /* skins */
    bi_put_i32(&b, SKIN_W);
    bi_put_i32(&b, SKIN_H);
    bi_put_i32(&b, nverts);
    bi_put_i32(&b, m->ntris);
    bi_put_i32(&b, 1);  /* frames: one group */
    bi_put_i32(&b, 0);  /* synctype */
    bi_put_i32(&b, 0);  /* flags */
    bi_put_f32(&b, 8.0f);  /* average triangle size (informative) */
    bi_put_i32(&b, 0);  /* a single skin */
    bi_put(&b, skin, (size_t)SKIN_W * SKIN_H);
    for (int i = 0; i < nverts; i++)
        for (int k = 0; k < 3; k++) bi_put_i32(&b, m->st[i][k]);
    for (int i = 0; i < m->ntris; i++)
        for (int k = 0; k < 4; k++) bi_put_i32(&b, m->tri[i][k]);

    /* the frame group: its bounds, the poses' end times, then the poses */
    bi_put_i32(&b, 1);
    bi_put_i32(&b, BI_MODEL_POSES);
    const uint8_t gmin[4] = {0, 0, 0, 0}, gmax[4] = {255, 255, 255, 0};
    bi_put(&b, gmin, 4), bi_put(&b, gmax, 4);
    for (int p = 0; p < BI_MODEL_POSES; p++) bi_put_f32(&b, BI_MODEL_INTERVAL * (float)(p + 1));
    for (int p = 0; p < BI_MODEL_POSES; p++) {
        uint8_t (*v)[4] = malloc(sizeof *v * (size_t)nverts);
        if (!v) { b.failed = 1; break; }
        uint8_t vmin[4] = {255, 255, 255, 0}, vmax[4] = {0, 0, 0, 0};
        for (int i = 0; i < nverts; i++) {
            for (int k = 0; k < 3; k++) {
                float f = scale[k] > 0 ? (pos[p][i][k] - lo[k]) / scale[k] : 0;
                v[i][k] = (uint8_t)clampi((int)lrintf(f), 0, 255);
                vmin[k] = v[i][k] < vmin[k] ? v[i][k] : vmin[k];
                vmax[k] = v[i][k] > vmax[k] ? v[i][k] : vmax[k];
            }
            v[i][3] = 0;  /* light normal index: the loader computes normals */
        }
        bi_put(&b, vmin, 4), bi_put(&b, vmax, 4);
        char name[16] = {0};
        name[0] = 'f', name[1] = 'l', name[2] = 'o', name[3] = 'a', name[4] = 't';
        name[5] = (char)('1' + p);
        bi_put(&b, name, 16);
        bi_put(&b, v, (size_t)nverts * 4);
        free(v);
    }
    free(m), free(pos), free(skin);
    if (b.failed) {
        free(b.data);
        return ew_fail(err, "builtin model: out of memory");
    }
    *mdl = b.data, *size = b.len;
    return 0;
}
