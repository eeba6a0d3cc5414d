/* pointcloud.h: point clouds read from and written to PLY files (the ground
 * truth of METHOD.md section 1, gt_points.ply; nerfstudio's sparse points,
 * its ply_file_path) and their bounding boxes.
 *
 * The reader takes ascii, binary_little_endian and binary_big_endian PLY
 * with any scalar type for x, y, z (char .. double, also int8 .. float64).
 * Other vertex properties (normals, colours, list properties) and other
 * elements (faces) are skipped. Every count in the header is checked against
 * the bytes that follow before anything is allocated, so a hostile header
 * fails with one line "PATH: ..." instead of exhausting memory. */
#ifndef WS_POINTCLOUD_H
#define WS_POINTCLOUD_H
#include <limits.h>
#include "nn/base/status.h"

/* The most points a cloud (or a nearest-neighbour set or query batch) may
 * hold, so that every coordinate index i * 3 + a fits in an int. */
#define WS_MAX_POINTS (INT_MAX / 3)

typedef struct {
    int n;       /* number of points (> 0 after a successful load) */
    double *xyz; /* n x 3 */
} ws_pointcloud;

/* Reads the vertex positions of a PLY file. Fails with WS_EINPUT on a
 * malformed file (no vertices, missing x/y/z, truncated data, non-finite
 * coordinates, counts that do not fit the file). */
int ws_pointcloud_load_ply(const char *path, ws_pointcloud *pc, ws_status *st);
void ws_pointcloud_free(ws_pointcloud *pc);

/* Writes n points (x y z each) as an ASCII PLY file of double x, y, z, to a
 * temporary name renamed into place (base/outfile.h), with 17 significant
 * digits, so that the reader above gives back the same doubles. */
int ws_pointcloud_save_ply(const char *path, const double *xyz, int n, ws_status *st);

/* Axis-aligned bounding box of n points (n >= 1). */
void ws_points_bbox(const double *xyz, int n, double lo[3], double hi[3]);
/* Length of the bounding box's diagonal (0 for n = 0). */
double ws_points_diagonal(const double *xyz, int n);

#endif
