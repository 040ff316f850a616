/* PNG output (8-bit frames as indexed PNGs, true-colour frames as RGB) and
 * input (any PNG to RGB8). */
#define _POSIX_C_SOURCE 200809L
#include "ew_util.h"

#include <errno.h>
#include <png.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* Bigger than any frame (7680x4320) or reference image; keeps w*h*3 far
 * from overflowing and refuses absurd headers before allocating. */
#define EW_PNG_MAX_SIDE 32768

/* libpng reports errors through a callback that must not return: keep the
 * message, then unwind to the setjmp in the caller. */
typedef struct png_ctx {
    char msg[256];
} png_ctx;

static void on_error(png_structp png, png_const_charp msg) {
    png_ctx *ctx = png_get_error_ptr(png);
    if (ctx)
        snprintf(ctx->msg, sizeof ctx->msg, "%s", msg ? msg : "unknown error");
    png_longjmp(png, 1);
}

/* Warnings (odd chunks, bad gamma) are not worth a line on stderr. */
static void on_warning(png_structp png, png_const_charp msg) {
    (void)png;
    (void)msg;
}

/* One writer for both: palette != NULL writes pixels8 as an indexed PNG,
 * else pixels32 (R, G, B, A bytes) as RGB. */
static int write_png(const char *path, const uint8_t *pixels8, const uint32_t *pixels32, int width, int height,
                     const uint8_t *palette, ew_error *err) {
    if (!path || !*path)
        return ew_fail(err, "(png): no output path");
    if (palette ? !pixels8 : !pixels32)
        return ew_fail(err, "%s: cannot write: no pixels or palette", path);
    if (width <= 0 || height <= 0 || width > EW_PNG_MAX_SIDE || height > EW_PNG_MAX_SIDE)
        return ew_fail(err, "%s: cannot write: bad image size %dx%d", path, width, height);

    FILE *f = fopen(path, "wb");
    if (!f)
        return ew_fail(err, "%s: cannot write: %s", path, strerror(errno));
    /* A half-written PNG is removed on failure, but only a regular file:
     * never a device or pipe the caller named (/dev/stdout, /dev/full). */
    struct stat st;
    const int regular = fstat(fileno(f), &st) == 0 && S_ISREG(st.st_mode);

    png_ctx ctx = { "" };
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &ctx, on_error, on_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    /* Changed after setjmp and needed after a longjmp: volatile. */
    uint8_t *volatile row = NULL;

    if (!png || !info) {
        png_destroy_write_struct(png ? &png : NULL, NULL);
        fclose(f);
        if (regular)
            remove(path);
        return ew_fail(err, "%s: cannot write: out of memory", path);
    }
    if (setjmp(png_jmpbuf(png))) {
        int e = errno, io = ferror(f);
        png_destroy_write_struct(&png, &info);
        free(row);
        fclose(f);
        if (regular)
            remove(path);
        /* libpng's own "Write Error" says less than the OS does. */
        if (io || strcmp(ctx.msg, "Write Error") == 0)
            return ew_fail(err, "%s: cannot write: %s", path, strerror(e ? e : EIO));
        return ew_fail(err, "%s: cannot write: %s", path, ctx.msg);
    }

    row = malloc((size_t)width * 3);
    if (!row)
        png_error(png, "out of memory");
    png_init_io(png, f);
    png_set_IHDR(png, info, (png_uint_32)width, (png_uint_32)height, 8,
                 palette ? PNG_COLOR_TYPE_PALETTE : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    /* Speed over size: frames are written in milliseconds of rendering, and
     * zlib's default effort took four times the render at 1920x1080.  An
     * indexed picture is compressed unfiltered (filters rarely help
     * palette indices), at zlib level 2. */
    png_set_compression_level(png, 2);
    if (palette) png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE);
    if (palette) {
        png_color pal[256];
        for (int i = 0; i < 256; i++)
            pal[i].red = palette[i * 3], pal[i].green = palette[i * 3 + 1], pal[i].blue = palette[i * 3 + 2];
        png_set_PLTE(png, info, pal, 256);
    }
    png_write_info(png, info);
    for (int y = 0; y < height; y++) {
        if (palette) {  /* indexed: the frame's own bytes, a third of RGB's */
            png_write_row(png, (png_const_bytep)(pixels8 + (size_t)y * (size_t)width));
            continue;
        }
        const uint32_t *src = pixels32 + (size_t)y * (size_t)width;
        uint8_t *dst = row;
        for (int x = 0; x < width; x++, dst += 3)
            memcpy(dst, &src[x], 3);  /* R, G, B bytes first in memory */
        png_write_row(png, row);
    }
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    free(row);

    /* Buffered data may only fail to reach the disk now (e.g. disk full). */
    errno = 0;
    int bad = ferror(f);
    if (fclose(f) != 0 || bad) {
        int e = errno ? errno : EIO;
        if (regular)
            remove(path);
        return ew_fail(err, "%s: cannot write: %s", path, strerror(e));
    }
    return 0;
}

int ew_write_png(const char *path, const uint8_t *pixels, int width, int height, const uint8_t palette[768],
                 ew_error *err) {
    if (!palette) return ew_fail(err, "%s: cannot write: no pixels or palette", path && *path ? path : "(png)");
    return write_png(path, pixels, NULL, width, height, palette, err);
}

int ew_write_png_rgba(const char *path, const uint32_t *pixels, int width, int height, ew_error *err) {
    return write_png(path, NULL, pixels, width, height, NULL, err);
}

int ew_read_png_rgb(const char *path, uint8_t **rgb, int *width, int *height, ew_error *err) {
    if (rgb)
        *rgb = NULL;
    if (!path || !*path)
        return ew_fail(err, "(png): no input path");
    if (!rgb || !width || !height)
        return ew_fail(err, "%s: cannot read: no output given", path);

    FILE *f = fopen(path, "rb");
    if (!f)
        return ew_fail(err, "%s: cannot read: %s", path, strerror(errno));

    uint8_t sig[8];
    size_t got = fread(sig, 1, sizeof sig, f);
    if (got != sizeof sig || png_sig_cmp(sig, 0, sizeof sig) != 0) {
        int e = ferror(f) ? errno : 0;
        fclose(f);
        if (e)
            return ew_fail(err, "%s: cannot read: %s", path, strerror(e));
        return ew_fail(err, "%s: not a PNG file", path);
    }

    png_ctx ctx = { "" };
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &ctx, on_error, on_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    uint8_t *volatile out = NULL;
    png_bytep *volatile rows = NULL;

    if (!png || !info) {
        png_destroy_read_struct(png ? &png : NULL, NULL, NULL);
        fclose(f);
        return ew_fail(err, "%s: cannot read: out of memory", path);
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, NULL);
        free(out);
        free(rows);
        fclose(f);
        /* A short file surfaces as libpng's "Read Error". */
        if (strcmp(ctx.msg, "Read Error") == 0)
            return ew_fail(err, "%s: bad PNG: truncated file", path);
        return ew_fail(err, "%s: bad PNG: %s", path, ctx.msg);
    }

    png_init_io(png, f);
    png_set_sig_bytes(png, sizeof sig);
    png_set_user_limits(png, EW_PNG_MAX_SIDE, EW_PNG_MAX_SIDE);
    png_read_info(png, info);

    png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
    int type = png_get_color_type(png, info);
    int depth = png_get_bit_depth(png, info);

    /* Normalise every format to 8-bit RGB: palette and low-depth gray are
     * expanded, 16-bit scaled down, alpha (and tRNS) dropped, gray copied to
     * three channels. */
    if (type == PNG_COLOR_TYPE_PALETTE || depth < 8)
        png_set_expand(png);
    if (depth == 16)
        png_set_scale_16(png);
    if ((type & PNG_COLOR_MASK_ALPHA) || png_get_valid(png, info, PNG_INFO_tRNS))
        png_set_strip_alpha(png);
    if (type == PNG_COLOR_TYPE_GRAY || type == PNG_COLOR_TYPE_GRAY_ALPHA)
        png_set_gray_to_rgb(png);
    png_set_interlace_handling(png);
    png_read_update_info(png, info);

    if (png_get_channels(png, info) != 3 || png_get_bit_depth(png, info) != 8 ||
        png_get_rowbytes(png, info) != (size_t)w * 3)
        png_error(png, "unsupported pixel format");

    out = malloc((size_t)w * h * 3);
    rows = malloc((size_t)h * sizeof *rows);
    if (!out || !rows)
        png_error(png, "out of memory");
    for (png_uint_32 y = 0; y < h; y++)
        rows[y] = out + (size_t)y * w * 3;
    png_read_image(png, rows);
    png_read_end(png, NULL);

    png_destroy_read_struct(&png, &info, NULL);
    free(rows);
    fclose(f);
    *rgb = out;
    *width = (int)w;
    *height = (int)h;
    return 0;
}
