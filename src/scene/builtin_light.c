/*
 * Built-in scene: line of sight through the cell grid, light map samples
 * and the potentially visible set.  Everything is exact cell walking, so
 * shadows and visibility match the geometry the BSP is built from.
 */
#include "scene/builtin.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int bi_trace(const bi_grid *g, const float a[3], const float b[3]) {
    double p[3], d[3], tmax[3], tdelta[3];
    int c[3], step[3];
    for (int k = 0; k < 3; k++) {
        p[k] = a[k];
        d[k] = (double)b[k] - a[k];
        c[k] = (int)floor(p[k] / BI_CELL);
        if (d[k] > 0) {
            step[k] = 1;
            tmax[k] = ((c[k] + 1) * (double)BI_CELL - p[k]) / d[k];
            tdelta[k] = BI_CELL / d[k];
        } else if (d[k] < 0) {
            step[k] = -1;
            tmax[k] = (c[k] * (double)BI_CELL - p[k]) / d[k];
            tdelta[k] = -BI_CELL / d[k];
        } else {
            step[k] = 0;
            tmax[k] = tdelta[k] = HUGE_VAL;
        }
    }
    for (;;) {
        int kind = bi_kind(g, c[0], c[1], c[2]);
        if (kind == BI_SOLID || kind == BI_SKY) return kind;
        int ax = tmax[0] < tmax[1] ? (tmax[0] < tmax[2] ? 0 : 2) : (tmax[1] < tmax[2] ? 1 : 2);
        if (tmax[ax] > 1.0) return -1;
        c[ax] += step[ax];
        tmax[ax] += tdelta[ax];
    }
}

int bi_light_point(const bi_scene *s, const float p[3], const float n[3]) {
    double total = s->ambient;
    for (int i = 0; i < s->nlights; i++) {
        const bi_light *l = &s->lights[i];
        double d[3] = {l->origin[0] - p[0], l->origin[1] - p[1], l->origin[2] - p[2]};
        double dist = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (dist >= l->intensity) continue;
        double c = dist < 1 ? 1 : (d[0] * n[0] + d[1] * n[1] + d[2] * n[2]) / dist;
        if (c <= 0 || bi_trace(&s->grid, p, l->origin) >= 0) continue;
        total += (l->intensity - dist) * c;
    }
    /* sunlight: the surface sees the sky looking back along the sun's rays */
    double c = -(s->sun_dir[0] * n[0] + s->sun_dir[1] * n[1] + s->sun_dir[2] * n[2]);
    if (s->sun_intensity > 0 && c > 0) {
        float far[3];
        for (int k = 0; k < 3; k++) far[k] = p[k] - s->sun_dir[k] * 8192.0f;
        if (bi_trace(&s->grid, p, far) == BI_SKY) total += s->sun_intensity * c;
    }
    return total < 0 ? 0 : total > 255 ? 255 : (int)lrint(total);
}

/* ---- PVS ------------------------------------------------------------------- */

/* Sample points inside a leaf box: a small lattice inset from the faces,
 * kept off cell boundaries so rays never run along a cell wall. */
static int leaf_points(const int lo[3], const int hi[3], float (*pts)[3]) {
    float axis[3][4];
    int cnt[3];
    for (int k = 0; k < 3; k++) {
        int ext = hi[k] - lo[k];
        cnt[k] = 2 + (ext > 48) + (ext > 128);
        for (int i = 0; i < cnt[k]; i++) {
            double v = lo[k] + 1 + (ext - 2) * (double)i / (cnt[k] - 1);
            if (fmod(v, BI_CELL) == 0) v += 0.5;
            axis[k][i] = (float)v;
        }
    }
    int n = 0;
    /* the centre first: it decides most visible pairs at once */
    for (int k = 0; k < 3; k++) pts[n][k] = (lo[k] + hi[k]) * 0.5f + 0.25f;
    n++;
    for (int z = 0; z < cnt[2]; z++)
        for (int y = 0; y < cnt[1]; y++)
            for (int x = 0; x < cnt[0]; x++) {
                pts[n][0] = axis[0][x], pts[n][1] = axis[1][y], pts[n][2] = axis[2][z];
                n++;
            }
    return n;
}

static int boxes_touch(const int alo[3], const int ahi[3], const int blo[3], const int bhi[3]) {
    for (int k = 0; k < 3; k++) {
        if (ahi[k] != blo[k] && bhi[k] != alo[k]) continue;
        int u = (k + 1) % 3, v = (k + 2) % 3;
        if (ahi[u] > blo[u] && bhi[u] > alo[u] && ahi[v] > blo[v] && bhi[v] > alo[v]) return 1;
    }
    return 0;
}

int bi_compute_pvs(const bi_grid *g, int n, const int (*lo)[3], const int (*hi)[3],
                   const uint8_t *open, uint8_t *vis) {
    enum { MAXP = 1 + 4 * 4 * 4 };
    float (*pts)[MAXP][3] = malloc(sizeof *pts * (size_t)n);
    int *npts = malloc(sizeof *npts * (size_t)n);
    uint8_t *base = malloc((size_t)n * n);
    if (!pts || !npts || !base) {
        free(pts), free(npts), free(base);
        return -1;
    }
    memset(vis, 0, (size_t)n * n);
    for (int a = 0; a < n; a++) npts[a] = open[a] ? leaf_points(lo[a], hi[a], pts[a]) : 0;
    for (int a = 0; a < n; a++) {
        if (!open[a]) continue;
        vis[(size_t)a * n + a] = 1;
        for (int b = a + 1; b < n; b++) {
            if (!open[b]) continue;
            int seen = boxes_touch(lo[a], hi[a], lo[b], hi[b]);
            for (int i = 0; i < npts[a] && !seen; i++)
                for (int j = 0; j < npts[b] && !seen; j++)
                    seen = bi_trace(g, pts[a][i], pts[b][j]) < 0;
            vis[(size_t)a * n + b] = vis[(size_t)b * n + a] = (uint8_t)seen;
        }
    }
    /* Sampled rays can miss a sight line through a narrow gap; a missing
     * leaf shows as a hole while an extra one only costs time, so also
     * count the open neighbours of every leaf seen as visible. */
    memcpy(base, vis, (size_t)n * n);
    for (int b = 0; b < n; b++) {
        if (!open[b]) continue;
        for (int c = 0; c < n; c++) {
            if (c == b || !open[c] || !boxes_touch(lo[b], hi[b], lo[c], hi[c])) continue;
            for (int a = 0; a < n; a++)
                if (base[(size_t)a * n + b]) vis[(size_t)a * n + c] = vis[(size_t)c * n + a] = 1;
        }
    }
    free(pts), free(npts), free(base);
    return 0;
}
