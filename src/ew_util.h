/* Small helpers shared by every stage (internal). */
#ifndef EW_UTIL_H
#define EW_UTIL_H

#include "edgewise.h"
#include "edgewise_lab.h"  /* internal code sees the test calls too */
#include <math.h>
#include <stdint.h>
#include <string.h>

#if defined(__GNUC__)
#define EW_PRINTF(a, b) __attribute__((format(printf, a, b)))
#define EW_LIKELY(x) __builtin_expect(!!(x), 1)
#else
#define EW_PRINTF(a, b)
#define EW_LIKELY(x) (x)
#endif

/* (int)ceilf, (int)ceil and (int)floor, the same values, but by a
 * truncation and a compare where x is well inside int's range: without
 * SSE4.1 the compiler's inline rounding is some thirty instructions. */
static inline int ew_ceilf_int(float x) {
    if (EW_LIKELY(x > -2147483520.0f && x < 2147483520.0f)) {
        int i = (int)x;
        return i + (i < x);
    }
    return (int)ceilf(x);
}
static inline int ew_ceil_int(double x) {
    if (EW_LIKELY(x > -2147483647.0 && x < 2147483647.0)) {
        int i = (int)x;
        return i + (i < x);
    }
    return (int)ceil(x);
}
static inline int ew_floor_int(double x) {
    if (EW_LIKELY(x > -2147483647.0 && x < 2147483647.0)) {
        int i = (int)x;
        return i - (i > x);
    }
    return (int)floor(x);
}

/* The one checked float-to-int conversion for numbers a file or a caller
 * can make anything (entity and worldspawn values, light levels, radii,
 * times): x truncated toward zero and held to [lo, hi], NaN gives
 * fallback.  A bare (int) cast of NaN or of a value beyond int's range is
 * undefined behaviour (UBSan reports it; x86 gives INT_MIN). */
static inline int ew_int_checked(double x, int lo, int hi, int fallback) {
    if (x >= (double)lo && x <= (double)hi) return (int)x;
    if (x < (double)lo) return lo;
    if (x > (double)hi) return hi;
    return fallback;
}

/* Formats one error line into err (if non-NULL); always returns -1. */
int ew_fail(ew_error *err, const char *fmt, ...) EW_PRINTF(2, 3);

/* Little-endian reads from a byte buffer (callers check bounds first). */
static inline uint32_t ew_u32(const uint8_t *p) {
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
static inline int32_t ew_i32(const uint8_t *p) { return (int32_t)ew_u32(p); }
static inline uint16_t ew_u16(const uint8_t *p) { return (uint16_t)(p[0] | p[1] << 8); }
static inline int16_t ew_i16(const uint8_t *p) { return (int16_t)ew_u16(p); }
static inline float ew_f32(const uint8_t *p) {
    uint32_t u = ew_u32(p);
    float f;
    memcpy(&f, &u, 4);
    return f;
}

double ew_now_ms(void);  /* monotonic clock */

/* Warning lists (a world's, a scene's): appends one formatted line (at most
 * 64 kept; out of memory drops it); frees a list. */
#define EW_MAX_WARNINGS 64
void ew_warn(char ***list, int *n, const char *fmt, ...) EW_PRINTF(3, 4);
void ew_warn_free(char **list, int n);

/* Names in maps and paks compare without regard to ASCII case, as the game did. */
static inline int ew_lower(int c) { return c >= 'A' && c <= 'Z' ? c + 32 : c; }
static inline int ew_same_name(const char *a, const char *b) {
    for (; *a && *b; a++, b++)
        if (ew_lower((unsigned char)*a) != ew_lower((unsigned char)*b)) return 0;
    return *a == *b;
}

#endif
