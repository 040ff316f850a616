/* A band's set-up, its spans and its scratch (hsr/hsr.h); the method's
 * own state hangs from ew_band.own (the edge scan's: hsr/active.h). */
#include "hsr/active.h"  /* ew_span_sink */

#include <stdlib.h>
#include <string.h>

/* Spans start small and grow on demand up to the budget, so many bands
 * cost little memory. */
#define FIRST_SPANS 4096

int ew_band_init(ew_band *b, int max_surfs, int max_spans) {
    b->has_spans = malloc((size_t)max_surfs);
    b->cap_spans = max_spans < FIRST_SPANS ? max_spans : FIRST_SPANS;
    b->spans = malloc(sizeof(ew_span) * b->cap_spans);
    b->max_spans = max_spans;
    return b->has_spans && b->spans ? 0 : -1;
}

void ew_band_free(ew_band *b) {
    if (b->own_ops) b->own_ops->free(b->own);
    b->own = NULL, b->own_ops = NULL;
    free(b->has_spans), free(b->spans);
    free(b->rowmark), free(b->scratch);
}

void ew_band_reset(ew_band *b) {
    b->dropped = 0;
    b->unsorted = 0;
    memset(b->counters, 0, sizeof b->counters);
    if (b->own_ops && b->own_ops->reset) b->own_ops->reset(b->own);
}

int ew_band_budget_full(const ew_band *b) {
    if (b->nspans >= b->max_spans) return 1;
    return b->own_ops && b->own_ops->full && b->own_ops->full(b->own);
}

int ew_band_grow_spans(ew_band *b) {
    if (b->cap_spans >= b->max_spans) return -1;
    int n = b->cap_spans * 2 > b->max_spans ? b->max_spans : b->cap_spans * 2;
    void *p = realloc(b->spans, sizeof(ew_span) * (size_t)n);
    if (!p) return -1;
    b->spans = p, b->cap_spans = n;
    return 0;
}

void *ew_band_scratch(ew_band *b, size_t bytes) {
    if (bytes <= b->scratch_bytes) return b->scratch;
    void *p = realloc(b->scratch, bytes);
    if (!p) return NULL;
    memset((char *)p + b->scratch_bytes, 0, bytes - b->scratch_bytes);
    b->scratch = p, b->scratch_bytes = bytes;
    return p;
}

/* A span for the methods that make them one at a time (through the band's fields). */
void ew_band_span(ew_band *b, int surf, int u0, int u1, int v) {
    ew_span_sink o = {b->spans, b->nspans, b->cap_spans, b->has_spans};
    ew_sink_span(b, &o, surf, u0, u1, v);
    b->nspans = o.n;
}
