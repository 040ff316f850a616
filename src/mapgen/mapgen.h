/*
 * The map generator (src/mapgen/): a small map compiler.  A level described
 * as a grid of 16-unit cells is turned into a complete BSP29 image (exact
 * axial BSP, merged faces without T-junctions, procedural textures, light
 * maps, PVS) plus a palette and colormap; it also writes the triangle model
 * (MDL) that the built-in scene places over that world.  This header is
 * what the library (ew_assets_create_builtin, ew_scene_create_builtin) and the tests use;
 * mapgen_internal.h is shared between the generator's own files only.
 */
#ifndef EW_MAPGEN_H
#define EW_MAPGEN_H

#include "edgewise.h"
#include <stddef.h>
#include <stdint.h>

/* Generates the built-in level (builtin_level.c): a malloc'd BSP29 image
 * (caller frees), the palette and the colormap.  Deterministic: every call
 * gives the same bytes. */
int ew_builtin_generate(uint8_t **bsp, size_t *bsp_size, uint8_t palette[768],
                        uint8_t colormap[EW_COLORMAP_SIZE], ew_error *err);

/* What ew_builtin_generate_ex writes besides the plain map (for the
 * loaders' tests and fuzz seeds).  All zero (or a NULL pointer) is the
 * plain map, byte for byte what ew_builtin_generate writes. */
#define EW_MAPGEN_MAX_LIGHTS 8
typedef struct ew_mapgen_options {
    int lit;             /* 1: a .lit image too (*lit, *lit_size) */
    int rgblighting;     /* 1: a BSPX RGBLIGHTING lump */
    int lmshift_lumps;   /* 1: BSPX LMSHIFT, LMOFFSET and LMSTYLE, every face's light map
                          * baked one sample every 1 << lmshift texels */
    int lmshift;         /* 0..8 */
    int decoupled;       /* 1: BSPX DECOUPLED_LM: each face's light map on the two world
                          * axes of its plane, decoupled_units world units a sample
                          * (sample i at coordinate (floor(lo / units) + i) * units) */
    float decoupled_units;  /* 0: 12 */
    /* Colour of each of the scene's lights (r, g, b multipliers, 3 floats
     * a light, EW_MAPGEN_MAX_LIGHTS lights); NULL: white, so the coloured
     * light's three channels equal the monochrome light exactly.  Ambient
     * and sun light stay white. */
    const float *light_tint;
} ew_mapgen_options;

/* ew_builtin_generate with options (NULL: the plain map); lit and lit_size
 * receive the malloc'd .lit image when o->lit (else NULL, 0; both may be
 * NULL when not wanted).  The light maps of every layout are baked at the
 * sample points of that layout.  BSPX lumps follow the standard lumps,
 * 4-byte aligned; with LMSHIFT and DECOUPLED_LM the faces' own light
 * offsets point at the moved light maps. */
int ew_builtin_generate_ex(const ew_mapgen_options *o, uint8_t **bsp, size_t *bsp_size,
                           uint8_t palette[768], uint8_t colormap[EW_COLORMAP_SIZE], uint8_t **lit,
                           size_t *lit_size, ew_error *err);
/* The baker's light (0..255, and its colour with the tints of o, NULL:
 * white) at world point p of the built-in level on a surface facing along
 * n: what a light-map sample there holds. */
int ew_builtin_light_at(const ew_mapgen_options *o, const float p[3], const float n[3], uint8_t rgb[3]);

/* The stress level (stress_level.c): a hall whose floor and far walls
 * carry detail cells of 16 units laid as checkerboards, each cell a face of
 * its own, for timing hidden-surface methods against the polygons in view
 * (about one visible polygon per detail cell from its one view, an
 * intermission camera).  detail 0..EW_STRESS_MAX_DETAIL; a malloc'd BSP29
 * image as ew_builtin_generate's.  Deterministic; more detail only adds
 * cells. */
#define EW_STRESS_MAX_DETAIL 26000
int ew_stress_generate(int detail, uint8_t **bsp, size_t *bsp_size, uint8_t palette[768],
                       uint8_t colormap[EW_COLORMAP_SIZE], ew_error *err);

/* Textures, in the order of the textures lump. */
enum { BI_T_BRICK, BI_T_METAL, BI_T_FLOOR, BI_T_STONE, BI_T_WOOD, BI_T_WATER,
       BI_T_SKY, BI_T_BUTTON0, BI_T_BUTTON1, BI_T_DOOR, BI_NUM_TEXTURES };

/* Colour ramps of the palette: index ramp * 16 + shade (0 dark .. 15
 * bright); 224..255 are fullbrights (BI_FB_*) that light leaves alone. */
enum { BI_R_GREY, BI_R_BROWN, BI_R_TAN, BI_R_RED, BI_R_RUST, BI_R_OLIVE, BI_R_GREEN,
       BI_R_TEAL, BI_R_BLUE, BI_R_STEEL, BI_R_PURPLE, BI_R_GOLD, BI_R_FLESH, BI_R_STONE };
enum { BI_FB_YELLOW = 224, BI_FB_RED = 232, BI_FB_GREEN = 240, BI_FB_BLUE = 248, BI_FB_WHITE = 254 };

/* Palette index of a ramp and a shade (clamped to 0..15). */
uint8_t bi_px(int ramp, double shade);

/* The built-in scene's triangle model (mdl_writer.c), a hooded lantern bearer
 * floating over the floor, as an MDL version 6 image (malloc'd, caller
 * frees; deterministic).  One 128x64 skin, one frame: a group of
 * BI_MODEL_POSES poses, BI_MODEL_INTERVAL seconds each, so it animates by
 * time.  Model space: x forward, y left, z up, the origin under its feet;
 * the lantern it holds is at bi_model_lantern (pose 0, before bobbing). */
#define BI_MODEL_POSES 8
#define BI_MODEL_INTERVAL 0.15f
#define BI_MODEL_SKIN_W 128
#define BI_MODEL_SKIN_H 64
extern const float bi_model_lantern[3];
int bi_model_generate(uint8_t **mdl, size_t *size, ew_error *err);

#endif
