/*
 * edgewise fly: the y4m it writes (header, frame count and size, frames that
 * move), frame 4 against `edgewise render` of the camera --cameras gives for
 * it (converted to YCbCr here with the same BT.601 full-range formula), a PNG
 * sequence, a recorded --path FILE, and the usage errors.  Issue 36: a path
 * file is held to --seconds' limit and read by whole lines, and a failed or
 * interrupted run leaves no partial output (y4m, mp4 through a stand-in
 * ffmpeg, PNG frames) and an older file intact.
 */
#define _DEFAULT_SOURCE
#include "util.h"
#include "edgewise_lab.h"

#include <dirent.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static char tmpdir[256];
static ew_t_run *run_r;

static void run(const char *const *args) { ew_t_run_cli(run_r, tmpdir, args); }

static unsigned char *slurp_bin(const char *path, size_t *size) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *b = malloc(n > 0 ? (size_t)n : 1);
    *size = b ? fread(b, 1, (size_t)n, f) : 0;
    fclose(f);
    return b;
}

static uint8_t clamp8(double v) { return (uint8_t)(v < 0 ? 0 : v > 255 ? 255 : lround(v)); }

static int file_exists(const char *rel) {
    char p[512];
    snprintf(p, sizeof p, "%s/%s", tmpdir, rel);
    return access(p, F_OK) == 0;
}

static void check_usage(const char *const *args, int status, const char *what) {
    run(args);
    CHECK(run_r->status == status, "%s: exit %d, want %d (%s)", what, run_r->status, status, run_r->err);
    CHECK(ew_t_count_lines(run_r->err) == 1, "%s: one error line, got: %s", what, run_r->err);
    CHECK(strstr(run_r->err, "edgewise: ") == run_r->err, "%s: %s", what, run_r->err);
}

static void write_text(const char *rel, const char *text, size_t n) {
    char p[512];
    snprintf(p, sizeof p, "%s/%s", tmpdir, rel);
    FILE *f = fopen(p, "wb");
    if (f) {
        fwrite(text, 1, n, f);
        fclose(f);
    }
}

/* Files in tmpdir whose names end in ".part" (fly's temporary names). */
static int part_files(void) {
    DIR *d = opendir(tmpdir);
    int n = 0;
    struct dirent *e;
    while (d && (e = readdir(d))) {
        size_t l = strlen(e->d_name);
        n += l > 5 && !strcmp(e->d_name + l - 5, ".part");
    }
    if (d) closedir(d);
    return n;
}

/* A path file refused: exit 1, one line naming FILE:LINE, nothing written. */
static void path_refused(const char *what, const char *text, size_t n, int line, const char *needle) {
    write_text("bad_path.txt", text, n);
    char at[64];
    snprintf(at, sizeof at, "--path bad_path.txt:%d: ", line);
    run((const char *const[]){"fly", "builtin", "--size", "320x200", "--fps", "2", "--path", "bad_path.txt",
                              "--out", "bad.y4m", "--cameras", "bad_cams.txt", NULL});
    CHECK(run_r->status == 1 && ew_t_count_lines(run_r->err) == 1 && strstr(run_r->err, at) &&
              strstr(run_r->err, needle),
          "%s: want exit 1 and one line with '%s' and '%s', got %d: %s", what, at, needle, run_r->status,
          run_r->err);
    CHECK(!file_exists("bad.y4m") && !file_exists("bad_cams.txt") && !part_files(), "%s: no file left", what);
}

/* fly running in tmpdir in the background (output to /dev/null); its pid. */
static pid_t spawn_fly(const char *const *args) {
    pid_t pid = fork();
    if (pid == 0) {
        int fd = open("/dev/null", O_WRONLY);
        if (fd >= 0) dup2(fd, 1), dup2(fd, 2);
        if (chdir(tmpdir) != 0) _exit(126);
        const char *argv[32] = {getenv("EW_CLI")};
        for (int i = 0; args[i] && i < 30; i++) argv[i + 1] = args[i];
        execv(argv[0], (char *const *)argv);
        _exit(127);
    }
    return pid;
}

static void sleep_ms(long ms) {
    struct timespec ts = {ms / 1000, (ms % 1000) * 1000000L};
    nanosleep(&ts, NULL);
}

/* Issue 36: limits, long lines, and what a failed run leaves. */
static void hardening(void) {
    /* ---- a path file's span is held to --seconds' 3600 s ---- */
    const char span[] = "0 0 0 0 0 0 0\n1e9 0 0 0 0 0 0\n";
    path_refused("times 0 and 1e9", span, strlen(span), 2, "spans at most 3600 s");
    /* the frame count overflowed lround: a one-frame video and exit 0 before */
    const char huge[] = "1e30 0 0 0 0 0 0\n1.0000001e30 0 0 0 0 0 0\n";
    path_refused("times 1e30 and 1.0000001e30", huge, strlen(huge), 2, "spans at most 3600 s");
    const char over[] = "# a comment\n5 0 0 0 0 0 0\n3605.001 0 0 0 0 0 0\n";
    path_refused("a span of 3600.001 s", over, strlen(over), 3, "spans at most 3600 s");
    const char edge[] = "5 0 0 0 0 0 0\n3605 0 0 0 0 0 0\n";
    write_text("edge.txt", edge, strlen(edge));
    run((const char *const[]){"fly", "builtin", "--size", "320x200", "--fps", "1", "--seconds", "1", "--path",
                              "edge.txt", "--out", "edge.y4m", NULL});
    CHECK(run_r->status == 0 && strstr(run_r->err, " 1 frames"), "a span of 3600 s is taken: %d %s", run_r->status,
          run_r->err);
    /* numbers as on the command line: decimal only */
    const char hex[] = "0 0 0 0 0 0 0\n0x10 0 0 0 0 0 0\n";
    path_refused("a hex time", hex, strlen(hex), 2, "seven decimal numbers");
    const char nan[] = "0 0 0 0 0 nan 0\n";
    path_refused("a nan angle", nan, strlen(nan), 1, "seven decimal numbers");
    const char eight[] = "0 0 0 0 0 0 0 0\n";
    path_refused("eight numbers", eight, strlen(eight), 1, "seven decimal numbers");
    const char back[] = "1 0 0 0 0 0 0\n0.5 0 0 0 0 0 0\n";
    path_refused("a time going back", back, strlen(back), 2, "goes back");
    /* frame 0 could not be drawn: a 43-byte header-only y4m and exit 1 before */
    const char far[] = "0 1e30 0 0 0 0 0\n";
    path_refused("a position of 1e30", far, strlen(far), 1, "from -1000000 to 1000000");
    const char nul[] = "0 0 0 0 0 0 0\n1 0 0\0 0 0 0 0\n";
    path_refused("a NUL byte", nul, sizeof nul - 1, 2, "NUL");

    /* ---- lines of any length: a 600-character comment first, a 100000-character one later ---- */
    size_t big = 100000;
    char *text = malloc(big + 6000);  /* the long lines and a few short ones */
    if (text) {
        size_t n = 0;
        text[n++] = '#';
        for (int i = 0; i < 600; i++) text[n++] = 'c';
        n += (size_t)sprintf(text + n, "\n0 230 290 110 0 350 0\n#");
        for (size_t i = 0; i < big; i++) text[n++] = i % 80 ? 'c' : ' ';
        n += (size_t)sprintf(text + n, "\n1 200 250 120 0 10 0\n");
        write_text("long.txt", text, n);
        run((const char *const[]){"fly", "builtin", "--size", "320x200", "--fps", "2", "--path", "long.txt", "--out",
                                  "long.y4m", NULL});
        CHECK(run_r->status == 0 && strstr(run_r->err, " 3 frames"), "long comment lines: exit %d: %s",
              run_r->status, run_r->err);
        /* a camera line over 4095 bytes is refused as such */
        n = 0;
        n += (size_t)sprintf(text + n, "0 0 0 0 0 0 0\n1 ");
        for (int i = 0; i < 5000; i++) text[n++] = '0';
        n += (size_t)sprintf(text + n, "1 0 0 0 0 0\n");
        path_refused("a 5000-byte camera line", text, n, 2, "longer than 4095 bytes");
        free(text);
    }

    /* ---- --out an existing folder: said before any frame ---- */
    char p[512];
    snprintf(p, sizeof p, "%s/dir.y4m", tmpdir);
    mkdir(p, 0755);
    check_usage((const char *const[]){"fly", "builtin", "--size", "320x200", "--out", "dir.y4m", NULL}, 1,
                "--out a folder");
    check_usage((const char *const[]){"fly", "builtin", "--size", "320x200", "--out", "c.y4m", "--cameras", "dir.y4m",
                                      NULL},
                1, "--cameras a folder");
    CHECK(!file_exists("c.y4m") && !part_files(), "--cameras a folder: nothing written");

    /* ---- a PNG frame that cannot be written: the frames before it go ---- */
    snprintf(p, sizeof p, "%s/fail_003.png", tmpdir);
    mkdir(p, 0755);
    run((const char *const[]){"fly", "builtin", "--size", "320x200", "--seconds", "1", "--fps", "6", "--out",
                              "fail_%03d.png", NULL});
    CHECK(run_r->status == 1 && ew_t_count_lines(run_r->err) == 1, "png frame 3 unwritable: exit %d: %s",
          run_r->status, run_r->err);
    CHECK(!file_exists("fail_000.png") && !file_exists("fail_002.png") && file_exists("fail_003.png"),
          "png frame 3 unwritable: frames 0 to 2 removed, the folder left");

    /* ---- killed mid-video: no partial file, the older video intact ---- */
    write_text("keep.y4m", "old", 3);
    write_text("keep_cams.txt", "old", 3);
    pid_t pid = spawn_fly((const char *const[]){"fly", "builtin", "--size", "320x200", "--seconds", "600", "--out",
                                                "keep.y4m", "--cameras", "keep_cams.txt", NULL});
    int started = 0;
    for (int i = 0; i < 200 && !started; i++) {
        sleep_ms(50);
        started = part_files() == 2;
    }
    CHECK(started, "fly writes keep.y4m and keep_cams.txt under temporary names");
    sleep_ms(200);
    kill(pid, SIGTERM);
    int status = 0;
    waitpid(pid, &status, 0);
    CHECK(WIFEXITED(status) && WEXITSTATUS(status) == 1, "SIGTERM: exit 1 after cleaning up (status 0x%x)", status);
    char old[16];
    snprintf(p, sizeof p, "%s/keep.y4m", tmpdir);
    ew_t_slurp(p, old, sizeof old);
    CHECK(!strcmp(old, "old"), "an interrupted run keeps the older keep.y4m");
    snprintf(p, sizeof p, "%s/keep_cams.txt", tmpdir);
    ew_t_slurp(p, old, sizeof old);
    CHECK(!strcmp(old, "old"), "an interrupted run keeps the older keep_cams.txt");
    CHECK(!part_files(), "an interrupted run leaves no temporary file");

    /* ---- .mp4 through a stand-in ffmpeg that copies its input, then one that fails ---- */
    char bin[300], script[400];
    snprintf(bin, sizeof bin, "%s/bin", tmpdir);
    mkdir(bin, 0755);
    snprintf(script, sizeof script, "%s/ffmpeg", bin);
    const char *old_path = getenv("PATH");
    char *saved = old_path ? strdup(old_path) : NULL, newpath[4096];
    snprintf(newpath, sizeof newpath, "%s:%s", bin, old_path ? old_path : "/usr/bin:/bin");
    setenv("PATH", newpath, 1);
    for (int fail = 0; fail < 2; fail++) {
        FILE *f = fopen(script, "w");
        if (f) {
            fprintf(f, "#!/bin/sh\nfor a in \"$@\"; do last=\"$a\"; done\n%s\n",
                    fail ? "head -c 100 > \"$last\"; exit 1" : "cat > \"$last\"");
            fclose(f);
            chmod(script, 0755);
        }
        run((const char *const[]){"fly", "builtin", "--size", "320x200", "--seconds", "1", "--fps", "5", "--out",
                                  "v.mp4", NULL});
        if (!fail) {
            snprintf(p, sizeof p, "%s/v.mp4", tmpdir);
            size_t vs = 0;
            unsigned char *v = slurp_bin(p, &vs);
            CHECK(run_r->status == 0 && v && vs == strlen("YUV4MPEG2 W320 H200 F5:1 Ip A1:1 C420jpeg\n") +
                                                       5 * (6 + 320 * 200 * 3 / 2),
                  "mp4: ffmpeg's output moved into place (%zu bytes): %s", vs, run_r->err);
            free(v);
        } else {
            CHECK(run_r->status == 1 && ew_t_count_lines(run_r->err) == 1 && strstr(run_r->err, "ffmpeg"),
                  "mp4: a failing ffmpeg: exit %d: %s", run_r->status, run_r->err);
        }
        CHECK(!part_files(), "mp4 (ffmpeg %s): no temporary file left", fail ? "failing" : "working");
    }
    snprintf(p, sizeof p, "%s/v.mp4", tmpdir);
    size_t vs = 0;
    unsigned char *v = slurp_bin(p, &vs);
    CHECK(v && vs > 100, "mp4: a failed run keeps the older v.mp4 (%zu bytes)", vs);
    free(v);
    if (saved) setenv("PATH", saved, 1);
    free(saved);
}

int main(void) {
    const char *cli = getenv("EW_CLI");
    run_r = malloc(sizeof *run_r);
    snprintf(tmpdir, sizeof tmpdir, "/tmp/ew_fly_XXXXXX");
    if (!cli || !run_r || !mkdtemp(tmpdir)) {
        fprintf(stderr, "no EW_CLI or no temporary directory\n");
        return 1;
    }
    const int W = 320, H = 200, N = 10;

    /* ---- the y4m ---- */
    run((const char *const[]){"fly", "builtin", "--size", "320x200", "--seconds", "1", "--fps", "10", "--out",
                              "T.y4m", "--cameras", "cams.txt", NULL});
    CHECK(run_r->status == 0, "fly y4m: exit %d: %s", run_r->status, run_r->err);
    CHECK(ew_t_count_lines(run_r->err) == 1 && strstr(run_r->err, "10 frames"), "summary line: %s", run_r->err);
    char path[512];
    snprintf(path, sizeof path, "%s/T.y4m", tmpdir);
    size_t size = 0;
    unsigned char *y4m = slurp_bin(path, &size);
    const char *hdr = "YUV4MPEG2 W320 H200 F10:1 Ip A1:1 C420jpeg\n";
    size_t hl = strlen(hdr), fsz = (size_t)W * H * 3 / 2;
    CHECK(y4m && size >= hl && !memcmp(y4m, hdr, hl), "y4m header");
    CHECK(size == hl + N * (6 + fsz), "y4m size %zu, want %zu (10 frames)", size, hl + N * (6 + fsz));
    int frames_ok = y4m && size == hl + N * (6 + fsz);
    for (int k = 0; frames_ok && k < N; k++)
        CHECK(!memcmp(y4m + hl + k * (6 + fsz), "FRAME\n", 6), "frame %d marker", k);
    for (int k = 0; frames_ok && k + 1 < N; k++) {
        const unsigned char *a = y4m + hl + k * (6 + fsz) + 6, *b = a + 6 + fsz;
        CHECK(memcmp(a, b, fsz) != 0, "frames %d and %d are the same", k, k + 1);
    }

    /* ---- frame 4 == edgewise render of its camera ---- */
    char cams[4096];
    snprintf(path, sizeof path, "%s/cams.txt", tmpdir);
    ew_t_slurp(path, cams, sizeof cams);
    CHECK(ew_t_count_lines(cams) == N, "cameras: %d lines", ew_t_count_lines(cams));
    const char *line = cams;
    for (int i = 0; i < 4 && line; i++) {
        line = strchr(line, '\n');
        if (line) line++;
    }
    long fno = -1;
    char t[64] = "", x[64] = "", y[64] = "", z[64] = "", p[64] = "", yw[64] = "", r[64] = "";
    CHECK(line && sscanf(line, "%ld %63s %63s %63s %63s %63s %63s %63s", &fno, t, x, y, z, p, yw, r) == 8 && fno == 4,
          "camera line of frame 4");
    CHECK(fabs(atof(t) - 0.4) < 1e-9, "frame 4's time %s, want 0.4", t);
    char pos[200], ang[200];
    snprintf(pos, sizeof pos, "%s,%s,%s", x, y, z);
    snprintf(ang, sizeof ang, "%s,%s,%s", p, yw, r);
    run((const char *const[]){"render", "builtin", "--size", "320x200", "--pos", pos, "--angles", ang, "--time", t,
                              "--out", "f4.png", NULL});
    CHECK(run_r->status == 0, "render of frame 4's camera: %s", run_r->err);
    uint8_t *rgb = NULL;
    int w = 0, h = 0;
    ew_error err = {""};
    snprintf(path, sizeof path, "%s/f4.png", tmpdir);
    CHECK(ew_read_png_rgb(path, &rgb, &w, &h, &err) == 0 && w == W && h == H, "read f4.png: %s", err.msg);
    if (rgb && frames_ok && w == W && h == H) {
        const unsigned char *Y = y4m + hl + 4 * (6 + fsz) + 6, *U = Y + W * H, *V = U + (W / 2) * (H / 2);
        int worst = 0;
        for (int i = 0; i < W * H; i++) {
            const uint8_t *c = rgb + 3 * i;
            int d = abs(clamp8(0.299 * c[0] + 0.587 * c[1] + 0.114 * c[2]) - Y[i]);
            if (d > worst) worst = d;
        }
        for (int j = 0; j < H / 2; j++)
            for (int i = 0; i < W / 2; i++) {
                double cb = 0, cr = 0;
                for (int dy = 0; dy < 2; dy++)
                    for (int dx = 0; dx < 2; dx++) {
                        const uint8_t *c = rgb + 3 * ((2 * j + dy) * W + 2 * i + dx);
                        cb += 128 - 0.168736 * c[0] - 0.331264 * c[1] + 0.5 * c[2];
                        cr += 128 + 0.5 * c[0] - 0.418688 * c[1] - 0.081312 * c[2];
                    }
                int du = abs(clamp8(cb / 4) - U[j * (W / 2) + i]), dv = abs(clamp8(cr / 4) - V[j * (W / 2) + i]);
                if (du > worst) worst = du;
                if (dv > worst) worst = dv;
            }
        CHECK(worst <= 1, "frame 4 differs from edgewise render of its camera by %d levels", worst);
    }
    free(rgb);
    free(y4m);

    /* ---- a PNG sequence ---- */
    run((const char *const[]){"fly", "builtin", "--size", "320x200", "--seconds", "0.5", "--fps", "6", "--out",
                              "seq_%03d.png", NULL});
    CHECK(run_r->status == 0, "png sequence: %s", run_r->err);
    CHECK(file_exists("seq_000.png") && file_exists("seq_002.png") && !file_exists("seq_003.png"),
          "png sequence: seq_000..seq_002 (3 frames) and no more");

    /* ---- a recorded path: 3 lines over 1 s at 4 fps = 4 frames ---- */
    snprintf(path, sizeof path, "%s/path.txt", tmpdir);
    FILE *f = fopen(path, "w");
    if (f) {
        fputs("0 230 290 110 0 350 0\n0.5 200 250 120 0 10 0\n1 150 200 130 10 30 0\n", f);
        fclose(f);
    }
    run((const char *const[]){"fly", "builtin", "--size", "320x200", "--fps", "4", "--path", "path.txt",
                              "--out", "p.y4m", "--cameras", "pcams.txt", NULL});
    CHECK(run_r->status == 0, "--path FILE: %s", run_r->err);
    snprintf(path, sizeof path, "%s/pcams.txt", tmpdir);
    ew_t_slurp(path, cams, sizeof cams);
    CHECK(ew_t_count_lines(cams) == 5, "--path FILE: 5 frames (0 to 1 s at 4 fps), got %d", ew_t_count_lines(cams));
    double ft, fx, fy, fz, fp, fyaw, fr;
    long k1;
    const char *l1 = strchr(cams, '\n');
    /* Frame 1 at 0.25 s: halfway between the first two lines; yaw 350 -> 10 the short way (0). */
    CHECK(l1 && sscanf(l1 + 1, "%ld %lf %lf %lf %lf %lf %lf %lf", &k1, &ft, &fx, &fy, &fz, &fp, &fyaw, &fr) == 8 &&
              k1 == 1 && fabs(ft - 0.25) < 1e-9 && fabs(fx - 215) < 1e-3 && fabs(fy - 270) < 1e-3 &&
              fabs(fz - 115) < 1e-3 && fabs(fyaw) < 1e-3,
          "--path FILE frame 1: %s", l1 ? l1 + 1 : "(none)");
    snprintf(path, sizeof path, "%s/p.y4m", tmpdir);
    unsigned char *pv = slurp_bin(path, &size);
    CHECK(pv && size == strlen("YUV4MPEG2 W320 H200 F4:1 Ip A1:1 C420jpeg\n") + 5 * (6 + fsz), "p.y4m: 5 frames");
    free(pv);

    /* ---- usage errors ---- */
    check_usage((const char *const[]){"fly", "builtin", "--size", "321x200", "--out", "a.y4m", NULL}, 2,
                "odd size");
    check_usage((const char *const[]){"fly", "builtin", "--fps", "0", "--out", "a.y4m", NULL}, 2, "fps 0");
    check_usage((const char *const[]){"fly", "builtin", "--fps", "x", "--out", "a.y4m", NULL}, 2, "fps x");
    check_usage((const char *const[]){"fly", "builtin", "--seconds", "-1", "--out", "a.y4m", NULL}, 2,
                "seconds -1");
    check_usage((const char *const[]){"fly", "builtin", "--out", "a.avi", NULL}, 2, "unknown extension");
    check_usage((const char *const[]){"fly", "builtin", "--out", "f%d%d.png", NULL}, 2, "two conversions");
    check_usage((const char *const[]){"fly", "builtin", "--out", "f%s.png", NULL}, 2, "%s conversion");
    check_usage((const char *const[]){"fly", "builtin", NULL}, 2, "no --out");
    check_usage((const char *const[]){"fly", "builtin", "--out", "a.y4m", "--bogus", NULL}, 2, "unknown option");
    CHECK(!file_exists("a.y4m"), "no output after a usage error");
    /* .mp4 without ffmpeg on PATH (PATH set to an empty folder for the run). */
    const char *old = getenv("PATH");
    char *saved = old ? strdup(old) : NULL;
    setenv("PATH", tmpdir, 1);
    check_usage((const char *const[]){"fly", "builtin", "--out", "a.mp4", NULL}, 1, "mp4 without ffmpeg");
    CHECK(strstr(run_r->err, "ffmpeg") != NULL, "the error names ffmpeg: %s", run_r->err);
    if (saved) setenv("PATH", saved, 1);
    free(saved);
    check_usage((const char *const[]){"fly", "builtin", "--path", "nope.txt", "--out", "a.y4m", NULL}, 1,
                "missing path file");

    hardening();

    run((const char *const[]){"fly", "--help", NULL});
    CHECK(run_r->status == 0 && strstr(run_r->out, "--cameras") && strstr(run_r->out, "walls"), "fly --help");

    char cmd[600];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmpdir);
    free(run_r);
    return ew_t_finish();
}
