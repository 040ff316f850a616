#define _POSIX_C_SOURCE 200809L
#include "ew_util.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

int ew_fail(ew_error *err, const char *fmt, ...) {
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->msg, sizeof err->msg, fmt, ap);
        va_end(ap);
    }
    return -1;
}

double ew_now_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

void ew_warn(char ***list, int *n, const char *fmt, ...) {
    if (*n >= EW_MAX_WARNINGS) return;
    char line[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    char **l = realloc(*list, sizeof *l * (size_t)(*n + 1));
    if (!l) return;
    *list = l;
    size_t len = strlen(line) + 1;
    if (!(l[*n] = malloc(len))) return;
    memcpy(l[*n], line, len);
    (*n)++;
}

void ew_warn_free(char **list, int n) {
    for (int i = 0; i < n; i++) free(list[i]);
    free(list);
}
