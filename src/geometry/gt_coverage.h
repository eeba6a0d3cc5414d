/* gt_coverage.h: does the ground truth hold all of the object the photos
 * show?
 *
 * The ground-truth point cloud (gt_points.ply) is data too, and can miss a
 * part (the shared rose's has no stem although every photo shows one;
 * docs/METHOD.md section 12). Its points are projected into every view: the pixels
 * they fall in are marked, and a silhouette pixel is covered when a marked
 * pixel lies within
 *     r = f (WS_GT_DISC_SPACINGS spacing + tube) / d_near + WS_GT_SLACK px
 * of it (f the focal; d_near the depth of the view's nearest point, so that
 * every point's disc is at least the size its own depth gives; spacing the
 * median distance from a point to its nearest neighbour: on a surface or
 * curve sampled that densely every part lies within about one spacing of
 * a point, and two leave room for sparser patches; tube the radius of the
 * tubes whose axes the points are, for a wire scene's ground truth;
 * WS_GT_SLACK two pixel diagonals: half a diagonal from the point to the
 * centre of the pixel it marks, half for the silhouette pixel's own
 * extent, as in the hull (hull.h), and one for the resampling of the photo
 * to the working size, after which the silhouettes of the complete clouds
 * measured still had a rim of one pixel). A view's uncovered fraction is
 * the share of its silhouette (silhouette.h) that is not covered. Hidden
 * points are marked too: the test asks whether the cloud has anything
 * along the pixel's ray, not whether it is the visible surface, so it never
 * blames a complete cloud.
 *
 * Where it misses: the visual hull of the split with the most views
 * (hull.h, at the check's resolution), and of its voxels those whose
 * centre falls on an uncovered silhouette pixel in more than half of the
 * views whose silhouette holds it (and is held by at least a quarter of
 * the split's views, so that a voxel few views see decides nothing). The
 * cloud is flagged when that split's mean uncovered fraction is at least
 * WS_GT_UNCOVERED_FLAG and at least WS_GT_REGION_VOXELS such voxels exist
 * (a rim of stray pixels leaves a voxel or two, a missing part a run of
 * them); the line names the file, the fraction, and the voxels' centroid
 * and extent (docs/RESULTS.md gives the numbers measured and the margins). */
#ifndef WS_GEOMETRY_GT_COVERAGE_H
#define WS_GEOMETRY_GT_COVERAGE_H
#include "geometry/silhouette.h"
#include "io/pointcloud.h"
#include "io/scene.h"
#include "nn/base/status.h"

#define WS_GT_DISC_SPACINGS 2.0
#define WS_GT_SLACK 2.83
#define WS_GT_UNCOVERED_FLAG 0.02
#define WS_GT_REGION_VOXELS 8
#define WS_GT_LINE 1024 /* bytes of the line */

typedef struct {
    int n;          /* views; 0: the split is absent */
    double mean;    /* uncovered fraction of the silhouettes, mean over the views */
    double worst;   /* the largest */
    int worst_view; /* its index in the split */
} ws_gt_coverage_split;

typedef struct {
    ws_gt_coverage_split split[WS_NSPLITS];
    double spacing;      /* median nearest-neighbour distance of the points */
    double ball;         /* the radius each point is drawn with, before the pixel slack */
    int reference;       /* the split whose hull locates the gap (the most views); -1: none */
    long region_voxels;  /* hull voxels uncovered in most views that see them */
    double centroid[3];  /* their centroid */
    double lo[3], hi[3]; /* their bounding box (voxel centres) */
    int flagged;         /* the ground truth misses part of the object */
    char line[WS_GT_LINE]; /* what is wrong, naming `path`; "" when not flagged */
} ws_gt_coverage;

/* scene: loaded with its images; sil[s]: the silhouettes of split s's
 * views (one per view in view order); gt: the points read from `path`
 * (named in the line); tube: the radius of the tubes around them, 0 for
 * none; resolution: hull voxels along its longest side (the check's,
 * WS_CHECK_RESOLUTION). */
int ws_gt_coverage_measure(const ws_scene *scene, const ws_silhouette *const sil[WS_NSPLITS],
                           const ws_pointcloud *gt, double tube, const char *path, int resolution,
                           ws_gt_coverage *c, ws_status *st);

#endif
