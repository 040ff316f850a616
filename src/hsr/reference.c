/* The reference path: hidden surfaces removed by brute force, independent
 * of the edge list.  The same front end picks the visible faces; each is
 * filled pixel by pixel with a per-pixel z-buffer test from its plane
 * equation (raster/zpoly.c), textured from the same lit surfaces with a
 * true divide per pixel.  Slow and simple on purpose: the tests trust it. */
#include "ew_render.h"
#include "ew_util.h"

#include <string.h>

/* One world-space polygon of face fi; v is the camera in the face's own
 * space.  Returns 1 if it won any pixel. */
static int ref_poly(ew_renderer *r, int *ids, int fi, const ew_view *v, float (*in)[3], int n) {
    const ew_world *w = r->world;
    const ew_face *f = &w->faces[fi];
    ew_zpoly p;
    if (!ew_zpoly_project(r, in, n, &p)) return 0;
    ew_zpoly_look look = {w, f, v, ew_face_texture(w, f, v->time), NULL, 0, 0, 0};  /* exact: a divide per pixel */
    if (!(f->flags & (EW_SURF_SKY | EW_SURF_TURB))) {
        int build;
        look.mip = ew_face_mip(&r->view, w, f, p.nearzi);
        ew_cached_surf *e = ew_cache_lookup(r, fi, look.mip, &build);
        if (e && build) ew_cache_build(r, e, r->blocklights);
        if (e) look.surf = e->pixels, look.surf_width = e->width;
    }
    return ew_zpoly_fill(r, &p, &look, ids, fi, 0, r->height) > 0;
}

typedef struct ref_ctx { int *ids; } ref_ctx;

static void ref_face(ew_renderer *r, int fi, int clipflags, void *vctx) {
    (void)clipflags;  /* clipped against every plane regardless */
    const ew_world *w = r->world;
    const ew_face *f = &w->faces[fi];
    if (f->numedges > EW_MAX_POLY - 8) return;
    float in[EW_MAX_POLY][3];
    for (int i = 0; i < f->numedges; i++) {
        const float *p = w->verts[ew_face_vertex(w, f, i)];
        in[i][0] = p[0], in[i][1] = p[1], in[i][2] = p[2];
    }
    ref_poly(r, ((ref_ctx *)vctx)->ids, fi, &r->view, in, f->numedges);
}

static int ref_brush_face(ew_renderer *r, void *ctx, int fi, const ew_view *mv,
                          const float normal[3], float (*p)[3], int n) {
    (void)normal;
    return ref_poly(r, ((ref_ctx *)ctx)->ids, fi, mv, p, n);
}

/* Renders into the renderer's own frame and z-buffer (so the moving
 * things drawn after it meet the same z-buffer test), then copies out. */
int ew_render_reference(ew_renderer *r, const ew_camera *cam, uint8_t *pixels, int *face_ids,
                        ew_error *err) {
    size_t px = (size_t)r->width * r->height;
    ref_ctx c = {face_ids};
    if (ew_frame_begin(r, cam) < 0) return ew_fail(err, "reference: bad camera");
    for (size_t i = 0; i < px; i++) {
        r->zbuf[i] = 0;
        r->frame[i] = 0;
        if (face_ids) face_ids[i] = -1;
    }
    r->face_hook = ref_face;
    r->face_hook_ctx = &c;
    ew_walk_world(r);
    r->face_hook = NULL;
    r->face_hook_ctx = NULL;
    ew_for_brush_faces(r, ref_brush_face, &c);
    ew_zfill_mark_all(r);  /* the z-buffer is the reference's own, complete */
    ew_prepare_entities(r);
    ew_rows all = {0, r->height, &r->stats, 1};
    ew_draw_entities(r, &all);
    if (pixels) memcpy(pixels, r->frame, px);
    return 0;
}
