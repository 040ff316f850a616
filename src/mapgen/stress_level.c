/*
 * The stress level: the built-in world's generator at growing detail, for
 * measuring how each hidden-surface method's cost grows with the number of
 * polygons in view (`edgewise hsr --stress`).
 *
 * One hall, 204 x 204 cells (3264 units) and 24 cells high, brick walls on
 * a brick floor, with sixteen brick pillars of four heights that hide parts
 * of the floor (so methods that overdraw have something to overdraw).  The
 * detail is laid on the floor and on the two walls the view faces as patches of 8 x 8
 * cells in a checkerboard of two materials: every cell of a patch is then
 * a face of its own (neighbours differ in texture, so nothing merges), and
 * each patch cuts the brick faces around it.  Patches are taken in a fixed
 * shuffled order, so more detail only adds patches, spread evenly over the
 * hall.  The view set is one intermission camera high in a corner, looking
 * down the diagonal over the whole hall.
 */
#include "mapgen_internal.h"
#include "ew_util.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum {
    SX = 208, SY = 208, SZ = 28,   /* the grid */
    LO = 2, HI = 206,              /* the hall's cells along x and y: [LO, HI) */
    ZLO = 2, ZHI = 26,             /* ... and along z */
    PATCH = 8,
    NPX = (HI - LO) / PATCH,       /* 25 patches a row (the last 4 cells stay brick) */
    NPZ = (ZHI - ZLO) / PATCH,     /* 3 patches up a wall */
    NFLOOR = NPX * NPX, NWALL = NPX * NPZ, NPATCHES = NFLOOR + 2 * NWALL,
};

/* Detailed cells past this would need more vertices or edges than BSP29
 * holds (65535): the checkerboard shares both with its neighbours, two
 * edges and one vertex a cell. */
#define MAX_DETAIL EW_STRESS_MAX_DETAIL

static void cell_set(bi_grid *g, int x, int y, int z, int kind, int mat) {
    size_t i = ((size_t)z * g->n[1] + y) * g->n[0] + x;
    g->kind[i] = (uint8_t)kind;
    g->mat[i] = (uint8_t)mat;
}

/* The solid cells under patch p: floor patches lie in layer z = ZLO - 1,
 * wall patches in the far walls x = HI and y = HI (the ones the camera in
 * the near corner faces). */
static void patch_cells(bi_grid *g, int p) {
    for (int j = 0; j < PATCH; j++)
        for (int i = 0; i < PATCH; i++) {
            int x, y, z;
            if (p < NFLOOR) {
                x = LO + (p % NPX) * PATCH + i, y = LO + (p / NPX) * PATCH + j, z = ZLO - 1;
            } else {
                int q = (p - NFLOOR) % NWALL, along = LO + (q % NPX) * PATCH + i;
                z = ZLO + (q / NPX) * PATCH + j;
                if (p - NFLOOR < NWALL) x = HI, y = along;
                else x = along, y = HI;
            }
            cell_set(g, x, y, z, BI_SOLID, (x + y + z) & 1 ? BI_M_STONE : BI_M_METAL);
        }
}

/* A fixed shuffle of the patches (a xorshift generator, the same on every
 * machine), so detail N is always a prefix of detail N + 1's patches. */
static void patch_order(int order[NPATCHES]) {
    for (int i = 0; i < NPATCHES; i++) order[i] = i;
    uint32_t s = 0x2545F491u;
    for (int i = NPATCHES - 1; i > 0; i--) {
        s ^= s << 13, s ^= s >> 17, s ^= s << 5;
        int j = (int)(s % (uint32_t)(i + 1)), t = order[i];
        order[i] = order[j], order[j] = t;
    }
}

static const bi_light stress_lights[] = {
    {{800, 800, 300}, 900},   {{2400, 800, 300}, 900},  {{800, 2400, 300}, 900},
    {{2400, 2400, 300}, 900}, {{1632, 1632, 360}, 700}, {{3100, 1632, 200}, 600},
    {{1632, 3100, 200}, 600},
};

/* Eye high in the corner (x, y small), looking down the diagonal. */
static const int stress_eye[3] = {72, 72, 360}, stress_mangle[3] = {24, 45, 0};

int ew_stress_generate(int detail, uint8_t **bsp, size_t *bsp_size, uint8_t palette[768],
                       uint8_t colormap[EW_COLORMAP_SIZE], ew_error *err) {
    *bsp = NULL, *bsp_size = 0;
    if (detail < 0 || detail > EW_STRESS_MAX_DETAIL)
        return ew_fail(err, "builtin: detail %d out of range (0 to %d)", detail, EW_STRESS_MAX_DETAIL);
    bi_scene sc;
    memset(&sc, 0, sizeof sc);
    bi_grid *g = &sc.grid;
    g->n[0] = SX, g->n[1] = SY, g->n[2] = SZ;
    g->kind = malloc((size_t)SX * SY * SZ);
    g->mat = malloc((size_t)SX * SY * SZ);
    char *ents = malloc(512);
    int rc = -1;
    if (!g->kind || !g->mat || !ents) {
        ew_fail(err, "builtin: out of memory");
        goto done;
    }
    memset(g->kind, BI_SOLID, (size_t)SX * SY * SZ);
    memset(g->mat, BI_M_BRICK, (size_t)SX * SY * SZ);
    for (int z = ZLO; z < ZHI; z++)
        for (int y = LO; y < HI; y++)
            for (int x = LO; x < HI; x++) cell_set(g, x, y, z, BI_EMPTY, 0);
    /* pillars on a 4 x 4 grid, 3 x 3 cells, 4 to 16 cells tall */
    for (int k = 0; k < 16; k++) {
        int px = LO + 24 + (k % 4) * 48, py = LO + 24 + (k / 4) * 48, h = 4 + 4 * ((k * 7) % 4);
        for (int z = ZLO; z < ZLO + h; z++)
            for (int y = py; y < py + 3; y++)
                for (int x = px; x < px + 3; x++) cell_set(g, x, y, z, BI_SOLID, BI_M_BRICK);
    }
    /* detail: whole patches of PATCH x PATCH cells until detail cells are laid
     * (the calibration: about one visible polygon per detail cell) */
    int order[NPATCHES];
    patch_order(order);
    for (int i = 0, laid = 0; i < NPATCHES && laid < detail && laid < MAX_DETAIL; i++, laid += PATCH * PATCH)
        patch_cells(g, order[i]);

    snprintf(ents, 512,
             "{\n\"classname\" \"worldspawn\"\n\"message\" \"edgewise stress hall, detail %d\"\n"
             "\"wad\" \"\"\n}\n"
             "{\n\"classname\" \"info_intermission\"\n\"origin\" \"%d %d %d\"\n"
             "\"mangle\" \"%d %d %d\"\n}\n",
             detail, stress_eye[0], stress_eye[1], stress_eye[2], stress_mangle[0], stress_mangle[1],
             stress_mangle[2]);
    sc.entities = ents;
    sc.nlights = (int)(sizeof stress_lights / sizeof stress_lights[0]);
    memcpy(sc.lights, stress_lights, sizeof stress_lights);
    sc.ambient = 48;  /* no sky: the sun never reaches in */

    bi_make_palette(palette);
    bi_make_colormap(palette, colormap);
    bi_buf out = {0};
    if (bi_build_bsp(&sc, palette, &out, err)) {
        free(out.data);
        goto done;
    }
    *bsp = out.data, *bsp_size = out.len;
    rc = 0;
done:
    free(g->kind), free(g->mat), free(ents);
    return rc;
}
