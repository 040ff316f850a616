/* Fog by depth, as today's source ports draw worldspawn "fog": a colour
 * at view depth z moves towards the fog colour by 1 - exp(-(density z /
 * 64)^2).  In an 8-bit frame the fogged colour is the nearest palette
 * colour, from a table per fog level (light/blend.h).  The sky is fogged
 * half way, whatever its depth, as the ports do by default.
 *
 * The world is fogged span by span from the span's own 1/z, which is
 * linear along it, so its fog level only rises or only falls: the span
 * falls into runs of one level, each found from the level's 1/z threshold
 * (no divide unless 1/z lies within a hair of it), and a run is one table
 * row (8-bit) or one blend weight (true colour, four pixels at a time).
 * Each pixel takes the level the old whole-frame pass gave it (every
 * pixel's 1/z filled, then a divide per pixel): the same frames.
 *
 * In the normal frame (fog->fill) this is done in the span draw, a few
 * dozen spans at a time right after they are drawn, while their pixels
 * are in the cache; and where fog is whole the fog colour is all that
 * shows, so it is written instead of texels.  The fog pass after the
 * models then reads the z-buffer only where moving things may have drawn
 * nearer (the rows' deferred z-fill, zlo..zhi) and fogs what they drew by
 * its own depth.  Otherwise (debug views, the full z-fill) the pass fogs
 * everything, span by span likewise. */
#include "raster/zfill.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ew_simd.h"
/* Where the processor has more than SSE2 (asked at run time, the build
 * assumes only SSE2; ew_set_simd caps it): with AVX-512 VBMI a run's table
 * row in four registers, 64 pixels a lookup (the two-table byte permute);
 * true colour 16 pixels a blend with AVX-512, 8 with AVX2.  (An AVX2 table
 * row as sixteen byte shuffles of 16 entries was no faster than the
 * scalar lookups, 2026-12-06.) */
#if defined(__x86_64__) && defined(__GNUC__)
#define EW_FOG_AVX512 1
#include <immintrin.h>
#endif

int ew_fog_cpu_simd(void) {
#ifdef EW_FOG_AVX512
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw"))
        return __builtin_cpu_supports("avx512vbmi") ? EW_FOG_SIMD_VBMI : EW_FOG_SIMD_AVX512;
    if (__builtin_cpu_supports("avx2")) return EW_FOG_SIMD_AVX2;
#endif
    return EW_FOG_SIMD_BASE;
}

void ew_fog_levels(ew_fog *f) {
    int n = EW_FOG_QSTEPS;
    for (int i = 0; i <= n; i++) {
        double amount = 1.0 - exp(-(double)i / EW_FOG_QSCALE);
        f->level[i] = (uint8_t)lrint(amount * (EW_FOG_LEVELS - 1));
    }
    for (int i = n + 1; i < (int)sizeof f->level; i++) f->level[i] = 0;  /* never a level, only gathered past */
    f->sky_level = (EW_FOG_LEVELS - 1) / 2;
    f->simd = ew_fog_cpu_simd();
    /* The levels rise by at most one an entry, so each is reached. */
    for (int k = 0, i = 0; k <= EW_FOG_LEVELS; k++) {
        while (i <= n && f->level[i] < k) i++;
        f->first[k] = (uint16_t)i;  /* n + 1: never */
    }
}

void ew_fog_prepare(ew_span_ctx *draw, ew_frame *f, ew_blend *blend, int may_fill) {
    ew_fog *fog = &draw->fog;
    fog->table = NULL;
    fog->fill = 0;
    if (f->cfg.classic) return;
    const float *rgb = f->cfg.fog_density >= 0 ? f->cfg.fog_rgb : f->world->worldspawn.fog_rgb;
    float d = f->cfg.fog_density >= 0 ? f->cfg.fog_density : f->world->worldspawn.fog_density;
    if (!(d > 0)) return;
    for (int k = 0; k < 3; k++) fog->rgb[k] = (int)(rgb[k] * 255 + 0.5f);
    if (!(fog->table = ew_blend_fog(blend, rgb))) {  /* the 8-bit tables; also "fog on" in true colour */
        f->stats.dropped++;
        return;
    }
    fog->w = (d / 64) * (d / 64);
    /* Level >= k where q = w / zi^2 reaches first[k] / QSCALE, i.e. where
     * zi <= sqrt(QSCALE w / first[k]).  A float q is within a few parts in
     * 1e7 of the true one, so 1e-5 either side of the threshold decides it;
     * between, the level itself is computed. */
    for (int k = 0; k <= EW_FOG_LEVELS; k++) {
        double t = k == 0 ? INFINITY : fog->first[k] > EW_FOG_QSTEPS ? 0 : sqrt(EW_FOG_QSCALE * (double)fog->w / fog->first[k]);
        fog->zt[k] = (float)t;
        fog->zt_lo[k] = (float)(t * (1 - 1e-5));
        fog->zt_hi[k] = (float)(t * (1 + 1e-5));
    }
    if (f->target.bpp == 1) {
        fog->full = blend->fog_full;
        fog->full_px = blend->fog_full_colour;
    } else {  /* level 63 mixes by 256/256: the fog colour exactly */
        fog->full = EW_FOG_LEVELS - 1;
        fog->full_px = ew_rgba(fog->rgb[0], fog->rgb[1], fog->rgb[2]);
    }
    fog->fill = may_fill && fog->full < EW_FOG_LEVELS;
    fog->seg = 1 << draw->subdiv_shift;
}

/* ---- a span's 1/z: zi0 + i dz at its i-th pixel, as the z-fill writes it ---- */

static inline float line_zi(float zi0, float dz, int i) { return zi0 + (float)i * dz; }

/* The level at 1/z zi > 0 is at least k (1 <= k <= EW_FOG_LEVELS). */
static inline int at_least(const ew_fog *f, float zi, int k) {
    if (zi <= f->zt_lo[k]) return 1;
    if (zi > f->zt_hi[k]) return 0;
    return ew_fog_level(f, zi) >= k;
}

/* Along a line whose 1/z stays above 0 over [i, e), where the level at i is
 * below k and at e - 1 at least k (rise), or the other way round: the first
 * j in (i, e) past the change, from where the threshold falls (rdz: 1/dz),
 * checked there and by halving if that was off. */
static inline int line_flip(const ew_fog *f, float zi0, float dz, float rdz, int i, int e, int k, int rise) {
    int lo = i, hi = e - 1;  /* P(lo) false, P(hi) true; P(j): past the change */
#define P(j) (at_least(f, line_zi(zi0, dz, (j)), k) == rise)
    float t = (f->zt[k] - zi0) * rdz;  /* where 1/z crosses the threshold */
    int j = t > (float)lo && t < (float)hi ? (int)t + 1 : t <= (float)lo ? lo + 1 : hi;
    if (j > hi) j = hi;
    if (P(j)) {
        if (j - 1 == lo || !P(j - 1)) return j;
        hi = j - 1;
        if (hi - 1 == lo || !P(hi - 1)) return hi;
        hi--;
    } else {
        lo = j;
        if (P(lo + 1)) return lo + 1;
        lo++;
    }
    while (hi - lo > 1) {
        int mid = lo + (hi - lo) / 2;
        if (P(mid)) hi = mid;
        else lo = mid;
    }
#undef P
    return hi;
}

/* ---- fogging pixels ---- */

static inline void fog_px(const ew_fog *f, int bpp, uint8_t *row, int x, int k) {
    if (bpp == 1)
        row[x] = f->table[k * 256 + row[x]];
    else
        ew_set32(row, x, ew_fog_rgba(f, k, ew_get32(row, x)));
}

#ifdef EW_FOG_AVX512
/* p[x] = tab[p[x]] for n pixels: the row's low and high halves looked up
 * by the index's low 7 bits, the top bit choosing; the last pixels masked. */
__attribute__((target("avx512f,avx512bw,avx512vbmi"))) static void lut_vbmi(const uint8_t *tab, uint8_t *p, int n) {
    const __m512i t0 = _mm512_loadu_si512((const void *)tab), t1 = _mm512_loadu_si512((const void *)(tab + 64));
    const __m512i t2 = _mm512_loadu_si512((const void *)(tab + 128)), t3 = _mm512_loadu_si512((const void *)(tab + 192));
    for (int x = 0; x < n; x += 64) {
        const __mmask64 m = n - x >= 64 ? ~(__mmask64)0 : ((__mmask64)1 << (n - x)) - 1;
        const __m512i v = _mm512_maskz_loadu_epi8(m, p + x);
        const __m512i lo = _mm512_permutex2var_epi8(t0, v, t1), hi = _mm512_permutex2var_epi8(t2, v, t3);
        _mm512_mask_storeu_epi8(p + x, m, _mm512_mask_blend_epi8(_mm512_movepi8_mask(v), lo, hi));
    }
}

/* Eight pixels c + ((fog - c) a >> 8), as fog_run32's four-lane loop. */
__attribute__((target("avx2"))) static inline __m256i mix8(__m256i v, __m256i m, __m256i fa, __m256i alpha) {
    const __m256i zero = _mm256_setzero_si256();
    __m256i lo = _mm256_unpacklo_epi8(v, zero), hi = _mm256_unpackhi_epi8(v, zero);
    lo = _mm256_srli_epi16(_mm256_add_epi16(_mm256_mullo_epi16(lo, m), fa), 8);
    hi = _mm256_srli_epi16(_mm256_add_epi16(_mm256_mullo_epi16(hi, m), fa), 8);
    return _mm256_or_si256(_mm256_packus_epi16(lo, hi), alpha);
}

/* fog_run32's blend, 8 pixels at a time (n >= 8).  The last eight (which
 * may overlap the eight before) are read before anything is written, so
 * each pixel is blended once, from its own value. */
__attribute__((target("avx2"))) static void mix_avx2(uint8_t *p, int n, int a, const int rgb[3]) {
    const __m256i m = _mm256_set1_epi16((short)(256 - a));
    const __m256i fa = _mm256_set1_epi64x((long long)((uint64_t)(rgb[0] * a) | (uint64_t)(rgb[1] * a) << 16 |
                                                      (uint64_t)(rgb[2] * a) << 32));
    const __m256i alpha = _mm256_set1_epi32((int)ew_rgba(0, 0, 0));
    uint8_t *end = p + (size_t)(n - 8) * 4;
    const __m256i last = mix8(_mm256_loadu_si256((const __m256i *)end), m, fa, alpha);
    for (; p < end; p += 32)
        _mm256_storeu_si256((__m256i *)p, mix8(_mm256_loadu_si256((const __m256i *)p), m, fa, alpha));
    _mm256_storeu_si256((__m256i *)end, last);
}

/* Sixteen pixels c (256 - a) + fog a >> 8 channel by channel (c + ((fog -
 * c) a >> 8), as ew_fog_rgba): m = 256 - a and fa = fog a in 16-bit lanes
 * for the pixels the bytes' low and high unpacking gives (mlo, falo: the
 * first two of each four, mhi, fahi: the last two); alpha 255. */
__attribute__((target("avx512f,avx512bw"))) static inline __m512i blend16(__m512i v, __m512i mlo, __m512i mhi,
                                                                          __m512i falo, __m512i fahi) {
    const __m512i zero = _mm512_setzero_si512();
    __m512i lo = _mm512_unpacklo_epi8(v, zero), hi = _mm512_unpackhi_epi8(v, zero);
    lo = _mm512_srli_epi16(_mm512_add_epi16(_mm512_mullo_epi16(lo, mlo), falo), 8);
    hi = _mm512_srli_epi16(_mm512_add_epi16(_mm512_mullo_epi16(hi, mhi), fahi), 8);
    return _mm512_or_si512(_mm512_packus_epi16(lo, hi), _mm512_set1_epi32((int)ew_rgba(0, 0, 0)));
}

/* fog_run32's blend, 16 pixels at a time. */
__attribute__((target("avx512f,avx512bw"))) static void mix_avx512(uint8_t *p, int n, int a, const int rgb[3]) {
    const __m512i m = _mm512_set1_epi16((short)(256 - a));
    const __m512i fa = _mm512_set1_epi64((long long)((uint64_t)(rgb[0] * a) | (uint64_t)(rgb[1] * a) << 16 |
                                                     (uint64_t)(rgb[2] * a) << 32));
    for (int x = 0; x < n; x += 16) {
        const __mmask16 k = n - x >= 16 ? (__mmask16)0xFFFF : (__mmask16)((1u << (n - x)) - 1);
        const __m512i v = _mm512_maskz_loadu_epi32(k, p + (size_t)x * 4);
        _mm512_mask_storeu_epi32(p + (size_t)x * 4, k, blend16(v, m, m, fa, fa));
    }
}

/* fog_over's pixels [x, e) of a row, 16 at a time: those whose 1/z is not
 * the line's (something drawn over the world) fogged by their own depth,
 * each lane the scalar code's arithmetic (the same single-precision
 * multiply, add and divide), the level and the 8-bit table looked up by
 * four-byte gathers (both tables have three bytes to spare), the true-
 * colour blend fog_run32's with a weight a lane.  A model near the eye
 * covers a tenth of the frame (lqdm7's view 25 at 1920x1080: 196,000
 * pixels), each fogged with a divide and a lookup of its own. */
__attribute__((target("avx512f,avx512bw"))) static void over_avx512(const ew_fog *f, int bpp, uint8_t *row,
                                                                     const float *zr, int x, int e, int u, float zi0,
                                                                     float dz) {
    const __m512i lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    const __m512 vzi0 = _mm512_set1_ps(zi0), vdz = _mm512_set1_ps(dz), zero = _mm512_setzero_ps();
    const __m512 w = _mm512_set1_ps(f->w), qmax = _mm512_set1_ps(EW_FOG_QMAX), qscale = _mm512_set1_ps(EW_FOG_QSCALE);
    const __m512i qsteps = _mm512_set1_epi32(EW_FOG_QSTEPS), byte = _mm512_set1_epi32(0xFF);
    const __m512i zero16 = _mm512_setzero_si512(), c256 = _mm512_set1_epi16(256);
    const __m512i fog16 = _mm512_set1_epi64((long long)((uint64_t)f->rgb[0] | (uint64_t)f->rgb[1] << 16 |
                                                        (uint64_t)f->rgb[2] << 32));
    for (; x < e; x += 16) {
        const __mmask16 in = e - x >= 16 ? (__mmask16)0xFFFF : (__mmask16)((1u << (e - x)) - 1);
        const __m512 z = _mm512_maskz_loadu_ps(in, zr + x);
        const __m512 line = _mm512_add_ps(vzi0, _mm512_mul_ps(_mm512_cvtepi32_ps(_mm512_add_epi32(_mm512_set1_epi32(x - u), lane)), vdz));
        const __mmask16 over = _mm512_mask_cmp_ps_mask(_mm512_mask_cmp_ps_mask(in, z, line, _CMP_NEQ_UQ), z, zero, _CMP_GT_OQ);
        if (!over) continue;
        /* ew_fog_level: q = w / z^2, whole fog past QMAX (and for NaN) */
        const __m512 q = _mm512_div_ps(w, _mm512_mul_ps(z, z));
        const __mmask16 near = _mm512_mask_cmp_ps_mask(over, q, qmax, _CMP_LT_OQ);
        const __m512i idx = _mm512_mask_mov_epi32(qsteps, near, _mm512_cvttps_epi32(_mm512_mul_ps(q, qscale)));
        const __m512i k = _mm512_and_si512(_mm512_mask_i32gather_epi32(zero16, over, idx, f->level, 1), byte);
        const __mmask16 put = _mm512_mask_cmpgt_epi32_mask(over, k, zero16);
        if (!put) continue;
        if (bpp == 1) {
            const __m512i c = _mm512_cvtepu8_epi32(_mm512_castsi512_si128(_mm512_maskz_loadu_epi8((__mmask64)in, row + x)));
            const __m512i t = _mm512_mask_i32gather_epi32(zero16, put, _mm512_or_si512(_mm512_slli_epi32(k, 8), c),
                                                          f->table, 1);
            _mm512_mask_storeu_epi8(row + x, (__mmask64)put, _mm512_castsi128_si512(_mm512_cvtepi32_epi8(t)));
        } else {
            /* a = k 256 / 63 (fog_run32's weight): the quotient is an integer
             * only at k 0 and 63, elsewhere 1/63 or more from one, so the
             * float divide truncates to it */
            const __m512i a = _mm512_cvttps_epi32(
                _mm512_div_ps(_mm512_cvtepi32_ps(_mm512_slli_epi32(k, 8)), _mm512_set1_ps((float)(EW_FOG_LEVELS - 1))));
            const __m512i a2 = _mm512_or_si512(a, _mm512_slli_epi32(a, 16));
            const __m512i alo = _mm512_unpacklo_epi32(a2, a2), ahi = _mm512_unpackhi_epi32(a2, a2);
            uint8_t *p = row + (size_t)x * 4;
            const __m512i v = _mm512_maskz_loadu_epi32(put, p);
            _mm512_mask_storeu_epi32(p, put, blend16(v, _mm512_sub_epi16(c256, alo), _mm512_sub_epi16(c256, ahi),
                                                    _mm512_mullo_epi16(fog16, alo), _mm512_mullo_epi16(fog16, ahi)));
        }
    }
}
#endif

/* n pixels of one level k from p on. */
static void fog_run8(const ew_fog *f, uint8_t *p, int n, int k) {
    if (k <= 0) return;
    if (k >= f->full) {
        memset(p, (int)f->full_px, (size_t)n);
        return;
    }
    const uint8_t *tab = f->table + k * 256;
#ifdef EW_FOG_AVX512
    if (f->simd == EW_FOG_SIMD_VBMI && n >= 8) {
        lut_vbmi(tab, p, n);
        return;
    }
#endif
    int x = 0;
    for (; x + 4 <= n; x += 4) {  /* four loads before the stores, which might alias them */
        uint8_t a = tab[p[x]], b = tab[p[x + 1]], c = tab[p[x + 2]], d = tab[p[x + 3]];
        p[x] = a, p[x + 1] = b, p[x + 2] = c, p[x + 3] = d;
    }
    for (; x < n; x++) p[x] = tab[p[x]];
}

static void fill32(uint8_t *p, int n, uint32_t v) {
    for (int x = 0; x < n; x++) ew_set32(p, x, v);
}

static void fog_run32(const ew_fog *f, uint8_t *p, int n, int k) {
    if (k <= 0) return;
    if (k >= EW_FOG_LEVELS - 1) {
        fill32(p, n, f->full_px);
        return;
    }
    int x = 0;
#ifdef EW_FOG_AVX512
    if (f->simd >= EW_FOG_SIMD_AVX512 && n >= 4) {
        mix_avx512(p, n, k * 256 / (EW_FOG_LEVELS - 1), f->rgb);
        return;
    }
    if (f->simd == EW_FOG_SIMD_AVX2 && n >= 8) {
        mix_avx2(p, n, k * 256 / (EW_FOG_LEVELS - 1), f->rgb);
        return;
    }
#endif
#if EW_SIMD4
    /* c + ((fog - c) a >> 8) is (c (256 - a) + fog a) >> 8: both terms
     * fit 16 unsigned bits; alpha 255, as ew_rgba. */
    const int a = k * 256 / (EW_FOG_LEVELS - 1);
    const ew_v4i m = ew_v4i_set1_16(256 - a);
    const ew_v4i fa = ew_v4i_setr16(f->rgb[0] * a, f->rgb[1] * a, f->rgb[2] * a, 0, f->rgb[0] * a, f->rgb[1] * a,
                                    f->rgb[2] * a, 0);
    const ew_v4i alpha = ew_v4i_set1((int32_t)ew_rgba(0, 0, 0));
    for (; x + 4 <= n; x += 4) {
        ew_v4i v = ew_v4i_loadu(p + (size_t)x * 4);
        ew_v4i lo = ew_v4i_bytes_lo(v), hi = ew_v4i_bytes_hi(v);
        lo = EW_V4I_SRL16(ew_v4i_add16(ew_v4i_mullo16(lo, m), fa), 8);
        hi = EW_V4I_SRL16(ew_v4i_add16(ew_v4i_mullo16(hi, m), fa), 8);
        v = ew_v4i_or(ew_v4i_packus8(lo, hi), alpha);
        ew_v4i_storeu(p + (size_t)x * 4, v);
    }
#endif
    for (; x < n; x++) ew_set32(p, x, ew_fog_rgba(f, k, ew_get32(p, x)));
}

static inline void fog_run(const ew_fog *f, int bpp, uint8_t *row, int x, int n, int k) {
    if (bpp == 1) fog_run8(f, row + x, n, k);
    else fog_run32(f, row + (size_t)x * 4, n, k);
}

/* ---- a row's spans ---- */

/* A span's line and how its pixels are fogged. */
typedef struct fog_line {
    const ew_fog *f;
    int          bpp;
    uint8_t     *row;
    const float *zr;     /* the row's z-buffer */
    int          u;      /* the span's first column: the line's i = 0 */
    float        zi0, dz;
    int          sky;    /* the sky's own pixels take its level */
} fog_line;

/* Pixels [x0, x1) whose level on the line is k, where the z-buffer holds
 * what is nearest (zread): a pixel whose 1/z is not the line's belongs to
 * something drawn over it and goes by its own depth.  Returns the pixels
 * fogged (1/z above 0). */
static long fog_zread(const fog_line *l, int x0, int x1, int k) {
    long n = 0;
    for (int x = x0; x < x1; x++) {
        float z = l->zr[x];
        int kk = k;
        if (z != line_zi(l->zi0, l->dz, x - l->u)) {
            if (!(z > 0)) continue;
            kk = ew_fog_level(l->f, z);
        }
        if (kk > 0) fog_px(l->f, l->bpp, l->row, x, kk);
        n++;
    }
    return n;
}

/* The line's pixels [x0, x1), each by its own level (a line through 1/z 0,
 * or one whose level changes every few pixels). */
static long fog_each(const fog_line *l, int x0, int x1, int zread) {
    long n = 0;
    for (int x = x0; x < x1; x++) {
        float zi = line_zi(l->zi0, l->dz, x - l->u);
        if (zread && l->zr[x] != zi) {
            zi = l->zr[x];  /* something nearer */
        } else if (l->sky) {
            fog_px(l->f, l->bpp, l->row, x, l->f->sky_level);
            n++;
            continue;
        }
        if (!(zi > 0)) continue;
        int k = ew_fog_level(l->f, zi);
        if (k > 0) fog_px(l->f, l->bpp, l->row, x, k);
        n++;
    }
    return n;
}

/* Runs shorter than this on average: level by level costs more than pixel
 * by pixel. */
enum { MIN_RUN = 6 };

/* The line's pixels [x0, x1), run by run. */
static long fog_piece(const fog_line *l, int x0, int x1, int zread) {
    if (x0 >= x1) return 0;
    const ew_fog *f = l->f;
    if (l->sky) {
        if (zread) return fog_zread(l, x0, x1, f->sky_level);
        fog_run(f, l->bpp, l->row, x0, x1 - x0, f->sky_level);
        return x1 - x0;
    }
    int i = x0 - l->u, e = x1 - l->u;
    float za = line_zi(l->zi0, l->dz, i), ze = line_zi(l->zi0, l->dz, e - 1);
    if (!(za > 0 && ze > 0)) return fog_each(l, x0, x1, zread);
    int k = ew_fog_level(f, za), kend = ew_fog_level(f, ze);
    if (abs(kend - k) * MIN_RUN > e - i) return fog_each(l, x0, x1, zread);
    if (k == kend) {
        if (zread) return fog_zread(l, x0, x1, k);
        fog_run(f, l->bpp, l->row, x0, x1 - x0, k);
        return x1 - x0;
    }
    /* Where each level ends, all first: each from where 1/z crosses its
     * threshold, checked on both sides of it (by the level itself, or a
     * search, only where 1/z is within a hair of it), so no run waits on
     * the one before; then the runs. */
    const int rise = kend > k, nb = rise ? kend - k : k - kend;
    const float zi0 = l->zi0, dz = l->dz, rdz = 1.0f / dz;
    int end[EW_FOG_LEVELS];
    for (int q = 0; q < nb; q++) {
        const int m = rise ? k + 1 + q : k - q;  /* past it: level >= m (rise), < m (fall) */
        const float t = (f->zt[m] - zi0) * rdz;
        int j = t > (float)i && t < (float)(e - 1) ? (int)t + 1 : t <= (float)i ? i + 1 : e - 1;
        const float z1 = line_zi(zi0, dz, j), z0 = line_zi(zi0, dz, j - 1);
        const int sure = rise ? z1 <= f->zt_lo[m] && z0 > f->zt_hi[m] : z1 > f->zt_hi[m] && z0 <= f->zt_lo[m];
        end[q] = sure ? j : line_flip(f, zi0, dz, rdz, i, e, m, rise);
    }
    long n = 0;
    for (int q = 0; q <= nb; q++) {
        const int j = q < nb ? end[q] : e, kk = rise ? k + q : k - q;
        if (j <= i) continue;
        if (zread) n += fog_zread(l, l->u + i, l->u + j, kk);
        else fog_run(f, l->bpp, l->row, l->u + i, j - i, kk), n += j - i;
        i = j;
    }
    return n;
}

/* The span draw's choice (fog->fill): from which of span sp's pixels on
 * (its count: none) fog covers it whole and its fog colour is written
 * instead of what its drawer would draw.  The span is cut only after a
 * whole segment, where the drawer's steps up to the cut are those of the
 * whole span: the lit and liquid drawers aim a last segment at its own
 * last pixel, so one pixel past a segment; two-pass lighting at the next
 * segment's first, so at a segment's end. */
static int fill_from(const ew_fog *f, const ew_span *sp, const ew_surf_draw *d, float zi0, float dz) {
    const int kind = d->kind, full = f->full;
    if (kind != EW_DRAW_LIT && kind != EW_DRAW_TURB && kind != EW_DRAW_TWOPASS && kind != EW_DRAW_FLAT)
        return sp->count;
    float z1 = line_zi(zi0, dz, sp->count - 1);
    if (!(zi0 > 0 && z1 > 0) || !at_least(f, z1, full)) return sp->count;
    if (at_least(f, zi0, full)) return 0;
    int j = line_flip(f, zi0, dz, 1.0f / dz, 0, sp->count, full, 1), keep;
    if (kind == EW_DRAW_TWOPASS) keep = (j + 15) / 16 * 16;
    else if (kind == EW_DRAW_FLAT) keep = j;
    else keep = (j - 1 + f->seg - 1) / f->seg * f->seg + 1;
    return keep < sp->count ? keep : sp->count;
}

/* One span of a row whose z-buffer holds what is nearest over [lo, hi). */
static long fog_span(const ew_fog *f, const ew_target *t, const ew_span *sp, const ew_surf_draw *d, int lo,
                     int hi) {
    const ew_gradients *g = &d->g;
    fog_line l = {f, t->bpp, ew_target_at(t, 0, sp->v), ew_target_z(t, 0, sp->v), sp->u,
                  g->zi_u * sp->u + g->zi_v * sp->v + g->zi_0, g->zi_u, d->kind == EW_DRAW_SKY};
    int a = sp->u, e = sp->u + sp->count;
    /* What the span draw filled is done (outside the z-buffer's part). */
    int ef = f->fill && !l.sky ? sp->u + fill_from(f, sp, d, l.zi0, l.dz) : e;
    int za = lo > a ? lo : a, zb = hi < e ? hi : e;
    if (za >= zb) return fog_piece(&l, a, ef, 0) + (e - ef);
    long n = fog_piece(&l, a, za < ef ? za : ef, 0) + fog_piece(&l, za, zb, 1) + fog_piece(&l, zb, ef, 0);
    /* the filled pixels left out, counted as fogged */
    int skip = e - ef - (zb > ef ? zb - (za > ef ? za : ef) : 0);
    return n + skip;
}

/* A span of a sorted row fogged as it was drawn (fog->fill): what was
 * drawn over it within [lo, hi), where the z-buffer holds what is nearest
 * (a 1/z not the span's own), is fogged by its own depth.  (The span's own
 * pixels were counted as they were drawn.) */
static void fog_over(const ew_fog *f, const ew_target *t, const ew_span *sp, const ew_surf_draw *d, int lo, int hi) {
    const ew_gradients *g = &d->g;
    fog_line l = {f, t->bpp, ew_target_at(t, 0, sp->v), ew_target_z(t, 0, sp->v), sp->u,
                  g->zi_u * sp->u + g->zi_v * sp->v + g->zi_0, g->zi_u, d->kind == EW_DRAW_SKY};
    int a = lo > sp->u ? lo : sp->u, e = hi < sp->u + sp->count ? hi : sp->u + sp->count;
    int x = a;
#ifdef EW_FOG_AVX512
    if (f->simd >= EW_FOG_SIMD_AVX512) {
        over_avx512(f, l.bpp, l.row, l.zr, a, e, l.u, l.zi0, l.dz);
        return;
    }
#endif
#if EW_SIMD4
    /* Mostly the world's own 1/z: four compared at a time (each lane the
     * scalar's multiply and add), the rest looked at one by one. */
    const ew_v4f zi0 = ew_v4f_set1(l.zi0), dz = ew_v4f_set1(l.dz), zero = ew_v4f_set1(0.0f);
    for (; x + 4 <= e; x += 4) {
        const ew_v4f i = ew_v4i_to_f(ew_v4i_add(ew_v4i_set1(x - l.u), ew_v4i_setr(0, 1, 2, 3)));
        const ew_v4f z = ew_v4f_loadu(l.zr + x);
        const ew_v4f over = ew_v4f_and(ew_v4f_ne(z, ew_v4f_add(zi0, ew_v4f_mul(i, dz))), ew_v4f_gt(z, zero));
        if (!ew_v4f_mask(over)) continue;
        for (int k = x; k < x + 4; k++) {
            float zk = l.zr[k];
            if (zk == line_zi(l.zi0, l.dz, k - l.u) || !(zk > 0)) continue;
            int lev = ew_fog_level(f, zk);
            if (lev > 0) fog_px(f, l.bpp, l.row, k, lev);
        }
    }
#endif
    for (; x < e; x++) {
        float z = l.zr[x];
        if (z == line_zi(l.zi0, l.dz, x - l.u) || !(z > 0)) continue;
        int k = ew_fog_level(f, z);
        if (k > 0) fog_px(f, l.bpp, l.row, x, k);
    }
}

/* ---- the rows the old way: every pixel's depth from the z-buffer ---- */

/* Pixels [x0, x1) of a row by their depth (zi 0: nothing drawn there). */
static long fog_depths(const ew_fog *f, int bpp, float *zr, uint8_t *px, int x0, int x1) {
    long n = 0;
    for (int x = x0; x < x1; x++)
        if (zr[x] > 0) fog_px(f, bpp, px, x, ew_fog_level(f, zr[x])), n++;
    return n;
}

/* A row whose spans may overlap (a band left unsorted: painter's order, a
 * z-buffer's runs), its z filled: each pixel is fogged once, as the surface
 * of the last span over it (the one drawn on top), found by walking the
 * spans from the last and skipping pixels already done.  Fogging every
 * span's pixels would fog a pixel again for each polygon drawn over it. */
static long fog_unsorted(const ew_target *t, const ew_surf_draw *surf_draw, const ew_fog *fog, const ew_span *spans,
                         int nspans, uint8_t *done) {
    long n = 0;
    int v = spans[0].v;
    for (int i = nspans - 1; i >= 0; i--) {
        const ew_span *sp = &spans[i];
        for (int x = sp->u, end = sp->u + sp->count; x < end;) {
            while (x < end && done[x]) x++;
            int x0 = x;
            while (x < end && !done[x]) done[x++] = 1;
            if (x > x0) {
                ew_span one = {x0, v, x - x0, sp->surf};
                n += fog_span(fog, t, &one, &surf_draw[sp->surf], 0, t->width);
            }
        }
    }
    for (int i = 0; i < nspans; i++) memset(done + spans[i].u, 0, (size_t)spans[i].count);
    return n;
}

void ew_draw_fog(const ew_fog *fog, const ew_target *t, ew_zfill *zf, const ew_surf_draw *surf_draw,
                 const ew_rows *rows) {
    if (!fog->table) return;
    long n = 0;
    uint8_t *done = NULL;  /* unsorted rows: pixels fogged, allocated on the first */
    for (int y = rows->y0; y < rows->y1; y++) {
        if (zf->row_nspans[y] == 0) {  /* no spans (the reference method): depth everywhere */
            n += fog_depths(fog, t->bpp, ew_target_z(t, 0, y), ew_target_at(t, 0, y), 0, t->width);
            continue;
        }
        const ew_band *b = &zf->bands[zf->row_band[y]];
        const ew_span *spans = b->spans + zf->row_span0[y];
        int ns = zf->row_nspans[y];
        if (b->unsorted) {
            if (!done && !(done = calloc((size_t)t->width, 1))) {
                rows->stats->dropped++;
                break;
            }
            ew_zfill_rect(zf, 0, y, t->width, y + 1);
            n += fog_unsorted(t, surf_draw, fog, spans, ns, done);
            continue;
        }
        /* Spans in order: the z-buffer is read only where it was filled. */
        int lo = zf->all ? 0 : zf->zlo[y], hi = zf->all ? t->width : zf->zhi[y];
        if (fog->fill) {  /* the world fogged and counted as drawn: only what is over it */
            if (lo >= hi) continue;  /* nothing drawn over this row's world */
            for (int i = 0; i < ns; i++)  /* (a method's row need not run left to right) */
                if (spans[i].u < hi && spans[i].u + spans[i].count > lo) fog_over(fog, t, &spans[i], &surf_draw[spans[i].surf], lo, hi);
            continue;
        }
        for (int i = 0; i < ns; i++) n += fog_span(fog, t, &spans[i], &surf_draw[spans[i].surf], lo, hi);
    }
    free(done);
    rows->stats->fog_pixels += n;
}

/* ---- the span draw with whole fog left out ---- */

static void fill_px(const ew_target *t, int u, int v, int n, uint32_t px) {
    uint8_t *p = ew_target_at(t, u, v);
    if (t->bpp == 1) memset(p, (int)px, (size_t)n);
    else fill32(p, n, px);
}

/* The spans at most so many at a time: drawn, then fogged while their
 * pixels are at hand. */
enum { CHUNK = 64 };

long ew_fog_draw_spans(const ew_span_ctx *c, const ew_span *spans, int n, const ew_surf_draw *draw, int full_z,
                       int unsorted) {
    const ew_fog *f = &c->fog;
    const ew_target *t = c->target;
    long fogged = 0;
    for (int i0 = 0; i0 < n; i0 += CHUNK) {
        const int i1 = i0 + CHUNK < n ? i0 + CHUNK : n;
        int keep[CHUNK];  /* each span's pixels drawn, the rest filled */
        int from = i0;    /* spans [from, i) go to the drawers as they are */
        for (int i = i0; i < i1; i++) {
            const ew_span *sp = &spans[i];
            const ew_surf_draw *d = &draw[sp->surf];
            const ew_gradients *g = &d->g;
            int k = keep[i - i0] = fill_from(f, sp, d, g->zi_u * sp->u + g->zi_v * sp->v + g->zi_0, g->zi_u);
            if (k >= sp->count) continue;
            if (i > from) ew_draw_spans(c, spans + from, i - from, draw, full_z);
            from = i + 1;
            if (k > 0) {
                ew_span head = *sp;
                head.count = k;
                ew_draw_spans(c, &head, 1, draw, full_z);
            }
            fill_px(t, sp->u + k, sp->v, sp->count - k, f->full_px);
        }
        if (i1 > from) ew_draw_spans(c, spans + from, i1 - from, draw, full_z);
        /* An unsorted band's spans overlap: the fog pass finds each pixel's
         * top one. */
        if (unsorted) continue;
        for (int i = i0; i < i1; i++) {
            const ew_span *sp = &spans[i];
            const ew_surf_draw *d = &draw[sp->surf];
            const ew_gradients *g = &d->g;
            fog_line l = {f, t->bpp, ew_target_at(t, 0, sp->v), NULL, sp->u,
                          g->zi_u * sp->u + g->zi_v * sp->v + g->zi_0, g->zi_u, d->kind == EW_DRAW_SKY};
            fogged += fog_piece(&l, sp->u, sp->u + keep[i - i0], 0) + (sp->count - keep[i - i0]);
        }
    }
    return fogged;
}
