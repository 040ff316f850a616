/* simd_wasm_main.c - tests/simd_checks.h as a program of its own, which
 * test_simd.c compiles with emcc -msimd128 and runs under node: src/ew_simd.h's
 * WebAssembly half against the same scalar statements as the SSE2 half. */
#include "simd_checks.h"

int main(void) {
#if EW_SIMD4
    int passed, failed = simd_checks(&passed);
    printf("wasm: %d checks passed, %d failed\n", passed, failed);
    return failed ? 1 : 0;
#else
    printf("wasm: no four-lane backend (built without -msimd128?)\n");
    return 2;
#endif
}
