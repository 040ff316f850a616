/* Fog and translucency checked per pixel: every hidden-surface method's
 * colours against the reference's own compositing (hsr/ref_compose.c:
 * per pixel, the see-through fragments sorted by depth, composited over the
 * opaque pixel in RGB, each fogged at its own depth, the sky half way),
 * which shares nothing with the fog, blend and see-through passes the
 * other methods use.
 *
 * On fogged shared maps (a light and a dense fog; with their entities,
 * liquids at alpha 0.5), at
 * 320x200, in 8-bit and true colour, a frame and the reference are cut into
 * 8x8 blocks; a block disagrees when its mean R, G or B differs by more than
 * 12 levels.  Per method: the mean and worst share of disagreeing blocks
 * over the views, and of exactly equal pixels.  Checked:
 *   1. every method's worst view stays under the block threshold (8-bit
 *      frames: a looser one, see MAX_BAD_8BIT), its mean under 0.5%;
 *   2. a control: the edge method with its fog density 1.5 times the
 *      reference's fails it (the comparison sees a fog slightly wrong);
 *   3. the old reference (fences and fog through the shared passes, which
 *      fogged the sky by its depth) fails it against its own compositing
 *      on the views with the most sky, under a fog unlike the sky. */
#include "edgewise_lab.h"
#include "util.h"
#include "renderer.h"  /* the old reference's pass choice, rebuilt for check 3 */

#include <stdlib.h>
#include <string.h>

#define W 320
#define H 200
#define N (W * H)
#define BLOCK 8
#define LEVELS 12.0
/* % of blocks: every method's worst view must stay under it, and its mean
 * over the views under MAX_MEAN.  8-bit frames get more: the shared passes
 * fog a liquid's texel to the nearest palette colour, then blend that over
 * the fogged floor through a second nearest-colour table, and under a dense
 * fog the two roundings drift towards blue in the palette's sparse grey
 * midtones (e4m1's water under fog 0.25: 6.2% of blocks, red -2.5 and
 * blue +1.6 levels on the frame's mean; true colour: 0%). */
#define MAX_BAD_TRUE 2.0
#define MAX_BAD_8BIT 8.0
#define MAX_MEAN 0.5

static const char *const maps[] = {"e1m1", "e4m1", "start", "lqdm7"};
enum { NMAPS = sizeof maps / sizeof *maps, VIEW_STEP = 5 };
/* a light fog and a dense one */
static const float fogs[][4] = {{0.08f, 0.3f, 0.3f, 0.35f}, {0.25f, 0.45f, 0.42f, 0.38f}};
enum { NFOGS = sizeof fogs / sizeof *fogs };

typedef struct cmp { double bad, exact; } cmp;

/* The frame as RGB bytes. */
static void frame_rgb(ew_renderer *r, uint8_t *rgb) {
    if (ew_frame_color(r) == EW_COLOR_TRUE) {
        const uint8_t *px = (const uint8_t *)ew_frame_rgba(r);
        for (int i = 0; i < N; i++) memcpy(rgb + 3 * i, px + 4 * i, 3);
    } else {
        const uint8_t *px = ew_frame_pixels(r), *pal = ew_frame_palette(r);
        for (int i = 0; i < N; i++) memcpy(rgb + 3 * i, pal + 3 * px[i], 3);
    }
}

/* % of 8x8 blocks whose mean colour differs by more than LEVELS in a
 * channel, and % of pixels exactly equal. */
static cmp compare(const uint8_t *a, const uint8_t *b) {
    long bad = 0, blocks = 0, same = 0;
    for (int i = 0; i < N; i++) same += memcmp(a + 3 * i, b + 3 * i, 3) == 0;
    for (int by = 0; by + BLOCK <= H; by += BLOCK)
        for (int bx = 0; bx + BLOCK <= W; bx += BLOCK) {
            double d[3] = {0, 0, 0};
            for (int y = by; y < by + BLOCK; y++)
                for (int x = bx; x < bx + BLOCK; x++)
                    for (int k = 0; k < 3; k++) d[k] += (double)a[3 * (y * W + x) + k] - b[3 * (y * W + x) + k];
            int off = 0;
            for (int k = 0; k < 3; k++) off |= d[k] / (BLOCK * BLOCK) > LEVELS || d[k] / (BLOCK * BLOCK) < -LEVELS;
            bad += off, blocks++;
        }
    return (cmp){100.0 * bad / blocks, 100.0 * same / N};
}

static uint8_t ref_rgb[N * 3], px_rgb[N * 3];

typedef struct loaded {
    ew_assets *a;
    ew_scene *scene;
    ew_camera views[EW_MAX_VIEWS + 1];  /* and a camera of our own */
    int nviews;
} loaded;

static ew_renderer *make(const loaded *l, ew_color_mode color) {
    ew_error err;
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){.world = l->a->world, .palette = l->a->palette,
                                                            .colormap = l->a->colormap, .width = W, .height = H,
                                                            .threads = 1, .color = color}, &err);
    CHECK(r != NULL, "%s", err.msg);
    if (!r) return NULL;
    if (l->scene) ew_set_scene(r, l->scene);
    ew_set_liquid_alpha(r, 0.5f);
    return r;
}

static void reference(ew_renderer *r, const ew_camera *c, uint8_t *rgb) {
    ew_error err;
    CHECK(ew_render_reference(r, c, NULL, NULL, &err) == 0, "%s", err.msg);
    frame_rgb(r, rgb);
}

static void shot(ew_renderer *r, const ew_camera *c, uint8_t *rgb) {
    CHECK(ew_render(r, c, NULL) == 0, "render");
    frame_rgb(r, rgb);
}

typedef struct tally { double sum_bad, worst_bad, sum_exact, worst_exact; int n; char worst_at[64]; } tally;
static void add(tally *t, cmp c, const char *map, int view) {
    if (t->n == 0 || c.bad > t->worst_bad) {
        t->worst_bad = c.bad;
        snprintf(t->worst_at, sizeof t->worst_at, "%s view %d", map, view);
    }
    if (t->n == 0 || c.exact < t->worst_exact) t->worst_exact = c.exact;
    t->sum_bad += c.bad, t->sum_exact += c.exact, t->n++;
}

/* 1 and 2: every method against the reference, one pixel format. */
static void methods(loaded *ls, ew_color_mode color) {
    const char *fmt = color == EW_COLOR_TRUE ? "true colour" : "8-bit";
    const double max_bad = color == EW_COLOR_TRUE ? MAX_BAD_TRUE : MAX_BAD_8BIT;
    tally t[EW_HSR_COUNT], ctl;
    memset(t, 0, sizeof t), memset(&ctl, 0, sizeof ctl);
    for (int m = 0; m < NMAPS * NFOGS; m++) {
        const float *fog = fogs[m / NMAPS];
        ew_renderer *r = make(&ls[m % NMAPS], color);
        if (!r) continue;
        ew_set_fog(r, fog[0], fog[1], fog[2], fog[3]);
        int nv = ls[m % NMAPS].nviews;
        for (int v = 0; v < nv; v = v + VIEW_STEP < nv || v == nv - 1 ? v + VIEW_STEP : nv - 1) {
            const ew_camera *c = &ls[m % NMAPS].views[v];
            char at[32];
            snprintf(at, sizeof at, "%s fog %.2f", maps[m % NMAPS], fog[0]);
            reference(r, c, ref_rgb);
            for (int h = 0; h < EW_HSR_COUNT; h++) {
                if (h == EW_HSR_REFERENCE || !ew_hsr_available((ew_hsr_method)h)) continue;
                CHECK(ew_set_hsr(r, (ew_hsr_method)h) == 0, "set hsr %d", h);
                shot(r, c, px_rgb);
                cmp k = compare(px_rgb, ref_rgb);
                add(&t[h], k, at, v);
                if (h == EW_HSR_EDGE && !strcmp(maps[m % NMAPS], "e4m1") && v == nv - 1)
                    printf("%-11s edge, %s, the camera over the water: blocks off %.2f%%, exact pixels %.1f%%\n",
                           fmt, at, k.bad, k.exact);
            }
            /* 2: the control, the fog 1.5 times denser than the reference's */
            CHECK(ew_set_hsr(r, EW_HSR_EDGE) == 0, "set hsr");
            ew_set_fog(r, fog[0] * 1.5f, fog[1], fog[2], fog[3]);
            shot(r, c, px_rgb);
            add(&ctl, compare(px_rgb, ref_rgb), at, v);
            ew_set_fog(r, fog[0], fog[1], fog[2], fog[3]);
        }
        ew_renderer_destroy(r);
    }
    for (int h = 0; h < EW_HSR_COUNT; h++) {
        if (t[h].n == 0) continue;
        printf("%-11s %-10s views %2d  blocks off by > %.0f: mean %.2f%% worst %.2f%% (%s)  "
               "exact pixels: mean %.1f%% worst %.1f%%\n",
               fmt, ew_hsr_name((ew_hsr_method)h), t[h].n, LEVELS, t[h].sum_bad / t[h].n, t[h].worst_bad,
               t[h].worst_at, t[h].sum_exact / t[h].n, t[h].worst_exact);
        CHECK(t[h].worst_bad <= max_bad, "%s %s: %.2f%% of blocks differ from the reference at %s", fmt,
              ew_hsr_name((ew_hsr_method)h), t[h].worst_bad, t[h].worst_at);
        CHECK(t[h].sum_bad / t[h].n <= MAX_MEAN, "%s %s: %.2f%% of blocks differ from the reference on the mean",
              fmt, ew_hsr_name((ew_hsr_method)h), t[h].sum_bad / t[h].n);
    }
    printf("%-11s control: edge with fog density x1.5: blocks off mean %.2f%% worst %.2f%% (%s)\n", fmt,
           ctl.sum_bad / ctl.n, ctl.worst_bad, ctl.worst_at);
    /* failed on the mean of the views, not only at the worst */
    CHECK(ctl.sum_bad / ctl.n > max_bad, "%s: a fog 1.5 times too dense passes the threshold (mean %.2f%%)", fmt,
          ctl.sum_bad / ctl.n);
}

/* 3: the old reference, its z-buffer with the shared fences, fog and
 * translucent passes, against its own compositing, where the sky shows. */
static void old_reference(loaded *ls) {
    ew_hsr old = ew_hsr_reference;
    old.flags = (old.flags | EW_HSR_FENCES) & ~(unsigned)EW_HSR_OWN_COMPOSE;
    double worst = 0;
    char at[64] = "";
    for (int m = 0; m < NMAPS; m++) {
        ew_renderer *r = make(&ls[m], EW_COLOR_8BIT);
        if (!r) continue;
        const ew_world *w = ls[m].a->world;
        static int ids[N];
        /* the view with the most sky */
        int best = -1;
        long best_sky = 0;
        for (int v = 0; v < ls[m].nviews; v++) {
            ew_error err;
            CHECK(ew_render_reference(r, &ls[m].views[v], NULL, ids, &err) == 0, "%s", err.msg);
            long sky = 0;
            for (int i = 0; i < N; i++) sky += ids[i] >= 0 && (w->faces[ids[i]].flags & EW_SURF_SKY);
            if (sky > best_sky) best_sky = sky, best = v;
        }
        if (best < 0 || best_sky < N / 20) {
            ew_renderer_destroy(r);
            continue;
        }
        /* a dense fog of a colour unlike the sky's: fogged whole by depth, half way as the sky */
        ew_set_fog(r, 0.3f, 0.9f, 0.9f, 0.2f);
        const ew_camera *c = &ls[m].views[best];
        reference(r, c, ref_rgb);
        const ew_hsr *was = r->f.cfg.hsr;
        r->f.cfg.hsr = &old;
        shot(r, c, px_rgb);
        r->f.cfg.hsr = was;
        cmp k = compare(px_rgb, ref_rgb);
        printf("old reference (shared fog) %s view %d (sky %.1f%% of pixels): blocks off %.2f%%, exact %.1f%%\n",
               maps[m], best, 100.0 * best_sky / N, k.bad, k.exact);
        if (k.bad > worst) worst = k.bad, snprintf(at, sizeof at, "%s view %d", maps[m], best);
        ew_renderer_destroy(r);
    }
    CHECK(worst > MAX_BAD_8BIT, "the old reference's sky fog passes against its own compositing (worst %.2f%% %s)",
          worst, at);
}

int main(void) {
    if (!ew_t_need_shared("data/librequake/maps/e1m1.bsp")) return ew_t_finish();
    loaded ls[NMAPS];
    memset(ls, 0, sizeof ls);
    for (int m = 0; m < NMAPS; m++) {
        if (!(ls[m].a = ew_t_load_map_scene(maps[m], &ls[m].scene, ls[m].views, &ls[m].nviews))) return ew_t_finish();
        /* e4m1: a camera above its water, looking down through it (the
         * water covers most of the frame), as the last view */
        if (!strcmp(maps[m], "e4m1"))
            ls[m].views[ls[m].nviews++] = (ew_camera){{1162, 1898, -352}, {35, 0, 0}, 90, 0};
    }
    methods(ls, EW_COLOR_8BIT);
    methods(ls, EW_COLOR_TRUE);
    old_reference(ls);
    for (int m = 0; m < NMAPS; m++) ew_scene_destroy(ls[m].scene), ew_assets_destroy(ls[m].a);
    return ew_t_finish();
}
