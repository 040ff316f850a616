/*
 * dark.c - a nearly black frame is never silent: every command that writes
 * a picture of a map (render, demo, shots, fly, the viewer's screenshots)
 * measures the frame's mean brightness and, under DARK_LUMA, warns with the
 * likely cause, found through the public and lab calls:
 *   - the eye is in solid: inside a wall or outside the map (the point
 *     hull's contents at the eye);
 *   - nothing is in view: the camera looks out into the void;
 *   - the map's light data is dark as a whole (the mean of its samples);
 *   - light style 0, the main light, turned down (--lightstyle 0=...);
 *   - a near surface fills most of the frame: the camera faces a dark wall
 *     (the frame's depth);
 *   - else the light where the camera looks is dark.
 */
#include "cli.h"

#include <stdio.h>
#include <string.h>

double frame_mean_luma(const ew_renderer *r) {
    size_t n = (size_t)ew_frame_width(r) * (size_t)ew_frame_height(r);
    double sum = 0;
    const uint8_t *px = ew_frame_pixels(r);
    if (px) {
        const uint8_t *pal = ew_frame_palette(r);  /* the colours written, gamma included */
        double lum[256];
        for (int i = 0; i < 256; i++) lum[i] = 0.299 * pal[3 * i] + 0.587 * pal[3 * i + 1] + 0.114 * pal[3 * i + 2];
        for (size_t i = 0; i < n; i++) sum += lum[px[i]];
    } else if (ew_frame_rgba(r)) {
        const uint8_t *c = (const uint8_t *)ew_frame_rgba(r);
        for (size_t i = 0; i < n; i++) sum += 0.299 * c[4 * i] + 0.587 * c[4 * i + 1] + 0.114 * c[4 * i + 2];
    }
    return n ? sum / (double)n : 0;
}

/* A wall nearer than this (units) over more than half the frame: "faces a wall". */
#define NEAR_WALL 64.0f
/* The map's light samples averaging under this (of 255): its light data is dark. */
#define DARK_LIGHT_DATA 8.0

void dark_cause(ew_renderer *r, const ew_world *w, const ew_camera *cam, char *why, size_t size) {
    if (ew_point_contents(w, EW_HULL_POINT, cam->origin) == EW_CONTENTS_SOLID) {
        snprintf(why, size, "the camera (%g,%g,%g) is in solid: inside a wall or outside the map", cam->origin[0],
                 cam->origin[1], cam->origin[2]);
        return;
    }
    const float *z = ew_frame_zbuffer(r);
    long n = (long)ew_frame_width(r) * ew_frame_height(r), drawn = 0, near = 0;
    for (long i = 0; z && i < n; i++) {
        drawn += z[i] > 0;
        near += z[i] > 1.0f / NEAR_WALL;
    }
    if (z && drawn == 0) {
        snprintf(why, size, "nothing is in view: the camera (%g,%g,%g) looks out of the map into the void",
                 cam->origin[0], cam->origin[1], cam->origin[2]);
        return;
    }
    double light = ew_world_light_mean(w);
    if (light >= 0 && light < DARK_LIGHT_DATA) {
        snprintf(why, size, "the map's light data is dark (its light samples average %.1f of 255)", light);
        return;
    }
    int style0 = ew_get_lightstyle(r, 0);
    if (style0 >= 0 && style0 < 64) {
        snprintf(why, size, "light style 0, the map's main light, is at %d of 256 (--lightstyle)", style0);
        return;
    }
    if (z && near * 2 > n) {
        snprintf(why, size, "the camera faces a dark wall (nearer than %g units over %.0f%% of the frame)",
                 NEAR_WALL, 100.0 * (double)near / (double)n);
        return;
    }
    if (light < 0)
        snprintf(why, size, "the map has no light data (drawn fullbright), yet the frame is dark: its textures, "
                 "--gamma or the debug mode");
    else
        snprintf(why, size, "the light where the camera looks is dark: the map's light data there (its samples "
                 "average %.1f of 255 over the whole map)", light);
}

int warn_if_dark(ew_renderer *r, const ew_world *w, const ew_camera *cam, const char *what, int quiet,
                 double *mean) {
    double m = frame_mean_luma(r);
    if (mean) *mean = m;
    if (m >= DARK_LUMA) return 0;
    if (!quiet) {
        char why[400];
        dark_cause(r, w, cam, why, sizeof why);
        error_line("warning: %s: the frame is nearly black (mean brightness %.1f%% of full scale, under %.1f%%): %s",
                   what, m / 2.55, DARK_LUMA / 2.55, why);
    }
    return 1;
}
