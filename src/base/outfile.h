/* outfile.h: output files that are never left half-written.
 *
 * Everything wiresketch writes goes to a temporary name beside the target
 * (PATH.tmp.PID) and is renamed onto PATH only after every byte was written,
 * flushed and synced; on failure the temporary file is removed. A reader
 * therefore sees the old file or the complete new one, never a fragment. */
#ifndef WS_OUTFILE_H
#define WS_OUTFILE_H
#include <stdio.h>
#include "base/paths.h"
#include "nn/base/status.h"

typedef struct {
    FILE *fp;
    char path[4096];
    char tmp[WS_PATH_MAX];
    int live; /* its slot in the registry of live temporary files, or -1 */
} ws_outfile;

/* Opens PATH.tmp.PID for writing ("wb") and registers it as live until
 * commit or abort. The first open in a directory (per process) removes the
 * stale temporary files there: NAME.tmp.PID whose PID is not a running
 * process on this machine (left by a run killed with SIGKILL). */
int ws_outfile_open(ws_outfile *f, const char *path, ws_status *st);
/* Flushes, syncs, closes and renames onto the target; checks every step
 * (a full disk shows up here). On failure the temporary file is removed. */
int ws_outfile_commit(ws_outfile *f, ws_status *st);
/* Closes and removes the temporary file; the target is untouched. */
void ws_outfile_abort(ws_outfile *f);

/* Installs handlers for SIGINT, SIGTERM, SIGHUP and SIGXCPU that remove every live
 * temporary file and then end the process by the same signal (as if
 * unhandled). A command may install its own (fit stops gracefully). */
void ws_outfile_remove_on_signals(void);
/* Removes every live temporary file; async-signal-safe. */
void ws_outfile_remove_live(void);

/* Creates directory `dir` (one level) unless it exists. */
int ws_mkdir(const char *dir, ws_status *st);

#endif
