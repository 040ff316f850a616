/*
 * draw_options.c - the options that change what is drawn, parsed, checked,
 * described and applied in one place for render, demo, bench and soak, so a
 * picture `render` makes can be timed (bench) and soaked (soak) as it is.
 *
 * Each option has one rule, and the help line and the error message both
 * print that same text.
 */
#define _POSIX_C_SOURCE 200809L  /* stat */
#include "cli.h"
#include "edgewise.h"
#include "edgewise_lab.h"  /* ew_set_full_zfill, ew_set_occlusion_cull */

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

enum {
    D_NOENT, D_ARASTER, D_SUBTHRESH, D_FULLZ, D_OCC, D_CLASSIC, D_WATERALPHA, D_FOG, D_NOFOG,
    D_NOWARP, D_HSR, D_COLOR, D_NOLIT, D_DITHER, D_LIGHTING, D_LIGHTSTYLE, D_GAMMA, D_DEBUG, D_COUNT
};

#define MAX_FOG_DENSITY 100.0

/* The drawing options' names, by D_*: their rows (metavariable, help,
 * rule) are in the option table (cli/options.c). */
static const char *const draw_names[D_COUNT] = {
    [D_NOENT] = "--no-entities", [D_ARASTER] = "--alias-raster", [D_SUBTHRESH] = "--subdiv-threshold",
    [D_FULLZ] = "--full-zfill", [D_OCC] = "--occlusion", [D_CLASSIC] = "--classic",
    [D_WATERALPHA] = "--wateralpha", [D_FOG] = "--fog", [D_NOFOG] = "--no-fog", [D_NOWARP] = "--no-waterwarp",
    [D_HSR] = "--hsr", [D_COLOR] = "--color", [D_NOLIT] = "--no-lit", [D_DITHER] = "--dither",
    [D_LIGHTING] = "--lighting", [D_LIGHTSTYLE] = "--lightstyle", [D_GAMMA] = "--gamma", [D_DEBUG] = "--debug",
};

/* The row of drawing option k (every command that draws shares them). */
static const cli_option *draw_row(int k) { return cli_find(CLI_RENDER, draw_names[k], -1); }

/* --debug's values, in ew_debug_mode order from EW_DEBUG_SPANS. */
static const char *const debug_names[] = { "spans", "edges", "overdraw", "lighting", "textures", "mips", "builds" };
enum { NDEBUG_NAMES = sizeof debug_names / sizeof *debug_names };

/* The options --classic turns off, so they cannot go with it. */
#define CLASSIC_CONFLICTS \
    ((1 << D_WATERALPHA) | (1 << D_FOG) | (1 << D_NOFOG) | (1 << D_NOWARP) | (1 << D_COLOR) | (1 << D_DITHER))

void draw_opts_init(draw_opts *d) {
    memset(d, 0, sizeof *d);
    d->alias_raster = EW_ALIAS_AUTO;
    d->occlusion = EW_OCCLUSION_AUTO;
    d->wateralpha = -1;
    d->hsr = EW_HSR_EDGE;
    d->map_rgb = -1;
}

void draw_opts_usage(FILE *f) { cli_print_options(f, CLI_RENDER, 1); }

static int bad_value(int k, const char *v) {
    const cli_option *o = draw_row(k);
    error_line("%s %s: %s must be %s", o->name, v, o->metavar, o->rule);
    return -1;
}

/* A finite decimal number (parse_decimal), *end_out just past it. */
static int number(const char *s, const char **end_out, double *out) {
    return parse_decimal(s, end_out, out);
}

static int whole_number(const char *s, double *out) {
    const char *end;
    return number(s, &end, out) == 0 && *end == '\0' ? 0 : -1;
}

static int set_value(draw_opts *d, int k, const char *v) {
    double x;
    switch (k) {
    case D_ARASTER:
        if (strcmp(v, "auto") == 0) d->alias_raster = EW_ALIAS_AUTO;
        else if (strcmp(v, "affine") == 0) d->alias_raster = EW_ALIAS_AFFINE;
        else if (strcmp(v, "subdiv") == 0) d->alias_raster = EW_ALIAS_SUBDIV;
        else if (strcmp(v, "masks") == 0) d->alias_raster = EW_ALIAS_MASKS;
        else if (strcmp(v, "sprite-cache") == 0) d->alias_raster = EW_ALIAS_SPRITE_CACHE;
        else return bad_value(k, v);
        return 0;
    case D_OCC:
        if (strcmp(v, "off") == 0) d->occlusion = EW_OCCLUSION_OFF;
        else if (strcmp(v, "auto") == 0) d->occlusion = EW_OCCLUSION_AUTO;
        else if (strcmp(v, "always") == 0) d->occlusion = EW_OCCLUSION_ALWAYS;
        else return bad_value(k, v);
        return 0;
    case D_SUBTHRESH:
        if (whole_number(v, &x) < 0 || !(x > 0 && x <= 10000))
            return bad_value(k, v);
        d->subdiv_threshold = x;
        return 0;
    case D_WATERALPHA:
        if (whole_number(v, &x) < 0 || !(x > 0 && x <= 1))
            return bad_value(k, v);
        d->wateralpha = x;
        return 0;
    case D_FOG: {
        const char *p = v;
        double f[4];
        for (int i = 0; i < 4; i++) {
            const char *end;
            if (number(p, &end, &f[i]) < 0 || *end != (i < 3 ? ',' : '\0'))
                return bad_value(k, v);
            p = end + 1;
        }
        if (!(f[0] >= 0 && f[0] <= MAX_FOG_DENSITY))
            return bad_value(k, v);
        for (int i = 1; i < 4; i++)
            if (!(f[i] >= 0 && f[i] <= 1))
                return bad_value(k, v);
        for (int i = 0; i < 4; i++) d->fog[i] = f[i];
        return 0;
    }
    case D_COLOR:
        if (strcmp(v, "8bit") == 0) d->color = EW_COLOR_8BIT;
        else if (strcmp(v, "true") == 0) d->color = EW_COLOR_TRUE;
        else return bad_value(k, v);
        return 0;
    case D_LIGHTSTYLE: {
        char *end;
        errno = 0;
        long st = strtol(v, &end, 10);
        if (end == v || *end != '=' || st < 0 || st > 63 || !isdigit((unsigned char)*v) ||
            d->nstyles >= (int)(sizeof d->styles / sizeof d->styles[0]))
            return bad_value(k, v);
        const char *val = end + 1;
        size_t len = strlen(val);
        int letters = len > 0 && len <= 64;
        for (size_t i = 0; letters && i < len; i++) letters = val[i] >= 'a' && val[i] <= 'z';
        struct draw_style *s = &d->styles[d->nstyles];
        s->style = (int)st;
        if (strcmp(val, "on") == 0 || strcmp(val, "off") == 0) {
            s->kind = 2, s->value = strcmp(val, "on") == 0;
        } else if (isdigit((unsigned char)*val) && whole_number(val, &x) == 0 && x >= 0 && x <= 1024 &&
                   x == (double)(int)x) {
            s->kind = 0, s->value = (int)x;
        } else if (letters) {
            s->kind = 1;
            memcpy(s->pattern, val, len + 1);
        } else {
            return bad_value(k, v);
        }
        d->nstyles++;
        return 0;
    }
    case D_LIGHTING:
        if (strcmp(v, "cache") == 0) d->lighting = EW_LIGHTING_CACHE;
        else if (strcmp(v, "two-pass") == 0) d->lighting = EW_LIGHTING_TWO_PASS;
        else return bad_value(k, v);
        return 0;
    case D_GAMMA:
        if (whole_number(v, &x) < 0 || !(x >= 0.5 && x <= 3))
            return bad_value(k, v);
        d->gamma = x;
        return 0;
    case D_DEBUG:
        for (int m = 0; m < NDEBUG_NAMES; m++)
            if (strcmp(v, debug_names[m]) == 0) {
                d->debug = EW_DEBUG_SPANS + m;
                return 0;
            }
        return bad_value(k, v);
    case D_HSR: {
        int m = ew_hsr_from_name(v);
        if (m < 0 || !ew_hsr_available((ew_hsr_method)m)) return bad_value(k, v);
        d->hsr = m;
        return 0;
    }
    }
    return 0;
}

int draw_option(draw_opts *d, const char *cmd, const cli_option *opt, const char *v) {
    if (!opt || !opt->draw)
        return 0;
    int k = 0;
    while (k < D_COUNT && strcmp(draw_names[k], opt->name) != 0)
        k++;
    if (k == D_COUNT)
        return 0;
    if (opt->metavar && set_value(d, k, v) < 0)
        return -1;
    if (k == D_FOG || k == D_NOFOG) {
        int other = k == D_FOG ? D_NOFOG : D_FOG;
        if (d->given & (1 << other)) {
            error_line("%s: --fog and --no-fog cannot be combined", cmd);
            return -1;
        }
    }
    if ((k == D_CLASSIC && (d->given & CLASSIC_CONFLICTS)) ||
        (((1 << k) & CLASSIC_CONFLICTS) && (d->given & (1 << D_CLASSIC)))) {
        error_line("%s: --classic is the 1996 look (8-bit, white light, no see-through surfaces, fog or "
                   "underwater warp): it cannot be combined with --color, --wateralpha, --fog, --no-fog, "
                   "--no-waterwarp or --dither", cmd);
        return -1;
    }
    /* --dither mixes palette colours for coloured light in 8-bit frames:
     * with true colour or without coloured light it would do nothing. */
    int dither = k == D_DITHER || (d->given & (1 << D_DITHER));
    int true_color = (k == D_COLOR || (d->given & (1 << D_COLOR))) && d->color == EW_COLOR_TRUE;
    int no_lit = k == D_NOLIT || (d->given & (1 << D_NOLIT));
    if (dither && true_color) {
        error_line("%s: --dither mixes palette colours for coloured light in 8-bit frames: it does nothing with "
                   "--color true", cmd);
        return -1;
    }
    if (dither && no_lit) {
        error_line("%s: --dither mixes palette colours for coloured light in 8-bit frames: it does nothing with "
                   "--no-lit", cmd);
        return -1;
    }
    d->given |= 1 << k;
    switch (k) {
    case D_NOENT: d->no_entities = 1; break;
    case D_FULLZ: d->full_zfill = 1; break;
    case D_CLASSIC: d->classic = 1; break;
    case D_NOFOG: d->fog_mode = 2; for (int c = 0; c < 4; c++) d->fog[c] = 0; break;
    case D_FOG: d->fog_mode = 1; break;
    case D_NOWARP: d->no_waterwarp = 1; break;
    case D_NOLIT: d->no_lit = 1; break;
    case D_DITHER: d->dither = 1; break;
    }
    return 1;
}

int draw_opts_apply(const draw_opts *d, ew_renderer *r, const ew_scene *scene) {
    ew_set_alias_raster(r, (ew_alias_raster)d->alias_raster, (float)d->subdiv_threshold);
    ew_set_full_zfill(r, d->full_zfill);
    ew_set_occlusion_cull(r, (ew_occlusion_mode)d->occlusion);
    ew_set_classic(r, d->classic);
    ew_set_liquid_alpha(r, (float)d->wateralpha);
    if (d->fog_mode)
        ew_set_fog(r, (float)d->fog[0], (float)d->fog[1], (float)d->fog[2], (float)d->fog[3]);
    else
        ew_set_fog(r, -1, 0, 0, 0);
    ew_set_waterwarp(r, !d->no_waterwarp);
    ew_set_hsr(r, (ew_hsr_method)d->hsr);
    ew_set_lit(r, !d->no_lit);
    ew_set_dither(r, d->dither);
    ew_set_lighting(r, (ew_lighting_mode)d->lighting);
    ew_set_gamma(r, d->gamma > 0 ? (float)d->gamma : 1.0f);
    for (int i = 0; i < 64; i++) ew_reset_lightstyle(r, i);
    for (int i = 0; i < d->nstyles; i++) {
        const struct draw_style *s = &d->styles[i];
        if (s->kind == 0) ew_set_lightstyle(r, s->style, s->value);
        else if (s->kind == 1) ew_set_lightstyle_pattern(r, s->style, s->pattern);
        else ew_set_lightstyle_switch(r, s->style, s->value);
    }
    ew_set_scene(r, scene);
    return ew_set_debug(r, (ew_debug_mode)d->debug);
}

void draw_opts_json(FILE *f, const draw_opts *d) {
    static const char *const modes[] = { "auto", "affine", "subdiv", "masks", "sprite-cache" };
    fprintf(f, ",\"entities\":%s,\"alias_raster\":\"%s\",\"subdiv_threshold\":",
            d->no_entities ? "false" : "true", modes[d->alias_raster]);
    json_number(f, d->subdiv_threshold > 0 ? d->subdiv_threshold : 40);
    static const char *const occ[] = { "off", "auto", "always" };
    fprintf(f, ",\"zfill\":\"%s\",\"occlusion\":\"%s\",\"classic\":%s,\"wateralpha\":",
            d->full_zfill ? "full" : "deferred", occ[d->occlusion], d->classic ? "true" : "false");
    if (d->wateralpha > 0)
        json_number(f, d->wateralpha);
    else
        fputs("null", f);   /* the map's */
    fputs(",\"fog\":", f);
    if (d->fog_mode) {
        for (int i = 0; i < 4; i++) {
            fputs(i ? "," : "[", f);
            json_number(f, d->fog[i]);
        }
        fputc(']', f);
    } else {
        fputs("null", f);   /* the map's */
    }
    fprintf(f, ",\"waterwarp\":%s,\"hsr\":\"%s\"", d->no_waterwarp || d->classic ? "false" : "true",
            ew_hsr_name((ew_hsr_method)d->hsr));
    fprintf(f, ",\"color\":\"%s\",\"lit\":%s,\"dither\":%s", d->color == EW_COLOR_TRUE ? "true" : "8bit",
            d->no_lit || d->classic || d->map_rgb == 0 ? "false" : "true", d->dither ? "true" : "false");
    fprintf(f, ",\"lighting\":\"%s\"", d->lighting == EW_LIGHTING_TWO_PASS ? "two-pass" : "cache");
    fputs(",\"gamma\":", f);
    json_number(f, d->gamma > 0 ? d->gamma : 1.0);
    fputs(",\"lightstyles\":[", f);
    for (int i = 0; i < d->nstyles; i++) {
        const struct draw_style *s = &d->styles[i];
        fprintf(f, "%s\"%d=", i ? "," : "", s->style);
        if (s->kind == 0) fprintf(f, "%d\"", s->value);
        else if (s->kind == 1) fprintf(f, "%s\"", s->pattern);
        else fprintf(f, "%s\"", s->value ? "on" : "off");
    }
    fputc(']', f);
    fputs(",\"debug\":", f);
    if (d->debug >= EW_DEBUG_SPANS && d->debug - EW_DEBUG_SPANS < NDEBUG_NAMES)
        json_string(f, debug_names[d->debug - EW_DEBUG_SPANS]);
    else
        fputs("null", f);
}

/* ---- loading, with the warnings ---------------------------------------- */

static void warning_line(const char *msg) {
    char buf[1024];
    snprintf(buf, sizeof buf, "%s", msg);
    for (char *p = buf; *p; p++)
        if ((unsigned char)*p < ' ' || *p == 0x7f)
            *p = '?';
    fprintf(stderr, "edgewise: warning: %s\n", buf);
}

void print_world_warnings(const ew_world *w, int quiet) {
    const char *msg;
    for (int i = 0; !quiet && (msg = ew_world_warning(w, i)) != NULL; i++)
        warning_line(msg);
}

void print_scene_warnings(const ew_scene *s, int quiet) {
    const char *msg;
    for (int i = 0; !quiet && s && (msg = ew_scene_warning(s, i)) != NULL; i++)
        warning_line(msg);
}

/* What every command takes as MAP, for the errors that refuse one. */
#define MAP_FORMS "a .bsp file, a map name with --data, or 'builtin'"

static int ends_with_bsp(const char *s) {
    size_t n = strlen(s);
    return n >= 4 && s[n - 4] == '.' && (s[n - 3] | 32) == 'b' && (s[n - 2] | 32) == 's' &&
           (s[n - 1] | 32) == 'p';
}

/* A MAP that names something on disk that cannot be a map (a directory, a
 * device), or a path that is neither a file nor a map name: one error line
 * naming what was given, rather than "maps/<path>.bsp not found". */
static int refuse_map_path(const char *map) {
    struct stat st;
    if (stat(map, &st) == 0) {
        if (S_ISDIR(st.st_mode))
            error_line("%s: a directory, not a map (" MAP_FORMS ")", map);
        else if (!S_ISREG(st.st_mode))
            error_line("%s: not a regular file (a device or pipe), not a map (" MAP_FORMS ")", map);
        else
            return 0;
        return -1;
    }
    /* Absolute or ./ ../ paths are files, never names inside maps/. */
    if (!ends_with_bsp(map) && (map[0] == '/' || strncmp(map, "./", 2) == 0 || strncmp(map, "../", 3) == 0)) {
        error_line("%s: no such file, and a path is not a map name (" MAP_FORMS ")", map);
        return -1;
    }
    return 0;
}

int stress_detail(const char *map) {
    size_t n = strlen(STRESS_MAP_PREFIX);
    long l;
    if (strncmp(map, STRESS_MAP_PREFIX, n) != 0)
        return -1;
    if (parse_long(map + n, &l) < 0 || l < 0 || l > EW_STRESS_MAX_DETAIL)
        return -2;
    return (int)l;
}

/* The stress hall (src/mapgen/stress_level.c) at detail d, as assets. */
static ew_assets *stress_assets(const char *map, int d) {
    ew_error err = { "" };
    ew_assets *a = ew_assets_create_stress(d, map, &err);
    if (!a) error_line("%s", err.msg[0] ? err.msg : "builtin: out of memory");
    return a;
}

ew_assets *load_map(const char *map, const char *data, int quiet) {
    ew_error err = { "" };
    int detail = stress_detail(map);
    if (detail == -2) {
        error_line("%s: the detail must be a whole number from 0 to %d", map, EW_STRESS_MAX_DETAIL);
        return NULL;
    }
    if (detail >= 0)
        return stress_assets(map, detail);
    if (!is_builtin(map) && refuse_map_path(map) < 0)
        return NULL;
    ew_assets *a = is_builtin(map) ? ew_assets_create_builtin(&err) : ew_assets_create(map, cli_search_path(data), &err);
    if (!a)
        error_line("%s", err.msg[0] ? err.msg : "cannot load the map");
    else
        print_world_warnings(a->world, quiet);
    return a;
}

int draw_opts_scene(const draw_opts *d, const ew_assets *a, const char *map, const char *data,
                    int need_scene, int quiet, ew_scene **out) {
    ew_error err = { "" };
    *out = NULL;
    if (d->no_entities && !need_scene)
        return 0;
    /* the stress hall has no moving things: an empty scene */
    ew_scene *s = d->no_entities || stress_detail(map) >= 0 ? ew_scene_create(a->world, &err)
                  : is_builtin(map) ? ew_scene_create_builtin(a->world, &err)
                                    : ew_scene_create_from_map(a->world, map, cli_search_path(data), &err);
    if (!s) {
        error_line("%s", err.msg[0] ? err.msg : "cannot make the scene");
        return -1;
    }
    print_scene_warnings(s, quiet);
    *out = s;
    return 0;
}

void cli_args_init(cli_args *a, cli_cmd cmd, int argc, char **argv, const char **maps, int max_maps,
                   draw_opts *draw, const char *help, const char *help_tail) {
    cli_parser_init(&a->p, cmd, argc, argv, 2);
    a->maps = maps, a->nmaps = 0, a->max_maps = max_maps, a->draw = draw;
    a->help = help, a->help_tail = help_tail, a->opt = NULL, a->value = NULL, a->stop = 0, a->quiet = 0;
}

/* The map in value, or -1 after one error line. */
static int add_map(cli_args *a, const char *cmd, const char *value) {
    if (!*value) {
        error_line("%s: empty map name", cmd);
        return -1;
    }
    if (a->nmaps == a->max_maps) {
        if (a->max_maps == 1)
            error_line("%s: one map only ('%s' and '%s')", cmd, a->maps[0], value);
        else if (a->max_maps == 0)
            error_line("%s: unexpected argument '%s'", cmd, value);
        else
            error_line("%s: more than %d maps", cmd, a->max_maps);
        return -1;
    }
    a->maps[a->nmaps++] = value;
    return 0;
}

int cli_next_arg(cli_args *a) {
    const char *cmd = cli_commands[a->p.cmd].form;
    for (;;) {
        int r = cli_parse(&a->p, &a->opt, &a->value);
        if (r < 0 || (r == CLI_POSITIONAL && add_map(a, cmd, a->value) < 0)) {
            a->stop = -1;
            return 0;
        }
        if (r == CLI_END) return 0;
        if (r == CLI_POSITIONAL) continue;
        if (cli_is(a->opt, "--quiet")) {
            a->quiet = 1;
            continue;
        }
        if (a->help && cli_is(a->opt, "--help")) {
            cli_print_help(stdout, a->p.cmd, a->help);
            if (a->draw) draw_opts_usage(stdout);
            if (a->help_tail) fputs(a->help_tail, stdout);
            a->stop = 1;
            return 0;
        }
        int dr = a->draw ? draw_option(a->draw, cmd, a->opt, a->value) : 0;
        if (dr < 0) {
            a->stop = -1;
            return 0;
        }
        if (dr == 0) return 1;
    }
}

int cli_set_once(const char *cmd, const char *name, const char *v, const char **slot) {
    if (!*v) {
        error_line("%s: %s: empty name", cmd, name);
        return -1;
    }
    if (*slot) {
        error_line("%s: %s given twice", cmd, name);
        return -1;
    }
    *slot = v;
    return 0;
}

int cli_add_size(const char *cmd, const char *v, int (*sizes)[2], int *n, int max) {
    if (*n == max) {
        error_line("%s: more than %d sizes", cmd, max);
        return -1;
    }
    if (parse_size(v, &sizes[*n][0], &sizes[*n][1]) < 0) return -1;
    (*n)++;
    return 0;
}

int cli_int_once(const char *cmd, const char *name, const char *v, long lo, long hi, int *given, int *out) {
    long l;
    if (parse_long(v, &l) < 0 || l < lo || l > hi) {
        error_line("%s: %s %s: expected %ld to %ld", cmd, name, v, lo, hi);
        return -1;
    }
    if ((*given)++) {
        error_line("%s: %s given twice", cmd, name);
        return -1;
    }
    *out = (int)l;
    return 0;
}
