/*
 * cmd_polyhedra.c - edgewise render builtin:polyhedra: one frame of the
 * moving polyhedra (ew_polyhedra_*, no BSP: a 1/z-sorted global edge list)
 * to a PNG, with --stats as one JSON object that also checks the frame
 * against a z-buffer of the same polygons.  Without SDL2 it also holds the
 * stub of edgewise view builtin:polyhedra (the window is
 * app/viewer/view_polyhedra.c).
 */
#define _POSIX_C_SOURCE 200809L
#include "cli.h"

#include <ctype.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum { EXIT_USAGE = 2 };

static const char polyhedra_usage[] =
    "usage: edgewise render builtin:polyhedra [options]\n"
    "\n"
    "Convex polyhedra spinning and flying through each other, no BSP at all:\n"
    "every front face goes into a global edge list sorted by 1/z per pixel\n"
    "(the Black Book's Listing 51.1), with interpenetrating faces split where\n"
    "their planes cross.  Every pixel is written once.\n"
    "\n"
    "options:\n"
    "  --time T        seconds, 0 to 1000000 (default 0)\n"
    "  --size WxH      frame size, 320x200 up to 7680x4320 (default 640x480)\n"
    "  --objects N     number of polyhedra, 1 to 64 (default 12)\n"
    "  --out FILE.png  output (default polyhedra.png)\n"
    "  --stats         the frame's counters as one JSON object, with its agreement\n"
    "                  with a per-pixel z-buffer of the same polygons\n"
    "  --independent   no intersection resolution: the chapter's independent span\n"
    "                  sorting, wrong where objects pass through each other\n"
    "  --zbuffer       draw the frame by the z-buffer instead\n";

int is_polyhedra(const char *map) { return strcmp(map, "builtin:polyhedra") == 0; }

/* The map argument, not the value of an option that names a file. */
int has_polyhedra(int argc, char **argv) {
    static const char *const file_opts[] = {"--out", "--data", "--script", "--record", "--lit"};
    for (int i = 2; i < argc; i++) {
        if (!is_polyhedra(argv[i])) continue;
        int is_value = 0;
        for (size_t k = 0; k < sizeof file_opts / sizeof file_opts[0]; k++)
            is_value |= strcmp(argv[i - 1], file_opts[k]) == 0;
        if (!is_value) return 1;
    }
    return 0;
}

static double ms_now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

int parse_polyhedra_time(const char *v, double *t) {
    const char *end = v;
    double d = 0;
    int ok = parse_decimal(v, &end, &d) == 0 && !*end && d >= 0 && d <= 1e6;
    if (!ok) {
        error_line("--time %s: must be a number of seconds from 0 to 1000000", v);
        return -1;
    }
    *t = d;
    return 0;
}

int parse_polyhedra_objects(const char *v, int *n) {
    long l;
    if (parse_long(v, &l) < 0 || l < 1 || l > EW_POLYHEDRA_MAX) {
        error_line("--objects %s: must be a whole number from 1 to %d", v, EW_POLYHEDRA_MAX);
        return -1;
    }
    *n = (int)l;
    return 0;
}

int cmd_polyhedra(int argc, char **argv) {
    int width = 640, height = 480, objects = EW_POLYHEDRA_DEFAULT, stats = 0, independent = 0;
    int zbuffer = 0;
    double t = 0;
    const char *out = "polyhedra.png";
    int named = 0;
    for (int i = 2; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            fputs(polyhedra_usage, stdout);
            return 0;
        }
        if (a[0] != '-' || !a[1]) {  /* the one word that is not an option */
            if (!is_polyhedra(a) || named++) {
                error_line("render builtin:polyhedra: unexpected argument '%s'", a);
                return EXIT_USAGE;
            }
            continue;
        }
        if (strcmp(a, "--stats") == 0) { stats = 1; continue; }
        if (strcmp(a, "--independent") == 0) { independent = 1; continue; }
        if (strcmp(a, "--zbuffer") == 0) { zbuffer = 1; continue; }
        int k = strcmp(a, "--time") == 0 ? 0 : strcmp(a, "--size") == 0 ? 1
              : strcmp(a, "--objects") == 0 ? 2 : strcmp(a, "--out") == 0 ? 3 : -1;
        if (k < 0) {
            error_line("render builtin:polyhedra: unknown option '%s' (try 'edgewise render "
                       "builtin:polyhedra --help')", a);
            return EXIT_USAGE;
        }
        if (i + 1 >= argc) {
            error_line("render builtin:polyhedra: option '%s' needs a value", a);
            return EXIT_USAGE;
        }
        const char *v = argv[++i];
        if ((k == 0 && parse_polyhedra_time(v, &t) < 0) ||
            (k == 1 && parse_size(v, &width, &height) < 0) ||
            (k == 2 && parse_polyhedra_objects(v, &objects) < 0))
            return EXIT_USAGE;
        if (k == 3) {
            if (!*v) {
                error_line("--out: empty file name");
                return EXIT_USAGE;
            }
            out = v;
        }
    }

    ew_error err = { "" };
    int rc = 1;
    uint8_t *frame = malloc((size_t)width * height), *check = NULL;
    ew_polyhedra *p = ew_polyhedra_create(objects, width, height, NULL, &err);
    if (!frame || !p) {
        error_line("%s", p ? "out of memory" : err.msg);
        goto done;
    }
    ew_polyhedra_set_crossings(p, !independent);
    ew_polyhedra_stats st, zs;
    double t0 = ms_now();
    int r = zbuffer ? ew_polyhedra_render_zbuffer(p, t, frame, &st, &err)
                    : ew_polyhedra_render(p, t, frame, &st, &err);
    double ms = ms_now() - t0;
    if (r < 0) {
        error_line("%s", err.msg);
        goto done;
    }
    if (ew_write_png(out, frame, width, height, ew_polyhedra_palette(p), &err) < 0) {
        error_line("%s", err.msg);
        goto done;
    }
    if (stats) {
        /* The z-buffer of the same polygons, for the agreement figure. */
        check = malloc((size_t)width * height);
        double z0 = ms_now();
        if (!check || ew_polyhedra_render_zbuffer(p, t, check, &zs, &err) < 0) {
            error_line("%s", check ? err.msg : "out of memory");
            goto done;
        }
        double zms = ms_now() - z0;
        long long same = 0, n = (long long)width * height;
        for (long long i = 0; i < n; i++)
            same += frame[i] == check[i];
        printf("{\"scene\":\"builtin:polyhedra\",\"method\":\"%s\",\"time\":", zbuffer ? "zbuffer"
               : independent ? "edge-independent" : "edge");
        json_number(stdout, t);
        printf(",\"width\":%d,\"height\":%d,\"objects\":%d,\"out\":", width, height, objects);
        json_string(stdout, out);
        printf(",\"polygons\":%d,\"clipped\":%d,\"edges\":%d,\"spans\":%d,\"pixels_written\":%lld,"
               "\"pixels_covered\":%lld,\"overdraw\":",
               st.polygons, st.clipped, st.edges, st.spans, st.pixels, st.covered);
        json_number(stdout, (double)st.pixels / (double)n);
        printf(",\"crossings\":%d,\"ties\":%d,\"ms\":", st.crossings, st.ties);
        json_number(stdout, ms);
        fputs(",\"zbuffer_overdraw\":", stdout);
        json_number(stdout, (double)zs.pixels / (double)n);
        fputs(",\"zbuffer_ms\":", stdout);
        json_number(stdout, zms);
        fputs(",\"agreement\":", stdout);
        json_number(stdout, (double)same / (double)n);
        fputs("}\n", stdout);
    }
    fprintf(stderr, "wrote %s (%dx%d)\n", out, width, height);
    rc = 0;
done:
    free(frame), free(check);
    ew_polyhedra_destroy(p);
    if (fflush(stdout) != 0 && rc == 0) {
        error_line("stdout: %s", strerror(errno));
        rc = 1;
    }
    return rc;
}

#ifndef EW_HAVE_SDL2
int cmd_view_polyhedra(int argc, char **argv) {
    (void)argc;
    (void)argv;
    error_line("view: this edgewise was built without SDL2 (install libsdl2-dev and rebuild)");
    return 1;
}
#endif
