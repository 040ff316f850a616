/* Four-lane vectors for the hand-written inner loops (internal): the
 * operations the span, sky, fog and surface loops use (32-bit lanes, and
 * 16-bit lanes in the same register), as SSE2 on x86-64 and as WebAssembly
 * SIMD in the browser build (emcc -msimd128), so one loop serves both.
 * EW_SIMD4 is 1 where one of them is there; otherwise the callers keep
 * their plain C loops.
 *
 * Every operation gives the same bits on both: min and max are SSE's
 * (a NaN operand gives the second one), ew_v4f_trunc is cvttps2dq's
 * (INT32_MIN for NaN and out of range), and lane-0 operations
 * (ew_v4f_div0) say nothing about the other lanes.  Emscripten's own SSE2
 * headers were not used: they turn cvttps into four scalar conversions
 * with range checks, which cost the browser build what SIMD gained. */
#ifndef EW_SIMD_H
#define EW_SIMD_H

#include <stdint.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#define EW_SIMD4 1
typedef __m128i ew_v4i;
typedef __m128 ew_v4f;
#define EW_V4_INLINE static inline __attribute__((always_inline))

EW_V4_INLINE ew_v4f ew_v4f_loadu(const float *p) { return _mm_loadu_ps(p); }
EW_V4_INLINE ew_v4f ew_v4f_set1(float x) { return _mm_set1_ps(x); }
EW_V4_INLINE ew_v4f ew_v4f_setr(float a, float b, float c, float d) { return _mm_setr_ps(a, b, c, d); }
EW_V4_INLINE ew_v4f ew_v4f_add(ew_v4f a, ew_v4f b) { return _mm_add_ps(a, b); }
EW_V4_INLINE ew_v4f ew_v4f_mul(ew_v4f a, ew_v4f b) { return _mm_mul_ps(a, b); }
EW_V4_INLINE ew_v4f ew_v4f_div(ew_v4f a, ew_v4f b) { return _mm_div_ps(a, b); }
/* x / b in lane 0 (the other lanes: anything). */
EW_V4_INLINE ew_v4f ew_v4f_div0(float x, ew_v4f b) { return _mm_div_ss(_mm_set_ss(x), b); }
EW_V4_INLINE ew_v4f ew_v4f_min(ew_v4f a, ew_v4f b) { return _mm_min_ps(a, b); }
EW_V4_INLINE ew_v4f ew_v4f_max(ew_v4f a, ew_v4f b) { return _mm_max_ps(a, b); }
/* Lane k of a in all four (k a constant). */
#define EW_V4F_SPLAT(a, k) _mm_shuffle_ps((a), (a), (k) * 0x55)
/* Truncated towards zero; INT32_MIN in a lane that is NaN or out of
 * range, as cvttps2dq gives it. */
EW_V4_INLINE ew_v4i ew_v4f_trunc(ew_v4f a) { return _mm_cvttps_epi32(a); }
EW_V4_INLINE ew_v4f ew_v4f_sub(ew_v4f a, ew_v4f b) { return _mm_sub_ps(a, b); }
EW_V4_INLINE ew_v4f ew_v4f_sqrt(ew_v4f a) { return _mm_sqrt_ps(a); }
EW_V4_INLINE void ew_v4f_storeu(float *p, ew_v4f a) { _mm_storeu_ps(p, a); }
/* Comparisons give all-ones lanes where true; a NaN lane compares false
 * except in ew_v4f_ne and ew_v4f_not_le. */
EW_V4_INLINE ew_v4f ew_v4f_gt(ew_v4f a, ew_v4f b) { return _mm_cmpgt_ps(a, b); }
EW_V4_INLINE ew_v4f ew_v4f_ne(ew_v4f a, ew_v4f b) { return _mm_cmpneq_ps(a, b); }
EW_V4_INLINE ew_v4f ew_v4f_not_le(ew_v4f a, ew_v4f b) { return _mm_cmpnle_ps(a, b); }
EW_V4_INLINE ew_v4f ew_v4f_and(ew_v4f a, ew_v4f b) { return _mm_and_ps(a, b); }
/* m ? a : b lane by lane, m a comparison's mask. */
EW_V4_INLINE ew_v4f ew_v4f_select(ew_v4f m, ew_v4f a, ew_v4f b) { return _mm_or_ps(_mm_and_ps(m, a), _mm_andnot_ps(m, b)); }
/* One bit a lane: the lanes' sign bits, lane 0 lowest. */
EW_V4_INLINE int ew_v4f_mask(ew_v4f a) { return _mm_movemask_ps(a); }
/* (prev3, a0, a1, a2): the last lane of prev carried in front of a. */
EW_V4_INLINE ew_v4f ew_v4f_carry(ew_v4f prev, ew_v4f a) {
    return _mm_shuffle_ps(_mm_shuffle_ps(prev, a, _MM_SHUFFLE(0, 0, 3, 3)), a, _MM_SHUFFLE(2, 1, 2, 0));
}
EW_V4_INLINE ew_v4f ew_v4i_to_f(ew_v4i a) { return _mm_cvtepi32_ps(a); }
EW_V4_INLINE ew_v4i ew_v4f_bits(ew_v4f a) { return _mm_castps_si128(a); }
EW_V4_INLINE ew_v4i ew_v4i_eq(ew_v4i a, ew_v4i b) { return _mm_cmpeq_epi32(a, b); }
/* All ones where a > b (signed). */
EW_V4_INLINE ew_v4i ew_v4i_gt(ew_v4i a, ew_v4i b) { return _mm_cmpgt_epi32(a, b); }
/* Bytes: all ones where equal. */
EW_V4_INLINE ew_v4i ew_v4i_eq8(ew_v4i a, ew_v4i b) { return _mm_cmpeq_epi8(a, b); }
/* ~m & a. */
EW_V4_INLINE ew_v4i ew_v4i_andnot(ew_v4i m, ew_v4i a) { return _mm_andnot_si128(m, a); }

EW_V4_INLINE ew_v4i ew_v4i_loadu(const void *p) { return _mm_loadu_si128((const __m128i *)p); }
EW_V4_INLINE void ew_v4i_storeu(void *p, ew_v4i a) { _mm_storeu_si128((__m128i *)p, a); }
EW_V4_INLINE ew_v4i ew_v4i_set1(int32_t x) { return _mm_set1_epi32(x); }
EW_V4_INLINE ew_v4i ew_v4i_setr(int32_t a, int32_t b, int32_t c, int32_t d) { return _mm_setr_epi32(a, b, c, d); }
EW_V4_INLINE ew_v4i ew_v4i_zero(void) { return _mm_setzero_si128(); }
/* x in lane 0, zeros above. */
EW_V4_INLINE ew_v4i ew_v4i_first(int32_t x) { return _mm_cvtsi32_si128(x); }
EW_V4_INLINE ew_v4i ew_v4i_add(ew_v4i a, ew_v4i b) { return _mm_add_epi32(a, b); }
EW_V4_INLINE ew_v4i ew_v4i_sub(ew_v4i a, ew_v4i b) { return _mm_sub_epi32(a, b); }
EW_V4_INLINE ew_v4i ew_v4i_and(ew_v4i a, ew_v4i b) { return _mm_and_si128(a, b); }
EW_V4_INLINE ew_v4i ew_v4i_or(ew_v4i a, ew_v4i b) { return _mm_or_si128(a, b); }
/* Signed lanes; SSE2 has these for 16 bits only. */
EW_V4_INLINE ew_v4i ew_v4i_max(ew_v4i a, ew_v4i b) {
    __m128i m = _mm_cmpgt_epi32(b, a);
    return _mm_or_si128(_mm_and_si128(m, b), _mm_andnot_si128(m, a));
}
EW_V4_INLINE ew_v4i ew_v4i_min(ew_v4i a, ew_v4i b) {
    __m128i m = _mm_cmpgt_epi32(a, b);
    return _mm_or_si128(_mm_and_si128(m, b), _mm_andnot_si128(m, a));
}
/* (a[i0], a[i1], a[i2], a[i3]), the indices constants. */
#define EW_V4I_SHUF(a, i0, i1, i2, i3) _mm_shuffle_epi32((a), _MM_SHUFFLE(i3, i2, i1, i0))
/* Lane k (a constant) as an integer. */
#define EW_V4I_LANE(a, k) ((k) == 0 ? _mm_cvtsi128_si32(a) : _mm_cvtsi128_si32(_mm_shuffle_epi32((a), (k) * 0x55)))
/* (0, a0, a1, a2): every lane moved up one. */
EW_V4_INLINE ew_v4i ew_v4i_up1(ew_v4i a) { return _mm_slli_si128(a, 4); }
/* (0, 0, a0, a1). */
EW_V4_INLINE ew_v4i ew_v4i_up2(ew_v4i a) { return _mm_slli_si128(a, 8); }
/* (a0, b0, a1, b1), (a2, b2, a3, b3) and (a0, a1, b0, b1). */
EW_V4_INLINE ew_v4i ew_v4i_zip_lo(ew_v4i a, ew_v4i b) { return _mm_unpacklo_epi32(a, b); }
EW_V4_INLINE ew_v4i ew_v4i_zip_hi(ew_v4i a, ew_v4i b) { return _mm_unpackhi_epi32(a, b); }
EW_V4_INLINE ew_v4i ew_v4i_lo_lo(ew_v4i a, ew_v4i b) { return _mm_unpacklo_epi64(a, b); }
/* Shifts by a constant count. */
#define EW_V4I_SRA(a, n) _mm_srai_epi32((a), (n))
#define EW_V4I_SRL(a, n) _mm_srli_epi32((a), (n))
/* The eight signed 32-bit lanes of a then b narrowed to 16 bits with
 * saturation, and the sums of adjacent 16-bit products (pmaddwd). */
EW_V4_INLINE ew_v4i ew_v4i_pack16(ew_v4i a, ew_v4i b) { return _mm_packs_epi32(a, b); }
EW_V4_INLINE ew_v4i ew_v4i_madd16(ew_v4i a, ew_v4i b) { return _mm_madd_epi16(a, b); }
/* 16-bit lane k (a constant), zero-extended. */
#define EW_V4I_U16(a, k) ((uint32_t)_mm_extract_epi16((a), (k)))

/* Eight 16-bit lanes in the same register, for the blends and the surface
 * builder: set, add, the low and (signed) high halves of products, shifts,
 * comparison, interleaving, and the bytes widened and narrowed. */
/* x's low 16 bits in all eight lanes (spelt out: gcc's _mm_set1_epi16 of a
 * variable took more registers in the surface builder's rows). */
EW_V4_INLINE ew_v4i ew_v4i_set1_16(int x) { return _mm_shuffle_epi32(_mm_shufflelo_epi16(_mm_cvtsi32_si128(x), 0), 0); }
EW_V4_INLINE ew_v4i ew_v4i_setr16(int a, int b, int c, int d, int e, int f, int g, int h) {
    return _mm_setr_epi16((short)a, (short)b, (short)c, (short)d, (short)e, (short)f, (short)g, (short)h);
}
EW_V4_INLINE ew_v4i ew_v4i_add16(ew_v4i a, ew_v4i b) { return _mm_add_epi16(a, b); }
EW_V4_INLINE ew_v4i ew_v4i_mullo16(ew_v4i a, ew_v4i b) { return _mm_mullo_epi16(a, b); }
EW_V4_INLINE ew_v4i ew_v4i_mulhi16(ew_v4i a, ew_v4i b) { return _mm_mulhi_epi16(a, b); }
#define EW_V4I_SLL16(a, n) _mm_slli_epi16((a), (n))
#define EW_V4I_SRL16(a, n) _mm_srli_epi16((a), (n))
EW_V4_INLINE ew_v4i ew_v4i_eq16(ew_v4i a, ew_v4i b) { return _mm_cmpeq_epi16(a, b); }
/* (a0, b0, a1, b1, a2, b2, a3, b3) and the same of lanes 4-7. */
EW_V4_INLINE ew_v4i ew_v4i_zip16_lo(ew_v4i a, ew_v4i b) { return _mm_unpacklo_epi16(a, b); }
EW_V4_INLINE ew_v4i ew_v4i_zip16_hi(ew_v4i a, ew_v4i b) { return _mm_unpackhi_epi16(a, b); }
/* Bytes 0-7 (8-15) of a zero-extended to 16-bit lanes. */
EW_V4_INLINE ew_v4i ew_v4i_bytes_lo(ew_v4i a) { return _mm_unpacklo_epi8(a, _mm_setzero_si128()); }
EW_V4_INLINE ew_v4i ew_v4i_bytes_hi(ew_v4i a) { return _mm_unpackhi_epi8(a, _mm_setzero_si128()); }
/* Sixteen signed 16-bit lanes (a's, then b's) to unsigned bytes, saturated. */
EW_V4_INLINE ew_v4i ew_v4i_packus8(ew_v4i a, ew_v4i b) { return _mm_packus_epi16(a, b); }
/* Eight bytes from p in the low half, zeros above; and an aligned load. */
EW_V4_INLINE ew_v4i ew_v4i_load8(const void *p) { return _mm_loadl_epi64((const __m128i *)p); }
EW_V4_INLINE ew_v4i ew_v4i_load(const void *p) { return _mm_load_si128((const __m128i *)p); }
/* (a2, a3, b2, b3). */
EW_V4_INLINE ew_v4i ew_v4i_hi_hi(ew_v4i a, ew_v4i b) { return _mm_unpackhi_epi64(a, b); }

#elif defined(__wasm_simd128__)
#include <wasm_simd128.h>
#define EW_SIMD4 1
typedef v128_t ew_v4i;
typedef v128_t ew_v4f;
#define EW_V4_INLINE static inline __attribute__((always_inline))

EW_V4_INLINE ew_v4f ew_v4f_loadu(const float *p) { return wasm_v128_load(p); }
EW_V4_INLINE ew_v4f ew_v4f_set1(float x) { return wasm_f32x4_splat(x); }
EW_V4_INLINE ew_v4f ew_v4f_setr(float a, float b, float c, float d) { return wasm_f32x4_make(a, b, c, d); }
EW_V4_INLINE ew_v4f ew_v4f_add(ew_v4f a, ew_v4f b) { return wasm_f32x4_add(a, b); }
EW_V4_INLINE ew_v4f ew_v4f_mul(ew_v4f a, ew_v4f b) { return wasm_f32x4_mul(a, b); }
EW_V4_INLINE ew_v4f ew_v4f_div(ew_v4f a, ew_v4f b) { return wasm_f32x4_div(a, b); }
EW_V4_INLINE ew_v4f ew_v4f_div0(float x, ew_v4f b) { return wasm_f32x4_div(wasm_f32x4_splat(x), b); }
/* SSE's minps and maxps: a < b ? a : b and a > b ? a : b (pmin and pmax
 * with the operands turned round). */
EW_V4_INLINE ew_v4f ew_v4f_min(ew_v4f a, ew_v4f b) { return wasm_f32x4_pmin(b, a); }
EW_V4_INLINE ew_v4f ew_v4f_max(ew_v4f a, ew_v4f b) { return wasm_f32x4_pmax(b, a); }
#define EW_V4F_SPLAT(a, k) wasm_i32x4_shuffle((a), (a), (k), (k), (k), (k))
/* trunc_sat gives 0 for NaN and saturates; x86 gives INT32_MIN for both. */
EW_V4_INLINE ew_v4i ew_v4f_trunc(ew_v4f a) {
    const v128_t ok = wasm_f32x4_lt(wasm_f32x4_abs(a), wasm_f32x4_splat(2147483648.0f));
    return wasm_v128_bitselect(wasm_i32x4_trunc_sat_f32x4(a), wasm_i32x4_splat(INT32_MIN), ok);
}
EW_V4_INLINE ew_v4f ew_v4f_sub(ew_v4f a, ew_v4f b) { return wasm_f32x4_sub(a, b); }
EW_V4_INLINE ew_v4f ew_v4f_sqrt(ew_v4f a) { return wasm_f32x4_sqrt(a); }
EW_V4_INLINE void ew_v4f_storeu(float *p, ew_v4f a) { wasm_v128_store(p, a); }
EW_V4_INLINE ew_v4f ew_v4f_gt(ew_v4f a, ew_v4f b) { return wasm_f32x4_gt(a, b); }
EW_V4_INLINE ew_v4f ew_v4f_ne(ew_v4f a, ew_v4f b) { return wasm_f32x4_ne(a, b); }
EW_V4_INLINE ew_v4f ew_v4f_not_le(ew_v4f a, ew_v4f b) { return wasm_v128_not(wasm_f32x4_le(a, b)); }
EW_V4_INLINE ew_v4f ew_v4f_and(ew_v4f a, ew_v4f b) { return wasm_v128_and(a, b); }
EW_V4_INLINE ew_v4f ew_v4f_select(ew_v4f m, ew_v4f a, ew_v4f b) { return wasm_v128_bitselect(a, b, m); }
EW_V4_INLINE int ew_v4f_mask(ew_v4f a) { return (int)wasm_i32x4_bitmask(a); }
EW_V4_INLINE ew_v4f ew_v4f_carry(ew_v4f prev, ew_v4f a) { return wasm_i32x4_shuffle(prev, a, 3, 4, 5, 6); }
EW_V4_INLINE ew_v4f ew_v4i_to_f(ew_v4i a) { return wasm_f32x4_convert_i32x4(a); }
EW_V4_INLINE ew_v4i ew_v4f_bits(ew_v4f a) { return a; }
EW_V4_INLINE ew_v4i ew_v4i_eq(ew_v4i a, ew_v4i b) { return wasm_i32x4_eq(a, b); }
EW_V4_INLINE ew_v4i ew_v4i_gt(ew_v4i a, ew_v4i b) { return wasm_i32x4_gt(a, b); }
EW_V4_INLINE ew_v4i ew_v4i_eq8(ew_v4i a, ew_v4i b) { return wasm_i8x16_eq(a, b); }
EW_V4_INLINE ew_v4i ew_v4i_andnot(ew_v4i m, ew_v4i a) { return wasm_v128_andnot(a, m); }

EW_V4_INLINE ew_v4i ew_v4i_loadu(const void *p) { return wasm_v128_load(p); }
EW_V4_INLINE void ew_v4i_storeu(void *p, ew_v4i a) { wasm_v128_store(p, a); }
EW_V4_INLINE ew_v4i ew_v4i_set1(int32_t x) { return wasm_i32x4_splat(x); }
EW_V4_INLINE ew_v4i ew_v4i_setr(int32_t a, int32_t b, int32_t c, int32_t d) { return wasm_i32x4_make(a, b, c, d); }
EW_V4_INLINE ew_v4i ew_v4i_zero(void) { return wasm_i32x4_splat(0); }
EW_V4_INLINE ew_v4i ew_v4i_first(int32_t x) { return wasm_i32x4_make(x, 0, 0, 0); }
EW_V4_INLINE ew_v4i ew_v4i_add(ew_v4i a, ew_v4i b) { return wasm_i32x4_add(a, b); }
EW_V4_INLINE ew_v4i ew_v4i_sub(ew_v4i a, ew_v4i b) { return wasm_i32x4_sub(a, b); }
EW_V4_INLINE ew_v4i ew_v4i_and(ew_v4i a, ew_v4i b) { return wasm_v128_and(a, b); }
EW_V4_INLINE ew_v4i ew_v4i_or(ew_v4i a, ew_v4i b) { return wasm_v128_or(a, b); }
EW_V4_INLINE ew_v4i ew_v4i_max(ew_v4i a, ew_v4i b) { return wasm_i32x4_max(a, b); }
EW_V4_INLINE ew_v4i ew_v4i_min(ew_v4i a, ew_v4i b) { return wasm_i32x4_min(a, b); }
#define EW_V4I_SHUF(a, i0, i1, i2, i3) wasm_i32x4_shuffle((a), (a), (i0), (i1), (i2), (i3))
#define EW_V4I_LANE(a, k) wasm_i32x4_extract_lane((a), (k))
EW_V4_INLINE ew_v4i ew_v4i_up1(ew_v4i a) { return wasm_i32x4_shuffle(wasm_i32x4_splat(0), a, 0, 4, 5, 6); }
EW_V4_INLINE ew_v4i ew_v4i_up2(ew_v4i a) { return wasm_i32x4_shuffle(wasm_i32x4_splat(0), a, 0, 1, 4, 5); }
EW_V4_INLINE ew_v4i ew_v4i_zip_lo(ew_v4i a, ew_v4i b) { return wasm_i32x4_shuffle(a, b, 0, 4, 1, 5); }
EW_V4_INLINE ew_v4i ew_v4i_zip_hi(ew_v4i a, ew_v4i b) { return wasm_i32x4_shuffle(a, b, 2, 6, 3, 7); }
EW_V4_INLINE ew_v4i ew_v4i_lo_lo(ew_v4i a, ew_v4i b) { return wasm_i32x4_shuffle(a, b, 0, 1, 4, 5); }
#define EW_V4I_SRA(a, n) wasm_i32x4_shr((a), (n))
#define EW_V4I_SRL(a, n) wasm_u32x4_shr((a), (n))
EW_V4_INLINE ew_v4i ew_v4i_pack16(ew_v4i a, ew_v4i b) { return wasm_i16x8_narrow_i32x4(a, b); }
EW_V4_INLINE ew_v4i ew_v4i_madd16(ew_v4i a, ew_v4i b) { return wasm_i32x4_dot_i16x8(a, b); }
#define EW_V4I_U16(a, k) ((uint32_t)wasm_u16x8_extract_lane((a), (k)))

EW_V4_INLINE ew_v4i ew_v4i_set1_16(int x) { return wasm_i16x8_splat((int16_t)x); }
EW_V4_INLINE ew_v4i ew_v4i_setr16(int a, int b, int c, int d, int e, int f, int g, int h) {
    return wasm_i16x8_make((int16_t)a, (int16_t)b, (int16_t)c, (int16_t)d, (int16_t)e, (int16_t)f, (int16_t)g, (int16_t)h);
}
EW_V4_INLINE ew_v4i ew_v4i_add16(ew_v4i a, ew_v4i b) { return wasm_i16x8_add(a, b); }
EW_V4_INLINE ew_v4i ew_v4i_mullo16(ew_v4i a, ew_v4i b) { return wasm_i16x8_mul(a, b); }
/* The high halves of the 32-bit products (pmulhw has no instruction here). */
EW_V4_INLINE ew_v4i ew_v4i_mulhi16(ew_v4i a, ew_v4i b) {
    return wasm_i16x8_shuffle(wasm_i32x4_extmul_low_i16x8(a, b), wasm_i32x4_extmul_high_i16x8(a, b), 1, 3, 5, 7, 9,
                              11, 13, 15);
}
#define EW_V4I_SLL16(a, n) wasm_i16x8_shl((a), (n))
#define EW_V4I_SRL16(a, n) wasm_u16x8_shr((a), (n))
EW_V4_INLINE ew_v4i ew_v4i_eq16(ew_v4i a, ew_v4i b) { return wasm_i16x8_eq(a, b); }
EW_V4_INLINE ew_v4i ew_v4i_zip16_lo(ew_v4i a, ew_v4i b) { return wasm_i16x8_shuffle(a, b, 0, 8, 1, 9, 2, 10, 3, 11); }
EW_V4_INLINE ew_v4i ew_v4i_zip16_hi(ew_v4i a, ew_v4i b) { return wasm_i16x8_shuffle(a, b, 4, 12, 5, 13, 6, 14, 7, 15); }
EW_V4_INLINE ew_v4i ew_v4i_bytes_lo(ew_v4i a) { return wasm_u16x8_extend_low_u8x16(a); }
EW_V4_INLINE ew_v4i ew_v4i_bytes_hi(ew_v4i a) { return wasm_u16x8_extend_high_u8x16(a); }
EW_V4_INLINE ew_v4i ew_v4i_packus8(ew_v4i a, ew_v4i b) { return wasm_u8x16_narrow_i16x8(a, b); }
EW_V4_INLINE ew_v4i ew_v4i_load8(const void *p) { return wasm_v128_load64_zero(p); }
EW_V4_INLINE ew_v4i ew_v4i_load(const void *p) { return wasm_v128_load(p); }
EW_V4_INLINE ew_v4i ew_v4i_hi_hi(ew_v4i a, ew_v4i b) { return wasm_i64x2_shuffle(a, b, 1, 3); }

#else
#define EW_SIMD4 0
#endif

#endif
