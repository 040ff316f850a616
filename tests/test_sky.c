/* The sky's layers made one (raster/sky.c, ew_sky_comp): spans drawn
 * through the nine composited planes must equal, byte for byte, the same
 * spans drawn layer by layer (two texels a pixel, the back one where the
 * front one is clear), in 8-bit and true colour.
 *
 * On made-up skies (random texels, a third of the front layer clear): the
 * Quake size (two 128x128 layers), a small square one and a tall one; under
 * scrolls chosen where the planes' choice is on a knife edge (whole
 * numbers, halves, a hair either side of them, the largest scroll a time
 * gives) and at random; looking every way at 320x200 and 1920x1080, whole
 * rows and random pieces of rows.  Controls: each of the nine planes,
 * overwritten, changes some pixel under those scrolls (so every plane is
 * read and the comparison can fail); a sky whose layers are not a power of
 * two gets no planes (and is drawn layer by layer). */
#include "util.h"
#include "raster/raster.h"
#include "world/view.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static unsigned seed = 12345;
static unsigned next(unsigned n) {
    seed = seed * 1103515245u + 12345u;
    return (seed >> 8) % n;
}

typedef struct sky {
    ew_texture tex;
    uint8_t   *px;
} sky;

static sky make_sky(int width, int height) {
    sky s;
    memset(&s, 0, sizeof s);
    if (!(s.px = malloc((size_t)width * height))) return s;
    for (int y = 0; y < height; y++)
        for (int x = 0; x < width; x++) {
            uint8_t v = (uint8_t)(1 + next(255));
            if (x < width / 2 && next(3) == 0) v = 0;  /* the front layer's holes */
            s.px[y * width + x] = v;
        }
    snprintf(s.tex.name, sizeof s.tex.name, "sky%dx%d", width, height);
    s.tex.width = width, s.tex.height = height;
    for (int m = 0; m < 4; m++) s.tex.mip[m] = s.px;
    s.tex.flags = EW_SURF_SKY;
    return s;
}

enum { MAXW = 1920 };
static uint8_t frame[2][MAXW * 4];  /* one row, with planes and without */
static uint32_t palette[256];

/* Row v of a view (u0 .. u0 + n) drawn both ways; the bytes that differ. */
static long row_differs(const ew_view *view, const ew_texture *t, const ew_sky_comp *comp, float scroll, int bpp,
                        int v, int u0, int n) {
    ew_target tg[2];
    ew_span_ctx c[2];
    for (int k = 0; k < 2; k++) {
        /* pitch 0: every row is the one row held */
        tg[k] = (ew_target){.pixels = frame[k], .width = view->width, .height = view->height, .pitch = 0, .bpp = bpp,
                            .rgba = palette};
        c[k] = (ew_span_ctx){.target = &tg[k], .subdiv_shift = 4, .view = view, .sky_scroll = scroll,
                             .sky_comp = k ? NULL : comp, .rgba = palette};
        memset(frame[k], k ? 0x5a : 0xa5, sizeof frame[k]);
    }
    ew_span sp = {.u = u0, .v = v, .count = n};
    for (int k = 0; k < 2; k++) ew_draw_sky_span(&c[k], &sp, t);
    long d = 0;
    for (int i = 0; i < n * bpp; i++) d += frame[0][u0 * bpp + i] != frame[1][u0 * bpp + i];
    return d;
}

static const float edge_scrolls[] = {0.0f, 0.25f, 0.5f, 0.49999f, 0.50001f, 0.99998f, 1.0f, 1.00002f,
                                     7.5f, 17.75f, 255.999f, 256.0f, 1000.4999f, 2047.5f, 4095.0f, 4095.9995f};
enum { NEDGE = sizeof edge_scrolls / sizeof *edge_scrolls };

/* Every scroll of the test over a few views and rows: the bytes that
 * differ (compared: the pixels drawn). */
static long sweep(const ew_texture *t, ew_sky_comp *comp, int poison_plane, long *compared) {
    const int sizes[][2] = {{320, 200}, {1920, 1080}};
    const int nviews = EW_T_SANITIZED ? 3 : 8, nrandom = EW_T_SANITIZED ? 4 : 16;
    long differ = 0;
    for (int si = 0; si < NEDGE + nrandom; si++) {
        float scroll = si < NEDGE ? edge_scrolls[si] : (float)(next(4096 * 64)) / 64.0f + (float)next(1000) / 64000.0f;
        if (ew_sky_comp_make(comp, t, scroll) != 0) {
            CHECK(0, "%s: no planes at scroll %g", t->name, scroll);
            continue;
        }
        if (poison_plane >= 0) {
            size_t plane = (size_t)(t->width / 2) * t->height;
            memset(comp->planes + plane * (size_t)poison_plane, 0xee, plane);
        }
        for (int z = 0; z < 2; z++)
            for (int vi = 0; vi < nviews; vi++) {
                ew_camera cam = {{(float)next(2000) - 1000, (float)next(2000) - 1000, (float)next(500)},
                                 {(float)next(170) - 85.0f, (float)next(360), (float)next(30) - 15.0f},
                                 60.0f + (float)next(90), 0};
                ew_view view;
                ew_view_setup(&view, &cam, sizes[z][0], sizes[z][1]);
                for (int bpp = 1; bpp <= 4; bpp += 3)
                    for (int r = 0; r < 6; r++) {
                        int v = (int)next((unsigned)sizes[z][1]);
                        int u0 = r < 2 ? 0 : (int)next((unsigned)sizes[z][0]);
                        int n = r < 2 ? sizes[z][0] : 1 + (int)next((unsigned)(sizes[z][0] - u0));
                        differ += row_differs(&view, t, comp, scroll, bpp, v, u0, n);
                        *compared += n;
                    }
            }
        if (poison_plane >= 0) comp->tex = NULL;  /* made again next time */
    }
    return differ;
}

/* Each plane's texels against their definition: the front texel, or where
 * it is clear the back layer's texel (w0 + a, w0 + b) texels behind. */
static void check_planes(const ew_texture *t, ew_sky_comp *comp) {
    const float scrolls[] = {0.0f, 0.4f, 0.6f, 3.0f, 100.5f, 4095.9f};
    const int half = t->width / 2, rows = t->height;
    long bad = 0;
    for (int i = 0; i < 6; i++) {
        if (ew_sky_comp_make(comp, t, scrolls[i]) != 0) {
            CHECK(0, "%s: no planes at scroll %g", t->name, scrolls[i]);
            continue;
        }
        CHECK(comp->w0 == (int)lroundf(scrolls[i]) - 1 || comp->w0 == (int)floorf(scrolls[i] + 0.5f) - 1,
              "%s: scroll %g gives shifts from %d", t->name, scrolls[i], comp->w0);
        for (int p = 0; p < 9; p++)
            for (int y = 0; y < rows; y++)
                for (int x = 0; x < half; x++) {
                    int sx = comp->w0 + p % 3, sy = comp->w0 + p / 3;
                    int bx = ((x - sx) % half + half) % half, by = ((y - sy) % rows + rows) % rows;
                    uint8_t f = t->mip[0][y * t->width + x], want = f ? f : t->mip[0][by * t->width + half + bx];
                    bad += comp->planes[(size_t)p * half * rows + (size_t)y * half + x] != want;
                }
    }
    CHECK(bad == 0, "%s: %ld plane texels are not the front layer over the shifted back one", t->name, bad);
}

int main(void) {
    for (int i = 0; i < 256; i++) palette[i] = 0xff000000u | (uint32_t)next(1u << 24);
    const int shapes[][2] = {{256, 128}, {64, 32}, {32, 128}};
    for (int k = 0; k < 3; k++) {
        sky s = make_sky(shapes[k][0], shapes[k][1]);
        CHECK(s.px != NULL, "out of memory");
        if (!s.px) continue;
        ew_sky_comp comp = {0};
        long compared = 0, differ = sweep(&s.tex, &comp, -1, &compared);
        CHECK(differ == 0 && compared > 0, "%s: %ld of %ld pixels' bytes differ through the planes", s.tex.name, differ,
              compared);
        printf("%s: %ld pixels through the planes, %ld bytes differing\n", s.tex.name, compared, differ);
        check_planes(&s.tex, &comp);
        if (k == 0) {
            /* The planes of equal shifts across and down are read by most
             * pixels; the others where a segment's two shifts straddle a
             * whole texel, which a random view seldom meets. */
            int read = 0;
            for (int p = 0; p < 9; p++) {
                long c = 0, d = sweep(&s.tex, &comp, p, &c);
                read += d > 0;
                if (p % 4 == 0)
                    CHECK(d > 0, "%s: plane %d overwritten, yet no pixel changed (is it read?)", s.tex.name, p);
            }
            printf("%s: %d of the 9 planes, overwritten, changed pixels\n", s.tex.name, read);
        }
        ew_sky_comp_free(&comp);
        free(s.px);
    }
    /* Layers not a power of two: no planes, the spans draw layer by layer. */
    sky odd = make_sky(192, 128);
    ew_sky_comp comp = {0};
    CHECK(odd.px && ew_sky_comp_make(&comp, &odd.tex, 3.5f) != 0 && comp.tex == NULL,
          "a sky of 96-texel layers gets no planes");
    ew_sky_comp_free(&comp);
    free(odd.px);
    return ew_t_finish();
}
