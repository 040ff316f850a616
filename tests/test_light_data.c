/*
 * Light data beyond the light lump: .lit files and the BSPX lumps
 * (RGBLIGHTING, LMSHIFT/LMOFFSET/LMSTYLE, DECOUPLED_LM), read into
 * ew_world.rgblight and ew_world.facelm (asset/lightdata.c).  Maps come
 * from the project's own writer (mapgen.h, ew_builtin_generate_ex); each
 * malformed case must give exactly one warning naming the file and the
 * problem while the map still loads; the real .lit files of the shared
 * maps attach quietly.
 */
#include "util.h"
#include "ew_world.h"
#include "light/light.h"
#include "renderer.h"
#include "mapgen_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static uint8_t palette[768], colormap[EW_COLORMAP_SIZE];

static gen generate(const ew_mapgen_options *o) { return generate_map(o, palette, colormap); }

static ew_world *load(const uint8_t *d, size_t n, const char *name) {
    ew_error err = {""};
    ew_world *w = ew_world_create(d, n, name, &err);
    CHECK(w != NULL, "%s does not load: %s", name, err.msg);
    return w;
}

/* Exactly one warning, naming the file and containing `what`. */
static void one_warning(const ew_world *w, const char *file, const char *what, const char *label) {
    const char *m = ew_world_warning(w, 0);
    CHECK(m && !ew_world_warning(w, 1), "%s: %d warnings (want 1): %s | %s", label, w->nwarnings, m ? m : "-",
          ew_world_warning(w, 1) ? ew_world_warning(w, 1) : "-");
    if (!m) return;
    CHECK(strstr(m, file) != NULL, "%s: warning does not name %s: %s", label, file, m);
    CHECK(strstr(m, what) != NULL, "%s: warning does not say '%s': %s", label, what, m);
    printf("  %-28s %s\n", label, m);
}

/* Offset of the BSPX entry named name in a generated image (the directory
 * follows the last standard lump, 4-byte aligned); -1 if none. */
static long bspx_entry(const uint8_t *d, size_t n, const char *name, long *dir_out) {
    uint32_t end = 0;
    for (int i = 0; i < EW_NUM_LUMPS; i++) {
        uint32_t e = (uint32_t)(d[4 + 8 * i] | d[5 + 8 * i] << 8 | d[6 + 8 * i] << 16 | (uint32_t)d[7 + 8 * i] << 24) +
                     (uint32_t)(d[8 + 8 * i] | d[9 + 8 * i] << 8 | d[10 + 8 * i] << 16 | (uint32_t)d[11 + 8 * i] << 24);
        if (e > end) end = e;
    }
    long dir = (long)((end + 3) & ~3u);
    if (dir_out) *dir_out = dir;
    if ((size_t)dir + 8 > n || memcmp(d + dir, "BSPX", 4)) return -1;
    int cnt = d[dir + 4];
    for (int i = 0; i < cnt; i++)
        if (!strcmp((const char *)d + dir + 8 + 32 * i, name)) return dir + 8 + 32 * i;
    return -1;
}
static int32_t rd32(const uint8_t *p) { return (int32_t)((uint32_t)p[0] | p[1] << 8 | p[2] << 16 | (uint32_t)p[3] << 24); }
static void wr32(uint8_t *p, int32_t v) {
    for (int k = 0; k < 4; k++) p[k] = (uint8_t)((uint32_t)v >> (8 * k));
}

/* ---- .lit ------------------------------------------------------------------- */

static void test_lit(void) {
    gen plain = generate(NULL);
    ew_mapgen_options o = {.lit = 1};
    gen g = generate(&o);
    CHECK(g.size == plain.size && !memcmp(g.bsp, plain.bsp, g.size), ".lit option changed the BSP");
    ew_world *w = load(g.bsp, g.size, "lit.bsp");
    if (!w) return;
    CHECK(g.lit_size == 8 + 3 * (size_t)w->lightsize, ".lit image size %zu for %d samples", g.lit_size, w->lightsize);
    CHECK(ew_world_attach_lit(w, g.lit, g.lit_size, "maps/lit.lit") == 0 && w->rgblight, "good .lit not attached");
    CHECK(w->nwarnings == 0, "good .lit warned: %s", ew_world_warning(w, 0));
    int same = 1;
    for (int i = 0; i < w->lightsize && w->rgblight; i++)
        for (int c = 0; c < 3; c++) same &= w->rgblight[3 * i + c] == w->lighting[i];
    CHECK(same, "white .lit differs from the mono light");
    ew_world_destroy(w);

    struct { const char *label, *what; size_t size; int patch; } bad[] = {
        {"lit: wrong size", "does not match", g.lit_size + 3, 0},
        {"lit: bad magic", "QLIT", g.lit_size, 1},
        {"lit: bad version", "version 2", g.lit_size, 2},
        {"lit: truncated header", "truncated .lit header", 6, 0},
        {"lit: truncated samples", "truncated .lit", g.lit_size - 3, 0},
    };
    uint8_t *buf = malloc(g.lit_size + 3);
    for (size_t k = 0; buf && k < sizeof bad / sizeof bad[0]; k++) {
        memset(buf, 0, g.lit_size + 3);
        memcpy(buf, g.lit, g.lit_size);
        if (bad[k].patch == 1) buf[1] = 'X';
        if (bad[k].patch == 2) wr32(buf + 4, 2);
        w = load(g.bsp, g.size, "lit.bsp");
        if (!w) continue;
        CHECK(ew_world_attach_lit(w, buf, bad[k].size, "maps/bad.lit") == 1, "%s: attached", bad[k].label);
        CHECK(w->rgblight == NULL, "%s: rgblight set", bad[k].label);
        one_warning(w, "maps/bad.lit", bad[k].what, bad[k].label);
        ew_world_destroy(w);
    }
    free(buf);
    free(g.bsp), free(g.lit), free(plain.bsp);
}

/* The real .lit files beside the shared maps. */
static void test_shared_lits(void) {
    static const char *const maps[] = {"e2m1", "e4m1", "lqdm7", "slope", "start"};
    if (!ew_t_need_shared("data/librequake/maps/start.lit")) return;
    for (size_t i = 0; i < sizeof maps / sizeof maps[0]; i++) {
        char rel[128];
        snprintf(rel, sizeof rel, "data/librequake/maps/%s.lit", maps[i]);
        uint8_t *d;
        size_t n;
        ew_error err = {""};
        if (ew_read_file(ew_t_shared(rel), &d, &n, &err)) {
            CHECK(0, "%s", err.msg);
            continue;
        }
        ew_assets *a = ew_t_load_map(maps[i]);
        if (a) {
            const ew_world *w = a->world;
            CHECK(w->rgblight != NULL, "%s: .lit not attached", maps[i]);
            CHECK(n == 8 + 3 * (size_t)w->lightsize, "%s: .lit %zu bytes for %d samples", maps[i], n, w->lightsize);
            for (int k = 0; ew_world_warning(w, k); k++)
                CHECK(!strstr(ew_world_warning(w, k), ".lit"), "%s: %s", maps[i], ew_world_warning(w, k));
            CHECK(w->rgblight && !memcmp(w->rgblight, d + 8, n - 8), "%s: rgblight is not the .lit's", maps[i]);
            int coloured = 0;
            for (int k = 0; w->rgblight && k < w->lightsize; k++)
                coloured += w->rgblight[3 * k] != w->rgblight[3 * k + 1] || w->rgblight[3 * k + 1] != w->rgblight[3 * k + 2];
            printf("  %-6s .lit attached: %d samples, %d coloured\n", maps[i], w->lightsize, coloured);
        }
        ew_assets_destroy(a);
        free(d);
    }
}

/* ---- BSPX ------------------------------------------------------------------- */

static void test_rgblighting(void) {
    ew_mapgen_options o = {.rgblighting = 1, .lit = 1};
    gen g = generate(&o);
    ew_world *w = load(g.bsp, g.size, "rgb.bsp");
    if (w) {
        CHECK(w->nwarnings == 0, "RGBLIGHTING warned: %s", ew_world_warning(w, 0));
        CHECK(w->rgblight != NULL && w->facelm == NULL, "RGBLIGHTING not read");
        int same = 1;
        for (int i = 0; w->rgblight && i < w->lightsize; i++)
            for (int c = 0; c < 3; c++) same &= w->rgblight[3 * i + c] == w->lighting[i];
        CHECK(same, "r=g=b RGBLIGHTING differs from the mono light");
        CHECK(w->rgblight && !memcmp(w->rgblight, g.lit + 8, g.lit_size - 8), "RGBLIGHTING differs from the .lit");
        ew_world_destroy(w);
    }
    /* tinted lights: the .lit wins over the lump */
    static const float tint[3 * EW_MAPGEN_MAX_LIGHTS] = {1, 0.3f, 0.2f, 0.2f, 0.4f, 1, 1, 1, 0.2f, 0.3f, 1, 0.3f,
                                                         1, 0.6f, 0.3f, 0.5f, 0.5f, 1, 1, 0.2f, 1, 0.8f, 0.8f, 0.8f};
    ew_mapgen_options t = {.lit = 1, .light_tint = tint};
    gen tg = generate(&t);
    w = load(g.bsp, g.size, "rgb.bsp");
    if (w) {
        CHECK(ew_world_attach_lit(w, tg.lit, tg.lit_size, "tint.lit") == 0, "tinted .lit not attached");
        CHECK(w->rgblight && !memcmp(w->rgblight, tg.lit + 8, tg.lit_size - 8), ".lit does not replace RGBLIGHTING");
        int coloured = 0;
        for (int i = 0; w->rgblight && i < w->lightsize; i++) coloured += w->rgblight[3 * i] != w->rgblight[3 * i + 2];
        CHECK(coloured > w->lightsize / 20, "tinted light shows no colour (%d of %d)", coloured, w->lightsize);
        ew_world_destroy(w);
    }
    free(tg.bsp), free(tg.lit);

    /* a wrong-size lump */
    long e = bspx_entry(g.bsp, g.size, "RGBLIGHTING", NULL);
    CHECK(e > 0, "no RGBLIGHTING entry");
    if (e > 0) {
        wr32(g.bsp + e + 28, rd32(g.bsp + e + 28) - 3);
        w = load(g.bsp, g.size, "rgb.bsp");
        if (w) {
            one_warning(w, "rgb.bsp", "RGBLIGHTING", "RGBLIGHTING: wrong size");
            CHECK(w->rgblight == NULL, "bad RGBLIGHTING used");
            ew_world_destroy(w);
        }
    }
    free(g.bsp), free(g.lit);
}

/* Faces' light maps lie one after another in the order of the faces, so
 * the sizes the loader found must add up to what the writer baked. */
static void check_packed(const ew_world *w, const char *label) {
    long at = 0;
    int ok = 1;
    for (int i = 0; i < w->numfaces; i++) {
        const ew_facelm *lm = &w->facelm[i];
        if (lm->lightofs < 0) continue;
        ok &= lm->lightofs == at;
        int ns = 0;
        while (ns < 4 && w->faces[i].styles[ns] != 255) ns++;
        at += (long)lm->width * lm->height * ns;
    }
    CHECK(ok && at == w->lightsize, "%s: light maps not packed as baked (%ld of %d)", label, at, w->lightsize);
}

/* Light at a few samples of the loaded layout against the baker's value at
 * the world point the layout puts them (samples well inside their face). */
static void check_samples(const ew_world *w, const ew_mapgen_options *o, const char *label) {
    int tested = 0, close = 0;
    for (int i = 0; i < w->numfaces && tested < 120; i += 3) {
        const ew_face *f = &w->faces[i];
        const ew_facelm *lm = &w->facelm[i];
        if (lm->lightofs < 0) continue;
        const ew_texinfo *ti = &w->texinfo[f->texinfo];
        const ew_plane *pl = &w->planes[f->plane];
        float lo[3] = {1e9f, 1e9f, 1e9f}, hi[3] = {-1e9f, -1e9f, -1e9f};
        for (int e = 0; e < f->numedges; e++)
            for (int k = 0; k < 3; k++) {
                float v = w->verts[ew_face_vertex(w, f, e)][k];
                lo[k] = fminf(lo[k], v), hi[k] = fmaxf(hi[k], v);
            }
        double a = lm->st_to_lm[0][0], b = lm->st_to_lm[0][1], c = lm->st_to_lm[1][0], d = lm->st_to_lm[1][1];
        double det = a * d - b * c;
        for (int v = 0; v < lm->height; v++)
            for (int u = 0; u < lm->width; u++) {
                /* (s, t) of sample (u, v), then the plane point with that (s, t) */
                double du = u - lm->st_to_lm[0][2], dv = v - lm->st_to_lm[1][2];
                double s = (d * du - b * dv) / det, t = (-c * du + a * dv) / det;
                double m[3][4];
                for (int k = 0; k < 3; k++) {
                    m[0][k] = ti->vecs[0][k], m[1][k] = ti->vecs[1][k], m[2][k] = pl->normal[k];
                }
                m[0][3] = s - ti->vecs[0][3], m[1][3] = t - ti->vecs[1][3], m[2][3] = pl->dist;
                double D = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
                float p[3];
                for (int k = 0; k < 3; k++) {
                    double mm[3][3];
                    for (int r = 0; r < 3; r++)
                        for (int q = 0; q < 3; q++) mm[r][q] = q == k ? m[r][3] : m[r][q];
                    double Dk = mm[0][0] * (mm[1][1] * mm[2][2] - mm[1][2] * mm[2][1]) -
                                mm[0][1] * (mm[1][0] * mm[2][2] - mm[1][2] * mm[2][0]) +
                                mm[0][2] * (mm[1][0] * mm[2][1] - mm[1][1] * mm[2][0]);
                    p[k] = (float)(Dk / D);
                }
                int inside = 1;
                for (int k = 0; k < 3; k++)
                    if (hi[k] > lo[k]) inside &= p[k] > lo[k] + 1.5f && p[k] < hi[k] - 1.5f;
                if (!inside) continue;
                float n[3];
                for (int k = 0; k < 3; k++) n[k] = (f->flags & EW_SURF_PLANEBACK) ? -pl->normal[k] : pl->normal[k];
                for (int k = 0; k < 3; k++) p[k] += n[k];
                uint8_t rgb[3];
                int want = ew_builtin_light_at(o, p, n, rgb);
                int got = w->lighting[lm->lightofs + v * lm->width + u];
                tested++;
                close += abs(got - want) <= 1;
                if (tested >= 120) goto done;
                u += lm->width / 3 + 1;  /* a few samples a face */
            }
    }
done:
    CHECK(tested >= 40 && close >= tested * 95 / 100, "%s: %d of %d samples match the baker", label, close, tested);
    printf("  %-28s %d of %d samples equal the baker's light at their world point\n", label, close, tested);
}

static void test_layouts(void) {
    gen plain = generate(NULL);
    ew_world *pw = load(plain.bsp, plain.size, "plain.bsp");
    if (!pw) return;
    CHECK(pw->facelm == NULL && pw->rgblight == NULL && pw->nwarnings == 0, "plain map has light extras");

    ew_mapgen_options o4 = {.lmshift_lumps = 1, .lmshift = 4};
    gen g4 = generate(&o4);
    ew_world *w = load(g4.bsp, g4.size, "shift4.bsp");
    if (w) {
        CHECK(w->nwarnings == 0, "LMSHIFT 4 warned: %s", ew_world_warning(w, 0));
        CHECK(w->facelm != NULL, "LMSHIFT 4: no facelm");
        CHECK(w->lightsize == pw->lightsize && !memcmp(w->lighting, pw->lighting, (size_t)w->lightsize),
              "LMSHIFT 4 light differs from the plain map's");
        int same = 1;
        for (int i = 0; w->facelm && i < w->numfaces; i++) {
            ew_facelm q;
            const ew_face *f = &pw->faces[i];
            q.width = (f->extents[0] >> 4) + 1, q.height = (f->extents[1] >> 4) + 1, q.lightofs = f->lightofs;
            const ew_facelm *lm = &w->facelm[i];
            same &= lm->width == q.width && lm->height == q.height && lm->lightofs == q.lightofs &&
                    w->faces[i].lightofs == f->lightofs && !memcmp(w->faces[i].styles, f->styles, 4);
            if (f->lightofs >= 0)
                same &= lm->st_to_lm[0][0] == 1.0f / 16 && lm->st_to_lm[0][1] == 0 &&
                        lm->st_to_lm[0][2] == -(float)f->texturemins[0] / 16 && lm->st_to_lm[1][1] == 1.0f / 16 &&
                        lm->st_to_lm[1][2] == -(float)f->texturemins[1] / 16;
        }
        CHECK(same, "LMSHIFT 4 layout is not Quake's");
        /* the light under models reads the same */
        ew_error err = {""};
        ew_renderer_desc d = {.world = w, .palette = palette, .colormap = colormap, .width = 320, .height = 200, .threads = 1};
        ew_renderer *r4 = ew_renderer_create(&d, &err);
        d.world = pw;
        ew_renderer *rp = ew_renderer_create(&d, &err);
        ew_camera views[EW_MAX_VIEWS];
        int nv = ew_benchmark_views(pw, views), eq = 1;
        for (int i = 0; r4 && rp && i < nv; i++) {
            int rgb[3];
            int a = ew_light_point_rgb(&r4->f, views[i].origin, rgb);
            eq &= a == ew_light_point(&rp->f, views[i].origin) && rgb[0] == a && rgb[1] == a && rgb[2] == a;
        }
        CHECK(r4 && rp && nv > 0 && eq, "light point differs on the LMSHIFT 4 map");
        ew_renderer_destroy(r4), ew_renderer_destroy(rp);
        ew_world_destroy(w);
    }
    free(g4.bsp);

    for (int shift = 3; shift <= 5; shift += 2) {
        ew_mapgen_options o = {.lmshift_lumps = 1, .lmshift = shift, .rgblighting = 1};
        gen g = generate(&o);
        char name[32], label[40];
        snprintf(name, sizeof name, "shift%d.bsp", shift);
        snprintf(label, sizeof label, "LMSHIFT %d", shift);
        w = load(g.bsp, g.size, name);
        if (w) {
            CHECK(w->nwarnings == 0, "%s warned: %s", label, ew_world_warning(w, 0));
            CHECK(w->facelm && w->rgblight, "%s: no facelm / rgblight", label);
            if (w->facelm) {
                int sized = 1;
                for (int i = 0; i < w->numfaces; i++) {
                    const ew_face *f = &w->faces[i];
                    if (w->facelm[i].lightofs < 0) continue;
                    int step = 1 << shift;
                    /* the builtin's texture coordinates are whole texels */
                    int ws = (int)(ceil((f->texturemins[0] + f->extents[0]) / (double)step) - floor(f->texturemins[0] / (double)step)) + 1;
                    sized &= w->facelm[i].width <= ws && w->facelm[i].width >= (f->extents[0] - 32) / step + 1;
                }
                CHECK(sized, "%s: sizes off the texture extents", label);
                check_packed(w, label);
                check_samples(w, &o, label);
            }
            ew_world_destroy(w);
        }
        free(g.bsp);
    }

    ew_mapgen_options od = {.decoupled = 1, .decoupled_units = 12};
    gen gd = generate(&od);
    w = load(gd.bsp, gd.size, "decoupled.bsp");
    if (w) {
        CHECK(w->nwarnings == 0, "DECOUPLED_LM warned: %s", ew_world_warning(w, 0));
        CHECK(w->facelm != NULL, "DECOUPLED_LM: no facelm");
        if (w->facelm) {
            check_packed(w, "DECOUPLED_LM");
            check_samples(w, &od, "DECOUPLED_LM 12 units");
        }
        ew_world_destroy(w);
    }
    ew_world_destroy(pw);
    free(plain.bsp), free(gd.bsp);

    /* ---- refusals: one warning each, the map still loads ---- */
    struct { const char *label, *lump, *what; int kind; } bad[] = {
        {"BSPX: directory overruns", "LMSHIFT", "overruns the file", 0},
        {"BSPX: lump outside the file", "LMSHIFT", "outside the file", 1},
        {"LMSHIFT: count != faces", "LMSHIFT", "LMSHIFT", 2},
        {"LMSHIFT: shift out of range", "LMSHIFT", "out of range", 3},
        {"DECOUPLED_LM: outside lump", "DECOUPLED_LM", "outside the light lump", 4},
        {"DECOUPLED_LM: count != faces", "DECOUPLED_LM", "DECOUPLED_LM", 5},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        ew_mapgen_options o = {.lmshift_lumps = bad[k].kind < 4, .lmshift = 5, .decoupled = bad[k].kind >= 4};
        gen g = generate(&o);
        long dir, e = bspx_entry(g.bsp, g.size, bad[k].lump, &dir);
        CHECK(e > 0, "%s: no %s entry", bad[k].label, bad[k].lump);
        if (e <= 0) {
            free(g.bsp);
            continue;
        }
        int32_t ofs = rd32(g.bsp + e + 24), len = rd32(g.bsp + e + 28);
        switch (bad[k].kind) {
        case 0: wr32(g.bsp + dir + 4, (int32_t)((g.size - (size_t)dir) / 32 + 1)); break;
        case 1: wr32(g.bsp + e + 24, (int32_t)g.size - len / 2); break;
        case 2: wr32(g.bsp + e + 28, len - 1); break;
        case 3: {
            /* the first lit face's shift */
            long lofs = bspx_entry(g.bsp, g.size, "LMOFFSET", NULL);
            int i = 0;
            while (rd32(g.bsp + rd32(g.bsp + lofs + 24) + 4 * i) < 0) i++;
            g.bsp[ofs + i] = 9;
            break;
        }
        case 4: {
            int i = 0;
            while (rd32(g.bsp + ofs + 40 * i + 4) < 0) i++;
            wr32(g.bsp + ofs + 40 * i + 4, rd32(g.bsp + 4 + 8 * EW_LUMP_LIGHTING + 4) - 2);
            break;
        }
        case 5: wr32(g.bsp + e + 28, len - 40); break;
        }
        w = load(g.bsp, g.size, "bspx.bsp");
        if (w) {
            one_warning(w, "bspx.bsp", bad[k].what, bad[k].label);
            CHECK(w->facelm == NULL && w->rgblight == NULL, "%s: layout used", bad[k].label);
            for (int i = 0; i < w->numfaces; i++) {
                const ew_face *f = &w->faces[i];
                int ns = 0;
                while (ns < 4 && f->styles[ns] != 255) ns++;
                if (f->lightofs >= 0 &&
                    f->lightofs + (long)((f->extents[0] >> 4) + 1) * ((f->extents[1] >> 4) + 1) * ns > w->lightsize) {
                    CHECK(0, "%s: face %d light map outside the lump", bad[k].label, i);
                    break;
                }
            }
            ew_world_destroy(w);
        }
        free(g.bsp);
    }
}

int main(void) {
    test_lit();
    test_shared_lits();
    test_rgblighting();
    test_layouts();
    return ew_t_finish();
}
