/* The public header as an application sees it (edgewise.h alone): the
 * version, the renderer description and its defaults and refusals, the
 * create/destroy pairs and the palette-to-RGBA helpers. */
#define _POSIX_C_SOURCE 200809L
#include "edgewise.h"
#include "util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#ifdef EDGEWISE_LAB_H
#error "edgewise.h must not pull in edgewise_lab.h"
#endif
#ifndef EW_PROJECT_VERSION
#error "CMakeLists.txt passes EW_PROJECT_VERSION (project(edgewise VERSION ...))"
#endif

#define STR2(x) #x
#define STR(x) STR2(x)

static void test_version(void) {
    CHECK(strcmp(EW_VERSION, EW_PROJECT_VERSION) == 0,
          "edgewise.h says %s, CMakeLists.txt's project() %s", EW_VERSION, EW_PROJECT_VERSION);
    const char *parts = STR(EW_VERSION_MAJOR) "." STR(EW_VERSION_MINOR) "." STR(EW_VERSION_PATCH);
    CHECK(strcmp(parts, EW_VERSION) == 0, "EW_VERSION_MAJOR/MINOR/PATCH give %s, EW_VERSION %s",
          parts, EW_VERSION);
    CHECK(ew_version() && strcmp(ew_version(), EW_VERSION) == 0, "ew_version() = %s",
          ew_version() ? ew_version() : "(null)");

    /* `edgewise --version` prints the library's version. */
    if (!getenv("EW_CLI")) return;
    char dir[1024];
    const char *t = getenv("TMPDIR");
    snprintf(dir, sizeof dir, "%s/ew_api_XXXXXX", t && *t ? t : "/tmp");
    if (!mkdtemp(dir)) {
        CHECK(0, "mkdtemp %s", dir);
        return;
    }
    static ew_t_run r;
    const char *args[] = { "--version", NULL };
    ew_t_run_cli(&r, dir, args);
    char want[64];
    snprintf(want, sizeof want, "edgewise %s\n", EW_VERSION);
    CHECK(r.status == 0 && strcmp(r.out, want) == 0, "--version printed '%s'", r.out);
    char path[1100];
    snprintf(path, sizeof path, "%s/stdout.txt", dir), remove(path);
    snprintf(path, sizeof path, "%s/stderr.txt", dir), remove(path);
    rmdir(dir);
}

static void test_rgba(void) {
    uint8_t pal[768];
    for (int i = 0; i < 768; i++) pal[i] = (uint8_t)(i * 7 + 3);
    uint32_t table[256];
    ew_palette_rgba(pal, table);
    int bad = 0;
    for (int i = 0; i < 256; i++) {
        uint8_t b[4];
        memcpy(b, &table[i], 4);
        bad += b[0] != pal[i * 3] || b[1] != pal[i * 3 + 1] || b[2] != pal[i * 3 + 2] || b[3] != 255;
    }
    CHECK(bad == 0, "%d palette entries not R,G,B,255 in memory", bad);

    uint8_t px[300];
    for (int i = 0; i < 300; i++) px[i] = (uint8_t)(i * 13);
    uint32_t out[301];
    out[300] = 0xdeadbeef;
    ew_pixels_to_rgba(px, 300, table, out);
    bad = 0;
    for (int i = 0; i < 300; i++) {
        uint8_t b[4];
        memcpy(b, &out[i], 4);
        bad += out[i] != table[px[i]] || b[0] != pal[px[i] * 3] || b[3] != 255;
    }
    CHECK(bad == 0 && out[300] == 0xdeadbeef, "%d pixels expanded wrongly (or past n)", bad);
    ew_pixels_to_rgba(px, 0, table, out);  /* nothing */
}

/* One line, naming what was wrong. */
static int refused(const ew_renderer_desc *d, const char *word) {
    ew_error err;
    strcpy(err.msg, "");
    ew_renderer *r = ew_renderer_create(d, &err);
    int ok = r == NULL && err.msg[0] && !strchr(err.msg, '\n') && strstr(err.msg, word);
    if (!ok) fprintf(stderr, "  desc not refused as '%s': '%s'\n", word, err.msg);
    ew_renderer_destroy(r);
    return ok;
}

/* The frame of the first view with the given description (threads 1
 * unless set), after apply (may be NULL); malloc'd, NULL on failure. */
static uint8_t *frame_of(ew_renderer_desc d, const ew_scene *sc, const ew_camera *cam,
                         void (*apply)(ew_renderer *)) {
    ew_error err;
    if (!d.threads) d.threads = 1;
    ew_renderer *r = ew_renderer_create(&d, &err);
    CHECK(r != NULL, "%s", err.msg);
    if (!r) return NULL;
    if (apply) apply(r);
    ew_set_scene(r, sc);
    uint8_t *px = NULL;
    size_t n = (size_t)ew_frame_width(r) * ew_frame_height(r);
    if (ew_render(r, cam, NULL) == 0 && (px = malloc(n))) memcpy(px, ew_frame_pixels(r), n);
    ew_renderer_destroy(r);
    return px;
}
static void set_subdiv1(ew_renderer *r) { ew_set_subdivision(r, 1); }
static void set_affine(ew_renderer *r) { ew_set_alias_raster(r, EW_ALIAS_AFFINE, 0); }
static void set_subdiv_tris(ew_renderer *r) { ew_set_alias_raster(r, EW_ALIAS_SUBDIV, 0); }

static int same(const uint8_t *a, const uint8_t *b, size_t n) { return a && b && !memcmp(a, b, n); }

static void test_desc(void) {
    ew_error err;
    ew_assets *a = ew_assets_create_builtin(&err);
    CHECK(a != NULL, "%s", err.msg);
    if (!a) return;
    const ew_renderer_desc base = { .world = a->world, .palette = a->palette, .colormap = a->colormap };

    /* All defaults: 640x480, one thread per core. */
    ew_renderer *r = ew_renderer_create(&base, &err);
    CHECK(r != NULL, "zero desc: %s", err.msg);
    if (r) {
        long cores = sysconf(_SC_NPROCESSORS_ONLN);
        int want = cores < 1 ? 1 : cores > EW_MAX_THREADS ? EW_MAX_THREADS : (int)cores;
        CHECK(ew_frame_width(r) == 640 && ew_frame_height(r) == 480, "default size %dx%d",
              ew_frame_width(r), ew_frame_height(r));
        CHECK(ew_get_threads(r) >= 1 && ew_get_threads(r) <= want, "default threads %d (cores %ld)",
              ew_get_threads(r), cores);
        ew_renderer_destroy(r);
    }
    ew_renderer_desc d = base;
    d.width = 320, d.height = 200, d.threads = 2, d.subdivision = 32, d.cache_mb = 1;
    d.color = EW_COLOR_8BIT, d.hsr = EW_HSR_REFERENCE, d.alias_raster = EW_ALIAS_SUBDIV;
    d.alias_threshold = 100;
    r = ew_renderer_create(&d, &err);
    CHECK(r != NULL && ew_frame_width(r) == 320 && ew_get_threads(r) >= 1, "every field set: %s",
          err.msg);
    ew_renderer_destroy(r);

    /* Refusals: one error line and NULL. */
    CHECK(refused(NULL, "description"), "NULL desc");
    d = base, d.world = NULL;
    CHECK(refused(&d, "world"), "no world");
    d = base, d.palette = NULL;
    CHECK(refused(&d, "palette"), "no palette");
    d = base, d.colormap = NULL;
    CHECK(refused(&d, "colormap"), "no colormap");
    d = base, d.width = 100, d.height = 100;
    CHECK(refused(&d, "100x100"), "tiny frame");
    d = base, d.width = 8000, d.height = 5000;
    CHECK(refused(&d, "8000x5000"), "huge frame");
    d = base, d.width = 640;
    CHECK(refused(&d, "640x0"), "width without height");
    d = base, d.threads = -1;
    CHECK(refused(&d, "threads -1"), "negative threads");
    d = base, d.subdivision = 3;
    CHECK(refused(&d, "subdivision 3"), "subdivision 3");
    d = base, d.subdivision = 64;
    CHECK(refused(&d, "subdivision 64"), "subdivision 64");
    d = base, d.subdivision = -16;
    CHECK(refused(&d, "subdivision -16"), "negative subdivision");
    d = base, d.cache_mb = -1;
    CHECK(refused(&d, "cache_mb -1"), "negative cache");
    d = base, d.color = (ew_color_mode)7;
    CHECK(refused(&d, "colour mode 7"), "unknown colour mode");
    d = base, d.hsr = (ew_hsr_method)9;
    CHECK(refused(&d, "hidden-surface method 9"), "unknown hsr");
    d = base, d.alias_raster = (ew_alias_raster)5;
    CHECK(refused(&d, "alias rasterizer 5"), "unknown alias raster");
    d = base, d.alias_threshold = -1;
    CHECK(refused(&d, "threshold"), "negative threshold");
    d = base, d.alias_threshold = NAN;
    CHECK(refused(&d, "threshold"), "NaN threshold");

    /* The description does what the setters do, to the byte. */
    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(a->world, views);
    ew_scene *sc = ew_scene_create_builtin(a->world, &err);
    CHECK(nv > 0 && sc != NULL, "builtin views %d, scene: %s", nv, err.msg);
    if (nv > 0 && sc) {
        const size_t n = 320 * 200;
        ew_renderer_desc s = base;
        s.width = 320, s.height = 200;
        uint8_t *def = frame_of(s, sc, &views[0], NULL);
        s.subdivision = 16, s.alias_threshold = 40, s.cache_mb = 64;
        uint8_t *explicit_def = frame_of(s, sc, &views[0], NULL);
        CHECK(same(def, explicit_def, n), "the defaults spelled out give another frame");
        s = base, s.width = 320, s.height = 200, s.threads = 2;
        uint8_t *two = frame_of(s, sc, &views[0], NULL);
        CHECK(same(def, two, n), "threads = 2 gives another frame");

        s = base, s.width = 320, s.height = 200, s.subdivision = 1;
        uint8_t *d1 = frame_of(s, sc, &views[0], NULL);
        s.subdivision = 0;
        uint8_t *s1 = frame_of(s, sc, &views[0], set_subdiv1);
        CHECK(same(d1, s1, n), "subdivision 1 by desc and by ew_set_subdivision differ");

        s.alias_raster = EW_ALIAS_AFFINE;
        uint8_t *da = frame_of(s, sc, &views[0], NULL);
        s.alias_raster = EW_ALIAS_AUTO;
        uint8_t *sa = frame_of(s, sc, &views[0], set_affine);
        CHECK(same(da, sa, n), "affine alias raster by desc and by setter differ");
        s.alias_raster = EW_ALIAS_SUBDIV;
        uint8_t *dsub = frame_of(s, sc, &views[0], NULL);
        s.alias_raster = EW_ALIAS_AUTO;
        uint8_t *ssub = frame_of(s, sc, &views[0], set_subdiv_tris);
        CHECK(same(dsub, ssub, n), "subdivided alias raster by desc and by setter differ");

        s.hsr = EW_HSR_REFERENCE;
        uint8_t *ref = frame_of(s, sc, &views[0], NULL);
        CHECK(ref != NULL, "EW_HSR_REFERENCE renders");
        free(def), free(explicit_def), free(two), free(d1), free(s1), free(da), free(sa);
        free(dsub), free(ssub), free(ref);
    }
    ew_scene_destroy(sc);
    ew_assets_destroy(a);
}

static void test_lifetimes(void) {
    ew_error err;
    /* Every destroy takes NULL. */
    ew_fs_destroy(NULL);
    ew_world_destroy(NULL);
    ew_assets_destroy(NULL);
    ew_renderer_destroy(NULL);
    ew_scene_destroy(NULL);

    strcpy(err.msg, "");
    CHECK(ew_fs_create("/nonexistent/edgewise/game", &err) == NULL && err.msg[0],
          "fs on a missing folder: '%s'", err.msg);
    const uint8_t junk[64] = { 'j', 'u', 'n', 'k' };
    strcpy(err.msg, "");
    CHECK(ew_world_create(junk, sizeof junk, "junk.bsp", &err) == NULL && strstr(err.msg, "junk.bsp"),
          "junk world: '%s'", err.msg);
    strcpy(err.msg, "");
    CHECK(ew_assets_create("/nonexistent/x.bsp", NULL, &err) == NULL && strstr(err.msg, "x.bsp"),
          "missing map: '%s'", err.msg);

    ew_assets *a = ew_assets_create_builtin(&err);
    CHECK(a && a->world, "builtin: %s", err.msg);
    if (a) {
        ew_scene *s = ew_scene_create(a->world, &err);
        CHECK(s != NULL, "empty scene: %s", err.msg);
        /* Entities: an origin beyond +-1e7 or not finite, or an angle not
         * finite, is refused; one far off but within the bound renders. */
        const float nan3[3] = { NAN, 0, 0 }, inf_angle[3] = { 0, INFINITY, 0 }, beyond[3] = { 2e7f, 0, 0 },
                    far_off[3] = { 9e6f, -9e6f, 9e6f };
        if (s) {
            CHECK(ew_scene_add_brush(s, 1, nan3, NULL) == -1, "a NaN origin was taken");
            CHECK(ew_scene_add_brush(s, 1, NULL, inf_angle) == -1, "an infinite angle was taken");
            CHECK(ew_scene_add_brush(s, 1, beyond, NULL) == -1, "an origin at 2e7 was taken");
            CHECK(ew_scene_add_brush(s, 1, far_off, NULL) == 0, "an origin at 9e6 was refused");
            ew_camera views[EW_MAX_VIEWS];
            const ew_renderer_desc d = { .world = a->world, .palette = a->palette, .colormap = a->colormap,
                                         .width = 320, .height = 200 };
            uint8_t *px = ew_benchmark_views(a->world, views) > 0 ? frame_of(d, s, &views[0], NULL) : NULL;
            CHECK(px != NULL, "a scene with a far-off brush entity does not render");
            free(px);
        }
        ew_scene_destroy(s);
    }
    ew_assets_destroy(a);
}

/* ew_scene_missing_file: the model files a map's entities asked for and the
 * game directory lacked, each once (what the web page fetches); none when
 * the directory has them, none for a scene made otherwise. */
static void test_missing_files(void) {
    if (!ew_t_need_shared("data/librequake/maps/lqdm7.bsp")) return;
    ew_assets *a = ew_t_load_map("lqdm7");
    if (!a) return;
    char empty[] = "/tmp/ew_api_XXXXXX";
    ew_error err = { "" };
    if (!mkdtemp(empty)) {
        CHECK(0, "mkdtemp");
        ew_assets_destroy(a);
        return;
    }
    ew_scene *bare = ew_scene_create_from_map(a->world, "lqdm7", empty, &err);
    ew_scene *full = ew_scene_create_from_map(a->world, "lqdm7", ew_t_shared("data/librequake"), &err);
    CHECK(bare && full, "scenes: %s", err.msg);
    int n = 0, bad = 0, dup = 0, miss_ents = 0;
    while (bare && ew_scene_missing_file(bare, n)) {
        const char *f = ew_scene_missing_file(bare, n);
        if (strncmp(f, "progs/", 6) != 0 && strncmp(f, "maps/b_", 7) != 0) bad++;
        for (int k = 0; k < n; k++) dup += strcmp(f, ew_scene_missing_file(bare, k)) == 0;
        n++;
    }
    if (bare) ew_scene_counts(bare, NULL, NULL, &miss_ents);
    CHECK(n > 0 && bad == 0 && dup == 0 && miss_ents >= n, "lqdm7 without models: %d files missing (%d not "
          "progs/ or maps/b_, %d twice), %d entities", n, bad, dup, miss_ents);
    /* every one of them is in the game directory: there, none is missing */
    for (int i = 0; i < n; i++) {
        char path[1200];
        snprintf(path, sizeof path, "data/librequake/%s", ew_scene_missing_file(bare, i));
        CHECK(ew_t_have_shared(path), "%s: not in the game directory", path);
    }
    CHECK(full && ew_scene_missing_file(full, 0) == NULL, "lqdm7 with its models: %s missing",
          full && ew_scene_missing_file(full, 0) ? ew_scene_missing_file(full, 0) : "-");
    CHECK(ew_scene_missing_file(bare, -1) == NULL && ew_scene_missing_file(bare, n) == NULL &&
          ew_scene_missing_file(NULL, 0) == NULL, "out of range: NULL");
    ew_scene *plain = ew_scene_create(a->world, &err);
    CHECK(plain && ew_scene_missing_file(plain, 0) == NULL, "a scene made by ew_scene_create misses nothing");
    ew_scene_destroy(plain);
    ew_scene_destroy(bare);
    ew_scene_destroy(full);
    rmdir(empty);
    ew_assets_destroy(a);
}

int main(void) {
    test_version();
    test_rgba();
    test_desc();
    test_lifetimes();
    test_missing_files();
    return ew_t_finish();
}
