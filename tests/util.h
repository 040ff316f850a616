/* Tiny test harness shared by every tests/test_*.c (one ctest each). */
#ifndef EW_TEST_UTIL_H
#define EW_TEST_UTIL_H

#include "edgewise.h"
#include <stdio.h>

extern int ew_t_passed, ew_t_failed;

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
/* Prints "N passed, N failed" and returns the process exit code. */
int ew_t_finish(void);

#endif
