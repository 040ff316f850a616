/*
 * cmd_view_stub.c - edgewise view in a build without SDL2: one line saying
 * so and a non-zero exit (the viewer itself is app/viewer/, built only when
 * CMake finds SDL2).
 */
#include "cli.h"

#ifndef EW_HAVE_SDL2
int cmd_view(int argc, char **argv) {
    (void)argc;
    (void)argv;
    error_line("view: this edgewise was built without SDL2 (install libsdl2-dev and rebuild)");
    return 1;
}
#else
/* The viewer is app/viewer/viewer.c. */
typedef int ew_cmd_view_stub_unused;
#endif
