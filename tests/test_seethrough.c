/* See-through surfaces (fences, translucent liquids), fog and the underwater
 * view, at 320x200:
 *   1. the edge list agrees with the reference method (visible surfaces,
 *      exact colours at a divide per pixel; under fog or translucency, where
 *      the reference composites its own way, 80% of them) on every view of start
 *      (fences), e4m1 with liquids at alpha 0.5 (plus views made to look at
 *      its water) and lqdm7 fogged;
 *   2. the fence key colour (255) never shows where the reference shows
 *      something else; in classic mode it does show (start view 3);
 *   3. a model behind a fence shows only through its holes, one in front
 *      hides the bars; a model under translucent water shows, tinted, and
 *      opaque water hides it;
 *   4. ew_set_classic equals a renderer made classic, with see-through stats 0;
 *   5. bad setter input falls back as documented;
 *   6. fog moves far pixels towards the fog colour more than near ones;
 *   7. an eye inside water is underwater (warped frame), above it is not. */
#include "edgewise_lab.h"
#include "util.h"
#include "ew_world.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define W 320
#define H 200
#define N (W * H)

static int leaf_at(const ew_world *w, const float p[3]) {
    int n = w->models[0].headnode;
    while (n >= 0) {
        const ew_node *nd = &w->nodes[n];
        const ew_plane *pl = &w->planes[nd->plane];
        float d = pl->normal[0] * p[0] + pl->normal[1] * p[1] + pl->normal[2] * p[2] - pl->dist;
        n = nd->children[d >= 0 ? 0 : 1];
    }
    return -1 - n;
}
static int contents_at(const ew_world *w, const float p[3]) { return w->leaves[leaf_at(w, p)].contents; }

static void face_centroid(const ew_world *w, const ew_face *f, float c[3]) {
    c[0] = c[1] = c[2] = 0;
    for (int i = 0; i < f->numedges; i++)
        for (int k = 0; k < 3; k++) c[k] += w->verts[ew_face_vertex(w, f, i)][k] / (float)f->numedges;
}

/* A model file and the box every vertex lies in (MDL header: a vertex is
 * bytes * scale + translate, so translate .. translate + 255 scale). */
typedef struct model_file { uint8_t *data; size_t size; float lo[3], hi[3]; } model_file;
static int load_mdl(const char *name, model_file *m) {
    char rel[256];
    ew_error err;
    snprintf(rel, sizeof rel, "data/librequake/progs/%s", name);
    memset(m, 0, sizeof *m);
    if (ew_read_file(ew_t_shared(rel), &m->data, &m->size, &err) != 0 || m->size < 44 ||
        memcmp(m->data, "IDPO", 4) != 0) {
        CHECK(0, "%s: %s", name, err.msg);
        return -1;
    }
    for (int k = 0; k < 3; k++) {
        float s, t;
        memcpy(&s, m->data + 8 + 4 * k, 4), memcpy(&t, m->data + 20 + 4 * k, 4);
        m->lo[k] = t, m->hi[k] = t + 255 * s;
    }
    return 0;
}

static ew_renderer *make(const ew_assets *a, int classic) {
    ew_error err;
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                            .colormap = a->colormap, .width = W, .height = H,
                                                            .threads = 1, .classic = classic}, &err);
    CHECK(r != NULL, "%s", err.msg);
    if (r) ew_enable_face_ids(r, 1);
    return r;
}

/* Renders; copies pixels (and ids) out. */
static void shot(ew_renderer *r, const ew_camera *c, uint8_t *px, int *ids, ew_stats *st) {
    CHECK(ew_render(r, c, st) == 0, "render");
    if (px) memcpy(px, ew_frame_pixels(r), N);
    if (ids) memcpy(ids, ew_frame_face_ids(r), sizeof(int) * N);
}

static long diff(const uint8_t *a, const uint8_t *b) {
    long n = 0;
    for (int i = 0; i < N; i++) n += a[i] != b[i];
    return n;
}

static double pal_dist(const uint8_t *pal, int c, const float rgb[3]) {
    double s = 0;
    for (int k = 0; k < 3; k++) {
        double d = pal[3 * c + k] - 255.0 * rgb[k];
        s += d * d;
    }
    return sqrt(s);
}

/* A camera above water of the world looking down at it through a liquid
 * surface at alpha 0.5: the best of a few made from the largest upward
 * water faces (most translucent pixels); 0 if none. */
static int water_view(const ew_world *w, ew_renderer *r, ew_camera *best, int *best_face) {
    long best_px = 0;
    int tried = 0;
    for (int f = 0; f < w->models[0].numfaces && tried < 12; f++) {
        const ew_face *fa = &w->faces[f];
        const ew_texture *tex = &w->textures[w->texinfo[fa->texinfo].texture];
        const ew_plane *pl = &w->planes[fa->plane];
        float nz = (fa->flags & EW_SURF_PLANEBACK) ? -pl->normal[2] : pl->normal[2];
        /* water by its name: the loader's tex->liquid comes with worldspawn parsing */
        int water = tex->name[0] == '*' && strncmp(tex->name, "*lava", 5) && strncmp(tex->name, "*slime", 6) &&
                    strncmp(tex->name, "*tele", 5);
        if (!water || nz < 0.99f) continue;
        float c[3], p[3];
        face_centroid(w, fa, c);
        int deep = 1;  /* water at least 96 units deep under its centre, room for a model */
        for (float d = 2; d <= 96 && deep; d += 4)
            p[0] = c[0], p[1] = c[1], p[2] = c[2] - d, deep = contents_at(w, p) == EW_CONTENTS_WATER;
        if (!deep) continue;
        tried++;
        for (int yaw = 0; yaw < 360; yaw += 90) {
            float rad = (float)yaw * 3.14159265f / 180;
            ew_camera cam = {{c[0] - 80 * cosf(rad), c[1] - 80 * sinf(rad), c[2] + 56}, {35, (float)yaw, 0}, 90, 0};
            if (contents_at(w, cam.origin) != EW_CONTENTS_EMPTY) continue;
            ew_stats st;
            ew_set_liquid_alpha(r, 0.5f);
            CHECK(ew_render(r, &cam, &st) == 0, "water view");
            if (st.translucent_pixels > best_px) best_px = st.translucent_pixels, *best = cam, *best_face = f;
        }
    }
    return best_px > N / 8;
}

typedef struct tally { double sum, worst; int n, worst_view; } tally;

/* 1: agreement with the reference over the views. */
static void agreement(const char *map, ew_assets *a, ew_renderer *r, const ew_camera *views, int nv) {
    static int ids[N], ref_ids[N];
    static uint8_t px1[N], ref_px[N], plain[N];
    ew_error err;
    tally face = {0, 1, 0, 0}, exact = {0, 1, 0, 0};
    long see = 0, fogged = 0, k255 = 0;
    for (int v = 0; v < nv; v++) {
        ew_stats st;
        CHECK(ew_set_subdivision(r, 16) == 0, "subdivision");
        shot(r, &views[v], NULL, ids, &st);
        see += st.fence_pixels + st.translucent_pixels;
        CHECK(ew_set_subdivision(r, 1) == 0, "subdivision");
        shot(r, &views[v], px1, NULL, NULL);
        CHECK(ew_render_reference(r, &views[v], ref_px, ref_ids, &err) == 0, "%s", err.msg);
        long same = 0, same_x = 0;
        for (int i = 0; i < N; i++) {
            same += ids[i] == ref_ids[i];
            same_x += px1[i] == ref_px[i];
            /* 2: the fence key colour where the reference has another */
            k255 += px1[i] == 255 && ref_px[i] != 255;
        }
        if (!strcmp(map, "lqdm7")) {  /* how much the fog changes */
            ew_set_fog(r, 0, 0, 0, 0);
            shot(r, &views[v], plain, NULL, NULL);
            fogged += diff(plain, px1);
            ew_set_fog(r, 0.25f, 0.45f, 0.42f, 0.38f);
        }
        double ag = (double)same / N, agx = (double)same_x / N;
        CHECK(ag >= 0.99, "%s view %d: visible surfaces agree on %.2f%%", map, v, 100 * ag);
        /* The reference composites fog and translucency its own way, in RGB
         * to the nearest palette colour (hsr/ref_compose.c), not through
         * the 8-bit tables: under them exact colours agree less, and the
         * colours are compared by 8x8 block means in test_fog_oracle. */
        double need = !strcmp(map, "lqdm7") || st.translucent_pixels > 0 ? 0.80 : 0.99;
        CHECK(agx >= need, "%s view %d: exact colours agree on %.2f%%", map, v, 100 * agx);
        face.sum += ag, exact.sum += agx, face.n++;
        if (ag < face.worst) face.worst = ag, face.worst_view = v;
        if (agx < exact.worst) exact.worst = agx, exact.worst_view = v;
    }
    CHECK(k255 == 0, "%s: key colour 255 at %ld pixels where the reference has another colour", map, k255);
    printf("agreement %-6s views %2d  surfaces: mean %.3f%% worst %.3f%% (view %d)  exact colours: mean %.3f%% "
           "worst %.3f%% (view %d)  see-through px %ld  key-255 leaks %ld",
           map, nv, 100 * face.sum / nv, 100 * face.worst, face.worst_view, 100 * exact.sum / nv, 100 * exact.worst,
           exact.worst_view, see, k255);
    if (!strcmp(map, "lqdm7")) printf("  fogged (changed) %.1f%% of pixels", 100.0 * fogged / ((double)N * nv));
    printf("\n");
    CHECK(ew_set_subdivision(r, 16) == 0, "subdivision");
    (void)a;
}

static int *g_ids0, *g_ids1;
static uint8_t *g_a, *g_b, *g_c, *g_d;

/* 2-4, 5 on start: fences, moving things around them, classic. */
static void start_tests(ew_assets *a) {
    const ew_world *w = a->world;
    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(w, views);
    CHECK(nv > 3, "start views %d", nv);
    if (nv <= 3) return;
    ew_renderer *r = make(a, 0), *rc = make(a, 1);
    if (!r || !rc) return;
    agreement("start", a, r, views, nv);
    const ew_camera *cam = &views[3];
    ew_stats st, stc;

    /* 4: classic off and on, and a renderer made classic */
    shot(r, cam, g_a, NULL, &st);
    long fence_px = st.fence_pixels;
    CHECK(st.fence_pixels > 0 && st.seethrough_surfaces > 0, "start view 3: fence pixels %ld surfaces %d",
          st.fence_pixels, st.seethrough_surfaces);
    ew_set_classic(r, 1);
    ew_set_liquid_alpha(r, 0.5f), ew_set_fog(r, 0.5f, 1, 1, 1);  /* classic ignores these */
    long k255_classic = 0, k255_default = 0;
    for (int v = 0; v < nv; v++) {
        shot(r, &views[v], g_b, NULL, &st);
        shot(rc, &views[v], g_c, NULL, &stc);
        CHECK(diff(g_b, g_c) == 0, "start view %d: ew_set_classic differs from .classic = 1 at %ld px", v,
              diff(g_b, g_c));
        CHECK(st.seethrough_surfaces == 0 && st.fence_pixels == 0 && st.translucent_pixels == 0 &&
              st.fog_pixels == 0 && st.underwater == 0 && stc.seethrough_surfaces == 0 && stc.fence_pixels == 0,
              "start view %d classic stats: %d %ld %ld %ld %d", v, st.seethrough_surfaces, st.fence_pixels,
              st.translucent_pixels, st.fog_pixels, st.underwater);
        if (v == 3)
            for (int i = 0; i < N; i++) k255_classic += g_b[i] == 255, k255_default += g_a[i] == 255;
    }
    ew_set_classic(r, 0);
    ew_set_liquid_alpha(r, -1), ew_set_fog(r, -1, 0, 0, 0);
    CHECK(k255_classic > 0 && k255_default == 0, "start view 3: key colour pixels classic %ld default %ld",
          k255_classic, k255_default);
    printf("start view 3: fence pixels %ld, key colour 255 pixels: classic %ld, default %ld\n", fence_px,
           k255_classic, k255_default);
    ew_renderer_destroy(rc);

    /* 3: fences and moving things.  Exact texturing, so the holes of the
     * classic frame (key colour) fall where the default frame's are. */
    ew_set_subdivision(r, 1);
    ew_set_classic(r, 1);
    shot(r, cam, g_b, g_ids1, NULL);  /* classic: the fence region, opaque */
    ew_set_classic(r, 0);
    shot(r, cam, g_a, g_ids0, NULL);  /* default, no model */
    long region = 0, bars = 0;
    int front = -1;
    int *bar_count = calloc((size_t)w->numfaces, sizeof(int));
    for (int i = 0; i < N; i++) {
        int in = g_ids1[i] >= 0 && (w->faces[g_ids1[i]].flags & EW_SURF_FENCE);
        region += in;
        if (in && g_ids0[i] == g_ids1[i]) {  /* the front face: the fence face with the most bars */
            bars++;
            if (++bar_count[g_ids1[i]] > (front >= 0 ? bar_count[front] : 0)) front = g_ids1[i];
        }
    }
    free(bar_count);
    CHECK(front >= 0 && bars > 0 && bars < region, "start view 3: fence region %ld, bars %ld", region, bars);
    if (front < 0) {
        ew_renderer_destroy(r);
        return;
    }
    /* The sign: the box of fence faces around the front face (letters and
     * the see-through box around them, against the wall). */
    float lo[3] = {1e9f, 1e9f, 1e9f}, hi[3] = {-1e9f, -1e9f, -1e9f}, c[3];
    face_centroid(w, &w->faces[front], c);
    for (int f = 0; f < w->numfaces; f++) {
        if (!(w->faces[f].flags & EW_SURF_FENCE)) continue;
        float fc[3];
        face_centroid(w, &w->faces[f], fc);
        if (fabsf(fc[0] - c[0]) > 40 || fabsf(fc[1] - c[1]) > 40 || fabsf(fc[2] - c[2]) > 40) continue;
        for (int i = 0; i < w->faces[f].numedges; i++)
            for (int k = 0; k < 3; k++) {
                float q = w->verts[ew_face_vertex(w, &w->faces[f], i)][k];
                if (q < lo[k]) lo[k] = q;
                if (q > hi[k]) hi[k] = q;
            }
    }
    /* along the ray through the box's centre on the front face's plane, to
     * the box's middle depth */
    float dir[3], mid[3];
    const ew_plane *pl = &w->planes[w->faces[front].plane];
    for (int k = 0; k < 3; k++) mid[k] = (lo[k] + hi[k]) / 2;
    float off = mid[0] * pl->normal[0] + mid[1] * pl->normal[1] + mid[2] * pl->normal[2] - pl->dist;
    for (int k = 0; k < 3; k++) c[k] = mid[k] - off * pl->normal[k], dir[k] = c[k] - cam->origin[k];
    float dn = dir[0] * pl->normal[0] + dir[1] * pl->normal[1] + dir[2] * pl->normal[2];
    float tmid = 1 + ((mid[0] - c[0]) * pl->normal[0] + (mid[1] - c[1]) * pl->normal[1] +
                      (mid[2] - c[2]) * pl->normal[2]) / dn;
    ew_error err;
    model_file spike, soldier;
    if (load_mdl("k_spike.mdl", &spike) == 0 && load_mdl("soldier.mdl", &soldier) == 0) {
        ew_scene *s = ew_scene_create(w, &err);
        CHECK(s != NULL, "%s", err.msg);
        int ms = ew_scene_load_model(s, "progs/k_spike.mdl", spike.data, spike.size, &err);
        CHECK(ms >= 0, "%s", err.msg);
        float org[3], zero[3] = {0, 0, 0};
        for (int k = 0; k < 3; k++) {
            org[k] = cam->origin[k] + tmid * dir[k] - (spike.lo[k] + spike.hi[k]) / 2;
            CHECK(org[k] + spike.lo[k] > lo[k] && org[k] + spike.hi[k] < hi[k],
                  "the spike fits in the sign's box (axis %d: %.1f..%.1f in %.1f..%.1f)", k, org[k] + spike.lo[k],
                  org[k] + spike.hi[k], lo[k], hi[k]);
        }
        CHECK(ew_scene_add_entity(s, ms, org, zero, 0, 0) >= 0, "add spike");
        ew_set_scene(r, s);
        ew_set_classic(r, 1);
        shot(r, cam, g_c, NULL, NULL);
        long classic_changed = diff(g_b, g_c);
        CHECK(classic_changed == 0, "behind the fence, classic (opaque fence) changed %ld pixels", classic_changed);
        ew_set_classic(r, 0);
        shot(r, cam, g_c, NULL, &st);
        long changed = 0, in_holes = 0, on_bars = 0, outside = 0;
        for (int i = 0; i < N; i++) {
            if (g_a[i] == g_c[i]) continue;
            int in = g_ids1[i] >= 0 && (w->faces[g_ids1[i]].flags & EW_SURF_FENCE);
            int bar = in && g_ids0[i] == g_ids1[i];
            changed++;
            on_bars += bar, in_holes += in && !bar, outside += !in;
        }
        CHECK(changed > 0 && in_holes == changed && on_bars == 0 && outside == 0 && st.alias_pixels > 0,
              "model behind the fence: %ld changed, %ld in holes, %ld on bars, %ld outside", changed, in_holes,
              on_bars, outside);
        printf("model behind the fence (start view 3, face %d %s): %ld pixels changed, all in holes: %ld, on bars "
               "%ld, outside %ld (fence region %ld px, bars %ld)\n",
               front, w->textures[w->texinfo[w->faces[front].texinfo].texture].name, changed, in_holes, on_bars,
               outside, region, bars);
        ew_scene_destroy(s);

        /* In front: a soldier half way along the ray hides the bars. */
        s = ew_scene_create(w, &err);
        int mo = ew_scene_load_model(s, "progs/soldier.mdl", soldier.data, soldier.size, &err);
        CHECK(mo >= 0, "%s", err.msg);
        for (int k = 0; k < 3; k++)
            org[k] = cam->origin[k] + 0.6f * dir[k] - (k == 2 ? (soldier.lo[2] + soldier.hi[2]) / 2 : 0);
        CHECK(ew_scene_add_entity(s, mo, org, zero, 0, 0) >= 0, "add soldier");
        ew_set_scene(r, s);
        shot(r, cam, g_c, NULL, &st);
        changed = on_bars = in_holes = 0;
        for (int i = 0; i < N; i++) {
            if (g_a[i] == g_c[i]) continue;
            int in = g_ids1[i] >= 0 && (w->faces[g_ids1[i]].flags & EW_SURF_FENCE);
            int bar = in && g_ids0[i] == g_ids1[i];
            changed++, on_bars += bar, in_holes += in && !bar;
        }
        CHECK(on_bars > bars / 4 && in_holes > 0, "model in front of the fence: %ld changed, %ld on bars of %ld",
              changed, on_bars, bars);
        printf("model in front of the fence: %ld pixels changed, %ld on bars (of %ld), %ld in holes\n", changed,
               on_bars, bars, in_holes);
        ew_set_scene(r, NULL);
        ew_scene_destroy(s);
    }
    free(spike.data), free(soldier.data);
    ew_renderer_destroy(r);
}

/* The fence key colour on e2m1 (2). */
static void e2m1_tests(ew_assets *a) {
    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(a->world, views);
    ew_renderer *r = make(a, 0);
    if (!r) return;
    long leaks = 0, fence = 0;
    for (int v = 0; v < nv; v++) {
        ew_error err;
        ew_stats st;
        shot(r, &views[v], g_a, NULL, &st);
        fence += st.fence_pixels;
        CHECK(ew_render_reference(r, &views[v], g_b, NULL, &err) == 0, "%s", err.msg);
        for (int i = 0; i < N; i++) leaks += g_a[i] == 255 && g_b[i] != 255;
    }
    CHECK(leaks == 0 && fence > 0, "e2m1: key colour 255 at %ld pixels where the reference has another; fence px %ld",
          leaks, fence);
    printf("e2m1 views %d: fence pixels %ld, key-255 leaks (default 16px vs reference) %ld\n", nv, fence, leaks);
    ew_renderer_destroy(r);
}

/* e4m1: translucent water (1, 3), classic (4), bad alpha (5), underwater (7). */
static void e4m1_tests(ew_assets *a) {
    const ew_world *w = a->world;
    ew_camera views[EW_MAX_VIEWS + 4];
    int nv = ew_benchmark_views(w, views);
    ew_renderer *r = make(a, 0), *rc = make(a, 1);
    if (!r || !rc) return;
    ew_camera wv;
    int wface = -1;
    int have_water = water_view(w, r, &wv, &wface);
    CHECK(have_water, "e4m1: no view through water found");
    if (have_water) views[nv++] = wv;
    ew_set_liquid_alpha(r, 0.5f);
    agreement("e4m1", a, r, views, nv);
    ew_stats st, stc;

    /* 4: classic */
    ew_set_classic(r, 1);
    for (int k = 0; k < 2; k++) {
        int v = k ? nv - 1 : 0;
        shot(r, &views[v], g_a, NULL, &st);
        shot(rc, &views[v], g_b, NULL, &stc);
        CHECK(diff(g_a, g_b) == 0 && st.seethrough_surfaces == 0 && st.translucent_pixels == 0,
              "e4m1 view %d classic: %ld px differ, translucent %ld", v, diff(g_a, g_b), st.translucent_pixels);
    }
    ew_set_classic(r, 0);
    if (!have_water) {
        ew_renderer_destroy(r), ew_renderer_destroy(rc);
        return;
    }
    printf("e4m1 water view: origin %.0f %.0f %.0f angles %.0f %.0f (face %d)\n", wv.origin[0], wv.origin[1],
           wv.origin[2], wv.angles[0], wv.angles[1], wface);

    /* 5: bad alpha values */
    ew_renderer *fresh = make(a, 0);
    shot(fresh, &wv, g_c, NULL, NULL);  /* the map's own alpha */
    ew_renderer_destroy(fresh);
    ew_set_liquid_alpha(r, 1);
    shot(r, &wv, g_d, NULL, &st);  /* opaque */
    CHECK(st.translucent_pixels == 0, "alpha 1: translucent %ld", st.translucent_pixels);
    const float bad[] = {NAN, -1, 7, INFINITY, -INFINITY};
    for (int b = 0; b < 5; b++) {
        ew_set_liquid_alpha(r, 0.5f);
        ew_set_liquid_alpha(r, bad[b]);
        CHECK(ew_render(r, &wv, &st) == 0, "alpha %g", bad[b]);
        const uint8_t *want = bad[b] > 1 ? g_d : g_c;  /* > 1: opaque; else the map's */
        CHECK(diff(ew_frame_pixels(r), want) == 0, "liquid alpha %g: %ld px differ from its fallback", bad[b],
              diff(ew_frame_pixels(r), want));
    }
    ew_set_liquid_alpha(r, 0.001f);  /* clamped up to the least opacity, still drawn */
    CHECK(ew_render(r, &wv, &st) == 0 && st.translucent_pixels > 0, "alpha 0.001: %ld", st.translucent_pixels);

    /* 3: a model under the water along the ray through the face's centre */
    model_file mf;
    if (load_mdl("armor.mdl", &mf) != 0) return;
    float c[3], org[3], zero[3] = {0, 0, 0};
    face_centroid(w, &w->faces[wface], c);
    int placed = 0;
    for (float depth = 24; depth <= 160 && !placed; depth += 8) {
        float t = 1 + depth / (wv.origin[2] - c[2]);  /* depth below the surface */
        for (int k = 0; k < 3; k++) org[k] = wv.origin[k] + t * (c[k] - wv.origin[k]);
        org[2] -= mf.hi[2] / 2;
        placed = 1;
        for (int corner = 0; corner < 8; corner++) {
            float p[3];
            for (int k = 0; k < 3; k++) p[k] = org[k] + ((corner >> k) & 1 ? mf.hi[k] : mf.lo[k]);
            placed &= contents_at(w, p) == EW_CONTENTS_WATER;
        }
    }
    CHECK(placed, "no place under the water for the model");
    ew_error err;
    ew_scene *s = ew_scene_create(w, &err);
    int m = ew_scene_load_model(s, "progs/armor.mdl", mf.data, mf.size, &err);
    CHECK(m >= 0 && ew_scene_add_entity(s, m, org, zero, 0, 0) >= 0, "%s", err.msg);
    static uint8_t n05[N], m05[N], n1[N], m1[N], m0[N];
    static int ids1[N];
    ew_set_liquid_alpha(r, 1);
    shot(r, &wv, n1, ids1, NULL);
    ew_set_liquid_alpha(r, 0.5f);
    shot(r, &wv, n05, NULL, NULL);
    ew_set_liquid_alpha(r, 0.01f);  /* the water nearly gone (1/16) */
    ew_set_scene(r, s);
    shot(r, &wv, m0, NULL, NULL);
    ew_set_liquid_alpha(r, 0.5f);
    shot(r, &wv, m05, NULL, &st);
    ew_set_liquid_alpha(r, 1);
    shot(r, &wv, m1, NULL, NULL);
    long hidden = diff(n1, m1), changed = 0, in_water = 0, tinted = 0;
    for (int i = 0; i < N; i++) {
        if (n05[i] == m05[i]) continue;
        changed++;
        in_water += ids1[i] >= 0 && (w->faces[ids1[i]].flags & EW_SURF_TURB);
        tinted += m05[i] != m0[i];
    }
    CHECK(hidden == 0, "opaque water: the model under it changed %ld px", hidden);
    CHECK(changed > 0 && in_water == changed && st.alias_pixels > 0, "alpha 0.5: model changed %ld px, %ld in water",
          changed, in_water);
    CHECK(tinted * 10 >= changed * 9, "alpha 0.5: only %ld of %ld model pixels differ from the model without water",
          tinted, changed);
    printf("model under water (e4m1, armor.mdl at %.0f %.0f %.0f): alpha 1 changed %ld px; alpha 0.5 changed %ld px, "
           "%ld in the water, %ld (%.1f%%) differ from the model seen through alpha 1/16\n",
           org[0], org[1], org[2], hidden, changed, in_water, tinted, 100.0 * tinted / (changed ? changed : 1));
    ew_set_scene(r, NULL);
    ew_scene_destroy(s);
    free(mf.data);

    /* 7: underwater: the eye where the model was */
    if (placed) {
        ew_camera uw = {{org[0], org[1], org[2] + mf.hi[2] / 2}, {0, wv.angles[1], 0}, 90, 0.5};
        CHECK(contents_at(w, uw.origin) == EW_CONTENTS_WATER, "eye not in water");
        shot(r, &uw, g_a, NULL, &st);
        CHECK(st.underwater == 1, "eye in water: underwater %d", st.underwater);
        ew_set_waterwarp(r, 0);
        shot(r, &uw, g_b, NULL, &stc);
        ew_set_waterwarp(r, 1);
        long d = diff(g_a, g_b);
        CHECK(d > N / 2 && stc.underwater == 0, "underwater: warp changes %ld px, no-warp underwater %d", d,
              stc.underwater);
        shot(r, &wv, NULL, NULL, &st);
        CHECK(st.underwater == 0, "above water: underwater %d", st.underwater);
        uw.time = 1.0;
        shot(r, &uw, g_c, NULL, NULL);
        printf("underwater (e4m1 at %.0f %.0f %.0f): underwater=1, warp+tint changes %.1f%% of pixels; the warp "
               "drifts with time: %ld px differ from t+0.5 s\n",
               uw.origin[0], uw.origin[1], uw.origin[2], 100.0 * d / N, diff(g_a, g_c));
        CHECK(diff(g_a, g_c) > 0, "warp does not drift with time");
    }
    ew_renderer_destroy(r), ew_renderer_destroy(rc);
}

/* lqdm7: fog (1, 5, 6). */
static void lqdm7_tests(ew_assets *a) {
    const ew_world *w = a->world;
    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(w, views);
    ew_renderer *r = make(a, 0);
    if (!r) return;
    const float fog[3] = {0.45f, 0.42f, 0.38f};
    ew_set_fog(r, 0.25f, fog[0], fog[1], fog[2]);
    agreement("lqdm7", a, r, views, nv);

    /* 6: far pixels move towards the fog colour more than near ones */
    double near_sum = 0, far_sum = 0;
    long near_n = 0, far_n = 0;
    for (int v = 0; v < nv; v += 4) {
        static float z[N];
        ew_set_fog(r, 0, 0, 0, 0);
        shot(r, &views[v], g_a, g_ids0, NULL);
        memcpy(z, ew_frame_zbuffer(r), sizeof z);
        ew_set_fog(r, 0.25f, fog[0], fog[1], fog[2]);
        shot(r, &views[v], g_b, NULL, NULL);
        for (int i = 0; i < N; i++) {
            if (z[i] <= 0 || g_ids0[i] < 0 || (w->faces[g_ids0[i]].flags & EW_SURF_SKY)) continue;
            double dist = 1 / z[i], moved = pal_dist(a->palette, g_a[i], fog) - pal_dist(a->palette, g_b[i], fog);
            if (dist < 96) near_sum += moved, near_n++;
            if (dist > 384) far_sum += moved, far_n++;
        }
    }
    CHECK(near_n > 1000 && far_n > 1000, "near %ld far %ld pixels", near_n, far_n);
    double nm = near_sum / (near_n ? near_n : 1), fm = far_sum / (far_n ? far_n : 1);
    CHECK(fm > nm + 10, "fog: far pixels moved %.1f towards the fog colour, near ones %.1f", fm, nm);
    printf("fog (density 0.25): near pixels (z < 96, %ld) moved %.1f towards the fog colour, far ones (z > 384, %ld) "
           "%.1f (RGB distance)\n",
           near_n, nm, far_n, fm);

    /* 5: bad fog values: the map's (a fresh renderer's frame) */
    ew_renderer *fresh = make(a, 0);
    shot(fresh, &views[0], g_a, NULL, NULL);
    ew_renderer_destroy(fresh);
    const float bad[] = {NAN, -1, INFINITY, 1e7f};
    for (int b = 0; b < 4; b++) {
        ew_stats st;
        ew_set_fog(r, 0.25f, fog[0], fog[1], fog[2]);
        ew_set_fog(r, bad[b], 1, 1, 1);
        CHECK(ew_render(r, &views[0], &st) == 0, "fog %g", bad[b]);
        CHECK(diff(ew_frame_pixels(r), g_a) == 0, "fog density %g: %ld px differ from the map's fog", bad[b],
              diff(ew_frame_pixels(r), g_a));
    }
    /* bad colours clamp to 0..1 */
    ew_set_fog(r, 0.25f, 0, 0, 1);
    shot(r, &views[0], g_b, NULL, NULL);
    ew_set_fog(r, 0.25f, NAN, -3, 9);
    shot(r, &views[0], g_c, NULL, NULL);
    CHECK(diff(g_b, g_c) == 0 && diff(g_a, g_b) > N / 4, "fog colour (NaN,-3,9) vs (0,0,1): %ld px differ",
          diff(g_b, g_c));
    ew_renderer_destroy(r);
}

int main(void) {
    if (!ew_t_need_shared("data/librequake/maps/start.bsp")) return ew_t_finish();
    g_ids0 = malloc(sizeof(int) * N), g_ids1 = malloc(sizeof(int) * N);
    g_a = malloc(N), g_b = malloc(N), g_c = malloc(N), g_d = malloc(N);
    const char *maps[] = {"start", "e2m1", "e4m1", "lqdm7"};
    void (*run[])(ew_assets *) = {start_tests, e2m1_tests, e4m1_tests, lqdm7_tests};
    for (int i = 0; i < 4; i++) {
        ew_assets *a = ew_t_load_map(maps[i]);
        if (!a) continue;
        run[i](a);
        ew_assets_destroy(a);
    }
    free(g_ids0), free(g_ids1), free(g_a), free(g_b), free(g_c), free(g_d);
    return ew_t_finish();
}
