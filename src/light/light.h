/* Light (internal): light maps into lit surfaces, the surface cache that
 * keeps them across frames, dynamic lights, and the light under a model. */
#ifndef EW_LIGHT_H
#define EW_LIGHT_H

#include "light/blend.h"
#include "light/twopass.h"
#include "world/front.h"  /* ew_marks: the frame number, the dynamic lights on each face */
#include "world/view.h"

struct ew_scene;

/* ---- surface cache (light/cache.c) ---- */
/* An entry and its pixels are one block carved from the cache's slabs. */
typedef struct ew_cached_surf {
    struct ew_cached_surf *lru_prev, *lru_next;
    int      face, mip, texture;
    int      light[4];   /* style values it was lit with */
    unsigned dlights;    /* dynamic lights it was built with */
    unsigned gen;        /* the cache's gen when built */
    int      width, height;
    int      last_frame;
    uint8_t *pixels;     /* right after the entry, in the same block */
} ew_cached_surf;

#define EW_CACHE_BINS 240
typedef struct ew_cache_block ew_cache_block;
typedef struct ew_cache_slab  ew_cache_slab;
typedef struct ew_surf_cache {
    int bpp;                      /* bytes a texel: 1, or 4 in true colour */
    unsigned gen;                 /* bumped when every surface must be rebuilt (a light setting) */
    ew_cached_surf **slot;        /* numfaces * 4 (per mip) */
    ew_cached_surf  *lru_head, *lru_tail;
    size_t bytes, budget;         /* pixels held, and the budget for them */
    /* The arena: slabs allocated on demand (about budget / 4 each), free
     * blocks kept by size class and merged with free neighbours. */
    ew_cache_slab  *slabs;
    size_t          slab_bytes, used_bytes;   /* slabs' total, blocks in use */
    ew_cache_block *bins[EW_CACHE_BINS];
} ew_surf_cache;

int  ew_cache_init(ew_surf_cache *c, int numfaces, size_t budget);
/* Every surface evicted (the slabs stay, their blocks free), as before a
 * first frame: the next frame builds all it shows. */
void ew_cache_flush(ew_surf_cache *c);
void ew_cache_free(ew_surf_cache *c);


/* ---- the light curve (light/curve.c) ----
 * Colour of palette index c under light row l (8.8, as the colormap's),
 * per channel: the colormap's own colour for that row, in RGB, and
 * between two rows the straight line from one to the next.  So white light
 * in true colour is the 8-bit frame's colour at every whole row and
 * smooth between them, and coloured light takes each channel from its own
 * row.  Fullbright colours (unchanged in every row) stay unlit. */
typedef struct ew_lightcurve {
    const uint8_t *palette;
    /* pair[row][c]: R, G, B, 0 of palette[colormap[row][c]], then twice
     * the step to the same of row + 1 (row 64 = row 63), as 16-bit lanes:
     * a texel's light runs between the two, and the true-colour surface
     * build reads both in one aligned 16-byte load. */
    _Alignas(16) int16_t pair[64][256][8];
    uint8_t        fullbright[256];
    uint32_t       rgba[256];     /* the palette as 32-bit pixels (ew_rgba) */
} ew_lightcurve;
void ew_lightcurve_fit(ew_lightcurve *lc, const uint8_t palette[768], const uint8_t *colormap);
/* Channel ch of colour c under light row l (8.8, below 64 << 8: light_row's
 * range in light/surface.c): a + (((b - a) * f) >> 8) between the rows. */
static inline int ew_lightcurve_at(const ew_lightcurve *lc, int c, int l, int ch) {
    const int16_t *p = lc->pair[l >> 8][c];
    return p[ch] + (((p[4 + ch] / 2) * (l & 255)) >> 8);
}

/* ---- the frame's lit surfaces (light's own state) ----
 * Per surface of the edge list, its cache entry (normal surfaces only) and
 * how its spans are drawn; and what lighting reads besides the frame, set
 * by the renderer. */
struct ew_surf_draw;
typedef struct ew_lit {
    ew_surf_cache    cache;
    ew_cached_surf **surf_cache;
    struct ew_surf_draw *surf_draw;              /* how each surface is drawn (raster/'s type; made by renderer.c) */
    ew_cached_surf **to_build;  int nbuild;
    int             *grad_list; int ngrad;       /* surfaces whose gradients are needed */
    uint8_t         *surf_state, *surf_mip;      /* per surface: prepare_surfaces' read-only findings */
    int              maxlm;                      /* largest light map, in samples */
    int             *blocklights;                /* building scratch, maxlm * 3 per thread */
    ew_lightcurve    curve;                      /* palette colour x light (light/curve.c) */
    const uint8_t   *nearest;                    /* 8-bit coloured light: RGB cube -> index */
    ew_twopass       tp;                         /* two-pass lighting: this frame's inputs */
    ew_tp_face      *tp_faces;                   /* two-pass lighting: per surface (max_surfs) */
    const ew_marks  *marks;                      /* the frame number, the dynamic lights on each face */
    const struct ew_scene *scene;                /* the scene's dynamic lights (ew_set_scene), or NULL */
    ew_blend        *blend;                      /* 8-bit coloured light: the nearest-colour cubes */
    const ew_debug  *dbg;                        /* the debug modes that change surfaces */
} ew_lit;

/* light/lit.c: its rooms for max_surfs surfaces of the edge list, the
 * light curve of palette and colormap, and a cache of budget bytes of
 * bpp-byte texels (0, or -1 without memory: ew_lit_free then); the
 * building scratch for nthreads threads (0 frees it). */
int  ew_lit_init(ew_lit *lit, const ew_world *w, const uint8_t *palette, const uint8_t *colormap, int max_surfs,
                 size_t budget, int bpp);
int  ew_lit_threads(ew_lit *lit, int nthreads);
void ew_lit_free(ew_lit *lit);

/* ---- the surface cache's use in a frame (light/cache.c) ---- */
/* Finds (or makes room for) the lit surface of a face at a mip level and
 * marks it used this frame; *build is set when its pixels must be built
 * (ew_lit_build, which may run on any thread: entries are distinct).
 * Serial: lookups allocate and evict.  NULL when out of memory. */
ew_cached_surf *ew_lit_lookup(ew_lit *lit, ew_frame *f, int face, int mip, int *build);
/* Its two halves for a hit: ew_lit_peek (any thread, reads only) gives
 * the entry if it is current, else NULL; ew_lit_touch (serial) marks
 * that entry used this frame.  An entry touched this frame is never
 * evicted in it. */
ew_cached_surf *ew_lit_peek(const ew_lit *lit, const ew_frame *f, int face, int mip);
void ew_lit_touch(ew_lit *lit, ew_frame *f, ew_cached_surf *e);
void ew_lit_build(const ew_lit *lit, const ew_frame *f, ew_cached_surf *e, int *scratch);

/* ---- lit surfaces (light/surface.c) ---- */
/* Light samples of a face (its light map's size: Quake's grid or BSPX). */
int  ew_face_samples(const ew_world *w, const ew_face *f);
/* 1 if surfaces of world w are built from coloured light this frame. */
int  ew_use_rgb_light(const ew_frame *f, const ew_world *w);
int  ew_face_mip(const ew_view *v, const ew_world *w, const ew_face *f, float nearzi);
const ew_texture *ew_face_texture(const ew_world *w, const ew_face *f, double time);
/* Builds face f of world w lit by style values light[] (and, for the
 * frame's own world, the dynamic lights in bits dlights) into out. */
void ew_build_surface(const ew_lit *lit, const ew_frame *fr, const ew_world *w, const ew_face *f,
                      const ew_texture *tex, int mip, const int light[4], unsigned dlights,
                      uint8_t *out, int *scratch);

/* ---- dynamic lights (light/dlight.c) ---- */
/* Marks the faces in reach of the scene's dynamic lights; the lights on a
 * face this frame (bit i = light i); adds them to a light map. */
void     ew_mark_dlights(ew_marks *m, const ew_frame *f, const struct ew_scene *sc);
unsigned ew_face_dlights(const ew_marks *m, int face);
/* Adds the lights in bits to a face's samples (smax x tmax, nc channels
 * interleaved; st_to_lm NULL for Quake's 16-texel grid, else the BSPX
 * layout's mapping of texture points to samples). */
void     ew_add_dlights(const ew_frame *fr, const struct ew_scene *sc, const ew_face *f, unsigned bits,
                        int *blocklights, int nc, int smax, int tmax, const float (*st_to_lm)[3]);

/* ---- light on moving things (light/lightpoint.c, light/model_light.c) ---- */
/* The world's light level under point p (0..255): traces straight down up
 * to 2048 units through model 0 to the first face hit and samples its
 * light map there (styles scaled by f->cfg.lightstyle[], no dynamic
 * lights).  0 when nothing is hit or the face has no light map; 255 if the
 * map is unlit. */
int  ew_light_point(const ew_frame *f, const float p[3]);
/* The same with its colour: rgb[0..2] 0..255 from the coloured light (the
 * mono level three times without it); returns the mono level. */
int  ew_light_point_rgb(const ew_frame *f, const float p[3], int rgb[3]);
/* An alias model's ambient and directional shade at origin: the floor
 * under it plus the scene's dynamic lights in reach. */
void ew_light_model(const ew_frame *f, const struct ew_scene *sc, const float origin[3], int *ambient, int *shade);
/* The colour of that light, as multipliers of 256 per channel (256, 256, 256:
 * white); 0 when the light is white (no coloured light, or grey). */
int  ew_light_tint(const ew_frame *f, const float origin[3], int tint[3]);

/* ---- light styles (light/styles.c) ----
 * A style's value each frame (256 = the light map as compiled): by
 * default the game's pattern for it at the frame's time, 256 in classic
 * mode; or what the caller set (a fixed value or a pattern of its own). */
/* 1 if p is 1..EW_STYLE_PATTERN_MAX letters 'a'..'z'. */
int  ew_style_pattern_ok(const char *p);
/* The value of one letter: ('c' - 'a') * 22, so 'a' = 0, 'm' = 264, 'z' = 550. */
int  ew_style_letter_value(char c);
/* The pattern style s (0..63) follows by default in a world whose light
 * entities start the styles in starts_off off (bit s). */
const char *ew_style_default_pattern(int style, uint64_t starts_off);
/* This frame's value of every style at time seconds (ten letters a second). */
void ew_styles_frame(int out[64], const ew_style_setting set[64], uint64_t starts_off, int classic,
                     double time);

/* ---- item boxes' lit surfaces (light/box_surfs.c) ---- */
/* Every face of a box at every mip, rebuilt only when a light style on it
 * or its texture frame changes (serial, once per frame). */
typedef struct ew_box_surf {
    uint8_t *pixels[4];
    int      width[4];
    int      light[4];          /* style values they were lit with */
    const ew_texture *tex;      /* and the texture frame (animated textures) */
    unsigned gen;               /* and the surface cache's gen (light/cache.c) */
    int      built;
} ew_box_surf;
typedef struct ew_box_surfs {
    int         nfaces;
    ew_box_surf face[];         /* model 0's faces */
} ew_box_surfs;
/* Makes scene model mi's (an item box world bw) surfaces current in the
 * list (*surfs, *n: per scene model, grown to hold mi); -1 when out of
 * memory. */
int  ew_box_surfs_prepare(ew_box_surfs ***surfs, int *n, const ew_lit *lit, const ew_frame *f, int mi,
                          const ew_world *bw);
void ew_box_surfs_free(ew_box_surfs **surfs, int n);

#endif
