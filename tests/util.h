/* Tiny test harness shared by every tests/test_*.c (one ctest each). */
#ifndef EW_TEST_UTIL_H
#define EW_TEST_UTIL_H

#include "edgewise.h"
#include <stdio.h>

extern int ew_t_passed, ew_t_failed, ew_t_skipped;

/* EW_T_SANITIZED: 1 in a build under AddressSanitizer (gcc or clang), where
 * the slow tests check fewer views or rounds in the same way. */
#if defined(__SANITIZE_ADDRESS__)
#define EW_T_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define EW_T_SANITIZED 1
#endif
#endif
#ifndef EW_T_SANITIZED
#define EW_T_SANITIZED 0
#endif

/* CHECK(cond, fmt, ...): counts a pass, or prints the failure with its line. */
#define CHECK(cond, ...)                                                   \
    do {                                                                   \
        if (cond) {                                                        \
            ew_t_passed++;                                                 \
        } else {                                                           \
            ew_t_failed++;                                                 \
            fprintf(stderr, "FAIL %s:%d: %s: ", __FILE__, __LINE__, #cond); \
            fprintf(stderr, __VA_ARGS__);                                  \
            fputc('\n', stderr);                                           \
        }                                                                  \
    } while (0)

/* Path of a file under ../shared (EW_SHARED overrides); static buffer. */
const char *ew_t_shared(const char *rel);
/* 1 if ../shared/<rel> exists. */
int ew_t_have_shared(const char *rel);
/* Prints "SKIP: <why>" and counts a skip: the part of the test that could
 * not run (a missing tool or data file).  ew_t_finish then exits 77, which
 * ctest reports as skipped (SKIP_RETURN_CODE), unless a check failed. */
void ew_t_skip(const char *fmt, ...);
/* 1 if ../shared/<rel> exists; else 0 after an ew_t_skip naming it. */
int ew_t_need_shared(const char *rel);
/* ew_t_shared made absolute, for a command run in another folder; static buffer. */
const char *ew_t_shared_abs(const char *rel);
/* Loads ../shared/data/librequake/maps/NAME.bsp with its palette and
 * colormap (free with ew_assets_destroy); NULL after a failed CHECK
 * naming the problem. */
ew_assets *ew_t_load_map(const char *name);
/* The map NAME ("builtin": the built-in world) as ew_t_load_map, in
 * *scene its entities (the built-in scene's for "builtin") and in views
 * (EW_MAX_VIEWS) its view set, *nviews of them (checked to be some); NULL
 * after a failed CHECK.  *scene may be NULL after a failed CHECK too. */
ew_assets *ew_t_load_map_scene(const char *name, ew_scene **scene, ew_camera *views, int *nviews);
/* ew_t_load_map_scene with a cloud of 2000 particles (radius 300, seed 11)
 * around the first view added to the scene, for the fog tests: NULL, with
 * nothing to free, after a failed CHECK. */
ew_assets *ew_t_load_map_cloud(const char *name, ew_scene **scene, ew_camera *views, int *nviews);
/* The bytes by which two renderers' last frames differ: w x h pixels, in
 * true colour (4 bytes a pixel, ew_frame_rgba) or 8-bit (ew_frame_pixels). */
long ew_t_frames_differ(const ew_renderer *x, const ew_renderer *y, int w, int h, int true_colour);
/* Prints "N passed, N failed, N skipped" and returns the process exit
 * code: 1 if a check failed, else 77 if anything was skipped, else 0. */
int ew_t_finish(void);

/* ---- running the edgewise command (EW_CLI, set by CMake) ---------------- */

typedef struct ew_t_run {
    int  status;      /* exit code, or -1 if it did not exit normally */
    int  signal;      /* the signal that killed it, 0 if none */
    char out[65536];  /* stdout */
    char err[8192];   /* stderr */
} ew_t_run;

/* Runs EW_CLI with args (NULL-terminated), no shell, in directory dir;
 * stdout and stderr go through files in dir (so a terminal-only progress
 * line stays off). */
void ew_t_run_cli(ew_t_run *r, const char *dir, const char *const *args);
int  ew_t_count_lines(const char *s);
/* Reads a text file into buf (at most size - 1 bytes, NUL-terminated; empty if unreadable). */
void ew_t_slurp(const char *path, char *buf, size_t size);
/* The number after "key": in a JSON text (true/false read as 1/0); NAN if absent. */
double ew_t_json_num(const char *json, const char *key);

/* The program name (or a path, if it has a '/') found on PATH, in out: 1,
 * or 0 if there is none. */
int ew_t_find_exe(const char *name, char *out, size_t n);

/* ---- files the tests write ------------------------------------------------ */

/* Writes n bytes to path: 0, or -1 if it could not. */
int ew_t_write_file(const char *path, const void *d, size_t n);
/* dir/rel in one of four rotating buffers (so two can be used in one call). */
const char *ew_t_in_dir(const char *dir, const char *rel);
/* Little-endian 32-bit numbers, as in a .bsp or .pak. */
uint32_t ew_t_le32(const uint8_t *p);
void ew_t_put_le32(uint8_t *p, uint32_t v);

#endif
