/*
 * edgewise fly: the y4m it writes (header, frame count and size, frames that
 * move), frame 4 against `edgewise render` of the camera --cameras gives for
 * it (converted to YCbCr here with the same BT.601 full-range formula), a PNG
 * sequence, a recorded --path FILE, and the usage errors.
 */
#define _DEFAULT_SOURCE
#include "util.h"
#include "edgewise_tools.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
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

    run((const char *const[]){"fly", "--help", NULL});
    CHECK(run_r->status == 0 && strstr(run_r->out, "--cameras") && strstr(run_r->out, "walls"), "fly --help");

    char cmd[600];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmpdir);
    free(run_r);
    return ew_t_finish();
}
