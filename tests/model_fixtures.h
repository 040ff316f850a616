/* Test fixtures for the model tests: MDL and SPR files built in memory, and
 * a closed sphere-like mesh (an icosphere).  Static functions, included by
 * test_alias.c and test_models.c. */
#ifndef EW_MODEL_FIXTURES_H
#define EW_MODEL_FIXTURES_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct fx_buf {
    uint8_t *d;
    size_t   n, cap;
} fx_buf;

static void fx_put(fx_buf *b, const void *p, size_t n) {
    if (b->n + n > b->cap) {
        b->cap = (b->n + n) * 2 + 256;
        b->d = realloc(b->d, b->cap);
        if (!b->d) abort();
    }
    memcpy(b->d + b->n, p, n);
    b->n += n;
}
static void fx_i32(fx_buf *b, int32_t v) {
    uint8_t x[4] = {(uint8_t)v, (uint8_t)(v >> 8), (uint8_t)(v >> 16), (uint8_t)(v >> 24)};
    fx_put(b, x, 4);
}
static void fx_f32(fx_buf *b, float f) {
    uint32_t u;
    memcpy(&u, &f, 4);
    fx_i32(b, (int32_t)u);
}

/* A mesh: positions and triangles (front faces wound as the files do:
 * clockwise seen from outside). */
typedef struct fx_mesh {
    int    nverts, ntris;
    float (*pos)[3];
    int   (*tri)[3];
} fx_mesh;

static int fx_mid(fx_mesh *m, int a, int b) {
    float p[3];
    for (int k = 0; k < 3; k++) p[k] = (m->pos[a][k] + m->pos[b][k]) * 0.5f;
    float l = sqrtf(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    for (int k = 0; k < 3; k++) p[k] /= l;
    for (int i = 0; i < m->nverts; i++)
        if (fabsf(m->pos[i][0] - p[0]) < 1e-6f && fabsf(m->pos[i][1] - p[1]) < 1e-6f &&
            fabsf(m->pos[i][2] - p[2]) < 1e-6f)
            return i;
    memcpy(m->pos[m->nverts], p, sizeof p);
    return m->nverts++;
}

/* Unit icosphere, `level` times subdivided (level 3: 642 vertices, 1280
 * triangles).  Free pos and tri. */
static fx_mesh fx_icosphere(int level) {
    fx_mesh m;
    int maxv = 12, maxt = 20;
    for (int i = 0; i < level; i++) maxv = maxv + maxt * 3 / 2, maxt *= 4;
    m.pos = malloc(sizeof *m.pos * (size_t)maxv);
    m.tri = malloc(sizeof *m.tri * (size_t)maxt);
    const float t = 1.6180339887f;
    const float base[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                               {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    /* counter-clockwise seen from outside */
    const int faces[20][3] = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                              {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                              {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    m.nverts = 12, m.ntris = 20;
    for (int i = 0; i < 12; i++) {
        float l = sqrtf(base[i][0] * base[i][0] + base[i][1] * base[i][1] + base[i][2] * base[i][2]);
        for (int k = 0; k < 3; k++) m.pos[i][k] = base[i][k] / l;
    }
    memcpy(m.tri, faces, sizeof faces);
    for (int lv = 0; lv < level; lv++) {
        int n = m.ntris;
        int (*old)[3] = malloc(sizeof *old * (size_t)n);
        memcpy(old, m.tri, sizeof *old * (size_t)n);
        m.ntris = 0;
        for (int i = 0; i < n; i++) {
            int a = old[i][0], b = old[i][1], c = old[i][2];
            int ab = fx_mid(&m, a, b), bc = fx_mid(&m, b, c), ca = fx_mid(&m, c, a);
            int nt[4][3] = {{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}};
            memcpy(m.tri[m.ntris], nt, sizeof nt);
            m.ntris += 4;
        }
        free(old);
    }
    /* The files wind the other way. */
    for (int i = 0; i < m.ntris; i++) {
        int x = m.tri[i][1];
        m.tri[i][1] = m.tri[i][2], m.tri[i][2] = x;
    }
    return m;
}

/* Options for fx_mdl. */
typedef struct fx_mdl_opts {
    int   skinw, skinh;
    int   skin_group;    /* 0: one single skin; n > 0: one group of n images */
    int   frame_group;   /* 0: one simple frame; n > 0: one group of n poses */
    float radius;        /* mesh is scaled by this */
} fx_mdl_opts;

/* Writes an MDL version 6 image of the mesh.  Texture coordinates are a
 * spherical mapping into the skin; the skin is a checker of two colours. */
static uint8_t *fx_mdl(const fx_mesh *mesh, const fx_mdl_opts *o, size_t *size) {
    fx_buf b = {0};
    float r = o->radius;
    float scale = 2 * r / 255.0f;
    fx_put(&b, "IDPO", 4);
    fx_i32(&b, 6);
    for (int k = 0; k < 3; k++) fx_f32(&b, scale);
    for (int k = 0; k < 3; k++) fx_f32(&b, -r);
    fx_f32(&b, r);                                   /* bounding radius */
    for (int k = 0; k < 3; k++) fx_f32(&b, 0);       /* eye */
    fx_i32(&b, 1);                                   /* numskins */
    fx_i32(&b, o->skinw);
    fx_i32(&b, o->skinh);
    fx_i32(&b, mesh->nverts);
    fx_i32(&b, mesh->ntris);
    fx_i32(&b, 1);                                   /* numframes */
    fx_i32(&b, 0);                                   /* synctype */
    fx_i32(&b, 0);                                   /* flags */
    fx_f32(&b, 1);                                   /* size */
    int nimg = o->skin_group > 0 ? o->skin_group : 1;
    if (o->skin_group > 0) {
        fx_i32(&b, 1);
        fx_i32(&b, o->skin_group);
        for (int i = 0; i < o->skin_group; i++) fx_f32(&b, 0.1f * (i + 1));
    } else {
        fx_i32(&b, 0);
    }
    for (int i = 0; i < nimg; i++)
        for (int y = 0; y < o->skinh; y++)
            for (int x = 0; x < o->skinw; x++) {
                uint8_t c = (uint8_t)((((x >> 2) ^ (y >> 2)) & 1) ? 15 + i : 200 + i);
                fx_put(&b, &c, 1);
            }
    for (int i = 0; i < mesh->nverts; i++) {
        const float *p = mesh->pos[i];
        float u = atan2f(p[1], p[0]) / 6.2831853f + 0.5f, v = acosf(p[2] < -1 ? -1 : p[2] > 1 ? 1 : p[2]) / 3.1415926f;
        fx_i32(&b, 0);
        fx_i32(&b, (int32_t)(u * (o->skinw - 1)));
        fx_i32(&b, (int32_t)(v * (o->skinh - 1)));
    }
    for (int i = 0; i < mesh->ntris; i++) {
        fx_i32(&b, 1);
        for (int k = 0; k < 3; k++) fx_i32(&b, mesh->tri[i][k]);
    }
    int nposes = o->frame_group > 0 ? o->frame_group : 1;
    if (o->frame_group > 0) {
        fx_i32(&b, 1);
        fx_i32(&b, o->frame_group);
        uint8_t bb[8] = {0, 0, 0, 0, 255, 255, 255, 0};
        fx_put(&b, bb, 8);
        for (int i = 0; i < o->frame_group; i++) fx_f32(&b, 0.1f * (i + 1));
    } else {
        fx_i32(&b, 0);
    }
    for (int f = 0; f < nposes; f++) {
        uint8_t bb[8] = {0, 0, 0, 0, 255, 255, 255, 0};
        fx_put(&b, bb, 8);
        char name[16] = "pose";
        name[4] = (char)('0' + f % 10);
        fx_put(&b, name, 16);
        for (int i = 0; i < mesh->nverts; i++) {
            uint8_t v[4];
            for (int k = 0; k < 3; k++) {
                float q = (mesh->pos[i][k] * r * (1.0f - 0.02f * f) + r) / scale;
                int qi = (int)floorf(q + 0.5f);
                v[k] = (uint8_t)(qi < 0 ? 0 : qi > 255 ? 255 : qi);
            }
            v[3] = 0;
            fx_put(&b, v, 4);
        }
    }
    *size = b.n;
    return b.d;
}

/* A small SPR: `frames` single frames, plus (if group > 0) one group of
 * `group` pictures; each picture w x h with a transparent border column. */
static uint8_t *fx_spr(int type, int w, int h, int frames, int group, size_t *size) {
    fx_buf b = {0};
    fx_put(&b, "IDSP", 4);
    fx_i32(&b, 1);
    fx_i32(&b, type);
    fx_f32(&b, (float)(w > h ? w : h));
    fx_i32(&b, w);
    fx_i32(&b, h);
    fx_i32(&b, frames + (group > 0));
    fx_f32(&b, 0);
    fx_i32(&b, 0);
    for (int f = 0; f < frames + (group > 0); f++) {
        int n = 1;
        if (f == frames) {
            fx_i32(&b, 1);
            fx_i32(&b, group);
            for (int i = 0; i < group; i++) fx_f32(&b, 0.05f * (i + 1));
            n = group;
        } else {
            fx_i32(&b, 0);
        }
        for (int k = 0; k < n; k++) {
            fx_i32(&b, -w / 2);
            fx_i32(&b, h / 2);
            fx_i32(&b, w);
            fx_i32(&b, h);
            for (int y = 0; y < h; y++)
                for (int x = 0; x < w; x++) {
                    uint8_t c = x == 0 ? 255 : (uint8_t)(100 + f + k);
                    fx_put(&b, &c, 1);
                }
        }
    }
    *size = b.n;
    return b.d;
}

#endif
