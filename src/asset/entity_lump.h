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

/* Reads up to n numbers separated by blanks from the value of key into v.
 * Missing, malformed or non-finite components are 0; returns how many
 * numbers were read (0 if the key is absent). */
int ew_entity_floats(const ew_entity *e, const char *key, float *v, int n);

#endif
