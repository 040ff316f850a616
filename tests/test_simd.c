/*
 * test_simd.c - src/ew_simd.h, the four-lane vectors that the span, sky,
 * item-box, fog and surface loops are written on, gives x86's bits in both
 * of its builds: every operation against a scalar statement of what it must
 * give (tests/simd_checks.h), on NaN, infinities, -0, +-2^31 and beyond,
 * 16- and 8-bit saturation.
 *
 *   - natively (SSE2 on x86-64; skipped where the processor has neither);
 *   - as WebAssembly SIMD: tests/simd_wasm_main.c compiled by emcc
 *     -msimd128 (one file, -sSINGLE_FILE) and run under node.  Skipped
 *     without emcc or node, which CI does not allow (.ci/run installs both).
 *
 * The web page's frames equal the native ones byte for byte (test_web) only
 * while these agree; this finds a disagreement on inputs no view reaches.
 */
#define _POSIX_C_SOURCE 200809L
#include "util.h"
#include "simd_checks.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

int main(void) {
#if EW_SIMD4
    int passed, failed = simd_checks(&passed);
    printf("native: %d checks passed, %d failed\n", passed, failed);
    CHECK(failed == 0 && passed > 10000, "native (SSE2): %d of %d checks failed", failed, failed + passed);
#else
    ew_t_skip("no four-lane backend on this processor (ew_simd.h: SSE2 or WebAssembly SIMD)");
#endif

    const char *src = getenv("EW_SOURCE");
    char emcc[1024], node[1024];
    if (!src) {
        ew_t_skip("EW_SOURCE not set (run through ctest)");
        return ew_t_finish();
    }
    if (!ew_t_find_exe("emcc", emcc, sizeof emcc)) {
        ew_t_skip("emcc not found (apt-get install emscripten): the WebAssembly half is not checked");
        return ew_t_finish();
    }
    if (!ew_t_find_exe("node", node, sizeof node)) {
        ew_t_skip("node not found (apt-get install nodejs): the WebAssembly half is not checked");
        return ew_t_finish();
    }
    char tmp[] = "/tmp/ew_simd_XXXXXX";
    if (!mkdtemp(tmp)) {
        CHECK(0, "mkdtemp failed");
        return ew_t_finish();
    }
    /* Debian's emcc runs its JavaScript optimiser under node with Debian's
     * acorn module (the Makefile's web target does the same). */
    const char *np = getenv("NODE_PATH");
    char cmd[6000], log[300], out[8192];
    snprintf(log, sizeof log, "%s/log", tmp);
    snprintf(cmd, sizeof cmd,
             "NODE_PATH='%s%s/usr/share/nodejs' '%s' -O2 -msimd128 -std=c11 -Wall -Wextra -I'%s/src' -I'%s/tests' "
             "'%s/tests/simd_wasm_main.c' -sSINGLE_FILE=1 -sENVIRONMENT=node -o '%s/simd.js' > '%s' 2>&1",
             np ? np : "", np ? ":" : "", emcc, src, src, src, tmp, log);
    int rc = system(cmd);
    ew_t_slurp(log, out, sizeof out);
    CHECK(rc == 0, "emcc failed: %s", out);
    if (rc == 0) {
        snprintf(cmd, sizeof cmd, "'%s' '%s/simd.js' > '%s' 2>&1", node, tmp, log);
        rc = system(cmd);
        ew_t_slurp(log, out, sizeof out);
        fputs(out, stdout);
        CHECK(rc == 0 && WIFEXITED(rc) && WEXITSTATUS(rc) == 0 && strstr(out, " 0 failed"),
              "WebAssembly SIMD: the checks failed (exit %d)", WIFEXITED(rc) ? WEXITSTATUS(rc) : -1);
    }
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmp);
    if (system(cmd) != 0) printf("note: could not remove %s\n", tmp);
    return ew_t_finish();
}
