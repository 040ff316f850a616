/* Fog by depth, as today's source ports draw worldspawn "fog": a colour
 * at view depth z moves towards the fog colour by 1 - exp(-(density z /
 * 64)^2).  In an 8-bit frame the fogged colour is the nearest palette
 * colour, from a table per fog level (light/blend.h).  The sky is fogged
 * half way, whatever its depth, as the ports do by default. */
#include "raster/zfill.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void ew_fog_levels(ew_fog *f) {
    int n = EW_FOG_QSTEPS;
    for (int i = 0; i <= n; i++) {
        double amount = 1.0 - exp(-(double)i / EW_FOG_QSCALE);
        f->level[i] = (uint8_t)lrint(amount * (EW_FOG_LEVELS - 1));
    }
    f->sky_level = (EW_FOG_LEVELS - 1) / 2;
}

void ew_fog_prepare(ew_fog *fog, ew_frame *f, ew_blend *blend) {
    fog->table = NULL;
    if (f->cfg.classic) return;
    const float *rgb = f->cfg.fog_density >= 0 ? f->cfg.fog_rgb : f->world->worldspawn.fog_rgb;
    float d = f->cfg.fog_density >= 0 ? f->cfg.fog_density : f->world->worldspawn.fog_density;
    if (!(d > 0)) return;
    for (int k = 0; k < 3; k++) fog->rgb[k] = (int)(rgb[k] * 255 + 0.5f);
    if (!(fog->table = ew_blend_fog(blend, rgb))) {  /* the 8-bit tables; also "fog on" in true colour */
        f->stats.dropped++;
        return;
    }
    fog->w = (d / 64) * (d / 64);
}

/* Pixel x of a row fogged by level k, in either pixel format. */
static inline void fog_px(const ew_fog *f, int bpp, uint8_t *row, int x, int k) {
    if (bpp == 1)
        row[x] = f->table[k * 256 + row[x]];
    else
        ew_set32(row, x, ew_fog_rgba(f, k, ew_get32(row, x)));
}

/* Pixels [x0, x1) of a row by their depth (zi 0: nothing drawn there). */
static long fog_run(const ew_fog *f, int bpp, float *zr, uint8_t *px, int x0, int x1) {
    long n = 0;
    for (int x = x0; x < x1; x++)
        if (zr[x] > 0) fog_px(f, bpp, px, x, ew_fog_level(f, zr[x])), n++;
    return n;
}

/* Span by span (they cover the row once): the sky's own pixels, where
 * nothing nearer was drawn over it, are found by their 1/z, recomputed
 * exactly as the z-fill wrote it, and take the sky's level. */
static long fog_spans(const ew_target *t, const ew_surf_draw *surf_draw, const ew_fog *fog, const ew_span *spans,
                      int nspans) {
    long n = 0;
    for (int i = 0; i < nspans; i++) {
        const ew_span *sp = &spans[i];
        float *zr = ew_target_z(t, 0, sp->v);
        uint8_t *px = ew_target_at(t, 0, sp->v);
        const ew_surf_draw *d = &surf_draw[sp->surf];
        if (d->kind != EW_DRAW_SKY) {
            n += fog_run(fog, t->bpp, zr, px, sp->u, sp->u + sp->count);
            continue;
        }
        const ew_gradients *g = &d->g;
        float zi = g->zi_u * sp->u + g->zi_v * sp->v + g->zi_0, dz = g->zi_u;
        for (int x = sp->u; x < sp->u + sp->count; x++) {
            if (zr[x] == zi + (float)(x - sp->u) * dz)
                fog_px(fog, t->bpp, px, x, fog->sky_level);
            else if (zr[x] > 0)
                fog_px(fog, t->bpp, px, x, ew_fog_level(fog, zr[x]));
            n++;
        }
    }
    return n;
}

/* A row whose spans may overlap (a band left unsorted: painter's order, a
 * z-buffer's runs): each pixel is fogged once, as the surface of the last
 * span over it (the one drawn on top), found by walking the spans from the
 * last and skipping pixels already done.  Fogging every span's pixels would
 * fog a pixel again for each polygon drawn over it. */
static long fog_unsorted(const ew_target *t, const ew_surf_draw *surf_draw, const ew_fog *fog, const ew_span *spans,
                         int nspans, uint8_t *done) {
    long n = 0;
    int v = spans[0].v;
    for (int i = nspans - 1; i >= 0; i--) {
        const ew_span *sp = &spans[i];
        for (int x = sp->u, end = sp->u + sp->count; x < end;) {
            while (x < end && done[x]) x++;
            int x0 = x;
            while (x < end && !done[x]) done[x++] = 1;
            if (x > x0) {
                ew_span one = {x0, v, x - x0, sp->surf};
                n += fog_spans(t, surf_draw, fog, &one, 1);
            }
        }
    }
    for (int i = 0; i < nspans; i++) memset(done + spans[i].u, 0, (size_t)spans[i].count);
    return n;
}

void ew_draw_fog(const ew_fog *fog, const ew_target *t, ew_zfill *zf, const ew_surf_draw *surf_draw,
                 const ew_rows *rows) {
    if (!fog->table) return;
    ew_zfill_rect(zf, 0, rows->y0, t->width, rows->y1);  /* every pixel's depth */
    long n = 0;
    uint8_t *done = NULL;  /* unsorted rows: pixels fogged, allocated on the first */
    for (int y = rows->y0; y < rows->y1; y++) {
        if (zf->row_nspans[y] == 0) {  /* no spans (the reference method): depth everywhere */
            n += fog_run(fog, t->bpp, ew_target_z(t, 0, y), ew_target_at(t, 0, y), 0, t->width);
            continue;
        }
        const ew_band *b = &zf->bands[zf->row_band[y]];
        const ew_span *spans = b->spans + zf->row_span0[y];
        if (b->unsorted) {
            if (!done && !(done = calloc((size_t)t->width, 1))) {
                rows->stats->dropped++;
                break;
            }
            n += fog_unsorted(t, surf_draw, fog, spans, zf->row_nspans[y], done);
        } else {
            n += fog_spans(t, surf_draw, fog, spans, zf->row_nspans[y]);
        }
    }
    free(done);
    rows->stats->fog_pixels += n;
}
