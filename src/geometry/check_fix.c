/* check_fix.c: the corrected copy of a scene (ws_check_write_fixed, check.h). */
#include <cJSON.h>
#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "base/outfile.h"
#include "geometry/check.h"
#include "nn/base/bytes.h"

#define TRANSFORMS_MAX_BYTES ((size_t)64 << 20)

/* Applies split r's fix to the parsed transforms `root` (checked by the
 * scene loader already: an object with camera_angle_x and frames). */
static int fix_transforms(cJSON *root, const ws_check_split *r, ws_status *st) {
    cJSON *frames = cJSON_GetObjectItemCaseSensitive(root, "frames");
    int n = cJSON_GetArraySize(frames);
    if (r->repair_shift) {
        int s = r->repair_shift;
        cJSON **moved = ws_calloc(n, sizeof *moved, "frames", st);
        if (!moved) return st->code;
        for (int k = 0; k < n; k++) {
            int c = k + s;
            if (c >= 0 && c < n)
                moved[k] = cJSON_Duplicate(
                    cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(frames, c), "transform_matrix"), 1);
        }
        for (int k = n - 1; k >= 0; k--) {
            if (moved[k])
                cJSON_ReplaceItemInObjectCaseSensitive(cJSON_GetArrayItem(frames, k), "transform_matrix",
                                                       moved[k]);
            else
                cJSON_DeleteItemFromArray(frames, k);
        }
        free(moved);
    }
    if (r->cause == WS_CAUSE_OPENCV)
        for (cJSON *f = frames->child; f; f = f->next) {
            cJSON *m = cJSON_GetObjectItemCaseSensitive(f, "transform_matrix");
            for (int i = 0; i < 3; i++)
                for (int j = 1; j <= 2; j++) {
                    cJSON *e = cJSON_GetArrayItem(cJSON_GetArrayItem(m, i), j);
                    cJSON_SetNumberValue(e, -e->valuedouble);
                }
        }
    if (r->cause == WS_CAUSE_FOCAL) {
        cJSON *angle = cJSON_GetObjectItemCaseSensitive(root, "camera_angle_x");
        cJSON_SetNumberValue(angle, 2 * atan(tan(0.5 * angle->valuedouble) / r->focal_scale));
    }
    if (r->cause == WS_CAUSE_BAD_FRAMES)
        for (int d = r->ndisagree - 1; d >= 0; d--) cJSON_DeleteItemFromArray(frames, r->disagree[d]);
    return WS_OK;
}

static int write_split(const ws_scene *scene, int s, const ws_check_split *r, const char *out,
                       ws_status *st) {
    char in_path[WS_PATH_MAX], out_path[WS_PATH_MAX];
    snprintf(in_path, sizeof in_path, "%s/transforms_%s.json", scene->dir, ws_split_names[s]);
    snprintf(out_path, sizeof out_path, "%s/transforms_%s.json", out, ws_split_names[s]);
    unsigned char *bytes = NULL;
    size_t length = 0;
    if (ws_read_file(in_path, TRANSFORMS_MAX_BYTES, &bytes, &length, st)) return st->code;
    cJSON *root = cJSON_ParseWithLength((const char *)bytes, length);
    free(bytes);
    if (!root) return ws_fail(st, WS_EINPUT, "%s: changed while it was checked", in_path);
    char *text = NULL;
    int rc = fix_transforms(root, r, st);
    if (!rc && !(text = cJSON_Print(root))) rc = ws_fail(st, WS_ENOMEM, "out of memory for %s", out_path);
    cJSON_Delete(root);
    ws_outfile f;
    if (!rc && !(rc = ws_outfile_open(&f, out_path, st))) {
        fputs(text, f.fp);
        fputc('\n', f.fp);
        rc = ws_outfile_commit(&f, st);
    }
    free(text);
    return rc;
}

/* Links every entry of the scene directory but its transforms files. */
static int link_rest(const char *dir, const char *out, ws_status *st) {
    char real[PATH_MAX];
    if (!realpath(dir, real)) return ws_fail(st, WS_EIO, "%s: %s", dir, strerror(errno));
    DIR *d = opendir(real);
    if (!d) return ws_fail(st, WS_EIO, "%s: %s", dir, strerror(errno));
    int rc = WS_OK;
    for (struct dirent *e; !rc && (e = readdir(d));) {
        if (e->d_name[0] == '.' || !strncmp(e->d_name, "transforms_", 11)) continue;
        char target[PATH_MAX + 256], link[4400];
        snprintf(target, sizeof target, "%s/%s", real, e->d_name);
        snprintf(link, sizeof link, "%s/%s", out, e->d_name);
        if (symlink(target, link) && errno != EEXIST)
            rc = ws_fail(st, WS_EIO, "%s: cannot link: %s", link, strerror(errno));
    }
    closedir(d);
    return rc;
}

int ws_check_write_fixed(const ws_scene *scene, const ws_check_report *r, const char *out,
                         ws_status *st) {
    char a[PATH_MAX], b[PATH_MAX];
    if (ws_mkdir(out, st)) return st->code;
    if (realpath(scene->dir, a) && realpath(out, b) && !strcmp(a, b))
        return ws_fail(st, WS_EUSAGE, "--write-fixed: %s is the scene itself", out);
    for (int s = 0; s < WS_NSPLITS; s++)
        if (r->split[s].n > 0 && write_split(scene, s, &r->split[s], out, st)) return st->code;
    return link_rest(scene->dir, out, st);
}
