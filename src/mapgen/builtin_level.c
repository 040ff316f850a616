/*
 * The built-in scene: a small level the project makes itself, so `make
 * demo` needs no files from outside the repository.
 *
 * Layout (cells of 16 units; x east, y north, z up):
 *   - a courtyard open to the sky (brick walls on a stone plinth under a
 *     cornice), with a pool of water, two stone pillars, a metal platform
 *     reached by two steps and a niche holding an animated button;
 *   - a metal corridor east into a lower brick hall with a metal column and
 *     a second button on its far wall;
 *   - a wooden staircase north from the hall up into a tall stone room with
 *     a window looking back into the courtyard.
 *   - a plank door (submodel *1, a func_door) standing half open in the
 *     corridor's mouth, slid aside into the wall.
 * The grid is turned into a real BSP29 image (bsp_writer.c), which
 * ew_assets_create_builtin (src/asset/assets.c) loads through ew_world_create like
 * any map.  The moving things drawn over it (the door's entity, a triangle
 * model, particles, a dynamic light) are ew_scene_create_builtin's
 * (src/scene/builtin_scene.c).
 */
#include "mapgen_internal.h"
#include "ew_util.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { NX = 64, NY = 50, NZ = 22 };

static void fill(bi_grid *g, int x0, int y0, int z0, int x1, int y1, int z1, int kind, int mat) {
    for (int z = z0; z < z1; z++)
        for (int y = y0; y < y1; y++)
            for (int x = x0; x < x1; x++) {
                size_t i = ((size_t)z * g->n[1] + y) * g->n[0] + x;
                g->kind[i] = (uint8_t)kind;
                g->mat[i] = (uint8_t)mat;
            }
}
/* Solid with a material (paint walls before carving rooms out of them). */
static void paint(bi_grid *g, int x0, int y0, int z0, int x1, int y1, int z1, int mat) {
    fill(g, x0, y0, z0, x1, y1, z1, BI_SOLID, mat);
}
static void carve(bi_grid *g, int x0, int y0, int z0, int x1, int y1, int z1) {
    fill(g, x0, y0, z0, x1, y1, z1, BI_EMPTY, 0);
}

static void layout(bi_grid *g) {
    fill(g, 0, 0, 0, NX, NY, NZ, BI_SOLID, BI_M_BRICK);

    /* courtyard: brick walls on a stone plinth under a stone cornice, sky above */
    paint(g, 2, 2, 0, 28, 36, 4, BI_M_STONE);
    carve(g, 2, 2, 4, 28, 36, 14);
    fill(g, 2, 2, 14, 28, 36, 16, BI_SKY, 0);
    for (int z = 4; z < 14; z += 9) {  /* plinth at the floor, cornice at the top */
        paint(g, 2, 2, z, 28, 3, z + 1, BI_M_STONE);
        paint(g, 2, 35, z, 28, 36, z + 1, BI_M_STONE);
        paint(g, 2, 2, z, 3, 36, z + 1, BI_M_STONE);
        paint(g, 27, 2, z, 28, 36, z + 1, BI_M_STONE);
    }
    carve(g, 12, 4, 3, 22, 11, 4);                /* pool: air above the water */
    fill(g, 12, 4, 1, 22, 11, 3, BI_WATER, 0);
    for (int i = 0; i < 2; i++) {                 /* pillars with a base */
        int y = i ? 21 : 9;
        paint(g, 7, y - 1, 4, 11, y + 3, 5, BI_M_STONE);
        paint(g, 8, y, 5, 10, y + 2, 12, BI_M_STONE);
        paint(g, 7, y - 1, 12, 11, y + 3, 13, BI_M_STONE);
    }
    paint(g, 2, 26, 4, 8, 36, 7, BI_M_PLATFORM);  /* platform and two steps */
    paint(g, 8, 26, 4, 10, 36, 6, BI_M_PLATFORM);
    paint(g, 10, 26, 4, 12, 36, 5, BI_M_PLATFORM);
    /* a metal niche in the west wall with the animated button */
    paint(g, 0, 15, 4, 2, 21, 10, BI_M_METAL);
    carve(g, 1, 16, 5, 3, 20, 9);
    paint(g, 0, 17, 6, 1, 19, 8, BI_M_BUTTON);

    /* metal corridor east into the hall */
    paint(g, 27, 11, 3, 34, 17, 11, BI_M_METAL);
    carve(g, 27, 12, 4, 34, 16, 10);

    /* hall: tiled floor, brick walls, wooden ceiling, a metal column */
    paint(g, 34, 4, 0, 56, 24, 4, BI_M_TILE);
    carve(g, 34, 4, 4, 56, 24, 12);
    paint(g, 44, 12, 4, 46, 14, 12, BI_M_METAL);
    paint(g, 56, 14, 6, 57, 16, 8, BI_M_BUTTON);

    /* stone room to the north, floor 48 units above the hall */
    paint(g, 29, 29, 0, 59, 47, 17, BI_M_STONE);
    paint(g, 30, 30, 0, 58, 46, 7, BI_M_WOOD);
    carve(g, 30, 30, 7, 58, 46, 16);
    paint(g, 36, 40, 7, 38, 42, 16, BI_M_BRICK);  /* brick columns */
    paint(g, 50, 40, 7, 52, 42, 16, BI_M_BRICK);
    paint(g, 42, 35, 7, 46, 38, 8, BI_M_STONE);   /* a low stone dais */
    carve(g, 27, 31, 9, 30, 35, 12);              /* window into the courtyard */

    /* wooden stairs from the hall up to the stone room */
    paint(g, 44, 24, 0, 48, 30, 7, BI_M_WOOD);
    carve(g, 44, 24, 5, 48, 26, 11);
    carve(g, 44, 26, 6, 48, 28, 12);
    carve(g, 44, 28, 7, 48, 30, 13);
}

static const bi_light scene_lights[] = {
    {{80, 496, 184}, 250},   /* over the platform */
    {{72, 288, 120}, 160},   /* in front of the niche */
    {{496, 224, 144}, 200},  /* corridor */
    {{640, 176, 176}, 300},  /* hall */
    {{736, 432, 184}, 180},  /* stairs */
    {{704, 600, 232}, 320},  /* stone room */
};

/* Player start: in the courtyard, 24 units above the floor.  Its four
 * views: the corridor with the pool and the sky (the demo picture), the
 * platform and the window, the niche beside a pillar, the pool. */
static const int start_origin[3] = {230, 290, 88}, start_angle = 335;
static const int intermission_origin[3] = {56, 56, 200}, intermission_mangle[3] = {18, 40, 0};

/* The door: 64 x 96 x 8 units just behind the corridor's metal frame,
 * slid half its width along +y (its "angle" 90) into the wall, which
 * hides that half. */
static const bi_box door = {{452, 160, 64}, {460, 224, 160}, BI_T_DOOR};
static const int door_angle = 270;

static char *make_entities(void) {
    size_t cap = 8192;
    char *e = malloc(cap);
    if (!e) return NULL;
    int n = snprintf(e, cap,
                     "{\n\"classname\" \"worldspawn\"\n\"message\" \"edgewise built-in scene\"\n"
                     "\"wad\" \"\"\n}\n"
                     "{\n\"classname\" \"info_player_start\"\n\"origin\" \"%d %d %d\"\n\"angle\" \"%d\"\n}\n"
                     "{\n\"classname\" \"info_intermission\"\n\"origin\" \"%d %d %d\"\n"
                     "\"mangle\" \"%d %d %d\"\n}\n",
                     start_origin[0], start_origin[1], start_origin[2], start_angle,
                     intermission_origin[0], intermission_origin[1], intermission_origin[2],
                     intermission_mangle[0], intermission_mangle[1], intermission_mangle[2]);
    n += snprintf(e + n, cap - (size_t)n,
                  "{\n\"classname\" \"func_door\"\n\"model\" \"*1\"\n\"angle\" \"%d\"\n}\n",
                  door_angle);
    for (size_t i = 0; i < sizeof scene_lights / sizeof scene_lights[0]; i++) {
        const bi_light *l = &scene_lights[i];
        n += snprintf(e + n, cap - (size_t)n,
                      "{\n\"classname\" \"light\"\n\"origin\" \"%d %d %d\"\n\"light\" \"%d\"\n}\n",
                      (int)l->origin[0], (int)l->origin[1], (int)l->origin[2], (int)l->intensity);
    }
    return e;
}

/* The scene: grid, lights, sun, entities, door (free with free_scene). */
static int make_scene(bi_scene *sc, ew_error *err) {
    memset(sc, 0, sizeof *sc);
    sc->grid.n[0] = NX, sc->grid.n[1] = NY, sc->grid.n[2] = NZ;
    sc->grid.kind = malloc((size_t)NX * NY * NZ);
    sc->grid.mat = malloc((size_t)NX * NY * NZ);
    char *ents = make_entities();
    sc->entities = ents;
    if (!sc->grid.kind || !sc->grid.mat || !ents) return ew_fail(err, "builtin: out of memory");
    layout(&sc->grid);
    /* the outer shell must be solid: faces only exist on interior planes */
    for (int z = 0; z < NZ; z++)
        for (int y = 0; y < NY; y++)
            for (int x = 0; x < NX; x++)
                if ((x == 0 || y == 0 || z == 0 || x == NX - 1 || y == NY - 1 || z == NZ - 1) &&
                    bi_kind(&sc->grid, x, y, z) != BI_SOLID)
                    return ew_fail(err, "builtin: the scene leaks at cell %d %d %d", x, y, z);
    sc->nlights = (int)(sizeof scene_lights / sizeof scene_lights[0]);
    memcpy(sc->lights, scene_lights, sizeof scene_lights);
    /* afternoon sun from the south-west, high up */
    sc->sun_dir[0] = 0.50f, sc->sun_dir[1] = 0.33f, sc->sun_dir[2] = -0.80f;
    sc->sun_intensity = 150;
    sc->ambient = 22;
    sc->submodels[0] = door;
    sc->nsubmodels = 1;
    return 0;
}

static void free_scene(bi_scene *sc) {
    free(sc->grid.kind), free(sc->grid.mat), free((char *)sc->entities);
}

int ew_builtin_generate_ex(const ew_mapgen_options *o, uint8_t **bsp, size_t *bsp_size,
                           uint8_t palette[768], uint8_t colormap[EW_COLORMAP_SIZE], uint8_t **lit,
                           size_t *lit_size, ew_error *err) {
    *bsp = NULL, *bsp_size = 0;
    if (lit) *lit = NULL;
    if (lit_size) *lit_size = 0;
    if (o && ((o->lmshift_lumps && (o->lmshift < 0 || o->lmshift > 8)) || (o->decoupled && !(o->decoupled_units >= 0 && o->decoupled_units <= 1024))))
        return ew_fail(err, "builtin: options out of range (lmshift %d, decoupled units %g)", o->lmshift,
                       (double)o->decoupled_units);
    bi_scene sc;
    if (make_scene(&sc, err)) {
        free_scene(&sc);
        return -1;
    }
    bi_buf litbuf = {0};
    sc.opt = o;
    sc.lit_out = &litbuf;

    bi_make_palette(palette);
    bi_make_colormap(palette, colormap);
    bi_buf out = {0};
    int rc = bi_build_bsp(&sc, palette, &out, err);
    free_scene(&sc);
    if (rc) {
        free(out.data), free(litbuf.data);
        return -1;
    }
    *bsp = out.data, *bsp_size = out.len;
    if (lit && lit_size && litbuf.len) {
        *lit = litbuf.data, *lit_size = litbuf.len;
    } else {
        free(litbuf.data);
    }
    return 0;
}

int ew_builtin_generate(uint8_t **bsp, size_t *bsp_size, uint8_t palette[768],
                        uint8_t colormap[EW_COLORMAP_SIZE], ew_error *err) {
    return ew_builtin_generate_ex(NULL, bsp, bsp_size, palette, colormap, NULL, NULL, err);
}

int ew_builtin_light_at(const ew_mapgen_options *o, const float p[3], const float n[3], uint8_t rgb[3]) {
    bi_scene sc;
    ew_error err;
    uint8_t scratch[3];
    int v = -1;
    if (make_scene(&sc, &err) == 0) {
        sc.opt = o;
        v = bi_light_point_rgb(&sc, p, n, rgb ? rgb : scratch);
    }
    free_scene(&sc);
    return v;
}
