/* Moving things the world hides (raster/models.c, ew_set_hide_occluded):
 * alias models and item boxes whose screen box lies behind the world's 1/z
 * everywhere are neither posed nor drawn.  On every view of e1m1, e4m1,
 * lqdm7 and start with their own entities, in each alias rasterizer, on
 * one thread and on two, the frame and the finished z-buffer with the test
 * on must equal those with it off bit for bit (at 320x200, and at
 * 1920x1080 on every third view in the default rasterizer); the counts must add up (a
 * hidden thing is counted culled and hidden, and every other count stays);
 * and on these maps many things must really be left out.  Then one model
 * placed behind a wall of start, where it must be hidden, and in front of
 * it, where it must be drawn. */
#include "edgewise_lab.h"
#include "util.h"
#include "renderer.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define W 320  /* the size check_wall and most comparisons use */
#define H 200

typedef struct totals {
    long frames, frame_diff, z_diff, hidden, hidden_alias_tris;
} totals;

static void compare(const char *name, const ew_assets *a, ew_scene *sc, const ew_camera *views, int nv, int step,
                    ew_alias_raster mode, int threads, int w, int h, totals *t) {
    ew_error err;
    ew_renderer *on = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                             .colormap = a->colormap, .width = w, .height = h,
                                                             .threads = threads},
                                         &err);
    ew_renderer *off = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                              .colormap = a->colormap, .width = w, .height = h,
                                                              .threads = threads},
                                          &err);
    CHECK(on && off, "%s: %s", name, err.msg);
    if (!on || !off) {
        ew_renderer_destroy(on), ew_renderer_destroy(off);
        return;
    }
    ew_set_hide_occluded(off, 0);
    ew_set_alias_raster(on, mode, 40), ew_set_alias_raster(off, mode, 40);
    ew_set_scene(on, sc), ew_set_scene(off, sc);
    for (int v = 0; v < nv; v += step) {
        ew_camera cam = views[v];
        cam.time = 0.1f * (float)v;  /* the sprite cache sees moving frames */
        ew_stats a1, a0;
        CHECK(ew_render(on, &cam, &a1) == 0 && ew_render(off, &cam, &a0) == 0, "%s view %d", name, v);
        long fd = 0, zd = 0;
        const uint8_t *p1 = ew_frame_pixels(on), *p0 = ew_frame_pixels(off);
        for (int i = 0; i < w * h; i++) fd += p1[i] != p0[i];
        const float *z1 = ew_frame_zbuffer(on), *z0 = ew_frame_zbuffer(off);
        for (int i = 0; i < w * h; i++) zd += memcmp(&z1[i], &z0[i], sizeof(float)) != 0;
        CHECK(fd == 0 && zd == 0, "%s view %d, %dx%d, mode %d, %d threads: %ld pixels and %ld z values differ", name,
              v, w, h, (int)mode, threads, fd, zd);
        CHECK(a0.entities_hidden == 0, "%s view %d: %d hidden with the test off", name, v, a0.entities_hidden);
        CHECK(a1.entities_drawn + a1.entities_hidden == a0.entities_drawn &&
                  a1.entities_culled == a0.entities_culled + a1.entities_hidden &&
                  a1.alias_pixels == a0.alias_pixels && a1.alias_tris <= a0.alias_tris,
              "%s view %d, mode %d, %d threads: drawn %d + hidden %d against %d, culled %d against %d, pixels %ld "
              "against %ld, triangles %d against %d",
              name, v, (int)mode, threads, a1.entities_drawn, a1.entities_hidden, a0.entities_drawn,
              a1.entities_culled, a0.entities_culled, a1.alias_pixels, a0.alias_pixels, a1.alias_tris, a0.alias_tris);
        t->frames++, t->frame_diff += fd, t->z_diff += zd, t->hidden += a1.entities_hidden;
        t->hidden_alias_tris += a0.alias_tris - a1.alias_tris;
    }
    ew_renderer_destroy(on), ew_renderer_destroy(off);
}

/* A soldier straight ahead of start's first view, just behind the wall
 * there, then half way to it. */
static void check_wall(void) {
    ew_scene *sc = NULL;
    ew_camera views[EW_MAX_VIEWS];
    int nv = 0;
    ew_assets *a = ew_t_load_map_scene("start", &sc, views, &nv);
    if (!a || !sc) {
        ew_scene_destroy(sc), ew_assets_destroy(a);
        return;
    }
    ew_error err;
    uint8_t *data = NULL;
    size_t size = 0;
    CHECK(ew_read_file(ew_t_shared("data/librequake/progs/soldier.mdl"), &data, &size, &err) == 0, "%s", err.msg);
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                            .colormap = a->colormap, .width = W, .height = H,
                                                            .threads = 1},
                                        &err);
    CHECK(r != NULL, "%s", err.msg);
    if (r && data) {
        /* How far the world is at the middle of the screen: the first
         * view's wall (1/z from the z-buffer, without a scene). */
        ew_render(r, &views[0], NULL);
        float zi = ew_frame_zbuffer(r)[(H / 2) * W + W / 2], wall = zi > 0 ? 1 / zi : 0;
        CHECK(wall > 120 && wall < 4000, "start view 0: the wall ahead at depth %g", wall);
        ew_view vw;
        ew_view_setup(&vw, &views[0], W, H);
        /* Its bounds reach 16 units towards the eye: at 45 behind the wall
         * they are behind it by more than the test's margin (2%), and its
         * box still reaches the room in front, so the PVS lets it through. */
        const float depth[2] = {wall + 45, wall * 0.5f};
        for (int k = 0; k < 2 && wall > 0; k++) {
            ew_scene *one = ew_scene_create(a->world, &err);
            int mdl = one ? ew_scene_load_model(one, "progs/soldier.mdl", data, size, &err) : -1;
            CHECK(mdl >= 0, "soldier.mdl: %s", err.msg);
            if (mdl < 0) {
                ew_scene_destroy(one);
                break;
            }
            float at[3];
            for (int i = 0; i < 3; i++) at[i] = vw.origin[i] + vw.forward[i] * depth[k];
            ew_scene_add_entity(one, mdl, at, NULL, 0, 0);
            ew_set_scene(r, one);
            ew_stats st;
            CHECK(ew_render(r, &views[0], &st) == 0, "soldier at %g", depth[k]);
            printf("soldier at depth %.0f (wall at %.0f): drawn %d, hidden %d, %ld pixels\n", depth[k], wall,
                   st.entities_drawn, st.entities_hidden, st.alias_pixels);
            if (k == 0)
                CHECK(st.entities_hidden == 1 && st.entities_drawn == 0 && st.alias_tris == 0,
                      "behind the wall: %d hidden, %d drawn, %d triangles", st.entities_hidden, st.entities_drawn,
                      st.alias_tris);
            else
                CHECK(st.entities_hidden == 0 && st.entities_drawn == 1 && st.alias_pixels > 50,
                      "in front of the wall: %d hidden, %d drawn, %ld pixels", st.entities_hidden,
                      st.entities_drawn, st.alias_pixels);
            ew_set_scene(r, NULL);
            ew_scene_destroy(one);
        }
    }
    free(data);
    ew_renderer_destroy(r);
    ew_scene_destroy(sc);
    ew_assets_destroy(a);
}

int main(void) {
    check_wall();
    const char *maps[] = {"e1m1", "e4m1", "lqdm7", "start"};
    const ew_alias_raster modes[] = {EW_ALIAS_AUTO, EW_ALIAS_AFFINE, EW_ALIAS_SUBDIV, EW_ALIAS_MASKS,
                                     EW_ALIAS_SPRITE_CACHE};
    long frames = 0, hidden = 0;
    for (int m = 0; m < 4; m++) {
        ew_scene *sc = NULL;
        ew_camera views[EW_MAX_VIEWS];
        int nv = 0;
        ew_assets *a = ew_t_load_map_scene(maps[m], &sc, views, &nv);
        if (a && sc) {
            totals t = {0};
            for (int k = 0; k < 5; k++) compare(maps[m], a, sc, views, nv, 1, modes[k], 1, W, H, &t);
            compare(maps[m], a, sc, views, nv, 1, EW_ALIAS_AUTO, 2, W, H, &t);
            /* Large, every third view (test_golden checks every view's frame
             * at this size): item boxes' faces there cover whole pixels a
             * unit outside their model's bounds. */
            compare(maps[m], a, sc, views, nv, 3, EW_ALIAS_AUTO, 2, 1920, 1080, &t);
            printf("%s: %ld frames, %ld pixels and %ld z values differ; %ld things hidden, %ld alias triangles "
                   "not drawn\n",
                   maps[m], t.frames, t.frame_diff, t.z_diff, t.hidden, t.hidden_alias_tris);
            CHECK(t.hidden > 0, "%s: nothing hidden in %ld frames", maps[m], t.frames);
            frames += t.frames, hidden += t.hidden;
        }
        ew_scene_destroy(sc);
        ew_assets_destroy(a);
    }
    /* The maps' monsters stand in rooms that the PVS lets through. */
    CHECK(hidden >= frames / 2, "only %ld things hidden in %ld frames", hidden, frames);
    return ew_t_finish();
}
