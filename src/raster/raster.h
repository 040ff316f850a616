/* The back end (internal): span drawers, sky, liquids, the z-buffered
 * polygon fill, and what a band's drawing calls may touch.  Drawers take
 * only the frame target and the per-frame tables they read (ew_span_ctx),
 * not the renderer. */
#ifndef EW_RASTER_H
#define EW_RASTER_H

#include "frame.h"
#include "light/blend.h"
#include "raster/target.h"
#include "world/view.h"  /* EW_MAX_POLY, the view's helpers */

/* Screen gradients of a face: s/z, t/z and 1/z are linear in screen space. */
typedef struct ew_gradients {
    /* 1/z = zi_u*u + zi_v*v + zi_0, s/z and t/z likewise (seen from the
     * eye).  Laid out term by term, each (1/z, s/z, t/z, 0), so the lit
     * spans load a term of all three as one vector. */
    float zi_u, s_u, t_u, pad_u;
    float zi_v, s_v, t_v, pad_v;
    float zi_0, s_0, t_0, pad_0;
    int32_t s_adjust, t_adjust;   /* 16.16: s = (s/z) * z + s_adjust */
    int32_t s_max, t_max;         /* 16.16 clamp limits */
} ew_gradients;
/* raster/gradients.c: face f of world w seen through v (the camera in the
 * face's own space) at a mip level. */
void ew_face_gradients(const ew_world *w, const ew_view *v, const ew_face *f, int mip,
                       ew_gradients *g);
/* Its 1/z plane alone is ew_face_zplane (world/view.h). */

/* How one surface's spans are drawn this frame (set before the bands draw). */
enum { EW_DRAW_BACKGROUND, EW_DRAW_LIT, EW_DRAW_SKY, EW_DRAW_TURB, EW_DRAW_FLAT, EW_DRAW_DEBUG,
       EW_DRAW_TWOPASS /* lit in two passes per pixel (light/twopass.h) */ };
typedef struct ew_surf_draw {
    ew_gradients g;           /* screen gradients (mip of its lit surface; 0 for sky and liquids) */
    const uint8_t *pixels;    /* EW_DRAW_LIT: the lit surface, pitch bytes a row */
    int pitch;
    int lit16;                /* EW_DRAW_LIT, set with g (ew_span_prepare): 1 or 2 (narrow) for the
                                 16-pixel drawer of 8-bit frames, 0 for the general one */
    int kind;                 /* EW_DRAW_*; FLAT: no memory for its lit surface */
    const ew_texture *tex;    /* sky and liquids */
    uint32_t flat;            /* EW_DRAW_DEBUG: one colour (raster/debug.h) */
} ew_surf_draw;

/* Fog by depth in an 8-bit frame: colour c at 1/z zi becomes
 * table[ew_fog_level(f, zi) * 256 + c] (raster/fog.c). */
#define EW_FOG_QMAX   8.0f    /* (density z / 64)^2 past which fog is whole */
#define EW_FOG_QSCALE 512.0f
#define EW_FOG_QSTEPS 4096    /* QMAX * QSCALE */
typedef struct ew_fog {
    const uint8_t *table;     /* EW_FOG_LEVELS x 256 (light/blend.h), NULL: no fog */
    float   w;                /* (density / 64)^2, so q = w / zi^2 = (density z / 64)^2 */
    int     sky_level;        /* the sky is fogged half way, as the ports do */
    int     rgb[3];           /* true colour: the fog colour, 0..255 */
    /* Set by the prepare for the drawers: from level `full` on, every colour
     * becomes full_px (the fog colour as the target stores it); with fill
     * the span draw writes full_px where fog is whole instead of the texels
     * (ew_fog_draw_spans).  The level is at least k where 1/z <= zt[k]:
     * surely where 1/z <= zt_lo[k], surely not where 1/z > zt_hi[k]. */
    int      full, fill;
    int      seg;             /* the drawers' segment: 1 << subdiv_shift */
    int      simd;            /* the widest fog loops in use: EW_FOG_SIMD_* (ew_fog_levels, ew_set_simd) */
    uint32_t full_px;
    float    zt[EW_FOG_LEVELS + 1], zt_lo[EW_FOG_LEVELS + 1], zt_hi[EW_FOG_LEVELS + 1];
    uint16_t first[EW_FOG_LEVELS + 1];  /* the first entry of level[] at each level or above */
    /* q -> level of 1 - exp(-q); three bytes more, so a four-byte gather
     * at any entry stays inside (raster/fog.c) */
    uint8_t level[EW_FOG_QSTEPS + 4];
} ew_fog;
/* The fog runs' loops by the instructions they use, chosen at run time
 * (the build assumes SSE2 alone): the build's four lanes (ew_simd.h),
 * AVX2, AVX-512 BW, and AVX-512 VBMI (a 256-entry byte table in four
 * registers).  Every level draws the same pixels. */
enum { EW_FOG_SIMD_BASE, EW_FOG_SIMD_AVX2, EW_FOG_SIMD_AVX512, EW_FOG_SIMD_VBMI };
/* The widest this processor has. */
int ew_fog_cpu_simd(void);
/* Fills the level table (once, at the renderer's creation); simd: the
 * processor's widest. */
void ew_fog_levels(ew_fog *f);
static inline int ew_fog_level(const ew_fog *f, float zi) {
    float q = f->w / (zi * zi);
    if (!(q < EW_FOG_QMAX)) return f->level[EW_FOG_QSTEPS];
    return f->level[(int)(q * EW_FOG_QSCALE)];
}
/* A true-colour pixel fogged by level k, exactly (no palette). */
static inline uint32_t ew_fog_rgba(const ew_fog *f, int k, uint32_t v) {
    int c[3], a = k * 256 / (EW_FOG_LEVELS - 1);
    ew_rgba_split(v, c);
    for (int i = 0; i < 3; i++) c[i] += ((f->rgb[i] - c[i]) * a) >> 8;
    return ew_rgba(c[0], c[1], c[2]);
}
/* src over dst at opacity a of 256. */
static inline uint32_t ew_blend_rgba(uint32_t src, uint32_t dst, int a) {
    int s[3], d[3];
    ew_rgba_split(src, s), ew_rgba_split(dst, d);
    for (int i = 0; i < 3; i++) d[i] += ((s[i] - d[i]) * a) >> 8;
    return ew_rgba(d[0], d[1], d[2]);
}

/* The sky's two layers made one for the frame (raster/sky.c), as the 1996
 * renderer composited its sky: a sky pixel then reads one texel, not one
 * of each layer.  The back layer lies at a fractional offset from the
 * front one, so one picture cannot hold it: a span segment's back layer
 * sits a whole number of texels E behind the front one (E the integer part
 * of the two 16.16 starts' difference, plus one where a pixel's fraction
 * borrows), and E takes at most three values w0..w0 + 2 across and down
 * in a frame.  So nine planes: front over back shifted by each pair, the
 * same pixels as reading both layers (test_sky). */
typedef struct ew_sky_comp {
    const ew_texture *tex;    /* the layers they were made of; NULL: none */
    int      w0;              /* the shifts w0, w0 + 1, w0 + 2 */
    uint8_t *planes;          /* 9 planes of (width / 2) x height: shift (w0 + a, w0 + b) at plane a + 3 b */
    size_t   cap;
} ew_sky_comp;
/* The planes for t at this scroll (ew_sky_scroll), made again only when t
 * or w0 changes: 0, or -1 for a sky the planes do not serve (not a power
 * of two, too large) or no memory, which the spans then draw layer by layer. */
int  ew_sky_comp_make(ew_sky_comp *sc, const ew_texture *t, float scroll);
void ew_sky_comp_free(ew_sky_comp *sc);

/* What the span drawers read, set once per frame. */
typedef struct ew_span_ctx {
    const ew_target *target;
    int            subdiv_shift;   /* perspective divide every 1 << shift pixels */
    const ew_view *view;           /* the sky's rays */
    float          sky_scroll;     /* sky layers' offset for this frame's time */
    const ew_sky_comp *sky_comp;   /* its layers made one (for sky_comp->tex), or NULL */
    int32_t        turb[128];      /* liquid warp for this frame's time */
    int            turb_phase;     /* the phase turb holds, plus 129 (0: none yet) */
    ew_fog         fog;            /* this frame's fog (table NULL: none) */
    const uint32_t *rgba;          /* true colour: the palette as pixels (sky, liquids) */
    const struct ew_twopass *tp;   /* two-pass lighting: the frame's inputs, and */
    const struct ew_tp_face *tp_faces;  /* per surface (EW_DRAW_TWOPASS spans) */
} ew_span_ctx;

/* raster/span.c, sky.c, turb.c: one span of each kind.  A band draws its
 * spans in the order the scan made them (row by row), so the frame is
 * written front to back in memory and the span list is read straight
 * through. */
void ew_draw_lit_span(const ew_span_ctx *c, const ew_span *sp, const ew_surf_draw *d);
void ew_draw_sky_span(const ew_span_ctx *c, const ew_span *sp, const ew_texture *t);
void ew_draw_turb_span(const ew_span_ctx *c, const ew_span *sp, const ew_gradients *g, const ew_texture *t);
void ew_draw_flat_span(const ew_span_ctx *c, const ew_span *sp);  /* black */
/* n spans, each by its surface's ew_surf_draw; with full_z the world's 1/z
 * goes under every span too (ew_set_full_zfill). */
void ew_draw_spans(const ew_span_ctx *c, const ew_span *spans, int n, const ew_surf_draw *draw, int full_z);
/* Once a surface's gradients are set: which drawer its spans take. */
void ew_span_prepare(ew_surf_draw *d);

/* Sky colour of one pixel (shared with the reference path). */
uint8_t ew_sky_pixel(const ew_view *v, const ew_texture *t, float u, float y);
/* The sky layers' offset in texels at a time (the back layer's; the front
 * one moves twice as far). */
float   ew_sky_scroll(double time);
/* *held: the phase the table holds plus 129 (0 = none); the table is only
 * computed again when the phase changes. */
void    ew_turb_table(int32_t table[128], int *held, double time);
uint8_t ew_turb_texel(const int32_t table[128], const ew_texture *t, int32_t s, int32_t tt);

/* Rows of the frame a drawing call may touch, and where its counters go:
 * moving things are drawn band by band, each band only in its own rows. */

/* raster/zpoly.c: the z-buffered polygon fill (reference path, item boxes) */
typedef struct ew_zpoly {
    int    n;
    float  u[EW_MAX_POLY], v[EW_MAX_POLY];
    float  nearzi;
    double sign;
    int    x0, y0, x1, y1;
} ew_zpoly;
/* raster/models.c: an item box this frame, projected once (in the models
 * pass's work) for every piece of the draw, which only fills. */
typedef struct ew_box_frame {
    int     frame;                  /* the frame it was prepared for: else not drawn */
    int     in_view;                /* a face has an area on screen */
    int     hidden;                 /* the world hides it (raster/models.c): not in view */
    int     y0, y1;                 /* the rows its faces reach */
    int     zrect, zx0, zy0, zx1, zy1;  /* one z-fill rectangle holds every face's */
    int     face0, nfaces;          /* its faces to fill, in ents.box_faces; face0 set by the reserve */
    int     dropped;                /* lit faces in view with no surface */
    ew_view mv;                     /* the camera in the box's space */
} ew_box_frame;
typedef struct ew_box_face {
    ew_zpoly zp;                    /* projected and oriented */
    int      face;                  /* of the box model */
} ew_box_face;

typedef struct ew_zpoly_look {
    const ew_world   *world;
    const ew_face    *face;
    const ew_view    *view;         /* the camera in the face's own space */
    const ew_texture *tex;          /* sky and liquids */
    const uint8_t    *surf;         /* lit surface (others) */
    int               surf_width, mip;
    int               stepped;      /* lit surfaces and liquids: a divide every 16 pixels as
                                       world spans (ew_stepper), not at every pixel */
    int               mode;         /* EW_ZP_* */
    const uint8_t    *blend;        /* EW_ZP_BLEND, 8-bit: [src * 256 + dst] */
    int               alpha256;     /* EW_ZP_BLEND, true colour: opacity of 256 */
} ew_zpoly_look;
enum {
    EW_ZP_OPAQUE,   /* z-tested, z-written (the default) */
    EW_ZP_FENCE,    /* the same, but texel 255 is a hole: nothing written there */
    EW_ZP_BLEND     /* z-tested, blended over what is there through look->blend, fogged at
                       its own depth first; no z written */
};
/* Clips (whole frustum) and projects a world-space polygon; 0 if nothing is left. */
int  ew_zpoly_project(const ew_view *v, float (*in)[3], int n, ew_zpoly *p);
/* Its two halves, for a caller that shares projected corners between
 * polygons no frustum plane cuts: one point's screen position and 1/z,
 * and the polygon of m such points (u, v and nearzi set) made ready to
 * fill; the same values as ew_zpoly_project's. */
void ew_zpoly_vertex(const ew_view *v, const float pt[3], float *u, float *vv, float *zi);
int  ew_zpoly_close(const ew_view *v, ew_zpoly *p, int m);
/* ew_zpoly_close in its two steps: the rectangle (n, x0 .. y1; 0 when it
 * holds no pixel centre) of the corners' extremes found by the caller (1e30
 * and -1e30 to start, taken with < and > in corner order), then the
 * orientation (0: no area, not drawn). */
int  ew_zpoly_rect(const ew_view *v, ew_zpoly *p, int m, float umin, float umax, float vmin, float vmax);
int  ew_zpoly_orient(ew_zpoly *p);
/* Fills it into the target where nearer, within rows [y0, y1); ids[pixel]
 * = id where it wins (ids may be NULL).  Returns the pixels won. */
long ew_zpoly_fill(const ew_span_ctx *c, const ew_zpoly *p, const ew_zpoly_look *look, int *ids, int id,
                   int y0, int y1);

/* See-through polygons of this frame (world/divert.c sorts them out of the
 * front end, raster/seethrough.c draws them): fences first, then the
 * translucent ones back to front.  kind: EW_SEE_* (frame.h). */
typedef struct ew_see_poly {
    ew_zpoly       p;           /* clipped and projected */
    ew_zpoly_look  look;        /* its texels and how it is drawn */
    int            face, key, kind;
    float          alpha;
} ew_see_poly;
typedef struct ew_see {
    ew_see_poly *polys; int n, cap;
    int         *order;  int cap_order;  /* fences, then translucent far to near */
    int          n_drawn, nfences;       /* in order[]: all, and the fences among them */
} ew_see;

struct ew_zfill;

/* raster/seethrough.c: fence textures (alpha-tested, z-written), then
 * translucent surfaces (blended far to near, no z), as the front end
 * collected them (world/divert.c). */
struct ew_lit;
void ew_see_prepare(ew_see *see, ew_frame *f, struct ew_lit *lit);
/* Adds face fi's world-space polygon (seen through v, the camera in the
 * face's space) to the see-through list with its BSP key, clipped and
 * projected (the front end's ew_front_out.see); at most max_polys (the edge
 * list's budget), the rest counted in dropped. */
void ew_see_add(ew_see *see, ew_frame *f, int max_polys, float (*verts)[3], int n, int fi, const ew_view *v,
                int key, int kind, float alpha);
void ew_draw_fences(const ew_see *see, const ew_frame *f, const ew_span_ctx *draw, struct ew_zfill *zf,
                    const ew_rows *rows);
void ew_draw_translucent(const ew_see *see, const ew_frame *f, const ew_span_ctx *draw, struct ew_zfill *zf,
                         const ew_rows *rows);

/* raster/fog.c: fog over what is opaque by its depth (the translucent
 * surfaces fog their own texels as they blend).  The prepare sets this
 * frame's fog (fog->table NULL: none); may_fill: the span draw may leave
 * out the texels fog covers whole (not in the debug views, nor with the
 * full z-fill, whose z the drawers write). */
void ew_fog_prepare(ew_span_ctx *draw, ew_frame *f, ew_blend *blend, int may_fill);
/* ew_draw_spans for a frame with fog->fill: a span, or the end of one, that
 * fog covers whole is filled with the fog colour instead of drawn, and the
 * rest is fogged as soon as drawn (unless the band is unsorted: its spans
 * overlap, and the fog pass finds each pixel's top one).  The span is cut
 * only where its drawer's pixels before the cut stay the same (after a
 * whole segment), so the fogged frame is the same.  Returns the pixels it
 * fogged or filled (the stats' fog_pixels; 0 for an unsorted band, which
 * ew_draw_fog counts), so the fog pass need not walk those spans again. */
long ew_fog_draw_spans(const ew_span_ctx *c, const ew_span *spans, int n, const ew_surf_draw *draw, int full_z,
                       int unsorted);
void ew_draw_fog(const ew_fog *fog, const ew_target *t, struct ew_zfill *zf, const ew_surf_draw *surf_draw,
                 const ew_rows *rows);

/* raster/warp.c: the underwater view, after every band is drawn (it reads
 * rows of other bands): the frame warped and tinted by the liquid the eye
 * is in, from a copy of it.  ew_warp_begin (serial) returns 0 when there
 * is nothing to do. */
typedef struct ew_warp {
    uint8_t       *copy;            /* the source frame, then per row its x shift, per column its y shift */
    const uint8_t *tint;            /* 8-bit: the tint table this frame */
    int            rgb[3], amount;  /* true colour: the tint itself */
} ew_warp;
int  ew_warp_begin(ew_warp *w, ew_frame *f, ew_blend *blend);
void ew_warp_rows(const ew_warp *w, const ew_target *t, int y0, int y1);
void ew_warp_free(ew_warp *w);

#endif
