/*
 * Loaders: BSP29 / BSP2 / 2PSB, PAK, game directories, palette/colormap.
 * A tiny box-room BSP29 is built here so the success paths and every
 * corruption run without ../shared; the real LibreQuake maps, when present,
 * are loaded, converted to BSP2/2PSB in memory, truncated and fuzzed.
 */
#define _POSIX_C_SOURCE 200809L
#include "ew_util.h"
#include "ew_world.h"
#include "edgewise_lab.h"
#include "util.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- byte buffers -------------------------------------------------------- */

typedef struct buf {
    uint8_t *p;
    size_t   n, cap;
} buf;

static void b_put(buf *b, const void *src, size_t n) {
    if (b->n + n > b->cap) {
        size_t cap = b->cap ? b->cap * 2 : 256;
        while (cap < b->n + n) cap *= 2;
        uint8_t *p = realloc(b->p, cap);
        if (!p) abort();
        b->p = p;
        b->cap = cap;
    }
    if (n) memcpy(b->p + b->n, src, n);
    b->n += n;
}
static void b_u8(buf *b, int v) { uint8_t x = (uint8_t)v; b_put(b, &x, 1); }
static void b_u16(buf *b, uint32_t v) { b_u8(b, v & 255); b_u8(b, (v >> 8) & 255); }
static void b_u32(buf *b, uint32_t v) { b_u16(b, v & 0xffff); b_u16(b, v >> 16); }
static void b_i32(buf *b, int32_t v) { b_u32(b, (uint32_t)v); }
static void b_f32(buf *b, float f) { uint32_t u; memcpy(&u, &f, 4); b_u32(b, u); }
static void b_zero(buf *b, size_t n) { while (n--) b_u8(b, 0); }

static void p_u32(uint8_t *p, uint32_t v) {
    p[0] = v & 255; p[1] = (v >> 8) & 255; p[2] = (v >> 16) & 255; p[3] = (uint8_t)(v >> 24);
}
static void p_i32(uint8_t *p, int32_t v) { p_u32(p, (uint32_t)v); }
static void p_u16(uint8_t *p, uint32_t v) { p[0] = v & 255; p[1] = (v >> 8) & 255; }
static void p_f32(uint8_t *p, float f) { uint32_t u; memcpy(&u, &f, 4); p_u32(p, u); }

static uint8_t *dup_bytes(const uint8_t *p, size_t n) {
    uint8_t *d = malloc(n ? n : 1);
    if (!d) abort();
    memcpy(d, p, n);
    return d;
}

/* Header fields of a BSP image. */
static uint32_t lump_ofs(const uint8_t *img, int l) { return ew_u32(img + 4 + 8 * l); }
static uint32_t lump_len(const uint8_t *img, int l) { return ew_u32(img + 8 + 8 * l); }

/* Lumps in header order, each 4-aligned; the last one ends the file. */
static uint8_t *assemble(const char magic[4], buf lumps[EW_NUM_LUMPS], size_t *size) {
    buf img = {0};
    b_put(&img, magic, 4);
    b_zero(&img, EW_NUM_LUMPS * 8);
    for (int i = 0; i < EW_NUM_LUMPS; i++) {
        while (img.n % 4) b_u8(&img, 0);
        p_u32(img.p + 4 + 8 * i, (uint32_t)img.n);
        p_u32(img.p + 8 + 8 * i, (uint32_t)lumps[i].n);
        b_put(&img, lumps[i].p, lumps[i].n);
        free(lumps[i].p);
        lumps[i] = (buf){0};
    }
    *size = img.n;
    return img.p;
}

/* ---- the tiny box room ------------------------------------------------------
 *
 * A 128-unit cube seen from inside: 6 planes, 8 vertices, 6 faces, a chain
 * of 6 nodes (one per wall; the outside of each is the solid leaf 0) ending
 * in the one empty leaf 1.  Textures: 0 "wall" 16x16, 1 "sky1" 16x16,
 * 2 missing (-1), 3 "+0anim", 4 "+1anim", 5 "+Aanim" (8x8), 6 "*water"
 * compiled without pixels.  Faces: 0 x- (wall), 1 x+ (+0anim at half
 * scale, back side), 2 y- (wall, two light styles), 3 y+ (missing slot),
 * 4 z- (wall, no light map), 5 z+ (sky).
 */

enum { TINY_NO_TEXTURES = 1, TINY_NO_VIS = 2 };

static const int tiny_poly[6][4] = {
    {0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
static const int tiny_texinfo[6] = {0, 5, 1, 6, 2, 3};
static const int tiny_lightofs[6] = {0, 81, 106, 268, -1, -1};
#define TINY_LIGHTSIZE 349
static const char tiny_entities[] =
    "{\n\"classname\" \"worldspawn\"\n}\n"
    "{\n\"classname\" \"info_player_start\"\n\"origin\" \"0 0 0\"\n}\n";

static uint8_t tex_pixel(int slot, int mip, int i) { return (uint8_t)(slot * 37 + mip * 11 + i * 3 + 1); }

static void put_miptex(buf *b, const char *name, int w, int h, int slot, int with_pixels) {
    char nm[16] = {0};
    memcpy(nm, name, strlen(name));
    b_put(b, nm, 16);
    b_u32(b, (uint32_t)w);
    b_u32(b, (uint32_t)h);
    uint32_t o = 40;
    for (int k = 0; k < 4; k++) {
        b_u32(b, with_pixels ? o : 0);
        o += (uint32_t)((w >> k) * (h >> k));
    }
    if (!with_pixels) return;
    for (int k = 0; k < 4; k++)
        for (int i = 0; i < (w >> k) * (h >> k); i++) b_u8(b, tex_pixel(slot, k, i));
}

static uint8_t *build_tiny(int opts, size_t *size) {
    buf L[EW_NUM_LUMPS] = {{0}};

    b_put(&L[EW_LUMP_ENTITIES], tiny_entities, strlen(tiny_entities));  /* no NUL */

    for (int i = 0; i < 6; i++) {
        int axis = i / 2;
        for (int k = 0; k < 3; k++) b_f32(&L[EW_LUMP_PLANES], k == axis ? 1.0f : 0.0f);
        b_f32(&L[EW_LUMP_PLANES], i % 2 ? 64.0f : -64.0f);
        b_i32(&L[EW_LUMP_PLANES], axis);
    }

    if (!(opts & TINY_NO_TEXTURES)) {
        buf t = {0};
        int n = 7, ofs[7];
        buf body = {0};
        const char *names[7] = {"wall", "sky1", NULL, "+0anim", "+1anim", "+Aanim", "*water"};
        const int sz[7] = {16, 16, 0, 8, 8, 8, 64};
        for (int i = 0; i < n; i++) {
            if (!names[i]) {
                ofs[i] = -1;
                continue;
            }
            ofs[i] = 4 + 4 * n + (int)body.n;
            put_miptex(&body, names[i], sz[i], sz[i], i, i != 6);
        }
        b_i32(&t, n);
        for (int i = 0; i < n; i++) b_i32(&t, ofs[i]);
        b_put(&t, body.p, body.n);
        free(body.p);
        L[EW_LUMP_TEXTURES] = t;
    }

    for (int v = 0; v < 8; v++)
        for (int k = 0; k < 3; k++) b_f32(&L[EW_LUMP_VERTEXES], (v >> k) & 1 ? 64.0f : -64.0f);

    if (!(opts & TINY_NO_VIS)) b_u8(&L[EW_LUMP_VISIBILITY], 0x01);

    /* node i splits on plane i; the room is in front of planes 0,2,4 and
     * behind 1,3,5; the last node's room side is leaf 1 (-2). */
    for (int i = 0; i < 6; i++) {
        int inner = i < 5 ? i + 1 : -2;
        b_i32(&L[EW_LUMP_NODES], i);
        b_u16(&L[EW_LUMP_NODES], (uint32_t)(i % 2 ? -1 : inner));
        b_u16(&L[EW_LUMP_NODES], (uint32_t)(i % 2 ? inner : -1));
        for (int k = 0; k < 3; k++) b_u16(&L[EW_LUMP_NODES], (uint32_t)-64);
        for (int k = 0; k < 3; k++) b_u16(&L[EW_LUMP_NODES], 64);
        b_u16(&L[EW_LUMP_NODES], (uint32_t)i);
        b_u16(&L[EW_LUMP_NODES], 1);
    }

    /* texinfo: 0 x-axis wall, 1 y-axis wall, 2 z-axis wall, 3 z sky,
     * 4 z *water, 5 x-axis +0anim at half scale, 6 y-axis missing slot */
    {
        const int axis[7] = {0, 1, 2, 2, 2, 0, 1};
        const int tex[7] = {0, 0, 0, 1, 6, 3, 2};
        for (int i = 0; i < 7; i++) {
            float sc = i == 5 ? 0.5f : 1.0f;
            int s = (axis[i] + 1) % 3, t = (axis[i] + 2) % 3;
            for (int k = 0; k < 3; k++) b_f32(&L[EW_LUMP_TEXINFO], k == s ? sc : 0.0f);
            b_f32(&L[EW_LUMP_TEXINFO], 0.0f);
            for (int k = 0; k < 3; k++) b_f32(&L[EW_LUMP_TEXINFO], k == t ? sc : 0.0f);
            b_f32(&L[EW_LUMP_TEXINFO], 0.0f);
            b_i32(&L[EW_LUMP_TEXINFO], tex[i]);
            b_i32(&L[EW_LUMP_TEXINFO], i == 3 || i == 4 ? 1 : 0);
        }
    }

    for (int i = 0; i < 6; i++) {
        b_u16(&L[EW_LUMP_FACES], (uint32_t)i);         /* plane */
        b_u16(&L[EW_LUMP_FACES], (uint32_t)(i % 2));   /* side */
        b_i32(&L[EW_LUMP_FACES], 4 * i);               /* firstedge */
        b_u16(&L[EW_LUMP_FACES], 4);
        b_u16(&L[EW_LUMP_FACES], (uint32_t)tiny_texinfo[i]);
        b_u8(&L[EW_LUMP_FACES], tiny_lightofs[i] < 0 ? 255 : 0);
        b_u8(&L[EW_LUMP_FACES], i == 2 ? 1 : 255);
        b_u8(&L[EW_LUMP_FACES], 255);
        b_u8(&L[EW_LUMP_FACES], 255);
        b_i32(&L[EW_LUMP_FACES], tiny_lightofs[i]);
    }

    for (int i = 0; i < TINY_LIGHTSIZE; i++) b_u8(&L[EW_LUMP_LIGHTING], (i * 7) & 255);

    /* no clipnodes: the loader only checks their size */

    /* leaf 0: solid; leaf 1: the room */
    for (int l = 0; l < 2; l++) {
        b_i32(&L[EW_LUMP_LEAFS], l ? EW_CONTENTS_EMPTY : EW_CONTENTS_SOLID);
        b_i32(&L[EW_LUMP_LEAFS], l ? 0 : -1);
        for (int k = 0; k < 6; k++) b_u16(&L[EW_LUMP_LEAFS], l ? (uint32_t)(k < 3 ? -64 : 64) : 0);
        b_u16(&L[EW_LUMP_LEAFS], 0);
        b_u16(&L[EW_LUMP_LEAFS], l ? 6 : 0);
        for (int k = 0; k < 4; k++) b_u8(&L[EW_LUMP_LEAFS], l ? 10 + k : 0);
    }

    for (int i = 0; i < 6; i++) b_u16(&L[EW_LUMP_MARKSURFACES], (uint32_t)i);

    /* edge 0 unused; face f owns edges 1+4f..4+4f; face 1 stores its edges
     * reversed and walks them with negative surfedges */
    b_u16(&L[EW_LUMP_EDGES], 0);
    b_u16(&L[EW_LUMP_EDGES], 0);
    for (int f = 0; f < 6; f++)
        for (int k = 0; k < 4; k++) {
            int a = tiny_poly[f][k], b = tiny_poly[f][(k + 1) % 4];
            b_u16(&L[EW_LUMP_EDGES], (uint32_t)(f == 1 ? b : a));
            b_u16(&L[EW_LUMP_EDGES], (uint32_t)(f == 1 ? a : b));
            b_i32(&L[EW_LUMP_SURFEDGES], f == 1 ? -(1 + 4 * f + k) : 1 + 4 * f + k);
        }

    for (int k = 0; k < 3; k++) b_f32(&L[EW_LUMP_MODELS], -64.0f);
    for (int k = 0; k < 3; k++) b_f32(&L[EW_LUMP_MODELS], 64.0f);
    for (int k = 0; k < 3; k++) b_f32(&L[EW_LUMP_MODELS], 0.0f);
    for (int k = 0; k < 4; k++) b_i32(&L[EW_LUMP_MODELS], 0);
    b_i32(&L[EW_LUMP_MODELS], 1);  /* visleafs */
    b_i32(&L[EW_LUMP_MODELS], 0);
    b_i32(&L[EW_LUMP_MODELS], 6);

    char magic[4];
    p_u32((uint8_t *)magic, 29);
    return assemble(magic, L, size);
}

/* ---- BSP29 -> BSP2 / 2PSB re-encoding ------------------------------------ */

static uint8_t *convert(const uint8_t *src, size_t size, int to_2psb, size_t *out_size) {
    (void)size;
    buf L[EW_NUM_LUMPS] = {{0}};
    for (int l = 0; l < EW_NUM_LUMPS; l++) {
        const uint8_t *p = src + lump_ofs(src, l);
        uint32_t len = lump_len(src, l);
        buf *o = &L[l];
        switch (l) {
        case EW_LUMP_NODES:
            for (uint32_t i = 0; i < len / 24; i++, p += 24) {
                b_i32(o, ew_i32(p));
                b_i32(o, ew_i16(p + 4));
                b_i32(o, ew_i16(p + 6));
                for (int k = 0; k < 6; k++) {
                    if (to_2psb) b_u16(o, ew_u16(p + 8 + 2 * k));
                    else b_f32(o, ew_i16(p + 8 + 2 * k));
                }
                b_u32(o, ew_u16(p + 20));
                b_u32(o, ew_u16(p + 22));
            }
            break;
        case EW_LUMP_LEAFS:
            for (uint32_t i = 0; i < len / 28; i++, p += 28) {
                b_i32(o, ew_i32(p));
                b_i32(o, ew_i32(p + 4));
                for (int k = 0; k < 6; k++) {
                    if (to_2psb) b_u16(o, ew_u16(p + 8 + 2 * k));
                    else b_f32(o, ew_i16(p + 8 + 2 * k));
                }
                b_u32(o, ew_u16(p + 20));
                b_u32(o, ew_u16(p + 22));
                b_put(o, p + 24, 4);
            }
            break;
        case EW_LUMP_FACES:
            for (uint32_t i = 0; i < len / 20; i++, p += 20) {
                b_i32(o, ew_u16(p));
                b_i32(o, ew_i16(p + 2));
                b_i32(o, ew_i32(p + 4));
                b_i32(o, ew_u16(p + 8));
                b_i32(o, ew_u16(p + 10));
                b_put(o, p + 12, 4);
                b_i32(o, ew_i32(p + 16));
            }
            break;
        case EW_LUMP_EDGES:
            for (uint32_t i = 0; i < len / 2; i++) b_u32(o, ew_u16(p + 2 * i));
            break;
        case EW_LUMP_MARKSURFACES:
            for (uint32_t i = 0; i < len / 2; i++) b_u32(o, ew_u16(p + 2 * i));
            break;
        case EW_LUMP_CLIPNODES:
            for (uint32_t i = 0; i < len / 8; i++, p += 8) {
                b_i32(o, ew_i32(p));
                b_i32(o, ew_i16(p + 4));
                b_i32(o, ew_i16(p + 6));
            }
            break;
        default:
            b_put(o, p, len);
        }
    }
    return assemble(to_2psb ? "2PSB" : "BSP2", L, out_size);
}

/* ---- helpers ------------------------------------------------------------- */

static int mentions(const ew_error *err, const char *s) { return s && strstr(err->msg, s) != NULL; }

/* Loads an image that must be rejected: NULL, a message naming the file and
 * (if want is given) containing want. */
static void expect_bad(const uint8_t *img, size_t size, const char *file, const char *want,
                       const char *what) {
    ew_error err = {{0}};
    ew_world *w = ew_world_create(img, size, file, &err);
    CHECK(w == NULL, "%s: loaded a corrupt image", what);
    ew_world_destroy(w);
    CHECK(err.msg[0] && mentions(&err, file), "%s: message does not name %s: '%s'", what, file, err.msg);
    if (want) CHECK(mentions(&err, want), "%s: message lacks '%s': '%s'", what, want, err.msg);
}

/* Patches a copy of the image, expects rejection. */
typedef void (*patch_fn)(uint8_t *img, size_t size);
static void corrupt(const uint8_t *img, size_t size, const char *file, patch_fn fn, const char *want,
                    const char *what) {
    uint8_t *c = dup_bytes(img, size);
    fn(c, size);
    expect_bad(c, size, file, want, what);
    free(c);
}

static uint8_t *rec(uint8_t *img, int lump, int index, int recsize) {
    return img + lump_ofs(img, lump) + (size_t)index * recsize;
}
static uint8_t *miptex(uint8_t *img, int slot) {
    uint8_t *t = img + lump_ofs(img, EW_LUMP_TEXTURES);
    return t + ew_i32(t + 4 + 4 * slot);
}

/* Every field of two loaded worlds, pixels included. */
static int same_world(const ew_world *a, const ew_world *b) {
#define SAME_ARR(f, n) (a->n == b->n && (a->n == 0 || memcmp(a->f, b->f, sizeof *a->f * (size_t)a->n) == 0))
    if (!SAME_ARR(planes, numplanes) || !SAME_ARR(verts, numverts) || !SAME_ARR(edges, numedges) ||
        !SAME_ARR(surfedges, numsurfedges) || !SAME_ARR(texinfo, numtexinfo) ||
        !SAME_ARR(faces, numfaces) || !SAME_ARR(marksurfaces, nummarksurfaces) ||
        !SAME_ARR(nodes, numnodes) || !SAME_ARR(leaves, numleaves) || !SAME_ARR(models, nummodels) ||
        !SAME_ARR(lighting, lightsize) || !SAME_ARR(visdata, vissize))
        return 0;
#undef SAME_ARR
    if (strcmp(a->entities, b->entities) || a->numtextures != b->numtextures ||
        a->textures_missing != b->textures_missing)
        return 0;
    for (int i = 0; i < a->numtextures; i++) {
        const ew_texture *x = &a->textures[i], *y = &b->textures[i];
        if (strcmp(x->name, y->name) || x->width != y->width || x->height != y->height ||
            x->flags != y->flags || x->anim_total != y->anim_total || x->anim_min != y->anim_min ||
            x->anim_max != y->anim_max || x->anim_next != y->anim_next ||
            x->alternate_anims != y->alternate_anims)
            return 0;
        for (int k = 0; k < 4; k++)
            if (memcmp(x->mip[k], y->mip[k], (size_t)(x->width >> k) * (size_t)(x->height >> k)))
                return 0;
    }
    return 1;
}

/* Structural invariants any loaded world must satisfy. */
static void check_invariants(const ew_world *w, const char *name) {
    int bad = 0;
    for (int i = 0; i < w->numnodes && !bad; i++)
        for (int k = 0; k < 2; k++) {
            int c = w->nodes[i].children[k];
            if (c >= 0 ? w->nodes[c].parent != i : (-1 - c != 0 && w->leaves[-1 - c].parent != i)) bad = 1;
        }
    CHECK(!bad, "%s: parent links disagree with children", name);
    bad = 0;
    for (int i = 0; i < w->numfaces && !bad; i++) {
        const ew_face *f = &w->faces[i];
        for (int e = 0; e < f->numedges; e++) {
            /* a corner is where its side starts: edge v[0], or v[1] when the surfedge runs it backwards */
            int se = w->surfedges[f->firstedge + e], v = ew_face_vertex(w, f, e);
            if (v < 0 || v >= w->numverts || v != (int)(se < 0 ? w->edges[-se][1] : w->edges[se][0])) bad = 1;
        }
        if (f->texturemins[0] % 16 || f->texturemins[1] % 16 || f->extents[0] % 16 || f->extents[1] % 16)
            bad = 2;
        if ((f->lightofs < 0) != (f->styles[0] == 255)) bad = 3;
    }
    CHECK(!bad, "%s: face invariant %d broken", name, bad);
    const ew_texture *ph = &w->textures[w->numtextures - 1];
    CHECK(ph->flags == EW_SURF_MISSING && ph->width == 16 && ph->height == 16,
          "%s: last texture is not the placeholder", name);
    bad = 0;
    for (int i = 0; i < w->numtextures; i++) {
        const ew_texture *t = &w->textures[i];
        if (t->width < 8 || t->height < 8 || t->width % 8 || t->height % 8) bad = 1;
        if ((t->flags & EW_SURF_MISSING) && t->mip[0] != ph->mip[0]) bad = 2;
        if (t->anim_total && (t->anim_next < 0 || t->anim_next >= w->numtextures ||
                              t->anim_min < 0 || t->anim_max != t->anim_min + 1 || t->anim_max > t->anim_total))
            bad = 3;
    }
    CHECK(!bad, "%s: texture invariant %d broken", name, bad);
    CHECK(w->entities != NULL, "%s: no entity string", name);
}

static int find_texture(const ew_world *w, const char *name) {
    for (int i = 0; i < w->numtextures; i++)
        if (!strcmp(w->textures[i].name, name)) return i;
    return -1;
}

/* ---- the tiny map: success paths ----------------------------------------- */

static void test_tiny_ok(void) {
    size_t size;
    uint8_t *img = build_tiny(0, &size);
    ew_error err = {{0}};
    ew_world *w = ew_world_create(img, size, "some/dir/tiny.bsp", &err);
    CHECK(w != NULL, "tiny map did not load: %s", err.msg);
    if (!w) {
        free(img);
        return;
    }
    CHECK(!strcmp(w->name, "tiny.bsp"), "name '%s'", w->name);
    CHECK(!strcmp(w->version, "29"), "version '%s'", w->version);
    CHECK(w->numplanes == 6 && w->numverts == 8 && w->numedges == 25 && w->numsurfedges == 24,
          "geometry counts %d %d %d %d", w->numplanes, w->numverts, w->numedges, w->numsurfedges);
    CHECK(w->numtexinfo == 7 && w->numtextures == 8 && w->textures_missing == 2,
          "texture counts %d %d %d", w->numtexinfo, w->numtextures, w->textures_missing);
    CHECK(w->numfaces == 6 && w->nummarksurfaces == 6 && w->numnodes == 6 && w->numleaves == 2 &&
              w->nummodels == 1,
          "tree counts %d %d %d %d %d", w->numfaces, w->nummarksurfaces, w->numnodes, w->numleaves,
          w->nummodels);
    CHECK(w->lightsize == TINY_LIGHTSIZE && w->lighting[10] == 70, "lighting %d", w->lightsize);
    CHECK(w->vissize == 1 && w->visdata[0] == 1, "vis %d", w->vissize);
    CHECK(!strcmp(w->entities, tiny_entities), "entities '%s'", w->entities);
    CHECK(!strcmp(ew_world_entities(w), tiny_entities), "ew_world_entities");

    ew_world_info info;
    ew_world_get_info(w, &info);
    CHECK(!strcmp(info.version, "29") && info.models == 1 && info.textures == 7 &&
              info.textures_missing == 2 && info.faces == 6 && info.leaves == 2 && info.nodes == 6,
          "info %s %d %d %d %d %d %d", info.version, info.models, info.textures, info.textures_missing,
          info.faces, info.leaves, info.nodes);
    CHECK(!strcmp(info.lumps[EW_LUMP_MARKSURFACES].name, "marksurfaces") &&
              info.lumps[EW_LUMP_FACES].count == 6 && info.lumps[EW_LUMP_FACES].length == 120 &&
              info.lumps[EW_LUMP_FACES].offset == lump_ofs(img, EW_LUMP_FACES) &&
              info.lumps[EW_LUMP_TEXTURES].count == 7 && info.lumps[EW_LUMP_LIGHTING].count == TINY_LIGHTSIZE,
          "lump info");

    /* textures */
    const ew_texture *t = w->textures, *ph = &w->textures[7];
    CHECK(!strcmp(t[0].name, "wall") && t[0].width == 16 && t[0].flags == 0, "texture 0");
    int pix_ok = 1;
    for (int k = 0; k < 4; k++)
        for (int i = 0; i < (16 >> k) * (16 >> k); i++)
            if (t[0].mip[k][i] != tex_pixel(0, k, i)) pix_ok = 0;
    for (int i = 0; i < 4; i++)  /* 8x8 texture: mip 2 is 2x2 */
        if (t[5].mip[2][i] != tex_pixel(5, 2, i)) pix_ok = 0;
    CHECK(pix_ok, "texture pixels not copied faithfully");
    CHECK(t[1].flags == EW_SURF_SKY, "sky1 flags %d", t[1].flags);
    CHECK(t[2].flags == EW_SURF_MISSING && t[2].name[0] == 0 && t[2].mip[0] == ph->mip[0] &&
              t[2].mip[3] == ph->mip[3] && t[2].width == 16,
          "missing slot");
    CHECK(!strcmp(t[6].name, "*water") && t[6].flags == (EW_SURF_TURB | EW_SURF_MISSING) &&
              t[6].mip[1] == ph->mip[1] && t[6].width == 16,
          "named slot without pixels: flags %d", t[6].flags);
    CHECK(ph->mip[0][0] == 255 && ph->mip[0][8] == 0 && ph->mip[0][8 * 16] == 0 &&
              ph->mip[0][8 * 16 + 8] == 255 && ph->mip[0][7 * 16 + 7] == 255 && ph->mip[3][0] == 255 &&
              ph->mip[3][1] == 0 && ph->mip[3][3] == 255 && ph->mip[1][4] == 0,
          "placeholder checkerboard");
    CHECK(t[3].anim_total == 2 && t[3].anim_min == 0 && t[3].anim_max == 1 && t[3].anim_next == 4 &&
              t[3].alternate_anims == 5,
          "+0anim: %d %d %d %d %d", t[3].anim_total, t[3].anim_min, t[3].anim_max, t[3].anim_next,
          t[3].alternate_anims);
    CHECK(t[4].anim_total == 2 && t[4].anim_min == 1 && t[4].anim_max == 2 && t[4].anim_next == 3 &&
              t[4].alternate_anims == 5,
          "+1anim");
    CHECK(t[5].anim_total == 1 && t[5].anim_min == 0 && t[5].anim_next == 5 && t[5].alternate_anims == 3,
          "+Aanim");
    CHECK(t[0].anim_total == 0 && t[0].anim_next == -1 && t[0].alternate_anims == -1, "static texture");

    /* texinfo */
    CHECK(w->texinfo[0].mipadjust == 1 && w->texinfo[5].mipadjust == 2, "mipadjust %g %g",
          w->texinfo[0].mipadjust, w->texinfo[5].mipadjust);
    CHECK(w->texinfo[3].texture == 1 && w->texinfo[3].flags == 1, "texinfo 3");

    /* faces */
    const ew_face *f = w->faces;
    CHECK(f[0].texturemins[0] == -64 && f[0].texturemins[1] == -64 && f[0].extents[0] == 128 &&
              f[0].extents[1] == 128 && f[0].lightofs == 0 && f[0].flags == 0,
          "face 0: %d %d %d %d", f[0].texturemins[0], f[0].texturemins[1], f[0].extents[0], f[0].extents[1]);
    CHECK(f[1].flags == EW_SURF_PLANEBACK && f[1].extents[0] == 64 && f[1].texturemins[0] == -32 &&
              f[1].lightofs == 81,
          "face 1: flags %d extents %d", f[1].flags, f[1].extents[0]);
    CHECK(f[2].styles[0] == 0 && f[2].styles[1] == 1 && f[2].styles[2] == 255, "face 2 styles");
    CHECK(f[3].flags == (EW_SURF_PLANEBACK | EW_SURF_MISSING), "face 3 flags %d", f[3].flags);
    CHECK(f[4].lightofs == -1 && f[4].styles[0] == 255 && f[4].extents[0] == 128, "face 4 unlit");
    CHECK(f[5].flags == (EW_SURF_SKY | EW_SURF_PLANEBACK) && f[5].texturemins[0] == -8192 &&
              f[5].extents[1] == 16384 && f[5].lightofs == -1,
          "face 5 sky");
    int order_ok = 1;
    for (int i = 0; i < 6; i++)
        for (int k = 0; k < 4; k++)
            if (ew_face_vertex(w, &f[i], k) != tiny_poly[i][k]) order_ok = 0;
    CHECK(order_ok, "face vertex order (negative surfedges)");

    /* tree */
    int par_ok = w->nodes[0].parent == -1 && w->leaves[1].parent == 5 && w->leaves[0].parent == -1;
    for (int i = 1; i < 6; i++) par_ok &= w->nodes[i].parent == i - 1;
    CHECK(par_ok, "parent links");
    CHECK(w->nodes[5].children[0] == -1 && w->nodes[5].children[1] == -2 && w->nodes[0].children[0] == 1,
          "children encoding");
    CHECK(w->leaves[1].contents == EW_CONTENTS_EMPTY && w->leaves[1].visofs == 0 &&
              w->leaves[1].nummarks == 6 && w->leaves[1].mins[0] == -64 && w->leaves[1].maxs[2] == 64 &&
              w->leaves[1].ambient[3] == 13 && w->leaves[0].visofs == -1,
          "leaf 1");
    CHECK(w->nodes[2].mins[1] == -64 && w->nodes[2].maxs[1] == 64 && w->nodes[2].firstface == 2 &&
              w->nodes[2].numfaces == 1,
          "node 2");
    CHECK(w->models[0].headnode == 0 && w->models[0].visleafs == 1 && w->models[0].numfaces == 6 &&
              w->models[0].maxs[0] == 64,
          "model 0");
    check_invariants(w, "tiny");

    /* BSP2 and 2PSB re-encodings load to the very same world */
    for (int v = 0; v < 2; v++) {
        size_t n2;
        uint8_t *img2 = convert(img, size, v, &n2);
        ew_world *w2 = ew_world_create(img2, n2, "tiny2.bsp", &err);
        CHECK(w2 != NULL, "tiny %s did not load: %s", v ? "2PSB" : "BSP2", err.msg);
        if (w2) {
            CHECK(!strcmp(w2->version, v ? "2PSB" : "BSP2"), "version %s", w2->version);
            CHECK(same_world(w, w2), "tiny %s differs from BSP29", w2->version);
        }
        ew_world_destroy(w2);
        free(img2);
    }
    ew_world_destroy(w);
    free(img);

    /* No textures lump: everything uses the placeholder. */
    img = build_tiny(TINY_NO_TEXTURES | TINY_NO_VIS, &size);
    w = ew_world_create(img, size, "bare.bsp", &err);
    CHECK(w != NULL, "map without textures/vis did not load: %s", err.msg);
    if (w) {
        CHECK(w->numtextures == 1 && w->textures_missing == 0 && w->texinfo[5].texture == 0 &&
                  (w->faces[0].flags & EW_SURF_MISSING) && (w->faces[5].flags & EW_SURF_SKY) == 0,
              "placeholder-only world");
        CHECK(w->vissize == 0 && w->visdata == NULL && w->leaves[1].visofs == -1,
              "no vis: visofs %d", w->leaves[1].visofs);
        ew_world_info info2;
        ew_world_get_info(w, &info2);
        CHECK(info2.textures == 0, "info textures %d", info2.textures);
        check_invariants(w, "bare");
    }
    ew_world_destroy(w);
    free(img);
}

/* ---- the tiny map: corruptions ------------------------------------------- */

#define PATCH(fname, body) \
    static void fname(uint8_t *img, size_t size) { (void)size; body; }

PATCH(p_version30, p_i32(img, 30))
PATCH(p_magic_ibsp, memcpy(img, "IBSP", 4))
PATCH(p_faces_past_end, p_u32(img + 4 + 8 * EW_LUMP_FACES, (uint32_t)size))
PATCH(p_faces_too_long, p_u32(img + 8 + 8 * EW_LUMP_FACES, (uint32_t)size))
PATCH(p_faces_neg_ofs, p_i32(img + 4 + 8 * EW_LUMP_FACES, -4))
PATCH(p_models_len_huge, p_u32(img + 8 + 8 * EW_LUMP_MODELS, 0x7fffffc0))
PATCH(p_planes_len_odd, p_u32(img + 8 + 8 * EW_LUMP_PLANES, 19))
PATCH(p_face_texinfo, p_u16(rec(img, EW_LUMP_FACES, 3, 20) + 10, 99))
PATCH(p_face_plane, p_u16(rec(img, EW_LUMP_FACES, 2, 20), 6))
PATCH(p_face_side, p_u16(rec(img, EW_LUMP_FACES, 2, 20) + 2, 2))
PATCH(p_face_firstedge, p_i32(rec(img, EW_LUMP_FACES, 5, 20) + 4, 21))
PATCH(p_face_firstedge_neg, p_i32(rec(img, EW_LUMP_FACES, 0, 20) + 4, -1))
PATCH(p_face_numedges2, p_u16(rec(img, EW_LUMP_FACES, 0, 20) + 8, 2))
PATCH(p_face_numedges_neg, p_u16(rec(img, EW_LUMP_FACES, 0, 20) + 8, (uint32_t)-3))
PATCH(p_face_light_past, p_i32(rec(img, EW_LUMP_FACES, 3, 20) + 16, 269))
PATCH(p_face_light_neg, p_i32(rec(img, EW_LUMP_FACES, 0, 20) + 16, -5))
PATCH(p_face_styles_more, rec(img, EW_LUMP_FACES, 3, 20)[13] = 2)
PATCH(p_face_extent_huge, p_f32(rec(img, EW_LUMP_TEXINFO, 0, 40) + 4, 40.0f))
PATCH(p_surfedge_range, p_i32(rec(img, EW_LUMP_SURFEDGES, 3, 4), 25))
PATCH(p_surfedge_neg_range, p_i32(rec(img, EW_LUMP_SURFEDGES, 3, 4), -25))
PATCH(p_surfedge_intmin, p_i32(rec(img, EW_LUMP_SURFEDGES, 3, 4), INT32_MIN))
PATCH(p_edge_vertex, p_u16(rec(img, EW_LUMP_EDGES, 7, 4) + 2, 8))
PATCH(p_vertex_inf, p_f32(rec(img, EW_LUMP_VERTEXES, 2, 12) + 4, INFINITY))
PATCH(p_plane_nan, p_f32(rec(img, EW_LUMP_PLANES, 2, 20) + 12, NAN))
PATCH(p_plane_type, p_i32(rec(img, EW_LUMP_PLANES, 2, 20) + 16, 9))
PATCH(p_node_child_node, p_u16(rec(img, EW_LUMP_NODES, 0, 24) + 4, 6))
PATCH(p_node_child_leaf, p_u16(rec(img, EW_LUMP_NODES, 0, 24) + 6, (uint32_t)-3))
PATCH(p_node_cycle, p_u16(rec(img, EW_LUMP_NODES, 4, 24) + 4, 1))
PATCH(p_node_self, p_u16(rec(img, EW_LUMP_NODES, 5, 24) + 6, 5))
PATCH(p_leaf_shared, p_u16(rec(img, EW_LUMP_NODES, 4, 24) + 6, (uint32_t)-2))
PATCH(p_node_plane, p_i32(rec(img, EW_LUMP_NODES, 1, 24), 6))
PATCH(p_node_faces, p_u16(rec(img, EW_LUMP_NODES, 1, 24) + 22, 6))
PATCH(p_leaf_marks, p_u16(rec(img, EW_LUMP_LEAFS, 1, 28) + 22, 7))
PATCH(p_leaf_firstmark, p_u16(rec(img, EW_LUMP_LEAFS, 1, 28) + 20, 1))
PATCH(p_leaf_visofs, p_i32(rec(img, EW_LUMP_LEAFS, 1, 28) + 4, 1))
PATCH(p_leaf_visofs_neg, p_i32(rec(img, EW_LUMP_LEAFS, 1, 28) + 4, -7))
PATCH(p_mark_range, p_u16(rec(img, EW_LUMP_MARKSURFACES, 2, 2), 6))
PATCH(p_model_head, p_i32(rec(img, EW_LUMP_MODELS, 0, 64) + 36, 6))
PATCH(p_model_head_neg, p_i32(rec(img, EW_LUMP_MODELS, 0, 64) + 36, -1))
PATCH(p_model_faces, p_i32(rec(img, EW_LUMP_MODELS, 0, 64) + 60, 7))
PATCH(p_model_visleafs, p_i32(rec(img, EW_LUMP_MODELS, 0, 64) + 52, 2))
PATCH(p_no_models, p_u32(img + 8 + 8 * EW_LUMP_MODELS, 0))
PATCH(p_texinfo_miptex, p_i32(rec(img, EW_LUMP_TEXINFO, 1, 40) + 32, 7))
PATCH(p_texinfo_miptex_neg, p_i32(rec(img, EW_LUMP_TEXINFO, 1, 40) + 32, -1))
PATCH(p_tex_count_huge, p_i32(img + lump_ofs(img, EW_LUMP_TEXTURES), 1000000))
PATCH(p_tex_count_neg, p_i32(img + lump_ofs(img, EW_LUMP_TEXTURES), -2))
PATCH(p_tex_lump_short, p_u32(img + 8 + 8 * EW_LUMP_TEXTURES, 2))
PATCH(p_tex_dataofs_past, p_i32(img + lump_ofs(img, EW_LUMP_TEXTURES) + 4,
                                (int32_t)lump_len(img, EW_LUMP_TEXTURES) - 20))
PATCH(p_tex_dataofs_neg, p_i32(img + lump_ofs(img, EW_LUMP_TEXTURES) + 8, -2))
PATCH(p_tex_mip_past, p_u32(miptex(img, 1) + 24 + 12, 0x10000))
PATCH(p_tex_mip_huge, p_u32(miptex(img, 0) + 24, 0xfffffff0u))
PATCH(p_tex_width12, p_u32(miptex(img, 0) + 16, 12))
PATCH(p_tex_width0, p_u32(miptex(img, 3) + 16, 0))
PATCH(p_tex_height_huge, p_u32(miptex(img, 0) + 20, 8192))
PATCH(p_anim_gap, miptex(img, 4)[1] = '2')
PATCH(p_anim_alt_gap, miptex(img, 5)[1] = 'c')

static void test_tiny_corrupt(void) {
    size_t size;
    uint8_t *img = build_tiny(0, &size);
    const char *F = "tiny.bsp";
    static const struct {
        patch_fn fn;
        const char *want, *what;
    } cases[] = {
        {p_version30, "unsupported BSP version 30", "version 30"},
        {p_magic_ibsp, "IBSP", "IBSP magic"},
        {p_faces_past_end, "lump 'faces' (index 7)", "faces lump past end"},
        {p_faces_too_long, "past end of file", "faces lump too long"},
        {p_faces_neg_ofs, "faces", "faces lump negative offset"},
        {p_models_len_huge, "models", "models lump huge"},
        {p_planes_len_odd, "multiple", "planes length not a multiple"},
        {p_face_texinfo, "texinfo 99", "face texinfo"},
        {p_face_plane, "face 2 uses plane 6", "face plane"},
        {p_face_side, "side", "face side"},
        {p_face_firstedge, "surfedges", "face edges past surfedges"},
        {p_face_firstedge_neg, "surfedges", "face firstedge negative"},
        {p_face_numedges2, "2 edges", "face with 2 edges"},
        {p_face_numedges_neg, "face 0", "face numedges negative"},
        {p_face_light_past, "past the lighting lump", "light map past lump"},
        {p_face_light_neg, "light map", "negative light offset"},
        {p_face_styles_more, "past the lighting lump", "second style past lump"},
        {p_face_extent_huge, "extent", "huge texture extents"},
        {p_surfedge_range, "surfedge 3", "surfedge out of range"},
        {p_surfedge_neg_range, "surfedge 3", "negative surfedge out of range"},
        {p_surfedge_intmin, "surfedge 3", "surfedge INT_MIN"},
        {p_edge_vertex, "edge 7", "edge vertex out of range"},
        {p_vertex_inf, "vertex 2", "infinite vertex"},
        {p_plane_nan, "plane 2", "NaN plane"},
        {p_plane_type, "type 9", "plane type"},
        {p_node_child_node, "node 0", "node child node out of range"},
        {p_node_child_leaf, "leaf 2", "node child leaf out of range"},
        {p_node_cycle, "reached twice", "node cycle"},
        {p_node_self, "node 5 reached twice", "node self loop"},
        {p_leaf_shared, "leaf 1 reached twice", "leaf shared by two nodes"},
        {p_node_plane, "node 1 uses plane 6", "node plane"},
        {p_node_faces, "node 1", "node faces past end"},
        {p_leaf_marks, "leaf 1", "leaf marksurfaces past end"},
        {p_leaf_firstmark, "leaf 1", "leaf firstmark past end"},
        {p_leaf_visofs, "visibility", "leaf visofs past vis"},
        {p_leaf_visofs_neg, "visibility", "leaf visofs negative"},
        {p_mark_range, "marksurface 2", "marksurface out of range"},
        {p_model_head, "head node", "model headnode out of range"},
        {p_model_head_neg, "head node", "model headnode negative"},
        {p_model_faces, "model 0", "model faces past end"},
        {p_model_visleafs, "vis leaves", "model visleafs"},
        {p_no_models, "no models", "no models"},
        {p_texinfo_miptex, "texture 7", "texinfo miptex out of range"},
        {p_texinfo_miptex_neg, "texture -1", "texinfo miptex -1"},
        {p_tex_count_huge, "textures", "huge texture count"},
        {p_tex_count_neg, "textures", "negative texture count"},
        {p_tex_lump_short, "textures", "textures lump of 2 bytes"},
        {p_tex_dataofs_past, "texture 0", "miptex offset past lump"},
        {p_tex_dataofs_neg, "texture 1", "miptex offset negative"},
        {p_tex_mip_past, "mip 3", "mip data past lump"},
        {p_tex_mip_huge, "mip 0", "mip offset huge"},
        {p_tex_width12, "12x16", "texture width 12"},
        {p_tex_width0, "0x8", "texture width 0"},
        {p_tex_height_huge, "16x8192", "texture height 8192"},
        {p_anim_gap, "anim", "animation gap"},
        {p_anim_alt_gap, "anim", "alternate animation gap"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        corrupt(img, size, F, cases[i].fn, cases[i].want, cases[i].what);

    /* Every proper prefix (the models lump ends the file, so all are cut). */
    expect_bad(img, 0, F, "too short", "empty file");
    expect_bad(NULL, 0, F, "too short", "NULL data");
    expect_bad(img, 123, F, "file too short for a BSP header (123 bytes)", "123-byte file");
    int prefix_fail = 0;
    for (size_t n = 0; n < size; n++) {
        ew_error err = {{0}};
        uint8_t *c = dup_bytes(img, n);  /* exact-size copy so ASan sees overreads */
        ew_world *w = ew_world_create(c, n, F, &err);
        if (w || !mentions(&err, F)) prefix_fail++;
        ew_world_destroy(w);
        free(c);
    }
    CHECK(prefix_fail == 0, "%d of %zu prefixes of the tiny map were accepted or unnamed", prefix_fail, size);

    /* BSP2 / 2PSB: the same checks on the 32-bit fields. */
    for (int v = 0; v < 2; v++) {
        size_t n2;
        uint8_t *b2 = convert(img, size, v, &n2);
        int nrs = v ? 32 : 44, lrs = v ? 32 : 44, first = v ? 24 : 36, lfirst = v ? 20 : 32;
        uint8_t *c;
#define BSP2_CASE(stmt, want, what)           \
    c = dup_bytes(b2, n2);                    \
    stmt;                                     \
    expect_bad(c, n2, "big.bsp", want, what); \
    free(c);
        BSP2_CASE(p_i32(rec(c, EW_LUMP_NODES, 0, nrs) + 4, INT32_MAX), "node 0", "bsp2 node child huge");
        BSP2_CASE(p_i32(rec(c, EW_LUMP_NODES, 0, nrs) + 8, INT32_MIN), "node 0", "bsp2 node child INT_MIN");
        BSP2_CASE(p_i32(rec(c, EW_LUMP_NODES, 3, nrs) + 4, 0), "reached twice", "bsp2 node cycle");
        BSP2_CASE(p_u32(rec(c, EW_LUMP_NODES, 1, nrs) + first, 0xffffffffu), "node 1", "bsp2 node firstface");
        BSP2_CASE(p_u32(rec(c, EW_LUMP_LEAFS, 1, lrs) + lfirst, 0xffffffffu), "leaf 1", "bsp2 leaf firstmark");
        BSP2_CASE(p_u32(rec(c, EW_LUMP_LEAFS, 1, lrs) + lfirst + 4, 0x80000000u), "leaf 1", "bsp2 leaf nummarks");
        BSP2_CASE(p_i32(rec(c, EW_LUMP_FACES, 2, 28) + 12, 0x7fffffff), "face 2", "bsp2 face numedges");
        BSP2_CASE(p_i32(rec(c, EW_LUMP_FACES, 2, 28) + 16, -1), "texinfo -1", "bsp2 face texinfo -1");
        BSP2_CASE(p_i32(rec(c, EW_LUMP_FACES, 2, 28), 70000), "plane 70000", "bsp2 face plane");
        BSP2_CASE(p_i32(rec(c, EW_LUMP_FACES, 2, 28) + 8, INT32_MAX - 1), "surfedges", "bsp2 face firstedge overflow");
        BSP2_CASE(p_u32(rec(c, EW_LUMP_EDGES, 3, 8), 0xffffffffu), "edge 3", "bsp2 edge vertex");
        BSP2_CASE(p_u32(rec(c, EW_LUMP_MARKSURFACES, 1, 4), 0x80000000u), "marksurface 1", "bsp2 marksurface");
        BSP2_CASE(p_u32(c + 8 + 8 * EW_LUMP_NODES, 24u * 6), "multiple", "bsp2 nodes with BSP29 record size");
#undef BSP2_CASE
        int bad = 0;
        for (size_t n = 0; n < n2; n++) {
            ew_error err = {{0}};
            uint8_t *cut = dup_bytes(b2, n);
            ew_world *w = ew_world_create(cut, n, "big.bsp", &err);
            if (w || !mentions(&err, "big.bsp")) bad++;
            ew_world_destroy(w);
            free(cut);
        }
        CHECK(bad == 0, "%d prefixes of the %s tiny map were accepted", bad, v ? "2PSB" : "BSP2");
        free(b2);
    }
    free(img);
}

/* Random byte damage: either a clean rejection or a world that satisfies
 * the invariants, never a crash (ASan/UBSan watch this). */
static void fuzz(const uint8_t *img, size_t size, const char *file, int rounds, uint32_t seed) {
    int loaded = 0, unnamed = 0;
    uint32_t s = seed;
    for (int r = 0; r < rounds; r++) {
        uint8_t *c = dup_bytes(img, size);
        int flips = 1 + r % 4;
        for (int k = 0; k < flips; k++) {
            s = s * 1664525u + 1013904223u;
            size_t at = (s >> 8) % size;
            s = s * 1664525u + 1013904223u;
            c[at] = (r & 1) ? (uint8_t)(s >> 24) : (uint8_t)(c[at] ^ (1u << ((s >> 16) & 7)));
        }
        ew_error err = {{0}};
        ew_world *w = ew_world_create(c, size, file, &err);
        if (w) {
            loaded++;
            if (r % 16 == 0) check_invariants(w, file);
        } else if (!mentions(&err, file)) {
            unnamed++;
        }
        ew_world_destroy(w);
        free(c);
    }
    CHECK(unnamed == 0, "%s: %d fuzzed rejections did not name the file", file, unnamed);
    printf("fuzz %s: %d rounds, %d still loaded\n", file, rounds, loaded);
}

/* ---- real maps ------------------------------------------------------------ */

static const struct {
    const char *name;
    int missing;
} real_maps[] = {
    {"b_batt0", 0}, {"b_batt1", 0}, {"b_bh10", 0},  {"b_bh100", 1}, {"b_bh25", 0},
    {"b_exbox2", 0}, {"b_explob", 0}, {"b_nail0", 0}, {"b_nail1", 0}, {"b_rock0", 0},
    {"b_rock1", 0}, {"b_shell0", 0}, {"b_shell1", 0}, {"e1m1", 18},  {"e2m1", 0},
    {"e4m1", 3},    {"lqdm1", 0},   {"lqdm7", 0},    {"slope", 0},   {"start", 0},
};

static void test_real_maps(void) {
    if (!ew_t_need_shared("data/librequake/maps/e1m1.bsp")) return;
    for (size_t m = 0; m < sizeof real_maps / sizeof real_maps[0]; m++) {
        char rel[128];
        snprintf(rel, sizeof rel, "data/librequake/maps/%s.bsp", real_maps[m].name);
        const char *path = ew_t_shared(rel);
        uint8_t *data;
        size_t size;
        ew_error err = {{0}};
        CHECK(ew_read_file(path, &data, &size, &err) == 0, "%s", err.msg);
        if (!data) continue;
        ew_world *w = ew_world_create(data, size, path, &err);
        CHECK(w != NULL, "%s did not load: %s", real_maps[m].name, err.msg);
        if (w) {
            ew_world_info in;
            ew_world_get_info(w, &in);
            printf("%-9s models %3d textures %3d missing %2d faces %5d leaves %4d nodes %4d\n",
                   real_maps[m].name, in.models, in.textures, in.textures_missing, in.faces, in.leaves,
                   in.nodes);
            CHECK(in.textures_missing == real_maps[m].missing, "%s: %d missing textures, expected %d",
                  real_maps[m].name, in.textures_missing, real_maps[m].missing);
            CHECK(!strcmp(in.version, "29") && in.models >= 1 && in.textures > 0 && in.faces > 0 &&
                      in.leaves > 1 && in.nodes > 0 && w->lightsize > 0 && w->models[0].visleafs > 0,
                  "%s: implausible counts", real_maps[m].name);
            CHECK(in.lumps[EW_LUMP_FACES].count == in.faces && in.lumps[EW_LUMP_LEAFS].count == in.leaves &&
                      in.lumps[EW_LUMP_EDGES].count == w->numedges &&
                      in.lumps[EW_LUMP_TEXTURES].count == in.textures,
                  "%s: lump counts disagree", real_maps[m].name);
            CHECK(w->entities[0] == '{' && strstr(w->entities, "worldspawn") != NULL,
                  "%s: no worldspawn", real_maps[m].name);
            check_invariants(w, real_maps[m].name);
            int sky = 0;
            for (int i = 0; i < w->numfaces; i++) sky += (w->faces[i].flags & EW_SURF_SKY) != 0;
            if (!strcmp(real_maps[m].name, "e1m1")) {
                CHECK(sky > 0, "e1m1 has no sky faces");
                int water = find_texture(w, "+0water_f1"), alt = find_texture(w, "+a_tscrn2");
                int jump = find_texture(w, "+0tek_jump1");
                CHECK(water >= 0 && w->textures[water].anim_total == 4 &&
                          w->textures[water].alternate_anims == -1,
                      "e1m1 +0water_f1 cycle");
                CHECK(alt >= 0 && w->textures[alt].anim_total == 1 && w->textures[alt].anim_next == alt &&
                          w->textures[alt].alternate_anims == -1,
                      "e1m1 +a_tscrn2 (alternate cycle alone)");
                CHECK(jump >= 0 && w->textures[jump].anim_total == 2 &&
                          w->textures[jump].alternate_anims == find_texture(w, "+atek_jump1"),
                      "e1m1 +0tek_jump1 with alternate");
                if (water >= 0) {
                    /* walking anim_next returns to the start after anim_total steps */
                    int t = water, steps = 0;
                    do t = w->textures[t].anim_next, steps++;
                    while (t != water && steps < 20);
                    CHECK(steps == 4, "e1m1 water cycle length %d", steps);
                }
            }
        }

        /* BSP2 and 2PSB re-encodings: identical worlds. */
        if (w && (!strcmp(real_maps[m].name, "e1m1") || !strcmp(real_maps[m].name, "b_bh100") ||
                  !strcmp(real_maps[m].name, "start"))) {
            for (int v = 0; v < 2; v++) {
                size_t n2;
                uint8_t *b2 = convert(data, size, v, &n2);
                ew_world *w2 = ew_world_create(b2, n2, "conv.bsp", &err);
                CHECK(w2 != NULL, "%s as %s: %s", real_maps[m].name, v ? "2PSB" : "BSP2", err.msg);
                if (w2) CHECK(same_world(w, w2), "%s as %s differs", real_maps[m].name, w2->version);
                ew_world_destroy(w2);
                /* and damage the converted image */
                uint8_t *c = dup_bytes(b2, n2);
                p_i32(rec(c, EW_LUMP_NODES, 10, v ? 32 : 44) + 4, 10);  /* node 10 -> itself */
                expect_bad(c, n2, "conv.bsp", "reached twice", "converted map with a self-loop");
                memcpy(c, b2, n2);
                int lit = 0;  /* first face with a light map */
                while (lit < w->numfaces - 1 && w->faces[lit].lightofs < 0) lit++;
                p_u32(rec(c, EW_LUMP_FACES, lit, 28) + 24, (uint32_t)w->lightsize - 1);
                expect_bad(c, n2, "conv.bsp", "past the lighting lump", "converted map light offset");
                free(c);
                free(b2);
            }
        }

        /* Prefixes: all those that cut the last lump must fail cleanly. */
        if (w && (!strcmp(real_maps[m].name, "e1m1") || !strcmp(real_maps[m].name, "b_batt0"))) {
            size_t end = 0;
            for (int l = 0; l < EW_NUM_LUMPS; l++) {
                size_t e = (size_t)lump_ofs(data, l) + lump_len(data, l);
                if (e > end) end = e;
            }
            int bad = 0, tried = 0;
            for (int k = 0; k <= 40; k++) {
                size_t n = k < 20 ? (size_t)k * 7 : (end - 1) * (size_t)(k - 20) / 20;
                if (k == 40) n = end - 1;
                uint8_t *cut = dup_bytes(data, n);
                ew_world *wc = ew_world_create(cut, n, path, &err);
                if (wc || !mentions(&err, path)) bad++;
                tried++;
                ew_world_destroy(wc);
                free(cut);
            }
            CHECK(bad == 0, "%s: %d of %d prefixes accepted", real_maps[m].name, bad, tried);
        }

        if (w && !strcmp(real_maps[m].name, "b_batt0")) fuzz(data, size, "b_batt0.bsp", 3000, 12345);

        /* A few targeted breakages of the real file. */
        if (w && !strcmp(real_maps[m].name, "e1m1")) {
            uint8_t *c = dup_bytes(data, size);
            p_u16(rec(c, EW_LUMP_FACES, 100, 20) + 10, (uint32_t)w->numtexinfo);
            expect_bad(c, size, "e1m1.bsp", "face 100 uses texinfo", "e1m1 face texinfo");
            memcpy(c, data, size);
            p_i32(rec(c, EW_LUMP_SURFEDGES, 50, 4), w->numedges);
            expect_bad(c, size, "e1m1.bsp", "surfedge 50", "e1m1 surfedge");
            memcpy(c, data, size);
            p_i32(c + 4 + 8 * EW_LUMP_LIGHTING, (int32_t)size);
            expect_bad(c, size, "e1m1.bsp", "lighting", "e1m1 lighting lump past end");
            free(c);
        }
        ew_world_destroy(w);
        free(data);
    }
}

/* ---- PAK ----------------------------------------------------------------- */

typedef struct pak_file {
    const char *name;
    const char *text;
} pak_file;

/* "PACK" header, file data, then the directory at the end. */
static uint8_t *build_pak(const pak_file *files, int n, size_t *size) {
    buf b = {0};
    b_put(&b, "PACK", 4);
    b_zero(&b, 8);
    uint32_t *ofs = calloc((size_t)n + 1, sizeof *ofs);
    for (int i = 0; i < n; i++) {
        ofs[i] = (uint32_t)b.n;
        b_put(&b, files[i].text, strlen(files[i].text));
    }
    uint32_t dirofs = (uint32_t)b.n;
    for (int i = 0; i < n; i++) {
        char nm[56] = {0};
        memcpy(nm, files[i].name, strlen(files[i].name));
        b_put(&b, nm, 56);
        b_u32(&b, ofs[i]);
        b_u32(&b, (uint32_t)strlen(files[i].text));
    }
    p_u32(b.p + 4, dirofs);
    p_u32(b.p + 8, (uint32_t)(n * 64));
    free(ofs);
    *size = b.n;
    return b.p;
}

static void expect_pak_bad(const uint8_t *p, size_t n, const char *want, const char *what) {
    ew_error err = {{0}};
    ew_pak_entry *e = (ew_pak_entry *)1;
    int count = 7;
    int rc = ew_pak_parse(p, n, "test.pak", &e, &count, &err);
    CHECK(rc == -1 && e == NULL && count == 0, "%s: accepted", what);
    CHECK(mentions(&err, "test.pak"), "%s: message does not name the pak: '%s'", what, err.msg);
    if (want) CHECK(mentions(&err, want), "%s: message lacks '%s': '%s'", what, want, err.msg);
    if (rc == 0) free(e);
}

static void test_pak(void) {
    const pak_file files[] = {{"maps/a.bsp", "AAAA"}, {"gfx/palette.lmp", "PAL"}, {"empty", ""}};
    size_t size;
    uint8_t *pak = build_pak(files, 3, &size);
    ew_error err = {{0}};
    ew_pak_entry *e = NULL;
    int n = 0;
    CHECK(ew_pak_parse(pak, size, "test.pak", &e, &n, &err) == 0, "pak: %s", err.msg);
    CHECK(n == 3, "pak entries %d", n);
    if (n == 3) {
        CHECK(!strcmp(e[0].name, "maps/a.bsp") && e[0].offset == 12 && e[0].size == 4 &&
                  !memcmp(pak + e[0].offset, "AAAA", 4),
              "entry 0");
        CHECK(!strcmp(e[1].name, "gfx/palette.lmp") && e[1].size == 3 && e[2].size == 0, "entries 1, 2");
    }
    free(e);

    uint8_t *c = dup_bytes(pak, size);
    expect_pak_bad(c, 11, "too short", "11-byte pak");
    expect_pak_bad(c, size - 1, "past end", "directory cut by one byte");
    expect_pak_bad(c, size - 64, "past end", "directory cut by one entry");
    int bad = 0;
    for (size_t k = 0; k < size; k++) {
        uint8_t *cut = dup_bytes(pak, k);
        ew_pak_entry *ce = NULL;
        int cn = 0;
        if (ew_pak_parse(cut, k, "test.pak", &ce, &cn, &err) == 0) bad++, free(ce);
        free(cut);
    }
    CHECK(bad == 0, "%d pak prefixes accepted", bad);

    memcpy(c, "PAKK", 4);
    expect_pak_bad(c, size, "PACK", "bad magic");
    memcpy(c, pak, size);
    p_u32(c + 8, 3 * 64 - 1);
    expect_pak_bad(c, size, "multiple", "dirlen not a multiple of 64");
    memcpy(c, pak, size);
    p_i32(c + 4, -64);
    expect_pak_bad(c, size, "directory", "negative dirofs");
    memcpy(c, pak, size);
    uint8_t *ent1 = c + ew_u32(c + 4) + 64;
    p_u32(ent1 + 60, (uint32_t)size);  /* entry 1 size: past the end */
    expect_pak_bad(c, size, "entry 1", "entry past end");
    memcpy(c, pak, size);
    p_i32(ent1 + 56, -1);
    expect_pak_bad(c, size, "entry 1", "entry negative offset");
    memcpy(c, pak, size);
    memset(ent1, 'x', 56);
    expect_pak_bad(c, size, "NUL", "name without NUL");
    free(c);
    free(pak);

    /* an empty pak is fine */
    pak = build_pak(files, 0, &size);
    CHECK(ew_pak_parse(pak, size, "empty.pak", &e, &n, &err) == 0 && n == 0, "empty pak: %s", err.msg);
    free(e);
    free(pak);
}

/* ---- game directories and assets (on disk) -------------------------------- */

static char tmpdir[256];

static void write_file(const char *rel, const void *data, size_t n) {
    char path[512];
    snprintf(path, sizeof path, "%s/%s", tmpdir, rel);
    FILE *f = fopen(path, "wb");
    CHECK(f != NULL, "cannot create %s", path);
    if (!f) return;
    fwrite(data, 1, n, f);
    fclose(f);
}
static void write_pak(const char *rel, const pak_file *files, int n) {
    size_t size;
    uint8_t *p = build_pak(files, n, &size);
    write_file(rel, p, size);
    free(p);
}
static void make_dir(const char *rel) {
    char path[512];
    snprintf(path, sizeof path, "%s/%s", tmpdir, rel);
    mkdir(path, 0700);
}
static const char *tmp_path(const char *rel) {
    static char path[4][512];
    static int next;
    char *p = path[next++ & 3];
    snprintf(p, 512, "%s/%s", tmpdir, rel);
    return p;
}

static void expect_load(const ew_fs *fs, const char *name, const char *text) {
    uint8_t *d;
    size_t n;
    ew_error err = {{0}};
    int rc = ew_fs_load(fs, name, &d, &n, &err);
    CHECK(rc == 0 && n == strlen(text) && !memcmp(d, text, n), "%s: expected '%s' (%s)", name, text,
          rc ? err.msg : "wrong content");
    free(d);
}

static void test_fs_and_assets(void) {
    snprintf(tmpdir, sizeof tmpdir, "/tmp/ew_test_loaders_XXXXXX");
    if (!mkdtemp(tmpdir)) {
        CHECK(0, "mkdtemp failed");
        return;
    }
    ew_error err = {{0}};

    /* ew_read_file */
    uint8_t *d;
    size_t n;
    CHECK(ew_read_file(tmp_path("nope"), &d, &n, &err) == -1 && mentions(&err, "nope") &&
              mentions(&err, "cannot open"),
          "missing file: '%s'", err.msg);
    CHECK(ew_read_file(tmpdir, &d, &n, &err) == -1 && mentions(&err, tmpdir), "directory: '%s'", err.msg);
    write_file("empty", "", 0);
    CHECK(ew_read_file(tmp_path("empty"), &d, &n, &err) == 0 && n == 0 && d != NULL, "empty file: %s", err.msg);
    free(d);

    /* game directory: loose > pak1 > pak0; pak3 is ignored (pak2 missing) */
    make_dir("game");
    make_dir("game/gfx");
    const pak_file p0[] = {{"a.txt", "pak0-a"}, {"b.txt", "pak0-b"}, {"c.txt", "pak0-c"}};
    const pak_file p1[] = {{"b.txt", "pak1-b"}, {"c.txt", "pak1-c"}, {"GFX/Upper.txt", "upper"}};
    const pak_file p3[] = {{"d.txt", "pak3-d"}};
    write_pak("game/pak0.pak", p0, 3);
    write_pak("game/pak1.pak", p1, 3);
    write_pak("game/pak3.pak", p3, 1);
    write_file("game/c.txt", "loose-c", 7);
    ew_fs *fs = ew_fs_create(tmp_path("game"), &err);
    CHECK(fs != NULL, "ew_fs_create: %s", err.msg);
    if (fs) {
        expect_load(fs, "a.txt", "pak0-a");
        expect_load(fs, "b.txt", "pak1-b");
        expect_load(fs, "c.txt", "loose-c");
        expect_load(fs, "gfx/upper.txt", "upper");
        int rc = ew_fs_load(fs, "d.txt", &d, &n, &err);
        CHECK(rc == -1 && mentions(&err, "d.txt not found") && mentions(&err, "2 paks") &&
                  mentions(&err, tmp_path("game")),
              "not found: '%s'", err.msg);
        ew_fs_destroy(fs);
    }
    CHECK(ew_fs_create(tmp_path("game/c.txt"), &err) == NULL && mentions(&err, "not a directory"),
          "fs on a file: '%s'", err.msg);
    CHECK(ew_fs_create(tmp_path("nodir"), &err) == NULL && mentions(&err, "nodir"), "fs on nothing: '%s'",
          err.msg);

    /* a broken pak makes the directory unusable, naming the pak */
    make_dir("broken");
    write_file("broken/pak0.pak", "PACK\x0c\0\0\0\x40\0\0\0", 12);
    CHECK(ew_fs_create(tmp_path("broken"), &err) == NULL && mentions(&err, "pak0.pak"),
          "broken pak: '%s'", err.msg);

    /* assets: by name through the game directory, by path with ../gfx */
    uint8_t pal[768], cmap[EW_COLORMAP_SIZE + 1];
    for (int i = 0; i < 768; i++) pal[i] = (uint8_t)(i * 5);
    for (int i = 0; i < EW_COLORMAP_SIZE + 1; i++) cmap[i] = (uint8_t)(i / 64);
    write_file("game/gfx/palette.lmp", pal, 768);
    write_file("game/gfx/colormap.lmp", cmap, EW_COLORMAP_SIZE + 1);  /* a trailing byte is fine */
    make_dir("game/maps");
    size_t tsize;
    uint8_t *tiny = build_tiny(0, &tsize);
    write_file("game/maps/tiny.bsp", tiny, tsize);
    /* a map only in a pak */
    {
        buf b = {0};
        b_put(&b, "PACK", 4);
        b_zero(&b, 8);
        b_put(&b, tiny, tsize);
        char nm[56] = "maps/inpak.bsp";
        uint32_t dirofs = (uint32_t)b.n;
        b_put(&b, nm, 56);
        b_u32(&b, 12);
        b_u32(&b, (uint32_t)tsize);
        p_u32(b.p + 4, dirofs);
        p_u32(b.p + 8, 64);
        write_file("game/pak2.pak", b.p, b.n);
        free(b.p);
    }

    ew_assets *a = NULL;
    CHECK((a = ew_assets_create("tiny", tmp_path("game"), &err)) != NULL, "assets by name: %s", err.msg);
    if (a) {
        CHECK(!strcmp(a->world->name, "tiny.bsp") && a->world->numfaces == 6, "assets world '%s'", a->world->name);
        CHECK(!memcmp(a->palette, pal, 768) && !memcmp(a->colormap, cmap, EW_COLORMAP_SIZE), "assets tables");
        ew_assets_destroy(a);
        ew_assets_destroy(NULL);  /* accepted, as free(NULL) */
    }
    CHECK((a = ew_assets_create("inpak", tmp_path("game"), &err)) != NULL && a->world &&
              !strcmp(a->world->name, "inpak.bsp"),
          "assets from pak: %s", err.msg);
    ew_assets_destroy(a);
    CHECK((a = ew_assets_create(tmp_path("game/maps/tiny.bsp"), NULL, &err)) != NULL &&
              !memcmp(a->palette, pal, 768),
          "assets by path: %s", err.msg);
    ew_assets_destroy(a);
    CHECK((a = ew_assets_create(tmp_path("game/maps/tiny.bsp"), tmp_path("game"), &err)) != NULL,
          "assets by path with data dir: %s", err.msg);
    ew_assets_destroy(a);
    CHECK((a = ew_assets_create("tiny", NULL, &err)) == NULL && mentions(&err, "tiny: not a .bsp file and no --data"),
          "assets without data dir: '%s'", err.msg);
    CHECK((a = ew_assets_create("nosuch", tmp_path("game"), &err)) == NULL &&
              mentions(&err, "maps/nosuch.bsp not found"),
          "assets missing map: '%s'", err.msg);
    CHECK((a = ew_assets_create(tmp_path("game/maps/none.bsp"), NULL, &err)) == NULL && mentions(&err, "none.bsp"),
          "assets missing bsp: '%s'", err.msg);

    /* short palette / colormap through the whole path */
    write_file("game/gfx/palette.lmp", pal, 767);
    CHECK((a = ew_assets_create("tiny", tmp_path("game"), &err)) == NULL && mentions(&err, "palette.lmp"),
          "short palette: '%s'", err.msg);
    write_file("game/gfx/palette.lmp", pal, 768);
    write_file("game/gfx/colormap.lmp", cmap, 100);
    CHECK((a = ew_assets_create(tmp_path("game/maps/tiny.bsp"), NULL, &err)) == NULL &&
              mentions(&err, "colormap.lmp"),
          "short colormap: '%s'", err.msg);
    /* a corrupt map through assets names the map */
    write_file("game/maps/tiny.bsp", tiny, tsize / 2);
    CHECK((a = ew_assets_create("tiny", tmp_path("game"), &err)) == NULL && mentions(&err, "maps/tiny.bsp"),
          "corrupt map via assets: '%s'", err.msg);
    free(tiny);

    /* clean up */
    const char *files[] = {"empty", "game/pak0.pak", "game/pak1.pak", "game/pak2.pak", "game/pak3.pak",
                           "game/c.txt", "game/gfx/palette.lmp", "game/gfx/colormap.lmp",
                           "game/maps/tiny.bsp", "broken/pak0.pak"};
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) unlink(tmp_path(files[i]));
    const char *dirs[] = {"game/gfx", "game/maps", "game", "broken"};
    for (size_t i = 0; i < sizeof dirs / sizeof dirs[0]; i++) rmdir(tmp_path(dirs[i]));
    rmdir(tmpdir);
}

/* ---- palette / colormap ------------------------------------------------------ */

static void test_lmp(void) {
    uint8_t buf1[EW_COLORMAP_SIZE + 1], pal[768], cmap[EW_COLORMAP_SIZE];
    for (size_t i = 0; i < sizeof buf1; i++) buf1[i] = (uint8_t)(i * 13);
    ew_error err = {{0}};
    CHECK(ew_palette_parse(buf1, 768, "p.lmp", pal, &err) == 0 && !memcmp(pal, buf1, 768), "palette");
    CHECK(ew_palette_parse(buf1, 767, "p.lmp", pal, &err) == -1 && mentions(&err, "p.lmp") &&
              mentions(&err, "767"),
          "short palette: '%s'", err.msg);
    CHECK(ew_palette_parse(buf1, 0, "p.lmp", pal, &err) == -1 && mentions(&err, "p.lmp"), "empty palette");
    CHECK(ew_colormap_parse(buf1, sizeof buf1, "c.lmp", cmap, &err) == 0 &&
              !memcmp(cmap, buf1, EW_COLORMAP_SIZE),
          "colormap with a trailing byte");
    CHECK(ew_colormap_parse(buf1, EW_COLORMAP_SIZE - 1, "c.lmp", cmap, &err) == -1 &&
              mentions(&err, "c.lmp"),
          "short colormap: '%s'", err.msg);

    if (ew_t_need_shared("data/librequake/gfx/palette.lmp")) {
        uint8_t *d;
        size_t n;
        const char *pp = ew_t_shared("data/librequake/gfx/palette.lmp");
        const char *cp = ew_t_shared("data/librequake/gfx/colormap.lmp");
        CHECK(ew_read_file(pp, &d, &n, &err) == 0 && ew_palette_parse(d, n, pp, pal, &err) == 0,
              "real palette: %s", err.msg);
        free(d);
        CHECK(ew_read_file(cp, &d, &n, &err) == 0 && n == EW_COLORMAP_SIZE &&
                  ew_colormap_parse(d, n, cp, cmap, &err) == 0,
              "real colormap: %s", err.msg);
        free(d);
        /* the real map through ew_assets_create: by path and by name */
        ew_assets *a = NULL;
        const char *map = ew_t_shared("data/librequake/maps/e1m1.bsp");
        CHECK((a = ew_assets_create(map, NULL, &err)) != NULL && a->world &&
                  !strcmp(a->world->name, "e1m1.bsp") && !memcmp(a->palette, pal, 768),
              "real e1m1 by path: %s", err.msg);
        ew_assets_destroy(a);
        CHECK((a = ew_assets_create("start", ew_t_shared("data/librequake"), &err)) != NULL && a->world &&
                  !memcmp(a->colormap, cmap, EW_COLORMAP_SIZE),
              "real start by name: %s", err.msg);
        ew_assets_destroy(a);
    }
}

int main(void) {
    test_tiny_ok();
    test_tiny_corrupt();
    {
        size_t size;
        uint8_t *img = build_tiny(0, &size);
        fuzz(img, size, "tiny.bsp", 4000, 777);
        size_t n2;
        uint8_t *b2 = convert(img, size, 0, &n2);
        fuzz(b2, n2, "tiny2.bsp", 2000, 4242);
        free(b2);
        free(img);
    }
    test_real_maps();
    test_pak();
    test_fs_and_assets();
    test_lmp();
    return ew_t_finish();
}
