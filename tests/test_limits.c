/*
 * The limits of docs/limits.md hold: the loader refuses what the renderer
 * could not bound (textures sharing pixels, faces
 * with more edges than the clipper holds), damaged PVS rows stay inside
 * their lump, brush fragments stop at their depth limit, and the surface
 * cache never holds more than twice its budget.  Files are the seed room
 * of fuzz/seed_files.c with one lump changed.
 */
#include "util.h"
#include "seed_files.h"
#include "renderer.h"

#include <stdlib.h>
#include <string.h>

static uint8_t palette[768], colormap[EW_COLORMAP_SIZE];

static uint32_t rd32(const uint8_t *p) {
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
static void wr32(uint8_t *p, uint32_t v) {
    for (int i = 0; i < 4; i++) p[i] = (uint8_t)(v >> (8 * i));
}

/* Start of lump i in a BSP image, and its length. */
static uint8_t *lump(uint8_t *bsp, int i, uint32_t *len) {
    if (len) *len = rd32(bsp + 8 + 8 * i);
    return bsp + rd32(bsp + 4 + 8 * i);
}

/* A copy of bsp with lump i replaced by data (appended at the end). */
static uint8_t *replace_lump(const ew_seed_buf *bsp, int i, const uint8_t *data, uint32_t len, size_t *size) {
    *size = bsp->len + len;
    uint8_t *d = malloc(*size);
    memcpy(d, bsp->d, bsp->len);
    memcpy(d + bsp->len, data, len);
    wr32(d + 4 + 8 * i, (uint32_t)bsp->len);
    wr32(d + 8 + 8 * i, len);
    return d;
}

/* Loads d; returns the world or NULL, and checks the error mentions want. */
static ew_world *load(const uint8_t *d, size_t n, const char *want) {
    ew_error err = {""};
    ew_world *w = ew_world_create(d, n, "limits.bsp", &err);
    if (want) {
        CHECK(!w, "accepted a file that should fail with '%s'", want);
        CHECK(strstr(err.msg, want) != NULL, "error '%s' lacks '%s'", err.msg, want);
    } else {
        CHECK(w != NULL, "refused: %s", err.msg);
    }
    return w;
}

static void render_ok(const ew_world *w, const char *what) {
    ew_error err = {""};
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){ .world = w, .palette = palette,
            .colormap = colormap, .width = 320, .height = 200, .threads = 1 }, &err);
    CHECK(r != NULL, "%s: %s", what, err.msg);
    if (!r) return;
    ew_camera views[EW_MAX_VIEWS];
    int n = ew_benchmark_views(w, views);
    for (int i = 0; i < n; i++) CHECK(ew_render(r, &views[i], NULL) == 0, "%s: view %d", what, i);
    ew_renderer_destroy(r);
}

static void loader_limits(const ew_seed_buf *room) {
    ew_world *w = load(room->d, room->len, NULL);
    if (w) render_ok(w, "room");
    ew_world_destroy(w);

    /* The floor's t axis zeroed: extent 0, one row of light samples and
     * a surface one texel tall (ericw-tools writes such faces): it loads
     * and renders (tests/test_flat_extent.c looks closer). */
    uint8_t *d = malloc(room->len);
    memcpy(d, room->d, room->len);
    memset(lump(d, EW_LUMP_TEXINFO, NULL) + 16, 0, 16);
    w = load(d, room->len, NULL);
    if (w) render_ok(w, "extent 0");
    ew_world_destroy(w);
    free(d);

    /* 249 edges on a face: more than the renderer's clipper holds. */
    d = malloc(room->len);
    memcpy(d, room->d, room->len);
    uint8_t *face = lump(d, EW_LUMP_FACES, NULL);
    face[8] = 249 & 255, face[9] = 249 >> 8;
    load(d, room->len, "249 edges");
    free(d);

    /* 64 texture slots sharing one 64x64 texture: 64 copies of its pixels
     * from a lump holding one. */
    enum { SLOTS = 64, SIDE = 64, PIXELS = SIDE * SIDE * 85 / 64 };
    uint32_t len = 4 + 4 * SLOTS + 40 + PIXELS;
    uint8_t *tex = calloc(1, len);
    wr32(tex, SLOTS);
    for (int i = 0; i < SLOTS; i++) wr32(tex + 4 + 4 * i, 4 + 4 * SLOTS);
    uint8_t *mt = tex + 4 + 4 * SLOTS;
    memcpy(mt, "shared", 7);
    wr32(mt + 16, SIDE), wr32(mt + 20, SIDE);
    for (int k = 0, o = 40; k < 4; k++) wr32(mt + 24 + 4 * k, (uint32_t)o), o += (SIDE >> k) * (SIDE >> k);
    size_t n;
    d = replace_lump(room, EW_LUMP_TEXTURES, tex, len, &n);
    load(d, n, "overlap");
    free(d);
    /* The same texture in one slot (the room's other six missing) loads. */
    enum { ROOM_SLOTS = 7 };
    wr32(tex, ROOM_SLOTS);
    wr32(tex + 4, 4 + 4 * ROOM_SLOTS);
    for (int i = 1; i < ROOM_SLOTS; i++) wr32(tex + 4 + 4 * i, 0xFFFFFFFFu);
    memmove(tex + 4 + 4 * ROOM_SLOTS, mt, 40 + PIXELS);
    d = replace_lump(room, EW_LUMP_TEXTURES, tex, 4 + 4 * ROOM_SLOTS + 40 + PIXELS, &n);
    ew_world_destroy(load(d, n, NULL));
    free(d);
    free(tex);

    /* PVS rows cut short: a zero run whose count is past the lump, a run
     * far longer than the leaves.  Decoding stays inside the lump. */
    static const uint8_t rows[][2] = {{0x00, 0x00}, {0x00, 0xff}};
    for (int i = 0; i < 2; i++) {
        d = replace_lump(room, EW_LUMP_VISIBILITY, rows[i], (uint32_t)(1 + i), &n);
        w = load(d, n, NULL);
        if (w) render_ok(w, "short PVS row");
        ew_world_destroy(w);
        free(d);
    }
}

/* A brush model split down a 1500-node chain: the fragments stop at the
 * depth limit (counted as dropped) instead of exhausting the stack. */
static void deep_tree(void) {
    const char *src = getenv("EW_SOURCE");
    char path[1024];
    snprintf(path, sizeof path, "%s/tests/regress/render/deep_chain_brush.bin", src && *src ? src : ".");
    uint8_t *d;
    size_t n;
    ew_error err = {""};
    if (ew_read_file(path, &d, &n, &err) != 0) {
        CHECK(0, "%s", err.msg);
        return;
    }
    ew_world *w = load(d, n, NULL);
    free(d);
    if (!w) return;
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){ .world = w, .palette = palette,
            .colormap = colormap, .width = 320, .height = 200, .threads = 1 }, &err);
    ew_scene *s = ew_scene_create(w, &err);
    CHECK(r && s && ew_scene_add_brush(s, 1, NULL, NULL) >= 0, "scene: %s", err.msg);
    if (r && s) {
        ew_set_scene(r, s);
        ew_camera cam = {{0, 0, 22}, {0, 30, 0}, 90, 0};
        ew_stats st;
        CHECK(ew_render(r, &cam, &st) == 0, "render");
        CHECK(st.dropped > 0, "fragments past the depth limit not counted (dropped %d)", st.dropped);
    }
    ew_renderer_destroy(r);
    ew_scene_destroy(s);
    ew_world_destroy(w);
}

/* The cache may pass its budget only by this frame's surfaces, and never
 * hold more than twice it; what would pass that is refused and counted. */
static void cache_cap(const ew_world *w, const char *name) {
    ew_error err = {""};
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){ .world = w, .palette = palette,
            .colormap = colormap, .width = 640, .height = 400, .threads = 1 }, &err);
    CHECK(r != NULL, "%s: %s", name, err.msg);
    if (!r) return;
    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(w, views), refused = 0;
    r->lit.cache.budget = 32 * 1024;
    for (int i = 0; i < nv; i++) {
        ew_stats st;
        CHECK(ew_render(r, &views[i], &st) == 0, "%s: view %d", name, i);
        CHECK(r->lit.cache.bytes <= 2 * r->lit.cache.budget, "%s: view %d: cache %zu bytes, cap %zu", name, i,
              r->lit.cache.bytes, 2 * r->lit.cache.budget);
        CHECK(st.pixels_covered == st.pixels, "%s: view %d: refused surfaces must still be drawn", name, i);
        refused += st.dropped > 0;
    }
    CHECK(refused > 0, "%s: a 32 KB cache refused nothing", name);
    r->lit.cache.budget = (size_t)16 << 20;
    for (int i = 0; i < nv; i++) {
        ew_stats st;
        ew_render(r, &views[i], &st);
        CHECK(st.dropped == 0, "%s: view %d: dropped %d with the normal budget", name, i, st.dropped);
    }
    ew_renderer_destroy(r);
}

int main(void) {
    for (int i = 0; i < 768; i++) palette[i] = (uint8_t)(i / 3);
    for (int i = 0; i < EW_COLORMAP_SIZE; i++) colormap[i] = (uint8_t)i;
    ew_seed_buf room = {0};
    ew_seed_room(&room);
    loader_limits(&room);
    free(room.d);
    deep_tree();

    ew_assets *a = NULL;
    ew_error err = {""};
    if ((a = ew_assets_create_builtin(&err)) != NULL) {
        cache_cap(a->world, "builtin");
        ew_assets_destroy(a);
    } else {
        CHECK(0, "builtin: %s", err.msg);
    }
    /* Missing shared data is a skip (exit 77), which CI counts as a failure. */
    if (ew_t_need_shared("data/librequake/maps/e1m1.bsp")) {
        a = ew_assets_create("e1m1", ew_t_shared("data/librequake"), &err);
        CHECK(a != NULL, "e1m1: %s", err.msg);
        if (a) {
            cache_cap(a->world, "e1m1");
            ew_assets_destroy(a);
        }
    }
    return ew_t_finish();
}
