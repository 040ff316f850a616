/* Two-pass lighting: a face's texture drawn unlit, then lit per pixel from
 * its light map (light/twopass.h says why it shares nothing with the
 * surface cache, and the semantics both follow).  Written from the
 * definitions: a ray per pixel, the light map's samples interpolated in
 * floating point, the colormap or its RGB rows applied per pixel. */
#include "light/twopass.h"

#include <math.h>
#include <string.h>

static int wrap(int x, int n) {
    x %= n;
    return x < 0 ? x + n : x;
}

void ew_tp_face_setup(const ew_twopass *tp, const ew_view *v, int fi, int mip, const ew_texture *tex,
                      ew_tp_face *pf) {
    const ew_world *w = tp->world;
    const ew_face *f = &w->faces[fi];
    const ew_texinfo *ti = &w->texinfo[f->texinfo];
    const ew_plane *pl = &w->planes[f->plane];
    memset(pf, 0, sizeof *pf);
    pf->f = f, pf->tex = tex, pf->mip = mip;
    pf->tw = tex->width >> mip, pf->th = tex->height >> mip;
    if (pf->tw < 1) pf->tw = 1;
    if (pf->th < 1) pf->th = 1;
    for (int a = 0; a < 2; a++) {
        pf->mins[a] = f->texturemins[a] >> mip;
        pf->size[a] = f->extents[a] >> mip;
        if (pf->size[a] < 1) pf->size[a] = 1;
    }
    pf->fence = (tex->flags & EW_SURF_FENCE) && !tp->classic;

    /* The ray of pixel (x, y): o + d t, d = forward + right a - up b with
     * a = (x - xcenter) / xscale, b = (y - ycenter) / yscale; it meets the
     * plane n.p = dist at t = (dist - n.o) / n.d.  n.d and vec.d are linear
     * in x and y, so each is a base and two slopes. */
    double n[3] = {pl->normal[0], pl->normal[1], pl->normal[2]};
    double no = n[0] * v->origin[0] + n[1] * v->origin[1] + n[2] * v->origin[2];
    pf->k = (double)pl->dist - no;
    double nf = 0, nr = 0, nu = 0;
    for (int i = 0; i < 3; i++) nf += n[i] * v->forward[i], nr += n[i] * v->right[i], nu += n[i] * v->up[i];
    double ax = 1.0 / v->xscale, ay = 1.0 / v->yscale;
    pf->dx = nr * ax, pf->dy = -nu * ay;
    pf->d0 = nf - nr * ax * v->xcenter + nu * ay * v->ycenter;
    for (int a = 0; a < 2; a++) {
        const float *vec = ti->vecs[a];
        double sf = 0, sr = 0, su = 0, so = vec[3];
        for (int i = 0; i < 3; i++) {
            sf += vec[i] * (double)v->forward[i], sr += vec[i] * (double)v->right[i];
            su += vec[i] * (double)v->up[i], so += vec[i] * (double)v->origin[i];
        }
        pf->so[a] = so;
        pf->sx[a] = sr * ax, pf->sy[a] = -su * ay;
        pf->s0[a] = sf - sr * ax * v->xcenter + su * ay * v->ycenter;
    }

    /* The light map: Quake's grid (a sample every 16 texels from
     * texturemins) or the map's BSPX layout for this face. */
    pf->smax = (f->extents[0] >> 4) + 1, pf->tmax = (f->extents[1] >> 4) + 1;
    pf->lightofs = f->lightofs;
    pf->lm[0][0] = 1.0 / 16, pf->lm[0][1] = 0, pf->lm[0][2] = -f->texturemins[0] / 16.0;
    pf->lm[1][0] = 0, pf->lm[1][1] = 1.0 / 16, pf->lm[1][2] = -f->texturemins[1] / 16.0;
    if (w->facelm) {
        const ew_facelm *L = &w->facelm[fi];
        pf->smax = L->width, pf->tmax = L->height, pf->lightofs = L->lightofs;
        for (int a = 0; a < 2; a++)
            for (int b = 0; b < 3; b++) pf->lm[a][b] = L->st_to_lm[a][b];
    }
    /* No samples, or samples outside the lump: a face with no light map. */
    int styles = 0;
    while (styles < 4 && f->styles[styles] != 255) styles++;
    long long need = (long long)pf->smax * pf->tmax * styles;
    if (pf->smax <= 0 || pf->tmax <= 0 || pf->lightofs < 0 || !w->lighting ||
        (long long)pf->lightofs + need > (long long)w->lightsize)
        pf->lightofs = -1;
}

/* Texture coordinate a (0: s, 1: t) of pixel (x, y), in texels of mip 0. */
static inline double tex_coord(const ew_tp_face *pf, int a, double x, double y, double den) {
    return pf->so[a] + (pf->s0[a] + pf->sx[a] * x + pf->sy[a] * y) * pf->k / den;
}

uint8_t ew_tp_texel(const ew_tp_face *pf, int x, int y, int *X, int *Y) {
    double den = pf->d0 + pf->dx * x + pf->dy * y;
    int xy[2];
    for (int a = 0; a < 2; a++) {
        double s = den != 0 ? tex_coord(pf, a, x, y, den) : 0;
        if (!(s > -1e9)) s = -1e9;  /* NaN too */
        if (s > 1e9) s = 1e9;
        /* floor(s / 2^mip), from texturemins at that mip, held to the face */
        int i = (int)floor(s / (double)(1 << pf->mip)) - pf->mins[a];
        xy[a] = i < 0 ? 0 : i >= pf->size[a] ? pf->size[a] - 1 : i;
    }
    *X = xy[0], *Y = xy[1];
    int col = wrap(pf->mins[0] + xy[0], pf->tw), row = wrap(pf->mins[1] + xy[1], pf->th);
    return pf->tex->mip[pf->mip][row * pf->tw + col];
}

void ew_tp_light(const ew_twopass *tp, const ew_tp_face *pf, int X, int Y, int light[3]) {
    const ew_world *w = tp->world;
    if (!w->lighting) {  /* a map with no light at all: textures at the colormap's middle row */
        light[0] = light[1] = light[2] = -1;
        return;
    }
    if (pf->lightofs < 0) {
        light[0] = light[1] = light[2] = 0;
        return;
    }
    /* The texel's corner in texture space (mip 0 texels), then its sample. */
    double S = pf->f->texturemins[0] + (double)X * (1 << pf->mip);
    double T = pf->f->texturemins[1] + (double)Y * (1 << pf->mip);
    double u = pf->lm[0][0] * S + pf->lm[0][1] * T + pf->lm[0][2];
    double v = pf->lm[1][0] * S + pf->lm[1][1] * T + pf->lm[1][2];
    if (!(u > 0)) u = 0;
    if (!(v > 0)) v = 0;
    if (u > pf->smax - 1) u = pf->smax - 1;
    if (v > pf->tmax - 1) v = pf->tmax - 1;
    int iu = (int)u, iv = (int)v;
    int iu1 = iu + 1 < pf->smax ? iu + 1 : iu, iv1 = iv + 1 < pf->tmax ? iv + 1 : iv;
    double fu = u - iu, fv = v - iv;
    double wgt[4] = {(1 - fu) * (1 - fv), fu * (1 - fv), (1 - fu) * fv, fu * fv};
    int at[4] = {iv * pf->smax + iu, iv * pf->smax + iu1, iv1 * pf->smax + iu, iv1 * pf->smax + iu1};
    int size = pf->smax * pf->tmax;
    double sum[3] = {0, 0, 0};
    for (int k = 0; k < 4 && pf->f->styles[k] != 255; k++) {
        double value = tp->style[pf->f->styles[k]];
        size_t base = (size_t)pf->lightofs + (size_t)k * (size_t)size;
        for (int c = 0; c < 4; c++) {
            if (tp->rgb) {
                const uint8_t *p = w->rgblight + (base + (size_t)at[c]) * 3;
                for (int ch = 0; ch < 3; ch++) sum[ch] += wgt[c] * p[ch] * value;
            } else {
                double m = wgt[c] * w->lighting[base + (size_t)at[c]] * value;
                sum[0] += m, sum[1] += m, sum[2] += m;
            }
        }
    }
    for (int ch = 0; ch < 3; ch++) light[ch] = (int)(sum[ch] < 4e8 ? sum[ch] : 4e8);
}

/* Light (as ew_tp_light) to a colormap row in 8.8. */
static int light_to_row(int l) {
    if (l < 0) return 32 << 8;  /* no light data in the map */
    int row = (255 * 256 - l) / 4;
    return row < 64 ? 64 : row;
}

/* Channel ch of colour c under row (8.8): the colormap rows' RGB, straight
 * between two rows. */
static double row_rgb(const ew_twopass *tp, int c, int row, int ch) {
    int r0 = row >> 8, r1 = r0 + 1 < 64 ? r0 + 1 : 63;
    double f = (row & 255) / 256.0;
    double a = tp->palette[tp->colormap[r0 * 256 + c] * 3 + ch];
    double b = tp->palette[tp->colormap[r1 * 256 + c] * 3 + ch];
    return a + (b - a) * f;
}

void ew_tp_begin(ew_twopass *tp, const ew_world *w, const uint8_t *palette, const uint8_t *colormap,
                 const int *style, int rgb, int bpp, int classic) {
    tp->world = w, tp->palette = palette, tp->colormap = colormap, tp->style = style;
    tp->rgb = rgb, tp->bpp = bpp, tp->classic = classic;
    if (tp->fullbright_of == colormap) return;
    for (int c = 0; c < 256; c++) {
        int same = 1;
        for (int r = 0; r < 64 && same; r++) same = colormap[r * 256 + c] == c;
        tp->fullbright[c] = (uint8_t)same;
    }
    tp->fullbright_of = colormap;
}

uint32_t ew_tp_shade(const ew_twopass *tp, const ew_tp_face *pf, uint8_t c, const int light[3]) {
    int row[3];
    for (int ch = 0; ch < 3; ch++) row[ch] = light_to_row(light[ch]);
    int grey = row[0] == row[1] && row[1] == row[2];
    if (tp->bpp == 1) {
        if (grey || tp->fullbright[c]) return tp->colormap[(row[0] >> 8) * 256 + c];
        /* Tinted light in 8 bits (the rule docs/lighting.md states):
         * light whose channels spread less than a quarter of its level
         * keeps the colormap's ramp at the mean row; a real tint takes
         * the palette colour (not a fullbright, not the key colour)
         * nearest the lit RGB by a distance that weighs the difference's
         * chroma (what is left once its grey part, the channels' mean, is
         * taken away) twice and its grey part once. */
        int mean = (row[0] + row[1] + row[2]) / 3;
        int lo = row[0], hi = row[0];
        for (int ch = 1; ch < 3; ch++) lo = row[ch] < lo ? row[ch] : lo, hi = row[ch] > hi ? row[ch] : hi;
        if ((hi - lo) * 4 <= 255 * 64 - mean) return tp->colormap[(mean >> 8) * 256 + c];
        double rgb[3];
        for (int ch = 0; ch < 3; ch++) rgb[ch] = (int)row_rgb(tp, c, row[ch], ch);
        int best = 0;
        double bd = 1e30;
        for (int i = 0; i < 224; i++) {
            double e[3], g = 0, d = 0;
            for (int ch = 0; ch < 3; ch++) e[ch] = tp->palette[i * 3 + ch] - rgb[ch], g += e[ch] / 3;
            for (int ch = 0; ch < 3; ch++) d += 2 * (e[ch] - g) * (e[ch] - g) + g * g;
            if (d < bd) bd = d, best = i;
        }
        return (uint32_t)best;
    }
    if (pf->fence && c == 255) return 0;  /* a hole */
    int out[3];
    for (int ch = 0; ch < 3; ch++) {
        double x = row_rgb(tp, c, row[ch], ch);
        out[ch] = (int)(x + 0.5);
    }
    /* R, G, B, A bytes in memory (raster/target.h) */
    uint32_t px;
    uint8_t b[4] = {(uint8_t)out[0], (uint8_t)out[1], (uint8_t)out[2], 255};
    memcpy(&px, b, 4);
    return px;
}

void ew_tp_run(const ew_twopass *tp, const ew_tp_face *pf, uint8_t *row, int y, int x0, int x1) {
    enum { CHUNK = 256 };
    uint8_t idx[CHUNK];
    for (int a = x0; a < x1; a += CHUNK) {
        int b = a + CHUNK < x1 ? a + CHUNK : x1;
        /* Pass one: the unlit texture. */
        for (int x = a; x < b; x++) {
            int X, Y;
            uint8_t c = ew_tp_texel(pf, x, y, &X, &Y);
            idx[x - a] = c;
            if (tp->bpp == 1) {
                if (!(pf->fence && c == 255)) row[x] = c;
            } else {
                uint8_t px[4] = {tp->palette[c * 3], tp->palette[c * 3 + 1], tp->palette[c * 3 + 2], 255};
                if (!(pf->fence && c == 255)) memcpy(row + (size_t)x * 4, px, 4);
            }
        }
        /* Pass two: each pixel lit from the light map at its own texel. */
        for (int x = a; x < b; x++) {
            uint8_t c = idx[x - a];
            if (pf->fence && c == 255) continue;
            int X, Y, light[3];
            (void)ew_tp_texel(pf, x, y, &X, &Y);  /* the light map's coordinates, found again */
            ew_tp_light(tp, pf, X, Y, light);
            uint32_t v = ew_tp_shade(tp, pf, tp->bpp == 1 ? row[x] : c, light);
            if (tp->bpp == 1)
                row[x] = (uint8_t)v;
            else
                memcpy(row + (size_t)x * 4, &v, 4);
        }
    }
}

/* ---- the renderer's two passes (ew_tp_span) ---- */

/* The texture point of pixel (x, y) in 16.16 texels of the mip, from
 * texturemins, held to the face. */
static void st_fixed(const ew_tp_face *pf, int x, int y, int32_t out[2]) {
    double den = pf->d0 + pf->dx * x + pf->dy * y;
    for (int a = 0; a < 2; a++) {
        double s = den != 0 ? tex_coord(pf, a, x, y, den) : 0;
        double v = s / (double)(1 << pf->mip) - pf->mins[a];
        double hi = (double)pf->size[a] - 1.0 / 65536;
        if (!(v > 0)) v = 0;  /* NaN too */
        if (v > hi) v = hi;
        out[a] = (int32_t)(v * 65536.0);
    }
}

static inline int wrap_to(int x, int n, int mask) { return mask >= 0 ? x & mask : x % n; }

/* Light at texel (X, Y) on Quake's grid, in fixed point: the four samples
 * around the texel's corner weighted in 1/256. */
static void grid_light(const ew_twopass *tp, const ew_tp_face *pf, int X, int Y, int light[3]) {
    const ew_world *w = tp->world;
    int u16 = X << (pf->mip + 12), v16 = Y << (pf->mip + 12);  /* 16.16 samples */
    int iu = u16 >> 16, iv = v16 >> 16, fu = (u16 >> 8) & 255, fv = (v16 >> 8) & 255;
    if (iu > pf->smax - 1) iu = pf->smax - 1, fu = 0;
    if (iv > pf->tmax - 1) iv = pf->tmax - 1, fv = 0;
    int iu1 = iu + 1 < pf->smax ? iu + 1 : iu, iv1 = iv + 1 < pf->tmax ? iv + 1 : iv;
    int at[4] = {iv * pf->smax + iu, iv * pf->smax + iu1, iv1 * pf->smax + iu, iv1 * pf->smax + iu1};
    int wt[4] = {(256 - fu) * (256 - fv), fu * (256 - fv), (256 - fu) * fv, fu * fv};
    int size = pf->smax * pf->tmax, nc = tp->rgb ? 3 : 1;
    int sum[3] = {0, 0, 0};
    for (int k = 0; k < 4 && pf->f->styles[k] != 255; k++) {
        int value = tp->style[pf->f->styles[k]];
        size_t base = (size_t)pf->lightofs + (size_t)k * (size_t)size;
        const uint8_t *lm = nc == 3 ? w->rgblight + base * 3 : w->lighting + base;
        for (int ch = 0; ch < nc; ch++) {
            int b = 0;
            for (int c = 0; c < 4; c++) b += lm[at[c] * nc + ch] * wt[c];
            sum[ch] += (b >> 8) * value;  /* 8.8 sample times the style's value */
        }
    }
    for (int ch = 0; ch < 3; ch++) light[ch] = sum[nc == 3 ? ch : 0] >> 8;
}

void ew_tp_span(const ew_twopass *tp, const ew_tp_face *pf, uint8_t *row, int y, int x0, int x1) {
    enum { SEG = 16 };
    const int mw = (pf->tw & (pf->tw - 1)) == 0 ? pf->tw - 1 : -1, mh = (pf->th & (pf->th - 1)) == 0 ? pf->th - 1 : -1;
    const int bs = wrap(pf->mins[0], pf->tw), bt = wrap(pf->mins[1], pf->th);
    const uint8_t *tex = pf->tex->mip[pf->mip];
    const int grid = pf->lightofs >= 0 && !tp->world->facelm && tp->world->lighting;
    for (int a = x0; a < x1; a += SEG) {
        int n = a + SEG < x1 ? SEG : x1 - a;
        int32_t st0[2], st1[2];
        st_fixed(pf, a, y, st0);
        st_fixed(pf, a + n, y, st1);
        int32_t ds = (st1[0] - st0[0]) / n, dt = (st1[1] - st0[1]) / n;
        uint8_t idx[SEG];
        /* Pass one: the unlit texture. */
        int32_t s = st0[0], t = st0[1];
        for (int i = 0; i < n; i++, s += ds, t += dt) {
            int col = wrap_to(bs + (s >> 16), pf->tw, mw), rw = wrap_to(bt + (t >> 16), pf->th, mh);
            uint8_t c = idx[i] = tex[rw * pf->tw + col];
            if (pf->fence && c == 255) continue;
            if (tp->bpp == 1) {
                row[a + i] = c;
            } else {
                uint8_t px[4] = {tp->palette[c * 3], tp->palette[c * 3 + 1], tp->palette[c * 3 + 2], 255};
                memcpy(row + (size_t)(a + i) * 4, px, 4);
            }
        }
        /* Pass two: the light map's coordinates stepped again, each pixel lit. */
        s = st0[0], t = st0[1];
        for (int i = 0; i < n; i++, s += ds, t += dt) {
            uint8_t c = idx[i];
            if (pf->fence && c == 255) continue;
            int X = s >> 16, Y = t >> 16, light[3];
            if (grid)
                grid_light(tp, pf, X, Y, light);
            else
                ew_tp_light(tp, pf, X, Y, light);
            if (tp->bpp == 1) {
                int r0 = light_to_row(light[0]);
                if ((light[0] == light[1] && light[1] == light[2]) || tp->fullbright[c])
                    row[a + i] = tp->colormap[(r0 >> 8) * 256 + row[a + i]];
                else
                    row[a + i] = (uint8_t)ew_tp_shade(tp, pf, c, light);
                continue;
            }
            uint8_t px[4] = {0, 0, 0, 255};
            for (int ch = 0; ch < 3; ch++) {
                int rr = light_to_row(light[ch]), r0 = rr >> 8, r1 = r0 + 1 < 64 ? r0 + 1 : 63, f = rr & 255;
                int lo = tp->palette[tp->colormap[r0 * 256 + c] * 3 + ch], up = tp->palette[tp->colormap[r1 * 256 + c] * 3 + ch];
                px[ch] = (uint8_t)(lo + (((up - lo) * f) >> 8));
            }
            memcpy(row + (size_t)(a + i) * 4, px, 4);
        }
    }
}
