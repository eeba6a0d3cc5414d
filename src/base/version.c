/* version.c: the build's version and commit (see version.h), passed by
 * the Makefile, which rebuilds this file alone when they change. */
#include "base/version.h"

#ifndef WS_VERSION
#define WS_VERSION "unknown"
#endif
#ifndef WS_COMMIT
#define WS_COMMIT "unknown"
#endif

const char *ws_version(void) { return WS_VERSION; }
const char *ws_build_commit(void) { return WS_COMMIT; }
