/* Light styles as the game shows them.  A style's brightness follows a
 * pattern of letters, ten letters a second, looping: 'a' is dark, 'm' is
 * the light map as compiled ("normal"), 'z' a little over twice that.
 *
 * The scale: the engine multiplies (letter - 'a') by 22, so 'a' = 0,
 * 'm' = 264 and 'z' = 550, where 256 is the light map unscaled (a style
 * with no pattern at all is 256).
 *
 * The patterns of styles 0..11 are the ones every Quake mod's worldspawn
 * sets (game data, typed in here); 12..31 are normal; 32..63 are the
 * switchable styles the light compiler gives to targeted lights: on ("m")
 * unless a light entity using the style starts off ("a"). */
#include "light/light.h"
#include "ew_util.h"

#include <math.h>
#include <string.h>

static const char *const standard[12] = {
    "m",                                                    /*  0 normal */
    "mmnmmommommnonmmonqnmmo",                              /*  1 flicker */
    "abcdefghijklmnopqrstuvwxyzyxwvutsrqponmlkjihgfedcba",  /*  2 slow strong pulse */
    "mmmmmaaaaammmmmaaaaaabcdefgabcdefg",                   /*  3 candle */
    "mamamamamama",                                         /*  4 fast strobe */
    "jklmnopqrstuvwxyzyxwvutsrqponmlkj",                    /*  5 gentle pulse */
    "nmonqnmomnmomomno",                                    /*  6 flicker 2 */
    "mmmaaaabcdefgmmmmaaaammmaamm",                         /*  7 candle 2 */
    "mmmaaammmaaammmabcdefaaaammmmabcdefmmmaaaa",           /*  8 candle 3 */
    "aaaaaaaazzzzzzzz",                                     /*  9 slow strobe */
    "mmamammmmammamamaaamammma",                            /* 10 fluorescent flicker */
    "abcdefghijklmnopqrrqponmlkjihgfedcba",                 /* 11 slow pulse, not to black */
};

int ew_style_pattern_ok(const char *p) {
    if (!p) return 0;
    size_t n = 0;
    for (; p[n]; n++)
        if (p[n] < 'a' || p[n] > 'z' || n >= EW_STYLE_PATTERN_MAX) return 0;
    return n > 0;
}

int ew_style_letter_value(char c) { return (c - 'a') * 22; }

const char *ew_style_default_pattern(int style, uint64_t starts_off) {
    if (style >= 0 && style < 12) return standard[style];
    if (style >= 32 && style < 64 && (starts_off >> style & 1)) return "a";
    return "m";
}

/* The letter of pattern p shown at frame count `tick` (tenths of a second). */
static int pattern_value(const char *p, double tick) {
    double n = (double)strlen(p);
    double i = fmod(tick, n);
    if (i < 0) i += n;
    return ew_style_letter_value(p[ew_int_checked(i, 0, (int)n - 1, 0)]);
}

void ew_styles_frame(int out[64], const ew_style_setting set[64], uint64_t starts_off, int classic,
                     double time) {
    /* Tenths of a second, with a little slack so that a time written in
     * decimal ("--time 0.7", 0.69999999 as a float) lands on its letter. */
    double tick = floor(time * 10 + 1e-3);
    for (int s = 0; s < 64; s++) {
        const ew_style_setting *st = &set[s];
        if (st->mode == EW_STYLE_FIXED) out[s] = st->value;
        else if (st->mode == EW_STYLE_PATTERN) out[s] = pattern_value(st->pattern, tick);
        else if (classic) out[s] = 256;  /* the reference renders' conditions */
        else out[s] = pattern_value(ew_style_default_pattern(s, starts_off), tick);
    }
}
