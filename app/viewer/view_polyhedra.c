/*
 * view_polyhedra.c - edgewise view builtin:polyhedra: the moving polyhedra
 * (ew_polyhedra_*: a 1/z-sorted edge list, no BSP) animated in a window.
 * The counters of each frame are in the window's title.  Keys: Space pause,
 * Left/Right step a tenth of a second (paused) or slow/speed up, I
 * intersection resolution on/off (off: the chapter's independent sorting,
 * wrong where objects pass through each other), Z the z-buffer instead,
 * F12 a screenshot (polyhedra_shot.png), Esc or Q quit.
 *
 * Built only with SDL2, like viewer.c; cli/cmd_polyhedra.c stands in
 * without it.
 */
#define _POSIX_C_SOURCE 200809L
#include "cli.h"
#include "edgewise.h"

#include <SDL.h>

#include <stdlib.h>
#include <string.h>
#include <time.h>

static const char usage[] =
    "usage: edgewise view builtin:polyhedra [options]\n"
    "\n"
    "The moving polyhedra of 'edgewise render builtin:polyhedra', animated.\n"
    "keys: Space pause, Left/Right slower/faster (paused: step 0.1 s), I intersection\n"
    "resolution on/off, Z z-buffer on/off, F12 screenshot (polyhedra_shot.png), Esc/Q quit\n"
    "\n"
    "options:\n"
    CLI_OPTIONS_HERE;

static double secs(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

int cmd_view_polyhedra(int argc, char **argv) {
    polyhedra_opts po = { 640, 480, EW_POLYHEDRA_DEFAULT, 1, 0, 0, 0, 0, 0, NULL };
    int pr = parse_polyhedra_args(argc, argv, CLI_VIEW_POLYHEDRA, usage, &po);
    if (pr)
        return pr == 1 ? 0 : pr;
    int w = po.width, h = po.height, scale = po.scale, objects = po.objects;
    long frames = po.frames;
    double t = po.time;
    const char *out = po.out;

    ew_error err = { "" };
    int rc = 1;
    ew_polyhedra *p = ew_polyhedra_create(objects, w, h, NULL, &err);
    uint8_t *px = malloc((size_t)w * h);
    uint32_t *rgba = malloc(sizeof *rgba * (size_t)w * h), table[256];
    SDL_Window *win = NULL;
    SDL_Renderer *sdl = NULL;
    SDL_Texture *tex = NULL;
    if (!p || !px || !rgba) {
        error_line("%s", p ? "out of memory" : err.msg);
        goto done;
    }
    ew_palette_rgba(ew_polyhedra_palette(p), table);
    if (SDL_Init(SDL_INIT_VIDEO) != 0) {
        error_line("view: cannot open the display: %s", SDL_GetError());
        goto done;
    }
    SDL_SetHint(SDL_HINT_RENDER_SCALE_QUALITY, "0");
    win = SDL_CreateWindow("edgewise - builtin:polyhedra", SDL_WINDOWPOS_CENTERED,
                           SDL_WINDOWPOS_CENTERED, w * scale, h * scale, SDL_WINDOW_RESIZABLE);
    if (!win || !(sdl = SDL_CreateRenderer(win, -1, 0)) ||
        !(tex = SDL_CreateTexture(sdl, SDL_PIXELFORMAT_RGBA32, SDL_TEXTUREACCESS_STREAMING, w, h))) {
        error_line("view: cannot open a window: %s", SDL_GetError());
        goto sdl_done;
    }
    int paused = 0, crossings = 1, zbuf = 0, quit = 0, shot = 0;
    double speed = 1, last = secs();
    for (long f = 0; !quit; f++) {
        SDL_Event e;
        while (SDL_PollEvent(&e)) {
            if (e.type == SDL_QUIT)
                quit = 1;
            if (e.type != SDL_KEYDOWN)
                continue;
            switch (e.key.keysym.sym) {
            case SDLK_ESCAPE: case SDLK_q: quit = 1; break;
            case SDLK_SPACE: paused = !paused; break;
            case SDLK_i: crossings = !crossings; break;
            case SDLK_z: zbuf = !zbuf; break;
            case SDLK_F12: shot = 1; break;
            case SDLK_LEFT: if (paused) t = t > 0.1 ? t - 0.1 : 0; else speed /= 1.5; break;
            case SDLK_RIGHT: if (paused) t += 0.1; else speed *= 1.5; break;
            default: break;
            }
        }
        double now = secs();
        if (!paused)
            t += frames ? 1.0 / 30 : (now - last) * speed;
        last = now;
        if (t > 1e6)
            t = 0;
        ew_polyhedra_set_crossings(p, crossings);
        ew_polyhedra_stats st;
        double t0 = secs();
        int r = zbuf ? ew_polyhedra_render_zbuffer(p, t, px, &st, &err)
                     : ew_polyhedra_render(p, t, px, &st, &err);
        double ms = (secs() - t0) * 1000;
        if (r < 0) {
            error_line("%s", err.msg);
            goto sdl_done;
        }
        char title[256];
        snprintf(title, sizeof title,
                 "edgewise - builtin:polyhedra  t %.2f  %s  polys %d edges %d spans %d crossings %d  "
                 "overdraw %.2f  %.2f ms%s", t, zbuf ? "z-buffer" : crossings ? "edge list" :
                 "edge list, independent", st.polygons, st.edges, st.spans, st.crossings,
                 (double)st.pixels / ((double)w * h), ms, paused ? "  (paused)" : "");
        SDL_SetWindowTitle(win, title);
        if (shot) {
            if (ew_write_png("polyhedra_shot.png", px, w, h, ew_polyhedra_palette(p), &err) < 0)
                error_line("%s", err.msg);
            else
                fprintf(stderr, "wrote polyhedra_shot.png\n");
            shot = 0;
        }
        ew_pixels_to_rgba(px, (size_t)w * h, table, rgba);
        SDL_UpdateTexture(tex, NULL, rgba, w * 4);
        SDL_RenderClear(sdl);
        SDL_RenderCopy(sdl, tex, NULL, NULL);
        SDL_RenderPresent(sdl);
        if (frames && f + 1 >= frames)
            quit = 1;
        if (!frames)
            SDL_Delay(1);  /* let the rest of the machine breathe */
    }
    if (out && ew_write_png(out, px, w, h, ew_polyhedra_palette(p), &err) < 0) {
        error_line("%s", err.msg);
        goto sdl_done;
    }
    if (out)
        fprintf(stderr, "wrote %s (%dx%d)\n", out, w, h);
    rc = 0;
sdl_done:
    if (tex) SDL_DestroyTexture(tex);
    if (sdl) SDL_DestroyRenderer(sdl);
    if (win) SDL_DestroyWindow(win);
    SDL_Quit();
done:
    free(px), free(rgba);
    ew_polyhedra_destroy(p);
    return rc;
}
