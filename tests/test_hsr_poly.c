/* The polygon-by-polygon hidden-surface methods (spans, zbuffer, painter,
 * drawbuffer: hsr/poly_rows.h) on every view of e1m1, lqdm7 and start at
 * 320x200, against the reference path (a brute-force z-buffer over the
 * same faces) and against each other:
 *   - the face winning each pixel agrees with the reference on >= 99%;
 *   - spans and drawbuffer write every pixel exactly once (overdraw 1.0),
 *     and give the edge list's faces (>= 99.99% of pixels);
 *   - painter writes every polygon whole: its writes are exactly the
 *     z-buffer's depth tests, so it overdraws wherever polygons overlap,
 *     and it ends with the z-buffer's faces almost everywhere;
 *   - zbuffer: depth tests >= depth passes >= pixels covered;
 *   - drawbuffer: bits tested + 8 per byte skipped or filled = the pixels
 *     of every polygon's spans (the depth tests of the z-buffer);
 *   - every method's frame and counters are the same on 1 and 2 threads.
 * With each map's entities (brush models sort among the polygons).
 * Prints each method's agreement and overdraw. */
#include "edgewise_lab.h"
#include "util.h"
#include "ew_world.h"

#include <stdlib.h>
#include <string.h>

#define W 320
#define H 200
#define NPX (W * H)

enum { M_SPANS, M_ZBUFFER, M_PAINTER, M_DRAWBUFFER, NM };
static const ew_hsr_method methods[NM] = {EW_HSR_SPANS, EW_HSR_ZBUFFER, EW_HSR_PAINTER, EW_HSR_DRAWBUFFER};

typedef struct tally {
    double agree_sum, agree_worst, od_sum, od_max, edge_sum, edge_worst;
    long counters[EW_HSR_COUNTERS], bytes;
    int views;
} tally;

static double agreement(const int *a, const int *b) {
    long same = 0;
    for (int i = 0; i < NPX; i++) same += a[i] == b[i];
    return (double)same / NPX;
}

/* e1m1 at 640x480, every view: the faces of every method are the edge
 * list's (at this size the door's two halves overlap at their seam in view
 * 0, where only a per-row 1/z order of the fragments gets it right), and
 * with a divide at every pixel the pixels too: same surfaces, same light,
 * only visibility differs.  Prints the share of equal pixels. */
static void test_large(void) {
    enum { LW = 640, LH = 480 };
    ew_assets *a = ew_t_load_map("e1m1");
    if (!a) return;
    ew_error err;
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                            .colormap = a->colormap, .width = LW, .height = LH,
                                                            .threads = 1},
                                        &err);
    CHECK(r != NULL, "%s", err.msg);
    if (!r) {
        ew_assets_destroy(a);
        return;
    }
    ew_enable_face_ids(r, 1);
    ew_set_subdivision(r, 1);
    ew_scene *sc = ew_scene_create_from_map(a->world, ew_t_shared("data/librequake/maps/e1m1.bsp"), NULL, &err);
    CHECK(sc != NULL, "%s", err.msg);
    if (sc) ew_set_scene(r, sc);
    int *eids = malloc(sizeof(int) * LW * LH);
    uint8_t *epx = malloc(LW * LH);
    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(a->world, views);
    double worst_px[NM] = {1, 1, 1, 1};
    for (int v = 0; v < nv; v++) {
        ew_set_hsr(r, EW_HSR_EDGE);
        CHECK(ew_render(r, &views[v], NULL) == 0, "e1m1 view %d", v);
        memcpy(eids, ew_frame_face_ids(r), sizeof(int) * LW * LH);
        memcpy(epx, ew_frame_pixels(r), LW * LH);
        for (int m = 0; m < NM; m++) {
            ew_set_hsr(r, methods[m]);
            CHECK(ew_render(r, &views[v], NULL) == 0, "e1m1 view %d", v);
            const int *ids = ew_frame_face_ids(r);
            const uint8_t *px = ew_frame_pixels(r);
            long same = 0, same_px = 0;
            for (int i = 0; i < LW * LH; i++) same += ids[i] == eids[i], same_px += px[i] == epx[i];
            CHECK(same == LW * LH, "e1m1 640x480 view %d: %s faces differ from edge at %ld pixels", v,
                  ew_hsr_name(methods[m]), (long)LW * LH - same);
            CHECK(same_px == LW * LH, "e1m1 640x480 view %d: %s pixels differ from edge at %ld pixels", v,
                  ew_hsr_name(methods[m]), (long)LW * LH - same_px);
            double f = (double)same_px / (LW * LH);
            if (f < worst_px[m]) worst_px[m] = f;
        }
    }
    for (int m = 0; m < NM; m++) {
        printf("%-10s e1m1 640x480, divide every pixel: pixels equal to edge's, worst view %.3f%%\n",
               ew_hsr_name(methods[m]), 100 * worst_px[m]);
    }
    free(eids), free(epx);
    ew_renderer_destroy(r);
    ew_scene_destroy(sc);
    ew_assets_destroy(a);
}

int main(void) {
    const char *maps[] = {"e1m1", "lqdm7", "start"};
    if (!ew_t_need_shared("data/librequake/maps/e1m1.bsp")) return ew_t_finish();
    for (int m = 0; m < NM; m++) CHECK(ew_hsr_available(methods[m]), "%s not built", ew_hsr_name(methods[m]));
    ew_error err;
    int *ref_ids = malloc(sizeof(int) * NPX), *edge_ids = malloc(sizeof(int) * NPX);
    int *ids[NM];
    uint8_t *px[NM];
    for (int m = 0; m < NM; m++) ids[m] = malloc(sizeof(int) * NPX), px[m] = malloc(NPX);
    tally all[NM];
    memset(all, 0, sizeof all);
    for (int m = 0; m < NM; m++) all[m].agree_worst = all[m].edge_worst = 1;
    int overlapping = 0, nviews = 0;

    for (int mi = 0; mi < 3; mi++) {
        ew_assets *a = ew_t_load_map(maps[mi]);
        if (!a) continue;
        ew_camera views[EW_MAX_VIEWS];
        int nv = ew_benchmark_views(a->world, views);
        CHECK(nv > 0, "%s has no views", maps[mi]);
        ew_renderer *r[2];
        for (int t = 0; t < 2; t++) {
            r[t] = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                          .colormap = a->colormap, .width = W, .height = H,
                                                          .threads = t + 1},
                                      &err);
            CHECK(r[t] != NULL, "%s", err.msg);
        }
        if (!r[0] || !r[1]) {
            ew_renderer_destroy(r[0]), ew_renderer_destroy(r[1]), ew_assets_destroy(a);
            continue;
        }
        CHECK(ew_get_threads(r[1]) == 2, "2 threads: got %d", ew_get_threads(r[1]));
        /* The map's entities: brush models (doors, lifts) join the polygons
         * and sort by 1/z within a leaf; alias models test the z-fill. */
        char rel[64];
        snprintf(rel, sizeof rel, "data/librequake/maps/%s.bsp", maps[mi]);
        ew_scene *sc = ew_scene_create_from_map(a->world, ew_t_shared(rel), NULL, &err);
        CHECK(sc != NULL, "%s", err.msg);
        if (sc) ew_set_scene(r[0], sc), ew_set_scene(r[1], sc);
        ew_enable_face_ids(r[0], 1), ew_enable_face_ids(r[1], 1);
        for (int v = 0; v < nv; v++) {
            nviews++;
            CHECK(ew_render_reference(r[0], &views[v], NULL, ref_ids, &err) == 0, "%s", err.msg);
            CHECK(ew_set_hsr(r[0], EW_HSR_EDGE) == 0, "edge");
            CHECK(ew_render(r[0], &views[v], NULL) == 0, "%s view %d: edge", maps[mi], v);
            memcpy(edge_ids, ew_frame_face_ids(r[0]), sizeof(int) * NPX);
            ew_stats st[NM];
            for (int m = 0; m < NM; m++) {
                const char *name = ew_hsr_name(methods[m]);
                CHECK(ew_set_hsr(r[0], methods[m]) == 0 && ew_set_hsr(r[1], methods[m]) == 0, "%s", name);
                CHECK(ew_render(r[0], &views[v], &st[m]) == 0, "%s view %d: %s", maps[mi], v, name);
                memcpy(ids[m], ew_frame_face_ids(r[0]), sizeof(int) * NPX);
                memcpy(px[m], ew_frame_pixels(r[0]), NPX);
                /* 2 threads, twice: the second frame's bands follow the
                 * first one's costs, so the rows split differently. */
                for (int k = 0; k < 2; k++) {
                    ew_stats st2;
                    CHECK(ew_render(r[1], &views[v], &st2) == 0, "%s view %d: %s", maps[mi], v, name);
                    CHECK(memcmp(px[m], ew_frame_pixels(r[1]), NPX) == 0 &&
                              memcmp(ids[m], ew_frame_face_ids(r[1]), sizeof(int) * NPX) == 0,
                          "%s view %d: %s differs on 2 threads (frame %d)", maps[mi], v, name, k);
                    /* The counters too: each is counted once per row or
                     * per polygon, wherever the bands split the rows. */
                    CHECK(memcmp(st2.hsr_counters, st[m].hsr_counters, sizeof st2.hsr_counters) == 0 &&
                              st2.pixels_written == st[m].pixels_written,
                          "%s view %d: %s counts differently on 2 threads: %ld %ld %ld %ld, 1 thread %ld %ld %ld %ld",
                          maps[mi], v, name, st2.hsr_counters[0], st2.hsr_counters[1], st2.hsr_counters[2],
                          st2.hsr_counters[3], st[m].hsr_counters[0], st[m].hsr_counters[1], st[m].hsr_counters[2],
                          st[m].hsr_counters[3]);
                }
                double ag = agreement(ids[m], ref_ids);
                CHECK(ag >= 0.99, "%s view %d: %s agrees with the reference on %.2f%% of pixels", maps[mi], v,
                      name, 100 * ag);
                CHECK(st[m].dropped == 0, "%s view %d: %s dropped %d", maps[mi], v, name, st[m].dropped);
                CHECK(st[m].hsr_bytes > 0, "%s view %d: %s holds %ld bytes", maps[mi], v, name, st[m].hsr_bytes);
                tally *t = &all[m];
                t->agree_sum += ag;
                if (ag < t->agree_worst) t->agree_worst = ag;
                t->od_sum += st[m].overdraw;
                if (st[m].overdraw > t->od_max) t->od_max = st[m].overdraw;
                double ae = agreement(ids[m], edge_ids);
                /* Same polygons, same pixels, same order as the edge list:
                 * the methods that write each pixel once give its frame. */
                if (methods[m] == EW_HSR_SPANS || methods[m] == EW_HSR_DRAWBUFFER)
                    CHECK(ae >= 0.9999, "%s view %d: %s agrees with edge on %.3f%%", maps[mi], v, name, 100 * ae);
                t->edge_sum += ae;
                if (ae < t->edge_worst) t->edge_worst = ae;
                for (int k = 0; k < EW_HSR_COUNTERS; k++) t->counters[k] += st[m].hsr_counters[k];
                if (st[m].hsr_bytes > t->bytes) t->bytes = st[m].hsr_bytes;
                t->views++;
            }
            /* Exactly once: every pixel of the frame, one write each. */
            for (int m = 0; m < NM; m += 3) {
                CHECK(st[m].overdraw == 1.0 && st[m].pixels_written == st[m].pixels_covered,
                      "%s view %d: %s overdraw %.4f (%ld writes, %ld pixels)", maps[mi], v, ew_hsr_name(methods[m]),
                      st[m].overdraw, st[m].pixels_written, st[m].pixels_covered);
                CHECK(st[m].pixels_covered == st[m].pixels, "%s view %d: %s covered %ld of %ld", maps[mi], v,
                      ew_hsr_name(methods[m]), st[m].pixels_covered, st[m].pixels);
            }
            /* The z-buffer: every pixel of every polygon tested once. */
            const long *zc = st[M_ZBUFFER].hsr_counters;
            CHECK(zc[0] >= zc[1] && zc[1] >= st[M_ZBUFFER].pixels_covered && st[M_ZBUFFER].pixels_covered > NPX / 2,
                  "%s view %d: zbuffer depth tests %ld, passes %ld, covered %ld", maps[mi], v, zc[0], zc[1],
                  st[M_ZBUFFER].pixels_covered);
            CHECK(st[M_ZBUFFER].pixels_written == zc[1], "%s view %d: zbuffer wrote %ld pixels, %ld passed",
                  maps[mi], v, st[M_ZBUFFER].pixels_written, zc[1]);
            /* The painter draws every polygon whole: as many writes as the
             * z-buffer made tests, and overdraw wherever polygons overlap. */
            const ew_stats *ps = &st[M_PAINTER];
            CHECK(ps->pixels_written == zc[0] && ps->hsr_counters[2] == zc[0],
                  "%s view %d: painter wrote %ld (counted %ld), zbuffer tested %ld", maps[mi], v,
                  ps->pixels_written, ps->hsr_counters[2], zc[0]);
            CHECK(ps->pixels_covered == st[M_ZBUFFER].pixels_covered, "%s view %d: painter covered %ld, zbuffer %ld",
                  maps[mi], v, ps->pixels_covered, st[M_ZBUFFER].pixels_covered);
            if (zc[0] > st[M_ZBUFFER].pixels_covered) {
                overlapping++;
                CHECK(ps->overdraw > 1.0, "%s view %d: painter overdraw %.4f over overlapping polygons", maps[mi],
                      v, ps->overdraw);
            }
            CHECK(ps->hsr_counters[0] > 0 && ps->hsr_counters[0] <= ps->surfaces,
                  "%s view %d: painter drew %ld polygons of %d", maps[mi], v, ps->hsr_counters[0], ps->surfaces);
            double pz = agreement(ids[M_PAINTER], ids[M_ZBUFFER]);
            CHECK(pz >= 0.995, "%s view %d: painter and zbuffer faces agree on %.2f%%", maps[mi], v, 100 * pz);
            /* The draw-buffer tests each polygon pixel once, bit or byte. */
            const long *dc = st[M_DRAWBUFFER].hsr_counters;
            CHECK(dc[0] + 8 * (dc[1] + dc[2]) == zc[0], "%s view %d: drawbuffer %ld bits + 8 x %ld bytes != %ld",
                  maps[mi], v, dc[0], dc[1] + dc[2], zc[0]);
            CHECK(dc[2] > 0, "%s view %d: drawbuffer filled no byte at once", maps[mi], v);
            /* Sorted spans: a clipped span looked at a drawn one at least. */
            const long *sc = st[M_SPANS].hsr_counters;
            CHECK(sc[0] >= sc[1] && sc[1] >= sc[2] && sc[3] >= sc[1] && sc[0] >= H, "%s view %d: spans counters %ld %ld %ld %ld",
                  maps[mi], v, sc[0], sc[1], sc[2], sc[3]);
        }
        ew_renderer_destroy(r[0]), ew_renderer_destroy(r[1]);
        ew_scene_destroy(sc);
        ew_assets_destroy(a);
    }
    CHECK(overlapping > 0, "no view with overlapping polygons");
    /* Over all views: hidden spans were clipped, drawn bytes skipped. */
    CHECK(all[M_SPANS].counters[1] > 0 && all[M_DRAWBUFFER].counters[1] > 0, "spans clipped %ld, bytes skipped %ld",
          all[M_SPANS].counters[1], all[M_DRAWBUFFER].counters[1]);
    for (int m = 0; m < NM; m++) {
        const tally *t = &all[m];
        if (!t->views) continue;
        printf("%-10s views %2d  faces vs reference: mean %.3f%% worst %.3f%%  vs edge: mean %.3f%% worst %.3f%%  "
               "overdraw: mean %.4f max %.4f  counters:",
               ew_hsr_name(methods[m]), t->views, 100 * t->agree_sum / t->views, 100 * t->agree_worst,
               100 * t->edge_sum / t->views, 100 * t->edge_worst, t->od_sum / t->views, t->od_max);
        for (int k = 0; k < EW_HSR_COUNTERS; k++)
            if (ew_hsr_counter_name(methods[m], k))
                printf(" %s %ld", ew_hsr_counter_name(methods[m], k), t->counters[k] / t->views);
        printf(" (per view)  memory %ld bytes at most\n", t->bytes);
    }
    printf("views %d, with overlapping polygons %d\n", nviews, overlapping);
    test_large();
    free(ref_ids), free(edge_ids);
    for (int m = 0; m < NM; m++) free(ids[m]), free(px[m]);
    return ew_t_finish();
}
