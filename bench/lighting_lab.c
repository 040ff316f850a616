/* lighting_lab: chapter 69's two-pass lighting against the surface cache
 * (docs/lighting.md).  Built as a target (build/lighting_lab); run
 *
 *     ./build/lighting_lab [DATA_DIR [STEP]]   (default ../shared/data/librequake, every view)
 *
 * and read; nothing here fails on a time.  One thread, world only, no fog,
 * white light (the book's case; two-pass lighting's tinted 8-bit texels
 * search the whole palette per pixel, the oracle's way, and are timed apart).
 * For e1m1, e4m1, lqdm7 and start at 320x200, 1920x1080 and 3840x2160, in
 * 8-bit and true colour, over every STEP-th view:
 *   - cache, warm: each view's frame after the same view was drawn (the
 *     surfaces it needs are cached): median and worst view;
 *   - cache, cold: each view's first frame after the surface cache was
 *     emptied (ew_flush_surfaces), as on a new view with nothing
 *     cached: median and worst view, surfaces built, and builds per second
 *     (built surfaces over the time they add, cold less warm);
 *   - two-pass: median and worst view (cold and warm are the same: it
 *     keeps nothing);
 *   - the draw stage alone (ms_draw: the world's pixel work) of two-pass
 *     against the warm cache: the book's "twice the pixel work";
 *   - memory: the cache's bytes after a pass over the views (the surfaces
 *     the view set needs), against two-pass's none. */
#define _POSIX_C_SOURCE 200809L
#include "edgewise_lab.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(double *v, int n) {
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n ? (n & 1 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2) : 0;
}

static double worst(const double *v, int n) {
    double m = 0;
    for (int i = 0; i < n; i++) m = v[i] > m ? v[i] : m;
    return m;
}

enum { REPS = 3 };

/* Best of REPS frames of view cam (each after flush if cold): its time and stats. */
static double frame(ew_renderer *r, const ew_camera *cam, int cold, ew_stats *out) {
    double best = 1e30;
    for (int k = 0; k < REPS; k++) {
        ew_stats st;
        if (cold) ew_flush_surfaces(r);
        else ew_render(r, cam, NULL);  /* what it needs, cached */
        ew_render(r, cam, &st);
        if (st.ms_total < best) best = st.ms_total, *out = st;
    }
    return best;
}

int main(int argc, char **argv) {
    const char *data = argc > 1 ? argv[1] : "../shared/data/librequake";
    int step = argc > 2 ? atoi(argv[2]) : 1;
    if (step < 1) step = 1;
    static const char *maps[] = {"e1m1", "e4m1", "lqdm7", "start"};
    static const int sizes[][2] = {{320, 200}, {1920, 1080}, {3840, 2160}};
    printf("%-6s %-9s %-5s %5s | %8s %8s | %8s %8s %6s %9s | %8s %8s | %6s %7s | %8s\n", "map", "size", "color",
           "views", "warm med", "worst", "cold med", "worst", "built", "builds/s", "2pass med", "worst", "level",
           "draw x", "cache MB");
    for (int mi = 0; mi < 4; mi++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/maps/%s.bsp", data, maps[mi]);
        ew_error err;
        ew_assets *a = ew_assets_create(path, data, &err);
        if (!a) {
            fprintf(stderr, "lighting_lab: %s\n", err.msg);
            return 1;
        }
        ew_camera views[EW_MAX_VIEWS];
        int nv = ew_benchmark_views(a->world, views);
        for (int si = 0; si < 3; si++)
            for (int c = 0; c < 2; c++) {
                ew_color_mode color = c ? EW_COLOR_TRUE : EW_COLOR_8BIT;
                ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                                        .colormap = a->colormap,
                                                                        .width = sizes[si][0], .height = sizes[si][1],
                                                                        .threads = 1, .color = color}, &err);
                if (!r) {
                    fprintf(stderr, "lighting_lab: %s\n", err.msg);
                    return 1;
                }
                ew_set_fog(r, 0, 0, 0, 0);
                ew_set_lit(r, 0);  /* white light, as the book's: coloured 8-bit two-pass searches the palette */
                double warm[EW_MAX_VIEWS], cold[EW_MAX_VIEWS], two[EW_MAX_VIEWS], dw[EW_MAX_VIEWS], d2[EW_MAX_VIEWS];
                double built = 0, build_ms = 0;
                int n = 0;
                long cache_bytes = 0;
                for (int v = 0; v < nv; v += step, n++) {
                    ew_stats sw = {0}, sc = {0}, s2 = {0};
                    ew_set_lighting(r, EW_LIGHTING_CACHE);
                    cold[n] = frame(r, &views[v], 1, &sc);
                    warm[n] = frame(r, &views[v], 0, &sw);
                    dw[n] = sw.ms_draw;
                    built += sc.surfaces_built;
                    if (cold[n] > warm[n]) build_ms += cold[n] - warm[n];
                    ew_set_lighting(r, EW_LIGHTING_TWO_PASS);
                    two[n] = frame(r, &views[v], 0, &s2);
                    d2[n] = s2.ms_draw;
                }
                /* the cache's holding after a pass over the views */
                ew_set_lighting(r, EW_LIGHTING_CACHE);
                for (int v = 0; v < nv; v += step) {
                    ew_stats st;
                    ew_render(r, &views[v], &st);
                    cache_bytes = st.surface_cache_bytes;
                }
                double wmed = median(warm, n), wworst = worst(warm, n), cmed = median(cold, n),
                       cworst = worst(cold, n), tmed = median(two, n), tworst = worst(two, n);
                double dmed = median(dw, n), d2med = median(d2, n);
                char size[16];
                snprintf(size, sizeof size, "%dx%d", sizes[si][0], sizes[si][1]);
                printf("%-6s %-9s %-5s %5d | %8.2f %8.2f | %8.2f %8.2f %6.0f %9.0f | %8.2f %8.2f | %6.2f %7.2f | "
                       "%8.2f\n",
                       maps[mi], size, c ? "true" : "8bit", n, wmed, wworst, cmed, cworst, built / n,
                       build_ms > 0 ? built / (build_ms / 1000) : 0, tmed, tworst, tworst / tmed,
                       dmed > 0 ? d2med / dmed : 0, cache_bytes / 1048576.0);
                fflush(stdout);
                ew_renderer_destroy(r);
            }
        ew_assets_destroy(a);
    }
    printf("level: two-pass worst view / its median.  draw x: two-pass's draw stage / the warm cache's (median).\n"
           "builds/s: surfaces built in the cold frames / the time they added (cold - warm).\n");
    return 0;
}
