/* The library's version (EW_VERSION of the header it was built with). */
#include "edgewise.h"

const char *ew_version(void) { return EW_VERSION; }
