/* Renderer behaviour on a real map: surface cache hits and rebuilds, edge
 * sharing, light styles, animated textures, budgets, sizes and bad input. */
#include "util.h"
#include "renderer.h"
#include "edgewise_lab.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static long count_diff(const uint8_t *a, const uint8_t *b, long n) {
    long d = 0;
    for (long i = 0; i < n; i++) d += a[i] != b[i];
    return d;
}

#include "surfaces.h"

/* Sets light style `style` to value and renders view c again (the view of
 * the last frame): exactly the visible lit surfaces whose face uses that
 * style must be rebuilt, and no other.  Seen twice: the frame's list of
 * surfaces to build, and one texel of every lit surface of the previous
 * frame poisoned before the render (a surface not rebuilt keeps it; then
 * restored).  Returns the number rebuilt, -1 on a failed check. */
static int check_style_rebuilds(ew_renderer *r, const ew_camera *c, int style, int value, ew_stats *st) {
    const ew_world *w = r->f.world;
    ew_cached_surf **prev = malloc(sizeof *prev * (size_t)r->el.max_surfs);
    ew_cached_surf **cur = malloc(sizeof *cur * (size_t)r->el.max_surfs);
    uint8_t *saved = malloc((size_t)r->el.max_surfs);
    int np = frame_entries(r, prev), ok = 1;
    for (int i = 0; i < np; i++) saved[i] = prev[i]->pixels[0], prev[i]->pixels[0] ^= 0x5A;
    ew_set_lightstyle(r, style, value);
    CHECK(ew_render(r, c, st) == 0, "render");
    int nc = frame_entries(r, cur), expected = 0;
    /* The same view: the same lit surfaces, all still in the cache. */
    int same = nc == np;
    for (int i = 0; i < nc && same; i++) same = cur[i] == prev[i];
    CHECK(same, "style %d: the same view used %d lit surfaces, then %d", style, np, nc);
    if (!same) ok = 0;
    int wrong_list = 0, wrong_built = 0, first_list = -1, first_built = -1;
    for (int i = 0; same && i < nc; i++) {
        ew_cached_surf *e = cur[i];
        int uses = face_uses_style(&w->faces[e->face], style), listed = 0;
        expected += uses;
        for (int k = 0; k < r->lit.nbuild; k++) listed += r->lit.to_build[k] == e;
        int kept = e->pixels[0] == (uint8_t)(saved[i] ^ 0x5A);
        if (listed != uses && !wrong_list++) first_list = e->face;
        if (!uses && !kept && !wrong_built++) first_built = e->face;
        if (kept) e->pixels[0] = saved[i];
    }
    CHECK(wrong_list == 0, "style %d: %d lit surfaces (first: face %d) listed to build %s", style, wrong_list,
          first_list, "though their use of the style says otherwise");
    CHECK(wrong_built == 0, "style %d: %d lit surfaces not using it were rebuilt (first: face %d)", style,
          wrong_built, first_built);
    if (wrong_list || wrong_built) ok = 0;
    CHECK(st->surfaces_built == expected && r->lit.nbuild == expected,
          "style %d set to %d: built %d (listed %d), expected exactly the %d visible lit surfaces using it",
          style, value, st->surfaces_built, r->lit.nbuild, expected);
    if (st->surfaces_built != expected || r->lit.nbuild != expected) ok = 0;
    free(prev), free(cur), free(saved);
    return ok ? expected : -1;
}

int main(void) {
    if (!ew_t_need_shared("data/librequake/maps/e1m1.bsp")) return ew_t_finish();
    ew_error err;
    ew_assets *a = ew_assets_create(ew_t_shared("data/librequake/maps/e1m1.bsp"), NULL, &err);
    CHECK(a != NULL, "%s", err.msg);
    if (!a) return ew_t_finish();
    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(a->world, views);
    CHECK(nv == 29, "e1m1 has %d views", nv);

    /* Sizes outside 320x200..7680x4320 are refused with a message. */
    CHECK(ew_renderer_create(&(ew_renderer_desc){ .world = a->world, .palette = a->palette,
            .colormap = a->colormap, .width = 100, .height = 100, .threads = 1 }, &err) == NULL &&
              strstr(err.msg, "100x100"), "tiny frame: %s", err.msg);
    CHECK(ew_renderer_create(&(ew_renderer_desc){ .world = a->world, .palette = a->palette,
            .colormap = a->colormap, .width = 8000, .height = 5000, .threads = 1 }, &err) == NULL, "huge frame");

    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){ .world = a->world, .palette = a->palette,
            .colormap = a->colormap, .width = 320, .height = 200, .threads = 1 }, &err);
    CHECK(r != NULL, "%s", err.msg);
    if (!r) return ew_t_finish();
    long n = 320 * 200;
    uint8_t *first = malloc(n);

    /* Surface cache: the second frame of a view builds nothing. */
    ew_stats s1, s2;
    CHECK(ew_render(r, &views[0], &s1) == 0, "render");
    memcpy(first, ew_frame_pixels(r), n);
    CHECK(s1.surfaces_built > 0 && s1.surfaces_cached == 0, "first frame built %d cached %d",
          s1.surfaces_built, s1.surfaces_cached);
    CHECK(ew_render(r, &views[0], &s2) == 0, "render");
    ew_lab_stats lab2;  /* the lab's probes of the same frame */
    ew_frame_lab_stats(r, &lab2);
    CHECK(s2.surfaces_built == 0 && s2.surfaces_cached == s1.surfaces_built,
          "second frame built %d cached %d (first built %d)", s2.surfaces_built,
          s2.surfaces_cached, s1.surfaces_built);
    CHECK(count_diff(first, ew_frame_pixels(r), n) == 0, "same view, same pixels");

    /* surfaces_shown: the edge list's surfaces that won a span, counted here
     * from the bands' spans; on e1m1 some are always hidden behind others. */
    long shown_all = 0, surfs_all = 0;
    uint8_t *seen = calloc((size_t)r->el.max_surfs, 1);
    for (int v = 0; v < nv && seen; v++) {
        ew_stats st;
        CHECK(ew_render(r, &views[v], &st) == 0, "render view %d", v);
        memset(seen, 0, (size_t)r->el.max_surfs);
        int distinct = 0;
        for (int b = 0; b < r->sched.nbands; b++)
            for (int i = 0; i < r->sched.bands[b].nspans; i++) {
                int s = r->sched.bands[b].spans[i].surf;
                distinct += s > 0 && !seen[s];
                seen[s] = 1;
            }
        CHECK(st.surfaces_shown == distinct && distinct > 0 && distinct <= st.surfaces,
              "view %d: surfaces_shown %d, %d surfaces in the spans, %d in the list", v, st.surfaces_shown, distinct,
              st.surfaces);
        shown_all += st.surfaces_shown, surfs_all += st.surfaces;
    }
    CHECK(shown_all < surfs_all, "every surface of every view won a span (%ld of %ld)", shown_all, surfs_all);
    free(seen);

    /* The serial time, and its parts within it. */
    CHECK(s2.ms_serial > 0 &&
              lab2.ms_serial_begin + lab2.ms_serial_walk + lab2.ms_serial_brush + lab2.ms_serial_prepare +
                      lab2.ms_serial_passes <= s2.ms_serial + 1e-6,
          "serial %g of %g ms", s2.ms_serial, s2.ms_total);
    /* The parallel runs' times (ew_lab_stats.ms_run_*): within the frame;
     * on one thread each run's busy time is the caller's, within its wall
     * time, and on two at most twice it. */
    double walls = 0;
    for (int k = 0; k < EW_RUNS; k++) {
        CHECK(lab2.ms_run_busy[k] >= 0 && lab2.ms_run_busy[k] <= lab2.ms_run_wall[k] + 1e-6,
              "one thread, run %d: busy %g ms, wall %g", k, lab2.ms_run_busy[k], lab2.ms_run_wall[k]);
        walls += lab2.ms_run_wall[k];
    }
    CHECK(lab2.ms_run_busy[EW_RUN_SCAN] > 0 && lab2.ms_run_busy[EW_RUN_DRAW] > 0 && walls <= s2.ms_total + 1e-6,
          "runs: scan %g, draw %g, all %g of %g ms", lab2.ms_run_busy[EW_RUN_SCAN], lab2.ms_run_busy[EW_RUN_DRAW], walls,
          s2.ms_total);
    CHECK(ew_set_threads(r, 2) == 2, "two threads");
    ew_stats s3;
    ew_lab_stats lab3;
    CHECK(ew_render(r, &views[0], &s3) == 0 && count_diff(first, ew_frame_pixels(r), n) == 0,
          "two threads: the same frame");
    ew_frame_lab_stats(r, &lab3);
    walls = 0;
    for (int k = 0; k < EW_RUNS; k++) {
        CHECK(lab3.ms_run_busy[k] >= 0 && lab3.ms_run_busy[k] <= 2 * lab3.ms_run_wall[k] + 1e-6,
              "two threads, run %d: busy %g ms, wall %g", k, lab3.ms_run_busy[k], lab3.ms_run_wall[k]);
        walls += lab3.ms_run_wall[k];
    }
    CHECK(lab3.ms_run_busy[EW_RUN_SCAN] > 0 && lab3.ms_run_busy[EW_RUN_DRAW] > 0 && walls <= s3.ms_total + 1e-6,
          "two threads, runs: scan %g, draw %g, all %g of %g ms", lab3.ms_run_busy[EW_RUN_SCAN],
          lab3.ms_run_busy[EW_RUN_DRAW], walls, s3.ms_total);
    CHECK(ew_set_threads(r, 1) == 1, "one thread again");
    /* The row profile: strips of 8 rows, the same frame, a time per row. */
    CHECK(ew_set_row_profile(r, 1) == 1, "row profile on one thread");
    CHECK(ew_render(r, &views[0], NULL) == 0 && count_diff(first, ew_frame_pixels(r), n) == 0,
          "the row profile changes the frame");
    float scan_ms[200], draw_ms[200];
    for (int y = 0; y < 200; y++) scan_ms[y] = draw_ms[y] = -1;
    CHECK(ew_frame_row_ms(r, scan_ms, draw_ms, 200) == 200, "row costs: height");
    int positive = 0;
    double draw_total = 0;
    for (int y = 0; y < 200; y++) {
        positive += scan_ms[y] >= 0 && (y % 8 == 0 || scan_ms[y] == scan_ms[y - 1]);
        positive += draw_ms[y] >= 0 && (y % 8 == 0 || draw_ms[y] == draw_ms[y - 1]);
        draw_total += draw_ms[y];
    }
    CHECK(positive == 400, "row costs: %d of 2 x 200 rows non-negative and even within their strip", positive);
    CHECK(draw_total > 0, "row costs: the draw took no time (%g ms)", draw_total);
    CHECK(ew_set_row_profile(r, 0) == 1, "row profile off");
    /* The placement rule: even costs give even bands; a costly row gets a
     * band of 8 rows to itself (at least 8 a band); too few rows, equal rows. */
    float cost[200];
    int bounds[26];
    for (int y = 0; y < 200; y++) cost[y] = 1;
    ew_place_bands(cost, 200, 4, bounds);
    CHECK(bounds[0] == 0 && bounds[1] == 50 && bounds[2] == 100 && bounds[3] == 150 && bounds[4] == 200,
          "even bands: %d %d %d %d %d", bounds[0], bounds[1], bounds[2], bounds[3], bounds[4]);
    cost[100] = 1000;
    ew_place_bands(cost, 200, 4, bounds);
    CHECK(bounds[1] >= 92 && bounds[1] <= 101 && bounds[2] - bounds[1] >= 8 && bounds[4] == 200,
          "a costly row: %d %d %d %d %d", bounds[0], bounds[1], bounds[2], bounds[3], bounds[4]);
    ew_place_bands(cost, 200, 25, bounds);
    for (int i = 0; i < 25; i++) CHECK(bounds[i + 1] - bounds[i] == 8, "25 bands of 200 rows: band %d", i);
    ew_place_bands(cost, 100, 25, bounds);
    CHECK(bounds[25] == 100 && bounds[1] == 4, "too few rows: %d %d", bounds[1], bounds[25]);
    /* The draw's guided pieces: on even costs and 2 threads each takes a
     * quarter of the rows left (the first 48 of 192), never fewer than 8,
     * and together they cover the frame once. */
    float even[192];
    for (int y = 0; y < 192; y++) even[y] = 1;
    ew_place_pieces(even, 192, 8, 2, bounds);
    CHECK(bounds[0] == 0 && bounds[1] == 48 && bounds[2] == 84 && bounds[8] == 192, "guided pieces: %d %d %d %d",
          bounds[0], bounds[1], bounds[2], bounds[8]);
    for (int i = 0; i < 8; i++) CHECK(bounds[i + 1] - bounds[i] >= 8, "guided piece %d has %d rows", i, bounds[i + 1] - bounds[i]);
    for (int i = 1; i < 7; i++)
        CHECK(bounds[i + 1] - bounds[i] <= bounds[i] - bounds[i - 1], "guided piece %d larger than piece %d", i, i - 1);
    ew_place_pieces(even, 192, 4, 1, bounds);
    CHECK(bounds[1] == 48 && bounds[2] == 96 && bounds[4] == 192, "one thread: even pieces %d %d", bounds[1], bounds[2]);

    /* Neighbouring faces share emitted edges. */
    CHECK(s1.edges_cached > 0 && s1.edges > 0, "edges %d, reused %d", s1.edges, s1.edges_cached);

    /* A light style change rebuilds exactly the surfaces that use it: a
     * style no visible face uses rebuilds none, style 0 exactly its own. */
    int unused = -1;
    for (int st = 63; st > 0 && unused < 0; st--) {
        int used = 0;
        for (int f = 0; f < a->world->numfaces && !used; f++) used = face_uses_style(&a->world->faces[f], st);
        if (!used) unused = st;
    }
    CHECK(unused > 0, "e1m1 uses every light style");
    int was = unused > 0 ? r->f.cfg.lightstyle[unused] : 0;
    if (unused > 0) {
        CHECK(check_style_rebuilds(r, &views[0], unused, 512, &s2) == 0, "unused style %d rebuilt %d",
              unused, s2.surfaces_built);
        ew_set_lightstyle(r, unused, was);
    }
    int uses0 = check_style_rebuilds(r, &views[0], 0, 512, &s2);
    printf("style 0 doubled: rebuilt %d of %d lit surfaces\n", uses0, s1.surfaces_built);
    CHECK(s2.surfaces_built > 0 && s2.surfaces_built <= s1.surfaces_built && uses0 > 0,
          "style 0 doubled: rebuilt %d of %d", s2.surfaces_built, s1.surfaces_built);
    long brighter = 0;
    for (long i = 0; i < n; i++) {
        const uint8_t *p0 = a->palette + first[i] * 3, *p1 = a->palette + ew_frame_pixels(r)[i] * 3;
        brighter += p1[0] + p1[1] + p1[2] > p0[0] + p0[1] + p0[2];
    }
    CHECK(brighter > n / 4, "double light brightened only %ld pixels", brighter);
    ew_set_lightstyle(r, 0, 256);

    /* A switchable style (lights in e1m1 use styles 1..63): the first view
     * showing one rebuilds only the surfaces using it, not its neighbours. */
    int sv = -1, style = -1, nlit = 0;
    ew_cached_surf **ents = malloc(sizeof *ents * (size_t)r->el.max_surfs);
    for (int v = 0; v < nv && sv < 0; v++) {
        CHECK(ew_render(r, &views[v], NULL) == 0, "view %d", v);
        nlit = frame_entries(r, ents);
        for (int i = 0; i < nlit && sv < 0; i++) {
            const ew_face *f = &a->world->faces[ents[i]->face];
            for (int k = 0; k < 4 && f->styles[k] != 255 && sv < 0; k++)
                if (f->styles[k] != 0) sv = v, style = f->styles[k];
        }
    }
    free(ents);
    CHECK(sv >= 0, "no view of e1m1 shows a switchable light style");
    if (sv >= 0) {
        int old = r->f.cfg.lightstyle[style];
        int n_style = check_style_rebuilds(r, &views[sv], style, old / 2, &s2);
        printf("view %d, style %d halved: rebuilt %d of %d lit surfaces\n", sv, style, n_style, nlit);
        CHECK(n_style > 0 && n_style < nlit, "view %d style %d: rebuilt %d of %d", sv, style, n_style, nlit);
        ew_set_lightstyle(r, style, old);
    }

    /* Every view: counters sane, all pixels written exactly once. */
    for (int v = 0; v < nv; v++) {
        ew_stats st;
        CHECK(ew_render(r, &views[v], &st) == 0, "view %d", v);
        CHECK(st.pixels == n && st.pixels_written == n && st.overdraw == 1.0 && st.dropped == 0,
              "view %d: written %ld overdraw %g dropped %d", v, st.pixels_written, st.overdraw, st.dropped);
        CHECK(st.visible_leaves > 0 && st.surfaces > 0 && st.spans >= 200, "view %d counters", v);
    }

    /* Animated textures: some view changes between time 0 and 0.2 s... */
    long changed = 0;
    for (int v = 0; v < nv && !changed; v++) {
        ew_camera c = views[v];
        ew_render(r, &c, NULL);
        memcpy(first, ew_frame_pixels(r), n);
        c.time = 0.2;
        ew_render(r, &c, NULL);
        changed = count_diff(first, ew_frame_pixels(r), n);
    }
    CHECK(changed > 0, "no view of e1m1 changed with time");

    /* Budgets: with room for only 40 surfaces the frame still completes,
     * counts what it refused, and writes every pixel (the rest is background). */
    int saved = r->el.max_surfs;
    r->el.max_surfs = 40;
    ew_stats sb;
    CHECK(ew_render(r, &views[0], &sb) == 0, "render on a small budget");
    CHECK(sb.dropped > 0 && sb.surfaces <= 39, "dropped %d, surfaces %d", sb.dropped, sb.surfaces);
    r->el.max_surfs = saved;

    /* Bad cameras are refused, not rendered. */
    ew_camera bad = views[0];
    bad.origin[0] = NAN;
    CHECK(ew_render(r, &bad, NULL) == -1, "NaN origin accepted");
    bad = views[0];
    bad.fov = 500;
    CHECK(ew_render(r, &bad, NULL) == -1, "fov 500 accepted");
    CHECK(ew_set_subdivision(r, 3) == -1 && ew_set_subdivision(r, 8) == 0, "subdivision values");

    /* A camera outside the map (in solid) still draws a whole frame. */
    ew_camera out = views[0];
    out.origin[0] = out.origin[1] = out.origin[2] = 30000;
    ew_stats so;
    CHECK(ew_render(r, &out, &so) == 0 && so.overdraw <= 1.0, "outside the map");
    ew_renderer_destroy(r);

    /* No resolution ceiling: 7680x4320 renders every pixel once, and seen at
     * 1/8 scale (mean colour of each 8x8 block) it is the 960x540 frame: the
     * fixed-point formats hold at the largest size.  Checked on several views. */
    const int big_w = 7680, big_h = 4320, small_w = 960, small_h = 540;
    ew_renderer *big = ew_renderer_create(&(ew_renderer_desc){
            .world = a->world, .palette = a->palette,
            .colormap = a->colormap, .width = big_w, .height = big_h, .threads = 1 }, &err);
    ew_renderer *small = ew_renderer_create(&(ew_renderer_desc){
            .world = a->world, .palette = a->palette,
            .colormap = a->colormap, .width = small_w, .height = small_h, .threads = 1 }, &err);
    CHECK(big && small, "%s", err.msg);
    int check_views[3] = {0, 8, 12};
    for (int k = 0; big && small && k < 3; k++) {
        ew_stats st;
        const ew_camera *c = &views[check_views[k]];
        CHECK(ew_render(big, c, &st) == 0 && ew_render(small, c, NULL) == 0, "render view %d", check_views[k]);
        CHECK(st.pixels_written == st.pixels && st.overdraw == 1.0 && st.dropped == 0,
              "%dx%d view %d: written %ld of %ld, dropped %d", big_w, big_h, check_views[k],
              st.pixels_written, st.pixels, st.dropped);
        const uint8_t *bp = ew_frame_pixels(big), *sp = ew_frame_pixels(small);
        long off = 0;
        for (int by = 0; by < small_h; by++)
            for (int bx = 0; bx < small_w; bx++) {
                int sum[3] = {0, 0, 0};
                for (int y = 0; y < 8; y++)
                    for (int x = 0; x < 8; x++)
                        for (int ch = 0; ch < 3; ch++)
                            sum[ch] += a->palette[bp[(size_t)(by * 8 + y) * big_w + bx * 8 + x] * 3 + ch];
                const uint8_t *q = a->palette + sp[by * small_w + bx] * 3;
                int bad = 0;
                for (int ch = 0; ch < 3; ch++) bad |= abs(sum[ch] / 64 - q[ch]) > 40;
                off += bad;
            }
        /* Texel-level detail differs (different mip levels and sampling);
         * a broken format would move or smear whole surfaces. */
        double frac = (double)off / ((long)small_w * small_h);
        CHECK(frac < 0.10, "view %d: %.1f%% of 1/8-scale pixels of the 7680x4320 frame differ from 960x540",
              check_views[k], 100 * frac);
        printf("7680x4320 view %d at 1/8 scale vs 960x540: %.2f%% of pixels off by > 40 levels\n",
               check_views[k], 100 * frac);
    }
    ew_renderer_destroy(big);
    ew_renderer_destroy(small);
    free(first);
    ew_assets_destroy(a);
    return ew_t_finish();
}
