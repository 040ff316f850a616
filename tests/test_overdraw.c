/* Overdraw from the pixels themselves, not from the span list's accounting:
 * every span of a rendered frame is drawn again alone, by the renderer's own
 * drawers, into scratch targets prefilled with a sentinel (0x00 in one, 0xFF
 * in the other: a pixel is written when it differs from the sentinel in
 * either).  Each span must write exactly its own pixels [u, u + count) of
 * row v and nothing else (its row and the rows above and below are read in
 * full, the whole scratch frame once at the end), every pixel of the frame
 * must be written exactly once over all spans, and the pixels written must
 * be the real frame's.  A frame that is empty or nearly so fails too. */
#include "util.h"
#include "renderer.h"

#include <stdlib.h>
#include <string.h>

typedef struct scratch {
    ew_target  t[2];       /* sentinel 0x00, sentinel 0xFF */
    ew_span_ctx ctx[2];
    uint8_t   *blank[2];   /* one row of each sentinel */
} scratch;

static const uint8_t sentinel[2] = {0x00, 0xFF};
static long kind_spans[EW_DRAW_FLAT + 1];  /* spans redrawn by kind, over the whole test */

static void scratch_init(scratch *s, const ew_renderer *r) {
    const ew_target *f = &r->f.target;
    for (int k = 0; k < 2; k++) {
        s->t[k] = *f;
        s->t[k].pixels = malloc((size_t)f->pitch * f->height);
        s->t[k].zbuf = calloc((size_t)f->width * f->height, sizeof(float));
        memset(s->t[k].pixels, sentinel[k], (size_t)f->pitch * f->height);
        s->ctx[k] = r->draw;
        s->ctx[k].target = &s->t[k];
        s->blank[k] = malloc((size_t)f->pitch);
        memset(s->blank[k], sentinel[k], (size_t)f->pitch);
    }
}

static void scratch_free(scratch *s) {
    for (int k = 0; k < 2; k++) free(s->t[k].pixels), free(s->t[k].zbuf), free(s->blank[k]);
}

/* Bytes [x0, x1) of row y are still the sentinel in both scratch frames. */
static int untouched(const scratch *s, int y, int x0, int x1) {
    if (x1 <= x0) return 1;
    size_t bpp = (size_t)s->t[0].bpp;
    for (int k = 0; k < 2; k++)
        if (memcmp(ew_target_at(&s->t[k], x0, y), s->blank[k], (size_t)(x1 - x0) * bpp) != 0) return 0;
    return 1;
}

typedef struct tally {
    long spans, bad_spans, stray, stray_spans, unwritten, mismatch;
    char first_stray[160], first_unwritten[160], first_mismatch[160], first_bad[160];
} tally;

/* Draws span j of band b alone into both scratch frames and checks it;
 * counts its pixels in writes[]; leaves the scratch frames blank again. */
static void redraw_span(const ew_renderer *r, scratch *s, const ew_band *b, int j, uint8_t *writes, tally *t) {
    const ew_span *sp = &b->spans[j];
    const int w = r->f.target.width, h = r->f.target.height;
    t->spans++;
    if (sp->count <= 0 || sp->u < 0 || sp->u + sp->count > w || sp->v < b->y0 || sp->v >= b->y1 || sp->v >= h ||
        sp->surf < 0 || sp->surf >= r->el.nsurfs) {
        if (!t->bad_spans++)
            snprintf(t->first_bad, sizeof t->first_bad, "u %d count %d v %d surf %d in band [%d, %d)", sp->u,
                     sp->count, sp->v, sp->surf, b->y0, b->y1);
        return;
    }
    kind_spans[r->lit.surf_draw[sp->surf].kind]++;
    for (int k = 0; k < 2; k++) ew_draw_spans(&s->ctx[k], sp, 1, r->lit.surf_draw, 0);

    const int u0 = sp->u, u1 = sp->u + sp->count, v = sp->v;
    /* Nothing outside the span on its row, nor on the rows around it. */
    int clean = untouched(s, v, 0, u0) && untouched(s, v, u1, w);
    if (v > 0) clean = clean && untouched(s, v - 1, 0, w);
    if (v + 1 < h) clean = clean && untouched(s, v + 1, 0, w);
    if (!clean) {
        long n = 0;
        int fx = -1, fy = -1;
        for (int y = v > 0 ? v - 1 : v; y <= v + 1 && y < h; y++)
            for (int x = 0; x < w; x++) {
                if (y == v && x >= u0 && x < u1) continue;
                if (!untouched(s, y, x, x + 1)) {
                    if (fx < 0) fx = x, fy = y;
                    n++;
                }
            }
        if (!t->stray_spans++)
            snprintf(t->first_stray, sizeof t->first_stray,
                     "span u %d count %d v %d (surface %d, kind %d) wrote %ld pixels outside it, first (%d, %d)", u0,
                     sp->count, v, sp->surf, r->lit.surf_draw[sp->surf].kind, n, fx, fy);
        t->stray += n;
    }
    /* Inside: every pixel written, once, and as the real frame has it. */
    const uint8_t *a = ew_target_at(&s->t[0], 0, v), *z = ew_target_at(&s->t[1], 0, v);
    const uint8_t *real = ew_target_at(&r->f.target, 0, v);
    for (int x = u0; x < u1; x++) {
        int written = a[x] != sentinel[0] || z[x] != sentinel[1];
        if (!written) {
            if (!t->unwritten++)
                snprintf(t->first_unwritten, sizeof t->first_unwritten, "(%d, %d) of span u %d count %d", x, v, u0,
                         sp->count);
            continue;
        }
        if (writes[(size_t)v * w + x] < 255) writes[(size_t)v * w + x]++;
        if (a[x] != z[x] || a[x] != real[x]) {
            if (!t->mismatch++)
                snprintf(t->first_mismatch, sizeof t->first_mismatch,
                         "(%d, %d): redrawn %d / %d, frame %d (surface %d)", x, v, a[x], z[x], real[x], sp->surf);
        }
    }
    /* Blank again: the span's pixels, or its three rows after a stray write. */
    for (int k = 0; k < 2; k++) {
        if (clean)
            memset(ew_target_at(&s->t[k], u0, v), sentinel[k], (size_t)sp->count * (size_t)s->t[k].bpp);
        else
            for (int y = v > 0 ? v - 1 : v; y <= v + 1 && y < h; y++)
                memset(ew_target_at(&s->t[k], 0, y), sentinel[k], (size_t)s->t[k].pitch);
    }
}

/* Renders view c and checks its spans pixel by pixel. */
static void check_view(ew_renderer *r, const ew_camera *c, const char *what) {
    ew_stats st;
    CHECK(ew_render(r, c, &st) == 0, "%s: render", what);
    const int w = r->f.target.width, h = r->f.target.height;
    scratch s;
    scratch_init(&s, r);
    uint8_t *writes = calloc((size_t)w * h, 1);
    tally t;
    memset(&t, 0, sizeof t);
    for (int i = 0; i < r->sched.nbands; i++) {
        const ew_band *b = &r->sched.bands[i];
        for (int j = 0; j < b->nspans; j++) redraw_span(r, &s, b, j, writes, &t);
    }
    int blank = 1;
    for (int y = 0; y < h && blank; y++) blank = untouched(&s, y, 0, w);

    long never = 0, twice = 0;
    int fx = -1, fy = -1, tx = -1, ty = -1;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            int n = writes[(size_t)y * w + x];
            if (n == 0 && !never++) fx = x, fy = y;
            if (n > 1 && !twice++) tx = x, ty = y;
        }
    int used[256] = {0}, colours = 0;
    for (int y = 0; y < h; y++) {
        const uint8_t *row = ew_target_at(&r->f.target, 0, y);
        for (int x = 0; x < w; x++) used[row[x]] = 1;
    }
    for (int i = 0; i < 256; i++) colours += used[i];

    CHECK(t.spans > 100 && colours > 8, "%s: an empty frame: %ld spans, %d colours", what, t.spans, colours);
    CHECK(t.bad_spans == 0, "%s: %ld spans outside the frame or their band, first %s", what, t.bad_spans,
          t.first_bad);
    CHECK(t.stray_spans == 0, "%s: %ld spans wrote %ld pixels outside themselves; first %s", what, t.stray_spans,
          t.stray, t.first_stray);
    CHECK(t.unwritten == 0, "%s: %ld pixels of spans not written, first %s", what, t.unwritten, t.first_unwritten);
    CHECK(never == 0 && twice == 0, "%s: %ld pixels never written (first (%d, %d)), %ld written more than once "
          "(first (%d, %d))", what, never, fx, fy, twice, tx, ty);
    CHECK(t.mismatch == 0, "%s: %ld redrawn pixels differ from the frame, first %s", what, t.mismatch,
          t.first_mismatch);
    CHECK(blank, "%s: a scratch frame holds a write that no span's check saw", what);
    /* The span list's own accounting agrees. */
    CHECK(st.pixels_written == (long)w * h && st.overdraw == 1.0, "%s: written %ld overdraw %g", what,
          st.pixels_written, st.overdraw);
    printf("%s: %ld spans, %d colours, every pixel written once\n", what, t.spans, colours);
    free(writes);
    scratch_free(&s);
}

static void check_map(const char *map, const int *view_list, int nviews, int big_view) {
    ew_assets *a = ew_t_load_map(map);
    if (!a) return;
    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(a->world, views);
    ew_error err;
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette, .colormap = a->colormap, .width = 320, .height = 200, .threads = 1, .classic = 1}, &err);
    CHECK(r != NULL, "%s: %s", map, err.msg);
    char what[96];
    for (int threads = 1; r && threads <= 2; threads++) {
        CHECK(ew_set_threads(r, threads) == threads, "%s: %d threads", map, threads);
        for (int i = 0; i < nviews; i++) {
            CHECK(view_list[i] < nv, "%s has %d views, not %d", map, nv, view_list[i] + 1);
            if (view_list[i] >= nv) continue;
            snprintf(what, sizeof what, "%s view %d 320x200 %d thread%s", map, view_list[i], threads,
                     threads > 1 ? "s" : "");
            check_view(r, &views[view_list[i]], what);
        }
    }
    /* A surface cache too small for the frame: the surfaces it refuses are
     * drawn flat (black), through the flat drawer. */
    ew_renderer_destroy(r);
    ew_renderer *tight = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette, .colormap = a->colormap, .width = 320, .height = 200, .threads = 1, .classic = 1}, &err);
    CHECK(tight != NULL, "%s: %s", map, err.msg);
    if (tight && nviews > 0) {
        tight->lit.cache.budget = 16384;
        snprintf(what, sizeof what, "%s view %d 320x200, 16 KiB surface cache", map, view_list[nviews - 1]);
        check_view(tight, &views[view_list[nviews - 1]], what);
    }
    ew_renderer_destroy(tight);
    if (big_view >= 0 && big_view < nv) {
        ew_renderer *big = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette, .colormap = a->colormap, .width = 1920, .height = 1080, .threads = 1, .classic = 1}, &err);
        CHECK(big != NULL, "%s: %s", map, err.msg);
        if (big) {
            CHECK(ew_set_threads(big, 2) == 2, "%s: 2 threads at 1920x1080", map);
            snprintf(what, sizeof what, "%s view %d 1920x1080 2 threads", map, big_view);
            check_view(big, &views[big_view], what);
            ew_renderer_destroy(big);
        }
    }
    ew_assets_destroy(a);
}

int main(void) {
    static const int e1m1_views[] = {0, 8, 12}, start_views[] = {0, 3};
    check_map("e1m1", e1m1_views, 3, 8);
    check_map("start", start_views, 2, -1);
    static const char *const kinds[] = {"background", "lit", "sky", "liquid", "flat"};
    for (int k = EW_DRAW_LIT; k <= EW_DRAW_FLAT; k++)
        CHECK(kind_spans[k] > 0, "no %s span was redrawn: its drawer went unchecked", kinds[k]);
    printf("spans redrawn: %ld background, %ld lit, %ld sky, %ld liquid, %ld flat\n", kind_spans[0],
           kind_spans[1], kind_spans[2], kind_spans[3], kind_spans[4]);
    return ew_t_finish();
}
