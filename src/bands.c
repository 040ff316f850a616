/* How a frame's rows are cut into bands (the renderer's place_bands and
 * `edgewise bench --bands`), and the per-row cost profile bench reads to
 * predict the imbalance of many bands on a machine with few cores. */
#include "bands.h"
#include "ew_util.h"  /* edgewise_lab.h: the public declarations */
#include "asset/scene.h"

/* Rows cut at running-cost targets: band b (of n) ends where the running
 * cost first reaches target(b), after at least 8 rows, or when the bands
 * left need all the rows left; the last band takes the rest.  guide 0:
 * equal shares; guide g > 0: each band takes 1/g of the cost still left. */
static void place(const float *row_cost, int h, int n, double guide, int *bounds) {
    bounds[0] = 0;
    if (n <= 1 || h < 8 * n) {  /* one band, or too few rows for 8 a band: equal rows */
        for (int i = 1; i <= n; i++) bounds[i] = (int)((long)h * i / n);
        return;
    }
    double total = 0;
    for (int v = 0; v < h; v++) total += row_cost[v];
    double acc = 0, target = guide > 0 ? total / guide : total / n;
    int band = 0, y0 = 0;
    for (int v = 0; v < h && band < n - 1; v++) {
        acc += row_cost[v];
        int rows_left = h - (v + 1), bands_left = n - band - 1;
        if ((acc >= target && v + 1 - y0 >= 8) || rows_left == 8 * bands_left) {
            bounds[++band] = v + 1;
            y0 = v + 1;
            target = guide > 0 ? acc + (total - acc) / guide : total * (band + 1) / n;
        }
    }
    for (; band < n; band++) {  /* the last band takes the rest */
        y0 = band == n - 1 ? h : y0 + 8;
        bounds[band + 1] = y0;
    }
}

void ew_place_bands(const float *row_cost, int h, int n, int *bounds) { place(row_cost, h, n, 0, bounds); }

/* Pieces are handed out in order to whichever thread is free, so the
 * thread that finishes last waits for at most the last piece it took:
 * "guided" sizes, each piece 1/(2 threads) of the cost left, make the first
 * pieces large (few set-ups) and the last small (little waiting). */
void ew_place_pieces(const float *row_cost, int h, int n, int threads, int *bounds) {
    place(row_cost, h, n, threads > 1 ? 2.0 * threads : 0, bounds);
}

/* The frame's cost to draw per row, known once the bands are scanned and
 * the models posed, in units of one pixel's drawing: every row has width
 * pixels, each span costs about as much as ROW_SPAN pixels to set up (at
 * 1920x1080, 2.3 us a row of pixels and 41 ns a span, measured per band),
 * and a posed model as MODEL_PX pixels a pixel of its screen box. */
#define ROW_SPAN 34.0f
#define MODEL_PX 1.0f
void ew_estimate_draw_costs(const ew_target *t, const ew_ents *en, const ew_zfill *zf, float *cost) {
    const int h = t->height, w = t->width;
    for (int v = 0; v <= h; v++) cost[v] = 0;
    const struct ew_scene *sc = en->scene;
    for (int i = 0; en->nalias && sc && i < en->nent_frame && i < sc->nents; i++) {
        const ew_alias_xf *xf = &en->xf[i];
        if (!en->ent_frame[i].visible || sc->models[sc->ents[i].model].kind != EW_MODEL_ALIAS || !xf->visible)
            continue;
        float u0 = xf->umin > 0 ? xf->umin : 0, u1 = xf->umax < (float)w ? xf->umax : (float)w;
        float v0 = xf->vmin > 0 ? xf->vmin : 0, v1 = xf->vmax < (float)h ? xf->vmax : (float)h;
        if (!(u1 > u0 && v1 > v0)) continue;  /* also NaN */
        cost[(int)v0] += MODEL_PX * (u1 - u0);
        cost[(int)v1] -= MODEL_PX * (u1 - u0);
    }
    float run = 0;
    for (int v = 0; v < h; v++) {
        run += cost[v];
        cost[v] = (float)w + run + ROW_SPAN * (float)zf->row_nspans[v];
    }
}

void ew_frame_cuts(int threads, int height, int *bands, int *pieces) {
    int nb = threads <= 1 ? 1 : threads * EW_BANDS_PER_THREAD;
    int ni = threads <= 1 ? 1 : threads * EW_DRAW_ITEMS_PER_THREAD;
    if (nb > height / 8) nb = height / 8;  /* at least 8 rows a band */
    if (ni > height / 8) ni = height / 8;
    *bands = nb, *pieces = ni < nb ? nb : ni;
}
