/*
 * Maps from the map compiler mappers use today: ../shared/data/ericw holds
 * LibreQuake's start and dev compiled by ericw-tools 2.0.0-alpha9 in seven
 * containers each (its README says how).  At 320x200, default look:
 *   1. every map loads without a warning and renders its view set (start
 *      also from the two cameras that see its coloured cubes) in 8-bit and
 *      true colour (under ASan+UBSan too, every second view: make test-asan);
 *   2. faces with no light map (an all-zero DECOUPLED_LM entry: width 0,
 *      height 0, offset -1, read from the file here) are drawn dark, pixel
 *      for pixel as the same faces of the plain BSP29 build, with and
 *      without a dynamic light on them; those faces are triggers, which
 *      scenes leave out, so each is added as a brush and looked at;
 *   3. the same light in another container gives the same frame byte for
 *      byte: BSP29 + .lit = BSP2 + .lit = BSP2 + RGBLIGHTING alone (coloured
 *      light on and off), a map's .lit = its own RGBLIGHTING lump, and
 *      start's BSP29 + LMSHIFT 3 + .lit = BSP2 + LMSHIFT 3 + RGBLIGHTING;
 *   4. `edgewise info` lists every map's BSPX lumps, each as used or not,
 *      and unknown ones without an error;
 *   5. the loader's checks of a DECOUPLED_LM entry (matrix finite, samples
 *      inside the light lump; 0 samples = no light map).
 * Counts of what was compared are printed.
 */
#define _POSIX_C_SOURCE 200809L  /* mkdtemp */
#include "edgewise_lab.h"
#include "util.h"
#include "ew_world.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define W 320
#define H 200
#define NPX (W * H)

/* Under AddressSanitizer every second camera of the view set (the cube
 * cameras always): every map is still drawn, in half the time. */
#define VIEW_STEP (EW_T_SANITIZED ? 2 : 1)

static const char *const suffixes[] = {"_plain",     "_bsp2_bspxlit", "_lmscale8",          "_lmshiftmix",
                                       "_decoupled", "_decoupled_novanilla", "_bsp2_bspxall"};
#define NSUF (int)(sizeof suffixes / sizeof suffixes[0])
/* The BSPX lumps each build carries (README), and whether edgewise uses
 * them; "RGBLIGHTING" is replaced by the .lit where one lies beside. */
static const char *const lumps_of[NSUF] = {
    "",
    "RGBLIGHTING",
    "LMSHIFT RGBLIGHTING",
    "LMSHIFT LMOFFSET RGBLIGHTING",
    "DECOUPLED_LM RGBLIGHTING",
    "DECOUPLED_LM RGBLIGHTING",
    "LMSHIFT RGBLIGHTING LIGHTINGDIR FACENORMALS LIGHTGRID_OCTREE BRUSHLIST",
};

/* start's coloured cubes (README); dev has no such cameras. */
static const ew_camera cube_cams[2] = {{{-100, -560, 60}, {20, 250, 0}, 90, 0},
                                       {{-48, -600, 80}, {30, 270, 0}, 90, 0}};

static long n_frames, n_pairs, n_pair_bytes, n_dark_px, n_dark_faces, n_info;

typedef struct map {
    char       name[64];
    ew_assets *a;       /* with its .lit when there is one */
    ew_world  *bare;    /* the same BSP without the .lit (its RGBLIGHTING lump), or NULL */
    ew_scene  *scene, *bare_scene;
    uint8_t   *bsp;     /* the file, for reading its BSPX directory here */
    size_t     size;
    int        has_lit;
} map;

static const char *data_dir(void) { return ew_t_shared("data/ericw"); }

static int load_map(map *m, const char *base, const char *suffix) {
    memset(m, 0, sizeof *m);
    snprintf(m->name, sizeof m->name, "%s%s", base, suffix);
    char rel[256], path[1024], dir[1024];
    ew_error err = {""};
    snprintf(dir, sizeof dir, "%s", data_dir());
    m->a = ew_assets_create(m->name, dir, &err);
    CHECK(m->a != NULL, "%s: %s", m->name, err.msg);
    if (!m->a) return -1;
    CHECK(ew_world_warning(m->a->world, 0) == NULL, "%s: warning: %s", m->name, ew_world_warning(m->a->world, 0));
    snprintf(rel, sizeof rel, "data/ericw/maps/%s.lit", m->name);
    m->has_lit = ew_t_have_shared(rel);
    snprintf(rel, sizeof rel, "data/ericw/maps/%s.bsp", m->name);
    snprintf(path, sizeof path, "%s", ew_t_shared(rel));
    CHECK(ew_read_file(path, &m->bsp, &m->size, &err) == 0, "%s: %s", path, err.msg);
    m->scene = ew_scene_create_from_map(m->a->world, path, dir, &err);
    CHECK(m->scene != NULL, "%s: scene: %s", m->name, err.msg);
    if (m->bsp && m->has_lit) {
        m->bare = ew_world_create(m->bsp, m->size, path, &err);
        CHECK(m->bare != NULL, "%s: %s", m->name, err.msg);
        if (m->bare) {
            m->bare_scene = ew_scene_create_from_map(m->bare, path, dir, &err);
            CHECK(m->bare_scene != NULL, "%s: scene: %s", m->name, err.msg);
        }
    }
    return m->bsp && m->scene ? 0 : -1;
}

static void free_map(map *m) {
    ew_scene_destroy(m->scene), ew_scene_destroy(m->bare_scene);
    ew_world_destroy(m->bare);
    ew_assets_destroy(m->a);
    free(m->bsp);
}

static ew_renderer *make(const ew_world *w, const ew_assets *a, ew_color_mode c) {
    ew_error err = {""};
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){.world = w, .palette = a->palette,
                                                            .colormap = a->colormap, .width = W, .height = H,
                                                            .color = c, .threads = 1},
                                        &err);
    CHECK(r != NULL, "renderer: %s", err.msg);
    return r;
}

static size_t frame_bytes(ew_color_mode c) { return (size_t)NPX * (c == EW_COLOR_TRUE ? 4 : 1); }

static const void *frame_of(const ew_renderer *r) {
    return ew_frame_color(r) == EW_COLOR_TRUE ? (const void *)ew_frame_rgba(r) : (const void *)ew_frame_pixels(r);
}

/* The map's cameras: its view set, and start's cube cameras. */
static int cameras(const map *m, ew_camera cams[EW_MAX_VIEWS + 2]) {
    int n = ew_benchmark_views(m->a->world, cams);
    CHECK(n > 0, "%s: no views", m->name);
    int k = 0;
    for (int i = 0; i < n; i += VIEW_STEP) cams[k++] = cams[i];
    n = k;
    if (strncmp(m->name, "start", 5) == 0) cams[n++] = cube_cams[0], cams[n++] = cube_cams[1];
    return n;
}

/* Every camera's frame, one after another (malloc'd; NULL after a failed CHECK). */
static uint8_t *render_all(const map *m, int bare, ew_color_mode c, int lit, const ew_camera *cams, int n) {
    const ew_world *w = bare ? m->bare : m->a->world;
    ew_renderer *r = make(w, m->a, c);
    if (!r) return NULL;
    ew_set_scene(r, bare ? m->bare_scene : m->scene);
    ew_set_lit(r, lit);
    size_t fb = frame_bytes(c);
    uint8_t *out = malloc(fb * (size_t)n);
    for (int i = 0; out && i < n; i++) {
        CHECK(ew_render(r, &cams[i], NULL) == 0, "%s: render %d", m->name, i);
        memcpy(out + fb * (size_t)i, frame_of(r), fb);
        n_frames++;
    }
    ew_renderer_destroy(r);
    return out;
}

/* 1 if the frames of a and b are byte-identical; names the first view
 * that differs. */
static void same_frames(const char *what, const uint8_t *a, const uint8_t *b, ew_color_mode c, int n) {
    if (!a || !b) return;
    size_t fb = frame_bytes(c);
    int bad = -1, nbad = 0;
    long px = 0;
    for (int i = 0; i < n; i++)
        if (memcmp(a + fb * (size_t)i, b + fb * (size_t)i, fb) != 0) {
            if (bad < 0) bad = i;
            nbad++;
            size_t bpp = c == EW_COLOR_TRUE ? 4 : 1;
            for (size_t k = 0; k < (size_t)NPX; k++)
                px += memcmp(a + fb * (size_t)i + k * bpp, b + fb * (size_t)i + k * bpp, bpp) != 0;
        }
    CHECK(nbad == 0, "%s (%s): %d of %d frames differ (first: camera %d; %ld pixels)", what,
          c == EW_COLOR_TRUE ? "true colour" : "8-bit", nbad, n, bad, px);
    n_pairs += n, n_pair_bytes += (long)fb * n;
}

/* A frame has content: three values at least (some of dev's views see
 * one dark grid texture: 5 palette colours). */
static int varied(const uint8_t *f, ew_color_mode c) {
    int distinct = 0;
    if (c == EW_COLOR_TRUE) {
        const uint32_t *p = (const uint32_t *)(const void *)f;
        for (int i = 1; i < NPX && distinct < 3; i++) distinct += p[i] != p[i - 1];
    } else {
        int seen[256] = {0};
        for (int i = 0; i < NPX; i++) distinct += !seen[f[i]]++;
    }
    return distinct >= 3;
}

/* ---- 1 and 3: every map rendered, and the same light in other containers ---- */

static void test_containers(map maps[NSUF], const char *base) {
    ew_camera cams[EW_MAX_VIEWS + 2];
    int n = cameras(&maps[0], cams);
    const ew_color_mode modes[2] = {EW_COLOR_8BIT, EW_COLOR_TRUE};
    for (int mi = 0; mi < 2; mi++) {
        ew_color_mode c = modes[mi];
        size_t fb = frame_bytes(c);
        uint8_t *lit_on[NSUF] = {0};
        for (int s = 0; s < NSUF; s++) {
            if (!maps[s].a) continue;
            lit_on[s] = render_all(&maps[s], 0, c, 1, cams, n);
            int flat = 0;
            for (int i = 0; lit_on[s] && i < n; i++) flat += !varied(lit_on[s] + fb * (size_t)i, c);
            CHECK(lit_on[s] && flat == 0, "%s (%d): %d of %d frames nearly uniform", maps[s].name, (int)c, flat, n);
        }
        char what[256];
        /* BSP29 + .lit against BSP2 + .lit and BSP2 + RGBLIGHTING alone */
        map *p = &maps[0], *b = &maps[1];
        if (p->a && b->a && b->bare) {
            uint8_t *bare_on = render_all(b, 1, c, 1, cams, n);
            snprintf(what, sizeof what, "%s: %s (.lit) = %s (.lit)", base, p->name, b->name);
            same_frames(what, lit_on[0], lit_on[1], c, n);
            snprintf(what, sizeof what, "%s: %s (.lit) = %s (RGBLIGHTING)", base, p->name, b->name);
            same_frames(what, lit_on[0], bare_on, c, n);
            uint8_t *p_off = render_all(p, 0, c, 0, cams, n), *b_off = render_all(b, 0, c, 0, cams, n);
            uint8_t *x_off = render_all(b, 1, c, 0, cams, n);
            snprintf(what, sizeof what, "%s: %s = %s, coloured light off", base, p->name, b->name);
            same_frames(what, p_off, b_off, c, n);
            snprintf(what, sizeof what, "%s: %s = %s (RGBLIGHTING), coloured light off", base, p->name, b->name);
            same_frames(what, p_off, x_off, c, n);
            /* the coloured light is there to compare: it changes some frame */
            int differ = 0;
            for (int i = 0; p_off && lit_on[0] && i < n; i++)
                differ += memcmp(p_off + fb * (size_t)i, lit_on[0] + fb * (size_t)i, fb) != 0;
            CHECK(differ > 0, "%s: coloured light changes no frame", p->name);
            free(bare_on), free(p_off), free(b_off), free(x_off);
        }
        /* a map's .lit against its own RGBLIGHTING lump */
        for (int s = 1; s < NSUF; s++) {
            map *m = &maps[s];
            if (!m->a || !m->bare || s == 1) continue;  /* _bsp2_bspxlit: above */
            uint8_t *bare_on = render_all(m, 1, c, 1, cams, n);
            snprintf(what, sizeof what, "%s: .lit = RGBLIGHTING", m->name);
            same_frames(what, lit_on[s], bare_on, c, n);
            free(bare_on);
        }
        /* start's BSP29 + LMSHIFT 3 + .lit and BSP2 + LMSHIFT 3 + RGBLIGHTING
         * share their light (dev's differ: -facestyles 8 lit it otherwise) */
        if (!strcmp(base, "start") && maps[2].a && maps[6].a) {
            snprintf(what, sizeof what, "%s = %s", maps[2].name, maps[6].name);
            same_frames(what, lit_on[2], lit_on[6], c, n);
            uint8_t *a_off = render_all(&maps[2], 0, c, 0, cams, n), *b_off = render_all(&maps[6], 0, c, 0, cams, n);
            snprintf(what, sizeof what, "%s = %s, coloured light off", maps[2].name, maps[6].name);
            same_frames(what, a_off, b_off, c, n);
            free(a_off), free(b_off);
        }
        for (int s = 0; s < NSUF; s++) free(lit_on[s]);
    }
}

/* ---- 2: faces with no light map are dark ------------------------------------ */

/* Where a BSP image's BSPX directory starts: after the last of its 15
 * standard lumps, 4-byte aligned. */
static uint64_t bspx_pos(const uint8_t *d) {
    uint64_t end = 0;
    for (int i = 0; i < 15; i++) {
        uint32_t o, l;
        memcpy(&o, d + 4 + 8 * i, 4), memcpy(&l, d + 8 + 8 * i, 4);
        if ((uint64_t)o + l > end) end = (uint64_t)o + l;
    }
    return (end + 3) & ~(uint64_t)3;
}

/* The file's DECOUPLED_LM lump, read here from the BSPX directory (after
 * the last standard lump, 4-byte aligned); NULL if none. */
static const uint8_t *decoupled_lump(const map *m, size_t *len) {
    const uint8_t *d = m->bsp;
    if (m->size < 124) return NULL;
    uint64_t pos = bspx_pos(d);
    if (pos + 8 > m->size || memcmp(d + pos, "BSPX", 4) != 0) return NULL;
    int32_t n;
    memcpy(&n, d + pos + 4, 4);
    for (int i = 0; i < n && pos + 8 + 32 * (uint64_t)(i + 1) <= m->size; i++) {
        const uint8_t *e = d + pos + 8 + 32 * i;
        if (strncmp((const char *)e, "DECOUPLED_LM", 24) != 0) continue;
        int32_t o, l;
        memcpy(&o, e + 24, 4), memcpy(&l, e + 28, 4);
        if (o < 0 || l < 0 || (uint64_t)o + (uint64_t)l > m->size) return NULL;
        *len = (size_t)l;
        return d + o;
    }
    return NULL;
}

/* Pixels of the faces marked in unlit, in the decoupled map's frame and
 * the plain map's frame of the same camera and brush (rd[c], rp[c]: the
 * two maps' renderers in 8-bit and true colour, face ids on): equal byte
 * for byte, and, without a dynamic light, dark (8-bit: a colour of the
 * colormap's darkest row, row 63; true colour: every channel at most 24). */
static void compare_unlit(const map *dm, const map *pm, ew_renderer *rd[2], ew_renderer *rp[2], int model,
                          const ew_camera *cam, const uint8_t *unlit, int with_dlight, long *px_out) {
    static const float zero[3] = {0, 0, 0};
    uint8_t darkest[256] = {0};
    for (int i = 0; i < 256; i++) darkest[dm->a->colormap[63 * 256 + i]] = 1;
    ew_error err;
    ew_scene *sd = ew_scene_create(dm->a->world, &err), *sp = ew_scene_create(pm->a->world, &err);
    CHECK(sd && sp, "scene for %s: %s", dm->name, err.msg);
    if (!sd || !sp) {
        ew_scene_destroy(sd), ew_scene_destroy(sp);
        return;
    }
    CHECK(ew_scene_add_brush(sd, model, zero, zero) >= 0 && ew_scene_add_brush(sp, model, zero, zero) >= 0,
          "%s: brush *%d", dm->name, model);
    if (with_dlight) {
        float at[3] = {cam->origin[0], cam->origin[1], cam->origin[2]};
        ew_scene_add_dlight(sd, at, 600), ew_scene_add_dlight(sp, at, 600);
    }
    for (int mi = 0; mi < 2; mi++) {
        ew_color_mode c = mi ? EW_COLOR_TRUE : EW_COLOR_8BIT;
        ew_set_scene(rd[mi], sd), ew_set_scene(rp[mi], sp);
        CHECK(ew_render(rd[mi], cam, NULL) == 0 && ew_render(rp[mi], cam, NULL) == 0, "%s: render", dm->name);
        n_frames += 2;
        const int *id = ew_frame_face_ids(rd[mi]), *ip = ew_frame_face_ids(rp[mi]);
        long px = 0, differ = 0, bright = 0;
        for (int i = 0; id && ip && i < NPX; i++) {
            if (id[i] < 0 || id[i] >= dm->a->world->numfaces || !unlit[id[i]]) continue;
            if (ip[i] != id[i]) continue;  /* another face won in the plain frame (a tie at an edge) */
            px++;
            if (c == EW_COLOR_TRUE) {
                uint32_t a = ew_frame_rgba(rd[mi])[i], b = ew_frame_rgba(rp[mi])[i];
                differ += a != b;
                const uint8_t *q = (const uint8_t *)&a;
                if (!with_dlight && (q[0] > 24 || q[1] > 24 || q[2] > 24)) bright++;
            } else {
                uint8_t a = ew_frame_pixels(rd[mi])[i], b = ew_frame_pixels(rp[mi])[i];
                differ += a != b;
                if (!with_dlight && !darkest[a]) bright++;
            }
        }
        CHECK(differ == 0, "%s: brush *%d (%s%s): %ld of %ld unlit pixels differ from %s", dm->name, model,
              mi ? "true colour" : "8-bit", with_dlight ? ", dynamic light" : "", differ, px, pm->name);
        CHECK(bright == 0, "%s: brush *%d (%s): %ld of %ld unlit pixels are not dark", dm->name, model,
              mi ? "true colour" : "8-bit", bright, px);
        *px_out += px;
        ew_set_scene(rd[mi], NULL), ew_set_scene(rp[mi], NULL);
    }
    ew_scene_destroy(sd), ew_scene_destroy(sp);
}

static void test_unlit(map *dm, const map *pm) {
    size_t len = 0;
    const uint8_t *dec = decoupled_lump(dm, &len);
    const ew_world *w = dm->a->world, *pw = pm->a->world;
    CHECK(dec && len == 40 * (size_t)w->numfaces, "%s: no DECOUPLED_LM lump of %d faces", dm->name, w->numfaces);
    if (!dec || len != 40 * (size_t)w->numfaces) return;
    uint8_t *unlit = calloc((size_t)w->numfaces, 1);
    int nunlit = 0;
    for (int i = 0; i < w->numfaces; i++) {
        const uint8_t *e = dec + 40 * (size_t)i;
        int32_t ofs;
        memcpy(&ofs, e + 4, 4);
        int zero = e[0] == 0 && e[1] == 0 && e[2] == 0 && e[3] == 0 && ofs == -1;
        /* sky and liquids draw no light map in any build */
        if (!zero || (w->faces[i].flags & (EW_SURF_SKY | EW_SURF_TURB))) continue;
        /* the same face in the plain build: same place, no light map either */
        int same = i < pw->numfaces && pw->faces[i].plane == w->faces[i].plane &&
                   pw->faces[i].texinfo == w->faces[i].texinfo &&
                   pw->faces[i].firstedge == w->faces[i].firstedge && pw->faces[i].lightofs == -1;
        CHECK(same, "%s: face %d is not the plain build's unlit face %d", dm->name, i, i);
        if (same) unlit[i] = 1, nunlit++;
    }
    CHECK(nunlit > 0, "%s: no face with an all-zero DECOUPLED_LM entry", dm->name);
    /* Each brush model whose faces include unlit ones, looked at from six
     * sides and two diagonals, outside its box. */
    ew_renderer *rd[2], *rp[2];
    for (int mi = 0; mi < 2; mi++) {
        rd[mi] = make(w, dm->a, mi ? EW_COLOR_TRUE : EW_COLOR_8BIT);
        rp[mi] = make(pw, pm->a, mi ? EW_COLOR_TRUE : EW_COLOR_8BIT);
        if (rd[mi]) ew_enable_face_ids(rd[mi], 1);
        if (rp[mi]) ew_enable_face_ids(rp[mi], 1);
    }
    int models = 0, seen = 0;
    long px = 0;
    for (int m = 1; rd[0] && rd[1] && rp[0] && rp[1] && m < w->nummodels; m++) {
        const ew_model *md = &w->models[m];
        int has = 0;
        for (int k = 0; k < md->numfaces; k++) has += md->firstface + k < w->numfaces && unlit[md->firstface + k];
        if (!has) continue;
        models++;
        float c[3], ext = 0;
        for (int k = 0; k < 3; k++) {
            c[k] = (md->mins[k] + md->maxs[k]) / 2;
            float e = md->maxs[k] - md->mins[k];
            ext = e > ext ? e : ext;
        }
        static const float dirs[8][3] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},      {0, -1, 0},
                                         {0, 0, 1},  {0, 0, -1}, {0.6f, 0.6f, 0.5f}, {-0.6f, -0.6f, 0.5f}};
        long before = px;
        for (int d = 0; d < 8; d++) {
            float dl = sqrtf(dirs[d][0] * dirs[d][0] + dirs[d][1] * dirs[d][1] + dirs[d][2] * dirs[d][2]);
            float dist = ext * 0.5f + 48;
            ew_camera cam = {{0, 0, 0}, {0, 0, 0}, 90, 0};
            for (int k = 0; k < 3; k++) cam.origin[k] = c[k] + dirs[d][k] / dl * dist;
            float v[3] = {c[0] - cam.origin[0], c[1] - cam.origin[1], c[2] - cam.origin[2]};
            /* positive pitch looks down */
            cam.angles[0] = (float)(-atan2(v[2], sqrt(v[0] * v[0] + v[1] * v[1])) * 180 / 3.14159265358979);
            cam.angles[1] = (float)(atan2(v[1], v[0]) * 180 / 3.14159265358979);
            compare_unlit(dm, pm, rd, rp, m, &cam, unlit, 0, &px);
            if (d == 0) compare_unlit(dm, pm, rd, rp, m, &cam, unlit, 1, &px);
        }
        seen += px > before;
    }
    for (int mi = 0; mi < 2; mi++) ew_renderer_destroy(rd[mi]), ew_renderer_destroy(rp[mi]);
    printf("%s: %d faces with no light map (all-zero DECOUPLED_LM entries), in %d brush models; %d of them "
           "seen, %ld pixels compared with %s\n",
           dm->name, nunlit, models, seen, px, pm->name);
    CHECK(seen > 0 && px > 1000, "%s: unlit faces barely seen (%d models, %ld pixels)", dm->name, seen, px);
    n_dark_faces += nunlit, n_dark_px += px;
    free(unlit);
}

/* ---- 4: edgewise info lists the BSPX lumps ----------------------------------- */

static void test_info(const map *m, int s) {
    char tmp[] = "/tmp/ew_ericw_XXXXXX";
    if (!mkdtemp(tmp)) {
        CHECK(0, "mkdtemp");
        return;
    }
    const char *dir = ew_t_shared_abs("data/ericw");
    char d[2048];
    snprintf(d, sizeof d, "%s", dir);
    ew_t_run *r = malloc(sizeof *r);
    const char *const args[] = {"info", m->name, "--data", d, NULL};
    ew_t_run_cli(r, tmp, args);
    CHECK(r->status == 0 && r->signal == 0, "info %s: status %d signal %d: %s", m->name, r->status, r->signal, r->err);
    /* every lump of the build on a line of its own, used or not */
    char want[256];
    snprintf(want, sizeof want, "%s", lumps_of[s]);
    int nl = 0;
    for (char *tok = strtok(want, " "); tok; tok = strtok(NULL, " ")) {
        nl++;
        char line[128];
        snprintf(line, sizeof line, "\n%s ", tok);
        const char *at = strstr(r->out, line);
        CHECK(at != NULL, "info %s: no line for BSPX lump %s:\n%s", m->name, tok, r->out);
        if (!at) continue;
        const char *eol = strchr(at + 1, '\n');
        size_t ll = eol ? (size_t)(eol - at - 1) : strlen(at + 1);
        char text[160];
        snprintf(text, sizeof text, "%.*s", (int)(ll < sizeof text ? ll : sizeof text - 1), at + 1);
        int known = !strcmp(tok, "RGBLIGHTING") || !strcmp(tok, "LMSHIFT") || !strcmp(tok, "LMOFFSET") ||
                    !strcmp(tok, "DECOUPLED_LM");
        const char *expect = !known                                          ? "unused"
                             : !strcmp(tok, "RGBLIGHTING") && m->has_lit ? "replaced by .lit"
                                                                          : "used";
        size_t el = strlen(expect);
        CHECK(ll >= el && strcmp(text + ll - el, expect) == 0, "info %s: lump %s: '%s', want '%s'", m->name, tok,
              text, expect);
    }
    char count[64];
    if (nl) snprintf(count, sizeof count, "\nbspx      %d lump%s\n", nl, nl == 1 ? "" : "s");
    else snprintf(count, sizeof count, "\nbspx      none\n");
    CHECK(strstr(r->out, count) != NULL, "info %s: no '%s' line:\n%s", m->name, count + 1, r->out);
    n_info++;
    free(r);
    char f[1100];
    snprintf(f, sizeof f, "%s/stdout.txt", tmp), remove(f);
    snprintf(f, sizeof f, "%s/stderr.txt", tmp), remove(f);
    remove(tmp);
}

/* An unknown BSPX lump beside a known one: listed, the map loads without
 * a warning, and the known lump is still used. */
static void test_unknown_lump(const map *m) {
    /* start_bsp2_bspxlit with one more directory entry, ZZ_UNKNOWN: the
     * directory grows by 32 bytes (the lumps after it move along), the new
     * lump's 4 bytes go at the end */
    const uint8_t *d = m->bsp;
    uint64_t pos = bspx_pos(d);
    int32_t n;
    memcpy(&n, d + pos + 4, 4);
    size_t dir_end = (size_t)pos + 8 + 32 * (size_t)n;
    size_t tail = m->size - dir_end;
    size_t size = dir_end + 32 + tail + 4;  /* the unknown lump's 4 bytes last */
    uint8_t *b = malloc(size);
    memcpy(b, d, dir_end);
    memset(b + dir_end, 0, 32);
    memcpy(b + dir_end + 32, d + dir_end, tail);
    memcpy(b + size - 4, "ZZZZ", 4);
    int32_t n1 = n + 1;
    memcpy(b + pos + 4, &n1, 4);
    for (int i = 0; i < n; i++) {  /* lumps after the directory move by 32 */
        int32_t o;
        memcpy(&o, b + pos + 8 + 32 * i + 24, 4);
        if ((size_t)o >= dir_end) o += 32;
        memcpy(b + pos + 8 + 32 * i + 24, &o, 4);
    }
    uint8_t *e = b + dir_end;
    memcpy(e, "ZZ_UNKNOWN", 11);
    int32_t o = (int32_t)(size - 4), l = 4;
    memcpy(e + 24, &o, 4), memcpy(e + 28, &l, 4);
    ew_error err = {""};
    ew_world *w = ew_world_create(b, size, "unknown.bsp", &err);
    CHECK(w != NULL, "unknown lump: %s", err.msg);
    if (w) {
        CHECK(ew_world_warning(w, 0) == NULL, "unknown lump: warning %s", ew_world_warning(w, 0));
        ew_bspx_lump_info li;
        int found = 0, rgb = 0, k;
        for (k = 0; ew_world_bspx_lump(w, k, &li) == 0; k++) {
            if (!strcmp(li.name, "ZZ_UNKNOWN")) found = li.use == EW_BSPX_UNUSED && li.length == 4;
            if (!strcmp(li.name, "RGBLIGHTING")) rgb = li.use == EW_BSPX_USED;
        }
        CHECK(k == n + 1 && found && rgb, "unknown lump: %d lumps, unknown listed %d, RGBLIGHTING used %d", k, found,
              rgb);
        CHECK(w->rgblight != NULL, "unknown lump: RGBLIGHTING not read");
        ew_world_destroy(w);
    }
    free(b);
}

/* The loader's checks of each DECOUPLED_LM entry, on start_decoupled with
 * one entry changed: a lit face's matrix not finite, or its light map
 * running past the light lump: one warning, the layout left out (Quake's
 * grid, inside the lump); a lit face given 0 samples a side: no light map,
 * no warning, the rest of the layout kept. */
static void test_decoupled_checks(const map *m) {
    size_t len = 0;
    const uint8_t *dec = decoupled_lump(m, &len);
    if (!dec) return;
    size_t at = (size_t)(dec - m->bsp);
    int nf = (int)(len / 40), lit = -1;
    for (int i = 0; i < nf && lit < 0; i++) {
        int32_t ofs;
        memcpy(&ofs, dec + 40 * (size_t)i + 4, 4);
        if (ofs >= 0 && !(m->a->world->faces[i].flags & (EW_SURF_SKY | EW_SURF_TURB))) lit = i;
    }
    CHECK(lit >= 0, "%s: no lit face", m->name);
    if (lit < 0) return;
    struct { const char *label, *want; int kind; } cases[] = {
        {"matrix NaN", "not finite", 0},
        {"past the light lump", "outside the light lump", 1},
        {"0 samples wide", NULL, 2},
    };
    for (int k = 0; k < 3; k++) {
        uint8_t *b = malloc(m->size);
        memcpy(b, m->bsp, m->size);
        uint8_t *e = b + at + 40 * (size_t)lit;
        if (cases[k].kind == 0) {
            float nan = NAN;
            memcpy(e + 8, &nan, 4);
        } else if (cases[k].kind == 1) {
            /* its samples from the lighting lump's last byte on */
            int32_t light_len, last;
            memcpy(&light_len, b + 4 + 8 * 8 + 4, 4);
            last = light_len - 1;
            memcpy(e + 4, &last, 4);
        } else {
            memset(e, 0, 2);
        }
        ew_error err = {""};
        ew_world *w = ew_world_create(b, m->size, "changed.bsp", &err);
        CHECK(w != NULL, "%s: %s", cases[k].label, err.msg);
        if (w) {
            const char *w0 = ew_world_warning(w, 0);
            if (cases[k].want) {
                CHECK(w0 && strstr(w0, cases[k].want) && strstr(w0, "DECOUPLED_LM") && !ew_world_warning(w, 1),
                      "%s: warnings '%s'", cases[k].label, w0 ? w0 : "(none)");
                CHECK(w->facelm == NULL, "%s: layout used", cases[k].label);
            } else {
                CHECK(w0 == NULL, "%s: warning %s", cases[k].label, w0);
                CHECK(w->facelm && w->facelm[lit].lightofs == -1 && w->faces[lit].lightofs == -1,
                      "%s: face %d still lit", cases[k].label, lit);
            }
            ew_world_destroy(w);
        }
        free(b);
    }
}

/* The two-pass light oracle against every one of these maps (cache against
 * per-pixel light, by colour) is tests/test_light_oracle.c. */

int main(void) {
    if (!ew_t_need_shared("data/ericw/maps/start_plain.bsp")) return ew_t_finish();
    static const char *const bases[] = {"start", "dev"};
    for (int bi = 0; bi < 2; bi++) {
        map maps[NSUF];
        for (int s = 0; s < NSUF; s++) load_map(&maps[s], bases[bi], suffixes[s]);
        test_containers(maps, bases[bi]);
        if (maps[0].a && maps[4].a) test_unlit(&maps[4], &maps[0]);
        if (maps[0].a && maps[5].a) test_unlit(&maps[5], &maps[0]);
        for (int s = 0; s < NSUF; s++)
            if (maps[s].a) test_info(&maps[s], s);
        if (bi == 0 && maps[1].bsp) test_unknown_lump(&maps[1]);
        if (bi == 0 && maps[4].bsp && maps[4].a) test_decoupled_checks(&maps[4]);
        for (int s = 0; s < NSUF; s++) free_map(&maps[s]);
    }
    printf("ericw: %ld frames rendered; %ld frame pairs byte-compared (%ld bytes); %ld faces with no light map, "
           "%ld of their pixels compared; info on %ld maps\n",
           n_frames, n_pairs, n_pair_bytes, n_dark_faces, n_dark_px, n_info);
    return ew_t_finish();
}
