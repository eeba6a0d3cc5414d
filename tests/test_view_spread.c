/* test_view_spread.c: train views spread over their directions
 * (geometry/view_spread.h), as the photo hull's carving takes 48 of them.
 * Cameras on a sphere around the origin (a Fibonacci spiral, so the
 * capture's own views are about evenly spread):
 *   - up to 48 views: all of them, in view order;
 *   - 200 views: 48 of them, in view order, the first
 *     view among them; spread as farthest-point picking spreads them: no
 *     train view is farther from its nearest chosen one than the two
 *     nearest chosen ones are from each other, and the chosen ones are
 *     farther apart than the capture's nearest neighbours (so the partners
 *     of the carving are as far apart as with fewer views). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "check.h"
#include "geometry/view_spread.h"

enum { MANY = 200, MOST = 48 };

/* n cameras at distance 4 from the origin, on a Fibonacci sphere. */
static int sphere_views(ws_view *views, int n, ws_status *st) {
    for (int k = 0; k < n; k++) {
        const double z = 1 - (2 * k + 1.0) / n, r = sqrt(1 - z * z), phi = k * M_PI * (3 - sqrt(5));
        const double c2w[4][4] = {
            {1, 0, 0, 4 * r * cos(phi)}, {0, 1, 0, 4 * r * sin(phi)}, {0, 0, 1, 4 * z}, {0, 0, 0, 1}};
        if (ws_camera_init(&views[k].cam, c2w, 0.7, 32, 32, "test camera", st)) return st->code;
    }
    return WS_OK;
}

/* The angle, in degrees, between the directions of two cameras from the
 * origin. */
static double angle(const ws_view *a, const ws_view *b) {
    double p[3], q[3], pp = 0, qq = 0, pq = 0;
    ws_camera_position(&a->cam, p);
    ws_camera_position(&b->cam, q);
    for (int i = 0; i < 3; i++) pp += p[i] * p[i], qq += q[i] * q[i], pq += p[i] * q[i];
    return acos(fmax(-1, fmin(1, pq / sqrt(pp * qq)))) * 180 / M_PI;
}

int main(void) {
    ws_status st = {0};
    static ws_view views[MANY];
    const ws_view *chosen[MOST];
    const double centre[3] = {0, 0, 0};
    int n = 0, rc = sphere_views(views, MANY, &st);
    CHECK(rc == WS_OK, "cameras: %s", st.msg);
    if (rc) return check_summary();

    const ws_split few = {MOST - 8, views};
    rc = ws_view_spread(&few, centre, MOST, chosen, &n, &st);
    int all = rc == WS_OK && n == few.n;
    for (int k = 0; all && k < n; k++) all = chosen[k] == &views[k];
    CHECK(all, "%d views: %d chosen, not all of them in order (%s)", few.n, n, st.msg);

    const ws_split many = {MANY, views};
    rc = ws_view_spread(&many, centre, MOST, chosen, &n, &st);
    CHECK(rc == WS_OK && n == MOST, "%d views: %d chosen (%s)", MANY, n, st.msg);
    if (rc || n != MOST) return check_summary();
    int ordered = chosen[0] == &views[0];
    for (int k = 1; k < n; k++) ordered &= chosen[k] > chosen[k - 1];
    CHECK(ordered, "the chosen views are not in view order from the first one");
    double apart = INFINITY, cover = 0, capture = INFINITY;
    for (int a = 0; a < n; a++)
        for (int b = a + 1; b < n; b++) apart = fmin(apart, angle(chosen[a], chosen[b]));
    for (int v = 0; v < MANY; v++) {
        double nearest = INFINITY;
        for (int a = 0; a < n; a++) nearest = fmin(nearest, angle(&views[v], chosen[a]));
        cover = fmax(cover, nearest);
        for (int w = 0; w < MANY; w++)
            if (w != v) capture = fmin(capture, angle(&views[v], &views[w]));
    }
    printf("%d views on a sphere, nearest two %.1f degrees apart; the %d chosen at least %.1f apart, every view "
           "within %.1f of one\n", MANY, capture, n, apart, cover);
    CHECK(cover <= apart + 1e-9, "a view is %.2f degrees from the chosen ones, which are %.2f apart: not spread",
          cover, apart);
    CHECK(apart >= 1.5 * capture, "the chosen views are %.2f degrees apart, the capture's %.2f: not spread", apart,
          capture);
    return check_summary();
}
