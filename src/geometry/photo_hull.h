/* photo_hull.h: the object of a capture without masks, carved out of the
 * region of interest (geometry/roi.h) by what the photos agree on.
 *
 * A point of the object's surface looks about the same from two nearby
 * views that both see it; a point of empty space inside the region is seen
 * through, onto whatever lies behind it at another depth (a wall, the
 * floor), which is a different place, and so mostly of a different colour,
 * from each view. Space carving (Kutulakos & Seitz 2000) keeps the largest
 * shape whose visible points all agree:
 *   views    = the train views, when there are at most
 *              WS_PHOTO_HULL_VIEWS; else that many spread over their
 *              directions from the region's centre (geometry/
 *              view_spread.h). The partners below are then as far apart
 *              as in the captures the constants were chosen on; among 200
 *              views a view's nearest partner would be 10 - 12.5 degrees
 *              away, where the background seen through empty space
 *              shifts too little to disagree, and every view costs every
 *              pass time (docs/RESULTS.md, "A capture of 200 views");
 *   grid     = cubes of side h, `resolution` along the region's longest
 *              side from its lowest corner, all occupied at first;
 *   surface  = the occupied cubes with an empty (or outside) 6-neighbour;
 *   depth_v  = at each pixel of view v, the nearest surface cube
 *              whose square of half-side WS_PHOTO_HULL_SPLAT f h / d
 *              covers the pixel's centre (or whose centre is in it);
 *   v sees a surface cube at depth d when it is in front of v, its centre
 *              projects into the frame, and d <= depth_v there plus
 *              WS_PHOTO_HULL_DEPTH_TOL h;
 *   c_v      = the photo's colour at that pixel;
 *   partners = of the views that see the cube, the nearest to v (in
 *              direction from the region's centre) at least
 *              WS_PHOTO_HULL_PAIR_DEG away, and the nearest after it whose
 *              direction from v's is across the first's (the cosine of the
 *              angle between them, on the sphere of views, at most
 *              WS_PHOTO_HULL_CROSS): a background of stripes looks the same
 *              along them and different across;
 *   d_vw     = how near w's photo comes to c_v within max(1, round(SPLAT f
 *              h / d)) pixels of the cube's centre (its footprint: a cube
 *              on an edge sees both sides' colours): the least, over those
 *              pixels, of the largest channel difference;
 *   a pair (v, w) agrees by 1 when d_vw <= WS_PHOTO_HULL_TAU_FULL, by 0
 *              when d_vw >= WS_PHOTO_HULL_TAU_NONE, linearly between;
 *   carved   = every surface cube seen by at least WS_PHOTO_HULL_MIN_VIEWS
 *              views with at least as many pairs, whose agreements sum to
 *              less than WS_PHOTO_HULL_AGREE of the pairs; all at once,
 *              then again with the new surface, until a pass carves
 *              nothing.
 * A graded agreement, not a cut at one distance: on a solid's faces under
 * a light that moves with the camera d_vw lies near any such cut for many
 * pairs, so a cut flips them with a grey level of noise (a JPEG of quality
 * 95), and each cube carved there bares the next one behind it, which the
 * same views see at nearly the same colours: a wedge carved deep into the
 * solid (docs/RESULTS.md, "A graded colour agreement").
 * Nearby views, not all of them: the light on a surface changes with the
 * side it is seen from (shading, a flash, exposure), slowly, while the
 * background seen through empty space changes at once. Of what stays, the
 * parts (26-connected) smaller than WS_PHOTO_HULL_PART of the largest are
 * dropped: a background of one colour somewhere can leave a fleck no pair
 * disagrees on. The rest is the object's photo hull, about a cube wider
 * than the object; a background of one colour all around leaves the region
 * whole (then the photos' own silhouettes serve). Deterministic: each pass
 * decides every cube from the same surface. The constants were chosen on
 * the box-room cube (docs/RESULTS.md, "The photo hull"). */
#ifndef WS_PHOTO_HULL_H
#define WS_PHOTO_HULL_H
#include <stdint.h>
#include "geometry/roi.h"
#include "io/scene.h"
#include "nn/base/status.h"

#define WS_PHOTO_HULL_SPLAT 0.6
#define WS_PHOTO_HULL_DEPTH_TOL 2.0
#define WS_PHOTO_HULL_PAIR_DEG 10.0
#define WS_PHOTO_HULL_CROSS 0.7
#define WS_PHOTO_HULL_TAU_FULL 0.06
#define WS_PHOTO_HULL_TAU_NONE 0.10
#define WS_PHOTO_HULL_AGREE 0.7
#define WS_PHOTO_HULL_MIN_VIEWS 3
#define WS_PHOTO_HULL_PART 0.05
#define WS_PHOTO_HULL_VIEWS 48 /* train views that carve: see "views" above */

typedef struct {
    double lo[3];       /* the grid's lowest corner: the region's */
    double voxel;       /* h, world units */
    int n[3];           /* cubes along x, y, z */
    uint8_t *occupied;  /* n[0] n[1] n[2], x fastest: 1 = object */
    long kept;          /* occupied cubes */
    long *surface;      /* the surface cubes' indices, in grid order */
    long nsurface;
    int passes;         /* carving passes made */
} ws_photo_hull;

/* Carves the region roi with the train views of scene (photos loaded, all
 * of the working size). Fails only when out of memory. */
int ws_photo_hull_make(const ws_scene *scene, const ws_roi *roi, int resolution, ws_photo_hull *h, ws_status *st);
void ws_photo_hull_free(ws_photo_hull *h);

/* After a caller has emptied cubes of h->occupied (geometry/support_plane.h
 * carves the air over a support): counts kept again and lists the surface
 * again. Fails only when out of memory. */
int ws_photo_hull_update(ws_photo_hull *h, ws_status *st);

/* The 26-connected parts of the occupied cubes (those of them marked in
 * among, when not NULL; a byte per cube): label[i] (a long per cube) the
 * part of cube i, numbered in grid order of their first cubes, -1 for the
 * cubes left out; stack: scratch of a long per cube. Returns the parts'
 * sizes (*nparts of them; the caller frees), NULL when out of memory. */
long *ws_photo_hull_parts(const ws_photo_hull *h, const uint8_t *among, long *label, long *stack, long *nparts,
                          ws_status *st);

/* depth, mask (cam->height x cam->width; either may be NULL): the nearest
 * surface cube over each pixel as depth_v above (INFINITY where none), and
 * 1 where a cube covers the pixel, else 0: the object's mask in cam. */
void ws_photo_hull_project(const ws_photo_hull *h, const ws_camera *cam, float *depth, float *mask);

#endif
