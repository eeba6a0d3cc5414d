/* support_plane.h: the flat support an object stands on (a table, the
 * floor) when the region of interest holds part of it, found in the photo
 * hull (geometry/photo_hull.h), and the air over it that carving left.
 *
 * Over a textured support, a cube of air just above it sees nearly the same
 * patch from every view (between views 10 - 40 degrees apart the parallax
 * is less than a tile), so carving leaves a layer of air on it, several
 * cubes deep where the texture is coarse. The layer's top hides the
 * support from the views, and the support's lines vote there, where they
 * are not; the object's foot stands in the layer. So:
 *   u      = the mean of the unit directions from the region's centre to
 *            the train cameras: "up" for views taken from above a support
 *            (none is looked for when |mean| < WS_SUPPORT_MIN_UP: views
 *            from all round);
 *   tops   = the hull's cubes whose neighbour one grid step towards u
 *            (round(u) per axis) is in the grid and empty, and under which
 *            the hull is solid: a walk along -u from the cube stays in
 *            occupied cubes to the grid's side (nothing under a table's
 *            top or a floor is ever seen, so nothing there is carved; under
 *            a chair's seat or a box floating on a stand it is);
 *   layer  = the slice WS_SUPPORT_LAYER cubes thick across u that holds
 *            the most tops; the normal n is then the least eigenvector of
 *            the scatter of those tops (the plane fitted to them), turned
 *            towards u, and the slice found again across n (twice);
 *   found  = the layer lies in the lower WS_SUPPORT_LOWER of the grid's
 *            extent across n (the object stands on a support, so the
 *            region of interest around it lies mostly above; a layer
 *            higher up is the ceiling of what the colours could carve
 *            from too few or too small views), the tops within
 *            WS_SUPPORT_REACH cubes of it cover at least WS_SUPPORT_SHARE
 *            of the grid's cross-section across n, and the hull stands
 *            above the layer's air somewhere (the object on it: some cube
 *            is foot, below);
 *   floor, top = the WS_SUPPORT_LOW and WS_SUPPORT_HIGH quantiles of the
 *            heights n . x of the tops within WS_SUPPORT_REACH cubes of the
 *            layer: the support's surface (where carving went down to it,
 *            along its texture's lines) and the top of the air left on it;
 *   foot   = the occupied cubes above floor + half a cube and up to
 *            top + WS_SUPPORT_MARGIN cubes from which a walk along n stays
 *            in the hull to above that height, into a part of the hull
 *            there (26-connected) at least WS_SUPPORT_PART the size of the
 *            largest: the object standing on the support (a solid's base,
 *            a chair's legs), not a pillar of air the colours left;
 *   air    = the other occupied cubes in that slab: carved
 *            (ws_support_plane_carve), so that the views see the support
 *            where it is.
 *   reach  = of each foot (a 26-connected part of them), half its width
 *            in cubes, the square root of its cubes over the slab's
 *            height (top + WS_SUPPORT_MARGIN cubes less floor), rounded,
 *            at least WS_SUPPORT_NEAR_MIN and at most WS_SUPPORT_NEAR.
 * A point on the support (height n . x at most top + WS_SUPPORT_MARGIN
 * cubes) further from every foot cube than its reach (along the grid's
 * axes: the largest of the three offsets) is the support's own (a tile's
 * grout line, the grain of a table) and draws no stroke
 * (ws_support_plane_holds). The object's lower edges, where it meets the
 * support, are not: colour carving under a light that changes with the
 * view cuts a solid's hull, and so its foot, several cubes inside its
 * faces, deepest near the support (up to 10 cubes on the capture bed's
 * cube), so a wide foot reaches WS_SUPPORT_NEAR cubes; a thin one (a
 * chair's leg) cannot be cut that deep, and reaching as far would keep
 * the grout beside it. The constants were chosen on the capture bed's
 * floor scenes (docs/RESULTS.md, "An object standing on the floor" and
 * "The lower edges of an object on the floor"). */
#ifndef WS_SUPPORT_PLANE_H
#define WS_SUPPORT_PLANE_H
#include <stdint.h>
#include "geometry/photo_hull.h"
#include "io/scene.h"
#include "nn/base/status.h"

#define WS_SUPPORT_MIN_UP 0.25
#define WS_SUPPORT_LAYER 3      /* cubes */
#define WS_SUPPORT_SHARE 0.25
#define WS_SUPPORT_LOWER 0.5
#define WS_SUPPORT_REACH 8      /* cubes */
#define WS_SUPPORT_LOW 0.02
#define WS_SUPPORT_HIGH 0.95
#define WS_SUPPORT_MARGIN 2     /* cubes */
#define WS_SUPPORT_NEAR 6       /* cubes */
#define WS_SUPPORT_NEAR_MIN 2   /* cubes */
#define WS_SUPPORT_PART 0.05

typedef struct {
    int found;
    double normal[3]; /* n: unit, towards the cameras */
    double share;     /* the layer's tops over the grid's cross-section across n (0 for a layer too high) */
    double floor;     /* n . x of the support's surface */
    double top;       /* n . x of the top of the air left on it */
    long carved;      /* cubes of that air carved */
    uint8_t *foot;    /* the hull's grid, x fastest: the object's foot, each cube its foot's reach in cubes (0: none) */
    int n[3];         /* that grid: cubes along x, y, z, */
    double lo[3];     /* its lowest corner */
    double voxel;     /* and its spacing */
} ws_support_plane;

/* Looks for a support in h, the photo hull of train's views. Fails only
 * when out of memory; s->found says whether one is there. */
int ws_support_plane_find(const ws_photo_hull *h, const ws_split *train, ws_support_plane *s, ws_status *st);

/* Carves the air over a found support out of h and lists h's surface
 * again. Fails only when out of memory. */
int ws_support_plane_carve(ws_support_plane *s, ws_photo_hull *h, ws_status *st);

/* Whether point p (3) lies on a found support away from the object's foot. */
int ws_support_plane_holds(const ws_support_plane *s, const double p[3]);

void ws_support_plane_free(ws_support_plane *s);

#endif
