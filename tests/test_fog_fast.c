/* Fog done in the span draw (raster/fog.c, fog->fill): the world's pixels
 * fogged span by span as they are drawn, the fog colour written instead of
 * texels where fog is whole, and afterwards only what moving things drew
 * over the world fogged by its z-buffer depth.  Checked against the fog
 * pass that fogs every pixel after the models, which the full z-fill takes
 * (ew_set_full_zfill: the drawers write the z the pass reads): on every
 * view of e1m1, e4m1 and lqdm7 with their entities and a particle cloud,
 * under a dense fog (most pixels whole or nearly) and a light one, in
 * 8-bit and true colour, with the edge list (sorted bands) and the painter's
 * method (unsorted: filled in the draw, fogged by the pass), on one thread
 * and on two, the frames must be identical byte for byte, and the pixels
 * counted as fogged the same. */
#include "edgewise_lab.h"
#include "util.h"

#include <stdlib.h>
#include <string.h>

#define W 320
#define H 200

static const float fogs[][4] = {{1.0f, 0.3f, 0.3f, 0.35f}, {0.08f, 0.45f, 0.42f, 0.38f}};
enum { NFOGS = sizeof fogs / sizeof *fogs };

typedef struct tally { long frames, differing, pixels_off; } tally;

static ew_renderer *make(const ew_assets *a, ew_scene *sc, ew_color_mode color, ew_hsr_method hsr, int threads,
                         int full_z, const float *fog) {
    ew_error err;
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                            .colormap = a->colormap, .width = W, .height = H,
                                                            .threads = threads, .color = color, .hsr = hsr},
                                        &err);
    CHECK(r != NULL, "%s", err.msg);
    if (!r) return NULL;
    ew_set_full_zfill(r, full_z);
    ew_set_scene(r, sc);
    ew_set_liquid_alpha(r, 0.5f);
    ew_set_fog(r, fog[0], fog[1], fog[2], fog[3]);
    return r;
}

static void check_map(const char *name, tally *t) {
    ew_scene *sc = NULL;
    ew_camera views[EW_MAX_VIEWS];
    int nv = 0;
    ew_assets *a = ew_t_load_map_cloud(name, &sc, views, &nv);
    if (!a) return;
    for (int fi = 0; fi < NFOGS; fi++)
        for (int c = 0; c < 2; c++)
            for (int h = 0; h < 2; h++)
                for (int threads = 1; threads <= 2; threads++) {
                    ew_color_mode color = c ? EW_COLOR_TRUE : EW_COLOR_8BIT;
                    ew_hsr_method hsr = h ? EW_HSR_PAINTER : EW_HSR_EDGE;
                    if (!ew_hsr_available(hsr)) continue;
                    ew_renderer *fast = make(a, sc, color, hsr, threads, 0, fogs[fi]);
                    ew_renderer *pass = make(a, sc, color, hsr, threads, 1, fogs[fi]);
                    if (fast && pass)
                        for (int v = 0; v < nv; v++) {
                            ew_stats fs, ps;
                            CHECK(ew_render(fast, &views[v], &fs) == 0 && ew_render(pass, &views[v], &ps) == 0,
                                  "%s view %d", name, v);
                            /* counted as drawn (and filled) in the one, by the pass in the other */
                            CHECK(fs.fog_pixels > 0 && fs.fog_pixels <= fs.pixels && fs.fog_pixels == ps.fog_pixels,
                                  "%s view %d: fog_pixels %ld, the pass's %ld", name, v, fs.fog_pixels, ps.fog_pixels);
                            const long off = ew_t_frames_differ(fast, pass, W, H, c);
                            t->frames++;
                            t->differing += off > 0;
                            t->pixels_off += off;
                            CHECK(off == 0, "%s view %d, fog %.2f, %s, %s, %d thread(s): %ld bytes differ", name, v,
                                  fogs[fi][0], c ? "true colour" : "8-bit", ew_hsr_name(hsr), threads, off);
                        }
                    ew_renderer_destroy(fast);
                    ew_renderer_destroy(pass);
                }
    ew_scene_destroy(sc);
    ew_assets_destroy(a);
}

int main(void) {
    const char *maps[] = {"e1m1", "e4m1", "lqdm7"};
    tally t = {0, 0, 0};
    for (int m = 0; m < 3; m++) {
        char rel[64];
        snprintf(rel, sizeof rel, "data/librequake/maps/%s.bsp", maps[m]);
        if (!ew_t_need_shared(rel)) continue;
        check_map(maps[m], &t);
    }
    printf("%ld frames, %ld differing from the fog pass's, %ld bytes off\n", t.frames, t.differing, t.pixels_off);
    return ew_t_finish();
}
