#define _POSIX_C_SOURCE 200809L
#include "util.h"

#include <fcntl.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

int ew_t_passed, ew_t_failed, ew_t_skipped;

const char *ew_t_shared(const char *rel) {
    static char buf[4][1024];
    static int next;
    const char *root = getenv("EW_SHARED");
    char *out = buf[next++ & 3];
    snprintf(out, 1024, "%s/%s", root && *root ? root : "../shared", rel);
    return out;
}

int ew_t_have_shared(const char *rel) { return access(ew_t_shared(rel), R_OK) == 0; }

void ew_t_skip(const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    printf("SKIP: ");
    vprintf(fmt, ap);
    putchar('\n');
    va_end(ap);
    ew_t_skipped++;
}

int ew_t_need_shared(const char *rel) {
    if (ew_t_have_shared(rel)) return 1;
    ew_t_skip("%s not found (set EW_SHARED)", ew_t_shared(rel));
    return 0;
}

const char *ew_t_shared_abs(const char *rel) {
    static char out[2048];
    char cwd[1024] = "";
    const char *p = ew_t_shared(rel);
    if (p[0] != '/' && !getcwd(cwd, sizeof cwd)) cwd[0] = '\0';
    snprintf(out, sizeof out, "%s%s%s", cwd, cwd[0] ? "/" : "", p);
    return out;
}

ew_assets *ew_t_load_map(const char *name) {
    char rel[256];
    ew_error err;
    snprintf(rel, sizeof rel, "data/librequake/maps/%s.bsp", name);
    ew_assets *a = ew_assets_create(ew_t_shared(rel), NULL, &err);
    CHECK(a != NULL, "%s", err.msg);
    return a;
}

ew_assets *ew_t_load_map_scene(const char *name, ew_scene **scene, ew_camera *views, int *nviews) {
    ew_error err;
    ew_assets *a;
    *scene = NULL;
    if (!strcmp(name, "builtin")) {
        CHECK((a = ew_assets_create_builtin(&err)) != NULL, "builtin: %s", err.msg);
        if (!a) return NULL;
        *scene = ew_scene_create_builtin(a->world, &err);
    } else {
        if (!(a = ew_t_load_map(name))) return NULL;
        char rel[256];
        snprintf(rel, sizeof rel, "data/librequake/maps/%s.bsp", name);
        *scene = ew_scene_create_from_map(a->world, ew_t_shared(rel), NULL, &err);
    }
    CHECK(*scene != NULL, "%s: scene: %s", name, err.msg);
    *nviews = ew_benchmark_views(a->world, views);
    CHECK(*nviews > 0, "%s: no views", name);
    return a;
}

ew_assets *ew_t_load_map_cloud(const char *name, ew_scene **scene, ew_camera *views, int *nviews) {
    ew_assets *a = ew_t_load_map_scene(name, scene, views, nviews);
    if (!a || !*scene) {
        ew_scene_destroy(*scene);
        ew_assets_destroy(a);
        *scene = NULL;
        return NULL;
    }
    const float center[3] = {views[0].origin[0], views[0].origin[1], views[0].origin[2]};
    CHECK(ew_scene_add_particles(*scene, 2000, center, 300, 11) == 2000, "%s: particles", name);
    return a;
}

long ew_t_frames_differ(const ew_renderer *x, const ew_renderer *y, int w, int h, int true_colour) {
    const size_t bytes = (size_t)w * (size_t)h * (true_colour ? 4 : 1);
    const uint8_t *a = true_colour ? (const uint8_t *)ew_frame_rgba(x) : ew_frame_pixels(x);
    const uint8_t *b = true_colour ? (const uint8_t *)ew_frame_rgba(y) : ew_frame_pixels(y);
    long off = 0;
    for (size_t i = 0; i < bytes; i++) off += a[i] != b[i];
    return off;
}

int ew_t_finish(void) {
    printf("%d passed, %d failed, %d skipped\n", ew_t_passed, ew_t_failed, ew_t_skipped);
    return ew_t_failed ? 1 : ew_t_skipped ? 77 : 0;
}

void ew_t_slurp(const char *path, char *buf, size_t size) {
    buf[0] = '\0';
    FILE *f = fopen(path, "rb");
    if (!f) return;
    size_t n = fread(buf, 1, size - 1, f);
    buf[n] = '\0';
    fclose(f);
}

void ew_t_run_cli(ew_t_run *r, const char *dir, const char *const *args) {
    const char *cli = getenv("EW_CLI");
    const char *argv[64];
    int n = 0;
    argv[n++] = cli ? cli : "edgewise";
    for (; *args && n < 63; args++) argv[n++] = *args;
    argv[n] = NULL;
    char out[1024], err[1024];
    snprintf(out, sizeof out, "%s/stdout.txt", dir);
    snprintf(err, sizeof err, "%s/stderr.txt", dir);
    fflush(NULL);
    pid_t pid = fork();
    if (pid == 0) {
        int fo = open(out, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        int fe = open(err, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fo < 0 || fe < 0 || chdir(dir) != 0) _exit(127);
        dup2(fo, 1);
        dup2(fe, 2);
        execv(argv[0], (char *const *)argv);
        _exit(127);
    }
    int st = 0;
    r->status = -1;
    r->signal = 0;
    if (pid > 0 && waitpid(pid, &st, 0) == pid) {
        if (WIFEXITED(st)) r->status = WEXITSTATUS(st);
        else if (WIFSIGNALED(st)) r->signal = WTERMSIG(st);
    }
    ew_t_slurp(out, r->out, sizeof r->out);
    ew_t_slurp(err, r->err, sizeof r->err);
}

int ew_t_count_lines(const char *s) {
    int n = 0;
    for (; *s; s++) n += *s == '\n';
    return n;
}

double ew_t_json_num(const char *json, const char *key) {
    char k[128];
    snprintf(k, sizeof k, "\"%s\":", key);
    const char *p = strstr(json, k);
    if (!p) return NAN;
    p += strlen(k);
    if (strncmp(p, "true", 4) == 0) return 1;
    if (strncmp(p, "false", 5) == 0) return 0;
    char *end;
    double v = strtod(p, &end);
    return end == p ? NAN : v;
}

int ew_t_write_file(const char *path, const void *d, size_t n) {
    FILE *f = fopen(path, "wb");
    if (!f) return -1;
    int ok = fwrite(d, 1, n, f) == n;
    return fclose(f) == 0 && ok ? 0 : -1;
}

const char *ew_t_in_dir(const char *dir, const char *rel) {
    static char buf[4][512];
    static int k;
    k = (k + 1) % 4;
    snprintf(buf[k], sizeof buf[k], "%s/%s", dir, rel);
    return buf[k];
}

uint32_t ew_t_le32(const uint8_t *p) {
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

void ew_t_put_le32(uint8_t *p, uint32_t v) {
    for (int i = 0; i < 4; i++) p[i] = (uint8_t)(v >> (8 * i));
}

int ew_t_find_exe(const char *name, char *out, size_t n) {
    if (strchr(name, '/')) {
        snprintf(out, n, "%s", name);
        return access(out, X_OK) == 0;
    }
    const char *path = getenv("PATH");
    if (!path) return 0;
    char buf[4096];
    snprintf(buf, sizeof buf, "%s", path);
    for (char *save = NULL, *d = strtok_r(buf, ":", &save); d; d = strtok_r(NULL, ":", &save)) {
        snprintf(out, n, "%s/%s", d, name);
        if (access(out, X_OK) == 0) return 1;
    }
    return 0;
}
