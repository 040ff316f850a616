/*
 * install_check: a helper of tests/install_test.sh, built like the examples
 * against the installed library (edgewise_lab.h's PNG reader):
 *
 *   install_check size FILE.png    prints "W H"
 *   install_check sum FILE         prints "WxH fnv1a64 HEX" of a PNG or a P6 PPM,
 *                                  the line examples/render_buffer prints
 */
#include <edgewise.h>
#include <edgewise_lab.h>

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A binary P6 PPM with maxval 255, to malloc'd RGB8; 0 or -1. */
static int read_ppm(const char *path, uint8_t **rgb, int *w, int *h)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return -1;
    int maxval = 0, ok = fscanf(f, "P6 %d %d %d", w, h, &maxval) == 3 && maxval == 255 &&
                         *w > 0 && *h > 0 && *w <= 65536 && *h <= 65536 && fgetc(f) == '\n';
    size_t n = ok ? (size_t)*w * (size_t)*h * 3 : 0;
    *rgb = ok ? malloc(n) : NULL;
    ok = *rgb && fread(*rgb, 1, n, f) == n;
    fclose(f);
    if (!ok) {
        free(*rgb);
        *rgb = NULL;
    }
    return ok ? 0 : -1;
}

int main(int argc, char **argv)
{
    if (argc != 3 || (strcmp(argv[1], "size") && strcmp(argv[1], "sum"))) {
        fprintf(stderr, "usage: install_check size|sum FILE\n");
        return 2;
    }
    const char *path = argv[2];
    size_t len = strlen(path);
    int is_ppm = len > 4 && strcmp(path + len - 4, ".ppm") == 0;
    uint8_t *rgb = NULL;
    int w = 0, h = 0;
    ew_error err;
    if (is_ppm ? read_ppm(path, &rgb, &w, &h) : ew_read_png_rgb(path, &rgb, &w, &h, &err)) {
        fprintf(stderr, "install_check: %s\n", is_ppm ? "cannot read the PPM" : err.msg);
        return 1;
    }
    if (strcmp(argv[1], "size") == 0) {
        printf("%d %d\n", w, h);
    } else {
        uint64_t sum = 14695981039346656037u;
        for (size_t i = 0; i < (size_t)w * (size_t)h * 3; i++) {
            sum ^= rgb[i];
            sum *= 1099511628211u;
        }
        printf("%dx%d fnv1a64 %016" PRIx64 "\n", w, h, sum);
    }
    free(rgb);
    return 0;
}
