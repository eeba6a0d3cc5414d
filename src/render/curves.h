/* curves.h: cubic Bezier curves and their Gaussians (METHOD.md section 2).
 *
 * A sketch is n curves of 4 control points each, P[(c * 4 + j) * 3 + xyz].
 * Each curve is sampled into Gaussians spaced 2 * thickness * (1 - overlap)
 * apart in arc length; the sample parameters t_k are constants of the
 * backward pass, so dL/dP_j = sum_k B_j(t_k) dL/dmu_k. */
#ifndef WS_CURVES_H
#define WS_CURVES_H
#include "nn/base/rng.h"
#include "nn/base/status.h"

/* Gaussians per curve at the most: a longer curve is capped (with a warning
 * on stderr) rather than allowed to exhaust memory. */
#define WS_MAX_GAUSSIANS_PER_CURVE 4096
/* Uniform parameter samples t = i / (WS_ARC_SAMPLES - 1) on which the arc
 * length of a curve is measured (as the original). */
#define WS_ARC_SAMPLES 300
/* Numbers per curve: 4 control points x 3 coordinates. */
#define WS_CURVE_FLOATS 12

typedef struct {
    int n;            /* number of curves */
    double *P;        /* n x 4 x 3 control points */
    double thickness; /* Gaussian world radius */
    double overlap;   /* spacing = 2 * thickness * (1 - overlap) */
} ws_curves;

typedef struct {
    int n, cap;   /* Gaussians in use, allocated capacity */
    double *mu;   /* n x 3 centres */
    double *t;    /* n curve parameters (constants of the backward pass) */
    int *curve;   /* n: which curve each Gaussian belongs to */
    int capped;   /* number of curves that hit WS_MAX_GAUSSIANS_PER_CURVE */
} ws_gaussians;

/* n curves with all control points 0, thickness 0.02 and overlap 0.6 (the
 * defaults of METHOD.md section 7). */
int ws_curves_alloc(ws_curves *c, int n, ws_status *st);
void ws_curves_free(ws_curves *c);

/* The original's initialisation: each curve a straight segment of `length`
 * centred on a uniform random point of the sphere (center, radius), in a
 * uniform random direction tangent to the sphere; control points at -1/2,
 * -1/6, +1/6, +1/2 of its length. Per curve the draws are 3 normals for
 * the point (normalised) and then 3 normals for the direction (projected
 * onto the tangent plane, normalised); a draw of (near) zero length is
 * redrawn. Allocates c. */
int ws_curves_init_random(ws_curves *c, int n, const double center[3], double radius,
                          double length, double thickness, double overlap, ws_rng *rng,
                          ws_status *st);

/* Curve ci becomes the straight segment of `length` centred at mid along
 * the unit direction dir, control points at -1/2, -1/6, +1/6, +1/2. */
void ws_curve_set_segment(ws_curves *c, int ci, const double mid[3], const double dir[3],
                          double length);

/* A uniform random unit vector orthogonal to `normal` (unit, or zero for
 * any direction). */
void ws_random_direction(ws_rng *rng, const double normal[3], double out[3]);

/* Curve files: {"thickness": r, "overlap": o, "curves": [[[x,y,z] x 4], ...]}.
 * Reading checks every number is finite, every curve has 4 points of 3,
 * thickness > 0 and overlap in [0, 1); errors name the file and count curves
 * and points from 0: "C.json: curve 3: point 2 is not 3 numbers". On failure
 * c is left empty (n = 0, P = NULL). Saving writes "%.17g" numbers through a
 * temporary file, so a save/load round trip is exact; non-finite control
 * points are refused (WS_ENUMERIC). */
int ws_curves_load(const char *path, ws_curves *c, ws_status *st);
int ws_curves_save(const char *path, const ws_curves *c, ws_status *st);
/* What every writer of a sketch checks first (curve files, OBJ, PLY, SVG):
 * WS_ENUMERIC "PATH: curve K has a non-finite control point" for the first
 * such curve. */
int ws_curves_check_finite(const char *path, const ws_curves *c, ws_status *st);

/* The cubic Bernstein weights B_j(t) = C(3,j) t^j (1-t)^(3-j). */
void ws_bernstein(double t, double B[4]);

/* Point of curve `ci` at parameter t (cubic Bernstein). */
void ws_curve_point(const ws_curves *c, int ci, double t, double p[3]);

/* Arc length of curve `ci`, measured as its Gaussians' spacing is (on
 * WS_ARC_SAMPLES samples). */
double ws_curve_length(const ws_curves *c, int ci);

/* Samples every curve into Gaussians (grows g as needed; start from a zeroed
 * ws_gaussians and reuse it). Curve c's Gaussians follow curve c - 1's, in
 * order of t. A curve with M >= 2 Gaussians has t_0 = 0 and t_{M-1} = 1;
 * with M = 1 (L <= spacing) its one Gaussian sits at the arc-length midpoint
 * (t = 0.5 for a degenerate curve). A curve longer than
 * WS_MAX_GAUSSIANS_PER_CURVE spacings gets that many, spread over its whole
 * length; a one-line warning goes to stderr when some curves are capped and
 * their number differs from g->capped of the previous call (so a fit does
 * not repeat it every step). Fails with WS_ENUMERIC on a non-finite control point and WS_EINPUT
 * on a thickness or overlap outside its range. */
int ws_curves_sample(const ws_curves *c, ws_gaussians *g, ws_status *st);
void ws_gaussians_free(ws_gaussians *g);

/* dP (n x 4 x 3, overwritten) from dmu (g->n x 3) through the Bernstein
 * weights of each Gaussian's t. */
void ws_curves_backward(const ws_curves *c, const ws_gaussians *g, const double *dmu, double *dP);

#endif
