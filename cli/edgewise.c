/*
 * edgewise: the command line.
 *
 *   edgewise render MAP [options]   one frame to a PNG (and --stats as JSON)
 *   edgewise demo [options]         the built-in scene, no files needed
 *   edgewise views MAP              the view set of BENCHMARK.md
 *   edgewise info MAP               what the BSP holds
 *
 * stdout carries only data (stats JSON, views, info) so it can be piped;
 * progress ("wrote x.png") and errors go to stderr.  Every error is one line
 * "edgewise: <message>"; usage errors exit 2, everything else that fails 1.
 */
#include "edgewise.h"
#include "cli.h"

#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Which view of the built-in scene `edgewise demo` shows. */
#define EW_DEMO_VIEW 0

enum { EXIT_USAGE = 2 };

/* Frame sizes ew_renderer_create accepts. */
enum { MIN_W = 320, MIN_H = 200, MAX_W = 7680, MAX_H = 4320 };

/* Camera values beyond these only make the renderer's float maths overflow. */
#define MAX_COORD 1e6
/* The rules of --fov and --pos/--angles, the same in the help and the errors. */
#define VEC3_RULE "three numbers from -1000000 to 1000000 separated by commas"
#define MAX_TIME 1e6

static const char usage_head[] =
    "usage: edgewise COMMAND [ARGS]\n"
    "\n"
    "commands:\n"
    "@COMMANDS@\n"
    "  help, --help           this text\n"
    "  --version              the version\n"
    "\n"
    "MAP is a path to a .bsp file, a map name looked up as maps/NAME.bsp in\n"
    "the game directory given by --data, or the word 'builtin'.  render and view\n"
    "also take 'builtin:polyhedra': moving polyhedra drawn by a 1/z-sorted edge\n"
    "list, no BSP (see edgewise render builtin:polyhedra --help).\n"
    "\n"
    "render options:\n"
    CLI_OPTIONS_HERE
    "\n"
    "what is drawn (render, demo, bench and soak alike):\n";
static const char usage_tail[] =
    "\n"
    "demo options: --size, --view, --fov, --time, --out (default demo.png), --stats,\n"
    "  --quiet, the light, particle and thread options of render and what is drawn\n"
    "\n"
    "Numbers are decimal (12, -0.5, .25, 1e3): no hex, inf or nan, no blanks.\n"
    "\n"
    "Warnings about a map's optional data (a malformed worldspawn key, ...) go to\n"
    "stderr as 'edgewise: warning: ...' lines in every command that loads a map.\n"
    "\n"
    "examples:\n"
    "  edgewise demo\n"
    "  edgewise render e1m1 --data ../shared/data/librequake --view 3 --size 1280x720\n"
    "  edgewise render maps/start.bsp --pos 0,0,64 --angles 0,90,0 --out start.png\n"
    "  edgewise views e1m1 --data ../shared/data/librequake\n";

/* Prints one error line; control characters (from file names or arguments)
 * are replaced so the message stays one line. */
static void print_usage(void) {
    const char *m = strstr(usage_head, "@COMMANDS@\n");
    printf("%.*s", (int)(m - usage_head), usage_head);
    for (int c = 0; c < CLI_NCMDS; c++) {
        const cli_command *cc = &cli_commands[c];
        if (c == CLI_HELP || strcmp(cc->form, cc->name) != 0) continue;  /* help below; the forms */
        char head[64];
        snprintf(head, sizeof head, "%s %.*s", cc->name, (int)strcspn(cc->synopsis, "\n"), cc->synopsis);
        printf("  %-22s %s\n", head, cc->summary);  /* one line a command (tests/install_test.sh) */
    }
    cli_print_help(stdout, CLI_RENDER, m + strlen("@COMMANDS@\n"));
    draw_opts_usage(stdout);
    fputs(usage_tail, stdout);
}

void error_line(const char *fmt, ...) {
    char buf[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    for (char *p = buf; *p; p++)
        if ((unsigned char)*p < ' ' || *p == 0x7f)
            *p = '?';
    fprintf(stderr, "edgewise: %s\n", buf);
}

/* ---- options --------------------------------------------------------------- */

enum {
    O_DATA = 1 << 0, O_SIZE = 1 << 1, O_VIEW = 1 << 2, O_POS = 1 << 3, O_ANGLES = 1 << 4,
    O_FOV = 1 << 5, O_TIME = 1 << 6, O_OUT = 1 << 7, O_STATS = 1 << 8,
    O_DLIGHT = 1 << 11, O_QUIET = 1 << 12,
    O_PARTICLES = 1 << 14, O_THREADS = 1 << 15
};
#define MAX_CLI_DLIGHTS 32

/* The O_* flag of each option render, demo, views and info take (their
 * rows: cli/options.c); 0 for the drawing options and --help. */
static int flag_of(const char *name) {
    static const struct { const char *name; int flag; } flags[] = {
        { "--data", O_DATA }, { "--size", O_SIZE }, { "--view", O_VIEW }, { "--pos", O_POS },
        { "--angles", O_ANGLES }, { "--fov", O_FOV }, { "--time", O_TIME }, { "--out", O_OUT },
        { "--stats", O_STATS }, { "--dlight", O_DLIGHT },
        { "--particles", O_PARTICLES }, { "--threads", O_THREADS },
    };
    for (size_t k = 0; k < sizeof flags / sizeof flags[0]; k++)
        if (strcmp(flags[k].name, name) == 0) return flags[k].flag;
    return 0;
}

typedef struct options {
    int         given;        /* O_* flags seen */
    const char *map, *data, *out;
    int         width, height, view;
    float       pos[3], angles[3];
    double      fov, time;
    float       dlights[MAX_CLI_DLIGHTS][7];  /* x, y, z, radius, r, g, b */
    int         ndlights;
    int         particles, threads;
    draw_opts   draw;         /* what is drawn (cli/draw_options.c) */
} options;

/* strtol accepts leading blanks; a command-line number should not. */
static int starts_number(const char *s) {
    return *s && !isspace((unsigned char)*s);
}

int parse_long(const char *s, long *out) {
    if (!starts_number(s))
        return -1;
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (end == s || *end || errno == ERANGE)
        return -1;
    *out = v;
    return 0;
}

/* The one number syntax of the command line: [+-] digits [. digits] [e [+-]
 * digits], a digit before or after the point.  strtod alone also takes hex
 * floats (0x10), "inf", "nan" and leading blanks, which help never promises. */
int parse_decimal(const char *s, const char **end, double *out) {
    const char *p = s;
    if (*p == '+' || *p == '-') p++;
    int digits = 0;
    while (*p >= '0' && *p <= '9') p++, digits++;
    if (*p == '.') {
        p++;
        while (*p >= '0' && *p <= '9') p++, digits++;
    }
    if (!digits) return -1;
    if (*p == 'e' || *p == 'E') {
        const char *q = p + 1;
        if (*q == '+' || *q == '-') q++;
        if (*q >= '0' && *q <= '9') {
            while (*q >= '0' && *q <= '9') q++;
            p = q;
        }
    }
    char *stop;
    errno = 0;
    double v = strtod(s, &stop);
    if (stop != p || !isfinite(v)) return -1;  /* strtod read something else; or out of range */
    *out = v;
    *end = p;
    return 0;
}

static int parse_double(const char *s, double *out) {
    const char *end;
    return parse_decimal(s, &end, out) == 0 && *end == '\0' ? 0 : -1;
}

/* "X,Y,Z": exactly three finite numbers within +-MAX_COORD; one rule, one message. */
static int parse_vec3(const char *opt, const char *s, float v[3]) {
    const char *p = s;
    for (int i = 0; i < 3; i++) {
        const char *end;
        double d;
        if (parse_decimal(p, &end, &d) < 0 || fabs(d) > MAX_COORD || *end != (i < 2 ? ',' : '\0'))
            goto bad;
        v[i] = (float)d;
        p = end + 1;
    }
    return 0;
bad:
    error_line("%s %s: must be " VEC3_RULE ", e.g. %s", opt, s,
               strcmp(opt, "--pos") == 0 ? "128,-64,40" : "0,90,0");
    return -1;
}

/* --threads N of every command: 0 (one per core) up to the library's cap. */
int parse_threads(const char *v, int *out) {
    long l;
    if (parse_long(v, &l) < 0 || l < 0 || l > EW_MAX_THREADS) {
        error_line("--threads %s: must be " THREADS_RULE, v);
        return -1;
    }
    *out = (int)l;
    return 0;
}

int parse_size(const char *s, int *w, int *h) {
    long lw, lh;
    const char *x = strpbrk(s, "xX");
    char buf[64];
    if (!x || (size_t)(x - s) >= sizeof buf)
        goto bad;
    memcpy(buf, s, (size_t)(x - s));
    buf[x - s] = '\0';
    if (parse_long(buf, &lw) < 0 || parse_long(x + 1, &lh) < 0)
        goto bad;
    if (lw < MIN_W || lw > MAX_W || lh < MIN_H || lh > MAX_H) {
        error_line("--size %s: out of range (from %dx%d up to %dx%d)", s, MIN_W, MIN_H, MAX_W,
                   MAX_H);
        return -1;
    }
    *w = (int)lw;
    *h = (int)lh;
    return 0;
bad:
    error_line("--size %s: expected WIDTHxHEIGHT, e.g. 640x480", s);
    return -1;
}

int check_png_name(const char *opt, const char *name) {
    size_t n = strlen(name);
    if (n > 4 && name[n - 4] == '.' && tolower((unsigned char)name[n - 3]) == 'p' &&
        tolower((unsigned char)name[n - 2]) == 'n' && tolower((unsigned char)name[n - 1]) == 'g')
        return 0;
    error_line("%s %s: edgewise writes PNG pictures only: the name must end in .png", opt, name);
    return -1;
}

/* Checks and stores one option's value; prints the error itself. */
static int set_option(options *o, int flag, const char *name, const char *v) {
    long l;
    double d;
    switch (flag) {
    case O_DATA:
        if (!*v) {
            error_line("--data: empty directory name");
            return -1;
        }
        o->data = v;
        return 0;
    case O_OUT:
        if (!*v) {
            error_line("--out: empty file name");
            return -1;
        }
        if (check_png_name("--out", v) < 0) return -1;
        o->out = v;
        return 0;
    case O_SIZE:
        return parse_size(v, &o->width, &o->height);
    case O_VIEW:
        if (parse_long(v, &l) < 0) {
            error_line("--view %s: not a whole number", v);
            return -1;
        }
        /* The upper bound depends on the map: checked once it is loaded. */
        if (l < 0 || l > INT_MAX) {
            error_line("--view %s: out of range (views are numbered from 0)", v);
            return -1;
        }
        o->view = (int)l;
        return 0;
    case O_POS:
        return parse_vec3(name, v, o->pos);
    case O_ANGLES:
        return parse_vec3(name, v, o->angles);
    case O_FOV:
        if (parse_double(v, &d) < 0) {
            error_line("--fov %s: not a number", v);
            return -1;
        }
        if (!(d > 1 && d < 179)) {
            error_line("--fov %s: must be " FOV_RULE, v);
            return -1;
        }
        o->fov = d;
        return 0;
    case O_TIME:
        if (parse_double(v, &d) < 0) {
            error_line("--time %s: not a number", v);
            return -1;
        }
        if (d < 0 || d > MAX_TIME) {
            error_line("--time %s: must be between 0 and %g seconds", v, MAX_TIME);
            return -1;
        }
        o->time = d;
        return 0;
    case O_DLIGHT: {
        if (o->ndlights >= MAX_CLI_DLIGHTS) {
            error_line("--dlight: at most %d lights", MAX_CLI_DLIGHTS);
            return -1;
        }
        float *dl = o->dlights[o->ndlights];
        /* X,Y,Z,R or X,Y,Z,R,r,g,b: split at the commas, each a number. */
        double f[7];
        int n = 0;
        const char *p = v, *end = v;
        while (n < 7) {
            if (parse_decimal(p, &end, &f[n]) < 0) break;
            n++;
            if (*end == ',') p = end + 1;
            else break;
        }
        int ok = (n == 4 || n == 7) && *end == '\0' && f[3] > 0 && f[3] <= 100000 && fabs(f[0]) <= 1e6 &&
                 fabs(f[1]) <= 1e6 && fabs(f[2]) <= 1e6;
        for (int k = 4; ok && k < n; k++) ok = f[k] >= 0 && f[k] <= 1;
        if (!ok) {
            error_line("--dlight %s: X,Y,Z,R[,r,g,b] must be a position, a radius above 0, at most 100000, "
                       "and optionally a colour of three numbers from 0 to 1", v);
            return -1;
        }
        for (int k = 0; k < 4; k++) dl[k] = (float)f[k];
        for (int k = 4; k < 7; k++) dl[k] = n == 7 ? (float)f[k] : 1.0f;
        o->ndlights++;
        return 0;
    }
    case O_PARTICLES:
        if (parse_long(v, &l) < 0 || l < 0 || l > 1000000) {
            error_line("--particles %s: expected a count from 0 to 1000000", v);
            return -1;
        }
        o->particles = (int)l;
        return 0;
    case O_THREADS:
        return parse_threads(v, &o->threads);
    }
    return 0;
}

/* Parses argv[2..] for command cmd (its options: the table's rows).
 * needs_map: the command takes MAP.  Returns 0, 1 for --help (usage
 * printed), or -1 (error printed). */
static int parse_args(int argc, char **argv, cli_cmd cmd_id, int needs_map, options *o) {
    const char *cmd = cli_commands[cmd_id].name, *map[1] = { NULL };
    cli_args args;
    cli_args_init(&args, cmd_id, argc, argv, map, needs_map, &o->draw, NULL, NULL);
    while (cli_next_arg(&args)) {
        const cli_option *opt = args.opt;
        const char *value = args.value;
        if (cli_is(opt, "--help")) {
            print_usage();
            return 1;
        }
        int flag = flag_of(opt->name);
        if (value && set_option(o, flag, opt->name, value) < 0)
            return -1;
        o->given |= flag;
    }
    if (args.stop)
        return args.stop;
    if (map[0]) o->map = map[0];
    if (args.quiet) o->given |= O_QUIET;
    if (needs_map && !o->map) {
        error_line("%s: missing MAP (a .bsp path, a map name with --data, or 'builtin')", cmd);
        return -1;
    }
    if (!!(o->given & O_POS) != !!(o->given & O_ANGLES)) {
        error_line("%s: --pos and --angles go together", cmd);
        return -1;
    }
    if (o->ndlights && o->draw.lighting == EW_LIGHTING_TWO_PASS) {
        error_line("%s: --dlight is drawn by the surface cache only: it cannot be combined with --lighting two-pass",
                   cmd);
        return -1;
    }
    if ((o->given & O_POS) && (o->given & O_VIEW)) {
        error_line("%s: --view cannot be combined with --pos/--angles", cmd);
        return -1;
    }
    return 0;
}

/* ---- shared steps ---------------------------------------------------------- */

int is_builtin(const char *map) { return strcmp(map, "builtin") == 0; }

/* "maps/e1m1.bsp" -> "e1m1", for default file names and the stats. */
void map_basename(const char *map, char *out, size_t size) {
    const char *b = strrchr(map, '/');
    b = b ? b + 1 : map;
    size_t n = strlen(b);
    if (n > 4 && (strcmp(b + n - 4, ".bsp") == 0 || strcmp(b + n - 4, ".BSP") == 0))
        n -= 4;
    if (n == 0) {
        b = "map";
        n = 3;
    }
    snprintf(out, size, "%.*s", (int)n, b);
}

static ew_assets *load(const options *o) { return load_map(o->map, o->data, !!(o->given & O_QUIET)); }

/* Valid UTF-8 (RFC 3629: shortest forms, no surrogates, at most U+10FFFF):
 * the length of the sequence at p, 0 if p does not start one. */
static int utf8_length(const unsigned char *p) {
    unsigned char c = p[0];
    int n;
    unsigned char lo = 0x80, hi = 0xbf;  /* the second byte's range */
    if (c < 0x80) return 1;
    if (c >= 0xc2 && c <= 0xdf) n = 2;
    else if (c >= 0xe0 && c <= 0xef) n = 3, lo = c == 0xe0 ? 0xa0 : 0x80, hi = c == 0xed ? 0x9f : 0xbf;
    else if (c >= 0xf0 && c <= 0xf4) n = 4, lo = c == 0xf0 ? 0x90 : 0x80, hi = c == 0xf4 ? 0x8f : 0xbf;
    else return 0;
    if (p[1] < lo || p[1] > hi) return 0;
    for (int i = 2; i < n; i++)
        if (p[i] < 0x80 || p[i] > 0xbf) return 0;  /* a NUL ends the check too */
    return n;
}

size_t json_char(const unsigned char **p, char out[8]) {
    const unsigned char *s = *p;
    int n = utf8_length(s);
    if (n == 1 && (*s == '"' || *s == '\\')) {
        out[0] = '\\', out[1] = (char)*s, out[2] = '\0';
        n = 1;
    } else if (n == 1 && *s >= 0x20 && *s != 0x7f) {
        out[0] = (char)*s, out[1] = '\0';
    } else if (n > 1) {
        memcpy(out, s, (size_t)n);
        out[n] = '\0';
    } else {
        /* a control byte, DEL, or a byte outside valid UTF-8: its Latin-1 reading */
        snprintf(out, 8, "\\u%04x", *s);
        n = 1;
    }
    *p = s + n;
    return strlen(out);
}

void json_string(FILE *f, const char *s) {
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)s; *p;) {
        char c[8];
        json_char(&p, c);
        fputs(c, f);
    }
    fputc('"', f);
}

/* JSON has no inf/nan. */
void json_number(FILE *f, double v) {
    if (isfinite(v))
        fprintf(f, "%.6g", v);
    else
        fputs("null", f);
}

static void print_stats(const char *name, const options *o, int view, const ew_camera *cam,
                        const char *out, const ew_stats *s, int dark) {
    FILE *f = stdout;
    fputs("{\"map\":", f);
    json_string(f, name);
    fprintf(f, ",\"width\":%d,\"height\":%d,\"view\":", o->width, o->height);
    if (view >= 0)
        fprintf(f, "%d", view);
    else
        fputs("null", f);
    fputs(",\"origin\":[", f);
    for (int i = 0; i < 3; i++) {
        json_number(f, cam->origin[i]);
        fputs(i < 2 ? "," : "],\"angles\":[", f);
    }
    for (int i = 0; i < 3; i++) {
        json_number(f, cam->angles[i]);
        fputs(i < 2 ? "," : "]", f);
    }
    fputs(",\"fov\":", f);
    json_number(f, cam->fov);
    fputs(",\"time\":", f);
    json_number(f, cam->time);
    fputs(",\"out\":", f);
    json_string(f, out);
    fprintf(f,
            ",\"pixels\":%ld,\"pixels_written\":%ld,\"pixels_covered\":%ld,\"overdraw\":",
            s->pixels, s->pixels_written, s->pixels_covered);
    json_number(f, s->overdraw);
    fprintf(f,
            ",\"edges\":%d,\"edges_cached\":%d,\"surfaces\":%d,\"surfaces_shown\":%d,\"faces_occluded\":%d,"
            "\"spans\":%d,\"surfaces_built\":%d,\"surfaces_cached\":%d,\"visible_leaves\":%d,\"dropped\":%d",
            s->edges, s->edges_cached, s->surfaces, s->surfaces_shown, s->faces_occluded, s->spans, s->surfaces_built,
            s->surfaces_cached, s->visible_leaves, s->dropped);
    fprintf(f,
            ",\"entities_drawn\":%d,\"entities_culled\":%d,\"entities_hidden\":%d,\"entities_unknown\":%d,"
            "\"models_missing\":%d,\"alias_tris\":%d,\"alias_tris_subdiv\":%d,\"alias_pixels\":%ld,"
            "\"alias_sprite_hits\":%d,\"alias_sprite_misses\":%d,\"particles\":%d,\"surfaces_rebuilt_by_dlights\":%d",
            s->entities_drawn, s->entities_culled, s->entities_hidden, s->entities_unknown, s->models_missing,
            s->alias_tris, s->alias_tris_subdiv, s->alias_pixels,
            s->alias_sprite_hits, s->alias_sprite_misses, s->particles,
            s->surfaces_rebuilt_by_dlights);
    fprintf(f,
            ",\"seethrough_surfaces\":%d,\"fence_pixels\":%ld,\"translucent_pixels\":%ld,"
            "\"fog_pixels\":%ld,\"underwater\":%s",
            s->seethrough_surfaces, s->fence_pixels, s->translucent_pixels, s->fog_pixels,
            s->underwater ? "true" : "false");
    fprintf(f, ",\"dark\":%s", dark ? "true" : "false");
    /* the hidden-surface method's own counters, by the names it gives them */
    fprintf(f, ",\"hsr_bytes\":%ld,\"hsr_counters\":{", s->hsr_bytes);
    for (int i = 0, n = 0; i < EW_HSR_COUNTERS; i++) {
        const char *name = ew_hsr_counter_name((ew_hsr_method)o->draw.hsr, i);
        if (!name) continue;
        fputs(n++ ? "," : "", f);
        json_string(f, name);
        fprintf(f, ":%ld", s->hsr_counters[i]);
    }
    fputs("}", f);
    draw_opts_json(f, &o->draw);
    const char *ms_names[6] = { "ms_front", "ms_scan", "ms_draw", "ms_models", "ms_total", "ms_serial" };
    const double ms[6] = { s->ms_front, s->ms_scan, s->ms_draw, s->ms_models, s->ms_total, s->ms_serial };
    for (int i = 0; i < 6; i++) {
        fprintf(f, ",\"%s\":", ms_names[i]);
        json_number(f, ms[i]);
    }
    fputs("}\n", f);
}

/* ---- commands -------------------------------------------------------------- */

static int cmd_render(options *o, int default_view, const char *default_out) {
    ew_assets *a = load(o);
    if (!a)
        return 1;

    char name[256];
    map_basename(o->map, name, sizeof name);
    int rc = 1, view = -1;
    ew_renderer *r = NULL;
    ew_scene *scene = NULL;
    ew_error err = { "" };
    ew_camera cam;
    memset(&cam, 0, sizeof cam);

    if (o->given & O_POS) {
        memcpy(cam.origin, o->pos, sizeof cam.origin);
        memcpy(cam.angles, o->angles, sizeof cam.angles);
        cam.fov = 90;
    } else {
        ew_camera views[EW_MAX_VIEWS];
        int n = ew_benchmark_views(a->world, views);
        view = (o->given & O_VIEW) ? o->view : default_view;
        if (n == 0) {
            error_line("%s: no views (no info_player* or info_intermission entity); "
                       "use --pos and --angles", name);
            goto done;
        }
        if (view >= n) {
            /* A usage error like --view -1, found only once the map is loaded. */
            error_line("--view %d: out of range, %s has %d view%s (0 to %d)", view, name, n,
                       n == 1 ? "" : "s", n - 1);
            rc = EXIT_USAGE;
            goto done;
        }
        cam = views[view];
    }
    if (o->given & O_FOV)
        cam.fov = (float)o->fov;
    if (o->given & O_TIME)
        cam.time = o->time;

    char out[512];
    if (o->out)
        snprintf(out, sizeof out, "%s", o->out);
    else if (default_out)
        snprintf(out, sizeof out, "%s", default_out);
    else if (view >= 0)
        snprintf(out, sizeof out, "%s_v%d.png", name, view);
    else
        snprintf(out, sizeof out, "%s_free.png", name);

    r = ew_renderer_create(&(ew_renderer_desc){ .world = a->world, .palette = a->palette,
            .colormap = a->colormap, .width = o->width, .height = o->height, .threads = 1,
            .color = (ew_color_mode)o->draw.color }, &err);
    if (!r) {
        error_line("%s", err.msg[0] ? err.msg : "cannot create the renderer");
        goto done;
    }
    if ((o->given & O_THREADS) && ew_set_threads(r, o->threads) < 0) {
        error_line("--threads %d: out of memory", o->threads);
        goto done;
    }
    /* The moving things: the map's entities (or the built-in scene's),
     * plus lights and particles asked for on the command line. */
    if (draw_opts_scene(&o->draw, a, o->map, o->data, o->ndlights || o->particles,
                        !!(o->given & O_QUIET), &scene) < 0)
        goto done;
    if (scene) {
        for (int i = 0; i < o->ndlights; i++)
            ew_scene_add_dlight_rgb(scene, o->dlights[i], o->dlights[i][3], &o->dlights[i][4]);
        if (o->particles) {
            /* A cloud in front of the camera, the same every run. */
            ew_camera probe = cam;
            float d2r = 3.14159265f / 180, fwd[3], c[3];
            fwd[0] = cosf(probe.angles[0] * d2r) * cosf(probe.angles[1] * d2r);
            fwd[1] = cosf(probe.angles[0] * d2r) * sinf(probe.angles[1] * d2r);
            fwd[2] = -sinf(probe.angles[0] * d2r);
            for (int k = 0; k < 3; k++) c[k] = cam.origin[k] + fwd[k] * 160;
            ew_scene_add_particles(scene, o->particles, c, 64, 1996);
        }
    }
    if (draw_opts_apply(&o->draw, r, scene) < 0) {
        error_line("%s: out of memory for the debug mode", name);
        goto done;
    }
    ew_stats st;
    memset(&st, 0, sizeof st);
    if (ew_render(r, &cam, &st) < 0 || !(ew_frame_pixels(r) || ew_frame_rgba(r)) ||
        ew_frame_width(r) != o->width || ew_frame_height(r) != o->height) {
        error_line("%s: cannot render this camera (origin %g,%g,%g angles %g,%g,%g fov %g)",
                   name, cam.origin[0], cam.origin[1], cam.origin[2], cam.angles[0],
                   cam.angles[1], cam.angles[2], cam.fov);
        goto done;
    }
    if (ew_write_frame_png(r, out, &err) < 0) {
        error_line("%s", err.msg);
        goto done;
    }
    /* A nearly black picture is never silent (cli/dark.c): one warning with its likely cause. */
    int dark = warn_if_dark(r, a->world, &cam, out, !!(o->given & O_QUIET), NULL);
    o->draw.map_rgb = ew_world_has_rgb_light(a->world);  /* "lit": coloured light actually used */
    if (o->given & O_STATS)
        print_stats(name, o, view, &cam, out, &st, dark);
    fprintf(stderr, "wrote %s (%dx%d)\n", out, o->width, o->height);
    rc = 0;
done:
    ew_renderer_destroy(r);
    ew_scene_destroy(scene);
    ew_assets_destroy(a);
    if (fflush(stdout) != 0 && rc == 0) {
        error_line("stdout: %s", strerror(errno));
        rc = 1;
    }
    return rc;
}

static int cmd_views(options *o) {
    ew_assets *a = load(o);
    if (!a)
        return 1;
    ew_camera views[EW_MAX_VIEWS];
    int n = ew_benchmark_views(a->world, views);
    for (int i = 0; i < n; i++) {
        /* The yaw as a compass reading, 0 to under 360 (a player start's
         * four views turn by 90 from its angle and may pass 360). */
        double yaw = fmod((double)views[i].angles[1], 360.0);
        if (yaw < 0) yaw += 360.0;
        if (yaw >= 359.9995) yaw = 0;  /* would print as 360 */
        printf("%d %g %g %g %g %g %g\n", i, views[i].origin[0], views[i].origin[1],
               views[i].origin[2], views[i].angles[0], yaw, views[i].angles[2]);
    }
    ew_assets_destroy(a);
    if (fflush(stdout) != 0) {
        error_line("stdout: %s", strerror(errno));
        return 1;
    }
    return 0;
}

static int cmd_info(options *o) {
    ew_assets *a = load(o);
    if (!a)
        return 1;
    ew_world_info info;
    memset(&info, 0, sizeof info);
    ew_world_get_info(a->world, &info);
    char version[sizeof info.version + 1];
    snprintf(version, sizeof version, "%.*s", (int)sizeof info.version, info.version);

    printf("map       %s\n", o->map);
    printf("version   %s\n", version[0] ? version : "?");
    printf("%-14s %10s %10s %8s\n", "lump", "offset", "length", "count");
    for (int i = 0; i < 15; i++) {
        const ew_lump_info *l = &info.lumps[i];
        printf("%-14s %10lu %10lu %8d\n", l->name ? l->name : "?", (unsigned long)l->offset,
               (unsigned long)l->length, l->count);
    }
    /* BSPX lumps after the standard ones: every one listed, known or not */
    ew_bspx_lump_info bx;
    int nbx = 0;
    while (ew_world_bspx_lump(a->world, nbx, &bx) == 0) nbx++;
    if (nbx > 0) {
        static const char *const use[] = {"unused", "used", "ignored", "replaced by .lit"};
        printf("bspx      %d lump%s\n", nbx, nbx == 1 ? "" : "s");
        printf("%-24s %10s %10s  %s\n", "bspx lump", "offset", "length", "edgewise");
        for (int i = 0; ew_world_bspx_lump(a->world, i, &bx) == 0; i++)
            printf("%-24s %10lu %10lu  %s\n", bx.name, (unsigned long)bx.offset, (unsigned long)bx.length,
                   (unsigned)bx.use < 4 ? use[bx.use] : "?");
    } else {
        printf("bspx      none\n");
    }
    printf("models    %d\n", info.models);
    printf("textures  %d (%d missing)\n", info.textures, info.textures_missing);
    printf("faces     %d\n", info.faces);
    printf("leaves    %d\n", info.leaves);
    printf("nodes     %d\n", info.nodes);
    ew_assets_destroy(a);
    if (fflush(stdout) != 0) {
        error_line("stdout: %s", strerror(errno));
        return 1;
    }
    return 0;
}

int main(int argc, char **argv) {
    if (argc < 2) {
        error_line("missing command (try 'edgewise --help')");
        return EXIT_USAGE;
    }
    const char *cmd = argv[1];
    if (strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0 || strcmp(cmd, "help") == 0) {
        print_usage();
        return 0;
    }
    if (strcmp(cmd, "--version") == 0 || strcmp(cmd, "version") == 0) {
        printf("edgewise %s\n", ew_version());
        return 0;
    }

    options o;
    memset(&o, 0, sizeof o);
    o.width = 640;
    o.height = 480;
    o.fov = 90;
    draw_opts_init(&o.draw);

    int pr;
    /* The moving polyhedra have no map: their own command line. */
    if (strcmp(cmd, "render") == 0 && has_polyhedra(argc, argv))
        return cmd_polyhedra(argc, argv);
    if (strcmp(cmd, "view") == 0 && has_polyhedra(argc, argv))
        return cmd_view_polyhedra(argc, argv);
    if (strcmp(cmd, "render") == 0) {
        pr = parse_args(argc, argv, CLI_RENDER, 1, &o);
        return pr < 0 ? EXIT_USAGE : pr > 0 ? 0 : cmd_render(&o, 0, NULL);
    }
    if (strcmp(cmd, "demo") == 0) {
        pr = parse_args(argc, argv, CLI_DEMO, 0, &o);
        o.map = "builtin";
        return pr < 0 ? EXIT_USAGE : pr > 0 ? 0 : cmd_render(&o, EW_DEMO_VIEW, "demo.png");
    }
    if (strcmp(cmd, "views") == 0) {
        pr = parse_args(argc, argv, CLI_VIEWS, 1, &o);
        return pr < 0 ? EXIT_USAGE : pr > 0 ? 0 : cmd_views(&o);
    }
    if (strcmp(cmd, "info") == 0) {
        pr = parse_args(argc, argv, CLI_INFO, 1, &o);
        return pr < 0 ? EXIT_USAGE : pr > 0 ? 0 : cmd_info(&o);
    }
    if (strcmp(cmd, "bench") == 0)
        return cmd_bench(argc, argv);
    if (strcmp(cmd, "soak") == 0)
        return cmd_soak(argc, argv);
    if (strcmp(cmd, "hsr") == 0)
        return cmd_hsr(argc, argv);
    if (strcmp(cmd, "view") == 0)
        return cmd_view(argc, argv);
    if (strcmp(cmd, "shots") == 0)
        return cmd_shots(argc, argv);
    if (strcmp(cmd, "fly") == 0)
        return cmd_fly(argc, argv);
    if (strcmp(cmd, "timedemo") == 0)
        return cmd_timedemo(argc, argv);
    cli_unknown_command(cmd);
    return EXIT_USAGE;
}
