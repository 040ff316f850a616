/*
 * Small valid files of every format the fuzzers read, made from scratch
 * (see seed_files.h): the seeds of make_seeds, and the stage the MDL and
 * SPR fuzz targets render their models in.
 */
#include "seed_files.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- byte buffer ---------------------------------------------------------- */

static void put(ew_seed_buf *b, const void *p, size_t n) {
    if (n == 0) return;
    if (b->len + n > b->cap) {
        size_t cap = b->cap ? b->cap : 1024;
        while (cap < b->len + n) cap *= 2;
        uint8_t *d = realloc(b->d, cap);
        if (!d) {
            fprintf(stderr, "seed_files: out of memory\n");
            exit(1);
        }
        b->d = d, b->cap = cap;
    }
    if (p)
        memcpy(b->d + b->len, p, n);
    else
        memset(b->d + b->len, 0, n);
    b->len += n;
}
static void put_u8(ew_seed_buf *b, int v) { uint8_t x = (uint8_t)v; put(b, &x, 1); }
static void put_u16(ew_seed_buf *b, int v) { put_u8(b, v & 255), put_u8(b, (v >> 8) & 255); }
static void put_i32(ew_seed_buf *b, int32_t v) {
    uint32_t u = (uint32_t)v;
    for (int i = 0; i < 4; i++) put_u8(b, (int)(u >> (8 * i)) & 255);
}
static void put_f32(ew_seed_buf *b, float f) {
    int32_t v;
    memcpy(&v, &f, 4);
    put_i32(b, v);
}
static void put_str(ew_seed_buf *b, const char *s, size_t field) {
    char tmp[64] = {0};
    memcpy(tmp, s, strlen(s) < field ? strlen(s) : field - 1);
    put(b, tmp, field);
}
static void pad4(ew_seed_buf *b) { while (b->len % 4) put_u8(b, 0); }

static int32_t rd_i32(const uint8_t *p) {
    return (int32_t)((uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24);
}
static int rd_i16(const uint8_t *p) { return (int16_t)(p[0] | p[1] << 8); }
static int rd_u16(const uint8_t *p) { return p[0] | p[1] << 8; }

/* ---- the room: a BSP29 box seen from inside ------------------------------- */

enum { NUM_LUMPS = 15 };
enum { L_ENT, L_PLANES, L_TEX, L_VERTS, L_VIS, L_NODES, L_TEXINFO, L_FACES, L_LIGHT,
       L_CLIP, L_LEAFS, L_MARKS, L_EDGES, L_SURFEDGES, L_MODELS };

static const float room_min[3] = {-64, -64, -32}, room_max[3] = {64, 64, 64};

/* Textures: name, width, height (missing: no pixels, offset -1). */
static const struct { const char *name; int w, h, missing; } room_tex[] = {
    {"brick", 16, 16, 0}, {"sky1", 32, 16, 0},     {"*water", 16, 16, 0}, {"+0button", 16, 16, 0},
    {"+1button", 16, 16, 0}, {"{grate", 16, 16, 0}, {"gone", 16, 16, 1},
};
enum { NTEX = sizeof room_tex / sizeof room_tex[0] };

/* The six walls: axis, which end of the box, texture, light styles. */
static const struct { int axis, high, tex; uint8_t styles[4]; } room_face[6] = {
    {2, 0, 0, {0, 255, 255, 255}},   /* floor, brick, lit */
    {2, 1, 1, {255, 255, 255, 255}}, /* ceiling, sky */
    {0, 0, 2, {255, 255, 255, 255}}, /* -x wall, water */
    {0, 1, 3, {0, 1, 255, 255}},     /* +x wall, animated button, two styles */
    {1, 0, 5, {0, 255, 255, 255}},   /* -y wall, fence */
    {1, 1, 6, {255, 255, 255, 255}}, /* +y wall, missing texture, no light map */
};

static void lump_textures(ew_seed_buf *b) {
    int ofs[NTEX], pos = 4 + 4 * NTEX;
    for (int i = 0; i < NTEX; i++) {
        if (room_tex[i].missing) {
            ofs[i] = -1;
            continue;
        }
        ofs[i] = pos;
        int w = room_tex[i].w, h = room_tex[i].h;
        pos += 40 + w * h + (w / 2) * (h / 2) + (w / 4) * (h / 4) + (w / 8) * (h / 8);
    }
    put_i32(b, NTEX);
    for (int i = 0; i < NTEX; i++) put_i32(b, ofs[i]);
    for (int i = 0; i < NTEX; i++) {
        if (room_tex[i].missing) continue;
        int w = room_tex[i].w, h = room_tex[i].h, mo = 40;
        put_str(b, room_tex[i].name, 16);
        put_i32(b, w), put_i32(b, h);
        for (int k = 0; k < 4; k++) {
            put_i32(b, mo);
            mo += (w >> k) * (h >> k);
        }
        for (int k = 0; k < 4; k++)
            for (int y = 0; y < h >> k; y++)
                for (int x = 0; x < w >> k; x++) put_u8(b, (i * 37 + x * 3 + y * 11 + k) & 255);
    }
}

/* Corner c of the box: bit 0 = x, bit 1 = y, bit 2 = z at the high end. */
static void corner(int c, float v[3]) {
    for (int k = 0; k < 3; k++) v[k] = (c >> k) & 1 ? room_max[k] : room_min[k];
}

/* The four corners of wall f, clockwise seen from inside the room. */
static void wall_corners(int f, int out[4]) {
    int axis = room_face[f].axis, a = (axis + 1) % 3, b = (axis + 2) % 3;
    int base = room_face[f].high << axis;
    int ring[4] = {0, 1 << a, (1 << a) | (1 << b), 1 << b};
    for (int i = 0; i < 4; i++) out[i] = base | ring[i];
    /* The face looks into the room: +axis from the low wall, -axis from
     * the high one.  Clockwise from the front means the winding's normal
     * points away from the viewer. */
    float p[3][3];
    for (int i = 0; i < 3; i++) corner(out[i], p[i]);
    float e1[3], e2[3], n[3];
    for (int k = 0; k < 3; k++) e1[k] = p[1][k] - p[0][k], e2[k] = p[2][k] - p[0][k];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    float facing = room_face[f].high ? -1.0f : 1.0f;
    if (n[axis] * facing > 0) {
        int t = out[1];
        out[1] = out[3];
        out[3] = t;
    }
}

/* Texture axes of a wall: s along the next axis, t down (or along -y). */
static void wall_vecs(int f, float vecs[2][4]) {
    memset(vecs, 0, sizeof(float) * 8);
    int axis = room_face[f].axis;
    if (axis == 2) {
        vecs[0][0] = 1, vecs[1][1] = -1;
    } else {
        vecs[0][axis == 0 ? 1 : 0] = 1;
        vecs[1][2] = -1;
    }
}

static int wall_lightmap_size(int f, const int c[4]) {
    float vecs[2][4];
    wall_vecs(f, vecs);
    int ext[2];
    for (int j = 0; j < 2; j++) {
        float lo = 1e9f, hi = -1e9f;
        for (int i = 0; i < 4; i++) {
            float v[3];
            corner(c[i], v);
            float s = v[0] * vecs[j][0] + v[1] * vecs[j][1] + v[2] * vecs[j][2] + vecs[j][3];
            lo = s < lo ? s : lo, hi = s > hi ? s : hi;
        }
        int bmin = (int)floorf(lo / 16), bmax = (int)ceilf(hi / 16);
        ext[j] = (bmax - bmin) * 16;
    }
    return ((ext[0] >> 4) + 1) * ((ext[1] >> 4) + 1);
}

void ew_seed_room(ew_seed_buf *out) {
    ew_seed_buf L[NUM_LUMPS];
    memset(L, 0, sizeof L);

    const char *ents =
        "{\n\"classname\" \"worldspawn\"\n\"message\" \"edgewise fuzz seed\"\n}\n"
        "{\n\"classname\" \"info_player_start\"\n\"origin\" \"0 0 0\"\n\"angle\" \"30\"\n}\n"
        "{\n\"classname\" \"info_intermission\"\n\"origin\" \"10 -20 30\"\n\"mangle\" \"20 200 0\"\n}\n";
    put(&L[L_ENT], ents, strlen(ents) + 1);

    /* Planes: one per wall, normals along +axis as compilers write them. */
    for (int f = 0; f < 6; f++) {
        int axis = room_face[f].axis;
        for (int k = 0; k < 3; k++) put_f32(&L[L_PLANES], k == axis ? 1.0f : 0.0f);
        put_f32(&L[L_PLANES], room_face[f].high ? room_max[axis] : room_min[axis]);
        put_i32(&L[L_PLANES], axis);
    }
    lump_textures(&L[L_TEX]);
    for (int c = 0; c < 8; c++) {
        float v[3];
        corner(c, v);
        for (int k = 0; k < 3; k++) put_f32(&L[L_VERTS], v[k]);
    }
    put_u8(&L[L_VIS], 0x01);  /* leaf 1 sees itself */

    /* Edges shared between walls: edge 0 is unused, as in Quake. */
    int edge_v[32][2], nedges = 1;
    int surfedges[24], nse = 0;
    edge_v[0][0] = edge_v[0][1] = 0;
    int lightofs = 0;
    for (int f = 0; f < 6; f++) {
        int c[4];
        wall_corners(f, c);
        int first = nse;
        for (int i = 0; i < 4; i++) {
            int a = c[i], b = c[(i + 1) % 4], se = 0;
            for (int e = 1; e < nedges && !se; e++) {
                if (edge_v[e][0] == b && edge_v[e][1] == a) se = -e;
                if (edge_v[e][0] == a && edge_v[e][1] == b) se = e;
            }
            if (!se) {
                edge_v[nedges][0] = a, edge_v[nedges][1] = b;
                se = nedges++;
            }
            surfedges[nse++] = se;
        }
        float vecs[2][4];
        wall_vecs(f, vecs);
        for (int j = 0; j < 2; j++)
            for (int k = 0; k < 4; k++) put_f32(&L[L_TEXINFO], vecs[j][k]);
        put_i32(&L[L_TEXINFO], room_face[f].tex);
        put_i32(&L[L_TEXINFO], room_face[f].tex == 1 || room_face[f].tex == 2);  /* special */

        int nstyles = 0;
        while (nstyles < 4 && room_face[f].styles[nstyles] != 255) nstyles++;
        put_u16(&L[L_FACES], f);                   /* plane */
        put_u16(&L[L_FACES], room_face[f].high);   /* side: the high walls look along -axis */
        put_i32(&L[L_FACES], first);
        put_u16(&L[L_FACES], 4);
        put_u16(&L[L_FACES], f);                   /* texinfo */
        put(&L[L_FACES], room_face[f].styles, 4);
        put_i32(&L[L_FACES], nstyles ? lightofs : -1);
        int size = wall_lightmap_size(f, c) * nstyles;
        for (int i = 0; i < size; i++) put_u8(&L[L_LIGHT], 64 + (i * 7 + f * 29) % 160);
        lightofs += size;
    }
    for (int e = 0; e < nedges; e++) put_u16(&L[L_EDGES], edge_v[e][0]), put_u16(&L[L_EDGES], edge_v[e][1]);
    for (int i = 0; i < nse; i++) put_i32(&L[L_SURFEDGES], surfedges[i]);

    /* A chain of six nodes, one per wall: the room is on the inner side of
     * each, solid leaf 0 on the outer side; the last leads to leaf 1. */
    for (int f = 0; f < 6; f++) {
        int next = f < 5 ? f + 1 : -2, solid = -1;
        int inner_is_front = !room_face[f].high;
        put_i32(&L[L_NODES], f);
        put_u16(&L[L_NODES], inner_is_front ? next : solid);
        put_u16(&L[L_NODES], inner_is_front ? solid : next);
        for (int k = 0; k < 3; k++) put_u16(&L[L_NODES], (int)room_min[k]);
        for (int k = 0; k < 3; k++) put_u16(&L[L_NODES], (int)room_max[k]);
        put_u16(&L[L_NODES], f), put_u16(&L[L_NODES], 1);
        /* clip hull: the same chain with contents instead of leaves */
        int cnext = f < 5 ? f + 1 : -1 /* empty */, csolid = -2;
        put_i32(&L[L_CLIP], f);
        put_u16(&L[L_CLIP], inner_is_front ? cnext : csolid);
        put_u16(&L[L_CLIP], inner_is_front ? csolid : cnext);
    }
    /* Leaves: 0 solid, 1 the room. */
    put_i32(&L[L_LEAFS], -2), put_i32(&L[L_LEAFS], -1), put(&L[L_LEAFS], NULL, 12 + 4 + 4);
    put_i32(&L[L_LEAFS], -1), put_i32(&L[L_LEAFS], 0);
    for (int k = 0; k < 3; k++) put_u16(&L[L_LEAFS], (int)room_min[k]);
    for (int k = 0; k < 3; k++) put_u16(&L[L_LEAFS], (int)room_max[k]);
    put_u16(&L[L_LEAFS], 0), put_u16(&L[L_LEAFS], 6);
    put(&L[L_LEAFS], "\x10\x00\x00\x00", 4);  /* ambient sounds */
    for (int f = 0; f < 6; f++) put_u16(&L[L_MARKS], f);

    for (int k = 0; k < 3; k++) put_f32(&L[L_MODELS], room_min[k]);
    for (int k = 0; k < 3; k++) put_f32(&L[L_MODELS], room_max[k]);
    for (int k = 0; k < 3; k++) put_f32(&L[L_MODELS], 0);
    put_i32(&L[L_MODELS], 0), put_i32(&L[L_MODELS], 0), put_i32(&L[L_MODELS], 0), put_i32(&L[L_MODELS], 0);
    put_i32(&L[L_MODELS], 1);                               /* visleafs */
    put_i32(&L[L_MODELS], 0), put_i32(&L[L_MODELS], 6);     /* faces */

    put_i32(out, 29);
    size_t pos = 4 + NUM_LUMPS * 8;
    for (int i = 0; i < NUM_LUMPS; i++) {
        put_i32(out, (int32_t)pos), put_i32(out, (int32_t)L[i].len);
        pos += (L[i].len + 3) & ~(size_t)3;
    }
    for (int i = 0; i < NUM_LUMPS; i++) {
        put(out, L[i].d, L[i].len);
        pad4(out);
        free(L[i].d);
    }
}

/* ---- BSP29 -> BSP2 / 2PSB ------------------------------------------------- */

/* Rewrites a valid BSP29 with the 32-bit records of BSP2 (float bounds) or
 * 2PSB (16-bit bounds); other lumps are copied. Returns 0 or -1. */
int ew_seed_convert29(const uint8_t *d, size_t size, int bsp2, ew_seed_buf *out) {
    if (size < 4 + NUM_LUMPS * 8 || rd_i32(d) != 29) return -1;
    ew_seed_buf L[NUM_LUMPS];
    memset(L, 0, sizeof L);
    for (int i = 0; i < NUM_LUMPS; i++) {
        int32_t ofs = rd_i32(d + 4 + 8 * i), len = rd_i32(d + 8 + 8 * i);
        if (ofs < 0 || len < 0 || (size_t)ofs + (size_t)len > size) {
            for (int k = 0; k < i; k++) free(L[k].d);
            return -1;
        }
        const uint8_t *p = d + ofs;
        ew_seed_buf *o = &L[i];
        /* bounds: three int16 mins then three maxs */
#define BOUNDS(q)                                                                 \
    for (int k = 0; k < 6; k++) {                                                 \
        if (bsp2) put_f32(o, (float)rd_i16((q) + 2 * k)); else put_u16(o, rd_u16((q) + 2 * k)); \
    }
        switch (i) {
        case L_NODES:
            for (int r = 0; r + 24 <= len; r += 24) {
                put_i32(o, rd_i32(p + r));
                put_i32(o, rd_i16(p + r + 4)), put_i32(o, rd_i16(p + r + 6));
                BOUNDS(p + r + 8)
                put_i32(o, rd_u16(p + r + 20)), put_i32(o, rd_u16(p + r + 22));
            }
            break;
        case L_FACES:
            for (int r = 0; r + 20 <= len; r += 20) {
                put_i32(o, rd_u16(p + r)), put_i32(o, rd_i16(p + r + 2));
                put_i32(o, rd_i32(p + r + 4)), put_i32(o, rd_u16(p + r + 8));
                put_i32(o, rd_u16(p + r + 10));
                put(o, p + r + 12, 4);
                put_i32(o, rd_i32(p + r + 16));
            }
            break;
        case L_CLIP:
            for (int r = 0; r + 8 <= len; r += 8) {
                put_i32(o, rd_i32(p + r));
                put_i32(o, rd_i16(p + r + 4)), put_i32(o, rd_i16(p + r + 6));
            }
            break;
        case L_LEAFS:
            for (int r = 0; r + 28 <= len; r += 28) {
                put_i32(o, rd_i32(p + r)), put_i32(o, rd_i32(p + r + 4));
                BOUNDS(p + r + 8)
                put_i32(o, rd_u16(p + r + 20)), put_i32(o, rd_u16(p + r + 22));
                put(o, p + r + 24, 4);
            }
            break;
        case L_MARKS:
            for (int r = 0; r + 2 <= len; r += 2) put_i32(o, rd_u16(p + r));
            break;
        case L_EDGES:
            for (int r = 0; r + 4 <= len; r += 4) put_i32(o, rd_u16(p + r)), put_i32(o, rd_u16(p + r + 2));
            break;
        default:
            put(o, p, (size_t)len);
        }
#undef BOUNDS
    }
    put(out, bsp2 ? "BSP2" : "2PSB", 4);
    size_t pos = 4 + NUM_LUMPS * 8;
    for (int i = 0; i < NUM_LUMPS; i++) {
        put_i32(out, (int32_t)pos), put_i32(out, (int32_t)L[i].len);
        pos += (L[i].len + 3) & ~(size_t)3;
    }
    for (int i = 0; i < NUM_LUMPS; i++) {
        put(out, L[i].d, L[i].len);
        pad4(out);
        free(L[i].d);
    }
    return 0;
}

/* ---- PAK, MDL, SPR -------------------------------------------------------- */

void ew_seed_pak(ew_seed_buf *out, const uint8_t *room, size_t room_len, const uint8_t palette[768]) {
    static const char note[] = "edgewise fuzz seed\n";
    const struct { const char *name; const void *d; size_t n; } files[] = {
        {"maps/room.bsp", room, room_len},
        {"gfx/palette.lmp", palette, 768},
        {"readme.txt", note, sizeof note - 1},
    };
    size_t pos = 12;
    for (int i = 0; i < 3; i++) pos += files[i].n;
    put(out, "PACK", 4);
    put_i32(out, (int32_t)pos), put_i32(out, 3 * 64);
    for (int i = 0; i < 3; i++) put(out, files[i].d, files[i].n);
    pos = 12;
    for (int i = 0; i < 3; i++) {
        put_str(out, files[i].name, 56);
        put_i32(out, (int32_t)pos), put_i32(out, (int32_t)files[i].n);
        pos += files[i].n;
    }
}

/* A tetrahedron: 4 vertices, 4 triangles; skins 8x8 (one single, one
 * group of two), frames: one single, one group of two. */
void ew_seed_mdl(ew_seed_buf *b) {
    put(b, "IDPO", 4);
    put_i32(b, 6);
    for (int k = 0; k < 3; k++) put_f32(b, 0.25f);   /* scale */
    for (int k = 0; k < 3; k++) put_f32(b, -16.0f);  /* origin */
    put_f32(b, 24.0f);                               /* bounding radius */
    for (int k = 0; k < 3; k++) put_f32(b, k == 2 ? 8.0f : 0.0f);
    put_i32(b, 2), put_i32(b, 8), put_i32(b, 8);     /* skins, skin size */
    put_i32(b, 4), put_i32(b, 4), put_i32(b, 2);     /* verts, tris, frames */
    put_i32(b, 0), put_i32(b, 0), put_f32(b, 1.0f);  /* synctype, flags, size */
    put_i32(b, 0);
    for (int i = 0; i < 64; i++) put_u8(b, i * 3);
    put_i32(b, 1), put_i32(b, 2), put_f32(b, 0.1f), put_f32(b, 0.2f);
    for (int i = 0; i < 128; i++) put_u8(b, 255 - i);
    static const int st[4][3] = {{0, 0, 0}, {0x20, 7, 0}, {0, 0, 7}, {0, 7, 7}};
    for (int i = 0; i < 4; i++) put_i32(b, st[i][0]), put_i32(b, st[i][1]), put_i32(b, st[i][2]);
    static const int tri[4][4] = {{1, 0, 1, 2}, {0, 0, 3, 1}, {1, 1, 3, 2}, {0, 2, 3, 0}};
    for (int i = 0; i < 4; i++)
        for (int k = 0; k < 4; k++) put_i32(b, tri[i][k]);
    static const uint8_t vert[4][4] = {{0, 0, 0, 0}, {128, 0, 0, 1}, {0, 128, 0, 2}, {0, 0, 128, 3}};
    for (int fr = 0; fr < 3; fr++) {
        if (fr == 0) put_i32(b, 0);
        if (fr == 1) {
            put_i32(b, 1), put_i32(b, 2);
            put(b, "\0\0\0\0", 4), put(b, "\x80\x80\x80\0", 4);
            put_f32(b, 0.1f), put_f32(b, 0.2f);
        }
        put(b, "\0\0\0\0", 4), put(b, "\x80\x80\x80\0", 4);
        put_str(b, fr == 0 ? "stand" : fr == 1 ? "run1" : "run2", 16);
        for (int i = 0; i < 4; i++)
            for (int k = 0; k < 4; k++) put_u8(b, k < 3 ? (vert[i][k] + fr * 16) & 255 : vert[i][3]);
    }
}

static void spr_frame(ew_seed_buf *b, int w, int h, int seed) {
    put_i32(b, -w / 2), put_i32(b, h / 2), put_i32(b, w), put_i32(b, h);
    for (int i = 0; i < w * h; i++) put_u8(b, (i * 5 + seed) % 256 == 255 ? 0 : (i * 5 + seed) % 256);
}

void ew_seed_spr(ew_seed_buf *b) {
    put(b, "IDSP", 4);
    put_i32(b, 1), put_i32(b, 2), put_f32(b, 8.0f);  /* version, parallel, radius */
    put_i32(b, 8), put_i32(b, 8), put_i32(b, 2);     /* max size, frames */
    put_f32(b, 0.0f), put_i32(b, 0);                 /* beam length, synctype */
    put_i32(b, 0);
    spr_frame(b, 8, 8, 1);
    put_i32(b, 1), put_i32(b, 2), put_f32(b, 0.1f), put_f32(b, 0.2f);
    spr_frame(b, 4, 4, 2);
    spr_frame(b, 8, 4, 3);
}


/* ---- a demo ----------------------------------------------------------------- */

typedef struct demo_w {
    ew_seed_buf *b;
    int proto;
    unsigned flags;
    size_t block;
} demo_w;

static void dm_coord(demo_w *w, float v) {
    if (w->proto == 999 && (w->flags & 0x10)) put_f32(w->b, v);
    else if (w->proto == 999 && (w->flags & 0x80)) put_i32(w->b, (int32_t)(v * 16));
    else if (w->proto == 999 && (w->flags & 0x08)) put_u16(w->b, (int)v), put_u8(w->b, 0);
    else put_u16(w->b, (int)(v * 8) & 0xffff);
}
static void dm_angle(demo_w *w, float v) {
    if (w->proto == 999 && (w->flags & 0x04)) put_f32(w->b, v);
    else if (w->proto == 999 && (w->flags & 0x02)) put_u16(w->b, (int)(v * 65536 / 360) & 0xffff);
    else put_u8(w->b, (int)(v * 256 / 360) & 255);
}
static void dm_begin(demo_w *w, float yaw) {
    w->block = w->b->len;
    put_i32(w->b, 0), put_f32(w->b, 0), put_f32(w->b, yaw), put_f32(w->b, 0);
}
static void dm_end(demo_w *w) {
    uint32_t len = (uint32_t)(w->b->len - w->block - 16);
    for (int k = 0; k < 4; k++) w->b->d[w->block + (size_t)k] = (uint8_t)(len >> (8 * k));
}
static void dm_str(ew_seed_buf *b, const char *s) { put(b, s, strlen(s) + 1); }

void ew_seed_demo(ew_seed_buf *b, int proto, unsigned flags) {
    demo_w w = {b, proto, flags, 0};
    put(b, "-1\n", 3);
    dm_begin(&w, 0);
    put_u8(b, 11), put_i32(b, proto);
    if (proto == 999) put_i32(b, (int32_t)flags);
    put_u8(b, 1), put_u8(b, 0), dm_str(b, "seed");
    dm_str(b, "maps/room.bsp"), dm_str(b, "*1"), dm_str(b, "progs/player.mdl"), dm_str(b, "");
    dm_str(b, "misc/null.wav"), dm_str(b, "");
    put_u8(b, 5), put_u16(b, 1);
    put_u8(b, 12), put_u8(b, 1), dm_str(b, "mmnmmommommnonmmonqnmmo");
    put_u8(b, 22), put_u16(b, 2), put_u8(b, 2), put_u8(b, 0), put_u8(b, 0), put_u8(b, 0);
    for (int k = 0; k < 3; k++) dm_coord(&w, 0), dm_angle(&w, 0);
    put_u8(b, 20), put_u8(b, 3), put_u8(b, 0), put_u8(b, 0), put_u8(b, 0);
    for (int k = 0; k < 3; k++) dm_coord(&w, 32), dm_angle(&w, 45);
    put_u8(b, 25), put_u8(b, 2);
    dm_end(&w);
    for (int i = 0; i < 4; i++) {
        dm_begin(&w, (float)i * 10);
        put_u8(b, 7), put_f32(b, 1.0f + 0.1f * (float)i);
        /* the player: origin, angles, frame */
        put_u8(b, 0x80 | 0x01 | 0x02 | 0x04 | 0x08 | 0x10 | 0x40);
        put_u8(b, 0x01 | 0x02 | 0x04 | (proto != 15 ? 0x80 : 0));  /* angle1, angle3, model; extend1 */
        if (proto != 15) put_u8(b, 0x01 | 0x08);  /* alpha, lerpfinish */
        put_u8(b, 1), put_u8(b, 3), put_u8(b, i);
        dm_coord(&w, 16.0f * (float)i), dm_angle(&w, 0), dm_coord(&w, 8), dm_angle(&w, 90), dm_coord(&w, 24),
            dm_angle(&w, 0);
        if (proto != 15) put_u8(b, 200), put_u8(b, 25);
        put_u8(b, 0x80 | 0x02), put_u8(b, 2), dm_coord(&w, 64);  /* the door */
        put_u8(b, 15), put_u16(b, 1 | (1 << 12) | (1 << 14)), put_u8(b, 22), put_i32(b, 1), put_u8(b, 0),
            put_u8(b, 3), put_u16(b, 100);
        for (int k = 0; k < 6; k++) put_u8(b, 1);
        put_u8(b, 23), put_u8(b, i == 3 ? 5 : 3);
        if (i == 3) put_u16(b, 1), dm_coord(&w, 0), dm_coord(&w, 0), dm_coord(&w, 0);
        dm_coord(&w, 8), dm_coord(&w, 8), dm_coord(&w, 8);
        put_u8(b, 18), dm_coord(&w, 4), dm_coord(&w, 4), dm_coord(&w, 4);
        put_u8(b, 0), put_u8(b, 0), put_u8(b, 16), put_u8(b, 20), put_u8(b, 73);
        dm_end(&w);
    }
    dm_begin(&w, 0);
    put_u8(b, 30), put_u8(b, 2);
    dm_end(&w);
}
