/* The built-in scene's moving things in the demo picture (view 0, what
 * `make demo` draws): ew_scene_create_builtin spawns the door and adds the lantern
 * bearers, the dynamic light and the fountain; view 0 shows all of them.
 * Each is checked against the same view rendered without the scene: the
 * door's pixels are its own and nearer than what it hides, the model and
 * the particles change their areas, and the light only brightens the
 * world around it.  Also: the frame stays fully covered once, the scene is
 * the same every time, and time animates the model. */
#include "edgewise_lab.h"
#include "util.h"
#include "renderer.h"
#include "mapgen.h"
#include "asset/scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define W 640
#define H 480

static long luma(const uint8_t *pal, int c) { return 3L * pal[c * 3] + 4L * pal[c * 3 + 1] + 2L * pal[c * 3 + 2]; }

/* Screen position of a world point in camera cam; 0 if behind it. */
static int project(const ew_camera *cam, const float p[3], int *x, int *y) {
    ew_view v;
    ew_view_setup(&v, cam, W, H);
    float q[3];
    ew_view_transform(&v, p, q);
    if (q[2] < 1) return 0;
    *x = (int)lrintf(v.xcenter + v.xscale * q[0] / q[2]);
    *y = (int)lrintf(v.ycenter - v.yscale * q[1] / q[2]);
    return 1;
}

/* Pixels of the box [x0,x1) x [y0,y1) (clipped) whose colour differs. */
static long differ(const uint8_t *a, const uint8_t *b, int x0, int y0, int x1, int y1, long *total) {
    long n = 0, t = 0;
    for (int y = y0 < 0 ? 0 : y0; y < y1 && y < H; y++)
        for (int x = x0 < 0 ? 0 : x0; x < x1 && x < W; x++, t++) n += a[y * W + x] != b[y * W + x];
    if (total) *total = t;
    return n;
}

int main(void) {
    ew_error err;
    ew_assets *a = NULL;
    CHECK((a = ew_assets_create_builtin(&err)) != NULL, "%s", err.msg);
    if (!a) return ew_t_finish();
    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(a->world, views);
    CHECK(nv >= 1, "no views");
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){ .world = a->world, .palette = a->palette,
            .colormap = a->colormap, .width = W, .height = H, .threads = 1 }, &err);
    CHECK(r != NULL, "%s", err.msg);
    ew_scene *s = ew_scene_create_builtin(a->world, &err);
    CHECK(s != NULL, "ew_scene_create_builtin: %s", err.msg);
    if (!r || !s || nv < 1) {
        ew_scene_destroy(s), ew_renderer_destroy(r), ew_assets_destroy(a);
        return ew_t_finish();
    }
    int ents = 0, unknown = -1, missing = -1;
    ew_scene_counts(s, &ents, &unknown, &missing);
    CHECK(ents >= 2 && unknown == 0 && missing == 0, "scene: %d entities, %d unknown, %d missing", ents, unknown,
          missing);
    CHECK(a->world->nummodels == 2, "the world has %d models", a->world->nummodels);
    const ew_model *door = &a->world->models[a->world->nummodels > 1 ? 1 : 0];

    /* the world alone */
    ew_camera cam = views[0];
    uint8_t *px0 = malloc(W * H), *px1 = malloc(W * H);
    float *z0 = malloc(sizeof(float) * W * H);
    int *ids = malloc(sizeof(int) * W * H);
    ew_enable_face_ids(r, 1);
    ew_stats st;
    CHECK(ew_render(r, &cam, &st) == 0, "render without the scene");
    memcpy(px0, ew_frame_pixels(r), W * H);
    memcpy(z0, ew_frame_zbuffer(r), sizeof(float) * W * H);

    /* with the scene */
    ew_set_scene(r, s);
    CHECK(ew_render(r, &cam, &st) == 0, "render with the scene");
    memcpy(px1, ew_frame_pixels(r), W * H);
    memcpy(ids, ew_frame_face_ids(r), sizeof(int) * W * H);
    const float *z1 = ew_frame_zbuffer(r);
    printf("view 0: %d entities drawn, %d alias triangles, %ld model pixels, %d particles, %d surfaces relit\n",
           st.entities_drawn, st.alias_tris, st.alias_pixels, st.particles, st.surfaces_rebuilt_by_dlights);
    CHECK(st.entities_drawn >= 2, "%d entities drawn (door + model)", st.entities_drawn);
    CHECK(st.alias_tris > 0 && st.alias_pixels > 0, "%d alias triangles, %ld pixels", st.alias_tris,
          st.alias_pixels);
    CHECK(st.particles > 0, "%d particles", st.particles);
    CHECK(st.surfaces_rebuilt_by_dlights > 0, "%d surfaces rebuilt by dynamic lights",
          st.surfaces_rebuilt_by_dlights);
    CHECK(st.overdraw == 1.0 && st.pixels_covered == st.pixels && st.dropped == 0,
          "overdraw %g, covered %ld of %ld, dropped %d", st.overdraw, st.pixels_covered, st.pixels, st.dropped);

    /* The door: pixels won by its faces, drawn in its texture, nearer
     * than whatever was there without it. */
    long door_px = 0, door_changed = 0, door_nearer = 0;
    int dx0 = W, dx1 = -1, dy0 = H, dy1 = -1;
    for (int i = 0; i < W * H; i++) {
        if (ids[i] < door->firstface || ids[i] >= door->firstface + door->numfaces) continue;
        door_px++;
        door_changed += px0[i] != px1[i];
        door_nearer += z1[i] > z0[i] * 1.0001f;
        int x = i % W, y = i / W;
        dx0 = x < dx0 ? x : dx0, dx1 = x > dx1 ? x : dx1, dy0 = y < dy0 ? y : dy0, dy1 = y > dy1 ? y : dy1;
    }
    printf("door: %ld pixels in x %d..%d, y %d..%d; %ld changed, %ld nearer\n", door_px, dx0, dx1, dy0, dy1,
           door_changed, door_nearer);
    CHECK(door_px > 2000, "the door covers only %ld pixels of view 0", door_px);
    CHECK(door_changed > door_px * 9 / 10, "only %ld of the door's %ld pixels differ from the world alone",
          door_changed, door_px);
    CHECK(door_nearer > door_px * 99 / 100, "only %ld of the door's %ld pixels are nearer than what it hides",
          door_nearer, door_px);
    /* it stands upright in the doorway: taller than wide on screen, above the bottom */
    CHECK(dy1 - dy0 > dx1 - dx0 && dy1 < H - 20, "door box on screen %d..%d x %d..%d", dx0, dx1, dy0, dy1);

    /* The model: drawn over the world where each bearer stands (alias
     * pixels replace world pixels and are nearer). */
    int bearers_seen = 0, bx = -1, by = -1;
    for (int e = 0; e < s->nents; e++) {
        const ew_scene_entity *en = &s->ents[e];
        if (en->model < 0) continue;
        float mid[3] = {en->origin[0], en->origin[1], en->origin[2] + 36};
        int x, y;
        if (!project(&cam, mid, &x, &y) || x < 20 || x >= W - 20 || y < 40 || y >= H - 40) continue;
        long total, n = differ(px0, px1, x - 8, y - 30, x + 8, y + 30, &total);
        long nearer = 0;
        for (int yy = y - 30; yy < y + 30; yy++)
            for (int xx = x - 8; xx < x + 8; xx++) nearer += z1[yy * W + xx] > z0[yy * W + xx] * 1.0001f;
        printf("bearer %d at (%d, %d): %ld of %ld pixels differ, %ld nearer\n", e, x, y, n, total, nearer);
        CHECK(n > total * 3 / 4 && nearer > total * 3 / 4, "bearer %d: %ld of %ld pixels differ, %ld nearer", e, n,
              total, nearer);
        if (!bearers_seen++) bx = x, by = y;
    }
    CHECK(bearers_seen >= 1, "no lantern bearer in view 0");

    /* The light: world pixels (same depth as without the scene) around
     * the light get brighter, none markedly darker. */
    CHECK(s->ndlights >= 1, "%d dynamic lights", s->ndlights);
    int lights_seen = 0;
    for (int l = 0; l < s->ndlights; l++) {
        int x, y;
        if (!project(&cam, s->dlights[l].origin, &x, &y) || x < 0 || x >= W || y < 0 || y >= H) continue;
        lights_seen++;
        long brighter = 0, darker = 0;
        for (int yy = y - 100; yy < y + 100; yy++)
            for (int xx = x - 100; xx < x + 100; xx++) {
                if (xx < 0 || yy < 0 || xx >= W || yy >= H) continue;
                int i = yy * W + xx;
                int on_door = ids[i] >= door->firstface && ids[i] < door->firstface + door->numfaces;
                if (z1[i] != z0[i] || on_door) continue;
                long d = luma(a->palette, px1[i]) - luma(a->palette, px0[i]);
                brighter += d > 0, darker += d < -60;
            }
        printf("light %d at (%d, %d): %ld world pixels brighter, %ld darker\n", l, x, y, brighter, darker);
        CHECK(brighter > 2000 && darker * 20 < brighter, "light %d: %ld pixels brighter, %ld darker", l, brighter,
              darker);
    }
    CHECK(lights_seen >= 1, "no dynamic light in view 0");

    /* The fountain: bright drops (fullbright blues and white) where the
     * world alone has none. */
    long drops = 0;
    for (int i = 0; i < W * H; i++) drops += px1[i] >= BI_FB_BLUE && px1[i] != px0[i];
    CHECK(drops > 200, "%ld fountain pixels", drops);

    /* The same scene every time, drawn the same. */
    ew_scene *s2 = ew_scene_create_builtin(a->world, &err);
    CHECK(s2 != NULL, "%s", err.msg);
    if (s2) {
        ew_set_scene(r, s2);
        ew_render(r, &cam, NULL);
        CHECK(!memcmp(px1, ew_frame_pixels(r), W * H), "a second ew_scene_create_builtin draws differently");
        ew_set_scene(r, s);
        ew_scene_destroy(s2);
    }

    /* Time animates the model: another pose 0.3 s later. */
    ew_camera later = cam;
    later.time = 0.3;
    ew_render(r, &later, &st);
    CHECK(st.overdraw == 1.0 && st.pixels_covered == st.pixels, "time 0.3: overdraw %g, covered %ld", st.overdraw,
          st.pixels_covered);
    if (bearers_seen) {
        long total, moved = differ(px1, ew_frame_pixels(r), bx - 30, by - 60, bx + 30, by + 60, &total);
        CHECK(moved > 50, "time 0.3: only %ld of %ld pixels around the model changed", moved, total);
    }

    ew_set_scene(r, NULL);
    free(px0), free(px1), free(z0), free(ids);
    ew_scene_destroy(s);
    ew_renderer_destroy(r);
    ew_assets_destroy(a);
    return ew_t_finish();
}
