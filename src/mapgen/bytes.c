/* The map compiler's output buffer: little-endian values appended to a
 * growing byte array (a failed allocation sticks in b->failed and the
 * writer checks it once at the end).  Below every other mapgen file, so
 * the BSP, texture and MDL writers share it without calling each other. */
#include "mapgen_internal.h"

#include <stdlib.h>
#include <string.h>

void bi_put(bi_buf *b, const void *p, size_t n) {
    if (b->failed) return;
    if (b->len + n > b->cap) {
        size_t nc = b->cap ? b->cap : 4096;
        while (nc < b->len + n) nc *= 2;
        uint8_t *q = realloc(b->data, nc);
        if (!q) { b->failed = 1; return; }
        b->data = q, b->cap = nc;
    }
    if (n) memcpy(b->data + b->len, p, n);
    b->len += n;
}
void bi_put_zeros(bi_buf *b, size_t n) {
    static const uint8_t z[64];
    while (n) {
        size_t k = n < sizeof z ? n : sizeof z;
        bi_put(b, z, k);
        n -= k;
    }
}
void bi_put_u8(bi_buf *b, uint8_t v) { bi_put(b, &v, 1); }
void bi_put_u16(bi_buf *b, uint16_t v) {
    uint8_t q[2] = {(uint8_t)v, (uint8_t)(v >> 8)};
    bi_put(b, q, 2);
}
void bi_put_i16(bi_buf *b, int16_t v) { bi_put_u16(b, (uint16_t)v); }
void bi_put_i32(bi_buf *b, int32_t v) {
    uint32_t u = (uint32_t)v;
    uint8_t q[4] = {(uint8_t)u, (uint8_t)(u >> 8), (uint8_t)(u >> 16), (uint8_t)(u >> 24)};
    bi_put(b, q, 4);
}
void bi_put_f32(bi_buf *b, float v) {
    uint32_t u;
    memcpy(&u, &v, 4);
    bi_put_i32(b, (int32_t)u);
}
