/* simd_checks.h - every operation of src/ew_simd.h against a scalar
 * statement of what it must give (x86's SSE2 semantics, written out in
 * plain C), on inputs that reach the edges: NaN, infinities, -0, values
 * at and beyond +-2^31, 16-bit and 8-bit saturation, the one product
 * pmaddwd wraps.  Included by tests/test_simd.c, which runs it natively
 * (SSE2) and compiles it with emcc -msimd128 to run under node
 * (WebAssembly SIMD): the web page's frames equal the native ones only if
 * both backends give these same bits.
 *
 * simd_checks() returns the number of failures and prints each one (at
 * most 20), with *passed counting the checks that held. */
#ifndef EW_SIMD_CHECKS_H
#define EW_SIMD_CHECKS_H

#include "ew_simd.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#if EW_SIMD4

static int sc_failed, sc_passed;

static void sc_report(const char *op, int lane, uint32_t got, uint32_t want, const uint32_t *in, int nin) {
    if (got == want) {
        sc_passed++;
        return;
    }
    if (sc_failed++ < 20) {
        printf("FAIL %s lane %d: got %08x, want %08x; inputs", op, lane, got, want);
        for (int i = 0; i < nin; i++) printf(" %08x", in[i]);
        printf("\n");
    }
}

static uint32_t fbits(float f) {
    uint32_t u;
    memcpy(&u, &f, 4);
    return u;
}
static float bitsf(uint32_t u) {
    float f;
    memcpy(&f, &u, 4);
    return f;
}

/* Lanes in and out of vectors. */
static ew_v4f vf(const float *x) { return ew_v4f_loadu(x); }
static ew_v4i vi(const uint32_t *x) { return ew_v4i_loadu(x); }
static void outi(ew_v4i v, uint32_t o[4]) { ew_v4i_storeu(o, v); }
static void outf(ew_v4f v, uint32_t o[4]) {
    float f[4];
    ew_v4f_storeu(f, v);
    for (int i = 0; i < 4; i++) o[i] = fbits(f[i]);
}
static void check4(const char *op, const uint32_t got[4], const uint32_t want[4], const uint32_t *in, int nin) {
    for (int k = 0; k < 4; k++) sc_report(op, k, got[k], want[k], in, nin);
}
/* The eight 16-bit lanes of four 32-bit ones, and back. */
static void u16s(const uint32_t w[4], uint16_t h[8]) { memcpy(h, w, 16); }
static void w32s(const uint16_t h[8], uint32_t w[4]) { memcpy(w, h, 16); }

/* x86's cvttps2dq of one lane. */
static uint32_t ref_trunc(float x) {
    if (!(fabsf(x) < 2147483648.0f)) return 0x80000000u;
    return (uint32_t)(int32_t)x;
}
static int16_t sat16(int32_t x) { return (int16_t)(x > 32767 ? 32767 : x < -32768 ? -32768 : x); }
static uint8_t satu8(int16_t x) { return (uint8_t)(x > 255 ? 255 : x < 0 ? 0 : x); }

static const float sc_floats[] = {
    0.0f, -0.0f, 1.5f, -1.5f, 2.5f, -2.5f, 0.1f, -0.99f, 65535.99f, 1e9f, -1e9f, 2147483520.0f,
    2147483648.0f, -2147483648.0f, -2147483904.0f, 3e9f, -3e9f, 1e-40f, INFINITY, -INFINITY, NAN, 7.0f, -65536.0f,
    123456.789f,
};
static const uint32_t sc_ints[] = {
    0, 1, 0xffffffffu, 32767, 32768, 0xffff8000u, 0xffff7fffu, 65535, 65536, 0x7fffffffu, 0x80000000u, 0x7fff8000u,
    12345678, 0xfac68b4fu /* -87654321 */, 255, 256, 0x80008000u, 0x00ff00ffu, 0x12345678u, 0xdeadbeefu,
};
enum { NF = sizeof sc_floats / sizeof *sc_floats, NI = sizeof sc_ints / sizeof *sc_ints };

/* Every window of four inputs from a start, wrapping: each lane sees
 * every value, next to different neighbours. */
static void pick_f(int s, int stride, float o[4]) {
    for (int k = 0; k < 4; k++) o[k] = sc_floats[(s + k * stride) % NF];
}
static void pick_i(int s, int stride, uint32_t o[4]) {
    for (int k = 0; k < 4; k++) o[k] = sc_ints[(s + k * stride) % NI];
}

static void checks_float(void) {
    for (int s = 0; s < NF; s++)
        for (int t = 0; t < NF; t++) {
            float a[4], b[4];
            pick_f(s, 1, a);
            pick_f(t, 3, b);
            const ew_v4f A = vf(a), B = vf(b);
            uint32_t in[8], got[4], want[4];
            for (int k = 0; k < 4; k++) in[k] = fbits(a[k]), in[4 + k] = fbits(b[k]);
/* A NaN the operation makes may differ in sign and payload between x86 and
 * WebAssembly; the callers never keep one (their clamps and truncation
 * treat every NaN alike), so any NaN stands for any. */
#define F2(name, expr, ref)                                                            \
    do {                                                                               \
        outf(expr, got);                                                               \
        for (int k = 0; k < 4; k++) {                                                  \
            want[k] = fbits(ref);                                                      \
            if (isnan(bitsf(want[k])) && isnan(bitsf(got[k]))) got[k] = want[k];       \
        }                                                                              \
        check4(name, got, want, in, 8);                                                \
    } while (0)
            F2("add", ew_v4f_add(A, B), a[k] + b[k]);
            F2("sub", ew_v4f_sub(A, B), a[k] - b[k]);
            F2("mul", ew_v4f_mul(A, B), a[k] * b[k]);
            F2("div", ew_v4f_div(A, B), a[k] / b[k]);
            F2("min", ew_v4f_min(A, B), a[k] < b[k] ? a[k] : b[k]);
            F2("max", ew_v4f_max(A, B), a[k] > b[k] ? a[k] : b[k]);
#undef F2
#define M2(name, expr, cond)                                          \
    do {                                                              \
        outf(expr, got);                                              \
        for (int k = 0; k < 4; k++) want[k] = (cond) ? ~0u : 0u;      \
        check4(name, got, want, in, 8);                               \
    } while (0)
            M2("gt", ew_v4f_gt(A, B), a[k] > b[k]);
            M2("ne", ew_v4f_ne(A, B), !(a[k] == b[k]));
            M2("not_le", ew_v4f_not_le(A, B), !(a[k] <= b[k]));
#undef M2
            /* and, select on bits; the mask of a comparison */
            outf(ew_v4f_and(A, B), got);
            for (int k = 0; k < 4; k++) want[k] = in[k] & in[4 + k];
            check4("and", got, want, in, 8);
            const ew_v4f m = ew_v4f_gt(A, B);
            outf(ew_v4f_select(m, A, B), got);
            for (int k = 0; k < 4; k++) want[k] = a[k] > b[k] ? in[k] : in[4 + k];
            check4("select", got, want, in, 8);
            int mask = 0;
            for (int k = 0; k < 4; k++) mask |= (a[k] > b[k]) << k;
            sc_report("mask", 0, (uint32_t)ew_v4f_mask(m), (uint32_t)mask, in, 8);
            sc_report("mask of signs", 0, (uint32_t)ew_v4f_mask(A),
                      (in[0] >> 31) | (in[1] >> 31) << 1 | (in[2] >> 31) << 2 | (in[3] >> 31) << 3, in, 4);
            outf(ew_v4f_carry(A, B), got);
            want[0] = in[3], want[1] = in[4], want[2] = in[5], want[3] = in[6];
            check4("carry", got, want, in, 8);
            /* lane 0 of div0 only */
            outf(ew_v4f_div0(a[0], B), got);
            want[0] = fbits(a[0] / b[0]);
            if (isnan(bitsf(want[0])) && isnan(bitsf(got[0]))) got[0] = want[0];
            sc_report("div0", 0, got[0], want[0], in, 8);
        }
    for (int s = 0; s < NF; s++) {
        float a[4];
        pick_f(s, 5, a);
        const ew_v4f A = vf(a);
        uint32_t in[4], got[4], want[4];
        for (int k = 0; k < 4; k++) in[k] = fbits(a[k]);
        outi(ew_v4f_trunc(A), got);
        for (int k = 0; k < 4; k++) want[k] = ref_trunc(a[k]);
        check4("trunc", got, want, in, 4);
        outf(ew_v4f_sqrt(A), got);
        for (int k = 0; k < 4; k++) want[k] = fbits(sqrtf(a[k]));
        for (int k = 0; k < 4; k++)
            if (isnan(bitsf(want[k])) && isnan(bitsf(got[k]))) got[k] = want[k];
        check4("sqrt", got, want, in, 4);
        outi(ew_v4f_bits(A), got);
        check4("bits", got, in, in, 4);
        outf(ew_v4f_set1(a[0]), got);
        for (int k = 0; k < 4; k++) want[k] = in[0];
        check4("set1", got, want, in, 4);
        outf(ew_v4f_setr(a[0], a[1], a[2], a[3]), got);
        check4("setr", got, in, in, 4);
        outf(EW_V4F_SPLAT(A, 2), got);
        for (int k = 0; k < 4; k++) want[k] = in[2];
        check4("splat", got, want, in, 4);
    }
}

static void checks_int(void) {
    for (int s = 0; s < NI; s++)
        for (int t = 0; t < NI; t++) {
            uint32_t a[4], b[4], got[4], want[4], in[8];
            pick_i(s, 1, a);
            pick_i(t, 7, b);
            memcpy(in, a, 16), memcpy(in + 4, b, 16);
            const ew_v4i A = vi(a), B = vi(b);
#define I2(name, expr, ref)                                      \
    do {                                                         \
        outi(expr, got);                                         \
        for (int k = 0; k < 4; k++) want[k] = (uint32_t)(ref);   \
        check4(name, got, want, in, 8);                          \
    } while (0)
            I2("add", ew_v4i_add(A, B), a[k] + b[k]);
            I2("sub", ew_v4i_sub(A, B), a[k] - b[k]);
            I2("and", ew_v4i_and(A, B), a[k] & b[k]);
            I2("or", ew_v4i_or(A, B), a[k] | b[k]);
            I2("andnot", ew_v4i_andnot(A, B), ~a[k] & b[k]);
            I2("max", ew_v4i_max(A, B), (int32_t)a[k] > (int32_t)b[k] ? a[k] : b[k]);
            I2("min", ew_v4i_min(A, B), (int32_t)a[k] < (int32_t)b[k] ? a[k] : b[k]);
            I2("eq", ew_v4i_eq(A, B), a[k] == b[k] ? ~0u : 0u);
            I2("to_f", ew_v4f_bits(ew_v4i_to_f(A)), fbits((float)(int32_t)a[k]));
            I2("zip_lo", ew_v4i_zip_lo(A, B), (k & 1 ? b : a)[k >> 1]);
            I2("zip_hi", ew_v4i_zip_hi(A, B), (k & 1 ? b : a)[2 + (k >> 1)]);
            I2("lo_lo", ew_v4i_lo_lo(A, B), k < 2 ? a[k] : b[k - 2]);
            I2("hi_hi", ew_v4i_hi_hi(A, B), k < 2 ? a[2 + k] : b[k]);
            I2("up1", ew_v4i_up1(A), k ? a[k - 1] : 0u);
            I2("up2", ew_v4i_up2(A), k > 1 ? a[k - 2] : 0u);
            static const int order[4] = {3, 0, 2, 1};
            I2("shuf", EW_V4I_SHUF(A, 3, 0, 2, 1), a[order[k]]);
            I2("sra 4", EW_V4I_SRA(A, 4), (uint32_t)((int32_t)a[k] >> 4));
            I2("sra 31", EW_V4I_SRA(A, 31), (uint32_t)((int32_t)a[k] >> 31));
            I2("srl 16", EW_V4I_SRL(A, 16), a[k] >> 16);
            I2("srl 1", EW_V4I_SRL(A, 1), a[k] >> 1);
            I2("set1", ew_v4i_set1((int32_t)a[2]), a[2]);
            I2("setr", ew_v4i_setr((int32_t)a[0], (int32_t)a[1], (int32_t)a[2], (int32_t)a[3]), a[k]);
            I2("first", ew_v4i_first((int32_t)a[1]), k ? 0u : a[1]);
#undef I2
            sc_report("lane 0", 0, (uint32_t)EW_V4I_LANE(A, 0), a[0], in, 4);
            sc_report("lane 3", 3, (uint32_t)EW_V4I_LANE(A, 3), a[3], in, 4);
            /* 16-bit and 8-bit lanes */
            uint16_t ha[8], hb[8], hw[8];
            u16s(a, ha), u16s(b, hb);
            int16_t sw[8];
            int32_t pw[4];
            for (int k = 0; k < 4; k++) sw[k] = sat16((int32_t)a[k]), sw[4 + k] = sat16((int32_t)b[k]);
            outi(ew_v4i_pack16(A, B), got);
            w32s((const uint16_t *)(const void *)sw, want);
            check4("pack16", got, want, in, 8);
            for (int k = 0; k < 4; k++)
                pw[k] = (int32_t)((uint32_t)((int32_t)(int16_t)ha[2 * k] * (int16_t)hb[2 * k]) +
                                  (uint32_t)((int32_t)(int16_t)ha[2 * k + 1] * (int16_t)hb[2 * k + 1]));
            outi(ew_v4i_madd16(A, B), got);
            check4("madd16", got, (const uint32_t *)(const void *)pw, in, 8);
            const uint32_t u16[8] = {EW_V4I_U16(A, 0), EW_V4I_U16(A, 1), EW_V4I_U16(A, 2), EW_V4I_U16(A, 3),
                                     EW_V4I_U16(A, 4), EW_V4I_U16(A, 5), EW_V4I_U16(A, 6), EW_V4I_U16(A, 7)};
            for (int k = 0; k < 8; k++) sc_report("u16", k, u16[k], ha[k], in, 4);
#define H2(name, expr, ref)                                   \
    do {                                                      \
        for (int k = 0; k < 8; k++) hw[k] = (uint16_t)(ref);  \
        outi(expr, got);                                      \
        w32s(hw, want);                                       \
        check4(name, got, want, in, 8);                       \
    } while (0)
            H2("add16", ew_v4i_add16(A, B), ha[k] + hb[k]);
            H2("mullo16", ew_v4i_mullo16(A, B), (int32_t)(int16_t)ha[k] * (int16_t)hb[k]);
            H2("mulhi16", ew_v4i_mulhi16(A, B), ((int32_t)(int16_t)ha[k] * (int16_t)hb[k]) >> 16);
            H2("eq16", ew_v4i_eq16(A, B), ha[k] == hb[k] ? 0xffff : 0);
            H2("sll16 7", EW_V4I_SLL16(A, 7), ha[k] << 7);
            H2("srl16 8", EW_V4I_SRL16(A, 8), ha[k] >> 8);
            H2("zip16_lo", ew_v4i_zip16_lo(A, B), (k & 1 ? hb : ha)[k >> 1]);
            H2("zip16_hi", ew_v4i_zip16_hi(A, B), (k & 1 ? hb : ha)[4 + (k >> 1)]);
            H2("set1_16", ew_v4i_set1_16((int)a[1]), a[1]);
            H2("setr16", ew_v4i_setr16(ha[0], ha[1], ha[2], ha[3], ha[4], ha[5], ha[6], ha[7]), ha[k]);
            uint8_t ba[16], bw[16];
            memcpy(ba, a, 16);
            H2("bytes_lo", ew_v4i_bytes_lo(A), ba[k]);
            H2("bytes_hi", ew_v4i_bytes_hi(A), ba[8 + k]);
#undef H2
            for (int k = 0; k < 8; k++) bw[k] = satu8((int16_t)ha[k]), bw[8 + k] = satu8((int16_t)hb[k]);
            outi(ew_v4i_packus8(A, B), got);
            memcpy(want, bw, 16);
            check4("packus8", got, want, in, 8);
            uint8_t bb[16];
            memcpy(bb, b, 16);
            for (int k = 0; k < 16; k++) bw[k] = ba[k] == bb[k] ? 0xff : 0;
            outi(ew_v4i_eq8(A, B), got);
            memcpy(want, bw, 16);
            check4("eq8", got, want, in, 8);
            outi(ew_v4i_load8(a), got);
            want[0] = a[0], want[1] = a[1], want[2] = want[3] = 0;
            check4("load8", got, want, in, 4);
            _Alignas(16) uint32_t al[4];
            memcpy(al, a, 16);
            outi(ew_v4i_load(al), got);
            check4("load", got, a, in, 4);
        }
    uint32_t z[4], zero[4] = {0, 0, 0, 0};
    outi(ew_v4i_zero(), z);
    check4("zero", z, zero, zero, 0);
}

static int simd_checks(int *passed) {
    sc_failed = sc_passed = 0;
    checks_float();
    checks_int();
    *passed = sc_passed;
    return sc_failed;
}

#endif
#endif
