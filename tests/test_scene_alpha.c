/* ew_scene_set_alpha: a brush entity's opacity.  The built-in world's door
 * (submodel 1) alone in a scene, on the built-in view that shows most of
 * it, drawn opaque (alpha 1), half see-through (0.5), nearly invisible
 * (0.01) and not at all (no entity): in true colour, where blending is
 * exact, the half-opaque door's pixels are the mean of the opaque door's
 * and the background's, the nearly invisible one's stay within a sixteenth
 * of the background, and nothing outside the door changes.  Values outside
 * (0, 1] and unknown entities are refused and leave the entity as it was.
 * Needs no files. */
#include "util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define W 320
#define H 200
#define N (W * H)

static int chan(uint32_t px, int c) { return ((const uint8_t *)&px)[c]; }

/* The largest channel difference of two pixels. */
static int diff(uint32_t a, uint32_t b) {
    int d = 0;
    for (int c = 0; c < 3; c++) {
        int e = abs(chan(a, c) - chan(b, c));
        if (e > d) d = e;
    }
    return d;
}

/* Renders camera cam with the scene (NULL: none) into out; 0 on success. */
static int frame(ew_renderer *r, const ew_scene *s, const ew_camera *cam, uint32_t *out) {
    ew_set_scene(r, s);
    if (ew_render(r, cam, NULL) != 0) return -1;
    memcpy(out, ew_frame_rgba(r), sizeof(uint32_t) * N);
    return 0;
}

int main(void) {
    ew_error err;
    ew_assets *a = ew_assets_create_builtin(&err);
    CHECK(a != NULL, "builtin: %s", err.msg);
    if (!a) return ew_t_finish();
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){ .world = a->world, .palette = a->palette,
            .colormap = a->colormap, .width = W, .height = H, .threads = 1, .color = EW_COLOR_TRUE }, &err);
    CHECK(r != NULL, "renderer: %s", err.msg);
    ew_scene *s = ew_scene_create(a->world, &err);
    CHECK(s != NULL, "scene: %s", err.msg);
    if (!r || !s) return ew_t_finish();
    const float zero[3] = { 0, 0, 0 };
    int door = ew_scene_add_brush(s, 1, zero, zero);
    CHECK(door >= 0, "the door (submodel 1) added: %d", door);

    /* Refusals: outside (0, 1], unknown entities, no scene. */
    CHECK(ew_scene_set_alpha(s, door, 0) == -1, "alpha 0 refused");
    CHECK(ew_scene_set_alpha(s, door, -0.5f) == -1, "alpha -0.5 refused");
    CHECK(ew_scene_set_alpha(s, door, 1.5f) == -1, "alpha 1.5 refused");
    CHECK(ew_scene_set_alpha(s, door, NAN) == -1, "alpha NaN refused");
    CHECK(ew_scene_set_alpha(s, door + 1, 0.5f) == -1, "an unknown entity refused");
    CHECK(ew_scene_set_alpha(s, -1, 0.5f) == -1, "entity -1 refused");
    CHECK(ew_scene_set_alpha(NULL, 0, 0.5f) == -1, "no scene refused");
    CHECK(ew_scene_set_alpha(s, door, 1) == 0, "alpha 1 accepted");

    uint32_t *bg = malloc(sizeof(uint32_t) * N), *op = malloc(sizeof(uint32_t) * N);
    uint32_t *half = malloc(sizeof(uint32_t) * N), *faint = malloc(sizeof(uint32_t) * N);
    uint32_t *again = malloc(sizeof(uint32_t) * N);
    if (!bg || !op || !half || !faint || !again) {
        CHECK(0, "out of memory");
        return ew_t_finish();
    }

    /* The view where the opaque door covers most pixels. */
    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(a->world, views), best = -1, best_px = 0;
    CHECK(nv > 0, "builtin: no views");
    for (int v = 0; v < nv; v++) {
        if (frame(r, NULL, &views[v], bg) || frame(r, s, &views[v], op)) {
            CHECK(0, "view %d: render failed", v);
            continue;
        }
        int n = 0;
        for (int i = 0; i < N; i++) n += diff(bg[i], op[i]) > 24;
        if (n > best_px) best_px = n, best = v;
    }
    CHECK(best >= 0 && best_px > 500, "the door covers %d pixels at most (view %d)", best_px, best);
    if (best < 0) return ew_t_finish();
    const ew_camera *cam = &views[best];

    CHECK(frame(r, NULL, cam, bg) == 0, "background");
    CHECK(frame(r, s, cam, op) == 0, "alpha 1");
    CHECK(ew_scene_set_alpha(s, door, 0.5f) == 0, "alpha 0.5 accepted");
    CHECK(frame(r, s, cam, half) == 0, "alpha 0.5");
    CHECK(ew_scene_set_alpha(s, door, 0.01f) == 0, "alpha 0.01 accepted");
    CHECK(frame(r, s, cam, faint) == 0, "alpha 0.01");

    /* Over the door's pixels (opaque door and background clearly apart):
     * half is their mean, faint within a sixteenth of the way from the
     * background; elsewhere nothing changes. */
    int door_px = 0, mean_ok = 0, half_moved = 0, faint_ok = 0, outside = 0, outside_changed = 0;
    for (int i = 0; i < N; i++) {
        int d = diff(bg[i], op[i]);
        if (d > 24) {
            door_px++;
            int ok = 1;
            for (int c = 0; c < 3; c++) {
                int want = (chan(bg[i], c) + chan(op[i], c) + 1) / 2;
                ok &= abs(chan(half[i], c) - want) <= 6;
            }
            mean_ok += ok;
            half_moved += diff(half[i], bg[i]) > 4 && diff(half[i], op[i]) > 4;
            faint_ok += diff(faint[i], bg[i]) <= d / 16 + 4;
        } else if (d == 0) {
            outside++;
            outside_changed += half[i] != bg[i] || faint[i] != bg[i];
        }
    }
    printf("view %d: %d door pixels; half: %d the mean, %d apart from both; faint: %d near the background; "
           "%d of %d others changed\n", best, door_px, mean_ok, half_moved, faint_ok, outside_changed, outside);
    CHECK(mean_ok >= door_px * 9 / 10, "alpha 0.5: %d of %d door pixels the mean of door and background", mean_ok,
          door_px);
    CHECK(half_moved >= door_px * 9 / 10, "alpha 0.5: %d of %d door pixels apart from both door and background",
          half_moved, door_px);
    CHECK(faint_ok >= door_px * 9 / 10, "alpha 0.01: %d of %d door pixels within 1/16 of the background", faint_ok,
          door_px);
    CHECK(outside_changed <= outside / 200, "%d of %d pixels away from the door changed", outside_changed, outside);

    /* A refused value leaves the last accepted one: 0.5 again, then 0. */
    CHECK(ew_scene_set_alpha(s, door, 0.5f) == 0 && ew_scene_set_alpha(s, door, 0) == -1, "0.5, then 0 refused");
    CHECK(frame(r, s, cam, again) == 0 && memcmp(again, half, sizeof(uint32_t) * N) == 0,
          "after a refused alpha 0 the door is drawn at 0.5 still");
    /* And alpha 1 again is the opaque frame, byte for byte. */
    CHECK(ew_scene_set_alpha(s, door, 1) == 0 && frame(r, s, cam, again) == 0 &&
              memcmp(again, op, sizeof(uint32_t) * N) == 0,
          "alpha 1 again: the opaque frame");

    free(bg), free(op), free(half), free(faint), free(again);
    ew_scene_destroy(s);
    ew_renderer_destroy(r);
    ew_assets_destroy(a);
    return ew_t_finish();
}
