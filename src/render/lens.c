/* lens.c: lens distortion models, forward and inverse (see lens.h,
 * METHOD.md "Lens models").
 *
 * The inverse is Newton's method on the forward model itself, so it is as
 * exact as the forward model's rounding: no approximate inverse
 * polynomial. It is unique only where the distortion is one-to-one, which
 * ws_lens_check establishes from the image centre out to the frame's
 * farthest corner (r_max); beyond it the model folds back or leaves the
 * frame, and the inverse refuses those points. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "render/lens.h"

const char *const ws_lens_model_names[] = {"SIMPLE_PINHOLE", "PINHOLE",     "SIMPLE_RADIAL",
                                           "RADIAL",         "OPENCV",      "OPENCV_FISHEYE",
                                           "FULL_OPENCV"};
const int ws_lens_model_count = sizeof ws_lens_model_names / sizeof ws_lens_model_names[0];

const int ws_lens_model_params[] = {3, 4, 4, 5, 8, 8, 12};

/* Steps of the radial walk of ws_lens_check from the centre to the frame's
 * corner: a fold narrower than 1/1024 of the corner's radius goes unseen,
 * and such a fold affects under a pixel of a 1000-pixel frame. */
#define WALK_STEPS_TO_CORNER 1024
/* How far beyond the corner's distorted radius the walk looks for the
 * undistorted one, in multiples of it (strong barrel distortion squeezes a
 * wide field into the frame; beyond 64x the frame sees nearly 90 degrees
 * off-axis, which no pinhole image of sensible size holds). */
#define WALK_MAX_FACTOR 64
/* How far past the corner's distorted radius the one-to-one range must
 * reach where the lens allows: a tangential term shifts a ray by about
 * 3 p r^2, well under a tenth of r for any real lens (|p| < 0.01). */
#define CORNER_MARGIN 0.1
/* Newton's stopping point: residual in normalised units (1e-12 of a focal
 * length is 1e-9 pixel at a focal of 1000 pixels). */
#define NEWTON_TOLERANCE 1e-12
#define NEWTON_ITERATIONS 100

int ws_lens_is_pinhole(const ws_lens *l) {
    for (int i = 0; i < 4; i++)
        if (l->k[i] != 0) return 0;
    for (int i = 0; i < 3; i++)
        if (l->kd[i] != 0) return 0;
    return l->p[0] == 0 && l->p[1] == 0;
}

/* Perspective radial factor at r^2: numerator over denominator. */
static double radial_factor(const ws_lens *l, double r2, double *den) {
    const double *k = l->k, *d = l->kd;
    *den = 1 + r2 * (d[0] + r2 * (d[1] + r2 * d[2]));
    return (1 + r2 * (k[0] + r2 * (k[1] + r2 * (k[2] + r2 * k[3])))) / *den;
}

/* Fisheye: theta_d of the angle theta. */
static double fisheye_theta_d(const ws_lens *l, double theta) {
    const double *k = l->k, t2 = theta * theta;
    return theta * (1 + t2 * (k[0] + t2 * (k[1] + t2 * (k[2] + t2 * k[3]))));
}

void ws_lens_distort(const ws_lens *l, double x, double y, double *xd, double *yd) {
    const double r2 = x * x + y * y;
    if (l->fisheye) {
        const double r = sqrt(r2);
        /* theta_d / r -> 1 as r -> 0: the formula's limit, not 0 / 0 */
        const double s = r > 1e-15 ? fisheye_theta_d(l, atan(r)) / r : 1.0;
        *xd = x * s;
        *yd = y * s;
        return;
    }
    double den;
    const double radial = radial_factor(l, r2, &den);
    *xd = x * radial + 2 * l->p[0] * x * y + l->p[1] * (r2 + 2 * x * x);
    *yd = y * radial + l->p[0] * (r2 + 2 * y * y) + 2 * l->p[1] * x * y;
}

/* The distorted radius at undistorted radius r along the x axis of a
 * perspective lens (its radial part: tangential terms are checked by the
 * Jacobian), or, fisheye, at angle r; *ok = 0 where the denominator is not
 * positive. */
static double radial_profile(const ws_lens *l, double r, int *ok) {
    if (l->fisheye) {
        *ok = 1;
        return fisheye_theta_d(l, r);
    }
    double den;
    const double f = radial_factor(l, r * r, &den);
    *ok = den > 0;
    return r * f;
}

/* The determinant of the forward model's Jacobian at (x, y) (central
 * differences of step h). */
static double jacobian(const ws_lens *l, double x, double y, double h, double J[2][2]) {
    double a[2], b[2];
    ws_lens_distort(l, x + h, y, &a[0], &a[1]);
    ws_lens_distort(l, x - h, y, &b[0], &b[1]);
    J[0][0] = (a[0] - b[0]) / (2 * h);
    J[1][0] = (a[1] - b[1]) / (2 * h);
    ws_lens_distort(l, x, y + h, &a[0], &a[1]);
    ws_lens_distort(l, x, y - h, &b[0], &b[1]);
    J[0][1] = (a[0] - b[0]) / (2 * h);
    J[1][1] = (a[1] - b[1]) / (2 * h);
    return J[0][0] * J[1][1] - J[0][1] * J[1][0];
}

int ws_lens_check(ws_lens *l, const char *what, ws_status *st) {
    const double v[] = {l->fx, l->fy, l->cx, l->cy, l->k[0], l->k[1], l->k[2], l->k[3],
                        l->kd[0], l->kd[1], l->kd[2], l->p[0], l->p[1]};
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++)
        if (!isfinite(v[i])) return ws_fail(st, WS_EINPUT, "%s: lens value %g is not finite", what, v[i]);
    if (!(l->fx > 0 && l->fy > 0))
        return ws_fail(st, WS_EINPUT, "%s: focal lengths %g, %g must be positive", what, l->fx,
                       l->fy);
    if (l->width < 1 || l->height < 1)
        return ws_fail(st, WS_EINPUT, "%s: frame %d x %d is empty", what, l->width, l->height);
    l->r_max = HUGE_VAL;
    if (ws_lens_is_pinhole(l)) return WS_OK;
    /* the distorted radius (fisheye: theta_d) the frame reaches */
    double corner = 0;
    for (int c = 0; c < 4; c++) {
        double x = ((c & 1) * l->width - l->cx) / l->fx, y = ((c >> 1) * l->height - l->cy) / l->fy;
        corner = fmax(corner, hypot(x, y));
    }
    /* walk out from the centre until the profile passes the corner, and
     * CORNER_MARGIN beyond (tangential terms move the corner's ray off the
     * radial profile); it must grow all the way to the corner (fisheye: in
     * theta, below 90 degrees), and r_max ends where it stops growing */
    const double step = l->fisheye ? (M_PI / 2) / (WALK_STEPS_TO_CORNER * 4)
                                   : corner / WALK_STEPS_TO_CORNER;
    const double limit = l->fisheye ? M_PI / 2 - step : corner * WALK_MAX_FACTOR;
    double r = 0, previous = 0;
    int ok = 1;
    while (previous < corner * (1 + CORNER_MARGIN) && r < limit) {
        const double rd = radial_profile(l, r + step, &ok);
        if (!ok || !(rd > previous)) {
            if (previous >= corner) break;
            return ws_fail(st, WS_EINPUT,
                           "%s: lens distortion folds the image (the distorted radius stops "
                           "growing at %.0f px from the principal point, inside the frame, whose "
                           "corner is %.0f px out)",
                           what, previous * l->fx, corner * l->fx);
        }
        r += step;
        previous = rd;
    }
    if (previous < corner && !l->fisheye)
        return ws_fail(st, WS_EINPUT,
                       "%s: lens distortion folds the image (the frame's corner, %.0f px out, "
                       "is beyond the distorted radius %.0f px of any ray)",
                       what, corner * l->fx, previous * l->fx);
    l->r_max = l->fisheye ? tan(r) : r;
    if (l->fisheye || (l->p[0] == 0 && l->p[1] == 0)) return WS_OK;
    /* tangential terms: the Jacobian stays positive over the disc */
    const int n = 64;
    for (int i = 0; i <= n; i++)
        for (int j = 0; j <= n; j++) {
            double x = l->r_max * (2.0 * j / n - 1), y = l->r_max * (2.0 * i / n - 1), J[2][2];
            if (x * x + y * y > l->r_max * l->r_max) continue;
            if (!(jacobian(l, x, y, 1e-7 * l->r_max, J) > 0))
                return ws_fail(st, WS_EINPUT,
                               "%s: lens distortion folds the image (its Jacobian is not "
                               "positive at %.0f, %.0f px from the principal point)",
                               what, x * l->fx, y * l->fy);
        }
    return WS_OK;
}

int ws_lens_undistort(const ws_lens *l, double xd, double yd, double *x, double *y) {
    const double target = hypot(xd, yd);
    if (l->fisheye) { /* radial only: solve theta_d(theta) = |(xd, yd)| */
        const double theta_max = atan(l->r_max);
        double theta = fmin(target, theta_max);
        int converged = target == 0;
        for (int it = 0; it < NEWTON_ITERATIONS && !converged; it++) {
            const double h = 1e-7 * (1 + theta);
            const double e = fisheye_theta_d(l, theta) - target;
            const double slope = (fisheye_theta_d(l, theta + h) - fisheye_theta_d(l, theta - h)) / (2 * h);
            converged = fabs(e) < NEWTON_TOLERANCE;
            if (!converged) theta = fmin(fmax(theta - e / slope, 0.0), theta_max);
        }
        const double s = target > 0 ? tan(theta) / target : 1.0;
        *x = xd * s;
        *y = yd * s;
        return converged && theta < theta_max ? 0 : -1;
    }
    double px = xd, py = yd, e[2];
    ws_lens_distort(l, px, py, &e[0], &e[1]);
    e[0] -= xd;
    e[1] -= yd;
    double err = hypot(e[0], e[1]);
    for (int it = 0; it < NEWTON_ITERATIONS && err > NEWTON_TOLERANCE; it++) {
        double J[2][2];
        const double det = jacobian(l, px, py, 1e-7 * (1 + hypot(px, py)), J);
        if (!(fabs(det) > 0)) break;
        const double dx = (J[1][1] * e[0] - J[0][1] * e[1]) / det,
                     dy = (J[0][0] * e[1] - J[1][0] * e[0]) / det;
        /* halve the step until the residual shrinks: Newton from the
         * distorted point can overshoot where the distortion is strong */
        double scale = 1, nx = px, ny = py, ne[2] = {e[0], e[1]}, nerr = err;
        for (int half = 0; half < 40; half++, scale *= 0.5) {
            nx = px - scale * dx;
            ny = py - scale * dy;
            ws_lens_distort(l, nx, ny, &ne[0], &ne[1]);
            ne[0] -= xd;
            ne[1] -= yd;
            nerr = hypot(ne[0], ne[1]);
            if (nerr < err) break;
        }
        if (!(nerr < err)) break;
        px = nx;
        py = ny;
        e[0] = ne[0];
        e[1] = ne[1];
        err = nerr;
    }
    *x = px;
    *y = py;
    return err <= NEWTON_TOLERANCE * (1 + target) && hypot(px, py) <= l->r_max ? 0 : -1;
}

int ws_lens_from_colmap(ws_lens *l, const char *model, const double *q, int nparams, int width,
                        int height, const char *what, ws_status *st) {
    int m = 0;
    while (m < ws_lens_model_count && strcmp(model, ws_lens_model_names[m])) m++;
    if (m == ws_lens_model_count)
        return ws_fail(st, WS_EINPUT,
                       "%s: unknown camera model '%s' (SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL, "
                       "RADIAL, OPENCV, OPENCV_FISHEYE or FULL_OPENCV)",
                       what, model);
    if (nparams != ws_lens_model_params[m])
        return ws_fail(st, WS_EINPUT, "%s: camera model %s takes %d parameters, not %d", what,
                       model, ws_lens_model_params[m], nparams);
    memset(l, 0, sizeof *l);
    l->width = width;
    l->height = height;
    const int one_focal = m == 0 || m == 2 || m == 3; /* f, cx, cy, ... */
    l->fx = q[0];
    l->fy = one_focal ? q[0] : q[1];
    l->cx = q[one_focal ? 1 : 2];
    l->cy = q[one_focal ? 2 : 3];
    const double *d = q + (one_focal ? 3 : 4); /* the distortion parameters */
    switch (m) {
    case 2: l->k[0] = d[0]; break;
    case 3: l->k[0] = d[0], l->k[1] = d[1]; break;
    case 4: l->k[0] = d[0], l->k[1] = d[1], l->p[0] = d[2], l->p[1] = d[3]; break;
    case 5:
        l->fisheye = 1;
        for (int i = 0; i < 4; i++) l->k[i] = d[i];
        break;
    case 6:
        l->k[0] = d[0], l->k[1] = d[1], l->p[0] = d[2], l->p[1] = d[3], l->k[2] = d[4];
        for (int i = 0; i < 3; i++) l->kd[i] = d[5 + i];
        break;
    }
    return ws_lens_check(l, what, st);
}

int ws_lens_to_colmap(const ws_lens *l, double *q) {
    q[0] = l->fx, q[1] = l->fy, q[2] = l->cx, q[3] = l->cy;
    if (l->fisheye) {
        for (int i = 0; i < 4; i++) q[4 + i] = l->k[i];
        return 5;
    }
    if (ws_lens_is_pinhole(l)) return 1;
    if (l->k[3] != 0) return -1;
    q[4] = l->k[0], q[5] = l->k[1], q[6] = l->p[0], q[7] = l->p[1];
    if (l->k[2] == 0 && l->kd[0] == 0 && l->kd[1] == 0 && l->kd[2] == 0) return 4;
    q[8] = l->k[2];
    for (int i = 0; i < 3; i++) q[9 + i] = l->kd[i];
    return 6;
}
