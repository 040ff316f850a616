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
    CLI_OPTIONS_HERE;

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

int parse_polyhedra_args(int argc, char **argv, cli_cmd form, const char *help, polyhedra_opts *o) {
    const char *name = cli_commands[form].form;
    int named = 0;
    cli_parser p;
    cli_parser_init(&p, form, argc, argv, 2);
    for (;;) {
        const cli_option *opt;
        const char *v;
        long l;
        int r = cli_parse(&p, &opt, &v);
        if (r < 0) return EXIT_USAGE;
        if (r == CLI_END) break;
        if (r == CLI_POSITIONAL) {  /* the one word that is not an option */
            if (!is_polyhedra(v) || named++) {
                error_line("%s: unexpected argument '%s'", name, v);
                return EXIT_USAGE;
            }
            continue;
        }
        if (cli_is(opt, "--help")) {
            cli_print_help(stdout, form, help);
            return 1;
        }
        if (cli_is(opt, "--stats")) o->stats = 1;
        else if (cli_is(opt, "--independent")) o->independent = 1;
        else if (cli_is(opt, "--zbuffer")) o->zbuffer = 1;
        else if (cli_is(opt, "--time")) {
            if (parse_polyhedra_time(v, &o->time) < 0) return EXIT_USAGE;
        } else if (cli_is(opt, "--size")) {
            if (parse_size(v, &o->width, &o->height) < 0) return EXIT_USAGE;
        } else if (cli_is(opt, "--objects")) {
            if (parse_polyhedra_objects(v, &o->objects) < 0) return EXIT_USAGE;
        } else if (cli_is(opt, "--scale")) {
            if (parse_long(v, &l) < 0 || l < 1 || l > 8) {
                error_line("--scale %s: must be a whole number from 1 to 8", v);
                return EXIT_USAGE;
            }
            o->scale = (int)l;
        } else if (cli_is(opt, "--frames")) {
            if (parse_long(v, &o->frames) < 0 || o->frames < 1 || o->frames > 100000000) {
                error_line("--frames %s: must be a whole number from 1 to 100000000", v);
                return EXIT_USAGE;
            }
        } else if (cli_is(opt, "--out")) {
            if (!*v) {
                error_line("--out: empty file name");
                return EXIT_USAGE;
            }
            if (check_png_name("--out", v) < 0) return EXIT_USAGE;
            o->out = v;
        }
    }
    return 0;
}

int cmd_polyhedra(int argc, char **argv) {
    polyhedra_opts po = { 640, 480, EW_POLYHEDRA_DEFAULT, 1, 0, 0, 0, 0, 0, "polyhedra.png" };
    int pr = parse_polyhedra_args(argc, argv, CLI_RENDER_POLYHEDRA, polyhedra_usage, &po);
    if (pr)
        return pr == 1 ? 0 : pr;
    int width = po.width, height = po.height, objects = po.objects, stats = po.stats;
    int independent = po.independent, zbuffer = po.zbuffer;
    double t = po.time;
    const char *out = po.out;

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
/* Its arguments are checked all the same (usage errors exit 2). */
int cmd_view_polyhedra(int argc, char **argv) {
    static const char help[] = "usage: edgewise view builtin:polyhedra [options]\n\noptions:\n" CLI_OPTIONS_HERE;
    polyhedra_opts po = { 640, 480, EW_POLYHEDRA_DEFAULT, 1, 0, 0, 0, 0, 0, NULL };
    int pr = parse_polyhedra_args(argc, argv, CLI_VIEW_POLYHEDRA, help, &po);
    if (pr)
        return pr == 1 ? 0 : pr;
    error_line("view: this edgewise was built without SDL2 (install libsdl2-dev and rebuild)");
    return 1;
}
#endif
