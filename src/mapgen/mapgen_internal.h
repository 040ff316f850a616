/*
 * Shared between the map generator's own files (the .c files of src/mapgen);
 * the generator's interface is mapgen.h.
 */
#ifndef EW_MAPGEN_INTERNAL_H
#define EW_MAPGEN_INTERNAL_H

#include "mapgen.h"

#define BI_CELL 16  /* cell edge in world units */

/* Cell kinds; they map to leaf contents EMPTY, SOLID, WATER, SKY. */
enum { BI_EMPTY, BI_SOLID, BI_WATER, BI_SKY, BI_NUM_KINDS };

/* Materials of solid cells: each gives a texture for the floor on top of
 * the cell, for its sides and for the ceiling under it. */
enum { BI_M_BRICK, BI_M_STONE, BI_M_METAL, BI_M_WOOD, BI_M_PLATFORM,
       BI_M_BUTTON, BI_M_TILE, BI_NUM_MATERIALS };

typedef struct bi_grid {
    int      n[3];     /* cells along x, y, z */
    uint8_t *kind;     /* BI_EMPTY.. per cell, x fastest */
    uint8_t *mat;      /* BI_M_* per cell (used for solid cells) */
} bi_grid;

/* Kind of a cell; everything outside the grid is solid. */
static inline int bi_kind(const bi_grid *g, int x, int y, int z) {
    if (x < 0 || y < 0 || z < 0 || x >= g->n[0] || y >= g->n[1] || z >= g->n[2])
        return BI_SOLID;
    return g->kind[((size_t)z * g->n[1] + y) * g->n[0] + x];
}
static inline int bi_mat(const bi_grid *g, int x, int y, int z) {
    return g->mat[((size_t)z * g->n[1] + y) * g->n[0] + x];
}

typedef struct bi_light {
    float origin[3];
    float intensity;   /* Quake "light" value: reach in units */
} bi_light;

#define BI_MAX_LIGHTS 8

/* A brush model (a door): an axis-aligned box in world units with one
 * texture, written as submodel *1, *2, ... with a small BSP of its own. */
typedef struct bi_box {
    int mins[3], maxs[3];
    int tex;
} bi_box;

#define BI_MAX_SUBMODELS 4
typedef struct bi_scene {
    bi_grid  grid;
    bi_light lights[BI_MAX_LIGHTS];
    int      nlights;
    float    sun_dir[3];     /* unit vector the sunlight travels along */
    float    sun_intensity;  /* added where a face sees the sky along -sun_dir */
    float    ambient;
    const char *entities;    /* NUL-terminated entity lump text */
    bi_box   submodels[BI_MAX_SUBMODELS];  /* submodel *i+1 */
    int      nsubmodels;
    const ew_mapgen_options *opt;  /* NULL: the plain map */
    struct bi_buf *lit_out;        /* .lit image when opt->lit */
} bi_scene;

/* Texture of the face visible from a cell of kind self_kind against the
 * cell (kind, mat) on the other side; facing is 0..5 = +x -x +y -y +z -z,
 * the direction the face looks (from the other cell into self). */
int bi_face_texture(int self_kind, int other_kind, int other_mat, int facing);

/* Growable byte buffer; after an allocation failure it stays failed. */
typedef struct bi_buf bi_buf;
struct bi_buf {
    uint8_t *data;
    size_t   len, cap;
    int      failed;
};
void bi_put(bi_buf *b, const void *p, size_t n);
void bi_put_zeros(bi_buf *b, size_t n);
void bi_put_i32(bi_buf *b, int32_t v);
void bi_put_i16(bi_buf *b, int16_t v);
void bi_put_u16(bi_buf *b, uint16_t v);
void bi_put_f32(bi_buf *b, float v);
void bi_put_u8(bi_buf *b, uint8_t v);

/* textures.c: palette, colormap and the textures lump. */
void bi_make_palette(uint8_t palette[768]);
void bi_make_colormap(const uint8_t palette[768], uint8_t colormap[EW_COLORMAP_SIZE]);
int  bi_write_textures(const uint8_t palette[768], bi_buf *lump);
int  bi_texture_is_special(int tex);  /* sky and liquids: no light map */
void bi_texture_size(int tex, int *w, int *h);
/* Deterministic noise for procedural images: value noise summed over
 * octaves on a lattice of period cells, tiling (u, v) in [0,1). */
double bi_fbm(double u, double v, int period, int octaves, uint32_t seed);

/* light_bake.c: light and visibility.
 * Line of sight through the grid: walks the cells the segment a->b passes
 * through and returns the kind of the first cell that blocks (solid or
 * sky; leaving the grid counts as solid), or -1 if the segment is clear. */
int bi_trace(const bi_grid *g, const float a[3], const float b[3]);

/* Light value (0..255) at world point p on a surface facing along normal n. */
int bi_light_point(const bi_scene *s, const float p[3], const float n[3]);
/* The same with colour (s->opt's tints; white without): returns the mono
 * value, fills rgb. */
int bi_light_point_rgb(const bi_scene *s, const float p[3], const float n[3], uint8_t rgb[3]);

/* Fills vis[a * nleaves + b] = 1 if leaf box a may see leaf box b (a
 * conservative portal flow; symmetric).  Boxes are in world units;
 * open[a] = 0 marks leaves that block sight and take no part. */
int bi_compute_pvs(int nleaves, const int (*lo)[3], const int (*hi)[3], const uint8_t *open,
                   uint8_t *vis);

/* clip_hull.c: a clip hull of the grid for a box of extents mins..maxs
 * (the player's: -16,-16,-24 .. 16,16,32): nodes on the axial plane
 * coordinate[axis] = dist, children node indices into *nodes (>= 0) or
 * EW_CONTENTS_EMPTY / EW_CONTENTS_SOLID; node 0 is the head.  0, or -1
 * when out of memory. */
typedef struct bi_clipnode {
    int axis, dist, child[2];
} bi_clipnode;
int bi_build_clip_hull(const bi_grid *g, const int mins[3], const int maxs[3], bi_clipnode **nodes, int *count);

/* bsp_writer.c: builds the BSP image of a scene into out. */
int bi_build_bsp(const bi_scene *s, const uint8_t palette[768], bi_buf *out, ew_error *err);

#endif
