/*
 * edgewise.h - software Quake world renderer (the Black Book architecture).
 *
 * One header, documented where each thing is declared.  The flow is:
 *
 *   ew_fs      *fs    = ew_fs_open("id1", &err);               game directory + paks
 *   ew_assets   a;    ew_assets_load(fs, "e1m1", &a, &err);    map + palette + colormap
 *   ew_renderer *r    = ew_renderer_create(a.world, a.palette, a.colormap, 640, 480, &err);
 *   ew_camera   cam   = {{x,y,z}, {pitch,yaw,roll}, 90, 0};
 *   ew_render(r, &cam, &stats);                                 8-bit frame + z-buffer
 *   ew_write_png("out.png", ew_frame_pixels(r), 640, 480, a.palette, &err);
 *
 * Every function that can fail takes an ew_error * and fills it with one
 * line naming the file and the problem; it then returns NULL or -1.
 * Nothing here keeps global state: a world is read-only once loaded and can
 * be shared; a renderer owns all per-frame state.
 */
#ifndef EDGEWISE_H
#define EDGEWISE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ---- errors ------------------------------------------------------------ */

/* One human-readable line, e.g. "maps/x.bsp: lump 'faces': face 12 uses
 * texinfo 900 (only 310)".  msg is always NUL-terminated. */
typedef struct ew_error {
    char msg[512];
} ew_error;

/* ---- raw files and game directories ------------------------------------ */

/* Reads a whole file into a malloc'd buffer (caller frees). */
int ew_read_file(const char *path, uint8_t **data, size_t *size, ew_error *err);

/* A Quake game directory: loose files win over paks, later paks
 * (pak1.pak over pak0.pak) win over earlier ones, as Quake searches. */
typedef struct ew_fs ew_fs;

ew_fs *ew_fs_open(const char *dir, ew_error *err);
void   ew_fs_close(ew_fs *fs);
/* Loads "maps/e1m1.bsp" (a path relative to the game directory).
 * Returns 0, or -1 with err set (not found, truncated pak entry, I/O). */
int    ew_fs_load(const ew_fs *fs, const char *name, uint8_t **data, size_t *size,
                  ew_error *err);

/* PAK archive directory, validated against the archive's size.
 * Entries point into the caller's buffer. */
typedef struct ew_pak_entry {
    char     name[57];
    uint32_t offset, size;
} ew_pak_entry;
int ew_pak_parse(const uint8_t *data, size_t size, const char *filename,
                 ew_pak_entry **entries, int *count, ew_error *err);

/* palette.lmp: 256 RGB triples (768 bytes). colormap.lmp: 64 light rows of
 * 256 colours (row 0 brightest, row 63 black); extra trailing bytes ok. */
#define EW_COLORMAP_SIZE (64 * 256)
int ew_palette_parse(const uint8_t *data, size_t size, const char *filename,
                     uint8_t palette[768], ew_error *err);
int ew_colormap_parse(const uint8_t *data, size_t size, const char *filename,
                      uint8_t colormap[EW_COLORMAP_SIZE], ew_error *err);

/* ---- worlds ------------------------------------------------------------ */

/* A loaded BSP (version 29, BSP2 or 2PSB), validated and read-only. */
typedef struct ew_world ew_world;

ew_world *ew_world_load(const uint8_t *data, size_t size, const char *filename,
                        ew_error *err);
void      ew_world_free(ew_world *w);

/* What `edgewise info` prints. */
typedef struct ew_lump_info {
    const char *name;   /* "entities", "planes", ... */
    uint32_t    offset, length;
    int         count;  /* records in the lump (bytes for byte lumps) */
} ew_lump_info;
typedef struct ew_world_info {
    char         version[8];  /* "29", "BSP2" or "2PSB" */
    ew_lump_info lumps[15];
    int          models, textures, textures_missing, faces, leaves, nodes;
} ew_world_info;
void        ew_world_get_info(const ew_world *w, ew_world_info *info);
const char *ew_world_entities(const ew_world *w);

/* ---- the view set (../shared/BENCHMARK.md) ------------------------------ */

#define EW_MAX_VIEWS 32
typedef struct ew_camera {
    float  origin[3];  /* eye, Quake units */
    float  angles[3];  /* pitch, yaw, roll in degrees; x forward, y left, z up */
    float  fov;        /* horizontal field of view in degrees (90 if 0) */
    double time;       /* seconds: animated textures, sky scroll, liquids */
} ew_camera;

/* The benchmark's view set (../shared/BENCHMARK.md): fills up to
 * EW_MAX_VIEWS cameras from the entity lump (four per player start, one per
 * intermission); returns the count (0 if the map has neither). */
int ew_benchmark_views(const ew_world *w, ew_camera views[EW_MAX_VIEWS]);

/* ---- everything needed to render one map -------------------------------- */

typedef struct ew_assets {
    ew_world *world;
    uint8_t   palette[768];
    uint8_t   colormap[EW_COLORMAP_SIZE];
} ew_assets;

/* MAP is a path to a .bsp (palette/colormap from ../gfx/ beside it, or from
 * data_dir if given) or a map name looked up in the game directory data_dir
 * as maps/NAME.bsp.  Returns 0 or -1. */
int  ew_assets_load(const char *map, const char *data_dir, ew_assets *out,
                    ew_error *err);
/* The built-in scene: a world the project generates itself (geometry,
 * procedural textures, palette, colormap, light maps, PVS), written as a
 * BSP29 image and loaded through ew_world_load like any map. */
int  ew_assets_builtin(ew_assets *out, ew_error *err);
void ew_assets_free(ew_assets *a);

/* ---- the renderer ------------------------------------------------------- */

typedef struct ew_renderer ew_renderer;

/* Frame sizes from 320x200 up to 7680x4320. The world, palette and colormap
 * must outlive the renderer. */
ew_renderer *ew_renderer_create(const ew_world *w, const uint8_t palette[768],
                                const uint8_t colormap[EW_COLORMAP_SIZE],
                                int width, int height, ew_error *err);
void         ew_renderer_free(ew_renderer *r);

/* Per-frame counters (`edgewise render --stats`). */
typedef struct ew_stats {
    long   pixels;          /* width * height */
    long   pixels_written;  /* world pixels written by spans */
    long   pixels_covered;  /* distinct pixels written */
    double overdraw;        /* pixels_written / pixels_covered */
    int    edges;           /* edges in the global edge list */
    int    edges_cached;    /* edges reused from a neighbouring polygon */
    int    surfaces;        /* surfaces (polygons) in the edge list */
    int    spans;
    int    surfaces_built;  /* surface-cache misses this frame */
    int    surfaces_cached; /* surface-cache hits this frame */
    int    visible_leaves;  /* leaves in the PVS and the frustum */
    int    dropped;         /* edges/surfaces/spans refused by a budget */
    /* moving things (entities) */
    int    entities_drawn, entities_culled, entities_unknown, models_missing;
    int    alias_tris;          /* alias triangles drawn (front-facing, in view) */
    int    alias_tris_subdiv;   /* ... of which by the subdivision rasterizer */
    long   alias_pixels;        /* alias/sprite pixels that passed the z test */
    int    particles;           /* particles drawn */
    int    surfaces_rebuilt_by_dlights;
    double ms_front, ms_scan, ms_draw, ms_models, ms_total;
} ew_stats;

/* Renders one frame of the world into the renderer's 8-bit frame buffer and
 * 1/z buffer.  stats may be NULL.  Returns 0 or -1 (bad camera). */
int ew_render(ew_renderer *r, const ew_camera *cam, ew_stats *stats);

int            ew_frame_width(const ew_renderer *r);
int            ew_frame_height(const ew_renderer *r);
const uint8_t *ew_frame_pixels(const ew_renderer *r);   /* width*height, row-major */
/* The frame's 1/z per pixel (larger is nearer; 0 where nothing was drawn):
 * the world's, and the moving things' where they won.  Moving things are
 * the only readers during a frame, so ew_render z-fills the world only
 * under them (deferred z-fill) and this call fills in the rest, once per
 * frame, the first time it is asked for. */
const float   *ew_frame_zbuffer(ew_renderer *r);
/* Z-fill under every world span as it is drawn (1), as the original
 * renderer did, or only where moving things need it (0, the default).
 * The frame and ew_frame_zbuffer are the same either way; 1 is slower
 * and exists to measure what deferring saves. */
void           ew_set_full_zfill(ew_renderer *r, int on);

/* Threads that render bands of each frame (0 = one per core, at most 16).
 * Returns the count in use, or -1 when out of memory. */
int ew_set_threads(ew_renderer *r, int n);
int ew_get_threads(const ew_renderer *r);

/* Light style values (256 = normal, twice that = double bright). Default:
 * 256 for every style, which is what the reference renders show. */
void ew_set_lightstyle(ew_renderer *r, int style, int value);

/* Perspective-correct divide every `pixels` pixels along a span (1, 2, 4,
 * 8, 16 or 32; default 16, as the original), affine in between.  1 makes
 * texturing exact, for measuring what the approximation changes.
 * Returns 0, or -1 for another value. */
int ew_set_subdivision(ew_renderer *r, int pixels);

/* How alias (triangle) models are rasterized: affine triangles with
 * Gouraud shading, Carmack's recursive subdivision (for small models), or
 * automatic choice by the model's projected size (subdivision when its
 * screen height is below threshold_px).  Default: auto, 40 pixels. */
typedef enum ew_alias_raster { EW_ALIAS_AUTO, EW_ALIAS_AFFINE, EW_ALIAS_SUBDIV } ew_alias_raster;
void ew_set_alias_raster(ew_renderer *r, ew_alias_raster mode, float threshold_px);

/* Test/verification hook: when enabled, the next frames also record the
 * face index that won each pixel (-1 where nothing was drawn). */
void       ew_enable_face_ids(ew_renderer *r, int on);
const int *ew_frame_face_ids(const ew_renderer *r);

/* The reference path, independent of the edge list: every visible face of
 * the same frame rasterized with a per-pixel z-buffer from its plane
 * equation, textured and lit from the same surfaces.  Writes width*height
 * palette indices and (if face_ids != NULL) the winning face per pixel. */
int ew_render_reference(ew_renderer *r, const ew_camera *cam, uint8_t *pixels,
                        int *face_ids, ew_error *err);

/* ---- moving things ------------------------------------------------------ */

/* A scene: entities drawn over a world.  Brush models (doors, lifts,
 * buttons: the world's submodels *1, *2, ...) go into the world's edge list
 * and sort against it; alias models, sprites and particles are z-buffered
 * over the z-filled world. */
typedef struct ew_scene ew_scene;

ew_scene *ew_scene_create(const ew_world *w, ew_error *err);
/* Every entity of the map: brush models by "model" "*N", and known
 * classnames' models found in the game directory (data_dir, else the folder
 * above the map's own folder).  Unknown classnames and missing model files
 * are counted (ew_scene_counts), not errors. */
ew_scene *ew_scene_from_map(const ew_world *w, const char *map, const char *data_dir,
                            ew_error *err);
/* The built-in scene's own moving things (made in memory like its world):
 * its door, a triangle model, particles and a dynamic light. */
ew_scene *ew_scene_builtin(const ew_world *w, ew_error *err);
void ew_scene_free(ew_scene *s);
/* Adds world submodel N (1..) at an offset and rotation; entity index or -1. */
int  ew_scene_add_brush(ew_scene *s, int submodel, const float origin[3], const float angles[3]);
/* Loads an alias model (MDL), sprite (SPR) or item box (BSP) from memory
 * for entities to use; returns its model index (the same index again for
 * the same name), or -1 with err set. */
int  ew_scene_load_model(ew_scene *s, const char *name, const uint8_t *data, size_t size,
                         ew_error *err);
/* An entity using model (an index from ew_scene_load_model) at origin with
 * Quake angles (pitch yaw roll), frame and skin; entity index or -1. */
int  ew_scene_add_entity(ew_scene *s, int model, const float origin[3], const float angles[3],
                         int frame, int skin);
/* n particles in a deterministic cloud (same seed, same cloud). */
int  ew_scene_add_particles(ew_scene *s, int n, const float center[3], float radius, uint32_t seed);
/* A dynamic light: adds light within radius to the surfaces it reaches. */
int  ew_scene_add_dlight(ew_scene *s, const float origin[3], float radius);
void ew_scene_counts(const ew_scene *s, int *entities, int *unknown, int *missing);
/* The scene ew_render draws with the world (NULL: world only).  It must
 * outlive its use by the renderer. */
void ew_set_scene(ew_renderer *r, const ew_scene *s);

/* ---- output --------------------------------------------------------------*/

/* Expands 8-bit pixels through the palette and writes an RGB PNG. */
int ew_write_png(const char *path, const uint8_t *pixels, int width, int height,
                 const uint8_t palette[768], ew_error *err);
/* Reads an RGB/RGBA/gray PNG to malloc'd RGB8 (used by the fidelity tests). */
int ew_read_png_rgb(const char *path, uint8_t **rgb, int *width, int *height,
                    ew_error *err);

#ifdef __cplusplus
}
#endif
#endif
