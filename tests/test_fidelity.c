/* Fidelity to the seed system: every view of e1m1, lqdm7, e4m1 and start at
 * 640x480 against what the original 1996 renderer drew
 * (../shared/reference/winquake).  Compares the mean colour of every 8x8
 * block; a block "differs" when a channel is off by more than 12 levels.
 * At most 10% of blocks may differ on any view. */
#include "edgewise_lab.h"
#include "util.h"

#include <stdlib.h>
#include <string.h>

#define W 640
#define H 480
#define B 8

static double block_diff(const uint8_t *a, const uint8_t *b) {
    int bad = 0, total = 0;
    for (int by = 0; by < H / B; by++)
        for (int bx = 0; bx < W / B; bx++) {
            int sa[3] = {0}, sb[3] = {0};
            for (int y = 0; y < B; y++)
                for (int x = 0; x < B; x++)
                    for (int c = 0; c < 3; c++) {
                        size_t o = ((size_t)(by * B + y) * W + bx * B + x) * 3 + c;
                        sa[c] += a[o], sb[c] += b[o];
                    }
            int off = 0;
            for (int c = 0; c < 3; c++)
                if (abs(sa[c] - sb[c]) > 12 * B * B) off = 1;
            bad += off, total++;
        }
    return (double)bad / total;
}

int main(void) {
    const char *maps[] = {"e1m1", "lqdm7", "e4m1", "start"};
    if (!ew_t_need_shared("reference/winquake/e1m1_640x480_v0.png")) return ew_t_finish();
    ew_error err;
    uint8_t *rgb = malloc((size_t)W * H * 3);
    double overall_worst = 0;
    for (int mi = 0; mi < 4; mi++) {
        ew_assets *a = NULL;
        char path[256];
        int rc;
        if (!(a = ew_t_load_map(maps[mi]))) continue;
        ew_camera views[EW_MAX_VIEWS];
        int nv = ew_benchmark_views(a->world, views);
        ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){
                .world = a->world, .palette = a->palette,
                .colormap = a->colormap, .width = W, .height = H, .threads = 1, .classic = 1 }, &err);
        CHECK(r != NULL, "%s", err.msg);
        double sum = 0, worst = 0;
        int worst_view = -1, compared = 0;
        for (int v = 0; r && v < nv; v++) {
            snprintf(path, sizeof path, "reference/winquake/%s_640x480_v%d.png", maps[mi], v);
            if (!ew_t_have_shared(path)) continue;
            uint8_t *ref;
            int rw, rh;
            rc = ew_read_png_rgb(ew_t_shared(path), &ref, &rw, &rh, &err);
            CHECK(rc == 0 && rw == W && rh == H, "%s", err.msg);
            if (rc) continue;
            CHECK(ew_render(r, &views[v], NULL) == 0, "%s view %d", maps[mi], v);
            const uint8_t *px = ew_frame_pixels(r);
            for (size_t i = 0; i < (size_t)W * H; i++) memcpy(rgb + i * 3, a->palette + px[i] * 3, 3);
            double d = block_diff(rgb, ref);
            CHECK(d <= 0.10, "%s view %d: %.1f%% of 8x8 blocks differ (limit 10%%)", maps[mi], v, d * 100);
            if (getenv("EW_VERBOSE")) printf("  %s v%d: %.2f%%\n", maps[mi], v, d * 100);
            sum += d, compared++;
            if (d > worst) worst = d, worst_view = v;
            free(ref);
        }
        CHECK(compared == nv, "%s: compared %d of %d views", maps[mi], compared, nv);
        printf("fidelity %-6s views %2d  mean %.2f%%  worst %.2f%% (view %d) of 8x8 blocks differ\n",
               maps[mi], compared, compared ? 100 * sum / compared : 0, 100 * worst, worst_view);
        if (worst > overall_worst) overall_worst = worst;
        ew_renderer_destroy(r);
        ew_assets_destroy(a);
    }
    printf("fidelity worst view overall: %.2f%%\n", overall_worst * 100);
    free(rgb);
    return ew_t_finish();
}
