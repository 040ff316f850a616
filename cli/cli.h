/*
 * cli.h - helpers of cli/edgewise.c shared with the commands that live in
 * their own files (cmd_*.c), so every command parses and reports alike.
 */
#ifndef EW_CLI_H
#define EW_CLI_H

#include "edgewise_lab.h"  /* and edgewise.h */
#include "options.h"       /* the option table and its parser */

#include <stddef.h>
#include <stdio.h>

#if defined(__GNUC__)
#define EW_CLI_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define EW_CLI_PRINTF(a, b)
#endif

/* The field of view every command accepts (the renderer's camera check). */
#define FOV_RULE "more than 1 and less than 179 degrees"

/* One "edgewise: <message>" line on stderr, control characters replaced. */
void error_line(const char *fmt, ...) EW_CLI_PRINTF(1, 2);
/* Whole decimal numbers, no blanks; 0 or -1 (nothing printed). */
int  parse_long(const char *s, long *out);
/* --threads N, the same rule in every command (help and error). */
#define THREADS_RULE "0 (one per core) to 64"
_Static_assert(EW_MAX_THREADS == 64, "THREADS_RULE states EW_MAX_THREADS");
/* --threads N: 0 to EW_MAX_THREADS; 0 or -1 (error printed). */
int  parse_threads(const char *v, int *out);
/* "WxH" within the renderer's limits; 0 or -1 (error printed). */
int  parse_size(const char *s, int *w, int *h);
/* A picture's file name: it must end in .png (any case), the one format
 * edgewise writes; 0, or -1 after one error line naming opt and the name. */
int  check_png_name(const char *opt, const char *name);
/* MAP is the word 'builtin'. */
int  is_builtin(const char *map);
/* "maps/e1m1.bsp" -> "e1m1". */
void map_basename(const char *map, char *out, size_t size);
/* A finite decimal number at the start of s ([+-] digits [. digits]
 * [e [+-] digits]; no blanks, hex, inf or nan), *end just past it: 0, or
 * -1 (nothing printed).  Every number the command reads goes through it. */
int  parse_decimal(const char *s, const char **end, double *out);
/* The JSON text of the character at *p, moving *p past it: a whole valid
 * UTF-8 sequence as it is; '"' and '\\' escaped; control bytes, DEL and
 * every byte that is not part of valid UTF-8 as \u00XX (so the output is
 * always UTF-8).  Returns strlen(out) (at most 6).  Every JSON writer uses it. */
size_t json_char(const unsigned char **p, char out[8]);
/* A JSON string (by json_char) / number (null for inf and nan). */
void json_string(FILE *f, const char *s);
void json_number(FILE *f, double v);

/* ---- what is drawn (cli/draw_options.c) --------------------------------------
 * The options that change the picture, the same in render, demo, bench and
 * soak: --no-entities, --alias-raster, --subdiv-threshold, --full-zfill,
 * --occlusion, --classic, --wateralpha, --fog, --no-fog, --no-waterwarp, --hsr, --color,
 * --no-lit, --dither, --debug. */
typedef struct draw_opts {
    int    given;             /* bit per option seen */
    int    no_entities, full_zfill, classic, no_waterwarp;
    int    occlusion;         /* ew_occlusion_mode */
    int    alias_raster;      /* ew_alias_raster */
    double subdiv_threshold;  /* 0: the renderer's (40) */
    double wateralpha;        /* < 0: the map's */
    int    fog_mode;          /* 0: the map's, 1: --fog, 2: --no-fog */
    double fog[4];            /* density, red, green, blue */
    int    hsr;               /* ew_hsr_method */
    int    color;             /* ew_color_mode: chosen when the renderer is made */
    int    no_lit, dither;
    int    lighting;          /* ew_lighting_mode */
    double gamma;             /* 0: 1 */
    struct draw_style {       /* --lightstyle N=V, in order */
        int  style, kind;     /* kind 0: value, 1: pattern, 2: switch on/off */
        int  value;
        char pattern[65];
    } styles[64];
    int    nstyles;
    int    debug;             /* ew_debug_mode (--debug) */
    int    map_rgb;           /* the map has coloured light (.lit, BSPX RGBLIGHTING): 1, 0, or -1
                               * unknown (draw_opts_init); draw_opts_json's "lit" is true only when
                               * coloured light is drawn: on, not classic, and not map_rgb 0 */
} draw_opts;

/* The defaults: what the map asks for, drawn by the edge list. */
void draw_opts_init(draw_opts *d);
/* Takes opt (a row of the option table, value its value) if it is a
 * drawing option.  Returns 0 if it is not one, 1 when taken, -1 after
 * printing one usage error line ("CMD: ..." for the option's form,
 * "--name VALUE: ARG must be RULE" for a bad value). */
int  draw_option(draw_opts *d, const char *cmd, const cli_option *opt, const char *value);
/* The help lines of every drawing option (the rules the errors print). */
void draw_opts_usage(FILE *f);

/* The arguments of a command that takes MAPs and the drawing options, one
 * option at a time (cli_parse, options.h): a positional argument is a map
 * (at most max_maps), a drawing option goes to draw (may be NULL), --help
 * prints help (cli_print_help), the drawing options and help_tail (help
 * NULL: --help is returned like any other option).  cli_next_arg returns 1
 * with opt and value (NULL for a flag) for the caller; 0 at the end, or
 * when stop is set: -1 after one error line, 1 after --help. */
typedef struct cli_args {
    cli_parser        p;
    const char      **maps;
    int               nmaps, max_maps;
    draw_opts        *draw;
    const char       *help, *help_tail;
    const cli_option *opt;
    const char       *value;
    int               stop;
    int               quiet;  /* --quiet was given (taken here, every command has it) */
} cli_args;
void cli_args_init(cli_args *a, cli_cmd cmd, int argc, char **argv, const char **maps, int max_maps,
                   draw_opts *draw, const char *help, const char *help_tail);
int  cli_next_arg(cli_args *a);
/* *slot = v for an option naming a file or folder given at most once;
 * 0, or -1 after one error line. */
int  cli_set_once(const char *cmd, const char *name, const char *v, const char **slot);
/* *out = v, a whole number lo..hi, for an option given at most once
 * (*given counts); 0, or -1 after one error line. */
int  cli_int_once(const char *cmd, const char *name, const char *v, long lo, long hi, int *given, int *out);
/* Appends the size WxH of v to sizes[*n] (at most max); 0, or -1 after one
 * error line. */
int  cli_add_size(const char *cmd, const char *v, int (*sizes)[2], int *n, int max);
/* Sets every drawing setting of r (defaults included) and its scene. */
int  draw_opts_apply(const draw_opts *d, ew_renderer *r, const ew_scene *scene);
/* ,"entities":..,"alias_raster":..,"subdiv_threshold":..,"zfill":..,
 * "classic":..,"wateralpha":..,"fog":..,"waterwarp":..,"hsr":.. for a JSON object. */
void draw_opts_json(FILE *f, const draw_opts *d);
/* The scene d asks for in *out: the map's entities (the built-in scene's
 * for 'builtin'), an empty scene with --no-entities when need_scene, else
 * NULL.  Prints its warnings unless quiet.  0, or -1 (error printed). */
int  draw_opts_scene(const draw_opts *d, const ew_assets *a, const char *map, const char *data,
                     int need_scene, int quiet, ew_scene **out);

/* builtin:detail=N, the stress hall of `edgewise hsr --stress`
 * (src/mapgen/stress_level.c), is a MAP of every command: N, -1 for
 * another MAP, -2 for a bad N. */
#define STRESS_MAP_PREFIX "builtin:detail="
int  stress_detail(const char *map);
/* Loads MAP ('builtin' and builtin:detail=N too) and prints its warnings unless quiet, one
 * "edgewise: warning: ..." line each; NULL with the error printed. */
ew_assets *load_map(const char *map, const char *data, int quiet);
void print_world_warnings(const ew_world *w, int quiet);
void print_scene_warnings(const ew_scene *s, int quiet);

/* ---- nearly black frames (cli/dark.c) ---------------------------------------
 * A frame whose mean brightness (luma, 0..255) is under DARK_LUMA (about 3%
 * of full scale) is "dark"; every command that writes a picture warns. */
#define DARK_LUMA 8.0
/* The frame's mean luma, 0..255 (either colour mode, the palette with gamma). */
double frame_mean_luma(const ew_renderer *r);
/* The likely cause of a dark frame, one phrase into why: the camera in
 * solid (inside a wall or outside the map), nothing in view, the map's light
 * data dark, a near wall filling the frame, or dark light where it looks. */
void dark_cause(ew_renderer *r, const ew_world *w, const ew_camera *cam, char *why, size_t size);
/* 1 if r's frame is dark, after one "edgewise: warning: WHAT: ..." line
 * naming the cause unless quiet; else 0.  *mean (may be NULL) gets the luma. */
int  warn_if_dark(ew_renderer *r, const ew_world *w, const ew_camera *cam, const char *what, int quiet,
                  double *mean);

/* ---- the benchmark protocol (cli/cmd_bench.c), shared by bench and hsr ----
 * The view set rendered once untimed (the warm-up: pages in the frame and
 * fills the surface cache), then `passes` times with each frame timed on
 * the monotonic clock: frames[(pass - 1) * nviews + v] in ms, and the
 * frame's counters in stats[] and its probes in labs[] alike (either may
 * be NULL).  hooks (may be
 * NULL) are called before every frame (pass 0 is the warm-up) and after
 * every timed one.  Returns 0, or -1 - v when view v cannot be rendered. */
typedef struct bench_hooks {
    void (*before)(void *ctx, int pass, int view);
    void (*after)(void *ctx, int pass, int view);
    void *ctx;
} bench_hooks;
int    bench_run_views(ew_renderer *r, const ew_camera *views, int nviews, int passes, double *frames,
                       ew_stats *stats, ew_lab_stats *labs, const bench_hooks *hooks);
/* The median of n values (sorts v). */
double bench_median(double *v, int n);

/* edgewise bench (cli/cmd_bench.c): argv[1] is "bench". */
int cmd_bench(int argc, char **argv);
/* edgewise soak (cli/cmd_soak.c): argv[1] is "soak". */
int cmd_soak(int argc, char **argv);
/* edgewise view (app/viewer/viewer.c with SDL2, else cli/cmd_view_stub.c). */
int cmd_view(int argc, char **argv);
/* edgewise shots (cli/cmd_shots.c): argv[1] is "shots". */
int cmd_shots(int argc, char **argv);
/* edgewise fly (cli/cmd_fly.c): argv[1] is "fly". */
int cmd_fly(int argc, char **argv);
/* edgewise timedemo (cli/cmd_timedemo.c): argv[1] is "timedemo". */
int cmd_timedemo(int argc, char **argv);
/* The demo's light styles (svc_lightstyle) into r, but those the drawing
 * options set (--lightstyle); cheap, called every frame (cli/cmd_timedemo.c). */
void demo_apply_lightstyles(ew_renderer *r, const ew_demo_state *st, const draw_opts *d);
/* Opens DEMO, reads it up to its server info and loads its map (from the
 * first model precache) with --game/--data: the demo (rewound), the
 * assets; -1 after one error line. */
int  demo_open_with_map(const char *path, const char *data, int quiet, ew_demo **demo, ew_assets **assets);
/* The demo's span: the time of the view entity's first update (*t0) and
 * of the last message (*t1), read through and rewound; 0, or -1 after one
 * error line (a damaged demo, or one that never shows its view entity). */
int  demo_span(ew_demo *d, const char *path, double *t0, double *t1);
/* edgewise hsr (cli/cmd_hsr.c): argv[1] is "hsr". */
int cmd_hsr(int argc, char **argv);

/* The moving polyhedra (cli/cmd_polyhedra.c): MAP 'builtin:polyhedra' of
 * render (argv[1] "render", argv[2] the map) and of view (the window in
 * app/viewer/view_polyhedra.c with SDL2, else a stub saying it is missing). */
int is_polyhedra(const char *map);
/* 'builtin:polyhedra' is one of argv[2..]. */
int has_polyhedra(int argc, char **argv);
int cmd_polyhedra(int argc, char **argv);
int cmd_view_polyhedra(int argc, char **argv);
/* --time (0 to 1e6 s) and --objects (1 to EW_POLYHEDRA_MAX); 0 or -1 (error printed). */
int parse_polyhedra_time(const char *v, double *t);
int parse_polyhedra_objects(const char *v, int *n);
/* The options of both polyhedra forms (the table's rows of
 * CLI_RENDER_POLYHEDRA or CLI_VIEW_POLYHEDRA), defaults first. */
typedef struct polyhedra_opts {
    int         width, height, objects, scale, stats, independent, zbuffer;
    long        frames;
    double      time;
    const char *out;
} polyhedra_opts;
/* Parses argv[2..] for form (usage printed for --help: help text).
 * Returns 0, 1 after --help, or 2 (EXIT_USAGE) after one error line. */
int parse_polyhedra_args(int argc, char **argv, cli_cmd form, const char *help, polyhedra_opts *o);

#endif
