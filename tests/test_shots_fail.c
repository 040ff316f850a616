/*
 * `edgewise shots` when things fail (issue 33, item 2), on maps made here
 * from the built-in level (no shared data):
 *   - a folder of twelve maps without a palette: exit 1, and after the
 *     summary each failed map is named with its one-line error, the first
 *     ten, then "and 2 more";
 *   - an empty .pak and a corrupt one beside a good map, and a game
 *     directory whose pak0.pak is corrupt beside its loose map: each bad pak
 *     is one failed source, the good maps are drawn, exit 1;
 *   - shots --jobs 2 killed (SIGTERM, then SIGINT) mid-batch (maps of 32
 *     views at 8K, seconds each): its workers die with it: half a second
 *     after the kill none is alive, and the output folder does not change
 *     from a quarter of a second after it on.
 */
#define _POSIX_C_SOURCE 200809L
#include "util.h"
#include "edgewise_lab.h"
#include "mapgen.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static char tmpdir[256];
#define IN_TMP(rel) ew_t_in_dir(tmpdir, rel)
static ew_t_run *run_r;
static uint8_t *bsp, pal[768], cmap[EW_COLORMAP_SIZE];
static size_t bsp_size;

static void mkdirs(const char *rel) {
    char p[512];
    snprintf(p, sizeof p, "%s/%s", tmpdir, rel);
    for (char *s = p + strlen(tmpdir) + 1; *s; s++)
        if (*s == '/') *s = '\0', mkdir(p, 0777), *s = '/';
    mkdir(p, 0777);
}

static int count_str(const char *s, const char *needle) {
    int n = 0;
    for (const char *p = s; (p = strstr(p, needle)) != NULL; p += strlen(needle)) n++;
    return n;
}

/* Twelve maps and no palette: every one fails, the summary names ten. */
static void no_palette(void) {
    mkdirs("nopal");
    for (int i = 0; i < 12; i++) {
        char rel[64];
        snprintf(rel, sizeof rel, "nopal/m%02d.bsp", i);
        CHECK(ew_t_write_file(IN_TMP(rel), bsp, bsp_size) == 0, "write %s", rel);
    }
    const char *const args[] = {"shots", IN_TMP("nopal"), "--out", IN_TMP("nopal_out"), "--size", "320x200", NULL};
    ew_t_run_cli(run_r, tmpdir, args);
    printf("no palette: exit %d, stderr:\n%s", run_r->status, run_r->err);
    CHECK(run_r->status == 1 && strstr(run_r->err, "12 failed"), "no palette: exit %d: %s", run_r->status,
          run_r->err);
    CHECK(count_str(run_r->err, "shots: failed: m") == 10 && count_str(run_r->err, "palette.lmp") == 10,
          "no palette: want the first ten maps named with their error, got:\n%s", run_r->err);
    CHECK(strstr(run_r->err, "failed: m00: ") && strstr(run_r->err, "failed: m09: ") &&
              !strstr(run_r->err, "failed: m10") && strstr(run_r->err, "and 2 more failed"),
          "no palette: want m00..m09 named, then 'and 2 more', got:\n%s", run_r->err);
    CHECK(ew_t_count_lines(run_r->err) == 12, "no palette: want 12 lines (summary, ten maps, the rest), got %d",
          ew_t_count_lines(run_r->err));
}

/* Bad paks beside good maps. */
static void bad_paks(void) {
    mkdirs("paks/gfx");
    mkdirs("paks/maps");
    CHECK(ew_t_write_file(IN_TMP("paks/gfx/palette.lmp"), pal, sizeof pal) == 0, "palette");
    CHECK(ew_t_write_file(IN_TMP("paks/gfx/colormap.lmp"), cmap, sizeof cmap) == 0, "colormap");
    CHECK(ew_t_write_file(IN_TMP("paks/maps/good.bsp"), bsp, bsp_size) == 0, "good.bsp");
    CHECK(ew_t_write_file(IN_TMP("paks/empty.pak"), "", 0) == 0, "empty.pak");
    CHECK(ew_t_write_file(IN_TMP("paks/junk.pak"), "PACK\377\377\377\177\020\000\000\000garbage!", 20) == 0, "junk.pak");
    const char *const args[] = {"shots", IN_TMP("paks/empty.pak"), IN_TMP("paks/maps/good.bsp"),
                                IN_TMP("paks/junk.pak"), "--out", IN_TMP("paks_out"), "--size", "320x200", NULL};
    ew_t_run_cli(run_r, tmpdir, args);
    printf("bad paks: exit %d, stderr:\n%s", run_r->status, run_r->err);
    CHECK(run_r->status == 1 && strstr(run_r->err, "3 maps, 1 picture written") && strstr(run_r->err, "2 failed"),
          "bad paks: want the good map drawn and the two paks failed (exit 1), got %d: %s", run_r->status,
          run_r->err);
    CHECK(strstr(run_r->err, "failed: empty.pak: ") && strstr(run_r->err, "failed: junk.pak: "),
          "bad paks: the paks are not named with their errors: %s", run_r->err);
    CHECK(access(IN_TMP("paks_out/good_best.png"), F_OK) == 0, "bad paks: good_best.png not written");

    /* A game directory: a loose map and a corrupt pak0.pak. */
    mkdirs("game/maps");
    mkdirs("game/gfx");
    CHECK(ew_t_write_file(IN_TMP("game/gfx/palette.lmp"), pal, sizeof pal) == 0, "palette");
    CHECK(ew_t_write_file(IN_TMP("game/gfx/colormap.lmp"), cmap, sizeof cmap) == 0, "colormap");
    CHECK(ew_t_write_file(IN_TMP("game/maps/loose.bsp"), bsp, bsp_size) == 0, "loose.bsp");
    CHECK(ew_t_write_file(IN_TMP("game/pak0.pak"), "PACK", 4) == 0, "pak0.pak");
    const char *const game[] = {"shots", IN_TMP("game"), "--out", IN_TMP("game_out"), "--size", "320x200", NULL};
    ew_t_run_cli(run_r, tmpdir, game);
    CHECK(run_r->status == 1 && strstr(run_r->err, "1 picture written") && strstr(run_r->err, "1 failed") &&
              strstr(run_r->err, "failed: pak0.pak: "),
          "game dir with a corrupt pak: got %d: %s", run_r->status, run_r->err);
    CHECK(access(IN_TMP("game_out/loose_best.png"), F_OK) == 0, "game dir: loose_best.png not written");
}

/* ---- killing the batch ---- */

static double now_s(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + t.tv_nsec / 1e9;
}

static void sleep_s(double s) {
    struct timespec t = {(time_t)s, (long)((s - (double)(time_t)s) * 1e9)};
    while (nanosleep(&t, &t) < 0 && errno == EINTR) {}
}

/* Files under dir: their count, total size and newest modification (ns). */
typedef struct snap {
    long files;
    long long bytes, newest;
} snap;
static snap snapshot(const char *dir) {
    snap s = {0, 0, 0};
    DIR *d = opendir(dir);
    struct dirent *e;
    while (d && (e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.') continue;
        char p[1024];
        struct stat st;
        snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
        if (stat(p, &st) < 0) continue;
        s.files++, s.bytes += st.st_size;
        long long t = (long long)st.st_mtim.tv_sec * 1000000000LL + st.st_mtim.tv_nsec;
        if (t > s.newest) s.newest = t;
    }
    if (d) closedir(d);
    return s;
}

/* The children of pid (from /proc), at most max. */
static int children_of(pid_t pid, pid_t *out, int max) {
    int n = 0;
    DIR *d = opendir("/proc");
    struct dirent *e;
    while (d && (e = readdir(d)) != NULL && n < max) {
        if (e->d_name[0] < '0' || e->d_name[0] > '9') continue;
        char p[300], buf[512];
        snprintf(p, sizeof p, "/proc/%s/stat", e->d_name);
        FILE *f = fopen(p, "r");
        if (!f) continue;
        size_t k = fread(buf, 1, sizeof buf - 1, f);
        fclose(f);
        buf[k] = '\0';
        const char *rp = strrchr(buf, ')');
        char state;
        int ppid;
        if (rp && sscanf(rp + 1, " %c %d", &state, &ppid) == 2 && ppid == pid) out[n++] = (pid_t)atoi(e->d_name);
    }
    if (d) closedir(d);
    return n;
}

/* Alive: in /proc and not a zombie. */
static int alive(pid_t pid) {
    char p[64], buf[512];
    snprintf(p, sizeof p, "/proc/%d/stat", (int)pid);
    FILE *f = fopen(p, "r");
    if (!f) return 0;
    size_t k = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[k] = '\0';
    const char *rp = strrchr(buf, ')');
    char state = 'X';
    if (rp) sscanf(rp + 1, " %c", &state);
    return state != 'Z' && state != 'X';
}

/* The built-in map with eight more player starts after its worldspawn (a
 * full view set of 32 views: seconds of work a map at 8K), its entity lump
 * replaced by one appended at the end. */
static int write_slow_map(const char *rel) {
    uint32_t ofs = ew_t_le32(bsp + 4), len = ew_t_le32(bsp + 8);
    char *ents = malloc(len + 1);
    if (!ents) return -1;
    memcpy(ents, bsp + ofs, len);
    ents[len] = '\0';
    char *close = strstr(ents, "}\n");
    size_t wend = close ? (size_t)(close + 2 - ents) : 0;
    char text[16384];
    size_t n = (size_t)snprintf(text, sizeof text, "%.*s", (int)wend, ents);
    for (int i = 0; i < 8; i++)
        n += (size_t)snprintf(text + n, sizeof text - n,
                              "{\n\"classname\" \"info_player_start\"\n\"origin\" \"230 290 88\"\n\"angle\" \"%d\"\n}\n",
                              10 * i);
    snprintf(text + n, sizeof text - n, "%s", ents + wend);
    free(ents);
    size_t tl = strlen(text) + 1, at = (bsp_size + 3) & ~(size_t)3;
    uint8_t *b = calloc(1, at + tl);
    if (!b) return -1;
    memcpy(b, bsp, bsp_size);
    memcpy(b + at, text, tl);
    ew_t_put_le32(b + 4, (uint32_t)at), ew_t_put_le32(b + 8, (uint32_t)tl);
    int rc = ew_t_write_file(IN_TMP(rel), b, at + tl);
    free(b);
    return rc;
}

/* The PNGs under dir (depth levels of folders): how many, how many unreadable. */
static void check_pngs(const char *dir, int depth, int *pngs, int *broken) {
    DIR *d = opendir(dir);
    struct dirent *e;
    while (d && (e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.') continue;
        char p[1024];
        struct stat st;
        if (snprintf(p, sizeof p, "%s/%s", dir, e->d_name) >= (int)sizeof p || stat(p, &st) < 0) continue;
        size_t n = strlen(e->d_name);
        if (S_ISDIR(st.st_mode)) {
            if (depth > 0) check_pngs(p, depth - 1, pngs, broken);
        } else if (n >= 4 && !strcmp(e->d_name + n - 4, ".png")) {
            uint8_t *rgb = NULL;
            int w = 0, h = 0;
            ew_error err = {""};
            (*pngs)++;
            if (ew_read_png_rgb(p, &rgb, &w, &h, &err) < 0) (*broken)++;
            free(rgb);
        }
    }
    if (d) closedir(d);
}

static void kill_midway(int sig, const char *name) {
    char out[512];
    snprintf(out, sizeof out, "%s/kill_%s", tmpdir, name);
    /* Six maps of 32 views each at 8K: many seconds of work. */
    mkdirs("slow/maps");
    mkdirs("slow/gfx");
    CHECK(ew_t_write_file(IN_TMP("slow/gfx/palette.lmp"), pal, sizeof pal) == 0, "palette");
    CHECK(ew_t_write_file(IN_TMP("slow/gfx/colormap.lmp"), cmap, sizeof cmap) == 0, "colormap");
    for (int i = 0; i < 6; i++) {
        char rel[64];
        snprintf(rel, sizeof rel, "slow/maps/s%d.bsp", i);
        CHECK(write_slow_map(rel) == 0, "write %s", rel);
    }
    const char *cli = getenv("EW_CLI");
    char maps[512];
    snprintf(maps, sizeof maps, "%s", IN_TMP("slow/maps"));
    const char *const args[] = {cli, "shots", maps, "--views", "all", "--size", "7680x4320", "--jobs", "2",
                                "--out", out, NULL};
    fflush(NULL);
    pid_t pid = fork();
    if (pid == 0) {
        int fd = open("/dev/null", O_WRONLY);
        if (fd >= 0) dup2(fd, 1), dup2(fd, 2);
        execv(cli, (char *const *)args);
        _exit(127);
    }
    CHECK(pid > 0, "fork");
    if (pid <= 0) return;
    /* Wait for the two workers and the first picture. */
    pid_t kids[8];
    int nk = 0;
    double t0 = now_s();
    while (now_s() - t0 < 60) {
        nk = children_of(pid, kids, 8);
        if (nk >= 2 && snapshot(out).files >= 2) break;  /* the manifest and a picture */
        sleep_s(0.02);
    }
    CHECK(nk == 2, "%s: want 2 workers before the kill, found %d", name, nk);
    double tk = now_s();
    kill(pid, sig);
    int status = 0;
    waitpid(pid, &status, 0);
    CHECK(WIFSIGNALED(status) && WTERMSIG(status) == sig, "%s: shots did not die of the signal (status %#x)", name,
          status);
    sleep_s(tk + 0.25 - now_s());
    snap a = snapshot(out);
    sleep_s(tk + 0.5 - now_s());
    int left = 0;
    for (int i = 0; i < nk; i++) left += alive(kids[i]);
    sleep_s(1.0);
    snap b = snapshot(out);
    printf("%s: %d worker(s) alive 0.5 s after the kill; from 0.25 s to 1.5 s after it, files %ld -> %ld, "
           "bytes %lld -> %lld\n", name, left, a.files, b.files, a.bytes, b.bytes);
    CHECK(left == 0, "%s: %d worker(s) still alive 0.5 s after shots was killed", name, left);
    CHECK(a.files == b.files && a.bytes == b.bytes && a.newest == b.newest,
          "%s: the output kept changing after shots was killed: %ld files %lld bytes, then %ld files %lld bytes",
          name, a.files, a.bytes, b.files, b.bytes);
    for (int i = 0; i < nk; i++)
        if (alive(kids[i])) kill(kids[i], SIGKILL);  /* leave nothing behind */
    /* Every picture left under its own name is whole: a resumed batch skips
     * what exists, so a truncated one would stay truncated. */
    int pngs = 0, broken = 0;
    check_pngs(out, 2, &pngs, &broken);
    printf("%s: %d pictures left, %d of them unreadable\n", name, pngs, broken);
    CHECK(broken == 0, "%s: %d of the %d pictures left after the kill are truncated", name, broken, pngs);
}

int main(void) {
    if (!getenv("EW_CLI")) {
        fprintf(stderr, "EW_CLI not set\n");
        return 1;
    }
    snprintf(tmpdir, sizeof tmpdir, "/tmp/ew_shotsfail_XXXXXX");
    run_r = malloc(sizeof *run_r);
    if (!run_r || !mkdtemp(tmpdir)) {
        fprintf(stderr, "cannot make a scratch folder\n");
        return 1;
    }
    ew_error err = {""};
    CHECK(ew_builtin_generate(&bsp, &bsp_size, pal, cmap, &err) == 0, "generate: %s", err.msg);
    if (bsp) {
        no_palette();
        bad_paks();
        kill_midway(SIGTERM, "SIGTERM");
        kill_midway(SIGINT, "SIGINT");
    }
    free(bsp);
    free(run_r);
    char cmd[400];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmpdir);
    return ew_t_finish();
}
