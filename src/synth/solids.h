/* solids.h: synthetic solid objects with sharp edges (`wiresketch scene
 * cube|dodecahedron|nut|bracket`), the test bed of the weight-free line loss.
 *
 * A solid is a closed triangle mesh with a unit normal at each triangle
 * corner (equal corners for a flat face; interpolated across the curved
 * wall of the nut's hole, which is smoothly shaded) and its sharp edges as
 * cubic Bezier curves: a straight edge a -> b has control points at 0, 1/3,
 * 2/3 and 1 of the way; a circle is 4 quarter arcs with the handle length
 * kappa = 4/3 (sqrt 2 - 1) of the radius (radial error 2.7e-4 of it).
 *   cube          side 1.1, 12 edges;
 *   dodecahedron  circumradius 0.85, 30 edges;
 *   nut           hexagonal prism (corner radius 0.75, height 0.5) with a
 *                 round hole (radius 0.35) along its axis: 18 edges of the
 *                 prism and the 2 circles of the hole (8 arcs), 26 curves;
 *   bracket       an L-shaped angle bracket (legs 1.1 long, 0.35 thick,
 *                 0.7 deep): a concave solid, 18 edges, one of them the
 *                 inner corner's crease.
 * Rendering (ws_solid_render): the nearest triangle along each ray, shaded
 *   albedo x (AMBIENT + KEY max(0, n.l) + FILL max(0, n.f))
 * with a key light l fixed in world space and a fill light f fixed to the
 * camera (from its upper left), so that faces of different orientation
 * differ in brightness like in a real render (a light on the camera's axis
 * would light two faces turned alike from it alike); the background image
 * (3 x height x width, e.g. room.h's) where no face is hit. */
#ifndef WS_SOLIDS_H
#define WS_SOLIDS_H
#include <stdint.h>
#include "render/camera.h"
#include "render/curves.h"
#include "io/image.h"
#include "synth/line_drawing.h"
#include "nn/base/status.h"

typedef struct {
    ws_curves edges;  /* the sharp edges: the ground truth of the scene */
    double center[3]; /* centre of the mesh's bounding box */
    float albedo[3];
    int ntri;
    double *corner; /* ntri x 3 corners x 3 */
    double *normal; /* ntri x 3 corners x 3, unit */
} ws_solid;

/* Is `name` one of the solids there are ("cube", "dodecahedron", "nut", "bracket")? */
int ws_solid_exists(const char *name);

/* Builds solid `name` with its bounding box centred on `center`; fails with
 * WS_EUSAGE for an unknown name. */
int ws_solid_make(ws_solid *s, const char *name, const double center[3], ws_status *st);
void ws_solid_free(ws_solid *s);

/* Renders s seen by cam into img (allocated here: 3 x height x width), the
 * average of supersample^2 rays per pixel spread evenly over it; g: NULL,
 * or a buffer of the camera's size to fill (supersample odd, so that one
 * ray passes through each pixel's centre: line_drawing.h). */
int ws_solid_render(const ws_solid *s, const ws_camera *cam, int supersample,
                    const ws_image *background, ws_image *img, ws_geometry_buffer *g, ws_status *st);

/* Writes n points of the surface (uniform by area, seeded) as an ASCII PLY
 * file: the scene's gt_points.ply. */
int ws_solid_write_points(const ws_solid *s, const char *path, int n, uint64_t seed,
                          ws_status *st);

#endif
