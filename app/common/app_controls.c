/*
 * app_controls.c - the key bindings, mouse look, movement keys and overlay
 * shared by the viewer and the web page (app_controls.h).
 */
#include "app_controls.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

const char *const app_debug_names[8] = { "normal", "spans", "edges", "overdraw", "lighting", "textures",
                                         "mips", "builds" };
const char *const app_raster_names[APP_RASTER_COUNT] = { "auto", "affine", "subdiv", "masks", "sprite-cache" };

app_action app_key(const char *name, int *arg) {
    int dummy;
    if (!arg) arg = &dummy;
    *arg = 0;
    if (!name || !*name) return APP_NONE;
    if (name[0] == 'F' && name[1] >= '1' && name[1] <= '9') {
        int n = name[1] - '0';
        if (name[2] >= '0' && name[2] <= '9' && !name[3]) n = n * 10 + (name[2] - '0');
        else if (name[2]) return APP_NONE;
        if (n >= 1 && n <= 7) {
            *arg = EW_DEBUG_SPANS + (n - 1);
            return APP_DEBUG;
        }
        return n == 12 ? APP_SCREENSHOT : APP_NONE;
    }
    if (!strcmp(name, "Escape")) return APP_RELEASE;
    if (!strcmp(name, "PageUp")) return APP_VIEW_NEXT;
    if (!strcmp(name, "PageDown")) return APP_VIEW_PREV;
    if (!strcmp(name, "Tab")) return APP_OVERLAY;
    if (name[1]) return APP_NONE;
    if (name[0] >= '0' && name[0] <= '9') {  /* views counted from 0, as --view and `edgewise views` */
        *arg = name[0] - '0';
        return APP_VIEW;
    }
    if (name[0] == '[') return APP_DEMO_BACK;
    if (name[0] == ']') return APP_DEMO_ON;
    switch (name[0] | 32) {
    case 'g': return APP_FREE_CAMERA;
    case 'p': return APP_PAUSE;
    case 'f': return APP_MOVE_MODE;
    case 'l': return APP_PVS_LOCK;
    case 'x': return APP_EXACT;
    case 't': return APP_THREADS;
    case 'e': return APP_ENTITIES;
    case 'h': return APP_HSR;
    case 'r': return APP_RASTER;
    default: return APP_NONE;
    }
}

void app_move_input(const app_held *h, const float angles[3], ew_move_input *in) {
    memset(in, 0, sizeof *in);
    memcpy(in->angles, angles, sizeof in->angles);
    in->forward = (float)(!!h->forward - !!h->back);
    in->right = (float)(!!h->right - !!h->left);
    in->up = (float)(!!h->up - !!h->down);
    in->jump = !!h->up;
    in->run = !!h->run;
}

void app_mouse_look(float angles[3], float dx, float dy) {
    angles[1] -= dx * 0.2f;
    angles[0] += dy * 0.2f;
    if (angles[0] > 89) angles[0] = 89;
    if (angles[0] < -89) angles[0] = -89;
    angles[1] = fmodf(angles[1], 360.0f);
}

int app_next_threads(int cur, int cores) {
    return cur < 2 && cores > 2 ? 2 : cur < cores ? 0 : 1;
}

int app_next_hsr(int cur) {
    for (int i = 1; i <= EW_HSR_COUNT; i++) {
        int c = (cur + i) % EW_HSR_COUNT;
        if (ew_hsr_available((ew_hsr_method)c)) return c;
    }
    return cur;
}

void app_draw_overlay(ew_renderer *r, const ew_stats *st, const ew_overlay_info *info, const char *extra) {
    ew_draw_stats_overlay(r, st, info);
    if (!extra || !*extra) return;
    char text[1024];
    int fh = ew_frame_height(r);
    int scale = fh / 480 < 1 ? 1 : fh / 480 > 4 ? 4 : fh / 480, tw, th;
    ew_format_stats_overlay(text, sizeof text, st, info);
    if (ew_text_size(text, scale, &tw, &th) == 0)
        ew_draw_text(r, 4 * scale, 4 * scale + th + 2 * scale, scale, extra, NULL);
}
