/* World faces that nearer faces hide (world/occlude.c,
 * ew_set_occlusion_cull): left out of the edge list, with the same frame.
 *
 * First the coverage map alone, on random convex polygons with growing
 * keys: every face it calls hidden has each pixel centre inside it lying
 * inside a face with a smaller key by at least the margin less float
 * error (so the edge list would have shown that face there, never the
 * hidden one); a face never hides behind one with its own key; and the map
 * in 1, 3 and 7 strips decides every face as the whole one does.  A few
 * placed squares check the cases by hand.
 *
 * Then every view of e1m1, lqdm7, e4m1 and start with their entities: the
 * frame and the z-buffer with the culling always on equal those with it off bit
 * for bit, at 320x200 and 640x480 on one thread and on two (in the 1996
 * look and today's), and at 1920x1080 on every third view; the counts add
 * up (surfaces + hidden faces = the surfaces without culling; the spans
 * and the surfaces that won them are the same); lqdm7, a map of many
 * rooms, loses at least a third of its surfaces; cameras at random near
 * the views' eyes (in walls, against them, any way turned, fields of view
 * 20-170) give the same frames on one thread and on three; the default (auto) hides
 * nothing where the PVS is small (start) and does hide on lqdm7; and the
 * other methods hide nothing. */
#include "edgewise_lab.h"
#include "renderer.h"
#include "util.h"
#include "world/occlude.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* ---- the coverage map alone ---------------------------------------------- */

#define MW 320
#define MH 200
#define NPOLY 400
/* Under the sanitizers (ten times slower) fewer rounds of random faces. */
#define ROUNDS (EW_T_SANITIZED ? 6 : 20)

typedef struct poly {
    ew_proj p[8];
    int     n, key;
} poly;

static uint32_t rng = 12345;
static float frand(void) {
    rng = rng * 1664525u + 1013904223u;
    return (float)(rng >> 8) / 16777216.0f;
}

/* Signed distance of (x, y) inside edge a->b of a polygon wound either way
 * (positive inside). */
static float inside_by(const poly *q, float x, float y) {
    float area = 0;
    for (int i = 0; i < q->n; i++) {
        const ew_proj *a = &q->p[i], *b = &q->p[(i + 1) % q->n];
        area += a->u * b->v - b->u * a->v;
    }
    float s = area > 0 ? 1.0f : -1.0f, d = INFINITY;
    for (int i = 0; i < q->n; i++) {
        const ew_proj *a = &q->p[i], *b = &q->p[(i + 1) % q->n];
        float ex = b->u - a->u, ey = b->v - a->v, len = sqrtf(ex * ex + ey * ey);
        if (len == 0) continue;
        float c = s * (ex * (y - a->v) - ey * (x - a->u)) / len;
        d = c < d ? c : d;
    }
    return d;
}

static void random_poly(poly *q, int key) {
    /* Most wholly on the screen, as the frustum clip leaves a face; some
     * with points clamped to its borders, which can leave them concave. */
    int clamped = frand() < 0.3f;
    float cx = frand() * (MW - 1), cy = frand() * (MH - 1);
    float r = 2 + frand() * frand() * 150, room = cx + 0.5f;
    room = MW - 0.5f - cx < room ? MW - 0.5f - cx : room;
    room = (cy + 0.5f) / 0.8f < room ? (cy + 0.5f) / 0.8f : room;
    room = (MH - 0.5f - cy) / 0.8f < room ? (MH - 0.5f - cy) / 0.8f : room;
    if (clamped) cx = frand() * (MW + 40) - 20, cy = frand() * (MH + 40) - 20;
    else r = r < room ? r : room;
    q->n = 3 + (int)(frand() * 5);
    float ang[8];
    for (int i = 0; i < q->n; i++) ang[i] = frand() * 6.2831853f;
    for (int i = 1; i < q->n; i++)  /* sorted: a convex polygon */
        for (int j = i; j > 0 && ang[j] < ang[j - 1]; j--) {
            float t = ang[j];
            ang[j] = ang[j - 1], ang[j - 1] = t;
        }
    for (int i = 0; i < q->n; i++) {
        float u = cx + r * cosf(ang[i]), v = cy + r * 0.8f * sinf(ang[i]);
        q->p[i].u = u < -0.5f ? -0.5f : u > MW - 0.5f ? MW - 0.5f : u;
        q->p[i].v = v < -0.5f ? -0.5f : v > MH - 0.5f ? MH - 0.5f : v;
        q->p[i].zi = 1;
    }
    q->key = key;
}

/* Every face of the list through a map cut in nstrips; hidden[i] set. */
static void decide(const poly *list, int n, int nstrips, int *hidden) {
    ew_occlusion o;
    memset(&o, 0, sizeof o);
    CHECK(ew_occ_init(&o, MW, MH) == 0, "coverage map");
    if (!o.bits) return;
    ew_occ_begin(&o, 1);
    if (nstrips > 1) CHECK(ew_occ_strips(&o, nstrips) == nstrips, "%d strips", nstrips);
    for (int i = 0; i < n; i++) {
        ew_occ_box b = ew_occ_box_of(&o, list[i].p, list[i].n, MW, MH);
        int h = 1;
        if (nstrips == 1)
            h = ew_occ_face(&o, &o.whole, list[i].p, list[i].n, b, list[i].key);
        else
            for (int s = 0; s < nstrips; s++) h &= ew_occ_face(&o, &o.strips[s], list[i].p, list[i].n, b, list[i].key);
        hidden[i] = h;
    }
    ew_occ_free(&o);
}

static void check_map(void) {
    static poly list[NPOLY];
    static int hidden[4][NPOLY];
    long nhidden = 0, pixels_checked = 0;
    for (int round = 0; round < ROUNDS; round++) {
        int key = 0;
        for (int i = 0; i < NPOLY; i++) {
            key += frand() < 0.7f;  /* runs of faces on one key, as a node's */
            random_poly(&list[i], key);
        }
        const int strips[4] = {1, 3, 7, 50};
        for (int k = 0; k < 4; k++) decide(list, NPOLY, strips[k], hidden[k]);
        for (int i = 0; i < NPOLY; i++) {
            CHECK(hidden[1][i] == hidden[0][i] && hidden[2][i] == hidden[0][i] && hidden[3][i] == hidden[0][i],
                  "round %d face %d: hidden %d whole, %d / %d / %d in 3, 7 and 50 strips", round, i, hidden[0][i],
                  hidden[1][i], hidden[2][i], hidden[3][i]);
            if (!hidden[0][i]) continue;
            nhidden++;
            /* Each pixel centre inside the hidden face: inside a face
             * with a smaller key, well inside. */
            const poly *f = &list[i];
            float area = 0;
            for (int k = 0; k < f->n; k++)
                area += f->p[k].u * f->p[(k + 1) % f->n].v - f->p[(k + 1) % f->n].u * f->p[k].v;
            if (fabsf(area) < 1e-3f) continue;  /* no area, no pixel (and inside_by sees no edge) */
            int bad = 0, x0 = MW, x1 = 0, y0 = MH, y1 = 0;
            for (int k = 0; k < f->n; k++) {
                int xa = (int)floorf(f->p[k].u), ya = (int)floorf(f->p[k].v);
                x0 = xa < x0 ? xa : x0, x1 = xa + 1 > x1 ? xa + 1 : x1;
                y0 = ya < y0 ? ya : y0, y1 = ya + 1 > y1 ? ya + 1 : y1;
            }
            for (int y = y0 < 0 ? 0 : y0; y <= y1 && y < MH; y++)
                for (int x = x0 < 0 ? 0 : x0; x <= x1 && x < MW; x++) {
                    if (inside_by(f, (float)x, (float)y) < 0) continue;
                    int well = 0;
                    for (int j = 0; j < i && list[j].key < f->key && !well; j++)
                        well = inside_by(&list[j], (float)x, (float)y) >= 0.2f;
                    pixels_checked++;
                    bad += !well;
                }
            CHECK(bad == 0, "round %d face %d (key %d): %d of its pixel centres are not well inside a nearer face",
                  round, i, f->key, bad);
        }
    }
    printf("coverage map: %ld of %d random faces hidden, %ld of their pixel centres checked\n", nhidden,
           ROUNDS * NPOLY, pixels_checked);
    CHECK(nhidden > ROUNDS * NPOLY / 10, "only %ld faces hidden", nhidden);
}

static poly square(float x0, float y0, float x1, float y1, int key) {
    poly q = {{{x0, y0, 1}, {x1, y0, 1}, {x1, y1, 1}, {x0, y1, 1}}, 4, key};
    return q;
}

/* Hand-placed cases on the 4-pixel tiles of a 320x200 map. */
static void check_cases(void) {
    const poly list[] = {
        square(10.3f, 10.3f, 100.7f, 90.7f, 1),  /* the occluder */
        square(20, 20, 60, 60, 1),               /* its own key: never hidden by it */
        square(20, 20, 60, 60, 2),               /* behind it: hidden */
        square(5, 20, 60, 60, 3),                /* out past its left side: seen */
        square(95, 20, 101.5f, 60, 4),           /* pixel centres x = 101 outside it: seen */
        square(14, 14, 80, 80, 5),               /* inside, by more than a tile and the margin: hidden */
        square(14, 14, 96, 86, 5),               /* its tiles reach rows 88-91, past the occluder's 90.7: seen */
        square(40, 40, 40.2f, 40.2f, 6),         /* no pixel centre, inside: hidden */
    };
    const int want[] = {0, 0, 1, 0, 0, 1, 0, 1};
    int n = (int)(sizeof list / sizeof *list), got[16];
    decide(list, n, 1, got);
    for (int i = 0; i < n; i++) CHECK(got[i] == want[i], "placed face %d: hidden %d, want %d", i, got[i], want[i]);
    /* A concave polygon (a U, as a clamped depth could leave one) covers
     * nothing: a line across its arms meets it twice, and the gap between
     * must not count as covered. */
    poly u = {{{10, 10, 1}, {40, 10, 1}, {40, 150, 1}, {120, 150, 1}, {120, 10, 1}, {150, 10, 1}, {150, 190, 1},
               {10, 190, 1}}, 8, 1};
    const poly cup[] = {u, square(60, 60, 100, 120, 2), square(15, 160, 140, 185, 3)};
    decide(cup, 3, 1, got);
    CHECK(!got[1] && !got[2], "behind a U: in its gap hidden %d, behind its foot hidden %d", got[1], got[2]);
}

/* ---- real maps: the same frames ------------------------------------------ */

typedef struct totals {
    long frames, differ, surfaces, occluded;
} totals;

static void compare(const char *name, const ew_assets *a, ew_scene *sc, const ew_camera *views, int nv, int step,
                    int w, int h, int threads, int classic, totals *t) {
    ew_error err;
    ew_renderer *r[2];
    for (int k = 0; k < 2; k++) {
        r[k] = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                      .colormap = a->colormap, .width = w, .height = h,
                                                      .threads = threads},
                                  &err);
        CHECK(r[k] != NULL, "%s: %s", name, err.msg);
        if (!r[k]) {
            if (k) ew_renderer_destroy(r[0]);
            return;
        }
        ew_set_classic(r[k], classic);
        ew_set_scene(r[k], sc);
    }
    ew_set_occlusion_cull(r[0], EW_OCCLUSION_OFF);
    ew_set_occlusion_cull(r[1], EW_OCCLUSION_ALWAYS);  /* auto would skip the small PVS sets */
    for (int v = 0; v < nv; v += step) {
        ew_stats s[2];
        CHECK(ew_render(r[0], &views[v], &s[0]) == 0 && ew_render(r[1], &views[v], &s[1]) == 0, "%s view %d", name, v);
        long fd = 0, zd = 0;
        const uint8_t *p0 = ew_frame_pixels(r[0]), *p1 = ew_frame_pixels(r[1]);
        for (int i = 0; i < w * h; i++) fd += p0[i] != p1[i];
        const float *z0 = ew_frame_zbuffer(r[0]), *z1 = ew_frame_zbuffer(r[1]);
        for (int i = 0; i < w * h; i++) zd += memcmp(&z0[i], &z1[i], sizeof(float)) != 0;
        CHECK(fd == 0 && zd == 0, "%s view %d %dx%d, %d threads, classic %d: %ld pixels and %ld z values differ", name,
              v, w, h, threads, classic, fd, zd);
        CHECK(s[0].faces_occluded == 0, "%s view %d: %d faces hidden with the culling off", name, v,
              s[0].faces_occluded);
        CHECK(s[1].surfaces + s[1].faces_occluded == s[0].surfaces && s[1].surfaces_shown == s[0].surfaces_shown &&
                  s[1].spans == s[0].spans && s[1].edges <= s[0].edges && s[1].dropped == 0,
              "%s view %d %dx%d, %d threads: %d surfaces + %d hidden against %d, shown %d against %d, spans %d "
              "against %d, edges %d against %d, dropped %d",
              name, v, w, h, threads, s[1].surfaces, s[1].faces_occluded, s[0].surfaces, s[1].surfaces_shown,
              s[0].surfaces_shown, s[1].spans, s[0].spans, s[1].edges, s[0].edges, s[1].dropped);
        t->frames++, t->differ += fd != 0 || zd != 0, t->surfaces += s[0].surfaces, t->occluded += s[1].faces_occluded;
    }
    ew_renderer_destroy(r[0]), ew_renderer_destroy(r[1]);
}

/* A 320x200 renderer on one thread, or NULL after a failed CHECK. */
static ew_renderer *small_renderer(const ew_assets *a) {
    ew_error err;
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                            .colormap = a->colormap, .width = 320, .height = 200,
                                                            .threads = 1},
                                        &err);
    CHECK(r != NULL, "%s", err.msg);
    return r;
}

/* The default, auto: only frames whose PVS has EW_OCC_AUTO_LEAVES leaves
 * or more; none of start's views has (it hides nothing there), every one
 * of lqdm7's does. */
static void check_auto(const char *name, const ew_assets *a, const ew_camera *views, int nv, int want_some) {
    ew_renderer *r = small_renderer(a);
    if (!r) return;
    ew_set_classic(r, 1);
    ew_set_occlusion_cull(r, (ew_occlusion_mode)7);  /* not a mode: auto */
    long hidden = 0, small = 0;
    for (int v = 0; v < nv; v++) {
        ew_stats st;
        CHECK(ew_render(r, &views[v], &st) == 0, "%s view %d", name, v);
        hidden += st.faces_occluded;
        if (r->marks.nvis < EW_OCC_AUTO_LEAVES) {
            small++;
            CHECK(st.faces_occluded == 0, "%s view %d: PVS of %d leaves, %d faces hidden in auto", name, v,
                  r->marks.nvis, st.faces_occluded);
        }
    }
    printf("%s, auto: %ld faces hidden, %ld of %d views with a PVS under %d leaves\n", name, hidden, small, nv,
           EW_OCC_AUTO_LEAVES);
    CHECK(want_some ? hidden > 0 && small == 0 : small == nv, "%s in auto: %ld hidden, %ld small PVS", name, hidden,
          small);
    ew_renderer_destroy(r);
}

/* Cameras anywhere near the view set's eyes (inside walls and against
 * them, where a point's depth is clamped), turned any way, with fields of
 * view from 20 to 170 degrees: the same frames and z-buffers with the
 * culling always on as off. */
static void check_random_cameras(const char *name, const ew_assets *a, const ew_camera *views, int nv, int n,
                                 int threads) {
    ew_error err;
    ew_renderer *r[2];
    for (int k = 0; k < 2; k++) {
        r[k] = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                      .colormap = a->colormap, .width = 320, .height = 200,
                                                      .threads = k ? threads : 1},
                                  &err);
        CHECK(r[k] != NULL, "%s", err.msg);
    }
    if (r[0] && r[1]) {
        ew_set_occlusion_cull(r[0], EW_OCCLUSION_OFF);
        ew_set_occlusion_cull(r[1], EW_OCCLUSION_ALWAYS);
        long differ = 0, hidden = 0;
        for (int i = 0; i < n; i++) {
            ew_camera c = views[i % nv];
            for (int k = 0; k < 3; k++) c.origin[k] += (frand() - 0.5f) * 512;
            c.angles[0] = (frand() - 0.5f) * 170, c.angles[1] = frand() * 360, c.angles[2] = (frand() - 0.5f) * 20;
            if (frand() < 0.3f) c.fov = 20 + frand() * 150;
            ew_stats s0, s1;
            CHECK(ew_render(r[0], &c, &s0) == 0 && ew_render(r[1], &c, &s1) == 0, "%s camera %d", name, i);
            int d = memcmp(ew_frame_pixels(r[0]), ew_frame_pixels(r[1]), 320 * 200) != 0 ||
                    memcmp(ew_frame_zbuffer(r[0]), ew_frame_zbuffer(r[1]), 320 * 200 * sizeof(float)) != 0;
            CHECK(!d, "%s camera %d at %g %g %g, angles %g %g %g, fov %g, %d threads: frames differ", name, i,
                  c.origin[0], c.origin[1], c.origin[2], c.angles[0], c.angles[1], c.angles[2], c.fov, threads);
            differ += d, hidden += s1.faces_occluded;
        }
        printf("%s: %d random cameras on %d thread(s), %ld differ, %ld faces hidden\n", name, n, threads, differ,
               hidden);
        CHECK(hidden > 0, "%s: random cameras hid nothing", name);
    }
    ew_renderer_destroy(r[0]), ew_renderer_destroy(r[1]);
}

/* The other methods take every face. */
static void check_other_methods(const ew_assets *a, const ew_camera *views) {
    ew_renderer *r = small_renderer(a);
    if (!r) return;
    const ew_hsr_method m[] = {EW_HSR_SPANS, EW_HSR_PAINTER, EW_HSR_ZBUFFER, EW_HSR_EDGE_Z};
    for (int k = 0; k < 4; k++) {
        CHECK(ew_set_hsr(r, m[k]) == 0, "method %d", (int)m[k]);
        ew_stats st;
        CHECK(ew_render(r, &views[21], &st) == 0, "method %d", (int)m[k]);
        CHECK(st.faces_occluded == 0, "method %d hid %d faces", (int)m[k], st.faces_occluded);
    }
    ew_renderer_destroy(r);
}

int main(void) {
    clock_t t0 = clock();
    check_cases();
    check_map();
    printf("(coverage map checks: %.1f s)\n", (double)(clock() - t0) / CLOCKS_PER_SEC);
    const char *maps[] = {"e1m1", "lqdm7", "e4m1", "start"};
    for (int m = 0; m < 4; m++) {
        ew_scene *sc = NULL;
        ew_camera views[EW_MAX_VIEWS];
        int nv = 0;
        ew_assets *a = ew_t_load_map_scene(maps[m], &sc, views, &nv);
        if (a && sc) {
            totals t = {0}, small = {0};
            compare(maps[m], a, sc, views, nv, 1, 320, 200, 1, 1, &small);
            compare(maps[m], a, sc, views, nv, 1, 320, 200, 2, 0, &t);
            compare(maps[m], a, sc, views, nv, 1, 640, 480, 1, 0, &t);
            compare(maps[m], a, sc, views, nv, 1, 640, 480, 2, 1, &t);
            compare(maps[m], a, sc, views, nv, 3, 1920, 1080, 2, 1, &t);
            printf("%s: %ld frames, %ld differ; at 320x200 in the 1996 look %ld of %ld surfaces hidden, "
                   "elsewhere %ld of %ld\n",
                   maps[m], t.frames + small.frames, t.differ + small.differ, small.occluded, small.surfaces,
                   t.occluded, t.surfaces);
            /* start is one open hall and a corridor: little hides anything there */
            if (strcmp(maps[m], "start")) CHECK(t.occluded > 0 && small.occluded > 0, "%s: no face hidden", maps[m]);
            check_random_cameras(maps[m], a, views, nv, ROUNDS * 10, 1);
            if (!strcmp(maps[m], "lqdm7")) check_random_cameras(maps[m], a, views, nv, ROUNDS * 5, 3);
            if (!strcmp(maps[m], "lqdm7") || !strcmp(maps[m], "start"))
                check_auto(maps[m], a, views, nv, !strcmp(maps[m], "lqdm7"));
            if (!strcmp(maps[m], "lqdm7")) {
                CHECK(small.occluded * 3 >= small.surfaces, "lqdm7: only %ld of %ld surfaces hidden", small.occluded,
                      small.surfaces);
                check_other_methods(a, views);
            }
        }
        ew_scene_destroy(sc);
        ew_assets_destroy(a);
    }
    return ew_t_finish();
}
