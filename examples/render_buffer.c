/*
 * render_buffer: render into the caller's own 32-bit buffer (what a window
 * or a texture upload wants), print a checksum of it and optionally write it
 * as a PPM image.
 *
 *   cc render_buffer.c -o render_buffer $(pkg-config --cflags --libs edgewise)
 *   ./render_buffer builtin 640x480 out.ppm
 *
 * The checksum is 64-bit FNV-1a over the R, G, B bytes of every pixel, row by
 * row: the same for any program that reads the same picture.
 */
#include <edgewise.h>

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The caller's frame: 32-bit pixels, bytes R, G, B, A in memory. */
typedef struct framebuffer {
    int       width, height;
    uint32_t *pixels;
} framebuffer;

/* Copies the renderer's frame into fb, whichever colour mode it has. */
static void copy_frame(const ew_renderer *r, framebuffer *fb)
{
    size_t n = (size_t)fb->width * (size_t)fb->height;
    if (ew_frame_color(r) == EW_COLOR_TRUE) {
        memcpy(fb->pixels, ew_frame_rgba(r), n * sizeof(uint32_t));
    } else {
        uint32_t table[256];
        ew_palette_rgba(ew_frame_palette(r), table);  /* the palette through the gamma */
        ew_pixels_to_rgba(ew_frame_pixels(r), n, table, fb->pixels);
    }
}

static uint64_t checksum_rgb(const framebuffer *fb)
{
    const uint8_t *p = (const uint8_t *)fb->pixels;
    uint64_t h = 14695981039346656037u;
    for (size_t i = 0; i < (size_t)fb->width * (size_t)fb->height; i++, p += 4)
        for (int c = 0; c < 3; c++) {
            h ^= p[c];
            h *= 1099511628211u;
        }
    return h;
}

static int write_ppm(const char *path, const framebuffer *fb)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    fprintf(f, "P6\n%d %d\n255\n", fb->width, fb->height);
    const uint8_t *p = (const uint8_t *)fb->pixels;
    for (size_t i = 0; i < (size_t)fb->width * (size_t)fb->height; i++, p += 4)
        fwrite(p, 1, 3, f);
    return fclose(f) == 0 ? 0 : -1;
}

int main(int argc, char **argv)
{
    if (argc < 2 || argc > 5) {
        fprintf(stderr, "usage: %s MAP|builtin [WxH] [OUT.ppm] [DATA_DIR]\n", argv[0]);
        return 2;
    }
    framebuffer fb = { 640, 480, NULL };
    if (argc > 2 && sscanf(argv[2], "%dx%d", &fb.width, &fb.height) != 2) {
        fprintf(stderr, "%s: the size must be WxH, e.g. 640x480\n", argv[0]);
        return 2;
    }
    const char *ppm = argc > 3 ? argv[3] : NULL;
    const char *data = argc > 4 ? argv[4] : NULL;

    ew_error err;
    ew_assets *a = strcmp(argv[1], "builtin") == 0 ? ew_assets_create_builtin(&err)
                                                   : ew_assets_create(argv[1], data, &err);
    if (!a) {
        fprintf(stderr, "%s\n", err.msg);
        return 1;
    }
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){
        .world = a->world, .palette = a->palette, .colormap = a->colormap,
        .width = fb.width, .height = fb.height }, &err);
    fb.pixels = malloc((size_t)fb.width * (size_t)fb.height * sizeof(uint32_t));
    int status = 1;
    if (!r) {
        fprintf(stderr, "%s\n", err.msg);
    } else if (!fb.pixels) {
        fprintf(stderr, "%s: out of memory\n", argv[0]);
    } else {
        ew_camera views[EW_MAX_VIEWS];
        ew_camera cam = { {0, 0, 0}, {0, 0, 0}, 90, 0 };
        if (ew_benchmark_views(a->world, views) > 0)
            cam = views[0];
        if (ew_render(r, &cam, NULL) != 0) {
            fprintf(stderr, "%s: render failed\n", argv[0]);
        } else {
            copy_frame(r, &fb);
            printf("%dx%d fnv1a64 %016" PRIx64 "\n", fb.width, fb.height, checksum_rgb(&fb));
            if (ppm && write_ppm(ppm, &fb) != 0)
                fprintf(stderr, "%s: cannot write %s\n", argv[0], ppm);
            else
                status = 0;
        }
    }
    free(fb.pixels);
    ew_renderer_destroy(r);
    ew_assets_destroy(a);
    return status;
}
