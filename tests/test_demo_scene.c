/* The built-in scene (what `make demo` draws) through the whole pipeline,
 * needing nothing outside the repository: every view fully written once,
 * sky, liquid and lit walls all present, agreement with the reference path,
 * animated textures move with time. */
#include "edgewise_lab.h"
#include "util.h"
#include "renderer.h"

#include <stdlib.h>
#include <string.h>

#define W 640
#define H 480

int main(void) {
    ew_error err;
    ew_assets *a = NULL;
    CHECK((a = ew_assets_create_builtin(&err)) != NULL, "%s", err.msg);
    if (!a) return ew_t_finish();
    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(a->world, views);
    CHECK(nv >= 4, "built-in scene has %d views", nv);
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){ .world = a->world, .palette = a->palette,
            .colormap = a->colormap, .width = W, .height = H, .threads = 1 }, &err);
    CHECK(r != NULL, "%s", err.msg);
    if (!r) return ew_t_finish();
    ew_enable_face_ids(r, 1);
    int *ids = malloc(sizeof(int) * W * H), *ref = malloc(sizeof(int) * W * H);
    long sky_px = 0, water_px = 0;
    for (int v = 0; v < nv; v++) {
        ew_stats st;
        CHECK(ew_render(r, &views[v], &st) == 0, "view %d", v);
        CHECK(st.overdraw == 1.0 && st.pixels_covered == st.pixels && st.dropped == 0,
              "view %d: overdraw %g covered %ld dropped %d", v, st.overdraw, st.pixels_covered, st.dropped);
        const uint8_t *px = ew_frame_pixels(r);
        int used[256] = {0}, distinct = 0;
        for (int i = 0; i < W * H; i++) used[px[i]] = 1;
        for (int i = 0; i < 256; i++) distinct += used[i];
        CHECK(distinct >= 40, "view %d uses only %d colours", v, distinct);
        memcpy(ids, ew_frame_face_ids(r), sizeof(int) * W * H);
        /* Every pixel was covered by a world surface, so every id is a face. */
        long bad_ids = 0;
        int first_bad = -1;
        for (int i = 0; i < W * H; i++)
            if ((ids[i] < 0 || ids[i] >= a->world->numfaces) && !bad_ids++) first_bad = i;
        CHECK(bad_ids == 0, "view %d: %ld pixels without a face id, first (%d, %d) id %d", v, bad_ids,
              first_bad % W, first_bad / W, first_bad >= 0 ? ids[first_bad] : 0);
        for (int i = 0; i < W * H; i++) {
            if (ids[i] < 0 || ids[i] >= a->world->numfaces) continue;
            const ew_face *f = &a->world->faces[ids[i]];
            sky_px += (f->flags & EW_SURF_SKY) != 0;
            water_px += (f->flags & EW_SURF_TURB) != 0;
        }
        CHECK(ew_render_reference(r, &views[v], NULL, ref, &err) == 0, "%s", err.msg);
        long same = 0;
        for (int i = 0; i < W * H; i++) same += ids[i] == ref[i];
        CHECK(same >= W * H * 99 / 100, "view %d: %.2f%% agree with the reference", v, 100.0 * same / (W * H));
    }
    CHECK(sky_px > 1000 && water_px > 1000, "sky %ld px, water %ld px over the views", sky_px, water_px);

    /* View 0 (the README picture): the sky is at the top, the floor at the bottom. */
    ew_render(r, &views[0], NULL);
    const int *fid = ew_frame_face_ids(r);
    int top = fid[W / 2], bottom = fid[(H - 1) * W + W / 2];
    CHECK(top >= 0 && top < a->world->numfaces && bottom >= 0 && bottom < a->world->numfaces,
          "view 0: face ids %d at the top centre, %d at the bottom centre", top, bottom);
    if (top >= 0 && top < a->world->numfaces && bottom >= 0 && bottom < a->world->numfaces) {
        CHECK(a->world->faces[top].flags & EW_SURF_SKY, "top centre of view 0 is not sky");
        const ew_plane *floor = &a->world->planes[a->world->faces[bottom].plane];
        CHECK(floor->normal[2] > 0.99f, "bottom centre of view 0 is not a floor");
    }

    /* Time moves the sky, the liquid and the animated button somewhere. */
    long changed = 0;
    for (int v = 0; v < nv; v++) {
        ew_camera c = views[v];
        ew_render(r, &c, NULL);
        uint8_t *t0 = malloc(W * H);
        memcpy(t0, ew_frame_pixels(r), W * H);
        c.time = 0.5;
        ew_render(r, &c, NULL);
        for (int i = 0; i < W * H; i++) changed += t0[i] != ew_frame_pixels(r)[i];
        free(t0);
    }
    CHECK(changed > 1000, "only %ld pixels changed with time", changed);

    free(ids), free(ref);
    ew_renderer_destroy(r);
    ew_assets_destroy(a);
    return ew_t_finish();
}
