/*
 * main.c - the web page's C side (app/web/, docs/web.md): the map loaded
 * from the page's in-memory file system, the camera moved by the shared
 * controls (app/common/), each frame rendered by ew_render and handed to
 * the page as RGBA bytes for a canvas's putImageData.  Uses only the
 * public API (edgewise.h).  page.js calls the web_* functions below
 * (exported, EMSCRIPTEN_KEEPALIVE); every text comes back through
 * web_message / web_state as a NUL-terminated string.
 *
 * Files the page was given are written to a folder of their own (/game1,
 * /game2, ...: a Quake game directory, pak files, maps/, gfx/, progs/), so
 * loading is the library's own ew_assets_create(NAME, DIR), as `edgewise
 * render NAME --data DIR`; the page removes the folder of a map that
 * failed, and keeps the one of the map shown.
 */
#include "app_controls.h"
#include "edgewise.h"

#include <emscripten/emscripten.h>

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct web {
    ew_assets   *a;
    ew_scene    *scene, *empty;
    ew_renderer *r;
    uint32_t    *rgba;          /* the frame for the canvas */
    size_t       rgba_n;
    ew_camera    views[EW_MAX_VIEWS];
    int          nviews, cur_view;
    ew_player    player;
    float        eye[3], angles[3];
    double       time;
    int          paused, overlay, entities, exact, pvs_lock, alias_raster, hsr, threads, color, classic;
    ew_debug_mode debug;
    int          fog_set;       /* 0: the map's own fog; 1: fog[] (the page's fog=D,R,G,B) */
    float        fog[4];
    double       fov;
    app_held     held;
    ew_stats     st;
    char         map[256];
    char         msg[2048];     /* the last message for the page (errors, warnings, key feedback) */
    char         state[2048];   /* web_state's JSON */
    char         overlay_extra[256];
} web;

static web W;

static void say(const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(W.msg, sizeof W.msg, fmt, ap);
    va_end(ap);
}

static void add_say(const char *fmt, ...) {
    size_t n = strlen(W.msg);
    if (n + 2 >= sizeof W.msg) return;
    if (n) W.msg[n++] = '\n', W.msg[n] = '\0';
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(W.msg + n, sizeof W.msg - n, fmt, ap);
    va_end(ap);
}

static void set_view(int n) {
    if (n < 0 || n >= W.nviews) return;
    W.cur_view = n;
    memcpy(W.eye, W.views[n].origin, sizeof W.eye);
    memcpy(W.angles, W.views[n].angles, sizeof W.angles);
    W.fov = W.views[n].fov > 0 ? W.views[n].fov : 90;
    ew_player_set_eye(&W.player, W.eye, W.player.mode);
}

/* Every drawing setting, as `edgewise render` sets them with no drawing
 * options (cli/draw_options.c, draw_opts_apply of draw_opts_init), plus
 * what the keys changed. */
static int apply_settings(ew_renderer *r) {
    ew_set_alias_raster(r, (ew_alias_raster)W.alias_raster, 0);
    ew_set_classic(r, W.classic);
    ew_set_liquid_alpha(r, -1);
    if (W.fog_set) ew_set_fog(r, W.fog[0], W.fog[1], W.fog[2], W.fog[3]);
    else ew_set_fog(r, -1, 0, 0, 0);
    ew_set_waterwarp(r, 1);
    ew_set_hsr(r, (ew_hsr_method)W.hsr);
    ew_set_lit(r, 1);
    ew_set_dither(r, 0);
    ew_set_lighting(r, EW_LIGHTING_CACHE);
    ew_set_gamma(r, 1.0f);
    for (int i = 0; i < 64; i++) ew_reset_lightstyle(r, i);
    ew_set_scene(r, W.entities ? W.scene : W.empty);
    ew_set_pvs_lock(r, W.pvs_lock);
    if (W.exact) ew_set_subdivision(r, 1);
    return ew_set_debug(r, W.debug);
}

/* A renderer of w x h with the current settings, in place of the one
 * there was; 0 or -1 (message set, no renderer).  The old one goes first:
 * its threads' Web Workers go back to the pool the page made at start
 * (one per logical processor), which a new one takes them from; a worker
 * made later would only start once the page's thread returns to the
 * browser, and the new renderer would wait for it. */
static int make_renderer(int w, int h) {
    if (!W.a) return -1;
    if (w < 320) w = 320;
    if (h < 200) h = 200;
    if (w > 7680) w = 7680;
    if (h > 4320) h = 4320;
    ew_renderer_destroy(W.r);
    W.r = NULL;
    ew_error err = { "" };
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){ .world = W.a->world, .palette = W.a->palette,
            .colormap = W.a->colormap, .width = w, .height = h, .threads = W.threads,
            .color = W.color ? EW_COLOR_TRUE : EW_COLOR_8BIT }, &err);
    if (!r) {
        say("%s", err.msg[0] ? err.msg : "cannot create the renderer");
        return -1;
    }
    W.r = r;
    if (apply_settings(r) < 0) {
        ew_renderer_destroy(r);
        W.r = NULL;
        say("out of memory for the debug mode");
        return -1;
    }
    size_t n = (size_t)w * (size_t)h;
    if (n > W.rgba_n) {
        uint32_t *p = realloc(W.rgba, n * sizeof *p);
        if (!p) {
            ew_renderer_destroy(r);
            W.r = NULL;
            say("out of memory for a %dx%d frame", w, h);
            return -1;
        }
        W.rgba = p, W.rgba_n = n;
    }
    return 0;
}

static void unload(void) {
    ew_renderer_destroy(W.r);
    ew_scene_destroy(W.scene);
    ew_scene_destroy(W.empty);
    ew_assets_destroy(W.a);
    W.r = NULL, W.scene = W.empty = NULL, W.a = NULL;
}

/* The map NAME from the game directory dir (maps/NAME.bsp, loose or in a pak; its .lit;
 * gfx/palette.lmp and colormap.lmp, else the built-in scene's palette and
 * colormap), or the built-in scene for "" or "builtin".  Loaded into new
 * objects first: a map that fails leaves the one shown before. */
static int load_assets(const char *name, const char *dir, ew_assets **out, ew_scene **scene) {
    ew_error err = { "" };
    *out = NULL, *scene = NULL;
    if (!*name || !strcmp(name, "builtin")) {
        if (!(*out = ew_assets_create_builtin(&err)) || !(*scene = ew_scene_create_builtin((*out)->world, &err))) {
            ew_assets_destroy(*out);
            *out = NULL;
            say("%s", err.msg);
            return -1;
        }
        return 0;
    }
    ew_fs *fs = ew_fs_create(dir, &err);
    if (!fs) {
        say("%s", err.msg);
        return -1;
    }
    uint8_t *data = NULL;
    size_t size = 0;
    ew_error e2 = { "" };
    int have_gfx = ew_fs_load(fs, "gfx/palette.lmp", &data, &size, &e2) == 0;
    free(data);
    data = NULL;
    have_gfx = have_gfx && ew_fs_load(fs, "gfx/colormap.lmp", &data, &size, &e2) == 0;
    free(data);
    data = NULL;
    ew_assets *a = NULL;
    if (have_gfx) {
        /* the command's own loader: palette, colormap, .lit as `render NAME --data DIR` */
        a = ew_assets_create(name, dir, &err);
    } else {
        /* no game data: the map itself, drawn with the built-in scene's colours */
        char path[300];
        snprintf(path, sizeof path, "maps/%s.bsp", name);
        ew_assets *b = ew_assets_create_builtin(&err);
        if (b && ew_fs_load(fs, path, &data, &size, &err) == 0) {
            ew_world *w = ew_world_create(data, size, path, &err);
            free(data);
            data = NULL;
            if (w) {
                snprintf(path, sizeof path, "maps/%s.lit", name);
                if (ew_fs_load(fs, path, &data, &size, &e2) == 0) ew_world_attach_lit(w, data, size, path);
                free(data);
                data = NULL;
                ew_world_destroy(b->world);
                b->world = w;
                a = b, b = NULL;
            }
        }
        ew_assets_destroy(b);
    }
    ew_fs_destroy(fs);
    if (!a) {
        say("%s", err.msg[0] ? err.msg : "cannot load the map");
        return -1;
    }
    if (!(*scene = ew_scene_create_from_map(a->world, name, dir, &err))) {
        ew_assets_destroy(a);
        say("%s", err.msg);
        return -1;
    }
    *out = a;
    say("%s", "");
    if (!have_gfx)
        say("no palette.lmp and colormap.lmp were given (gfx/ beside maps/, or in a pak): %s is drawn with the "
            "built-in scene's palette and colormap", name);
    for (int i = 0; ew_world_warning(a->world, i); i++) add_say("warning: %s", ew_world_warning(a->world, i));
    for (int i = 0; ew_scene_warning(*scene, i); i++) add_say("warning: %s", ew_scene_warning(*scene, i));
    return 0;
}

/* Loads a map from the game directory dir (see load_assets) at view `view` and makes a w x h renderer
 * with color (0 8-bit, 1 true), classic and threads (0 all cores).
 * Returns 0, or -1 with the message set; on failure the map shown before
 * stays. */
EMSCRIPTEN_KEEPALIVE int web_load(const char *name, const char *dir, int view, int w, int h, int color, int classic,
                                   int threads) {
    ew_assets *a;
    ew_scene *scene;
    if (load_assets(name ? name : "", dir ? dir : "/", &a, &scene) < 0) return -1;
    ew_error err = { "" };
    ew_scene *empty = ew_scene_create(a->world, &err);
    if (!empty) {
        say("%s", err.msg);
        ew_scene_destroy(scene);
        ew_assets_destroy(a);
        return -1;
    }
    if (classic && color) {
        add_say("classic: the 1996 look is 8-bit, so true colour is off");
        color = 0;
    }
    char keep[sizeof W.msg];
    memcpy(keep, W.msg, sizeof keep);
    unload();
    W.a = a, W.scene = scene, W.empty = empty;
    snprintf(W.map, sizeof W.map, "%s", name && *name ? name : "builtin");
    W.color = color, W.classic = classic, W.threads = threads < 0 ? 0 : threads;
    W.time = 0, W.paused = 0;
    W.entities = 1, W.debug = EW_DEBUG_NONE, W.exact = 0, W.pvs_lock = 0, W.hsr = EW_HSR_EDGE, W.alias_raster = 0;
    memset(&W.player, 0, sizeof W.player);
    memset(&W.held, 0, sizeof W.held);
    W.nviews = ew_benchmark_views(a->world, W.views);
    if (W.nviews == 0) {
        memset(&W.views[0], 0, sizeof W.views[0]);
        W.nviews = 1;
    }
    set_view(view >= 0 && view < W.nviews ? view : 0);
    if (make_renderer(w, h) < 0) {
        unload();
        return -1;
    }
    memcpy(W.msg, keep, sizeof W.msg);
    if (view >= W.nviews) add_say("view %d: out of range, %s has %d view%s (0 to %d); showing view 0", view, W.map,
                                  W.nviews, W.nviews == 1 ? "" : "s", W.nviews - 1);
    return 0;
}

/* Fog of density d (0 to 100: 0 none) and colour r, g, b (0 to 1), as
 * render's --fog D,R,G,B, in place of the map's own, for every map the
 * page loads from now on and the one shown.  Returns 0, or -1 with the
 * message set (nothing changed). */
EMSCRIPTEN_KEEPALIVE int web_set_fog(double d, double r, double g, double b) {
    if (!(d >= 0 && d <= 100) || !(r >= 0 && r <= 1) || !(g >= 0 && g <= 1) || !(b >= 0 && b <= 1)) {
        say("fog must be DENSITY,R,G,B: a density from 0 to 100, then three colour values from 0 to 1");
        return -1;
    }
    W.fog_set = 1;
    W.fog[0] = (float)d, W.fog[1] = (float)r, W.fog[2] = (float)g, W.fog[3] = (float)b;
    return W.r ? apply_settings(W.r) : 0;
}

/* The frame's size changed (the window was resized). */
EMSCRIPTEN_KEEPALIVE int web_resize(int w, int h) {
    if (W.r && w == ew_frame_width(W.r) && h == ew_frame_height(W.r)) return 0;
    return make_renderer(w, h);
}

EMSCRIPTEN_KEEPALIVE void web_set_camera(double x, double y, double z, double pitch, double yaw, double roll) {
    W.eye[0] = (float)x, W.eye[1] = (float)y, W.eye[2] = (float)z;
    W.angles[0] = (float)pitch, W.angles[1] = (float)yaw, W.angles[2] = (float)roll;
    W.fov = 90;
    ew_player_set_eye(&W.player, W.eye, W.player.mode);
}

/* Time: fixed at t (paused, as render --time t) when t >= 0. */
EMSCRIPTEN_KEEPALIVE void web_set_time(double t, int paused) {
    if (t >= 0) W.time = t;
    W.paused = paused;
}

EMSCRIPTEN_KEEPALIVE void web_set_overlay(int on) { W.overlay = on; }

/* The movement keys held: bits forward, back, left, right, up, down, run. */
EMSCRIPTEN_KEEPALIVE void web_held(int bits) {
    W.held = (app_held){ bits & 1, bits >> 1 & 1, bits >> 2 & 1, bits >> 3 & 1, bits >> 4 & 1, bits >> 5 & 1,
                         bits >> 6 & 1 };
}

EMSCRIPTEN_KEEPALIVE void web_mouse(double dx, double dy) { app_mouse_look(W.angles, (float)dx, (float)dy); }

/* A key press by its name (KeyboardEvent.key); returns the app_action (0:
 * not bound) and sets the message to what it did. */
EMSCRIPTEN_KEEPALIVE int web_key(const char *name) {
    int arg;
    app_action act = app_key(name, &arg);
    if (!W.r) return act;
    switch (act) {
    case APP_DEBUG: {
        ew_debug_mode m = (ew_debug_mode)arg;
        W.debug = W.debug == m ? EW_DEBUG_NONE : m;
        ew_set_debug(W.r, W.debug);
        W.debug = ew_get_debug(W.r);
        say("debug: %s", app_debug_names[W.debug]);
        break;
    }
    case APP_VIEW:
        set_view(arg);
        say("view %d of %d", W.cur_view, W.nviews);
        break;
    case APP_VIEW_NEXT: set_view((W.cur_view + 1) % W.nviews); say("view %d of %d", W.cur_view, W.nviews); break;
    case APP_VIEW_PREV:
        set_view((W.cur_view + W.nviews - 1) % W.nviews);
        say("view %d of %d", W.cur_view, W.nviews);
        break;
    case APP_PAUSE: W.paused = !W.paused; say("%s", W.paused ? "paused" : "running"); break;
    case APP_OVERLAY: W.overlay = !W.overlay; break;
    case APP_MOVE_MODE:
        W.player.mode = W.player.mode == EW_MOVE_FLY ? EW_MOVE_WALK : EW_MOVE_FLY;
        memset(W.player.velocity, 0, sizeof W.player.velocity);
        say("move: %s", W.player.mode == EW_MOVE_FLY ? "fly" : "walk");
        break;
    case APP_PVS_LOCK:
        W.pvs_lock = !W.pvs_lock;
        ew_set_pvs_lock(W.r, W.pvs_lock);
        say("pvs lock: %s", W.pvs_lock ? "on" : "off");
        break;
    case APP_EXACT:
        W.exact = !W.exact;
        ew_set_subdivision(W.r, W.exact ? 1 : 16);
        say("perspective: %s", W.exact ? "exact" : "16-pixel subdivision");
        break;
    case APP_THREADS: {
        int cur = ew_get_threads(W.r), cores = ew_set_threads(W.r, 0);
        int next = app_next_threads(cur, cores);
        if (cores < 0 || ew_set_threads(W.r, next) < 0) {
            say("threads: out of memory");
            break;
        }
        W.threads = next;
        int n = ew_get_threads(W.r);
        say("threads: %d%s", n, n == cores ? " (all cores)" : "");
        break;
    }
    case APP_ENTITIES:
        W.entities = !W.entities;
        ew_set_scene(W.r, W.entities ? W.scene : W.empty);
        say("entities: %s", W.entities ? "on" : "off");
        break;
    case APP_HSR: {
        int m = app_next_hsr(W.hsr);
        if (ew_set_hsr(W.r, (ew_hsr_method)m) == 0) W.hsr = m;
        say("hsr: %s", ew_hsr_name((ew_hsr_method)W.hsr));
        break;
    }
    case APP_RASTER:
        W.alias_raster = (W.alias_raster + 1) % APP_RASTER_COUNT;
        ew_set_alias_raster(W.r, (ew_alias_raster)W.alias_raster, 0);
        say("alias raster: %s", app_raster_names[W.alias_raster]);
        break;
    default: break;
    }
    return act;
}

/* The extra overlay lines under the statistics (the page's own: how many
 * threads and why). */
EMSCRIPTEN_KEEPALIVE void web_set_overlay_extra(const char *text) {
    snprintf(W.overlay_extra, sizeof W.overlay_extra, "%s", text ? text : "");
}

static void to_rgba(void) {
    int w = ew_frame_width(W.r), h = ew_frame_height(W.r);
    size_t n = (size_t)w * (size_t)h;
    if (ew_frame_color(W.r) == EW_COLOR_TRUE) {
        memcpy(W.rgba, ew_frame_rgba(W.r), n * sizeof *W.rgba);
    } else {
        uint32_t table[256];
        ew_palette_rgba(ew_frame_palette(W.r), table);
        ew_pixels_to_rgba(ew_frame_pixels(W.r), n, table, W.rgba);
    }
    uint8_t *p = (uint8_t *)W.rgba;  /* opaque for the canvas, whatever the frame's alpha */
    for (size_t i = 0; i < n; i++) p[4 * i + 3] = 255;
}

/* One frame: dt seconds of movement and time, the render, the overlay
 * (fps, ms_present: the page's measures), the RGBA bytes.  Returns their
 * address (width x height x 4 bytes), or 0 with the message set. */
EMSCRIPTEN_KEEPALIVE uint32_t *web_frame(double dt, double fps, double ms_present) {
    if (!W.r) return NULL;
    if (!(dt >= 0)) dt = 0;
    if (!W.paused) W.time += dt;
    ew_move_input in;
    app_move_input(&W.held, W.angles, &in);
    float before[3];
    memcpy(before, W.player.origin, sizeof before);
    ew_player_move(W.a->world, &W.player, &in, dt > 0.25 ? 0.25 : dt);
    if (memcmp(before, W.player.origin, sizeof before) != 0) ew_player_eye(&W.player, W.eye);
    ew_camera cam = { { W.eye[0], W.eye[1], W.eye[2] }, { W.angles[0], W.angles[1], W.angles[2] }, (float)W.fov,
                      W.time };
    if (ew_render(W.r, &cam, &W.st) < 0) {
        say("cannot render this camera (origin %g,%g,%g)", cam.origin[0], cam.origin[1], cam.origin[2]);
        return NULL;
    }
    if (W.overlay) {
        ew_overlay_info info = { fps, ms_present, &cam, 0, 0 };
        char extra[400];
        snprintf(extra, sizeof extra, "hsr %s\n%s", ew_hsr_name((ew_hsr_method)W.hsr), W.overlay_extra);
        app_draw_overlay(W.r, &W.st, &info, extra);
    }
    to_rgba();
    return W.rgba;
}

EMSCRIPTEN_KEEPALIVE const char *web_message(void) { return W.msg; }

/* The model files the map's entities asked for that its game directory lacks
 * (ew_scene_missing_file): the page fetches them beside the map and loads
 * it again.  NULL past the last. */
EMSCRIPTEN_KEEPALIVE const char *web_missing_file(int i) { return ew_scene_missing_file(W.scene, i); }

/* The state as JSON: map, frame size, threads, camera, move mode, the
 * last frame's stage times. */
EMSCRIPTEN_KEEPALIVE const char *web_state(void) {
    if (!W.r) return "{}";
    snprintf(W.state, sizeof W.state,
             "{\"map\":\"%s\",\"width\":%d,\"height\":%d,\"threads\":%d,\"color\":\"%s\",\"classic\":%d,"
             "\"view\":%d,\"views\":%d,\"pos\":[%.9g,%.9g,%.9g],\"angles\":[%.9g,%.9g,%.9g],\"time\":%.9g,"
             "\"move\":\"%s\",\"debug\":\"%s\",\"overlay\":%d,\"paused\":%d,"
             "\"ms\":{\"front\":%.4f,\"scan\":%.4f,\"draw\":%.4f,\"models\":%.4f,\"total\":%.4f}}",
             W.map, ew_frame_width(W.r), ew_frame_height(W.r), ew_get_threads(W.r), W.color ? "true" : "8bit",
             W.classic, W.cur_view, W.nviews, W.eye[0], W.eye[1], W.eye[2], W.angles[0], W.angles[1], W.angles[2],
             W.time, W.player.mode == EW_MOVE_FLY ? "fly" : "walk", app_debug_names[W.debug], W.overlay, W.paused,
             W.st.ms_front, W.st.ms_scan, W.st.ms_draw, W.st.ms_models, W.st.ms_total);
    return W.state;
}

/* ---- ?bench=1: the benchmark protocol of `edgewise bench` ------------------
 * The view set rendered once untimed, then `passes` times, each frame timed;
 * one JSON object per size and thread count with bench's fields of the
 * same names and meaning (map, width, height, threads, threads_requested,
 * threads_applied, views, passes, gap_ms, median_ms, mean_ms, p99_ms,
 * max_ms, cold, max_view, ns_per_pixel, stages), and the colour mode;
 * bench's serial-part probes and per-view rows are left out. */

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static char *bench_json;

EMSCRIPTEN_KEEPALIVE const char *web_bench(int w, int h, int threads, int passes) {
    free(bench_json);
    bench_json = NULL;
    if (!W.a) return "{\"error\":\"no map\"}";
    if (passes < 1) passes = 5;
    /* the page's renderer makes way (its workers), and is made again after */
    int fw = W.r ? ew_frame_width(W.r) : 640, fh = W.r ? ew_frame_height(W.r) : 480;
    ew_renderer_destroy(W.r);
    W.r = NULL;
    ew_error err = { "" };
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){ .world = W.a->world, .palette = W.a->palette,
            .colormap = W.a->colormap, .width = w, .height = h, .threads = 1,
            .color = W.color ? EW_COLOR_TRUE : EW_COLOR_8BIT }, &err);
    if (!r) {
        say("%s", err.msg);
        make_renderer(fw, fh);
        return "{\"error\":\"renderer\"}";
    }
    int saved_debug = W.debug, saved_exact = W.exact, saved_lock = W.pvs_lock;
    W.debug = EW_DEBUG_NONE, W.exact = 0, W.pvs_lock = 0;
    apply_settings(r);
    W.debug = saved_debug, W.exact = saved_exact, W.pvs_lock = saved_lock;
    ew_set_scene(r, W.scene);
    if (threads != 1) ew_set_threads(r, threads);
    int nv = W.nviews, n = nv * passes;
    double *ms = malloc(sizeof *ms * (size_t)n), *stage[5];
    for (int s = 0; s < 5; s++) stage[s] = malloc(sizeof(double) * (size_t)n);
    double mean = 0, max = 0;
    int max_view = 0;
    /* Warm-up: bench's one untimed pass, and more until a second has gone
     * by (at most 50 passes).  The browser first runs WebAssembly from its
     * baseline compiler and swaps in optimised code for the hot functions
     * in the background, call by call: one pass of a small map (17 views
     * of e2m1 at 640x480, 6 ms) was over before that, and its frames were
     * timed at 2-3x native instead of 1.4x. */
    int warm = 0;
    for (double t0 = emscripten_get_now(); warm < 1 || (warm < 50 && emscripten_get_now() - t0 < 1000); warm++)
        for (int v = 0; v < nv; v++) ew_render(r, &W.views[v], NULL);
    for (int p = 0; p < passes; p++)
        for (int v = 0; v < nv; v++) {
            ew_stats st;
            double t0 = emscripten_get_now();
            ew_render(r, &W.views[v], &st);
            double t = emscripten_get_now() - t0;
            int i = p * nv + v;
            ms[i] = t, mean += t;
            if (t > max) max = t, max_view = v;
            stage[0][i] = st.ms_front, stage[1][i] = st.ms_scan, stage[2][i] = st.ms_draw;
            stage[3][i] = st.ms_models, stage[4][i] = st.ms_total;
        }
    mean /= n;
    qsort(ms, (size_t)n, sizeof *ms, cmp_double);
    int k = (int)ceil(0.99 * n);
    double median = n % 2 ? ms[n / 2] : 0.5 * (ms[n / 2 - 1] + ms[n / 2]), p99 = ms[k < 1 ? 0 : k - 1];
    double med[5];
    for (int s = 0; s < 5; s++) {
        qsort(stage[s], (size_t)n, sizeof(double), cmp_double);
        med[s] = n % 2 ? stage[s][n / 2] : 0.5 * (stage[s][n / 2 - 1] + stage[s][n / 2]);
        free(stage[s]);
    }
    free(ms);
    size_t cap = 1024;
    bench_json = malloc(cap);
    if (bench_json)
        snprintf(bench_json, cap,
                 "{\"map\":\"%s\",\"width\":%d,\"height\":%d,\"threads\":%d,\"threads_requested\":%d,"
                 "\"threads_applied\":true,\"views\":%d,\"passes\":%d,\"gap_ms\":0,\"color\":\"%s\",\"classic\":%s,"
                 "\"median_ms\":%.10g,\"mean_ms\":%.10g,\"p99_ms\":%.10g,\"max_ms\":%.10g,\"cold\":false,"
                 "\"max_view\":%d,\"ns_per_pixel\":%.10g,\"warmup_passes\":%d,"
                 "\"stages\":{\"front\":%.10g,\"scan\":%.10g,\"draw\":%.10g,\"models\":%.10g,\"total\":%.10g}}",
                 W.map, w, h, ew_get_threads(r), threads, nv, passes, W.color ? "true" : "8bit",
                 W.classic ? "true" : "false", median, mean, p99, max, max_view, median * 1e6 / ((double)w * h), warm,
                 med[0], med[1], med[2], med[3], med[4]);
    ew_renderer_destroy(r);
    make_renderer(fw, fh);
    return bench_json ? bench_json : "{\"error\":\"out of memory\"}";
}

int main(void) { return 0; }
