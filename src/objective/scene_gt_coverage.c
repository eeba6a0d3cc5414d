/* scene_gt_coverage.c: a scene's ground-truth coverage (see scene_gt_coverage.h). */
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
    fprintf(fp, "\"gt_coverage\": {\"spacing\": %.9g, \"flagged\": %s, \"region_voxels\": %ld", c->spacing,
            c->flagged ? "true" : "false", c->region_voxels);
    for (int s = 0; s < WS_NSPLITS; s++)
        if (c->split[s].n)
            fprintf(fp, ", \"%s_uncovered\": %.9g, \"%s_uncovered_worst\": %.9g", ws_split_names[s],
                    c->split[s].mean, ws_split_names[s], c->split[s].worst);
    if (c->region_voxels)
        fprintf(fp, ", \"region_centroid\": [%.9g, %.9g, %.9g], \"region_lo\": [%.9g, %.9g, %.9g], "
                "\"region_hi\": [%.9g, %.9g, %.9g]", c->centroid[0], c->centroid[1], c->centroid[2], c->lo[0],
                c->lo[1], c->lo[2], c->hi[0], c->hi[1], c->hi[2]);
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
