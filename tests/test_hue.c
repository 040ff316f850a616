/*
 * Hue of coloured light in 8-bit frames (issue 30), on the ericw-tools maps
 * start and dev (../shared/data/ericw), at 640x480 from cameras that look at
 * their coloured lights (start's five lit cubes, dev's coloured walls):
 *   1. over the pixels of faces whose light is tinted, where the true-colour
 *      frame shows colour (max - min channel above 24 of 255), the 8-bit
 *      frame (through the palette) against the true-colour frame: the mean
 *      hue error (degrees, circular; a grey 8-bit pixel counts 90, the
 *      expected error of a guess) and the chroma ratio (sum of 8-bit chroma
 *      over sum of true-colour chroma), on each map, with and without the
 *      ordered dither, and on the blue cube alone (faces whose light is
 *      clearly blue); also over the means of 4x4 blocks (what the eye makes
 *      of a dither) and the lightness error (what the tint may cost).  Each
 *      must pass a threshold the old nearest-colour rule (the colormap's
 *      ramp unless the nearest colour is much closer) failed;
 *   2. white light keeps the classic look byte for byte: the maps with their
 *      .lit made grey (each sample the mono lump's value) draw the same 8-bit
 *      frames as with coloured light off, and --classic frames ignore the .lit;
 *   3. light that is nearly white (the mono lump with blue one level up)
 *      keeps the colormap's ramps on nearly every pixel.
 */
#include "edgewise_lab.h"
#include "util.h"
#include "ew_world.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define W 640
#define H 480
#define NPX (W * H)

#define TINTED_PIXEL 24  /* true-colour chroma (max - min) that counts as coloured */
#define TINTED_FACE  24  /* mean chroma of a face's light samples (style 0) that counts as tinted */

typedef struct map_case {
    const char *name;
    int ncams;
    float cam[6][6];            /* x y z pitch yaw roll */
    double max_hue, min_ratio;  /* on the map's tinted pixels, with and without the dither */
} map_case;

/* The cameras: start's two that see the cubes (ericw/README.md), and turns of
 * them; dev's coloured walls by its teleporters and its red room.  The
 * thresholds lie between the old rule's figures and the new ones (docs/color.md,
 * "A tint in 8-bit"): start 6.6 deg, chroma 0.54 then; dev's hue error
 * moves little (7.7 deg then, 7.3 to 7.8 now: its red floor has no better
 * colour), its chroma 0.81 then. */
static const map_case cases[] = {
    {"start_plain", 5,
     {{-100, -560, 60, 20, 250, 0}, {-48, -600, 80, 30, 270, 0}, {-48, -600, 80, 30, 255, 0},
      {-48, -600, 80, 30, 285, 0}, {-100, -560, 60, 20, 235, 0}},
     5.0, 0.60},
    {"dev_plain", 3, {{-290, -410, -30, 5, 265, 0}, {-280, -560, -20, 10, 90, 0}, {-280, -400, -20, 10, 270, 0}},
     8.5, 0.85},
    {"start_bsp2_bspxlit", 1, {{-48, -600, 80, 30, 270, 0}}, 5.0, 0.54},
};
/* The blue cube (start: the faces lit clearly blue, in every view; the
 * second camera has it in the middle): its chroma 0.45 of true colour's
 * under the old rule. */
#define BLUE_MAX_HUE   2.0
#define BLUE_MIN_RATIO 0.52
/* Lightness may pay for chroma, within bounds (a heavier chroma weight
 * brightens the blue cube's dark blues to 18 levels off). */
#define MAX_LIGHT_ERR      8.0
#define BLUE_MAX_LIGHT_ERR 12.0

static ew_camera camera(const float *c) {
    ew_camera cam = {{c[0], c[1], c[2]}, {c[3], c[4], c[5]}, 90, 0};
    return cam;
}

static ew_renderer *make(const ew_assets *a, const ew_world *w, ew_color_mode c) {
    ew_error err = {""};
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){.world = w, .palette = a->palette,
                                                            .colormap = a->colormap, .width = W, .height = H,
                                                            .color = c},
                                        &err);
    CHECK(r != NULL, "renderer: %s", err.msg);
    return r;
}

/* HSV hue in degrees and chroma (max - min) of an RGB colour; hue -1 if grey. */
static double hue_of(const uint8_t *p, int *chroma) {
    int r = p[0], g = p[1], b = p[2];
    int mx = r > g ? (r > b ? r : b) : (g > b ? g : b), mn = r < g ? (r < b ? r : b) : (g < b ? g : b);
    int c = mx - mn;
    *chroma = c;
    if (c == 0) return -1;
    double h = mx == r ? fmod((double)(g - b) / c + 6, 6) : mx == g ? (double)(b - r) / c + 2 : (double)(r - g) / c + 4;
    return h * 60;
}

/* Per face: 1 if its light (style 0 of the .lit) is tinted, 2 if clearly blue. */
static uint8_t *tinted_faces(const ew_world *w, int *ntinted, int *nblue) {
    uint8_t *t = calloc((size_t)w->numfaces, 1);
    *ntinted = *nblue = 0;
    for (int fi = 0; t && w->rgblight && fi < w->numfaces; fi++) {
        const ew_face *f = &w->faces[fi];
        int ofs = f->lightofs, n = ((f->extents[0] >> 4) + 1) * ((f->extents[1] >> 4) + 1);
        if (w->facelm) ofs = w->facelm[fi].lightofs, n = w->facelm[fi].width * w->facelm[fi].height;
        if (ofs < 0 || f->styles[0] == 255 || n <= 0 || ofs + n > w->lightsize) continue;
        double chroma = 0, sum[3] = {0, 0, 0};
        for (int i = 0; i < n; i++) {
            const uint8_t *q = w->rgblight + 3 * (size_t)(ofs + i);
            int c;
            hue_of(q, &c);
            chroma += c;
            for (int k = 0; k < 3; k++) sum[k] += q[k];
        }
        if (chroma / n < TINTED_FACE) continue;
        t[fi] = 1, ++*ntinted;
        if ((sum[2] - (sum[0] > sum[1] ? sum[0] : sum[1])) / n >= 32) t[fi] = 2, ++*nblue;
    }
    return t;
}

typedef struct hue_acc {
    double hue_err, c8, ct, light_err;
    long n;
} hue_acc;

static void add(hue_acc *a, const uint8_t t[3], const uint8_t e[3]) {
    int ct, c8;
    double ht = hue_of(t, &ct), h8 = hue_of(e, &c8), d = 90;
    if (h8 >= 0) {
        d = fabs(ht - h8);
        if (d > 180) d = 360 - d;
    }
    a->hue_err += d, a->c8 += c8, a->ct += ct, a->n++;
    a->light_err += fabs((e[0] + e[1] + e[2] - t[0] - t[1] - t[2]) / 3.0);
}

/* Adds one view (8-bit indices p8, true colour rgba, faces ids) to acc:
 * [0] every tinted pixel, [1] those of faces lit blue, and the same for the
 * means of 4x4 blocks wholly on tinted faces ([2], [3]: what the eye sees
 * of a dither). */
static void accumulate(const uint8_t *pal, const uint8_t *p8, const uint32_t *rgba, const int *ids, const uint8_t *tf,
                       hue_acc acc[4]) {
    for (int i = 0; i < NPX; i++) {
        int f = ids[i];
        if (f < 0 || !tf[f]) continue;
        uint8_t t[3];
        memcpy(t, &rgba[i], 3);  /* ew_rgba: R, G, B, A bytes in memory */
        int ct;
        hue_of(t, &ct);
        if (ct <= TINTED_PIXEL) continue;
        add(&acc[0], t, pal + 3 * p8[i]);
        if (tf[f] == 2) add(&acc[1], t, pal + 3 * p8[i]);
    }
    for (int by = 0; by + 4 <= H; by += 4)
        for (int bx = 0; bx + 4 <= W; bx += 4) {
            int st[3] = {0, 0, 0}, s8[3] = {0, 0, 0}, all = 1, blue = 1;
            for (int y = by; y < by + 4 && all; y++)
                for (int x = bx; x < bx + 4; x++) {
                    int i = y * W + x, f = ids[i];
                    if (f < 0 || !tf[f]) {
                        all = 0;
                        break;
                    }
                    blue &= tf[f] == 2;
                    const uint8_t *t = (const uint8_t *)&rgba[i], *e = pal + 3 * p8[i];
                    for (int k = 0; k < 3; k++) st[k] += t[k], s8[k] += e[k];
                }
            if (!all) continue;
            uint8_t t[3], e[3];
            for (int k = 0; k < 3; k++) t[k] = (uint8_t)((st[k] + 8) / 16), e[k] = (uint8_t)((s8[k] + 8) / 16);
            int ct;
            hue_of(t, &ct);
            if (ct <= TINTED_PIXEL) continue;
            add(&acc[2], t, e);
            if (blue) add(&acc[3], t, e);
        }
}

static double mean_hue(const hue_acc *a) { return a->n ? a->hue_err / a->n : 0; }
static double ratio(const hue_acc *a) { return a->ct > 0 ? a->c8 / a->ct : 0; }
static double light_err(const hue_acc *a) { return a->n ? a->light_err / a->n : 0; }

/* The map's world again (no .lit attached) with a .lit made from its own mono
 * light: each sample's channels at the mono value, blue raised by tint_blue. */
static ew_world *mono_lit_world(const char *name, int tint_blue) {
    char rel[256];
    snprintf(rel, sizeof rel, "data/ericw/maps/%s.bsp", name);
    uint8_t *bsp = NULL;
    size_t size = 0;
    ew_error err = {""};
    ew_world *w = NULL;
    if (ew_read_file(ew_t_shared(rel), &bsp, &size, &err) == 0) w = ew_world_create(bsp, size, name, &err);
    CHECK(w != NULL, "%s: %s", name, err.msg);
    free(bsp);
    if (!w) return NULL;
    if (w->rgblight) {  /* a BSPX RGBLIGHTING lump: not what this test wants */
        ew_world_destroy(w);
        CHECK(0, "%s: carries coloured light of its own", name);
        return NULL;
    }
    size_t n = 8 + 3 * (size_t)w->lightsize;
    uint8_t *lit = malloc(n);
    memcpy(lit, "QLIT\1\0\0\0", 8);
    for (int i = 0; i < w->lightsize; i++) {
        uint8_t m = w->lighting[i];
        int b = m + tint_blue;
        lit[8 + 3 * i] = lit[8 + 3 * i + 1] = m;
        lit[8 + 3 * i + 2] = (uint8_t)(b > 255 ? 255 : b);
    }
    CHECK(ew_world_attach_lit(w, lit, n, name) == 0 && w->rgblight, "%s: made .lit refused", name);
    free(lit);
    return w;
}

/* An ericw map of the cases with its light, and its entities in *scene
 * (the cubes are brush entities); NULL after a failed CHECK. */
static ew_assets *load_case(const map_case *mc, ew_scene **scene) {
    char rel[256];
    snprintf(rel, sizeof rel, "data/ericw/maps/%s.bsp", mc->name);
    ew_error err = {""};
    *scene = NULL;
    ew_assets *a = ew_assets_create(ew_t_shared(rel), NULL, &err);
    CHECK(a != NULL, "%s: %s", mc->name, err.msg);
    if (!a) return NULL;
    *scene = ew_scene_create_from_map(a->world, ew_t_shared(rel), NULL, &err);
    CHECK(*scene != NULL, "%s: scene: %s", mc->name, err.msg);
    return a;
}

/* ---- 1. hue and chroma of tinted light ------------------------------------------ */

static void test_hue(void) {
    uint8_t *p8 = malloc(NPX);
    uint32_t *rgba = malloc(4 * (size_t)NPX);
    int *ids = malloc(sizeof(int) * NPX);
    for (size_t mi = 0; mi < sizeof cases / sizeof cases[0]; mi++) {
        const map_case *mc = &cases[mi];
        ew_scene *scene;
        ew_assets *a = load_case(mc, &scene);
        if (!a) continue;
        CHECK(a->world->rgblight != NULL, "%s: no coloured light", mc->name);
        int ntinted, nblue;
        uint8_t *tf = tinted_faces(a->world, &ntinted, &nblue);
        ew_renderer *rt = make(a, a->world, EW_COLOR_TRUE), *r8 = make(a, a->world, EW_COLOR_8BIT);
        if (!rt || !r8 || !tf || !scene) goto next;
        ew_set_scene(rt, scene), ew_set_scene(r8, scene);
        ew_enable_face_ids(rt, 1);
        double block_light[2] = {0, 0};
        for (int dither = 0; dither < 2; dither++) {
            ew_set_dither(r8, dither);
            hue_acc acc[4] = {{0}};
            for (int c = 0; c < mc->ncams; c++) {
                ew_camera cam = camera(mc->cam[c]);
                CHECK(ew_render(rt, &cam, NULL) == 0 && ew_render(r8, &cam, NULL) == 0, "%s camera %d", mc->name, c);
                memcpy(rgba, ew_frame_rgba(rt), 4 * (size_t)NPX);
                memcpy(ids, ew_frame_face_ids(rt), sizeof(int) * NPX);
                memcpy(p8, ew_frame_pixels(r8), NPX);
                accumulate(a->palette, p8, rgba, ids, tf, acc);
            }
            const hue_acc *all = &acc[0], *blue = &acc[1], *ball = &acc[2], *bblue = &acc[3];
            const char *how = dither ? "dither" : "no dither";
            int start = strncmp(mc->name, "start", 5) == 0;
            printf("1. %-18s %-9s %d tinted faces, %ld tinted pixels: hue error %4.1f deg, chroma ratio %.2f, "
                   "lightness error %4.1f; 4x4 means: %4.1f deg, %.2f, %4.1f\n", mc->name, how, ntinted, all->n,
                   mean_hue(all), ratio(all), light_err(all), mean_hue(ball), ratio(ball), light_err(ball));
            if (start)
                printf("1. %-18s %-9s the blue cube: %d faces, %ld pixels: hue error %4.1f deg, chroma ratio %.2f, "
                       "lightness error %4.1f; 4x4 means: %4.1f deg, %.2f, %4.1f\n", mc->name, how, nblue, blue->n,
                       mean_hue(blue), ratio(blue), light_err(blue), mean_hue(bblue), ratio(bblue), light_err(bblue));
            block_light[dither] = light_err(ball);
            CHECK(all->n >= 20000 && ball->n >= 1000, "%s: only %ld tinted pixels in view (%ld blocks)", mc->name,
                  all->n, ball->n);
            CHECK(mean_hue(all) <= mc->max_hue, "%s %s: mean hue error %.1f deg (at most %.1f)", mc->name, how,
                  mean_hue(all), mc->max_hue);
            CHECK(ratio(all) >= mc->min_ratio, "%s %s: chroma ratio %.2f (at least %.2f)", mc->name, how, ratio(all),
                  mc->min_ratio);
            CHECK(light_err(all) <= MAX_LIGHT_ERR, "%s %s: lightness error %.1f (at most %.1f)", mc->name, how,
                  light_err(all), MAX_LIGHT_ERR);
            if (start) {
                CHECK(blue->n >= 20000, "%s: only %ld pixels of the blue cube", mc->name, blue->n);
                CHECK(mean_hue(blue) <= BLUE_MAX_HUE && ratio(blue) >= BLUE_MIN_RATIO,
                      "%s %s: the blue cube's hue error %.1f deg (at most %.0f), chroma ratio %.2f (at least %.2f)",
                      mc->name, how, mean_hue(blue), BLUE_MAX_HUE, ratio(blue), BLUE_MIN_RATIO);
                CHECK(light_err(blue) <= BLUE_MAX_LIGHT_ERR, "%s %s: the blue cube's lightness error %.1f (at most %.1f)",
                      mc->name, how, light_err(blue), BLUE_MAX_LIGHT_ERR);
            }
        }
        /* The dither mixes colours: over 4x4 blocks its mean comes nearer
         * the true colour's lightness than the nearest colours alone. */
        CHECK(block_light[1] < block_light[0] - 0.5, "%s: the dither leaves 4x4 means %.1f levels off in lightness, "
              "without it %.1f", mc->name, block_light[1], block_light[0]);
    next:
        ew_renderer_destroy(rt), ew_renderer_destroy(r8);
        ew_scene_destroy(scene);
        free(tf);
        ew_assets_destroy(a);
    }
    free(p8), free(rgba), free(ids);
}

/* ---- 2, 3. white and nearly white light ------------------------------------------ */

static void test_white(void) {
    uint8_t *white = malloc(NPX);
    for (size_t mi = 0; mi < 2; mi++) {
        const map_case *mc = &cases[mi];
        ew_scene *scene;
        ew_assets *a = load_case(mc, &scene);
        if (!a) continue;
        ew_world *wg = mono_lit_world(mc->name, 0), *wn = mono_lit_world(mc->name, 1);
        ew_renderer *r0 = make(a, a->world, EW_COLOR_8BIT), *rg = wg ? make(a, wg, EW_COLOR_8BIT) : NULL;
        ew_renderer *rn = wn ? make(a, wn, EW_COLOR_8BIT) : NULL, *rc = make(a, a->world, EW_COLOR_8BIT);
        ew_renderer *rc0 = make(a, a->world, EW_COLOR_8BIT);
        if (r0 && rg && rn && rc && rc0 && scene) {
            ew_renderer *all[] = {r0, rg, rn, rc, rc0};
            for (int k = 0; k < 5; k++) ew_set_scene(all[k], scene);
            ew_set_lit(r0, 0);
            ew_set_classic(rc, 1), ew_set_classic(rc0, 1), ew_set_lit(rc0, 0);
            int grey_diff = 0, classic_diff = 0;
            long same = 0, total = 0;
            for (int dither = 0; dither < 2; dither++) {
                ew_set_dither(rg, dither), ew_set_dither(rn, dither), ew_set_dither(rc, dither);
                for (int c = 0; c < mc->ncams; c++) {
                    ew_camera cam = camera(mc->cam[c]);
                    CHECK(ew_render(r0, &cam, NULL) == 0 && ew_render(rg, &cam, NULL) == 0 &&
                          ew_render(rn, &cam, NULL) == 0 && ew_render(rc, &cam, NULL) == 0 &&
                          ew_render(rc0, &cam, NULL) == 0, "%s camera %d", mc->name, c);
                    memcpy(white, ew_frame_pixels(r0), NPX);
                    grey_diff += memcmp(white, ew_frame_pixels(rg), NPX) != 0;
                    classic_diff += memcmp(ew_frame_pixels(rc0), ew_frame_pixels(rc), NPX) != 0;
                    const uint8_t *pn = ew_frame_pixels(rn);
                    for (int i = 0; i < NPX; i++) same += pn[i] == white[i];
                    total += NPX;
                }
            }
            printf("2. %-18s grey .lit vs no .lit: 8-bit frames differ on %d of %d; --classic with and without "
                   ".lit differ on %d\n", mc->name, grey_diff, 2 * mc->ncams, classic_diff);
            printf("3. %-18s light one level blue of white: %.2f%% of 8-bit pixels as under white light\n", mc->name,
                   100.0 * same / total);
            CHECK(grey_diff == 0, "%s: grey light changes the 8-bit frame on %d cameras", mc->name, grey_diff);
            CHECK(classic_diff == 0, "%s: the .lit changes --classic frames on %d cameras", mc->name, classic_diff);
            CHECK(same >= total * 97 / 100, "%s: nearly white light leaves only %.2f%% of pixels on the ramps",
                  mc->name, 100.0 * same / total);
        }
        ew_renderer_destroy(r0), ew_renderer_destroy(rg), ew_renderer_destroy(rn), ew_renderer_destroy(rc);
        ew_renderer_destroy(rc0);
        ew_scene_destroy(scene);
        ew_world_destroy(wg), ew_world_destroy(wn);
        ew_assets_destroy(a);
    }
    free(white);
}

int main(void) {
    if (!ew_t_need_shared("data/ericw/maps/start_plain.lit")) return ew_t_finish();
    test_hue();
    test_white();
    return ew_t_finish();
}
