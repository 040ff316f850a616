/*
 * make_seeds OUTDIR: writes the seed corpora of the fuzz targets, all made
 * here (nothing copied from game data):
 *   OUTDIR/bsp29   a tiny valid BSP29 room and the built-in scene
 *   OUTDIR/bsp2    both converted to BSP2 and to 2PSB
 *   OUTDIR/render  the room (all three formats) and the built-in scene
 *   OUTDIR/pak     a tiny PAK holding the room, a palette and a text file
 *   OUTDIR/lmp     the built-in palette and colormap
 *   OUTDIR/mdl     a tiny alias model (a skin group and a frame group)
 *   OUTDIR/spr     a tiny sprite (a single frame and a frame group)
 *   OUTDIR/demo    small demos in protocols 15, 666 and 999 (three flag sets)
 * make_seeds OUTDIR MAP.bsp...: also converts those BSP29 maps (the real
 * ones in ../shared, read at run time) to BSP2 in OUTDIR/bsp2-extra, extra
 * seeds for the BSP2 target.
 * make_seeds OUTDIR ... --real FILE...: real light data (the ericw maps of
 * ../shared, read at run time, never kept in the repository) made into
 * seeds of the two light targets:
 *   FILE.lit  its header and payload, cut (or repeated) to the built-in
 *             map's light size: OUTDIR/lit/real-FILE.lit
 *   FILE.bsp  its BSPX lumps (RGBLIGHTING, LMSHIFT, LMOFFSET, DECOUPLED_LM,
 *             LIGHTGRID_OCTREE...) laid out after each of the four base
 *             maps, per-face lumps fitted to the base's face count and the
 *             light lumps to its light size: OUTDIR/bspx/real-FILE-vN.bspx
 * The room is small on purpose: the fuzzer mutates it thousands of times
 * a second, and every structure a renderer meets is in it (sky, liquid,
 * fence, animated and missing textures, two light styles, a PVS row, both
 * plane sides, shared edges).
 */
#define _POSIX_C_SOURCE 200809L
#include "edgewise.h"
#include "ew_world.h"
#include "mapgen.h"
#include "seed_files.h"
#include "fuzz_targets.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* Where the real data goes in a fitted seed: n bytes of src (len of them),
 * cut short or repeated whole units; len 0 gives zeros. */
static void fit(ew_seed_buf *b, const uint8_t *src, size_t len, size_t n) {
    size_t at = b->len;
    if (b->len + n > b->cap) {
        size_t cap = b->cap ? b->cap : 1024;
        while (cap < b->len + n) cap *= 2;
        uint8_t *d = realloc(b->d, cap);
        if (!d) exit(1);
        b->d = d, b->cap = cap;
    }
    for (size_t i = 0; i < n; i++) b->d[at + i] = len ? src[i % len] : 0;
    b->len += n;
}

static uint32_t rd32(const uint8_t *p) {
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
static void wr32(uint8_t *p, uint32_t v) {
    for (int i = 0; i < 4; i++) p[i] = (uint8_t)(v >> (8 * i));
}

/* Bytes the base map wants of a BSPX lump (0: keep the real size, up to
 * a cap: the lumps no reader here looks inside). */
static size_t bspx_want(const char *name, int numfaces, long lightsize, size_t real) {
    static const struct { const char *name; int per_face; } per_face[] = {
        {"LMSHIFT", 1}, {"LMOFFSET", 4}, {"LMSTYLE", 4}, {"LMSTYLE16", 8}, {"DECOUPLED_LM", 40},
    };
    for (size_t i = 0; i < sizeof per_face / sizeof per_face[0]; i++)
        if (!strcmp(name, per_face[i].name)) return (size_t)numfaces * (size_t)per_face[i].per_face;
    if (!strcmp(name, "RGBLIGHTING") || !strcmp(name, "LIGHTINGDIR")) return 3 * (size_t)lightsize;
    return real < 8192 ? real : 8192;
}

/* The BSPX part of real map `bsp` re-laid after base map v (whose standard
 * lumps end at cut): the seed's first byte is v.  -1 if it has no BSPX. */
static int real_bspx_seed(const uint8_t *bsp, size_t size, int v, size_t cut, int numfaces, long lightsize,
                          ew_seed_buf *out) {
    size_t end = ew_fuzz_bspx_cut(bsp, size), pos = (end + 3) & ~(size_t)3;
    if (size < 64 || pos + 8 > size || memcmp(bsp + pos, "BSPX", 4) != 0) return -1;
    uint32_t n = rd32(bsp + pos + 4);
    if (n == 0 || n > 64 || pos + 8 + 32 * (size_t)n > size) return -1;
    out->len = 0;
    uint8_t v8 = (uint8_t)v;
    fit(out, &v8, 1, 1);
    /* file offset of seed byte i (i >= 1) is cut + i - 1 */
    size_t dir = (cut + 3) & ~(size_t)3;
    fit(out, NULL, 0, dir - cut);
    fit(out, (const uint8_t *)"BSPX", 4, 4);
    uint8_t cnt[4];
    wr32(cnt, n);
    fit(out, cnt, 4, 4);
    size_t entries = out->len;
    fit(out, NULL, 0, 32 * (size_t)n);
    for (uint32_t i = 0; i < n; i++) {
        const uint8_t *e = bsp + pos + 8 + 32 * i;
        char name[25] = {0};
        memcpy(name, e, 24);
        uint32_t ofs = rd32(e + 24), len = rd32(e + 28);
        if ((uint64_t)ofs + len > size) len = 0;
        while ((out->len - 1 + cut) % 4) fit(out, NULL, 0, 1);
        size_t want = bspx_want(name, numfaces, lightsize, len);
        uint8_t *ent = out->d + entries + 32 * i;
        memcpy(ent, e, 24);
        wr32(ent + 24, (uint32_t)(out->len - 1 + cut));
        wr32(ent + 28, (uint32_t)want);
        fit(out, bsp + ofs, len, want);
    }
    return (int)n;
}

static void write_file(const char *dir, const char *sub, const char *name, const void *d, size_t n) {
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, sub);
    if (mkdir(path, 0755) != 0 && errno != EEXIST) {
        fprintf(stderr, "make_seeds: %s: %s\n", path, strerror(errno));
        exit(1);
    }
    snprintf(path, sizeof path, "%s/%s/%s", dir, sub, name);
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(d, 1, n, f) != n || fclose(f) != 0) {
        fprintf(stderr, "make_seeds: cannot write %s\n", path);
        exit(1);
    }
}

int main(int argc, char **argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: make_seeds OUTDIR [BSP29 MAP...] [--real FILE.lit|FILE.bsp...]\n");
        return 2;
    }
    const char *dir = argv[1];
    if (mkdir(dir, 0755) != 0 && errno != EEXIST) {
        fprintf(stderr, "make_seeds: %s: %s\n", dir, strerror(errno));
        return 1;
    }
    ew_seed_buf room = {0}, conv = {0};
    ew_seed_room(&room);

    /* Every seed must load, or the fuzzer starts from rejected inputs. */
    ew_error err = {""};
    ew_world *w = ew_world_create(room.d, room.len, "room.bsp", &err);
    if (!w) {
        fprintf(stderr, "make_seeds: the room does not load: %s\n", err.msg);
        return 1;
    }
    ew_world_destroy(w);
    write_file(dir, "bsp29", "room.bsp", room.d, room.len);
    write_file(dir, "render", "room.bsp", room.d, room.len);
    for (int bsp2 = 0; bsp2 < 2; bsp2++) {
        conv.len = 0;
        if (ew_seed_convert29(room.d, room.len, bsp2, &conv) != 0 ||
            !(w = ew_world_create(conv.d, conv.len, "room2.bsp", &err))) {
            fprintf(stderr, "make_seeds: room conversion failed: %s\n", err.msg);
            return 1;
        }
        ew_world_destroy(w);
        const char *name = bsp2 ? "room_bsp2.bsp" : "room_2psb.bsp";
        write_file(dir, "bsp2", name, conv.d, conv.len);
        write_file(dir, "render", name, conv.d, conv.len);
    }

    uint8_t *bi = NULL, palette[768], colormap[EW_COLORMAP_SIZE];
    size_t bi_size = 0;
    if (ew_builtin_generate(&bi, &bi_size, palette, colormap, &err) != 0) {
        fprintf(stderr, "make_seeds: built-in scene: %s\n", err.msg);
        return 1;
    }
    write_file(dir, "bsp29", "builtin.bsp", bi, bi_size);
    write_file(dir, "render", "builtin.bsp", bi, bi_size);
    for (int bsp2 = 0; bsp2 < 2; bsp2++) {
        conv.len = 0;
        if (ew_seed_convert29(bi, bi_size, bsp2, &conv) == 0)
            write_file(dir, "bsp2", bsp2 ? "builtin_bsp2.bsp" : "builtin_2psb.bsp", conv.d, conv.len);
    }
    write_file(dir, "lmp", "palette.lmp", palette, sizeof palette);
    write_file(dir, "lmp", "colormap.lmp", colormap, sizeof colormap);

    ew_seed_buf b = {0};
    ew_seed_pak(&b, room.d, room.len, palette);
    write_file(dir, "pak", "tiny.pak", b.d, b.len);
    b.len = 0;
    ew_seed_mdl(&b);
    write_file(dir, "mdl", "tetra.mdl", b.d, b.len);
    b.len = 0;
    ew_seed_spr(&b);
    write_file(dir, "spr", "tiny.spr", b.d, b.len);
    static const struct { int proto; unsigned flags; const char *name; } demos[] = {
        {15, 0, "nq.dem"}, {666, 0, "fitz.dem"}, {999, 0x82, "rmq_0x82.dem"}, {999, 0x10, "rmq_float.dem"},
        {999, 0x0c, "rmq_24bit.dem"}};
    for (size_t i = 0; i < sizeof demos / sizeof demos[0]; i++) {
        b.len = 0;
        ew_seed_demo(&b, demos[i].proto, demos[i].flags);
        if (ew_fuzz_demo(b.d, b.len) != 0) {
            fprintf(stderr, "make_seeds: demo seed %s rejected\n", demos[i].name);
            return 1;
        }
        write_file(dir, "demo", demos[i].name, b.d, b.len);
    }

    /* .lit: the built-in map's white and tinted light */
    {
        static const float tint[3 * EW_MAPGEN_MAX_LIGHTS] = {1, 0.3f, 0.2f, 0.2f, 0.4f, 1, 1, 1, 0.2f, 0.3f, 1, 0.3f,
                                                             1, 0.6f, 0.3f, 0.5f, 0.5f, 1, 1, 0.2f, 1, 0.8f, 0.8f, 0.8f};
        for (int k = 0; k < 2; k++) {
            ew_mapgen_options o = {.lit = 1, .light_tint = k ? tint : NULL};
            uint8_t *m = NULL, *lit = NULL;
            size_t mn = 0, ln = 0;
            if (ew_builtin_generate_ex(&o, &m, &mn, palette, colormap, &lit, &ln, &err) != 0 || ew_fuzz_lit(lit, ln) != 0) {
                fprintf(stderr, "make_seeds: .lit seed: %s\n", err.msg);
                return 1;
            }
            write_file(dir, "lit", k ? "tinted.lit" : "white.lit", lit, ln);
            free(m), free(lit);
        }
    }
    /* BSPX: a base-map byte and the part after the standard lumps */
    for (int v = 0; v < 4; v++) {
        ew_mapgen_options o;
        ew_fuzz_bspx_options(v, &o);
        uint8_t *m = NULL;
        size_t mn = 0;
        if (ew_builtin_generate_ex(&o, &m, &mn, palette, colormap, NULL, NULL, &err) != 0) {
            fprintf(stderr, "make_seeds: BSPX seed: %s\n", err.msg);
            return 1;
        }
        size_t cut = ew_fuzz_bspx_cut(m, mn);
        uint8_t *seed = malloc(mn - cut + 1);
        seed[0] = (uint8_t)v;
        memcpy(seed + 1, m + cut, mn - cut);
        if (ew_fuzz_bspx(seed, mn - cut + 1) != 0) {
            fprintf(stderr, "make_seeds: BSPX seed %d does not load\n", v);
            return 1;
        }
        static const char *const names[4] = {"rgb.bspx", "shift3.bspx", "shift5.bspx", "decoupled.bspx"};
        write_file(dir, "bspx", names[v], seed, mn - cut + 1);
        free(seed), free(m);
    }

    /* Real light data (--real FILE...): seeds of the .lit and BSPX targets */
    int first_real = argc;
    for (int i = 2; i < argc; i++)
        if (!strcmp(argv[i], "--real")) {
            first_real = i;
            break;
        }
    /* the four base maps and the built-in .lit size, made once (slow under
     * the sanitizers) */
    struct { uint8_t *m; size_t n, cut; int numfaces; long lightsize; } bases[4] = {{0}};
    size_t lit_size = 0;
    if (first_real + 1 < argc) {
        for (int v = 0; v < 4; v++) {
            ew_mapgen_options o;
            ew_fuzz_bspx_options(v, &o);
            ew_world *bw = NULL;
            if (ew_builtin_generate_ex(&o, &bases[v].m, &bases[v].n, palette, colormap, NULL, NULL, &err) != 0 ||
                !(bw = ew_world_create(bases[v].m, bases[v].n, "base.bsp", &err))) {
                fprintf(stderr, "make_seeds: BSPX base map %d: %s\n", v, err.msg);
                return 1;
            }
            bases[v].cut = ew_fuzz_bspx_cut(bases[v].m, bases[v].n);
            bases[v].numfaces = bw->numfaces, bases[v].lightsize = bw->lightsize;
            ew_world_destroy(bw);
        }
        ew_mapgen_options o = {.lit = 1};
        uint8_t *m = NULL, *lit = NULL;
        size_t mn = 0;
        if (ew_builtin_generate_ex(&o, &m, &mn, palette, colormap, &lit, &lit_size, &err) != 0) {
            fprintf(stderr, "make_seeds: built-in .lit: %s\n", err.msg);
            return 1;
        }
        free(m), free(lit);
    }
    for (int i = first_real + 1; i < argc; i++) {
        uint8_t *d = NULL;
        size_t n;
        const char *base = strrchr(argv[i], '/');
        base = base ? base + 1 : argv[i];
        size_t blen = strlen(base);
        if (ew_read_file(argv[i], &d, &n, &err) != 0) {
            fprintf(stderr, "make_seeds: %s\n", err.msg);
            continue;
        }
        char name[300];
        if (blen > 4 && !strcmp(base + blen - 4, ".lit")) {
            if (n > 8) {
                b.len = 0;
                fit(&b, d, 8, 8);
                fit(&b, d + 8, n - 8, lit_size - 8);
                snprintf(name, sizeof name, "real-%.200s", base);
                if (ew_fuzz_lit(b.d, b.len) != 0) fprintf(stderr, "make_seeds: %s: fitted .lit not accepted\n", argv[i]);
                write_file(dir, "lit", name, b.d, b.len);
            }
        } else {
            int lumps = -1;
            for (int v = 0; v < 4; v++) {
                lumps = real_bspx_seed(d, n, v, bases[v].cut, bases[v].numfaces, bases[v].lightsize, &b);
                if (lumps < 0) break;
                snprintf(name, sizeof name, "real-%.200s-v%d.bspx", base, v);
                ew_fuzz_bspx(b.d, b.len);  /* accepted or not, it must return */
                write_file(dir, "bspx", name, b.d, b.len);
            }
            if (lumps < 0) fprintf(stderr, "make_seeds: %s: no BSPX directory, no seed\n", argv[i]);
        }
        free(d);
    }

    for (int i = 2; i < first_real; i++) {
        uint8_t *d = NULL;
        size_t n;
        const char *base = strrchr(argv[i], '/');
        base = base ? base + 1 : argv[i];
        char name[300];
        snprintf(name, sizeof name, "%.280s_bsp2.bsp", base);
        conv.len = 0;
        if (ew_read_file(argv[i], &d, &n, &err) != 0 || ew_seed_convert29(d, n, 1, &conv) != 0) {
            fprintf(stderr, "make_seeds: %s: not converted (%s)\n", argv[i], err.msg);
        } else {
            write_file(dir, "bsp2-extra", name, conv.d, conv.len);
        }
        free(d);
    }

    for (int v = 0; v < 4; v++) free(bases[v].m);
    free(b.d), free(room.d), free(conv.d), free(bi);
    return 0;
}
