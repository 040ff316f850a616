/* Light styles as the game shows them (patterns at the frame's time,
 * switchable lights that start off, overrides, classic mode) and output
 * gamma, on the shared maps. */
#include "util.h"
#include "renderer.h"
#include "asset/light_entities.h"
#include "ew_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { W = 320, H = 200 };


/* Whether face f uses any style whose bit is set in changed. */
static int face_uses_any(const ew_face *f, uint64_t changed) {
    for (int k = 0; k < 4 && f->styles[k] != 255; k++)
        if (changed >> (f->styles[k] & 63) & 1) return 1;
    return 0;
}

#include "surfaces.h"

static ew_camera at_time(ew_camera c, double t) {
    c.time = t;
    return c;
}

/* Styles whose value differs between two frames' values. */
static uint64_t changed_styles(const int a[64], const int b[64]) {
    uint64_t m = 0;
    for (int s = 0; s < 64; s++)
        if (a[s] != b[s]) m |= (uint64_t)1 << s;
    return m;
}

static void get_styles(const ew_renderer *r, int out[64]) {
    for (int s = 0; s < 64; s++) out[s] = ew_get_lightstyle(r, s);
}

static void test_letters_and_parser(void) {
    CHECK(ew_style_letter_value('a') == 0 && ew_style_letter_value('m') == 264 && ew_style_letter_value('z') == 550,
          "letters: a %d, m %d, z %d", ew_style_letter_value('a'), ew_style_letter_value('m'),
          ew_style_letter_value('z'));
    CHECK(strcmp(ew_style_default_pattern(0, 0), "m") == 0 && strcmp(ew_style_default_pattern(20, 0), "m") == 0,
          "styles 0 and 12..31 are normal");
    CHECK(strcmp(ew_style_default_pattern(40, (uint64_t)1 << 40), "a") == 0 &&
              strcmp(ew_style_default_pattern(41, (uint64_t)1 << 40), "m") == 0, "switchable styles");
    const char *text =
        "{ \"classname\" \"worldspawn\" }\n"
        "{ \"classname\" \"light\" \"style\" \"40\" \"spawnflags\" \"1\" }\n"
        "{ \"classname\" \"light_fluoro\" \"style\" \"41\" \"spawnflags\" \"3\" }\n"
        "{ \"classname\" \"info_null\" \"style\" \"42\" \"spawnflags\" \"1\" }\n"
        "{ \"classname\" \"light\" \"style\" \"43\" }\n"
        "{ \"classname\" \"light\" \"style\" \"12\" \"spawnflags\" \"1\" }\n"
        "{ \"classname\" \"light\" \"style\" \"1e30\" \"spawnflags\" \"1\" }\n"
        "{ \"classname\" \"light\" \"style\" \"64\" \"spawnflags\" \"1\" }\n"
        "{ \"classname\" \"light\" \"style\" \"44\" \"spawnflags\" \"1\" }\n"
        "{ \"classname\" \"light\" \"style\" \"44\" \"spawnflags\" \"0\" }\n"  /* the last one wins */
        "{ \"classname\" \"light\" \"style\" \"63\" \"spawnflags\" \"nan\" }\n";
    uint64_t m = ew_light_styles_starting_off(text, strlen(text));
    CHECK(m == ((uint64_t)1 << 40 | (uint64_t)1 << 41), "starting off: %016llx", (unsigned long long)m);
    /* A damaged lump: the entities closed before the error count. */
    const char *bad = "{ \"classname\" \"light\" \"style\" \"35\" \"spawnflags\" \"1\" }\n{ \"classname\" \"light";
    m = ew_light_styles_starting_off(bad, strlen(bad));
    CHECK(m == (uint64_t)1 << 35, "damaged lump: %016llx", (unsigned long long)m);
    CHECK(ew_light_styles_starting_off(NULL, 0) == 0, "no lump");
}

/* Values per letter and per time, overrides, bad input. */
static void test_values(ew_renderer *r, ew_camera c) {
    static const char *const expect[12] = {
        "m", "mmnmmommommnonmmonqnmmo", "abcdefghijklmnopqrstuvwxyzyxwvutsrqponmlkjihgfedcba",
        "mmmmmaaaaammmmmaaaaaabcdefgabcdefg", "mamamamamama", "jklmnopqrstuvwxyzyxwvutsrqponmlkj",
        "nmonqnmomnmomomno", "mmmaaaabcdefgmmmmaaaammmaamm", "mmmaaammmaaammmabcdefaaaammmmabcdefmmmaaaa",
        "aaaaaaaazzzzzzzz", "mmamammmmammamamaaamammma", "abcdefghijklmnopqrrqponmlkjihgfedcba"};
    int wrong = 0;
    for (int k = 0; k < 120; k++) {
        ew_camera ck = at_time(c, 0.1 * k + 0.05);
        CHECK(ew_render(r, &ck, NULL) == 0, "render at %g", ck.time);
        for (int s = 0; s < 64; s++) {
            int want = s < 12 ? (expect[s][k % (int)strlen(expect[s])] - 'a') * 22 : 264;
            if (s >= 32 && (r->f.world->styles_start_off >> s & 1)) want = 0;
            if (ew_get_lightstyle(r, s) != want && !wrong++)
                CHECK(0, "style %d at %.2f s: %d, expected %d", s, ck.time, ew_get_lightstyle(r, s), want);
        }
    }
    CHECK(wrong == 0, "%d style values off their pattern", wrong);
    /* A time written in decimal lands on its letter (0.7 as a float is 0.6999999). */
    CHECK(ew_set_lightstyle_pattern(r, 20, "abcdefghij") == 0, "pattern");
    c.time = 0.7f;
    ew_render(r, &c, NULL);
    CHECK(ew_get_lightstyle(r, 20) == 7 * 22, "0.7 s: %d", ew_get_lightstyle(r, 20));
    c.time = -0.05;  /* before 0: the pattern runs backwards from its end */
    ew_render(r, &c, NULL);
    CHECK(ew_get_lightstyle(r, 20) == 9 * 22, "-0.05 s: %d", ew_get_lightstyle(r, 20));
    c.time = 1e7;
    CHECK(ew_render(r, &c, NULL) == 0 && ew_get_lightstyle(r, 20) >= 0 && ew_get_lightstyle(r, 20) <= 9 * 22,
          "far time: %d", ew_get_lightstyle(r, 20));
    ew_reset_lightstyle(r, 20);

    /* Overrides and reset. */
    ew_set_lightstyle(r, 1, 100);
    ew_set_lightstyle(r, 2, 5000);
    ew_set_lightstyle_switch(r, 3, 0);
    int held = 1;
    for (int k = 0; k < 30; k++) {
        ew_camera ck = at_time(c, 0.1 * k + 0.05);
        ew_render(r, &ck, NULL);
        held &= ew_get_lightstyle(r, 1) == 100 && ew_get_lightstyle(r, 2) == 1024 && ew_get_lightstyle(r, 3) == 0;
    }
    CHECK(held, "overrides hold at every time (1: %d, 2: %d, 3: %d)", ew_get_lightstyle(r, 1),
          ew_get_lightstyle(r, 2), ew_get_lightstyle(r, 3));
    for (int s = 1; s <= 3; s++) ew_reset_lightstyle(r, s);
    ew_camera ck = at_time(c, 0.1 * 4 + 0.05);  /* letters: 'm', 'e', 'm' */
    ew_render(r, &ck, NULL);
    CHECK(ew_get_lightstyle(r, 1) == 264 && ew_get_lightstyle(r, 2) == 4 * 22 && ew_get_lightstyle(r, 3) == 264,
          "reset: %d %d %d", ew_get_lightstyle(r, 1), ew_get_lightstyle(r, 2), ew_get_lightstyle(r, 3));

    /* Refused. */
    char longp[70];
    memset(longp, 'a', sizeof longp);
    longp[65] = 0;
    CHECK(ew_set_lightstyle_pattern(r, 5, "") == -1 && ew_set_lightstyle_pattern(r, 5, "aZ") == -1 &&
              ew_set_lightstyle_pattern(r, 5, "a1") == -1 && ew_set_lightstyle_pattern(r, 5, NULL) == -1 &&
              ew_set_lightstyle_pattern(r, 5, longp) == -1 && ew_set_lightstyle_pattern(r, 64, "m") == -1 &&
              ew_set_lightstyle_pattern(r, -1, "m") == -1 && ew_set_lightstyle_switch(r, 64, 1) == -1,
          "bad patterns refused");
    longp[64] = 0;
    CHECK(ew_set_lightstyle_pattern(r, 5, longp) == 0, "64 letters");
    ew_reset_lightstyle(r, 5);
    CHECK(ew_get_lightstyle(r, 64) == -1 && ew_get_lightstyle(r, -1) == -1, "unknown style");
    ew_set_lightstyle(r, 70, 3);  /* ignored */
}

/* Two frames a tenth of a second apart on letters that differ: different
 * frames, where the style's faces are, and exactly the visible lit
 * surfaces whose face uses a style that changed rebuilt. */
static void test_flicker(const ew_assets *a, const ew_camera *views, int nv) {
    const ew_world *w = a->world;
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){ .world = w, .palette = a->palette,
            .colormap = a->colormap, .width = W, .height = H, .threads = 1 }, NULL);
    CHECK(r != NULL, "renderer");
    if (!r) return;
    ew_enable_face_ids(r, 1);
    ew_cached_surf **ents = malloc(sizeof *ents * (size_t)r->el.max_surfs);
    int view = -1, style = -1, tick = -1;
    for (int v = 0; v < nv && view < 0; v++) {
        ew_camera c = at_time(views[v], 0.05);
        ew_render(r, &c, NULL);
        int n = frame_entries(r, ents);
        for (int i = 0; i < n && view < 0; i++)
            for (int s = 1; s < 12 && view < 0; s++) {
                if (!face_uses_style(&w->faces[ents[i]->face], s)) continue;
                /* an even tick: both times in one animated-texture frame (0.2 s) */
                for (int k = 0; k < 60 && view < 0; k += 2) {
                    ew_camera c0 = at_time(c, 0.1 * k + 0.05), c1 = at_time(c, 0.1 * k + 0.15);
                    ew_render(r, &c0, NULL);
                    int v0 = ew_get_lightstyle(r, s);
                    ew_render(r, &c1, NULL);
                    if (ew_get_lightstyle(r, s) != v0) view = v, style = s, tick = k;
                }
            }
    }
    CHECK(view >= 0, "no view of %s shows a flickering style", w->name);
    if (view < 0) goto done;
    ew_camera c0 = at_time(views[view], 0.1 * tick + 0.05), c1 = at_time(views[view], 0.1 * tick + 0.15);
    long n = (long)W * H;
    uint8_t *f0 = malloc((size_t)n);
    int *ids = malloc(sizeof(int) * (size_t)n);
    int s0[64], s1[64];
    ew_stats st;
    ew_render(r, &c0, NULL);
    ew_render(r, &c0, &st);
    CHECK(st.surfaces_built == 0, "the same frame again built %d", st.surfaces_built);
    memcpy(f0, ew_frame_pixels(r), (size_t)n);
    memcpy(ids, ew_frame_face_ids(r), sizeof(int) * (size_t)n);
    get_styles(r, s0);
    ew_render(r, &c1, &st);
    get_styles(r, s1);
    uint64_t changed = changed_styles(s0, s1);
    CHECK(changed >> style & 1, "style %d changed", style);
    const uint8_t *f1 = ew_frame_pixels(r);
    long on_style = 0, off_style = 0, differ = 0;
    for (long i = 0; i < n; i++) {
        if (f0[i] == f1[i]) continue;
        differ++;
        const ew_face *f = &w->faces[ids[i]];
        if (face_uses_style(f, style)) on_style++;
        else if (!face_uses_any(f, changed) && !(f->flags & (EW_SURF_SKY | EW_SURF_TURB))) off_style++;
    }
    printf("e1m1 view %d, style %d ('%s'), %.2f s -> %.2f s: value %d -> %d; %ld pixels differ, %ld of them on "
           "its faces, %ld on lit faces using no changed style\n",
           view, style, ew_style_default_pattern(style, 0), c0.time, c1.time, s0[style], s1[style], differ,
           on_style, off_style);
    CHECK(on_style > 0, "frames %.2f s apart equal on style %d's faces", 0.1, style);
    CHECK(off_style == 0, "%ld pixels changed on faces using no changed style", off_style);

    /* Which surfaces were rebuilt: the list to build, and a poisoned texel
     * in every surface of the first frame (kept unless rebuilt). */
    ew_render(r, &c0, NULL);
    int np = frame_entries(r, ents);
    uint8_t *saved = malloc((size_t)np);
    int *tex = malloc(sizeof(int) * (size_t)np);
    for (int i = 0; i < np; i++) saved[i] = ents[i]->pixels[0], ents[i]->pixels[0] ^= 0x5A, tex[i] = ents[i]->texture;
    ew_render(r, &c1, &st);
    ew_cached_surf **cur = malloc(sizeof *cur * (size_t)r->el.max_surfs);
    int nc = frame_entries(r, cur), same = nc == np;
    for (int i = 0; i < nc && same; i++) same = cur[i] == ents[i];
    CHECK(same, "the same view used %d lit surfaces, then %d", np, nc);
    int expected = 0, with_style = 0, wrong = 0;
    for (int i = 0; same && i < nc; i++) {
        ew_cached_surf *e = cur[i];
        const ew_face *f = &w->faces[e->face];
        int uses = face_uses_any(f, changed) || e->texture != tex[i], listed = 0;
        expected += uses;
        with_style += face_uses_style(f, style);
        for (int k = 0; k < r->lit.nbuild; k++) listed += r->lit.to_build[k] == e;
        int kept = e->pixels[0] == (uint8_t)(saved[i] ^ 0x5A);
        wrong += listed != uses || kept == uses;
    }
    printf("  rebuilt %d of %d visible lit surfaces (%d of them use style %d)\n", st.surfaces_built, nc,
           with_style, style);
    CHECK(wrong == 0, "%d lit surfaces rebuilt or kept against their styles", wrong);
    CHECK(expected > 0 && with_style > 0 && st.surfaces_built == expected && r->lit.nbuild == expected,
          "built %d (listed %d), expected exactly the %d visible lit surfaces using a changed style",
          st.surfaces_built, r->lit.nbuild, expected);
    CHECK(expected < nc, "every surface rebuilt (%d)", nc);
    free(saved), free(tex), free(cur), free(f0), free(ids);
done:
    free(ents);
    ew_renderer_destroy(r);
}

/* Classic mode: every style 256, frames equal a classic renderer's. */
static void test_classic(const ew_assets *a, const ew_camera *views, int nv) {
    ew_renderer_desc d = { .world = a->world, .palette = a->palette, .colormap = a->colormap, .width = W,
                           .height = H, .threads = 1, .classic = 1 };
    ew_renderer *rc = ew_renderer_create(&d, NULL), *fresh = NULL;
    d.classic = 0;
    ew_renderer *rs = ew_renderer_create(&d, NULL);  /* switched to classic later */
    CHECK(rc && rs, "renderers");
    if (!rc || !rs) goto done;
    ew_set_classic(rs, 1);
    int all256 = 1, equal = 1;
    long n = (long)W * H;
    for (int k = 0; k < 40; k++) {
        ew_camera c = at_time(views[k % nv], 0.1 * k + 0.05);
        ew_render(rc, &c, NULL);
        ew_render(rs, &c, NULL);
        for (int s = 0; s < 64; s++) all256 &= ew_get_lightstyle(rc, s) == 256 && ew_get_lightstyle(rs, s) == 256;
        if (k % 8 == 7) {  /* a fresh classic renderer at this time */
            d.classic = 1;
            fresh = ew_renderer_create(&d, NULL);
            ew_render(fresh, &c, NULL);
            equal &= memcmp(ew_frame_pixels(fresh), ew_frame_pixels(rc), (size_t)n) == 0;
            ew_renderer_destroy(fresh);
        }
        equal &= memcmp(ew_frame_pixels(rs), ew_frame_pixels(rc), (size_t)n) == 0;
    }
    CHECK(all256, "classic: a style other than 256");
    CHECK(equal, "classic frames differ from a classic renderer's");
    /* Overrides still apply in classic mode. */
    ew_set_lightstyle(rc, 1, 0);
    ew_render(rc, &views[0], NULL);
    CHECK(ew_get_lightstyle(rc, 1) == 0 && ew_get_lightstyle(rc, 2) == 256, "classic override");
done:
    ew_renderer_destroy(rc);
    ew_renderer_destroy(rs);
}

/* e4m1: its targeted lights of styles 32, 33 and 34 start off. */
static void test_switchable(void) {
    ew_assets *a = ew_t_load_map("e4m1");
    if (!a) return;
    const ew_world *w = a->world;
    CHECK(w->styles_start_off == ((uint64_t)7 << 32),
          "e4m1 styles starting off: %016llx", (unsigned long long)w->styles_start_off);
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){ .world = w, .palette = a->palette,
            .colormap = a->colormap, .width = W, .height = H, .threads = 1 }, NULL);
    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(w, views);
    if (!r || nv <= 0) {
        CHECK(0, "e4m1 renderer and views");
        ew_renderer_destroy(r);
        ew_assets_destroy(a);
        return;
    }
    /* White light: brightness through the colormap alone (the nearest
     * colours of coloured light may step a channel down as light goes up). */
    ew_set_lit(r, 0);
    ew_render(r, &views[0], NULL);
    CHECK(ew_get_lightstyle(r, 32) == 0 && ew_get_lightstyle(r, 33) == 0 && ew_get_lightstyle(r, 34) == 0 &&
              ew_get_lightstyle(r, 35) == 264,
          "e4m1: 32 %d, 33 %d, 34 %d, 35 %d", ew_get_lightstyle(r, 32), ew_get_lightstyle(r, 33),
          ew_get_lightstyle(r, 34), ew_get_lightstyle(r, 35));
    /* A view showing style 32's faces: switched on, they are rebuilt and lit. */
    ew_cached_surf **ents = malloc(sizeof *ents * (size_t)r->el.max_surfs);
    int view = -1, nuse = 0;
    for (int v = 0; v < nv && view < 0; v++) {
        ew_render(r, &views[v], NULL);
        int ne = frame_entries(r, ents);
        for (int i = 0; i < ne; i++) nuse += face_uses_style(&w->faces[ents[i]->face], 32);
        if (nuse) view = v;
    }
    if (view >= 0) {
        long n = (long)W * H, brighter = 0, darker = 0;
        uint8_t *off = malloc((size_t)n);
        ew_render(r, &views[view], NULL);
        memcpy(off, ew_frame_pixels(r), (size_t)n);
        ew_set_lightstyle_switch(r, 32, 1);
        ew_stats st;
        ew_render(r, &views[view], &st);
        const uint8_t *on = ew_frame_pixels(r);
        for (long i = 0; i < n; i++) {
            const uint8_t *p0 = a->palette + off[i] * 3, *p1 = a->palette + on[i] * 3;
            brighter += p1[0] + p1[1] + p1[2] > p0[0] + p0[1] + p0[2];
            darker += p1[0] + p1[1] + p1[2] < p0[0] + p0[1] + p0[2];
        }
        printf("e4m1 view %d: style 32 switched on: %d surfaces rebuilt (%d use it), %ld pixels brighter, %ld darker\n",
               view, st.surfaces_built, nuse, brighter, darker);
        CHECK(st.surfaces_built == nuse && ew_get_lightstyle(r, 32) == 264, "switched on: built %d of %d",
              st.surfaces_built, nuse);
        /* (the colormap's rows may pick a colour a step darker here and there) */
        CHECK(brighter > 1000 && darker * 100 < brighter, "switched on: %ld brighter, %ld darker", brighter, darker);
        free(off);
    } else {
        printf("e4m1: no benchmark view shows style 32\n");
        ew_set_lightstyle_switch(r, 32, 1);
        ew_render(r, &views[0], NULL);
        CHECK(ew_get_lightstyle(r, 32) == 264, "switched on");
    }
    ew_reset_lightstyle(r, 32);
    ew_render(r, &views[0], NULL);
    CHECK(ew_get_lightstyle(r, 32) == 0, "reset: off again");
    free(ents);
    ew_renderer_destroy(r);
    ew_assets_destroy(a);
}

/* PLTE of a PNG file: 768 bytes into out; 0 or -1. */
static int png_palette(const char *path, uint8_t out[768]) {
    FILE *f = fopen(path, "rb");
    if (!f) return -1;
    static uint8_t buf[1 << 20];
    size_t n = fread(buf, 1, sizeof buf, f);
    fclose(f);
    for (size_t i = 8; i + 4 + 768 <= n; i++)
        if (memcmp(buf + i, "PLTE", 4) == 0) {
            memcpy(out, buf + i + 4, 768);
            return 0;
        }
    return -1;
}

static void test_gamma(const ew_assets *a, const ew_camera *view) {
    long n = (long)W * H;
    ew_renderer_desc d = { .world = a->world, .palette = a->palette, .colormap = a->colormap, .width = W,
                           .height = H, .threads = 2 };
    ew_renderer *r = ew_renderer_create(&d, NULL);
    d.color = EW_COLOR_TRUE;
    ew_renderer *t = ew_renderer_create(&d, NULL);
    CHECK(r && t, "renderers");
    if (!r || !t) goto done;
    /* Refused values leave the gamma as it was. */
    CHECK(ew_get_gamma(r) == 1, "default gamma %g", (double)ew_get_gamma(r));
    CHECK(ew_set_gamma(r, 0.49f) == -1 && ew_set_gamma(r, 3.01f) == -1 && ew_set_gamma(r, 0) == -1 &&
              ew_set_gamma(r, -1) == -1 && ew_set_gamma(r, NAN) == -1 && ew_set_gamma(r, INFINITY) == -1 &&
              ew_get_gamma(r) == 1, "bad gamma refused");
    CHECK(ew_set_gamma(r, 0.5f) == 0 && ew_set_gamma(r, 3) == 0 && ew_set_gamma(r, 1) == 0, "0.5 and 3 taken");

    /* 8-bit: the same indices, another palette. */
    uint8_t *f1 = malloc((size_t)n);
    ew_render(r, view, NULL);
    memcpy(f1, ew_frame_pixels(r), (size_t)n);
    CHECK(memcmp(ew_frame_palette(r), a->palette, 768) == 0, "gamma 1: the palette itself");
    ew_set_gamma(r, 2);
    ew_render(r, view, NULL);
    CHECK(memcmp(ew_frame_pixels(r), f1, (size_t)n) == 0, "gamma changed 8-bit indices");
    const uint8_t *p2 = ew_frame_palette(r);
    int up = 0, down = 0;
    for (int i = 0; i < 768; i++) up += p2[i] > a->palette[i], down += p2[i] < a->palette[i];
    CHECK(up > 600 && down == 0, "gamma 2 palette: %d brighter, %d darker", up, down);
    uint8_t written[768];
    const char *png = "test_lightstyles_gamma.png";
    CHECK(ew_write_frame_png(r, png, NULL) == 0 && png_palette(png, written) == 0 &&
              memcmp(written, p2, 768) == 0, "the PNG carries the gamma palette");
    remove(png);
    ew_set_gamma(r, 0.5f);
    up = down = 0;
    for (int i = 0; i < 768; i++) up += ew_frame_palette(r)[i] > a->palette[i], down += ew_frame_palette(r)[i] < a->palette[i];
    CHECK(up == 0 && down > 600, "gamma 0.5 palette: %d brighter, %d darker", up, down);
    free(f1);

    /* True colour: each channel through one increasing curve. */
    uint32_t *t1 = malloc(sizeof(uint32_t) * (size_t)n);
    ew_render(t, view, NULL);
    memcpy(t1, ew_frame_rgba(t), sizeof(uint32_t) * (size_t)n);
    ew_set_gamma(t, 2);
    ew_render(t, view, NULL);
    int map[256];
    for (int i = 0; i < 256; i++) map[i] = -1;
    int consistent = 1, alpha = 1, raised = 0;
    const uint8_t *b1 = (const uint8_t *)t1, *b2 = (const uint8_t *)ew_frame_rgba(t);
    for (long i = 0; i < n * 4; i++) {
        if (i % 4 == 3) {
            alpha &= b1[i] == b2[i];
            continue;
        }
        if (map[b1[i]] < 0) map[b1[i]] = b2[i];
        consistent &= map[b1[i]] == b2[i];
        raised += b2[i] > b1[i];
    }
    int monotonic = 1, last = -1, seen = 0;
    for (int v = 0; v < 256; v++) {
        if (map[v] < 0) continue;
        seen++;
        monotonic &= map[v] >= last && map[v] >= v;
        last = map[v];
    }
    printf("true colour, gamma 2: %d channel values seen, %d channel samples raised of %ld\n", seen, raised, n * 3);
    CHECK(consistent && alpha, "gamma is not one curve per channel value");
    CHECK(monotonic && raised > n, "gamma 2 not an increasing brightening (%d raised)", raised);
    ew_set_gamma(t, 1);
    ew_render(t, view, NULL);
    CHECK(memcmp(ew_frame_rgba(t), t1, sizeof(uint32_t) * (size_t)n) == 0, "gamma 1 is the identity");
    free(t1);
done:
    ew_renderer_destroy(r);
    ew_renderer_destroy(t);
}

/* What the gamma costs at 1920x1080 in true colour, on one thread (a
 * figure printed, not checked: sanitizer builds are far slower). */
static void gamma_cost(void) {
    size_t n = 1920 * 1080;
    uint32_t *px = malloc(n * sizeof *px);
    uint8_t lut[256];
    ew_gamma_table(1.7f, lut);
    for (size_t i = 0; i < n; i++) px[i] = (uint32_t)(i * 2654435761u);
    double best = 1e9;
    for (int k = 0; k < 10; k++) {
        double t0 = ew_now_ms();
        ew_gamma_pixels(px, n, lut);
        double ms = ew_now_ms() - t0;
        if (ms < best) best = ms;
    }
    printf("gamma at 1920x1080, one thread: %.2f ms a frame (best of 10)\n", best);
    free(px);
}

int main(void) {
    test_letters_and_parser();
    ew_assets *a = ew_t_load_map("e1m1");
    if (!a) return ew_t_finish();
    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(a->world, views);
    CHECK(nv > 0, "e1m1 views");
    if (nv > 0) {
        ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){ .world = a->world, .palette = a->palette,
                .colormap = a->colormap, .width = W, .height = H, .threads = 1 }, NULL);
        CHECK(r != NULL, "renderer");
        if (r) test_values(r, views[0]);
        ew_renderer_destroy(r);
        test_flicker(a, views, nv);
        test_classic(a, views, nv);
        test_gamma(a, &views[0]);
    }
    ew_assets_destroy(a);
    test_switchable();
    gamma_cost();
    return ew_t_finish();
}
