/* view_lab: one view of a map's view set timed alone, warm and in the
 * benchmark's cycle (docs/performance.md, "What bounds each target on this
 * machine").  Built as a target
 * (build/view_lab); run
 *
 *     ./build/view_lab MAP DATA_DIR VIEW [WxH] [FRAMES] [options]
 *
 *   --true       true colour (default 8-bit)
 *   --modern     the default look (default --classic, the 1996 look)
 *   --threads N  render threads (default 1)
 *   --fog D,R,G,B  fog of density D and colour R,G,B (the default look's)
 *
 * and read; nothing here fails on a time.  Two rows: the view drawn
 * FRAMES times in a row (its world data, surfaces and frame stay in the
 * caches), then FRAMES times with every other view of the set drawn before
 * each of its frames, untimed, as `edgewise bench` goes from view to view
 * (what it reads has left the caches).  Each row: the view's mean frame
 * and its stages (ew_stats' front, scan and draw), and the surfaces that
 * won a span of those in the edge list.  Where the two rows differ, the
 * stage waits on memory; where they agree, it is work. */
#define _POSIX_C_SOURCE 200809L  /* clock_gettime */
#include <edgewise.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now_ms(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

/* A whole number in [lo, hi] from s, or -1. */
static long whole(const char *s, long lo, long hi) {
    char *end;
    long v = strtol(s, &end, 10);
    return *s && !*end && v >= lo && v <= hi ? v : -1;
}

typedef struct row { double frame, front, scan, draw; int shown, surfaces; } row;

/* The view's frames, each after the other views (cycle) or not. */
static int time_view(ew_renderer *r, const ew_camera *views, int nv, int view, int frames, int cycle, row *out) {
    ew_stats st;
    memset(out, 0, sizeof *out);
    if (ew_render(r, &views[view], &st) != 0) return -1;  /* its surfaces built, untimed */
    for (int i = 0; i < frames; i++) {
        if (cycle)
            for (int k = 0; k < nv; k++)
                if (k != view && ew_render(r, &views[k], &st) != 0) return -1;
        double t0 = now_ms();
        if (ew_render(r, &views[view], &st) != 0) return -1;
        out->frame += now_ms() - t0;
        out->front += st.ms_front, out->scan += st.ms_scan, out->draw += st.ms_draw;
        out->shown = st.surfaces_shown, out->surfaces = st.surfaces;
    }
    out->frame /= frames, out->front /= frames, out->scan /= frames, out->draw /= frames;
    return 0;
}

int main(int argc, char **argv) {
    if (argc < 4) {
        fprintf(stderr, "usage: view_lab MAP DATA_DIR VIEW [WxH] [FRAMES] [--true] [--modern] [--threads N] [--fog D,R,G,B]\n");
        return 2;
    }
    int w = 640, h = 480, frames = 200, color = 0, modern = 0, threads = 1, pos = 0;
    float fog[4] = {-1, 0, 0, 0};
    long n;
    int sw, sh;
    char extra;
    long view = whole(argv[3], 0, EW_MAX_VIEWS - 1);
    if (view < 0) {
        fprintf(stderr, "view_lab: VIEW must be a view number from 0 to %d, not '%s'\n", EW_MAX_VIEWS - 1, argv[3]);
        return 2;
    }
    for (int i = 4; i < argc; i++) {
        if (strcmp(argv[i], "--true") == 0) color = 1;
        else if (strcmp(argv[i], "--modern") == 0) modern = 1;
        else if (strcmp(argv[i], "--fog") == 0 && i + 1 < argc) {
            char end;
            if (sscanf(argv[++i], "%f,%f,%f,%f%c", &fog[0], &fog[1], &fog[2], &fog[3], &end) != 4 || !(fog[0] >= 0)) {
                fprintf(stderr, "view_lab: --fog must be D,R,G,B (density 0 or more), not '%s'\n", argv[i]);
                return 2;
            }
        } else if (strcmp(argv[i], "--threads") == 0 && i + 1 < argc) {
            n = whole(argv[++i], 0, 64);
            if (n < 0) {
                fprintf(stderr, "view_lab: --threads must be 0 to 64, not '%s'\n", argv[i]);
                return 2;
            }
            threads = (int)n;
        } else if (pos == 0 && sscanf(argv[i], "%dx%d%c", &sw, &sh, &extra) == 2 && sw > 0 && sh > 0) {
            w = sw, h = sh, pos = 1;
        } else if (pos <= 1 && (n = whole(argv[i], 1, 1000000)) > 0) {
            frames = (int)n;
            pos = 2;
        } else {
            fprintf(stderr, "view_lab: '%s' is not a size WxH, a number of frames or an option\n", argv[i]);
            return 2;
        }
    }
    ew_error err;
    ew_assets *a = ew_assets_create(argv[1], argv[2], &err);
    if (!a) {
        fprintf(stderr, "%s\n", err.msg);
        return 1;
    }
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                             .colormap = a->colormap, .width = w, .height = h,
                                                             .threads = threads,
                                                             .color = color ? EW_COLOR_TRUE : EW_COLOR_8BIT,
                                                             .classic = !modern},
                                        &err);
    if (!r) {
        fprintf(stderr, "%s\n", err.msg);
        ew_assets_destroy(a);
        return 1;
    }
    if (fog[0] >= 0) ew_set_fog(r, fog[0], fog[1], fog[2], fog[3]);
    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(a->world, views), status = 0;
    if (view >= nv) {
        fprintf(stderr, "view_lab: %s has %d views (0 to %d), not view %ld\n", argv[1], nv, nv - 1, view);
        status = 2;
    } else {
        printf("%s view %ld of %d, %dx%d, %s, %s, %d thread(s), %d frames a row\n", argv[1], view, nv, w, h,
               color ? "true colour" : "8-bit", modern ? "the default look" : "classic", threads, frames);
        printf("%-30s %8s %8s %8s %8s %s\n", "", "frame", "front", "scan", "draw", "shown/surfaces");
        for (int cycle = 0; cycle < 2 && status == 0; cycle++) {
            row o;
            if (time_view(r, views, nv, (int)view, frames, cycle, &o) != 0) {
                fprintf(stderr, "view_lab: a view of %s could not be rendered\n", argv[1]);
                status = 1;
                break;
            }
            printf("%-30s %8.3f %8.3f %8.3f %8.3f %d/%d\n", cycle ? "the other views between (ms)" : "again and again (ms)",
                   o.frame, o.front, o.scan, o.draw, o.shown, o.surfaces);
        }
    }
    ew_renderer_destroy(r);
    ew_assets_destroy(a);
    return status;
}
