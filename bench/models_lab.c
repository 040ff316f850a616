/* models_lab: the alias-model ideas of Black Book chapter 69 measured
 * (docs/hsr.md, part 6).  Built as a target (build/models_lab); run
 *
 *     ./build/models_lab [DATA_DIR [PICTURE.png]]   (default ../shared/data/librequake)
 *
 * and read; nothing here fails on a time.  Four tables:
 *   1. 200 soldiers at each screen size (640x480, one thread, z-buffer
 *      cleared, models only): time per model for affine, subdiv, masks and
 *      sprite-cache (a miss draws the image, a hit reuses it), and the share
 *      of triangles small enough for the mask table;
 *   2. the same models: pixels written twice and pixels missed or added
 *      against the exact fill (affine: the top-left rule on pixel centres,
 *      test_alias checks it against a reference per pixel);
 *   3. sprite-cache against exact drawing along moving camera paths: holes,
 *      extra and wrong-colour pixels, hit rate, for a few tolerances;
 *   4. e1m1 with its own monsters: frame time and model time per mode over
 *      the views that show models, frames compared with affine, and a
 *      moving path with sprite-cache. */
#define _POSIX_C_SOURCE 200809L  /* clock_gettime */
#include "renderer.h"
#include "ew_util.h"
#include "raster/alias.h"
#include "asset/mdl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum { N = 200, REPS = 25, NB = 5 };
static const float bucket_px[NB] = {5, 10, 20, 40, 80};

static ew_renderer *R;
static const ew_mdl *M;
static ew_xvert *XV;         /* N * numverts */
static ew_alias_xf XF[N];
static ew_sc_slot SLOT[N];

/* This thread's CPU time: the machine is shared, and time spent waiting
 * for a core is not the drawing's. */
static double cpu_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static uint32_t seed;
static float frand(void) {
    seed = seed * 1664525u + 1013904223u;
    return (float)(seed >> 8) / 16777216.0f;
}

/* N soldiers around `dist` (0.85..1.15 of it) spread over the view. */
static void place(ew_model_pose *p, const ew_view *v, float dist, uint32_t s0) {
    seed = s0;
    for (int i = 0; i < N; i++) {
        float z = dist * (0.85f + 0.3f * frand());
        float x = (frand() - 0.5f) * 1.6f * z, y = (frand() - 0.5f) * 1.1f * z;
        memset(&p[i], 0, sizeof p[i]);
        for (int k = 0; k < 3; k++) p[i].origin[k] = v->origin[k] + v->forward[k] * z + v->right[k] * x + v->up[k] * y;
        p[i].angles[1] = frand() * 360;
        p[i].frame = (int)(frand() * (float)M->numframes);
        p[i].ambient = 100, p[i].shade = 80;
    }
}

static void clear_target(void) {
    size_t n = (size_t)R->f.target.width * R->f.target.height;
    memset(R->f.target.zbuf, 0, n * sizeof(float));
    memset(R->f.target.pixels, 0, n * (size_t)R->f.target.bpp);
    memset(&R->f.stats, 0, sizeof R->f.stats);
}

static ew_rows all_rows(void) { return (ew_rows){0, R->f.target.height, &R->f.stats, 1}; }

/* Draws the N models in mode (sprite-cache through the slots). */
static void draw_all(const ew_model_pose *p, int mode) {
    R->f.cfg.alias_raster = mode;
    ew_rows rows = all_rows();
    for (int i = 0; i < N; i++) {
        ew_alias_xf *xf = &XF[i];
        if (!ew_alias_place(&R->f, M, &p[i], xf)) continue;
        /* sprite-cache as the models pass does it (raster/models.c) */
        if (mode == EW_ALIAS_SPRITE_CACHE && ew_sprite_cache_reuse(&R->f, &SLOT[i], M, xf, &p[i], ew_sprite_cache_tol(R->ents.sprite_cache))) {
            ew_sprite_cache_draw(&R->f, &R->zf, &SLOT[i], &rows);
            continue;
        }
        ew_alias_pose_verts(&R->f, M, &p[i], xf, XV + (size_t)i * M->numverts);
        if (mode == EW_ALIAS_SPRITE_CACHE) {
            ew_sprite_cache_redraw(&R->f, &SLOT[i], M, xf, &p[i]);
            if (SLOT[i].use) {
                ew_sprite_cache_draw(&R->f, &R->zf, &SLOT[i], &rows);
                continue;
            }
        }
        ew_alias_draw(&R->f, &R->zf, M, xf, &rows);
    }
}

/* us per model of one drawing of the N models; keeps the best in *best. */
static void time_once(const ew_model_pose *p, int mode, double *best) {
    clear_target();
    double t0 = cpu_ms();
    draw_all(p, mode);
    double t = (cpu_ms() - t0) * 1000.0 / N;
    if (t < *best) *best = t;
}

/* Interleaved, best of REPS each (other work on the machine only adds):
 * transform alone, affine, subdiv, masks, sprite-cache miss (every image
 * drawn), sprite-cache hit (every image reused). */
static void time_modes(const ew_model_pose *p, double us[6]) {
    for (int k = 0; k < 6; k++) us[k] = 1e30;
    for (int rep = 0; rep < REPS; rep++) {
        double t0 = cpu_ms();
        for (int i = 0; i < N; i++) ew_alias_transform(&R->f, M, &p[i], &XF[i], XV + (size_t)i * M->numverts);
        double t = (cpu_ms() - t0) * 1000.0 / N;
        if (t < us[0]) us[0] = t;
        time_once(p, EW_ALIAS_AFFINE, &us[1]);
        time_once(p, EW_ALIAS_SUBDIV, &us[2]);
        time_once(p, EW_ALIAS_MASKS, &us[3]);
        for (int i = 0; i < N; i++) SLOT[i].valid = 0;
        time_once(p, EW_ALIAS_SPRITE_CACHE, &us[4]);
        for (int i = 0; i < N; i++) SLOT[i].reused = 0;
        time_once(p, EW_ALIAS_SPRITE_CACHE, &us[5]);
    }
}

/* Share of the drawn triangles within the mask table's 5x5 box. */
static double mask_share(const ew_model_pose *p) {
    long small = 0, front = 0;
    for (int i = 0; i < N; i++) {
        ew_alias_xf *xf = &XF[i];
        if (!ew_alias_transform(&R->f, M, &p[i], xf, XV + (size_t)i * M->numverts) || !xf->accept) continue;
        for (int t = 0; t < M->numtris; t++) {
            const ew_avert *a = &xf->xv[M->tris[t].v[0]].sv, *b = &xf->xv[M->tris[t].v[1]].sv,
                           *c = &xf->xv[M->tris[t].v[2]].sv;
            if (!ew_alias_tri_visible(a, b, c)) continue;
            front++;
            int x0 = a->x, x1 = a->x, y0 = a->y, y1 = a->y;
            const ew_avert *o[2] = {b, c};
            for (int k = 0; k < 2; k++) {
                if (o[k]->x < x0) x0 = o[k]->x;
                if (o[k]->x > x1) x1 = o[k]->x;
                if (o[k]->y < y0) y0 = o[k]->y;
                if (o[k]->y > y1) y1 = o[k]->y;
            }
            small += x1 - x0 < EW_MASK_BOX && y1 - y0 < EW_MASK_BOX;
        }
    }
    return front ? (double)small / front : 0;
}

/* Coverage (z-buffer written) and pixel writes of one drawing of the N models. */
typedef struct cover {
    uint8_t *in, *pix;
    long     writes, covered;
} cover;

static void take(cover *c) {
    size_t n = (size_t)R->f.target.width * R->f.target.height;
    c->covered = 0;
    for (size_t i = 0; i < n; i++) {
        c->in[i] = R->f.target.zbuf[i] != 0;
        c->covered += c->in[i];
    }
    memcpy(c->pix, R->f.target.pixels, n);
    c->writes = R->f.stats.alias_pixels;
}

static void tables_1_2(const ew_view *v, float units_tall) {
    static const char *names[4] = {"affine", "subdiv", "masks", "sprite-cache"};
    static const int modes[4] = {EW_ALIAS_AFFINE, EW_ALIAS_SUBDIV, EW_ALIAS_MASKS, EW_ALIAS_SPRITE_CACHE};
    size_t n = (size_t)R->f.target.width * R->f.target.height;
    cover cv[4];
    for (int k = 0; k < 4; k++) cv[k].in = malloc(n), cv[k].pix = malloc(n);
    ew_model_pose p[N];
    printf("\n## 1. time per model, 200 soldiers, 640x480, one thread (best of %d, CPU us/model)\n\n", REPS);
    printf("| height px | tris/model | in 5x5 box | transform only | affine | subdiv | masks | sprite miss | sprite hit "
           "| sprite 1 miss + 3 hits | masks/affine | hit/affine |\n");
    printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    double cov_rows[NB][4][4];
    for (int b = 0; b < NB; b++) {
        float dist = units_tall * v->yscale / bucket_px[b];
        place(p, v, dist, 99u + (uint32_t)b);
        double share = mask_share(p);
        double t[6];
        time_modes(p, t);
        double tx = t[0], us[3] = {t[1], t[2], t[3]}, miss = t[4], hit = t[5];
        clear_target();
        draw_all(p, EW_ALIAS_AFFINE);
        int tris = R->f.stats.alias_tris;
        printf("| %.0f | %.0f | %.0f%% | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f |\n",
               bucket_px[b], (double)tris / N, share * 100, tx, us[0], us[1], us[2], miss, hit,
               (miss + 3 * hit) / 4, us[2] / us[0], hit / us[0]);
        fflush(stdout);
        /* Table 2's figures: coverage of each mode's first drawing. */
        for (int k = 0; k < 4; k++) {
            if (k == 3)
                for (int i = 0; i < N; i++) SLOT[i].valid = 0;
            clear_target();
            draw_all(p, modes[k]);
            take(&cv[k]);
        }
        for (int k = 0; k < 4; k++) {
            long missed = 0, extra = 0, colour = 0;
            for (size_t i = 0; i < n; i++) {
                missed += cv[0].in[i] && !cv[k].in[i];
                extra += !cv[0].in[i] && cv[k].in[i];
                colour += cv[0].in[i] && cv[k].in[i] && cv[0].pix[i] != cv[k].pix[i];
            }
            cov_rows[b][k][0] = (double)(cv[k].writes - cv[k].covered);
            cov_rows[b][k][1] = (double)missed, cov_rows[b][k][2] = (double)extra;
            cov_rows[b][k][3] = (double)cv[0].covered;
            (void)colour;
        }
    }
    printf("\n## 2. pixels against the exact fill (affine), same 200 soldiers, first frame\n\n");
    printf("writes - distinct = pixels written twice or more (a nearer triangle of the same model over a\n"
           "farther one passes the z test again; sprite-cache composites each pixel once);\n"
           "missed / extra: covered by the exact fill and not by the mode / the other way.\n\n");
    printf("| height px | exact px | affine twice | subdiv twice | subdiv missed | subdiv extra | masks twice | masks "
           "missed | masks extra | sprite twice | sprite missed | sprite extra |\n");
    printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (int b = 0; b < NB; b++)
        printf("| %.0f | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f |\n", bucket_px[b],
               cov_rows[b][0][3], cov_rows[b][0][0], cov_rows[b][1][0], cov_rows[b][1][1], cov_rows[b][1][2],
               cov_rows[b][2][0], cov_rows[b][2][1], cov_rows[b][2][2], cov_rows[b][3][0], cov_rows[b][3][1],
               cov_rows[b][3][2]);
    for (int k = 0; k < 4; k++) free(cv[k].in), free(cv[k].pix);
    (void)names;
}

/* ---- 3. sprite-cache along camera paths ----------------------------------- */

typedef struct path {
    const char *name;
    float speed, turn;  /* units/s sideways, degrees/s of yaw */
    int animate;        /* soldiers run through their frames at 10 a second */
} path;

static void table_3(const ew_camera *start, float units_tall, const char *png, const uint8_t *pal) {
    static const path paths[] = {
        {"still camera, animated", 0, 0, 1},
        {"walk 100 u/s, still poses", 100, 0, 0},
        {"walk 100 u/s + turn 10 deg/s, animated", 100, 10, 1},
        {"run 320 u/s + turn 45 deg/s, animated", 320, 45, 1},
    };
    static const ew_sc_tol tols[] = {
        {2.0f, 0.03f, 8, 3},   /* the default */
        {2.0f, 0.03f, 8, 1},   /* reused once */
        {5.0f, 0.08f, 16, 7},  /* loose */
    };
    enum { FRAMES = 60 };
    const float fps = 30;
    size_t n = (size_t)R->f.target.width * R->f.target.height;
    cover ex = {malloc(n), malloc(n), 0, 0}, sc = {malloc(n), malloc(n), 0, 0};
    printf("\n## 3. sprite-cache against exact drawing along camera paths (200 soldiers 20-40 px, %d frames at "
           "%.0f fps)\n\n", FRAMES, fps);
    printf("| path | angle, scale, light, reuse | hits | holes %% | extra %% | wrong colour %% | worst frame "
           "holes+extra %% |\n|---|---|---|---|---|---|---|\n");
    ew_view v0;
    ew_view_setup(&v0, start, R->f.target.width, R->f.target.height);
    ew_model_pose base[N], p[N];
    /* test_models' 200-soldier scene: 450..900 units ahead (40..20 px tall). */
    seed = 99;
    for (int i = 0; i < N; i++) {
        float f[3];
        for (int k = 0; k < 3; k++) seed = seed * 1664525u + 1013904223u, f[k] = (float)(seed >> 8) / 16777216.0f;
        float z = 450 + f[0] * 450, x = (f[1] - 0.5f) * 1.4f * z, y = (f[2] - 0.5f) * 0.9f * z;
        memset(&base[i], 0, sizeof base[i]);
        for (int k = 0; k < 3; k++)
            base[i].origin[k] = v0.origin[k] + v0.forward[k] * z + v0.right[k] * x + v0.up[k] * y;
        base[i].angles[1] = (float)(seed % 360);
        base[i].frame = (int)(seed % (uint32_t)M->numframes);
        base[i].ambient = 100, base[i].shade = 80;
    }
    (void)units_tall;
    R->f.cfg.alias_threshold = 40;
    for (int i = 0; i < N; i++) ew_sprite_cache_slot_free(&SLOT[i]);  /* table 1's images were larger */
    for (size_t pi = 0; pi < sizeof paths / sizeof *paths; pi++)
        for (size_t ti = 0; ti < sizeof tols / sizeof *tols; ti++) {
            ew_sprite_cache_set_tol(&R->ents.sprite_cache, &tols[ti]);
            for (int i = 0; i < N; i++) SLOT[i].valid = 0;
            long hits = 0, misses = 0, holes = 0, extra = 0, colour = 0, exact = 0;
            double worst = 0;
            for (int f = 0; f < FRAMES; f++) {
                float t = (float)f / fps;
                ew_camera cam = *start;
                cam.angles[1] += paths[pi].turn * t;
                for (int k = 0; k < 3; k++) cam.origin[k] += v0.right[k] * paths[pi].speed * t;
                ew_view_setup(&R->f.view, &cam, R->f.target.width, R->f.target.height);
                for (int i = 0; i < N; i++) {
                    p[i] = base[i];
                    if (paths[pi].animate) p[i].frame = (base[i].frame + (int)(t * 10)) % M->numframes;
                }
                clear_target();
                draw_all(p, EW_ALIAS_AFFINE);
                take(&ex);
                clear_target();
                draw_all(p, EW_ALIAS_SPRITE_CACHE);
                take(&sc);
                for (int i = 0; i < N; i++)
                    if (SLOT[i].use) hits += SLOT[i].hit, misses += !SLOT[i].hit;
                long h = 0, e = 0;
                for (size_t i = 0; i < n; i++) {
                    h += ex.in[i] && !sc.in[i];
                    e += !ex.in[i] && sc.in[i];
                    colour += ex.in[i] && sc.in[i] && ex.pix[i] != sc.pix[i];
                }
                holes += h, extra += e, exact += ex.covered;
                double w = ex.covered ? 100.0 * (double)(h + e) / (double)ex.covered : 0;
                if (w > worst) worst = w;
            }
            printf("| %s | %.0f deg, %.0f%%, %d, %d | %.0f%% | %.2f | %.2f | %.2f | %.2f |\n", paths[pi].name,
                   (double)tols[ti].angle_deg, (double)tols[ti].scale * 100, tols[ti].light, tols[ti].max_reuse,
                   100.0 * (double)hits / (double)(hits + misses), 100.0 * (double)holes / (double)exact,
                   100.0 * (double)extra / (double)exact, 100.0 * (double)colour / (double)exact, worst);
            fflush(stdout);
        }
    {
        size_t bytes = 0, held = 0;
        int images = 0;
        for (int i = 0; i < N; i++)
            if (SLOT[i].cap) {
                bytes += (size_t)SLOT[i].w * SLOT[i].h * (size_t)(SLOT[i].bpp + 4), images++;
                held += SLOT[i].cap * (size_t)(SLOT[i].bpp + 4);
            }
        printf("\nsprite-cache memory after the last path: %d images, %zu bytes (%.0f each: 1 byte of colour and 4 "
               "of 1/z a pixel of the model's box, 8-bit); %zu bytes held (each slot keeps its largest)\n",
               images, bytes, images ? (double)bytes / images : 0.0, held);
    }
    ew_sc_tol d = ew_sprite_cache_tol_default();
    ew_sprite_cache_set_tol(&R->ents.sprite_cache, &d);
    if (png) {
        /* A picture: the walking path's third frame (the images of frame 0
         * reused twice): exact | sprite-cache | the difference (holes
         * white, extra pixels red, wrong colours grey), the middle of the
         * view at 2x. */
        for (int i = 0; i < N; i++) SLOT[i].valid = 0;
        for (int f = 0; f < 3; f++) {
            float t = (float)f / fps;
            ew_camera cam = *start;
            cam.angles[1] += 10 * t;
            for (int k = 0; k < 3; k++) cam.origin[k] += v0.right[k] * 100 * t;
            ew_view_setup(&R->f.view, &cam, R->f.target.width, R->f.target.height);
            for (int i = 0; i < N; i++) p[i] = base[i], p[i].frame = (base[i].frame + (int)(t * 10)) % M->numframes;
            clear_target();
            draw_all(p, EW_ALIAS_AFFINE);
            take(&ex);
            clear_target();
            draw_all(p, EW_ALIAS_SPRITE_CACHE);
            take(&sc);
        }
        enum { CW = 240, CH = 180, Z = 2 };
        int W = R->f.target.width, H = R->f.target.height, cx0 = (W - CW) / 2, cy0 = (H - CH) / 2;
        int ow = 3 * CW * Z + 2 * 4, oh = CH * Z;
        uint8_t *out = calloc((size_t)ow * oh, 1);
        for (int y = 0; y < oh; y++)
            for (int x = 0; x < CW * Z; x++) {
                size_t i = (size_t)(cy0 + y / Z) * W + cx0 + x / Z;
                uint8_t *row = out + (size_t)y * ow;
                row[x] = ex.pix[i];
                row[CW * Z + 4 + x] = sc.pix[i];
                row[2 * (CW * Z + 4) + x] = ex.in[i] && !sc.in[i]   ? 254    /* white */
                                            : !ex.in[i] && sc.in[i] ? 251    /* red */
                                            : ex.in[i] && ex.pix[i] != sc.pix[i] ? 8 /* grey */
                                                                                 : 0;
            }
        ew_error err;
        if (ew_write_png(png, out, ow, oh, pal, &err)) fprintf(stderr, "models_lab: %s\n", err.msg);
        else printf("\nwrote %s\n", png);
        free(out);
    }
    free(ex.in), free(ex.pix), free(sc.in), free(sc.pix);
}

/* ---- 5. stack-based mesh rendering ------------------------------------------
 * The book's pointer to Bar-Yehuda and Gotsman: the mesh as a stream of
 * commands that push a vertex (transformed as it is pushed) into a small
 * stack of K slots, and draw a triangle from three slots, so every vertex
 * the drawing touches is in a tiny array.  Here the stream is compiled by
 * simulating K slots with least-recently-used replacement over the
 * triangles in a greedy order (next: the triangle with most of its
 * vertices in the slots); a vertex evicted and needed again is pushed (and
 * transformed) again: the time/space trade.  Lab only, against the same
 * vertex code drawing from a pool (every vertex transformed once, triangles
 * indexing it), with the file's triangle order and a shuffled one.  Models
 * wholly in view only (no clipping in either). */

typedef struct lab_v {
    ew_avert sv;
    int32_t  sback;
} lab_v;

typedef struct stream {
    int  ncmd, npush;
    int *cmd;  /* push: slot << 20 | vertex (>= 0, op 0); triangle: -(1 + index) followed by 3 slots */
} stream;

static int32_t snap_px(float f, int32_t hi) {
    float x = f > 0 ? f : 0;
    x = x < (float)hi ? x : (float)hi;
    return (int32_t)(x + 0.5f);
}

static inline void lab_vert(const ew_alias_xf *xf, const ew_mdl_pose *pose, const ew_model_pose *p, int i,
                            lab_v *o) {
    const uint8_t *bv = pose->verts[i].v;
    float q[3];
    for (int k = 0; k < 3; k++) q[k] = xf->bm[k][0] * bv[0] + xf->bm[k][1] * bv[1] + xf->bm[k][2] * bv[2] + xf->bt[k];
    const float *n = pose->normals[i];
    float dot = n[0] * xf->lm[0] + n[1] * xf->lm[1] + n[2] * xf->lm[2];
    o->sv.l = ew_alias_light_row(p->ambient + (dot > 0 ? (int)((float)p->shade * dot) : 0));
    const ew_mdl_st *st = &M->st[i];
    o->sv.s = st->s << 16 < xf->smax ? st->s << 16 : xf->smax;
    o->sv.t = st->t << 16 < xf->tmax ? st->t << 16 : xf->tmax;
    int32_t sb = (st->s + (st->onseam ? M->skinwidth / 2 : 0)) << 16;
    o->sback = sb < xf->smax ? sb : xf->smax;
    float zi = 1.0f / q[2];
    o->sv.zi = zi;
    o->sv.x = snap_px(R->f.view.xcenter + R->f.view.xscale * q[0] * zi, R->f.target.width - 1);
    o->sv.y = snap_px(R->f.view.ycenter - R->f.view.yscale * q[1] * zi, R->f.target.height - 1);
}

static inline void lab_tri(ew_araster *ra, const ew_mdl_tri *t, const lab_v *a, const lab_v *b, const lab_v *c) {
    ew_avert x = a->sv, y = b->sv, z = c->sv;
    if (!ew_alias_tri_visible(&x, &y, &z)) return;
    if (!t->facesfront) x.s = a->sback, y.s = b->sback, z.s = c->sback;
    ew_alias_affine_tri(ra, &x, &y, &z);
}

static void lab_raster(ew_araster *ra, const ew_alias_xf *xf) {
    memset(ra, 0, sizeof *ra);
    ra->target = &R->f.target;
    ra->rgba = R->f.target.rgba;
    ra->x0 = 0, ra->y0 = 0, ra->x1 = R->f.target.width, ra->y1 = R->f.target.height;
    ra->skin = M->skinpixels + (size_t)xf->image * M->skinwidth * M->skinheight;
    ra->skinw = M->skinwidth, ra->skinh = M->skinheight;
    ra->colormap = R->f.colormap;
}

static void draw_pool(const ew_model_pose *p, const ew_mdl_tri *tris, lab_v *pool) {
    for (int i = 0; i < N; i++) {
        ew_alias_xf xf;
        if (!ew_alias_place(&R->f, M, &p[i], &xf) || !xf.accept) continue;
        const ew_mdl_pose *pose = &M->poses[xf.pose];
        for (int v = 0; v < M->numverts; v++) lab_vert(&xf, pose, &p[i], v, &pool[v]);
        ew_araster ra;
        lab_raster(&ra, &xf);
        for (int t = 0; t < M->numtris; t++)
            lab_tri(&ra, &tris[t], &pool[tris[t].v[0]], &pool[tris[t].v[1]], &pool[tris[t].v[2]]);
    }
}

static void draw_stack(const ew_model_pose *p, const stream *st) {
    lab_v stack[64];
    for (int i = 0; i < N; i++) {
        ew_alias_xf xf;
        if (!ew_alias_place(&R->f, M, &p[i], &xf) || !xf.accept) continue;
        const ew_mdl_pose *pose = &M->poses[xf.pose];
        ew_araster ra;
        lab_raster(&ra, &xf);
        for (int k = 0; k < st->ncmd;) {
            int c = st->cmd[k++];
            if (c >= 0) {
                lab_vert(&xf, pose, &p[i], c & 0xFFFFF, &stack[c >> 20]);
            } else {
                const ew_mdl_tri *t = &M->tris[-c - 1];
                lab_tri(&ra, t, &stack[st->cmd[k]], &stack[st->cmd[k + 1]], &stack[st->cmd[k + 2]]);
                k += 3;
            }
        }
    }
}

static stream compile_stream(int K) {
    stream s = {0, 0, malloc(sizeof(int) * (size_t)M->numtris * 7)};
    int slot_v[64], slot_age[64], clock = 0;
    for (int k = 0; k < K; k++) slot_v[k] = -1, slot_age[k] = 0;
    uint8_t *done = calloc((size_t)M->numtris, 1);
    for (int n = 0; n < M->numtris; n++) {
        int best = -1, best_in = -1;
        for (int t = 0; t < M->numtris; t++) {  /* greedy: most vertices already in the slots */
            if (done[t]) continue;
            int in = 0;
            for (int j = 0; j < 3; j++)
                for (int k = 0; k < K; k++) in += slot_v[k] == M->tris[t].v[j];
            if (in > best_in) best_in = in, best = t;
            if (in == 3) break;
        }
        done[best] = 1;
        int slots[3];
        for (int j = 0; j < 3; j++) {
            int v = M->tris[best].v[j], at = -1;
            for (int k = 0; k < K; k++)
                if (slot_v[k] == v) at = k;
            if (at < 0) {  /* push into the least recently used slot not used by this triangle */
                int lru = -1;
                for (int k = 0; k < K; k++) {
                    int mine = 0;
                    for (int q = 0; q < j; q++) mine |= slots[q] == k;
                    if (!mine && (lru < 0 || slot_age[k] < slot_age[lru])) lru = k;
                }
                at = lru, slot_v[at] = v;
                s.cmd[s.ncmd++] = at << 20 | v;
                s.npush++;
            }
            slot_age[at] = ++clock;
            slots[j] = at;
        }
        s.cmd[s.ncmd++] = -(1 + best);
        for (int j = 0; j < 3; j++) s.cmd[s.ncmd++] = slots[j];
    }
    free(done);
    return s;
}

static void table_5(const ew_view *v, float units_tall) {
    enum { NK = 3 };
    static const int ks[NK] = {8, 16, 32};
    stream st[NK];
    for (int i = 0; i < NK; i++) st[i] = compile_stream(ks[i]);
    ew_mdl_tri *shuffled = malloc(sizeof *shuffled * (size_t)M->numtris);
    memcpy(shuffled, M->tris, sizeof *shuffled * (size_t)M->numtris);
    seed = 5;
    for (int i = M->numtris - 1; i > 0; i--) {
        int j = (int)(frand() * (float)(i + 1));
        if (j > i) j = i;
        ew_mdl_tri t = shuffled[i];
        shuffled[i] = shuffled[j], shuffled[j] = t;
    }
    lab_v *pool = malloc(sizeof *pool * (size_t)M->numverts);
    printf("\n## 5. stack-based rendering (lab): CPU us/model, models wholly in view, best of %d\n\n", REPS);
    printf("vertex transforms per model: pool %d; stack of 8: %d, 16: %d, 32: %d\n\n", M->numverts, st[0].npush,
           st[1].npush, st[2].npush);
    printf("| height px | pool, file order | pool, shuffled | stack 8 | stack 16 | stack 32 | stack 16 / pool | "
           "coverage differs, stack 16 vs pool |\n|---|---|---|---|---|---|---|---|\n");
    ew_model_pose p[N];
    for (int b = 0; b < NB; b++) {
        place(p, v, units_tall * v->yscale / bucket_px[b], 99u + (uint32_t)b);
        double us[5] = {1e30, 1e30, 1e30, 1e30, 1e30};
        for (int rep = 0; rep < REPS; rep++)
            for (int k = 0; k < 5; k++) {
                clear_target();
                double t0 = cpu_ms();
                if (k == 0) draw_pool(p, M->tris, pool);
                else if (k == 1) draw_pool(p, shuffled, pool);
                else draw_stack(p, &st[k - 2]);
                double t = (cpu_ms() - t0) * 1000.0 / N;
                if (t < us[k]) us[k] = t;
            }
        /* The same pixels either way (the order of equal depths aside). */
        size_t n = (size_t)R->f.target.width * R->f.target.height;
        float *z0 = malloc(n * sizeof *z0);
        clear_target();
        draw_pool(p, M->tris, pool);
        memcpy(z0, R->f.target.zbuf, n * sizeof *z0);
        long px = R->f.stats.alias_pixels;
        clear_target();
        draw_stack(p, &st[1]);
        long differ = 0;
        for (size_t i = 0; i < n; i++) differ += (z0[i] != 0) != (R->f.target.zbuf[i] != 0);
        free(z0);
        (void)px;
        printf("| %.0f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %ld |\n", bucket_px[b], us[0], us[1], us[2], us[3],
               us[4], us[3] / us[0], differ);
        fflush(stdout);
    }
    free(pool), free(shuffled);
    for (int i = 0; i < NK; i++) free(st[i].cmd);
}

/* ---- 4. e1m1 with its monsters --------------------------------------------- */

static void table_4(ew_assets *a, const char *data) {
    ew_error err;
    char map[1200];
    snprintf(map, sizeof map, "%s/maps/e1m1.bsp", data);
    ew_scene *sc = ew_scene_create_from_map(a->world, map, data, &err);
    if (!sc) {
        printf("e1m1 scene: %s\n", err.msg);
        return;
    }
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                            .colormap = a->colormap, .width = 640, .height = 480,
                                                            .threads = 1},
                                        &err);
    if (!r) {
        ew_scene_destroy(sc);
        return;
    }
    ew_set_scene(r, sc);
    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(a->world, views), sel[EW_MAX_VIEWS], ns = 0, most = -1, most_models = 0;
    for (int i = 0; i < nv; i++) {
        ew_set_alias_raster(r, EW_ALIAS_AFFINE, 40);
        ew_render(r, &views[i], NULL);
        if (r->f.stats.alias_tris > 0) sel[ns++] = i;
        if (r->f.stats.alias_tris > most_models) most_models = r->f.stats.alias_tris, most = i;
    }
    static const char *names[4] = {"affine", "subdiv", "masks", "sprite-cache"};
    static const int modes[4] = {EW_ALIAS_AFFINE, EW_ALIAS_SUBDIV, EW_ALIAS_MASKS, EW_ALIAS_SPRITE_CACHE};
    size_t n = (size_t)r->f.target.width * r->f.target.height;
    uint8_t *ref = malloc(n * (size_t)ns);
    printf("\n## 4. e1m1 with its monsters, 640x480, one thread: the %d views that show models\n\n", ns);
    printf("Per view, best of 9 renders of each mode, interleaved; sprite-cache's first render of a view draws the "
           "images (misses), the others reuse them (hits), so its best is the reuse.\n\n");
    printf("| mode | entities drawn | triangles | model px | CPU ms frames (sum) | ms models (sum) | px differing from "
           "affine | sprite hits/misses |\n|---|---|---|---|---|---|---|---|\n");
    double ms_models[4] = {0}, ms_total[4] = {0};
    long tris[4] = {0}, px[4] = {0}, diff[4] = {0}, hits[4] = {0}, misses[4] = {0}, drawn[4] = {0};
    for (int s = 0; s < ns; s++) {
        double bm[4] = {1e30, 1e30, 1e30, 1e30}, bt[4] = {1e30, 1e30, 1e30, 1e30};
        for (int rep = 0; rep < 9; rep++)
            for (int k = 0; k < 4; k++) {
                ew_set_alias_raster(r, modes[k], 40);
                double t0 = cpu_ms();
                ew_render(r, &views[sel[s]], NULL);
                double t = cpu_ms() - t0;
                if (r->f.stats.ms_models < bm[k]) bm[k] = r->f.stats.ms_models;
                if (t < bt[k]) bt[k] = t;
                if (rep == 0) {
                    tris[k] += r->f.stats.alias_tris, px[k] += r->f.stats.alias_pixels;
                    drawn[k] += r->f.stats.entities_drawn;
                    if (k == 0) memcpy(ref + n * (size_t)s, r->f.target.pixels, n);
                    for (size_t i = 0; i < n; i++) diff[k] += r->f.target.pixels[i] != ref[n * (size_t)s + i];
                }
                hits[k] += r->f.stats.alias_sprite_hits, misses[k] += r->f.stats.alias_sprite_misses;
            }
        for (int k = 0; k < 4; k++) ms_models[k] += bm[k], ms_total[k] += bt[k];
    }
    for (int k = 0; k < 4; k++)
        printf("| %s | %ld | %ld | %ld | %.2f | %.2f | %ld | %ld/%ld |\n", names[k], drawn[k], tris[k], px[k],
               ms_total[k], ms_models[k], diff[k], hits[k], misses[k]);
    /* A moving path: from the view with the most model triangles, walking
     * sideways at 100 u/s and turning 10 deg/s at 30 fps, monsters animating;
     * sprite-cache frame against the affine frame of the same instant. */
    if (most >= 0) {
        enum { FRAMES = 60 };
        uint8_t *exact = malloc(n);
        long diff = 0, hits = 0, misses = 0, model_px = 0, worst = 0;
        ew_view v0;
        ew_view_setup(&v0, &views[most], 640, 480);
        for (int f = 0; f < FRAMES; f++) {
            ew_camera cam = views[most];
            float t = (float)f / 30;
            cam.time = t;
            cam.angles[1] += 10 * t;
            for (int k = 0; k < 3; k++) cam.origin[k] += v0.right[k] * 100 * t;
            ew_set_alias_raster(r, EW_ALIAS_AFFINE, 40);
            ew_render(r, &cam, NULL);
            memcpy(exact, r->f.target.pixels, n);
            model_px += r->f.stats.alias_pixels;
            ew_set_alias_raster(r, EW_ALIAS_SPRITE_CACHE, 40);
            ew_render(r, &cam, NULL);
            hits += r->f.stats.alias_sprite_hits, misses += r->f.stats.alias_sprite_misses;
            long d = 0;
            for (size_t i = 0; i < n; i++) d += r->f.target.pixels[i] != exact[i];
            diff += d;
            if (d > worst) worst = d;
        }
        printf("\ne1m1 path from view %d (sideways 100 u/s, turn 10 deg/s, 30 fps, %d frames): sprite-cache %ld hits, "
               "%ld misses; %ld pixels differ from exact drawing (%.1f%% of the %ld model pixels drawn exactly), "
               "worst frame %ld\n",
               most, FRAMES, hits, misses, diff, model_px ? 100.0 * (double)diff / (double)model_px : 0.0,
               model_px, worst);
        free(exact);
    }
    free(ref);
    ew_renderer_destroy(r);
    ew_scene_destroy(sc);
}

int main(int argc, char **argv) {
    const char *data = argc > 1 ? argv[1] : "../shared/data/librequake";
    ew_error err;
    char path[1200];
    snprintf(path, sizeof path, "%s/maps/e1m1.bsp", data);
    ew_assets *a = ew_assets_create(path, NULL, &err);
    if (!a) {
        fprintf(stderr, "models_lab: %s\n", err.msg);
        return 1;
    }
    snprintf(path, sizeof path, "%s/progs/soldier.mdl", data);
    uint8_t *bytes;
    size_t size;
    if (ew_read_file(path, &bytes, &size, &err)) {
        fprintf(stderr, "models_lab: %s\n", err.msg);
        return 1;
    }
    ew_mdl *soldier = ew_mdl_load(bytes, size, "soldier.mdl", &err);
    free(bytes);
    R = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette, .colormap = a->colormap,
                                               .width = 640, .height = 480, .threads = 1},
                           &err);
    if (!soldier || !R) {
        fprintf(stderr, "models_lab: %s\n", err.msg);
        return 1;
    }
    M = soldier;
    XV = malloc(sizeof *XV * (size_t)N * (size_t)M->numverts);
    size_t table_bytes;
    ew_alias_mask_table(&table_bytes);
    float units_tall = M->poses[0].maxs[2] - M->poses[0].mins[2];
    printf("# models_lab: soldier.mdl (%d triangles, %d vertices, %.0f units tall); mask table %zu bytes "
           "(%d^3 vertex triples of a %dx%d box)\n",
           M->numtris, M->numverts, (double)units_tall, table_bytes, EW_MASK_BOX * EW_MASK_BOX, EW_MASK_BOX,
           EW_MASK_BOX);
    ew_camera views[EW_MAX_VIEWS];
    ew_benchmark_views(a->world, views);
    ew_view_setup(&R->f.view, &views[0], R->f.target.width, R->f.target.height);
    /* Models only: the world's z-fill is off (nothing to fill from). */
    R->zf.all = 1;
    R->f.cfg.alias_threshold = 1000;  /* table 1: every size goes through the cache */
    ew_sc_tol tol = ew_sprite_cache_tol_default();
    ew_sprite_cache_set_tol(&R->ents.sprite_cache, &tol);  /* the tolerances live in the renderer */
    tables_1_2(&R->f.view, units_tall);
    table_3(&views[0], units_tall, argc > 2 ? argv[2] : NULL, a->palette);
    ew_view_setup(&R->f.view, &views[0], R->f.target.width, R->f.target.height);
    if (!getenv("MODELS_LAB_SKIP_STACK")) table_5(&R->f.view, units_tall);
    R->zf.all = 0;
    for (int i = 0; i < N; i++) ew_sprite_cache_slot_free(&SLOT[i]);
    table_4(a, data);
    free(XV);
    ew_mdl_free(soldier);
    ew_renderer_destroy(R);
    ew_assets_destroy(a);
    return 0;
}
