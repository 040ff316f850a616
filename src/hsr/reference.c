/* The reference method: hidden surfaces removed by brute force, independent
 * of the edge list.  The same front end hands over the visible faces; each
 * is clipped and projected, its lit surface looked up (and built) at once,
 * and every band then fills its rows of every polygon pixel by pixel with
 * a per-pixel z-buffer test from the face's plane equation, textured with
 * a true divide per pixel (raster/zpoly.c).  Slow and simple on purpose:
 * the tests trust it. */
#include "renderer.h"
#include "ew_util.h"

#include <stdlib.h>
#include <string.h>

struct ew_ref_poly {
    ew_zpoly      p;
    ew_zpoly_look look;
    int           face;
    int           two_pass;  /* lit in two passes per pixel (tp set) */
    ew_tp_face    tp;
};

static void ref_begin(ew_renderer *r) {
    r->ref.npolys = 0;
    ew_ref_compose_begin(r);  /* its per-pixel faces (hsr/ref_compose.c) */
    /* two-pass lighting: which polygon won each pixel */
    size_t npx = (size_t)r->f.target.width * (size_t)r->f.target.height;
    if (r->f.cfg.lighting == EW_LIGHTING_TWO_PASS && r->ref.npoly_of < npx) {
        free(r->ref.poly_of);
        r->ref.poly_of = malloc(sizeof(int) * npx);
        r->ref.npoly_of = r->ref.poly_of ? npx : 0;
    }
    r->el.nedges = 0;
    r->el.nsurfs = 1;  /* no spans: the back end draws nothing of the world */
}

/* One world-space polygon of face fi; v is the camera in the face's own space. */
static void ref_poly(ew_renderer *r, float (*in)[3], int n, int fi, const ew_view *v, int key) {
    (void)key;  /* the z-buffer needs no order */
    const ew_world *w = r->f.world;
    const ew_face *f = &w->faces[fi];
    ew_ref *ref = &r->ref;
    if (ref->npolys == ref->cap) {
        int cap = ref->cap ? ref->cap * 2 : 256;
        ew_ref_poly *p = realloc(ref->polys, sizeof *p * (size_t)cap);
        if (!p) {
            r->f.stats.dropped++;
            return;
        }
        ref->polys = p, ref->cap = cap;
    }
    ew_ref_poly *rp = &ref->polys[ref->npolys];
    if (!ew_zpoly_project(&r->f.view, in, n, &rp->p)) return;
    rp->face = fi;
    /* exact; a fence's holes are alpha-tested per pixel like the rest */
    rp->look = (ew_zpoly_look){w, f, v, ew_face_texture(w, f, v->time), NULL, 0, 0, 0,
                               (f->flags & EW_SURF_FENCE) && !r->f.cfg.classic ? EW_ZP_FENCE : EW_ZP_OPAQUE, NULL, 256};
    rp->two_pass = 0;
    if (!(f->flags & (EW_SURF_SKY | EW_SURF_TURB)) && r->f.cfg.lighting == EW_LIGHTING_TWO_PASS && !r->dbg.mode &&
        rp->look.mode == EW_ZP_OPAQUE) {
        /* two-pass lighting: no lit surface; ref_resolve lights its pixels */
        rp->look.mip = ew_face_mip(&r->f.view, w, f, rp->p.nearzi);
        rp->two_pass = 1;
        ew_tp_face_setup(&r->lit.tp, v, fi, rp->look.mip, rp->look.tex, &rp->tp);
    } else if (!(f->flags & (EW_SURF_SKY | EW_SURF_TURB))) {
        int build;
        rp->look.mip = ew_face_mip(&r->f.view, w, f, rp->p.nearzi);
        ew_cached_surf *e = ew_cache_lookup(r, fi, rp->look.mip, &build);
        if (e && build) ew_cache_build(r, e, r->lit.blocklights);
        if (e) rp->look.surf = e->pixels, rp->look.surf_width = e->width;
    }
    r->f.stats.surfaces++;
    ref->npolys++;
}

static void ref_face(ew_renderer *r, int fi, int clipflags, int key) {
    (void)clipflags;  /* clipped against every plane regardless */
    const ew_world *w = r->f.world;
    const ew_face *f = &w->faces[fi];
    if (f->numedges > EW_MAX_POLY - 8) return;
    float in[EW_MAX_POLY][3];
    ew_face_points(w, f, in);
    ref_poly(r, in, f->numedges, fi, &r->f.view, key);
}

/* Two-pass lighting, once every polygon is filled (z, sky, liquids; lit
 * faces get nothing yet) with its own number per pixel: the lit faces'
 * pixels drawn in the two passes, run by run along each row, and the
 * numbers turned into faces for ids. */
static void two_pass_rows(ew_renderer *r, const ew_band *b, int *ids) {
    const ew_target *t = &r->f.target;
    for (int y = b->y0; y < b->y1; y++) {
        const int *pr = r->ref.poly_of + (size_t)y * t->width;
        uint8_t *row = ew_target_at(t, 0, y);
        for (int x = 0, x1; x < t->width; x = x1) {
            int p = pr[x];
            for (x1 = x + 1; x1 < t->width && pr[x1] == p; x1++) {}
            if (p >= 0 && r->ref.polys[p].two_pass) ew_tp_run(&r->lit.tp, &r->ref.polys[p].tp, row, y, x, x1);
        }
        if (ids)
            for (int x = 0; x < t->width; x++) ids[(size_t)y * t->width + x] = pr[x] >= 0 ? r->ref.polys[pr[x]].face : -1;
    }
}

/* The band's rows: cleared to the background, then every polygon filled. */
static void ref_resolve(ew_renderer *r, ew_band *b) {
    const ew_target *t = &r->f.target;
    int *out = r->ref.ids ? r->ref.ids : r->f.cfg.face_ids_on ? r->f.face_ids : NULL;
    /* The faces go to the compose's buffer (it finds the sky by them), and
     * from there to the caller's. */
    int *own = ew_ref_compose_faces(r), *ids = own ? own : out;
    size_t npx = (size_t)t->width * (size_t)t->height;
    int two = r->f.cfg.lighting == EW_LIGHTING_TWO_PASS && r->ref.poly_of && r->ref.npoly_of >= npx;
    int *fill = two ? r->ref.poly_of : ids;  /* two-pass: each pixel's polygon first */
    b->nspans = 0;
    b->naet = 0;
    memset(b->has_spans, 0, (size_t)r->el.nsurfs);
    for (int y = b->y0; y < b->y1; y++) {
        uint8_t *row = ew_target_at(t, 0, y);
        for (int x = 0; x < t->width; x++) ew_put_index(t, row, x, 0);  /* the background: black */
        float *z = ew_target_z(t, 0, y);
        for (int x = 0; x < t->width; x++) z[x] = 0;
        if (fill)
            for (int x = 0; x < t->width; x++) fill[(size_t)y * t->width + x] = -1;
    }
    for (int i = 0; i < r->ref.npolys; i++) {
        const ew_ref_poly *rp = &r->ref.polys[i];
        ew_zpoly_fill(&r->draw, &rp->p, &rp->look, fill, two ? i : rp->face, b->y0, b->y1);
    }
    if (two) two_pass_rows(r, b, ids);
    if (own) ew_ref_compose_ids_out(r, out, b->y0, b->y1);
}

static size_t ref_memory(const ew_renderer *r) { return sizeof(ew_ref_poly) * (size_t)r->ref.cap; }

/* Fences go to the see-through list (fences 0) and with the translucent
 * surfaces and fog to its own compositing (own_compose 1). */
const ew_hsr ew_hsr_reference = {"reference", ref_begin, ref_face, ref_poly, ref_resolve, 0, {NULL}, 0, ref_memory,
                                  NULL, 1};

/* Renders the frame with the reference method (the moving things drawn
 * over its z-buffer as over the edge list's), then copies it out. */
int ew_render_reference(ew_renderer *r, const ew_camera *cam, uint8_t *pixels, int *face_ids,
                        ew_error *err) {
    const ew_hsr *was = r->f.cfg.hsr;
    r->f.cfg.hsr = &ew_hsr_reference;
    r->ref.ids = face_ids;
    int rc = ew_render(r, cam, NULL);
    r->ref.ids = NULL;
    r->f.cfg.hsr = was;
    if (rc < 0) return ew_fail(err, "reference: bad camera");
    if (pixels)  /* palette indices, or 4-byte pixels in true colour */
        for (int y = 0; y < r->f.target.height; y++)
            memcpy(pixels + (size_t)y * r->f.target.width * r->f.target.bpp, ew_target_at(&r->f.target, 0, y),
                   (size_t)r->f.target.width * r->f.target.bpp);
    return 0;
}
