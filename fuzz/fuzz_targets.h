/*
 * One function per fuzzed input format (internal).  Each runs one input
 * through the same code path a real file takes and must return for any
 * bytes: 0 if the input was accepted, 1 if it was rejected with an error
 * message.  The libFuzzer targets (fuzz/fuzz_*.c) and the regression test
 * (tests/test_regressions.c) share these, so a kept crash input replays
 * exactly what the fuzzer ran.
 */
#ifndef EW_FUZZ_TARGETS_H
#define EW_FUZZ_TARGETS_H

#include <stddef.h>
#include <stdint.h>

typedef int (*ew_fuzz_fn)(const uint8_t *data, size_t size);

int ew_fuzz_pak(const uint8_t *data, size_t size);
int ew_fuzz_bsp29(const uint8_t *data, size_t size);
int ew_fuzz_bsp2(const uint8_t *data, size_t size);
int ew_fuzz_lmp(const uint8_t *data, size_t size);
int ew_fuzz_render(const uint8_t *data, size_t size);
int ew_fuzz_mdl(const uint8_t *data, size_t size);
int ew_fuzz_spr(const uint8_t *data, size_t size);
/* A demo (.dem): ew_demo_open_memory, then every block read into the
 * state, whose promises (indices, counts, strings) are checked. */
int ew_fuzz_demo(const uint8_t *data, size_t size);
/* A .lit image attached to the built-in map (plain, white light). */
int ew_fuzz_lit(const uint8_t *data, size_t size);
/* Byte 0 picks a base map written by the generator (0 RGBLIGHTING, 1
 * LMSHIFT 3, 2 LMSHIFT 5, 3 DECOUPLED_LM; its standard lumps); the rest is
 * the BSPX directory and lumps put after them. */
int ew_fuzz_bspx(const uint8_t *data, size_t size);
/* The generator's options for base map v of the BSPX target (0..3), and
 * where its BSPX part starts in the generated image (make_seeds cuts the
 * seeds there). */
struct ew_mapgen_options;
/* The base maps of the two light targets, made once (slow under the
 * fuzzer's instrumentation: their LLVMFuzzerInitialize calls these, so
 * the per-input timeout does not count them). */
void ew_fuzz_lit_init(void);
void ew_fuzz_bspx_init(void);
void   ew_fuzz_bspx_options(int v, struct ew_mapgen_options *o);
size_t ew_fuzz_bspx_cut(const uint8_t *bsp, size_t size);

/* 1 if the MDL/SPR loaders are part of this build (they are written
 * separately; until they exist those two targets reject everything). */
extern const int ew_fuzz_have_mdl, ew_fuzz_have_spr;

/* Target by name ("pak", "bsp29", ...), NULL if unknown. */
ew_fuzz_fn ew_fuzz_target(const char *name);

#endif
