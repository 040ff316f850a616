/*
 * edgewise timedemo DEMO: a recorded game played as fast as it goes, every
 * block of the demo drawn as one frame (the benchmark every port quotes),
 * then the classic line "N frames S seconds F fps" and one JSON line: the
 * median, 99th percentile and worst frame, the worst frame's demo time,
 * and what the client met (missing models, frames whose camera was in
 * solid).  The drawing options are render's.
 */
#define _POSIX_C_SOURCE 200809L
#include "cli.h"
#include "edgewise.h"
#include "edgewise_lab.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char timedemo_usage[] =
    "usage: edgewise timedemo DEMO [--game DIR] [--data DIR] [--size WxH] [--threads N]\n"
    "                         [--out FILE.png [--at T]] [--to T] [--quiet] [what is drawn]\n"
    "\n"
    "Plays DEMO (a .dem file: protocols 15, 666 and 999), every block drawn as\n"
    "one frame as fast as possible, on the map and with the models the demo\n"
    "names, found under --game then --data.  Prints the classic line\n"
    "'N frames S seconds F fps' and one JSON line: frames, seconds, fps,\n"
    "median_ms, p99_ms, worst_ms, worst_time (the worst frame's demo time),\n"
    "camera_in_solid (frames whose eye was inside a wall), models_missing.\n"
    "A damaged demo: the frames before the damage are played, then one error\n"
    "line naming the block and the byte, and exit status 1.\n"
    "\n"
    CLI_OPTIONS_HERE
    "\n"
    "what is drawn (as in edgewise render):\n";

typedef struct td_opts {
    const char *demo, *data, *out;
    int         width, height, threads, quiet;
    double      at, to;
    int         at_given, to_given;
    draw_opts   draw;
} td_opts;

/* A demo time in seconds (within 1e9 either way), or one error line. */
static int parse_seconds(const char *name, const char *v, double *t) {
    const char *end;
    if (parse_decimal(v, &end, t) < 0 || *end || fabs(*t) > 1e9) {
        error_line("%s %s: expected a time in seconds", name, v);
        return -1;
    }
    return 0;
}

static int parse(int argc, char **argv, td_opts *o) {
    const char *pos[1];
    cli_args args;
    cli_args_init(&args, CLI_TIMEDEMO, argc, argv, pos, 1, &o->draw, timedemo_usage, NULL);
    while (cli_next_arg(&args)) {
        const cli_option *opt = args.opt;
        const char *v = args.value;
        if (cli_is(opt, "--data")) {
            if (cli_set_once("timedemo", "--data", v, &o->data) < 0) return -1;
        } else if (cli_is(opt, "--size")) {
            if (parse_size(v, &o->width, &o->height) < 0) return -1;
        } else if (cli_is(opt, "--threads")) {
            if (parse_threads(v, &o->threads) < 0) return -1;
        } else if (cli_is(opt, "--out")) {
            if (cli_set_once("timedemo", "--out", v, &o->out) < 0 || check_png_name("--out", v) < 0) return -1;
        } else if (cli_is(opt, "--at")) {
            if (parse_seconds("--at", v, &o->at) < 0) return -1;
            o->at_given = 1;
        } else if (cli_is(opt, "--to")) {
            if (parse_seconds("--to", v, &o->to) < 0) return -1;
            o->to_given = 1;
        }
    }
    if (args.stop) return args.stop;
    o->quiet = args.quiet;
    o->demo = args.nmaps ? pos[0] : NULL;
    if (!o->demo) {
        error_line("timedemo: missing DEMO (a .dem file)");
        return -1;
    }
    if (o->at_given && !o->out) {
        error_line("timedemo: --at needs --out FILE.png");
        return -1;
    }
    return 0;
}

void demo_apply_lightstyles(ew_renderer *r, const ew_demo_state *st, const draw_opts *d) {
    for (int i = 0; i < EW_DEMO_LIGHTSTYLES; i++) {
        int mine = 0;
        for (int k = 0; k < d->nstyles; k++) mine |= d->styles[k].style == i;
        if (mine || !(st->lightstyles_seen & ((uint64_t)1 << i))) continue;
        const char *p = st->lightstyles[i];
        /* "" is the normal light; a pattern the renderer refuses (a letter
         * outside a..z) leaves the style as it was */
        ew_set_lightstyle_pattern(r, i, p[0] ? p : "m");
    }
}

int demo_open_with_map(const char *path, const char *data, int quiet, ew_demo **demo, ew_assets **assets) {
    ew_error err = {""};
    *demo = NULL, *assets = NULL;
    ew_demo *d = ew_demo_open(path, &err);
    if (!d) {
        error_line("%s", err.msg);
        return -1;
    }
    const ew_demo_state *st = ew_demo_get_state(d);
    int rc;
    while (st->nmodels < 1 && (rc = ew_demo_read_block(d, &err)) == 1) {}
    if (st->nmodels < 1) {
        if (err.msg[0] && rc < 0) error_line("%s", err.msg);
        else error_line("%s: no server info with a map in the demo", path);
        ew_demo_close(d);
        return -1;
    }
    char map[64];
    map_basename(st->models[1], map, sizeof map);
    ew_demo_rewind(d);
    if (!data && !cli_search_path(NULL)) {
        error_line("%s: the demo plays on %s: give its game directory with --data DIR (and --game DIR)", path,
                   st->models[1]);
        ew_demo_close(d);
        return -1;
    }
    ew_assets *a = load_map(map, data, quiet);
    if (!a) {
        ew_demo_close(d);
        return -1;
    }
    *demo = d, *assets = a;
    return 0;
}

int demo_span(ew_demo *d, const char *path, double *t0, double *t1) {
    ew_error err = {""};
    const ew_demo_state *ds = ew_demo_get_state(d);
    int rd, seen = 0;
    *t0 = *t1 = 0;
    while ((rd = ew_demo_read_block(d, &err)) == 1) {
        if (!seen && ds->view_entity > 0 && ds->view_entity < ds->nentities && ds->entities[ds->view_entity].msgtime >= 0)
            seen = 1, *t0 = ds->time;
        *t1 = ds->time;
    }
    ew_demo_rewind(d);
    if (rd < 0) {
        error_line("%s", err.msg);
        return -1;
    }
    if (!seen) {
        error_line("%s: the demo never shows its view entity: nothing to draw", path);
        return -1;
    }
    return 0;
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

int cmd_timedemo(int argc, char **argv) {
    td_opts o = {.width = 640, .height = 480};
    draw_opts_init(&o.draw);
    int pr = parse(argc, argv, &o);
    if (pr != 0) return pr > 0 ? 0 : 2;

    ew_demo *d = NULL;
    ew_assets *a = NULL;
    if (demo_open_with_map(o.demo, o.data, o.quiet, &d, &a) < 0) return 1;
    o.draw.map_rgb = ew_world_has_rgb_light(a->world);
    ew_error err = {""};
    int rc = 1;
    ew_renderer *r = NULL;
    double *ms = NULL;
    ew_demo_client *c = ew_demo_client_create(d, a->world, cli_search_path(o.data), &err);
    if (!c) {
        error_line("%s", err.msg);
        goto done;
    }
    r = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette, .colormap = a->colormap,
                                               .width = o.width, .height = o.height, .threads = o.threads,
                                               .color = (ew_color_mode)o.draw.color}, &err);
    int nblocks = ew_demo_block_count(d);
    ms = malloc(sizeof *ms * (size_t)(nblocks + 1));
    double *times = malloc(sizeof *times * (size_t)(nblocks + 1));
    if (!r || !ms || !times) {
        error_line("%s", r ? "timedemo: out of memory" : err.msg);
        free(times);
        goto done;
    }
    ew_scene *scene = ew_demo_client_scene(c);
    draw_opts_apply(&o.draw, r, o.draw.no_entities ? NULL : scene);
    const ew_demo_state *st = ew_demo_get_state(d);
    int frames = 0, in_solid = 0, wrote = 0, read_rc, stopped = 0;
    ew_camera out_cam;
    memset(&out_cam, 0, sizeof out_cam);
    double worst_time = 0, total = 0;
    double t_start = ew_clock_ms();
    while ((read_rc = ew_demo_client_read(c, &err)) == 1) {
        /* nothing to draw before the view entity's first update (the
         * game's client waits for its signon too) */
        if (!st->protocol || st->nmodels < 1 || st->view_entity <= 0 || st->view_entity >= st->nentities ||
            st->entities[st->view_entity].msgtime < 0)
            continue;
        if (o.to_given && st->time > o.to) {
            if (!frames) {  /* an absolute demo time, easily given as seconds from the start */
                error_line("%s: --to %g is before the demo's first frame (demo time %.3f)", o.demo, o.to, st->time);
                rc = 2;
                free(times);
                goto done;
            }
            stopped = 1;
            break;
        }
        double t0 = ew_clock_ms();
        ew_camera cam;
        if (ew_demo_client_frame(c, st->time, &cam) < 0) continue;
        demo_apply_lightstyles(r, st, &o.draw);
        if (!o.draw.no_entities) ew_set_scene(r, scene);
        if (ew_render(r, &cam, NULL) < 0) {
            error_line("%s: block %d: the camera is unusable", o.demo, st->block - 1);
            free(times);
            goto done;
        }
        double t1 = ew_clock_ms();
        ms[frames] = t1 - t0, times[frames] = st->time;
        total += t1 - t0;
        if (ew_point_contents(a->world, 0, cam.origin) == EW_CONTENTS_SOLID) in_solid++;
        if (o.out && !wrote && o.at_given && st->time >= o.at) {
            if (ew_write_frame_png(r, o.out, &err) < 0) {
                error_line("%s", err.msg);
                free(times);
                goto done;
            }
            wrote = 1, out_cam = cam;
        }
        if (o.out && !wrote) out_cam = cam;  /* the last frame's, unless --at chose one */
        frames++;
    }
    double wall = (ew_clock_ms() - t_start) / 1000;
    if (o.out && !wrote && frames) {
        if (ew_write_frame_png(r, o.out, &err) < 0) {
            error_line("%s", err.msg);
            free(times);
            goto done;
        }
        wrote = 1;
    }
    int worst = 0;
    for (int i = 1; i < frames; i++)
        if (ms[i] > ms[worst]) worst = i;
    double worst_ms = frames ? ms[worst] : 0;
    worst_time = frames ? times[worst] : 0;
    free(times);
    qsort(ms, (size_t)frames, sizeof *ms, cmp_double);
    double median = frames ? ms[frames / 2] : 0;
    double p99 = frames ? ms[(int)((frames - 1) * 0.99)] : 0;
    double seconds = total / 1000;
    /* the classic line (Quake's timedemo reports frames over the wall time) */
    printf("%d frames %.1f seconds %.1f fps\n", frames, seconds, seconds > 0 ? frames / seconds : 0);
    printf("{\"demo\":");
    json_string(stdout, o.demo);
    printf(",\"map\":");
    json_string(stdout, ew_demo_client_map(c));
    printf(",\"width\":%d,\"height\":%d,\"threads\":%d,\"frames\":%d,\"seconds\":", o.width, o.height,
           ew_get_threads(r), frames);
    json_number(stdout, seconds);
    printf(",\"wall_seconds\":");
    json_number(stdout, wall);
    printf(",\"fps\":");
    json_number(stdout, seconds > 0 ? frames / seconds : 0);
    printf(",\"median_ms\":");
    json_number(stdout, median);
    printf(",\"p99_ms\":");
    json_number(stdout, p99);
    printf(",\"worst_ms\":");
    json_number(stdout, worst_ms);
    printf(",\"worst_time\":");
    json_number(stdout, worst_time);
    if (wrote) {
        printf(",\"out\":");
        json_string(stdout, o.out);
        printf(",\"out_camera\":[%.9g,%.9g,%.9g,%.9g,%.9g,%.9g],\"out_time\":%.9g", out_cam.origin[0],
               out_cam.origin[1], out_cam.origin[2], out_cam.angles[0], out_cam.angles[1], out_cam.angles[2],
               out_cam.time);
    }
    printf(",\"camera_in_solid\":%d,\"models_missing\":%d,\"complete\":%s", in_solid, ew_demo_client_missing(c),
           read_rc == 0 && !stopped ? "true" : "false");
    draw_opts_json(stdout, &o.draw);
    printf("}\n");
    fflush(stdout);
    if (!o.quiet && ew_demo_client_missing(c))
        fprintf(stderr, "edgewise: warning: %s: %d model files missing (not drawn); give the game directory "
                        "with --data (and a mod with --game)\n", o.demo, ew_demo_client_missing(c));
    if (read_rc < 0) {
        error_line("%s", err.msg);
        goto done;
    }
    rc = 0;
done:
    free(ms);
    ew_renderer_destroy(r);
    ew_demo_client_destroy(c);
    ew_assets_destroy(a);
    ew_demo_close(d);
    return rc;
}
