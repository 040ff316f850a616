/*
 * BSP loader: version 29, BSP2 and 2PSB, all into the 32-bit structures of
 * ew_world.h.  Every count, offset and index is checked against the file
 * here, so the renderer can trust the world without checks of its own.
 * Reads go through the little-endian helpers only after a bounds check.
 */
#include "ew_util.h"
#include "ew_world.h"
#include "asset/lightdata.h"
#include "light_entities.h"
#include "worldspawn.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

enum { FMT_29, FMT_BSP2, FMT_2PSB };

#define HEADER_SIZE (4 + EW_NUM_LUMPS * 8)
/* The renderer clips polygons in buffers of 256 vertices (EW_MAX_POLY in
 * world/view.h; clipping adds up to 4), so every face it is given fits;
 * Quake's own tools stop far below. */
#define MAX_FACE_EDGES 248
#define MAX_TEX_SIZE 4096
/* Light maps and surface caches are sized from the extents; Quake allows
 * 256 texels, modern compilers more, this bound keeps sizes sane. */
#define MAX_EXTENT EW_MAX_EXTENT
/* Vertices: far beyond any map (Quake's own stay within +-32768), close
 * enough that no product of two coordinates or of a coordinate and a unit
 * vector can overflow a float in the renderer's transforms. */
#define MAX_COORD 1.0e7f
/* Texture-space coordinates are converted to int; beyond this the map is
 * nonsense anyway (and the conversion would overflow). */
#define MAX_TEXCOORD 1.0e8f

static const char *const lump_names[EW_NUM_LUMPS] = {
    "entities", "planes",   "textures",  "vertexes",     "visibility",
    "nodes",    "texinfo",  "faces",     "lighting",     "clipnodes",
    "leafs",    "marksurfaces", "edges", "surfedges",    "models"};

/* Record size of each lump per format; 1 for byte lumps and the textures
 * lump (which has its own inner directory). */
static const int rec_size[3][EW_NUM_LUMPS] = {
    /*          ent pla tex ver vis nod  ti fac lit clp lea mrk edg sed mod */
    [FMT_29] = {1, 20, 1, 12, 1, 24, 40, 20, 1, 8, 28, 2, 4, 4, 64},
    [FMT_BSP2] = {1, 20, 1, 12, 1, 44, 40, 28, 1, 12, 44, 4, 8, 4, 64},
    [FMT_2PSB] = {1, 20, 1, 12, 1, 32, 40, 28, 1, 12, 32, 4, 8, 4, 64},
};

typedef struct ctx {
    const uint8_t *data;
    size_t         size;
    const char    *file;
    ew_error      *err;
    int            fmt;
    const uint8_t *lump[EW_NUM_LUMPS];
    int            len[EW_NUM_LUMPS];
    int            count[EW_NUM_LUMPS];
    /* a BSPX lump moves light maps (LMSHIFT, DECOUPLED_LM): a face whose
     * Quake-layout light map overruns the lump is kept unlit, not refused */
    int            light_moved;
} ctx;

/* "FILE: lump 'NAME': what" */
static int lump_fail(ctx *c, int lump, const char *fmt, ...) EW_PRINTF(3, 4);
static int lump_fail(ctx *c, int lump, const char *fmt, ...) {
    char what[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    return ew_fail(c->err, "%s: lump '%s': %s", c->file, lump_names[lump], what);
}

static void *alloc_array(ctx *c, int lump, int n, size_t elem) {
    void *p = calloc(n > 0 ? (size_t)n : 1, elem);
    if (!p) lump_fail(c, lump, "out of memory (%d records)", n);
    return p;
}

static int finite3(const float v[3]) {
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

/* ---- header ------------------------------------------------------------ */

static int read_header(ctx *c, ew_world *w) {
    if (c->size < HEADER_SIZE)
        return ew_fail(c->err, "%s: file too short for a BSP header (%zu bytes)", c->file, c->size);
    const uint8_t *d = c->data;
    if (ew_i32(d) == 29) {
        c->fmt = FMT_29;
        strcpy(w->version, "29");
    } else if (memcmp(d, "BSP2", 4) == 0) {
        c->fmt = FMT_BSP2;
        strcpy(w->version, "BSP2");
    } else if (memcmp(d, "2PSB", 4) == 0) {
        c->fmt = FMT_2PSB;
        strcpy(w->version, "2PSB");
    } else {
        int printable = 1;
        for (int i = 0; i < 4; i++)
            if (d[i] < 0x20 || d[i] > 0x7e) printable = 0;
        if (printable)
            return ew_fail(c->err, "%s: unsupported BSP version \"%.4s\" (expected 29, BSP2 or 2PSB)",
                           c->file, (const char *)d);
        return ew_fail(c->err, "%s: unsupported BSP version %d (expected 29, BSP2 or 2PSB)",
                       c->file, (int)ew_i32(d));
    }
    for (int i = 0; i < EW_NUM_LUMPS; i++) {
        int32_t ofs = ew_i32(d + 4 + 8 * i), len = ew_i32(d + 8 + 8 * i);
        int rs = rec_size[c->fmt][i];
        if (ofs < 0 || len < 0)
            return ew_fail(c->err, "%s: lump '%s' (index %d): negative offset %d or length %d",
                           c->file, lump_names[i], i, (int)ofs, (int)len);
        if ((uint64_t)ofs + (uint64_t)len > c->size)
            return ew_fail(c->err, "%s: lump '%s' (index %d): offset %d + length %d past end of file (%zu bytes)",
                           c->file, lump_names[i], i, (int)ofs, (int)len, c->size);
        if (len % rs != 0)
            return ew_fail(c->err, "%s: lump '%s' (index %d): length %d is not a multiple of the %d-byte record",
                           c->file, lump_names[i], i, (int)len, rs);
        c->lump[i] = d + ofs;
        c->len[i] = len;
        c->count[i] = len / rs;
        w->lumps[i].name = lump_names[i];
        w->lumps[i].offset = (uint32_t)ofs;
        w->lumps[i].length = (uint32_t)len;
        w->lumps[i].count = c->count[i];
    }
    return 0;
}

/* ---- simple lumps ------------------------------------------------------ */

static int load_planes(ctx *c, ew_world *w) {
    int n = c->count[EW_LUMP_PLANES];
    if (!(w->planes = alloc_array(c, EW_LUMP_PLANES, n, sizeof *w->planes))) return -1;
    w->numplanes = n;
    for (int i = 0; i < n; i++) {
        const uint8_t *p = c->lump[EW_LUMP_PLANES] + 20 * i;
        ew_plane *pl = &w->planes[i];
        for (int k = 0; k < 3; k++) pl->normal[k] = ew_f32(p + 4 * k);
        pl->dist = ew_f32(p + 12);
        pl->type = ew_i32(p + 16);
        if (!finite3(pl->normal) || !isfinite(pl->dist))
            return lump_fail(c, EW_LUMP_PLANES, "plane %d is not finite", i);
        /* Every reader takes normal . p - dist as a distance: a normal longer
         * than a unit (a finite 1e37 overflows those products to inf and
         * NaN) is not a plane a compiler writes.  Shorter ones are: real
         * maps hold all-zero planes (LibreQuake's b_exbox2, on a node and a
         * face), every point on them at distance 0. */
        double len2 = (double)pl->normal[0] * pl->normal[0] + (double)pl->normal[1] * pl->normal[1] +
                      (double)pl->normal[2] * pl->normal[2];
        if (!(len2 < 1.02))
            return lump_fail(c, EW_LUMP_PLANES, "plane %d: normal of length %g (at most 1)", i, sqrt(len2));
        if (pl->type < 0 || pl->type > 5)
            return lump_fail(c, EW_LUMP_PLANES, "plane %d has type %d (expected 0..5)", i, pl->type);
    }
    return 0;
}

static int load_vertexes(ctx *c, ew_world *w) {
    int n = c->count[EW_LUMP_VERTEXES];
    if (!(w->verts = alloc_array(c, EW_LUMP_VERTEXES, n, sizeof *w->verts))) return -1;
    w->numverts = n;
    for (int i = 0; i < n; i++) {
        const uint8_t *p = c->lump[EW_LUMP_VERTEXES] + 12 * i;
        for (int k = 0; k < 3; k++) w->verts[i][k] = ew_f32(p + 4 * k);
        if (!finite3(w->verts[i]))
            return lump_fail(c, EW_LUMP_VERTEXES, "vertex %d is not finite", i);
        for (int k = 0; k < 3; k++)
            if (fabsf(w->verts[i][k]) > MAX_COORD)
                return lump_fail(c, EW_LUMP_VERTEXES, "vertex %d: coordinate %g beyond +-%g", i,
                                 w->verts[i][k], MAX_COORD);
    }
    return 0;
}

static int load_edges(ctx *c, ew_world *w) {
    int n = c->count[EW_LUMP_EDGES];
    if (!(w->edges = alloc_array(c, EW_LUMP_EDGES, n, sizeof *w->edges))) return -1;
    w->numedges = n;
    for (int i = 0; i < n; i++) {
        for (int k = 0; k < 2; k++) {
            uint32_t v = c->fmt == FMT_29 ? ew_u16(c->lump[EW_LUMP_EDGES] + 4 * i + 2 * k)
                                          : ew_u32(c->lump[EW_LUMP_EDGES] + 8 * i + 4 * k);
            if (v >= (uint32_t)w->numverts)
                return lump_fail(c, EW_LUMP_EDGES, "edge %d uses vertex %u (only %d)", i, v,
                                 w->numverts);
            w->edges[i][k] = v;
        }
    }
    return 0;
}

static int load_surfedges(ctx *c, ew_world *w) {
    int n = c->count[EW_LUMP_SURFEDGES];
    if (!(w->surfedges = alloc_array(c, EW_LUMP_SURFEDGES, n, sizeof *w->surfedges))) return -1;
    if (!(w->surfverts = alloc_array(c, EW_LUMP_SURFEDGES, n, sizeof *w->surfverts))) return -1;
    w->numsurfedges = n;
    for (int i = 0; i < n; i++) {
        int32_t se = ew_i32(c->lump[EW_LUMP_SURFEDGES] + 4 * i);
        /* INT32_MIN has no positive counterpart */
        if (se == INT32_MIN || (se < 0 ? -se : se) >= w->numedges)
            return lump_fail(c, EW_LUMP_SURFEDGES, "surfedge %d uses edge %d (only %d)", i,
                             (int)se, w->numedges);
        w->surfedges[i] = se;
        w->surfverts[i] = (int)(se < 0 ? w->edges[-se][1] : w->edges[se][0]);
    }
    return 0;
}

/* Entities, lighting and visibility are plain bytes; empty lumps stay NULL
 * (the renderer treats a NULL visdata as "no PVS"). */
static int copy_bytes(ctx *c, int lump, uint8_t **out, int *n) {
    *n = c->len[lump];
    if (*n == 0) return 0;
    if (!(*out = malloc((size_t)*n))) return lump_fail(c, lump, "out of memory (%d bytes)", *n);
    memcpy(*out, c->lump[lump], (size_t)*n);
    return 0;
}

static int load_entities(ctx *c, ew_world *w) {
    int n = c->len[EW_LUMP_ENTITIES];
    /* The lump may or may not carry its own NUL; always add one. */
    if (!(w->entities = malloc((size_t)n + 1)))
        return lump_fail(c, EW_LUMP_ENTITIES, "out of memory (%d bytes)", n);
    memcpy(w->entities, c->lump[EW_LUMP_ENTITIES], (size_t)n);
    w->entities[n] = '\0';
    return 0;
}

/* ---- textures ---------------------------------------------------------- */

#define PLACEHOLDER_SIZE 16
#define PLACEHOLDER_BYTES (16 * 16 + 8 * 8 + 4 * 4 + 2 * 2)

static int texture_flags(const char *name) {
    if (ew_lower((unsigned char)name[0]) == 's' && ew_lower((unsigned char)name[1]) == 'k' &&
        ew_lower((unsigned char)name[2]) == 'y')
        return EW_SURF_SKY;
    if (name[0] == '*') return EW_SURF_TURB;
    if (name[0] == '{') return EW_SURF_FENCE;
    return 0;
}

/* Which liquid a '*' texture is, by its name, as the ports tell them apart
 * (for each liquid's worldspawn opacity): "*lava...", "*slime...",
 * "*tele..." in any case, any other '*' name is water. */
static int has_prefix(const char *name, const char *prefix) {
    for (; *prefix; name++, prefix++)
        if (ew_lower((unsigned char)*name) != *prefix) return 0;
    return 1;
}

static int liquid_kind(const char *name) {
    if (name[0] != '*') return EW_LIQUID_NONE;
    if (has_prefix(name + 1, "lava")) return EW_LIQUID_LAVA;
    if (has_prefix(name + 1, "slime")) return EW_LIQUID_SLIME;
    if (has_prefix(name + 1, "tele")) return EW_LIQUID_TELE;
    return EW_LIQUID_WATER;
}

/* Frame number of an animated name: 0..9 primary, 10..19 alternate
 * (+a..+j), -1 if the name does not animate. */
static int anim_frame(const char *name) {
    if (name[0] != '+') return -1;
    int ch = ew_lower((unsigned char)name[1]);
    if (ch >= '0' && ch <= '9') return ch - '0';
    if (ch >= 'a' && ch <= 'j') return 10 + ch - 'a';
    return -1;
}

/* Links the +0..+9 / +a..+j cycles.  Every texture of one base name is
 * handled at its first occurrence; a duplicate frame shares the fields of
 * the frame it duplicates. */
static int link_animations(ctx *c, ew_world *w, int n) {
    uint8_t *done = calloc(n > 0 ? (size_t)n : 1, 1);
    if (!done) return lump_fail(c, EW_LUMP_TEXTURES, "out of memory");
    int rc = 0;
    for (int i = 0; i < n && rc == 0; i++) {
        ew_texture *t = &w->textures[i];
        if (done[i] || anim_frame(t->name) < 0) continue;
        const char *base = t->name + 2;
        int frames[20], dups = 0;
        for (int k = 0; k < 20; k++) frames[k] = -1;
        for (int j = i; j < n; j++) {
            const ew_texture *u = &w->textures[j];
            int f = anim_frame(u->name);
            if (f < 0 || done[j] || !ew_same_name(u->name + 2, base)) continue;
            if (frames[f] < 0) {
                frames[f] = j;
                done[j] = 1;
            } else {
                dups = 1;
            }
        }
        int count[2] = {0, 0};
        for (int cyc = 0; cyc < 2; cyc++) {
            for (int k = 0; k < 10; k++)
                if (frames[cyc * 10 + k] >= 0) count[cyc] = k + 1;
            for (int k = 0; k < count[cyc]; k++) {
                if (frames[cyc * 10 + k] < 0) {
                    rc = lump_fail(c, EW_LUMP_TEXTURES,
                                   "animated texture '%s': frame '+%c%s' missing (cycle has %d frames)",
                                   t->name, cyc ? 'a' + k : '0' + k, base, count[cyc]);
                    break;
                }
            }
            if (rc) break;
        }
        if (rc) break;
        for (int cyc = 0; cyc < 2; cyc++) {
            for (int k = 0; k < count[cyc]; k++) {
                ew_texture *f = &w->textures[frames[cyc * 10 + k]];
                f->anim_total = count[cyc];
                f->anim_min = k;
                f->anim_max = k + 1;
                f->anim_next = frames[cyc * 10 + (k + 1) % count[cyc]];
                f->alternate_anims = count[!cyc] ? frames[!cyc * 10] : -1;
            }
        }
        if (!dups) continue;
        for (int j = i + 1; j < n; j++) {
            ew_texture *u = &w->textures[j];
            int f = anim_frame(u->name);
            if (f < 0 || done[j] || !ew_same_name(u->name + 2, base)) continue;
            const ew_texture *orig = &w->textures[frames[f]];
            u->anim_total = orig->anim_total;
            u->anim_min = orig->anim_min;
            u->anim_max = orig->anim_max;
            u->anim_next = orig->anim_next;
            u->alternate_anims = orig->alternate_anims;
            done[j] = 1;
        }
    }
    free(done);
    return rc;
}

static int load_textures(ctx *c, ew_world *w) {
    const uint8_t *L = c->lump[EW_LUMP_TEXTURES];
    int64_t len = c->len[EW_LUMP_TEXTURES];
    int n = 0;
    if (len > 0) {
        if (len < 4) return lump_fail(c, EW_LUMP_TEXTURES, "too short for a texture count (%d bytes)", (int)len);
        int32_t nm = ew_i32(L);
        if (nm < 0 || (int64_t)nm > (len - 4) / 4)
            return lump_fail(c, EW_LUMP_TEXTURES, "%d textures do not fit in %d bytes", (int)nm, (int)len);
        n = nm;
    }
    c->count[EW_LUMP_TEXTURES] = n;
    w->lumps[EW_LUMP_TEXTURES].count = n;

    /* n slots + the shared placeholder */
    if (!(w->textures = alloc_array(c, EW_LUMP_TEXTURES, n + 1, sizeof *w->textures))) return -1;
    w->numtextures = n + 1;

    /* Pass 1: names, sizes and bounds; how many pixel bytes to copy. */
    size_t total = PLACEHOLDER_BYTES;
    int32_t *ofs = alloc_array(c, EW_LUMP_TEXTURES, n, sizeof *ofs);
    if (!ofs) return -1;
    for (int i = 0; i < n; i++) {
        ew_texture *t = &w->textures[i];
        t->anim_next = t->alternate_anims = -1;
        int32_t o = ew_i32(L + 4 + 4 * i);
        ofs[i] = -1;
        if (o == -1) continue;  /* slot without data: missing */
        if (o < 0 || (int64_t)o + 40 > len) {
            free(ofs);
            return lump_fail(c, EW_LUMP_TEXTURES, "texture %d: miptex offset %d outside the lump (%d bytes)",
                             i, (int)o, (int)len);
        }
        const uint8_t *m = L + o;
        for (int k = 0; k < 15 && m[k]; k++) t->name[k] = (char)m[k];  /* 15 chars + NUL */
        uint32_t tw = ew_u32(m + 16), th = ew_u32(m + 20), mo[4];
        for (int k = 0; k < 4; k++) mo[k] = ew_u32(m + 24 + 4 * k);
        if (!mo[0] && !mo[1] && !mo[2] && !mo[3]) continue;  /* compiled without pixels */
        if (tw == 0 || th == 0 || tw > MAX_TEX_SIZE || th > MAX_TEX_SIZE || tw % 8 || th % 8) {
            free(ofs);
            return lump_fail(c, EW_LUMP_TEXTURES,
                             "texture %d ('%s'): bad size %ux%u (need multiples of 8, at most %d)",
                             i, t->name, tw, th, MAX_TEX_SIZE);
        }
        for (int k = 0; k < 4; k++) {
            uint64_t msize = (uint64_t)(tw >> k) * (th >> k);
            if ((uint64_t)o + mo[k] + msize > (uint64_t)len) {
                free(ofs);
                return lump_fail(c, EW_LUMP_TEXTURES,
                                 "texture %d ('%s'): mip %d at offset %u (%u bytes) past the lump (%d bytes)",
                                 i, t->name, k, mo[k], (unsigned)msize, (int)len);
            }
            total += msize;
        }
        t->width = (int)tw;
        t->height = (int)th;
        ofs[i] = o;
    }
    /* Every texture's pixels lie inside the lump, so more pixels than the
     * lump holds means textures share bytes: a small file must not become
     * a huge copy (memory stays bounded by the lump's size). */
    if (total - PLACEHOLDER_BYTES > (size_t)len) {
        free(ofs);
        return lump_fail(c, EW_LUMP_TEXTURES, "textures hold %zu pixel bytes, more than the lump's %d: they overlap",
                         total - PLACEHOLDER_BYTES, (int)len);
    }

    if (!(w->texpixels = malloc(total))) {
        free(ofs);
        return lump_fail(c, EW_LUMP_TEXTURES, "out of memory (%zu pixel bytes)", total);
    }

    /* The placeholder: 16x16 checkerboard of colours 0 and 255, per mip. */
    uint8_t *px = w->texpixels;
    ew_texture *ph = &w->textures[n];
    strcpy(ph->name, "ew_missing");
    ph->width = ph->height = PLACEHOLDER_SIZE;
    ph->flags = EW_SURF_MISSING;
    ph->anim_next = ph->alternate_anims = -1;
    for (int k = 0; k < 4; k++) {
        int s = PLACEHOLDER_SIZE >> k;
        ph->mip[k] = px;
        for (int y = 0; y < s; y++)
            for (int x = 0; x < s; x++) *px++ = ((y < s / 2) ^ (x < s / 2)) ? 0 : 255;
    }

    /* Pass 2: copy pixels; missing slots share the placeholder. */
    for (int i = 0; i < n; i++) {
        ew_texture *t = &w->textures[i];
        if (ofs[i] < 0) {
            t->width = t->height = PLACEHOLDER_SIZE;
            for (int k = 0; k < 4; k++) t->mip[k] = ph->mip[k];
            t->flags = texture_flags(t->name) | EW_SURF_MISSING;
            t->liquid = liquid_kind(t->name);
            w->textures_missing++;
            continue;
        }
        const uint8_t *m = L + ofs[i];
        for (int k = 0; k < 4; k++) {
            size_t msize = (size_t)(t->width >> k) * (size_t)(t->height >> k);
            memcpy(px, m + ew_u32(m + 24 + 4 * k), msize);
            t->mip[k] = px;
            px += msize;
        }
        t->flags = texture_flags(t->name);
        t->liquid = liquid_kind(t->name);
        /* A fence texture's holes are its index-255 pixels; without any it
         * is simply drawn solid, but the map probably meant otherwise. */
        if ((t->flags & EW_SURF_FENCE) && !memchr(t->mip[0], 255, (size_t)t->width * (size_t)t->height))
            ew_warn(&w->warnings, &w->nwarnings,
                    "%s: texture \"%s\" is a fence texture without see-through pixels (index 255); drawn solid",
                    w->name, t->name);
    }
    free(ofs);
    return link_animations(c, w, n);
}

static int load_texinfo(ctx *c, ew_world *w) {
    int n = c->count[EW_LUMP_TEXINFO];
    if (!(w->texinfo = alloc_array(c, EW_LUMP_TEXINFO, n, sizeof *w->texinfo))) return -1;
    w->numtexinfo = n;
    int ntex = w->numtextures - 1;  /* file slots, without the placeholder */
    for (int i = 0; i < n; i++) {
        const uint8_t *p = c->lump[EW_LUMP_TEXINFO] + 40 * i;
        ew_texinfo *ti = &w->texinfo[i];
        for (int j = 0; j < 2; j++)
            for (int k = 0; k < 4; k++) {
                ti->vecs[j][k] = ew_f32(p + 16 * j + 4 * k);
                if (!isfinite(ti->vecs[j][k]))
                    return lump_fail(c, EW_LUMP_TEXINFO, "texinfo %d: vector is not finite", i);
            }
        int32_t mt = ew_i32(p + 32);
        ti->flags = ew_i32(p + 36);
        if (ntex == 0) {
            ti->texture = 0;  /* a map without textures: everything uses the placeholder */
        } else if (mt < 0 || mt >= ntex) {
            return lump_fail(c, EW_LUMP_TEXINFO, "texinfo %d uses texture %d (only %d)", i, (int)mt, ntex);
        } else {
            ti->texture = mt;
        }
        /* Mip selection compensates for textures scaled on the surface. */
        float l0 = sqrtf(ti->vecs[0][0] * ti->vecs[0][0] + ti->vecs[0][1] * ti->vecs[0][1] +
                         ti->vecs[0][2] * ti->vecs[0][2]);
        float l1 = sqrtf(ti->vecs[1][0] * ti->vecs[1][0] + ti->vecs[1][1] * ti->vecs[1][1] +
                         ti->vecs[1][2] * ti->vecs[1][2]);
        float l = (l0 + l1) / 2;
        ti->mipadjust = l < 0.32f ? 4 : l < 0.49f ? 3 : l < 0.99f ? 2 : 1;
    }
    return 0;
}

/* ---- faces ------------------------------------------------------------- */

static int load_faces(ctx *c, ew_world *w) {
    int n = c->count[EW_LUMP_FACES];
    if (!(w->faces = alloc_array(c, EW_LUMP_FACES, n, sizeof *w->faces)) ||
        !(w->face_box = alloc_array(c, EW_LUMP_FACES, n, sizeof *w->face_box)))
        return -1;
    w->numfaces = n;
    for (int i = 0; i < n; i++) {
        int64_t plane, side, firstedge, numedges, texinfo;
        const uint8_t *styles;
        int32_t lightofs;
        if (c->fmt == FMT_29) {
            const uint8_t *p = c->lump[EW_LUMP_FACES] + 20 * i;
            /* Unsigned: big BSP29 maps use the full 16 bits for these. */
            plane = ew_u16(p);
            side = ew_i16(p + 2);
            firstedge = ew_i32(p + 4);
            numedges = ew_u16(p + 8);
            texinfo = ew_u16(p + 10);
            styles = p + 12;
            lightofs = ew_i32(p + 16);
        } else {
            const uint8_t *p = c->lump[EW_LUMP_FACES] + 28 * i;
            plane = ew_i32(p);
            side = ew_i32(p + 4);
            firstedge = ew_i32(p + 8);
            numedges = ew_i32(p + 12);
            texinfo = ew_i32(p + 16);
            styles = p + 20;
            lightofs = ew_i32(p + 24);
        }
        if (plane < 0 || plane >= w->numplanes)
            return lump_fail(c, EW_LUMP_FACES, "face %d uses plane %lld (only %d)", i,
                             (long long)plane, w->numplanes);
        if (side != 0 && side != 1)
            return lump_fail(c, EW_LUMP_FACES, "face %d has side %lld (expected 0 or 1)", i,
                             (long long)side);
        if (texinfo < 0 || texinfo >= w->numtexinfo)
            return lump_fail(c, EW_LUMP_FACES, "face %d uses texinfo %lld (only %d)", i,
                             (long long)texinfo, w->numtexinfo);
        if (numedges < 3 || numedges > MAX_FACE_EDGES)
            return lump_fail(c, EW_LUMP_FACES, "face %d has %lld edges (expected 3..%d)", i,
                             (long long)numedges, MAX_FACE_EDGES);
        if (firstedge < 0 || firstedge + numedges > w->numsurfedges)
            return lump_fail(c, EW_LUMP_FACES, "face %d uses surfedges %lld..%lld (only %d)", i,
                             (long long)firstedge, (long long)(firstedge + numedges - 1),
                             w->numsurfedges);

        ew_face *f = &w->faces[i];
        f->plane = (int)plane;
        f->firstedge = (int)firstedge;
        f->numedges = (int)numedges;
        f->texinfo = (int)texinfo;
        f->flags = side ? EW_SURF_PLANEBACK : 0;
        const ew_texinfo *ti = &w->texinfo[f->texinfo];
        f->flags |= w->textures[ti->texture].flags &
                    (EW_SURF_SKY | EW_SURF_TURB | EW_SURF_FENCE | EW_SURF_MISSING);
        float (*box)[3] = w->face_box[i];
        for (int k = 0; k < 3; k++) box[0][k] = INFINITY, box[1][k] = -INFINITY;
        for (int e = 0; e < f->numedges; e++) {
            const float *v = w->verts[ew_face_vertex(w, f, e)];
            for (int k = 0; k < 3; k++) {
                if (v[k] < box[0][k]) box[0][k] = v[k];
                if (v[k] > box[1][k]) box[1][k] = v[k];
            }
        }

        if (f->flags & (EW_SURF_SKY | EW_SURF_TURB)) {
            /* Warped/sky surfaces are drawn without a light map. */
            f->texturemins[0] = f->texturemins[1] = -8192;
            f->extents[0] = f->extents[1] = 16384;
            f->lightofs = -1;
            memset(f->styles, 255, 4);
            continue;
        }

        /* Texture extents in single precision, the way the light maps were
         * computed by the compiler, so the light map sizes agree. */
        float mins[2] = {INFINITY, INFINITY}, maxs[2] = {-INFINITY, -INFINITY};
        for (int e = 0; e < f->numedges; e++) {
            const float *v = w->verts[ew_face_vertex(w, f, e)];
            for (int j = 0; j < 2; j++) {
                float val = v[0] * ti->vecs[j][0] + v[1] * ti->vecs[j][1] +
                            v[2] * ti->vecs[j][2] + ti->vecs[j][3];
                /* huge vertices times big vectors overflow to inf or NaN */
                if (!(val > -MAX_TEXCOORD && val < MAX_TEXCOORD))
                    return lump_fail(c, EW_LUMP_FACES, "face %d: texture coordinates out of range", i);
                if (val < mins[j]) mins[j] = val;
                if (val > maxs[j]) maxs[j] = val;
            }
        }
        for (int j = 0; j < 2; j++) {
            int bmin = (int)floorf(mins[j] / 16), bmax = (int)ceilf(maxs[j] / 16);
            f->texturemins[j] = bmin * 16;
            f->extents[j] = (bmax - bmin) * 16;
            /* Zero: every vertex has the same texture coordinate along
             * this axis, on a multiple of 16 (ericw-tools writes such
             * faces).  The light map then has one row (column) of
             * samples and the surface is one texel along it
             * (ew_face_surf_size). */
            if (f->extents[j] > MAX_EXTENT)
                return lump_fail(c, EW_LUMP_FACES, "face %d: texture extent %d texels (limit %d)",
                                 i, f->extents[j], MAX_EXTENT);
        }

        int nstyles = 0;
        for (int k = 0; k < 4; k++) nstyles += styles[k] != 255;
        if (lightofs == -1 || styles[0] == 255) {
            /* No light map: say so in both fields so no reader looks further. */
            f->lightofs = -1;
            memset(f->styles, 255, 4);
            continue;
        }
        int64_t lsize = (int64_t)((f->extents[0] >> 4) + 1) * ((f->extents[1] >> 4) + 1) * nstyles;
        if ((lightofs < 0 || lightofs + lsize > w->lightsize) && c->light_moved) {
            f->lightofs = -1;  /* ew_bspx_layout places it, if it can */
            memset(f->styles, 255, 4);
            continue;
        }
        if (lightofs < 0 || lightofs + lsize > w->lightsize)
            return lump_fail(c, EW_LUMP_FACES,
                             "face %d: light map at offset %d (size %lld) past the lighting lump (%d bytes)",
                             i, (int)lightofs, (long long)lsize, w->lightsize);
        f->lightofs = lightofs;
        memcpy(f->styles, styles, 4);
    }
    return 0;
}

static int load_marksurfaces(ctx *c, ew_world *w) {
    int n = c->count[EW_LUMP_MARKSURFACES];
    if (!(w->marksurfaces = alloc_array(c, EW_LUMP_MARKSURFACES, n, sizeof *w->marksurfaces)))
        return -1;
    w->nummarksurfaces = n;
    for (int i = 0; i < n; i++) {
        uint32_t m = c->fmt == FMT_29 ? ew_u16(c->lump[EW_LUMP_MARKSURFACES] + 2 * i)
                                      : ew_u32(c->lump[EW_LUMP_MARKSURFACES] + 4 * i);
        if (m >= (uint32_t)w->numfaces)
            return lump_fail(c, EW_LUMP_MARKSURFACES, "marksurface %d uses face %u (only %d)", i, m,
                             w->numfaces);
        w->marksurfaces[i] = (int)m;
    }
    return 0;
}

/* ---- tree -------------------------------------------------------------- */

/* Bounding boxes: int16 in BSP29 and 2PSB, float in BSP2. */
static void read_bounds(const ctx *c, const uint8_t *p, float mins[3], float maxs[3]) {
    for (int k = 0; k < 3; k++) {
        if (c->fmt == FMT_BSP2) {
            mins[k] = ew_f32(p + 4 * k);
            maxs[k] = ew_f32(p + 12 + 4 * k);
        } else {
            mins[k] = ew_i16(p + 2 * k);
            maxs[k] = ew_i16(p + 6 + 2 * k);
        }
    }
}

static int load_leafs(ctx *c, ew_world *w) {
    int n = c->count[EW_LUMP_LEAFS];
    if (!(w->leaves = alloc_array(c, EW_LUMP_LEAFS, n, sizeof *w->leaves))) return -1;
    w->numleaves = n;
    int rs = rec_size[c->fmt][EW_LUMP_LEAFS];
    int bsz = c->fmt == FMT_BSP2 ? 24 : 12;  /* bytes of mins+maxs */
    for (int i = 0; i < n; i++) {
        const uint8_t *p = c->lump[EW_LUMP_LEAFS] + (size_t)rs * i;
        ew_leaf *l = &w->leaves[i];
        l->contents = ew_i32(p);
        l->visofs = ew_i32(p + 4);
        read_bounds(c, p + 8, l->mins, l->maxs);
        const uint8_t *q = p + 8 + bsz;
        uint32_t first, num;
        if (c->fmt == FMT_29) {
            first = ew_u16(q);
            num = ew_u16(q + 2);
            q += 4;
        } else {
            first = ew_u32(q);
            num = ew_u32(q + 4);
            q += 8;
        }
        memcpy(l->ambient, q, 4);
        if ((uint64_t)first + num > (uint64_t)w->nummarksurfaces)
            return lump_fail(c, EW_LUMP_LEAFS, "leaf %d uses marksurfaces %u + %u (only %d)", i,
                             first, num, w->nummarksurfaces);
        l->firstmark = (int)first;
        l->nummarks = (int)num;
        /* Compilers write visofs 0 when they ran no vis at all; leaf 0 (the
         * solid leaf) never uses its row.  Both mean "no PVS row". */
        if (w->vissize == 0 || (i == 0 && (l->visofs < 0 || l->visofs >= w->vissize)))
            l->visofs = -1;
        if (l->visofs != -1 && (l->visofs < 0 || l->visofs >= w->vissize))
            return lump_fail(c, EW_LUMP_LEAFS, "leaf %d: visibility offset %d past the visibility lump (%d bytes)",
                             i, l->visofs, w->vissize);
        l->parent = -1;
    }
    return 0;
}

static int load_nodes(ctx *c, ew_world *w) {
    int n = c->count[EW_LUMP_NODES];
    if (!(w->nodes = alloc_array(c, EW_LUMP_NODES, n, sizeof *w->nodes))) return -1;
    w->numnodes = n;
    int rs = rec_size[c->fmt][EW_LUMP_NODES];
    for (int i = 0; i < n; i++) {
        const uint8_t *p = c->lump[EW_LUMP_NODES] + (size_t)rs * i;
        ew_node *nd = &w->nodes[i];
        int32_t plane = ew_i32(p);
        const uint8_t *q;
        if (c->fmt == FMT_29) {
            nd->children[0] = ew_i16(p + 4);
            nd->children[1] = ew_i16(p + 6);
            read_bounds(c, p + 8, nd->mins, nd->maxs);
            q = p + 20;
        } else {
            nd->children[0] = ew_i32(p + 4);
            nd->children[1] = ew_i32(p + 8);
            read_bounds(c, p + 12, nd->mins, nd->maxs);
            q = p + (c->fmt == FMT_BSP2 ? 36 : 24);
        }
        uint32_t first, num;
        if (c->fmt == FMT_29) {
            first = ew_u16(q);
            num = ew_u16(q + 2);
        } else {
            first = ew_u32(q);
            num = ew_u32(q + 4);
        }
        if (plane < 0 || plane >= w->numplanes)
            return lump_fail(c, EW_LUMP_NODES, "node %d uses plane %d (only %d)", i, (int)plane,
                             w->numplanes);
        nd->plane = plane;
        for (int k = 0; k < 2; k++) {
            int ch = nd->children[k];
            if (ch >= 0 ? ch >= n : -1 - (int64_t)ch >= w->numleaves)
                return lump_fail(c, EW_LUMP_NODES, "node %d: child %d is %s %lld (only %d)", i, k,
                                 ch >= 0 ? "node" : "leaf", ch >= 0 ? (long long)ch : -1 - (long long)ch,
                                 ch >= 0 ? n : w->numleaves);
        }
        if ((uint64_t)first + num > (uint64_t)w->numfaces)
            return lump_fail(c, EW_LUMP_NODES, "node %d uses faces %u + %u (only %d)", i, first, num,
                             w->numfaces);
        nd->firstface = (int)first;
        nd->numfaces = (int)num;
        nd->parent = -1;
    }
    return 0;
}

static int load_models(ctx *c, ew_world *w) {
    int n = c->count[EW_LUMP_MODELS];
    if (n < 1) return lump_fail(c, EW_LUMP_MODELS, "no models (the world is model 0)");
    if (!(w->models = alloc_array(c, EW_LUMP_MODELS, n, sizeof *w->models))) return -1;
    w->nummodels = n;
    for (int i = 0; i < n; i++) {
        const uint8_t *p = c->lump[EW_LUMP_MODELS] + 64 * i;
        ew_model *m = &w->models[i];
        for (int k = 0; k < 3; k++) {
            m->mins[k] = ew_f32(p + 4 * k);
            m->maxs[k] = ew_f32(p + 12 + 4 * k);
            m->origin[k] = ew_f32(p + 24 + 4 * k);
        }
        m->headnode = ew_i32(p + 36);
        m->cliphead[0] = ew_i32(p + 40);  /* hull 1; hull 3 (p + 48) is unused */
        m->cliphead[1] = ew_i32(p + 44);
        m->visleafs = ew_i32(p + 52);
        int32_t first = ew_i32(p + 56), num = ew_i32(p + 60);
        if (m->headnode < 0 || m->headnode >= w->numnodes)
            return lump_fail(c, EW_LUMP_MODELS, "model %d has head node %d (only %d)", i, m->headnode,
                             w->numnodes);
        /* PVS rows cover leaves 1..visleafs. */
        if (m->visleafs < 0 || m->visleafs > w->numleaves - 1)
            return lump_fail(c, EW_LUMP_MODELS, "model %d has %d vis leaves (only %d leaves)", i,
                             m->visleafs, w->numleaves);
        if (first < 0 || num < 0 || (int64_t)first + num > w->numfaces)
            return lump_fail(c, EW_LUMP_MODELS, "model %d uses faces %d + %d (only %d)", i, (int)first,
                             (int)num, w->numfaces);
        m->firstface = first;
        m->numfaces = num;
    }
    return 0;
}

/* ---- clip hulls ---------------------------------------------------------- */

/* Largest contents value a clip hull leaf may hold (-1 empty .. -14
 * currents; -15 is allowed for compilers' own kinds). */
#define MIN_CLIP_CONTENTS (-15)

/* The clipnodes lump, as is: BSP29 stores each child as 16 bits, where
 * 0xfff0..0xffff are the contents -16..-1 and everything below a clipnode
 * index (so a map may have up to 65520 clipnodes, as today's ports read
 * it; for fewer than 32768 this is the same as a signed read).  BSP2 and
 * 2PSB store int32 children.  Indices are checked by check_clip. */
static int load_clipnodes(ctx *c, ew_world *w) {
    int n = c->count[EW_LUMP_CLIPNODES];
    if (!(w->clipnodes = alloc_array(c, EW_LUMP_CLIPNODES, n, sizeof *w->clipnodes))) return -1;
    w->numclipnodes = n;
    int rs = rec_size[c->fmt][EW_LUMP_CLIPNODES];
    for (int i = 0; i < n; i++) {
        const uint8_t *p = c->lump[EW_LUMP_CLIPNODES] + (size_t)rs * i;
        ew_clipnode *cn = &w->clipnodes[i];
        cn->plane = ew_i32(p);
        for (int k = 0; k < 2; k++) {
            if (c->fmt == FMT_29) {
                int v = ew_u16(p + 4 + 2 * k);
                cn->children[k] = v >= 0xfff0 ? v - 0x10000 : v;
            } else {
                cn->children[k] = ew_i32(p + 4 + 4 * k);
            }
        }
    }
    return 0;
}

static int bad_clip_ref(const ew_world *w, int ref) {
    return ref >= 0 ? ref >= w->numclipnodes : ref < MIN_CLIP_CONTENTS;
}

/* Checks the clip hulls 1 and 2 of every model: planes and children in
 * range, every head in range, and no cycle anywhere in the lump (Kahn's
 * peeling: a node is removed once nothing points to it; whatever is left
 * lies on a cycle).  A map without clipnodes simply has no collision; a
 * map whose clip hulls are malformed keeps rendering (they are not used
 * for drawing) with one warning, and has no collision either. */
static int check_clip(ctx *c, ew_world *w) {
    w->clip_ok = 0;
    int n = w->numclipnodes;
    if (n == 0) return 0;
    for (int i = 0; i < n; i++) {
        const ew_clipnode *cn = &w->clipnodes[i];
        if (cn->plane < 0 || cn->plane >= w->numplanes) {
            ew_warn(&w->warnings, &w->nwarnings,
                    "%s: lump 'clipnodes': clipnode %d uses plane %d (only %d); no collision", c->file, i,
                    cn->plane, w->numplanes);
            return 0;
        }
        for (int k = 0; k < 2; k++)
            if (bad_clip_ref(w, cn->children[k])) {
                ew_warn(&w->warnings, &w->nwarnings,
                        "%s: lump 'clipnodes': clipnode %d: child %d is %d (%d clipnodes, contents down to %d); no collision",
                        c->file, i, k, cn->children[k], n, MIN_CLIP_CONTENTS);
                return 0;
            }
    }
    for (int m = 0; m < w->nummodels; m++)
        for (int h = 0; h < 2; h++)
            if (bad_clip_ref(w, w->models[m].cliphead[h])) {
                ew_warn(&w->warnings, &w->nwarnings,
                        "%s: lump 'models': model %d: hull %d head clipnode %d (only %d); no collision", c->file,
                        m, h + 1, w->models[m].cliphead[h], n);
                return 0;
            }
    int *indeg = calloc((size_t)n, sizeof *indeg), *queue = malloc((size_t)n * sizeof *queue);
    if (!indeg || !queue) {
        free(indeg), free(queue);
        return lump_fail(c, EW_LUMP_CLIPNODES, "out of memory (%d records)", n);
    }
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 2; k++)
            if (w->clipnodes[i].children[k] >= 0) indeg[w->clipnodes[i].children[k]]++;
    int qn = 0;
    for (int i = 0; i < n; i++)
        if (indeg[i] == 0) queue[qn++] = i;
    for (int q = 0; q < qn; q++)
        for (int k = 0; k < 2; k++) {
            int ch = w->clipnodes[queue[q]].children[k];
            if (ch >= 0 && --indeg[ch] == 0) queue[qn++] = ch;
        }
    int cyclic = -1;
    for (int i = 0; i < n && cyclic < 0; i++)
        if (indeg[i] > 0) cyclic = i;
    free(indeg), free(queue);
    if (cyclic >= 0) {
        ew_warn(&w->warnings, &w->nwarnings,
                "%s: lump 'clipnodes': clipnode %d lies on a cycle; no collision", c->file, cyclic);
        return 0;
    }
    w->clip_ok = 1;
    return 0;
}

/* Parent links from each model's head node.  An explicit stack keeps the
 * walk bounded whatever the file says; every node and leaf (except the
 * shared solid leaf 0) must be reached at most once. */
static int link_parents(ctx *c, ew_world *w) {
    int *stack = alloc_array(c, EW_LUMP_NODES, w->numnodes, sizeof *stack);
    uint8_t *seen_node = alloc_array(c, EW_LUMP_NODES, w->numnodes, 1);
    uint8_t *seen_leaf = alloc_array(c, EW_LUMP_LEAFS, w->numleaves, 1);
    int rc = 0;
    if (!stack || !seen_node || !seen_leaf) {
        rc = -1;
        goto done;
    }
    for (int m = 0; m < w->nummodels && rc == 0; m++) {
        int head = w->models[m].headnode;
        if (seen_node[head]) {
            rc = lump_fail(c, EW_LUMP_NODES, "node %d reached twice (cycle or shared subtree)", head);
            break;
        }
        seen_node[head] = 1;
        w->nodes[head].parent = -1;
        int sp = 0;
        stack[sp++] = head;  /* each node is pushed once, so numnodes slots suffice */
        while (sp > 0 && rc == 0) {
            int nd = stack[--sp];
            for (int k = 0; k < 2; k++) {
                int ch = w->nodes[nd].children[k];
                if (ch >= 0) {
                    if (seen_node[ch]) {
                        rc = lump_fail(c, EW_LUMP_NODES, "node %d reached twice (cycle or shared subtree)", ch);
                        break;
                    }
                    seen_node[ch] = 1;
                    w->nodes[ch].parent = nd;
                    stack[sp++] = ch;
                } else {
                    int leaf = -1 - ch;
                    if (leaf == 0) continue;  /* the solid leaf is shared by design */
                    if (seen_leaf[leaf]) {
                        rc = lump_fail(c, EW_LUMP_LEAFS, "leaf %d reached twice (cycle or shared subtree)", leaf);
                        break;
                    }
                    seen_leaf[leaf] = 1;
                    w->leaves[leaf].parent = nd;
                }
            }
        }
    }
done:
    free(stack);
    free(seen_node);
    free(seen_leaf);
    return rc;
}

/* ---- public ------------------------------------------------------------ */

const char *ew_world_warning(const ew_world *w, int i) {
    return w && i >= 0 && i < w->nwarnings ? w->warnings[i] : NULL;
}

void ew_world_destroy(ew_world *w) {
    if (!w) return;
    ew_warn_free(w->warnings, w->nwarnings);
    free(w->planes);
    free(w->verts);
    free(w->edges);
    free(w->surfedges);
    free(w->surfverts);
    free(w->texinfo);
    free(w->textures);
    free(w->faces);
    free(w->face_box);
    free(w->marksurfaces);
    free(w->nodes);
    free(w->leaves);
    free(w->models);
    free(w->clipnodes);
    free(w->lighting);
    free(w->rgblight);
    free(w->facelm);
    free(w->bspx);
    free(w->visdata);
    free(w->entities);
    free(w->texpixels);
    free(w);
}

ew_world *ew_world_create(const uint8_t *data, size_t size, const char *filename, ew_error *err) {
    ctx c = {.data = data, .size = size, .file = filename, .err = err};
    if (!data) size = c.size = 0;
    ew_world *w = calloc(1, sizeof *w);
    if (!w) {
        ew_fail(err, "%s: out of memory", filename);
        return NULL;
    }
    const char *base = strrchr(filename, '/');
    snprintf(w->name, sizeof w->name, "%s", base ? base + 1 : filename);

    /* BSPX (asset/lightdata.c): optional; a malformed part is a warning */
    ew_bspx bx = {0};
    if (read_header(&c, w) || load_planes(&c, w) || load_vertexes(&c, w) || load_edges(&c, w) ||
        load_surfedges(&c, w) || load_entities(&c, w) ||
        copy_bytes(&c, EW_LUMP_LIGHTING, &w->lighting, &w->lightsize) ||
        copy_bytes(&c, EW_LUMP_VISIBILITY, &w->visdata, &w->vissize) || load_textures(&c, w) ||
        load_texinfo(&c, w) ||
        (ew_bspx_open(&bx, data, size, w->lumps, w, filename), ew_bspx_rgb(&bx, w, filename),
         c.light_moved = ew_bspx_moves_light(&bx), load_faces(&c, w)) ||
        load_marksurfaces(&c, w) ||
        load_leafs(&c, w) || load_nodes(&c, w) || load_models(&c, w) || link_parents(&c, w) ||
        load_clipnodes(&c, w) || check_clip(&c, w)) {
        ew_world_destroy(w);
        return NULL;
    }
    {
        int rec = rec_size[c.fmt][EW_LUMP_FACES];
        ew_bspx_layout(&bx, w, filename, c.lump[EW_LUMP_FACES], rec, c.fmt == FMT_29 ? 12 : 20);
    }
    ew_worldspawn_read(w);  /* opaque liquids and no fog unless the map asks */
    w->styles_start_off = ew_light_styles_starting_off(w->entities, strlen(w->entities));
    return w;
}

void ew_world_get_info(const ew_world *w, ew_world_info *info) {
    memset(info, 0, sizeof *info);
    memcpy(info->version, w->version, sizeof info->version);
    memcpy(info->lumps, w->lumps, sizeof info->lumps);
    info->models = w->nummodels;
    info->textures = w->numtextures - 1;  /* slots in the file, not the placeholder */
    info->textures_missing = w->textures_missing;
    info->faces = w->numfaces;
    info->leaves = w->numleaves;
    info->nodes = w->numnodes;
}

int ew_world_bspx_lump(const ew_world *w, int i, ew_bspx_lump_info *info) {
    if (!w || !info || i < 0 || i >= w->nbspx) return -1;
    *info = w->bspx[i];
    return 0;
}

const char *ew_world_entities(const ew_world *w) { return w->entities; }
