/* MDL version 6 loader: header, skins (single or timed groups), texture
 * coordinates, triangles, frames (single or timed groups).  Two passes over
 * the file: the first checks every count, size and index against the
 * buffer and counts what to allocate, the second copies.  Vertex normals
 * for Gouraud shading are computed from each frame's own geometry (the
 * area-weighted average of the normals of the triangles around a vertex). */
#include "asset/mdl.h"
#include "ew_util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define HEADER_SIZE 84

typedef struct cursor {
    const uint8_t *data;
    size_t size, pos;
    const char *name;
    ew_error *err;
} cursor;

static int need(cursor *c, size_t n, const char *what) {
    if (n > c->size - c->pos)
        return ew_fail(c->err, "%s: truncated in %s (needs %zu bytes at offset %zu, file has %zu)",
                       c->name, what, n, c->pos, c->size);
    return 0;
}

static int read_i32(cursor *c, int32_t *out, const char *what) {
    if (need(c, 4, what)) return -1;
    *out = ew_i32(c->data + c->pos);
    c->pos += 4;
    return 0;
}

/* n timed intervals: each must be positive and finite. */
static int read_times(cursor *c, int n, float *out, const char *what, int index) {
    if (need(c, (size_t)n * 4, what)) return -1;
    for (int i = 0; i < n; i++) {
        float f = ew_f32(c->data + c->pos + (size_t)i * 4);
        if (!isfinite(f) || f <= 0)
            return ew_fail(c->err, "%s: %s %d: interval %d is %g (must be positive)", c->name, what,
                           index, i, (double)f);
        if (out) out[i] = f;
    }
    c->pos += (size_t)n * 4;
    return 0;
}

/* The per-pass state: counts in pass 0, filling in pass 1. */
typedef struct loader {
    ew_mdl *m;
    int fill;
    int nimages, nposes, ntimes;
} loader;

static int parse_skins(cursor *c, loader *L) {
    ew_mdl *m = L->m;
    size_t img = (size_t)m->skinwidth * m->skinheight;
    for (int i = 0; i < m->numskins; i++) {
        int32_t type;
        if (read_i32(c, &type, "skins")) return -1;
        if (type != 0 && type != 1)
            return ew_fail(c->err, "%s: skin %d has type %d (0 single, 1 group)", c->name, i, type);
        int32_t n = 1;
        const float *times = NULL;
        if (type == 1) {
            if (read_i32(c, &n, "skin group")) return -1;
            if (n < 1 || (size_t)n > (c->size - c->pos) / 4)
                return ew_fail(c->err, "%s: skin group %d has %d images", c->name, i, n);
            float *t = L->fill ? m->timedata + L->ntimes : NULL;
            if (read_times(c, n, t, "skin group", i)) return -1;
            times = t;
            L->ntimes += n;
        }
        if ((size_t)n > (c->size - c->pos) / img)
            return ew_fail(c->err, "%s: truncated in skin %d (%d images of %dx%d)", c->name, i, n,
                           m->skinwidth, m->skinheight);
        if (L->fill) {
            m->skins[i].first = L->nimages;
            m->skins[i].count = n;
            m->skins[i].times = times;
            memcpy(m->skinpixels + (size_t)L->nimages * img, c->data + c->pos, img * (size_t)n);
        }
        c->pos += img * (size_t)n;
        L->nimages += n;
    }
    return 0;
}

static int parse_st_tris(cursor *c, loader *L) {
    ew_mdl *m = L->m;
    if (need(c, (size_t)m->numverts * 12, "texture coordinates")) return -1;
    for (int i = 0; i < m->numverts; i++) {
        const uint8_t *p = c->data + c->pos + (size_t)i * 12;
        int32_t onseam = ew_i32(p), s = ew_i32(p + 4), t = ew_i32(p + 8);
        if (s < 0 || s > m->skinwidth || t < 0 || t > m->skinheight)
            return ew_fail(c->err, "%s: vertex %d has texture coordinates (%d, %d) outside the %dx%d skin",
                           c->name, i, s, t, m->skinwidth, m->skinheight);
        if (L->fill) m->st[i] = (ew_mdl_st){onseam != 0, s, t};
    }
    c->pos += (size_t)m->numverts * 12;
    if (need(c, (size_t)m->numtris * 16, "triangles")) return -1;
    for (int i = 0; i < m->numtris; i++) {
        const uint8_t *p = c->data + c->pos + (size_t)i * 16;
        ew_mdl_tri tri = {ew_i32(p) != 0, {0, 0, 0}};
        for (int k = 0; k < 3; k++) {
            int32_t v = ew_i32(p + 4 + 4 * k);
            if (v < 0 || v >= m->numverts)
                return ew_fail(c->err, "%s: triangle %d uses vertex %d (only %d)", c->name, i, v,
                               m->numverts);
            tri.v[k] = v;
        }
        if (L->fill) m->tris[i] = tri;
    }
    c->pos += (size_t)m->numtris * 16;
    return 0;
}

/* One simple frame body: bboxmin, bboxmax, name[16], numverts vertices. */
static int parse_pose(cursor *c, loader *L, int frame) {
    ew_mdl *m = L->m;
    size_t vsize = (size_t)m->numverts * 4;
    if (need(c, 8 + 16 + vsize, "frame")) {
        return ew_fail(c->err, "%s: truncated in frame %d (needs %zu bytes at offset %zu, file has %zu)",
                       c->name, frame, 8 + 16 + vsize, c->pos, c->size);
    }
    if (L->fill) {
        ew_mdl_pose *pose = &m->poses[L->nposes];
        memcpy(pose->name, c->data + c->pos + 8, 16);
        pose->name[16] = 0;
        ew_mdl_vert *v = m->vertdata + (size_t)L->nposes * m->numverts;
        memcpy(v, c->data + c->pos + 24, vsize);
        pose->verts = v;
        pose->normals = (const float(*)[3])(m->normaldata + (size_t)L->nposes * m->numverts);
    }
    c->pos += 24 + vsize;
    L->nposes++;
    return 0;
}

static int parse_frames(cursor *c, loader *L) {
    ew_mdl *m = L->m;
    for (int i = 0; i < m->numframes; i++) {
        int32_t type;
        if (read_i32(c, &type, "frames")) return -1;
        if (type == 0) {
            if (L->fill) m->frames[i] = (ew_mdl_anim){L->nposes, 1, NULL};
            if (parse_pose(c, L, i)) return -1;
            continue;
        }
        int32_t n;
        if (read_i32(c, &n, "frame group")) return -1;
        size_t pose_size = 24 + (size_t)m->numverts * 4;
        if (n < 1 || (size_t)n > (c->size - c->pos) / pose_size)
            return ew_fail(c->err, "%s: frame group %d has %d frames", c->name, i, n);
        if (need(c, 8, "frame group")) return -1;  /* group bounds (recomputed below) */
        c->pos += 8;
        float *t = L->fill ? m->timedata + L->ntimes : NULL;
        if (read_times(c, n, t, "frame group", i)) return -1;
        L->ntimes += n;
        if (L->fill) m->frames[i] = (ew_mdl_anim){L->nposes, n, t};
        for (int k = 0; k < n; k++)
            if (parse_pose(c, L, i)) return -1;
    }
    return 0;
}

static int parse(cursor *c, loader *L) {
    c->pos = HEADER_SIZE;
    L->nimages = L->nposes = L->ntimes = 0;
    if (parse_skins(c, L) || parse_st_tris(c, L) || parse_frames(c, L)) return -1;
    return 0;
}

/* Bounds and area-weighted vertex normals of every pose, in model space. */
static void compute_pose_geometry(ew_mdl *m) {
    float *pos = malloc(sizeof(float) * 3 * (size_t)m->numverts);
    for (int pi = 0; pi < m->numposes; pi++) {
        ew_mdl_pose *pose = &m->poses[pi];
        float(*nrm)[3] = m->normaldata + (size_t)pi * m->numverts;
        for (int k = 0; k < 3; k++) pose->mins[k] = 1e30f, pose->maxs[k] = -1e30f;
        for (int i = 0; i < m->numverts; i++) {
            for (int k = 0; k < 3; k++) {
                float x = pose->verts[i].v[k] * m->scale[k] + m->translate[k];
                if (pos) pos[i * 3 + k] = x;
                if (x < pose->mins[k]) pose->mins[k] = x;
                if (x > pose->maxs[k]) pose->maxs[k] = x;
                nrm[i][k] = 0;
            }
        }
        if (!pos) {  /* out of memory for scratch: every normal straight up */
            for (int i = 0; i < m->numverts; i++) nrm[i][2] = 1;
            continue;
        }
        for (int t = 0; t < m->numtris; t++) {
            const int *v = m->tris[t].v;
            const float *a = pos + v[0] * 3, *b = pos + v[1] * 3, *cc = pos + v[2] * 3;
            float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
            float e2[3] = {cc[0] - a[0], cc[1] - a[1], cc[2] - a[2]};
            /* The files wind front faces clockwise seen from outside, so the
             * outward normal is e2 x e1. */
            float n[3] = {e2[1] * e1[2] - e2[2] * e1[1], e2[2] * e1[0] - e2[0] * e1[2],
                          e2[0] * e1[1] - e2[1] * e1[0]};
            for (int k = 0; k < 3; k++)
                for (int j = 0; j < 3; j++) nrm[v[k]][j] += n[j];
        }
        for (int i = 0; i < m->numverts; i++) {
            float l = sqrtf(nrm[i][0] * nrm[i][0] + nrm[i][1] * nrm[i][1] + nrm[i][2] * nrm[i][2]);
            if (l > 1e-12f) {
                for (int k = 0; k < 3; k++) nrm[i][k] /= l;
            } else {
                nrm[i][0] = nrm[i][1] = 0, nrm[i][2] = 1;
            }
        }
    }
    free(pos);
}

ew_mdl *ew_mdl_load(const uint8_t *data, size_t size, const char *name, ew_error *err) {
    if (!name) name = "mdl";
    if (!data || size < HEADER_SIZE) {
        ew_fail(err, "%s: %zu bytes is too short for an MDL header (%d)", name, size, HEADER_SIZE);
        return NULL;
    }
    if (memcmp(data, "IDPO", 4) != 0) {
        ew_fail(err, "%s: not an MDL file (no IDPO tag)", name);
        return NULL;
    }
    int32_t version = ew_i32(data + 4);
    if (version != 6) {
        ew_fail(err, "%s: MDL version %d (only 6 is supported)", name, version);
        return NULL;
    }
    ew_mdl hdr;
    memset(&hdr, 0, sizeof hdr);
    for (int k = 0; k < 3; k++) {
        hdr.scale[k] = ew_f32(data + 8 + 4 * k);
        hdr.translate[k] = ew_f32(data + 20 + 4 * k);
        hdr.eye[k] = ew_f32(data + 36 + 4 * k);
    }
    (void)ew_f32(data + 32);  /* the file's bounding radius: not trusted, computed below */
    int32_t numskins = ew_i32(data + 48), sw = ew_i32(data + 52), sh = ew_i32(data + 56);
    int32_t numverts = ew_i32(data + 60), numtris = ew_i32(data + 64), numframes = ew_i32(data + 68);
    hdr.synctype = ew_i32(data + 72);
    hdr.flags = ew_i32(data + 76);
    hdr.size = ew_f32(data + 80);
    float reach2 = 0;
    for (int k = 0; k < 3; k++) {
        if (!isfinite(hdr.scale[k]) || !isfinite(hdr.translate[k]) || fabsf(hdr.scale[k]) > 1e5f ||
            fabsf(hdr.translate[k]) > 1e6f) {
            ew_fail(err, "%s: scale/translate %d is not a sane number (%g, %g)", name, k,
                    (double)hdr.scale[k], (double)hdr.translate[k]);
            return NULL;
        }
        /* A vertex byte is 0..255: the farthest any can be from the origin. */
        float a = fabsf(hdr.translate[k]), b = fabsf(hdr.translate[k] + 255 * hdr.scale[k]);
        reach2 += (a > b ? a : b) * (a > b ? a : b);
    }
    hdr.radius = sqrtf(reach2);
    if (numskins < 1 || numskins > EW_MDL_MAX_SKINS) {
        ew_fail(err, "%s: %d skins (1..%d)", name, numskins, EW_MDL_MAX_SKINS);
        return NULL;
    }
    if (sw < 1 || sh < 1 || sw > EW_MDL_MAX_SKIN_SIDE || sh > EW_MDL_MAX_SKIN_SIDE) {
        ew_fail(err, "%s: skin size %dx%d (1..%d each way)", name, sw, sh, EW_MDL_MAX_SKIN_SIDE);
        return NULL;
    }
    if (numverts < 3 || numverts > EW_MDL_MAX_VERTS) {
        ew_fail(err, "%s: %d vertices (3..%d)", name, numverts, EW_MDL_MAX_VERTS);
        return NULL;
    }
    if (numtris < 1 || numtris > EW_MDL_MAX_TRIS) {
        ew_fail(err, "%s: %d triangles (1..%d)", name, numtris, EW_MDL_MAX_TRIS);
        return NULL;
    }
    if (numframes < 1 || numframes > EW_MDL_MAX_FRAMES) {
        ew_fail(err, "%s: %d frames (1..%d)", name, numframes, EW_MDL_MAX_FRAMES);
        return NULL;
    }
    hdr.numskins = numskins, hdr.skinwidth = sw, hdr.skinheight = sh;
    hdr.numverts = numverts, hdr.numtris = numtris, hdr.numframes = numframes;

    /* Pass 0: validate and count (nothing is written). */
    cursor c = {data, size, 0, name, err};
    loader L = {&hdr, 0, 0, 0, 0};
    if (parse(&c, &L)) return NULL;

    ew_mdl *m = calloc(1, sizeof *m);
    if (!m) goto oom;
    *m = hdr;
    snprintf(m->name, sizeof m->name, "%s", name);
    m->numskinimages = L.nimages;
    m->numposes = L.nposes;
    m->skins = calloc((size_t)numskins, sizeof *m->skins);
    m->skinpixels = malloc((size_t)L.nimages * sw * sh);
    m->st = malloc(sizeof *m->st * (size_t)numverts);
    m->tris = malloc(sizeof *m->tris * (size_t)numtris);
    m->frames = calloc((size_t)numframes, sizeof *m->frames);
    m->poses = calloc((size_t)L.nposes, sizeof *m->poses);
    m->vertdata = malloc(sizeof *m->vertdata * (size_t)L.nposes * numverts);
    m->normaldata = malloc(sizeof *m->normaldata * (size_t)L.nposes * numverts);
    m->timedata = malloc(sizeof(float) * (size_t)(L.ntimes ? L.ntimes : 1));
    if (!m->skins || !m->skinpixels || !m->st || !m->tris || !m->frames || !m->poses ||
        !m->vertdata || !m->normaldata || !m->timedata)
        goto oom;

    /* Pass 1: copy (cannot fail: pass 0 checked the same reads). */
    L = (loader){m, 1, 0, 0, 0};
    if (parse(&c, &L)) {
        ew_mdl_free(m);
        return NULL;
    }
    compute_pose_geometry(m);
    return m;
oom:
    ew_mdl_free(m);
    ew_fail(err, "%s: out of memory", name);
    return NULL;
}

void ew_mdl_free(ew_mdl *m) {
    if (!m) return;
    free(m->skins), free(m->skinpixels), free(m->st), free(m->tris), free(m->frames);
    free(m->poses), free(m->vertdata), free(m->normaldata), free(m->timedata);
    free(m);
}

int ew_mdl_anim_pick(const ew_mdl_anim *a, double time) {
    if (a->count <= 1 || !a->times) return a->first;
    double full = a->times[a->count - 1];
    if (!(full > 0) || !isfinite(time)) return a->first;
    double t = fmod(time, full);
    if (t < 0) t += full;
    for (int i = 0; i < a->count - 1; i++)
        if (a->times[i] > t) return a->first + i;
    return a->first + a->count - 1;
}
