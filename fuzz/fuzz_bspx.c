/* libFuzzer entry for the bspx format; the body is shared with the
 * regression test (fuzz_targets.c). */
#include "fuzz_targets.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    ew_fuzz_bspx(data, size);
    return 0;
}
