/* The edge-list renderer against the reference path (a brute-force z-buffer
 * over the same visible faces, independent of the edge list), on every view
 * of e1m1, lqdm7 and start at 320x200:
 *   - the face that wins each pixel agrees on at least 99% of pixels;
 *   - the colours agree exactly on at least 99% of pixels when both divide
 *     for perspective at every pixel (same surfaces, light, mip levels);
 *     with the default divide every 16 pixels the colour agreement is
 *     printed: the affine steps in between shift texel edges a little;
 *   - overdraw is exactly 1.0, every pixel is written, nothing dropped. */
#include "edgewise_lab.h"
#include "util.h"
#include "ew_world.h"

#include <stdlib.h>
#include <string.h>

#define W 320
#define H 200

typedef struct tally { double sum, worst; int worst_view; } tally;

static void add(tally *t, double x, int v) {
    t->sum += x;
    if (x < t->worst) t->worst = x, t->worst_view = v;
}

int main(void) {
    const char *maps[] = {"e1m1", "lqdm7", "start"};
    if (!ew_t_need_shared("data/librequake/maps/e1m1.bsp")) return ew_t_finish();
    ew_error err;
    int *ref_ids = malloc(sizeof(int) * W * H), *ids = malloc(sizeof(int) * W * H);
    uint8_t *ref_px = malloc(W * H), *px16 = malloc(W * H), *px1 = malloc(W * H);
    double worst_all = 1;
    for (int mi = 0; mi < 3; mi++) {
        ew_assets *a = NULL;
        int rc;
        if (!(a = ew_t_load_map(maps[mi]))) continue;
        ew_camera views[EW_MAX_VIEWS];
        int nv = ew_benchmark_views(a->world, views);
        CHECK(nv > 0, "%s has no views", maps[mi]);
        ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){
                .world = a->world, .palette = a->palette,
                .colormap = a->colormap, .width = W, .height = H, .threads = 1 }, &err);
        CHECK(r != NULL, "%s", err.msg);
        if (!r) continue;
        ew_enable_face_ids(r, 1);
        tally face = {0, 1, 0}, exact = {0, 1, 0}, col16 = {0, 1, 0};
        for (int v = 0; v < nv; v++) {
            ew_stats st;
            /* Default mode: a divide every 16 pixels. */
            CHECK(ew_set_subdivision(r, 16) == 0, "subdivision 16");
            CHECK(ew_render(r, &views[v], &st) == 0, "%s view %d", maps[mi], v);
            CHECK(st.overdraw == 1.0, "%s view %d: overdraw %.4f", maps[mi], v, st.overdraw);
            CHECK(st.pixels_covered == st.pixels && st.pixels_written == st.pixels,
                  "%s view %d: %ld of %ld pixels written (%ld writes)", maps[mi], v,
                  st.pixels_covered, st.pixels, st.pixels_written);
            CHECK(st.dropped == 0, "%s view %d: %d dropped", maps[mi], v, st.dropped);
            CHECK(st.surfaces_built + st.surfaces_cached > 0 && st.edges > 0 && st.spans >= H,
                  "%s view %d: counters %d %d %d", maps[mi], v, st.surfaces_built, st.edges, st.spans);
            memcpy(ids, ew_frame_face_ids(r), sizeof(int) * W * H);
            memcpy(px16, ew_frame_pixels(r), W * H);
            /* Exact mode: a divide at every pixel, like the reference. */
            CHECK(ew_set_subdivision(r, 1) == 0, "subdivision 1");
            CHECK(ew_render(r, &views[v], NULL) == 0, "%s view %d", maps[mi], v);
            memcpy(px1, ew_frame_pixels(r), W * H);  /* the reference reuses the frame */
            /* Only where a fence texture's holes and bars fall may it differ:
             * which texel is a hole moves with the texture mapping. */
            const int *ids1 = ew_frame_face_ids(r);
            long changed = 0;
            for (int i = 0; i < W * H; i++) {
                int fence = (ids[i] >= 0 && (a->world->faces[ids[i]].flags & EW_SURF_FENCE)) ||
                            (ids1[i] >= 0 && (a->world->faces[ids1[i]].flags & EW_SURF_FENCE));
                changed += ids[i] != ids1[i] && !fence;
            }
            CHECK(changed == 0, "%s view %d: subdivision changed the visible surfaces at %ld pixels (not fences)",
                  maps[mi], v, changed);

            rc = ew_render_reference(r, &views[v], ref_px, ref_ids, &err);
            CHECK(rc == 0, "%s", err.msg);
            long same = 0, same_exact = 0, same16 = 0, missing = 0;
            for (int i = 0; i < W * H; i++) {
                same += ids[i] == ref_ids[i];
                same_exact += px1[i] == ref_px[i];
                same16 += px16[i] == ref_px[i];
                missing += ref_ids[i] < 0;
            }
            double ag = (double)same / (W * H), agx = (double)same_exact / (W * H);
            CHECK(ag >= 0.99, "%s view %d: visible surfaces agree on %.2f%% of pixels", maps[mi], v, ag * 100);
            CHECK(agx >= 0.99, "%s view %d: exact colours agree on %.2f%% of pixels", maps[mi], v, agx * 100);
            /* The exact fill can leave a pixel row open where a map has a
             * sub-pixel crack (T-junction) that the edge list's rounding
             * closes; those count against agreement above, and stay rare. */
            CHECK(missing <= W * H / 1000, "%s view %d: reference left %ld pixels empty", maps[mi], v, missing);
            add(&face, ag, v);
            add(&exact, agx, v);
            add(&col16, (double)same16 / (W * H), v);
        }
        printf("agreement %-6s views %2d  surfaces: mean %.3f%% worst %.3f%% (view %d)  "
               "colours exact: mean %.3f%% worst %.3f%%  colours default 16px: mean %.2f%% worst %.2f%%\n",
               maps[mi], nv, 100 * face.sum / nv, 100 * face.worst, face.worst_view,
               100 * exact.sum / nv, 100 * exact.worst, 100 * col16.sum / nv, 100 * col16.worst);
        if (face.worst < worst_all) worst_all = face.worst;
        ew_renderer_destroy(r);
        ew_assets_destroy(a);
    }
    printf("agreement worst view overall (visible surfaces): %.3f%%\n", 100 * worst_all);
    free(ref_ids), free(ids), free(ref_px), free(px16), free(px1);
    return ew_t_finish();
}
