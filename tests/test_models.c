/* Model files and moving things in a real frame:
 *   - every .mdl and .spr in progs/ of ../shared/data/librequake loads;
 *   - broken MDL and SPR files (truncated at every length, absurd counts,
 *     bad indices, texture coordinates off the skin, bad intervals) give
 *     one error line and no crash;
 *   - e1m1, view 0: soldier.mdl drawn 100 units ahead with each rasterizer,
 *     s_explod.spr and a particle field change pixels, respect the world's
 *     z-buffer and count their stats; the light under the soldier;
 *   - (printed, not asserted) the speed of affine vs subdivision on 200
 *     small soldiers. */
#include "util.h"
#include "renderer.h"
#include "ew_util.h"
#include "raster/alias.h"
#include "model_fixtures.h"

#include <dirent.h>
#include <stdlib.h>
#include <string.h>

/* Every prefix of a good file (a truncation at every length): how many the
 * loader refuses with an error line that names the file. */
typedef void *(*load_fn)(const uint8_t *, size_t, const char *, ew_error *);
static void *mdl_from(const uint8_t *d, size_t n, const char *name, ew_error *e) { return ew_mdl_load(d, n, name, e); }
static void *spr_from(const uint8_t *d, size_t n, const char *name, ew_error *e) { return ew_spr_load(d, n, name, e); }
static void free_mdl(void *m) { ew_mdl_free(m); }
static void free_spr(void *m) { ew_spr_free(m); }

static int refused_truncations(const uint8_t *good, size_t size, const char *name, load_fn load,
                               void (*release)(void *)) {
    char prefix[64];
    snprintf(prefix, sizeof prefix, "%s: ", name);
    int refused = 0;
    for (size_t n = 0; n < size; n++) {
        uint8_t *d = malloc(n ? n : 1);
        memcpy(d, good, n);
        ew_error err = {""};
        void *t = load(d, n, name, &err);
        refused += t == NULL && strncmp(err.msg, prefix, strlen(prefix)) == 0;
        release(t);
        free(d);
    }
    return refused;
}

static int load_file(const char *path, uint8_t **data, size_t *size) {
    ew_error err;
    int rc = ew_read_file(path, data, size, &err);
    CHECK(rc == 0, "%s", err.msg);
    return rc;
}

static void test_load_all(void) {
    const char *dir = ew_t_shared("data/librequake/progs");
    DIR *d = opendir(dir);
    CHECK(d != NULL, "cannot open %s", dir);
    if (!d) return;
    int mdls = 0, sprs = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        size_t n = strlen(e->d_name);
        if (n < 5) continue;
        const char *ext = e->d_name + n - 4;
        int is_mdl = !strcmp(ext, ".mdl"), is_spr = !strcmp(ext, ".spr");
        if (!is_mdl && !is_spr) continue;
        char path[1200];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        uint8_t *data;
        size_t size;
        if (load_file(path, &data, &size)) continue;
        ew_error err = {{0}};
        if (is_mdl) {
            ew_mdl *m = ew_mdl_load(data, size, e->d_name, &err);
            CHECK(m != NULL, "%s", err.msg);
            if (m) {
                CHECK(m->numposes >= m->numframes && m->numskinimages >= m->numskins, "%s: counts", e->d_name);
                /* every normal is a unit vector; bounds hold the vertices */
                int ok = 1;
                for (int p = 0; p < m->numposes && ok; p++)
                    for (int v = 0; v < m->numverts; v++) {
                        const float *nv = m->poses[p].normals[v];
                        float l = nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2];
                        if (l < 0.98f || l > 1.02f) ok = 0;
                    }
                CHECK(ok, "%s: normals not unit length", e->d_name);
                mdls++;
            }
            ew_mdl_free(m);
        } else {
            ew_spr *s = ew_spr_load(data, size, e->d_name, &err);
            CHECK(s != NULL, "%s", err.msg);
            if (s) sprs++;
            ew_spr_free(s);
        }
        free(data);
    }
    closedir(d);
    CHECK(mdls >= 70 && sprs >= 4, "loaded %d models and %d sprites", mdls, sprs);
    printf("loaded %d .mdl and %d .spr files\n", mdls, sprs);
}

static void put32(uint8_t *p, int32_t v) {
    p[0] = (uint8_t)v, p[1] = (uint8_t)(v >> 8), p[2] = (uint8_t)(v >> 16), p[3] = (uint8_t)(v >> 24);
}
static void putf(uint8_t *p, float f) {
    int32_t v;
    memcpy(&v, &f, 4);
    put32(p, v);
}

/* Loads a patched copy of a good file (at `at`, an int or a float) with
 * `load`, as file `name`; expects a refusal in one line that names the
 * file and mentions `want`. */
static void expect_error(load_fn load, void (*release)(void *), const char *name, const uint8_t *good,
                         size_t size, size_t at, int32_t value, int is_float, float fvalue, const char *want) {
    uint8_t *d = malloc(size);
    memcpy(d, good, size);
    if (is_float)
        putf(d + at, fvalue);
    else
        put32(d + at, value);
    ew_error err = {{0}};
    void *m = load(d, size, name, &err);
    size_t nlen = strlen(name);
    CHECK(m == NULL, "%s: patch at %zu accepted (want '%s')", name, at, want);
    CHECK(strncmp(err.msg, name, nlen) == 0 && strncmp(err.msg + nlen, ": ", 2) == 0 && strstr(err.msg, want) &&
              !strchr(err.msg, '\n'),
          "%s: patch at %zu: error '%s' (want '%s')", name, at, err.msg, want);
    if (m) release(m);
    free(d);
}

static void expect_mdl_error(const uint8_t *good, size_t size, size_t at, int32_t value, int is_float,
                             float fvalue, const char *want) {
    expect_error(mdl_from, free_mdl, "bad.mdl", good, size, at, value, is_float, fvalue, want);
}

static void test_bad_mdl(void) {
    fx_mesh mesh = fx_icosphere(0);  /* 12 vertices, 20 triangles */
    fx_mdl_opts o = {8, 8, 2, 2, 10};
    size_t size;
    uint8_t *good = fx_mdl(&mesh, &o, &size);
    ew_error err = {{0}};
    ew_mdl *m = ew_mdl_load(good, size, "good.mdl", &err);
    CHECK(m != NULL, "%s", err.msg);
    if (m) {
        CHECK(m->numskins == 1 && m->numskinimages == 2 && m->numframes == 1 && m->numposes == 2 &&
                  m->numverts == 12 && m->numtris == 20,
              "counts %d %d %d %d", m->numskins, m->numskinimages, m->numframes, m->numposes);
        CHECK(ew_mdl_anim_pick(&m->frames[0], 0.05) == 0 && ew_mdl_anim_pick(&m->frames[0], 0.15) == 1 &&
                  ew_mdl_anim_pick(&m->frames[0], 0.25) == 0 && ew_mdl_anim_pick(&m->skins[0], 0.15) == 1,
              "group animation by time");
        CHECK(!strcmp(m->poses[1].name, "pose1"), "pose name '%s'", m->poses[1].name);
    }
    ew_mdl_free(m);

    /* Truncated at every length: an error line, never a crash. */
    int refused = refused_truncations(good, size, "cut.mdl", mdl_from, free_mdl);
    CHECK(refused == (int)size, "%d of %zu truncations refused with a message", refused, size);

    /* Layout of the fixture: header 84; skin group type, n, 2 intervals,
     * 2 images of 64; texture coordinates; triangles; frame group. */
    size_t skins = 84, st = skins + 16 + 128, tris = st + 12 * 12, frames = tris + 20 * 16;
    expect_mdl_error(good, size, 4, 7, 0, 0, "version 7");
    expect_mdl_error(good, size, 48, -1, 0, 0, "skins");
    expect_mdl_error(good, size, 48, 1000000000, 0, 0, "skins");
    expect_mdl_error(good, size, 52, 0, 0, 0, "skin size");
    expect_mdl_error(good, size, 56, 100000, 0, 0, "skin size");
    expect_mdl_error(good, size, 60, 2, 0, 0, "vertices");
    expect_mdl_error(good, size, 60, 1 << 30, 0, 0, "vertices");
    expect_mdl_error(good, size, 60, 13, 0, 0, "");  /* one vertex more than the file holds */
    expect_mdl_error(good, size, 64, 0, 0, 0, "triangles");
    expect_mdl_error(good, size, 64, 2000000000, 0, 0, "triangles");
    expect_mdl_error(good, size, 68, 0, 0, 0, "frames");
    expect_mdl_error(good, size, 68, -5, 0, 0, "frames");
    expect_mdl_error(good, size, 68, 2, 0, 0, "truncated");
    expect_mdl_error(good, size, 8, 0, 1, NAN, "scale");
    expect_mdl_error(good, size, skins, 5, 0, 0, "type 5");
    expect_mdl_error(good, size, skins + 4, 1000000000, 0, 0, "skin group 0");
    expect_mdl_error(good, size, skins + 4, 0, 0, 0, "skin group 0");
    expect_mdl_error(good, size, skins + 8, 0, 1, -0.1f, "interval 0");
    expect_mdl_error(good, size, skins + 12, 0, 1, NAN, "interval 1");
    expect_mdl_error(good, size, st + 4, 9, 0, 0, "texture coordinates");   /* s beyond 8 */
    expect_mdl_error(good, size, st + 8, -1, 0, 0, "texture coordinates");  /* t negative */
    expect_mdl_error(good, size, tris + 4, 12, 0, 0, "uses vertex 12");
    expect_mdl_error(good, size, tris + 16 * 7 + 12, -1, 0, 0, "triangle 7 uses vertex -1");
    expect_mdl_error(good, size, frames + 4, 1000000, 0, 0, "frame group 0");
    expect_mdl_error(good, size, frames + 4, -2, 0, 0, "frame group 0");
    expect_mdl_error(good, size, frames + 16, 0, 1, 0.0f, "interval 0");
    expect_mdl_error(good, size, frames + 20, 0, 1, -1.0f, "interval 1");
    memcpy(good, "IDPX", 4);
    CHECK(ew_mdl_load(good, size, "x.mdl", &err) == NULL && strstr(err.msg, "IDPO"), "%s", err.msg);
    CHECK(ew_mdl_load(NULL, 0, "x.mdl", &err) == NULL, "NULL data");
    free(good);
    free(mesh.pos), free(mesh.tri);
}

static void expect_spr_error(const uint8_t *good, size_t size, size_t at, int32_t value, int is_float,
                             float fvalue, const char *want) {
    expect_error(spr_from, free_spr, "bad.spr", good, size, at, value, is_float, fvalue, want);
}

static void test_bad_spr(void) {
    size_t size;
    uint8_t *good = fx_spr(2, 8, 6, 2, 3, &size);
    ew_error err = {{0}};
    ew_spr *s = ew_spr_load(good, size, "good.spr", &err);
    CHECK(s != NULL, "%s", err.msg);
    if (s) {
        CHECK(s->numframes == 3 && s->numpics == 5 && s->type == 2, "counts %d %d", s->numframes, s->numpics);
        CHECK(ew_spr_pick(s, 2, 0.07) == &s->pics[3] && ew_spr_pick(s, 2, 0.16) == &s->pics[2] &&
                  ew_spr_pick(s, 99, 0) == &s->pics[2] && ew_spr_pick(s, -1, 0) == &s->pics[0],
              "frame picking");
    }
    ew_spr_free(s);
    int refused = refused_truncations(good, size, "cut.spr", spr_from, free_spr);
    CHECK(refused == (int)size, "%d of %zu truncations refused with a message", refused, size);
    /* header 36; frame 0: type 4, origin 8, size 8, 48 pixels */
    size_t f0 = 36, f2 = 36 + 2 * (4 + 16 + 48);
    expect_spr_error(good, size, 4, 2, 0, 0, "version 2");
    expect_spr_error(good, size, 8, 9, 0, 0, "type 9");
    expect_spr_error(good, size, 24, 0, 0, 0, "frames");
    expect_spr_error(good, size, 24, 1 << 30, 0, 0, "frames");
    expect_spr_error(good, size, 24, 4, 0, 0, "truncated");
    expect_spr_error(good, size, 16, -3, 0, 0, "maximum size");
    expect_spr_error(good, size, f0, 3, 0, 0, "type 3");
    expect_spr_error(good, size, f0 + 12, 0, 0, 0, "picture size");
    expect_spr_error(good, size, f0 + 16, 100000, 0, 0, "picture size");
    expect_spr_error(good, size, f0 + 16, 7, 0, 0, "");
    expect_spr_error(good, size, f0 + 4, 1 << 30, 0, 0, "origin");
    expect_spr_error(good, size, f2 + 4, 1 << 30, 0, 0, "frame group 2");
    expect_spr_error(good, size, f2 + 4, 0, 0, 0, "frame group 2");
    expect_spr_error(good, size, f2 + 8, 0, 1, -0.5f, "interval 0");
    expect_spr_error(good, size, f2 + 16, 0, 1, INFINITY, "interval 2");
    free(good);
}

/* ---- in a real frame ------------------------------------------------------ */

typedef struct snapshot {
    uint8_t *frame;
    float   *zbuf;
} snapshot;

static void snap_take(ew_renderer *r, snapshot *s) {
    size_t n = (size_t)r->f.target.width * r->f.target.height;
    memcpy(s->frame, r->f.target.pixels, n);
    memcpy(s->zbuf, ew_frame_zbuffer(r), n * sizeof(float));  /* the whole frame's 1/z */
}
static void snap_restore(ew_renderer *r, const snapshot *s) {
    size_t n = (size_t)r->f.target.width * r->f.target.height;
    memcpy(r->f.target.pixels, s->frame, n);
    memcpy(r->f.target.zbuf, s->zbuf, n * sizeof(float));
}

/* Pixels whose z changed; fails if any got farther (the z test broken). */
static long changed_pixels(const ew_renderer *r, const snapshot *s, long *farther, long *colour_only) {
    long n = 0;
    *farther = 0, *colour_only = 0;
    for (long i = 0; i < (long)r->f.target.width * r->f.target.height; i++) {
        if (r->f.target.zbuf[i] != s->zbuf[i]) {
            n++;
            if (r->f.target.zbuf[i] < s->zbuf[i]) (*farther)++;
        } else if (r->f.target.pixels[i] != s->frame[i]) {
            (*colour_only)++;
        }
    }
    return n;
}

/* A model file from ../shared through the given loader (CHECKed). */
static void *load_shared(const char *rel, load_fn load) {
    uint8_t *data;
    size_t size;
    if (load_file(ew_t_shared(rel), &data, &size)) return NULL;
    ew_error err;
    void *m = load(data, size, rel, &err);
    CHECK(m != NULL, "%s", err.msg);
    free(data);
    return m;
}

static ew_mdl *load_mdl(const char *rel) { return load_shared(rel, mdl_from); }
static ew_spr *load_spr(const char *rel) { return load_shared(rel, spr_from); }

static void measure(ew_renderer *r, const ew_camera *cam, const ew_mdl *soldier) {
    /* 200 soldiers 450..900 units ahead (about 40..20 pixels tall at 640x480),
     * spread over the view; the z-buffer cleared so every triangle draws. */
    enum { N = 200, REPS = 30 };
    ew_model_pose poses[N];
    uint32_t seed = 99;
    ew_view_setup(&r->f.view, cam, r->f.target.width, r->f.target.height);
    const ew_view *v = &r->f.view;
    for (int i = 0; i < N; i++) {
        seed = seed * 1664525u + 1013904223u;
        float z = 450 + (float)(seed >> 8) / 16777216.0f * 450;
        seed = seed * 1664525u + 1013904223u;
        float x = ((float)(seed >> 8) / 16777216.0f - 0.5f) * 1.4f * z;
        seed = seed * 1664525u + 1013904223u;
        float y = ((float)(seed >> 8) / 16777216.0f - 0.5f) * 0.9f * z;
        ew_model_pose *p = &poses[i];
        memset(p, 0, sizeof *p);
        for (int k = 0; k < 3; k++) p->origin[k] = v->origin[k] + v->forward[k] * z + v->right[k] * x + v->up[k] * y;
        p->angles[1] = (float)(seed % 360);
        p->frame = (int)(seed % (uint32_t)soldier->numframes);
        p->ambient = 100, p->shade = 80;
    }
    const char *names[3] = {"affine", "subdivision", "auto (40 px)"};
    int modes[3] = {EW_ALIAS_AFFINE, EW_ALIAS_SUBDIV, EW_ALIAS_AUTO};
    double ms[3] = {1e30, 1e30, 1e30};
    ew_stats st[3];
    /* Interleaved, best of REPS each: other work on the machine only adds. */
    for (int rep = 0; rep < REPS; rep++) {
        for (int mi = 0; mi < 3; mi++) {
            r->f.cfg.alias_raster = modes[mi];
            r->f.cfg.alias_threshold = 40;
            memset(r->f.target.zbuf, 0, sizeof(float) * (size_t)r->f.target.width * r->f.target.height);
            memset(&r->f.stats, 0, sizeof r->f.stats);
            double t0 = ew_now_ms();
            for (int i = 0; i < N; i++) ew_draw_alias(r, soldier, &poses[i]);
            double t = ew_now_ms() - t0;
            if (t < ms[mi]) ms[mi] = t;
            st[mi] = r->f.stats;
        }
    }
    for (int mi = 0; mi < 3; mi++) {
        printf("measure: 200 soldiers (20-40 px tall, 640x480), %-12s %7.3f ms/frame (%.2f us/model): "
               "%d triangles (%d subdivided), %ld pixels\n",
               names[mi], ms[mi], ms[mi] * 1000 / N, st[mi].alias_tris, st[mi].alias_tris_subdiv,
               st[mi].alias_pixels);
        CHECK(st[mi].alias_tris > 0, "%s drew nothing", names[mi]);
    }
    CHECK(st[1].alias_tris_subdiv == st[1].alias_tris, "not all subdivided");
    printf("measure: affine / subdivision time = %.2f\n", ms[0] / ms[1]);
}

static void test_in_frame(void) {
    if (!ew_t_need_shared("data/librequake/maps/e1m1.bsp")) return;
    ew_error err;
    ew_assets *a = ew_assets_create(ew_t_shared("data/librequake/maps/e1m1.bsp"), NULL, &err);
    CHECK(a != NULL, "%s", err.msg);
    if (!a) return;
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){ .world = a->world, .palette = a->palette,
            .colormap = a->colormap, .width = 640, .height = 480, .threads = 1 }, &err);
    CHECK(r != NULL, "%s", err.msg);
    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(a->world, views);
    CHECK(nv > 0, "no views");
    ew_mdl *soldier = load_mdl("data/librequake/progs/soldier.mdl");
    ew_spr *explod = load_spr("data/librequake/progs/s_explod.spr");
    if (!r || nv <= 0 || !soldier || !explod) goto done;

    ew_camera cam = views[0];
    CHECK(ew_render(r, &cam, NULL) == 0, "render");
    size_t npx = (size_t)r->f.target.width * r->f.target.height;
    snapshot world = {malloc(npx), malloc(npx * sizeof(float))};
    snap_take(r, &world);
    const ew_view *v = &r->f.view;
    /* 100 units ahead, or nearer if a wall is closer (as seen at the centre). */
    float zc = world.zbuf[(r->f.target.height / 2) * r->f.target.width + r->f.target.width / 2];
    float dist = 100;
    if (zc > 0 && 0.6f / zc < dist) dist = 0.6f / zc;
    printf("e1m1 view 0: wall %.0f units ahead at the centre, models at %.0f\n", zc > 0 ? 1 / zc : -1.0, dist);

    ew_model_pose p;
    memset(&p, 0, sizeof p);
    for (int k = 0; k < 3; k++) p.origin[k] = v->origin[k] + v->forward[k] * dist;
    p.origin[2] -= 10;
    p.angles[1] = cam.angles[1] + 180;  /* facing the camera */
    int light = ew_light_point(&r->f, p.origin);
    CHECK(light >= 0 && light <= 255, "light %d", light);
    p.ambient = light < 24 ? 24 : light, p.shade = 64;

    int modes[3] = {EW_ALIAS_AFFINE, EW_ALIAS_SUBDIV, EW_ALIAS_AUTO};
    const char *names[3] = {"affine", "subdivision", "auto"};
    for (int mi = 0; mi < 3; mi++) {
        snap_restore(r, &world);
        memset(&r->f.stats, 0, sizeof r->f.stats);
        ew_set_alias_raster(r, modes[mi], 40);
        CHECK(ew_draw_alias(r, soldier, &p) == 1, "%s: soldier culled", names[mi]);
        long farther, colour_only;
        long n = changed_pixels(r, &world, &farther, &colour_only);
        CHECK(n > 500, "%s: only %ld pixels changed", names[mi], n);
        CHECK(farther == 0 && colour_only == 0, "%s: %ld pixels behind the world, %ld without z", names[mi], farther,
              colour_only);
        CHECK(r->f.stats.alias_tris > 100 && r->f.stats.alias_tris < soldier->numtris, "%s: %d triangles", names[mi],
              r->f.stats.alias_tris);
        CHECK(r->f.stats.alias_pixels >= n, "%s: %ld counted, %ld changed", names[mi], r->f.stats.alias_pixels, n);
        if (modes[mi] == EW_ALIAS_SUBDIV)
            CHECK(r->f.stats.alias_tris_subdiv == r->f.stats.alias_tris && r->f.stats.alias_pixels == n,
                  "subdivision: %d of %d, %ld counted, %ld changed", r->f.stats.alias_tris_subdiv, r->f.stats.alias_tris,
                  r->f.stats.alias_pixels, n);
        else
            CHECK(r->f.stats.alias_tris_subdiv == 0, "%s: %d subdivided", names[mi], r->f.stats.alias_tris_subdiv);
        printf("soldier %s: %d triangles, %ld pixels\n", names[mi], r->f.stats.alias_tris, n);
        if (mi == 0 && getenv("EW_MODELS_PNG")) {
            ew_write_png(getenv("EW_MODELS_PNG"), r->f.target.pixels, r->f.target.width, r->f.target.height, a->palette, &err);
        }
    }
    /* The same soldier behind the camera: culled, nothing changes. */
    snap_restore(r, &world);
    ew_model_pose behind = p;
    for (int k = 0; k < 3; k++) behind.origin[k] = v->origin[k] - v->forward[k] * 100;
    CHECK(ew_draw_alias(r, soldier, &behind) == 0, "soldier behind the camera drawn");
    CHECK(memcmp(r->f.target.pixels, world.frame, npx) == 0, "culled soldier changed pixels");

    /* The explosion sprite, a few frames. */
    for (int f = 0; f < explod->numframes; f += 2) {
        snap_restore(r, &world);
        memset(&r->f.stats, 0, sizeof r->f.stats);
        ew_model_pose sp = p;
        sp.frame = f;
        CHECK(ew_draw_sprite(r, explod, &sp) == 1, "explosion frame %d culled", f);
        long farther, colour_only;
        long n = changed_pixels(r, &world, &farther, &colour_only);
        CHECK(n > 50 && farther == 0 && colour_only == 0 && r->f.stats.alias_pixels == n,
              "explosion frame %d: %ld changed, %ld farther, %ld counted", f, n, farther, r->f.stats.alias_pixels);
    }
    /* A particle field. */
    {
        snap_restore(r, &world);
        memset(&r->f.stats, 0, sizeof r->f.stats);
        ew_particle parts[300];
        ew_particle_field(parts, 300, p.origin, 16, 1234);
        ew_draw_particles(r, parts, 300);
        long farther, colour_only;
        long n = changed_pixels(r, &world, &farther, &colour_only);
        CHECK(r->f.stats.particles == 300 && n > 300 && farther == 0 && colour_only == 0,
              "particles: %d drawn, %ld changed, %ld farther", r->f.stats.particles, n, farther);
    }
    /* Light under the soldier: style scaling, and nothing hit outside. */
    {
        ew_set_lightstyle(r, 0, 256);  /* the light map as compiled (the game's 'm' is 264) */
        int base = ew_light_point(&r->f, p.origin);
        ew_set_lightstyle(r, 0, 512);
        int twice = ew_light_point(&r->f, p.origin);
        ew_set_lightstyle(r, 0, 0);
        int dark = ew_light_point(&r->f, p.origin);
        ew_set_lightstyle(r, 0, 256);
        printf("light under the soldier: %d (style 0 doubled: %d, off: %d)\n", base, twice, dark);
        CHECK(base > 0 && base <= 255, "light %d", base);
        CHECK(twice >= base && (base > 127 || twice >= 2 * base - 2), "doubled style: %d from %d", twice, base);
        CHECK(dark <= base, "style off: %d from %d", dark, base);
        float outside[3] = {1e5f, 1e5f, 1e5f};
        CHECK(ew_light_point(&r->f, outside) == 0, "light outside the map");
        /* every view's eye has a floor under it somewhere within 2048 */
        int lit = 0;
        for (int i = 0; i < nv; i++) lit += ew_light_point(&r->f, views[i].origin) > 0;
        CHECK(lit * 2 >= nv, "only %d of %d views have light under them", lit, nv);
    }
    measure(r, &cam, soldier);
    free(world.frame), free(world.zbuf);
done:
    ew_mdl_free(soldier);
    ew_spr_free(explod);
    ew_renderer_destroy(r);
    ew_assets_destroy(a);
}

int main(void) {
    test_load_all();
    test_bad_mdl();
    test_bad_spr();
    test_in_frame();
    return ew_t_finish();
}
