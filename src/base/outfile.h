/* outfile.h: output files that are never left half-written and never
 * replace what the command reads.
 *
 * Everything wiresketch writes goes to a temporary file beside the target,
 * DIR/.wiresketch.tmp.PID.N.NAME, created new and exclusive (never opened
 * through a link or onto a file already there), and is renamed onto
 * DIR/NAME only after every byte was written, flushed and synced; on
 * failure the temporary file is removed. A reader therefore sees the old
 * file or the complete new one, never a fragment. A target that is a
 * character device, a FIFO or a socket (/dev/null, a named pipe,
 * /dev/stdout) is written through instead, never replaced; a directory or
 * a block device is refused.
 *
 * The command's inputs, named once with ws_outfile_protect, are never
 * replaced: an output file or folder that is one of them, or lies inside an
 * input folder (a scene), is refused, compared by device and inode so that
 * no other spelling (a link, "scene/../scene", a hard link) gets past. */
#ifndef WS_OUTFILE_H
#define WS_OUTFILE_H
#include <stdio.h>
#include "base/paths.h"
#include "nn/base/status.h"

typedef struct {
    FILE *fp;
    char path[WS_PATH_MAX];
    char tmp[WS_PATH_MAX]; /* "" when written through (streamed) */
    int live; /* its slot in the registry of live temporary files, or -1 */
} ws_outfile;

/* The inputs of the command, its files and its folders (NULL entries and
 * paths that do not exist are skipped), replacing those of an earlier
 * call: from now on ws_outfile_open and ws_mkdir refuse an output that is
 * one of them or lies inside one of the folders, with one line naming
 * both. At most WS_OUTFILE_MAX_INPUTS in all. */
#define WS_OUTFILE_MAX_INPUTS 16
int ws_outfile_protect(const char *const *files, int nfiles, const char *const *folders, int nfolders,
                       ws_status *st);
/* The same refusal for an output file or folder named on the command line,
 * checked before the work starts, so that a refused output costs nothing. */
int ws_outfile_check(const char *path, ws_status *st);

/* Opens a temporary file beside PATH for writing ("wb"; or PATH itself, a
 * character device, FIFO or socket, or a descriptor such as /dev/stdout)
 * and registers it as live until commit or abort. The first open in a
 * directory (per process) removes the stale temporary files there: only
 * files named .wiresketch.tmp.PID.N.NAME, owned by this user, whose PID is
 * no running process (left by a run killed with SIGKILL). */
int ws_outfile_open(ws_outfile *f, const char *path, ws_status *st);
/* Flushes, syncs, closes and renames onto the target; checks every step
 * (a full disk shows up here). On failure the temporary file is removed. */
int ws_outfile_commit(ws_outfile *f, ws_status *st);
/* Closes and removes the temporary file; the target is untouched (a
 * streamed target keeps what was written to it). */
void ws_outfile_abort(ws_outfile *f);

/* Installs handlers for SIGINT, SIGTERM, SIGHUP and SIGXCPU that remove every live
 * temporary file and then end the process by the same signal (as if
 * unhandled). A command may install its own (fit stops gracefully). */
void ws_outfile_remove_on_signals(void);

/* Creates directory `dir` (one level) unless it exists; a folder the user
 * named, so a symbolic link to a directory is used as one. Refused when it
 * is an input or lies inside an input folder (ws_outfile_protect). */
int ws_mkdir(const char *dir, ws_status *st);
/* The same for a folder the program names inside an output folder
 * (OUT/test, SCENE/rgb): a symbolic link there is refused, as it would send
 * the files somewhere the user did not ask for. */
int ws_mkdir_inside(const char *dir, ws_status *st);

#endif
