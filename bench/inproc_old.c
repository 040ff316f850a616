/* bench/inproc_old.c: side A of bench/inproc.c through the public calls of
 * cde885f (ew_assets_load, ew_view_set, ew_scene_from_map and a renderer
 * made from a world, palette and colormap).  bench/compare.sh builds it
 * against the old revision's include/ when INPROC=1 and that revision has
 * no ew_set_classic (its one look was the classic one). */
#include "edgewise.h"
#include "inproc_old.h"

#include <stdio.h>
#include <stdlib.h>

struct inproc_old {
    ew_assets    assets;
    ew_scene    *scene;
    ew_renderer *r;
    ew_camera    views[EW_MAX_VIEWS];
    int          nviews;
};

inproc_old *inproc_old_open(const char *map, const char *data, int w, int h, int threads, int entities,
                            char *err, int errsize) {
    inproc_old *o = calloc(1, sizeof *o);
    ew_error e = {{0}};
    if (!o) {
        snprintf(err, (size_t)errsize, "out of memory");
        return NULL;
    }
    if (ew_assets_load(map, data, &o->assets, &e) < 0) {
        snprintf(err, (size_t)errsize, "%s", e.msg);
        free(o);
        return NULL;
    }
    o->nviews = ew_view_set(o->assets.world, o->views);
    if (entities && !(o->scene = ew_scene_from_map(o->assets.world, map, data, &e))) goto fail;
    if (!(o->r = ew_renderer_create(o->assets.world, o->assets.palette, o->assets.colormap, w, h, &e))) goto fail;
    if (ew_set_threads(o->r, threads) < 0) {
        snprintf(e.msg, sizeof e.msg, "%d threads refused", threads);
        goto fail;
    }
    if (o->scene) ew_set_scene(o->r, o->scene);
    return o;
fail:
    snprintf(err, (size_t)errsize, "%s", e.msg);
    inproc_old_close(o);
    return NULL;
}

void inproc_old_close(inproc_old *o) {
    if (!o) return;
    if (o->r) ew_renderer_free(o->r);
    if (o->scene) ew_scene_free(o->scene);
    ew_assets_free(&o->assets);
    free(o);
}

int inproc_old_views(const inproc_old *o) { return o->nviews; }

int inproc_old_render(inproc_old *o, int v, double ms[4]) {
    ew_stats st;
    if (v < 0 || v >= o->nviews || ew_render(o->r, &o->views[v], &st) < 0) return -1;
    ms[0] = st.ms_front, ms[1] = st.ms_scan, ms[2] = st.ms_draw, ms[3] = st.ms_models;
    return 0;
}

const uint8_t *inproc_old_pixels(const inproc_old *o) { return ew_frame_pixels(o->r); }
