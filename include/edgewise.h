/*
 * edgewise.h - software Quake world renderer (the Black Book architecture).
 *
 * One header, documented where each thing is declared.  The flow is:
 *
 *   ew_error     err;
 *   ew_fs       *fs = ew_fs_create("id1", &err);            game directory + paks
 *   ew_assets   *a  = ew_assets_create("e1m1", "id1", &err); map + palette + colormap
 *   ew_renderer *r  = ew_renderer_create(&(ew_renderer_desc){
 *                         .world = a->world, .palette = a->palette,
 *                         .colormap = a->colormap,           every other field: 0 = default
 *                         .width = 640, .height = 480}, &err);
 *   ew_camera    cam = {{x,y,z}, {pitch,yaw,roll}, 90, 0};
 *   ew_render(r, &cam, &stats);                               8-bit frame + z-buffer
 *   ew_write_png("out.png", ew_frame_pixels(r), 640, 480, a->palette, &err);
 *   ew_renderer_destroy(r);  ew_assets_destroy(a);  ew_fs_destroy(fs);
 *
 * Everything the caller gets a pointer to comes from an ew_*_create and goes
 * back through the matching ew_*_destroy (which accepts NULL).
 * Every function that can fail takes an ew_error * and fills it with one
 * line naming the file and the problem; it then returns NULL or -1.
 * Nothing here keeps global state: a world is read-only once loaded and can
 * be shared; a renderer owns all per-frame state.
 *
 * Test and measurement calls (face ids, the reference renderer, full z-fill,
 * PNG reading, PAK parsing) are in edgewise_lab.h.
 */
#ifndef EDGEWISE_H
#define EDGEWISE_H

#include <stddef.h>
#include <stdint.h>

/* The version; CMakeLists.txt's project(edgewise VERSION ...) must agree
 * (test_api checks). */
#define EW_VERSION_MAJOR 0
#define EW_VERSION_MINOR 4
#define EW_VERSION_PATCH 0
#define EW_VERSION "0.4.0"

/* Every public function is declared EW_API: extern, and with
 * EW_SHARED_LIBRARY or EW_BUILD defined also exported from a shared
 * library (default visibility).  Define EW_API yourself to override. */
#ifndef EW_API
#if (defined(EW_SHARED_LIBRARY) || defined(EW_BUILD)) && defined(__GNUC__)
#define EW_API extern __attribute__((visibility("default")))
#else
#define EW_API extern
#endif
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* "0.4.0": EW_VERSION of the library that was linked. */
EW_API const char *ew_version(void);

/* ---- errors ------------------------------------------------------------ */

/* One human-readable line, e.g. "maps/x.bsp: lump 'faces': face 12 uses
 * texinfo 900 (only 310)".  msg is always NUL-terminated. */
typedef struct ew_error {
    char msg[512];
} ew_error;

/* ---- raw files and game directories ------------------------------------ */

/* Reads a whole file into a malloc'd buffer (caller frees). */
EW_API int ew_read_file(const char *path, uint8_t **data, size_t *size, ew_error *err);

/* A Quake game directory: loose files win over paks, later paks
 * (pak1.pak over pak0.pak) win over earlier ones, as Quake searches.
 * dir may also be a search list "GAME:BASE" (any number of directories
 * joined by ':', used when dir is not itself a directory): each is a game
 * directory of its own, searched in that order, as Quake's -game over id1
 * (`edgewise --game DIR --data DIR`).  Every data_dir below takes the
 * same lists. */
typedef struct ew_fs ew_fs;

EW_API ew_fs *ew_fs_create(const char *dir, ew_error *err);
EW_API void   ew_fs_destroy(ew_fs *fs);
/* Loads "maps/e1m1.bsp" (a path relative to the game directory).
 * Returns 0, or -1 with err set (not found, truncated pak entry, I/O). */
EW_API int    ew_fs_load(const ew_fs *fs, const char *name, uint8_t **data, size_t *size,
                         ew_error *err);

/* palette.lmp: 256 RGB triples (768 bytes). colormap.lmp: 64 light rows of
 * 256 colours (row 0 brightest, row 63 black); extra trailing bytes ok. */
#define EW_COLORMAP_SIZE (64 * 256)
EW_API int ew_palette_parse(const uint8_t *data, size_t size, const char *filename,
                            uint8_t palette[768], ew_error *err);
EW_API int ew_colormap_parse(const uint8_t *data, size_t size, const char *filename,
                             uint8_t colormap[EW_COLORMAP_SIZE], ew_error *err);

/* ---- worlds ------------------------------------------------------------ */

/* A loaded BSP (version 29, BSP2 or 2PSB), validated and read-only. */
typedef struct ew_world ew_world;

EW_API ew_world *ew_world_create(const uint8_t *data, size_t size, const char *filename,
                               ew_error *err);
EW_API void      ew_world_destroy(ew_world *w);

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
EW_API void        ew_world_get_info(const ew_world *w, ew_world_info *info);
/* The BSPX lumps after the standard ones (`edgewise info`), in the file's
 * order, any name (a lump edgewise does not know is listed, never an
 * error).  Fills info for lump i (from 0) and returns 0; -1 past the last
 * (a map without BSPX, or whose BSPX directory was malformed: a warning,
 * has none). */
typedef enum ew_bspx_use {
    EW_BSPX_UNUSED = 0,  /* not read by edgewise (LIGHTINGDIR, BRUSHLIST, unknown names...) */
    EW_BSPX_USED,        /* read and used: RGBLIGHTING, LMSHIFT, LMOFFSET, LMSTYLE, DECOUPLED_LM */
    EW_BSPX_IGNORED,     /* read but left out: malformed (a world warning says why), or
                          * LMSHIFT/LMOFFSET beside a DECOUPLED_LM that replaces them */
    EW_BSPX_REPLACED     /* RGBLIGHTING replaced by a .lit (ew_world_attach_lit) */
} ew_bspx_use;
typedef struct ew_bspx_lump_info {
    char        name[25];  /* NUL-terminated */
    uint32_t    offset, length;
    ew_bspx_use use;
} ew_bspx_lump_info;
EW_API int         ew_world_bspx_lump(const ew_world *w, int i, ew_bspx_lump_info *info);
/* Warnings met while loading: optional data that was malformed (a
 * worldspawn key, a fence texture without holes) and replaced by a sane
 * default, one line each naming the file and the problem.  i from 0; NULL
 * past the last. */
EW_API const char *ew_world_warning(const ew_world *w, int i);
/* Coloured light from a .lit file (data, size; filename names it in
 * warnings): "QLIT", int32 version 1, then 3 bytes (r, g, b) for each byte
 * of the map's light lump, so size = 8 + 3 x the light lump's size.  Returns
 * 0 when attached (it replaces coloured light from a BSPX RGBLIGHTING lump:
 * the .lit beside a map wins, as in today's ports); 1 when ignored, after
 * adding one warning to the world (wrong size, bad magic, version other
 * than 1, truncated, or a map without light): the map keeps its
 * monochrome light.  ew_world_create reads the BSPX lumps RGBLIGHTING,
 * LMSHIFT, LMOFFSET, LMSTYLE and DECOUPLED_LM itself (malformed ones are
 * warnings too); ew_assets_create attaches maps/NAME.lit on its own. */
EW_API int ew_world_attach_lit(ew_world *w, const uint8_t *data, size_t size, const char *filename);
EW_API const char *ew_world_entities(const ew_world *w);

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
EW_API int ew_benchmark_views(const ew_world *w, ew_camera views[EW_MAX_VIEWS]);

/* ---- everything needed to render one map -------------------------------- */

/* Heap object (ew_assets_create / ew_assets_destroy); read its fields. */
typedef struct ew_assets {
    ew_world *world;
    uint8_t   palette[768];
    uint8_t   colormap[EW_COLORMAP_SIZE];
} ew_assets;

/* MAP is a path to a .bsp (palette/colormap from ../gfx/ beside it, or from
 * data_dir if given) or a map name looked up in the game directory data_dir
 * as maps/NAME.bsp.  Its coloured light, NAME.lit, is attached when present
 * (ew_world_attach_lit): beside a .bsp path, or as maps/NAME.lit in the game
 * directory (loose or in a pak); a bad one is a world warning.  Returns the
 * assets, or NULL with err set. */
EW_API ew_assets *ew_assets_create(const char *map, const char *data_dir, ew_error *err);
/* The built-in scene: a world the project generates itself (geometry,
 * procedural textures, palette, colormap, light maps, PVS), written as a
 * BSP29 image and loaded through ew_world_create like any map. */
EW_API ew_assets *ew_assets_create_builtin(ew_error *err);
/* Frees the assets and their world (NULL: nothing). */
EW_API void       ew_assets_destroy(ew_assets *a);

/* ---- movement and collision (world/move.c) ------------------------------
 * A player that walks a map as in the game: box traces through the BSP's
 * clip hulls, and a mover with gravity, friction, jumping, sliding along
 * walls and stepping up stairs.  Only the world (model 0) collides; doors
 * and lifts are not moved.  Quake units and seconds throughout. */

/* The hulls ew_trace moves through: 0 a point (the rendering tree), 1 the
 * player's box (mins -16 -16 -24, maxs 16 16 32 about the origin), 2 the
 * large box (mins -32 -32 -24, maxs 32 32 64).  The map's compiler grew the
 * clip hulls by the box, so tracing the box is tracing its origin point. */
enum { EW_HULL_POINT = 0, EW_HULL_PLAYER = 1, EW_HULL_LARGE = 2 };

/* Where a trace stopped. */
typedef struct ew_trace_result {
    float fraction;    /* 0..1 of the way from start to end (1: nothing hit) */
    float end[3];      /* where the box stops (end if nothing was hit); a
                        * hit stops 1/32 unit short of the plane */
    float normal[3];   /* the plane hit, facing back towards start; 0 0 0 if none */
    int   startsolid;  /* start was inside solid */
    int   allsolid;    /* the whole segment lies in solid (fraction 0) */
} ew_trace_result;

/* Leaf contents (Quake's values). */
enum {
    EW_CONTENTS_EMPTY = -1, EW_CONTENTS_SOLID = -2, EW_CONTENTS_WATER = -3,
    EW_CONTENTS_SLIME = -4, EW_CONTENTS_LAVA = -5, EW_CONTENTS_SKY = -6
};

/* Moves the hull's box from start to end through the world (model 0) and
 * stops at the first solid (contents EW_CONTENTS_SOLID; liquids and sky
 * leaves pass).  Returns 0, or -1 (result: nothing hit, fraction 1) when
 * the world has no usable hull: a map without clipnodes or with malformed
 * ones (a world warning says so) for hulls 1 and 2, or a bad hull number or
 * non-finite point.  Read-only: any number of threads may trace at once. */
EW_API int ew_trace(const ew_world *w, int hull, const float start[3], const float end[3],
                    ew_trace_result *result);
/* Contents (EW_CONTENTS_*, -1 empty, -2 solid ...) of the hull at a point;
 * EW_CONTENTS_EMPTY where the hull is unusable (as ew_trace's -1). */
EW_API int ew_point_contents(const ew_world *w, int hull, const float p[3]);

/* How a player moves: fly (no collision: free motion along the view, the
 * viewer's default) or walk (gravity and the clip hull). */
typedef enum ew_move_mode { EW_MOVE_FLY = 0, EW_MOVE_WALK } ew_move_mode;

/* The player: origin is the centre of Quake's player box, the origin of an
 * info_player_start (feet at origin - 24, head at origin + 32); the eye is
 * EW_EYE_HEIGHT above it.  Zero-initialise, then set origin and mode. */
#define EW_EYE_HEIGHT 22.0f
typedef struct ew_player {
    float        origin[3];
    float        velocity[3];  /* units per second */
    int          on_ground;    /* walk: standing on a floor (set by ew_player_move) */
    ew_move_mode mode;
    int          jump_held;    /* internal: jump is taken once per press */
} ew_player;

/* One frame's controls. */
typedef struct ew_move_input {
    float angles[3];      /* view pitch, yaw, roll in degrees (as ew_camera) */
    float forward;        /* -1..1: forward (W) minus back (S) */
    float right;          /* -1..1: right (D) minus left (A) */
    float up;             /* -1..1: up (Space) minus down (C); fly mode only */
    float speed;          /* units/s at full input; 0 = EW_MOVE_SPEED */
    int   run;            /* doubles the speed (Shift) */
    int   jump;           /* walk: jump (held: once per press; pressed in the air: on landing) */
} ew_move_input;

/* The constants of walk mode, those of the game's server (sv_gravity,
 * sv_maxspeed, sv_friction, sv_stopspeed, sv_accelerate, cl_forwardspeed,
 * the jump's 270 and the 18-unit step): */
#define EW_MOVE_GRAVITY    800.0f  /* units/s^2 downwards */
#define EW_MOVE_SPEED      200.0f  /* walking speed (run: 400, capped by the max) */
#define EW_MOVE_MAX_SPEED  320.0f  /* walk mode's top ground speed */
#define EW_MOVE_FRICTION   4.0f    /* ground speed lost per second, as a fraction of the speed */
#define EW_MOVE_STOP_SPEED 100.0f  /* below this, friction acts as if at this speed */
#define EW_MOVE_ACCEL      10.0f   /* speed gained per second, x wish speed (ground and air) */
#define EW_MOVE_AIR_SPEED  30.0f   /* air control: the wish speed in the air is at most this */
#define EW_MOVE_JUMP       270.0f  /* upward speed of a jump */
#define EW_MOVE_STEP       18.0f   /* tallest step walked up without a jump */
#define EW_MOVE_MAX_FALL   2000.0f /* |velocity| is clamped to this per axis */
#define EW_MOVE_SUBSTEP    (1.0 / 72.0) /* largest time step simulated at once (s) */

/* Advances the player dt seconds (0 < dt; at most 1 s is simulated, in
 * equal sub-steps of at most EW_MOVE_SUBSTEP, so equal inputs give equal
 * results bit for bit).  Fly: velocity = the input along the view's
 * forward, right and world-up axes, no collision.  Walk: friction and
 * acceleration on the ground, gravity in the air, a jump when asked while
 * on the ground; the box slides along what it hits (up to four planes a
 * sub-step), steps up ledges of at most EW_MOVE_STEP and lands on floors
 * (a plane whose normal z >= 0.7).  A player that starts inside solid is
 * nudged out (up to EW_MOVE_STEP units) or stays put.  A world without a
 * usable clip hull (or NULL) moves a walking player as in fly mode.  Bad
 * values never spread: a NaN or infinite velocity component is zeroed; an
 * origin that is not finite or beyond +-1e6 is not moved (velocity zeroed);
 * dt NaN or <= 0 does nothing, dt > 1 is 1; NaN inputs count as 0 (in = NULL:
 * no keys). */
EW_API void ew_player_move(const ew_world *w, ew_player *p, const ew_move_input *in, double dt);
/* The eye: origin + (0, 0, EW_EYE_HEIGHT), as the view set's cameras. */
EW_API void ew_player_eye(const ew_player *p, float eye[3]);
/* Places the player with its eye at eye (origin = eye - EW_EYE_HEIGHT),
 * at rest, in the given mode. */
EW_API void ew_player_set_eye(ew_player *p, const float eye[3], ew_move_mode mode);

/* ---- the renderer ------------------------------------------------------- */

typedef struct ew_renderer ew_renderer;

/* Largest thread count a renderer uses. */
#define EW_MAX_THREADS 64

/* Pixel format of the frame. */
typedef enum ew_color_mode {
    EW_COLOR_8BIT = 0,  /* palette indices (ew_frame_pixels): the software look */
    EW_COLOR_TRUE       /* 32-bit pixels (ew_frame_rgba): surfaces lit in RGB */
} ew_color_mode;

/* Hidden-surface removal for the world: the method Quake shipped, the
 * reference the tests trust, and the alternatives the Black Book weighs
 * (docs/hsr.md).  Every method draws the same surfaces with the same span
 * drawers and lighting; only which pixels each polygon wins differs. */
typedef enum ew_hsr_method {
    EW_HSR_EDGE = 0,     /* "edge": the global edge list, BSP-order keys (the default) */
    EW_HSR_REFERENCE,    /* "reference": every visible face z-buffered per pixel, a
                          * divide per pixel (slow and simple: the tests trust it) */
    EW_HSR_EDGE_Z,       /* "edge-z": the edge list sorted by 1/z at each span start */
    EW_HSR_SPANS,        /* "spans": polygons front to back, each row's span clipped
                          * against the spans already drawn in that row */
    EW_HSR_ZBUFFER,      /* "zbuffer": polygons front to back, 1/z tested per pixel */
    EW_HSR_PAINTER,      /* "painter": polygons back to front, every one drawn whole */
    EW_HSR_DRAWBUFFER,   /* "drawbuffer": front to back, one bit per pixel drawn */
    EW_HSR_BEAMTREE,     /* "beamtree": front to back, clipped against a beam tree */
    EW_HSR_RAYCAST,      /* "raycast": rays on an 8x8 grid, subdivided where they differ */
    EW_HSR_COUNT
} ew_hsr_method;

/* Each method's own counters (ew_stats.hsr_counters), named by
 * ew_hsr_counter_name. */
#define EW_HSR_COUNTERS 4

/* The method's name ("edge", "edge-z", ...), or NULL for a value outside
 * the enum. */
EW_API const char *ew_hsr_name(ew_hsr_method method);
/* The method of that name, or -1. */
EW_API int ew_hsr_from_name(const char *name);
/* What counter i (0..EW_HSR_COUNTERS-1) of the method counts ("depth
 * tests", "beam tree nodes", ...), or NULL if the method leaves it 0. */
EW_API const char *ew_hsr_counter_name(ew_hsr_method method, int i);
/* 1 if this build has the method, 0 if not (or not a method). */
EW_API int ew_hsr_available(ew_hsr_method method);

/* How alias (triangle) models are rasterized: affine triangles with
 * Gouraud shading, Carmack's recursive subdivision (for small models), or
 * automatic choice by the model's projected size (subdivision when its
 * screen height is below a threshold).  Default: auto, 40 pixels.
 * Two experiments of Black Book chapter 69 (docs/hsr.md, part 6): masks
 * (triangles within 5x5 pixels drawn from a table of precalculated pixel
 * masks, larger ones affine) and sprite-cache (a model shorter than the
 * threshold drawn once into an image with its depth and reused as a
 * z-tested sprite while its pose, angle and size change little). */
typedef enum ew_alias_raster {
    EW_ALIAS_AUTO, EW_ALIAS_AFFINE, EW_ALIAS_SUBDIV, EW_ALIAS_MASKS, EW_ALIAS_SPRITE_CACHE
} ew_alias_raster;

/* What ew_renderer_create makes.  Zero-initialise it and set what you need:
 * every field left 0 takes its default. */
typedef struct ew_renderer_desc {
    const ew_world *world;            /* required; must outlive the renderer */
    const uint8_t  *palette;          /* 768 bytes, required; must outlive the renderer */
    const uint8_t  *colormap;         /* EW_COLORMAP_SIZE bytes, required; likewise */
    int   width, height;              /* 0: 640x480; 320x200 .. 7680x4320 */
    int   threads;                    /* 0: one per core (at most EW_MAX_THREADS) */
    int   subdivision;                /* 0: 16 (a divide every 16 pixels); 1,2,4,8,16,32 */
    int   cache_mb;                   /* 0: automatic (16 bytes a pixel, 16..512 MiB) */
    ew_color_mode color;              /* 0: EW_COLOR_8BIT; EW_COLOR_TRUE */
    ew_hsr_method hsr;                /* 0: EW_HSR_EDGE (global edge list); any available ew_hsr_method */
    ew_alias_raster alias_raster;     /* 0: EW_ALIAS_AUTO */
    float alias_threshold;            /* 0: 40 pixels */
    int   classic;                    /* 0: what today's maps ask for; 1: the 1996 look (ew_set_classic) */
} ew_renderer_desc;

/* A renderer for desc's world, or NULL with one error line (a missing
 * world/palette/colormap, a size outside 320x200..7680x4320 or given in
 * one dimension only, negative threads, cache_mb outside 0..65536, a subdivision not a
 * power of two up to 32, an unknown enum value, a negative or non-finite
 * threshold, out of memory).  The setters below change things later. */
EW_API ew_renderer *ew_renderer_create(const ew_renderer_desc *desc, ew_error *err);
EW_API void         ew_renderer_destroy(ew_renderer *r);

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
    int    alias_sprite_hits;   /* sprite-cache: models drawn from their cached image */
    int    alias_sprite_misses; /* ... and models (re)drawn into it */
    int    particles;           /* particles drawn */
    int    surfaces_rebuilt_by_dlights;
    /* see-through surfaces, fog and the underwater view (none in classic mode) */
    int    seethrough_surfaces; /* fence and translucent polygons drawn after the world */
    long   fence_pixels;        /* pixels written by fence textures (holes skip) */
    long   translucent_pixels;  /* pixels blended by translucent surfaces */
    long   fog_pixels;          /* pixels fogged */
    int    underwater;          /* the eye is in a liquid: view warped and tinted */
    /* the hidden-surface method's own counters (ew_hsr_counter_name) */
    long   hsr_counters[EW_HSR_COUNTERS];
    long   hsr_bytes;           /* memory the method holds beyond the edge list and spans */
    double ms_front, ms_scan, ms_draw, ms_models, ms_total;
    /* Serial time: the frame's wall time outside its parallel sections (the
     * worker pool's runs), start of frame to the stats, on any thread
     * count; by Amdahl's law it bounds what more cores can give.  Its
     * parts, and the parallel front end's longest items, are probes of the
     * lab: ew_frame_lab_stats (edgewise_lab.h). */
    double ms_serial;
    /* Surfaces of the edge list that won at least one span, of `surfaces`:
     * the rest got through the PVS, frustum and facing tests but lay wholly
     * behind nearer ones, and cost the front end and the scan all the same
     * (0 for the methods that write no spans, such as reference). */
    int    surfaces_shown;
    /* Moving things in the frustum and the PVS that the opaque world hides
     * entirely (alias models and item boxes whose screen box lies behind
     * the world's 1/z everywhere): neither posed nor drawn, and counted in
     * entities_culled too. */
    int    entities_hidden;
    /* World faces that passed the PVS, frustum and facing tests but that
     * nearer faces were found to cover entirely before their edges were
     * set up (the edge method, ew_set_occlusion_cull): not in `surfaces`. */
    int    faces_occluded;
    /* Bytes of lit surfaces the surface cache holds after the frame (0 in
     * two-pass lighting, which keeps none: ew_set_lighting). */
    long   surface_cache_bytes;
} ew_stats;

/* Renders one frame of the world into the renderer's 8-bit frame buffer and
 * 1/z buffer.  stats may be NULL.  Returns 0 or -1 (bad camera). */
EW_API int ew_render(ew_renderer *r, const ew_camera *cam, ew_stats *stats);

EW_API int            ew_frame_width(const ew_renderer *r);
EW_API int            ew_frame_height(const ew_renderer *r);
/* The frame: 8-bit palette indices (width*height, row-major), or NULL in
 * true colour; ew_frame_rgba the other way round: 32-bit pixels, the bytes
 * R, G, B, A in memory (as ew_palette_rgba). */
EW_API const uint8_t  *ew_frame_pixels(const ew_renderer *r);
EW_API const uint32_t *ew_frame_rgba(const ew_renderer *r);
EW_API ew_color_mode   ew_frame_color(const ew_renderer *r);
/* The frame's 1/z per pixel (larger is nearer; 0 where nothing was drawn):
 * the world's, and the moving things' where they won.  Moving things are
 * the only readers during a frame, so ew_render z-fills the world only
 * under them (deferred z-fill) and this call fills in the rest, once per
 * frame, the first time it is asked for. */
EW_API const float   *ew_frame_zbuffer(ew_renderer *r);

/* Threads that render bands of each frame (0 = one per processor this
 * process may run on, its affinity as taskset sets it; at most 64).
 * Returns the count in use, or -1 when out of memory. */
EW_API int ew_set_threads(ew_renderer *r, int n);
EW_API int ew_get_threads(const ew_renderer *r);

/* ---- light styles --------------------------------------------------------
 * Each face's light map has up to four styles (0..63); a style's value
 * scales its light (256 = the light map as compiled).  By default the
 * styles are what the game shows, computed each frame from the camera's
 * time: a pattern of letters, ten a second, looping, each letter worth
 * (letter - 'a') * 22 as in the original engine ('a' = 0 dark, 'm' = 264
 * normal, 'z' = 550).  Style 0 "m"; 1..11 Quake's standard patterns
 * (flicker, slow strong pulse, candle, fast strobe, gentle pulse, flicker
 * 2, candle 2, candle 3, slow strobe, fluorescent flicker, slow pulse);
 * 12..31 "m"; 32..63, the switchable lights, "m" (on) unless a light
 * entity of the map using the style starts off (spawnflags 1): "a".  In
 * classic mode (ew_set_classic) the defaults are 256 for every style, the
 * conditions of the reference renders; the settings below apply in both. */

/* A fixed value for a style (clamped to 0..1024), in effect at once; an
 * unknown style is ignored. */
EW_API void ew_set_lightstyle(ew_renderer *r, int style, int value);
/* A pattern of its own for a style: 1..64 letters 'a'..'z' (e.g. "az" to
 * blink five times a second).  0, or -1 (nothing changed) for another
 * string, NULL or an unknown style. */
EW_API int  ew_set_lightstyle_pattern(ew_renderer *r, int style, const char *pattern);
/* A switchable light on ("m") or off ("a"), whatever the map says.
 * 0, or -1 for an unknown style. */
EW_API int  ew_set_lightstyle_switch(ew_renderer *r, int style, int on);
/* The style back to its default (above). */
EW_API void ew_reset_lightstyle(ew_renderer *r, int style);
/* The value the last frame used for a style (256 before the first frame;
 * -1 for an unknown style). */
EW_API int  ew_get_lightstyle(const ew_renderer *r, int style);

/* Output gamma, 0.5..3 (default 1: none): each colour channel c becomes
 * 255 * (c / 255) ^ (1 / gamma), so above 1 brightens and below darkens.
 * 8-bit frames keep their palette indices: show them with
 * ew_frame_palette; true-colour frames get it in their pixels.  Returns 0,
 * or -1 (nothing changed) for another value. */
EW_API int   ew_set_gamma(ew_renderer *r, float gamma);
EW_API float ew_get_gamma(const ew_renderer *r);
/* The palette (768 bytes) to show the 8-bit frame with: the renderer's
 * palette through the gamma (the same colours at gamma 1).  ew_write_frame_png
 * writes it. */
EW_API const uint8_t *ew_frame_palette(const ew_renderer *r);

/* Perspective-correct divide every `pixels` pixels along a span (1, 2, 4,
 * 8, 16 or 32; default 16, as the original), affine in between.  1 makes
 * texturing exact, for measuring what the approximation changes.
 * Returns 0, or -1 for another value. */
EW_API int ew_set_subdivision(ew_renderer *r, int pixels);

/* Alias model rasterizer and auto threshold (threshold_px <= 0 keeps the
 * current one); see ew_alias_raster. */
EW_API void ew_set_alias_raster(ew_renderer *r, ew_alias_raster mode, float threshold_px);

/* Coloured light: a map's .lit file or BSPX RGBLIGHTING lump is used when
 * there is one (on, the default); off lights with the monochrome lump. */
EW_API void ew_set_lit(ew_renderer *r, int on);
/* 8-bit frames with coloured light: each texel under a tinted light is the
 * palette colour nearest its RGB (chroma counted twice, so the tint shows);
 * on mixes two palette colours whose mean comes near the RGB in a 4x4
 * ordered pattern instead (default off).  Light tinted under a quarter of
 * its level keeps the colormap's ramps either way. */
EW_API void ew_set_dither(ew_renderer *r, int on);

/* How lit faces get their light (docs/lighting.md):
 *   EW_LIGHTING_CACHE     light-mapped surfaces built once and cached
 *                         (Quake's surface cache; the default);
 *   EW_LIGHTING_TWO_PASS  the alternative chapter 69 weighs: each face's
 *                         texture drawn unlit, then every pixel lit from the
 *                         light map sampled at it (no surfaces, no cache
 *                         memory, twice the pixel work).  Also the tests'
 *                         light oracle: it shares no code with the cache.
 * Dynamic lights and the debug views are drawn by the cache only. */
typedef enum ew_lighting_mode { EW_LIGHTING_CACHE = 0, EW_LIGHTING_TWO_PASS = 1 } ew_lighting_mode;
EW_API void ew_set_lighting(ew_renderer *r, ew_lighting_mode mode);
EW_API ew_lighting_mode ew_get_lighting(const ew_renderer *r);

/* The hidden-surface method of the next frames; 0, or -1 (the method
 * unchanged) if it is not an available ew_hsr_method. */
EW_API int ew_set_hsr(ew_renderer *r, ew_hsr_method method);

/* ---- debug modes: the pipeline made visible --------------------------------
 * A mode of the renderer (the viewer's keys, `edgewise render --debug MODE`)
 * for the frames that follow; EW_DEBUG_NONE (the default) gives the normal
 * frame back byte for byte.  Both pixel formats (8-bit: the palette colour
 * nearest each debug colour).  Other views of the pipeline need no mode:
 * exact perspective is ew_set_subdivision(r, 1), threads ew_set_threads,
 * entities on/off a scene or none (ew_set_scene), the alias rasterizer
 * ew_set_alias_raster, the visibility method ew_set_hsr. */
typedef enum ew_debug_mode {
    EW_DEBUG_NONE = 0,
    /* Each span of the edge list in its own colour (a hash of its number;
     * spans side by side in a row always differ): the zero-overdraw span
     * structure.  Nothing is drawn over the world (no models, see-through
     * surfaces, fog or underwater warp).  Edge method only. */
    EW_DEBUG_SPANS,
    /* The frame as normal (no underwater warp) with the global edge list's
     * edges over it: each edge a pixel a row, from v_first to v_last, at the
     * pixel the scan starts its span on.  Edge method only. */
    EW_DEBUG_EDGES,
    /* Heat map of the writes to each pixel: one per world span (the edge
     * list writes every world pixel once), plus one per pass over the world
     * (models, fences, translucent surfaces; fog is not counted) that changed
     * the pixel.  0 black, 1 dark blue, 2 green, 3 yellow, 4 orange, 5 or
     * more red.  No underwater warp. */
    EW_DEBUG_OVERDRAW,
    /* Light maps only: surfaces built from a flat grey texture, lit as usual
     * (styles, dynamic lights, coloured light), through the colormap or the
     * light curve. */
    EW_DEBUG_LIGHTING,
    /* Textures only: every light sample at normal light (colormap row 32),
     * as a map without light data; no light styles, no dynamic lights. */
    EW_DEBUG_TEXTURES,
    /* Each lit surface one flat colour by its mip level: 0 red, 1 green,
     * 2 blue, 3 yellow (sky and liquids as normal). */
    EW_DEBUG_MIPS,
    /* Surfaces built this frame (surface-cache misses) drawn flat magenta;
     * the others as normal.  The first frame of a renderer (and the first
     * after the cache is flushed) builds every surface it shows, so it is
     * all magenta: the mode shows the rebuilds between frames.  Edge
     * method only. */
    EW_DEBUG_BUILDS
} ew_debug_mode;
/* Sets the mode (an unknown value is EW_DEBUG_NONE).  The modes that change
 * surface building (lighting, textures, mips) invalidate the surface cache
 * when entered or left.  Returns 0, or -1 when out of memory (overdraw
 * needs two frame-sized buffers; the mode is then unchanged). */
EW_API int           ew_set_debug(ew_renderer *r, ew_debug_mode mode);
EW_API ew_debug_mode ew_get_debug(const ew_renderer *r);
/* Freezes the potentially visible set, like Quake's r_lockpvs: while on,
 * every frame marks the PVS of the leaf the eye was in at the last frame
 * before the lock (or the next frame's, if none was rendered), so walking
 * away shows what the PVS culls.  Off (the default): the eye's own leaf. */
EW_API void          ew_set_pvs_lock(ew_renderer *r, int on);

/* ---- see-through surfaces, fog, the underwater view ----------------------
 * What today's maps ask for, on by default:
 *   - fence textures ('{' names): palette index 255 is a hole showing what
 *     is behind (world and moving things), drawn after the moving things
 *     with a z test and an alpha test;
 *   - translucent liquids (worldspawn _wateralpha, _slimealpha, _lavaalpha,
 *     _telealpha) and brush entities with an "alpha" key: blended over what
 *     is behind them, back to front, after the fences; in 8-bit through
 *     tables of the nearest palette colour of each blend (one per alpha);
 *   - fog (worldspawn "fog" "density r g b", as today's source ports):
 *     colour c at view depth z becomes mix(fog, c, f), f = exp(-(density *
 *     z / 64)^2); the sky is fogged half way; in 8-bit through a table of the
 *     nearest palette colour per fog level;
 *   - the underwater view: with the eye in a water, slime or lava leaf the
 *     frame is warped by sines that drift with time and tinted with the
 *     liquid's colour, as the original did. */

/* The 1996 look: every item above off (fence holes painted in the key
 * colour, liquids opaque, no fog, no warp): the frames the WinQuake
 * fidelity tests check.  Default 0. */
EW_API void ew_set_classic(ew_renderer *r, int on);
/* Liquid opacity: alpha in (0, 1] for every liquid (at least 1/16), or < 0 (the default)
 * for what the map asks (1 where it asks nothing).  At 1 liquids are
 * opaque and drawn by the edge list. */
EW_API void ew_set_liquid_alpha(ew_renderer *r, float alpha);
/* Fog: density >= 0 and a colour (0..1 each) replace the map's; density 0
 * is no fog; density < 0 (the default) takes the map's worldspawn "fog". */
EW_API void ew_set_fog(ew_renderer *r, float density, float red, float green, float blue);
/* The underwater warp and tint (default on). */
EW_API void ew_set_waterwarp(ew_renderer *r, int on);

/* ---- moving things ------------------------------------------------------ */

/* A scene: entities drawn over a world.  Brush models (doors, lifts,
 * buttons: the world's submodels *1, *2, ...) go into the world's edge list
 * and sort against it; alias models, sprites and particles are z-buffered
 * over the z-filled world. */
typedef struct ew_scene ew_scene;

EW_API ew_scene *ew_scene_create(const ew_world *w, ew_error *err);
/* Every entity of the map: brush models by "model" "*N", and known
 * classnames' models found in the game directory (data_dir, else the folder
 * above the map's own folder).  Unknown classnames and missing model files
 * are counted (ew_scene_counts), not errors. */
EW_API ew_scene *ew_scene_create_from_map(const ew_world *w, const char *map,
                                          const char *data_dir, ew_error *err);
/* The built-in scene's own moving things (made in memory like its world):
 * its door, a triangle model, particles and a dynamic light. */
EW_API ew_scene *ew_scene_create_builtin(const ew_world *w, ew_error *err);
EW_API void ew_scene_destroy(ew_scene *s);
/* Adds world submodel N (1..) at an offset and rotation; entity index or -1
 * (as ew_scene_add_entity). */
EW_API int  ew_scene_add_brush(ew_scene *s, int submodel, const float origin[3],
                               const float angles[3]);
/* Loads an alias model (MDL), sprite (SPR) or item box (BSP) from memory
 * for entities to use; returns its model index (the same index again for
 * the same name), or -1 with err set. */
EW_API int  ew_scene_load_model(ew_scene *s, const char *name, const uint8_t *data, size_t size,
                                ew_error *err);
/* An entity using model (an index from ew_scene_load_model) at origin with
 * Quake angles (pitch yaw roll), frame and skin; entity index, or -1 for an
 * unknown model, an origin coordinate beyond +-10,000,000 or not finite, an
 * angle not finite, or no memory. */
EW_API int  ew_scene_add_entity(ew_scene *s, int model, const float origin[3],
                                const float angles[3], int frame, int skin);
/* A brush entity's opacity, in (0, 1] (1: opaque, the default); 0 or -1
 * for an unknown entity or a value outside that range. */
EW_API int  ew_scene_set_alpha(ew_scene *s, int entity, float alpha);
/* n particles in a deterministic cloud (same seed, same cloud). */
EW_API int  ew_scene_add_particles(ew_scene *s, int n, const float center[3], float radius,
                                   uint32_t seed);
/* A dynamic light: adds light within radius to the surfaces it reaches;
 * white, or the colour given (0..1 each; in 8-bit frames the surfaces it
 * reaches take the nearest palette colours, as with coloured light; not in
 * classic mode). */
EW_API int  ew_scene_add_dlight(ew_scene *s, const float origin[3], float radius);
EW_API int  ew_scene_add_dlight_rgb(ew_scene *s, const float origin[3], float radius, const float color[3]);
EW_API void ew_scene_counts(const ew_scene *s, int *entities, int *unknown, int *missing);
/* Removes every entity, dynamic light and particle, keeping the loaded
 * models (a scene rebuilt each frame: a demo's client).  Give the scene to
 * the renderer again (ew_set_scene) after refilling it. */
EW_API void ew_scene_clear(ew_scene *s);
/* One particle of palette colour 0..255 at org; its index, or -1 (bad
 * colour or place, no memory, a million particles). */
EW_API int  ew_scene_add_particle(ew_scene *s, const float org[3], int color);
/* Warnings met while making the scene from a map's entities (a brush
 * entity's "alpha" that is not a number from 0 to 1, ...), one line each;
 * i from 0, NULL past the last. */
EW_API const char *ew_scene_warning(const ew_scene *s, int i);
/* The model files the map's entities asked for that ew_scene_create_from_map
 * could not load, each once, as game-directory paths ("progs/soldier.mdl",
 * "maps/b_batt1.bsp"), in the order the entities first asked: i from 0, NULL
 * past the last (a scene made otherwise has none).  What a caller that
 * fetches files on demand (the web page, app/web/) fetches before making
 * the scene again. */
EW_API const char *ew_scene_missing_file(const ew_scene *s, int i);
/* The scene ew_render draws with the world (NULL: world only).  It must
 * outlive its use by the renderer.  Call it again after adding entities
 * to the scene it draws (the renderer sizes its per-entity room here). */
EW_API void ew_set_scene(ew_renderer *r, const ew_scene *s);

/* ---- text and the statistics overlay ------------------------------------ */

/* Text drawn by edgewise into the renderer's frame (after ew_render, before
 * the frame is shown or written) with its built-in bitmap font: printable
 * ASCII 32..126, fixed width, each glyph 5x7 font pixels in a 6x8 cell.  A
 * block of text is laid out as a grid of cells with a margin of one font
 * pixel around it: W = (6 * longest line + 1) * scale by
 * H = (8 * lines + 1) * scale frame pixels, the glyph of line l, column c
 * at (x + (1 + 6c) * scale, y + (1 + 8l) * scale).  '\n' starts a new line;
 * any other character outside 32..126 is drawn as a hollow box. */

/* What the text looks like behind it (flags, combine with |). */
#define EW_TEXT_SHADOW  1  /* a black copy one font pixel right and down */
#define EW_TEXT_OUTLINE 2  /* black around every glyph pixel (8 neighbours) */
#define EW_TEXT_BOX     4  /* the whole block darkened to 3/8 (readable over anything) */

/* Largest scale (font pixel = scale x scale frame pixels). */
#define EW_TEXT_MAX_SCALE 16

/* The text's colour and background.  Zero-initialised: black text, nothing
 * behind it.  A NULL style means white text with EW_TEXT_SHADOW | EW_TEXT_BOX. */
typedef struct ew_text_style {
    uint8_t rgb[3];     /* the colour: true-colour frames draw it as it is; 8-bit
                         * frames the palette colour nearest to it (0..254) */
    int     use_index;  /* 1: 8-bit frames draw palette index `index` instead */
    uint8_t index;
    int     flags;      /* EW_TEXT_SHADOW, EW_TEXT_OUTLINE, EW_TEXT_BOX */
} ew_text_style;

/* Draws text into r's frame (either colour mode) with the top-left corner
 * of its block at (x, y) (may be negative or past the frame: everything is
 * clipped to the frame, nothing is written outside it).  Everything drawn,
 * box, shadow and outline included, lies inside the W x H block that
 * ew_text_size gives.  Returns 0, or -1 (NULL r or text, scale outside
 * 1..EW_TEXT_MAX_SCALE). */
EW_API int ew_draw_text(ew_renderer *r, int x, int y, int scale, const char *text,
                        const ew_text_style *style);
/* The block that ew_draw_text covers: *w, *h in frame pixels (0 x 0 for
 * ""; a trailing '\n' adds an empty line).  Returns 0, or -1 as ew_draw_text. */
EW_API int ew_text_size(const char *text, int scale, int *w, int *h);

/* What the overlay shows beside ew_stats, measured by the caller. */
typedef struct ew_overlay_info {
    double fps;                /* frames per second (<= 0: shown as "-") */
    double ms_present;         /* the caller's time to show a frame, ms */
    const ew_camera *camera;   /* position and angles (NULL: those lines left out) */
    int    corner;             /* 0 top-left, 1 top-right, 2 bottom-left, 3 bottom-right */
    int    scale;              /* 0: automatic, frame height / 480 within 1..4 */
} ew_overlay_info;

/* The overlay's text, one '\n'-separated line each, no trailing newline:
 *
 *   fps 59.9 (16.7 ms)                  extra only; "fps -" if fps <= 0
 *   ms front 1.23 scan 0.45             ew_stats ms_front, ms_scan
 *   ms draw 3.21 models 0.10            ms_draw, ms_models
 *   ms total 5.00 present 0.30          ms_total; present: extra only
 *   edges 1234 surfs 567 shown 89       edges, surfaces, surfaces_shown
 *   spans 8901 cache built 12 hit 345   spans, surfaces_built, surfaces_cached
 *   leaves 67                           visible_leaves
 *   pos 480.0 -352.0 88.0               extra->camera origin (x y z)
 *   ang 0.0 90.0 0.0                    extra->camera angles (pitch yaw roll)
 *
 * Times in ms with two decimals, fps and position/angles with one.  extra
 * may be NULL (its lines are left out).  Writes at most size bytes
 * (NUL-terminated when size > 0); returns the length the whole text needs,
 * as snprintf. */
EW_API int ew_format_stats_overlay(char *buf, size_t size, const ew_stats *st,
                                   const ew_overlay_info *extra);
/* Draws that text into r's frame in a corner (extra->corner, top-left
 * without extra), 4 * scale pixels from the frame's edges, white with a
 * shadow over a darkened box (the NULL style of ew_draw_text).  Returns 0,
 * or -1 (NULL r or st, a corner outside 0..3, a scale outside
 * 0..EW_TEXT_MAX_SCALE). */
EW_API int ew_draw_stats_overlay(ew_renderer *r, const ew_stats *st, const ew_overlay_info *extra);

/* ---- moving convex polyhedra: Listing 51.1's 1/z-sorted edge list ---------
 * A scene with no BSP at all (`edgewise render builtin:polyhedra`): convex
 * polyhedra (cubes, slabs, tetrahedra, octahedra, prisms, pyramids; every
 * sixth glued to the one before, so the two abut) with flat-shaded faces
 * spin and fly through each other as time goes on, seen
 * by a fixed camera (90 degree horizontal field of view).  Each front face
 * is clipped to the near plane and the screen, projected, and its edges put
 * in a global edge list; every scanline walks the edges in x order with a
 * surface stack sorted by 1/z at the current pixel (the Black Book, chapter
 * 51): a leading edge sorts its surface in (equal 1/z, abutting, decided by
 * the 1/z slope in x), a trailing edge takes it out; where the planes of
 * two active surfaces cross between edges (interpenetrating objects) the
 * crossing is computed and the nearest surface switches there.  Every
 * pixel is written by exactly one span.  A per-pixel z-buffer of the same
 * polygons is there to check it. */
typedef struct ew_polyhedra ew_polyhedra;

/* Most polyhedra in one scene. */
#define EW_POLYHEDRA_MAX 64
/* The scene's own default number of polyhedra. */
#define EW_POLYHEDRA_DEFAULT 12

/* One frame's counters. */
typedef struct ew_polyhedra_stats {
    int       polygons;   /* front faces drawn (after culling and clipping) */
    int       clipped;    /* of those, faces cut by the near plane or the screen */
    int       edges;      /* edges in the global edge list */
    int       spans;      /* spans emitted, background included (z-buffer: 0) */
    long long pixels;     /* pixel writes: the edge list's spans (width x height
                           * exactly), the z-buffer's clear plus every passed test */
    long long covered;    /* pixels showing a polygon rather than the background */
    int       crossings;  /* intersections resolved: the nearest surface changed
                           * between two edges because two planes crossed there */
    int       ties;       /* abutting: equal 1/z where a surface started or the
                           * stack was re-sorted, decided by the 1/z slope in x */
} ew_polyhedra_stats;

/* One span of the last edge-list frame: count pixels of colour from (x, y). */
typedef struct ew_polyhedra_span {
    int32_t y, x, count;
    uint8_t color;
} ew_polyhedra_span;

/* A scene of `objects` polyhedra (1..EW_POLYHEDRA_MAX; the same count gives
 * the same scene) drawn into width x height frames (16..16384 each).
 * palette: 768 bytes to draw with (each shade becomes its nearest colour),
 * or NULL for the built-in one (16 ramps of 16 shades, ramp 0 grey).
 * NULL with err set on bad arguments or out of memory. */
EW_API ew_polyhedra *ew_polyhedra_create(int objects, int width, int height,
                                         const uint8_t palette[768], ew_error *err);
EW_API void          ew_polyhedra_destroy(ew_polyhedra *p);
/* The frame at `time` seconds (finite, |time| <= 1e6) by the 1/z-sorted edge
 * list into pixels (width x height palette indices, rows packed); st may be
 * NULL.  0, or -1 with err set. */
EW_API int ew_polyhedra_render(ew_polyhedra *p, double time, uint8_t *pixels,
                               ew_polyhedra_stats *st, ew_error *err);
/* The same frame by a per-pixel z-buffer of the same polygons (1/z at each
 * pixel centre from the same plane equations, largest wins). */
EW_API int ew_polyhedra_render_zbuffer(ew_polyhedra *p, double time, uint8_t *pixels,
                                       ew_polyhedra_stats *st, ew_error *err);
/* The spans of the last ew_polyhedra_render, top row first, left to right
 * within a row; *count gets their number. */
EW_API const ew_polyhedra_span *ew_polyhedra_spans(const ew_polyhedra *p, int *count);
/* Intersection resolution (default on).  Off, the nearest surface is only
 * decided where edges start and end: the chapter's independent span
 * sorting, right only for objects that never touch. */
EW_API void ew_polyhedra_set_crossings(ew_polyhedra *p, int on);
/* The 768-byte palette the frames index (the one given, or the built-in). */
EW_API const uint8_t *ew_polyhedra_palette(const ew_polyhedra *p);

/* ---- demos: recorded games (.dem) ---------------------------------------
 * A demo is what a Quake client recorded of a game: the CD track as a line
 * of text ("-1\n"), then blocks, each an int32 length, the view angles
 * (three floats: pitch, yaw, roll) and that many bytes of the server's
 * messages to the client.  The reader knows NetQuake's protocol 15,
 * FitzQuake's 666 (larger model and frame numbers, alpha, the extended
 * entity and client-data bits, the *2 spawn messages, fog, skybox) and
 * RMQ's 999 with its flags choosing the size of coordinates and angles
 * (EW_DEMO_PRFL_*), as today's ports record them.  It applies every
 * message a client needs to draw to a state (ew_demo_state) and skips
 * the rest (sounds, text, scores) by their known length.
 *
 *   ew_demo *d = ew_demo_open("demo3.dem", &err);
 *   while ((rc = ew_demo_read_block(d, &err)) == 1) {
 *       const ew_demo_state *st = ew_demo_get_state(d);  ...the client state
 *   }
 *   rc < 0: err names the block and the byte offset of the bad message;
 *   the state holds everything before it.
 *
 * A message the reader does not know, one that runs past its block, or a
 * block whose length runs past the file (or beyond EW_DEMO_MAX_BLOCK) is one
 * error naming the block and the byte offset; every block before it stays
 * readable.  Nothing read from the file is trusted: every count, index and
 * length is checked. */
typedef struct ew_demo ew_demo;

#define EW_DEMO_MAX_BLOCK   65536  /* bytes of messages in one block */
#define EW_DEMO_MAX_MODELS  4096   /* model precache slots (1.. ; 0 is none) */
#define EW_DEMO_MAX_ENTITIES 32768 /* entity numbers 0..32767 */
#define EW_DEMO_MAX_STATICS 4096
#define EW_DEMO_MAX_EVENTS  512    /* temp entities and particle bursts of one block */
#define EW_DEMO_LIGHTSTYLES 64
#define EW_DEMO_SVC_KINDS   64     /* message kinds counted (svc numbers 0..63) */

/* RMQ's protocol flags (protocol 999). */
#define EW_DEMO_PRFL_SHORTANGLE 0x02  /* angles as int16 (360/65536 degrees) */
#define EW_DEMO_PRFL_FLOATANGLE 0x04  /* angles as float32 */
#define EW_DEMO_PRFL_24BITCOORD 0x08  /* coordinates as int16 + a byte of 1/255 */
#define EW_DEMO_PRFL_FLOATCOORD 0x10  /* coordinates as float32 */
#define EW_DEMO_PRFL_EDICTSCALE 0x20  /* entity scale (a byte, read and ignored) */
#define EW_DEMO_PRFL_INT32COORD 0x80  /* coordinates as int32 (1/16 unit) */

/* One entity as the client knows it.  origin/angles are the latest
 * update's, prev_origin/prev_angles the one before (equal to the latest
 * when the client would not interpolate: a new or reappearing entity, a
 * model change, a jump of more than 100 units, U_NOLERP). */
typedef struct ew_demo_entity {
    int    model;             /* model precache index (0: none) */
    int    frame, skin, colormap, effects;  /* effects: EF_* bits (1 brightfield,
                                             * 2 muzzleflash, 4 brightlight, 8 dimlight) */
    float  alpha;             /* 0..1 (1 opaque) */
    float  origin[3], angles[3];
    float  prev_origin[3], prev_angles[3];
    double msgtime;           /* server time of its last update; < 0: never updated */
} ew_demo_entity;

/* A baseline or static entity: model, frame, colormap, skin, origin, angles, alpha. */
typedef struct ew_demo_baseline {
    int   model, frame, colormap, skin;
    float origin[3], angles[3];
    float alpha;
} ew_demo_baseline;

/* What a block brought besides the entities: temp entities and particle
 * bursts (svc_particle), for the client's effects. */
enum {
    /* temp entities: their protocol numbers */
    EW_TE_SPIKE = 0, EW_TE_SUPERSPIKE, EW_TE_GUNSHOT, EW_TE_EXPLOSION, EW_TE_TAREXPLOSION,
    EW_TE_LIGHTNING1, EW_TE_LIGHTNING2, EW_TE_WIZSPIKE, EW_TE_KNIGHTSPIKE, EW_TE_LIGHTNING3,
    EW_TE_LAVASPLASH, EW_TE_TELEPORT, EW_TE_EXPLOSION2, EW_TE_BEAM,
    /* svc_particle: count particles of colour from start along dir (count
     * 255: an explosion's 1024) */
    EW_DEMO_EV_PARTICLES = 100
};
typedef struct ew_demo_event {
    int   type;          /* EW_TE_* or EW_DEMO_EV_PARTICLES */
    int   entity;        /* beams: the entity they start from */
    float start[3], end[3];  /* end: beams only */
    float dir[3];        /* particles: direction (units per second / 16) */
    int   count, color;  /* particles; EW_TE_EXPLOSION2: color start and length */
    double time;         /* the server time it came at */
} ew_demo_event;

/* The client state after the blocks read so far. */
typedef struct ew_demo_state {
    int    protocol;               /* 15, 666 or 999 (0 before svc_serverinfo) */
    unsigned protocol_flags;       /* 999 only: EW_DEMO_PRFL_* */
    int    maxclients, gametype;
    char   level[128];             /* the level's title */
    char   models[EW_DEMO_MAX_MODELS][64]; /* precache names, [1].. ([1] is the map "maps/x.bsp") */
    int    nmodels;                /* names in models[1..nmodels] */
    int    nsounds;
    int    view_entity;            /* svc_setview (the player, 1.. ) */
    double time, prev_time;        /* svc_time: the latest two server times */
    float  view_angles[3];         /* the block's recorded view angles */
    float  prev_view_angles[3];    /* the block before's */
    float  set_angles[3];          /* the last svc_setangle */
    int    view_height;            /* client data: eye above the origin (default 22) */
    int    items, weapon_frame, weapon_model, health, armor, ammo, active_weapon;
    float  weapon_alpha;           /* 0..1 */
    int    stats[32];              /* svc_updatestat and client data (index 2: weapon model) */
    int    on_ground, in_water;
    int    intermission;           /* 1 intermission, 2 finale, 3 cutscene (0: playing) */
    int    paused;
    char   lightstyles[EW_DEMO_LIGHTSTYLES][65];  /* svc_lightstyle patterns ("" unset) */
    uint64_t lightstyle_bits;      /* styles set by the last block */
    uint64_t lightstyles_seen;     /* styles set since the server info ("" there: normal light) */
    float  fog[4];                 /* FitzQuake fog: density, r, g, b (0..1) */
    int    fog_set;                /* a svc_fog came (fog[] valid) */
    ew_demo_entity *entities;      /* [0 .. nentities-1]; 0 is the world */
    int    nentities;
    ew_demo_baseline *baselines;   /* [0 .. nentities-1] */
    ew_demo_baseline statics[EW_DEMO_MAX_STATICS];
    int    nstatics;
    ew_demo_event events[EW_DEMO_MAX_EVENTS];  /* the last block's */
    int    nevents;
    int    signon;                 /* svc_signonnum */
    long   messages[EW_DEMO_SVC_KINDS];  /* messages read, by svc number */
    long   entity_updates;         /* fast updates (entity messages), counted apart */
    int    updates_last_block;     /* entity updates in the last block */
    int    block;                  /* blocks read (the next block's index) */
    size_t offset;                 /* byte offset of the next block in the file */
} ew_demo_state;

/* Opens a demo file (read into memory) or a copy of size bytes at data
 * (name names it in errors).  NULL with err set when it is no demo at all
 * (no CD-track line, no whole block); a damaged block later on is kept for
 * ew_demo_read_block to report. */
EW_API ew_demo *ew_demo_open(const char *path, ew_error *err);
EW_API ew_demo *ew_demo_open_memory(const uint8_t *data, size_t size, const char *name, ew_error *err);
EW_API void     ew_demo_close(ew_demo *d);
/* Whole blocks in the file (before any damaged one). */
EW_API int      ew_demo_block_count(const ew_demo *d);
/* Reads the next block and applies its messages to the state: 1, 0 at
 * the end (after the last block), or -1 with err naming the block and
 * byte offset (then every later call fails the same way; the state keeps
 * what came before the bad message). */
EW_API int      ew_demo_read_block(ew_demo *d, ew_error *err);
/* Back to the first block, the state as just opened. */
EW_API void     ew_demo_rewind(ew_demo *d);
EW_API const ew_demo_state *ew_demo_get_state(const ew_demo *d);
/* The protocol's name of a message kind ("svc_time"), or NULL. */
EW_API const char *ew_demo_svc_name(int svc);

/* ---- a demo's client: what the game's client would draw ----------------
 * Reads a demo block by block and makes, for any time between the two
 * latest messages, the scene and camera the game's client draws: entities
 * interpolated between their two latest updates (angles the short way
 * round), items that spin (model flag EF_ROTATE) turned by time, brush
 * entities (doors, lifts) moved, static entities, the view at the view
 * entity's origin plus the view height with the recorded angles (in an
 * intermission or cutscene: the view entity's own origin and angles), the
 * weapon model in front of the view, dynamic lights for muzzle flashes,
 * bright and dim lights, rockets and explosions, particles for
 * explosions, blood, spikes and gunshots (svc_particle), rocket, grenade
 * and gib trails, teleport and lava splashes, and beams (lightning) from
 * their models.  Sounds, text and the status bar are left out.  The scene
 * belongs to the client; give it to the renderer (ew_set_scene) after each
 * ew_demo_client_frame.  Deterministic: the same time gives the same frame. */
typedef struct ew_demo_client ew_demo_client;

/* A client reading d (which it does not own; d must outlive it) over world
 * w, the demo's map, loading the models the demo precaches from data_dir
 * (a game directory or search list, as ew_fs_create; NULL: none, every
 * model missing).  Missing model files are counted, not errors. */
EW_API ew_demo_client *ew_demo_client_create(ew_demo *d, const ew_world *w, const char *data_dir,
                                             ew_error *err);
EW_API void ew_demo_client_destroy(ew_demo_client *c);
/* Reads the next block (ew_demo_read_block) and takes in what it brought
 * (models newly precached, temp entities as effects): 1, 0 at the end,
 * -1 with err set. */
EW_API int  ew_demo_client_read(ew_demo_client *c, ew_error *err);
/* Reads blocks until the latest message's time reaches t (or the demo
 * ends): 1, 0 once the demo has ended, -1 with err set. */
EW_API int  ew_demo_client_advance(ew_demo_client *c, double t, ew_error *err);
/* Makes the scene and the camera (fov 90) at client time t, clamped to the
 * two latest messages' times.  0, or -1 before any server info. */
EW_API int  ew_demo_client_frame(ew_demo_client *c, double t, ew_camera *cam);
EW_API ew_scene *ew_demo_client_scene(ew_demo_client *c);
/* The map the demo plays on: the first model precache ("maps/x.bsp"), or
 * "" before the server info. */
EW_API const char *ew_demo_client_map(const ew_demo_client *c);
/* Model precaches that no file was found for (or that did not load). */
EW_API int  ew_demo_client_missing(const ew_demo_client *c);

/* ---- output --------------------------------------------------------------*/

/* Writes 8-bit pixels as an indexed PNG (the palette and one byte a pixel). */
EW_API int ew_write_png(const char *path, const uint8_t *pixels, int width, int height,
                        const uint8_t palette[768], ew_error *err);
/* Writes 32-bit pixels (R, G, B, A bytes, as ew_frame_rgba) as an RGB PNG. */
EW_API int ew_write_png_rgba(const char *path, const uint32_t *pixels, int width, int height, ew_error *err);
/* The frame of a renderer (either colour mode) as a PNG. */
EW_API int ew_write_frame_png(const ew_renderer *r, const char *path, ew_error *err);

/* Palette to 32-bit pixels for a display: out[i] holds colour i as the
 * bytes R, G, B, A in memory order (A = 255), whatever the machine's byte
 * order, i.e. SDL_PIXELFORMAT_RGBA32 / GL_RGBA + GL_UNSIGNED_BYTE. */
EW_API void ew_palette_rgba(const uint8_t palette[768], uint32_t out[256]);
/* out[i] = table[pixels[i]] for n pixels (e.g. a frame through the table
 * of ew_palette_rgba). */
EW_API void ew_pixels_to_rgba(const uint8_t *pixels, size_t n, const uint32_t table[256],
                              uint32_t *out);

#ifdef __cplusplus
}
#endif
#endif
