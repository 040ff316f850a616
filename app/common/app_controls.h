/*
 * app_controls.h - what the SDL viewer (app/viewer/) and the web page
 * (app/web/) share: the key bindings, mouse look, the movement keys held,
 * the names the keys cycle through and the overlay's lines.  Written once,
 * compiled into both; it uses the public API (edgewise.h) only.
 */
#ifndef EW_APP_CONTROLS_H
#define EW_APP_CONTROLS_H

#include "edgewise.h"

#include <stddef.h>

/* What a key does (docs/viewer.md, "Keys"). */
typedef enum app_action {
    APP_NONE = 0,
    APP_VIEW,          /* 0-9: view N of the view set (app_key's *arg) */
    APP_VIEW_NEXT,     /* PgUp */
    APP_VIEW_PREV,     /* PgDn */
    APP_DEBUG,         /* F1-F7: debug mode *arg (EW_DEBUG_SPANS ..), again: off */
    APP_RELEASE,       /* Esc: release the mouse (the viewer: quit when not grabbed) */
    APP_PAUSE,         /* P */
    APP_OVERLAY,       /* Tab */
    APP_MOVE_MODE,     /* F: fly / walk */
    APP_PVS_LOCK,      /* L */
    APP_EXACT,         /* X: exact perspective */
    APP_THREADS,       /* T: 1, 2, all cores */
    APP_ENTITIES,      /* E */
    APP_HSR,           /* H: the next hidden-surface method */
    APP_RASTER,        /* R: the next alias rasterizer */
    APP_SCREENSHOT,    /* F12 */
    APP_DEMO_BACK,     /* [: a demo 5 s back (the viewer's --demo) */
    APP_DEMO_ON,       /* ]: 5 s on */
    APP_FREE_CAMERA    /* G: the demo's camera or a free one */
} app_action;

/* The action of a key by its name, as SDL_GetKeyName and the browser's
 * KeyboardEvent.key spell it ("w" or "W", "F1", "Tab", "PageUp",
 * "PageDown", "Escape", "0".."9", "[", "]"); *arg gets the view or debug
 * mode. */
app_action app_key(const char *name, int *arg);

/* The movement keys held (1 each). */
typedef struct app_held {
    int forward, back, left, right, up, down, run;
} app_held;
/* One frame's controls from the keys held and the view's angles: W/Up
 * forward, S/Down back, A/Left and D/Right sideways, Space up (fly) or jump
 * (walk), C down, Shift runs. */
void app_move_input(const app_held *h, const float angles[3], ew_move_input *in);
/* Mouse look: dx, dy pixels of motion turn the view 0.2 degrees each;
 * pitch stays within -89..89, yaw within (-360, 360). */
void app_mouse_look(float angles[3], float dx, float dy);

/* The next thread count of the T key: 1, 2, all cores, 1, ... (from any
 * count, the next one up); cores is the count 0 gives. */
int app_next_threads(int cur, int cores);
/* The next hidden-surface method this build has after cur. */
int app_next_hsr(int cur);

/* Names of the debug modes (EW_DEBUG_*: "normal", "spans", ...) and the
 * alias rasterizers (EW_ALIAS_*: "auto", "affine", ...). */
extern const char *const app_debug_names[8];
#define APP_RASTER_COUNT 5
extern const char *const app_raster_names[APP_RASTER_COUNT];

/* The overlay: the library's statistics overlay in the top-left corner and
 * below it the lines of `extra` (e.g. "hsr edge\npresent surface"), both
 * at the scale of the frame's height (height / 480 within 1..4). */
void app_draw_overlay(ew_renderer *r, const ew_stats *st, const ew_overlay_info *info, const char *extra);

#endif
