/* libFuzzer entry for demos (.dem); the body is shared with the
 * regression test (fuzz_targets.c). */
#include "fuzz_targets.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    ew_fuzz_demo(data, size);
    return 0;
}
