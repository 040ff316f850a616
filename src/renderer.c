/* The renderer context and the frame: the front end (PVS, BSP walk) hands
 * visible faces to the hidden-surface method, each band is resolved into
 * spans, the lit surfaces they need are built, then each band draws its
 * spans and the passes over the world (renderer.h, docs/architecture.md). */
#include "renderer.h"
#include "ew_util.h"
#include "overlay/overlay.h"
#include "asset/scene.h"
#include "world/edge_math.h"  /* ew_proj */

#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void front_face(void *ctx, int fi, int clipflags, int key);
static void front_poly(void *ctx, float (*verts)[3], int n, int fi, const ew_view *v, int key);
static void front_see(void *ctx, float (*verts)[3], int n, int fi, const ew_view *v, int key, int kind, float alpha);
static void front_entity_light(void *ctx, const float origin[3], ew_ent_frame *ef);

#define EW_MIN_W 320
#define EW_MIN_H 200
#define EW_MAX_W 7680
#define EW_MAX_H 4320

/* ---- what the hidden-surface method sees of the frame (hsr/hsr.h) ---- */

/* The edge list's own face and polygon (world/edges.c), which the edge
 * list's methods emit. */
static void hsr_emit_face(void *owner, int face, int clipflags, int key) {
    ew_renderer *r = owner;
    ew_front_face(&r->front, face, clipflags, key);
}
static void hsr_emit_poly(void *owner, float (*verts)[3], int n, int fi, const ew_view *v, int key) {
    ew_renderer *r = owner;
    ew_front_poly(&r->front, verts, n, fi, v, key);
}
/* A lit surface looked up, and built at once if new (the reference's
 * polygons and see-through surfaces: serial). */
static const uint8_t *hsr_lit_surface(void *owner, int face, int mip, int *width) {
    ew_renderer *r = owner;
    int build;
    ew_cached_surf *e = ew_lit_lookup(&r->lit, &r->f, face, mip, &build);
    if (!e) return NULL;
    if (build) ew_lit_build(&r->lit, &r->f, e, r->lit.blocklights);
    *width = e->width;
    return e->pixels;
}
/* Filled once a frame, before the method's begin (and once at creation). */
static void hsr_ctx_setup(ew_renderer *r) {
    ew_hsr_ctx *c = &r->hsr;
    c->f = &r->f, c->el = &r->el;
    c->bands = r->sched.bands, c->nbands = r->sched.nbands;
    c->draw = &r->draw, c->tp = &r->lit.tp, c->see = &r->see;
    c->debug = r->dbg.mode != 0;
    c->owner = r;
    c->emit_face = hsr_emit_face, c->emit_poly = hsr_emit_poly, c->lit_surface = hsr_lit_surface;
}

/* Checks desc and fills in its defaults; 0, or -1 with err set. */
static int resolve_desc(const ew_renderer_desc *in, ew_renderer_desc *d, ew_error *err) {
    if (!in) return ew_fail(err, "renderer: no description");
    *d = *in;
    if (!d->world || !d->palette || !d->colormap)
        return ew_fail(err, "renderer: no world, palette or colormap");
    if (!d->width && !d->height) d->width = 640, d->height = 480;
    if (d->width < EW_MIN_W || d->height < EW_MIN_H || d->width > EW_MAX_W || d->height > EW_MAX_H)
        return ew_fail(err, "renderer: frame size %dx%d outside %dx%d..%dx%d", d->width, d->height,
                       EW_MIN_W, EW_MIN_H, EW_MAX_W, EW_MAX_H);
    if (d->threads < 0)
        return ew_fail(err, "renderer: threads %d (0 for one per core, else 1..)", d->threads);
    if (!d->subdivision) d->subdivision = 16;
    int pow2 = 0;
    for (int shift = 0; shift <= 5; shift++) pow2 |= d->subdivision == 1 << shift;
    if (!pow2)
        return ew_fail(err, "renderer: subdivision %d (1, 2, 4, 8, 16 or 32)", d->subdivision);
    if (d->cache_mb < 0 || d->cache_mb > 65536)
        return ew_fail(err, "renderer: cache_mb %d (0 for automatic, else 1..65536)", d->cache_mb);
    if (d->color != EW_COLOR_8BIT && d->color != EW_COLOR_TRUE)
        return ew_fail(err, "renderer: unknown colour mode %d", (int)d->color);
    if (!ew_hsr_get((int)d->hsr))
        return ew_fail(err, "renderer: hidden-surface method %d is not one this build has", (int)d->hsr);
    if (d->alias_raster < EW_ALIAS_AUTO || d->alias_raster > EW_ALIAS_SPRITE_CACHE)
        return ew_fail(err, "renderer: unknown alias rasterizer %d", (int)d->alias_raster);
    if (!(d->alias_threshold >= 0 && d->alias_threshold < 1e6f))
        return ew_fail(err, "renderer: alias threshold %g (0 for 40 pixels)", (double)d->alias_threshold);
    if (!d->alias_threshold) d->alias_threshold = 40;
    return 0;
}

ew_renderer *ew_renderer_create(const ew_renderer_desc *desc, ew_error *err) {
    ew_renderer_desc d = { 0 };
    if (resolve_desc(desc, &d, err) < 0) return NULL;
    const ew_world *w = d.world;
    int width = d.width, height = d.height;
    /* Aligned: the scheduler's counters sit on cache lines of their own. */
    ew_renderer *r = aligned_alloc(_Alignof(ew_renderer), (sizeof(ew_renderer) + 63) / 64 * 64);
    if (!r) goto oom;
    memset(r, 0, sizeof *r);
    r->f.world = w, r->f.palette = d.palette, r->f.colormap = d.colormap;
    for (int i = 0; i < 64; i++) r->f.cfg.lightstyle[i] = 256;  /* until the first frame (light/styles.c) */
    ew_set_gamma(r, 1);
    ew_set_subdivision(r, d.subdivision);                      /* checked: 1..32, a power of two */
    r->f.cfg.alias_raster = d.alias_raster;
    r->f.cfg.alias_threshold = d.alias_threshold;
    r->f.cfg.hsr = ew_hsr_get((int)d.hsr);
    r->f.cfg.classic = d.classic != 0;
    r->f.cfg.liquid_alpha = -1, r->f.cfg.fog_density = -1;  /* the map's */
    r->f.cfg.waterwarp = 1;
    r->f.cfg.hide_occluded = 1;
    /* The frame target: 8-bit palette indices or 32-bit pixels, rows one
     * after another. */
    r->f.target.width = width, r->f.target.height = height;
    r->f.target.bpp = d.color == EW_COLOR_TRUE ? 4 : 1;
    r->f.target.pitch = width * r->f.target.bpp;
    r->f.target.rgba = r->lit.curve.rgba;
    r->f.cfg.use_lit = 1;
    r->draw.target = r->zf.target = &r->f.target;
    r->draw.view = &r->f.view;

    /* Budgets grow with the frame (more pixels can show more polygons) and
     * with the world: a frame may show every face of a map at once (the
     * stress hall of `edgewise hsr --stress` puts 20,000 in view at 320x200). */
    long px = (long)width * height;
    r->el.max_surfs = (int)(4096 + (px / 256 > w->numfaces ? px / 256 : w->numfaces));
    if (r->el.max_surfs > 65535) r->el.max_surfs = 65535;  /* surface numbers are 16-bit */
    r->el.max_edges = r->el.max_surfs * 6;
    int max_spans = height * 192;

    r->f.target.pixels = malloc((size_t)px * (size_t)r->f.target.bpp);
    r->f.target.zbuf = malloc(sizeof(float) * (size_t)px);
    r->marks.leaf_frame = calloc((size_t)w->numleaves + 1, sizeof(int));
    r->marks.node_frame = calloc((size_t)w->numnodes + 1, sizeof(int));
    r->marks.leaf_up = malloc(sizeof(int) * ((size_t)w->numleaves + 1));
    r->marks.node_up = malloc(sizeof(int) * ((size_t)w->numnodes + 1));
    r->marks.vis = malloc(sizeof(int) * ((size_t)w->numleaves + 2));
    r->marks.face_frame = calloc((size_t)w->numfaces + 1, sizeof(int));
    r->marks.leaf_key = calloc((size_t)w->numleaves + 1, sizeof(int));
    r->marks.leaf_keyframe = calloc((size_t)w->numleaves + 1, sizeof(int));
    r->marks.face_dlframe = calloc((size_t)w->numfaces + 1, sizeof(int));
    r->marks.face_dlbits = calloc((size_t)w->numfaces + 1, sizeof(unsigned));
    r->marks.edge_cache_frame = calloc((size_t)w->numedges + 1, sizeof(int));
    r->marks.edge_cache_index = calloc((size_t)w->numedges + 1, sizeof(int));
    r->marks.edge_cache_down = calloc((size_t)w->numedges + 1, 1);
    r->marks.vert_frame = calloc((size_t)w->numverts + 1, sizeof(int));
    r->marks.vert_proj = malloc(sizeof(ew_proj) * ((size_t)w->numverts + 1));
    r->el.edges = malloc(sizeof(ew_edge) * r->el.max_edges);
    r->el.row_first = malloc(sizeof(int32_t) * (size_t)(height + 2));
    r->el.by_row = malloc(sizeof(int32_t) * r->el.max_edges);
    r->el.by_row_last = malloc(sizeof(int32_t) * r->el.max_edges);
    r->el.surfs = malloc(sizeof(ew_surf) * r->el.max_surfs);
    r->el.max_spans = max_spans;
    r->sched.row_cost = malloc(sizeof(float) * ((size_t)height + 1));
    r->zf.row_band = calloc((size_t)height, sizeof(int32_t));
    r->zf.row_span0 = calloc((size_t)height, sizeof(int32_t));
    r->zf.row_nspans = calloc((size_t)height, sizeof(int32_t));
    r->zf.zlo = calloc((size_t)height, sizeof(int32_t));
    r->zf.zhi = calloc((size_t)height, sizeof(int32_t));
    if (!r->f.target.pixels || !r->f.target.zbuf || !r->marks.leaf_frame || !r->marks.node_frame || !r->marks.vis ||
        !r->marks.leaf_up || !r->marks.node_up ||
        !r->marks.face_frame ||
        !r->marks.leaf_key || !r->marks.leaf_keyframe || !r->marks.face_dlframe || !r->marks.face_dlbits ||
        !r->marks.edge_cache_frame || !r->marks.edge_cache_index || !r->marks.edge_cache_down || !r->el.edges ||
        !r->marks.vert_frame || !r->marks.vert_proj ||
        !r->el.row_first || !r->el.by_row || !r->el.by_row_last || !r->el.surfs || !r->sched.row_cost ||
        !r->zf.row_band || !r->zf.row_span0 || !r->zf.row_nspans || !r->zf.zlo || !r->zf.zhi)
        goto oom;
    for (int i = 0; i < w->numleaves; i++) r->marks.leaf_up[i] = w->leaves[i].parent;
    for (int i = 0; i < w->numnodes; i++) r->marks.node_up[i] = w->nodes[i].parent;
    /* The cache holds many frames' worth of surfaces at this size, so a
     * walk through a level rebuilds little (16 bytes a pixel, 16..512 MiB),
     * unless the caller chose a size. */
    size_t budget = (size_t)px * 16;
    if (budget < ((size_t)16 << 20)) budget = (size_t)16 << 20;
    if (budget > ((size_t)512 << 20)) budget = (size_t)512 << 20;
    budget *= (size_t)r->f.target.bpp;  /* true colour: 4 bytes a texel, as many surfaces */
    if (d.cache_mb) budget = (size_t)d.cache_mb << 20;
    if (ew_lit_init(&r->lit, w, d.palette, d.colormap, r->el.max_surfs, budget, r->f.target.bpp) < 0) goto oom;
    /* How each surface's spans are drawn: the draw's type (raster/raster.h),
     * one a surface of the list, beside the light's findings. */
    if (!(r->lit.surf_draw = calloc((size_t)r->el.max_surfs, sizeof *r->lit.surf_draw))) goto oom;
    r->zf.draw = r->lit.surf_draw;
    ew_fog_levels(&r->draw.fog);
    if (ew_blend_init(&r->blend, d.palette) < 0) goto oom;
    if (ew_front_init(&r->front, &r->f, &r->marks, &r->el, width, height) < 0) goto oom;
    r->front.out = (ew_front_out){r, 0, 0, front_face, front_poly, front_see, front_entity_light};
    if (ew_set_threads(r, d.threads) < 0) goto oom;
    ew_debug_init(&r->dbg, &r->f, &r->lit.curve);
    r->lit.marks = &r->marks, r->lit.blend = &r->blend, r->lit.dbg = &r->dbg;
    r->models = (ew_models){&r->ents, &r->marks, &r->el, &r->zf, &r->draw, &r->lit};
    r->passes.ctx = (ew_pass_ctx){
        .f = &r->f, .draw = &r->draw, .zf = &r->zf, .blend = &r->blend, .see = &r->see,
        .warp = &r->warp, .dbg = &r->dbg, .el = &r->el, .lit = &r->lit, .models = &r->models, .hsr = &r->hsr,
        .front = &r->front,
    };
    hsr_ctx_setup(r);
    return r;
oom:
    ew_renderer_destroy(r);
    ew_fail(err, "renderer: out of memory for a %dx%d frame", width, height);
    return NULL;
}

static void free_bands(ew_renderer *r) {
    ew_pool_free(r->sched.pool);
    r->sched.pool = NULL;
    for (int i = 0; i < r->sched.nbands; i++) ew_band_free(&r->sched.bands[i]);
    free(r->sched.bands);
    free(r->sched.items);
    r->sched.bands = NULL;
    r->sched.items = NULL;
    r->zf.bands = NULL;
    r->sched.nbands = 0;
    r->sched.nthreads = 0;
    ew_lit_threads(&r->lit, 0);
}

int ew_set_threads(ew_renderer *r, int n) {
    if (n <= 0) n = ew_pool_cores();
    if (n > EW_MAX_THREADS) n = EW_MAX_THREADS;
    if (r->sched.nbands) ew_zfill_rect(&r->zf, 0, 0, r->f.target.width, r->f.target.height);  /* the last frame's, while its spans exist */
    free_bands(r);
    /* The old bands' spans are gone, and the z-buffer is complete. */
    memset(r->zf.row_nspans, 0, sizeof(int32_t) * (size_t)r->f.target.height);
    ew_zfill_mark_all(&r->zf);
    /* A pool even for one thread (no workers): it times the parallel
     * sections (ew_stats.ms_serial is the rest). */
    r->sched.pool = ew_pool_create(n);
    n = r->sched.pool ? ew_pool_threads(r->sched.pool) : 1;
    /* One band alone; with threads, several each (at least 8 rows a band),
     * so a thread that finishes early takes the next band instead of idling,
     * and finer pieces for the draw (bands.c).  The row profile: strips of
     * 8 rows, drawn as they were scanned (the items are the bands then, as
     * in the debug views). */
    int nb, ni;
    ew_frame_cuts(n, r->f.target.height, &nb, &ni);
    if (r->sched.profile_rows) nb = ni = r->f.target.height / 8;
    /* Aligned like ew_band, so no two bands' counters share a cache line. */
    r->sched.bands = aligned_alloc(_Alignof(ew_band), sizeof(ew_band) * (size_t)nb);
    r->sched.max_items = ni;
    r->sched.items = aligned_alloc(_Alignof(ew_draw_item), sizeof(ew_draw_item) * (size_t)ni);
    if (!r->sched.bands || !r->sched.items || ew_lit_threads(&r->lit, n) < 0) return -1;
    memset(r->sched.items, 0, sizeof(ew_draw_item) * (size_t)ni);
    memset(r->sched.bands, 0, sizeof(ew_band) * (size_t)nb);
    r->zf.bands = r->sched.bands;
    r->sched.nthreads = n;
    r->sched.nbands = nb;
    for (int i = 0; i < nb; i++)
        if (ew_band_init(&r->sched.bands[i], r->el.max_surfs, r->el.max_spans) < 0) return -1;
    r->sched.bands_sized_for = 0;  /* no cost history for these bands yet */
    return n;
}

int ew_get_threads(const ew_renderer *r) { return r->sched.nthreads; }

void ew_renderer_destroy(ew_renderer *r) {
    if (!r) return;
    free(r->lit.surf_draw), r->lit.surf_draw = NULL;
    ew_lit_free(&r->lit);
    free_bands(r);
    free(r->sched.row_cost);
    free(r->zf.row_band), free(r->zf.row_span0), free(r->zf.row_nspans), free(r->zf.zlo), free(r->zf.zhi);
    free(r->f.target.pixels), free(r->f.target.zbuf), free(r->f.face_ids);
    free(r->marks.leaf_frame), free(r->marks.node_frame), free(r->marks.face_frame), free(r->marks.vis);
    free(r->marks.leaf_up), free(r->marks.node_up);
    free(r->marks.leaf_key), free(r->marks.leaf_keyframe), free(r->ents.ent_views), free(r->ents.ent_frame);
    ew_box_surfs_free(r->ents.box_surfs, r->ents.nbox_surfs);
    free(r->marks.face_dlframe), free(r->marks.face_dlbits);
    free(r->marks.edge_cache_frame), free(r->marks.edge_cache_index), free(r->marks.edge_cache_down);
    free(r->marks.vert_frame), free(r->marks.vert_proj);
    free(r->el.edges), free(r->el.row_first), free(r->el.by_row), free(r->el.by_row_last);
    free(r->el.surfs);
    ew_hsr_ctx_free(&r->hsr);
    free(r->see.polys), free(r->see.order);
    ew_warp_free(&r->warp);
    ew_blend_free(&r->blend);
    ew_sky_comp_free(&r->sky);
    ew_debug_free(&r->dbg);
    ew_front_free(&r->front);
    free(r->ents.xf), free(r->ents.xverts), free(r->ents.alias_list);
    free(r->ents.box_frame), free(r->ents.box_faces), free(r->ents.box_list);
    ew_sprite_cache_free(r->ents.sprite_cache);
    free(r->ents.tint_rgba), free(r->ents.tint_remap);
    free(r);
}

int ew_frame_width(const ew_renderer *r) { return r->f.target.width; }
int ew_frame_height(const ew_renderer *r) { return r->f.target.height; }
const uint8_t *ew_frame_pixels(const ew_renderer *r) { return r->f.target.bpp == 1 ? r->f.target.pixels : NULL; }
const uint32_t *ew_frame_rgba(const ew_renderer *r) {
    return r->f.target.bpp == 4 ? (const uint32_t *)(const void *)r->f.target.pixels : NULL;
}
ew_color_mode ew_frame_color(const ew_renderer *r) { return r->f.target.bpp == 4 ? EW_COLOR_TRUE : EW_COLOR_8BIT; }

int ew_write_frame_png(const ew_renderer *r, const char *path, ew_error *err) {
    if (r->f.target.bpp == 4)
        return ew_write_png_rgba(path, ew_frame_rgba(r), r->f.target.width, r->f.target.height, err);
    return ew_write_png(path, r->f.target.pixels, r->f.target.width, r->f.target.height, ew_frame_palette(r), err);
}

/* Surfaces built with the old setting are rebuilt (their cache entries
 * no longer match). */
static void relight(ew_renderer *r) { r->lit.cache.gen++; }
void ew_set_lit(ew_renderer *r, int on) {
    if (r->f.cfg.use_lit != (on != 0)) r->f.cfg.use_lit = on != 0, relight(r);
}
void ew_set_dither(ew_renderer *r, int on) {
    if (r->f.cfg.dither != (on != 0)) r->f.cfg.dither = on != 0, relight(r);
}

const float *ew_frame_zbuffer(ew_renderer *r) {
    ew_zfill_rect(&r->zf, 0, 0, r->f.target.width, r->f.target.height);  /* the rest of the world's 1/z */
    return r->f.target.zbuf;
}

void ew_set_lighting(ew_renderer *r, ew_lighting_mode mode) {
    r->f.cfg.lighting = mode == EW_LIGHTING_TWO_PASS ? EW_LIGHTING_TWO_PASS : EW_LIGHTING_CACHE;
}
ew_lighting_mode ew_get_lighting(const ew_renderer *r) { return (ew_lighting_mode)r->f.cfg.lighting; }
void ew_set_light_fault(ew_renderer *r, ew_light_fault fault) {
    if (r->f.cfg.light_fault != (int)fault) relight(r);
    r->f.cfg.light_fault = fault;
}
void ew_flush_surfaces(ew_renderer *r) { ew_cache_flush(&r->lit.cache); }
/* Two-pass lighting wants it for every lit surface of the frame. */
static int two_pass(const ew_renderer *r) { return r->f.cfg.lighting == EW_LIGHTING_TWO_PASS && !r->dbg.mode; }
void ew_set_full_zfill(ew_renderer *r, int on) { r->zf.all = on != 0; }
ew_simd_level ew_set_simd(ew_renderer *r, ew_simd_level level) {
    static const int cap[] = {[EW_SIMD_BEST] = EW_FOG_SIMD_VBMI, [EW_SIMD_BASE] = EW_FOG_SIMD_BASE,
                              [EW_SIMD_AVX2] = EW_FOG_SIMD_AVX2, [EW_SIMD_AVX512] = EW_FOG_SIMD_VBMI};
    int has = ew_fog_cpu_simd(), want = (unsigned)level <= EW_SIMD_AVX512 ? cap[level] : has;
    r->draw.fog.simd = want < has ? want : has;
    return r->draw.fog.simd >= EW_FOG_SIMD_AVX512 ? EW_SIMD_AVX512
         : r->draw.fog.simd == EW_FOG_SIMD_AVX2   ? EW_SIMD_AVX2
                                                  : EW_SIMD_BASE;
}
static const char *const simd_names[] = {"best", "sse2", "avx2", "avx512"};
const char *ew_simd_name(ew_simd_level level) {
    return (unsigned)level <= EW_SIMD_AVX512 ? simd_names[level] : NULL;
}
int ew_simd_from_name(const char *name) {
    for (int k = 0; name && k <= EW_SIMD_AVX512; k++)
        if (!strcmp(name, simd_names[k])) return k;
    return -1;
}
void ew_set_hide_occluded(ew_renderer *r, int on) { r->f.cfg.hide_occluded = on != 0; }
void ew_set_front_mode(ew_renderer *r, ew_front_mode mode) { r->f.cfg.front_phases = mode == EW_FRONT_PHASES; }
void ew_set_occlusion_cull(ew_renderer *r, ew_occlusion_mode mode) {
    r->front.occ.mode = mode == EW_OCCLUSION_OFF || mode == EW_OCCLUSION_ALWAYS ? mode : EW_OCCLUSION_AUTO;
}
const int *ew_frame_face_ids(const ew_renderer *r) { return r->f.face_ids; }

/* Light styles: each frame's values come from these settings (ew_frame_begin). */
void ew_set_lightstyle(ew_renderer *r, int style, int value) {
    if (style < 0 || style >= 64) return;
    r->f.cfg.style_set[style].mode = EW_STYLE_FIXED;
    r->f.cfg.style_set[style].value = value < 0 ? 0 : value > 1024 ? 1024 : value;
    r->f.cfg.lightstyle[style] = r->f.cfg.style_set[style].value;  /* the same any time: at once */
}
int ew_set_lightstyle_pattern(ew_renderer *r, int style, const char *pattern) {
    if (style < 0 || style >= 64 || !ew_style_pattern_ok(pattern)) return -1;
    ew_style_setting *st = &r->f.cfg.style_set[style];
    st->mode = EW_STYLE_PATTERN;
    snprintf(st->pattern, sizeof st->pattern, "%s", pattern);
    return 0;
}
int ew_set_lightstyle_switch(ew_renderer *r, int style, int on) {
    return ew_set_lightstyle_pattern(r, style, on ? "m" : "a");
}
void ew_reset_lightstyle(ew_renderer *r, int style) {
    if (style >= 0 && style < 64) memset(&r->f.cfg.style_set[style], 0, sizeof r->f.cfg.style_set[style]);
}
int ew_get_lightstyle(const ew_renderer *r, int style) {
    return style >= 0 && style < 64 ? r->f.cfg.lightstyle[style] : -1;
}

int ew_set_gamma(ew_renderer *r, float gamma) {
    if (!(gamma >= 0.5f && gamma <= 3.0f)) return -1;  /* NaN too */
    r->f.cfg.gamma = gamma;
    ew_gamma_table(gamma, r->f.cfg.gamma_lut);
    for (int i = 0; i < 768; i++) r->f.cfg.gamma_palette[i] = r->f.cfg.gamma_lut[r->f.palette[i]];
    return 0;
}
float ew_get_gamma(const ew_renderer *r) { return r->f.cfg.gamma; }
const uint8_t *ew_frame_palette(const ew_renderer *r) { return r->f.cfg.gamma_palette; }

int ew_set_subdivision(ew_renderer *r, int pixels) {
    for (int shift = 0; shift <= 5; shift++)
        if (pixels == 1 << shift) {
            r->f.cfg.subdiv_shift = shift;
            return 0;
        }
    return -1;
}

int ew_set_hsr(ew_renderer *r, ew_hsr_method method) {
    const ew_hsr *h = ew_hsr_get((int)method);
    if (!h) return -1;
    r->f.cfg.hsr = h;
    return 0;
}

void ew_set_classic(ew_renderer *r, int on) {
    if (r->f.cfg.classic != (on != 0)) r->f.cfg.classic = on != 0, relight(r);  /* .lit off in classic */
}
void ew_set_waterwarp(ew_renderer *r, int on) { r->f.cfg.waterwarp = on != 0; }

void ew_set_liquid_alpha(ew_renderer *r, float alpha) {
    r->f.cfg.liquid_alpha = alpha < 0 ? -1 : alpha > 1 ? 1 : alpha > 0.0625f ? alpha : 0.0625f;  /* NaN: the map's; the finest 8-bit step at least */
    if (!(alpha == alpha)) r->f.cfg.liquid_alpha = -1;
}

void ew_set_fog(ew_renderer *r, float density, float red, float green, float blue) {
    if (!(density >= 0) || !(density < 1e6f)) {  /* negative or NaN: the map's */
        r->f.cfg.fog_density = -1;
        return;
    }
    r->f.cfg.fog_density = density;
    const float c[3] = {red, green, blue};
    for (int k = 0; k < 3; k++) r->f.cfg.fog_rgb[k] = c[k] >= 0 ? (c[k] <= 1 ? c[k] : 1) : 0;
}

void ew_set_alias_raster(ew_renderer *r, ew_alias_raster mode, float threshold_px) {
    r->f.cfg.alias_raster = mode;
    if (threshold_px > 0 && threshold_px < 1e6f) r->f.cfg.alias_threshold = threshold_px;
}

void ew_enable_face_ids(ew_renderer *r, int on) {
    r->f.cfg.face_ids_on = on;
    if (on && !r->f.face_ids) r->f.face_ids = malloc(sizeof(int) * (size_t)r->f.target.width * r->f.target.height);
    if (!r->f.face_ids) r->f.cfg.face_ids_on = 0;
}

int ew_draw_text(ew_renderer *r, int x, int y, int scale, const char *text, const ew_text_style *style) {
    return r ? ew_text_draw(&r->f.target, r->f.palette, x, y, scale, text, style) : -1;
}
int ew_draw_stats_overlay(ew_renderer *r, const ew_stats *st, const ew_overlay_info *extra) {
    return r ? ew_stats_overlay_draw(&r->f.target, r->f.palette, st, extra) : -1;
}

void ew_set_scene(ew_renderer *r, const ew_scene *s) {
    if (s != r->ents.scene) {  /* the same scene again (its entities changed): its models stay */
        ew_box_surfs_free(r->ents.box_surfs, r->ents.nbox_surfs);  /* they belong to the old scene's models */
        r->ents.box_surfs = NULL, r->ents.nbox_surfs = 0;
    }
    r->ents.scene = r->lit.scene = s;
    int need = s ? s->nents : 0;
    if (need > r->ents.max_ent_views) {
        ew_view *v = realloc(r->ents.ent_views, sizeof *v * (size_t)need);
        if (v) r->ents.ent_views = v, r->ents.max_ent_views = need;
    }
}

/* The whole frame's rows of a model (the tests' calls, renderer.h). */
int ew_draw_alias(ew_renderer *r, const ew_mdl *m, const ew_model_pose *p) {
    ew_rows all = {0, r->f.target.height, &r->f.stats, 1};
    return ew_draw_alias_rows(&r->f, &r->zf, m, p, &all);
}
int ew_draw_sprite(ew_renderer *r, const ew_spr *s, const ew_model_pose *p) {
    ew_rows all = {0, r->f.target.height, &r->f.stats, 1};
    return ew_draw_sprite_rows(&r->f, &r->zf, s, p, &all);
}
void ew_draw_particles(ew_renderer *r, const ew_particle *p, int n) {
    ew_rows all = {0, r->f.target.height, &r->f.stats, 1};
    ew_draw_particles_rows(&r->f, &r->zf, p, n, &all);
}

int ew_set_debug(ew_renderer *r, ew_debug_mode mode) {
    int rc = ew_debug_set(&r->dbg, &r->f.target, (int)mode);
    if (rc > 0) r->lit.cache.gen++;  /* surfaces of another mode are never served */
    return rc < 0 ? -1 : 0;
}
ew_debug_mode ew_get_debug(const ew_renderer *r) { return (ew_debug_mode)r->dbg.mode; }
void ew_set_pvs_lock(ew_renderer *r, int on) { ew_debug_pvs_lock(&r->dbg, on); }

static int camera_ok(const ew_camera *c) {
    for (int i = 0; i < 3; i++)
        if (!isfinite(c->origin[i]) || !isfinite(c->angles[i]) || fabsf(c->origin[i]) > 1e6f) return 0;
    return isfinite(c->fov) && c->fov >= 0 && c->fov < 179 && isfinite(c->time);
}

/* Whether a scene has a dynamic light that is not white. */
static int coloured_dlights(const struct ew_scene *sc) {
    for (int i = 0; sc && i < sc->ndlights; i++)
        if (sc->dlights[i].color[0] != sc->dlights[i].color[1] || sc->dlights[i].color[1] != sc->dlights[i].color[2])
            return 1;
    return 0;
}

/* The front end's way up (world/front.h's ew_front_out): the method's
 * faces and polygons, the see-through pass, an entity's light. */
static void front_face(void *ctx, int fi, int clipflags, int key) {
    ew_renderer *r = ctx;
    r->f.cfg.hsr->face(&r->hsr, fi, clipflags, key);
}
static void front_poly(void *ctx, float (*verts)[3], int n, int fi, const ew_view *v, int key) {
    ew_renderer *r = ctx;
    r->f.cfg.hsr->poly(&r->hsr, verts, n, fi, v, key);
}
static void front_see(void *ctx, float (*verts)[3], int n, int fi, const ew_view *v, int key, int kind, float alpha) {
    ew_renderer *r = ctx;
    ew_see_add(&r->see, &r->f, (int)r->el.max_surfs, verts, n, fi, v, key, kind, alpha);
}
static void front_entity_light(void *ctx, const float origin[3], ew_ent_frame *ef) {
    const ew_renderer *r = ctx;
    ew_light_model(&r->f, r->ents.scene, origin, &ef->ambient, &ef->shade);
    ef->tinted = ew_light_tint(&r->f, origin, ef->tint);
}

/* The last parallel run's times added to the frame's probes
 * (ew_lab_stats.ms_run_*, kind EW_RUN_*). */
static void note_run(ew_renderer *r, int kind) {
    double wall, busy;
    ew_pool_last_run(r->sched.pool, &wall, &busy);
    r->lab.ms_run_wall[kind] += wall, r->lab.ms_run_busy[kind] += busy;
}

/* A parallel run of the frame's, timed (note_run). */
static void run_timed(ew_renderer *r, int kind, void (*job)(void *ctx, int thread)) {
    ew_pool_run(r->sched.pool, job, r);
    note_run(r, kind);
}

/* This frame's inputs of the front end: what the method takes, the
 * threads, the scene and room for its entities' answers. */
static void front_inputs(ew_renderer *r) {
    ew_front *fr = &r->front;
    const ew_hsr *h = r->f.cfg.hsr;
    fr->out.edge_list = (h->flags & EW_HSR_EDGE_LIST) != 0;
    fr->out.fences = (h->flags & EW_HSR_FENCES) != 0;
    fr->pool = r->sched.pool, fr->nthreads = r->sched.nthreads, fr->profile_rows = r->sched.profile_rows;
    fr->scene = r->ents.scene;
    fr->ent_views = r->ents.ent_views, fr->max_ent_views = r->ents.max_ent_views;
    fr->ms_front_items = 0;
    fr->ent_frame = r->ents.scene && ew_reserve_entities(&r->ents) == 0 ? r->ents.ent_frame : NULL;
}

static void job_cube(void *ctx, int thread) {
    ew_renderer *r = ctx;
    (void)thread;
    for (int k; (k = atomic_fetch_add(&r->sched.next_cube, 1)) < 64;) ew_blend_cube_slice(&r->blend, k);
}

/* Starts a frame: new frame number (resetting the marks if it wraps), view,
 * the span drawers' tables, the hidden-surface method, the PVS. */
int ew_frame_begin(ew_renderer *r, const ew_camera *cam) {
    if (!camera_ok(cam)) return -1;
    const ew_world *w = r->f.world;
    if (++r->marks.framecount == INT32_MAX) {
        memset(r->marks.leaf_frame, 0, sizeof(int) * (size_t)w->numleaves);
        memset(r->marks.node_frame, 0, sizeof(int) * (size_t)w->numnodes);
        memset(r->marks.face_frame, 0, sizeof(int) * (size_t)w->numfaces);
        memset(r->marks.leaf_keyframe, 0, sizeof(int) * (size_t)w->numleaves);
        memset(r->marks.face_dlframe, 0, sizeof(int) * (size_t)w->numfaces);
        memset(r->marks.edge_cache_frame, 0, sizeof(int) * (size_t)w->numedges);
        memset(r->marks.vert_frame, 0, sizeof(int) * (size_t)w->numverts);
        r->marks.framecount = 1;
    }
    memset(&r->f.stats, 0, sizeof r->f.stats);
    memset(&r->lab, 0, sizeof r->lab);
    ew_styles_frame(r->f.cfg.lightstyle, r->f.cfg.style_set, w->styles_start_off, r->f.cfg.classic, cam->time);
    ew_view_setup(&r->f.view, cam, r->f.target.width, r->f.target.height);
    ew_turb_table(r->draw.turb, &r->draw.turb_phase, cam->time);
    r->draw.sky_scroll = ew_sky_scroll(r->f.view.time);
    r->draw.sky_comp = NULL;  /* prepare_surfaces makes it where the frame shows sky */
    r->draw.subdiv_shift = r->f.cfg.subdiv_shift;
    r->draw.rgba = r->lit.curve.rgba;
    /* 8-bit coloured light needs the nearest-colour cubes (built once, on
     * every thread: tens of milliseconds on one). */
    if (!r->lit.nearest && r->f.target.bpp == 1 && !r->f.cfg.classic &&
        (ew_use_rgb_light(&r->f, r->f.world) || coloured_dlights(r->ents.scene))) {
        if (ew_blend_cube_begin(&r->blend, 1) > 0) {
            atomic_store(&r->sched.next_cube, 0);
            run_timed(r, EW_RUN_OTHER, job_cube);
            ew_blend_cube_end(&r->blend);
        }
        r->lit.nearest = r->blend.nearest;
    }
    /* Two-pass lighting's inputs, and its per-surface room (made on first use). */
    ew_tp_begin(&r->lit.tp, w, r->f.palette, r->f.colormap, r->f.cfg.lightstyle, ew_use_rgb_light(&r->f, w), r->f.target.bpp,
                r->f.cfg.classic);
    r->draw.tp = &r->lit.tp;
    if (two_pass(r) && !r->lit.tp_faces) r->lit.tp_faces = malloc(sizeof *r->lit.tp_faces * (size_t)r->el.max_surfs);
    r->draw.tp_faces = r->lit.tp_faces;
    hsr_ctx_setup(r);
    r->f.cfg.hsr->begin(&r->hsr);
    r->see.n = 0;
    front_inputs(r);
    /* The PVS of the eye's leaf, or of the leaf the lock kept (ew_set_pvs_lock). */
    int eye = ew_point_leaf(w, w->models[0].headnode, r->f.view.origin), leaf = eye;
    r->dbg.last_leaf = eye;
    if (r->dbg.pvs_lock) {
        if (r->dbg.pvs_leaf < 0) r->dbg.pvs_leaf = eye;
        leaf = r->dbg.pvs_leaf;
    }
    ew_pvs_mark(&r->front, leaf);
    r->f.eye_contents = w->leaves[eye].contents;
    /* Faces nearer faces hide are left out of the edge method's list only
     * (the others it feeds count and draw every face), in auto where the
     * PVS lets many leaves through (world/occlude.c). */
    ew_occ_begin(&r->front.occ, (r->f.cfg.hsr->flags & EW_HSR_OCCLUSION) && (r->front.occ.mode == EW_OCCLUSION_ALWAYS ||
                                                                  r->marks.nvis >= EW_OCC_AUTO_LEAVES));
    return 0;
}

/* Writes and coverage, measured on the method's output rather than
 * trusted.  Within a row the edge list emits spans left to right, so any
 * span starting before the previous one ended is overdraw; a method whose
 * rows may be out of order (b->unsorted) has each row's distinct pixels
 * counted on a scratch row. */
static void account_spans(ew_band *b, int width) {
    long written = 0, covered = 0;
    int row = -1, end = 0;
    if (b->unsorted && !b->rowmark) b->rowmark = calloc((size_t)width, 1);
    if (b->unsorted && b->rowmark) {
        for (int i = 0; i < b->nspans;) {
            int v = b->spans[i].v, j = i;
            for (; j < b->nspans && b->spans[j].v == v; j++) {
                const ew_span *sp = &b->spans[j];
                if (sp->surf == 0) continue;
                written += sp->count;
                for (int k = 0; k < sp->count; k++) covered += !b->rowmark[sp->u + k], b->rowmark[sp->u + k] = 1;
            }
            for (int k = i; k < j; k++) memset(b->rowmark + b->spans[k].u, 0, (size_t)b->spans[k].count);
            i = j;
        }
        b->written = written, b->covered = covered;
        return;
    }
    for (int i = 0; i < b->nspans; i++) {
        const ew_span *sp = &b->spans[i];
        if (sp->v != row) row = sp->v, end = 0;
        int start = sp->u > end ? sp->u : end, stop = sp->u + sp->count;
        if (sp->surf != 0) {
            written += sp->count;
            if (stop > start) covered += stop - start;
        }
        if (stop > end) end = stop;
    }
    b->written = written, b->covered = covered;
}

/* The face that won each pixel, for the tests' comparisons. */
static void record_face_ids(ew_renderer *r, const ew_band *b) {
    for (int i = 0; i < b->nspans; i++) {
        const ew_span *sp = &b->spans[i];
        int face = r->el.surfs[sp->surf].face;
        int *dst = r->f.face_ids + (size_t)sp->v * r->f.target.width + sp->u;
        for (int k = 0; k < sp->count; k++) dst[k] = face;
    }
}

/* Band boundaries: equal shares of the previous frame's cost, so no thread
 * idles while another finishes a busy band (cost per row is taken as even
 * within each band).  Without history, equal rows. */
static void place_bands(ew_renderer *r) {
    int n = r->sched.nbands, h = r->f.target.height;
    if (r->sched.bands_sized_for != n || r->sched.profile_rows) {
        for (int i = 0; i < n; i++) r->sched.bands[i].y0 = h * i / n, r->sched.bands[i].y1 = h * (i + 1) / n;
        return;
    }
    for (int i = 0; i < n; i++) {
        const ew_band *b = &r->sched.bands[i];
        double per_row = b->ms / (b->y1 - b->y0) + 1e-6;
        for (int v = b->y0; v < b->y1; v++) r->sched.row_cost[v] = (float)per_row;
    }
    int bounds[EW_MAX_BANDS + 1];
    ew_place_bands(r->sched.row_cost, h, n, bounds);  /* bands.c */
    for (int i = 0; i < n; i++) r->sched.bands[i].y0 = bounds[i], r->sched.bands[i].y1 = bounds[i + 1];
}

/* Each phase hands out its work with an atomic counter: a thread takes the
 * next band (or surface) until none is left. */
static void job_scan(void *ctx, int thread) {
    (void)thread;
    ew_renderer *r = ctx;
    for (int i; (i = atomic_fetch_add(&r->sched.next_band, 1)) < r->sched.nbands;) {
        double t0 = ew_now_ms();
        ew_band *b = &r->sched.bands[i];
        ew_band_reset(b);
        r->f.cfg.hsr->resolve(&r->hsr, b);
        ew_zfill_index_band(&r->zf, b, i);
        account_spans(b, r->f.target.width);
        if (r->f.cfg.face_ids_on) record_face_ids(r, b);  /* before the passes, which may win pixels */
        b->ms = ew_now_ms() - t0;
    }
}

/* The serial end of the front end: the bands placed for the scan. */
typedef struct front_tail_arg {
    ew_renderer *r;
    double       t1, t_end;  /* front end done, bands placed */
} front_tail_arg;
static void front_tail(void *arg) {
    front_tail_arg *a = arg;
    a->t1 = ew_now_ms();
    if (a->r->f.cfg.hsr->finish) a->r->f.cfg.hsr->finish(&a->r->hsr);
    place_bands(a->r);
    atomic_store(&a->r->sched.next_band, 0);
    a->t_end = ew_now_ms();
}

/* Builds the lit surfaces that must be built, then computes the surfaces'
 * gradients, a few dozen at a time. */
static void job_build(void *ctx, int thread) {
    ew_renderer *r = ctx;
    const ew_world *w = r->f.world;
    int *scratch = r->lit.blocklights + (size_t)r->lit.maxlm * 3 * thread;
    for (int k; (k = atomic_fetch_add(&r->sched.next_build, 1)) < r->lit.nbuild;)
        ew_lit_build(&r->lit, &r->f, r->lit.to_build[k], scratch);
    ew_passes_work(&r->passes);  /* e.g. alias models posed once for every band */
    enum { CHUNK = 32 };
    for (int k; (k = atomic_fetch_add(&r->sched.next_grad, CHUNK)) < r->lit.ngrad;) {
        int end = k + CHUNK < r->lit.ngrad ? k + CHUNK : r->lit.ngrad;
        for (; k < end; k++) {
            int s = r->lit.grad_list[k];
            const ew_surf *sf = &r->el.surfs[s];
            ew_surf_draw *d = &r->lit.surf_draw[s];
            ew_face_gradients(w, sf->view, &w->faces[sf->face], r->lit.surf_cache[s] ? r->lit.surf_cache[s]->mip : 0,
                              &d->g);
            ew_span_prepare(d);
            if (d->kind == EW_DRAW_TWOPASS) {
                const ew_face *f = &w->faces[sf->face];
                ew_tp_face_setup(&r->lit.tp, sf->view, sf->face, r->lit.surf_mip[s], ew_face_texture(w, f, r->f.view.time),
                                 &r->lit.tp_faces[s]);
            }
        }
    }
}

/* The whole-frame passes (the underwater warp, the gamma), band by band,
 * once every band is drawn. */
static void job_after(void *ctx, int thread) {
    (void)thread;
    ew_renderer *r = ctx;
    for (int i; (i = atomic_fetch_add(&r->sched.next_band, 1)) < r->sched.nbands;) {
        ew_rows rows = {r->sched.bands[i].y0, r->sched.bands[i].y1, &r->f.stats, 0};
        ew_passes_after(&r->passes, &rows);
    }
}

/* The draw's items: equal shares of the draw's cost per row, known once
 * the bands are scanned and the models posed.  The debug views and the row
 * profile draw band by band. */
static void place_draw(ew_renderer *r) {
    ew_sched *s = &r->sched;
    ew_draw_item *it = s->items;
    if (r->dbg.mode || s->profile_rows || s->nbands == 1) {
        s->nitems = s->nbands;
        for (int i = 0; i < s->nitems; i++) it[i].y0 = s->bands[i].y0, it[i].y1 = s->bands[i].y1;
        return;
    }
    int bounds[EW_MAX_ITEMS + 1];
    s->nitems = s->max_items;
    ew_estimate_draw_costs(&r->f.target, &r->ents, &r->zf, s->row_cost);  /* bands.c */
    ew_place_pieces(s->row_cost, r->f.target.height, s->nitems, s->nthreads, bounds);
    for (int i = 0; i < s->nitems; i++) it[i].y0 = bounds[i], it[i].y1 = bounds[i + 1];
}

/* An item's world spans, row by row from the scan's bands, then the moving
 * things in its rows: their z-fill is done by then, and no other item
 * touches those rows. */
static void job_draw(void *ctx, int thread) {
    (void)thread;
    ew_renderer *r = ctx;
    const ew_zfill *zf = &r->zf;
    for (int i; (i = atomic_fetch_add(&r->sched.next_band, 1)) < r->sched.nitems;) {
        double t0 = ew_now_ms();
        ew_draw_item *it = &r->sched.items[i];
        long fogged = 0;
        if (r->dbg.mode == EW_DEBUG_SPANS) {
            ew_debug_spans(&r->draw, &r->sched.bands[i], i);
        } else {
            /* Rows whose spans follow each other in one band: one call. */
            for (int y = it->y0, y1; y < it->y1; y = y1) {
                int band = zf->row_band[y], s0 = zf->row_span0[y], n = zf->row_nspans[y];
                for (y1 = y + 1; y1 < it->y1 && zf->row_band[y1] == band && zf->row_span0[y1] == s0 + n; y1++)
                    n += zf->row_nspans[y1];
                if (r->draw.fog.fill)  /* what fog covers whole: its colour, no texels */
                    fogged += ew_fog_draw_spans(&r->draw, zf->bands[band].spans + s0, n, r->lit.surf_draw,
                                                zf->all, zf->bands[band].unsorted);
                else
                    ew_draw_spans(&r->draw, zf->bands[band].spans + s0, n, r->lit.surf_draw, zf->all);
            }
        }
        double t1 = ew_now_ms();
        memset(&it->stats, 0, sizeof it->stats);
        it->stats.fog_pixels = fogged;
        ew_rows rows = {it->y0, it->y1, &it->stats, i == 0};
        ew_passes_draw(&r->passes, r->dbg.mode ? &r->sched.bands[i] : NULL, &rows);
        it->model_ms = ew_now_ms() - t1;
        it->ms = ew_now_ms() - t0;
    }
}

/* Between scan and draw, every surface that won a span gets its lit surface
 * looked up (allocating and evicting as needed) and its way of drawing
 * set; the surfaces to build and the gradients to compute are listed for
 * the parallel step that follows.  The read-only part runs on every thread
 * (job_surf_peek: whether a surface won a span, its mip, and whether its
 * cache entry is current); the calling thread then marks the hits used,
 * before any miss can evict them, and looks up the misses in order. */
enum { SURF_UNUSED, SURF_SKY_TURB, SURF_HIT, SURF_MISS };
enum { SURF_CHUNK = 64 };

/* A cached surface's first texels asked for ahead of the draw: when views
 * change, its spans would otherwise start on lines long gone from the
 * caches (2-3% of a 320x200 frame in bench's cycle of views).  The first
 * PREFETCH_BYTES only: that is all of most surfaces at small sizes. */
#define PREFETCH_BYTES 65536
static inline void prefetch_texels(const ew_renderer *r, const ew_cached_surf *e) {
    size_t bytes = (size_t)e->width * (size_t)e->height * (size_t)r->f.target.bpp;
    if (bytes > PREFETCH_BYTES) bytes = PREFETCH_BYTES;
    for (size_t o = 0; o < bytes; o += 64) __builtin_prefetch(e->pixels + o);
}

static void job_surf_peek(void *ctx, int thread) {
    (void)thread;
    ew_renderer *r = ctx;
    const ew_world *w = r->f.world;
    const int ns = r->el.nsurfs, nb = r->sched.nbands, tp = two_pass(r) && r->lit.tp_faces;
    for (int k; (k = atomic_fetch_add(&r->sched.next_item, SURF_CHUNK)) < ns;) {
        int end = k + SURF_CHUNK < ns ? k + SURF_CHUNK : ns;
        for (int s = k > 0 ? k : 1; s < end; s++) {
            int used = 0;
            for (int i = 0; i < nb && !used; i++) used = r->sched.bands[i].has_spans[s];
            r->lit.surf_cache[s] = NULL;
            if (!used) {
                r->lit.surf_state[s] = SURF_UNUSED;
                continue;
            }
            const ew_surf *sf = &r->el.surfs[s];
            const ew_face *f = &w->faces[sf->face];
            if (f->flags & (EW_SURF_SKY | EW_SURF_TURB)) {
                r->lit.surf_state[s] = SURF_SKY_TURB;
                continue;
            }
            int mip = ew_face_mip(&r->f.view, w, f, sf->nearzi);
            r->lit.surf_mip[s] = (uint8_t)mip;
            if (tp) {  /* two-pass lighting: no surface to find */
                r->lit.surf_state[s] = SURF_MISS;
                continue;
            }
            const ew_cached_surf *e = r->lit.surf_cache[s] = ew_lit_peek(&r->lit, &r->f, sf->face, mip);
            r->lit.surf_state[s] = e ? SURF_HIT : SURF_MISS;
            if (e) prefetch_texels(r, e);
        }
    }
}

static void prepare_surfaces(ew_renderer *r) {
    const ew_world *w = r->f.world;
    r->lit.nbuild = 0;
    r->lit.ngrad = 0;
    memset(&r->lit.surf_draw[0], 0, sizeof r->lit.surf_draw[0]);  /* the background: black and far */
    atomic_store(&r->sched.next_item, 0);
    run_timed(r, EW_RUN_OTHER, job_surf_peek);
    for (int s = 1; s < r->el.nsurfs; s++) {
        int state = r->lit.surf_state[s];
        if (state == SURF_UNUSED) continue;
        r->lit.grad_list[r->lit.ngrad++] = s;
        ew_surf_draw *d = &r->lit.surf_draw[s];
        if (state == SURF_SKY_TURB) {
            const ew_face *f = &w->faces[r->el.surfs[s].face];
            d->kind = f->flags & EW_SURF_SKY ? EW_DRAW_SKY : EW_DRAW_TURB;
            d->tex = ew_face_texture(w, f, r->f.view.time);
            /* The first sky's layers made one for the spans (a map with
             * two skies draws the others layer by layer). */
            if (d->kind == EW_DRAW_SKY && !r->draw.sky_comp &&
                ew_sky_comp_make(&r->sky, d->tex, r->draw.sky_scroll) == 0)
                r->draw.sky_comp = &r->sky;
        } else if (state == SURF_HIT) {
            ew_lit_touch(&r->lit, &r->f, r->lit.surf_cache[s]);
        }
    }
    int tp = two_pass(r) && r->lit.tp_faces;
    for (int s = 1; s < r->el.nsurfs; s++) {
        int state = r->lit.surf_state[s];
        if (state != SURF_HIT && state != SURF_MISS) continue;
        ew_surf_draw *d = &r->lit.surf_draw[s];
        if (tp) {  /* set up with the gradients (job_build) */
            d->kind = EW_DRAW_TWOPASS;
            continue;
        }
        ew_cached_surf *e = r->lit.surf_cache[s];
        int build = 0;
        if (state == SURF_MISS)
            e = r->lit.surf_cache[s] = ew_lit_lookup(&r->lit, &r->f, r->el.surfs[s].face, r->lit.surf_mip[s], &build);
        if (!e) {
            r->f.stats.dropped++;
            d->kind = EW_DRAW_FLAT;
            continue;
        }
        d->kind = EW_DRAW_LIT;
        d->pixels = e->pixels, d->pitch = e->width, d->lit16 = 0;
        if (build) {
            r->lit.to_build[r->lit.nbuild++] = e;
            if (r->dbg.mode == EW_DEBUG_BUILDS) d->kind = EW_DRAW_DEBUG, d->flat = r->dbg.build;
        }
    }
    r->f.stats.surfaces_shown = r->lit.ngrad;  /* the surfaces with a span */
}

/* The frame's clocks (ew_stats' times): a mark at the end of each serial
 * step, with the serial time since the last mark, wall time between two
 * marks less the time spent inside ew_pool_run (the parallel sections). */
enum { MARK_START, MARK_BEGUN, MARK_SCANNED, MARK_SURFACES, MARK_PASSES, MARK_DRAWN, NMARKS };
typedef struct frame_clock {
    double at[NMARKS], serial[NMARKS];
    double t, par;                   /* the last mark: wall time and parallel time then */
    double par0;                     /* parallel time at the start */
    double front_ms, walk_ms, brush_ms, tail_ms;  /* the front end (front_end) */
    double serial_in_run;            /* serial steps inside the front end's pool run */
} frame_clock;

static double serial_lap(const ew_renderer *r, frame_clock *c) {
    double t = ew_now_ms(), par = ew_pool_parallel_ms(r->sched.pool);
    double ms = (t - c->t) - (par - c->par);
    c->t = t, c->par = par;
    return ms;
}
static void clock_mark(const ew_renderer *r, frame_clock *c, int mark) {
    if (mark == MARK_START) {
        c->t = c->at[MARK_START] = ew_now_ms();
        c->par = c->par0 = ew_pool_parallel_ms(r->sched.pool);
        return;
    }
    c->at[mark] = ew_now_ms();
    c->serial[mark] = serial_lap(r, c);
}

/* The frame's counters from the bands' and the draw's items', and its times. */
static void frame_stats(ew_renderer *r, const frame_clock *c) {
    ew_stats *st = &r->f.stats;
    if (r->ents.scene) ew_scene_counts(r->ents.scene, NULL, &st->entities_unknown, &st->models_missing);
    st->pixels = (long)r->f.target.width * r->f.target.height;
    st->edges = r->el.nedges;
    st->surfaces = r->el.nsurfs - 1;
    double models_ms = 0;
    for (int i = 0; i < r->sched.nbands; i++) {
        const ew_band *b = &r->sched.bands[i];
        st->spans += b->nspans;
        st->dropped += b->dropped;
        st->pixels_written += b->written, st->pixels_covered += b->covered;
        for (int k = 0; k < EW_HSR_COUNTERS; k++) st->hsr_counters[k] += b->counters[k];
    }
    for (int i = 0; i < r->sched.nitems; i++) {
        const ew_stats *m = &r->sched.items[i].stats;
        st->dropped += m->dropped;
        st->entities_drawn += m->entities_drawn, st->entities_culled += m->entities_culled;
        st->entities_hidden += m->entities_hidden;
        st->alias_tris += m->alias_tris, st->alias_tris_subdiv += m->alias_tris_subdiv;
        st->alias_pixels += m->alias_pixels, st->particles += m->particles;
        st->alias_sprite_hits += m->alias_sprite_hits, st->alias_sprite_misses += m->alias_sprite_misses;
        st->fence_pixels += m->fence_pixels, st->translucent_pixels += m->translucent_pixels;
        st->fog_pixels += m->fog_pixels;
        models_ms += r->sched.items[i].model_ms;
    }
    if (r->f.cfg.hsr->memory) st->hsr_bytes = (long)r->f.cfg.hsr->memory(&r->hsr);
    st->surface_cache_bytes = (long)r->lit.cache.bytes;
    st->overdraw = st->pixels_covered ? (double)st->pixels_written / st->pixels_covered : 0;
    /* Models are drawn inside the bands' draw step; ms_models is their
     * time summed over bands, per thread (the wall time they took), plus
     * the serial per-frame entity pass. */
    const double *at = c->at;
    double t0 = at[MARK_START], t1 = c->front_ms, t2 = at[MARK_SCANNED], t3 = at[MARK_DRAWN];
    models_ms = models_ms / r->sched.nthreads + (at[MARK_PASSES] - at[MARK_SURFACES]);
    st->ms_front = t1 - t0, st->ms_scan = t2 - t1, st->ms_draw = t3 - t2 - models_ms;
    st->ms_models = models_ms, st->ms_total = t3 - t0;
    /* Serial: from the start of the frame to here, outside ew_pool_run. */
    st->ms_serial = (ew_now_ms() - t0) - (ew_pool_parallel_ms(r->sched.pool) - c->par0) + c->serial_in_run;
    ew_lab_stats *lab = &r->lab;  /* the probes (edgewise_lab.h) */
    lab->ms_serial_begin = c->serial[MARK_BEGUN], lab->ms_serial_walk = c->walk_ms, lab->ms_serial_brush = c->brush_ms;
    lab->ms_serial_prepare = c->tail_ms + c->serial[MARK_SURFACES], lab->ms_serial_passes = c->serial[MARK_PASSES];
    lab->ms_front_items = r->front.ms_front_items;
}

/* The walk, brush models, then the bands scanned.  On more than
 * EW_FRONT_LOOP_THREADS threads (or with EW_FRONT_PHASES) the walk, the
 * faces' clipping and edge setup run on every thread, the scan follows in
 * the same pool run (world/front_par.c); on fewer the calling thread walks
 * in one loop below.  The serial
 * steps in that run (its layout and numbering, the brush models, band
 * placement) are counted in ms_serial by their own clocks. */
static void front_end(ew_renderer *r, frame_clock *c) {
    front_tail_arg ft = {r, 0, 0};
    double tw = ew_now_ms(), front_serial[2] = {0, 0};
    if (ew_walk_world_parallel(&r->front, r->f.cfg.front_phases, front_tail, &ft, job_scan, r, front_serial) < 0) {
        ew_pvs_finish(&r->front);
        ew_walk_world(&r->front);
        ew_pool_wake(r->sched.pool);  /* for the scan (a second wake is harmless) */
        double tb = ew_now_ms();
        ew_walk_brush_models(&r->front);
        front_tail(&ft);
        serial_lap(r, c);
        run_timed(r, EW_RUN_SCAN, job_scan);
        c->walk_ms = tb - tw, c->brush_ms = ft.t1 - tb;
        c->serial_in_run = 0;
    } else {
        note_run(r, EW_RUN_SCAN);  /* the phases and the scan, one run */
        c->serial_in_run = front_serial[0] + front_serial[1] + (ft.t_end - ft.t1);
        c->walk_ms = front_serial[0], c->brush_ms = front_serial[1];
    }
    c->tail_ms = ft.t_end - ft.t1;
    c->front_ms = ft.t1;
}

int ew_render(ew_renderer *r, const ew_camera *cam, ew_stats *stats) {
    frame_clock clock;
    clock_mark(r, &clock, MARK_START);
    /* The frame's processor time: this thread's, and the workers' in jobs. */
    double cpu0 = ew_pool_thread_cpu_ms(), work0 = ew_pool_work_ms(r->sched.pool);
    /* Woken first, so a worker's kernel wake-up overlaps the frame's begin;
     * where the calling thread walks the front end alone (front_end), only
     * once the walk is done, so the worker does not poll all through it. */
    if (!ew_front_walks_alone(r->sched.nthreads, r->f.cfg.front_phases)) ew_pool_wake(r->sched.pool);
    if (ew_frame_begin(r, cam) < 0) {
        ew_pool_rest(r->sched.pool);
        return -1;
    }
    ew_mark_dlights(&r->marks, &r->f, r->ents.scene);  /* before the walk: a method may look up lit surfaces as faces arrive */
    clock_mark(r, &clock, MARK_BEGUN);
    front_end(r, &clock);
    clock_mark(r, &clock, MARK_SCANNED);
    prepare_surfaces(r);
    clock_mark(r, &clock, MARK_SURFACES);
    ew_passes_prepare(&r->passes);
    clock_mark(r, &clock, MARK_PASSES);
    atomic_store(&r->sched.next_build, 0);
    atomic_store(&r->sched.next_grad, 0);
    run_timed(r, EW_RUN_BUILD, job_build);
    place_draw(r);
    atomic_store(&r->sched.next_band, 0);
    run_timed(r, EW_RUN_DRAW, job_draw);
    r->sched.bands_sized_for = r->sched.nbands;
    if (ew_passes_after_begin(&r->passes)) {  /* the underwater warp, the gamma */
        atomic_store(&r->sched.next_band, 0);
        run_timed(r, EW_RUN_OTHER, job_after);
    }
    ew_pool_rest(r->sched.pool);  /* the last parallel step: no polling between frames */
    clock_mark(r, &clock, MARK_DRAWN);
    frame_stats(r, &clock);
    r->lab.ms_work = ew_pool_thread_cpu_ms() - cpu0 + ew_pool_work_ms(r->sched.pool) - work0;
    if (stats) *stats = r->f.stats;
    return 0;
}

/* Renders the frame with the reference method (the moving things drawn
 * over its z-buffer as over the edge list's), then copies it out. */
int ew_render_reference(ew_renderer *r, const ew_camera *cam, uint8_t *pixels, int *face_ids,
                        ew_error *err) {
    const ew_hsr *was = r->f.cfg.hsr;
    r->f.cfg.hsr = &ew_hsr_reference;
    r->hsr.ref_ids = face_ids;
    int rc = ew_render(r, cam, NULL);
    r->hsr.ref_ids = NULL;
    r->f.cfg.hsr = was;
    if (rc < 0) return ew_fail(err, "reference: bad camera");
    if (pixels)  /* palette indices, or 4-byte pixels in true colour */
        for (int y = 0; y < r->f.target.height; y++)
            memcpy(pixels + (size_t)y * r->f.target.width * r->f.target.bpp, ew_target_at(&r->f.target, 0, y),
                   (size_t)r->f.target.width * r->f.target.bpp);
    return 0;
}
