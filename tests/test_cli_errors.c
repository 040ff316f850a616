/*
 * The errors a new user met (issue 12), through the `edgewise` command (path
 * in EW_CLI): each is one "edgewise: ..." line naming the file and the
 * problem, usage errors exit 2 and other failures 1, and each option states
 * one rule in its help and its error.  Scratch game directories are made in
 * a temporary folder from the shared map e1m1 (no models: the missing-model
 * warning; its light lump zeroed: a dark frame; a pak with a corrupt map and
 * corrupt paks).
 */
#define _POSIX_C_SOURCE 200809L
#include "util.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char tmpdir[256];
static const char *data;  /* ../shared/data/librequake, absolute; NULL without it */

#define ARGS(...) ((const char *const[]){ __VA_ARGS__, NULL })

/* Runs the command in tmpdir; r is static (the result is large). */
static ew_t_run *run(const char *const *args) {
    static ew_t_run r;
    ew_t_run_cli(&r, tmpdir, args);
    return &r;
}

/* Exactly one stderr line, "edgewise: " + want, and the exit status. */
static void expect_line_(int line, const char *const *args, int status, const char *want) {
    ew_t_run *r = run(args);
    char full[1024];
    snprintf(full, sizeof full, "edgewise: %s\n", want);
    CHECK(r->signal == 0 && r->status == status, "line %d: exit %d (want %d), stderr: %s", line, r->status,
          status, r->err);
    CHECK(strcmp(r->err, full) == 0, "line %d: stderr\n  %s want\n  %s", line, r->err, full);
}
#define expect_line(args, status, want) expect_line_(__LINE__, args, status, want)

static char *path_in(char out[600], const char *rel) {
    snprintf(out, 600, "%s/%s", tmpdir, rel);
    return out;
}

static int write_file(const char *path, const void *bytes, size_t n) {
    FILE *f = fopen(path, "wb");
    if (!f) return -1;
    size_t w = fwrite(bytes, 1, n, f);
    return fclose(f) == 0 && w == n ? 0 : -1;
}

static uint8_t *read_file(const char *path, size_t *n) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t *b = malloc(len > 0 ? (size_t)len : 1);
    if (b && fread(b, 1, (size_t)len, f) != (size_t)len) {
        free(b);
        b = NULL;
    }
    fclose(f);
    *n = (size_t)len;
    return b;
}

static void copy_from_data(const char *rel, const char *to) {
    char src[600], dst[600];
    snprintf(src, sizeof src, "%s/%s", data, rel);
    size_t n;
    uint8_t *b = read_file(src, &n);
    CHECK(b && write_file(path_in(dst, to), b, n) == 0, "copy %s to %s", src, dst);
    free(b);
}

/* A game directory DIR in tmpdir with the shared palette and colormap. */
static void game_dir(const char *dir) {
    char p[600], rel[300];
    mkdir(path_in(p, dir), 0755);
    snprintf(rel, sizeof rel, "%s/maps", dir);
    mkdir(path_in(p, rel), 0755);
    snprintf(rel, sizeof rel, "%s/gfx", dir);
    mkdir(path_in(p, rel), 0755);
    snprintf(rel, sizeof rel, "%s/gfx/palette.lmp", dir);
    copy_from_data("gfx/palette.lmp", rel);
    snprintf(rel, sizeof rel, "%s/gfx/colormap.lmp", dir);
    copy_from_data("gfx/colormap.lmp", rel);
}

static void put32(uint8_t *p, int32_t v) {
    uint32_t u = (uint32_t)v;
    p[0] = (uint8_t)u, p[1] = (uint8_t)(u >> 8), p[2] = (uint8_t)(u >> 16), p[3] = (uint8_t)(u >> 24);
}

/* A pak of one entry: name, offset and size as given, body bytes after the header. */
static void write_pak(const char *rel, const char *name, int32_t ofs, int32_t len, const uint8_t *body,
                      size_t body_len) {
    size_t dirofs = 12 + body_len, size = dirofs + 64;
    uint8_t *b = calloc(1, size);
    memcpy(b, "PACK", 4);
    put32(b + 4, (int32_t)dirofs);
    put32(b + 8, 64);
    memcpy(b + 12, body, body_len);
    memcpy(b + dirofs, name, strlen(name));
    put32(b + dirofs + 56, ofs);
    put32(b + dirofs + 60, len);
    char p[600];
    CHECK(write_file(path_in(p, rel), b, size) == 0, "write %s", rel);
    free(b);
}

/* Rules that the old messages contradicted, and usage errors found late. */
static void rules(void) {
    /* --dlight: one line, and the rule says what is allowed. */
    expect_line(ARGS("render", "builtin", "--dlight", "1,2,3"), 2,
                "--dlight 1,2,3: X,Y,Z,R[,r,g,b] must be a position, a radius above 0, at most 100000, "
                "and optionally a colour of three numbers from 0 to 1");
    expect_line(ARGS("render", "builtin", "--dlight", "0,0,0,0"), 2,
                "--dlight 0,0,0,0: X,Y,Z,R[,r,g,b] must be a position, a radius above 0, at most 100000, "
                "and optionally a colour of three numbers from 0 to 1");
    /* --fov: the open interval, as the renderer takes it. */
    expect_line(ARGS("render", "builtin", "--fov", "179"), 2,
                "--fov 179: must be more than 1 and less than 179 degrees");
    expect_line(ARGS("render", "builtin", "--fov", "1"), 2, "--fov 1: must be more than 1 and less than 179 degrees");
    expect_line(ARGS("render", "builtin", "--subdiv-threshold", "0"), 2,
                "--subdiv-threshold 0: PX must be a number of pixels above 0, at most 10000 (default 40)");
    /* --pos: out of range or not finite is the same rule, not a "format" error. */
    expect_line(ARGS("render", "builtin", "--pos", "-inf,3.4e38,1e-45", "--angles", "0,0,0"), 2,
                "--pos -inf,3.4e38,1e-45: must be three numbers from -1000000 to 1000000 separated by "
                "commas, e.g. 128,-64,40");
    expect_line(ARGS("render", "builtin", "--pos", "0,0,2e6", "--angles", "0,0,0"), 2,
                "--pos 0,0,2e6: must be three numbers from -1000000 to 1000000 separated by commas, e.g. 128,-64,40");
    /* --threads: 0 to 64 (EW_MAX_THREADS) in every command. */
    const char *want = "--threads 65: must be 0 (one per core) to 64";
    expect_line(ARGS("render", "builtin", "--threads", "65"), 2, want);
    expect_line(ARGS("demo", "--threads", "65"), 2, want);
    expect_line(ARGS("soak", "builtin", "--frames", "1", "--threads", "65"), 2, want);
    expect_line(ARGS("bench", "builtin", "--threads", "65"), 2, want);
    /* The help states the same rules. */
    ew_t_run *r = run(ARGS("--help"));
    CHECK(strstr(r->out, "--threads N") && strstr(r->out, "0 (one per core) to 64") &&
          strstr(r->out, "more than 1 and less than 179 degrees") &&
          strstr(r->out, "three numbers from -1000000 to 1000000 separated by commas"),
          "help: %s", r->out);
    r = run(ARGS("soak", "--help"));
    CHECK(strstr(r->out, "0 (one per core) to 64") != NULL, "soak help: %s", r->out);
    r = run(ARGS("bench", "--help"));
    CHECK(strstr(r->out, "0 (one per core) to 64") != NULL, "bench help: %s", r->out);
    /* --view past the map's views: a usage error (2) like --view -1, naming the map's stem. */
    expect_line(ARGS("render", "builtin", "--view", "-1"), 2, "--view -1: out of range (views are numbered from 0)");
    expect_line(ARGS("render", "builtin", "--view", "32"), 2, "--view 32: out of range, builtin has 5 views (0 to 4)");
    if (data) {
        char map[600];
        snprintf(map, sizeof map, "%s/maps/e1m1.bsp", data);
        expect_line(ARGS("render", map, "--view", "32"), 2, "--view 32: out of range, e1m1 has 29 views (0 to 28)");
    }
}

/* MAP paths that are not maps name what was given. */
static void not_maps(void) {
    expect_line(ARGS("render", "/tmp"), 1,
                "/tmp: a directory, not a map (a .bsp file, a map name with --data, or 'builtin')");
    expect_line(ARGS("render", "/dev/zero"), 1,
                "/dev/zero: not a regular file (a device or pipe), not a map (a .bsp file, a map name with "
                "--data, or 'builtin')");
    expect_line(ARGS("info", "/no/such/map"), 1,
                "/no/such/map: no such file, and a path is not a map name (a .bsp file, a map name with "
                "--data, or 'builtin')");
    if (data) {
        expect_line(ARGS("render", "/tmp", "--data", data), 1,
                    "/tmp: a directory, not a map (a .bsp file, a map name with --data, or 'builtin')");
        expect_line(ARGS("views", "/dev/zero", "--data", data), 1,
                    "/dev/zero: not a regular file (a device or pipe), not a map (a .bsp file, a map name "
                    "with --data, or 'builtin')");
    }
}

/* A map without its model files: one warning line, silenced by --quiet. */
static void missing_models(void) {
    game_dir("g");
    copy_from_data("maps/e1m1.bsp", "g/maps/e1m1.bsp");
    const char *want = "edgewise: warning: e1m1.bsp: 17 model files missing or unreadable (maps/b_bh10.bsp, "
                       "maps/b_shell0.bsp, progs/armor.mdl, progs/soldier.mdl and 13 more), 96 entities not "
                       "drawn; item boxes (maps/b_*.bsp) are not in the game directory\n"
                       "wrote m.png (640x480)\n";
    ew_t_run *r = run(ARGS("render", "e1m1", "--data", "g", "--out", "m.png"));
    CHECK(r->status == 0 && strcmp(r->err, want) == 0, "missing models: exit %d, stderr:\n%s", r->status, r->err);
    r = run(ARGS("render", "g/maps/e1m1.bsp", "--out", "m.png"));
    CHECK(r->status == 0 && strcmp(r->err, want) == 0, "missing models (path): exit %d, stderr:\n%s", r->status,
          r->err);
    r = run(ARGS("render", "e1m1", "--data", "g", "--out", "m.png", "--quiet"));
    CHECK(r->status == 0 && strcmp(r->err, "wrote m.png (640x480)\n") == 0, "--quiet: stderr:\n%s", r->err);
    /* With the shared game directory every model is there: no such line. */
    r = run(ARGS("render", "e1m1", "--data", data, "--out", "m.png"));
    CHECK(r->status == 0 && !strstr(r->err, "missing or unreadable"), "shared data: stderr:\n%s", r->err);
}

/* Errors inside a pak name the pak; corrupt entries print readable. */
static void paks(void) {
    game_dir("p");
    uint8_t junk[64];
    memset(junk, 'x', sizeof junk);
    write_pak("p/pak0.pak", "maps/bad.bsp", 12, (int32_t)sizeof junk, junk, sizeof junk);
    ew_t_run *r = run(ARGS("render", "bad", "--data", "p"));
    CHECK(r->status == 1 && ew_t_count_lines(r->err) == 1 && strncmp(r->err, "edgewise: p/pak0.pak: maps/bad.bsp: ", 36) == 0,
          "pak map: exit %d, stderr: %s", r->status, r->err);

    /* A negative offset: said so, not summed. */
    write_pak("p/pak0.pak", "maps/neg.bsp", -5, 10, junk, sizeof junk);
    expect_line(ARGS("render", "neg", "--data", "p"), 1, "p/pak0.pak: entry 0 ('maps/neg.bsp'): negative offset -5");
    /* Control bytes and high bytes in a name are escaped. */
    write_pak("p/pak0.pak", "maps/\001\033x\377.bsp", 12, 1000000, junk, sizeof junk);
    expect_line(ARGS("render", "neg", "--data", "p"), 1,
                "p/pak0.pak: entry 0 ('maps/\\x01\\x1bx\\xff.bsp'): offset 12 + size 1000000 past end of file "
                "(140 bytes)");
}

/* A map whose light lump is zeroed draws black: --stats says "dark":true
 * and warns; the same map with its light is not dark. */
static void dark(void) {
    char src[600];
    snprintf(src, sizeof src, "%s/maps/e1m1.bsp", data);
    size_t n;
    uint8_t *b = read_file(src, &n);
    CHECK(b && n > 128, "read %s", src);
    if (!b) return;
    /* Lump 8 (lighting): offset and length at 4 + 8 * 8. */
    uint32_t ofs = (uint32_t)b[68] | (uint32_t)b[69] << 8 | (uint32_t)b[70] << 16 | (uint32_t)b[71] << 24;
    uint32_t len = (uint32_t)b[72] | (uint32_t)b[73] << 8 | (uint32_t)b[74] << 16 | (uint32_t)b[75] << 24;
    CHECK(len > 0 && ofs + (uint64_t)len <= n, "e1m1 light lump %u+%u", ofs, len);
    if (len > 0 && ofs + (uint64_t)len <= n) memset(b + ofs, 0, len);
    char dst[600];
    CHECK(write_file(path_in(dst, "g/maps/dark.bsp"), b, n) == 0, "write dark.bsp");
    free(b);

    ew_t_run *r = run(ARGS("render", "g/maps/dark.bsp", "--no-entities", "--stats", "--out", "d.png"));
    CHECK(r->status == 0 && ew_t_json_num(r->out, "dark") == 1, "dark map: exit %d, out %s", r->status, r->out);
    CHECK(strcmp(r->err, "edgewise: warning: d.png: the frame is nearly black (mean brightness 0.0% of full scale, "
                         "under 3.1%): the map's light data is dark (its light samples average 0.0 of 255)\n"
                         "wrote d.png (640x480)\n") == 0,
          "dark map: stderr:\n%s", r->err);
    r = run(ARGS("render", "g/maps/dark.bsp", "--no-entities", "--stats", "--out", "d.png", "--quiet"));
    CHECK(r->status == 0 && ew_t_json_num(r->out, "dark") == 1 && strcmp(r->err, "wrote d.png (640x480)\n") == 0,
          "dark --quiet: %s", r->err);
    r = run(ARGS("render", "g/maps/e1m1.bsp", "--no-entities", "--stats", "--out", "d.png"));
    CHECK(r->status == 0 && ew_t_json_num(r->out, "dark") == 0 && strcmp(r->err, "wrote d.png (640x480)\n") == 0,
          "lit map: dark %g, stderr %s", ew_t_json_num(r->out, "dark"), r->err);
    r = run(ARGS("demo", "--stats", "--out", "d.png"));
    CHECK(r->status == 0 && ew_t_json_num(r->out, "dark") == 0, "demo: dark %g", ew_t_json_num(r->out, "dark"));
}

/* Numbers are decimal, as help says (issue 36): strtod's hex floats, inf,
 * nan and leading blanks are refused by every option that reads a number
 * (one usage line naming the option and the value), and the decimal
 * spellings help allows are taken. */
static void decimal_only(void) {
    const char *bad[] = {"0x10", "0X1p4", "inf", "nan", "-Infinity", " 16", "16 ", "1e999", "1e", ".", "+-1", ""};
    for (size_t b = 0; b < sizeof bad / sizeof *bad; b++) {
        const char *x = bad[b];
        char v3[64], v4[64], fog[64], style[64];
        snprintf(v3, sizeof v3, "%s,0,0", x);
        snprintf(v4, sizeof v4, "0,0,0,%s", x);
        snprintf(fog, sizeof fog, "%s,1,1,1", x);
        snprintf(style, sizeof style, "0=%s", x);
        struct {
            const char *opt, *val;
            const char *const *args;
        } cases[] = {
            {"--pos", v3, ARGS("render", "builtin", "--pos", v3, "--angles", "0,0,0")},
            {"--angles", v3, ARGS("render", "builtin", "--pos", "0,0,0", "--angles", v3)},
            {"--fov", x, ARGS("render", "builtin", "--fov", x)},
            {"--time", x, ARGS("render", "builtin", "--time", x)},
            {"--dlight", v4, ARGS("render", "builtin", "--dlight", v4)},
            {"--fog", fog, ARGS("render", "builtin", "--fog", fog)},
            {"--wateralpha", x, ARGS("render", "builtin", "--wateralpha", x)},
            {"--subdiv-threshold", x, ARGS("render", "builtin", "--subdiv-threshold", x)},
            {"--gamma", x, ARGS("render", "builtin", "--color", "true", "--gamma", x)},
            {"--lightstyle", style, ARGS("render", "builtin", "--lightstyle", style)},
            {"--time", x, ARGS("render", "builtin:polyhedra", "--time", x)},
            {"--seconds", x, ARGS("fly", "builtin", "--seconds", x, "--out", "a.y4m")},
        };
        for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
            if (!strcmp(cases[i].opt, "--lightstyle") && strspn(x, "abcdefghijklmnopqrstuvwxyz") == strlen(x))
                continue;  /* "inf", "nan": light style patterns, letters a to z */
            ew_t_run *r = run(cases[i].args);
            char head[200];
            snprintf(head, sizeof head, "edgewise: %s %s", cases[i].opt, cases[i].val);
            int ok = r->status == 2 && ew_t_count_lines(r->err) == 1;
            /* an empty value is refused before its rule: the line names the option */
            ok = ok && (*x ? strncmp(r->err, head, strlen(head)) == 0 : strstr(r->err, cases[i].opt) != NULL);
            CHECK(ok, "%s '%s': want exit 2 and one line '%s...', got %d: %s", cases[i].opt, cases[i].val, head,
                  r->status, r->err);
        }
    }
    /* What help allows: signs, a point with digits on one side, exponents. */
    ew_t_run *r = run(ARGS("render", "builtin", "--size", "320x200", "--pos", "+1.,-.5,1E2", "--angles",
                           "0,-9e1,0.0", "--fov", "9.e1", "--time", "1e-3", "--dlight", "0,0,40,2.5e2,1,.5,0",
                           "--out", "dec.png"));
    CHECK(r->status == 0, "decimal spellings: exit %d: %s", r->status, r->err);
}

int main(void) {
    if (!getenv("EW_CLI")) {
        fprintf(stderr, "EW_CLI not set\n");
        return 1;
    }
    snprintf(tmpdir, sizeof tmpdir, "/tmp/ew_errors_XXXXXX");
    if (!mkdtemp(tmpdir)) {
        fprintf(stderr, "cannot make a scratch folder\n");
        return 1;
    }
    static char abs_data[512];
    if (ew_t_need_shared("data/librequake/maps/e1m1.bsp")) {
        snprintf(abs_data, sizeof abs_data, "%s", ew_t_shared_abs("data/librequake"));
        data = abs_data;
    }
    rules();
    decimal_only();
    not_maps();
    if (data) {
        missing_models();
        paks();
        dark();
    }
    char cmd[600];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmpdir);
    return ew_t_finish();
}
