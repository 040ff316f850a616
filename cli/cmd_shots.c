/*
 * edgewise shots MAP|DIR|PAK... [--data DIR] [--out DIR] [--size WxH]
 *                [--views all|N,M|best] [--jobs N] [--force]
 *                [--manifest FILE.jsonl] [--contact-sheet FILE.png] [--quiet]
 *                [what is drawn, --color included]
 *
 * Batch pictures.  The inputs expand to a list of maps: a .bsp path (or a
 * map name with --data, or 'builtin'), a game directory (its maps/NAME.bsp,
 * loose and inside its pak*.pak, loose winning), a directory of .bsp files,
 * or a .pak (its maps/NAME.bsp).  Each map is loaded once; each chosen view is
 * rendered and written as OUTDIR/MAP_vN.png (OUTDIR/MAP_best.png for
 * --views best), and one JSON line per picture goes to the manifest.
 *
 * Work is split by map: --jobs N forks N workers that take the next map
 * from a counter in shared memory, append their own manifest lines (one
 * write(2) each, on an O_APPEND descriptor, shorter than PIPE_BUF) and
 * report each map started and finished to the parent through a pipe; the
 * parent draws the progress.  Each worker holds one map and one frame at a
 * time, so memory grows with N times the largest map plus frame.
 */
#define _DEFAULT_SOURCE
#include "cli.h"
#include "edgewise.h"
#include "edgewise_lab.h"

#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#define MAX_JOBS 256
#define SUMMARY_FAILURES 10  /* failed maps named in the summary, then a count */
#define LINE_MAX_BYTES 4000  /* one manifest line: below PIPE_BUF (4096) */

static const char shots_usage[] =
    "usage: edgewise shots MAP|DIR|PAK... [--data DIR] [--out DIR] [--size WxH]\n"
    "                      [--views all|N,M|best] [--jobs N] [--force]\n"
    "                      [--manifest FILE.jsonl] [--contact-sheet FILE.png] [--quiet]\n"
    "                      [what is drawn]\n"
    "\n"
    "Renders views of many maps to OUTDIR/MAP_vN.png (MAP_best.png for --views\n"
    "best) and appends one JSON line per picture to the manifest: map, source,\n"
    "view, camera, size, ms, stats, \"dark\" when the picture is nearly black, or\n"
    "the error.  A MAP is a .bsp path, a map name with --data, or 'builtin'; a\n"
    "DIR a game directory (maps/*.bsp, loose and in its pak*.pak) or a folder of\n"
    ".bsp files; a PAK every maps/*.bsp inside it.  A map that fails, or a pak\n"
    "that is empty or corrupt, is recorded and the batch goes on; maps without\n"
    "views (item boxes) are noted, not failures.  Exit status 0 if every map\n"
    "rendered, 1 if some failed, 2 for bad arguments.  Progress is a bar on a\n"
    "terminal, else one summary line; then each failed map with its error (the\n"
    "first ten, then how many more).  Killed (SIGINT, SIGTERM, SIGHUP), shots\n"
    "stops its --jobs workers with it.\n"
    "\n"
    CLI_OPTIONS_HERE
    "\n"
    "what is drawn (as in edgewise render):\n";

/* ---- the list of maps ------------------------------------------------------ */

/* SRC_FAILED: a source that gave no maps (an empty or corrupt .pak): one
 * failed entry of the batch, with its error, while the rest goes on. */
enum { SRC_FILE, SRC_GAMEDIR, SRC_PAK, SRC_BUILTIN, SRC_FAILED };

typedef struct map_item {
    int  kind;
    char source[1024];  /* the file it comes from (a .bsp, a pak) */
    char load[1024];    /* what to load: the path, the map name, the inner path */
    char dir[1024];     /* the game directory (SRC_GAMEDIR), else "" */
    char stem[128];     /* output name, unique in the batch */
    char error[400];    /* SRC_FAILED: why */
} map_item;

typedef struct map_list {
    map_item *items;
    int       n, cap;
} map_list;

typedef struct shots_opts {
    const char **inputs;
    int          ninputs;
    const char  *data, *outdir, *manifest, *sheet;
    int          width, height, jobs, force, quiet;
    int          views_mode;  /* 0 best, 1 all, 2 list */
    int          views[EW_MAX_VIEWS], nviews;
    draw_opts    draw;
} shots_opts;

static int ends_with_ci(const char *s, const char *suffix) {
    size_t n = strlen(s), m = strlen(suffix);
    if (n < m) return 0;
    for (size_t i = 0; i < m; i++)
        if (tolower((unsigned char)s[n - m + i]) != tolower((unsigned char)suffix[i])) return 0;
    return 1;
}

static map_item *list_add(map_list *l, int kind, const char *source, const char *load, const char *dir,
                          const char *stem) {
    if (l->n == l->cap) {
        int cap = l->cap ? l->cap * 2 : 32;
        map_item *p = realloc(l->items, sizeof *p * (size_t)cap);
        if (!p) return NULL;
        l->items = p, l->cap = cap;
    }
    map_item *m = &l->items[l->n++];
    memset(m, 0, sizeof *m);
    m->kind = kind;
    snprintf(m->source, sizeof m->source, "%s", source);
    snprintf(m->load, sizeof m->load, "%s", load);
    snprintf(m->dir, sizeof m->dir, "%s", dir ? dir : "");
    /* A stem that is already taken gets _2, _3...: every picture its own file. */
    char base[100];
    snprintf(base, sizeof base, "%s", stem);
    for (char *p = base; *p; p++)
        if (*p == '/' || (unsigned char)*p < ' ') *p = '_';
    snprintf(m->stem, sizeof m->stem, "%s", base);
    for (int k = 2;; k++) {
        int taken = 0;
        for (int i = 0; i + 1 < l->n && !taken; i++) taken = !strcmp(l->items[i].stem, m->stem);
        if (!taken) break;
        snprintf(m->stem, sizeof m->stem, "%s_%d", base, k);
    }
    return m;
}

static int cmp_str(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

/* The .bsp names (without extension) in a folder, sorted; NULL-terminated, malloc'd. */
static char **bsp_names(const char *dir, int *count) {
    *count = 0;
    DIR *d = opendir(dir);
    if (!d) return NULL;
    char **names = NULL;
    int cap = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        size_t n = strlen(e->d_name);
        if (n <= 4 || !ends_with_ci(e->d_name, ".bsp")) continue;
        if (*count + 1 >= cap) {
            cap = cap ? cap * 2 : 64;
            char **p = realloc(names, sizeof *p * (size_t)cap);
            if (!p) break;
            names = p;
        }
        names[*count] = strndup(e->d_name, n - 4);
        if (names[*count]) (*count)++;
    }
    closedir(d);
    if (names) qsort(names, (size_t)*count, sizeof *names, cmp_str);
    return names;
}

static void free_names(char **names, int n) {
    for (int i = 0; i < n; i++) free(names[i]);
    free(names);
}

/* The maps/NAME.bsp entries of a pak (NAME without a folder), in the pak's order. */
static int pak_maps(const char *pak, char ***out, int *count, ew_error *err) {
    uint8_t *data = NULL;
    size_t size = 0;
    ew_pak_entry *entries = NULL;
    int n = 0;
    *out = NULL, *count = 0;
    if (ew_read_file(pak, &data, &size, err) < 0) return -1;
    if (ew_pak_parse(data, size, pak, &entries, &n, err) < 0) {
        free(data);
        return -1;
    }
    char **names = calloc((size_t)n + 1, sizeof *names);
    for (int i = 0; names && i < n; i++) {
        const char *nm = entries[i].name;
        if (strncmp(nm, "maps/", 5) || strchr(nm + 5, '/') || !ends_with_ci(nm, ".bsp") || strlen(nm) <= 9)
            continue;
        names[(*count)++] = strndup(nm + 5, strlen(nm) - 9);
    }
    free(entries);
    free(data);
    *out = names;
    return names ? 0 : -1;
}

/* A source that failed (SRC_FAILED) as one entry of the batch, named by its file. */
static int add_failed(map_list *l, const char *source, const char *msg) {
    char stem[256];
    const char *b = strrchr(source, '/');
    snprintf(stem, sizeof stem, "%.255s", b && b[1] ? b + 1 : source);
    map_item *m = list_add(l, SRC_FAILED, source, source, NULL, stem);
    if (!m) return -1;
    snprintf(m->error, sizeof m->error, "%.399s", msg);
    return 0;
}

static int name_in(char **names, int n, const char *s) {
    for (int i = 0; i < n; i++)
        if (!strcmp(names[i], s)) return 1;
    return 0;
}

/* Expands one input; -1 after an error line (a usage error: nothing to
 * render).  A .pak that cannot be read (empty, corrupt) or holds no maps
 * is one failed entry (SRC_FAILED), not a usage error: the batch goes on. */
static int expand_input(map_list *l, const char *in) {
    struct stat st;
    char path[1024];
    if (is_builtin(in)) return list_add(l, SRC_BUILTIN, "builtin", "builtin", NULL, "builtin") ? 0 : -1;
    if (stat(in, &st) == 0 && S_ISDIR(st.st_mode)) {
        snprintf(path, sizeof path, "%s/maps", in);
        struct stat ms;
        if (stat(path, &ms) == 0 && S_ISDIR(ms.st_mode)) {
            /* A game directory: loose maps, then those only in its paks. */
            int nl = 0, total = 0, first = l->n, bad_pak = 0;
            char **loose = bsp_names(path, &nl);
            for (int i = 0; i < nl; i++) {
                char src[1200];
                snprintf(src, sizeof src, "%s/maps/%s.bsp", in, loose[i]);
                list_add(l, SRC_GAMEDIR, src, loose[i], in, loose[i]), total++;
            }
            for (int p = 0; p < 100; p++) {
                char pak[1100], **names;
                int np;
                ew_error err = {""};
                snprintf(pak, sizeof pak, "%s/pak%d.pak", in, p);
                if (access(pak, F_OK) != 0) break;
                if (pak_maps(pak, &names, &np, &err) < 0) {
                    if (add_failed(l, pak, err.msg) < 0) {
                        free_names(loose, nl);
                        return -1;
                    }
                    total++, bad_pak = 1;
                    continue;
                }
                for (int i = 0; i < np; i++)
                    if (!name_in(loose, nl, names[i])) list_add(l, SRC_GAMEDIR, pak, names[i], in, names[i]), total++;
                free_names(names, np);
            }
            free_names(loose, nl);
            /* The library's game directory refuses a corrupt pak: then each
             * loose map loads as a file (its palette from ../gfx) and each
             * map of a good pak from that pak, as if given alone. */
            for (int i = first; bad_pak && i < l->n; i++) {
                map_item *it = &l->items[i];
                if (it->kind != SRC_GAMEDIR) continue;
                if (ends_with_ci(it->source, ".pak")) {
                    char inner[1024];
                    snprintf(inner, sizeof inner, "maps/%.1000s.bsp", it->load);
                    snprintf(it->load, sizeof it->load, "%s", inner);
                    it->kind = SRC_PAK;
                } else {
                    snprintf(it->load, sizeof it->load, "%s", it->source);
                    it->kind = SRC_FILE;
                }
                it->dir[0] = '\0';
            }
            if (!total) {
                error_line("shots: %s: a game directory without maps", in);
                return -1;
            }
            return 0;
        }
        int n = 0;
        char **names = bsp_names(in, &n);
        for (int i = 0; i < n; i++) {
            char src[1200];
            snprintf(src, sizeof src, "%s/%s.bsp", in, names[i]);
            list_add(l, SRC_FILE, src, src, NULL, names[i]);
        }
        free_names(names, n);
        if (!n) {
            error_line("shots: %s: a directory without maps/ or .bsp files", in);
            return -1;
        }
        return 0;
    }
    if (ends_with_ci(in, ".pak")) {
        char **names;
        int n;
        ew_error err = {""};
        if (pak_maps(in, &names, &n, &err) < 0) return add_failed(l, in, err.msg);
        for (int i = 0; i < n; i++) {
            char inner[200];
            snprintf(inner, sizeof inner, "maps/%s.bsp", names[i]);
            list_add(l, SRC_PAK, in, inner, NULL, names[i]);
        }
        free_names(names, n);
        if (!n) {
            char msg[1200];
            snprintf(msg, sizeof msg, "%s: no maps/*.bsp inside", in);
            return add_failed(l, in, msg);
        }
        return 0;
    }
    char stem[256];
    map_basename(in, stem, sizeof stem);
    return list_add(l, SRC_FILE, in, in, NULL, stem) ? 0 : -1;
}

/* ---- arguments --------------------------------------------------------------- */

static int parse_views(const char *v, shots_opts *o) {
    if (!strcmp(v, "best")) return o->views_mode = 0, 0;
    if (!strcmp(v, "all")) return o->views_mode = 1, 0;
    o->views_mode = 2, o->nviews = 0;
    const char *p = v;
    while (*p) {
        char num[16];
        size_t n = strcspn(p, ",");
        long x;
        snprintf(num, sizeof num, "%.*s", (int)(n < 15 ? n : 15), p);
        if (n == 0 || n > 3 || parse_long(num, &x) < 0 || x < 0 || x >= EW_MAX_VIEWS ||
            o->nviews == EW_MAX_VIEWS) {
            error_line("--views %s: expected best, all, or view numbers 0 to %d separated by commas", v,
                       EW_MAX_VIEWS - 1);
            return -1;
        }
        int dup = 0;
        for (int i = 0; i < o->nviews; i++) dup |= o->views[i] == (int)x;
        if (!dup) o->views[o->nviews++] = (int)x;
        p += n;
        if (*p == ',' && *++p == '\0') {
            error_line("--views %s: expected best, all, or view numbers 0 to %d separated by commas", v,
                       EW_MAX_VIEWS - 1);
            return -1;
        }
    }
    if (!o->nviews) {
        error_line("--views: expected best, all, or view numbers 0 to %d separated by commas", EW_MAX_VIEWS - 1);
        return -1;
    }
    return 0;
}

/* 0, 1 after --help, -1 (error printed). */
static int parse(int argc, char **argv, shots_opts *o) {
    cli_args args;
    cli_args_init(&args, CLI_SHOTS, argc, argv, o->inputs, argc, &o->draw, shots_usage, NULL);
    while (cli_next_arg(&args)) {
        const cli_option *opt = args.opt;
        const char *v = args.value;
        if (cli_is(opt, "--force")) {
            o->force = 1;
            continue;
        }
        const char *names[] = {"--data", "--out", "--size", "--views", "--jobs", "--manifest", "--contact-sheet"};
        int which = 0;
        for (int k = 0; k < 7; k++)
            if (cli_is(opt, names[k])) which = k;
        if (!*v && which != 2 && which != 3 && which != 4) {
            error_line("%s: empty name", names[which]);
            return -1;
        }
        long l;
        switch (which) {
        case 0: o->data = v; break;
        case 1: o->outdir = v; break;
        case 2:
            if (parse_size(v, &o->width, &o->height) < 0) return -1;
            break;
        case 3:
            if (parse_views(v, o) < 0) return -1;
            break;
        case 4:
            if (parse_long(v, &l) < 0 || l < 1 || l > MAX_JOBS) {
                error_line("--jobs %s: expected a whole number from 1 to %d", v, MAX_JOBS);
                return -1;
            }
            o->jobs = (int)l;
            break;
        case 5: o->manifest = v; break;
        case 6:
            if (check_png_name("--contact-sheet", v) < 0) return -1;
            o->sheet = v;
            break;
        }
    }
    if (args.stop)
        return args.stop;
    o->ninputs = args.nmaps, o->quiet = args.quiet;
    if (!o->ninputs) {
        error_line("shots: missing MAP, DIR or PAK (see edgewise shots --help)");
        return -1;
    }
    return 0;
}

/* ---- loading one map ------------------------------------------------------------ */

/* A map inside a pak given by path: its world from the pak's bytes; palette
 * and colormap from the pak itself, else from --data, else from the game
 * directory the pak sits in. */
static ew_assets *load_from_pak(const map_item *m, const char *data, ew_error *err) {
    uint8_t *buf = NULL, *pal = NULL, *cmap = NULL;
    size_t size = 0, psize = 0, csize = 0;
    ew_pak_entry *e = NULL;
    int n = 0;
    ew_assets *a = NULL;
    ew_fs *fs = NULL;
    if (ew_read_file(m->source, &buf, &size, err) < 0 || ew_pak_parse(buf, size, m->source, &e, &n, err) < 0)
        goto done;
    const ew_pak_entry *bsp = NULL, *pe = NULL, *ce = NULL;
    for (int i = 0; i < n; i++) {
        if (!strcmp(e[i].name, m->load)) bsp = &e[i];
        if (!strcmp(e[i].name, "gfx/palette.lmp")) pe = &e[i];
        if (!strcmp(e[i].name, "gfx/colormap.lmp")) ce = &e[i];
    }
    if (!bsp) {
        snprintf(err->msg, sizeof err->msg, "%.300s: %.150s: not in the pak", m->source, m->load);
        goto done;
    }
    a = calloc(1, sizeof *a);
    if (!a) {
        snprintf(err->msg, sizeof err->msg, "%.400s: out of memory", m->source);
        goto done;
    }
    char name[2100];
    snprintf(name, sizeof name, "%s: %s", m->source, m->load);
    if (pe && ce) {
        if (ew_palette_parse(buf + pe->offset, pe->size, "gfx/palette.lmp", a->palette, err) < 0 ||
            ew_colormap_parse(buf + ce->offset, ce->size, "gfx/colormap.lmp", a->colormap, err) < 0)
            goto fail;
    } else {
        char dir[1024];
        if (data) {
            snprintf(dir, sizeof dir, "%s", cli_search_path(data));
        } else {
            snprintf(dir, sizeof dir, "%s", m->source);
            char *slash = strrchr(dir, '/');
            if (slash) *slash = '\0';
            else snprintf(dir, sizeof dir, ".");
        }
        if (!(fs = ew_fs_create(dir, err)) || ew_fs_load(fs, "gfx/palette.lmp", &pal, &psize, err) < 0 ||
            ew_fs_load(fs, "gfx/colormap.lmp", &cmap, &csize, err) < 0 ||
            ew_palette_parse(pal, psize, "gfx/palette.lmp", a->palette, err) < 0 ||
            ew_colormap_parse(cmap, csize, "gfx/colormap.lmp", a->colormap, err) < 0)
            goto fail;
    }
    a->world = ew_world_create(buf + bsp->offset, bsp->size, name, err);
    if (a->world) goto done;
fail:
    free(a);
    a = NULL;
done:
    ew_fs_destroy(fs);
    free(pal), free(cmap), free(e), free(buf);
    return a;
}

static ew_assets *load_item(const map_item *m, const char *data, ew_error *err) {
    switch (m->kind) {
    case SRC_BUILTIN: return ew_assets_create_builtin(err);
    case SRC_GAMEDIR: return ew_assets_create(m->load, cli_search_path(m->dir), err);
    case SRC_PAK: return load_from_pak(m, data, err);
    default: return ew_assets_create(m->load, cli_search_path(data), err);
    }
}

/* ---- choosing the best view ------------------------------------------------------ */

#define YAWS 24
/* The player start's eye turned, level, to the most open direction. */
static void most_open(const ew_world *w, ew_camera *cam) {
    float dist[YAWS];
    const float pi = 3.14159265f;
    for (int k = 0; k < YAWS; k++) {
        float yaw = (float)k * (360.0f / YAWS) * pi / 180, end[3];
        end[0] = cam->origin[0] + cosf(yaw) * 8192;
        end[1] = cam->origin[1] + sinf(yaw) * 8192;
        end[2] = cam->origin[2];
        ew_trace_result tr;
        dist[k] = ew_trace(w, EW_HULL_POINT, cam->origin, end, &tr) == 0 && !tr.startsolid ? tr.fraction * 8192 : 0;
    }
    int best = -1;
    float best_score = -1;
    for (int k = 0; k < YAWS; k++) {
        float s = 0;
        for (int d = -2; d <= 2; d++) s += dist[(k + d + YAWS) % YAWS];
        if (s > best_score + 1e-3f) best_score = s, best = k;
    }
    cam->angles[0] = 0, cam->angles[2] = 0;
    if (best >= 0 && best_score > 0) cam->angles[1] = (float)best * (360.0f / YAWS);
}

/* ---- one map -------------------------------------------------------------------- */


/* --views best: the candidates are every info_intermission camera of the
 * entity lump (in its order, wherever it falls beyond the view set's 32),
 * then every player start turned level to its most open direction, at
 * most BEST_MAX of each.  Each is drawn small (a 320x200 probe, the
 * renderer's smallest frame) with the batch's drawing options; the first
 * whose eye is not in solid and whose probe is not nearly black wins, so
 * an intermission camera is taken when it is lit and an unlit one never
 * is while another candidate is lit.  When every probe is dark (or in
 * solid), the brightest.  *kind: 1 an intermission camera, 0 a player
 * start (both left alone without candidates); *probed: the probes drawn;
 * returns the winner's probe luma, or -1 when no probe could be drawn
 * (then the first candidate, unprobed). */
#define BEST_MAX 12
#define PROBE_W 320
#define PROBE_H 200
static double choose_best(const shots_opts *o, const ew_assets *a, const ew_scene *scene, ew_camera *best,
                          int *kind, int *probed) {
    ew_camera all[4 * BEST_MAX], cand[2 * BEST_MAX];
    int kinds[4 * BEST_MAX], ckind[2 * BEST_MAX], n = 0, ni = 0, ns = 0;
    int nall = ew_entity_cameras(a->world, all, kinds, 4 * BEST_MAX);
    for (int i = 0; i < nall && ni < BEST_MAX; i++)
        if (kinds[i]) cand[n] = all[i], ckind[n++] = 1, ni++;
    for (int i = 0; i < nall && ns < BEST_MAX; i++)
        if (!kinds[i]) {
            cand[n] = all[i];
            most_open(a->world, &cand[n]);
            ckind[n++] = 0, ns++;
        }
    *probed = 0;
    if (n == 0) return -1;
    *best = cand[0], *kind = ckind[0];
    ew_error err = {""};
    ew_renderer *p = ew_renderer_create(&(ew_renderer_desc){ .world = a->world, .palette = a->palette,
            .colormap = a->colormap, .width = PROBE_W, .height = PROBE_H, .threads = 1,
            .color = (ew_color_mode)o->draw.color }, &err);
    if (!p || draw_opts_apply(&o->draw, p, scene) < 0) {
        ew_renderer_destroy(p);
        return -1;
    }
    double best_luma = -2;
    for (int i = 0; i < n; i++) {
        int solid = ew_point_contents(a->world, EW_HULL_POINT, cand[i].origin) == EW_CONTENTS_SOLID;
        if (ew_render(p, &cand[i], NULL) < 0) continue;
        (*probed)++;
        double luma = frame_mean_luma(p), score = solid ? -1 : luma;
        if (score > best_luma) best_luma = score, *best = cand[i], *kind = ckind[i];
        if (!solid && luma >= DARK_LUMA) break;  /* the first lit one, in the order of preference */
    }
    ew_renderer_destroy(p);
    return *probed ? best_luma : -1;
}

typedef struct map_result {
    int  status;     /* 0 rendered, 1 failed, 2 no views (noted) */
    int  pictures;   /* written */
    int  skipped;    /* already there */
    char error[400]; /* the first error of a failed map, one line */
} map_result;

typedef struct line_buf {
    char   s[LINE_MAX_BYTES + 96];
    size_t n;
} line_buf;

static void lb_add(line_buf *b, const char *fmt, ...) EW_CLI_PRINTF(2, 3);
static void lb_add(line_buf *b, const char *fmt, ...) {
    if (b->n >= LINE_MAX_BYTES) return;
    va_list ap;
    va_start(ap, fmt);
    int k = vsnprintf(b->s + b->n, LINE_MAX_BYTES - b->n, fmt, ap);
    va_end(ap);
    if (k > 0) b->n += (size_t)k < LINE_MAX_BYTES - b->n ? (size_t)k : LINE_MAX_BYTES - b->n - 1;
}

static void lb_str(line_buf *b, const char *s) {
    lb_add(b, "\"");
    for (const unsigned char *p = (const unsigned char *)s; *p && b->n < LINE_MAX_BYTES - 8;) {
        char c[8];
        json_char(&p, c);  /* the escaping of every JSON writer (cli/edgewise.c) */
        lb_add(b, "%s", c);
    }
    lb_add(b, "\"");
}

static void lb_num(line_buf *b, double v) {
    if (isfinite(v)) lb_add(b, "%.6g", v);
    else lb_add(b, "null");
}

/* The line's start: map, source, view (null for a whole-map record), file. */
static void line_start(line_buf *b, const map_item *m, int view, const char *file) {
    b->n = 0;
    lb_add(b, "{\"map\":");
    lb_str(b, m->stem);
    lb_add(b, ",\"source\":");
    lb_str(b, m->source);
    if (m->kind == SRC_PAK || (m->kind == SRC_GAMEDIR && ends_with_ci(m->source, ".pak"))) {
        char entry[200];
        if (m->kind == SRC_PAK) snprintf(entry, sizeof entry, "%.190s", m->load);
        else snprintf(entry, sizeof entry, "maps/%.180s.bsp", m->load);
        lb_add(b, ",\"entry\":");
        lb_str(b, entry);
    }
    lb_add(b, ",\"view\":");
    if (view == -2) lb_add(b, "\"best\"");
    else if (view >= 0) lb_add(b, "%d", view);
    else lb_add(b, "null");
    lb_add(b, ",\"file\":");
    if (file) lb_str(b, file);
    else lb_add(b, "null");
}

/* Ends the line and appends it with one write (O_APPEND: whole lines). */
static void line_emit(line_buf *b, int fd) {
    if (b->n > LINE_MAX_BYTES - 2) b->n = LINE_MAX_BYTES - 2;
    b->s[b->n++] = '}';
    b->s[b->n++] = '\n';
    if (fd >= 0 && write(fd, b->s, b->n) < 0) error_line("manifest: %s", strerror(errno));
}

/* An error line in the manifest; the map failed (res), its first error kept for the summary. */
static void line_error(map_result *res, line_buf *b, const map_item *m, int view, const char *file, const char *msg,
                       int fd) {
    char clean[600];
    snprintf(clean, sizeof clean, "%s", msg);
    char *nl = strchr(clean, '\n');
    if (nl) *nl = '\0';
    if (res->status != 1) snprintf(res->error, sizeof res->error, "%.399s", clean);
    res->status = 1;
    line_start(b, m, view, file);
    lb_add(b, ",\"status\":\"error\",\"error\":");
    lb_str(b, clean);
    line_emit(b, fd);
}

static void picture_path(const shots_opts *o, const map_item *m, int view, char *out, size_t size) {
    if (view == -2) snprintf(out, size, "%s/%s_best.png", o->outdir, m->stem);
    else snprintf(out, size, "%s/%s_v%d.png", o->outdir, m->stem, view);
}

static void line_skipped(line_buf *b, const map_item *m, int view, const char *file, int fd) {
    line_start(b, m, view, file);
    lb_add(b, ",\"status\":\"skipped\",\"reason\":\"exists\"");
    line_emit(b, fd);
}

static map_result shoot_map(const shots_opts *o, const map_item *m, int fd) {
    map_result res;
    memset(&res, 0, sizeof res);
    line_buf *b = malloc(sizeof *b);
    if (!b) {
        res.status = 1;
        snprintf(res.error, sizeof res.error, "out of memory");
        return res;
    }
    char file[1400];
    if (m->kind == SRC_FAILED) {
        line_error(&res, b, m, -1, NULL, m->error, fd);
        free(b);
        return res;
    }
    /* Resume without loading when the pictures are known by name. */
    if (!o->force && o->views_mode != 1) {
        int have = 0, want = o->views_mode == 0 ? 1 : o->nviews;
        for (int i = 0; i < want; i++) {
            picture_path(o, m, o->views_mode == 0 ? -2 : o->views[i], file, sizeof file);
            have += access(file, F_OK) == 0;
        }
        if (have == want) {
            for (int i = 0; i < want; i++) {
                int v = o->views_mode == 0 ? -2 : o->views[i];
                picture_path(o, m, v, file, sizeof file);
                line_skipped(b, m, v, file, fd);
            }
            res.skipped = want;
            free(b);
            return res;
        }
    }
    ew_error err = {""};
    double t0 = ew_clock_ms();
    ew_assets *a = load_item(m, o->data, &err);
    if (a && !o->quiet) print_world_warnings(a->world, 0);
    ew_scene *scene = NULL;
    ew_renderer *r = NULL;
    if (!a) {
        line_error(&res, b, m, -1, NULL, err.msg[0] ? err.msg : "cannot load the map", fd);
        free(b);
        return res;
    }
    double load_ms = ew_clock_ms() - t0;
    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(a->world, views);
    int list[EW_MAX_VIEWS], nlist = 0;
    ew_camera best_cam;
    if (nv == 0) {
        line_start(b, m, -1, NULL);
        lb_add(b, ",\"status\":\"no_views\",\"note\":\"no info_player_* or info_intermission entity (an item box?)\"");
        line_emit(b, fd);
        res.status = 2;
        goto done;
    }
    if (o->views_mode == 0) {
        list[nlist++] = -2;  /* its camera chosen once the scene is made (choose_best) */
    } else if (o->views_mode == 1) {
        for (int i = 0; i < nv; i++) list[nlist++] = i;
    } else {
        for (int i = 0; i < o->nviews; i++) list[nlist++] = o->views[i];
    }
    /* A scene: the map's own moving things (--data for their models). */
    const char *game = cli_search_path(m->kind == SRC_GAMEDIR ? m->dir : o->data);
    const char *scene_map = m->kind == SRC_BUILTIN ? "builtin" : m->kind == SRC_PAK ? m->source : m->load;
    if (!o->draw.no_entities) {
        scene = m->kind == SRC_BUILTIN ? ew_scene_create_builtin(a->world, &err)
                                       : ew_scene_create_from_map(a->world, scene_map, game, &err);
        if (!scene) {
            line_error(&res, b, m, -1, NULL, err.msg[0] ? err.msg : "cannot make the scene", fd);
            res.status = 1;
            goto done;
        }
    } else if (draw_opts_scene(&o->draw, a, "builtin", NULL, 0, 1, &scene) < 0) {
        line_error(&res, b, m, -1, NULL, "cannot make the scene", fd);
        goto done;
    }
    r = ew_renderer_create(&(ew_renderer_desc){ .world = a->world, .palette = a->palette,
            .colormap = a->colormap, .width = o->width, .height = o->height, .threads = 1,
            .color = (ew_color_mode)o->draw.color }, &err);
    if (!r || draw_opts_apply(&o->draw, r, scene) < 0) {
        line_error(&res, b, m, -1, NULL, err.msg[0] ? err.msg : "cannot create the renderer", fd);
        res.status = 1;
        goto done;
    }
    int best_kind = -1, best_probed = 0;  /* kind -1: the view set's first view (no candidate) */
    best_cam = views[0];
    if (o->views_mode == 0) choose_best(o, a, scene, &best_cam, &best_kind, &best_probed);
    for (int i = 0; i < nlist; i++) {
        int v = list[i];
        picture_path(o, m, v, file, sizeof file);
        if (v >= nv) {
            char msg[160];
            snprintf(msg, sizeof msg, "view %d: out of range, the map has %d view%s (0 to %d)", v, nv,
                     nv == 1 ? "" : "s", nv - 1);
            line_error(&res, b, m, v, NULL, msg, fd);
            res.status = 1;
            continue;
        }
        if (!o->force && access(file, F_OK) == 0) {
            line_skipped(b, m, v, file, fd);
            res.skipped++;
            continue;
        }
        ew_camera cam = v == -2 ? best_cam : views[v];
        ew_stats st;
        memset(&st, 0, sizeof st);
        double t1 = ew_clock_ms();
        if (ew_render(r, &cam, &st) < 0) {
            line_error(&res, b, m, v, NULL, "cannot render this camera", fd);
            res.status = 1;
            continue;
        }
        double render_ms = ew_clock_ms() - t1;
        double luma = 0;
        warn_if_dark(r, a->world, &cam, file, o->quiet, &luma);  /* one line per dark picture */
        double t2 = ew_clock_ms();
        /* Written under a temporary name and renamed when whole: a batch
         * killed mid-picture leaves no truncated PNG that a resumed run
         * would skip as done. */
        char part[sizeof file + 32];
        snprintf(part, sizeof part, "%s.%ld.part", file, (long)getpid());
        err.msg[0] = '\0';
        if (ew_write_frame_png(r, part, &err) < 0 || rename(part, file) != 0) {
            if (!err.msg[0]) snprintf(err.msg, sizeof err.msg, "%.400s: cannot rename its temporary file into place", file);
            remove(part);
            line_error(&res, b, m, v, NULL, err.msg, fd);
            res.status = 1;
            continue;
        }
        double png_ms = ew_clock_ms() - t2;
        res.pictures++;
        line_start(b, m, v, file);
        lb_add(b, ",\"status\":\"ok\",\"origin\":[");
        for (int k = 0; k < 3; k++) lb_num(b, cam.origin[k]), lb_add(b, k < 2 ? "," : "],\"angles\":[");
        for (int k = 0; k < 3; k++) lb_num(b, cam.angles[k]), lb_add(b, k < 2 ? "," : "]");
        lb_add(b, ",\"fov\":");
        lb_num(b, cam.fov);
        lb_add(b, ",\"width\":%d,\"height\":%d,\"color\":\"%s\"", o->width, o->height,
               o->draw.color == EW_COLOR_TRUE ? "true" : "8bit");
        lb_add(b, ",\"ms_load\":");
        lb_num(b, i == 0 ? load_ms : 0);
        lb_add(b, ",\"ms_render\":");
        lb_num(b, render_ms);
        lb_add(b, ",\"ms_png\":");
        lb_num(b, png_ms);
        lb_add(b, ",\"luma\":");
        lb_num(b, luma);
        lb_add(b, ",\"dark\":%s", luma < DARK_LUMA ? "true" : "false");
        if (v == -2)
            lb_add(b, ",\"best_from\":\"%s\",\"best_probed\":%d",
                   best_kind == 1 ? "intermission" : best_kind == 0 ? "player_start" : "view_set", best_probed);
        lb_add(b, ",\"stats\":{\"pixels_written\":%ld,\"surfaces\":%d,\"edges\":%d,\"spans\":%d,"
               "\"visible_leaves\":%d,\"entities_drawn\":%d,\"models_missing\":%d,\"dropped\":%d}",
               st.pixels_written, st.surfaces, st.edges, st.spans, st.visible_leaves, st.entities_drawn,
               st.models_missing, st.dropped);
        line_emit(b, fd);
    }
done:
    ew_renderer_destroy(r);
    ew_scene_destroy(scene);
    ew_assets_destroy(a);
    free(b);
    return res;
}

/* ---- progress ---------------------------------------------------------------------- */

typedef struct progress {
    int    tty, total, done, failed, noviews, pictures, skipped;
    map_result *results;      /* per map of the list (NULL: none kept) */
    unsigned char *finished;  /* per map: its finish was reported */
    double t0, last;
    char   current[128];
} progress;

static void fmt_time(char *out, size_t size, double s) {
    if (!(s >= 0) || s > 1e7) snprintf(out, size, "--:--");
    else if (s >= 3600) snprintf(out, size, "%d:%02d:%02d", (int)s / 3600, (int)s / 60 % 60, (int)s % 60);
    else snprintf(out, size, "%d:%02d", (int)s / 60, (int)s % 60);
}

static void progress_draw(progress *p, int final) {
    if (!p->tty) return;
    double now = ew_clock_ms();
    if (!final && now - p->last < 100) return;
    p->last = now;
    double el = (now - p->t0) / 1000;
    char e[32], left[32];
    fmt_time(e, sizeof e, el);
    fmt_time(left, sizeof left, p->done ? el / p->done * (p->total - p->done) : -1);
    char bar[21];
    int fill = p->total ? p->done * 20 / p->total : 20;
    for (int i = 0; i < 20; i++) bar[i] = i < fill ? '#' : '.';
    bar[20] = '\0';
    fprintf(stderr, "\r\033[K[%s] %d/%d maps, %d pictures, %s elapsed, %s left%s%.40s", bar, p->done, p->total,
            p->pictures, e, left, final || !p->current[0] ? "" : ", ", final ? "" : p->current);
    if (final) fputc('\n', stderr);
    fflush(stderr);
}

/* What a worker tells the parent (one write each: well under PIPE_BUF). */
typedef struct report {
    int kind;   /* 0 started, 1 finished */
    int index;
    map_result res;
} report;

static void account(progress *p, const map_list *l, const report *rp) {
    if (rp->kind == 0) {
        snprintf(p->current, sizeof p->current, "%s", l->items[rp->index].stem);
    } else {
        if (p->finished) {
            if (p->finished[rp->index]) return;  /* reported twice: counted once */
            p->finished[rp->index] = 1;
        }
        if (p->results) p->results[rp->index] = rp->res;
        p->done++;
        p->pictures += rp->res.pictures;
        p->skipped += rp->res.skipped;
        p->failed += rp->res.status == 1;
        p->noviews += rp->res.status == 2;
    }
    progress_draw(p, 0);
}

static int write_all(int fd, const void *buf, size_t n) {
    const char *p = buf;
    while (n) {
        ssize_t k = write(fd, p, n);
        if (k < 0 && errno == EINTR) continue;
        if (k <= 0) return -1;
        p += k, n -= (size_t)k;
    }
    return 0;
}

/* The workers of the batch, for the parent's signal handler: a SIGINT,
 * SIGTERM or SIGHUP to the parent stops them (SIGTERM each), then the
 * parent dies of the signal as it would have.  (Each worker also asks the
 * kernel for SIGKILL when its parent dies: PR_SET_PDEATHSIG.) */
static volatile pid_t worker_pids[MAX_JOBS];
static volatile sig_atomic_t nworkers;

static void stop_workers(int sig) {
    for (int j = 0; j < nworkers; j++)
        if (worker_pids[j] > 0) kill(worker_pids[j], SIGTERM);
    signal(sig, SIG_DFL);
    raise(sig);
}

/* Renders every map with N worker processes; 0, or -1 (fork failed). */
static int run_jobs(const shots_opts *o, const map_list *l, int fd, progress *p) {
    atomic_int *next = mmap(NULL, sizeof *next, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
    int pipefd[2];
    if (next == MAP_FAILED) return -1;
    if (pipe(pipefd) < 0) {
        munmap(next, sizeof *next);
        return -1;
    }
    atomic_init(next, 0);
    pid_t pids[MAX_JOBS];
    int started = 0;
    fflush(NULL);
    pid_t parent = getpid();
    struct sigaction sa, prev[3];
    const int sigs[3] = {SIGINT, SIGTERM, SIGHUP};
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = stop_workers;
    sigemptyset(&sa.sa_mask);
    for (int k = 0; k < 3; k++) {
        sigaction(sigs[k], NULL, &prev[k]);
        if (prev[k].sa_handler != SIG_IGN) sigaction(sigs[k], &sa, NULL);  /* nohup's SIG_IGN stays */
    }
    sigset_t block, old;
    sigemptyset(&block);
    sigaddset(&block, SIGINT);
    sigaddset(&block, SIGTERM);
    sigaddset(&block, SIGHUP);
    for (int j = 0; j < o->jobs && j < l->n; j++) {
        /* No signal between the fork and the worker's pid in the list. */
        sigprocmask(SIG_BLOCK, &block, &old);
        pid_t pid = fork();
        if (pid < 0) {
            sigprocmask(SIG_SETMASK, &old, NULL);
            break;
        }
        if (pid == 0) {
            /* The worker dies with its parent (killed by anything, even
             * SIGKILL), and takes the default actions, not the parent's. */
            signal(SIGINT, SIG_DFL), signal(SIGTERM, SIG_DFL), signal(SIGHUP, SIG_DFL);
            prctl(PR_SET_PDEATHSIG, SIGKILL);
            sigprocmask(SIG_SETMASK, &old, NULL);
            if (getppid() != parent) _exit(1);  /* the parent went before the line above */
            close(pipefd[0]);
            int i;
            while ((i = atomic_fetch_add(next, 1)) < l->n) {
                report rp;
                memset(&rp, 0, sizeof rp);
                rp.index = i;
                write_all(pipefd[1], &rp, sizeof rp);
                rp.res = shoot_map(o, &l->items[i], fd);
                rp.kind = 1;
                write_all(pipefd[1], &rp, sizeof rp);
            }
            fflush(NULL);
            _exit(0);
        }
        pids[started++] = pid;
        worker_pids[nworkers] = pid;
        nworkers = started;
        sigprocmask(SIG_SETMASK, &old, NULL);
    }
    close(pipefd[1]);
    report rp;
    int got[2] = {0, 0};
    for (;;) {
        ssize_t k = read(pipefd[0], &rp, sizeof rp);
        if (k < 0 && errno == EINTR) continue;
        if (k != (ssize_t)sizeof rp) break;
        if (rp.index < 0 || rp.index >= l->n) continue;
        got[rp.kind == 1]++;
        account(p, l, &rp);
    }
    close(pipefd[0]);
    for (int j = 0; j < started; j++) waitpid(pids[j], NULL, 0);
    nworkers = 0;
    for (int k = 0; k < 3; k++) sigaction(sigs[k], &prev[k], NULL);
    /* A worker that died (a crash, killed) leaves its maps unfinished: failures. */
    for (int i = 0; p->finished && i < l->n; i++)
        if (!p->finished[i] && p->results) {
            p->results[i].status = 1;
            snprintf(p->results[i].error, sizeof p->results[i].error,
                     "not finished: its worker stopped (crashed or killed)");
        }
    p->failed += l->n - p->done;
    p->done = l->n;
    munmap(next, sizeof *next);
    return started ? 0 : -1;
}

/* ---- the contact sheet -------------------------------------------------------------- */

#define SHEET_THUMB_W 320
#define SHEET_LABEL_SCALE 2
#define SHEET_GAP 8

/* Text drawn with the library's font: the mask of the pixels ew_draw_text
 * sets, from a scratch true-colour renderer of the label's size (the
 * built-in world, one frame rendered so the frame exists).  The frame holds
 * a picture, so the text is drawn twice in two colours and the pixels that
 * took both are the glyphs. */
static uint8_t *label_mask(const ew_assets *a, const char *text, int w, int h) {
    ew_error err;
    int fw = w > 320 ? w : 320, fh = h > 200 ? h : 200;  /* the renderer's smallest frame */
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){ .world = a->world, .palette = a->palette,
            .colormap = a->colormap, .width = fw, .height = fh, .threads = 1, .color = EW_COLOR_TRUE }, &err);
    uint8_t *mask = r ? calloc((size_t)w * (size_t)h, 1) : NULL;
    ew_camera views[EW_MAX_VIEWS];
    if (mask && (ew_benchmark_views(a->world, views) < 1 || ew_render(r, &views[0], NULL) < 0 || !ew_frame_rgba(r))) {
        free(mask);
        mask = NULL;
    }
    if (mask) {
        ew_text_style s1 = {{255, 255, 255}, 0, 0, 0}, s2 = {{255, 0, 0}, 0, 0, 0};
        const uint8_t *px = (const uint8_t *)ew_frame_rgba(r);
        ew_draw_text(r, 0, 0, SHEET_LABEL_SCALE, text, &s1);
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                const uint8_t *c = px + 4 * ((size_t)y * fw + x);
                mask[y * w + x] = c[0] == 255 && c[1] == 255 && c[2] == 255;
            }
        ew_draw_text(r, 0, 0, SHEET_LABEL_SCALE, text, &s2);
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                const uint8_t *c = px + 4 * ((size_t)y * fw + x);
                mask[y * w + x] &= c[0] == 255 && c[1] == 0 && c[2] == 0;
            }
    }
    ew_renderer_destroy(r);
    return mask;
}

static int contact_sheet(const shots_opts *o, const map_list *l) {
    char (*files)[1400] = malloc(sizeof *files * (size_t)l->n * EW_MAX_VIEWS);
    char (*labels)[160] = malloc(sizeof *labels * (size_t)l->n * EW_MAX_VIEWS);
    int n = 0, rc = -1;
    if (!files || !labels) goto out;
    for (int i = 0; i < l->n; i++) {
        int count = o->views_mode == 0 ? 1 : o->views_mode == 1 ? EW_MAX_VIEWS : o->nviews;
        for (int k = 0; k < count; k++) {
            int v = o->views_mode == 0 ? -2 : o->views_mode == 1 ? k : o->views[k];
            picture_path(o, &l->items[i], v, files[n], sizeof files[n]);
            if (access(files[n], R_OK) != 0) continue;
            if (v == -2) snprintf(labels[n], sizeof labels[n], "%s", l->items[i].stem);
            else snprintf(labels[n], sizeof labels[n], "%s v%d", l->items[i].stem, v);
            n++;
        }
    }
    if (!n) {
        error_line("--contact-sheet %s: no pictures to put on it", o->sheet);
        goto out;
    }
    int tw = o->width < SHEET_THUMB_W ? o->width : SHEET_THUMB_W;
    int th = (int)((long)o->height * tw / o->width);
    if (th < 1) th = 1;
    int lh = 10 * SHEET_LABEL_SCALE;
    int cols = (int)ceil(sqrt((double)n * th / tw * 1.3));
    if (cols < 1) cols = 1;
    if (cols > n) cols = n;
    int rows = (n + cols - 1) / cols;
    int sw = cols * (tw + SHEET_GAP) + SHEET_GAP, sh = rows * (th + lh + SHEET_GAP) + SHEET_GAP;
    uint32_t *sheet = malloc(sizeof *sheet * (size_t)sw * (size_t)sh);
    ew_error err = {""};
    ew_assets *font = ew_assets_create_builtin(&err);
    if (!sheet || !font) {
        error_line("--contact-sheet: %s", font ? "out of memory" : err.msg);
        free(sheet);
        ew_assets_destroy(font);
        goto out;
    }
    uint8_t *sp = (uint8_t *)sheet;
    for (size_t i = 0; i < (size_t)sw * (size_t)sh; i++) sp[4 * i] = sp[4 * i + 1] = sp[4 * i + 2] = 24, sp[4 * i + 3] = 255;
    for (int t = 0; t < n; t++) {
        int x0 = SHEET_GAP + t % cols * (tw + SHEET_GAP), y0 = SHEET_GAP + t / cols * (th + lh + SHEET_GAP);
        uint8_t *rgb = NULL;
        int w = 0, h = 0;
        if (ew_read_png_rgb(files[t], &rgb, &w, &h, &err) == 0 && w > 0 && h > 0) {
            /* A box filter: the mean of the source pixels under each thumbnail pixel. */
            for (int y = 0; y < th; y++) {
                int sy0 = (int)((long)y * h / th), sy1 = (int)((long)(y + 1) * h / th);
                if (sy1 <= sy0) sy1 = sy0 + 1;
                for (int x = 0; x < tw; x++) {
                    int sx0 = (int)((long)x * w / tw), sx1 = (int)((long)(x + 1) * w / tw);
                    if (sx1 <= sx0) sx1 = sx0 + 1;
                    unsigned sum[3] = {0, 0, 0}, cnt = 0;
                    for (int sy = sy0; sy < sy1 && sy < h; sy++)
                        for (int sx = sx0; sx < sx1 && sx < w; sx++, cnt++)
                            for (int c = 0; c < 3; c++) sum[c] += rgb[3 * ((size_t)sy * w + sx) + c];
                    uint8_t *d = sp + 4 * ((size_t)(y0 + y) * sw + x0 + x);
                    for (int c = 0; c < 3; c++) d[c] = (uint8_t)(cnt ? sum[c] / cnt : 0);
                }
            }
        }
        free(rgb);
        int lw = 0, lhh = 0;
        char text[160];
        snprintf(text, sizeof text, "%s", labels[t]);
        /* Cut the label to the thumbnail's width. */
        while (ew_text_size(text, SHEET_LABEL_SCALE, &lw, &lhh) == 0 && lw > tw && strlen(text) > 1)
            text[strlen(text) - 1] = '\0';
        if (lw > 0 && lhh > 0) {
            uint8_t *mask = label_mask(font, text, lw, lhh);
            for (int y = 0; mask && y < lhh; y++)
                for (int x = 0; x < lw; x++)
                    if (mask[y * lw + x] && y0 + th + y < sh) {
                        uint8_t *d = sp + 4 * ((size_t)(y0 + th + y) * sw + x0 + x);
                        d[0] = d[1] = d[2] = 230;
                    }
            free(mask);
        }
    }
    rc = ew_write_png_rgba(o->sheet, sheet, sw, sh, &err);
    if (rc < 0) error_line("%s", err.msg);
    free(sheet);
    ew_assets_destroy(font);
out:
    free(files);
    free(labels);
    return rc;
}

/* ---- the command -------------------------------------------------------------------- */

static int make_dirs(const char *path) {
    char buf[1024];
    snprintf(buf, sizeof buf, "%s", path);
    for (char *p = buf + 1; *p; p++) {
        if (*p != '/') continue;
        *p = '\0';
        if (mkdir(buf, 0777) < 0 && errno != EEXIST) return -1;
        *p = '/';
    }
    return mkdir(buf, 0777) < 0 && errno != EEXIST ? -1 : 0;
}

int cmd_shots(int argc, char **argv) {
    shots_opts o;
    memset(&o, 0, sizeof o);
    o.width = 640, o.height = 360, o.jobs = 1, o.outdir = "shots";
    draw_opts_init(&o.draw);
    o.inputs = calloc((size_t)argc + 1, sizeof *o.inputs);
    if (!o.inputs) return 1;
    int pr = parse(argc, argv, &o);
    if (pr != 0) {
        free(o.inputs);
        return pr > 0 ? 0 : 2;
    }
    map_list l = {NULL, 0, 0};
    for (int i = 0; i < o.ninputs; i++)
        if (expand_input(&l, o.inputs[i]) < 0) {
            free(l.items);
            free(o.inputs);
            return 2;
        }
    char manifest[1100];
    if (o.manifest) snprintf(manifest, sizeof manifest, "%s", o.manifest);
    else snprintf(manifest, sizeof manifest, "%s/manifest.jsonl", o.outdir);
    int rc = 1, fd = -1;
    progress p;
    memset(&p, 0, sizeof p);
    if (make_dirs(o.outdir) < 0) {
        error_line("--out %s: %s", o.outdir, strerror(errno));
        goto done;
    }
    fd = open(manifest, O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (fd < 0) {
        error_line("--manifest %s: %s", manifest, strerror(errno));
        goto done;
    }
    p.tty = isatty(2);
    p.total = l.n;
    p.t0 = ew_clock_ms();
    p.results = calloc((size_t)l.n, sizeof *p.results);
    p.finished = calloc((size_t)l.n, 1);
    if (o.jobs == 1) {
        for (int i = 0; i < l.n; i++) {
            report rp;
            memset(&rp, 0, sizeof rp);
            rp.index = i;
            account(&p, &l, &rp);
            rp.res = shoot_map(&o, &l.items[i], fd);
            rp.kind = 1;
            account(&p, &l, &rp);
        }
    } else if (run_jobs(&o, &l, fd, &p) < 0) {
        error_line("shots: cannot start the workers: %s", strerror(errno));
        goto done;
    }
    progress_draw(&p, 1);
    double secs = (ew_clock_ms() - p.t0) / 1000;
    fprintf(stderr, "shots: %d map%s, %d picture%s written, %d skipped (already there), %d without views, "
            "%d failed, %.1f s (%.1f pictures/s), manifest %s\n", p.total, p.total == 1 ? "" : "s", p.pictures,
            p.pictures == 1 ? "" : "s", p.skipped, p.noviews, p.failed, secs, secs > 0 ? p.pictures / secs : 0,
            manifest);
    /* Each failed map with its error, in the list's order: the first ten, then a count. */
    int named = 0;
    for (int i = 0; p.results && i < l.n; i++) {
        if (p.results[i].status != 1) continue;
        if (named++ < SUMMARY_FAILURES)
            error_line("shots: failed: %s: %s", l.items[i].stem,
                       p.results[i].error[0] ? p.results[i].error : "(no message)");
    }
    if (named > SUMMARY_FAILURES)
        error_line("shots: ... and %d more failed (every error is in the manifest %s)", named - SUMMARY_FAILURES,
                   manifest);
    rc = p.failed ? 1 : 0;
    if (o.sheet && contact_sheet(&o, &l) < 0) rc = 1;
done:
    if (fd >= 0) close(fd);
    free(p.results);
    free(p.finished);
    free(l.items);
    free(o.inputs);
    return rc;
}
