/* Front end: world faces that nearer world faces hide are left out of the
 * edge list before their edges are set up.
 *
 * The walk hands faces over front to back, and the edge list sorts world
 * surfaces by that order (the BSP key), not by depth: wherever an earlier
 * face covers a pixel, a later one cannot show there.  So a coarse
 * coverage map suffices, with no depth in it: the screen in square tiles,
 * one bit each, set once every pixel centre of the tile lies inside a
 * face already handed over.  A face whose every tile that it might touch
 * is set would win no pixel; it is dropped before its edges are set up,
 * scanned and stepped down every row.  Both sides err the safe way: a
 * tile is set only if it lies inside the face's polygon by a margin (the
 * 16.16 edges the scan steps lie within a hundredth of a pixel of the
 * polygon), and a face tests every tile of its bounding box grown by a
 * pixel.  So the pixels do not change, only the work.
 *
 * Faces with the same key (a node's faces, which lie on one plane and do
 * not overlap) never hide one another: a face's tiles are noted as
 * pending, and set only when a face with a larger key comes.
 *
 * The map can be kept in horizontal strips, each noting only its rows:
 * a face is hidden if it is hidden in every strip, and a strip's bits are
 * then exactly the rows of the whole map's, so any number of strips (the
 * parallel front end's, world/front_par.c) decides as one strip (the
 * one-thread emission's, world/edges.c) does. */
#include "world/occlude.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MARGIN 0.25f  /* pixels: how far inside a face a set tile's pixel centres lie */
#define MAX_ROWS 256   /* tile rows of a face worked on at a time */
#define MIN_ROWS 6
#define MIN_COLS 6

int ew_occ_init(ew_occlusion *o, int width, int height) {
    /* Tiles of 4 pixels up to 1024 wide, 8 up to 2048, then 16: about
     * 128 to 256 tiles across and a few words a row. */
    o->shift = width <= 1024 ? 2 : width <= 2048 ? 3 : 4;
    int t = 1 << o->shift;
    o->tw = (width + t - 1) / t, o->th = (height + t - 1) / t;
    o->words = (o->tw + 63) / 64;
    o->bits = calloc((size_t)o->th * (size_t)o->words, sizeof(uint64_t));
    o->whole = (ew_occ_strip){.ty0 = 0, .ty1 = o->th - 1, .key = -1};
    o->mode = EW_OCCLUSION_AUTO;
    return o->bits ? 0 : -1;
}

void ew_occ_free(ew_occlusion *o) {
    free(o->bits);
    free(o->whole.pend);
    for (int i = 0; i < o->nstrips; i++) free(o->strips[i].pend);
    free(o->strips);
    o->bits = NULL, o->strips = NULL, o->whole.pend = NULL, o->nstrips = 0;
}

static void strip_reset(ew_occ_strip *s) { s->key = -1, s->npend = 0, s->any = 0, s->failed = 0; }

int ew_occ_strips(ew_occlusion *o, int n) {
    if (n > o->th) n = o->th;
    if (n < 1) n = 1;
    if (n != o->nstrips) {
        for (int i = 0; i < o->nstrips; i++) free(o->strips[i].pend);
        free(o->strips);
        o->nstrips = 0;
        if (!(o->strips = calloc((size_t)n, sizeof *o->strips))) return -1;
        o->nstrips = n;
    }
    for (int i = 0; i < n; i++) {
        o->strips[i].ty0 = o->th * i / n;
        o->strips[i].ty1 = o->th * (i + 1) / n - 1;
        strip_reset(&o->strips[i]);
    }
    return n;
}

void ew_occ_begin(ew_occlusion *o, int on) {
    o->on = on && o->mode != EW_OCCLUSION_OFF && o->bits;
    if (!o->on) return;
    memset(o->bits, 0, sizeof(uint64_t) * (size_t)o->th * (size_t)o->words);
    strip_reset(&o->whole);
    for (int i = 0; i < o->nstrips; i++) strip_reset(&o->strips[i]);
}

ew_occ_box ew_occ_box_of(const ew_occlusion *o, const ew_proj *p, int n, int width, int height) {
    float umin = p[0].u, umax = p[0].u, vmin = p[0].v, vmax = p[0].v;
    for (int i = 1; i < n; i++) {
        umin = p[i].u < umin ? p[i].u : umin, umax = p[i].u > umax ? p[i].u : umax;
        vmin = p[i].v < vmin ? p[i].v : vmin, vmax = p[i].v > vmax ? p[i].v : vmax;
    }
    /* Every pixel the scan can give the face (centres from ceil(umin) to
     * ceil(umax) - 1 across) and a pixel more each way.  The points lie on
     * the screen from -0.5 (ew_project clamps them), so truncation is a
     * floor there: x0 <= floor(umin) - 1, x1 >= ceil(umax) + 1. */
    int x0 = (int)(umin + 1.0f) - 2, x1 = (int)umax + 2, y0 = (int)(vmin + 1.0f) - 2, y1 = (int)vmax + 2;
    x0 = x0 < 0 ? 0 : x0, y0 = y0 < 0 ? 0 : y0;
    x1 = x1 > width - 1 ? width - 1 : x1, y1 = y1 > height - 1 ? height - 1 : y1;
    ew_occ_box b = {x0 >> o->shift, x1 >> o->shift, y0 >> o->shift, y1 >> o->shift, vmin, vmax, 0, -1};
    if (x0 > x1 || y0 > y1) {
        b.ty0 = 1, b.ty1 = 0;  /* no pixel */
        return b;
    }
    /* The tile rows whose both boundary lines (below) lie within the
     * points' rows.  Small faces add too little to be worth it: only faces
     * with at least MIN_ROWS such rows and a box MIN_COLS tiles wider than
     * its margins are noted (decided on the whole face, so every strip
     * agrees). */
    const float inv = 1.0f / (float)(1 << o->shift);
    int ra = ew_ceilf_int((vmin + 0.5f) * inv), rb = (int)((vmax + 0.5f) * inv + 1.0f) - 2;
    if (ra + MIN_ROWS - 1 <= rb && b.tx1 - b.tx0 >= 1 + MIN_COLS) b.ra = ra, b.rb = rb;
    return b;
}

static void row_set(uint64_t *row, int tx0, int tx1) {
    for (int w = tx0 >> 6; w <= tx1 >> 6; w++) row[w] |= ew_occ_mask(w, tx0, tx1);
}

void ew_occ_flush(ew_occlusion *o, ew_occ_strip *s) {
    s->any |= s->npend > 0;
    for (int i = 0; i < s->npend; i++) {
        const ew_occ_range *g = &s->pend[i];
        row_set(o->bits + (size_t)g->ty * (size_t)o->words, g->tx0, g->tx1);
    }
    s->npend = 0;
}

static int note(ew_occ_strip *s, int ty, int tx0, int tx1) {
    if (s->npend == s->cap) {
        int cap = s->cap ? s->cap * 2 : 256;
        ew_occ_range *q = realloc(s->pend, sizeof *q * (size_t)cap);
        if (!q) return -1;
        s->pend = q, s->cap = cap;
    }
    s->pend[s->npend++] = (ew_occ_range){(int16_t)ty, (int16_t)tx0, (int16_t)tx1};
    return 0;
}

/* The extents below assume a convex polygon.  A face's projection is one
 * up to float error (vertices in a line bend a little either way), unless
 * a point very near the eye had its depth clamped (ew_project): a face
 * with a point more than a twentieth of a pixel inside the line between
 * its neighbours is tested but covers nothing. */
static int convex(const ew_proj *p, int n) {
    float area = 0;
    for (int i = 0, j = n - 1; i < n; j = i++) area += p[j].u * p[i].v - p[i].u * p[j].v;
    for (int i = 0; i < n; i++) {
        const ew_proj *a = &p[i], *b = &p[(i + 1) % n], *c = &p[(i + 2) % n];
        float cross = (b->u - a->u) * (c->v - a->v) - (b->v - a->v) * (c->u - a->u);  /* b against a -> c */
        if ((cross > 0) == (area > 0) || cross == 0) continue;
        float dx = c->u - a->u, dy = c->v - a->v;
        if (cross * cross > 0.0025f * (dx * dx + dy * dy)) return 0;  /* b is 1/20 px or more inside */
    }
    return 1;
}

void ew_occ_note(ew_occlusion *o, ew_occ_strip *s, const ew_proj *p, int n, ew_occ_box b) {
    if (!convex(p, n)) return;
    /* The tiles whose pixel centres all lie inside by the margin.  Tile
     * row k spans the lines from k * t - 1/2 to (k + 1) * t - 1/2 (its
     * pixel centres' rows and half a row more each way); a convex polygon
     * spans on every line between two lines what it spans on both.  So
     * the polygon's extent on each tile boundary line, shared by the tile
     * rows above and below it, is all that is needed. */
    const int t = 1 << o->shift;
    const float tf = (float)t, inv = 1.0f / tf;
    int ra = b.ra > s->ty0 ? b.ra : s->ty0, rb = b.rb < s->ty1 ? b.rb : s->ty1;
    for (int r0 = ra; r0 <= rb; r0 += MAX_ROWS) {  /* MAX_ROWS tile rows at a time */
        int nl = (rb - r0 + 1 < MAX_ROWS ? rb - r0 + 1 : MAX_ROWS) + 1;  /* boundary lines */
        float lo[MAX_ROWS + 1], hi[MAX_ROWS + 1];
        for (int k = 0; k < nl; k++) lo[k] = INFINITY, hi[k] = -INFINITY;
        /* Each edge gives its x on the lines y with top.v <= y < bottom.v. */
        const float y0 = (float)(r0 * t) - 0.5f;
        for (int i = 0, j = n - 1; i < n; j = i++) {
            const ew_proj *a = &p[j], *c = &p[i];
            if (a->v == c->v) continue;
            if (a->v > c->v) {
                const ew_proj *x = a;
                a = c, c = x;
            }
            int k0 = ew_ceilf_int((a->v - y0) * inv), k1 = ew_ceilf_int((c->v - y0) * inv) - 1;
            k0 = k0 < 0 ? 0 : k0, k1 = k1 > nl - 1 ? nl - 1 : k1;
            if (k0 > k1) continue;
            float slope = (c->u - a->u) / (c->v - a->v);
            for (int k = k0; k <= k1; k++) {
                float x = a->u + (y0 + (float)(k * t) - a->v) * slope;
                lo[k] = x < lo[k] ? x : lo[k];
                hi[k] = x > hi[k] ? x : hi[k];
            }
        }
        for (int k = 0; k + 1 < nl; k++) {
            float xl = (lo[k] > lo[k + 1] ? lo[k] : lo[k + 1]) + MARGIN;
            float xr = (hi[k] < hi[k + 1] ? hi[k] : hi[k + 1]) - MARGIN;
            if (!(xr - xl >= tf - 1)) continue;  /* also a line the face misses (infinities) */
            int tx0 = ew_ceilf_int(xl * inv), tx1 = (int)((xr - (tf - 1)) * inv + 1.0f) - 1;  /* xr - (t - 1) >= xl > -1 */
            tx0 = tx0 < 0 ? 0 : tx0, tx1 = tx1 > o->tw - 1 ? o->tw - 1 : tx1;
            if (tx0 <= tx1 && note(s, r0 + k, tx0, tx1) < 0) s->failed = 1;  /* no memory: nothing more hidden */
        }
    }
}
