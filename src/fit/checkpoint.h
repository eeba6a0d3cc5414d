/* checkpoint.h: the state of a fit on disk, so that it can be resumed.
 *
 * DIR/checkpoint.bin holds the fit's command-line arguments (a resumed run
 * uses the same settings) and its whole ws_fit_state. Little-endian: magic
 * "WSKCKPT\0", u32 version, the arguments, the state, and a zlib crc32 of
 * everything before it as the last 4 bytes. It is written to a temporary
 * name and renamed, so a kill at any moment leaves the previous complete
 * checkpoint or the new one; a damaged file is refused, never half-used. */
#ifndef WS_CHECKPOINT_H
#define WS_CHECKPOINT_H
#include "fit/fit_state.h"

/* The most bytes a checkpoint may have: the reader refuses a larger file,
 * so the writer refuses to write one, and a fit checks before it starts
 * (ws_checkpoint_state_bytes) that its checkpoints will stay below. */
#define WS_CHECKPOINT_MAX_BYTES ((size_t)1 << 31)

/* The bytes of the state of a fit of n_curves curves and n_train training
 * views after log_rows steps that kept `snapshots` snapshots (what a
 * checkpoint holds but its header and arguments). */
double ws_checkpoint_state_bytes(int n_curves, int n_train, long log_rows, long snapshots);

int ws_checkpoint_save(const char *path, const ws_fit_state *s, int argc,
                       const char *const *argv, ws_status *st);

/* Reads the arguments (argv[0..argc) and the strings are allocated; free
 * with ws_checkpoint_free_args) and, when s is not NULL, the state. */
int ws_checkpoint_load(const char *path, ws_fit_state *s, int *argc, char ***argv,
                       ws_status *st);
void ws_checkpoint_free_args(int argc, char **argv);

#endif
