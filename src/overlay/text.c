/* Text into a frame target with the built-in font (font.c), and the
 * statistics overlay of the viewer (edgewise.h documents both). */
#include "overlay/overlay.h"

#include <stdio.h>

#include "edgewise.h"

/* The palette colour nearest to rgb (squared distance), 0..254: 255 is the
 * fence textures' hole colour. */
static uint8_t nearest_index(const uint8_t *pal, int r, int g, int b) {
    int best = 0;
    long best_d = -1;
    for (int i = 0; i < 255; i++) {
        long dr = pal[i * 3] - r, dg = pal[i * 3 + 1] - g, db = pal[i * 3 + 2] - b;
        long d = dr * dr + dg * dg + db * db;
        if (best_d < 0 || d < best_d) best_d = d, best = i;
    }
    return (uint8_t)best;
}

/* The box: every pixel darkened to 3/8.  8-bit pixels become the palette
 * colour nearest to their darkened colour (looked up once per colour met). */
static void darken_rect(const ew_target *t, const uint8_t *pal, long long x0, long long y0,
                        long long x1, long long y1) {
    if (x0 < 0) x0 = 0;
    if (y0 < 0) y0 = 0;
    if (x1 > t->width) x1 = t->width;
    if (y1 > t->height) y1 = t->height;
    if (x0 >= x1 || y0 >= y1) return;
    uint8_t dark[256], known[256] = {0};
    for (int y = (int)y0; y < (int)y1; y++) {
        uint8_t *row = ew_target_at(t, 0, y);
        for (int x = (int)x0; x < (int)x1; x++) {
            if (t->bpp == 1) {
                uint8_t c = row[x];
                if (!known[c]) {
                    dark[c] = nearest_index(pal, pal[c * 3] * 3 / 8, pal[c * 3 + 1] * 3 / 8,
                                            pal[c * 3 + 2] * 3 / 8);
                    known[c] = 1;
                }
                row[x] = dark[c];
            } else {
                uint8_t px[4];
                memcpy(px, row + (size_t)x * 4, 4);
                for (int k = 0; k < 3; k++) px[k] = (uint8_t)(px[k] * 3 / 8);
                memcpy(row + (size_t)x * 4, px, 4);
            }
        }
    }
}

/* A solid rectangle [x0, x1) x [y0, y1), clipped. */
static void fill_rect(const ew_target *t, long long x0, long long y0, long long x1, long long y1,
                      uint8_t index, uint32_t rgba) {
    if (x0 < 0) x0 = 0;
    if (y0 < 0) y0 = 0;
    if (x1 > t->width) x1 = t->width;
    if (y1 > t->height) y1 = t->height;
    for (long long y = y0; y < y1; y++) {
        uint8_t *row = ew_target_at(t, 0, (int)y);
        for (long long x = x0; x < x1; x++) {
            if (t->bpp == 1)
                row[x] = index;
            else
                ew_set32(row, (int)x, rgba);
        }
    }
}

/* The block's size in cells: the longest line and the line count. */
static void text_cells(const char *text, long long *cols, long long *lines) {
    long long c = 0, best = 0, n = *text ? 1 : 0;
    for (const char *p = text; *p; p++) {
        if (*p == '\n')
            n++, c = 0;
        else if (++c > best)
            best = c;
    }
    *cols = best, *lines = n;
}

/* One pass over the text: the glyphs at offset (dx, dy) font pixels, in
 * index/rgba.  Characters wholly outside the frame are skipped. */
static void glyph_pass(const ew_target *t, long long x, long long y, int s, const char *text,
                       int dx, int dy, uint8_t index, uint32_t rgba) {
    long long line = 0, col = 0;
    for (const char *p = text; *p; p++) {
        if (*p == '\n') {
            line++, col = 0;
            continue;
        }
        long long gx = x + (1 + EW_FONT_CELL_W * col + dx) * s;
        long long gy = y + (1 + EW_FONT_CELL_H * line + dy) * s;
        col++;
        if (gx >= t->width || gy >= t->height || gx + EW_FONT_GLYPH_W * s <= 0 ||
            gy + EW_FONT_GLYPH_H * s <= 0)
            continue;
        uint8_t rows[EW_FONT_GLYPH_H];
        ew_font_glyph((unsigned char)*p, rows);
        for (int r = 0; r < EW_FONT_GLYPH_H; r++)
            for (int c = 0; c < EW_FONT_GLYPH_W; c++)
                if (rows[r] >> (EW_FONT_GLYPH_W - 1 - c) & 1)
                    fill_rect(t, gx + c * s, gy + r * s, gx + (c + 1) * s, gy + (r + 1) * s, index, rgba);
    }
}

int ew_target_text(const ew_target *t, int x, int y, int scale, const char *text, const ew_text_ink *ink) {
    if (!t || !text || !ink || scale < 1 || scale > EW_TEXT_MAX_SCALE) return -1;
    long long cols, lines;
    text_cells(text, &cols, &lines);
    if (!lines) return 0;
    if (ink->flags & EW_TEXT_BOX)
        darken_rect(t, ink->palette, x, y, x + (EW_FONT_CELL_W * cols + 1) * scale,
                    y + (EW_FONT_CELL_H * lines + 1) * scale);
    if (ink->flags & EW_TEXT_OUTLINE) {
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++)
                if (dx || dy) glyph_pass(t, x, y, scale, text, dx, dy, ink->dark, ink->dark_rgba);
    } else if (ink->flags & EW_TEXT_SHADOW) {
        glyph_pass(t, x, y, scale, text, 1, 1, ink->dark, ink->dark_rgba);
    }
    glyph_pass(t, x, y, scale, text, 0, 0, ink->fg, ink->fg_rgba);
    return 0;
}

int ew_text_size(const char *text, int scale, int *w, int *h) {
    if (!text || scale < 1 || scale > EW_TEXT_MAX_SCALE) return -1;
    long long cols, lines;
    text_cells(text, &cols, &lines);
    long long ww = lines ? (EW_FONT_CELL_W * cols + 1) * scale : 0;
    long long hh = lines ? (EW_FONT_CELL_H * lines + 1) * scale : 0;
    if (ww > 0x7fffffff || hh > 0x7fffffff) return -1;
    if (w) *w = (int)ww;
    if (h) *h = (int)hh;
    return 0;
}

int ew_text_draw(const ew_target *t, const uint8_t *pal, int x, int y, int scale, const char *text,
                 const ew_text_style *style) {
    if (!text) return -1;
    static const ew_text_style def = {{255, 255, 255}, 0, 0, EW_TEXT_SHADOW | EW_TEXT_BOX};
    if (!style) style = &def;
    ew_text_ink ink;
    ink.flags = style->flags;
    ink.palette = pal;
    ink.fg = style->use_index ? style->index : nearest_index(pal, style->rgb[0], style->rgb[1], style->rgb[2]);
    ink.dark = nearest_index(pal, 0, 0, 0);
    ink.fg_rgba = ew_rgba(style->rgb[0], style->rgb[1], style->rgb[2]);
    ink.dark_rgba = ew_rgba(0, 0, 0);
    return ew_target_text(t, x, y, scale, text, &ink);
}

int ew_format_stats_overlay(char *buf, size_t size, const ew_stats *st, const ew_overlay_info *extra) {
    if (!st) {
        if (buf && size) buf[0] = 0;
        return 0;
    }
    char fps[64] = "", present[48] = "", cam[128] = "";
    if (extra) {
        if (extra->fps > 0)
            snprintf(fps, sizeof fps, "fps %.1f (%.1f ms)\n", extra->fps, 1000.0 / extra->fps);
        else
            snprintf(fps, sizeof fps, "fps -\n");
        snprintf(present, sizeof present, " present %.2f", extra->ms_present);
        if (extra->camera) {
            const ew_camera *c = extra->camera;
            snprintf(cam, sizeof cam, "\npos %.1f %.1f %.1f\nang %.1f %.1f %.1f", c->origin[0],
                     c->origin[1], c->origin[2], c->angles[0], c->angles[1], c->angles[2]);
        }
    }
    return snprintf(buf, size,
                    "%sms front %.2f scan %.2f\nms draw %.2f models %.2f\nms total %.2f%s\n"
                    "edges %d surfs %d shown %d\nspans %d cache built %d hit %d\nleaves %d%s",
                    fps, st->ms_front, st->ms_scan, st->ms_draw, st->ms_models, st->ms_total, present,
                    st->edges, st->surfaces, st->surfaces_shown, st->spans, st->surfaces_built, st->surfaces_cached,
                    st->visible_leaves, cam);
}

int ew_stats_overlay_draw(const ew_target *t, const uint8_t *pal, const ew_stats *st, const ew_overlay_info *extra) {
    if (!st) return -1;
    int corner = extra ? extra->corner : 0, scale = extra ? extra->scale : 0;
    if (corner < 0 || corner > 3 || scale < 0 || scale > EW_TEXT_MAX_SCALE) return -1;
    if (!scale) {
        scale = t->height / 480;
        scale = scale < 1 ? 1 : scale > 4 ? 4 : scale;
    }
    char text[1024];
    ew_format_stats_overlay(text, sizeof text, st, extra);
    int w, h;
    if (ew_text_size(text, scale, &w, &h) < 0) return -1;
    int m = 4 * scale;
    int x = corner & 1 ? t->width - m - w : m;
    int y = corner & 2 ? t->height - m - h : m;
    return ew_text_draw(t, pal, x, y, scale, text, NULL);
}
