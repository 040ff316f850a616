/*
 * Colour: true-colour frames and coloured light (.lit, BSPX), at 320x200.
 *   1. true colour agrees with the reference path in true colour on every
 *      view of e1m1, lqdm7 and start (visible faces, exact colours);
 *   2. white light in true colour looks like the 8-bit frame (8x8 block
 *      means within 12 levels on at least 98% of blocks);
 *   3. exact equalities on the map writer's maps: a white .lit = no .lit,
 *      RGBLIGHTING = .lit, LMSHIFT 4 = the plain map;
 *   4. LMSHIFT 3, 5 and DECOUPLED_LM put the light where the plain map has
 *      it (and a deliberately wrong projection does not);
 *   5. the .lit's colour shows on lqdm7, start and e4m1, in the direction
 *      of the light's colour, and 8-bit frames use more palette entries;
 *   6. coloured dynamic lights;
 *   7. bad colour settings, and toggling lit/dither rebuilds and restores.
 * Under AddressSanitizer the shared maps use every second view.
 */
#include "edgewise_lab.h"
#include "util.h"
#include "ew_world.h"
#include "mapgen_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define W 320
#define H 200
#define NPX (W * H)

#define VIEW_STEP (EW_T_SANITIZED ? 2 : 1)

static ew_renderer *make(const ew_world *w, const uint8_t *pal, const uint8_t *cmap, ew_color_mode c) {
    ew_error err = {""};
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){.world = w, .palette = pal, .colormap = cmap,
                                                            .width = W, .height = H, .color = c},
                                        &err);
    CHECK(r != NULL, "renderer: %s", err.msg);
    return r;
}

/* The frame as R, G, B, A bytes (8-bit frames through the palette). */
static void frame_rgb(const ew_renderer *r, const uint8_t *pal, uint8_t *out) {
    if (ew_frame_color(r) == EW_COLOR_TRUE) {
        memcpy(out, ew_frame_rgba(r), 4 * (size_t)NPX);
        return;
    }
    const uint8_t *px = ew_frame_pixels(r);
    for (int i = 0; i < NPX; i++) {
        for (int c = 0; c < 3; c++) out[4 * i + c] = pal[3 * px[i] + c];
        out[4 * i + 3] = 255;
    }
}

/* A copy of the frame in its own format (NPX or 4 * NPX bytes). */
static size_t frame_bytes(const ew_renderer *r) { return ew_frame_color(r) == EW_COLOR_TRUE ? 4 * (size_t)NPX : NPX; }
static void frame_copy(const ew_renderer *r, uint8_t *out) {
    memcpy(out, ew_frame_color(r) == EW_COLOR_TRUE ? (const void *)ew_frame_rgba(r) : (const void *)ew_frame_pixels(r),
           frame_bytes(r));
}

/* ---- 1. true colour against the reference ------------------------------------ */

static void test_reference_true(void) {
    static const char *const maps[] = {"e1m1", "lqdm7", "start"};
    int *ids = malloc(sizeof(int) * NPX), *ref_ids = malloc(sizeof(int) * NPX);
    uint32_t *px = malloc(4 * NPX), *ref = malloc(4 * NPX);
    for (int mi = 0; mi < 3; mi++) {
        ew_assets *a = ew_t_load_map(maps[mi]);
        if (!a) continue;
        ew_camera views[EW_MAX_VIEWS];
        int nv = ew_benchmark_views(a->world, views);
        ew_renderer *r = make(a->world, a->palette, a->colormap, EW_COLOR_TRUE);
        CHECK(nv > 0, "%s: no views", maps[mi]);
        if (!r) {
            ew_assets_destroy(a);
            continue;
        }
        ew_enable_face_ids(r, 1);
        double fsum = 0, fworst = 1, csum = 0, cworst = 1;
        int n = 0;
        for (int v = 0; v < nv; v += VIEW_STEP, n++) {
            ew_error err = {""};
            CHECK(ew_set_subdivision(r, 1) == 0, "subdivision 1");
            CHECK(ew_render(r, &views[v], NULL) == 0, "%s view %d", maps[mi], v);
            CHECK(ew_frame_pixels(r) == NULL && ew_frame_rgba(r) != NULL, "true colour frame pointers");
            memcpy(ids, ew_frame_face_ids(r), sizeof(int) * NPX);
            memcpy(px, ew_frame_rgba(r), 4 * NPX);
            CHECK(ew_render_reference(r, &views[v], (uint8_t *)ref, ref_ids, &err) == 0, "%s", err.msg);
            long sf = 0, sc = 0;
            for (int i = 0; i < NPX; i++) sf += ids[i] == ref_ids[i], sc += px[i] == ref[i];
            double f = (double)sf / NPX, c = (double)sc / NPX;
            CHECK(f >= 0.99, "%s view %d: visible faces agree on %.2f%%", maps[mi], v, 100 * f);
            CHECK(c >= 0.99, "%s view %d: true colours agree on %.2f%%", maps[mi], v, 100 * c);
            fsum += f, csum += c;
            if (f < fworst) fworst = f;
            if (c < cworst) cworst = c;
        }
        printf("1. true colour vs reference %-6s views %2d  faces: mean %.3f%% worst %.3f%%  "
               "colours exact: mean %.3f%% worst %.3f%%\n",
               maps[mi], n, 100 * fsum / n, 100 * fworst, 100 * csum / n, 100 * cworst);
        ew_renderer_destroy(r);
        ew_assets_destroy(a);
    }
    free(ids), free(ref_ids), free(px), free(ref);
}

/* ---- 2. white light: true colour looks like 8-bit ------------------------------ */

/* Blocks of 8x8 pixels whose mean differs by more than tol levels in any
 * channel; *nblocks gets the count of blocks. */
static long blocks_off(const uint8_t *a, const uint8_t *b, double tol, long *nblocks) {
    long off = 0;
    *nblocks = 0;
    for (int by = 0; by + 8 <= H; by += 8)
        for (int bx = 0; bx + 8 <= W; bx += 8) {
            double d[3] = {0, 0, 0};
            for (int y = by; y < by + 8; y++)
                for (int x = bx; x < bx + 8; x++)
                    for (int c = 0; c < 3; c++) d[c] += a[4 * (y * W + x) + c] - b[4 * (y * W + x) + c];
            int bad = 0;
            for (int c = 0; c < 3; c++) bad |= fabs(d[c] / 64) > tol;
            off += bad;
            ++*nblocks;
        }
    return off;
}

static void test_white_like_8bit(void) {
    static const char *const maps[] = {"e1m1", "lqdm7", "e4m1", "start"};
    uint8_t *t = malloc(4 * NPX), *e = malloc(4 * NPX);
    for (int mi = 0; mi < 4; mi++) {
        ew_assets *a = ew_t_load_map(maps[mi]);
        if (!a) continue;
        ew_camera views[EW_MAX_VIEWS];
        int nv = ew_benchmark_views(a->world, views);
        ew_renderer *rt = make(a->world, a->palette, a->colormap, EW_COLOR_TRUE);
        ew_renderer *r8 = make(a->world, a->palette, a->colormap, EW_COLOR_8BIT);
        if (rt && r8) {
            ew_set_lit(rt, 0), ew_set_lit(r8, 0);
            long off = 0, all = 0, worst = 0;
            int worst_view = 0;
            for (int v = 0; v < nv; v += VIEW_STEP) {
                CHECK(ew_render(rt, &views[v], NULL) == 0 && ew_render(r8, &views[v], NULL) == 0, "%s view %d",
                      maps[mi], v);
                frame_rgb(rt, a->palette, t);
                frame_rgb(r8, a->palette, e);
                long nb, o = blocks_off(t, e, 12, &nb);
                off += o, all += nb;
                if (o > worst) worst = o, worst_view = v;
            }
            double frac = all ? (double)off / all : 1;
            printf("2. white light, true colour vs 8-bit %-6s: %ld of %ld blocks (%.3f%%) off by > 12 levels; "
                   "worst view %d (%ld blocks)\n",
                   maps[mi], off, all, 100 * frac, worst_view, worst);
            CHECK(frac <= 0.02, "%s: %.2f%% of 8x8 blocks differ by more than 12 levels", maps[mi], 100 * frac);
        }
        ew_renderer_destroy(rt), ew_renderer_destroy(r8);
        ew_assets_destroy(a);
    }
    free(t), free(e);
}

/* ---- maps from the map writer --------------------------------------------------- */

static uint8_t gpal[768], gcmap[EW_COLORMAP_SIZE];

static gen generate(const ew_mapgen_options *o) { return generate_map(o, gpal, gcmap); }

static ew_world *load(const gen *g, int attach_lit, const char *name) {
    ew_error err = {""};
    ew_world *w = g->bsp ? ew_world_create(g->bsp, g->size, name, &err) : NULL;
    CHECK(w != NULL, "%s: %s", name, err.msg);
    if (w && attach_lit) CHECK(ew_world_attach_lit(w, g->lit, g->lit_size, name) == 0, "%s: .lit refused", name);
    return w;
}

static const float tint[3 * EW_MAPGEN_MAX_LIGHTS] = {1, 0.3f, 0.2f, 0.2f, 0.4f, 1, 1, 1, 0.2f, 0.3f, 1, 0.3f,
                                                     1, 0.6f, 0.3f, 0.5f, 0.5f, 1, 1, 0.2f, 1, 0.8f, 0.8f, 0.8f};

/* The builtin's views plus a few more cameras: turned and raised. */
static int cameras(const ew_world *w, ew_camera *cams) {
    ew_camera v[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(w, v), n = 0;
    for (int i = 0; i < nv && n + 2 <= 12; i++) {
        cams[n++] = v[i];
        ew_camera c = v[i];
        c.angles[0] = 25, c.angles[1] += 40, c.origin[2] += 24;
        cams[n++] = c;
    }
    return n;
}

/* Renders every camera in both worlds' renderers (same mode) and counts
 * the cameras whose frames differ. */
static int frames_differ(const ew_world *wa, const ew_world *wb, ew_color_mode mode, const ew_camera *cams, int n,
                         int subdiv) {
    ew_renderer *ra = make(wa, gpal, gcmap, mode), *rb = make(wb, gpal, gcmap, mode);
    int differ = -1;
    if (ra && rb) {
        differ = 0;
        ew_set_subdivision(ra, subdiv), ew_set_subdivision(rb, subdiv);
        uint8_t *fa = malloc(4 * NPX);
        for (int i = 0; i < n; i++) {
            CHECK(ew_render(ra, &cams[i], NULL) == 0 && ew_render(rb, &cams[i], NULL) == 0, "render");
            frame_copy(ra, fa);
            const void *fb = mode == EW_COLOR_TRUE ? (const void *)ew_frame_rgba(rb) : (const void *)ew_frame_pixels(rb);
            differ += memcmp(fa, fb, frame_bytes(ra)) != 0;
        }
        free(fa);
    }
    ew_renderer_destroy(ra), ew_renderer_destroy(rb);
    return differ;
}

/* ---- 3. exact equalities --------------------------------------------------------- */

static void test_equalities(void) {
    gen plain = generate(NULL);
    ew_mapgen_options ol = {.lit = 1};
    gen white = generate(&ol);
    ew_world *pw = load(&plain, 0, "plain.bsp"), *ww = load(&white, 1, "white.bsp");
    ew_camera cams[12];
    int nc = pw ? cameras(pw, cams) : 0;
    CHECK(nc >= 4, "only %d cameras on the built-in map", nc);
    if (pw && ww) {
        CHECK(ww->rgblight != NULL, "white .lit not attached");
        int d16 = frames_differ(pw, ww, EW_COLOR_8BIT, cams, nc, 16), d1 = frames_differ(pw, ww, EW_COLOR_8BIT, cams, nc, 1);
        int dt = frames_differ(pw, ww, EW_COLOR_TRUE, cams, nc, 16);
        printf("3. white .lit vs no .lit: 8-bit frames differ on %d of %d cameras (subdivision 16), %d (subdivision 1); "
               "true colour %d\n",
               d16, nc, d1, dt);
        CHECK(d16 == 0 && d1 == 0, "a white .lit changes the 8-bit frame (%d, %d of %d cameras)", d16, d1, nc);
    }

    /* RGBLIGHTING = .lit, with white and with tinted lights */
    for (int tinted = 0; tinted < 2; tinted++) {
        ew_mapgen_options olit = {.lit = 1, .light_tint = tinted ? tint : NULL};
        ew_mapgen_options olump = {.lit = 1, .rgblighting = 1, .light_tint = tinted ? tint : NULL};
        gen gl = generate(&olit), gx = generate(&olump);
        ew_world *wl = load(&gl, 1, "lit.bsp"), *wx = load(&gx, 0, "rgblighting.bsp");
        if (wl && wx && pw) {
            CHECK(wx->rgblight != NULL && ew_world_warning(wx, 0) == NULL, "RGBLIGHTING not read");
            int d8 = frames_differ(wl, wx, EW_COLOR_8BIT, cams, nc, 16);
            int dt = frames_differ(wl, wx, EW_COLOR_TRUE, cams, nc, 16);
            /* the tinted light must show, or the equality above proves nothing */
            int dmono = tinted ? frames_differ(pw, wx, EW_COLOR_TRUE, cams, nc, 16) : 0;
            printf("3. %s RGBLIGHTING vs .lit: frames differ on %d (8-bit) and %d (true colour) of %d cameras%s",
                   tinted ? "tinted" : "white", d8, dt, nc, tinted ? "" : "\n");
            if (tinted) printf("; the tinted map differs from the plain map on %d\n", dmono);
            CHECK(d8 == 0 && dt == 0, "RGBLIGHTING frames differ from the .lit's (%d, %d)", d8, dt);
            CHECK(!tinted || dmono == nc, "tinted light invisible on %d of %d cameras", nc - dmono, nc);
        }
        ew_world_destroy(wl), ew_world_destroy(wx);
        gen_free(&gl), gen_free(&gx);
    }

    /* LMSHIFT 4 = the plain map */
    ew_mapgen_options o4 = {.lmshift_lumps = 1, .lmshift = 4};
    gen g4 = generate(&o4);
    ew_world *w4 = load(&g4, 0, "shift4.bsp");
    if (w4 && pw) {
        CHECK(w4->facelm != NULL, "LMSHIFT 4 not read");
        int d8 = frames_differ(pw, w4, EW_COLOR_8BIT, cams, nc, 16), dt = frames_differ(pw, w4, EW_COLOR_TRUE, cams, nc, 16);
        printf("3. LMSHIFT 4 vs plain: frames differ on %d (8-bit) and %d (true colour) of %d cameras\n", d8, dt, nc);
        CHECK(d8 == 0 && dt == 0, "LMSHIFT 4 frames differ from the plain map's (%d, %d)", d8, dt);
    }
    ew_world_destroy(w4), gen_free(&g4);
    ew_world_destroy(pw), ew_world_destroy(ww);
    gen_free(&plain), gen_free(&white);
}

/* ---- 4. other light-map layouts ------------------------------------------------ */

/* Mean brightness (R + G + B) / 3 of each 8x8 block. */
static void block_light(const uint8_t *rgba, double *out) {
    int k = 0;
    for (int by = 0; by + 8 <= H; by += 8)
        for (int bx = 0; bx + 8 <= W; bx += 8, k++) {
            double s = 0;
            for (int y = by; y < by + 8; y++)
                for (int x = bx; x < bx + 8; x++) {
                    const uint8_t *p = rgba + 4 * (y * W + x);
                    s += p[0] + p[1] + p[2];
                }
            out[k] = s / (3 * 64);
        }
}
#define NBLOCKS ((W / 8) * (H / 8))

typedef struct layout_cmp {
    double mean_diff, far_frac;  /* mean |block difference|; blocks off by > 10% + 4 levels */
    double worst_ref;            /* worst agreement with its own reference */
} layout_cmp;

static layout_cmp compare_layout(const ew_world *pw, const ew_world *lw, ew_color_mode mode, const ew_camera *cams,
                                 int n) {
    layout_cmp out = {0, 0, 1};
    ew_renderer *rp = make(pw, gpal, gcmap, mode), *rl = make(lw, gpal, gcmap, mode);
    uint8_t *a = malloc(4 * NPX), *b = malloc(4 * NPX), *own = malloc(4 * NPX), *ref = malloc(4 * NPX);
    double *ba = malloc(sizeof(double) * NBLOCKS), *bb = malloc(sizeof(double) * NBLOCKS);
    long far = 0, cnt = 0;
    double sum = 0;
    if (rp && rl) {
        ew_set_subdivision(rp, 1), ew_set_subdivision(rl, 1);
        for (int i = 0; i < n; i++) {
            ew_error err = {""};
            CHECK(ew_render(rp, &cams[i], NULL) == 0 && ew_render(rl, &cams[i], NULL) == 0, "render");
            frame_rgb(rp, gpal, a);
            frame_rgb(rl, gpal, b);
            frame_copy(rl, own);
            CHECK(ew_render_reference(rl, &cams[i], ref, NULL, &err) == 0, "%s", err.msg);
            long same = 0;
            if (mode == EW_COLOR_TRUE)
                for (int k = 0; k < NPX; k++) same += !memcmp(own + 4 * k, ref + 4 * k, 4);
            else
                for (int k = 0; k < NPX; k++) same += own[k] == ref[k];
            double ag = (double)same / NPX;
            if (ag < out.worst_ref) out.worst_ref = ag;
            block_light(a, ba);
            block_light(b, bb);
            for (int k = 0; k < NBLOCKS; k++) {
                double d = fabs(ba[k] - bb[k]);
                sum += d, cnt++;
                far += d > 4 + 0.1 * ba[k];
            }
        }
    }
    out.mean_diff = cnt ? sum / cnt : 1e9;
    out.far_frac = cnt ? (double)far / cnt : 1;
    ew_renderer_destroy(rp), ew_renderer_destroy(rl);
    free(a), free(b), free(own), free(ref), free(ba), free(bb);
    return out;
}

/* Offset of the BSPX lump named name in a generated image, its length in *len; -1 if none. */
static long bspx_lump(const uint8_t *d, size_t n, const char *name, int32_t *len) {
    uint32_t end = 0;
    for (int i = 0; i < EW_NUM_LUMPS; i++) {
        const uint8_t *p = d + 4 + 8 * i;
        uint32_t e = (uint32_t)(p[0] | p[1] << 8 | p[2] << 16 | (uint32_t)p[3] << 24) +
                     (uint32_t)(p[4] | p[5] << 8 | p[6] << 16 | (uint32_t)p[7] << 24);
        if (e > end) end = e;
    }
    size_t dir = (end + 3) & ~3u;
    if (dir + 8 > n || memcmp(d + dir, "BSPX", 4)) return -1;
    for (int i = 0; i < d[dir + 4]; i++) {
        const uint8_t *e = d + dir + 8 + 32 * i;
        if (!strcmp((const char *)e, name)) {
            int32_t ofs;
            memcpy(&ofs, e + 24, 4), memcpy(len, e + 28, 4);  /* little-endian hosts */
            return ofs;
        }
    }
    return -1;
}

static void test_layouts(void) {
    gen plain = generate(NULL);
    ew_world *pw = load(&plain, 0, "plain.bsp");
    if (!pw) return;
    ew_camera cams[12];
    int nc = cameras(pw, cams);
    /* The layouts sample the same light field at other points, so blocks
     * differ a little where shadows have edges: a layout at least as dense
     * as the plain map's 16 texels may differ by 2 levels on average (and
     * 7% of blocks by more than 4 + 10%), LMSHIFT 5 (32 texels) by twice
     * that.  The wrong projections must fail those limits. */
    struct { const char *label; ew_mapgen_options o; int wrong; double mean, far; } cases[] = {
        {"LMSHIFT 3", {.lmshift_lumps = 1, .lmshift = 3}, 0, 2, 0.07},
        {"LMSHIFT 5", {.lmshift_lumps = 1, .lmshift = 5}, 0, 4, 0.14},
        {"DECOUPLED_LM 12", {.decoupled = 1, .decoupled_units = 12}, 0, 2, 0.07},
        {"DECOUPLED_LM 12, shifted 1 sample", {.decoupled = 1, .decoupled_units = 12}, 1, 2, 0.07},
        {"DECOUPLED_LM 12, u and v swapped", {.decoupled = 1, .decoupled_units = 12}, 2, 2, 0.07},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        gen g = generate(&cases[c].o);
        if (cases[c].wrong && g.bsp) {
            /* a wrong projection: every face's light map moved by 1 sample (12 units)
             * along u, or its two rows exchanged */
            int32_t len;
            long ofs = bspx_lump(g.bsp, g.size, "DECOUPLED_LM", &len);
            CHECK(ofs > 0 && len == 40 * pw->numfaces, "no DECOUPLED_LM lump");
            for (int f = 0; ofs > 0 && f < len / 40; f++) {
                uint8_t *m = g.bsp + ofs + 40 * f + 8;
                float row[2][4];
                memcpy(row, m, sizeof row);
                if (cases[c].wrong == 1)
                    row[0][3] += 1;
                else
                    for (int k = 0; k < 4; k++) {
                        float s = row[0][k];
                        row[0][k] = row[1][k], row[1][k] = s;
                    }
                memcpy(m, row, sizeof row);
            }
        }
        ew_world *lw = load(&g, 0, "layout.bsp");
        if (lw) {
            CHECK(lw->facelm != NULL && ew_world_warning(lw, 0) == NULL, "%s: layout not read (%s)", cases[c].label,
                  ew_world_warning(lw, 0) ? ew_world_warning(lw, 0) : "no warning");
            for (int m = 0; m < 2; m++) {
                ew_color_mode mode = m ? EW_COLOR_TRUE : EW_COLOR_8BIT;
                layout_cmp k = compare_layout(pw, lw, mode, cams, nc);
                printf("4. %-36s %-5s vs plain: mean block brightness difference %.2f, blocks far off %.2f%%; "
                       "own reference agreement worst %.2f%%\n",
                       cases[c].label, m ? "true" : "8-bit", k.mean_diff, 100 * k.far_frac, 100 * k.worst_ref);
                int close = k.mean_diff <= cases[c].mean && k.far_frac <= cases[c].far;
                if (cases[c].wrong)
                    CHECK(!close, "%s %s: a wrong projection passes the brightness comparison (%.2f, %.2f%%)",
                          cases[c].label, m ? "true" : "8-bit", k.mean_diff, 100 * k.far_frac);
                else
                    CHECK(close, "%s %s: light off the plain map's: mean %.2f, %.2f%% blocks far off", cases[c].label,
                          m ? "true" : "8-bit", k.mean_diff, 100 * k.far_frac);
                CHECK(k.worst_ref >= 0.99, "%s %s: agrees with its reference on %.2f%%", cases[c].label,
                      m ? "true" : "8-bit", 100 * k.worst_ref);
            }
        }
        ew_world_destroy(lw);
        gen_free(&g);
    }
    ew_world_destroy(pw);
    gen_free(&plain);
}

/* ---- 5. the .lit's colour shows ------------------------------------------------- */

/* Mean chroma (each sample's r, g, b less their mean) of a face's first
 * light map (style 0) in the .lit; 0 if the face has none. */
static int face_chroma(const ew_world *w, int fi, double d[3]) {
    const ew_face *f = &w->faces[fi];
    int ofs = f->lightofs, n = ((f->extents[0] >> 4) + 1) * ((f->extents[1] >> 4) + 1);
    if (w->facelm) ofs = w->facelm[fi].lightofs, n = w->facelm[fi].width * w->facelm[fi].height;
    d[0] = d[1] = d[2] = 0;
    if (ofs < 0 || f->styles[0] == 255 || n <= 0 || ofs + n > w->lightsize) return 0;
    for (int i = 0; i < n; i++) {
        const uint8_t *q = w->rgblight + 3 * (size_t)(ofs + i);
        double m = (q[0] + q[1] + q[2]) / 3.0;
        for (int c = 0; c < 3; c++) d[c] += q[c] - m;
    }
    for (int c = 0; c < 3; c++) d[c] /= n;
    return 1;
}

static void test_lit_colour(void) {
    static const char *const maps[] = {"lqdm7", "start", "e4m1"};
    uint8_t *on = malloc(4 * NPX), *off = malloc(4 * NPX), *p8on = malloc(NPX);
    int *ids = malloc(sizeof(int) * NPX);
    for (int mi = 0; mi < 3; mi++) {
        ew_assets *a = ew_t_load_map(maps[mi]);
        if (!a) continue;
        const ew_world *w = a->world;
        CHECK(w->rgblight != NULL, "%s: no .lit", maps[mi]);
        /* per face: the unit chroma direction of its light, or 0 if grey */
        float(*dir)[3] = calloc((size_t)w->numfaces, sizeof *dir);
        uint8_t *strong = calloc((size_t)w->numfaces, 1);
        int coloured_faces = 0;
        for (int f = 0; w->rgblight && f < w->numfaces; f++) {
            double d[3];
            if (!face_chroma(w, f, d)) continue;
            double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            if (l < 10) continue;  /* light that is grey on average */
            for (int c = 0; c < 3; c++) dir[f][c] = (float)(d[c] / l);
            strong[f] = l >= 20;  /* near a clearly coloured light: where palette entries are counted */
            coloured_faces++;
        }
        ew_camera views[EW_MAX_VIEWS];
        int nv = ew_benchmark_views(w, views);
        ew_renderer *rt = make(w, a->palette, a->colormap, EW_COLOR_TRUE), *r8 = make(w, a->palette, a->colormap, EW_COLOR_8BIT);
        ew_renderer *rt0 = make(w, a->palette, a->colormap, EW_COLOR_TRUE), *r80 = make(w, a->palette, a->colormap, EW_COLOR_8BIT);
        /* The fair monochrome frame for counting palette entries: the same
         * map with its .lit made grey (each sample's channels at their mean),
         * so light of the same brightness without the colour.  (The map's
         * own mono lump is the brightest channel: brighter, so more shades.) */
        ew_world *wg = NULL;
        ew_renderer *r8g = NULL;
        {
            char rel[128];
            uint8_t *bsp = NULL, *lit = NULL;
            size_t bsize = 0, lsize = 0;
            ew_error err;
            snprintf(rel, sizeof rel, "data/librequake/maps/%s.bsp", maps[mi]);
            if (ew_read_file(ew_t_shared(rel), &bsp, &bsize, &err) == 0) wg = ew_world_create(bsp, bsize, maps[mi], &err);
            snprintf(rel, sizeof rel, "data/librequake/maps/%s.lit", maps[mi]);
            if (wg && ew_read_file(ew_t_shared(rel), &lit, &lsize, &err) == 0) {
                for (size_t i = 8; i + 3 <= lsize; i += 3) {
                    uint8_t m = (uint8_t)((lit[i] + lit[i + 1] + lit[i + 2] + 1) / 3);
                    lit[i] = lit[i + 1] = lit[i + 2] = m;
                }
                CHECK(ew_world_attach_lit(wg, lit, lsize, rel) == 0, "%s: grey .lit refused", maps[mi]);
            }
            free(bsp), free(lit);
            r8g = wg ? make(wg, a->palette, a->colormap, EW_COLOR_8BIT) : NULL;
            CHECK(r8g != NULL, "%s: grey-lit renderer", maps[mi]);
        }
        long npix = 0, toward = 0, against = 0, ent_on = 0, ent_off = 0, ent_grey = 0;
        double shift = 0;
        int views_used = 0;
        if (rt && r8 && rt0 && r80 && r8g) {
            ew_set_lit(rt0, 0), ew_set_lit(r80, 0);
            ew_enable_face_ids(rt, 1);
            for (int v = 0; v < nv; v += VIEW_STEP) {
                CHECK(ew_render(rt, &views[v], NULL) == 0 && ew_render(rt0, &views[v], NULL) == 0 &&
                      ew_render(r8, &views[v], NULL) == 0 && ew_render(r80, &views[v], NULL) == 0 &&
                      ew_render(r8g, &views[v], NULL) == 0, "%s view %d", maps[mi], v);
                const uint8_t *p8grey = ew_frame_pixels(r8g);
                memcpy(ids, ew_frame_face_ids(rt), sizeof(int) * NPX);
                frame_rgb(rt, a->palette, on);
                frame_rgb(rt0, a->palette, off);
                memcpy(p8on, ew_frame_pixels(r8), NPX);
                const uint8_t *p8off = ew_frame_pixels(r80);
                uint8_t used_on[256] = {0}, used_off[256] = {0}, used_grey[256] = {0};
                long here = 0, here_strong = 0;
                for (int i = 0; i < NPX; i++) {
                    int f = ids[i];
                    if (f < 0 || (dir[f][0] == 0 && dir[f][1] == 0 && dir[f][2] == 0)) continue;
                    const uint8_t *q = on + 4 * i, *o = off + 4 * i;
                    double mq = (q[0] + q[1] + q[2]) / 3.0, mo = (o[0] + o[1] + o[2]) / 3.0, s = 0;
                    for (int c = 0; c < 3; c++) s += ((q[c] - mq) - (o[c] - mo)) * dir[f][c];
                    shift += s, npix++, here++;
                    toward += s > 1, against += s < -1;
                    if (strong[f]) used_on[p8on[i]] = used_off[p8off[i]] = used_grey[p8grey[i]] = 1, here_strong++;
                }
                if (here_strong >= 500) {  /* palette entries where the view shows clearly coloured light */
                    views_used++;
                    for (int k = 0; k < 256; k++) ent_on += used_on[k], ent_off += used_off[k], ent_grey += used_grey[k];
                }
            }
        }
        double mean = npix ? shift / npix : 0;
        printf("5. %-6s %d coloured faces; %ld pixels on them: chroma moved along the light's colour by %.1f levels "
               "on average (%.1f%% toward, %.1f%% against); 8-bit palette entries there (%d views): %ld with .lit, "
               "%ld with it made grey, %ld without it (the mono lump)\n",
               maps[mi], coloured_faces, npix, mean, npix ? 100.0 * toward / npix : 0, npix ? 100.0 * against / npix : 0,
               views_used, ent_on, ent_grey, ent_off);
        CHECK(npix >= 2000, "%s: only %ld pixels of coloured light in view", maps[mi], npix);
        CHECK(mean >= 1.5 && toward >= npix * 2 / 5 && against * 5 <= toward, "%s: colour does not follow the light: %.2f levels, %ld toward, %ld against",
              maps[mi], mean, toward, against);
        /* More palette entries than the same light made grey, where the light
         * moves colours by 3 levels or more on average.  Where it is nearly
         * grey (lqdm7: 2.7 to 2.9) the counts only print: they come out
         * within a few percent either way, the 8-bit palette having little
         * to add for so slight a tint. */
        CHECK(views_used > 0, "%s: no view shows clearly coloured light", maps[mi]);
        if (mean >= 3)
            CHECK(ent_on > ent_grey, "%s: 8-bit with .lit uses %ld palette entries, with it grey %ld (colour shift %.1f)",
                  maps[mi], ent_on, ent_grey, mean);
        ew_renderer_destroy(rt), ew_renderer_destroy(r8), ew_renderer_destroy(rt0), ew_renderer_destroy(r80);
        ew_renderer_destroy(r8g);
        ew_world_destroy(wg);
        free(dir), free(strong);
        ew_assets_destroy(a);
    }
    free(on), free(off), free(p8on), free(ids);
}

/* ---- 6. coloured dynamic lights ------------------------------------------------- */

static void test_dlights(void) {
    ew_mapgen_options ol = {.lit = 1};
    gen g = generate(&ol);
    ew_world *pw = load(&g, 0, "plain.bsp"), *lw = load(&g, 1, "white.bsp");
    if (!pw || !lw) {
        ew_world_destroy(pw), ew_world_destroy(lw), gen_free(&g);
        return;
    }
    ew_camera cams[12];
    cameras(pw, cams);
    ew_camera cam = cams[0];
    float yaw = cam.angles[1] * 3.14159265f / 180;
    float at[3] = {cam.origin[0] + 96 * cosf(yaw), cam.origin[1] + 96 * sinf(yaw), cam.origin[2]};
    static const float red[3] = {1, 0, 0}, white[3] = {1, 1, 1};
    uint8_t *base = malloc(4 * NPX), *lit = malloc(4 * NPX), *wb = malloc(4 * NPX);
    for (int k = 0; k < 4; k++) {
        /* true colour without and with a (white) .lit, 8-bit with coloured
         * light (the white .lit), 8-bit monochrome */
        const ew_world *w = k == 1 || k == 2 ? lw : pw;
        ew_color_mode mode = k < 2 ? EW_COLOR_TRUE : EW_COLOR_8BIT;
        static const char *const labels[] = {"true colour", "true, .lit", "8-bit, .lit", "8-bit, no .lit"};
        const char *label = labels[k];
        ew_error err = {""};
        ew_scene *s0 = ew_scene_create(w, &err), *sr = ew_scene_create(w, &err), *sw = ew_scene_create(w, &err),
                 *sm = ew_scene_create(w, &err);
        ew_renderer *r = make(w, gpal, gcmap, mode);
        CHECK(s0 && sr && sw && sm, "scene: %s", err.msg);
        if (r && s0 && sr && sw && sm) {
            CHECK(ew_scene_add_dlight_rgb(sr, at, 250, red) >= 0 && ew_scene_add_dlight_rgb(sw, at, 250, white) >= 0 &&
                  ew_scene_add_dlight(sm, at, 250) >= 0, "dlights");
            ew_set_scene(r, s0);
            CHECK(ew_render(r, &cam, NULL) == 0, "render");
            frame_rgb(r, gpal, base);
            ew_set_scene(r, sr);
            CHECK(ew_render(r, &cam, NULL) == 0, "render");
            frame_rgb(r, gpal, lit);
            long changed = 0, gb_up = 0;
            double dr = 0, dg = 0, db = 0, redness = 0;
            for (int i = 0; i < NPX; i++) {
                const uint8_t *a = base + 4 * i, *b = lit + 4 * i;
                if (!memcmp(a, b, 3)) continue;
                changed++;
                dr += b[0] - a[0], dg += b[1] - a[1], db += b[2] - a[2];
                gb_up += b[1] > a[1] + 2 || b[2] > a[2] + 2;
                redness += (b[0] - (b[1] + b[2]) / 2.0) - (a[0] - (a[1] + a[2]) / 2.0);
            }
            double n = changed ? (double)changed : 1;
            printf("6. red dlight, %-15s: %ld pixels changed; mean change R %+.1f G %+.1f B %+.1f, redness %+.1f; "
                   "%ld with G or B up by > 2\n",
                   label, changed, dr / n, dg / n, db / n, redness / n, gb_up);
            CHECK(changed >= NPX / 50, "%s: red dlight changed only %ld pixels", label, changed);
            /* red in every mode (8-bit: the surfaces it reaches take the
             * nearest palette colours); in true colour green and blue are
             * untouched */
            CHECK(dr / n >= 8 && redness / n >= 8, "%s: red dlight not red: R %+.1f, redness %+.1f", label, dr / n,
                  redness / n);
            CHECK(k >= 2 || (fabs(dg / n) <= 0.5 && fabs(db / n) <= 0.5 && gb_up == 0),
                  "%s: red dlight raised G/B (%+.1f %+.1f, %ld pixels)", label, dg / n, db / n, gb_up);
            /* white by colour = the plain call, byte for byte */
            ew_set_scene(r, sw);
            CHECK(ew_render(r, &cam, NULL) == 0, "render");
            frame_copy(r, wb);
            ew_set_scene(r, sm);
            CHECK(ew_render(r, &cam, NULL) == 0, "render");
            frame_copy(r, lit);
            int same = !memcmp(wb, lit, frame_bytes(r));
            frame_rgb(r, gpal, lit);
            CHECK(same && memcmp(lit, base, 4 * NPX), "%s: white ew_scene_add_dlight_rgb differs from ew_scene_add_dlight (or lights nothing)", label);
            ew_set_scene(r, NULL);
        }
        ew_renderer_destroy(r);
        ew_scene_destroy(s0), ew_scene_destroy(sr), ew_scene_destroy(sw), ew_scene_destroy(sm);
    }
    free(base), free(lit), free(wb);
    ew_world_destroy(pw), ew_world_destroy(lw);
    gen_free(&g);
}

/* ---- 7. settings ------------------------------------------------------------------ */

static void test_settings(void) {
    ew_assets *a = ew_t_load_map("lqdm7");
    if (!a) return;
    static const int bad[] = {2, 7, -1};
    for (int i = 0; i < 3; i++) {
        ew_error err = {""};
        ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                                .colormap = a->colormap, .color = (ew_color_mode)bad[i]},
                                            &err);
        CHECK(r == NULL && err.msg[0], "color %d accepted", bad[i]);
        printf("7. color %d refused: %s\n", bad[i], err.msg);
        ew_renderer_destroy(r);
    }
    ew_camera views[EW_MAX_VIEWS];
    ew_benchmark_views(a->world, views);
    uint8_t *first = malloc(4 * NPX), *now = malloc(4 * NPX);
    for (int m = 0; m < 2; m++) {
        ew_color_mode mode = m ? EW_COLOR_TRUE : EW_COLOR_8BIT;
        const char *label = m ? "true colour" : "8-bit";
        ew_renderer *r = make(a->world, a->palette, a->colormap, mode);
        if (!r) continue;
        CHECK(ew_frame_color(r) == mode, "frame colour");
        ew_stats st;
#define FRAME(what)                                                                  \
    do {                                                                            \
        CHECK(ew_render(r, &views[0], &st) == 0, "%s: %s", label, what);            \
        frame_copy(r, now);                                                         \
    } while (0)
        FRAME("first");
        frame_copy(r, first);
        int built_first = st.surfaces_built;
        FRAME("warm");
        CHECK(st.surfaces_built == 0 && !memcmp(now, first, frame_bytes(r)), "%s: warm frame rebuilt %d surfaces",
              label, st.surfaces_built);
        /* Emptied (bench --cold): the next frame builds what the first one
         * did, and draws the same pixels. */
        ew_flush_surfaces(r);
        FRAME("cold");
        printf("7. %-11s first frame built %d surfaces, cold frame %d (frame %s)\n", label, built_first,
               st.surfaces_built, memcmp(now, first, frame_bytes(r)) ? "differs" : "= first");
        CHECK(built_first > 0 && st.surfaces_built == built_first && st.surfaces_cached == 0,
              "%s: cold frame built %d cached %d, the first built %d", label, st.surfaces_built, st.surfaces_cached,
              built_first);
        CHECK(!memcmp(now, first, frame_bytes(r)), "%s: the cold frame differs from the first", label);
        FRAME("warm after cold");
        CHECK(st.surfaces_built == 0 && !memcmp(now, first, frame_bytes(r)), "%s: warm after cold: built %d",
              label, st.surfaces_built);
        ew_set_lit(r, 0);
        FRAME("lit off");
        int built_off = st.surfaces_built, diff_off = memcmp(now, first, frame_bytes(r)) != 0;
        ew_set_lit(r, 0);
        FRAME("lit off again");
        int built_again = st.surfaces_built;
        ew_set_lit(r, 1);
        FRAME("lit on");
        int built_on = st.surfaces_built, back = !memcmp(now, first, frame_bytes(r));
        ew_set_dither(r, 1);
        FRAME("dither on");
        int built_d = st.surfaces_built, diff_d = memcmp(now, first, frame_bytes(r)) != 0;
        ew_set_dither(r, 0);
        FRAME("dither off");
        int built_d0 = st.surfaces_built, back_d = !memcmp(now, first, frame_bytes(r));
#undef FRAME
        printf("7. %-11s surfaces built: lit off %d (frame %s), again %d, lit on %d (frame %s); dither on %d (frame %s), "
               "off %d (frame %s)\n",
               label, built_off, diff_off ? "changed" : "same", built_again, built_on, back ? "= first" : "differs",
               built_d, diff_d ? "changed" : "same", built_d0, back_d ? "= first" : "differs");
        CHECK(built_off > 0 && diff_off, "%s: ew_set_lit(0) rebuilt %d surfaces, frame %s", label, built_off,
              diff_off ? "changed" : "the same");
        CHECK(built_again == 0, "%s: setting lit off twice rebuilt %d surfaces", label, built_again);
        CHECK(built_on > 0 && back, "%s: lit back on: %d rebuilt, frame %s", label, built_on, back ? "= first" : "differs");
        CHECK(built_d > 0 && built_d0 > 0 && back_d, "%s: dither toggles rebuilt %d / %d, frame back %d", label, built_d,
              built_d0, back_d);
        /* dithering is an 8-bit thing: it changes the coloured 8-bit frame, never true colour */
        CHECK(m ? !diff_d : diff_d, "%s: dither %s the frame", label, diff_d ? "changed" : "did not change");
        ew_renderer_destroy(r);
    }
    free(first), free(now);
    ew_assets_destroy(a);
}

int main(void) {
    if (!ew_t_need_shared("data/librequake/maps/start.lit")) return ew_t_finish();
    test_reference_true();
    test_white_like_8bit();
    test_equalities();
    test_layouts();
    test_lit_colour();
    test_dlights();
    test_settings();
    return ew_t_finish();
}
