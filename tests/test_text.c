/*
 * Text drawn into the frame with the built-in font, and the statistics
 * overlay.  The font: every printable glyph has ink, no two are the same
 * (space is blank), anything else is the box.  Drawing, in 8-bit and true
 * colour at scales 1..4: exactly the glyph pixels of the font take the
 * text colour, nothing outside the block ew_text_size gives changes, text
 * half off the frame is clipped (ASan sees any write outside it).  The
 * overlay is read back with a small "OCR" (each cell against the font's own
 * glyphs) and must say the numbers of the ew_stats it was given.
 *
 * g and q (issue 33: they read as 9): drawn, read back, each is a small
 * letter with a descender at least 10 pixels from '9' at any vertical
 * shift, q's stem ends in a spur.  EW_FONT_PNG=file.png writes them big.
 *
 * EW_OVERLAY_PNG=file.png writes start.bsp's first view at 640x480 with
 * the overlay (docs/overlay.png).
 */
#include "util.h"
#include "overlay/overlay.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

/* ---- the font -------------------------------------------------------------- */

static void test_font(void) {
    uint8_t g[95][EW_FONT_GLYPH_H], box[EW_FONT_GLYPH_H];
    int blank = 0, same = 0, inkless = 0;
    for (int c = 32; c <= 126; c++) {
        CHECK(ew_font_glyph(c, g[c - 32]) == 1, "char %d is printable", c);
        int ink = 0;
        for (int r = 0; r < EW_FONT_GLYPH_H; r++) ink += g[c - 32][r] != 0 && g[c - 32][r] < 32;
        if (c == ' ') blank = !memcmp(g[0], (uint8_t[EW_FONT_GLYPH_H]){0}, EW_FONT_GLYPH_H);
        else if (!ink) inkless++, fprintf(stderr, "glyph '%c' has no ink\n", c);
    }
    for (int a = 0; a < 95; a++)
        for (int b = a + 1; b < 95; b++)
            if (!memcmp(g[a], g[b], EW_FONT_GLYPH_H)) same++, fprintf(stderr, "'%c' == '%c'\n", a + 32, b + 32);
    CHECK(blank, "space is blank");
    CHECK(inkless == 0, "%d printable glyphs without ink", inkless);
    CHECK(same == 0, "%d pairs of identical glyphs", same);
    CHECK(ew_font_glyph(127, box) == 0 && ew_font_glyph(0x80, box) == 0 && ew_font_glyph(9, box) == 0, "box");
    CHECK(box[0] == 0x1f && box[3] == 0x11 && box[6] == 0x1f, "the box glyph is a hollow rectangle");
    for (int c = 32; c <= 126; c++) CHECK(memcmp(box, g[c - 32], EW_FONT_GLYPH_H) != 0, "'%c' is not the box", c);
    int w, h;
    CHECK(ew_text_size("ab\ncde", 2, &w, &h) == 0 && w == (6 * 3 + 1) * 2 && h == (8 * 2 + 1) * 2, "%dx%d", w, h);
    CHECK(ew_text_size("", 1, &w, &h) == 0 && w == 0 && h == 0, "empty");
    CHECK(ew_text_size("x\n", 1, &w, &h) == 0 && w == 7 && h == 17, "trailing newline: %dx%d", w, h);
    CHECK(ew_text_size("x", 0, &w, &h) == -1 && ew_text_size("x", EW_TEXT_MAX_SCALE + 1, &w, &h) == -1 &&
              ew_text_size(NULL, 1, &w, &h) == -1, "bad arguments");
}

/* ---- a renderer and its frame -------------------------------------------- */

typedef struct fixture {
    ew_assets   *a;
    ew_renderer *r;
    ew_camera    cam;
    int          w, h, bpp;
    uint8_t     *before;     /* the frame as rendered */
} fixture;

static const uint8_t *frame_bytes(const fixture *f) {
    return f->bpp == 1 ? ew_frame_pixels(f->r) : (const uint8_t *)ew_frame_rgba(f->r);
}
/* Renders a fresh frame and keeps a copy of it. */
static void rerender(fixture *f) {
    ew_render(f->r, &f->cam, NULL);
    memcpy(f->before, frame_bytes(f), (size_t)f->w * f->h * f->bpp);
}
static int fixture_open(fixture *f, ew_assets *a, ew_color_mode mode, int w, int h) {
    ew_error err;
    memset(f, 0, sizeof *f);
    f->a = a, f->w = w, f->h = h, f->bpp = mode == EW_COLOR_TRUE ? 4 : 1;
    f->r = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                  .colormap = a->colormap, .width = w, .height = h,
                                                  .threads = 1, .color = mode}, &err);
    CHECK(f->r != NULL, "%s", err.msg);
    if (!f->r) return -1;
    ew_camera views[EW_MAX_VIEWS];
    if (ew_benchmark_views(a->world, views) > 0) f->cam = views[0];
    f->before = malloc((size_t)w * h * f->bpp);
    rerender(f);
    return 0;
}
static void fixture_close(fixture *f) {
    ew_renderer_destroy(f->r);
    free(f->before);
}
static int px_changed(const fixture *f, int x, int y) {
    size_t o = ((size_t)y * f->w + x) * f->bpp;
    return memcmp(frame_bytes(f) + o, f->before + o, f->bpp) != 0;
}
/* 1 if pixel (x, y) is the colour: an index in 8-bit, rgb in true colour. */
static int px_is(const fixture *f, int x, int y, int index, const uint8_t rgb[3]) {
    const uint8_t *p = frame_bytes(f) + ((size_t)y * f->w + x) * f->bpp;
    return f->bpp == 1 ? p[0] == index : p[0] == rgb[0] && p[1] == rgb[1] && p[2] == rgb[2] && p[3] == 255;
}
/* Changed pixels inside [x0, x1) x [y0, y1) and outside it. */
static void count_changed(const fixture *f, int x0, int y0, int x1, int y1, long *in, long *out) {
    *in = *out = 0;
    for (int y = 0; y < f->h; y++)
        for (int x = 0; x < f->w; x++)
            if (px_changed(f, x, y)) {
                if (x >= x0 && x < x1 && y >= y0 && y < y1) ++*in;
                else ++*out;
            }
}
/* The palette colour nearest to rgb over 0..254, found here independently. */
static int nearest(const uint8_t *pal, int r, int g, int b) {
    int best = 0;
    long bd = LONG_MAX;
    for (int i = 0; i < 255; i++) {
        long d = (long)(pal[3 * i] - r) * (pal[3 * i] - r) + (long)(pal[3 * i + 1] - g) * (pal[3 * i + 1] - g) +
                 (long)(pal[3 * i + 2] - b) * (pal[3 * i + 2] - b);
        if (d < bd) bd = d, best = i;
    }
    return best;
}

/* ---- g and q are not 9 (issue 33) ---------------------------------------- */

/* Pixels that differ between two glyphs, the least over vertical shifts of
 * a (a small letter shifted down still reads as the digit). */
static int glyph_distance(const uint8_t a[EW_FONT_GLYPH_H], const uint8_t b[EW_FONT_GLYPH_H]) {
    int best = 99;
    for (int k = -3; k <= 3; k++) {
        int d = 0;
        for (int r = 0; r < EW_FONT_GLYPH_H; r++) {
            int ar = r - k >= 0 && r - k < EW_FONT_GLYPH_H ? a[r - k] : 0;
            d += __builtin_popcount((unsigned)(ar ^ b[r]) & 0x1f);
        }
        if (d < best) best = d;
    }
    return best;
}

/* "9gqp" drawn into the frame at scale s, each cell read back from the
 * pixels that changed. */
static void read_cells(fixture *f, int s, uint8_t cells[4][EW_FONT_GLYPH_H]) {
    rerender(f);
    ew_text_style st = {{255, 255, 255}, 1, 254, 0};
    int x0 = 20, y0 = 20;
    ew_draw_text(f->r, x0, y0, s, "9gqp", &st);
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < EW_FONT_GLYPH_H; r++) {
            cells[c][r] = 0;
            for (int b = 0; b < EW_FONT_GLYPH_W; b++)
                if (px_changed(f, x0 + s + (c * EW_FONT_CELL_W + b) * s, y0 + s + r * s))
                    cells[c][r] |= (uint8_t)(0x10 >> b);
        }
}

static void test_g_q(fixture *f) {
    uint8_t cell[4][EW_FONT_GLYPH_H];  /* 9 g q p as drawn */
    read_cells(f, 3, cell);
    for (int c = 0; c < 4; c++) {
        uint8_t rows[EW_FONT_GLYPH_H];
        ew_font_glyph("9gqp"[c], rows);
        CHECK(!memcmp(rows, cell[c], EW_FONT_GLYPH_H), "'%c' drawn as its glyph", "9gqp"[c]);
    }
    for (int c = 1; c <= 2; c++) {
        char ch = "9gqp"[c];
        int d = glyph_distance(cell[c], cell[0]);
        CHECK(d >= 10, "'%c' differs from '9' in only %d pixels (at its best vertical shift): it reads as 9", ch, d);
        CHECK(cell[c][0] == 0 && cell[c][1] == 0, "'%c' is a small letter: nothing above the x-height (rows 0-1)",
              ch);
        CHECK(cell[c][6] != 0, "'%c' has a descender", ch);
    }
    /* q's stem ends in a spur: its last row is not the stem alone (as p's
     * is), so it is not a 9 or a mirrored p read small. */
    CHECK(cell[2][6] != cell[2][5], "'q' ends in a spur");
    CHECK(glyph_distance(cell[1], cell[2]) >= 3, "'g' and 'q' differ");
    const char *png = getenv("EW_FONT_PNG");  /* the four letters, to look at */
    if (png && f->bpp == 1) {
        ew_error err;
        rerender(f);
        ew_text_style st = {{255, 255, 255}, 1, 254, EW_TEXT_BOX};
        ew_draw_text(f->r, 20, 20, 8, "9gqp 9 g q\nQ9 gig qaq", &st);
        if (ew_write_frame_png(f->r, png, &err) < 0) fprintf(stderr, "%s\n", err.msg);
    }
}


/* ---- drawing ------------------------------------------------------------- */

/* Plain text: exactly the font's glyph pixels take the colour, every other
 * pixel keeps its value. */
static void test_plain(fixture *f) {
    const char *text = "Hi! 42\nxyz{}~\x01";
    const uint8_t rgb[3] = {250, 40, 200};
    ew_text_style st = {{250, 40, 200}, 1, 251, 0};
    for (int s = 1; s <= 4; s++) {
        int x = 9, y = 5, w, h;
        rerender(f);
        CHECK(ew_draw_text(f->r, x, y, s, text, &st) == 0, "draw");
        ew_text_size(text, s, &w, &h);
        long in, out, glyph_px = 0, wrong = 0, stray = 0;
        count_changed(f, x, y, x + w, y + h, &in, &out);
        CHECK(out == 0, "scale %d: %ld pixels changed outside the block", s, out);
        /* expected mask: walk the text as the layout says */
        int line = 0, col = 0;
        uint8_t *mask = calloc((size_t)f->w * f->h, 1);
        for (const char *p = text; *p; p++) {
            if (*p == '\n') { line++, col = 0; continue; }
            uint8_t rows[EW_FONT_GLYPH_H];
            ew_font_glyph((unsigned char)*p, rows);
            for (int r = 0; r < EW_FONT_GLYPH_H; r++)
                for (int c = 0; c < EW_FONT_GLYPH_W; c++)
                    if (rows[r] >> (4 - c) & 1)
                        for (int yy = 0; yy < s; yy++)
                            for (int xx = 0; xx < s; xx++)
                                mask[(size_t)(y + (1 + 8 * line + r) * s + yy) * f->w + x + (1 + 6 * col + c) * s + xx] = 1;
            col++;
        }
        for (int yy = 0; yy < f->h; yy++)
            for (int xx = 0; xx < f->w; xx++) {
                if (mask[(size_t)yy * f->w + xx]) {
                    glyph_px++;
                    wrong += !px_is(f, xx, yy, 251, rgb);
                } else {
                    stray += px_changed(f, xx, yy);
                }
            }
        free(mask);
        CHECK(glyph_px > 100L * s * s && wrong == 0, "scale %d: %ld of %ld glyph pixels not the colour", s, wrong, glyph_px);
        CHECK(stray == 0, "scale %d: %ld pixels off the glyphs changed", s, stray);
        CHECK(in > 0 && in <= glyph_px, "scale %d: %ld changed", s, in);
    }
    /* rgb without use_index: the nearest palette colour in 8-bit */
    rerender(f);
    ew_text_style st2 = {{250, 40, 200}, 0, 0, 0};
    ew_draw_text(f->r, 0, 0, 1, "#", &st2);
    CHECK(px_is(f, 2, 1, nearest(f->a->palette, 250, 40, 200), rgb), "nearest colour");
}

/* Box, shadow and outline stay inside the block; clipping at every edge. */
static void test_styles_and_clip(fixture *f) {
    const char *text = "Clip me\nat the edge";
    int flags[3] = {EW_TEXT_SHADOW | EW_TEXT_BOX, EW_TEXT_OUTLINE, EW_TEXT_OUTLINE | EW_TEXT_BOX};
    for (int k = 0; k < 3; k++)
        for (int s = 1; s <= 4; s++) {
            ew_text_style st = {{255, 255, 255}, 0, 0, flags[k]};
            int w, h;
            ew_text_size(text, s, &w, &h);
            int pos[6][2] = {{20, 20}, {-w / 2, -h / 2}, {f->w - w / 2, f->h - h / 2},
                             {-w / 2, f->h - h / 3}, {f->w - 5, -3}, {f->w / 3, f->h / 2}};
            for (int i = 0; i < 6; i++) {
                rerender(f);
                CHECK(ew_draw_text(f->r, pos[i][0], pos[i][1], s, text, &st) == 0, "draw");
                long in, out;
                count_changed(f, pos[i][0], pos[i][1], pos[i][0] + w, pos[i][1] + h, &in, &out);
                CHECK(out == 0 && in > 0, "flags %d scale %d at (%d,%d): %ld in, %ld out", flags[k], s,
                      pos[i][0], pos[i][1], in, out);
            }
        }
    /* wholly off the frame, at the ends of int: nothing changes */
    int far[4][2] = {{INT_MIN, 0}, {INT_MAX, 0}, {0, INT_MIN}, {-100000, INT_MAX - 5}};
    for (int i = 0; i < 4; i++) {
        rerender(f);
        ew_draw_text(f->r, far[i][0], far[i][1], 4, "far away\nstill", NULL);
        long in, out;
        count_changed(f, 0, 0, 0, 0, &in, &out);
        CHECK(out == 0, "far text %d changed %ld pixels", i, out);
    }
    CHECK(ew_draw_text(f->r, 0, 0, 0, "x", NULL) == -1 && ew_draw_text(NULL, 0, 0, 1, "x", NULL) == -1 &&
              ew_draw_text(f->r, 0, 0, 1, NULL, NULL) == -1, "bad arguments");
}

/* ---- the overlay, read back ---------------------------------------------- */

/* Reads the block at (x, y): each cell's 5x7 pixels of colour (index/rgb)
 * against the font's glyphs; '?' for a cell that matches none. */
static void ocr(const fixture *f, int x, int y, int s, int cols, int lines, int index,
                const uint8_t rgb[3], char *out) {
    uint8_t g[95][EW_FONT_GLYPH_H];
    for (int c = 32; c <= 126; c++) ew_font_glyph(c, g[c - 32]);
    char *o = out;
    for (int l = 0; l < lines; l++) {
        char *line = o;
        for (int c = 0; c < cols; c++) {
            uint8_t rows[EW_FONT_GLYPH_H] = {0};
            for (int r = 0; r < EW_FONT_GLYPH_H; r++)
                for (int k = 0; k < EW_FONT_GLYPH_W; k++) {
                    int px = x + (1 + 6 * c + k) * s, py = y + (1 + 8 * l + r) * s;
                    if (px_is(f, px, py, index, rgb)) rows[r] |= (uint8_t)(1 << (4 - k));
                }
            char ch = '?';
            for (int i = 0; i < 95; i++)
                if (!memcmp(rows, g[i], EW_FONT_GLYPH_H)) ch = (char)(32 + i);
            *o++ = ch;
        }
        while (o > line && o[-1] == ' ') o--;   /* the block is as wide as the longest line */
        if (l + 1 < lines) *o++ = '\n';
    }
    *o = 0;
}

static void test_overlay(fixture *f) {
    ew_stats st = {0};
    st.ms_front = 1.25, st.ms_scan = 0.5, st.ms_draw = 3.75, st.ms_models = 0.125, st.ms_total = 6.03;
    st.edges = 1234, st.surfaces = 567, st.surfaces_shown = 89, st.spans = 8901, st.surfaces_built = 12;
    st.surfaces_cached = 345;
    st.visible_leaves = 67;
    ew_camera cam = {{480, -352.5f, 88}, {-10, 90, 0}, 90, 0};
    ew_overlay_info info = {59.9, 0.31, &cam, 0, 0};
    const uint8_t white[3] = {255, 255, 255};
    int wi = nearest(f->a->palette, 255, 255, 255);
    /* the lines, spelled out here from the numbers */
    const char *want[] = {"fps 59.9 (16.7 ms)", "ms front 1.25 scan 0.50", "ms draw 3.75 models 0.12",
                          "ms total 6.03 present 0.31", "edges 1234 surfs 567 shown 89",
                          "spans 8901 cache built 12 hit 345", "leaves 67", "pos 480.0 -352.5 88.0", "ang -10.0 90.0 0.0"};
    char expect[512] = "";
    for (int i = 0; i < 9; i++) strcat(strcat(expect, want[i]), i < 8 ? "\n" : "");
    char text[512];
    int n = ew_format_stats_overlay(text, sizeof text, &st, &info);
    CHECK(n == (int)strlen(expect) && !strcmp(text, expect), "format:\n%s\nwant:\n%s", text, expect);

    for (int corner = 0; corner < 4; corner++)
        for (int s = 1; s <= 3; s++) {
            rerender(f);
            info.corner = corner, info.scale = s;
            CHECK(ew_draw_stats_overlay(f->r, &st, &info) == 0, "overlay");
            int w, h;
            ew_text_size(expect, s, &w, &h);
            int x = corner & 1 ? f->w - 4 * s - w : 4 * s, y = corner & 2 ? f->h - 4 * s - h : 4 * s;
            long in, out;
            count_changed(f, x, y, x + w, y + h, &in, &out);
            CHECK(out == 0 && in > 0, "corner %d scale %d: %ld in, %ld out", corner, s, in, out);
            char read[1024];
            ocr(f, x, y, s, (w / s - 1) / 6, (h / s - 1) / 8, wi, white, read);
            CHECK(!strcmp(read, expect), "corner %d scale %d read back:\n%s", corner, s, read);
        }
    /* without extra: the stats lines only, top-left, automatic scale */
    rerender(f);
    CHECK(ew_draw_stats_overlay(f->r, &st, NULL) == 0, "overlay without extra");
    ew_format_stats_overlay(text, sizeof text, &st, NULL);
    CHECK(!strncmp(text, "ms front 1.25", 13) && !strstr(text, "fps") && !strstr(text, "pos") &&
              strstr(text, "ms total 6.03\n"), "%s", text);
    int w, h;
    ew_text_size(text, 1, &w, &h);
    char read[1024];
    ocr(f, 4, 4, 1, (w - 1) / 6, (h - 1) / 8, wi, white, read);
    CHECK(!strcmp(read, text), "read back:\n%s", read);
    info.corner = 4;
    CHECK(ew_draw_stats_overlay(f->r, &st, &info) == -1 && ew_draw_stats_overlay(f->r, NULL, NULL) == -1,
          "bad arguments");
    /* a short buffer: truncated, the length needed returned */
    char small[10];
    CHECK(ew_format_stats_overlay(small, sizeof small, &st, NULL) == (int)strlen(text) && strlen(small) == 9,
          "truncation");
}

/* docs/overlay.png: start.bsp at 640x480 with the overlay of its own stats. */
static void write_picture(const char *path) {
    if (!ew_t_need_shared("data/librequake/maps/start.bsp")) return;
    ew_assets *a = ew_t_load_map("start");
    if (!a) return;
    ew_error err;
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                            .colormap = a->colormap, .width = 640,
                                                            .height = 480}, &err);
    ew_camera views[EW_MAX_VIEWS];
    ew_camera cam = {{0}, {0}, 90, 0};
    if (ew_benchmark_views(a->world, views) > 0) cam = views[0];
    ew_stats st;
    ew_render(r, &cam, &st);   /* once to warm the surface cache, then the frame shown */
    ew_render(r, &cam, &st);
    ew_overlay_info info = {st.ms_total > 0 ? 1000.0 / st.ms_total : 0, 0.0, &cam, 0, 0};
    CHECK(ew_draw_stats_overlay(r, &st, &info) == 0, "overlay");
    ew_text_style title = {{255, 220, 120}, 0, 0, EW_TEXT_OUTLINE};
    ew_draw_text(r, 640 - 4 - (6 * 15 + 1) * 2, 480 - 4 - 17 * 2, 2, "edgewise start", &title);
    CHECK(ew_write_frame_png(r, path, &err) == 0, "%s", err.msg);
    printf("wrote %s\n", path);
    ew_renderer_destroy(r);
    ew_assets_destroy(a);
}

int main(void) {
    test_font();
    ew_error err;
    ew_assets *a = ew_assets_create_builtin(&err);
    CHECK(a != NULL, "%s", err.msg);
    if (a) {
        ew_color_mode modes[2] = {EW_COLOR_8BIT, EW_COLOR_TRUE};
        for (int m = 0; m < 2; m++) {
            fixture f;
            if (fixture_open(&f, a, modes[m], 640, 480) < 0) continue;
            test_plain(&f);
            test_g_q(&f);
            test_styles_and_clip(&f);
            test_overlay(&f);
            fixture_close(&f);
        }
        ew_assets_destroy(a);
    }
    const char *png = getenv("EW_OVERLAY_PNG");
    if (png) write_picture(png);
    return ew_t_finish();
}
