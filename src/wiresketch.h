/* wiresketch.h: the public interface of libwiresketch.
 *
 * A C program that embeds wiresketch includes this header and links
 * build/libwiresketch.a (plus OpenBLAS, libpng, zlib, cJSON, giflib, libm,
 * OpenMP). Everything works on data in memory; files are optional. Call
 * ws_runtime_init first (threads, OpenBLAS kernels: base/runtime.h).
 * See tools/embed_example.c. */
#ifndef WIRESKETCH_H
#define WIRESKETCH_H
#include "nn/base/status.h"
#include "nn/base/rng.h"
#include "base/runtime.h"
#include "render/camera.h"
#include "io/image.h"
#include "io/scene.h"
#include "render/curves.h"
#include "render/splat.h"
#include "render/augment.h"
#include "render/edges.h"
#include "objective/loss.h"
#include "fit/fit.h"
#include "metrics/quality.h"
#include "objective/objective.h"
#include "io/export.h"
#include "metrics/metrics.h"
#include "io/pointcloud.h"
#include "nn/clip.h"
#endif
