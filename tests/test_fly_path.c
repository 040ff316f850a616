/*
 * edgewise fly's default path stays in the open (issue 33, item 4): on every
 * shared LibreQuake map, `fly` at a low frame rate and a small size writes
 * its cameras (--cameras) and a y4m; then
 *   - no frame's eye is in solid or in the sky outside the map (point
 *     contents of the rendering hull, ew_point_contents);
 *   - no frame is nearly black (mean luma of the Y plane under 1% of full;
 *     320x200 frames) where what the eye sees is lit: a nearly black frame
 *     is drawn again here with its textures unlit (EW_DEBUG_TEXTURES) and
 *     fails when that too is dark (luma under 8): the eye sees nothing, not
 *     the map's dark light (the LibreQuake maps have unlit corridors and
 *     walls, frames 0.4-3% bright that are right);
 *   - `--path straight` is the old spline: it starts at the first view and
 *     is accepted.
 */
#define _DEFAULT_SOURCE
#include "util.h"
#include "edgewise_lab.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define W 320
#define H 200
#ifndef FPS
#define FPS "10"
#endif
#define DARK_LUMA 2.55  /* mean luma under 1% of full: nearly black */
#define LIT_LUMA 8.0    /* an unlit frame at least this bright shows the world */

static char tmpdir[256];

typedef struct cam_line {
    double t, pos[3], ang[3];
} cam_line;

/* The cameras file: its lines, their count (or -1). */
static int read_cameras(const char *path, cam_line **out) {
    FILE *f = fopen(path, "r");
    if (!f) return -1;
    int n = 0, cap = 0;
    cam_line *c = NULL;
    long k;
    cam_line l;
    while (fscanf(f, "%ld %lf %lf %lf %lf %lf %lf %lf", &k, &l.t, &l.pos[0], &l.pos[1], &l.pos[2], &l.ang[0],
                  &l.ang[1], &l.ang[2]) == 8) {
        if (n == cap) {
            cap = cap ? cap * 2 : 256;
            c = realloc(c, sizeof *c * (size_t)cap);
            if (!c) break;
        }
        c[n++] = l;
    }
    fclose(f);
    *out = c;
    return c ? n : -1;
}

/* Mean of each frame's Y plane of a W x H y4m; the number of frames. */
static int y4m_means(const char *path, double **out) {
    FILE *f = fopen(path, "rb");
    if (!f) return -1;
    char line[256];
    if (!fgets(line, sizeof line, f)) {
        fclose(f);
        return -1;
    }
    size_t fsz = (size_t)W * H * 3 / 2;
    uint8_t *buf = malloc(fsz);
    int n = 0, cap = 0;
    double *m = NULL;
    while (buf && fgets(line, sizeof line, f) && !strcmp(line, "FRAME\n") && fread(buf, 1, fsz, f) == fsz) {
        double s = 0;
        for (int i = 0; i < W * H; i++) s += buf[i];
        if (n == cap) {
            cap = cap ? cap * 2 : 256;
            m = realloc(m, sizeof *m * (size_t)cap);
            if (!m) break;
        }
        m[n++] = s / (W * H);
    }
    free(buf);
    fclose(f);
    *out = m;
    return m ? n : -1;
}

/* Mean luma of camera v rendered at W x H (the frame's palette or RGBA). */
static double frame_luma(ew_renderer *r, const ew_camera *v) {
    ew_camera c = *v;
    if (ew_render(r, &c, NULL) < 0) return -1;
    const uint8_t *px = ew_frame_pixels(r), *pal = ew_frame_palette(r);
    const uint8_t *rgba = (const uint8_t *)ew_frame_rgba(r);
    double s = 0;
    for (int i = 0; i < W * H; i++) {
        const uint8_t *p = px ? pal + 3 * px[i] : rgba + 4 * i;
        s += 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
    }
    return s / (W * H);
}

static void check_map(const char *name, const char *data, const char *path_kind, int *solid_frames,
                      int *dark_frames) {
    ew_assets *a = ew_t_load_map(name);
    if (!a) return;
    char y4m[512], cams[512];
    snprintf(y4m, sizeof y4m, "%s/%s_%s.y4m", tmpdir, name, path_kind);
    snprintf(cams, sizeof cams, "%s/%s_%s.cam", tmpdir, name, path_kind);
    ew_t_run r;
    const char *args[] = { "fly", name, "--data", data, "--path", path_kind, "--fps", FPS, "--size", "320x200",
                           "--cameras", cams, "--out", y4m, "--quiet", NULL };
    const char *args_default[] = { "fly", name, "--data", data, "--fps", FPS, "--size", "320x200",
                                   "--cameras", cams, "--out", y4m, "--quiet", NULL };
    ew_t_run_cli(&r, tmpdir, strcmp(path_kind, "views") ? args : args_default);
    CHECK(r.status == 0, "%s: fly --path %s: exit %d: %s", name, path_kind, r.status, r.err);
    cam_line *c = NULL;
    double *luma = NULL;
    int n = read_cameras(cams, &c), nf = y4m_means(y4m, &luma);
    CHECK(n > 0 && nf == n, "%s: %d cameras, %d frames", name, n, nf);

    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(a->world, views);
    ew_error err = { "" };
    ew_renderer *rd = ew_renderer_create(&(ew_renderer_desc){ .world = a->world, .palette = a->palette,
            .colormap = a->colormap, .width = W, .height = H, .threads = 1 }, &err);
    CHECK(rd != NULL, "%s: renderer: %s", name, err.msg);
    int solid = 0, dark = 0;
    for (int i = 0; rd && i < n && i < nf; i++) {
        float p[3] = { (float)c[i].pos[0], (float)c[i].pos[1], (float)c[i].pos[2] };
        int ct = ew_point_contents(a->world, EW_HULL_POINT, p);
        if (ct == EW_CONTENTS_SOLID || ct == EW_CONTENTS_SKY) {
            if (solid < 3)
                printf("%s --path %s: frame %d (t %.2f) eye %.1f,%.1f,%.1f in %s\n", name, path_kind, i, c[i].t,
                       p[0], p[1], p[2], ct == EW_CONTENTS_SOLID ? "solid" : "the sky");
            solid++;
        }
        if (luma[i] < DARK_LUMA) {
            ew_camera cam;
            memset(&cam, 0, sizeof cam);
            for (int k = 0; k < 3; k++) cam.origin[k] = p[k], cam.angles[k] = (float)c[i].ang[k];
            cam.fov = 90;
            cam.time = c[i].t;
            ew_set_debug(rd, EW_DEBUG_TEXTURES);
            double unlit = frame_luma(rd, &cam);
            ew_set_debug(rd, EW_DEBUG_NONE);
            if (unlit < LIT_LUMA) {
                if (dark < 3)
                    printf("%s --path %s: frame %d (t %.2f) eye %.1f,%.1f,%.1f nearly black (luma %.1f, unlit "
                           "%.1f)\n", name, path_kind, i, c[i].t, p[0], p[1], p[2], luma[i], unlit);
                dark++;
            }
        }
    }
    printf("%s --path %s: %d frames, %d eyes in solid or the sky, %d nearly black\n", name, path_kind, n, solid,
           dark);
    if (!strcmp(path_kind, "views")) {
        CHECK(solid == 0, "%s: %d frames of the default path have the eye in solid or the sky", name, solid);
        CHECK(dark == 0, "%s: %d frames of the default path are nearly black near a lit view", name, dark);
        /* It starts at the first view. */
        if (n > 0 && nv > 0)
            CHECK(fabs(c[0].pos[0] - views[0].origin[0]) < 0.01 && fabs(c[0].pos[1] - views[0].origin[1]) < 0.01 &&
                  fabs(c[0].pos[2] - views[0].origin[2]) < 0.01, "%s: the path starts at view 0", name);
    }
    *solid_frames += solid;
    *dark_frames += dark;
    ew_renderer_destroy(rd);
    free(c);
    free(luma);
    unlink(y4m);
    unlink(cams);
    ew_assets_destroy(a);
}

int main(void) {
    if (!ew_t_need_shared("data/librequake/maps/e1m1.bsp")) return ew_t_finish();
    snprintf(tmpdir, sizeof tmpdir, "/tmp/ew_fly_path_XXXXXX");
    if (!mkdtemp(tmpdir)) {
        perror("mkdtemp");
        return 1;
    }
    char data[512];
    snprintf(data, sizeof data, "%s", ew_t_shared_abs("data/librequake"));
    static const char *const maps[] = { "e1m1", "lqdm7", "e4m1", "start", "lqdm1", "e2m1", "slope" };
    int solid = 0, dark = 0, ssolid = 0, sdark = 0;
    for (int i = 0; i < 7; i++) {
        char rel[128];
        snprintf(rel, sizeof rel, "data/librequake/maps/%s.bsp", maps[i]);
        if (!ew_t_need_shared(rel)) continue;
        check_map(maps[i], data, "views", &solid, &dark);
        /* The old straight spline is kept, and shows what the default avoids. */
        check_map(maps[i], data, "straight", &ssolid, &sdark);
    }
    printf("default path: %d frames in solid, %d nearly black; --path straight: %d in solid, %d nearly black\n",
           solid, dark, ssolid, sdark);
    CHECK(ssolid > 0 && sdark > 0, "--path straight puts the eye in solid (%d frames) and shows nothing (%d frames) "
          "somewhere on the shared maps: the test can see what the default path avoids", ssolid, sdark);
    rmdir(tmpdir);
    return ew_t_finish();
}
