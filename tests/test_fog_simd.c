/* The fog's loops at every width the processor has (ew_set_simd): the
 * build's SSE2, AVX2 (the true-colour blend 8 pixels at a time) and
 * AVX-512 (the 8-bit table row by VBMI, the blend 16 at a time, and what
 * the models drew over the world fogged 16 pixels at a time) must draw
 * the same frames byte for byte.  A development machine with AVX-512 runs
 * only its widest loops unless told otherwise, so without this test the
 * loops of most desktop processors would go unchecked.  On every view of
 * e1m1 and e4m1 with their entities and a particle cloud, under a dense
 * fog and a light one, in 8-bit and true colour, on one thread and two.
 * A width the processor lacks is named on stdout and not checked (the
 * test is skipped only where it has neither); asking for it must give the
 * widest the processor has. */
#include "edgewise_lab.h"
#include "util.h"

#include <string.h>

#define W 640
#define H 400

static const float fogs[][4] = {{1.0f, 0.3f, 0.3f, 0.35f}, {0.08f, 0.45f, 0.42f, 0.38f}};
enum { NFOGS = sizeof fogs / sizeof *fogs };

static const char *const level_names[] = {"best", "SSE2", "AVX2", "AVX-512"};

/* What the processor has, asked here rather than of the library. */
static int cpu_has(ew_simd_level level) {
#if defined(__x86_64__) && defined(__GNUC__)
    __builtin_cpu_init();
    if (level == EW_SIMD_AVX2) return __builtin_cpu_supports("avx2");
    if (level == EW_SIMD_AVX512) return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw");
#endif
    return level == EW_SIMD_BASE;
}

static ew_renderer *make(const ew_assets *a, ew_scene *sc, ew_color_mode color, int threads, const float *fog,
                         ew_simd_level level) {
    ew_error err;
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                            .colormap = a->colormap, .width = W, .height = H,
                                                            .threads = threads, .color = color},
                                        &err);
    CHECK(r != NULL, "%s", err.msg);
    if (!r) return NULL;
    ew_set_scene(r, sc);
    ew_set_liquid_alpha(r, 0.5f);
    ew_set_fog(r, fog[0], fog[1], fog[2], fog[3]);
    ew_simd_level got = ew_set_simd(r, level);
    CHECK(got == level, "ew_set_simd(%s) gave %s", level_names[level], level_names[got]);
    return r;
}

static long frames, differing;

static void check_map(const char *name, const ew_simd_level *levels, int nlevels) {
    ew_scene *sc = NULL;
    ew_camera views[EW_MAX_VIEWS];
    int nv = 0;
    ew_assets *a = ew_t_load_map_cloud(name, &sc, views, &nv);
    if (!a) return;
    for (int fi = 0; fi < NFOGS; fi++)
        for (int c = 0; c < 2; c++)
            for (int threads = 1; threads <= 2; threads++) {
                ew_color_mode color = c ? EW_COLOR_TRUE : EW_COLOR_8BIT;
                ew_renderer *base = make(a, sc, color, threads, fogs[fi], EW_SIMD_BASE);
                for (int li = 0; li < nlevels && base; li++) {
                    ew_renderer *wide = make(a, sc, color, threads, fogs[fi], levels[li]);
                    for (int v = 0; wide && v < nv; v++) {
                        ew_stats bs, ws;
                        CHECK(ew_render(base, &views[v], &bs) == 0 && ew_render(wide, &views[v], &ws) == 0,
                              "%s view %d", name, v);
                        CHECK(ws.fog_pixels > 0 && ws.fog_pixels == bs.fog_pixels, "%s view %d: fog_pixels %ld, %ld",
                              name, v, ws.fog_pixels, bs.fog_pixels);
                        const long off = ew_t_frames_differ(base, wide, W, H, c);
                        frames++;
                        differing += off > 0;
                        CHECK(off == 0, "%s view %d, fog %.2f, %s, %d thread(s): %s against SSE2: %ld bytes differ",
                              name, v, fogs[fi][0], c ? "true colour" : "8-bit", threads, level_names[levels[li]],
                              off);
                    }
                    ew_renderer_destroy(wide);
                }
                ew_renderer_destroy(base);
            }
    ew_scene_destroy(sc);
    ew_assets_destroy(a);
}

int main(void) {
    ew_simd_level levels[2];
    int nlevels = 0;
    for (ew_simd_level l = EW_SIMD_AVX2; l <= EW_SIMD_AVX512; l++)
        if (cpu_has(l)) levels[nlevels++] = l;
        else printf("this processor has no %s: those loops are not checked here\n", level_names[l]);
    /* A level the processor lacks gives the widest it has. */
    ew_assets *a = ew_t_have_shared("data/librequake/maps/e1m1.bsp") ? ew_t_load_map("e1m1") : NULL;
    if (a) {
        ew_error err;
        ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                                .colormap = a->colormap, .width = 320, .height = 200},
                                            &err);
        CHECK(r != NULL, "%s", err.msg);
        const ew_simd_level widest = cpu_has(EW_SIMD_AVX512) ? EW_SIMD_AVX512
                                   : cpu_has(EW_SIMD_AVX2)   ? EW_SIMD_AVX2
                                                             : EW_SIMD_BASE;
        for (ew_simd_level l = EW_SIMD_BEST; r && l <= EW_SIMD_AVX512; l++) {
            ew_simd_level want = l == EW_SIMD_BEST || !cpu_has(l) ? widest : l, got = ew_set_simd(r, l);
            CHECK(got == want, "ew_set_simd(%s) gave %s, this processor's answer is %s", level_names[l],
                  level_names[got], level_names[want]);
        }
        ew_renderer_destroy(r);
        ew_assets_destroy(a);
    }
    /* The names bench --simd takes, both ways. */
    for (ew_simd_level l = EW_SIMD_BEST; l <= EW_SIMD_AVX512; l++)
        CHECK(ew_simd_name(l) && ew_simd_from_name(ew_simd_name(l)) == (int)l, "level %d's name", (int)l);
    CHECK(ew_simd_name((ew_simd_level)9) == NULL && ew_simd_from_name("avx3") == -1 && ew_simd_from_name(NULL) == -1,
          "names outside the levels");
    if (!nlevels) ew_t_skip("this processor has neither AVX2 nor AVX-512: no wider loops to check");
    const char *maps[] = {"e1m1", "e4m1"};
    for (int m = 0; m < 2 && nlevels > 0; m++) {
        char rel[64];
        snprintf(rel, sizeof rel, "data/librequake/maps/%s.bsp", maps[m]);
        if (!ew_t_need_shared(rel)) continue;
        check_map(maps[m], levels, nlevels);
    }
    printf("%ld frames at the wider levels, %ld differing from SSE2's\n", frames, differing);
    return ew_t_finish();
}
