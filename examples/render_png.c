/*
 * render_png: load a map, render the first camera of its view set and write
 * the frame as a PNG.
 *
 *   cc render_png.c -o render_png $(pkg-config --cflags --libs edgewise)
 *   ./render_png builtin out.png                  (the built-in map: no game data)
 *   ./render_png e1m1 e1m1.png 1280x720 ../shared/data/librequake
 */
#include <edgewise.h>

#include <stdio.h>
#include <string.h>

int main(int argc, char **argv)
{
    if (argc < 3 || argc > 5) {
        fprintf(stderr, "usage: %s MAP|builtin OUT.png [WxH] [DATA_DIR]\n", argv[0]);
        return 2;
    }
    const char *map = argv[1], *out = argv[2];
    const char *data = argc > 4 ? argv[4] : NULL;
    int width = 640, height = 480;
    if (argc > 3 && sscanf(argv[3], "%dx%d", &width, &height) != 2) {
        fprintf(stderr, "%s: the size must be WxH, e.g. 640x480\n", argv[0]);
        return 2;
    }

    /* "builtin": the scene the library generates itself; anything else is a
     * .bsp path or a map name in the game directory DATA_DIR. */
    ew_error err;
    ew_assets *a = strcmp(map, "builtin") == 0 ? ew_assets_create_builtin(&err)
                                               : ew_assets_create(map, data, &err);
    if (!a) {
        fprintf(stderr, "%s\n", err.msg);
        return 1;
    }
    /* Every field left 0 takes its default (8-bit colour, one thread a core). */
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){
        .world = a->world, .palette = a->palette, .colormap = a->colormap,
        .width = width, .height = height }, &err);
    if (!r) {
        fprintf(stderr, "%s\n", err.msg);
        ew_assets_destroy(a);
        return 1;
    }

    ew_camera views[EW_MAX_VIEWS];
    ew_camera cam = { {0, 0, 0}, {0, 0, 0}, 90, 0 };
    if (ew_benchmark_views(a->world, views) > 0)
        cam = views[0];

    int status = 1;
    if (ew_render(r, &cam, NULL) != 0)
        fprintf(stderr, "%s: render failed\n", argv[0]);
    else if (ew_write_frame_png(r, out, &err) != 0)
        fprintf(stderr, "%s\n", err.msg);
    else {
        printf("%s: %dx%d, edgewise %s\n", out, ew_frame_width(r), ew_frame_height(r), ew_version());
        status = 0;
    }
    ew_renderer_destroy(r);
    ew_assets_destroy(a);
    return status;
}
