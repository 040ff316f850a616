/* Deferred z-fill: ew_render writes the world's 1/z only under the moving
 * things (ew_zfill_rect), ew_frame_zbuffer fills in the rest.  Checked
 * against the original way (every span z-filled as it is drawn,
 * ew_set_full_zfill) on every view of e1m1, lqdm7 and the built-in scene
 * with their entities plus a particle cloud, on one thread and on two:
 * the frames and the finished z-buffers must be identical bit for bit,
 * and the deferred frame must really have left most of the z-buffer alone.
 * Also the item boxes' kept surfaces: a light style change must relight
 * them, and changing it back must give the first picture again. */
#include "edgewise_lab.h"
#include "util.h"
#include "renderer.h"

#include <stdlib.h>
#include <string.h>

#define W 320
#define H 200
#define UNTOUCHED (-1.0f)  /* never a 1/z: those are >= 0 */

typedef struct totals {
    long frame_diff, z_diff, untouched, left_unfilled, pixels;
    int views;
} totals;

static void compare_views(const char *name, const ew_assets *a, ew_scene *sc, int threads, totals *t) {
    ew_error err;
    ew_renderer *lazy = ew_renderer_create(&(ew_renderer_desc){
            .world = a->world, .palette = a->palette,
            .colormap = a->colormap, .width = W, .height = H, .threads = 1 }, &err);
    ew_renderer *full = ew_renderer_create(&(ew_renderer_desc){
            .world = a->world, .palette = a->palette,
            .colormap = a->colormap, .width = W, .height = H, .threads = 1 }, &err);
    CHECK(lazy && full, "%s: %s", name, err.msg);
    if (!lazy || !full) {
        ew_renderer_destroy(lazy), ew_renderer_destroy(full);
        return;
    }
    ew_set_full_zfill(full, 1);
    CHECK(ew_set_threads(lazy, threads) == threads && ew_set_threads(full, threads) == threads,
          "%s: %d threads", name, threads);
    ew_set_scene(lazy, sc), ew_set_scene(full, sc);
    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(a->world, views);
    CHECK(nv > 0, "%s: no views", name);
    long drawn = 0;
    for (int v = 0; v < nv; v++) {
        for (int i = 0; i < W * H; i++) lazy->f.target.zbuf[i] = UNTOUCHED;
        ew_stats ls, fs;
        CHECK(ew_render(lazy, &views[v], &ls) == 0 && ew_render(full, &views[v], &fs) == 0, "%s view %d", name, v);
        drawn += ls.alias_pixels;
        CHECK(ls.pixels_covered == ls.pixels, "%s view %d: %ld of %ld pixels covered", name, v, ls.pixels_covered,
              ls.pixels);
        long untouched = 0, frame_diff = 0, z_diff = 0, left = 0;
        for (int i = 0; i < W * H; i++) untouched += lazy->f.target.zbuf[i] == UNTOUCHED;
        const float *lz = ew_frame_zbuffer(lazy), *fz = ew_frame_zbuffer(full);
        for (int i = 0; i < W * H; i++) {
            frame_diff += lazy->f.target.pixels[i] != full->f.target.pixels[i];
            z_diff += memcmp(&lz[i], &fz[i], sizeof(float)) != 0;
            left += lz[i] == UNTOUCHED;
        }
        CHECK(frame_diff == 0 && z_diff == 0 && left == 0,
              "%s view %d, %d threads: %ld pixels and %ld z values differ from full z-fill, %ld left unfilled", name,
              v, threads, frame_diff, z_diff, left);
        t->frame_diff += frame_diff, t->z_diff += z_diff, t->untouched += untouched, t->left_unfilled += left;
        t->pixels += W * H, t->views++;
    }
    CHECK(drawn > 0, "%s: no moving thing drew a pixel", name);
    /* Changing the thread count between a frame and ew_frame_zbuffer keeps
     * that frame's z-buffer whole. */
    ew_render(lazy, &views[0], NULL), ew_render(full, &views[0], NULL);
    ew_set_threads(lazy, threads == 1 ? 2 : 1);
    CHECK(memcmp(ew_frame_zbuffer(lazy), ew_frame_zbuffer(full), sizeof(float) * W * H) == 0,
          "%s: z-buffer after ew_set_threads differs from full z-fill", name);
    ew_renderer_destroy(lazy), ew_renderer_destroy(full);
}

static void check_map(const char *name, ew_assets *a, ew_scene *sc) {
    float center[3] = {0, 0, 0};
    ew_camera views[EW_MAX_VIEWS];
    if (ew_benchmark_views(a->world, views) > 0)
        for (int k = 0; k < 3; k++) center[k] = views[0].origin[k];
    /* Particles all around the first view's eye: z-filled one square at a time. */
    CHECK(ew_scene_add_particles(sc, 3000, center, 400, 7) == 3000, "%s: particles", name);
    /* An explosion sprite ahead of every view, some half in a wall. */
    uint8_t *data;
    size_t size;
    ew_error err;
    CHECK(ew_read_file(ew_t_shared("data/librequake/progs/s_explod.spr"), &data, &size, &err) == 0, "%s", err.msg);
    int spr = ew_scene_load_model(sc, "progs/s_explod.spr", data, size, &err);
    CHECK(spr >= 0, "%s: sprite: %s", name, err.msg);
    free(data);
    int nv = ew_benchmark_views(a->world, views);
    for (int v = 0; v < nv && spr >= 0; v++) {
        ew_view vw;
        ew_view_setup(&vw, &views[v], W, H);
        float at[3];
        for (int k = 0; k < 3; k++) at[k] = vw.origin[k] + vw.forward[k] * (120 + 60 * (v % 4)) + vw.right[k] * 20;
        ew_scene_add_entity(sc, spr, at, NULL, v % 5, 0);
    }
    totals t = {0};
    compare_views(name, a, sc, 1, &t);
    compare_views(name, a, sc, 2, &t);
    printf("%s: %d frames, %ld pixels and %ld z values differ from full z-fill, %.1f%% of the z-buffer left for "
           "ew_frame_zbuffer, %ld left unfilled after it\n",
           name, t.views, t.frame_diff, t.z_diff, t.pixels ? 100.0 * t.untouched / t.pixels : 0.0, t.left_unfilled);
    /* Deferring must defer: the moving things cover a small part of these views. */
    CHECK(t.untouched > t.pixels / 4, "%s: only %ld of %ld z values deferred", name, t.untouched, t.pixels);
}

/* A health box straight ahead of start's first view, drawn under three
 * values of light style 0. */
static void check_box_light(void) {
    ew_assets *a = ew_t_load_map("start");
    if (!a) return;
    ew_error err;
    uint8_t *data;
    size_t size;
    ew_scene *sc = ew_scene_create(a->world, &err);
    CHECK(sc != NULL, "empty scene: %s", err.msg);
    CHECK(ew_read_file(ew_t_shared("data/librequake/maps/b_bh25.bsp"), &data, &size, &err) == 0, "%s", err.msg);
    int box = sc ? ew_scene_load_model(sc, "maps/b_bh25.bsp", data, size, &err) : -1;
    CHECK(box >= 0, "b_bh25.bsp: %s", err.msg);
    free(data);
    ew_camera views[EW_MAX_VIEWS];
    ew_benchmark_views(a->world, views);
    ew_view vw;
    ew_view_setup(&vw, &views[0], W, H);
    float at[3];
    for (int k = 0; k < 3; k++) at[k] = vw.origin[k] + vw.forward[k] * 60;
    at[2] -= 16;
    if (box >= 0) ew_scene_add_entity(sc, box, at, NULL, 0, 0);
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){ .world = a->world, .palette = a->palette,
            .colormap = a->colormap, .width = W, .height = H, .threads = 1 }, &err);
    CHECK(r != NULL, "%s", err.msg);
    if (r && box >= 0) {
        uint8_t *lit = malloc(W * H), *dark = malloc(W * H), *plain = malloc(W * H);
        ew_render(r, &views[0], NULL);
        memcpy(plain, r->f.target.pixels, W * H);  /* no scene */
        ew_set_scene(r, sc);
        ew_stats st;
        ew_render(r, &views[0], &st);
        memcpy(lit, r->f.target.pixels, W * H);
        ew_set_lightstyle(r, 0, 0);
        ew_render(r, &views[0], NULL);
        memcpy(dark, r->f.target.pixels, W * H);
        ew_reset_lightstyle(r, 0);  /* back to its default */
        ew_render(r, &views[0], NULL);
        long box_px = 0, relit = 0, again = 0;
        for (int i = 0; i < W * H; i++) {
            if (lit[i] == plain[i]) continue;  /* not the box */
            box_px++;
            relit += dark[i] != lit[i];
            again += r->f.target.pixels[i] != lit[i];
        }
        printf("health box: %ld pixels, %ld of them changed with style 0 off, %ld differ after it is back\n",
               box_px, relit, again);
        CHECK(st.entities_drawn == 1 && box_px > 500, "box: %d drawn, %ld pixels", st.entities_drawn, box_px);
        CHECK(relit > box_px / 2, "style 0 off relit only %ld of %ld box pixels", relit, box_px);
        CHECK(again == 0, "%ld box pixels differ after style 0 came back", again);
        free(lit), free(dark), free(plain);
    }
    ew_renderer_destroy(r);
    ew_scene_destroy(sc);
    ew_assets_destroy(a);
}

int main(void) {
    check_box_light();
    ew_error err;
    const char *maps[] = {"e1m1", "lqdm7"};
    for (int m = 0; m < 2; m++) {
        ew_assets *a = ew_t_load_map(maps[m]);
        if (!a) continue;
        char path[512];
        snprintf(path, sizeof path, "%s", ew_t_shared("data/librequake/maps/"));
        size_t len = strlen(path);
        snprintf(path + len, sizeof path - len, "%s.bsp", maps[m]);
        ew_scene *sc = ew_scene_create_from_map(a->world, path, NULL, &err);
        CHECK(sc != NULL, "%s: %s", maps[m], err.msg);
        if (sc) check_map(maps[m], a, sc);
        ew_scene_destroy(sc);
        ew_assets_destroy(a);
    }
    ew_assets *b = NULL;
    CHECK((b = ew_assets_create_builtin(&err)) != NULL, "%s", err.msg);
    if (b) {
        ew_scene *sc = ew_scene_create_builtin(b->world, &err);
        CHECK(sc != NULL, "builtin scene: %s", err.msg);
        if (sc) check_map("builtin", b, sc);
        ew_scene_destroy(sc);
        ew_assets_destroy(b);
    }
    return ew_t_finish();
}
