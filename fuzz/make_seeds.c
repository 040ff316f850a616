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
 * make_seeds OUTDIR MAP.bsp...: also converts those BSP29 maps (the real
 * ones in ../shared, read at run time) to BSP2 in OUTDIR/bsp2-extra, extra
 * seeds for the BSP2 target.
 * The room is small on purpose: the fuzzer mutates it thousands of times
 * a second, and every structure a renderer meets is in it (sky, liquid,
 * fence, animated and missing textures, two light styles, a PVS row, both
 * plane sides, shared edges).
 */
#define _POSIX_C_SOURCE 200809L
#include "edgewise.h"
#include "mapgen.h"
#include "seed_files.h"
#include "fuzz_targets.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

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
        fprintf(stderr, "usage: make_seeds OUTDIR [BSP29 MAP...]\n");
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

    for (int i = 2; i < argc; i++) {
        uint8_t *d;
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

    free(b.d), free(room.d), free(conv.d), free(bi);
    return 0;
}
