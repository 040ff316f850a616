/* The see-through pass: fence textures and translucent surfaces, which the
 * front end kept out of the hidden-surface method (world/divert.c), drawn
 * over the world and the moving things with a z test against what is there.
 * Fences first, in any order: their texels write z, their holes (index
 * 255) nothing, so a monster behind a grate shows through the gaps and a
 * monster in front of it hides it.  Then translucent surfaces, far to near
 * in BSP order, each blended over what is there and writing no z (a monster
 * under water shows, tinted by it). */
#include "light/light.h"
#include "raster/zfill.h"

#include <stdlib.h>

/* Fences first; translucent ones far to near: larger BSP key first (keys
 * grow from front to back), then the farther nearest point. */
static const ew_see_poly *sort_base;
static int by_order(const void *pa, const void *pb) {
    const ew_see_poly *a = &sort_base[*(const int *)pa], *b = &sort_base[*(const int *)pb];
    if ((a->kind == EW_SEE_FENCE) != (b->kind == EW_SEE_FENCE)) return a->kind == EW_SEE_FENCE ? -1 : 1;
    if (a->key != b->key) return a->key > b->key ? -1 : 1;
    if (a->p.nearzi != b->p.nearzi) return a->p.nearzi < b->p.nearzi ? -1 : 1;
    return *(const int *)pa - *(const int *)pb;  /* stable: the order they came in */
}

void ew_see_prepare(ew_see *see, ew_frame *fr, ew_lit *lit) {
    const ew_world *w = fr->world;
    see->nfences = see->n_drawn = 0;
    fr->stats.seethrough_surfaces = 0;
    if (see->n == 0) return;
    if (see->n > see->cap_order) {
        int *o = realloc(see->order, sizeof *o * (size_t)see->cap);
        if (!o) {
            fr->stats.dropped += see->n;
            see->n = 0;
            return;
        }
        see->order = o, see->cap_order = see->cap;
    }
    int n = 0;
    for (int i = 0; i < see->n; i++) {
        ew_see_poly *sp = &see->polys[i];
        const ew_face *f = &w->faces[sp->face];
        ew_zpoly_look *look = &sp->look;
        look->tex = ew_face_texture(w, f, fr->view.time);
        /* Less than half the finest 8-bit step: invisible (maps use a
         * tiny "alpha" to hide a brush entity). */
        if (sp->kind == EW_SEE_BLEND && sp->alpha < 0.5f / EW_BLEND_LEVELS) continue;
        look->mode = sp->kind == EW_SEE_FENCE ? EW_ZP_FENCE : EW_ZP_BLEND;
        look->alpha256 = (int)(sp->alpha * 256 + 0.5f);
        if (sp->kind == EW_SEE_BLEND && fr->target.bpp == 1 &&
            !(look->blend = ew_blend_alpha(lit->blend, ew_blend_level(sp->alpha)))) {
            fr->stats.dropped++;
            continue;
        }
        if (!(f->flags & EW_SURF_TURB)) {  /* a lit surface, through the cache like the world's */
            int build;
            look->mip = ew_face_mip(&fr->view, w, f, sp->p.nearzi);
            ew_cached_surf *e = ew_lit_lookup(lit, fr, sp->face, look->mip, &build);
            if (!e) {
                fr->stats.dropped++;
                continue;
            }
            if (build) lit->to_build[lit->nbuild++] = e;  /* built with the world's */
            look->surf = e->pixels, look->surf_width = e->width;
        }
        see->order[n++] = i;
        see->nfences += sp->kind == EW_SEE_FENCE;
    }
    sort_base = see->polys;  /* serial: no other thread sorts */
    qsort(see->order, (size_t)n, sizeof *see->order, by_order);
    see->n_drawn = n;
    fr->stats.seethrough_surfaces = n;
}

static void draw_range(const ew_see *see, const ew_frame *f, const ew_span_ctx *draw, ew_zfill *zf,
                       const ew_rows *rows, int from, int to, long *count) {
    long px = 0;
    for (int k = from; k < to; k++) {
        const ew_see_poly *sp = &see->polys[see->order[k]];
        const ew_zpoly *p = &sp->p;
        if (p->y1 < rows->y0 || p->y0 >= rows->y1) continue;  /* another band's rows */
        ew_zfill_rect(zf, p->x0, p->y0 > rows->y0 ? p->y0 : rows->y0, p->x1 + 1,
                      p->y1 + 1 < rows->y1 ? p->y1 + 1 : rows->y1);
        px += ew_zpoly_fill(draw, p, &sp->look, f->cfg.face_ids_on ? f->face_ids : NULL, sp->face, rows->y0,
                            rows->y1);
    }
    *count += px;
}

void ew_draw_fences(const ew_see *see, const ew_frame *f, const ew_span_ctx *draw, ew_zfill *zf,
                    const ew_rows *rows) {
    draw_range(see, f, draw, zf, rows, 0, see->nfences, &rows->stats->fence_pixels);
}

void ew_draw_translucent(const ew_see *see, const ew_frame *f, const ew_span_ctx *draw, ew_zfill *zf,
                         const ew_rows *rows) {
    draw_range(see, f, draw, zf, rows, see->nfences, see->n_drawn, &rows->stats->translucent_pixels);
}

/* The front end's see-through faces and fragments (world/divert.c decides
 * which), clipped and projected. */
void ew_see_add(ew_see *see, ew_frame *f, int max_polys, float (*verts)[3], int n, int fi, const ew_view *v,
                int key, int kind, float alpha) {
    if (see->n == see->cap) {
        int cap = see->cap ? see->cap * 2 : 64;
        if (cap > max_polys) {  /* the same budget as the edge list's */
            f->stats.dropped++;
            return;
        }
        ew_see_poly *p = realloc(see->polys, sizeof *p * (size_t)cap);
        if (!p) {
            f->stats.dropped++;
            return;
        }
        see->polys = p, see->cap = cap;
    }
    ew_see_poly *sp = &see->polys[see->n];
    if (!ew_zpoly_project(&f->view, verts, n, &sp->p)) return;  /* outside the frustum */
    sp->face = fi, sp->key = key, sp->kind = kind, sp->alpha = alpha;
    sp->look = (ew_zpoly_look){f->world, &f->world->faces[fi], v, NULL, NULL, 0, 0, 1, EW_ZP_OPAQUE, NULL, 256};
    see->n++;
}
