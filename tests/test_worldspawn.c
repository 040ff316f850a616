/*
 * What a map asks of the renderer (asset/worldspawn.c, the texture liquid
 * kinds and fence check in asset/bsp.c, brush entities' "alpha" in
 * scene/scene.c): the real maps' values, and malformed keys written into the
 * built-in level's entity lump (a new lump appended to the BSP29 image and
 * lump 0 pointed at it).  Each malformed key gives exactly one warning
 * naming the file, the key and the value, keeps its default, and the map
 * still loads and renders.
 */
#define _POSIX_C_SOURCE 200809L
#include "ew_util.h"
#include "ew_world.h"
#include "edgewise_lab.h"
#include "mapgen/mapgen.h"
#include "asset/scene.h"
#include "util.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static uint8_t *g_bsp, g_palette[768], g_colormap[EW_COLORMAP_SIZE];
static size_t g_bsp_size;
static char *g_ents;  /* the built-in level's entity text */

static uint32_t rd32(const uint8_t *p) {
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
static void wr32(uint8_t *p, uint32_t v) {
    for (int k = 0; k < 4; k++) p[k] = (uint8_t)(v >> (8 * k));
}

/* The built-in image with its entity lump replaced by text (appended at
 * the end, 4-byte aligned, lump 0 = (offset, length) at bytes 4..11). */
static uint8_t *with_entities(const char *text, size_t *size) {
    size_t base = (g_bsp_size + 3) & ~(size_t)3, len = strlen(text) + 1;
    uint8_t *b = calloc(1, base + len);
    if (!b) abort();
    memcpy(b, g_bsp, g_bsp_size);
    memcpy(b + base, text, len);
    wr32(b + 4, (uint32_t)base);
    wr32(b + 8, (uint32_t)len);
    *size = base + len;
    return b;
}

/* The built-in entity text with extra pairs in worldspawn and in the door
 * ("model" "*1"); either may be "". */
static char *edited(const char *ws_pairs, const char *door_pairs) {
    size_t cap = strlen(g_ents) + strlen(ws_pairs) + strlen(door_pairs) + 64;
    char *out = malloc(cap);
    if (!out) abort();
    const char *ws = strstr(g_ents, "\"classname\" \"worldspawn\"");
    const char *door = strstr(g_ents, "\"model\" \"*1\"");
    if (!ws || !door || door < ws) abort();
    size_t a = (size_t)(ws - g_ents) + strlen("\"classname\" \"worldspawn\"");
    size_t b = (size_t)(door - g_ents) + strlen("\"model\" \"*1\"");
    snprintf(out, cap, "%.*s\n%s%.*s\n%s%s", (int)a, g_ents, ws_pairs, (int)(b - a), g_ents + a, door_pairs,
             g_ents + b);
    return out;
}

/* Renders one frame of w (with scene s, may be NULL), both looks. */
static int renders(const ew_world *w, const ew_scene *s) {
    int ok = 1;
    for (int classic = 0; classic < 2; classic++) {
        ew_error err = {""};
        ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){ .world = w, .palette = g_palette,
                .colormap = g_colormap, .width = 320, .height = 200, .threads = 1, .classic = classic }, &err);
        if (!r) return 0;
        ew_camera views[EW_MAX_VIEWS];
        if (ew_benchmark_views(w, views) <= 0) {
            ew_renderer_destroy(r);
            return 0;
        }
        if (s) ew_set_scene(r, s);
        ew_stats st;
        if (ew_render(r, &views[0], &st) != 0) ok = 0;
        ew_renderer_destroy(r);
    }
    return ok;
}

typedef struct expect {
    const char *ws, *door;      /* extra pairs */
    int   warnings;             /* world warnings */
    int   scene_warnings;
    const char *needle;         /* in the (one) warning line, besides the file name */
    float alpha[EW_NUM_LIQUIDS];
    float fog_density, fog_rgb[3];
    float door_alpha;
} expect;

#define OPAQUE {1, 1, 1, 1, 1}
#define GRAY {0.3f, 0.3f, 0.3f}

static void run_case(const expect *e) {
    char *text = edited(e->ws, e->door);
    size_t n;
    uint8_t *bsp = with_entities(text, &n);
    const char *name = "bad_worldspawn.bsp";
    ew_error err = {""};
    ew_world *w = ew_world_create(bsp, n, name, &err);
    CHECK(w != NULL, "[%s|%s] did not load: %s", e->ws, e->door, err.msg);
    if (!w) goto out;
    CHECK(w->nwarnings == e->warnings, "[%s|%s] %d world warnings, expected %d (first: %s)", e->ws, e->door,
          w->nwarnings, e->warnings, w->nwarnings ? ew_world_warning(w, 0) : "-");
    for (int i = 0; i < w->nwarnings; i++) {
        const char *l = ew_world_warning(w, i);
        CHECK(strstr(l, name) == l && strchr(l, '\n') == NULL, "warning does not start with the file: %s", l);
        CHECK(!e->needle || strstr(l, e->needle), "warning lacks '%s': %s", e->needle, l);
        printf("  world warning: %s\n", l);
    }
    for (int k = 0; k < EW_NUM_LIQUIDS; k++)
        CHECK(w->worldspawn.liquid_alpha[k] == e->alpha[k], "[%s] liquid %d alpha %g, expected %g", e->ws, k,
              w->worldspawn.liquid_alpha[k], e->alpha[k]);
    CHECK(w->worldspawn.fog_density == e->fog_density, "[%s] fog density %g, expected %g", e->ws,
          w->worldspawn.fog_density, e->fog_density);
    for (int k = 0; k < 3; k++)
        CHECK(w->worldspawn.fog_rgb[k] == e->fog_rgb[k], "[%s] fog colour %d = %g, expected %g", e->ws, k,
              w->worldspawn.fog_rgb[k], e->fog_rgb[k]);

    ew_scene *s = ew_scene_create_from_map(w, NULL, NULL, &err);
    CHECK(s != NULL, "scene: %s", err.msg);
    if (s) {
        CHECK(s->nwarnings == e->scene_warnings, "[%s] %d scene warnings, expected %d (first: %s)", e->door,
              s->nwarnings, e->scene_warnings, s->nwarnings ? ew_scene_warning(s, 0) : "-");
        for (int i = 0; i < s->nwarnings; i++) {
            const char *l = ew_scene_warning(s, i);
            CHECK(strstr(l, name) == l && strstr(l, "func_door") && strstr(l, "*1"),
                  "scene warning lacks the file or the entity: %s", l);
            CHECK(!e->needle || strstr(l, e->needle), "scene warning lacks '%s': %s", e->needle, l);
            printf("  scene warning: %s\n", l);
        }
        int found = 0;
        for (int i = 0; i < s->nents; i++)
            if (s->ents[i].model == -2) {
                found = 1;
                CHECK(s->ents[i].alpha == e->door_alpha, "[%s] door alpha %g, expected %g", e->door,
                      s->ents[i].alpha, e->door_alpha);
            }
        CHECK(found, "the door (*1) is not in the scene");
    }
    CHECK(renders(w, s), "[%s|%s] does not render", e->ws, e->door);
    ew_scene_destroy(s);
    ew_world_destroy(w);
out:
    free(bsp);
    free(text);
}

static void test_builtin_cases(void) {
    const expect cases[] = {
        /* untouched: defaults, no warnings */
        {"", "", 0, 0, NULL, OPAQUE, 0, GRAY, 1},
        /* well-formed */
        {"\"_wateralpha\" \"0.5\"\n", "", 0, 0, NULL, {1, 0.5f, 1, 1, 1}, 0, GRAY, 1},
        {"\"wateralpha\" \"0.25\"\n\"slimealpha\" \" 0.75 \"\n", "", 0, 0, NULL, {1, 0.25f, 0.75f, 1, 1}, 0, GRAY, 1},
        {"\"_lavaalpha\" \"0\"\n\"_telealpha\" \"0.4\"\n", "", 0, 0, NULL, {1, 1, 1, 1, 0.4f}, 0, GRAY, 1},
        {"\"_wateralpha\" \"1\"\n", "", 0, 0, NULL, OPAQUE, 0, GRAY, 1},
        {"\"fog\" \"0.05\"\n", "", 0, 0, NULL, OPAQUE, 0.05f, GRAY, 1},
        {"\"_fog\" \"0.1 0.2 0.3 0.4\"\n", "", 0, 0, NULL, OPAQUE, 0.1f, {0.2f, 0.3f, 0.4f}, 1},
        {"\"fog\" \"0 1 1 1\"\n", "", 0, 0, NULL, OPAQUE, 0, {1, 1, 1}, 1},
        {"", "\"alpha\" \"0.5\"\n", 0, 0, NULL, OPAQUE, 0, GRAY, 0.5f},
        {"", "\"alpha\" \"0\"\n", 0, 0, NULL, OPAQUE, 0, GRAY, 1},
        {"", "\"alpha\" \"1\"\n", 0, 0, NULL, OPAQUE, 0, GRAY, 1},
        /* malformed liquid opacities */
        {"\"_wateralpha\" \"nan\"\n", "", 1, 0, "\"_wateralpha\" \"nan\"", OPAQUE, 0, GRAY, 1},
        {"\"_wateralpha\" \"-1\"\n", "", 1, 0, "\"_wateralpha\" \"-1\"", OPAQUE, 0, GRAY, 1},
        {"\"_wateralpha\" \"7\"\n", "", 1, 0, "\"_wateralpha\" \"7\"", OPAQUE, 0, GRAY, 1},
        {"\"_wateralpha\" \"0.5x\"\n", "", 1, 0, "\"_wateralpha\" \"0.5x\"", OPAQUE, 0, GRAY, 1},
        {"\"_wateralpha\" \"\"\n", "", 1, 0, "\"_wateralpha\" \"\"", OPAQUE, 0, GRAY, 1},
        {"\"_wateralpha\" \"inf\"\n", "", 1, 0, "not an opacity", OPAQUE, 0, GRAY, 1},
        {"\"_slimealpha\" \"0.5 0.5\"\n\"_wateralpha\" \"0.5\"\n", "", 1, 0, "\"_slimealpha\"",
         {1, 0.5f, 1, 1, 1}, 0, GRAY, 1},
        /* malformed fog */
        {"\"fog\" \"0.1 1 1\"\n", "", 1, 0, "\"fog\" \"0.1 1 1\"", OPAQUE, 0, GRAY, 1},
        {"\"fog\" \"-0.5 1 1 1\"\n", "", 1, 0, "\"fog\" \"-0.5 1 1 1\"", OPAQUE, 0, GRAY, 1},
        {"\"fog\" \"abc\"\n", "", 1, 0, "\"fog\" \"abc\"", OPAQUE, 0, GRAY, 1},
        {"\"fog\" \"0.1 1 2 1\"\n", "", 1, 0, "colour", OPAQUE, 0, GRAY, 1},
        {"\"fog\" \"0.1 1 1 1 1\"\n", "", 1, 0, "text after", OPAQUE, 0, GRAY, 1},
        {"\"fog\" \"nan 1 1 1\"\n", "", 1, 0, "density", OPAQUE, 0, GRAY, 1},
        /* malformed brush entity alpha */
        {"", "\"alpha\" \"nan\"\n", 0, 1, "\"alpha\" \"nan\"", OPAQUE, 0, GRAY, 1},
        {"", "\"alpha\" \"-1\"\n", 0, 1, "\"alpha\" \"-1\"", OPAQUE, 0, GRAY, 1},
        {"", "\"alpha\" \"7\"\n", 0, 1, "\"alpha\" \"7\"", OPAQUE, 0, GRAY, 1},
        {"", "\"alpha\" \"inf\"\n", 0, 1, "\"alpha\" \"inf\"", OPAQUE, 0, GRAY, 1},
        {"", "\"alpha\" \"half\"\n", 0, 1, "not a number", OPAQUE, 0, GRAY, 1},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) run_case(&cases[i]);
}

/* A fence texture without index 255: renamed from a built-in texture whose
 * pixels lack it; one warning, and the map renders (solid). */
static void test_fence(void) {
    uint8_t *b = malloc(g_bsp_size);
    if (!b) abort();
    memcpy(b, g_bsp, g_bsp_size);
    uint32_t lofs = rd32(b + 4 + 8 * EW_LUMP_TEXTURES);
    uint32_t n = rd32(b + lofs);
    int renamed = -1;
    char old[16] = "";
    for (uint32_t i = 0; i < n && renamed < 0; i++) {
        uint32_t mo = rd32(b + lofs + 4 + 4 * i);
        uint8_t *mt = b + lofs + mo;
        uint32_t tw = rd32(mt + 16), th = rd32(mt + 20), p0 = rd32(mt + 24);
        if (mt[0] == '*' || mt[0] == '+' || !strncasecmp((char *)mt, "sky", 3)) continue;
        if (memchr(mt + p0, 255, (size_t)tw * th)) continue;
        memcpy(old, mt, 15);
        memmove(mt + 1, mt, 14);  /* "{" + the old name, still NUL-terminated within 16 */
        mt[0] = '{';
        mt[15] = 0;
        renamed = (int)i;
    }
    CHECK(renamed >= 0, "no built-in texture without index 255 to rename");
    if (renamed >= 0) {
        ew_error err = {""};
        ew_world *w = ew_world_create(b, g_bsp_size, "fence.bsp", &err);
        CHECK(w != NULL, "fence.bsp: %s", err.msg);
        if (w) {
            char want[128];
            snprintf(want, sizeof want,
                     "fence.bsp: texture \"{%.14s\" is a fence texture without see-through pixels (index 255); "
                     "drawn solid", old);
            CHECK(w->nwarnings == 1 && !strcmp(ew_world_warning(w, 0), want), "fence warning: %s (want %s)",
                  w->nwarnings ? ew_world_warning(w, 0) : "none", want);
            CHECK(w->textures[renamed].flags & EW_SURF_FENCE, "renamed texture is not a fence");
            CHECK(renders(w, NULL), "fence.bsp does not render");
            ew_world_destroy(w);
        }
    }
    free(b);
}

/* The liquid kind a name should get, written independently of the loader. */
static int expected_liquid(const char *name) {
    if (name[0] != '*') return EW_LIQUID_NONE;
    if (strncasecmp(name + 1, "lava", 4) == 0) return EW_LIQUID_LAVA;
    if (strncasecmp(name + 1, "slime", 5) == 0) return EW_LIQUID_SLIME;
    if (strncasecmp(name + 1, "tele", 4) == 0) return EW_LIQUID_TELE;
    return EW_LIQUID_WATER;
}

static void test_real_maps(void) {
    static const char *maps[] = {"e1m1", "e2m1", "e4m1", "lqdm1", "lqdm7", "start", "slope"};
    if (!ew_t_need_shared("data/librequake/maps/e1m1.bsp")) return;
    int kinds_all[EW_NUM_LIQUIDS] = {0};
    for (size_t m = 0; m < sizeof maps / sizeof *maps; m++) {
        ew_assets *a = ew_t_load_map(maps[m]);
        if (!a) continue;
        const ew_world *w = a->world;
        CHECK(w->nwarnings == 0, "%s: %d warnings (first: %s)", maps[m], w->nwarnings,
              w->nwarnings ? ew_world_warning(w, 0) : "-");
        /* The value the lump itself holds, read straight from its text. */
        const char *text = ew_world_entities(w);
        const char *k = strstr(text, "\"_wateralpha\" \"");
        float want_water = k ? strtof(k + strlen("\"_wateralpha\" \""), NULL) : 1;
        CHECK(w->worldspawn.liquid_alpha[EW_LIQUID_WATER] == want_water, "%s: wateralpha %g, lump says %g",
              maps[m], w->worldspawn.liquid_alpha[EW_LIQUID_WATER], want_water);
        CHECK(w->worldspawn.liquid_alpha[EW_LIQUID_NONE] == 1 && w->worldspawn.liquid_alpha[EW_LIQUID_SLIME] == 1 &&
                  w->worldspawn.liquid_alpha[EW_LIQUID_LAVA] == 1 && w->worldspawn.liquid_alpha[EW_LIQUID_TELE] == 1,
              "%s: a liquid other than water is not opaque", maps[m]);
        CHECK(w->worldspawn.fog_density == 0, "%s: fog %g without a fog key", maps[m], w->worldspawn.fog_density);
        if (!strcmp(maps[m], "e4m1"))
            CHECK(k && want_water == 0.6f, "e4m1: expected \"_wateralpha\" \"0.6\" in its entity lump");
        else
            CHECK(!k, "%s: has a _wateralpha key now", maps[m]);

        printf("%-6s liquids:", maps[m]);
        for (int i = 0; i < w->numtextures - 1; i++) {
            const ew_texture *t = &w->textures[i];
            int want = expected_liquid(t->name);
            CHECK(t->liquid == want, "%s: texture %s liquid %d, expected %d", maps[m], t->name, t->liquid, want);
            kinds_all[t->liquid]++;
            if (t->name[0] == '*') printf(" %s=%d", t->name, t->liquid);
            if (!strcmp(t->name, "*h2oteleskip")) CHECK(t->liquid == EW_LIQUID_WATER, "*h2oteleskip is not water");
            if (!strcmp(t->name, "*lava1")) CHECK(t->liquid == EW_LIQUID_LAVA, "*lava1 is not lava");
            if (!strcmp(t->name, "*slime2")) CHECK(t->liquid == EW_LIQUID_SLIME, "*slime2 is not slime");
            if (!strcmp(t->name, "*teleport")) CHECK(t->liquid == EW_LIQUID_TELE, "*teleport is not tele");
        }
        printf("\n");

        ew_error err = {""};
        ew_scene *s = ew_scene_create_from_map(w, NULL, NULL, &err);
        CHECK(s && s->nwarnings == 0, "%s: scene warnings (first: %s)", maps[m],
              s && s->nwarnings ? ew_scene_warning(s, 0) : "-");
        if (s && !strcmp(maps[m], "e1m1")) {
            /* e1m1's func_wall *73 has "alpha" "0.0000001": a valid, tiny opacity */
            int seen = 0;
            for (int i = 0; i < s->nents; i++)
                if (s->ents[i].model == -1 - 73) {
                    seen = 1;
                    CHECK(s->ents[i].alpha == 1e-7f, "e1m1 *73 alpha %g", s->ents[i].alpha);
                }
            CHECK(seen, "e1m1: *73 not in the scene");
        }
        ew_scene_destroy(s);
        ew_assets_destroy(a);
    }
    /* e1m1: *water0 *slime2 *water4 *teleport *tele1; lqdm7: *lava1 *tele3;
     * start: *slime1 *teleport and *h2oteleskip (water: "tele" is not its prefix) */
    CHECK(kinds_all[EW_LIQUID_WATER] > 0 && kinds_all[EW_LIQUID_SLIME] > 0 && kinds_all[EW_LIQUID_LAVA] > 0 &&
              kinds_all[EW_LIQUID_TELE] > 0,
          "the real maps lack a water, slime, lava or teleport texture (%d %d %d %d)", kinds_all[EW_LIQUID_WATER],
          kinds_all[EW_LIQUID_SLIME], kinds_all[EW_LIQUID_LAVA], kinds_all[EW_LIQUID_TELE]);
}

int main(void) {
    ew_error err = {""};
    if (ew_builtin_generate(&g_bsp, &g_bsp_size, g_palette, g_colormap, &err) != 0) {
        CHECK(0, "builtin: %s", err.msg);
        return ew_t_finish();
    }
    ew_world *w = ew_world_create(g_bsp, g_bsp_size, "builtin.bsp", &err);
    CHECK(w != NULL, "builtin: %s", err.msg);
    if (!w) return ew_t_finish();
    g_ents = strdup(ew_world_entities(w));
    ew_world_destroy(w);

    test_builtin_cases();
    test_fence();
    test_real_maps();

    free(g_ents);
    free(g_bsp);
    return ew_t_finish();
}
