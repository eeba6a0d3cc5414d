/* edge_consensus.h: what of the photos' edges a curve inside the region of
 * interest (geometry/roi.h) can explain across views, for a capture whose
 * views have no usable silhouette (an object over a busy background, no
 * mask; geometry/check.h) or whose user gives a box.
 *
 * A curve of the object is seen on an edge of every photo whose view it is
 * not hidden in; a background edge (a wall, the floor, anything at another
 * depth) falls on the object's edges in some views, by chance, not in
 * nearly all of those that see a point. So:
 *   views  = the train views, or WS_CONSENSUS_MAX_VIEWS of them spread
 *            over their directions from the region's centre when there
 *            are more (geometry/view_spread.h): "train views" below;
 *   E_v    = the thin edges of train view v's photo (render/thin_edges.h);
 *   D_v    = the distance to E_v (render/distance.h);
 *   grid   = the centres p of the cubes of `resolution` along the box's
 *            longest side that tile the region of interest (the fit's:
 *            WS_CONSENSUS_RESOLUTION);
 *   A_v    = at each pixel, the direction of the photo's luminance
 *            gradient (3 x 3 Sobel) at the nearest edge pixel within
 *            WS_CONSENSUS_ORIENT_REACH pixels;
 *   hull   = the photo hull of the region (geometry/photo_hull.h, on the
 *            same grid): the object carved out by the photos' colours,
 *            about a cube wider than it, with the air that carving left
 *            on a support the object stands on carved too
 *            (geometry/support_plane.h);
 *   v sees p when p is in front of v, in the frame, and not behind the
 *            hull's surface there (its depth at most the hull's nearest
 *            plus WS_PHOTO_HULL_DEPTH_TOL cubes): an edge on the far side
 *            of a solid is hidden from the views in front of it, and so
 *            is judged by the views that can see it;
 *   p is near an edge in view v when v sees p and
 *            D_v at the pixel p projects into is at most
 *            WS_CONSENSUS_VOTE_PX plus half the radius in pixels of p's
 *            cube's circumscribed ball (f rho / 2 d); the edge there, a
 *            line across A_v, and the camera span a plane of normal n_v;
 *   t(p)   = the direction most nearly perpendicular to the n_v of those
 *            views (the smallest eigenvector of sum n_v n_v^T), found
 *            again from the views within WS_CONSENSUS_ORIENT_DEG of
 *            perpendicular to the first: the 3D direction of the edge
 *            through p that the views' edges agree on;
 *   p hits view v when it is near an edge there and |n_v . t| <=
 *            sin(WS_CONSENSUS_ORIENT_DEG): the edge runs as an edge
 *            through p along t would (a busy background's edges at random
 *            orientations stop agreeing; only parallel families still do);
 *   strong: at least WS_CONSENSUS_MIN_VIEWS views see p and a share of
 *            WS_CONSENSUS_STRONG of them is hit;
 *   weak:   the same share at WS_CONSENSUS_WEAK among the views of a cap:
 *            those whose direction from the box's centre lies within
 *            WS_CONSENSUS_CAP_ANGLE degrees of one of 26 directions (to a
 *            cube's neighbours), when at least a quarter of the train views
 *            (and WS_CONSENSUS_MIN_VIEWS) are in it and see p. An edge of a
 *            solid is hidden from the views behind its faces, so only a
 *            part of the sphere of views sees it, all of them on an edge;
 *   kept:   the parts of the strong and weak points that hold at least
 *            WS_CONSENSUS_MIN_PART strong ones, grown from a strong point
 *            to its 26 neighbours and from a weak one only to the points
 *            up to WS_CONSENSUS_WEAK_REACH cubes away along each axis
 *            within acos(WS_CONSENSUS_ALONG) of its t: an edge of the
 *            object is a line of grid points along t, while chance
 *            agreement with a background's parallel lines scatters or
 *            fills blobs; a reach of 2 bridges the one-cube gaps a weak
 *            edge shows in soft photos (a lens' undistortion, JPEG); less the
 *            points on a support's own lines (ws_support_plane_holds).
 * The kept points are the object's edges as the views agree on them (a
 * band about the edges a few pixels wide). For any camera:
 *   N   = the distance to the pixels the kept points project into (in
 *         front of it);
 *   M   = the photo hull's own mask in cam (ws_photo_hull_project),
 *         made convex (render/convex_fill.h) when the hull is a solid's:
 *         it holds WS_CONSENSUS_SOLID or more cubes a kept point (a
 *         solid's hull fills its volume, 15 - 69 cubes a point on the
 *         capture bed's solids; a wire's is a tube about its points,
 *         0.3 - 0.35). Carving takes a solid's faces that the light,
 *         moving with the camera, shades differently from view to view
 *         (the lower faces, seen at grazing angles), which dents the
 *         hull's outline inside the object's edges; a convex outline
 *         has no dents, and the band below still bounds a concave solid.
 *         Not over a support: the hull holds the support's slab too;
 *   silhouette: N <= WS_CONSENSUS_SILHOUETTE_PX where M covers the
 *         pixel, WS_CONSENSUS_SOLID_BAND_PX where the hull is a solid's or
 *         over a support (ws_edge_consensus_band_px): a solid's weak edges
 *         (its lower edges, a faint crease) hold few kept points, up to a
 *         cube beside the photo's edge, and a narrow band there keeps the
 *         strokes off the edge; a wire's band, as wide as its tube, lets
 *         them off the axis when it is wider. A band along the object's
 *         edges (hidden ones too),
 *         cut to M's outline (so a wire's band, as wide as the tube's
 *         outlines and the background between them, keeps the tube),
 *         which the visual hull, the silhouette term, the initial curves
 *         and the respawn read as they read a mask's (a solid's hull is
 *         then a frame of its edges);
 *         it never touches the frame's edge, so every view carves the
 *         hull beyond its frame (the kept points are all of the object);
 *   line target: ws_line_target of the photo with M as its silhouette
 *         (so a wire's tube is drawn by its axis, and a solid's faces,
 *         wide, by their photo edges) and no mask, kept where
 *         N <= WS_CONSENSUS_KEEP_PX and no more than WS_CONSENSUS_OUTSIDE_PX
 *         outside M, where the photo's edge runs as the edge the views
 *         agree on does: within WS_CONSENSUS_ORIENT_DEG of the direction t
 *         of one of those kept points, projected into the view. A kept
 *         point on the object's outline lies beside the background's
 *         edges that meet it there (a wall's stripes, a floor's grout),
 *         which N alone keeps: across the outline they run across t, and
 *         beyond M they are the room's (M stands about a cube proud of the
 *         object). Not with the band as silhouette: its thin parts would
 *         draw the far side's edges, hidden behind the faces, by their
 *         axes. For a wire (a hull neither a solid's nor over a support)
 *         the hull is a tube a few cubes across, which carving cannot cut
 *         deeper than its outline, and it stands about a cube proud of the
 *         wire all round: so M's rim, its pixels within
 *         WS_CONSENSUS_OUTSIDE_PX of its outline, is left out of the line
 *         target's silhouette (else a thick tube, a knot's, is too wide
 *         there to be a thin part, and both its outlines are drawn).
 * A background edge at any depth thus pulls no stroke: it is outside the
 * region, or the views do not agree on it. Deterministic: the vote of each
 * point is its own, gathered in grid order. The constants were chosen on
 * the box-room cube (docs/RESULTS.md, "Busy backgrounds without masks"). */
#ifndef WS_EDGE_CONSENSUS_H
#define WS_EDGE_CONSENSUS_H
#include "geometry/photo_hull.h"
#include "geometry/roi.h"
#include "geometry/support_plane.h"
#include "geometry/silhouette.h"
#include "io/scene.h"
#include "nn/base/status.h"

#define WS_CONSENSUS_RESOLUTION 128
#define WS_CONSENSUS_VOTE_PX 1.0
#define WS_CONSENSUS_STRONG 0.75
#define WS_CONSENSUS_WEAK 0.7
#define WS_CONSENSUS_CAP_ANGLE 90.0 /* degrees */
#define WS_CONSENSUS_MIN_VIEWS 8
#define WS_CONSENSUS_MIN_PART 16
#define WS_CONSENSUS_MAX_VIEWS 256 /* train views that vote: all, or this many spread (geometry/view_spread.h) */
#define WS_CONSENSUS_ORIENT_REACH 2 /* pixels */
#define WS_CONSENSUS_ORIENT_DEG 20.0
#define WS_CONSENSUS_ALONG 0.7
#define WS_CONSENSUS_WEAK_REACH 2
#define WS_CONSENSUS_SILHOUETTE_PX 1.5
#define WS_CONSENSUS_SOLID_BAND_PX 2.5 /* the silhouette's band where the hull is not a wire's */
#define WS_CONSENSUS_KEEP_PX 3.0
#define WS_CONSENSUS_ALONG_RAY_PX 0.3 /* a cube's step along t projected shorter: t runs along the ray */
#define WS_CONSENSUS_OUTSIDE_PX 1.5 /* pixels: how far outside M a line target reaches, and a wire's rim (line target above) */
#define WS_CONSENSUS_SOLID 4.0 /* photo hull cubes a kept point, at least: a solid (M above) */
/* The share of --silhouette-weight a fit gives the silhouette term with
 * these silhouettes: a band cut by the photo hull bounds the object less
 * surely than a mask (the hull stands up to a cube inside the object where
 * carving takes the cubes on its outline, as along the room cube's bottom
 * edges, and pushes the curves there inside). Chosen on the capture bed's
 * solids at seeds 0-2 (docs/RESULTS.md, "The silhouette term without
 * masks"). */
#define WS_CONSENSUS_SILHOUETTE_SHARE (1.0 / 3)

typedef struct {
    ws_roi roi;
    double voxel;   /* the grid's spacing, world units */
    long tested;    /* grid points */
    int n;          /* kept points */
    double *p;      /* n x 3 */
    double *t;      /* n x 3: the unit direction of the edge through each kept point (t(p) above) */
    ws_photo_hull hull; /* the region carved by the photos' colours: who sees a point, and the
                           silhouettes' bound */
    int solid;          /* the hull is a solid's: its outline is made convex (M above) */
    ws_support_plane support; /* the flat support the object stands on, when the region holds one */
} ws_edge_consensus;

/* Votes over the train views of scene (photos loaded, all of the working
 * size) on a grid of `resolution` (>= 1) along the region's longest side.
 * Fails only when out of memory. */
int ws_edge_consensus_make(const ws_scene *scene, const ws_roi *roi, int resolution, ws_edge_consensus *c,
                           ws_status *st);
void ws_edge_consensus_free(ws_edge_consensus *c);

/* near (cam->height x cam->width): N above. */
int ws_edge_consensus_near(const ws_edge_consensus *c, const ws_camera *cam, float *near, ws_status *st);

/* The width of the silhouette's band, pixels (silhouette above). */
double ws_edge_consensus_band_px(const ws_edge_consensus *c);

/* The silhouette of view v (its camera and photo) as above. */
int ws_edge_consensus_silhouette(const ws_edge_consensus *c, const ws_view *v, ws_silhouette *s, ws_status *st);

/* The line target of view v (edge: H x W) as above. band: the view's
 * silhouette as ws_edge_consensus_silhouette makes it (view_targets.h
 * keeps it), the line target's silhouette when the hull is empty. */
int ws_edge_consensus_line_target(const ws_edge_consensus *c, const ws_view *v, const ws_silhouette *band,
                                  float *edge, ws_status *st);

#endif
