/* Everything one map needs: the BSP, the palette and the colormap, from a
 * .bsp path or by name from a game directory.  (The built-in map's are
 * made above asset/, in src/builtin.c: the map compiler is not asset/'s.) */
#define _POSIX_C_SOURCE 200809L
#include "ew_util.h"
#include "ew_world.h"
#include "asset/lightdata.h"

#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>

static int ends_with_bsp(const char *s) {
    size_t n = strlen(s);
    if (n < 4) return 0;
    const char *e = s + n - 4;
    return e[0] == '.' && (e[1] | 32) == 'b' && (e[2] | 32) == 's' && (e[3] | 32) == 'p';
}

static int is_file(const char *path) {
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

typedef int (*lmp_parse)(const uint8_t *, size_t, const char *, uint8_t *, ew_error *);

/* Reads one .lmp from the game directory (fs) or from a plain path. */
static int load_lmp(const ew_fs *fs, const char *name, lmp_parse parse, uint8_t *out,
                    ew_error *err) {
    uint8_t *data;
    size_t size;
    char where[1200];
    snprintf(where, sizeof where, "%s", name);
    int rc = fs ? ew_fs_load(fs, name, &data, &size, err) : ew_read_file(name, &data, &size, err);
    if (rc == 0 && fs) ew_fs_where(fs, name, where, sizeof where);
    if (rc == 0) rc = parse(data, size, where, out, err);
    free(data);
    return rc;
}

static int parse_palette(const uint8_t *d, size_t s, const char *f, uint8_t *out, ew_error *e) {
    return ew_palette_parse(d, s, f, out, e);
}
static int parse_colormap(const uint8_t *d, size_t s, const char *f, uint8_t *out, ew_error *e) {
    return ew_colormap_parse(d, s, f, out, e);
}

/* maps/NAME.lit beside the map: next to a .bsp path (NAME.bsp -> NAME.lit),
 * or in the game directory the .bsp came from.  Missing: nothing to do;
 * unreadable or malformed: a world warning, the light stays monochrome. */
static void attach_lit(ew_world *w, const ew_fs *fs, const char *map, int direct) {
    char lit[1100];
    uint8_t *data = NULL;
    size_t size = 0;
    ew_error err = {""};
    int rc;
    if (direct) {
        snprintf(lit, sizeof lit, "%s", map);
        char *slash = strrchr(lit, '/'), *dot = strrchr(lit, '.');
        if (dot && (!slash || dot > slash)) *dot = '\0';
        size_t n = strlen(lit);
        if (n + 5 > sizeof lit) return;
        memcpy(lit + n, ".lit", 5);
        if (!is_file(lit)) return;
        rc = ew_read_file(lit, &data, &size, &err);
    } else {
        snprintf(lit, sizeof lit, "maps/%s.lit", map);
        if (!ew_fs_exists(fs, lit)) return;
        rc = ew_fs_load(fs, lit, &data, &size, &err);
    }
    if (rc != 0)
        ew_warn(&w->warnings, &w->nwarnings, "%s: cannot read (%s); coloured light ignored", lit, err.msg);
    else
        ew_world_attach_lit(w, data, size, lit);
    free(data);
}

ew_assets *ew_assets_create(const char *map, const char *data_dir, ew_error *err) {
    ew_assets *out = calloc(1, sizeof *out);
    if (!out) {
        ew_fail(err, "%s: out of memory", map);
        return NULL;
    }
    ew_fs *fs = NULL;
    uint8_t *bsp = NULL;
    size_t bsp_size = 0;
    char bsp_name[1024];
    int direct = ends_with_bsp(map) || is_file(map);

    if (direct) {
        snprintf(bsp_name, sizeof bsp_name, "%s", map);
        if (ew_read_file(map, &bsp, &bsp_size, err) != 0) goto fail;
    } else {
        if (!data_dir || !*data_dir) {
            ew_fail(err, "%s: not a .bsp file and no --data directory given", map);
            goto fail;
        }
        snprintf(bsp_name, sizeof bsp_name, "maps/%s.bsp", map);
    }
    if (data_dir && *data_dir && !(fs = ew_fs_create(data_dir, err))) goto fail;
    if (!direct && ew_fs_load(fs, bsp_name, &bsp, &bsp_size, err) != 0) goto fail;

    /* Errors name the file as found: the pak and the path inside it. */
    char where[1200];
    snprintf(where, sizeof where, "%s", bsp_name);
    if (!direct) ew_fs_where(fs, bsp_name, where, sizeof where);
    if (!(out->world = ew_world_create(bsp, bsp_size, where, err))) goto fail;
    free(bsp);
    bsp = NULL;
    const char *base = strrchr(bsp_name, '/');
    base = base ? base + 1 : bsp_name;
    size_t n = strlen(base);
    if (n >= sizeof out->world->name) n = sizeof out->world->name - 1;
    memcpy(out->world->name, base, n);
    out->world->name[n] = '\0';

    attach_lit(out->world, fs, map, direct);

    if (fs) {
        if (load_lmp(fs, "gfx/palette.lmp", parse_palette, out->palette, err) != 0 ||
            load_lmp(fs, "gfx/colormap.lmp", parse_colormap, out->colormap, err) != 0)
            goto fail;
    } else {
        /* A bare .bsp: the gfx/ folder beside its maps/ folder. */
        char dir[1024], path[1100];
        snprintf(dir, sizeof dir, "%s", map);
        char *slash = strrchr(dir, '/');
        if (slash)
            *slash = '\0';
        else
            strcpy(dir, ".");
        snprintf(path, sizeof path, "%s/../gfx/palette.lmp", dir);
        if (load_lmp(NULL, path, parse_palette, out->palette, err) != 0) goto fail;
        snprintf(path, sizeof path, "%s/../gfx/colormap.lmp", dir);
        if (load_lmp(NULL, path, parse_colormap, out->colormap, err) != 0) goto fail;
    }
    ew_fs_destroy(fs);
    return out;
fail:
    free(bsp);
    ew_fs_destroy(fs);
    ew_assets_destroy(out);
    return NULL;
}

void ew_assets_destroy(ew_assets *a) {
    if (!a) return;
    ew_world_destroy(a->world);
    free(a);
}
