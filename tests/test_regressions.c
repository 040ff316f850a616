/*
 * Every input the fuzzers ever crashed on (tests/regress/TARGET/NAME), run
 * again through the same code as its fuzz target (fuzz/fuzz_targets.c):
 * the loader, or load + render one frame.  Each must come back cleanly,
 * accepted or rejected with a message; under `make test-asan` ASan and
 * UBSan catch anything subtler.  New findings go in as small files
 * (libFuzzer's -minimize_crash=1) named after what they broke.
 *
 * tests/regress/fly_path holds the odd `edgewise fly --path` files of the
 * robustness campaigns (issue 36), run through the command (EW_CLI): each
 * says on a "# expect:" line whether it is accepted or refused at which
 * line; refused is one error line naming FILE:LINE, exit 1, and no output
 * file left.
 */
#define _POSIX_C_SOURCE 200809L
#include "util.h"
#include "fuzz_targets.h"
#include "ew_util.h"

#include <dirent.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static int by_name(const void *a, const void *b) {
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* Sorted names of the entries of dir (without . and ..); count in *n. */
static char **list_dir(const char *dir, int *n) {
    *n = 0;
    DIR *d = opendir(dir);
    if (!d) return NULL;
    char **names = NULL;
    int cap = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (e->d_name[0] == '.') continue;
        if (*n == cap) {
            cap = cap ? cap * 2 : 16;
            char **nn = realloc(names, sizeof *names * (size_t)cap);
            if (!nn) break;
            names = nn;
        }
        names[(*n)++] = strdup(e->d_name);
    }
    closedir(d);
    if (names) qsort(names, (size_t)*n, sizeof *names, by_name);
    return names;
}

static void free_list(char **names, int n) {
    for (int i = 0; i < n; i++) free(names[i]);
    free(names);
}

/* Every file of DIR through `edgewise fly builtin --path FILE`; the count. */
static int fly_paths(const char *dir) {
    char tmp[] = "/tmp/ew_regress_XXXXXX";
    if (!getenv("EW_CLI") || !mkdtemp(tmp)) {
        CHECK(0, "fly_path: no EW_CLI or no temporary folder");
        return 0;
    }
    ew_t_run *r = malloc(sizeof *r);
    int n, accepted = 0;
    char **files = list_dir(dir, &n);
    for (int i = 0; r && i < n; i++) {
        char path[2600], text[256], out[2700];
        snprintf(path, sizeof path, "%s/%s", dir, files[i]);
        ew_t_slurp(path, text, sizeof text);
        const char *e = strstr(text, "# expect: ");
        int line = 0, accept = e && !strncmp(e + 10, "accepted", 8);
        CHECK(accept || (e && sscanf(e + 10, "refused at line %d", &line) == 1),
              "%s: no '# expect: accepted' or '# expect: refused at line N' line", path);
        ew_t_run_cli(r, tmp, (const char *const[]){"fly", "builtin", "--size", "320x200", "--fps", "4", "--path",
                                                   path, "--out", "out.y4m", NULL});
        snprintf(out, sizeof out, "%s/out.y4m", tmp);
        int made = access(out, F_OK) == 0;
        unlink(out);
        if (accept) {
            CHECK(r->status == 0 && made, "%s: want it accepted, got exit %d: %s", path, r->status, r->err);
            accepted++;
        } else {
            char at[2700];
            snprintf(at, sizeof at, "edgewise: --path %s:%d: ", path, line);
            CHECK(r->status == 1 && ew_t_count_lines(r->err) == 1 && !strncmp(r->err, at, strlen(at)) && !made,
                  "%s: want exit 1, one line '%s...' and no output, got %d%s: %s", path, at, r->status,
                  made ? " and out.y4m" : "", r->err);
        }
    }
    printf("%-8s %3d inputs replayed cleanly (%d accepted, %d refused)\n", "fly_path", n, accepted, n - accepted);
    free_list(files, n);
    free(r);
    rmdir(tmp);
    return n;
}

/* The file at path through fn, or with fn NULL through the bsp29 or the
 * bsp2 target by its magic (*bsp2 says which), the target's status in
 * *rc: 0, or -1 (reported) where the file cannot be read.  Kept apart from
 * the status, so a target that returned -1 is still caught. */
static int replay(const char *path, ew_fuzz_fn fn, int *bsp2, int *rc) {
    uint8_t *data;
    size_t size;
    ew_error err = {""};
    if (ew_read_file(path, &data, &size, &err) != 0) {
        CHECK(0, "%s", err.msg);
        return -1;
    }
    if (!fn) {
        *bsp2 = size >= 4 && (!memcmp(data, "BSP2", 4) || !memcmp(data, "2PSB", 4));
        fn = *bsp2 ? ew_fuzz_bsp2 : ew_fuzz_bsp29;
    }
    *rc = fn(data, size);
    free(data);
    return 0;
}

/* The real maps of ../shared DIR (every .bsp) through the loader targets,
 * by their magic: each must be accepted.  The targets check the loaded
 * world against what ew_world.h promises, on their own, and abort where a
 * promise is broken; so where the loader's promise widens (texture extent
 * 0 since 71fbb43, for ericw-tools' faces) and those checks do not follow,
 * this fails, where a fuzzer would stop at its first such input and fuzz
 * nothing more.  The count of maps. */
static int real_maps(const char *rel) {
    if (!ew_t_need_shared(rel)) return 0;
    const char *dir = ew_t_shared(rel);
    char d[1024];
    snprintf(d, sizeof d, "%s", dir);
    int n, maps = 0;
    char **files = list_dir(d, &n);
    for (int i = 0; i < n; i++) {
        size_t len = strlen(files[i]);
        if (len < 4 || strcmp(files[i] + len - 4, ".bsp")) continue;
        char path[2100];
        snprintf(path, sizeof path, "%s/%s", d, files[i]);
        int bsp2 = 0, rc;
        if (replay(path, NULL, &bsp2, &rc) < 0) continue;
        CHECK(rc == 0, "%s: the %s target rejected a real map", path, bsp2 ? "bsp2" : "bsp29");
        maps++;
    }
    free_list(files, n);
    CHECK(maps > 0, "no .bsp in %s", d);
    printf("%-24s %3d real maps accepted, the loader's promises held\n", rel, maps);
    return maps;
}

int main(void) {
    const char *src = getenv("EW_SOURCE");
    char root[1024];
    snprintf(root, sizeof root, "%s/tests/regress", src && *src ? src : ".");
    int ntargets, total = 0;
    char **targets = list_dir(root, &ntargets);
    /* No inputs is a failure, not a pass: the folder is part of the source. */
    CHECK(targets != NULL && ntargets > 0, "no regression inputs: cannot read %s (EW_SOURCE=%s)", root,
          src ? src : "unset");

    for (int t = 0; t < ntargets; t++) {
        if (!strcmp(targets[t], "fly_path")) {  /* through the command, not a fuzz target */
            char dir[1300];
            snprintf(dir, sizeof dir, "%s/%s", root, targets[t]);
            total += fly_paths(dir);
            continue;
        }
        ew_fuzz_fn fn = ew_fuzz_target(targets[t]);
        CHECK(fn != NULL, "%s/%s: no fuzz target of that name", root, targets[t]);
        if (!fn) continue;
        if ((!strcmp(targets[t], "mdl") && !ew_fuzz_have_mdl) ||
            (!strcmp(targets[t], "spr") && !ew_fuzz_have_spr)) {
            ew_t_skip("%s: loader not in this build", targets[t]);
            continue;
        }
        char dir[1300];
        snprintf(dir, sizeof dir, "%s/%s", root, targets[t]);
        int n, accepted = 0;
        char **files = list_dir(dir, &n);
        CHECK(n > 0, "%s: no inputs", dir);
        for (int i = 0; i < n; i++) {
            char path[2600];
            snprintf(path, sizeof path, "%s/%s", dir, files[i]);
            int rc;
            if (replay(path, fn, NULL, &rc) < 0) continue;
            CHECK(rc == 0 || rc == 1, "%s: returned %d", path, rc);
            accepted += rc == 0;
        }
        printf("%-8s %3d inputs replayed cleanly (%d accepted, %d rejected)\n", targets[t], n,
               accepted, n - accepted);
        total += n;
        free_list(files, n);
    }
    free_list(targets, ntargets);
    printf("%d regression inputs\n", total);
    CHECK(total > 0, "no regression inputs under %s", root);

    real_maps("data/librequake/maps");
    real_maps("data/ericw/maps");
    real_maps("data/demos/maps");  /* lqdm3: faces of texture extent 0 */

    /* The dlight NaN (render/dlight_nan_plane.bin): plane 0's normal is
     * (2.4e21, -1.4e37, 1), finite but not a direction, and the dynamic
     * light's distances overflowed to NaN before an int conversion.  The
     * loader now refuses such a plane by name. */
    {
        char path[1100];
        snprintf(path, sizeof path, "%s/render/dlight_nan_plane.bin", root);
        uint8_t *data;
        size_t size;
        ew_error err = {""};
        if (ew_read_file(path, &data, &size, &err) != 0) {
            CHECK(0, "%s", err.msg);
        } else {
            ew_world *w = ew_world_create(data, size, "dlight_nan_plane.bin", &err);
            CHECK(w == NULL && strstr(err.msg, "plane 0: normal of length"),
                  "a plane normal of length 1.4e37 is refused by name (got \"%s\")", w ? "loaded" : err.msg);
            ew_world_destroy(w);
            free(data);
        }
    }
    /* The one checked float-to-int conversion: NaN is the fallback, the
     * rest truncates toward zero inside [lo, hi] and is held to it. */
    CHECK(ew_int_checked(NAN, -5, 5, 7) == 7, "NaN gives the fallback");
    CHECK(ew_int_checked(INFINITY, -5, 5, 7) == 5 && ew_int_checked(-1e300, -5, 5, 7) == -5,
          "beyond the range is held to it");
    CHECK(ew_int_checked(3.9, -5, 5, 7) == 3 && ew_int_checked(-3.9, -5, 5, 7) == -3,
          "inside the range truncates toward zero");
    CHECK(ew_int_checked(2147483647.9, 0, 2147483647, 0) == 2147483647 &&
          ew_int_checked(-2147483648.5, -2147483647 - 1, 0, 0) == -2147483647 - 1,
          "int's own ends");
    return ew_t_finish();
}
