/*
 * --game DIR over --data DIR, as Quake's -game over id1: a search list
 * "GAME:BASE" of game directories (ew_fs_create), the first that has a
 * file gives it.
 *   - the library: a file in both comes from GAME, a file in BASE only
 *     from BASE, a file in neither is one error naming both; a missing
 *     directory in the list is an error naming it;
 *   - the command: lqdm3 (../shared/data/demos) with LibreQuake's models
 *     (../shared/data/librequake) draws every model, while the map's own
 *     folder alone misses some; every command that has --data has --game.
 */
#define _GNU_SOURCE
#include "util.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static void library(void) {
    char top[] = "/tmp/ew_game_XXXXXX";
    if (!mkdtemp(top)) {
        CHECK(0, "mkdtemp");
        return;
    }
    char game[512], base[512], list[1100];
    snprintf(game, sizeof game, "%s/mod", top);
    snprintf(base, sizeof base, "%s/id1", top);
    mkdir(game, 0755), mkdir(base, 0755);
    ew_t_write_file(ew_t_in_dir(game, "both.txt"), "game", 4);
    ew_t_write_file(ew_t_in_dir(base, "both.txt"), "base", 4);
    ew_t_write_file(ew_t_in_dir(base, "base.txt"), "only", 4);
    snprintf(list, sizeof list, "%s:%s", game, base);
    ew_error err = {{0}};
    ew_fs *fs = ew_fs_create(list, &err);
    CHECK(fs != NULL, "search list opens: %s", err.msg);
    if (fs) {
        uint8_t *d = NULL;
        size_t n = 0;
        CHECK(ew_fs_load(fs, "both.txt", &d, &n, &err) == 0 && n == 4 && memcmp(d, "game", 4) == 0,
              "a file in both comes from the game directory");
        free(d), d = NULL;
        CHECK(ew_fs_load(fs, "base.txt", &d, &n, &err) == 0 && n == 4 && memcmp(d, "only", 4) == 0,
              "a file in the base only comes from the base");
        free(d), d = NULL;
        CHECK(ew_fs_load(fs, "none.txt", &d, &n, &err) != 0 && strstr(err.msg, game) && strstr(err.msg, base),
              "a missing file names both directories: %s", err.msg);
        ew_fs_destroy(fs);
    }
    char bad[1100];
    snprintf(bad, sizeof bad, "%s/nowhere:%s", top, base);
    CHECK(ew_fs_create(bad, &err) == NULL && strstr(err.msg, "nowhere"), "a missing directory: %s", err.msg);
    CHECK(ew_fs_create("::", &err) == NULL, "an empty list entry is refused");
    remove(ew_t_in_dir(game, "both.txt")), remove(ew_t_in_dir(base, "both.txt")), remove(ew_t_in_dir(base, "base.txt"));
    rmdir(game), rmdir(base), rmdir(top);
}

static void command(void) {
    if (!ew_t_need_shared("data/demos/maps/lqdm3.bsp") || !ew_t_need_shared("data/librequake/progs")) return;
    char demos[1024], lq[1024];
    snprintf(demos, sizeof demos, "%s", ew_t_shared_abs("data/demos"));
    snprintf(lq, sizeof lq, "%s", ew_t_shared_abs("data/librequake"));
    char dir[] = "/tmp/ew_gamecli_XXXXXX";
    if (!mkdtemp(dir)) {
        CHECK(0, "mkdtemp");
        return;
    }
    ew_t_run run;
    const char *alone[] = {"render", "lqdm3", "--data", demos, "--view", "8", "--size", "320x200",
                           "--out", "f.png", "--stats", NULL};
    ew_t_run_cli(&run, dir, alone);
    double missing_alone = ew_t_json_num(run.out, "models_missing");
    CHECK(run.status == 0 && missing_alone > 0, "lqdm3 alone misses models (%g): %s", missing_alone, run.err);
    const char *mod[] = {"render", "lqdm3", "--game", demos, "--data", lq, "--view", "8", "--size", "320x200",
                         "--out", "f.png", "--stats", NULL};
    ew_t_run_cli(&run, dir, mod);
    double missing = ew_t_json_num(run.out, "models_missing");
    CHECK(run.status == 0 && missing == 0, "--game demos --data librequake: every model found (%g): %s",
          missing, run.err);
    const char *no_map[] = {"info", "lqdm3", "--data", lq, NULL};
    ew_t_run_cli(&run, dir, no_map);
    CHECK(run.status != 0 && ew_t_count_lines(run.err) == 1, "lqdm3 is not in librequake: %s", run.err);
    const char *info[] = {"info", "lqdm3", "--game", demos, "--data", lq, NULL};
    ew_t_run_cli(&run, dir, info);
    CHECK(run.status == 0 && strstr(run.out, "lqdm3"), "info through --game: %s", run.err);
    const char *colon[] = {"render", "lqdm3", "--game", "a:b", NULL};
    ew_t_run_cli(&run, dir, colon);
    CHECK(run.status != 0 && ew_t_count_lines(run.err) == 1, "--game with ':' is refused in one line: %s", run.err);
    const char *cmds[] = {"render", "views", "info", "bench", "hsr", "soak", "view", "shots", "fly", NULL};
    for (int i = 0; cmds[i]; i++) {
        const char *help[] = {cmds[i], "--help", NULL};
        ew_t_run_cli(&run, dir, help);
        if (!strcmp(cmds[i], "view") && strstr(run.err, "without SDL2")) {
            ew_t_skip("edgewise view was built without SDL2: its --help is not checked");
            continue;
        }
        CHECK(strstr(run.out, "--game") != NULL, "%s --help lists --game", cmds[i]);
    }
    remove(ew_t_in_dir(dir, "f.png"));
    rmdir(dir);
}

int main(void) {
    library();
    command();
    return ew_t_finish();
}
