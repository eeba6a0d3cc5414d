/* wiresketch.h: the public interface of libwiresketch, the one header a
 * program that embeds wiresketch includes (see tools/embed_example.c).
 *
 * Link build/libwiresketch.a or the shared library (`pkg-config --libs
 * wiresketch`: OpenBLAS, libpng, zlib, cJSON, giflib, libm, OpenMP).
 * Everything works on data in memory; files are optional. Every call that
 * can fail returns a code (WS_OK = 0) and fills a ws_status with a one-line
 * message naming the file and what is wrong.
 *
 * The interface is the headers included below and nothing else: `make
 * install` installs exactly these and the ones they include (the compiler
 * lists them), which tests/test_install.c checks file by file; the rest of
 * src/ and nn/ is internal and may change. Types whose layout a caller
 * needs (options, scenes, curves, results) are declared in full; the
 * others are opaque and made and freed by their own calls (ws_objective,
 * ws_loss, ws_clip_model). */
#ifndef WIRESKETCH_H
#define WIRESKETCH_H

/* Run time: ws_status and its codes, ws_malloc/ws_calloc (nn/base/status.h);
 * ws_runtime_init (threads, OpenBLAS's kernels) first, before any other
 * call, and ws_runtime_reexec_if_needed (OpenMP's waiting) before it. */
#include "nn/base/status.h"
#include "base/runtime.h"

/* Scene: views with cameras and photos at a working size (ws_scene_load),
 * images and PNG files, cameras. */
#include "io/scene.h"
#include "io/image.h"
#include "render/camera.h"

/* Curves: a sketch's cubic Beziers (ws_curves: load, save, random,
 * sample into Gaussians), the seeded generator they draw from, and the
 * splatting's options. */
#include "render/curves.h"
#include "nn/base/rng.h"
#include "render/splat.h"

/* Objective: the loss of a sketch in a view or a batch of views and its
 * gradient with respect to the control points (ws_objective), under the
 * loss's options (ws_loss_options: the terms and their weights). */
#include "objective/loss.h"
#include "objective/objective.h"

/* The CLIP model: loaded once and lent to losses (ws_loss_options.model). */
#include "objective/clip_model.h"

/* Fit: the whole optimisation into an output folder (ws_fit), resumable. */
#include "fit/fit.h"

/* Metrics: a sketch against ground-truth points or curves (ws_quality). */
#include "metrics/quality.h"

/* Export: curves as OBJ, PLY and SVG. */
#include "io/export.h"

#endif
