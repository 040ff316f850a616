/* The entity lump tokenizer and its number conversion (see entity_lump.h). */
#include "entity_lump.h"
#include "ew_util.h"

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Pairs are collected as offsets first: the arrays move while they grow. */
typedef struct span { int first, count; } span;

typedef struct parser {
    char   *buf;
    size_t  len, pos;
    int     line;
} parser;

/* Skips blanks and // comments; counts lines for the error messages. */
static void skip_space(parser *p) {
    while (p->pos < p->len) {
        char c = p->buf[p->pos];
        if (c == '\n') {
            p->line++;
            p->pos++;
        } else if ((unsigned char)c <= ' ') {
            p->pos++;
        } else if (c == '/' && p->pos + 1 < p->len && p->buf[p->pos + 1] == '/') {
            while (p->pos < p->len && p->buf[p->pos] != '\n')
                p->pos++;
        } else {
            return;
        }
    }
}

/* At a '"': NUL-terminates the string in place and returns its start, or
 * NULL if the closing quote is missing on this line. */
static const char *read_quoted(parser *p) {
    size_t start = p->pos + 1, q = start;
    while (q < p->len && p->buf[q] != '"' && p->buf[q] != '\n' && p->buf[q] != '\r')
        q++;
    if (q >= p->len || p->buf[q] != '"')
        return NULL;
    p->buf[q] = '\0';
    p->pos = q + 1;
    return p->buf + start;
}

/* Grows *arr (of elem-sized items) so index n fits. */
static int grow(void **arr, int *cap, int n, size_t elem) {
    if (n < *cap)
        return 0;
    if (*cap > INT_MAX / 2)
        return -1;
    int ncap = *cap ? *cap * 2 : 64;
    void *na = realloc(*arr, (size_t)ncap * elem);
    if (!na)
        return -1;
    *arr = na;
    *cap = ncap;
    return 0;
}

int ew_entities_parse(const char *text, size_t len, ew_entities *out, ew_error *err) {
    memset(out, 0, sizeof *out);
    if (!text)
        len = 0;
    const char *nul = len ? memchr(text, '\0', len) : NULL;
    if (nul)
        len = (size_t)(nul - text);

    parser p = { malloc(len + 1), len, 0, 1 };
    if (!p.buf)
        return ew_fail(err, "entities: out of memory");
    if (len)
        memcpy(p.buf, text, len);
    p.buf[len] = '\0';

    ew_entity_pair *pairs = NULL;
    span *spans = NULL;
    int npairs = 0, cap_pairs = 0, nents = 0, cap_ents = 0;
    int rc = 0, open_first = -1;   /* first pair of the entity being read */
    const char *what = NULL;       /* syntax error, if any */

    for (;;) {
        skip_space(&p);
        if (p.pos >= p.len) {
            if (open_first >= 0)
                what = "end of text inside an entity (missing '}')";
            break;
        }
        char c = p.buf[p.pos];
        if (open_first < 0) {
            if (c != '{') {
                what = "expected '{'";
                break;
            }
            open_first = npairs;
            p.pos++;
        } else if (c == '}') {
            if (grow((void **)&spans, &cap_ents, nents, sizeof *spans) < 0) {
                rc = -1;
                break;
            }
            spans[nents].first = open_first;
            spans[nents].count = npairs - open_first;
            nents++;
            open_first = -1;
            p.pos++;
        } else if (c == '"') {
            const char *key = read_quoted(&p);
            if (!key) {
                what = "unterminated string";
                break;
            }
            skip_space(&p);
            if (p.pos >= p.len || p.buf[p.pos] != '"') {
                what = "expected a quoted value after the key";
                break;
            }
            const char *value = read_quoted(&p);
            if (!value) {
                what = "unterminated string";
                break;
            }
            if (grow((void **)&pairs, &cap_pairs, npairs, sizeof *pairs) < 0) {
                rc = -1;
                break;
            }
            pairs[npairs].key = key;
            pairs[npairs].value = value;
            npairs++;
        } else {
            what = "expected a quoted key or '}'";
            break;
        }
    }

    if (rc < 0) {
        free(p.buf);
        free(pairs);
        free(spans);
        return ew_fail(err, "entities: out of memory");
    }

    /* Only closed entities are kept; the spans become pointers now that the
     * pair array no longer moves. */
    ew_entity *ents = nents ? malloc((size_t)nents * sizeof *ents) : NULL;
    if (nents && !ents) {
        free(p.buf);
        free(pairs);
        free(spans);
        return ew_fail(err, "entities: out of memory");
    }
    for (int i = 0; i < nents; i++) {
        ents[i].pairs = pairs ? pairs + spans[i].first : NULL;
        ents[i].count = spans[i].count;
    }
    free(spans);
    out->ents = ents;
    out->count = nents;
    out->pairs = pairs;
    out->text = p.buf;
    if (what)
        return ew_fail(err, "entities: line %d: %s", p.line, what);
    return 0;
}

void ew_entities_free(ew_entities *e) {
    if (!e)
        return;
    free(e->ents);
    free(e->pairs);
    free(e->text);
    memset(e, 0, sizeof *e);
}

const char *ew_entity_get(const ew_entity *e, const char *key) {
    for (int i = e->count - 1; i >= 0; i--)
        if (strcmp(e->pairs[i].key, key) == 0)
            return e->pairs[i].value;
    return NULL;
}

int ew_entity_number(const char *s, const char **end, double lo, double hi, double *out) {
    char *e;
    double d = strtod(s, &e);
    *end = e;
    if (e == s)
        return -1;
    if (!isfinite(d) || d < lo || d > hi)
        return 0;
    *out = d;
    return 1;
}

int ew_entity_floats(const ew_entity *e, const char *key, float *v, int n) {
    for (int i = 0; i < n; i++)
        v[i] = 0;
    const char *s = ew_entity_get(e, key);
    if (!s)
        return 0;
    int got = 0;
    while (got < n) {
        double d = 0;
        if (ew_entity_number(s, &s, -FLT_MAX, FLT_MAX, &d) < 0)
            break;
        /* refused (inf, 1e300): 0, a camera built from it would only
         * poison the renderer */
        v[got++] = (float)d;
    }
    return got;
}

int ew_entity_int(const ew_entity *e, const char *key, int fallback) {
    const char *s = ew_entity_get(e, key);
    double d;
    if (!s || ew_entity_number(s, &s, INT_MIN, INT_MAX, &d) != 1)
        return fallback;
    return ew_int_checked(d, INT_MIN, INT_MAX, fallback);
}

int ew_entity_submodel(const ew_entity *e) {
    const char *s = ew_entity_get(e, "model");
    double d;
    if (!s || s[0] != '*' || ew_entity_number(s + 1, &s, 1, INT_MAX, &d) != 1 || *s ||
        d != floor(d))
        return -1;
    return ew_int_checked(d, 1, INT_MAX, -1);
}
