/*
 * The nearest-colour cubes of 8-bit frames (light/blend.c, ew_blend_cube):
 * every one of the 64^3 cells of both cubes (plain: least squared RGB
 * distance; hue: least EW_HUE_DIST) against a search of all 224 choices
 * written here from the definition (the first index at the least distance),
 * for the built-in scene's palette, LibreQuake's (if ../shared is there),
 * and made-up palettes full of repeated colours and equal distances, where
 * only the tie rule decides.  The cubes' build does not search: it sweeps
 * a lower envelope of lines along each blue row (light/blend.c says why
 * that is exact), so this is what keeps it exact; built in
 * slices (as the renderer's threads build them), in any order, they are
 * the same.
 */
#define _POSIX_C_SOURCE 200809L
#include "util.h"
#include "light/blend.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum { CHOICES = 224, CELLS = 64 * 64 * 64 };

/* The cell centres, as blend.h documents the cube's steps: channel value
 * 255 (k / 63)^2 at step k. */
static int centre(int k) { return (int)lrint(255.0 * (k / 63.0) * (k / 63.0)); }

static void reference(const uint8_t pal[768], uint8_t *plain, uint8_t *hue) {
    for (int r = 0; r < 64; r++)
        for (int g = 0; g < 64; g++)
            for (int b = 0; b < 64; b++) {
                int best = 0, bestd = -1, besth = 0;
                long bestdh = 0;
                for (int i = 0; i < CHOICES; i++) {
                    int dr = pal[i * 3] - centre(r), dg = pal[i * 3 + 1] - centre(g), db = pal[i * 3 + 2] - centre(b);
                    int d = dr * dr + dg * dg + db * db, s = dr + dg + db;
                    long dh = (long)EW_HUE_DIST(d, s);
                    if (bestd < 0 || d < bestd) bestd = d, best = i;
                    if (i == 0 || dh < bestdh) bestdh = dh, besth = i;
                }
                plain[(r << 12) | (g << 6) | b] = (uint8_t)best;
                hue[(r << 12) | (g << 6) | b] = (uint8_t)besth;
            }
}

static double now_ms(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec * 1e3 + t.tv_nsec / 1e6;
}

static void check_palette(const char *name, const uint8_t pal[768]) {
    static uint8_t want_plain[CELLS], want_hue[CELLS];
    double r0 = now_ms();
    reference(pal, want_plain, want_hue);
    double ref_ms = now_ms() - r0;
    ew_blend b;
    ew_blend_init(&b, pal);
    double t0 = now_ms();
    const uint8_t *cube = ew_blend_cube(&b);
    double ms = now_ms() - t0;
    CHECK(cube && b.hue, "%s: no cubes", name);
    if (cube && b.hue) {
        long bad = 0, badh = 0;
        int first = -1;
        for (int i = 0; i < CELLS; i++) {
            if (cube[i] != want_plain[i] && first < 0) first = i;
            bad += cube[i] != want_plain[i];
            badh += b.hue[i] != want_hue[i];
        }
        CHECK(bad == 0 && badh == 0, "%s: %ld plain and %ld hue cells differ from the search (first %d: %d, want %d)",
              name, bad, badh, first, first >= 0 ? cube[first] : 0, first >= 0 ? want_plain[first] : 0);
        /* The cube must be the one ew_blend_at addresses. */
        CHECK(ew_blend_at(&b, 255, 255, 255) == ((63 << 12) | (63 << 6) | 63) && ew_blend_at(&b, 0, 0, 0) == 0,
              "%s: ew_blend_at does not address the corners", name);
        printf("  %-28s both cubes equal the search (%d cells each): built in %.1f ms, the search %.1f ms\n", name,
               CELLS, ms, ref_ms);
    }
    /* In slices, in any order (as a pool's threads take them): the same. */
    ew_blend s;
    ew_blend_init(&s, pal);
    CHECK(ew_blend_cube_begin(&s, 1) == 1, "%s: begin has nothing to build", name);
    for (int r = 63; r >= 0; r -= 2) ew_blend_cube_slice(&s, r);
    for (int r = 0; r < 64; r += 2) ew_blend_cube_slice(&s, r);
    ew_blend_cube_end(&s);
    CHECK(s.nearest && s.hue && cube && b.hue && !memcmp(s.nearest, cube, CELLS) && !memcmp(s.hue, b.hue, CELLS),
          "%s: the cubes built in slices differ", name);
    CHECK(ew_blend_cube_begin(&s, 1) == 0, "%s: begin after end builds again", name);
    ew_blend_free(&s);
    /* The plain cube alone (translucency without coloured light): the same,
     * and no hue cube. */
    ew_blend_init(&s, pal);
    CHECK(ew_blend_cube_begin(&s, 0) == 1, "%s: begin (plain) has nothing to build", name);
    for (int r = 0; r < 64; r++) ew_blend_cube_slice(&s, r);
    ew_blend_cube_end(&s);
    CHECK(s.nearest && !s.hue && cube && !memcmp(s.nearest, cube, CELLS), "%s: the plain cube alone differs", name);
    ew_blend_free(&s);
    ew_blend_free(&b);
}

static uint32_t rng = 12345;
static int next(int n) {
    rng = rng * 1664525u + 1013904223u;
    return (int)((rng >> 8) % (uint32_t)n);
}

int main(void) {
    ew_error err = {""};
    ew_assets *a = ew_assets_create_builtin(&err);
    CHECK(a != NULL, "built-in scene: %s", err.msg);
    if (a) check_palette("the built-in scene's palette", a->palette);
    ew_assets_destroy(a);

    if (ew_t_need_shared("data/librequake/gfx/palette.lmp")) {
        uint8_t *d = NULL;
        size_t n = 0;
        if (ew_read_file(ew_t_shared("data/librequake/gfx/palette.lmp"), &d, &n, &err) == 0 && n >= 768)
            check_palette("LibreQuake's palette", d);
        else
            CHECK(0, "LibreQuake's palette: %s", err.msg);
        free(d);
    }

    /* Repeats: 24 colours, each used nine or ten times, so every cell's
     * least distance is shared by several indices. */
    uint8_t pal[768];
    for (int i = 0; i < 256; i++)
        for (int c = 0; c < 3; c++) pal[i * 3 + c] = (uint8_t)(((i % 24) * 37 + c * 91) % 256);
    check_palette("24 colours, each repeated", pal);
    /* Equal distances: a coarse grid of values (multiples of 51 and their
     * midpoints), many colours the same distance from a cell's centre. */
    for (int i = 0; i < 768; i++) pal[i] = (uint8_t)(next(11) * 51 / 2);
    check_palette("a grid of equal distances", pal);
    /* Greys and near-greys only: the hue distance's own ties. */
    for (int i = 0; i < 256; i++) {
        int v = next(256);
        for (int c = 0; c < 3; c++) pal[i * 3 + c] = (uint8_t)(v + next(3) > 255 ? 255 : v + next(3));
    }
    check_palette("greys", pal);
    return ew_t_finish();
}
