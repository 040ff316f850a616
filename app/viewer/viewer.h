/*
 * viewer.h - edgewise view (app/viewer/viewer.c, built with SDL2 only;
 * cli/cmd_view_stub.c says it is missing otherwise).
 */
#ifndef EW_VIEWER_H
#define EW_VIEWER_H

/* edgewise view: argv[1] is "view".  Exit code: 0, 1 (error), 2 (usage). */
int cmd_view(int argc, char **argv);

#endif
