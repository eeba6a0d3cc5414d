/* test_line_evidence.c: the hull's creases (objective/line_evidence.h) on
 * a hand-made hull surface: a floor and a wall meeting at a right angle
 * (a crease along the fold, none far from it), and a flat floor alone
 * (none anywhere). */
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "objective/line_evidence.h"

#define G 24

/* Surface voxels of the floor z = 5 (x < fold, all y) and, with wall, of
 * the wall x = fold (z >= 5). */
static int make_surface(ws_scene_hull *h, int fold, int wall) {
    memset(h, 0, sizeof *h);
    h->hull.n[0] = h->hull.n[1] = h->hull.n[2] = G;
    h->hull.voxel = 1;
    h->surface.p = malloc(sizeof(double) * 3 * G * G * 2);
    h->surface.normal = calloc(3 * G * G * 2, sizeof(double));
    int n = 0;
    for (int y = 0; y < G; y++) {
        for (int x = 0; x < (wall ? fold : G); x++, n++) {
            double p[3] = {x + 0.5, y + 0.5, 5.5};
            memcpy(h->surface.p + 3 * n, p, sizeof p);
            h->surface.normal[3 * n + 2] = 1;
        }
        for (int z = 5; wall && z < G; z++, n++) {
            double p[3] = {fold + 0.5, y + 0.5, z + 0.5};
            memcpy(h->surface.p + 3 * n, p, sizeof p);
            h->surface.normal[3 * n] = 1;
        }
    }
    h->surface.n = n;
    return n;
}

int main(void) {
    ws_status st;
    ws_status_clear(&st);
    ws_scene_hull h;
    ws_line_evidence e;
    int n = make_surface(&h, 12, 1);
    CHECK(ws_line_evidence_init(&e, &h, &st) == 0, "%s", st.msg);
    int at_fold = 0, fold_creases = 0, far_creases = 0;
    for (int k = 0; k < n; k++) {
        const double *p = h.surface.p + 3 * k;
        double along_x = 12.5 - p[0], up = p[2] - 5.5; /* distance from the fold on each side */
        if (p[1] < 4 || p[1] > G - 4) continue;      /* away from the grid's ends */
        if (along_x + up <= 1) {
            at_fold++;
            fold_creases += e.crease[k];
        }
        if (along_x >= 5 || up >= 5) far_creases += e.crease[k];
    }
    CHECK(at_fold > 0 && fold_creases == at_fold, "fold: %d of %d voxels are creases", fold_creases, at_fold);
    CHECK(far_creases == 0, "%d creases 5 voxels or more from the fold", far_creases);
    ws_line_evidence_free(&e);
    free(h.surface.p);
    free(h.surface.normal);
    n = make_surface(&h, 0, 0);
    CHECK(ws_line_evidence_init(&e, &h, &st) == 0, "%s", st.msg);
    int creases = 0;
    for (int k = 0; k < n; k++) creases += e.crease[k];
    CHECK(creases == 0, "a plane: %d crease voxels", creases);
    ws_line_evidence_free(&e);
    free(h.surface.p);
    free(h.surface.normal);
    return check_summary();
}
