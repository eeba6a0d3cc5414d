/* wiresketch.h: the public interface of libwiresketch.
 *
 * A C program that embeds wiresketch includes this header and links
 * build/libwiresketch.a (plus OpenBLAS, libpng, zlib, cJSON, giflib, libm,
 * OpenMP). Everything works on data in memory; files are optional.
 * See tools/embed_example.c. */
#ifndef WIRESKETCH_H
#define WIRESKETCH_H
#include "status.h"
#include "rng.h"
#include "camera.h"
#include "image.h"
#include "scene.h"
#include "curves.h"
#include "splat.h"
#include "augment.h"
#include "edges.h"
#include "loss.h"
#include "fit.h"
#include "evaluate.h"
#include "export.h"
#include "metrics.h"
#include "pointcloud.h"
#include "clip.h"
#endif
