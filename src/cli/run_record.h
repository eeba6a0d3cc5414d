/* run_record.h: config.json, the record a fit keeps beside its outputs,
 * and what it takes to run the same fit again (`fit --config FILE`).
 *
 *   {"program": "wiresketch", "version": "0.1.0", "commit": "d267b48",
 *    "command_line": ["wiresketch", "fit", "SCENE", "--loss", "edges", ...],
 *    "scene": "SCENE",
 *    "settings": {"out": "DIR", "loss": "edges", "epochs": "auto", ...,
 *                 "quiet": false, "clip-conv-layer-weights": ["0", "0", "1", "1", "0"]}}
 *
 * settings holds every option of the run, defaults included, with the
 * value in effect (the loss `auto` chose, the defaults of that loss):
 * a flag as a boolean, a list as an array, everything else as the text
 * ws_arg_value gives, which reads back as the same value (numbers to 17
 * digits where 6 do not). The options that say what this invocation does
 * rather than what the fit is (--resume, --config, --overwrite) are left
 * out. version and commit are base/version.h's. This file owns the format. */
#ifndef WS_RUN_RECORD_H
#define WS_RUN_RECORD_H
#include "cli/args.h"
#include "io/report.h"

#define WS_RUN_RECORD_FILE "config.json"

/* 1 for --resume, --config and --overwrite, which are left out. */
int ws_run_record_invocation_option(const char *name);

/* Writes DIR/config.json (outfile.h) for a fit of `scene`: settings[k]
 * (name without "--", ws_arg_value's text) of kind kinds[k], k < n;
 * cmdline: the whole command line. */
int ws_run_record_write(const char *dir, const char *scene, int ncmdline, const char *const *cmdline,
                        const ws_report_item *settings, const ws_arg_kind *kinds, int n, ws_status *st);

/* The arguments after `fit` that run the recorded fit again: SCENE, then
 * --NAME VALUE for every setting (a flag's name when true, nothing when
 * false; an empty value, an option that was not given, is left out).
 * *argv and its strings are allocated; free with ws_run_record_free_args. */
int ws_run_record_read(const char *path, int *argc, char ***argv, ws_status *st);
void ws_run_record_free_args(int argc, char **argv);

/* WS_EUSAGE naming dir and the file when dir holds a fit's outputs (a
 * checkpoint, curves or a report); a config.json alone, of a run that
 * stopped before fitting, does not count. */
int ws_run_record_check_free(const char *dir, ws_status *st);

#endif
