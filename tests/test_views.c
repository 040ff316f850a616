/* The entity tokenizer, its checked number conversion and the view set of
 * BENCHMARK.md. */
#include "asset/entity_lump.h"
#include "scene/bench_views.h"
#include "util.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static int near(float a, float b) { return fabsf(a - b) < 1e-4f; }

static int cam_is(const ew_camera *c, float x, float y, float z, float p, float yaw, float r) {
    return near(c->origin[0], x) && near(c->origin[1], y) && near(c->origin[2], z) &&
           near(c->angles[0], p) && near(c->angles[1], yaw) && near(c->angles[2], r) &&
           near(c->fov, 90) && c->time == 0;
}

static void test_tokenizer(void) {
    ew_entities e;
    ew_error err = { "" };
    const char *text =
        "// a comment before\n"
        "{\n\"classname\" \"worldspawn\"\n\"wad\" \"C:\\quake\\id1.wad\" // trailing\n}\n"
        "{ \"classname\" \"light\" \"//not\" \"//a comment\" \"light\" \"200\" \"light\" \"300\" "
        "\"empty\" \"\" }{}";
    CHECK(ew_entities_parse(text, strlen(text), &e, &err) == 0, "%s", err.msg);
    CHECK(e.count == 3, "count %d", e.count);
    if (e.count == 3) {
        CHECK(e.ents[0].count == 2, "%d pairs", e.ents[0].count);
        CHECK(strcmp(ew_entity_get(&e.ents[0], "classname"), "worldspawn") == 0, "classname");
        CHECK(strcmp(ew_entity_get(&e.ents[0], "wad"), "C:\\quake\\id1.wad") == 0, "backslashes");
        /* "//" inside quotes is text, not a comment. */
        const char *v = ew_entity_get(&e.ents[1], "//not");
        CHECK(v && strcmp(v, "//a comment") == 0, "quoted slashes: %s", v ? v : "(null)");
        v = ew_entity_get(&e.ents[1], "light");
        CHECK(v && strcmp(v, "300") == 0, "repeated key: last wins, got %s", v ? v : "(null)");
        v = ew_entity_get(&e.ents[1], "empty");
        CHECK(v && *v == '\0', "empty value");
        CHECK(ew_entity_get(&e.ents[1], "missing") == NULL, "absent key");
        CHECK(e.ents[2].count == 0, "empty entity");
    }
    ew_entities_free(&e);

    /* Numbers: missing components are 0, junk stops the read. */
    const char *nums = "{ \"a\" \"1 -2.5 3e2\" \"b\" \"7\" \"c\" \"x y\" \"d\" \"1e999 4 5\" }";
    CHECK(ew_entities_parse(nums, strlen(nums), &e, &err) == 0, "%s", err.msg);
    if (e.count == 1) {
        float v[3];
        CHECK(ew_entity_floats(&e.ents[0], "a", v, 3) == 3 && v[0] == 1 && v[1] == -2.5f &&
                  v[2] == 300, "a: %g %g %g", v[0], v[1], v[2]);
        CHECK(ew_entity_floats(&e.ents[0], "b", v, 3) == 1 && v[0] == 7 && v[1] == 0 && v[2] == 0,
              "b");
        CHECK(ew_entity_floats(&e.ents[0], "c", v, 3) == 0 && v[0] == 0, "c");
        CHECK(ew_entity_floats(&e.ents[0], "d", v, 3) == 3 && v[0] == 0 && v[1] == 4, "d: %g",
              v[0]);
        CHECK(ew_entity_floats(&e.ents[0], "none", v, 3) == 0, "none");
    }
    ew_entities_free(&e);

    /* The length bounds the parse even without a NUL: only "{}" is read. */
    const char buf[] = { '{', '}', '{', '"', 'a' };
    CHECK(ew_entities_parse(buf, 2, &e, &err) == 0 && e.count == 1, "bounded: %s", err.msg);
    ew_entities_free(&e);
    CHECK(ew_entities_parse(buf, sizeof buf, &e, &err) < 0 && e.count == 1, "bounded error");
    ew_entities_free(&e);

    CHECK(ew_entities_parse(NULL, 10, &e, &err) == 0 && e.count == 0, "NULL text");
    ew_entities_free(&e);
    CHECK(ew_entities_parse("", 0, &e, &err) == 0 && e.count == 0, "empty text");
    ew_entities_free(&e);
}

/* Each malformed text keeps exactly the entities closed before the error. */
static void test_malformed(void) {
    static const struct {
        const char *text;
        int         kept;
    } cases[] = {
        { "{ \"a\" \"1\" } { \"b\" \"2\"", 1 },               /* missing '}' at the end */
        { "{ \"a\" \"1\" } { \"b\" }", 1 },                    /* key without value */
        { "{ \"a\" \"1 } { \"b\" \"2\" }", 0 },                /* unterminated on its line */
        { "{ \"a\" \"1\n\" }", 0 },                            /* newline inside a string */
        { "{ \"a\" \"1\" } }", 1 },                            /* stray '}' */
        { "{ \"a\" \"1\" } { { \"b\" \"2\" } }", 1 },          /* nested '{' */
        { "{ a 1 }", 0 },                                      /* unquoted */
        { "{ \"a\" \"1\" } / \"b\"", 1 },                      /* single slash */
        { "{ \"a\" \"1\" } x", 1 },                            /* junk between entities */
        { "{ \"a\"", 0 },                                      /* truncated */
        { "{ \"", 0 },
        { "\"", 0 },
        { "{", 0 },
        { "}", 0 },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        ew_entities e;
        ew_error err = { "" };
        int rc = ew_entities_parse(cases[i].text, strlen(cases[i].text), &e, &err);
        CHECK(rc < 0, "case %zu: rc %d", i, rc);
        CHECK(strncmp(err.msg, "entities: line ", 15) == 0, "case %zu: msg '%s'", i, err.msg);
        CHECK(e.count == cases[i].kept, "case %zu: kept %d, want %d", i, e.count,
              cases[i].kept);
        ew_entities_free(&e);
    }

    /* The line number points at the error. */
    ew_entities e;
    ew_error err = { "" };
    const char *text = "{\n\"a\" \"1\"\n}\n{\n\"b\"\n}\n";
    CHECK(ew_entities_parse(text, strlen(text), &e, &err) < 0 && strstr(err.msg, "line 6"),
          "line: %s", err.msg);
    ew_entities_free(&e);

    /* Every prefix of a valid lump parses without overreading (ASan checks
     * the bounds: each prefix is copied to an exactly-sized buffer). */
    const char *lump = "{ \"classname\" \"info_player_start\" \"origin\" \"1 2 3\" }\n"
                       "// c\n{ \"classname\" \"info_intermission\" }\n// end";
    size_t n = strlen(lump);
    for (size_t len = 0; len <= n; len++) {
        char *copy = malloc(len ? len : 1);
        memcpy(copy, lump, len);
        ew_entities_parse(copy, len, &e, NULL);
        CHECK(e.count <= 2, "prefix %zu", len);
        ew_entities_free(&e);
        free(copy);
    }
}

/* Random text made of the tokenizer's own characters: whatever it gets,
 * it must not crash or read out of bounds (ASan watches the bounds; each
 * text sits in an exactly-sized buffer with no NUL). */
static void test_fuzz(void) {
    static const char alphabet[] = "{}\"\"\"//\n\r \t ab0 -9.e";
    uint32_t seed = 12345;
    int closed = 0;
    for (int iter = 0; iter < 20000; iter++) {
        size_t len = (size_t)(iter % 97);
        char *text = malloc(len ? len : 1);
        for (size_t i = 0; i < len; i++) {
            seed = seed * 1664525u + 1013904223u;
            text[i] = alphabet[(seed >> 16) % (sizeof alphabet - 1)];
        }
        ew_entities e;
        ew_entities_parse(text, len, &e, NULL);
        for (int i = 0; i < e.count; i++) {
            float v[3];
            ew_entity_floats(&e.ents[i], "a", v, 3);
            closed++;
        }
        ew_entities_free(&e);
        free(text);
    }
    CHECK(closed > 0, "the fuzz never produced an entity");
}

/* Every number of an entity lump goes through ew_entity_number: values no
 * float or int can hold ("spawnflags" "1e30" was converted to int
 * unchecked: undefined behaviour) give the caller's fallback. */
static void test_checked_numbers(void) {
    const char *text =
        "{ \"i1\" \"1e30\" \"i2\" \"-inf\" \"i3\" \"nan\" \"i4\" \"-3e9\" \"i5\" \"3\" \"i6\" \"2.9\""
        "  \"i7\" \"-1\" \"i8\" \"x\" \"i9\" \"2147483647\" \"i10\" \"2147483648\" \"i11\" \" 7 junk\""
        "  \"f1\" \"1e40 0 0\" \"f2\" \"nan\" \"f3\" \"inf -1e39 nan\" \"f4\" \"-3.5 1e38 infinity 9\" }"
        "{ \"model\" \"*1\" } { \"model\" \"*1e30\" } { \"model\" \"*0\" } { \"model\" \"*1.5\" }"
        "{ \"model\" \"*12x\" } { \"model\" \"1\" } { } { \"model\" \"*-2\" } { \"model\" \"*nan\" }"
        "{ \"model\" \"*99999999999\" } { \"model\" \"*\" } { \"model\" \"*37\" }";
    ew_entities e;
    ew_error err = { "" };
    CHECK(ew_entities_parse(text, strlen(text), &e, &err) == 0 && e.count == 13, "%s", err.msg);
    if (e.count != 13) {
        ew_entities_free(&e);
        return;
    }
    const ew_entity *n = &e.ents[0];
    static const struct { const char *key; int want; } ints[] = {
        {"i1", -7}, {"i2", -7}, {"i3", -7}, {"i4", -7}, {"i5", 3}, {"i6", 2}, {"i7", -1},
        {"i8", -7}, {"i9", INT_MAX}, {"i10", -7}, {"i11", 7}, {"absent", -7},
    };
    for (size_t i = 0; i < sizeof ints / sizeof ints[0]; i++) {
        int got = ew_entity_int(n, ints[i].key, -7);
        CHECK(got == ints[i].want, "ew_entity_int %s: %d, want %d", ints[i].key, got, ints[i].want);
    }
    float v[4];
    CHECK(ew_entity_floats(n, "f1", v, 3) == 3 && v[0] == 0 && v[1] == 0 && v[2] == 0,
          "f1: %g %g %g", v[0], v[1], v[2]);
    CHECK(ew_entity_floats(n, "f2", v, 1) == 1 && v[0] == 0, "f2: %g", v[0]);
    CHECK(ew_entity_floats(n, "f3", v, 3) == 3 && v[0] == 0 && v[1] == 0 && v[2] == 0,
          "f3: %g %g %g", v[0], v[1], v[2]);
    CHECK(ew_entity_floats(n, "f4", v, 4) == 4 && v[0] == -3.5f && v[1] == 1e38f && v[2] == 0 &&
              v[3] == 9, "f4: %g %g %g %g", v[0], v[1], v[2], v[3]);

    /* The core conversion's three answers. */
    const char *end;
    double d = -1;
    CHECK(ew_entity_number(" 12.5 x", &end, 0, 100, &d) == 1 && d == 12.5 && *end == ' ', "12.5");
    d = -1;
    CHECK(ew_entity_number("1e30", &end, INT_MIN, INT_MAX, &d) == 0 && d == -1 && *end == '\0',
          "1e30 refused");
    CHECK(ew_entity_number("nan", &end, -1e300, 1e300, &d) == 0 && d == -1, "nan refused");
    CHECK(ew_entity_number("-infinity", &end, -HUGE_VAL, HUGE_VAL, &d) == 0, "inf refused");
    const char *junk = "junk";
    CHECK(ew_entity_number(junk, &end, 0, 1, &d) == -1 && end == junk, "no number");

    static const int subs[] = {1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, 37};
    for (int i = 0; i < 12; i++) {
        int got = ew_entity_submodel(&e.ents[1 + i]);
        const char *m = ew_entity_get(&e.ents[1 + i], "model");
        CHECK(got == subs[i], "ew_entity_submodel %s: %d, want %d", m ? m : "(none)", got, subs[i]);
    }
    ew_entities_free(&e);
}

/* The kept regression input (tests/regress/bsp29/entity_number_overflow.bin,
 * replayed by test_regressions): read as a map's scene and as the view set,
 * its numbers all fall back. */
static void test_regression_map(void) {
    const char *src = getenv("EW_SOURCE");
    char path[1024];
    snprintf(path, sizeof path, "%s/tests/regress/bsp29/entity_number_overflow.bin",
             src && *src ? src : ".");
    uint8_t *data = NULL;
    size_t size = 0;
    ew_error err = { "" };
    ew_world *w = NULL;
    if (ew_read_file(path, &data, &size, &err) == 0)
        w = ew_world_create(data, size, "entity_number_overflow.bin", &err);
    free(data);
    CHECK(w != NULL, "%s: %s", path, err.msg);
    if (!w)
        return;
    ew_camera v[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(w, v);
    CHECK(nv == 5, "%d views", nv);
    for (int k = 0; k < nv && k < 4; k++)
        CHECK(cam_is(&v[k], 0, 0, 22, 0, 90.0f * (float)k, 0), "start view %d", k);
    if (nv == 5)
        CHECK(cam_is(&v[4], 0, 0, 0, 0, 0, 0), "intermission: %g %g %g / %g %g %g", v[4].origin[0],
              v[4].origin[1], v[4].origin[2], v[4].angles[0], v[4].angles[1], v[4].angles[2]);
    ew_scene *s = ew_scene_create_from_map(w, NULL, NULL, &err);
    CHECK(s != NULL, "scene: %s", err.msg);
    if (s) {
        int ents = -1, unknown = -1, missing = -1;
        ew_scene_counts(s, &ents, &unknown, &missing);
        /* three items without a game directory and a door naming no submodel */
        CHECK(ents == 0 && unknown == 0 && missing == 4, "scene: %d entities, %d unknown, %d missing",
              ents, unknown, missing);
        ew_scene_destroy(s);
    }
    ew_world_destroy(w);
}

static void test_view_set(void) {
    ew_camera v[EW_MAX_VIEWS + 8];
    const char *text =
        "{ \"classname\" \"worldspawn\" \"message\" \"test\" }\n"
        "{ \"classname\" \"info_player_start\" \"origin\" \"100 -200 24\" \"angle\" \"90\" }\n"
        "{ \"classname\" \"light\" \"origin\" \"0 0 0\" }\n"
        "{ \"classname\" \"info_intermission\" \"origin\" \"1 2 3\" \"mangle\" \"10 20 30\" }\n"
        "{ \"origin\" \"5 5 5\" \"classname\" \"info_player_deathmatch\" }\n"
        "{ \"classname\" \"info_intermission\" \"origin\" \"-8 -9 -10\" }\n"
        "{ \"classname\" \"info_intermissionx\" \"origin\" \"0 0 0\" }\n"
        "{ \"classname\" \"xinfo_player_start\" \"origin\" \"0 0 0\" }\n"
        "{ \"origin\" \"0 0 0\" }\n";
    int n = ew_benchmark_views_from_entities(text, v, EW_MAX_VIEWS);
    CHECK(n == 10, "got %d views", n);
    if (n == 10) {
        CHECK(cam_is(&v[0], 100, -200, 46, 0, 90, 0), "v0");
        CHECK(cam_is(&v[1], 100, -200, 46, 0, 180, 0), "v1");
        CHECK(cam_is(&v[2], 100, -200, 46, 0, 270, 0), "v2");
        CHECK(cam_is(&v[3], 100, -200, 46, 0, 360, 0), "v3 yaw %g", v[3].angles[1]);
        CHECK(cam_is(&v[4], 1, 2, 3, 10, 20, 30), "intermission with mangle");
        CHECK(cam_is(&v[5], 5, 5, 27, 0, 0, 0), "player without angle");
        CHECK(cam_is(&v[8], 5, 5, 27, 0, 270, 0), "player without angle, last");
        CHECK(cam_is(&v[9], -8, -9, -10, 0, 0, 0), "intermission without mangle");
    }

    /* max smaller than one player's four views cuts mid-player. */
    CHECK(ew_benchmark_views_from_entities(text, v, 2) == 2, "max 2");
    CHECK(ew_benchmark_views_from_entities(text, v, 0) == 0, "max 0");
    CHECK(ew_benchmark_views_from_entities(NULL, v, 4) == 0, "NULL text");
    CHECK(ew_benchmark_views_from_entities("", v, 4) == 0, "no entities");

    /* Nine players make 36 views: only the first 32 are kept, in order. */
    char big[4096] = "";
    for (int i = 0; i < 9; i++) {
        char one[160];
        snprintf(one, sizeof one,
                 "{ \"classname\" \"info_player_coop\" \"origin\" \"%d 0 0\" \"angle\" \"%d\" }\n",
                 i * 10, i);
        strcat(big, one);
    }
    for (int i = 0; i < EW_MAX_VIEWS + 8; i++)
        v[i].fov = -1;
    n = ew_benchmark_views_from_entities(big, v, EW_MAX_VIEWS);
    CHECK(n == EW_MAX_VIEWS, "got %d views from 9 players", n);
    CHECK(cam_is(&v[31], 70, 0, 22, 0, 7 + 270, 0), "v31");
    CHECK(v[32].fov == -1, "wrote past max");

    /* A lump damaged half-way keeps the views before the damage. */
    const char *broken =
        "{ \"classname\" \"info_player_start\" \"origin\" \"0 0 0\" }\n"
        "{ \"classname\" \"info_intermission\" \"origin\" \"1 1 1\" }\n"
        "{ \"classname\" \"info_player_start\" \"origin\" \"0 0 0\" \n"
        "{ \"classname\" \"info_intermission\" }\n";
    CHECK(ew_benchmark_views_from_entities(broken, v, EW_MAX_VIEWS) == 5, "damaged lump");
}

/* Reads the entity lump straight from a BSP29 header (independent of the
 * loader) so the view counts are checked even before the loader exists. */
static char *bsp_entities(const char *path) {
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    unsigned char h[12];
    char *text = NULL;
    if (fread(h, 1, 12, f) == 12) {
        long ofs = h[4] | h[5] << 8 | h[6] << 16 | (long)h[7] << 24;
        long len = h[8] | h[9] << 8 | h[10] << 16 | (long)h[11] << 24;
        text = calloc((size_t)len + 1, 1);
        if (text && (fseek(f, ofs, SEEK_SET) != 0 || fread(text, 1, (size_t)len, f) != (size_t)len)) {
            free(text);
            text = NULL;
        }
    }
    fclose(f);
    return text;
}

/* The reference renders hold one image per view: their count is the map's
 * view count. */
static int reference_count(const char *map) {
    int n = 0;
    char rel[256];
    for (;;) {
        snprintf(rel, sizeof rel, "reference/winquake/%s_640x480_v%d.png", map, n);
        if (!ew_t_have_shared(rel))
            return n;
        n++;
    }
}

static void test_real_maps(void) {
    static const struct {
        const char *map;
        int         views;
    } maps[] = { { "e1m1", 29 }, { "lqdm7", 32 }, { "e4m1", 32 }, { "start", 20 } };
    for (size_t i = 0; i < sizeof maps / sizeof maps[0]; i++) {
        char rel[128];
        snprintf(rel, sizeof rel, "data/librequake/maps/%s.bsp", maps[i].map);
        if (!ew_t_need_shared(rel)) continue;
        int refs = reference_count(maps[i].map);
        CHECK(refs == maps[i].views, "%s: %d reference images", maps[i].map, refs);

        ew_camera direct[EW_MAX_VIEWS];
        char *text = bsp_entities(ew_t_shared(rel));
        CHECK(text != NULL, "%s: cannot read the entity lump", maps[i].map);
        int n = ew_benchmark_views_from_entities(text, direct, EW_MAX_VIEWS);
        free(text);
        CHECK(n == maps[i].views, "%s: %d views, want %d", maps[i].map, n, maps[i].views);

        /* Through the public API, once the loader is there. */
        uint8_t *data = NULL;
        size_t size = 0;
        ew_error err = { "" };
        ew_world *w = NULL;
        if (ew_read_file(ew_t_shared(rel), &data, &size, &err) == 0)
            w = ew_world_create(data, size, rel, &err);
        CHECK(w != NULL, "%s: %s", maps[i].map, err.msg);
        if (w) {
            ew_camera v[EW_MAX_VIEWS];
            int m = ew_benchmark_views(w, v);
            CHECK(m == n, "%s: ew_benchmark_views %d, direct %d", maps[i].map, m, n);
            for (int k = 0; k < m && k < n; k++)
                CHECK(cam_is(&v[k], direct[k].origin[0], direct[k].origin[1], direct[k].origin[2],
                             direct[k].angles[0], direct[k].angles[1], direct[k].angles[2]),
                      "%s: view %d differs", maps[i].map, k);
            ew_world_destroy(w);
        }
        free(data);
    }
}

int main(void) {
    test_tokenizer();
    test_malformed();
    test_fuzz();
    test_checked_numbers();
    test_regression_map();
    test_view_set();
    test_real_maps();
    return ew_t_finish();
}
