/* scene_gt_coverage.c: a scene's ground-truth coverage (see scene_gt_coverage.h). */
#include <string.h>
#include "base/json_number.h"
#include "geometry/check.h"
#include "objective/scene_gt_coverage.h"
#include "render/curves.h"

int ws_scene_gt_coverage(const ws_scene *scene, ws_view_targets *targets, const char *gt_points,
                         const char *gt_curves, ws_gt_coverage *c, ws_status *st) {
    const ws_silhouette *sil[WS_NSPLITS];
    ws_pointcloud pc = {0};
    ws_curves tubes = {0};
    int rc = WS_OK;
    for (int s = 0; s < WS_NSPLITS && !rc; s++) rc = ws_view_targets_silhouettes(targets, s, &sil[s], st);
    /* silhouettes that show no object (a busy background without masks)
     * say nothing of what the ground truth misses: nothing measured */
    int empty, edge;
    if (!rc && !ws_check_silhouettes_usable(sil[WS_TRAIN], scene->split[WS_TRAIN].n, &empty, &edge)) {
        memset(c, 0, sizeof *c);
        c->reference = -1;
        return WS_OK;
    }
    if (!rc) rc = ws_pointcloud_load_ply(gt_points, &pc, st);
    if (!rc && gt_curves && *gt_curves) rc = ws_curves_load(gt_curves, &tubes, st);
    if (!rc)
        rc = ws_gt_coverage_measure(scene, sil, &pc, gt_curves && *gt_curves ? tubes.thickness : 0, gt_points,
                                    WS_CHECK_RESOLUTION, c, st);
    ws_curves_free(&tubes);
    ws_pointcloud_free(&pc);
    return rc;
}

void ws_gt_coverage_json(FILE *fp, const ws_gt_coverage *c) {
    fputs("\"gt_coverage\": {", fp);
    ws_json_number(fp, "spacing", c->spacing, 9);
    fprintf(fp, ", \"flagged\": %s, \"region_voxels\": %ld", c->flagged ? "true" : "false", c->region_voxels);
    for (int s = 0; s < WS_NSPLITS; s++) {
        char key[2][40];
        snprintf(key[0], sizeof key[0], "%s_uncovered", ws_split_names[s]);
        snprintf(key[1], sizeof key[1], "%s_uncovered_worst", ws_split_names[s]);
        for (int j = 0; j < 2 && c->split[s].n; j++) {
            fputs(", ", fp);
            ws_json_number(fp, key[j], j ? c->split[s].worst : c->split[s].mean, 9);
        }
    }
    const char *const region[3] = {"region_centroid", "region_lo", "region_hi"};
    const double *corner[3] = {c->centroid, c->lo, c->hi};
    for (int k = 0; k < 3 && c->region_voxels; k++) {
        fprintf(fp, ", \"%s\": [", region[k]);
        int bad = 0;
        for (int j = 0; j < 3; j++) {
            fputs(j ? ", " : "", fp);
            bad += ws_json_value(fp, corner[k][j], 9);
        }
        fputc(']', fp);
        if (bad) fprintf(fp, ", \"%s_why\": \"%d of its values are not finite, which JSON cannot hold\"", region[k], bad);
    }
    if (c->flagged) {
        fprintf(fp, ", \"warning\": \"");
        for (const char *p = c->line; *p; p++)
            if (*p == '"' || *p == '\\')
                fprintf(fp, "\\%c", *p);
            else if ((unsigned char)*p < 0x20)
                fprintf(fp, "\\u%04x", (unsigned char)*p);
            else
                fputc(*p, fp);
        fputc('"', fp);
    }
    fprintf(fp, "}");
}
