/*
 * viewer.c - edgewise view: a window in which a map is rendered by the
 * library's software renderer, with mouse look, movement (fly / walk), the
 * renderer's debug modes on keys, an overlay, screenshots, a recorded camera
 * path and scripts that drive the viewer unattended.  SDL2 only opens the
 * window, reads input and presents finished frames through one streaming
 * texture; every pixel of the scene comes from ew_render.
 *
 * Built only when CMake finds SDL2 (EW_HAVE_SDL2); the library never links it.
 */
#define _POSIX_C_SOURCE 200809L
#include "app_controls.h"
#include "cli.h"
#include "edgewise.h"
#include "viewer.h"

#include <SDL.h>

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static const char view_usage[] =
    "usage: edgewise view MAP [options]\n"
    "\n"
    "A window in which MAP ('builtin' for the built-in scene) is rendered by\n"
    "edgewise; see docs/viewer.md for the keys and formats.  Keys: mouse look\n"
    "(click to grab, Esc releases), W A S D move, Space/C up/down, F fly/walk,\n"
    "0-9 view 0-9 of the view set (counted from 0, as --view N and edgewise views\n"
    "list them), PgUp/PgDn the next/previous view, P pause, Tab overlay, F1-F7\n"
    "debug modes, F12 screenshot, H hidden-surface method, L PVS lock, X exact\n"
    "perspective, T threads (1, 2, all cores), E entities, R alias rasterizer.\n"
    "With --demo DEMO instead of MAP: the recorded game plays (P pause, [ and ]\n"
    "5 s back and on, G the free camera and back).\n"
    "\n"
    "options:\n"
    CLI_OPTIONS_HERE
    "drawing options (as render):\n";

/* How finished frames reach the window (docs/viewer.md, "Presenting"):
 * the window's own surface (the frame converted straight into its pixel format, scaled in
 * the same pass, shown with SDL_UpdateWindowSurface: on X11 a shared-memory
 * put image), a streaming texture of the default (accelerated) SDL
 * renderer scaled by the GPU, or the same through SDL's software
 * renderer.  auto: the texture when OpenGL is a real GPU, else the
 * surface. */
typedef enum present_mode { PRESENT_AUTO, PRESENT_SURFACE, PRESENT_TEXTURE, PRESENT_SOFTWARE } present_mode;
static const char *const present_names[] = { "auto", "surface", "texture", "software" };

typedef struct view_opts {
    const char *map, *data, *script, *record, *demo;
    present_mode present;
    int         width, height, size_given, scale, threads, view, fullscreen, quiet;
    double      fov;
    draw_opts   draw;
} view_opts;

static double now_s(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* ---- arguments ------------------------------------------------------------ */

static int parse_view_args(int argc, char **argv, view_opts *o) {
    const char *map[1];
    cli_args args;
    cli_args_init(&args, CLI_VIEW, argc, argv, map, 1, &o->draw, view_usage, NULL);
    while (cli_next_arg(&args)) {
        const cli_option *opt = args.opt;
        const char *v = args.value;
        if (cli_is(opt, "--fullscreen")) { o->fullscreen = 1; continue; }
        {
            static const char *const with_value[] = { "--data", "--size", "--scale", "--threads", "--fov",
                                                      "--view", "--script", "--record", "--present", "--demo" };
            int k = 0;
            for (int j = 0; j < (int)(sizeof with_value / sizeof *with_value); j++)
                if (cli_is(opt, with_value[j])) k = j;
            long l;
            const char *dend;
            switch (k) {
            case 0: o->data = v; break;
            case 1:
                if (parse_size(v, &o->width, &o->height) < 0) return -1;
                o->size_given = 1;
                break;
            case 2:
                if (parse_long(v, &l) < 0 || l < 1 || l > 8) {
                    error_line("--scale %s: must be a whole number from 1 to 8", v);
                    return -1;
                }
                o->scale = (int)l;
                break;
            case 3:
                if (parse_long(v, &l) < 0 || l < 0 || l > EW_MAX_THREADS) {
                    error_line("--threads %s: must be a whole number from 0 to %d", v, EW_MAX_THREADS);
                    return -1;
                }
                o->threads = (int)l;
                break;
            case 4:
                if (parse_decimal(v, &dend, &o->fov) < 0 || *dend || !(o->fov > 1 && o->fov < 179)) {
                    error_line("--fov %s: must be " FOV_RULE, v);
                    return -1;
                }
                break;
            case 5:
                if (parse_long(v, &l) < 0 || l < 0 || l >= EW_MAX_VIEWS) {
                    error_line("--view %s: must be a whole number from 0 to %d", v, EW_MAX_VIEWS - 1);
                    return -1;
                }
                o->view = (int)l;
                break;
            case 6: o->script = v; break;
            case 7: o->record = v; break;
            case 8: {
                int m = -1;
                for (int j = 0; j < 4; j++)
                    if (strcmp(v, present_names[j]) == 0) m = j;
                if (m < 0) {
                    error_line("--present %s: must be auto, surface, texture or software", v);
                    return -1;
                }
                o->present = (present_mode)m;
                break;
            }
            case 9: o->demo = v; break;
            }
        }
    }
    if (args.stop)
        return args.stop;
    o->map = args.nmaps ? map[0] : NULL, o->quiet = args.quiet;
    if (o->map && o->demo) {
        error_line("view: --demo plays the demo's own map: no MAP with it");
        return -1;
    }
    if (!o->map && !o->demo) {
        error_line("view: missing MAP (a map name, a .bsp path or 'builtin')");
        return -1;
    }
    return 0;
}

/* ---- the viewer's state ----------------------------------------------------- */

typedef struct viewer {
    view_opts    *o;
    ew_assets    *a;
    ew_scene     *scene;     /* the map's entities (NULL: --no-entities) */
    ew_scene     *empty;     /* an empty scene: entities off */
    ew_renderer  *r;
    SDL_Window   *win;
    SDL_Renderer *sdl;
    SDL_Texture  *tex;        /* texture and software modes */
    present_mode  mode;       /* the mode in use (never auto) */
    Uint32        tex_format; /* the texture's pixel format */
    int           fw, fh;     /* frame size */
    uint32_t      table[256]; /* palette in the destination's pixel format */
    int          *xmap;       /* scaling: source column of each destination column */
    int           xmap_n, xmap_dw, xmap_fw;
    char          gl_name[128]; /* OpenGL's renderer string when probed */
    SDL_PixelFormat *tfmt;    /* the texture's format, for blit_frame */
    double        phase[3];   /* present ms summed: convert, upload + copy, show */
    ew_camera     views[EW_MAX_VIEWS];
    int           nviews, cur_view;
    ew_player     player;
    float         eye[3], angles[3];
    double        time;
    int           paused, overlay, grabbed, quit, entities, exact, pvs_lock;
    int           threads;    /* asked for: 0 all cores (T cycles 1, 2, all) */
    int           alias_raster;
    ew_debug_mode debug;
    int           shot_count;
    ew_demo      *demo;       /* --demo: the demo, its client (whose scene is v->scene) */
    ew_demo_client *dc;
    double        demo_t0, demo_t1;  /* its span: the first frame's time, the last message's */
    double        demo_seek;  /* seconds [ and ] moved it from the viewer's clock */
    int           follow;     /* the demo's camera (1) or the free camera (0, G) */
    int           demo_failed;
    uint8_t       held[SDL_NUM_SCANCODES];  /* keys held by the script */
} viewer;

static void set_view(viewer *v, int n) {
    if (n < 0 || n >= v->nviews)
        return;
    v->cur_view = n;
    memcpy(v->eye, v->views[n].origin, sizeof v->eye);
    memcpy(v->angles, v->views[n].angles, sizeof v->angles);
    ew_player_set_eye(&v->player, v->eye, v->player.mode);
}

/* The renderer at the frame size, with every setting the keys changed. */
static int make_renderer(viewer *v, int w, int h) {
    ew_error err = { "" };
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){ .world = v->a->world, .palette = v->a->palette,
            .colormap = v->a->colormap, .width = w, .height = h, .threads = v->threads,
            .color = (ew_color_mode)v->o->draw.color }, &err);
    if (!r) {
        error_line("%s", err.msg[0] ? err.msg : "cannot create the renderer");
        return -1;
    }
    if (draw_opts_apply(&v->o->draw, r, v->scene) < 0) {
        error_line("out of memory for the debug mode");
        ew_renderer_destroy(r);
        return -1;
    }
    ew_set_scene(r, v->entities ? v->scene : v->empty);
    ew_set_debug(r, v->debug);
    ew_set_pvs_lock(r, v->pvs_lock);
    if (v->exact) ew_set_subdivision(r, 1);
    ew_set_alias_raster(r, (ew_alias_raster)v->alias_raster, 0);
    SDL_Texture *tex = NULL;
    if (v->sdl && !(tex = SDL_CreateTexture(v->sdl, v->tex_format, SDL_TEXTUREACCESS_STREAMING, w, h))) {
        error_line("SDL: cannot create a %dx%d texture: %s", w, h, SDL_GetError());
        ew_renderer_destroy(r);
        return -1;
    }
    ew_renderer_destroy(v->r);
    if (v->tex) SDL_DestroyTexture(v->tex);
    v->r = r;
    v->tex = tex;
    v->fw = w;
    v->fh = h;
    return 0;
}

static void set_grab(viewer *v, int on) {
    v->grabbed = on;
    SDL_SetRelativeMouseMode(on ? SDL_TRUE : SDL_FALSE);
}

/* A key press (from the keyboard or a script's "key NAME"), bound by
 * app_key (app/common/, shared with the web page). */
static void press(viewer *v, SDL_Keycode k) {
    int arg;
    const app_action act = app_key(SDL_GetKeyName(k), &arg);
    switch (act) {
    case APP_DEBUG: {
        ew_debug_mode m = (ew_debug_mode)arg;
        v->debug = v->debug == m ? EW_DEBUG_NONE : m;
        ew_set_debug(v->r, v->debug);
        v->debug = ew_get_debug(v->r);
        fprintf(stderr, "debug: %s\n", app_debug_names[v->debug]);
        break;
    }
    case APP_VIEW: set_view(v, arg); break;
    case APP_RELEASE:
        if (v->grabbed) set_grab(v, 0);
        else v->quit = 1;
        break;
    case APP_VIEW_NEXT: set_view(v, v->nviews ? (v->cur_view + 1) % v->nviews : 0); break;
    case APP_VIEW_PREV: set_view(v, v->nviews ? (v->cur_view + v->nviews - 1) % v->nviews : 0); break;
    case APP_PAUSE: v->paused = !v->paused; break;
    case APP_DEMO_BACK:  /* the demo 5 s back / on */
    case APP_DEMO_ON:
        if (v->dc) {
            double at = v->time + v->demo_seek + (act == APP_DEMO_BACK ? -5 : 5);
            if (at < 0) at = 0;
            if (at > v->demo_t1 - v->demo_t0) at = v->demo_t1 - v->demo_t0;
            v->demo_seek = at - v->time;
            fprintf(stderr, "demo: %.1f s\n", at);
        }
        break;
    case APP_FREE_CAMERA:
        if (v->dc) {
            v->follow = !v->follow;
            fprintf(stderr, "camera: %s\n", v->follow ? "the demo's" : "free");
        }
        break;
    case APP_OVERLAY: v->overlay = !v->overlay; break;
    case APP_MOVE_MODE:
        v->player.mode = v->player.mode == EW_MOVE_FLY ? EW_MOVE_WALK : EW_MOVE_FLY;
        memset(v->player.velocity, 0, sizeof v->player.velocity);
        fprintf(stderr, "move: %s\n", v->player.mode == EW_MOVE_FLY ? "fly" : "walk");
        break;
    case APP_PVS_LOCK:
        v->pvs_lock = !v->pvs_lock;
        ew_set_pvs_lock(v->r, v->pvs_lock);
        fprintf(stderr, "pvs lock: %s\n", v->pvs_lock ? "on" : "off");
        break;
    case APP_EXACT:
        v->exact = !v->exact;
        ew_set_subdivision(v->r, v->exact ? 1 : 16);
        fprintf(stderr, "perspective: %s\n", v->exact ? "exact" : "16-pixel subdivision");
        break;
    case APP_THREADS: {  /* 1, 2, all cores, 1, ... (from --threads N: the next one up) */
        int cur = ew_get_threads(v->r), cores = ew_set_threads(v->r, 0);
        int next = app_next_threads(cur, cores);
        if (cores < 0 || ew_set_threads(v->r, next) < 0) {
            fprintf(stderr, "threads: out of memory\n");
            break;
        }
        v->threads = next;
        int n = ew_get_threads(v->r);
        fprintf(stderr, "threads: %d%s\n", n, n == cores ? " (all cores)" : "");
        break;
    }
    case APP_ENTITIES:
        v->entities = !v->entities;
        ew_set_scene(v->r, v->entities ? v->scene : v->empty);
        fprintf(stderr, "entities: %s\n", v->entities ? "on" : "off");
        break;
    case APP_HSR: {  /* the next hidden-surface method this build has */
        int m = app_next_hsr(v->o->draw.hsr);
        if (ew_set_hsr(v->r, (ew_hsr_method)m) == 0) v->o->draw.hsr = m;
        fprintf(stderr, "hsr: %s\n", ew_hsr_name((ew_hsr_method)v->o->draw.hsr));
        break;
    }
    case APP_RASTER:
        v->alias_raster = (v->alias_raster + 1) % APP_RASTER_COUNT;
        ew_set_alias_raster(v->r, (ew_alias_raster)v->alias_raster, 0);
        fprintf(stderr, "alias raster: %s\n", app_raster_names[v->alias_raster]);
        break;
    default: break;
    }
}

static void screenshot(viewer *v, const char *path, const ew_camera *cam) {
    char name[512];
    if (!path) {
        char base[256];
        map_basename(v->o->map, base, sizeof base);
        snprintf(name, sizeof name, "%s_view%03d.png", base, v->shot_count++);
        path = name;
    }
    ew_error err = { "" };
    if (ew_write_frame_png(v->r, path, &err) < 0) {
        error_line("%s", err.msg);
        return;
    }
    warn_if_dark(v->r, v->a->world, cam, path, v->o->quiet, NULL);  /* a black screenshot is never silent */
    printf("%s --pos %.9g,%.9g,%.9g --angles %.9g,%.9g,%.9g --time %.9g --size %dx%d\n", path, cam->origin[0],
           cam->origin[1], cam->origin[2], cam->angles[0], cam->angles[1], cam->angles[2], cam->time, v->fw,
           v->fh);
    fflush(stdout);
}

/* ---- scripts ------------------------------------------------------------------ */

enum { S_CAMERA, S_VIEW, S_KEY, S_DOWN, S_UP, S_SCREENSHOT, S_QUIT, S_STEP };
typedef struct script_cmd {
    double t;
    int    kind;
    float  v[6];
    int    n;
    SDL_Keycode key;
    char   path[256];
} script_cmd;

static int load_script(const char *path, script_cmd **out, int *count) {
    FILE *f = fopen(path, "r");
    if (!f) {
        error_line("%s: %s", path, strerror(errno));
        return -1;
    }
    script_cmd *cmds = NULL;
    int n = 0, cap = 0, lineno = 0, rc = 0;
    char line[512];
    while (fgets(line, sizeof line, f)) {
        lineno++;
        char *p = line;
        while (isspace((unsigned char)*p)) p++;
        if (!*p || *p == '#')
            continue;
        line[strcspn(line, "\r\n")] = '\0';
        script_cmd c;
        memset(&c, 0, sizeof c);
        char verb[32], arg1[256] = "", arg2[256] = "";
        int got = sscanf(p, "at %lf %31s %255s %255s", &c.t, verb, arg1, arg2);
        int ok = got >= 2 && isfinite(c.t) && c.t >= 0;
        if (ok && strcmp(verb, "camera") == 0) {
            c.kind = S_CAMERA;
            ok = got == 4 && sscanf(arg1, "%f,%f,%f", &c.v[0], &c.v[1], &c.v[2]) == 3 &&
                 sscanf(arg2, "%f,%f,%f", &c.v[3], &c.v[4], &c.v[5]) == 3;
        } else if (ok && strcmp(verb, "view") == 0) {
            c.kind = S_VIEW;
            ok = got == 3 && sscanf(arg1, "%d", &c.n) == 1;
        } else if (ok && (strcmp(verb, "key") == 0 || strcmp(verb, "down") == 0 || strcmp(verb, "up") == 0)) {
            c.kind = verb[0] == 'k' ? S_KEY : verb[0] == 'd' ? S_DOWN : S_UP;
            c.key = got == 3 ? SDL_GetKeyFromName(arg1) : SDLK_UNKNOWN;
            ok = c.key != SDLK_UNKNOWN;
        } else if (ok && strcmp(verb, "screenshot") == 0) {
            c.kind = S_SCREENSHOT;
            ok = got == 3;
            snprintf(c.path, sizeof c.path, "%s", arg1);
            if (ok && check_png_name("screenshot", c.path) < 0) {  /* PNG only, as --out: one line */
                rc = -1;
                break;
            }
        } else if (ok && strcmp(verb, "quit") == 0) {
            c.kind = S_QUIT;
            ok = got == 2;
        } else if (ok && strcmp(verb, "step") == 0) {
            c.kind = S_STEP;
            ok = got == 3 && sscanf(arg1, "%f", &c.v[0]) == 1 && c.v[0] > 0 && c.v[0] <= 1;
        } else {
            ok = 0;
        }
        if (!ok) {
            error_line("%s:%d: not a script command (at T camera X,Y,Z P,Y,R | view N | key NAME | down NAME | "
                       "up NAME | screenshot FILE | step DT | quit)", path, lineno);
            rc = -1;
            break;
        }
        if (n == cap) {
            cap = cap ? cap * 2 : 32;
            script_cmd *nc = realloc(cmds, (size_t)cap * sizeof *cmds);
            if (!nc) { rc = -1; break; }
            cmds = nc;
        }
        cmds[n++] = c;
    }
    fclose(f);
    if (rc < 0) {
        free(cmds);
        return -1;
    }
    /* Stable order by time (insertion sort: scripts are short). */
    for (int i = 1; i < n; i++)
        for (int j = i; j > 0 && cmds[j - 1].t > cmds[j].t; j--) {
            script_cmd t = cmds[j];
            cmds[j] = cmds[j - 1];
            cmds[j - 1] = t;
        }
    *out = cmds;
    *count = n;
    return 0;
}

/* ---- presenting ------------------------------------------------------------------- */

/* The frame into dst (dw x dh pixels of format fmt, 4 bytes each, pitch
 * bytes a row) in one pass: 8-bit pixels through the palette mapped to
 * fmt, true colour swizzled, and when the sizes differ a nearest-pixel
 * scale (each destination row from its source row, repeated rows copied). */
static void blit_frame(viewer *v, uint8_t *dst, int pitch, int dw, int dh, const SDL_PixelFormat *fmt) {
    const uint8_t *px = ew_frame_pixels(v->r);
    const uint32_t *rgba = ew_frame_rgba(v->r);
    int fw = v->fw, fh = v->fh;
    if (px) {
        const uint8_t *pal = ew_frame_palette(v->r);
        for (int i = 0; i < 256; i++)
            v->table[i] = SDL_MapRGB(fmt, pal[3 * i], pal[3 * i + 1], pal[3 * i + 2]);
    }
    if (dw == fw && dh == fh) {
        if (px && pitch == fw * 4) {
            ew_pixels_to_rgba(px, (size_t)fw * fh, v->table, (uint32_t *)dst);
            return;
        }
        for (int y = 0; y < fh; y++) {
            uint32_t *d = (uint32_t *)(dst + (size_t)y * pitch);
            if (px) {
                ew_pixels_to_rgba(px + (size_t)y * fw, (size_t)fw, v->table, d);
            } else if (fmt->format == SDL_PIXELFORMAT_RGBA32) {
                memcpy(d, rgba + (size_t)y * fw, (size_t)fw * 4);
            } else {
                const uint8_t *s = (const uint8_t *)(rgba + (size_t)y * fw);
                for (int x = 0; x < fw; x++, s += 4)
                    d[x] = ((Uint32)s[0] << fmt->Rshift) | ((Uint32)s[1] << fmt->Gshift) |
                           ((Uint32)s[2] << fmt->Bshift) | fmt->Amask;
            }
        }
        return;
    }
    if (v->xmap_dw != dw || v->xmap_fw != fw) {
        if (dw > v->xmap_n) {
            int *m = realloc(v->xmap, (size_t)dw * sizeof *m);
            if (!m) return;
            v->xmap = m;
            v->xmap_n = dw;
        }
        for (int x = 0; x < dw; x++) v->xmap[x] = (int)((long long)x * fw / dw);
        v->xmap_dw = dw;
        v->xmap_fw = fw;
    }
    const int *xm = v->xmap;
    int prev = -1;
    for (int y = 0; y < dh; y++) {
        int sy = (int)((long long)y * fh / dh);
        uint32_t *d = (uint32_t *)(dst + (size_t)y * pitch);
        if (sy == prev) {
            memcpy(d, dst + (size_t)(y - 1) * pitch, (size_t)dw * 4);
            continue;
        }
        prev = sy;
        if (px) {
            const uint8_t *s = px + (size_t)sy * fw;
            for (int x = 0; x < dw; x++) d[x] = v->table[s[xm[x]]];
        } else {
            const uint8_t *s = (const uint8_t *)(rgba + (size_t)sy * fw);
            for (int x = 0; x < dw; x++) {
                const uint8_t *q = s + 4 * xm[x];
                d[x] = ((Uint32)q[0] << fmt->Rshift) | ((Uint32)q[1] << fmt->Gshift) |
                       ((Uint32)q[2] << fmt->Bshift) | fmt->Amask;
            }
        }
    }
}

/* The finished frame onto the window by the mode in use.  Returns the ms
 * spent, all of it: until SDL_UpdateWindowSurface / SDL_RenderPresent
 * return (on X11 both wait for the server to take the image: SDL syncs
 * after its shared-memory put, Mesa's swap after its own); the phases are
 * summed in v->phase. */
static double present(viewer *v) {
    double t0 = now_s(), t1 = t0, t2 = t0;
    if (v->mode == PRESENT_SURFACE) {
        SDL_Surface *s = SDL_GetWindowSurface(v->win);
        if (s && s->format->BytesPerPixel == 4) {
            if (SDL_MUSTLOCK(s)) SDL_LockSurface(s);
            blit_frame(v, s->pixels, s->pitch, s->w, s->h, s->format);
            if (SDL_MUSTLOCK(s)) SDL_UnlockSurface(s);
            t1 = t2 = now_s();
            SDL_UpdateWindowSurface(v->win);
        } else {
            t1 = t2 = now_s();
        }
    } else {
        void *dst;
        int pitch;
        if (SDL_LockTexture(v->tex, NULL, &dst, &pitch) == 0) {
            blit_frame(v, dst, pitch, v->fw, v->fh, v->tfmt);
            t1 = now_s();
            SDL_UnlockTexture(v->tex);
        } else {
            t1 = now_s();
        }
        SDL_RenderCopy(v->sdl, v->tex, NULL, NULL);
        t2 = now_s();
        SDL_RenderPresent(v->sdl);
    }
    double t3 = now_s();
    v->phase[0] += (t1 - t0) * 1000.0;
    v->phase[1] += (t2 - t1) * 1000.0;
    v->phase[2] += (t3 - t2) * 1000.0;
    return (t3 - t0) * 1000.0;
}

/* Whether OpenGL here is a software rasterizer (or missing): a hidden
 * window with a GL context asked for GL_RENDERER, copied into name. */
static int gl_probe(char *name, size_t n) {
    name[0] = '\0';
    SDL_Window *w = SDL_CreateWindow("edgewise probe", 0, 0, 16, 16, SDL_WINDOW_OPENGL | SDL_WINDOW_HIDDEN);
    if (!w) return 1;
    int soft = 1;
    SDL_GLContext c = SDL_GL_CreateContext(w);
    if (c) {
        typedef const unsigned char *(*get_string_fn)(unsigned int);
        get_string_fn get = (get_string_fn)SDL_GL_GetProcAddress("glGetString");
        const char *r = get ? (const char *)get(0x1F01 /* GL_RENDERER */) : NULL;
        if (r) {
            snprintf(name, n, "%s", r);
            static const char *const sw[] = { "llvmpipe", "softpipe", "swrast", "Software", "software",
                                              "SwiftShader", "GDI Generic", "Basic Render" };
            soft = 0;
            for (size_t i = 0; i < sizeof sw / sizeof *sw; i++)
                if (strstr(r, sw[i])) soft = 1;
        }
        SDL_GL_DeleteContext(c);
    }
    SDL_DestroyWindow(w);
    return soft;
}

/* ---- the main loop ------------------------------------------------------------------ */

/* --demo: the demo at v->time seconds after its first frame (back to the
 * start and read again to go back); the demo's camera unless the free
 * camera is on.  The frame's time, or -1 after an error line. */
static double demo_frame(viewer *v) {
    double t = v->demo_t0 + v->time + v->demo_seek;
    if (t > v->demo_t1) t = v->demo_t1;
    if (t < v->demo_t0) t = v->demo_t0;
    const ew_demo_state *st = ew_demo_get_state(v->demo);
    ew_error err = { "" };
    if (t < st->prev_time - 1e-6 && st->block > 0) {  /* before what the client holds: read it again */
        ew_demo_client *c = NULL;
        ew_demo_rewind(v->demo);
        if (!(c = ew_demo_client_create(v->demo, v->a->world, cli_search_path(v->o->data), &err))) {
            error_line("%s", err.msg);
            return -1;
        }
        ew_demo_client_destroy(v->dc);
        v->dc = c;
        v->scene = ew_demo_client_scene(c);
    }
    if (!v->demo_failed && ew_demo_client_advance(v->dc, t, &err) < 0) {
        error_line("%s", err.msg);  /* the demo ends there: what came before stays */
        v->demo_failed = 1;
    }
    ew_camera dcam;
    if (ew_demo_client_frame(v->dc, t, &dcam) == 0 && v->follow) {
        memcpy(v->eye, dcam.origin, sizeof v->eye);
        memcpy(v->angles, dcam.angles, sizeof v->angles);
        ew_player_set_eye(&v->player, v->eye, v->player.mode);
    }
    demo_apply_lightstyles(v->r, st, &v->o->draw);
    ew_set_scene(v->r, v->entities ? v->scene : v->empty);
    return t;
}

static int run(viewer *v) {
    view_opts *o = v->o;
    script_cmd *cmds = NULL;
    int ncmds = 0, next_cmd = 0;
    if (o->script && load_script(o->script, &cmds, &ncmds) < 0)
        return 1;
    FILE *rec = NULL;
    if (o->record && !(rec = fopen(o->record, "w"))) {
        error_line("%s: %s", o->record, strerror(errno));
        free(cmds);
        return 1;
    }
    double step = 1.0 / 60.0;
    long frame = 0, script_frames = 0;
    double script_t = 0, last = now_s(), start = last, fps_t0 = last, fps = 0;
    double ms_present = 0, shown_present = 0, win_present = 0, sum_present = 0, sum_render = 0;
    int fps_frames = 0;
    int rc = 0;
    ew_stats st;
    memset(&st, 0, sizeof st);

    while (!v->quit) {
        double t = now_s(), dt = t - last;
        last = t;
        if (o->script) {
            script_t = script_frames * step;
            dt = step;
        }
        SDL_Event e;
        while (SDL_PollEvent(&e)) {
            switch (e.type) {
            case SDL_QUIT: v->quit = 1; break;
            case SDL_KEYDOWN:
                if (!e.key.repeat) press(v, e.key.keysym.sym);
                if (e.key.keysym.sym == SDLK_F12) {
                    ew_camera cam = { { v->eye[0], v->eye[1], v->eye[2] },
                                      { v->angles[0], v->angles[1], v->angles[2] }, (float)o->fov, v->time };
                    screenshot(v, NULL, &cam);
                }
                break;
            case SDL_MOUSEBUTTONDOWN:
                if (!v->grabbed) set_grab(v, 1);
                break;
            case SDL_MOUSEMOTION:
                if (v->grabbed) app_mouse_look(v->angles, (float)e.motion.xrel, (float)e.motion.yrel);
                break;
            case SDL_WINDOWEVENT:
                if (e.window.event == SDL_WINDOWEVENT_SIZE_CHANGED && !o->size_given) {
                    int w = e.window.data1 / o->scale, h = e.window.data2 / o->scale;
                    if (w < 320) w = 320;
                    if (h < 200) h = 200;
                    if ((w != v->fw || h != v->fh) && make_renderer(v, w, h) < 0) {
                        v->quit = 1;
                        rc = 1;
                    }
                }
                break;
            default: break;
            }
        }
        /* The script's commands due by this frame's time. */
        int shots[16], nshots = 0;
        while (next_cmd < ncmds && cmds[next_cmd].t <= script_t + 1e-9) {
            script_cmd *c = &cmds[next_cmd++];
            switch (c->kind) {
            case S_CAMERA:
                memcpy(v->eye, c->v, sizeof v->eye);
                memcpy(v->angles, c->v + 3, sizeof v->angles);
                ew_player_set_eye(&v->player, v->eye, v->player.mode);
                break;
            case S_VIEW: set_view(v, c->n); break;
            case S_KEY: press(v, c->key); break;
            case S_DOWN:
            case S_UP: {
                SDL_Scancode sc = SDL_GetScancodeFromKey(c->key);
                if (sc > SDL_SCANCODE_UNKNOWN && sc < SDL_NUM_SCANCODES) v->held[sc] = c->kind == S_DOWN;
                break;
            }
            case S_SCREENSHOT:
                if (nshots < 16) shots[nshots++] = (int)(c - cmds);
                break;
            case S_QUIT: v->quit = 1; break;
            case S_STEP: step = c->v[0]; break;
            }
        }
        if (!o->script && ncmds == 0 && !v->paused)
            v->time += dt;
        else if (o->script)
            v->time = v->paused ? v->time : script_t;

        /* Movement. */
        const Uint8 *ks = SDL_GetKeyboardState(NULL);
#define HELD(sc) (ks[sc] || v->held[sc])
        app_held held = { HELD(SDL_SCANCODE_W) || HELD(SDL_SCANCODE_UP), HELD(SDL_SCANCODE_S) || HELD(SDL_SCANCODE_DOWN),
                          HELD(SDL_SCANCODE_A) || HELD(SDL_SCANCODE_LEFT), HELD(SDL_SCANCODE_D) || HELD(SDL_SCANCODE_RIGHT),
                          HELD(SDL_SCANCODE_SPACE), HELD(SDL_SCANCODE_C),
                          HELD(SDL_SCANCODE_LSHIFT) || HELD(SDL_SCANCODE_RSHIFT) };
#undef HELD
        ew_move_input in;
        app_move_input(&held, v->angles, &in);
        float before[3];
        memcpy(before, v->player.origin, sizeof before);
        ew_player_move(v->a->world, &v->player, &in, dt > 0.25 ? 0.25 : dt);
        if (memcmp(before, v->player.origin, sizeof before) != 0)
            ew_player_eye(&v->player, v->eye);

        double cam_time = v->time;
        if (v->dc) {
            cam_time = demo_frame(v);
            if (cam_time < 0) {
                rc = 1;
                break;
            }
        }
        ew_camera cam = { { v->eye[0], v->eye[1], v->eye[2] }, { v->angles[0], v->angles[1], v->angles[2] },
                          (float)o->fov, cam_time };
        double r0 = now_s();
        if (ew_render(v->r, &cam, &st) < 0) {
            error_line("cannot render this camera (origin %g,%g,%g)", cam.origin[0], cam.origin[1], cam.origin[2]);
            rc = 1;
            break;
        }
        sum_render += (now_s() - r0) * 1000.0;
        if (v->overlay) {
            /* present: the last half second's mean (the last frame's before one has passed) */
            ew_overlay_info info = { fps, fps > 0 ? shown_present : ms_present, &cam, 0, 0 };
            /* below it: the hidden-surface method (H) and how frames are shown */
            char line[128];
            if (v->dc)
                snprintf(line, sizeof line, "hsr %s\npresent %s\ndemo %.1f of %.1f s%s", ew_hsr_name((ew_hsr_method)o->draw.hsr),
                         present_names[v->mode], cam_time - v->demo_t0, v->demo_t1 - v->demo_t0,
                         v->follow ? "" : " (free camera)");
            else
                snprintf(line, sizeof line, "hsr %s\npresent %s", ew_hsr_name((ew_hsr_method)o->draw.hsr),
                         present_names[v->mode]);
            app_draw_overlay(v->r, &st, &info, line);
        }
        for (int i = 0; i < nshots; i++)
            screenshot(v, cmds[shots[i]].path, &cam);
        if (rec)
            fprintf(rec, "%.6f %.4f %.4f %.4f %.4f %.4f %.4f\n", cam.time, cam.origin[0], cam.origin[1],
                    cam.origin[2], cam.angles[0], cam.angles[1], cam.angles[2]);
        ms_present = present(v);
        sum_present += ms_present;
        win_present += ms_present;
        frame++;
        script_frames++;
        fps_frames++;
        double t1 = now_s();
        if (t1 - fps_t0 >= 0.5) {
            fps = fps_frames / (t1 - fps_t0);
            shown_present = win_present / fps_frames;  /* the overlay: the mean of the last half second */
            win_present = 0;
            fps_frames = 0;
            fps_t0 = t1;
        }
    }
    double total = now_s() - start;
    const char *how = "window surface";
    SDL_RendererInfo ri;
    if (v->sdl) how = SDL_GetRendererInfo(v->sdl, &ri) == 0 ? ri.name : "?";
    if (frame > 0)
        fprintf(stderr, "view: %ld frames %dx%d in %.2f s: fps %.1f, render %.2f ms, present %.2f ms a frame "
                "(present %s through %s%s%s: convert %.2f, upload and copy %.2f, show %.2f ms)\n", frame, v->fw,
                v->fh, total, frame / total, sum_render / frame, sum_present / frame, present_names[v->mode], how,
                v->gl_name[0] ? ", GL " : "", v->gl_name, v->phase[0] / frame, v->phase[1] / frame,
                v->phase[2] / frame);
    if (rec && fclose(rec) != 0) {
        error_line("%s: %s", o->record, strerror(errno));
        rc = 1;
    }
    free(cmds);
    return rc;
}

/* SDL found no display it can show a window on when it falls back to a
 * driver that draws to nothing ("offscreen", "dummy"): with DISPLAY naming
 * no X server, SDL 2.26 opens its offscreen driver and the viewer would
 * render into it until killed.  Allowed when asked for by name
 * (SDL_VIDEODRIVER).  1, or 0 with the error printed. */
static int real_video_driver(void) {
    const char *drv = SDL_GetCurrentVideoDriver(), *asked = getenv("SDL_VIDEODRIVER");
    if (!drv || (strcmp(drv, "offscreen") && strcmp(drv, "dummy"))) return 1;
    if (asked && strstr(asked, drv)) return 1;
    const char *x = getenv("DISPLAY"), *wl = getenv("WAYLAND_DISPLAY");
    error_line("view: cannot open the display %s%s%s%s%s: no window can be shown there (SDL fell back to its "
               "'%s' video driver; set SDL_VIDEODRIVER=%s to render to nothing on purpose)",
               x && *x ? "DISPLAY=" : "", x && *x ? x : "", x && *x && wl && *wl ? ", " : "",
               wl && *wl ? "WAYLAND_DISPLAY=" : "", wl && *wl ? wl : "", drv, drv);
    return 0;
}

int cmd_view(int argc, char **argv) {
    view_opts o;
    memset(&o, 0, sizeof o);
    o.scale = 1;
    o.fov = 90;
    draw_opts_init(&o.draw);
    int pr = parse_view_args(argc, argv, &o);
    if (pr != 0)
        return pr < 0 ? 2 : 0;
    const char *x = getenv("DISPLAY"), *wl = getenv("WAYLAND_DISPLAY");
    if ((!x || !*x) && (!wl || !*wl)) {
        error_line("view: no display (neither DISPLAY nor WAYLAND_DISPLAY is set)");
        return 1;
    }
    viewer v;
    memset(&v, 0, sizeof v);
    v.o = &o;
    v.entities = 1;
    v.threads = o.threads;
    v.alias_raster = o.draw.alias_raster;
    v.debug = (ew_debug_mode)o.draw.debug;
    int rc = 1;
    ew_error err = { "" };
    if (o.demo) {
        if (demo_open_with_map(o.demo, o.data, o.quiet, &v.demo, &v.a) < 0)
            return 1;
        if (demo_span(v.demo, o.demo, &v.demo_t0, &v.demo_t1) < 0)
            goto done;
        if (!(v.dc = ew_demo_client_create(v.demo, v.a->world, cli_search_path(o.data), &err))) {
            error_line("%s", err.msg);
            goto done;
        }
        v.scene = ew_demo_client_scene(v.dc);
        v.follow = 1;
        o.map = o.demo;  /* the window's title */
    } else {
        if (!(v.a = load_map(o.map, o.data, o.quiet)))
            return 1;
        if (draw_opts_scene(&o.draw, v.a, o.map, o.data, 1, o.quiet, &v.scene) < 0)
            goto done;
    }
    if (!(v.empty = ew_scene_create(v.a->world, &err))) {
        error_line("%s", err.msg);
        goto done;
    }
    if (o.draw.no_entities) v.entities = 0;
    v.nviews = ew_benchmark_views(v.a->world, v.views);
    if (v.nviews == 0) {
        v.views[0].angles[1] = 0;
        v.nviews = 1;
    }
    if (o.view >= v.nviews) {
        error_line("--view %d: out of range, %s has %d view%s (0 to %d)", o.view, o.map, v.nviews,
                   v.nviews == 1 ? "" : "s", v.nviews - 1);
        goto done;
    }
    set_view(&v, o.view);

    /* DISPLAY alone: X11 is the one driver that can show the window.  Asked
     * for by name, SDL neither probes Wayland (whose library prints its own
     * line without a WAYLAND_DISPLAY) nor falls back to drawing to nothing. */
    if ((!wl || !*wl) && !getenv("SDL_VIDEODRIVER")) setenv("SDL_VIDEODRIVER", "x11", 0);
    if (SDL_Init(SDL_INIT_VIDEO) != 0) {
        error_line("view: cannot open the display %s%s: %s%s", x && *x ? "DISPLAY=" : "", x && *x ? x : "",
                   SDL_GetError(), x && *x && (!wl || !*wl) ? " (is an X server running there?)" : "");
        goto done;
    }
    if (!real_video_driver()) {
        SDL_Quit();
        goto done;
    }
    SDL_SetHint(SDL_HINT_RENDER_SCALE_QUALITY, "0");
    SDL_SetHint(SDL_HINT_RENDER_VSYNC, "0");
    SDL_SetHint(SDL_HINT_MOUSE_RELATIVE_MODE_WARP, "1");
    int fw = o.size_given ? o.width : 640 / o.scale, fh = o.size_given ? o.height : 480 / o.scale;
    if (fw < 320) fw = 320;
    if (fh < 200) fh = 200;
    v.mode = o.present;
    if (v.mode == PRESENT_AUTO || v.mode == PRESENT_TEXTURE) {
        int soft = gl_probe(v.gl_name, sizeof v.gl_name);
        if (v.mode == PRESENT_AUTO) v.mode = soft ? PRESENT_SURFACE : PRESENT_TEXTURE;
    }
    if (v.mode == PRESENT_SURFACE || v.mode == PRESENT_SOFTWARE)  /* SDL's own window surface, not a GL texture */
        SDL_SetHint(SDL_HINT_FRAMEBUFFER_ACCELERATION, "0");
    if (v.mode == PRESENT_SOFTWARE)
        SDL_SetHint(SDL_HINT_RENDER_DRIVER, "software");
    v.tex_format = SDL_PIXELFORMAT_ARGB8888;
    if (!(v.tfmt = SDL_AllocFormat(v.tex_format))) {
        error_line("view: SDL: %s", SDL_GetError());
        goto sdl_done;
    }
    char title[300];
    snprintf(title, sizeof title, "edgewise - %s", o.map);
    for (int attempt = 0; attempt < 2 && !v.win; attempt++) {
        v.win = SDL_CreateWindow(title, SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED, fw * o.scale, fh * o.scale,
                                 SDL_WINDOW_RESIZABLE | (o.fullscreen ? SDL_WINDOW_FULLSCREEN_DESKTOP : 0));
        if (!v.win) break;
        if (v.mode == PRESENT_SURFACE) {
            SDL_Surface *ws = SDL_GetWindowSurface(v.win);
            if (ws && ws->format->BytesPerPixel == 4) break;
            /* a window surface of another depth: the texture instead */
            SDL_DestroyWindow(v.win);
            v.win = NULL;
            v.mode = PRESENT_TEXTURE;
            continue;
        }
        v.sdl = SDL_CreateRenderer(v.win, -1, 0);
    }
    if (!v.win || (v.mode != PRESENT_SURFACE && !v.sdl)) {
        error_line("view: cannot open a window: %s", SDL_GetError());
        goto sdl_done;
    }
    if (o.fullscreen && !o.size_given) {
        int ww, wh;
        SDL_GetWindowSize(v.win, &ww, &wh);
        fw = ww / o.scale > 320 ? ww / o.scale : 320;
        fh = wh / o.scale > 200 ? wh / o.scale : 200;
    }
    if (make_renderer(&v, fw, fh) < 0)
        goto sdl_done;
    rc = run(&v);
sdl_done:
    if (v.tex) SDL_DestroyTexture(v.tex);
    if (v.sdl) SDL_DestroyRenderer(v.sdl);
    if (v.win) SDL_DestroyWindow(v.win);
    if (v.tfmt) SDL_FreeFormat(v.tfmt);
    free(v.xmap);
    SDL_Quit();
done:
    ew_renderer_destroy(v.r);
    if (v.dc) v.scene = NULL;  /* the client's */
    ew_demo_client_destroy(v.dc);
    ew_demo_close(v.demo);
    ew_scene_destroy(v.scene);
    ew_scene_destroy(v.empty);
    ew_assets_destroy(v.a);
    return rc;
}
