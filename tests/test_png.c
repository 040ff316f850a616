/* PNG output and input: round trips, every input format, clean errors. */
#define _POSIX_C_SOURCE 200809L
#include "edgewise_lab.h"
#include "util.h"

#include <png.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char tmpdir[256];

static const char *tmp_path(const char *name) {
    static char buf[4][512];
    static int next;
    char *out = buf[next++ & 3];
    snprintf(out, 512, "%s/%s", tmpdir, name);
    return out;
}

/* A palette whose entries are all distinct, so a wrong index shows. */
static void make_palette(uint8_t pal[768]) {
    for (int i = 0; i < 256; i++) {
        pal[3 * i + 0] = (uint8_t)i;
        pal[3 * i + 1] = (uint8_t)(255 - i);
        pal[3 * i + 2] = (uint8_t)(i * 7 + 3);
    }
}

static void test_round_trip(int w, int h) {
    uint8_t pal[768];
    make_palette(pal);
    uint8_t *px = malloc((size_t)w * h);
    for (int i = 0; i < w * h; i++)
        px[i] = (uint8_t)(i * 31 + i / w);
    ew_error err = { "" };
    const char *path = tmp_path("round.png");
    CHECK(ew_write_png(path, px, w, h, pal, &err) == 0, "%dx%d: %s", w, h, err.msg);

    uint8_t *rgb = NULL;
    int rw = 0, rh = 0;
    CHECK(ew_read_png_rgb(path, &rgb, &rw, &rh, &err) == 0, "%s", err.msg);
    CHECK(rw == w && rh == h, "size %dx%d, want %dx%d", rw, rh, w, h);
    if (rgb && rw == w && rh == h) {
        int bad = 0;
        for (int i = 0; i < w * h; i++)
            bad += memcmp(rgb + 3 * i, pal + 3 * px[i], 3) != 0;
        CHECK(bad == 0, "%dx%d: %d pixels differ", w, h, bad);
    }
    free(rgb);
    free(px);
    remove(path);
}

/* Writes a PNG of any format with libpng directly, to test the reader. */
static int write_raw_png(const char *path, int w, int h, int depth, int type,
                         const uint8_t *data, size_t rowbytes, const png_color *plte,
                         int nplte, const uint8_t *trns, int ntrns,
                         const png_color_16 *trns_color, int interlace) {
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        fclose(f);
        return -1;
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, depth, type,
                 interlace ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (plte)
        png_set_PLTE(png, info, plte, nplte);
    if (trns || trns_color)
        png_set_tRNS(png, info, trns, ntrns, trns_color);
    png_write_info(png, info);
    int passes = interlace ? png_set_interlace_handling(png) : 1;
    for (int p = 0; p < passes; p++)
        for (int y = 0; y < h; y++)
            png_write_row(png, data + (size_t)y * rowbytes);
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    fclose(f);
    return 0;
}

static void expect_rgb(const char *what, const char *path, int w, int h,
                       const uint8_t *want) {
    uint8_t *rgb = NULL;
    int rw = 0, rh = 0;
    ew_error err = { "" };
    int rc = ew_read_png_rgb(path, &rgb, &rw, &rh, &err);
    CHECK(rc == 0, "%s: %s", what, err.msg);
    CHECK(rw == w && rh == h, "%s: size %dx%d", what, rw, rh);
    if (rc == 0 && rw == w && rh == h) {
        int bad = 0;
        for (int i = 0; i < w * h * 3; i++)
            bad += rgb[i] != want[i];
        CHECK(bad == 0, "%s: %d bytes differ", what, bad);
    }
    free(rgb);
    remove(path);
}

static void test_formats(void) {
    enum { W = 5, H = 3 };
    uint8_t want[W * H * 3];
    const char *path = tmp_path("fmt.png");

    /* 8-bit gray -> RGB */
    uint8_t gray[W * H];
    for (int i = 0; i < W * H; i++) {
        gray[i] = (uint8_t)(i * 17);
        memset(want + 3 * i, gray[i], 3);
    }
    write_raw_png(path, W, H, 8, PNG_COLOR_TYPE_GRAY, gray, W, NULL, 0, NULL, 0, NULL, 0);
    expect_rgb("gray8", path, W, H, want);

    /* 8-bit gray with a tRNS colour: transparency is ignored */
    png_color_16 key = { 0, 0, 0, 0, 17 };
    write_raw_png(path, W, H, 8, PNG_COLOR_TYPE_GRAY, gray, W, NULL, 0, NULL, 0, &key, 0);
    expect_rgb("gray8+tRNS", path, W, H, want);

    /* 1-bit gray: 0 -> black, 1 -> white */
    uint8_t bits[H];
    for (int y = 0; y < H; y++) {
        bits[y] = (uint8_t)(0xA0 >> y);   /* 10100, 01010, 00101 */
        for (int x = 0; x < W; x++)
            memset(want + 3 * (y * W + x), (bits[y] >> (7 - x)) & 1 ? 255 : 0, 3);
    }
    write_raw_png(path, W, H, 1, PNG_COLOR_TYPE_GRAY, bits, 1, NULL, 0, NULL, 0, NULL, 0);
    expect_rgb("gray1", path, W, H, want);

    /* 16-bit gray+alpha: scaled to 8 bits, alpha dropped */
    uint8_t ga16[W * H * 4];
    for (int i = 0; i < W * H; i++) {
        uint16_t v = (uint16_t)(i * 4369);   /* 0, 0x1111, ... */
        ga16[4 * i + 0] = (uint8_t)(v >> 8);
        ga16[4 * i + 1] = (uint8_t)v;
        ga16[4 * i + 2] = 0x12;
        ga16[4 * i + 3] = 0x34;
        memset(want + 3 * i, v >> 8, 3);
    }
    write_raw_png(path, W, H, 16, PNG_COLOR_TYPE_GRAY_ALPHA, ga16, W * 4, NULL, 0, NULL, 0, NULL,
                  0);
    expect_rgb("gray16+alpha", path, W, H, want);

    /* RGBA 8-bit, interlaced */
    uint8_t rgba[W * H * 4];
    for (int i = 0; i < W * H; i++) {
        for (int c = 0; c < 3; c++)
            rgba[4 * i + c] = want[3 * i + c] = (uint8_t)(i * 13 + c * 80);
        rgba[4 * i + 3] = (uint8_t)(i * 9);
    }
    write_raw_png(path, W, H, 8, PNG_COLOR_TYPE_RGB_ALPHA, rgba, W * 4, NULL, 0, NULL, 0, NULL, 1);
    expect_rgb("rgba8 interlaced", path, W, H, want);

    /* RGB 16-bit */
    uint8_t rgb16[W * H * 6];
    for (int i = 0; i < W * H * 3; i++) {
        want[i] = (uint8_t)(i * 11);
        rgb16[2 * i] = want[i];
        rgb16[2 * i + 1] = want[i];   /* v * 257: scales back to exactly v */
    }
    write_raw_png(path, W, H, 16, PNG_COLOR_TYPE_RGB, rgb16, W * 6, NULL, 0, NULL, 0, NULL, 0);
    expect_rgb("rgb16", path, W, H, want);

    /* 4-bit palette with tRNS: expanded through the palette, alpha ignored */
    png_color plte[16];
    uint8_t trns[16];
    for (int i = 0; i < 16; i++) {
        plte[i].red = (uint8_t)(i * 16);
        plte[i].green = (uint8_t)(200 - i);
        plte[i].blue = (uint8_t)(i * 3);
        trns[i] = (uint8_t)(i * 10);
    }
    uint8_t pal4[H * 3];   /* 5 pixels -> 3 bytes per row */
    for (int y = 0; y < H; y++) {
        for (int x = 0; x < W; x++) {
            int idx = (x * 3 + y * 5) & 15;
            if (x % 2 == 0)
                pal4[y * 3 + x / 2] = (uint8_t)(idx << 4);
            else
                pal4[y * 3 + x / 2] |= (uint8_t)idx;
            uint8_t *o = want + 3 * (y * W + x);
            o[0] = plte[idx].red;
            o[1] = plte[idx].green;
            o[2] = plte[idx].blue;
        }
    }
    write_raw_png(path, W, H, 4, PNG_COLOR_TYPE_PALETTE, pal4, 3, plte, 16, trns, 16, NULL, 0);
    expect_rgb("palette4+tRNS", path, W, H, want);
}

static int has(const char *msg, const char *part) { return strstr(msg, part) != NULL; }

static void test_errors(void) {
    uint8_t pal[768];
    make_palette(pal);
    uint8_t px[320 * 4] = { 0 };
    ew_error err = { "" };

    const char *bad_dir = "/nonexistent-edgewise-dir/out.png";
    CHECK(ew_write_png(bad_dir, px, 320, 4, pal, &err) < 0, "wrote into a missing directory");
    CHECK(has(err.msg, bad_dir) && has(err.msg, "cannot write") &&
              has(err.msg, "No such file or directory"), "msg: %s", err.msg);

    const char *p = tmp_path("bad.png");
    CHECK(ew_write_png(p, px, 0, 4, pal, &err) < 0 && has(err.msg, p), "width 0: %s", err.msg);
    CHECK(ew_write_png(p, px, 4, -1, pal, &err) < 0 && has(err.msg, "size"), "height -1");
    CHECK(ew_write_png(p, px, 100000, 1, pal, &err) < 0, "width 100000");
    CHECK(ew_write_png(p, NULL, 4, 4, pal, &err) < 0, "NULL pixels");
    CHECK(ew_write_png(p, px, 4, 4, NULL, &err) < 0, "NULL palette");
    CHECK(ew_write_png(NULL, px, 4, 4, pal, &err) < 0, "NULL path");
    CHECK(access(p, F_OK) != 0, "a failed write left %s behind", p);
    CHECK(ew_write_png(tmpdir, px, 4, 4, pal, &err) < 0 && has(err.msg, "cannot write"),
          "directory as file: %s", err.msg);

    /* A full disk, and a failed write to a device must leave the device. */
    struct stat st;
    if (stat("/dev/full", &st) == 0 && S_ISCHR(st.st_mode) && access("/dev/full", W_OK) == 0) {
        CHECK(ew_write_png("/dev/full", px, 320, 4, pal, &err) < 0 &&
                  has(err.msg, "/dev/full: cannot write: No space left on device"),
              "full disk: %s", err.msg);
        CHECK(stat("/dev/full", &st) == 0 && S_ISCHR(st.st_mode), "/dev/full was removed");
    }

    uint8_t *rgb = (uint8_t *)&err;   /* must be reset to NULL on failure */
    int w, h;
    const char *missing = tmp_path("missing.png");
    CHECK(ew_read_png_rgb(missing, &rgb, &w, &h, &err) < 0 && has(err.msg, missing) &&
              has(err.msg, "cannot read"), "missing: %s", err.msg);
    CHECK(rgb == NULL, "rgb not reset");

    /* Not a PNG at all; an empty file; a PNG cut short at every length. */
    const char *junk = tmp_path("junk.png");
    FILE *f = fopen(junk, "wb");
    fputs("this is not a PNG file, just text\n", f);
    fclose(f);
    CHECK(ew_read_png_rgb(junk, &rgb, &w, &h, &err) < 0 && has(err.msg, junk) &&
              has(err.msg, "not a PNG"), "junk: %s", err.msg);
    f = fopen(junk, "wb");
    fclose(f);
    CHECK(ew_read_png_rgb(junk, &rgb, &w, &h, &err) < 0 && has(err.msg, "not a PNG"),
          "empty: %s", err.msg);

    const char *whole = tmp_path("whole.png");
    uint8_t frame[320 * 200];
    for (int i = 0; i < 320 * 200; i++)
        frame[i] = (uint8_t)(i * 7 ^ i >> 5);
    CHECK(ew_write_png(whole, frame, 320, 200, pal, &err) == 0, "%s", err.msg);
    uint8_t *bytes = NULL;
    size_t size = 0;
    f = fopen(whole, "rb");
    if (f) {
        fseek(f, 0, SEEK_END);
        size = (size_t)ftell(f);
        fseek(f, 0, SEEK_SET);
        bytes = malloc(size);
        if (fread(bytes, 1, size, f) != size)
            size = 0;
        fclose(f);
    }
    CHECK(size > 100, "reading back %s", whole);
    int failures = 0, cases = 0;
    for (size_t cut = 1; cut < size; cut += cut < 64 ? 1 : 97) {
        f = fopen(junk, "wb");
        fwrite(bytes, 1, cut, f);
        fclose(f);
        rgb = NULL;
        err.msg[0] = '\0';
        int rc = ew_read_png_rgb(junk, &rgb, &w, &h, &err);
        cases++;
        failures += rc < 0 && rgb == NULL && has(err.msg, junk);
        free(rgb);
    }
    CHECK(failures == cases, "truncated PNGs: %d of %d failed cleanly", failures, cases);

    /* A flipped byte in the image data: the CRC catches it. */
    if (size > 200) {
        bytes[size / 2] ^= 0x55;
        f = fopen(junk, "wb");
        fwrite(bytes, 1, size, f);
        fclose(f);
        rgb = NULL;
        CHECK(ew_read_png_rgb(junk, &rgb, &w, &h, &err) < 0 && has(err.msg, "bad PNG"),
              "corrupt: %s", err.msg);
        free(rgb);
    }
    free(bytes);
    remove(junk);
    remove(whole);
}

int main(void) {
    const char *t = getenv("TMPDIR");
    snprintf(tmpdir, sizeof tmpdir, "%s/ew_png_XXXXXX", t && *t ? t : "/tmp");
    if (!mkdtemp(tmpdir)) {
        perror("mkdtemp");
        return 1;
    }
    test_round_trip(320, 200);
    test_round_trip(641, 3);
    test_round_trip(1, 1);
    test_formats();
    test_errors();
    rmdir(tmpdir);
    return ew_t_finish();
}
