/*
 * Map generator: palette, colormap and procedural textures.
 *
 * The palette is laid out like Quake's: 14 ramps of 16 shades (dark to
 * bright) and 32 fullbright colours at 224..255 that lighting leaves alone.
 * Textures are drawn directly in palette indices (a ramp plus a shade), so
 * mip level 0 is exact; smaller mips box-filter in RGB and map back to the
 * nearest non-fullbright colour.  Everything is seeded, so the output is
 * the same on every run.
 */
#include "mapgen_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- palette ------------------------------------------------------------- */

/* Brightest colour of each ramp; shade 0 is near black. */
static const uint8_t ramp_top[14][3] = {
    {235, 235, 235}, /*  0 grey */
    {190, 140, 90},  /*  1 brown */
    {220, 195, 150}, /*  2 tan */
    {205, 95, 70},   /*  3 brick red */
    {235, 145, 60},  /*  4 rust */
    {175, 170, 100}, /*  5 olive */
    {110, 200, 90},  /*  6 green */
    {90, 190, 180},  /*  7 teal */
    {100, 140, 240}, /*  8 blue */
    {170, 185, 210}, /*  9 steel */
    {180, 120, 200}, /* 10 purple */
    {240, 210, 90},  /* 11 gold */
    {235, 175, 150}, /* 12 flesh */
    {175, 180, 160}, /* 13 stone */
};

static void lerp3(uint8_t *out, const int a[3], const int b[3], int i, int n) {
    for (int c = 0; c < 3; c++)
        out[c] = (uint8_t)(a[c] + (b[c] - a[c]) * i / (n > 1 ? n - 1 : 1));
}

void bi_make_palette(uint8_t pal[768]) {
    for (int r = 0; r < 14; r++)
        for (int i = 0; i < 16; i++) {
            /* grey starts at true black (index 0 is the sky's "clear") */
            double t = r == BI_R_GREY ? i / 15.0 : 0.06 + 0.94 * i / 15.0;
            for (int c = 0; c < 3; c++)
                pal[(r * 16 + i) * 3 + c] = (uint8_t)lrint(ramp_top[r][c] * t);
        }
    /* fullbrights: flame yellows, reds, greens, blues, white, placeholder */
    static const int fy0[3] = {255, 255, 170}, fy1[3] = {255, 110, 0};
    static const int fr0[3] = {255, 90, 70}, fr1[3] = {140, 0, 0};
    static const int fg0[3] = {170, 255, 130}, fg1[3] = {20, 130, 20};
    static const int fb0[3] = {190, 225, 255}, fb1[3] = {50, 60, 255};
    for (int i = 0; i < 8; i++) {
        lerp3(pal + (224 + i) * 3, fy0, fy1, i, 8);
        lerp3(pal + (232 + i) * 3, fr0, fr1, i, 8);
        lerp3(pal + (240 + i) * 3, fg0, fg1, i, 8);
    }
    for (int i = 0; i < 6; i++) lerp3(pal + (248 + i) * 3, fb0, fb1, i, 6);
    pal[254 * 3 + 0] = 255, pal[254 * 3 + 1] = 255, pal[254 * 3 + 2] = 255;
    pal[255 * 3 + 0] = 230, pal[255 * 3 + 1] = 130, pal[255 * 3 + 2] = 190;
}

/* Nearest ordinary (0..223) palette colour to an RGB value. */
static int nearest(const uint8_t pal[768], int r, int g, int b) {
    int best = 0;
    long bestd = -1;
    for (int i = 0; i < 224; i++) {
        long dr = r - pal[i * 3], dg = g - pal[i * 3 + 1], db = b - pal[i * 3 + 2];
        /* weighted like the eye: green counts most */
        long d = 3 * dr * dr + 4 * dg * dg + 2 * db * db;
        if (bestd < 0 || d < bestd) bestd = d, best = i;
    }
    return best;
}

void bi_make_colormap(const uint8_t pal[768], uint8_t cm[EW_COLORMAP_SIZE]) {
    for (int row = 0; row < 64; row++) {
        /* row 0 doubles the colour, row 32 keeps it, row 63 is ~black */
        double f = (64 - row) / 32.0;
        for (int c = 0; c < 256; c++) {
            if (c >= 224) { cm[row * 256 + c] = (uint8_t)c; continue; }
            int rgb[3];
            for (int k = 0; k < 3; k++) {
                double v = pal[c * 3 + k] * f;
                rgb[k] = v > 255 ? 255 : (int)lrint(v);
            }
            cm[row * 256 + c] = (uint8_t)nearest(pal, rgb[0], rgb[1], rgb[2]);
        }
    }
}

/* ---- deterministic noise -------------------------------------------------- */

static uint32_t hash3(uint32_t x, uint32_t y, uint32_t seed) {
    uint32_t h = x * 0x8da6b343u ^ y * 0xd8163841u ^ seed * 0xcb1ab31fu;
    h ^= h >> 15; h *= 0x2c1b3c6du;
    h ^= h >> 12; h *= 0x297a2d39u;
    h ^= h >> 15;
    return h;
}
static double rnd01(uint32_t x, uint32_t y, uint32_t seed) {
    return (hash3(x, y, seed) >> 8) / 16777216.0;
}

/* Value noise on a lattice of period x period cells; (u, v) in [0,1) tiles. */
static double vnoise(double u, double v, int period, uint32_t seed) {
    double x = u * period, y = v * period;
    int x0 = (int)floor(x), y0 = (int)floor(y);
    double fx = x - x0, fy = y - y0;
    fx = fx * fx * (3 - 2 * fx), fy = fy * fy * (3 - 2 * fy);
    int xa = ((x0 % period) + period) % period, ya = ((y0 % period) + period) % period;
    int xb = (xa + 1) % period, yb = (ya + 1) % period;
    double a = rnd01((uint32_t)xa, (uint32_t)ya, seed), b = rnd01((uint32_t)xb, (uint32_t)ya, seed);
    double c = rnd01((uint32_t)xa, (uint32_t)yb, seed), d = rnd01((uint32_t)xb, (uint32_t)yb, seed);
    return (a + (b - a) * fx) * (1 - fy) + (c + (d - c) * fx) * fy;
}
/* Fractal sum of octaves, roughly in [0,1]. */
static double fbm(double u, double v, int period, int octaves, uint32_t seed) {
    double sum = 0, amp = 0.5, norm = 0;
    for (int o = 0; o < octaves; o++) {
        sum += amp * vnoise(u, v, period << o, seed + (uint32_t)o * 101u);
        norm += amp;
        amp *= 0.5;
    }
    return sum / norm;
}

static uint8_t px(int ramp, double shade) {
    int s = (int)lrint(shade);
    s = s < 0 ? 0 : s > 15 ? 15 : s;
    return (uint8_t)(ramp * 16 + s);
}

double bi_fbm(double u, double v, int period, int octaves, uint32_t seed) {
    return fbm(u, v, period, octaves, seed);
}
uint8_t bi_px(int ramp, double shade) { return px(ramp, shade); }

/* ---- the textures ----------------------------------------------------------- */

static void tex_brick(uint8_t *p, int w, int h) {
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            int row = y / 16, yy = y % 16;
            int xs = (x + (row & 1) * 16) % w, col = xs / 32, xx = xs % 32;
            double n = fbm((double)x / w, (double)y / h, 8, 3, 11);
            if (yy < 2 || xx < 2) {  /* mortar */
                p[y * w + x] = px(BI_R_GREY, 5 + 3 * n);
                continue;
            }
            double base = 6.5 + 3.0 * rnd01((uint32_t)col, (uint32_t)row, 7);
            double s = base + 3.0 * (n - 0.5);
            if (yy == 2 || xx == 2) s += 1.5;      /* lit top-left edge */
            if (yy == 15 || xx == 31) s -= 2.0;    /* shadowed bottom-right */
            p[y * w + x] = px(BI_R_RED, s);
        }
}

static void tex_metal(uint8_t *p, int w, int h) {
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            int xx = x % 32, yy = y % 32;
            double n = fbm((double)x / w, (double)y / h, 4, 4, 23);
            double streak = vnoise((double)x / w, (double)y / h * 0.05, 32, 29);
            double s = 6.5 + 3.0 * (n - 0.5) + 2.0 * (streak - 0.5);
            if (xx == 0 || yy == 0) s = 12;
            else if (xx == 31 || yy == 31) s = 2;
            else if (xx == 1 || yy == 1) s += 2;
            else if (xx == 30 || yy == 30) s -= 2;
            /* rivets near the plate corners */
            for (int k = 0; k < 4; k++) {
                int cx = k & 1 ? 26 : 5, cy = k & 2 ? 26 : 5;
                int dx = xx - cx, dy = yy - cy;
                if (abs(dx) <= 1 && abs(dy) <= 1) s = dx + dy < 0 ? 13 : dx + dy > 0 ? 4 : 10;
            }
            p[y * w + x] = px(BI_R_STEEL, s);
        }
}

static void tex_floor(uint8_t *p, int w, int h) {
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            int xx = x % 32, yy = y % 32, checker = (x / 32 + y / 32) & 1;
            double n = fbm((double)x / w, (double)y / h, 8, 3, 37);
            if (xx < 2 || yy < 2) { p[y * w + x] = px(BI_R_BROWN, 3 + 2 * n); continue; }
            double s = (checker ? 9.0 : 6.5) + 3.0 * (n - 0.5);
            if (xx == 2 || yy == 2) s += 1;
            if (xx == 31 || yy == 31) s -= 1.5;
            p[y * w + x] = px(checker ? BI_R_TAN : BI_R_BROWN, s);
        }
}

/* Flagstones: rows of blocks of random width, each with its own shade,
 * weathered by noise and a few thin cracks. */
static void tex_stone(uint8_t *p, int w, int h) {
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double u = (double)x / w, v = (double)y / h;
            int row = y / 32, yy = y % 32;
            /* block edges of this row: widths 32..64 tiling the texture */
            int shift = (int)(rnd01((uint32_t)row, 3, 131) * 4) * 16;
            int xs = (x + shift) % w, col = xs / 64, xx = xs % 64;
            if (rnd01((uint32_t)row, (uint32_t)col, 137) < 0.5 && xx >= 32) col += 100, xx -= 32;
            double n = fbm(u, v, 8, 4, 41);
            double c = fbm(u, v, 4, 3, 43);
            if (yy < 2 || xx < 2) {
                p[y * w + x] = px(BI_R_GREY, 2.5 + 2 * n);
                continue;
            }
            double s = 6.0 + 3.0 * rnd01((uint32_t)row, (uint32_t)col, 139) + 4.0 * (n - 0.5);
            if (yy == 2 || xx == 2) s += 1.5;
            if (fabs(c - 0.5) < 0.012) s -= 3;
            p[y * w + x] = px(BI_R_STONE, s);
        }
}

static void tex_wood(uint8_t *p, int w, int h) {
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            int plank = x / 16, xx = x % 16;
            double off = rnd01((uint32_t)plank, 0, 53) * 6.28;
            double n = fbm((double)x / w, (double)y / h, 4, 3, 59);
            double grain = sin((double)y / h * 6.2831853 * 3 + off + 8 * n);
            double s = 7.0 + 1.8 * grain + 2.0 * rnd01((uint32_t)plank, 1, 61);
            if (xx == 0) s = 2;
            else if (xx == 15) s -= 2;
            else if (xx == 1) s += 1.5;
            p[y * w + x] = px(BI_R_BROWN, s);
        }
}

static void tex_water(uint8_t *p, int w, int h) {
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double u = (double)x / w, v = (double)y / h;
            double n = fbm(u, v, 4, 4, 71);
            double ripple = sin((u + v + 0.3 * n) * 6.2831853 * 2);
            p[y * w + x] = px(n > 0.62 ? BI_R_TEAL : BI_R_BLUE, 4.5 + 6 * (n - 0.5) + 1.5 * ripple);
        }
}

/* Left half: the front layer (clouds, 0 = clear); right half: the back. */
static void tex_sky(uint8_t *p, int w, int h) {
    int half = w / 2;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < half; x++) {
            double u = (double)x / half, v = (double)y / h;
            double n = fbm(u, v, 4, 5, 83);
            p[y * w + x] = n > 0.56 ? px(BI_R_GREY, 7 + (n - 0.56) * 40) : 0;
            double b = fbm(u, v, 4, 4, 89);
            p[y * w + half + x] = px(b > 0.6 ? BI_R_PURPLE : BI_R_BLUE, 3 + 7 * b);
        }
}

static void tex_button(uint8_t *p, int w, int h, int on) {
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double dx = x - (w - 1) / 2.0, dy = y - (h - 1) / 2.0, r = sqrt(dx * dx + dy * dy);
            uint8_t c;
            if (x == 0 || y == 0) c = px(BI_R_STEEL, 12);
            else if (x == w - 1 || y == h - 1) c = px(BI_R_STEEL, 2);
            else if (r < 7) c = on ? (uint8_t)(232 + (int)(r * 0.9)) : px(BI_R_RED, 3 + r * 0.5);
            else if (r < 9) c = px(BI_R_STEEL, dx + dy < 0 ? 3 : 11);  /* recessed rim */
            else c = px(BI_R_STEEL, 7 + 2 * fbm((double)x / w, (double)y / h, 4, 2, 97));
            p[y * w + x] = c;
        }
}

/* A plank door: four vertical planks held by two iron bands and a
 * diagonal brace, with a ring handle; 64x96, one door face. */
static void tex_door(uint8_t *p, int w, int h) {
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double u = (double)x / w, v = (double)y / h;
            int plank = x / 16, xx = x % 16;
            double n = fbm(u, v, 4, 3, 151);
            double off = rnd01((uint32_t)plank, 5, 157) * 6.28;
            /* grain runs down the planks */
            double grain = sin(u * 6.2831853 * 10 + off + 7 * fbm(u, v, 2, 2, 163));
            double s = 6.0 + 1.4 * grain + 1.5 * rnd01((uint32_t)plank, 7, 167) + 2.0 * (n - 0.5);
            int ramp = BI_R_BROWN;
            if (xx == 0) s = 1.5;
            else if (xx == 1) s += 1.5;
            else if (xx == 15) s -= 1.5;
            /* the brace: a plank from the lower band at the left up to the
             * upper band at the right */
            double along = (x - 2) / 60.0, centre = 74 - along * 52;
            double dy = y - centre;
            if (along >= -0.02 && along <= 1.02 && fabs(dy) < 6.5 && y > 20 && y < 76) {
                double g = sin((x + 0.87 * y) * 0.35 + 5 * n);
                s = 7.5 + 1.2 * g + 2.0 * (n - 0.5);
                if (dy < -5.5) s = 10.5;       /* lit upper edge */
                else if (dy > 5.5) s = 1.5;    /* shadowed lower edge */
            }
            /* iron bands with a rivet on each plank */
            for (int b = 0; b < 2; b++) {
                int y0 = b ? 76 : 12, yy = y - y0;
                if (yy < 0 || yy >= 8) continue;
                ramp = BI_R_STEEL;
                s = 5.0 + 3.0 * (fbm(u, v, 8, 2, 173) - 0.5);
                if (yy == 0) s = 11;
                else if (yy == 7) s = 1.5;
                int dx = xx - 8, dr = yy - 4;
                if (abs(dx) <= 1 && abs(dr) <= 1) s = dx + dr < 0 ? 13 : dx + dr > 0 ? 3 : 10;
            }
            /* a ring handle on a back plate */
            double hx = x - 52.5, hy = y - 50.5, r = sqrt(hx * hx + hy * hy);
            if (fabs(hx) <= 4.5 && hy >= -8.5 && hy <= -3.5) ramp = BI_R_STEEL, s = 4 + (hy < -7 ? 3 : 0);
            if (r >= 3.0 && r <= 5.0 && hy > -4) ramp = BI_R_STEEL, s = hx + hy < 0 ? 12 : 5;
            /* a darker frame round the whole door */
            if (x < 1 || x >= w - 1 || y < 1 || y >= h - 1) ramp = BI_R_BROWN, s = 1;
            p[y * w + x] = px(ramp, s);
        }
}

typedef struct texdef {
    const char *name;
    int w, h;
} texdef;
static const texdef texdefs[BI_NUM_TEXTURES] = {
    [BI_T_BRICK] = {"brick", 64, 64},     [BI_T_METAL] = {"metal", 64, 64},
    [BI_T_FLOOR] = {"floor", 64, 64},     [BI_T_STONE] = {"stone", 128, 128},
    [BI_T_WOOD] = {"wood", 64, 64},       [BI_T_WATER] = {"*water", 64, 64},
    [BI_T_SKY] = {"sky1", 256, 128},      [BI_T_BUTTON0] = {"+0button", 32, 32},
    [BI_T_BUTTON1] = {"+1button", 32, 32},  [BI_T_DOOR] = {"door", 64, 96},
};

int bi_texture_is_special(int tex) { return tex == BI_T_WATER || tex == BI_T_SKY; }

void bi_texture_size(int tex, int *w, int *h) {
    *w = texdefs[tex].w;
    *h = texdefs[tex].h;
}

static void draw(int t, uint8_t *p, int w, int h) {
    switch (t) {
    case BI_T_BRICK: tex_brick(p, w, h); break;
    case BI_T_METAL: tex_metal(p, w, h); break;
    case BI_T_FLOOR: tex_floor(p, w, h); break;
    case BI_T_STONE: tex_stone(p, w, h); break;
    case BI_T_WOOD: tex_wood(p, w, h); break;
    case BI_T_WATER: tex_water(p, w, h); break;
    case BI_T_SKY: tex_sky(p, w, h); break;
    case BI_T_BUTTON0: tex_button(p, w, h, 1); break;
    case BI_T_DOOR: tex_door(p, w, h); break;
    default: tex_button(p, w, h, 0); break;
    }
}

int bi_write_textures(const uint8_t pal[768], bi_buf *lump) {
    size_t start = lump->len;
    bi_put_i32(lump, BI_NUM_TEXTURES);
    size_t ofs_at = lump->len;
    bi_put_zeros(lump, 4 * BI_NUM_TEXTURES);
    for (int t = 0; t < BI_NUM_TEXTURES; t++) {
        int w = texdefs[t].w, h = texdefs[t].h;
        uint8_t *mip0 = malloc((size_t)w * h);
        if (!mip0) return -1;
        draw(t, mip0, w, h);
        size_t here = lump->len;
        if (!lump->failed) {
            uint32_t o = (uint32_t)(here - start);
            for (int k = 0; k < 4; k++) lump->data[ofs_at + 4 * t + k] = (uint8_t)(o >> (8 * k));
        }
        char name[16] = {0};
        memcpy(name, texdefs[t].name, strlen(texdefs[t].name));
        bi_put(lump, name, 16);
        bi_put_i32(lump, w);
        bi_put_i32(lump, h);
        int32_t ofs = 40;
        for (int m = 0; m < 4; m++) {
            bi_put_i32(lump, ofs);
            ofs += (w >> m) * (h >> m);
        }
        bi_put(lump, mip0, (size_t)w * h);
        for (int m = 1; m < 4; m++) {
            int mw = w >> m, mh = h >> m, k = 1 << m;
            for (int y = 0; y < mh; y++)
                for (int x = 0; x < mw; x++) {
                    int sum[3] = {0, 0, 0};
                    for (int j = 0; j < k; j++)
                        for (int i = 0; i < k; i++) {
                            int c = mip0[(y * k + j) * w + x * k + i];
                            for (int q = 0; q < 3; q++) sum[q] += pal[c * 3 + q];
                        }
                    int n = k * k;
                    bi_put_u8(lump, (uint8_t)nearest(pal, (sum[0] + n / 2) / n, (sum[1] + n / 2) / n,
                                                     (sum[2] + n / 2) / n));
                }
        }
        free(mip0);
    }
    return lump->failed ? -1 : 0;
}

/* The texture of a face of a cell of kind self_kind looking into a cell of
 * kind other_kind and material other_mat (the BSP writer asks per face). */
/* per material: floor (top of the cell), sides, ceiling (underside) */
static const uint8_t material_tex[BI_NUM_MATERIALS][3] = {
    [BI_M_BRICK] = {BI_T_FLOOR, BI_T_BRICK, BI_T_WOOD},
    [BI_M_STONE] = {BI_T_STONE, BI_T_STONE, BI_T_STONE},
    [BI_M_METAL] = {BI_T_METAL, BI_T_METAL, BI_T_METAL},
    [BI_M_WOOD] = {BI_T_WOOD, BI_T_WOOD, BI_T_WOOD},
    [BI_M_PLATFORM] = {BI_T_WOOD, BI_T_METAL, BI_T_METAL},
    [BI_M_BUTTON] = {BI_T_METAL, BI_T_BUTTON0, BI_T_METAL},
    [BI_M_TILE] = {BI_T_FLOOR, BI_T_STONE, BI_T_STONE},
};

int bi_face_texture(int self_kind, int other_kind, int other_mat, int facing) {
    if (other_kind == BI_SKY) return BI_T_SKY;
    /* the water surface, seen from above or below */
    if (other_kind == BI_WATER || (self_kind == BI_WATER && other_kind == BI_EMPTY)) return BI_T_WATER;
    int part = facing == 4 ? 0 : facing == 5 ? 2 : 1;
    return material_tex[other_mat][part];
}
