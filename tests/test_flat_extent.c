/*
 * Faces whose texture extent is 0 along s or t: every vertex has the same
 * texture coordinate on that axis, on a multiple of 16 (ericw-tools writes
 * such faces; LibreQuake's lqdm3 has them).  The light map then has one
 * row (column) of samples and the surface is one texel thick there.
 *
 *   - the built-in map with one texinfo's t axis made zero (every face
 *     using it gets extent 0 along t) loads, and renders in every look (8-bit,
 *     true colour, two-pass light, the reference, classic, dynamic lights)
 *     with those faces on screen: under ASan no read leaves a surface, and a
 *     frame rendered twice with the cache flushed between is the same
 *     (nothing of a surface left unwritten);
 *   - `edgewise info` and `render` of lqdm3 (../shared/data/demos) work and
 *     the frame is neither black nor one colour.
 */
#define _GNU_SOURCE
#include "util.h"
#include "edgewise_lab.h"
#include "mapgen/mapgen.h"

#include <stdint.h>
#include <stdio.h>
#include <unistd.h>
#include <stdlib.h>
#include <string.h>

static uint32_t rd32(const uint8_t *p) { return p[0] | p[1] << 8 | p[2] << 16 | (uint32_t)p[3] << 24; }
static uint16_t rd16(const uint8_t *p) { return (uint16_t)(p[0] | p[1] << 8); }

/* Zeroes the t vector of the non-special texinfo used by most faces;
 * returns that texinfo, or -1. */
static int flatten_texinfo(uint8_t *bsp, size_t size, int **faces_of, int *nfaces) {
    if (size < 124 || rd32(bsp) != 29) return -1;
    uint32_t tofs = rd32(bsp + 4 + 6 * 8), tlen = rd32(bsp + 4 + 6 * 8 + 4);
    uint32_t fofs = rd32(bsp + 4 + 7 * 8), flen = rd32(bsp + 4 + 7 * 8 + 4);
    if (tofs + tlen > size || fofs + flen > size) return -1;
    int nti = (int)(tlen / 40), nf = (int)(flen / 20);
    int *use = calloc((size_t)nti, sizeof *use);
    if (!use) return -1;
    for (int i = 0; i < nf; i++) {
        int ti = rd16(bsp + fofs + 20 * (size_t)i + 10);
        if (ti < nti) use[ti]++;
    }
    int best = -1;
    for (int i = 0; i < nti; i++)
        if (!(rd32(bsp + tofs + 40 * (size_t)i + 36) & 1) && (best < 0 || use[i] > use[best])) best = i;
    free(use);
    if (best < 0) return -1;
    memset(bsp + tofs + 40 * (size_t)best + 16, 0, 16);  /* vecs[1] = 0 0 0, offset 0 */
    *faces_of = malloc(sizeof(int) * (size_t)nf);
    *nfaces = 0;
    for (int i = 0; i < nf && *faces_of; i++)
        if (rd16(bsp + fofs + 20 * (size_t)i + 10) == best) (*faces_of)[(*nfaces)++] = i;
    return best;
}

static void builtin_flat(void) {
    uint8_t *bsp = NULL, pal[768], cmap[EW_COLORMAP_SIZE];
    size_t size = 0;
    ew_error err = {{0}};
    if (ew_builtin_generate(&bsp, &size, pal, cmap, &err) != 0) {
        CHECK(0, "generate: %s", err.msg);
        return;
    }
    int *flat = NULL, nflat = 0;
    int ti = flatten_texinfo(bsp, size, &flat, &nflat);
    CHECK(ti >= 0 && flat && nflat > 0, "a texinfo to flatten (%d, %d faces)", ti, nflat);
    ew_world *w = ew_world_create(bsp, size, "flat.bsp", &err);
    CHECK(w != NULL, "the map with extent-0 faces loads: %s", err.msg);
    if (!w || ti < 0 || !flat) {
        free(bsp), free(flat), ew_world_destroy(w);
        return;
    }
    ew_scene *scene = ew_scene_create_builtin(w, &err);
    CHECK(scene != NULL, "builtin scene: %s", err.msg);
    ew_camera views[EW_MAX_VIEWS];
    int nviews = ew_benchmark_views(w, views);
    CHECK(nviews > 0, "views");
    struct { ew_color_mode color; int classic, twopass; ew_hsr_method hsr; const char *name; } looks[] = {
        {EW_COLOR_8BIT, 0, 0, EW_HSR_EDGE, "8-bit"},
        {EW_COLOR_TRUE, 0, 0, EW_HSR_EDGE, "true colour"},
        {EW_COLOR_8BIT, 1, 0, EW_HSR_EDGE, "classic"},
        {EW_COLOR_8BIT, 0, 1, EW_HSR_EDGE, "two-pass"},
        {EW_COLOR_TRUE, 0, 0, EW_HSR_REFERENCE, "reference"},
    };
    long seen = 0;
    for (size_t l = 0; l < sizeof looks / sizeof looks[0]; l++) {
        ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){.world = w, .palette = pal, .colormap = cmap,
                                                               .width = 320, .height = 200, .threads = 2,
                                                               .color = looks[l].color, .hsr = looks[l].hsr,
                                                               .classic = looks[l].classic}, &err);
        CHECK(r != NULL, "%s renderer: %s", looks[l].name, err.msg);
        if (!r) continue;
        if (looks[l].twopass) ew_set_lighting(r, EW_LIGHTING_TWO_PASS);
        ew_set_scene(r, scene);
        ew_enable_face_ids(r, 1);
        size_t bytes = (size_t)320 * 200 * (looks[l].color == EW_COLOR_TRUE ? 4 : 1);
        uint8_t *first = malloc(bytes);
        int same = 1;
        for (int v = 0; v < nviews && first; v++) {
            CHECK(ew_render(r, &views[v], NULL) == 0, "%s view %d", looks[l].name, v);
            const void *px = looks[l].color == EW_COLOR_TRUE ? (const void *)ew_frame_rgba(r) : ew_frame_pixels(r);
            memcpy(first, px, bytes);
            const int *ids = ew_frame_face_ids(r);
            if (l == 0 && ids)
                for (int i = 0; i < 320 * 200; i++)
                    for (int k = 0; k < nflat; k++)
                        if (ids[i] == flat[k]) {
                            seen++;
                            break;
                        }
            ew_flush_surfaces(r);
            ew_render(r, &views[v], NULL);
            px = looks[l].color == EW_COLOR_TRUE ? (const void *)ew_frame_rgba(r) : ew_frame_pixels(r);
            if (memcmp(first, px, bytes) != 0) same = 0;
        }
        CHECK(same, "%s: every view the same after the cache is flushed", looks[l].name);
        free(first);
        ew_renderer_destroy(r);
    }
    CHECK(seen > 1000, "the extent-0 faces are on screen (%ld pixels over the views)", seen);
    ew_scene_destroy(scene);
    ew_world_destroy(w);
    free(bsp);
    free(flat);
}

static void lqdm3(void) {
    if (!ew_t_need_shared("data/demos/maps/lqdm3.bsp")) return;
    const char *data = ew_t_shared_abs("data/demos");
    char dir[4096];
    snprintf(dir, sizeof dir, "%s", data);
    ew_t_run run;
    const char *info[] = {"info", "lqdm3", "--data", dir, NULL};
    ew_t_run_cli(&run, ".", info);
    CHECK(run.status == 0, "info lqdm3: %s", run.err);
    CHECK(strstr(run.out, "faces     12139") != NULL, "info lists the faces: %.200s", run.out);
    char tmp[] = "/tmp/ew_flat_XXXXXX";
    if (!mkdtemp(tmp)) {
        CHECK(0, "mkdtemp");
        return;
    }
    const char *png = ew_t_in_dir(tmp, "lqdm3_v8.png");
    const char *render[] = {"render", "lqdm3", "--data", dir, "--view", "8", "--size", "320x200",
                            "--out", png, NULL};
    ew_t_run_cli(&run, ".", render);
    CHECK(run.status == 0, "render lqdm3: %s", run.err);
    uint8_t *rgb = NULL;
    int w = 0, h = 0;
    ew_error err;
    if (run.status == 0 && ew_read_png_rgb(png, &rgb, &w, &h, &err) == 0) {
        double sum = 0;
        int distinct = 0;
        static uint8_t seen[256];
        memset(seen, 0, sizeof seen);
        for (int i = 0; i < w * h; i++) {
            sum += rgb[3 * i] + rgb[3 * i + 1] + rgb[3 * i + 2];
            uint8_t k = (uint8_t)(rgb[3 * i] ^ rgb[3 * i + 1] * 7 ^ rgb[3 * i + 2] * 13);
            if (!seen[k]) seen[k] = 1, distinct++;
        }
        double mean = sum / (3.0 * w * h);
        CHECK(mean > 40 && mean < 230, "lqdm3 view 8 is lit (mean %.1f)", mean);
        CHECK(distinct > 30, "lqdm3 view 8 has texture (%d colour classes)", distinct);
        free(rgb);
    } else {
        CHECK(0, "read %s", png);
    }
    remove(png);
    rmdir(tmp);
}

int main(void) {
    builtin_flat();
    lqdm3();
    return ew_t_finish();
}
