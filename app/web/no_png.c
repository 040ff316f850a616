/*
 * no_png.c - the library's PNG calls in the web build, which links no
 * libpng (nothing may be downloaded at build time, so no emscripten port):
 * each fails with one line saying so.  The page saves its screenshots as
 * PNGs encoded by the browser (canvas.toBlob), from the frame's pixels.
 */
#include "edgewise.h"
#include "edgewise_lab.h"

#include <stdio.h>

static int no_png(ew_error *err, const char *path) {
    if (err)
        snprintf(err->msg, sizeof err->msg, "%s: this build writes and reads no PNG files (the web page "
                 "encodes its pictures in the browser)", path && *path ? path : "(png)");
    return -1;
}

int ew_write_png(const char *path, const uint8_t *pixels, int width, int height, const uint8_t palette[768],
                 ew_error *err) {
    (void)pixels, (void)width, (void)height, (void)palette;
    return no_png(err, path);
}

int ew_write_png_rgba(const char *path, const uint32_t *pixels, int width, int height, ew_error *err) {
    (void)pixels, (void)width, (void)height;
    return no_png(err, path);
}

int ew_read_png_rgb(const char *path, uint8_t **rgb, int *width, int *height, ew_error *err) {
    if (rgb) *rgb = NULL;
    (void)width, (void)height;
    return no_png(err, path);
}
