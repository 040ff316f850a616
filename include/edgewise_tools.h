/*
 * edgewise_tools.h - test and measurement calls of edgewise.
 *
 * What the tests, the fuzz targets and `edgewise bench` use to check and
 * measure the renderer, kept out of edgewise.h so that an application sees
 * only what it needs.  Same rules as edgewise.h (which this includes):
 * failures fill an ew_error and return NULL or -1; every function is EW_API.
 *
 *   ew_enable_face_ids(r, 1);                     record the face of each pixel
 *   ew_render(r, &cam, NULL);
 *   const int *ids = ew_frame_face_ids(r);        width*height face indices
 *   ew_render_reference(r, &cam, pixels, ref_ids, &err);   the same frame, z-buffered
 */
#ifndef EDGEWISE_TOOLS_H
#define EDGEWISE_TOOLS_H

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

/* The front end (BSP walk, clipping, edge set-up) of a frame on one
 * thread.  AUTO, the default: one loop down the tree, as ew_walk_world
 * does.  PHASES: the phases the front end runs in on many threads
 * (world/front_par.c), on one thread too, which costs it 10-20% more
 * there; bench sets it to measure what of a many-thread frame is serial
 * (ew_stats.ms_serial, the row profile) on one thread.  The frame is the
 * same either way; with more than one thread it is always the phases. */
typedef enum ew_front_mode { EW_FRONT_AUTO, EW_FRONT_PHASES } ew_front_mode;
EW_API void ew_set_front_mode(ew_renderer *r, ew_front_mode mode);

/* A deliberately wrong surface cache, for the light oracle's controls
 * (tests/test_light_oracle.c): the light map read one sample to the right
 * (EW_LIGHT_FAULT_SHIFT) or with s and t swapped (EW_LIGHT_FAULT_SWAP).
 * EW_LIGHT_FAULT_NONE (the default) is the right one. */
typedef enum ew_light_fault {
    EW_LIGHT_FAULT_NONE = 0, EW_LIGHT_FAULT_SHIFT = 1, EW_LIGHT_FAULT_SWAP = 2
} ew_light_fault;
EW_API void ew_set_light_fault(ew_renderer *r, ew_light_fault fault);
/* Every cached lit surface out of date: the next frames build each one they
 * show again, as the first frame of a new view does (bench/lighting_lab.c). */
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
