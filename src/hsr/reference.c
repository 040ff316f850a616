/* The reference method: hidden surfaces removed by brute force, independent
 * of the edge list.  The same front end hands over the visible faces; each
 * is clipped and projected, its lit surface looked up (and built) at once,
 * and every band then fills its rows of every polygon pixel by pixel with
 * a per-pixel z-buffer test from the face's plane equation, textured with
 * a true divide per pixel (raster/zpoly.c).  Slow and simple on purpose:
 * the tests trust it. */
#include "hsr/ref_compose.h"
#include "light/light.h"    /* ew_face_mip, ew_face_texture */
#include "light/twopass.h"
#include "raster/raster.h"  /* ew_zpoly */

#include <stdlib.h>
#include <string.h>

struct ew_ref_poly {
    ew_zpoly      p;
    ew_zpoly_look look;
    int           face;
    int           two_pass;  /* lit in two passes per pixel (tp set) */
    ew_tp_face    tp;
};

static void ref_begin(ew_hsr_ctx *c) {
    c->el->nedges = 0;
    c->el->nsurfs = 1;  /* no spans: the back end draws nothing of the world */
    ew_ref *ref = c->ref;
    if (!ref && !(ref = c->ref = calloc(1, sizeof *ref))) return;  /* every polygon dropped */
    ref->npolys = 0;
    ew_ref_compose_begin(c);  /* its per-pixel faces (hsr/ref_compose.c) */
    /* two-pass lighting: which polygon won each pixel */
    size_t npx = (size_t)c->f->target.width * (size_t)c->f->target.height;
    if (c->f->cfg.lighting == EW_LIGHTING_TWO_PASS && ref->npoly_of < npx) {
        free(ref->poly_of);
        ref->poly_of = malloc(sizeof(int) * npx);
        ref->npoly_of = ref->poly_of ? npx : 0;
    }
}

/* One world-space polygon of face fi; v is the camera in the face's own space. */
static void ref_poly(ew_hsr_ctx *c, float (*in)[3], int n, int fi, const ew_view *v, int key) {
    (void)key;  /* the z-buffer needs no order */
    const ew_world *w = c->f->world;
    const ew_face *f = &w->faces[fi];
    ew_ref *ref = c->ref;
    if (!ref) {
        c->f->stats.dropped++;
        return;
    }
    if (ref->npolys == ref->cap) {
        int cap = ref->cap ? ref->cap * 2 : 256;
        ew_ref_poly *p = realloc(ref->polys, sizeof *p * (size_t)cap);
        if (!p) {
            c->f->stats.dropped++;
            return;
        }
        ref->polys = p, ref->cap = cap;
    }
    ew_ref_poly *rp = &ref->polys[ref->npolys];
    if (!ew_zpoly_project(&c->f->view, in, n, &rp->p)) return;
    rp->face = fi;
    /* exact; a fence's holes are alpha-tested per pixel like the rest */
    rp->look = (ew_zpoly_look){w, f, v, ew_face_texture(w, f, v->time), NULL, 0, 0, 0,
                               (f->flags & EW_SURF_FENCE) && !c->f->cfg.classic ? EW_ZP_FENCE : EW_ZP_OPAQUE, NULL, 256};
    rp->two_pass = 0;
    if (!(f->flags & (EW_SURF_SKY | EW_SURF_TURB)) && c->f->cfg.lighting == EW_LIGHTING_TWO_PASS && !c->debug &&
        rp->look.mode == EW_ZP_OPAQUE) {
        /* two-pass lighting: no lit surface; ref_resolve lights its pixels */
        rp->look.mip = ew_face_mip(&c->f->view, w, f, rp->p.nearzi);
        rp->two_pass = 1;
        ew_tp_face_setup(c->tp, v, fi, rp->look.mip, rp->look.tex, &rp->tp);
    } else if (!(f->flags & (EW_SURF_SKY | EW_SURF_TURB))) {
        rp->look.mip = ew_face_mip(&c->f->view, w, f, rp->p.nearzi);
        int width;
        const uint8_t *surf = c->lit_surface(c->owner, fi, rp->look.mip, &width);
        if (surf) rp->look.surf = surf, rp->look.surf_width = width;
    }
    c->f->stats.surfaces++;
    ref->npolys++;
}

static void ref_face(ew_hsr_ctx *c, int fi, int clipflags, int key) {
    (void)clipflags;  /* clipped against every plane regardless */
    const ew_world *w = c->f->world;
    const ew_face *f = &w->faces[fi];
    if (f->numedges > EW_MAX_POLY - 8) return;
    float in[EW_MAX_POLY][3];
    ew_face_points(w, f, in);
    ref_poly(c, in, f->numedges, fi, &c->f->view, key);
}

/* Two-pass lighting, once every polygon is filled (z, sky, liquids; lit
 * faces get nothing yet) with its own number per pixel: the lit faces'
 * pixels drawn in the two passes, run by run along each row, and the
 * numbers turned into faces for ids. */
static void two_pass_rows(const ew_hsr_ctx *c, const ew_band *b, int *ids) {
    const ew_target *t = &c->f->target;
    const ew_ref *ref = c->ref;
    for (int y = b->y0; y < b->y1; y++) {
        const int *pr = ref->poly_of + (size_t)y * t->width;
        uint8_t *row = ew_target_at(t, 0, y);
        for (int x = 0, x1; x < t->width; x = x1) {
            int p = pr[x];
            for (x1 = x + 1; x1 < t->width && pr[x1] == p; x1++) {}
            if (p >= 0 && ref->polys[p].two_pass) ew_tp_run(c->tp, &ref->polys[p].tp, row, y, x, x1);
        }
        if (ids)
            for (int x = 0; x < t->width; x++) ids[(size_t)y * t->width + x] = pr[x] >= 0 ? ref->polys[pr[x]].face : -1;
    }
}

/* The band's rows: cleared to the background, then every polygon filled. */
static void ref_resolve(const ew_hsr_ctx *c, ew_band *b) {
    const ew_target *t = &c->f->target;
    const ew_ref *ref = c->ref;
    int *out = c->ref_ids ? c->ref_ids : c->f->cfg.face_ids_on ? c->f->face_ids : NULL;
    /* The faces go to the compose's buffer (it finds the sky by them), and
     * from there to the caller's. */
    int *own = ew_ref_compose_faces(c), *ids = own ? own : out;
    size_t npx = (size_t)t->width * (size_t)t->height;
    int two = ref && c->f->cfg.lighting == EW_LIGHTING_TWO_PASS && ref->poly_of && ref->npoly_of >= npx;
    int *fill = two ? ref->poly_of : ids;  /* two-pass: each pixel's polygon first */
    b->nspans = 0;
    memset(b->has_spans, 0, (size_t)c->el->nsurfs);
    for (int y = b->y0; y < b->y1; y++) {
        uint8_t *row = ew_target_at(t, 0, y);
        for (int x = 0; x < t->width; x++) ew_put_index(t, row, x, 0);  /* the background: black */
        float *z = ew_target_z(t, 0, y);
        for (int x = 0; x < t->width; x++) z[x] = 0;
        if (fill)
            for (int x = 0; x < t->width; x++) fill[(size_t)y * t->width + x] = -1;
    }
    for (int i = 0; ref && i < ref->npolys; i++) {
        const ew_ref_poly *rp = &ref->polys[i];
        ew_zpoly_fill(c->draw, &rp->p, &rp->look, fill, two ? i : rp->face, b->y0, b->y1);
    }
    if (two) two_pass_rows(c, b, ids);
    if (own) ew_ref_compose_ids_out(c, out, b->y0, b->y1);
}

static size_t ref_memory(const ew_hsr_ctx *c) { return c->ref ? sizeof(ew_ref_poly) * (size_t)c->ref->cap : 0; }

/* Fences go to the see-through list (no EW_HSR_FENCES) and with the
 * translucent surfaces and fog to its own compositing (EW_HSR_OWN_COMPOSE);
 * no spans: it writes the pixels itself. */
const ew_hsr ew_hsr_reference = {"reference", EW_HSR_OWN_COMPOSE, ref_begin, ref_face, ref_poly, NULL, ref_resolve,
                                  ref_memory, {NULL}};
