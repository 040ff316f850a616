#include "util.h"

#include <stdlib.h>
#include <unistd.h>

int ew_t_passed, ew_t_failed;

const char *ew_t_shared(const char *rel) {
    static char buf[4][1024];
    static int next;
    const char *root = getenv("EW_SHARED");
    char *out = buf[next++ & 3];
    snprintf(out, 1024, "%s/%s", root && *root ? root : "../shared", rel);
    return out;
}

int ew_t_have_shared(const char *rel) { return access(ew_t_shared(rel), R_OK) == 0; }

int ew_t_finish(void) {
    printf("%d passed, %d failed\n", ew_t_passed, ew_t_failed);
    return ew_t_failed ? 1 : 0;
}
