/* version.h: which build of wiresketch this is, for --version and the
 * record a fit keeps of itself (cli/run_record.h). */
#ifndef WS_VERSION_H
#define WS_VERSION_H

/* The release, "0.1.0" (the Makefile's VERSION). */
const char *ws_version(void);
/* The commit the program was built from, `git describe --always --dirty`
 * ("d267b48-dirty": uncommitted changes were built too), or "unknown" when
 * it was not built from a git checkout. */
const char *ws_build_commit(void);

#endif
