/* TEMPORARY stub: the built-in scene owner deletes this file. */
#include "ew_util.h"
int ew_assets_builtin(ew_assets *o, ew_error *e) { (void)o; return ew_fail(e, "builtin: not implemented"); }
