/*
 * edgewise_lab.h - the lab's and the benchmark's calls of edgewise.
 *
 * What the tests, the fuzz targets, `edgewise bench`, `soak`, `hsr` and
 * `shots` use to check and measure the renderer, kept out of edgewise.h so
 * that an application sees only what it needs.  Same rules as edgewise.h
 * (which this includes): failures fill an ew_error and return NULL or -1;
 * every function is EW_API, in libedgewise.a and libedgewise.so alike.
 *
 *   ew_enable_face_ids(r, 1);                     record the face of each pixel
 *   ew_render(r, &cam, NULL);
 *   const int *ids = ew_frame_face_ids(r);        width*height face indices
 *   ew_render_reference(r, &cam, pixels, ref_ids, &err);   the same frame, z-buffered
 *   ew_lab_stats lab;  ew_frame_lab_stats(r, &lab);         the last frame's probes
 *
 * Sections: checking the edge list; measuring (knobs, then the probes:
 * ew_lab_stats); the frame's cuts; worlds and views for the lab; files.
 */
#ifndef EDGEWISE_LAB_H
#define EDGEWISE_LAB_H

#include "edgewise.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- checking the edge list -------------------------------------------- */

/* When enabled, the next frames also record the face index that won each
 * pixel (-1 where nothing was drawn); NULL until then. */
EW_API void       ew_enable_face_ids(ew_renderer *r, int on);
EW_API const int *ew_frame_face_ids(const ew_renderer *r);

/* The reference path, independent of the edge list: every visible face of
 * the same frame rasterized with a per-pixel z-buffer from its plane
 * equation, textured and lit from the same surfaces.  Writes the frame
 * (if pixels != NULL: width*height palette indices, or 4-byte pixels in
 * true colour, so 4 * width * height bytes) and (if face_ids != NULL) the
 * winning face per pixel. */
EW_API int ew_render_reference(ew_renderer *r, const ew_camera *cam, uint8_t *pixels,
                               int *face_ids, ew_error *err);

/* ---- measuring ---------------------------------------------------------- */

/* Z-fill under every world span as it is drawn (1), as the original
 * renderer did, or only where moving things need it (0, the default).
 * The frame and ew_frame_zbuffer are the same either way; 1 is slower
 * and exists to measure what deferring saves. */
EW_API void ew_set_full_zfill(ew_renderer *r, int on);

/* Moving things the opaque world hides entirely: alias models and item
 * boxes whose screen box lies behind the world's 1/z at every pixel are
 * neither posed nor drawn (1, the default; ew_stats.entities_hidden counts
 * them), or drawn like the rest (0).  The frame and ew_frame_zbuffer are
 * the same either way; 0 exists to check that and to measure the saving. */
EW_API void ew_set_hide_occluded(ew_renderer *r, int on);

/* World faces that nearer world faces hide: the edge method can leave out
 * of its edge list every face whose pixels, on a coarse map of the screen,
 * faces earlier in BSP order already cover (ew_stats.faces_occluded counts
 * them).  AUTO, the default, does so in frames whose PVS has at least 500
 * leaves (a map of many rooms, where it repays its test of every face);
 * ALWAYS in every frame; OFF never.  The frame is the same in every mode,
 * on any number of threads: OFF and ALWAYS exist to check that and to
 * measure the saving.  The other methods keep every face. */
typedef enum ew_occlusion_mode { EW_OCCLUSION_OFF, EW_OCCLUSION_AUTO, EW_OCCLUSION_ALWAYS } ew_occlusion_mode;
EW_API void ew_set_occlusion_cull(ew_renderer *r, ew_occlusion_mode mode);

/* The front end (BSP walk, clipping, edge set-up) of a frame.  AUTO, the
 * default: on at most EW_FRONT_LOOP_THREADS threads one loop down the tree
 * on the calling thread, as ew_walk_world does (the other thread waits: on
 * two, the phases' hand-offs cost what the second thread saves); on more,
 * the phases the front end runs in on every thread (world/front_par.c).
 * PHASES: the phases on any number of threads, one too, which costs it
 * 10-20% more there; bench sets it to measure what of a many-thread frame
 * is serial (ew_stats.ms_serial, the row profile) on one thread.  The
 * frame is the same either way. */
#define EW_FRONT_LOOP_THREADS 2
typedef enum ew_front_mode { EW_FRONT_AUTO, EW_FRONT_PHASES } ew_front_mode;
EW_API void ew_set_front_mode(ew_renderer *r, ew_front_mode mode);

/* The widest instructions the loops chosen at run time may use (today the
 * fog runs: a table row per run of one level in 8-bit, a blend in true
 * colour).  BEST, the default, takes the widest the processor has; BASE
 * keeps to the build's SSE2 (or none), AVX2 stops short of AVX-512, as
 * most desktop processors do, so a machine with AVX-512 can test and time
 * what they run.  A level the processor lacks falls back to the widest it
 * has.  Returns the level in use.  The frame is the same at every level. */
typedef enum ew_simd_level { EW_SIMD_BEST, EW_SIMD_BASE, EW_SIMD_AVX2, EW_SIMD_AVX512 } ew_simd_level;
EW_API ew_simd_level ew_set_simd(ew_renderer *r, ew_simd_level level);
/* "best", "sse2", "avx2", "avx512" (NULL for another value), and back
 * (-1 for another name), as `bench --simd` spells them. */
EW_API const char *ew_simd_name(ew_simd_level level);
EW_API int ew_simd_from_name(const char *name);

/* A deliberately wrong surface cache, for the light oracle's controls
 * (tests/test_light_oracle.c): the light map read one sample to the right
 * (EW_LIGHT_FAULT_SHIFT) or with s and t swapped (EW_LIGHT_FAULT_SWAP).
 * EW_LIGHT_FAULT_NONE (the default) is the right one. */
typedef enum ew_light_fault {
    EW_LIGHT_FAULT_NONE = 0, EW_LIGHT_FAULT_SHIFT = 1, EW_LIGHT_FAULT_SWAP = 2
} ew_light_fault;
EW_API void ew_set_light_fault(ew_renderer *r, ew_light_fault fault);
/* Empties the surface cache (every lit surface, the item boxes' too): the
 * next frame builds each one it shows, as the first frame of a new view
 * does, and draws the same pixels (`edgewise bench --cold`,
 * bench/lighting_lab.c).  Here, not in edgewise.h: an application never
 * needs it (a change of any setting that alters surfaces rebuilds them by
 * itself); it is for measuring what the builds cost. */
EW_API void ew_flush_surfaces(ew_renderer *r);

/* How the renderer cuts a frame for its threads, in two phases with a wait
 * between: with more than one thread, the scan into EW_BANDS_PER_THREAD
 * bands a thread, placed by the last frame's scan costs, then the draw
 * (spans and moving things) into EW_DRAW_ITEMS_PER_THREAD pieces a
 * thread, placed by this frame's draw costs, known once the scan is done;
 * each at most height / 8 in all.  The draw's pieces are finer since the
 * last one taken idles the other threads and cutting them costs little. */
#define EW_BANDS_PER_THREAD 4
#define EW_DRAW_ITEMS_PER_THREAD 8
/* The renderer's counts of both (outside the row profile) for threads
 * threads at height rows: one each on one thread. */
EW_API void ew_frame_cuts(int threads, int height, int *bands, int *pieces);

/* How the renderer cuts a frame of height rows into n >= 1 bands: each
 * band ends where the running sum of row_cost first reaches its share of
 * the total, after at least 8 rows, so every band costs about the same
 * (with fewer than 8 * n rows: equal rows).  The renderer passes the last frame's scan
 * costs for its bands (each band's time spread over its rows); `edgewise
 * bench --bands` the one-thread frame's own.  Writes bounds[0..n]: band i is rows
 * bounds[i] .. bounds[i+1]-1. */
EW_API void ew_place_bands(const float *row_cost, int height, int n, int *bounds);

/* How the renderer cuts the draw's n pieces for `threads` threads, which
 * take them in order as each becomes free: "guided" sizes, each piece
 * 1/(2 threads) of the cost still left (at least 8 rows; the last piece
 * takes the rest), large first and small last, so the threads finish close
 * together.  One thread: as ew_place_bands.  bounds as there. */
EW_API void ew_place_pieces(const float *row_cost, int height, int n, int threads, int *bounds);

/* Per-row cost profile (for `edgewise bench --bands`).  On: the frame is
 * cut into fixed strips of 8 rows, whatever the thread count, each strip's
 * work timed (scan, spans, moving things in its rows); the frames are
 * the same as ever.  Re-makes the bands like ew_set_threads and returns
 * what it does.  Off: the bands as usual. */
EW_API int ew_set_row_profile(ew_renderer *r, int on);
/* The last frame's cost per row in ms, in its two parallel phases: the scan
 * (its band's time over its rows) into scan_ms, the draw (its piece's time,
 * spans and moving things, over its rows) into draw_ms, each [0 .. min(n,
 * height)-1] and either NULL to skip; returns the frame's height. */
EW_API int ew_frame_row_ms(const ew_renderer *r, float *scan_ms, float *draw_ms, int n);

/* ---- the last frame's probes ------------------------------------------- */

/* ew_lab_stats.ms_run_*'s entries.  EW_RUN_SCAN: the scan's bands, and
 * where the front end runs in phases on every thread (world/front_par.c),
 * those phases too (one run); EW_RUN_BUILD: the surfaces' builds, the
 * models' poses and the gradients; EW_RUN_DRAW: the spans and the moving
 * things; EW_RUN_OTHER: the rest (the surface-cache peek, the colour
 * cubes, the whole-frame passes). */
enum { EW_RUN_SCAN, EW_RUN_BUILD, EW_RUN_DRAW, EW_RUN_OTHER, EW_RUNS };

/* Where a frame's serial time goes, and what the parallel front end cannot
 * shorten: the scheduler's own measurements, for `edgewise bench`.  Their
 * sum is ew_stats.ms_serial (the frame's wall time outside the worker
 * pool's runs) less the warp set-up and the stats. */
typedef struct ew_lab_stats {
    double ms_serial_begin;    /* frame begin: view, dynamic lights */
    double ms_serial_walk;     /* the front end's serial steps (top of the BSP walk,
                                * layouts by prefix sum, edge linking) */
    double ms_serial_brush;    /* the brush entities' frustum test */
    double ms_serial_prepare;  /* band placement, surface-cache lookups that allocate */
    double ms_serial_passes;   /* the passes' preparation */
    /* While ew_set_row_profile is on, and only then: the largest single
     * work item of each of the parallel front end's phases, summed: what
     * no number of threads can shorten in the front end (else 0). */
    double ms_front_items;
    /* The frame's own work: processor time of the calling thread over
     * ew_render and of each worker inside the frame's jobs (not its
     * polling between them; a worker adds its part as it leaves a job, so
     * the last job's may count in the next frame's); the process's
     * processor time per frame over this shows what is burnt outside the
     * work (bench --gap). */
    double ms_work;
    /* The frame's parallel runs by kind (EW_RUN_*): each run's wall time,
     * and its busy time, the time every thread spent inside its job,
     * summed (a thread's waits inside the job, for the items it needs,
     * included).  busy / wall: how many threads the run kept busy; busy on
     * N threads over busy on one: the extra work N threads do there. */
    double ms_run_wall[EW_RUNS], ms_run_busy[EW_RUNS];
} ew_lab_stats;
/* The last frame's probes (all 0 before the first frame). */
EW_API void ew_frame_lab_stats(const ew_renderer *r, ew_lab_stats *lab);

/* A monotonic clock in milliseconds, the one the renderer times itself by. */
EW_API double ew_clock_ms(void);

/* 1 if the last frame left a budget full: surfaces, edges (room for one
 * more clipped face) or a band's spans or active edges; then its `dropped`
 * count is the budget's doing, not a fault. */
EW_API int ew_frame_budget_full(const ew_renderer *r);

/* ---- worlds and views for the lab ---------------------------------------- */

/* The leaf of the world tree (model 0) that holds p: 0 is the shared solid
 * leaf; its contents by ew_world_leaf_contents (EW_CONTENTS_*). */
EW_API int ew_world_point_leaf(const ew_world *w, const float p[3]);
/* Leaves of the world tree, 0..count-1 (count in ew_world_info.leaves);
 * contents of a leaf outside that range: EW_CONTENTS_SOLID. */
EW_API int ew_world_leaf_contents(const ew_world *w, int leaf);
/* The leaves of the world tree (not of brush models) whose contents are
 * open to a camera (not solid, not sky), in order, into leaves (NULL:
 * only counted); returns their count. */
EW_API int ew_world_open_leaves(const ew_world *w, int *leaves);
/* A leaf's bounding box (0, or -1 for a leaf outside the world). */
EW_API int ew_world_leaf_bounds(const ew_world *w, int leaf, float mins[3], float maxs[3]);
/* How far p lies from the nearest plane above the leaf in the tree (the
 * planes of every face that bounds it); FLT_MAX when there is none. */
EW_API float ew_world_leaf_clearance(const ew_world *w, int leaf, const float p[3]);
/* How far p lies from the nearest plane of the whole world. */
EW_API float ew_world_plane_clearance(const ew_world *w, const float p[3]);

/* The stress hall: the built-in map's rooms carrying detail cells of 16
 * units laid as checkerboards, each cell a face of its own, for timing
 * hidden-surface methods against the polygons in view (`builtin:detail=N`).
 * detail 0..EW_STRESS_MAX_DETAIL; NULL with err set outside it. */
#define EW_STRESS_MAX_DETAIL 26000
EW_API ew_assets *ew_assets_create_stress(int detail, const char *name, ew_error *err);

/* Of the views ew_benchmark_views makes (four a player start, one an
 * intermission), the index of the first info_intermission (*inter) and of
 * the first player start (*start), -1 where there is none. */
EW_API void ew_benchmark_view_roles(const ew_world *w, int *inter, int *start);

/* Every camera of the entity lump, not only the view set's first 32: each
 * info_intermission (from its "mangle") and each info_player_* (its eye
 * EW_EYE_HEIGHT units over its origin, turned by its "angle"), in the
 * lump's order, into cams (at most max); kinds[i] (kinds may be NULL) is 1
 * for an intermission camera, 0 for a player start.  Returns the count. */
EW_API int ew_entity_cameras(const ew_world *w, ew_camera *cams, int *kinds, int max);
/* The mean of the map's monochrome light samples (0..255), or -1 for a
 * map without light data (drawn fullbright). */
EW_API double ew_world_light_mean(const ew_world *w);
/* 1 if the world carries coloured light (a .lit attached, or a BSPX
 * RGBLIGHTING lump read), which ew_set_lit turns on and off; else 0. */
EW_API int ew_world_has_rgb_light(const ew_world *w);

/* ---- files --------------------------------------------------------------- */

/* Reads an RGB/RGBA/gray PNG to malloc'd RGB8 (used by the fidelity tests). */
EW_API int ew_read_png_rgb(const char *path, uint8_t **rgb, int *width, int *height,
                           ew_error *err);

/* PAK archive directory, validated against the archive's size.
 * Entries point into the caller's buffer; *entries is malloc'd. */
typedef struct ew_pak_entry {
    char     name[57];
    uint32_t offset, size;
} ew_pak_entry;
EW_API int ew_pak_parse(const uint8_t *data, size_t size, const char *filename,
                        ew_pak_entry **entries, int *count, ew_error *err);

#ifdef __cplusplus
}
#endif
#endif
