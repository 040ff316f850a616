/*
 * Moving things (internal): triangle (alias) models, sprites, particles,
 * and the light level of a point for lighting them.  All of them are drawn
 * after the world, z-buffered against the 1/z the world's spans z-filled
 * (larger 1/z is nearer), and write only the frame's target (pixels and
 * 1/z) and the counters of the rows they draw.
 *
 * The alias model pipeline (Black Book chapter 69): every vertex of the
 * frame is transformed, projected and snapped to integer screen
 * coordinates; one cross product of the snapped coordinates rejects back
 * faces and degenerate triangles together; the rest are drawn either with
 * affine texture mapping and Gouraud shading (light from a fixed
 * direction), or, for small models, with John Carmack's recursive
 * subdivision rasterizer.
 */
#ifndef EW_ALIAS_H
#define EW_ALIAS_H

#include "asset/mdl.h"
#include "asset/scene.h"  /* ew_particle */
#include "asset/spr.h"
#include "light/light.h"
#include "raster/zfill.h"

/* Where and how an entity is drawn. */
typedef struct ew_model_pose {
    float  origin[3], angles[3];  /* Quake entity angles: pitch yaw roll (alias models
                                     negate the pitch, as the game did) */
    int    frame, skin;           /* clamped to the model's; groups animate by time */
    double time;
    int    ambient, shade;        /* light: 0..255 ambient level, directional shade amount */
} ew_model_pose;

/* Return 1 if anything of the model was in view (drawn), 0 if culled.
 * They draw only into rows [rows->y0, rows->y1) of the frame's target,
 * z-filled through zf first, and count into rows->stats (triangles only
 * when rows->first): every band of a frame draws the same model the same
 * way, each its own rows.  (ew_draw_alias, ew_draw_sprite and
 * ew_draw_particles in renderer.h draw the whole frame.) */
int  ew_draw_alias_rows(const ew_frame *f, ew_zfill *zf, const ew_mdl *m, const ew_model_pose *p,
                        const ew_rows *rows);
int  ew_draw_sprite_rows(const ew_frame *f, ew_zfill *zf, const ew_spr *s, const ew_model_pose *p,
                         const ew_rows *rows);
void ew_draw_particles_rows(const ew_frame *f, ew_zfill *zf, const ew_particle *p, int n, const ew_rows *rows);
/* Fills out[0..n) with a deterministic cloud in a ball of `radius` around
 * center (same seed, same cloud); returns n (0 if n < 0 or out is NULL). */
int  ew_particle_field(ew_particle *out, int n, const float center[3], float radius, uint32_t seed);

/* The five clip planes in view space (near z = near_z, then the four
 * screen sides, which put projected centres within [-0.5, size - 0.5]):
 * n.p + d >= 0 inside.  Shared by models and sprites. */
typedef struct ew_view_planes_t {
    float n[5][3], d[5];
} ew_view_planes_t;
void ew_view_planes(const ew_view *v, float near_z, ew_view_planes_t *cp);

#include "raster/alias_tri.h"  /* the triangle rasterizers */

/* A vertex of the current frame: view space, clip flags, projection. */
typedef struct ew_xvert {
    /* p, s, t, l: set only for a model not wholly in view (xf->accept 0),
     * the only one whose triangles can be clipped */
    float   p[3];     /* view space: x right, y up, z forward */
    float   s, t, l;  /* texel (front), light row 8.8 as floats for clipping */
    int32_t sback;    /* 16.16 texel s on the back half (onseam) */
    int     clip;     /* bit k: outside clip plane k */
    ew_avert sv;      /* projected (valid when clip == 0) */
} ew_xvert;

/* One alias model posed for this frame: its vertices in view space and
 * projected, its screen bounds, and how it is rasterized.  Made once a
 * frame (ew_alias_transform, in parallel across models) and read by every
 * band the model crosses (ew_alias_draw), so no band transforms or lights
 * it again. */
typedef struct ew_alias_xf {
    int              visible;                  /* 0: outside the frustum (or a bad pose), or hidden */
    int              hidden;                   /* the world hides it (raster/models.c) */
    int              accept, behind, subdiv;   /* wholly in view; a corner behind the eye; rasterizer */
    float            umin, umax, vmin, vmax;   /* screen box of its bounds */
    float            zi_near;                  /* the largest 1/z of its bounds' corners (unless behind) */
    int              minx, miny, maxx, maxy;   /* of its projected vertices */
    int              image;                    /* skin picture */
    int              pose;                     /* vertex frame (m->poses) */
    float            rot[3][3], org[3];        /* model axes and origin in view space */
    float            bm[3][3], bt[3], lm[3];   /* byte vertex -> view space; light direction in model space */
    int32_t          smax, tmax;
    ew_view_planes_t cp;
    const ew_xvert  *xv;                       /* numverts of them */
    const uint32_t  *rgba;                     /* true colour: its light's tint, or NULL (white) */
    const uint8_t   *remap;                    /* 8-bit: the same as nearest colours, or NULL */
} ew_alias_xf;
int  ew_alias_transform(const ew_frame *f, const ew_mdl *m, const ew_model_pose *p, ew_alias_xf *xf,
                        ew_xvert *xv);
/* The transform in two steps: place (the pose's frame, skin, axes, origin,
 * the frustum test of its bounds, the screen box umin..vmax: no vertex;
 * 0 if culled) and then its vertices (xv, minx..maxy).  The sprite-cache
 * decides between the two. */
int  ew_alias_place(const ew_frame *f, const ew_mdl *m, const ew_model_pose *p, ew_alias_xf *xf);
void ew_alias_pose_verts(const ew_frame *f, const ew_mdl *m, const ew_model_pose *p, ew_alias_xf *xf,
                         ew_xvert *xv);
int  ew_alias_draw(const ew_frame *f, ew_zfill *zf, const ew_mdl *m, const ew_alias_xf *xf, const ew_rows *rows);

/* ---- sprite-cache (alias_sprite_cache.c) ----------------------------------
 * A posed model shorter on screen than cfg.alias_threshold, wholly in view,
 * is drawn (exactly, affine) into an image of its own: its pixels (target
 * format) and 1/z over its projected box.  Later frames draw that image as a
 * z-tested sprite, moved by how far the model's origin moved on screen and
 * its 1/z corrected by how far the origin moved in depth, as long as the
 * key holds (tolerances in ew_sc_tol, defaults in ew_sprite_cache_tol_default):
 * the same model, vertex frame, skin and light tint; the light within a few
 * levels; the model's axes in view space and the direction from the eye to
 * it each within an angle; its distance within a ratio; reused at most
 * max_reuse frames in a row.  Otherwise it is drawn again (a miss). */
typedef struct ew_sc_tol {
    float angle_deg;   /* axes and eye direction: largest change, degrees */
    float scale;       /* distance ratio: within 1 +- scale */
    int   light;       /* ambient and shade levels: largest change */
    int   max_reuse;   /* frames drawn from one image before it is redrawn */
} ew_sc_tol;
ew_sc_tol ew_sprite_cache_tol_default(void);
/* The renderer's tolerances (set serially, between frames; every image is
 * redrawn after a change), and the ones in use. */
struct ew_sprite_cache;
int              ew_sprite_cache_set_tol(struct ew_sprite_cache **c, const ew_sc_tol *tol);
const ew_sc_tol *ew_sprite_cache_tol(const struct ew_sprite_cache *c);

typedef struct ew_sc_slot {
    /* the key of the image */
    const ew_mdl *model;
    int           pose, image, ambient, shade, reused, valid;
    uint32_t      tint;                 /* hash of the light's colour table */
    float         rot[3][3], dir[3], dist;
    float         ox, oy, oz;           /* the origin on screen and its view depth when drawn */
    /* the image: w * h pixels of bpp bytes, their 1/z (0: not covered) */
    int           x0, y0, w, h, bpp;
    uint8_t      *pix;
    float        *zi;
    size_t        cap;
    int           ntris;                /* triangles drawn into it */
    /* this frame */
    int           use, hit;             /* draw the image; it was reused */
    int           dx, dy;               /* where: moved by (dx, dy) */
    float         dz;                   /* view depth added to every pixel */
} ew_sc_slot;

/* The slot of entity i, or NULL (not the sprite-cache mode, no memory). */
ew_sc_slot *ew_sprite_cache_slot(const struct ew_sprite_cache *c, const ew_frame *f, int i);
/* Called serially: slots for n entities (mode sprite-cache only); 0 or -1. */
int  ew_sprite_cache_grow(struct ew_sprite_cache **c, const ew_frame *f, int n);
void ew_sprite_cache_free(struct ew_sprite_cache *c);
/* Per model and frame, touching only the slot: after ew_alias_place (and
 * the light's tint in xf), reuse returns 1 if the image is reused this frame
 * (no vertex needs posing); if not, pose the vertices
 * (ew_alias_pose_verts) and redraw draws the image again, or leaves
 * slot->use 0 (too large, crossing the frame's edge: draw the model
 * exactly with ew_alias_draw). */
int  ew_sprite_cache_reuse(const ew_frame *f, ew_sc_slot *slot, const ew_mdl *m, const ew_alias_xf *xf,
                           const ew_model_pose *p, const ew_sc_tol *tol);
void ew_sprite_cache_redraw(const ew_frame *f, ew_sc_slot *slot, const ew_mdl *m, const ew_alias_xf *xf,
                            const ew_model_pose *p);
/* Draws the slot's image into rows (z-filled, z-tested); counts pixels and,
 * when rows->first, the hit or miss. */
void ew_sprite_cache_draw(const ew_frame *f, ew_zfill *zf, const ew_sc_slot *slot, const ew_rows *rows);
void ew_sprite_cache_slot_free(ew_sc_slot *slot);

/* ---- the models pass (raster/models.c) ---- */
/* The scene drawn with the world, and what this frame knows of it. */
typedef struct ew_ents {
    const struct ew_scene *scene;               /* or NULL */
    ew_view      *ent_views;  int max_ent_views; /* camera in each brush entity's space */
    ew_ent_frame *ent_frame;  int nent_frame, max_ent_frame;
    ew_box_surfs **box_surfs; int nbox_surfs;   /* per scene model: item box surfaces, or NULL */
    /* item boxes projected once a frame for every piece of the draw
     * (raster/models.c): per entity its frame, the faces to fill of all of
     * them, and the visible boxes, the parallel work after the alias models */
    struct ew_box_frame *box_frame; int max_box_frame;
    struct ew_box_face  *box_faces; int max_box_faces;
    int          *box_list;   int nbox;
    /* alias models posed once a frame for every band (raster/alias.h) */
    struct ew_alias_xf *xf;   int max_xf;       /* per entity */
    struct ew_xvert *xverts;  size_t max_xverts; /* their vertices, one run per visible model */
    int          *alias_list; int nalias;       /* visible alias entities, the parallel work first */
    uint32_t     *tint_rgba;                    /* per entity, 256: the palette in its light's colour */
    uint8_t      *tint_remap;                   /* per entity, 256: 8-bit, the nearest colours of that */
    /* EW_ALIAS_SPRITE_CACHE: per entity, its image kept across frames
     * (raster/alias_sprite_cache.c; sized in the prepare, slot i written only
     * by the pose work of entity i, read by the bands) */
    struct ew_sprite_cache *sprite_cache;
} ew_ents;

/* What the models pass reads and writes besides the frame (set up once by
 * the renderer). */
typedef struct ew_models {
    ew_ents            *ents;     /* its own state; world/entities.c lists the frame's entities */
    const ew_marks     *marks;    /* the frame number: which item boxes are this frame's */
    const ew_edge_list *el;       /* the world's surfaces, which may hide a model */
    ew_zfill           *zf;
    const ew_span_ctx  *draw;     /* the item boxes' fill */
    const ew_lit       *lit;      /* the light curve, nearest colours and blend cube of tinted models */
} ew_models;

/* Room for the frame's item boxes: nents entity frames and list slots
 * (before the entities are listed), then nfaces faces; -1 without memory. */
int  ew_boxes_grow(ew_ents *en, int nents, int nfaces);
/* Alias models, sprites, item boxes, then particles, z-buffered over the
 * z-filled world.  (Brush models are in the world.)  ew_models_work does
 * the frame's item-th piece of the work ew_prepare_entities leaves: the
 * visible alias models posed, then the item boxes projected, once for
 * every piece of the draw. */
void ew_models_work(const ew_models *md, const ew_frame *fr, int item);
/* raster/models_prepare.c: the models' pass prepared (serial): the
 * entities the front end let through (tested here unless its phases did:
 * world/entities.c), their poses' and item boxes' room, the item boxes'
 * surfaces made current; returns how many alias models are left to pose
 * and item boxes to project (ew_models_work).  Out of memory: no entities
 * (counted in dropped).  ew_reserve_entities sizes ents->ent_frame for the
 * scene (-1 out of memory). */
struct ew_front;
int  ew_prepare_entities(const ew_models *md, ew_lit *lit, ew_frame *f, struct ew_front *fr);
int  ew_reserve_entities(ew_ents *en);
void ew_draw_models(const ew_models *md, const ew_frame *fr, const ew_rows *rows);

#endif
