/*
 * The entity lump (internal): a list of entities, each a list of
 * "key" "value" pairs, in file order.
 *
 *   { "classname" "info_player_start" "origin" "0 0 24" "angle" "90" }
 *
 * Tokens outside quotes are '{', '}' and // comments (to the end of the
 * line).  Keys and values are double-quoted, may not span lines, and have no
 * escapes (a backslash is an ordinary character, as in map compilers).
 * Parsing stops at the first syntax error and keeps every entity closed
 * before it, so a damaged lump still yields what it can.
 */
#ifndef EW_ENTITY_LUMP_H
#define EW_ENTITY_LUMP_H

#include "edgewise.h"
#include <stddef.h>

typedef struct ew_entity_pair {
    const char *key, *value;
} ew_entity_pair;

typedef struct ew_entity {
    const ew_entity_pair *pairs;
    int                   count;
} ew_entity;

typedef struct ew_entities {
    ew_entity      *ents;
    int             count;
    ew_entity_pair *pairs;   /* storage behind every ents[i].pairs */
    char           *text;    /* storage behind every key and value */
} ew_entities;

/* Parses at most len bytes of text (less if a NUL comes first).  Returns 0,
 * or -1 with err set ("entities: line N: ...") on a syntax error, in which
 * case out still holds the entities closed before it, or on allocation
 * failure (out then empty).  Free out with ew_entities_free either way. */
int  ew_entities_parse(const char *text, size_t len, ew_entities *out, ew_error *err);
void ew_entities_free(ew_entities *e);

/* The value of key in e (the last one if the key repeats, as the game
 * does), or NULL. */
const char *ew_entity_get(const ew_entity *e, const char *key);

/* Numbers.  Every number taken from an entity lump goes through
 * ew_entity_number, the one checked conversion: a value like "1e30",
 * "nan" or "inf" must not reach a float-to-int cast or a camera (undefined
 * behaviour, or a poisoned frame), so anything not finite or outside the
 * range the caller can hold is refused and the caller uses its fallback.
 *
 * Reads one number (strtod's syntax, leading blanks skipped) at s and sets
 * *end past it.  Returns 1 with *out set if it is finite and within
 * [lo, hi]; 0 if a number was read but refused (*out untouched); -1 if
 * there is no number at s (*end = s). */
int ew_entity_number(const char *s, const char **end, double lo, double hi, double *out);

/* Reads up to n numbers separated by blanks from the value of key into v.
 * Missing, malformed, non-finite or beyond-float components are 0; returns
 * how many numbers were read (0 if the key is absent). */
int ew_entity_floats(const ew_entity *e, const char *key, float *v, int n);

/* The first number of the value of key as an int (truncated toward zero),
 * or fallback if the key is absent, holds no number, or the number is not
 * finite or outside int's range ("spawnflags" "1e30"). */
int ew_entity_int(const ew_entity *e, const char *key, int fallback);

/* The submodel an entity's "model" "*N" names: N >= 1, or -1 if the key is
 * absent or not a '*' followed by exactly a positive int. */
int ew_entity_submodel(const ew_entity *e);

#endif
