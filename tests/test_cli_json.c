/*
 * Every JSON the command writes is strict JSON in valid UTF-8, even for a
 * map whose file name and texture names hold bytes that are not UTF-8
 * (issue 36): render --stats, the shots manifest (an "error" string quotes
 * a corrupted texture name), bench, hsr --json and soak.  The maps are the
 * built-in level from the project's map writer, copied into a temporary
 * game folder with texture 0 renamed (and, for the failing one, given an
 * odd width).  The checker below is this test's own strict JSON grammar
 * (RFC 8259) and UTF-8 decoder (RFC 3629); it is first shown to refuse
 * what it must.
 */
#define _POSIX_C_SOURCE 200809L
#include "mapgen_util.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static char tmpdir[256];
static ew_t_run *run_r;

/* ---- a strict JSON checker ------------------------------------------------ */

typedef struct jp {
    const unsigned char *p, *end;
    int depth;
} jp;

static void ws(jp *j) {
    while (j->p < j->end && (*j->p == ' ' || *j->p == '\t' || *j->p == '\n' || *j->p == '\r')) j->p++;
}

/* One UTF-8 character decoded; -1 if malformed (overlong, surrogate,
 * beyond U+10FFFF, truncated, a stray continuation byte). */
static long utf8_decode(jp *j) {
    unsigned c = *j->p;
    int extra;
    long cp, min;
    if (c < 0x80) extra = 0, cp = c, min = 0;
    else if ((c & 0xe0) == 0xc0) extra = 1, cp = c & 0x1f, min = 0x80;
    else if ((c & 0xf0) == 0xe0) extra = 2, cp = c & 0x0f, min = 0x800;
    else if ((c & 0xf8) == 0xf0) extra = 3, cp = c & 0x07, min = 0x10000;
    else return -1;
    if (j->end - j->p <= extra) return -1;
    for (int i = 1; i <= extra; i++) {
        if ((j->p[i] & 0xc0) != 0x80) return -1;
        cp = cp << 6 | (j->p[i] & 0x3f);
    }
    if (cp < min || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff)) return -1;
    j->p += 1 + extra;
    return cp;
}

static int hex4(jp *j, long *v) {
    *v = 0;
    for (int i = 0; i < 4; i++, j->p++) {
        if (j->p >= j->end) return -1;
        int c = *j->p, d = c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10
                         : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
        if (d < 0) return -1;
        *v = *v * 16 + d;
    }
    return 0;
}

static int jstring(jp *j) {
    if (j->p >= j->end || *j->p != '"') return -1;
    j->p++;
    while (j->p < j->end && *j->p != '"') {
        if (*j->p < 0x20) return -1;
        if (*j->p == '\\') {
            j->p++;
            if (j->p >= j->end) return -1;
            if (*j->p == 'u') {
                long u, lo;
                j->p++;
                if (hex4(j, &u) < 0) return -1;
                if (u >= 0xdc00 && u <= 0xdfff) return -1;  /* a lone low surrogate */
                if (u >= 0xd800 && u <= 0xdbff) {           /* a pair */
                    if (j->end - j->p < 6 || j->p[0] != '\\' || j->p[1] != 'u') return -1;
                    j->p += 2;
                    if (hex4(j, &lo) < 0 || lo < 0xdc00 || lo > 0xdfff) return -1;
                }
            } else if (!strchr("\"\\/bfnrt", *j->p)) {
                return -1;
            } else {
                j->p++;
            }
            continue;
        }
        if (utf8_decode(j) < 0) return -1;
    }
    if (j->p >= j->end) return -1;
    j->p++;
    return 0;
}

static int digits(jp *j) {
    const unsigned char *s = j->p;
    while (j->p < j->end && *j->p >= '0' && *j->p <= '9') j->p++;
    return j->p > s ? 0 : -1;
}

static int jnumber(jp *j) {
    if (j->p < j->end && *j->p == '-') j->p++;
    if (j->p < j->end && *j->p == '0') j->p++;
    else if (j->p >= j->end || *j->p < '1' || *j->p > '9' || digits(j) < 0) return -1;
    if (j->p < j->end && *j->p == '.') {
        j->p++;
        if (digits(j) < 0) return -1;
    }
    if (j->p < j->end && (*j->p == 'e' || *j->p == 'E')) {
        j->p++;
        if (j->p < j->end && (*j->p == '+' || *j->p == '-')) j->p++;
        if (digits(j) < 0) return -1;
    }
    return 0;
}

static int jvalue(jp *j) {
    ws(j);
    if (j->p >= j->end || ++j->depth > 64) return -1;
    int rc = 0;
    unsigned c = *j->p;
    if (c == '{' || c == '[') {
        unsigned close = c == '{' ? '}' : ']';
        j->p++;
        ws(j);
        if (j->p < j->end && *j->p == close) {
            j->p++;
        } else {
            for (;;) {
                if (c == '{') {
                    ws(j);
                    if (jstring(j) < 0) return -1;
                    ws(j);
                    if (j->p >= j->end || *j->p != ':') return -1;
                    j->p++;
                }
                if (jvalue(j) < 0) return -1;
                ws(j);
                if (j->p < j->end && *j->p == ',') {
                    j->p++;
                    continue;
                }
                if (j->p < j->end && *j->p == close) {
                    j->p++;
                    break;
                }
                return -1;
            }
        }
    } else if (c == '"') {
        rc = jstring(j);
    } else if (c == '-' || (c >= '0' && c <= '9')) {
        rc = jnumber(j);
    } else {
        const char *lits[] = {"true", "false", "null"};
        rc = -1;
        for (int i = 0; i < 3 && rc; i++) {
            size_t n = strlen(lits[i]);
            if ((size_t)(j->end - j->p) >= n && !memcmp(j->p, lits[i], n)) j->p += n, rc = 0;
        }
    }
    j->depth--;
    return rc;
}

/* One JSON text, nothing but white space around it. */
static int json_ok(const char *s, size_t n) {
    jp j = {(const unsigned char *)s, (const unsigned char *)s + n, 0};
    if (jvalue(&j) < 0) return 0;
    ws(&j);
    return j.p == j.end;
}

/* Every line of s (JSON lines) strict JSON; the count in *lines. */
static int json_lines_ok(const char *s, int *lines) {
    *lines = 0;
    while (*s) {
        const char *nl = strchr(s, '\n');
        size_t n = nl ? (size_t)(nl - s) : strlen(s);
        if (!json_ok(s, n)) {
            fprintf(stderr, "not strict JSON in UTF-8: %.*s\n", (int)n, s);
            return 0;
        }
        ++*lines;
        s += n + (nl != NULL);
    }
    return 1;
}

static void checker_refuses(void) {
    const char *good[] = {"{\"a\":[1,-0.5,2e10,true,false,null],\"b\":\"caf\xc3\xa9 \\u00e9 \\ud83d\\ude00\"}",
                          "\"\xf0\x9f\x98\x80\"", "[]", "{}"};
    const char *bad[] = {"\"caf\xe9\"",          /* Latin-1 byte */
                         "\"\xc0\xaf\"",         /* overlong '/' */
                         "\"\xed\xa0\x80\"",     /* a surrogate in UTF-8 */
                         "\"\xf4\x90\x80\x80\"", /* beyond U+10FFFF */
                         "\"\xc3\"",             /* truncated */
                         "\"\x80\"",             /* a stray continuation byte */
                         "\"a\x01\"", "\"\\x41\"", "\"\\udc00\"", "[1,]", "01", "1.", "nan", "{\"a\" 1}",
                         "{\"a\":1}x", "\"open"};
    for (size_t i = 0; i < sizeof good / sizeof *good; i++)
        CHECK(json_ok(good[i], strlen(good[i])), "the checker refuses valid JSON %zu: %s", i, good[i]);
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++)
        CHECK(!json_ok(bad[i], strlen(bad[i])), "the checker accepts invalid JSON %zu", i);
}

/* ---- the maps ---------------------------------------------------------------- */

static int write_file(const char *path, const void *data, size_t n) {
    FILE *f = fopen(path, "wb");
    if (!f) return -1;
    size_t w = fwrite(data, 1, n, f);
    return fclose(f) == 0 && w == n ? 0 : -1;
}

static uint32_t le32(const uint8_t *p) { return p[0] | p[1] << 8 | p[2] << 16 | (uint32_t)p[3] << 24; }

/* Texture 0's miptex header in a BSP29 image (lump 2: textures), or NULL. */
static uint8_t *miptex0(uint8_t *bsp, size_t size) {
    if (size < 4 + 15 * 8) return NULL;
    uint32_t ofs = le32(bsp + 4 + 2 * 8), len = le32(bsp + 4 + 2 * 8 + 4);
    if (ofs + 8 > size || len < 8 || le32(bsp + ofs) < 1) return NULL;
    uint32_t m = le32(bsp + ofs + 4);
    if (m + 40 > len || ofs + m + 40 > size) return NULL;
    return bsp + ofs + m;
}

/* A UTF-8 "é", then a Latin-1 "é", 0xff and a lone continuation byte. */
static const char tex_name[16] = "\xc3\xa9t\xe9\xff\x80x";
/* The same as the manifest must spell it. */
static const char tex_json[] = "\xc3\xa9t\\u00e9\\u00ff\\u0080x";

/* tmpdir/g: gfx/palette.lmp, gfx/colormap.lmp, maps/<good>.bsp with the
 * odd texture name, maps/<bad>.bsp with it and an odd width too. */
static int make_maps(const char *good, const char *bad) {
    uint8_t pal[768], cmap[EW_COLORMAP_SIZE], *bsp = NULL;
    size_t size = 0;
    ew_error err = {""};
    char p[600];
    if (ew_builtin_generate(&bsp, &size, pal, cmap, &err) != 0) {
        CHECK(0, "generate: %s", err.msg);
        return -1;
    }
    int ok = 1;
    const char *dirs[] = {"g", "g/gfx", "g/maps"};
    for (int i = 0; i < 3; i++) {
        snprintf(p, sizeof p, "%s/%s", tmpdir, dirs[i]);
        ok &= mkdir(p, 0755) == 0;
    }
    snprintf(p, sizeof p, "%s/g/gfx/palette.lmp", tmpdir);
    ok &= write_file(p, pal, sizeof pal) == 0;
    snprintf(p, sizeof p, "%s/g/gfx/colormap.lmp", tmpdir);
    ok &= write_file(p, cmap, sizeof cmap) == 0;
    uint8_t *m = miptex0(bsp, size);
    CHECK(m != NULL, "the built-in map has a texture 0");
    if (m) {
        memcpy(m, tex_name, 16);
        snprintf(p, sizeof p, "%s/g/maps/%s.bsp", tmpdir, good);
        ok &= write_file(p, bsp, size) == 0;
        m[16] = 7;  /* width 7: the loader refuses it, quoting the name */
        snprintf(p, sizeof p, "%s/g/maps/%s.bsp", tmpdir, bad);
        ok &= write_file(p, bsp, size) == 0;
    }
    free(bsp);
    CHECK(ok && m, "the maps in %s/g", tmpdir);
    return ok && m ? 0 : -1;
}

static void run(const char *const *args) { ew_t_run_cli(run_r, tmpdir, args); }

int main(void) {
    run_r = malloc(sizeof *run_r);
    snprintf(tmpdir, sizeof tmpdir, "/tmp/ew_json_XXXXXX");
    if (!getenv("EW_CLI") || !run_r || !mkdtemp(tmpdir)) {
        fprintf(stderr, "no EW_CLI or no temporary directory\n");
        return 1;
    }
    checker_refuses();

    /* "caf" + UTF-8 é + Latin-1 é; "bad" + 0xff */
    const char *good = "caf\xc3\xa9\xe9", *bad = "bad\xff";
    const char *good_json = "\"caf\xc3\xa9\\u00e9\"", *bad_json = "\"bad\\u00ff\"";
    if (make_maps(good, bad) == 0) {
        char gmap[300], bmap[300];
        snprintf(gmap, sizeof gmap, "g/maps/%s.bsp", good);
        snprintf(bmap, sizeof bmap, "g/maps/%s.bsp", bad);
        int lines;

        /* render --stats: the map's name and the output's, both with those bytes */
        char out[300];
        snprintf(out, sizeof out, "%s.png", good);
        run((const char *const[]){"render", gmap, "--size", "320x200", "--stats", "--out", out, NULL});
        CHECK(run_r->status == 0, "render --stats: exit %d: %s", run_r->status, run_r->err);
        CHECK(json_lines_ok(run_r->out, &lines) && lines == 1, "render --stats: one strict JSON line: %s",
              run_r->out);
        CHECK(strstr(run_r->out, good_json) != NULL, "render --stats: the map's name as %s: %.120s", good_json,
              run_r->out);

        /* shots: one map drawn, one refused with the texture's name in "error" */
        run((const char *const[]){"shots", gmap, bmap, "--out", "shots", "--size", "320x200", NULL});
        CHECK(run_r->status == 1, "shots: exit %d (one map fails): %s", run_r->status, run_r->err);
        char man[400], text[65536];
        snprintf(man, sizeof man, "%s/shots/manifest.jsonl", tmpdir);
        ew_t_slurp(man, text, sizeof text);
        CHECK(json_lines_ok(text, &lines) && lines == 2, "shots: two strict JSON lines, got %d: %s", lines, text);
        CHECK(strstr(text, "\"status\":\"error\"") && strstr(text, tex_json) && strstr(text, bad_json) &&
                  strstr(text, good_json),
              "shots: the error quotes the texture as %s: %s", tex_json, text);

        /* bench, hsr --json -, soak: one line each */
        run((const char *const[]){"bench", gmap, "--size", "320x200", "--passes", "1", NULL});
        CHECK(run_r->status == 0 && json_lines_ok(run_r->out, &lines) && lines == 1 && strstr(run_r->out, good_json),
              "bench: exit %d, one strict JSON line: %s %s", run_r->status, run_r->out, run_r->err);
        run((const char *const[]){"hsr", gmap, "--methods", "edge", "--size", "320x200", "--repeat", "1", "--json",
                                  "-", NULL});
        CHECK(run_r->status == 0 && json_lines_ok(run_r->out, &lines) && lines == 1 && strstr(run_r->out, good_json),
              "hsr --json -: exit %d, one strict JSON line: %s %s", run_r->status, run_r->out, run_r->err);
        run((const char *const[]){"soak", gmap, "--frames", "4", "--size", "320x200", NULL});
        CHECK(run_r->status == 0 && json_lines_ok(run_r->out, &lines) && lines == 1 && strstr(run_r->out, good_json),
              "soak: exit %d, one strict JSON line: %s %s", run_r->status, run_r->out, run_r->err);
    }

    char cmd[600];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmpdir);
    free(run_r);
    return ew_t_finish();
}
