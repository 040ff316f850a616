/* Debug modes: the pipeline made visible (include/edgewise.h ew_debug_mode,
 * raster/debug.h for the hooks).  Colours are chosen once, when a mode is
 * set: true colour stores them as they are, 8-bit as the nearest palette
 * colour. */
#include "raster/debug.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

/* The nearest palette colour to (r, g, b) among those not in skip[]. */
static int nearest_index(const uint8_t *pal, int r, int g, int b, const uint32_t *skip, int nskip) {
    int best = 0, best_d = INT_MAX;
    for (int c = 0; c < 256; c++) {
        int taken = 0;
        for (int k = 0; k < nskip; k++) taken |= skip[k] == (uint32_t)c;
        if (taken) continue;
        int dr = pal[c * 3] - r, dg = pal[c * 3 + 1] - g, db = pal[c * 3 + 2] - b;
        int d = dr * dr + dg * dg + db * db;
        if (d < best_d) best_d = d, best = c;
    }
    return best;
}

/* The colours of the modes, distinct from one another within each set. */
static void pick_colours(ew_debug *d, const ew_frame *f, const ew_lightcurve *lc) {
    static const uint8_t mip_rgb[4][3] = {{210, 40, 40}, {40, 180, 40}, {50, 70, 220}, {230, 210, 40}};
    static const uint8_t heat_rgb[EW_DBG_HEAT][3] = {{0, 0, 0},     {20, 30, 150}, {30, 170, 40},
                                                     {230, 220, 40}, {240, 130, 20}, {230, 20, 20}};
    int eight = f->target.bpp == 1;
    const uint8_t *pal = f->palette;
    uint32_t used[16];
    int n = 0;
    for (int k = 0; k < 4; k++) {
        const uint8_t *c = mip_rgb[k];
        d->mip[k] = eight ? (uint32_t)nearest_index(pal, c[0], c[1], c[2], used, n) : ew_rgba(c[0], c[1], c[2]);
        used[n++] = d->mip[k];
    }
    d->build = eight ? (uint32_t)nearest_index(pal, 255, 0, 255, NULL, 0) : ew_rgba(255, 0, 255);
    d->edge = eight ? (uint32_t)nearest_index(pal, 255, 255, 255, NULL, 0) : ew_rgba(255, 255, 255);
    n = 0;
    for (int k = 0; k < EW_DBG_HEAT; k++) {
        const uint8_t *c = heat_rgb[k];
        d->heat[k] = eight ? (uint32_t)nearest_index(pal, c[0], c[1], c[2], used, n) : ew_rgba(c[0], c[1], c[2]);
        used[n++] = d->heat[k];
    }
    /* The flat texture of the lighting mode: the grey (not fullbright)
     * nearest to mid grey, so overbright light shows too. */
    int best = 0, best_d = INT_MAX;
    for (int c = 0; c < 256; c++) {
        if (pal[c * 3] != pal[c * 3 + 1] || pal[c * 3] != pal[c * 3 + 2] || lc->fullbright[c]) continue;
        int dv = abs(pal[c * 3] - 128);
        if (dv < best_d) best_d = dv, best = c;
    }
    d->grey = (uint8_t)best;
}

void ew_debug_init(ew_debug *d, const ew_frame *f, const ew_lightcurve *lc) {
    d->last_leaf = d->pvs_leaf = -1;
    pick_colours(d, f, lc);
}

void ew_debug_free(ew_debug *d) {
    free(d->count), free(d->snap);
    d->count = d->snap = NULL;
}

/* Lighting, textures and mips change what a surface is built from. */
static int changes_surfaces(int mode) {
    return mode == EW_DEBUG_LIGHTING || mode == EW_DEBUG_TEXTURES || mode == EW_DEBUG_MIPS;
}

int ew_debug_set(ew_debug *d, const ew_target *t, int m) {
    if (m < EW_DEBUG_NONE || m > EW_DEBUG_BUILDS) m = EW_DEBUG_NONE;
    if (m == EW_DEBUG_OVERDRAW && !d->count) {
        size_t px = (size_t)t->width * (size_t)t->height;
        d->count = malloc(px);
        d->snap = malloc(px * (size_t)t->bpp);
        if (!d->count || !d->snap) {
            ew_debug_free(d);
            return -1;
        }
    }
    int rebuild = m != d->mode && (changes_surfaces(m) || changes_surfaces(d->mode));
    d->mode = m;
    return rebuild;
}

void ew_debug_pvs_lock(ew_debug *d, int on) {
    if (on && !d->pvs_lock) d->pvs_leaf = d->last_leaf;  /* -1: the next frame's */
    d->pvs_lock = on != 0;
}

/* A colour into pixel x of a row, as the target stores it. */
static inline void put(const ew_target *t, uint8_t *row, int x, uint32_t color) {
    if (t->bpp == 1)
        row[x] = (uint8_t)color;
    else
        ew_set32(row, x, color);
}

void ew_debug_fill_span(const ew_span_ctx *c, const ew_span *sp, uint32_t color) {
    uint8_t *row = ew_target_at(c->target, sp->u, sp->v);
    if (c->target->bpp == 1) {
        memset(row, (int)(uint8_t)color, (size_t)sp->count);
        return;
    }
    for (int x = 0; x < sp->count; x++) ew_set32(row, x, color);
}

static uint32_t hash32(uint32_t x) {
    x ^= x >> 16, x *= 0x7feb352dU;
    x ^= x >> 15, x *= 0x846ca68bU;
    return x ^ (x >> 16);
}

/* Span i's colour: a hash of its number (the band's, then its own); 8-bit
 * any palette index but black. */
static uint32_t span_colour(const ew_target *t, uint32_t n) {
    uint32_t h = hash32(n);
    if (t->bpp == 1) return 1 + h % 255;
    return ew_rgba(48 + (int)(h & 0xBF), 48 + (int)((h >> 8) & 0xBF), 48 + (int)((h >> 16) & 0xBF));
}

void ew_debug_spans(const ew_span_ctx *draw, const ew_band *b, int band) {
    const ew_target *t = draw->target;
    uint32_t base = (uint32_t)band << 20;
    uint32_t prev = 0;
    for (int i = 0; i < b->nspans; i++) {
        const ew_span *sp = &b->spans[i];
        uint32_t c = span_colour(t, base + (uint32_t)i);
        /* A span touching the one before it in its row never shares its colour. */
        for (uint32_t k = 1; i > 0 && c == prev && b->spans[i - 1].v == sp->v; k++)
            c = span_colour(t, base + (uint32_t)i + (k << 28));
        ew_debug_fill_span(draw, sp, c);
        prev = c;
    }
}

/* Every edge of the global edge list crossing the band's rows, a pixel a
 * row where the scan puts its span's first pixel. */
void ew_debug_edges(const ew_debug *dbg, const ew_frame *f, const ew_edge_list *el, int shows_edges,
                    const ew_rows *rows) {
    if (!shows_edges) return;
    const ew_target *t = &f->target;
    const int y0 = rows->y0, y1 = rows->y1;
    for (int i = 0; i < el->nedges; i++) {
        const ew_edge *e = &el->edges[i];
        int va = e->v_first > y0 ? e->v_first : y0, vb = e->v_last < y1 - 1 ? e->v_last : y1 - 1;
        for (int v = va; v <= vb; v++) {
            int64_t u = (int64_t)e->u + (int64_t)(v - e->v_first) * e->u_step;
            int64_t x = (u + 0xFFFF) >> 16;
            if (x < 0) x = 0;
            if (x > t->width - 1) x = t->width - 1;
            put(t, ew_target_at(t, 0, v), (int)x, dbg->edge);
        }
    }
}

/* Overdraw: the band's world spans counted, then each pass over the world
 * (fog aside) counted where it changed a pixel (scene/passes.c), then the
 * counts painted. */
void ew_debug_count_spans(ew_debug *d, const ew_target *t, const ew_band *b, const ew_rows *rows) {
    int w = t->width;
    uint8_t *count = d->count;
    memset(count + (size_t)rows->y0 * w, 0, (size_t)(rows->y1 - rows->y0) * w);
    for (int i = 0; i < b->nspans; i++) {
        const ew_span *sp = &b->spans[i];
        if (sp->surf == 0) continue;  /* a gap: nothing written there */
        uint8_t *c = count + (size_t)sp->v * w + sp->u;
        for (int k = 0; k < sp->count; k++) c[k] += c[k] < 255;
    }
}

void ew_debug_snap(ew_debug *d, const ew_target *t, const ew_rows *rows) {
    size_t off = (size_t)rows->y0 * t->pitch, bytes = (size_t)(rows->y1 - rows->y0) * t->pitch;
    memcpy(d->snap + off, t->pixels + off, bytes);
}

void ew_debug_count_changes(ew_debug *d, const ew_target *t, const ew_rows *rows) {
    int w = t->width, bpp = t->bpp;
    for (int y = rows->y0; y < rows->y1; y++) {
        const uint8_t *now = ew_target_at(t, 0, y), *was = d->snap + (size_t)y * t->pitch;
        uint8_t *c = d->count + (size_t)y * w;
        for (int x = 0; x < w; x++)
            if (memcmp(now + (size_t)x * bpp, was + (size_t)x * bpp, (size_t)bpp) != 0) c[x] += c[x] < 255;
    }
}

void ew_debug_paint_heat(const ew_debug *d, const ew_target *t, const ew_rows *rows) {
    int w = t->width;
    for (int y = rows->y0; y < rows->y1; y++) {
        uint8_t *row = ew_target_at(t, 0, y);
        const uint8_t *c = d->count + (size_t)y * w;
        for (int x = 0; x < w; x++) put(t, row, x, d->heat[c[x] < EW_DBG_HEAT ? c[x] : EW_DBG_HEAT - 1]);
    }
}
