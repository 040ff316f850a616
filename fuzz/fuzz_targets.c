/* The per-format fuzz bodies (see fuzz_targets.h).  Besides surviving,
 * they check a few promises the rest of the code relies on and abort if
 * one is broken, so the fuzzer reports it like a crash:
 *   - a loaded world only holds indices the renderer can use unchecked;
 *   - a frame writes every pixel exactly once (overdraw 1) unless a budget
 *     dropped something.
 * The BSP targets also read the entity lump as a map's scene does (the
 * view set, classnames, spawnflags, submodels).  The render target draws
 * the map with its brush models and a dynamic light; the MDL and SPR
 * targets also draw what their loader accepted. */
#include "fuzz_targets.h"
#include "seed_files.h"

#include "edgewise.h"
#include "edgewise_lab.h"
#include "ew_util.h"
#include "ew_world.h"
#include "light/light.h"
#include "renderer.h"
#include "mapgen.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Defined by fuzz/loaders.cmake once the loaders' sources exist. */
#ifdef EW_FUZZ_HAVE_MDL
#include "asset/mdl.h"
#endif
#ifdef EW_FUZZ_HAVE_SPR
#include "asset/spr.h"
#endif

#ifdef EW_FUZZ_HAVE_MDL
const int ew_fuzz_have_mdl = 1;
#else
const int ew_fuzz_have_mdl = 0;
#endif
#ifdef EW_FUZZ_HAVE_SPR
const int ew_fuzz_have_spr = 1;
#else
const int ew_fuzz_have_spr = 0;
#endif

/* Reads stored here cannot be optimised away. */
unsigned ew_fuzz_sink;

static void broken(const char *what, int index) {
    fprintf(stderr, "fuzz: loader accepted a world that breaks its promise: %s (%d)\n", what, index);
    abort();
}

/* Every error path must leave a message. */
static int rejected(const ew_error *err) {
    if (!err->msg[0]) {
        fprintf(stderr, "fuzz: failure without an error message\n");
        abort();
    }
    return 1;
}

/* What ew_world.h says the loader has validated, checked independently. */
static void check_world(const ew_world *w) {
    for (int i = 0; i < w->numfaces; i++) {
        const ew_face *f = &w->faces[i];
        if (f->plane < 0 || f->plane >= w->numplanes) broken("face plane", i);
        if (f->texinfo < 0 || f->texinfo >= w->numtexinfo) broken("face texinfo", i);
        /* 248: what the renderer's clip buffers hold (EW_MAX_POLY - 8) */
        if (f->numedges < 3 || f->numedges > 248 || f->firstedge < 0 ||
            f->firstedge + f->numedges > w->numsurfedges)
            broken("face edges", i);
        for (int e = 0; e < f->numedges; e++) {
            if (ew_face_edge(w, f, e) >= w->numedges) broken("face edge index", i);
            if (ew_face_vertex(w, f, e) < 0 || ew_face_vertex(w, f, e) >= w->numverts)
                broken("face vertex index", i);
        }
        if (!(f->flags & (EW_SURF_SKY | EW_SURF_TURB)))
            for (int j = 0; j < 2; j++)
                if (f->extents[j] < 0 || f->extents[j] > 2048 || f->extents[j] % 16) broken("face extents", i);
        if (f->lightofs >= 0) {
            int ns = 0;
            while (ns < 4 && f->styles[ns] != 255) ns++;
            long size = (long)((f->extents[0] >> 4) + 1) * ((f->extents[1] >> 4) + 1) * ns;
            if (f->extents[0] < 0 || f->extents[1] < 0 || f->lightofs + size > w->lightsize)
                broken("face light map", i);
        }
    }
    for (int i = 0; i < w->numtexinfo; i++)
        if (w->texinfo[i].texture < 0 || w->texinfo[i].texture >= w->numtextures)
            broken("texinfo texture", i);
    for (int i = 0; i < w->numtextures; i++) {
        const ew_texture *t = &w->textures[i];
        if (t->width < 1 || t->height < 1 || !t->mip[0]) broken("texture size", i);
        if (t->anim_next >= w->numtextures || t->alternate_anims >= w->numtextures)
            broken("texture animation", i);
    }
    for (int i = 0; i < w->nummarksurfaces; i++)
        if (w->marksurfaces[i] < 0 || w->marksurfaces[i] >= w->numfaces) broken("marksurface", i);
    for (int i = 0; i < w->numleaves; i++) {
        const ew_leaf *l = &w->leaves[i];
        if (l->firstmark < 0 || l->nummarks < 0 || l->firstmark + l->nummarks > w->nummarksurfaces)
            broken("leaf marksurfaces", i);
        if (l->visofs != -1 && (l->visofs < 0 || l->visofs >= w->vissize)) broken("leaf visofs", i);
    }
    for (int i = 0; i < w->numnodes; i++) {
        const ew_node *n = &w->nodes[i];
        if (n->plane < 0 || n->plane >= w->numplanes) broken("node plane", i);
        for (int k = 0; k < 2; k++)
            if (n->children[k] >= w->numnodes || -1 - n->children[k] >= w->numleaves)
                broken("node child", i);
        if (n->firstface < 0 || n->numfaces < 0 || n->firstface + n->numfaces > w->numfaces)
            broken("node faces", i);
    }
    if (w->nummodels < 1) broken("no models", 0);
    for (int i = 0; i < w->nummodels; i++) {
        const ew_model *m = &w->models[i];
        if (m->headnode < 0 || m->headnode >= w->numnodes) broken("model head node", i);
        if (m->visleafs < 0 || m->visleafs >= w->numleaves) broken("model visleafs", i);
        if (m->firstface < 0 || m->numfaces < 0 || m->firstface + m->numfaces > w->numfaces)
            broken("model faces", i);
    }
}

/* The fuzzer's buffer is exactly `size` bytes, so ASan sees any read past
 * it; a patched copy must keep that property. */
static uint8_t *copy_with_magic(const uint8_t *data, size_t size, const uint8_t magic[4]) {
    uint8_t *d = malloc(size ? size : 1);
    if (!d) return NULL;
    memcpy(d, data, size);
    for (size_t i = 0; i < 4 && i < size; i++) d[i] = magic[i];
    return d;
}

static int load_world(const uint8_t *data, size_t size) {
    ew_error err = {""};
    ew_world *w = ew_world_create(data, size, "fuzz.bsp", &err);
    if (!w) return rejected(&err);
    check_world(w);
    ew_world_info info;
    ew_world_get_info(w, &info);
    ew_camera views[EW_MAX_VIEWS];
    int n = ew_benchmark_views(w, views);
    if (n < 0 || n > EW_MAX_VIEWS) broken("view count", n);
    (void)strlen(ew_world_entities(w));
    /* The entity lump read as a map's scene is (no game directory, so no
     * model files): every number in it goes through the parser's checks. */
    ew_scene *sc = ew_scene_create_from_map(w, NULL, NULL, &err);
    ew_scene_destroy(sc);
    ew_world_destroy(w);
    return 0;
}

int ew_fuzz_bsp29(const uint8_t *data, size_t size) {
    static const uint8_t v29[4] = {29, 0, 0, 0};
    uint8_t *d = copy_with_magic(data, size, v29);
    if (!d) return 1;
    int rc = load_world(d, size);
    free(d);
    return rc;
}

/* The BSP2 target keeps a 2PSB magic and makes everything else BSP2, so
 * the fuzzer spends its time on the 32-bit layouts. */
int ew_fuzz_bsp2(const uint8_t *data, size_t size) {
    const uint8_t *magic = (const uint8_t *)"BSP2";
    if (size >= 4 && memcmp(data, "2PSB", 4) == 0) magic = (const uint8_t *)"2PSB";
    uint8_t *d = copy_with_magic(data, size, magic);
    if (!d) return 1;
    int rc = load_world(d, size);
    free(d);
    return rc;
}

int ew_fuzz_pak(const uint8_t *data, size_t size) {
    ew_error err = {""};
    ew_pak_entry *e;
    int n;
    if (ew_pak_parse(data, size, "fuzz.pak", &e, &n, &err) != 0) return rejected(&err);
    /* Touch each entry's first and last byte: ASan flags any outside the file. */
    for (int i = 0; i < n; i++) {
        if (strlen(e[i].name) >= sizeof e[i].name) broken("pak name", i);
        if (e[i].size) ew_fuzz_sink += data[e[i].offset] + data[e[i].offset + e[i].size - 1];
    }
    free(e);
    return 0;
}

int ew_fuzz_lmp(const uint8_t *data, size_t size) {
    ew_error err = {""};
    static uint8_t palette[768], colormap[EW_COLORMAP_SIZE];
    int bad = 0;
    if (ew_palette_parse(data, size, "fuzz.lmp", palette, &err) != 0) bad = rejected(&err);
    err.msg[0] = '\0';
    if (ew_colormap_parse(data, size, "fuzz.lmp", colormap, &err) != 0) bad = rejected(&err);
    return bad;
}

int ew_fuzz_demo(const uint8_t *data, size_t size) {
    ew_error err = {""};
    ew_demo *d = ew_demo_open_memory(data, size, "fuzz.dem", &err);
    if (!d) return rejected(&err);
    int rc, blocks = 0;
    while ((rc = ew_demo_read_block(d, &err)) == 1) {
        const ew_demo_state *st = ew_demo_get_state(d);
        blocks++;
        if (st->nentities < 0 || st->nentities > EW_DEMO_MAX_ENTITIES) broken("demo entities", st->nentities);
        if (st->nevents < 0 || st->nevents > EW_DEMO_MAX_EVENTS) broken("demo events", st->nevents);
        if (st->nstatics < 0 || st->nstatics > EW_DEMO_MAX_STATICS) broken("demo statics", st->nstatics);
        if (st->nmodels < 0 || st->nmodels >= EW_DEMO_MAX_MODELS) broken("demo models", st->nmodels);
        for (int i = 0; i < st->nentities; i++) {
            const ew_demo_entity *e = &st->entities[i];
            if (e->model < 0 || e->model >= EW_DEMO_MAX_MODELS) broken("demo entity model", i);
            for (int k = 0; k < 3; k++)
                if (!isfinite(e->origin[k]) || !isfinite(e->prev_origin[k]) || !isfinite(e->angles[k])) broken("demo entity place", i);
        }
        for (int i = 0; i < EW_DEMO_LIGHTSTYLES; i++)
            if (strlen(st->lightstyles[i]) > 64) broken("demo light style", i);
        ew_fuzz_sink += (unsigned)st->nentities + (unsigned)st->nevents;
    }
    if (blocks > ew_demo_block_count(d)) broken("demo blocks", blocks);
    ew_demo_close(d);
    return rc < 0 ? rejected(&err) : 0;
}

/* A palette and colormap of our own: rendering needs them, their values
 * do not matter. */
static void make_tables(uint8_t palette[768], uint8_t colormap[EW_COLORMAP_SIZE]) {
    for (int i = 0; i < 768; i++) palette[i] = (uint8_t)(i / 3);
    for (int row = 0; row < 64; row++)
        for (int c = 0; c < 256; c++) colormap[row * 256 + c] = (uint8_t)(c * (63 - row) / 63);
}

int ew_fuzz_render(const uint8_t *data, size_t size) {
    static uint8_t palette[768], colormap[EW_COLORMAP_SIZE];
    static int have_tables;
    if (!have_tables) make_tables(palette, colormap), have_tables = 1;

    ew_error err = {""};
    ew_world *w = ew_world_create(data, size, "fuzz.bsp", &err);
    if (!w) return rejected(&err);
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){ .world = w, .palette = palette,
            .colormap = colormap, .width = 320, .height = 200, .threads = 1 }, &err);
    if (!r) {
        ew_world_destroy(w);
        return rejected(&err);
    }
    ew_camera views[EW_MAX_VIEWS], cam;
    memset(&cam, 0, sizeof cam);
    if (ew_benchmark_views(w, views) > 0) {
        cam = views[0];
    } else {
        const ew_model *m = &w->models[0];
        for (int k = 0; k < 3; k++) cam.origin[k] = (m->mins[k] + m->maxs[k]) * 0.5f;
        cam.fov = 90;
    }
    cam.time = 1.25;  /* past 0, so animations and the sky move */
    /* The map's brush models (some turned) and a dynamic light at the eye. */
    ew_scene *sc = ew_scene_create(w, &err);
    if (sc) {
        const float turned[3] = {0, 30, 0};
        for (int i = 1; i < w->nummodels && i <= 64; i++) ew_scene_add_brush(sc, i, NULL, i % 2 ? NULL : turned);
        ew_scene_add_dlight(sc, cam.origin, 300);
        ew_set_scene(r, sc);
    }
    ew_stats st;
    int rc = ew_render(r, &cam, &st);
    if (rc == 0 && st.dropped == 0 && st.pixels_written != st.pixels_covered) {
        fprintf(stderr, "fuzz: overdraw %ld written / %ld covered without drops\n",
                st.pixels_written, st.pixels_covered);
        abort();
    }
    ew_renderer_destroy(r);
    ew_scene_destroy(sc);
    ew_world_destroy(w);
    return rc == 0 ? 0 : 1;
}

/* Draws a model the loader accepted in the seed room, twice in view (near
 * and far, so both alias rasterizers run), with frame and skin 0 and 1 and
 * a time inside any group: the rasterizers meet whatever the loader let
 * through. */
static void render_model(const uint8_t *data, size_t size, const char *name) {
    static uint8_t palette[768], colormap[EW_COLORMAP_SIZE];
    static ew_world *room;
    ew_error err = {""};
    if (!room) {
        ew_seed_buf b = {0};
        ew_seed_room(&b);
        room = ew_world_create(b.d, b.len, "room.bsp", &err);
        free(b.d);
        make_tables(palette, colormap);
        if (!room) broken("the seed room does not load", 0);
    }
    ew_scene *s = ew_scene_create(room, &err);
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){ .world = room, .palette = palette,
            .colormap = colormap, .width = 320, .height = 200, .threads = 1 }, &err);
    int m = s ? ew_scene_load_model(s, name, data, size, &err) : -1;
    if (r && m >= 0) {
        /* the seed room's player start: (0, 0, 22) looking along yaw 30 */
        const float near_pt[3] = {26, 15, 10}, far_pt[3] = {52, 30, 30}, angles[3] = {0, 200, 0};
        ew_scene_add_entity(s, m, near_pt, angles, 0, 0);
        ew_scene_add_entity(s, m, far_pt, NULL, 1, 1);
        ew_set_scene(r, s);
        ew_camera cam = {{0, 0, 22}, {0, 30, 0}, 90, 1.25};
        ew_stats st;
        ew_render(r, &cam, &st);
        ew_set_alias_raster(r, EW_ALIAS_SUBDIV, 0);
        cam.time = 7.5;
        ew_render(r, &cam, &st);
    }
    ew_renderer_destroy(r);
    ew_scene_destroy(s);
}

int ew_fuzz_mdl(const uint8_t *data, size_t size) {
#ifdef EW_FUZZ_HAVE_MDL
    ew_error err = {""};
    ew_mdl *m = ew_mdl_load(data, size, "fuzz.mdl", &err);
    if (!m) return rejected(&err);
    ew_mdl_free(m);
    render_model(data, size, "fuzz.mdl");
    return 0;
#else
    (void)data, (void)size;
    return 1;
#endif
}

int ew_fuzz_spr(const uint8_t *data, size_t size) {
#ifdef EW_FUZZ_HAVE_SPR
    ew_error err = {""};
    ew_spr *s = ew_spr_load(data, size, "fuzz.spr", &err);
    if (!s) return rejected(&err);
    ew_spr_free(s);
    render_model(data, size, "fuzz.spr");
    return 0;
#else
    (void)data, (void)size;
    return 1;
#endif
}

/* ---- light data (.lit, BSPX) ---- */

/* What asset/lightdata.c promises about facelm and rgblight. */
static void check_light(const ew_world *w) {
    if (w->rgblight && !w->lighting) broken("rgblight without lighting", 0);
    if (!w->facelm) return;
    for (int i = 0; i < w->numfaces; i++) {
        const ew_facelm *lm = &w->facelm[i];
        for (int j = 0; j < 2; j++)
            for (int k = 0; k < 3; k++)
                if (!(lm->st_to_lm[j][k] > -1e30f && lm->st_to_lm[j][k] < 1e30f)) broken("facelm projection", i);
        if (lm->lightofs < 0) continue;
        int ns = 0;
        while (ns < 4 && w->faces[i].styles[ns] != 255) ns++;
        if (lm->width < 1 || lm->height < 1 || ns == 0 ||
            lm->lightofs + (long long)lm->width * lm->height * ns > w->lightsize)
            broken("facelm outside the light lump", i);
    }
}

/* The light under models at the map's views and a grid of points. */
static void probe_light(const ew_world *w) {
    static uint8_t palette[768], colormap[EW_COLORMAP_SIZE];
    static int have;
    if (!have) make_tables(palette, colormap), have = 1;
    ew_error err = {""};
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){ .world = w, .palette = palette,
            .colormap = colormap, .width = 320, .height = 200, .threads = 1 }, &err);
    if (!r) return;
    for (int i = 0; i < 64; i++) {
        float p[3] = {(float)(i % 8) * 130 + 8, (float)(i / 8) * 100 + 8, 120};
        int rgb[3];
        int v = ew_light_point_rgb(&r->f, p, rgb);
        if (v < 0 || v > 255 || rgb[0] < 0 || rgb[0] > 255 || rgb[1] < 0 || rgb[1] > 255 || rgb[2] < 0 || rgb[2] > 255)
            broken("light point range", i);
        ew_fuzz_sink += (unsigned)v + (unsigned)rgb[2];
    }
    ew_renderer_destroy(r);
}

static ew_world *lit_world;
static uint8_t *bspx_base[4];
static size_t bspx_cut_at[4];

void ew_fuzz_lit_init(void) {
    ew_world *w = lit_world;
    if (!w) {
        uint8_t *bsp, palette[768], colormap[EW_COLORMAP_SIZE];
        size_t n;
        ew_error err = {""};
        if (ew_builtin_generate(&bsp, &n, palette, colormap, &err)) broken("the built-in map", 0);
        w = ew_world_create(bsp, n, "builtin.bsp", &err);
        free(bsp);
        if (!w) broken("the built-in map does not load", 0);
        lit_world = w;
    }
}

int ew_fuzz_lit(const uint8_t *data, size_t size) {
    ew_fuzz_lit_init();
    ew_world *w = lit_world;
    int rc = ew_world_attach_lit(w, data, size, "fuzz.lit");
    if (rc == 0 && !w->rgblight) broken("attached without rgblight", 0);
    if (rc != 0 && (w->rgblight || w->nwarnings != 1)) broken("ignored .lit without exactly one warning", 0);
    check_light(w);
    if (rc == 0) probe_light(w);
    free(w->rgblight);
    w->rgblight = NULL;
    ew_warn_free(w->warnings, w->nwarnings);
    w->warnings = NULL, w->nwarnings = 0;
    return rc == 0 ? 0 : 1;
}

void ew_fuzz_bspx_options(int v, struct ew_mapgen_options *o) {
    memset(o, 0, sizeof *o);
    o->rgblighting = 1;
    if (v == 1 || v == 2) o->lmshift_lumps = 1, o->lmshift = v == 1 ? 3 : 5;
    if (v == 3) o->decoupled = 1, o->decoupled_units = 12;
}

static uint32_t ew_fuzz_le32(const uint8_t *p) {
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

size_t ew_fuzz_bspx_cut(const uint8_t *bsp, size_t size) {
    size_t end = 0;
    for (int i = 0; i < EW_NUM_LUMPS && 12 + 8 * (size_t)i <= size; i++) {
        size_t e = (size_t)ew_fuzz_le32(bsp + 4 + 8 * i) + ew_fuzz_le32(bsp + 8 + 8 * i);
        if (e > end) end = e;
    }
    return end;
}

static void bspx_init_one(int v) {
    uint8_t **base = bspx_base;
    size_t *cut = bspx_cut_at;
    if (!base[v]) {
        ew_mapgen_options o;
        ew_fuzz_bspx_options(v, &o);
        uint8_t *bsp, palette[768], colormap[EW_COLORMAP_SIZE];
        size_t n;
        ew_error err = {""};
        if (ew_builtin_generate_ex(&o, &bsp, &n, palette, colormap, NULL, NULL, &err)) broken("a BSPX base map", v);
        cut[v] = ew_fuzz_bspx_cut(bsp, n);
        base[v] = bsp;
    }
}

void ew_fuzz_bspx_init(void) {
    for (int v = 0; v < 4; v++) bspx_init_one(v);
}

int ew_fuzz_bspx(const uint8_t *data, size_t size) {
    uint8_t **base = bspx_base;
    size_t *cut = bspx_cut_at;
    if (size < 1) return 1;
    int v = data[0] & 3;
    bspx_init_one(v);
    /* exactly the bytes of the file, so ASan sees any read past it */
    size_t n = cut[v] + size - 1;
    uint8_t *d = malloc(n ? n : 1);
    if (!d) return 1;
    memcpy(d, base[v], cut[v]);
    memcpy(d + cut[v], data + 1, size - 1);
    ew_error err = {""};
    ew_world *w = ew_world_create(d, n, "fuzz.bsp", &err);
    if (!w) {
        free(d);
        return rejected(&err);
    }
    check_world(w);
    check_light(w);
    probe_light(w);
    ew_world_destroy(w);
    free(d);
    return 0;
}

ew_fuzz_fn ew_fuzz_target(const char *name) {
    static const struct { const char *name; ew_fuzz_fn fn; } targets[] = {
        {"pak", ew_fuzz_pak},     {"bsp29", ew_fuzz_bsp29}, {"bsp2", ew_fuzz_bsp2},
        {"lmp", ew_fuzz_lmp},     {"render", ew_fuzz_render}, {"mdl", ew_fuzz_mdl},
        {"spr", ew_fuzz_spr},     {"lit", ew_fuzz_lit},     {"bspx", ew_fuzz_bspx},
        {"demo", ew_fuzz_demo},
    };
    for (size_t i = 0; i < sizeof targets / sizeof targets[0]; i++)
        if (strcmp(targets[i].name, name) == 0) return targets[i].fn;
    return NULL;
}
