/* The light oracle: the edge list lit through the surface cache against the
 * reference (a z-buffer per pixel) lit in two passes per pixel
 * (light/twopass.c, which shares no code with the cache), compared by
 * colour, not by face:
 *   - 8x8 blocks whose mean differs by more than 12 levels in a channel
 *     (the fidelity test's measure), and pixels of exactly equal colour;
 *   - every view of the shared maps at 320x200, 8-bit and true colour,
 *     with .lit light, and ericw-tools' maps with BSPX RGBLIGHTING,
 *     LMSHIFT 3, mixed shifts with LMOFFSET and DECOUPLED_LM;
 *   - controls: the cache with its light map moved one sample, or with s
 *     and t swapped (ew_set_light_fault), must fail the same limits.
 * World only (no entities), no fog, opaque liquids: light alone. */
#include "edgewise_lab.h"
#include "mapgen_util.h"
#include "util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define W 320
#define H 200
/* Limits: the share of 8x8 blocks off by more than 12 levels, per view and
 * over a map's views.  The two methods differ in how they step light and
 * texture inside a texel (fixed point from the right-hand sample against
 * floating point per pixel), which moves a texel edge or a light level by
 * one now and then, never a block's mean by 12. */
#define VIEW_LIMIT 0.03
#define MEAN_LIMIT 0.005
/* ... and the pixels of exactly the same colour, over a map's views: the
 * two texture and light steppings part by a level or a texel in places,
 * far less than half the frame. */
#define EXACT_LIMIT 0.6

/* every fourth view under the sanitizers: the same checks, a quarter of the time */
#define VIEW_STEP (EW_T_SANITIZED ? 4 : 1)

typedef struct result {
    double bad, exact;   /* share of bad blocks, share of exact pixels */
} result;

/* The frame as RGB bytes (8-bit frames through the palette). */
static void frame_rgb(const ew_renderer *r, const uint8_t *pal, uint8_t *out) {
    if (ew_frame_color(r) == EW_COLOR_TRUE) {
        const uint8_t *p = (const uint8_t *)ew_frame_rgba(r);
        for (int i = 0; i < W * H; i++) memcpy(out + i * 3, p + i * 4, 3);
    } else {
        const uint8_t *p = ew_frame_pixels(r);
        for (int i = 0; i < W * H; i++) memcpy(out + i * 3, pal + p[i] * 3, 3);
    }
}

static result compare(const uint8_t *a, const uint8_t *b) {
    long bad = 0, blocks = 0, exact = 0;
    for (int i = 0; i < W * H; i++) exact += memcmp(a + i * 3, b + i * 3, 3) == 0;
    for (int by = 0; by + 8 <= H; by += 8)
        for (int bx = 0; bx + 8 <= W; bx += 8) {
            long sa[3] = {0, 0, 0}, sb[3] = {0, 0, 0};
            for (int y = by; y < by + 8; y++)
                for (int x = bx; x < bx + 8; x++)
                    for (int c = 0; c < 3; c++) sa[c] += a[(y * W + x) * 3 + c], sb[c] += b[(y * W + x) * 3 + c];
            int off = 0;
            for (int c = 0; c < 3; c++) off |= labs(sa[c] - sb[c]) > 12 * 64;
            bad += off, blocks++;
        }
    return (result){(double)bad / blocks, (double)exact / (W * H)};
}

typedef struct map_case {
    const char *dir;    /* under ../shared/data */
    const char *name;
    int extra_cams;     /* the ericw README's coloured-cube cameras */
} map_case;

typedef struct summary { double mean_bad, worst_bad, mean_exact, worst_exact; int views, worst_view; } summary;

/* Every VIEW_STEP-th view of a map (and its extra cameras): the cache
 * (with fault) against the two-pass reference. */
static void compare_views(const map_case *mc, const ew_assets *a, ew_color_mode color, int lit, ew_light_fault fault,
                          summary *s);

/* The edge list's own lighting: the cache (0), or its two-pass mode (1). */
static int edge_two_pass;

static int run_map(const map_case *mc, ew_color_mode color, int lit, ew_light_fault fault, summary *s) {
    char path[512], data[512];
    snprintf(path, sizeof path, "data/%s/maps/%s.bsp", mc->dir, mc->name);
    snprintf(data, sizeof data, "data/%s", mc->dir);
    char pathbuf[1024], databuf[1024];
    snprintf(pathbuf, sizeof pathbuf, "%s", ew_t_shared(path));
    snprintf(databuf, sizeof databuf, "%s", ew_t_shared(data));
    ew_error err;
    ew_assets *a = ew_assets_create(pathbuf, databuf, &err);
    CHECK(a != NULL, "%s", err.msg);
    if (!a) return -1;
    compare_views(mc, a, color, lit, fault, s);
    ew_assets_destroy(a);
    return 0;
}

static void compare_views(const map_case *mc, const ew_assets *a, ew_color_mode color, int lit, ew_light_fault fault,
                          summary *s) {
    ew_error err;
    ew_camera views[EW_MAX_VIEWS + 2];
    int nv = ew_benchmark_views(a->world, views);
    CHECK(nv > 0, "%s: no views", mc->name);
    if (mc->extra_cams) {
        views[nv++] = (ew_camera){{-100, -560, 60}, {20, 250, 0}, 90, 0};
        views[nv++] = (ew_camera){{-48, -600, 80}, {30, 270, 0}, 90, 0};
    }
    ew_renderer *edge = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                                .colormap = a->colormap, .width = W, .height = H,
                                                                .threads = 1, .color = color}, &err);
    ew_renderer *ref = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                               .colormap = a->colormap, .width = W, .height = H,
                                                               .threads = 1, .color = color,
                                                               .hsr = EW_HSR_REFERENCE}, &err);
    CHECK(edge && ref, "%s: %s", mc->name, err.msg);
    uint8_t *fa = malloc(W * H * 3), *fb = malloc(W * H * 3);
    *s = (summary){0, 0, 0, 1, 0, -1};
    for (int k = 0; edge && ref && k < 2; k++) {
        ew_renderer *r = k ? ref : edge;
        ew_set_lit(r, lit);
        ew_set_fog(r, 0, 0, 0, 0);
        ew_set_liquid_alpha(r, 1);
    }
    if (edge && ref) {
        ew_set_lighting(ref, EW_LIGHTING_TWO_PASS);
        ew_set_lighting(edge, edge_two_pass ? EW_LIGHTING_TWO_PASS : EW_LIGHTING_CACHE);
        ew_set_light_fault(edge, fault);
    }
    for (int v = 0; edge && ref && v < nv; v++) {
        if (v % VIEW_STEP && v < nv - 2 * mc->extra_cams) continue;
        int ok = ew_render(edge, &views[v], NULL) == 0;
        if (ok) frame_rgb(edge, a->palette, fa);
        ok = ok && ew_render(ref, &views[v], NULL) == 0;
        CHECK(ok, "%s view %d: render failed", mc->name, v);
        if (!ok) continue;
        frame_rgb(ref, a->palette, fb);
        result res = compare(fa, fb);
        s->views++;
        s->mean_bad += res.bad, s->mean_exact += res.exact;
        if (res.bad > s->worst_bad || s->worst_view < 0) s->worst_bad = res.bad, s->worst_view = v;
        if (res.exact < s->worst_exact) s->worst_exact = res.exact;
    }
    if (s->views) s->mean_bad /= s->views, s->mean_exact /= s->views;
    free(fa), free(fb);
    ew_renderer_destroy(edge), ew_renderer_destroy(ref);
}

/* The built-in level as the project's map writer bakes it in a BSPX layout
 * (LMSHIFT 3 and 5 with LMOFFSET, DECOUPLED_LM), in tinted light. */
static int run_generated(const char *label, const ew_mapgen_options *o, ew_color_mode color, summary *s) {
    ew_assets *a = calloc(1, sizeof *a);
    gen g = generate_map(o, a->palette, a->colormap);
    ew_error err = {""};
    a->world = g.bsp ? ew_world_create(g.bsp, g.size, label, &err) : NULL;
    CHECK(a->world != NULL, "%s: %s", label, err.msg);
    if (a->world) {
        map_case mc = {"mapgen", label, 0};
        compare_views(&mc, a, color, 1, EW_LIGHT_FAULT_NONE, s);
    }
    int rc = a->world ? 0 : -1;
    ew_world_destroy(a->world);
    free(a);
    gen_free(&g);
    return rc;
}

static const char *color_name(ew_color_mode c) { return c == EW_COLOR_TRUE ? "true" : "8bit"; }

int main(void) {
    if (!ew_t_need_shared("data/librequake/maps/e1m1.bsp") || !ew_t_need_shared("data/ericw/maps/start_plain.bsp"))
        return ew_t_finish();
    static const map_case cases[] = {
        {"librequake", "e1m1", 0},  {"librequake", "e2m1", 0},  {"librequake", "e4m1", 0},
        {"librequake", "lqdm1", 0}, {"librequake", "lqdm7", 0}, {"librequake", "slope", 0},
        {"librequake", "start", 0},
        {"ericw", "start_plain", 1},         {"ericw", "start_bsp2_bspxlit", 1},
        {"ericw", "start_lmscale8", 1},      {"ericw", "start_lmshiftmix", 1},
        {"ericw", "start_decoupled", 1},     {"ericw", "start_decoupled_novanilla", 1},
        {"ericw", "start_bsp2_bspxall", 1},  {"ericw", "dev_plain", 0},
        {"ericw", "dev_bsp2_bspxlit", 0},    {"ericw", "dev_lmscale8", 0},
        {"ericw", "dev_lmshiftmix", 0},      {"ericw", "dev_decoupled", 0},
        {"ericw", "dev_decoupled_novanilla", 0}, {"ericw", "dev_bsp2_bspxall", 0},
    };
    enum { NCASES = sizeof cases / sizeof *cases };
    double worst_all = 0, sum_all = 0;
    int n_all = 0;
    printf("%-28s %-5s %-5s %6s %9s %9s %9s %9s\n", "map", "color", "light", "views", "bad mean", "bad worst",
           "exact mean", "exact worst");
    for (int i = 0; i < NCASES; i++) {
        char rel[512];
        snprintf(rel, sizeof rel, "data/%s/maps/%s.bsp", cases[i].dir, cases[i].name);
        CHECK(ew_t_have_shared(rel), "%s missing", rel);
        if (!ew_t_have_shared(rel)) continue;
        for (int c = 0; c < 2; c++) {
            ew_color_mode color = c ? EW_COLOR_TRUE : EW_COLOR_8BIT;
            summary s;
            if (run_map(&cases[i], color, 1, EW_LIGHT_FAULT_NONE, &s) < 0) continue;
            printf("%-28s %-5s %-5s %6d %8.3f%% %8.3f%% %8.2f%% %8.2f%%  (worst view %d)\n", cases[i].name,
                   color_name(color), "lit", s.views, 100 * s.mean_bad, 100 * s.worst_bad, 100 * s.mean_exact,
                   100 * s.worst_exact, s.worst_view);
            CHECK(s.views > 0, "%s: no view compared", cases[i].name);
            CHECK(s.mean_exact >= EXACT_LIMIT, "%s %s: %.1f%% of pixels exactly equal (limit %.0f%%)", cases[i].name,
                  color_name(color), 100 * s.mean_exact, 100 * EXACT_LIMIT);
            CHECK(s.worst_bad <= VIEW_LIMIT, "%s %s: view %d has %.2f%% of its blocks off (limit %.1f%%)",
                  cases[i].name, color_name(color), s.worst_view, 100 * s.worst_bad, 100 * VIEW_LIMIT);
            CHECK(s.mean_bad <= MEAN_LIMIT, "%s %s: %.3f%% of blocks off over the views (limit %.1f%%)",
                  cases[i].name, color_name(color), 100 * s.mean_bad, 100 * MEAN_LIMIT);
            if (s.worst_bad > worst_all) worst_all = s.worst_bad;
            sum_all += s.mean_bad, n_all++;
        }
    }
    static const float tint[3 * EW_MAPGEN_MAX_LIGHTS] = {1, 0.4f, 0.3f, 0.3f, 1, 0.4f, 0.3f, 0.5f, 1, 1, 1, 0.3f,
                                                        1, 0.5f, 1, 0.5f, 1, 1, 1, 0.8f, 0.6f, 0.7f, 0.7f, 1};
    static const struct { const char *label; ew_mapgen_options o; } generated[] = {
        {"mapgen LMSHIFT 3", {.lmshift_lumps = 1, .lmshift = 3, .rgblighting = 1, .light_tint = tint}},
        {"mapgen LMSHIFT 5", {.lmshift_lumps = 1, .lmshift = 5, .rgblighting = 1, .light_tint = tint}},
        {"mapgen DECOUPLED_LM", {.decoupled = 1, .decoupled_units = 12, .rgblighting = 1, .light_tint = tint}},
    };
    for (int i = 0; i < (int)(sizeof generated / sizeof *generated); i++)
        for (int c = 0; c < 2; c++) {
            ew_color_mode color = c ? EW_COLOR_TRUE : EW_COLOR_8BIT;
            summary s;
            if (run_generated(generated[i].label, &generated[i].o, color, &s) < 0) continue;
            printf("%-28s %-5s %-5s %6d %8.3f%% %8.3f%% %8.2f%% %8.2f%%  (worst view %d)\n", generated[i].label,
                   color_name(color), "lit", s.views, 100 * s.mean_bad, 100 * s.worst_bad, 100 * s.mean_exact,
                   100 * s.worst_exact, s.worst_view);
            CHECK(s.views > 0 && s.worst_bad <= VIEW_LIMIT && s.mean_bad <= MEAN_LIMIT,
                  "%s %s: %.3f%% of blocks off over the views, %.2f%% in view %d", generated[i].label,
                  color_name(color), 100 * s.mean_bad, 100 * s.worst_bad, s.worst_view);
            if (s.worst_bad > worst_all) worst_all = s.worst_bad;
            sum_all += s.mean_bad, n_all++;
        }
    printf("light oracle: %d map x colour cases, mean %.3f%% of blocks off, worst view %.3f%%\n", n_all,
           n_all ? 100 * sum_all / n_all : 0, 100 * worst_all);

    /* The renderer's own two-pass mode (a ray every 16 pixels, light in
     * fixed point) against the exact one. */
    static const map_case own[] = {{"librequake", "e1m1", 0}, {"librequake", "lqdm7", 0}, {"ericw", "start_plain", 1},
                                   {"ericw", "dev_lmshiftmix", 0}};
    edge_two_pass = 1;
    for (int i = 0; i < (int)(sizeof own / sizeof *own); i++)
        for (int c = 0; c < 2; c++) {
            ew_color_mode color = c ? EW_COLOR_TRUE : EW_COLOR_8BIT;
            summary s;
            if (run_map(&own[i], color, 1, EW_LIGHT_FAULT_NONE, &s) < 0) continue;
            printf("two-pass renderer %-20s %-5s: bad mean %.3f%% worst %.3f%%, exact mean %.2f%%\n", own[i].name,
                   color_name(color), 100 * s.mean_bad, 100 * s.worst_bad, 100 * s.mean_exact);
            CHECK(s.views > 0 && s.worst_bad <= VIEW_LIMIT && s.mean_bad <= MEAN_LIMIT,
                  "two-pass renderer %s %s: %.3f%% of blocks off, %.2f%% in view %d", own[i].name, color_name(color),
                  100 * s.mean_bad, 100 * s.worst_bad, s.worst_view);
        }
    edge_two_pass = 0;

    /* Two threads draw the same two-pass frames as one (bands of one frame). */
    {
        ew_error err;
        ew_assets *a = ew_t_load_map("lqdm7");
        ew_camera views[EW_MAX_VIEWS];
        int nv = a ? ew_benchmark_views(a->world, views) : 0, same = 0, n = 0;
        for (int hsr = 0; hsr < 2 && a; hsr++) {
            ew_renderer *r[2];
            for (int k = 0; k < 2; k++) {
                r[k] = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                              .colormap = a->colormap, .width = W, .height = H,
                                                              .threads = k + 1, .color = EW_COLOR_TRUE,
                                                              .hsr = hsr ? EW_HSR_REFERENCE : EW_HSR_EDGE}, &err);
                if (r[k]) ew_set_lighting(r[k], EW_LIGHTING_TWO_PASS);
            }
            for (int v = 0; r[0] && r[1] && v < nv; v += 4) {
                ew_render(r[0], &views[v], NULL), ew_render(r[1], &views[v], NULL);
                same += memcmp(ew_frame_rgba(r[0]), ew_frame_rgba(r[1]), (size_t)W * H * 4) == 0, n++;
            }
            ew_renderer_destroy(r[0]), ew_renderer_destroy(r[1]);
        }
        printf("two-pass on 1 and 2 threads: %d of %d frames identical\n", same, n);
        CHECK(n > 0 && same == n, "two-pass: %d of %d frames differ between 1 and 2 threads", n - same, n);
        ew_assets_destroy(a);
    }

    /* Controls: a cache that reads its light map wrongly must fail. */
    static const map_case controls[] = {{"librequake", "e1m1", 0}, {"librequake", "start", 0}, {"librequake", "lqdm7", 0}};
    for (int i = 0; i < (int)(sizeof controls / sizeof *controls); i++)
        for (int fault = EW_LIGHT_FAULT_SHIFT; fault <= EW_LIGHT_FAULT_SWAP; fault++)
            for (int c = 0; c < 2; c++) {
                ew_color_mode color = c ? EW_COLOR_TRUE : EW_COLOR_8BIT;
                summary s;
                if (run_map(&controls[i], color, 0, (ew_light_fault)fault, &s) < 0) continue;
                int fails = s.worst_bad > VIEW_LIMIT || s.mean_bad > MEAN_LIMIT;
                printf("control %-20s %-5s %-5s: bad mean %.3f%% worst %.3f%%: %s\n", controls[i].name,
                       color_name(color), fault == EW_LIGHT_FAULT_SHIFT ? "shift" : "swap", 100 * s.mean_bad,
                       100 * s.worst_bad, fails ? "caught" : "MISSED");
                CHECK(fails, "control %s %s: a %s light map passed the oracle", controls[i].name,
                      color_name(color), fault == EW_LIGHT_FAULT_SHIFT ? "shifted" : "swapped");
            }
    return ew_t_finish();
}
