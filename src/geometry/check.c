/* check.c: the scene check (see check.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "geometry/check.h"
#include "geometry/hull.h"

#define MAX_SHIFT 2
/* The focal search (check.h): log2 of the scale over [-FOCAL_RANGE,
 * FOCAL_RANGE] in steps of FOCAL_COARSE, then around the best by halving
 * the step down to FOCAL_FINE, on every k-th image so that at most
 * FOCAL_VIEWS take part (its cost grows with the views; 24 gave the same
 * verdicts as all views on the copies compared: the rose, the nut, the
 * chair with its focal x1.1, the cube with x0.8). */
#define FOCAL_RANGE 1.0
#define FOCAL_COARSE 0.25
#define FOCAL_FINE (FOCAL_COARSE / 4)
#define FOCAL_VIEWS 24

/* A hypothesis: the image of frame k goes with the camera listed for frame
 * k + shift of the same transforms file (none there: left out), after
 * `flip` (OpenCV) and a focal scale. */
typedef struct {
    int shift, flip;
    double focal_scale;
    int every; /* images 0, every, 2 every, ... only */
} hypothesis;

/* The camera listed for frame `frame` of the file that holds split s
 * (ws_scene_file): a view of split s, or of any split in a nerfstudio
 * scene, whose frames are in one file; NULL where no view has that frame
 * (outside the file, or in a nerfstudio file a frame in no split). A
 * split's views are in frame order. */
static const ws_camera *listed_camera(const ws_scene *scene, int s, int frame) {
    for (int t = 0; t < WS_NSPLITS; t++) {
        if (t != s && scene->layout != WS_LAYOUT_NERFSTUDIO) continue;
        const ws_split *sp = &scene->split[t];
        int lo = 0, hi = sp->n;
        while (lo < hi) {
            int mid = (lo + hi) / 2;
            if (sp->views[mid].frame < frame)
                lo = mid + 1;
            else
                hi = mid;
        }
        if (lo < sp->n && sp->views[lo].frame == frame) return &sp->views[lo].cam;
    }
    return NULL;
}

static int make_camera(const ws_camera *listed, const hypothesis *h, ws_camera *out, ws_status *st) {
    double c2w[4][4];
    memcpy(c2w, listed->c2w, sizeof c2w);
    if (h->flip)
        for (int i = 0; i < 3; i++) {
            c2w[i][1] = -c2w[i][1];
            c2w[i][2] = -c2w[i][2];
        }
    double angle = 2 * atan(0.5 * listed->width / (listed->focal * h->focal_scale));
    return ws_camera_init(out, c2w, angle, listed->width, listed->height, "check", st);
}

/* Agreement of every image of split s with the others under hypothesis
 * h, on a conservative or a tight hull (hull.h); images without a camera
 * under it get NAN. Returns the mean over the images that have one in
 * *mean. */
static int agreement_under(const ws_scene *scene, int s, const ws_silhouette *sil, int resolution,
                           const hypothesis *h, int tight, double *agreement, double *mean,
                           ws_status *st) {
    const ws_split *sp = &scene->split[s];
    ws_camera *cams = ws_malloc(sizeof *cams * sp->n, "check cameras", st);
    ws_hull_view *hv = cams ? ws_malloc(sizeof *hv * sp->n, "check views", st) : NULL;
    double *a = hv ? ws_malloc(sizeof *a * sp->n, "check agreement", st) : NULL;
    int *image = a ? ws_malloc(sizeof *image * sp->n, "check pairs", st) : NULL;
    ws_hull hull = {0};
    int m = 0, rc = image ? WS_OK : st->code;
    for (int k = 0; k < sp->n && !rc; k++) {
        agreement[k] = NAN;
        const ws_camera *listed = listed_camera(scene, s, sp->views[k].frame + h->shift);
        if (!listed || k % h->every) continue;
        rc = make_camera(listed, h, &cams[m], st);
        hv[m] = (ws_hull_view){.cam = &cams[m], .sil = &sil[k]};
        image[m++] = k;
    }
    if (!rc && m > 0) rc = ws_hull_carve(hv, m, scene->center, resolution, ws_hull_default_tolerance(m), tight, &hull, st);
    if (!rc && m > 0) rc = ws_hull_agreement(hv, m, &hull, a, st);
    *mean = 0;
    for (int k = 0; k < m && !rc; k++) {
        agreement[image[k]] = a[k];
        *mean += a[k] / m;
    }
    ws_hull_free(&hull);
    free(cams);
    free(hv);
    free(a);
    free(image);
    return rc;
}

/* The focal scale whose tight hull agrees best with the split's images
 * (the listed focal wins ties): *scale, the tight mean agreement at the
 * listed focal in *listed and at *scale in *best. */
static int focal_search(const ws_scene *scene, int s, const ws_silhouette *sil, int resolution,
                        double *trial, double *scale, double *listed, double *best, ws_status *st) {
    const ws_split *sp = &scene->split[s];
    const int every = (sp->n + FOCAL_VIEWS - 1) / FOCAL_VIEWS;
    const hypothesis one = {0, 0, 1.0, every};
    int rc = agreement_under(scene, s, sil, resolution, &one, 1, trial, listed, st);
    double at = 0;
    *best = *listed;
    for (double x = -FOCAL_RANGE; x <= FOCAL_RANGE + 1e-9 && !rc; x += FOCAL_COARSE) {
        if (fabs(x) < 1e-9) continue;
        const hypothesis h = {0, 0, exp2(x), every};
        double mean;
        rc = agreement_under(scene, s, sil, resolution, &h, 1, trial, &mean, st);
        if (!rc && mean > *best) *best = mean, at = x;
    }
    for (double step = FOCAL_COARSE / 2; step >= FOCAL_FINE - 1e-12 && !rc; step /= 2) {
        const double around = at;
        for (int side = -1; side <= 1 && !rc; side += 2) {
            const hypothesis h = {0, 0, exp2(around + side * step), every};
            double mean;
            rc = agreement_under(scene, s, sil, resolution, &h, 1, trial, &mean, st);
            if (!rc && mean > *best) *best = mean, at = around + side * step;
        }
    }
    *scale = exp2(at);
    return rc;
}

static int check_split(const ws_scene *scene, int s, const ws_silhouette *sil, int resolution,
                       ws_check_split *r, ws_status *st) {
    const ws_split *sp = &scene->split[s];
    *r = (ws_check_split){.n = sp->n, .focal_scale = 1, .focal_estimate = 1};
    if (sp->n == 0) return WS_OK;
    double *trial = ws_malloc(sizeof *trial * sp->n, "check agreement", st);
    r->agreement = trial ? ws_malloc(sizeof *r->agreement * sp->n, "check agreement", st) : NULL;
    r->disagree = r->agreement ? ws_malloc(sizeof *r->disagree * sp->n, "check agreement", st) : NULL;
    int rc = r->disagree ? WS_OK : st->code;
    const hypothesis listed = {0, 0, 1.0, 1};
    if (!rc) rc = agreement_under(scene, s, sil, resolution, &listed, 0, r->agreement, &r->mean, st);
    if (!rc) {
        r->worst = 1;
        for (int k = 0; k < sp->n; k++) {
            r->worst = fmin(r->worst, r->agreement[k]);
            if (r->agreement[k] < WS_CHECK_VIEW_OK) r->disagree[r->ndisagree++] = k;
        }
    }
    int inconsistent = !rc && (r->mean < WS_CHECK_MEAN_OK || r->ndisagree > 0);
    if (inconsistent) {
        /* A few views that disagree with others that agree: bad frames. */
        int allowed = sp->n / 10 > 1 ? sp->n / 10 : 1;
        double others = 0;
        for (int k = 0, d = 0; k < sp->n; k++) {
            if (d < r->ndisagree && r->disagree[d] == k)
                d++;
            else
                others += r->agreement[k] / (sp->n - r->ndisagree);
        }
        if (r->ndisagree > 0 && r->ndisagree <= allowed && sp->n > r->ndisagree &&
            others >= WS_CHECK_MEAN_OK) {
            r->cause = WS_CAUSE_BAD_FRAMES;
            r->fixed_mean = others;
            inconsistent = 0;
        }
    }
    /* The focal estimate: the focal hypothesis of an inconsistent split, or
     * the tight test of a consistent one with enough views. */
    if (!rc && (inconsistent || (r->cause == WS_CAUSE_NONE && sp->n >= WS_CHECK_FOCAL_VIEWS)))
        rc = focal_search(scene, s, sil, resolution, trial, &r->focal_estimate, &r->tight_mean,
                          &r->tight_fixed, st);
    double best = r->mean + WS_CHECK_GAIN;
    /* Every hypothesis of one cause, in a fixed order (the focal one at the
     * estimated scale); ties keep the first. */
    for (int shift = -MAX_SHIFT; shift <= MAX_SHIFT && !rc && inconsistent; shift++)
        for (int flip = 0; flip <= 1 && !rc; flip++)
            for (int focal = 0; focal <= 1 && !rc; focal++) {
                if ((shift != 0) + flip + focal != 1 || (focal && r->focal_estimate == 1)) continue;
                hypothesis h = {shift, flip, focal ? r->focal_estimate : 1.0, 1};
                double mean;
                rc = agreement_under(scene, s, sil, resolution, &h, 0, trial, &mean, st);
                if (rc || !(mean >= WS_CHECK_MEAN_OK && mean > best)) continue;
                best = r->fixed_mean = mean;
                r->cause = shift ? WS_CAUSE_SHIFT : flip ? WS_CAUSE_OPENCV : WS_CAUSE_FOCAL;
                r->shift = shift;
                r->focal_scale = h.focal_scale;
            }
    /* A split the conservative hull finds consistent may still have a wrong
     * focal that the tight one shows (check.h). */
    if (!rc && !inconsistent && r->cause == WS_CAUSE_NONE && sp->n >= WS_CHECK_FOCAL_VIEWS &&
        fabs(log(r->focal_estimate)) > log(WS_CHECK_FOCAL_OFF) &&
        r->tight_fixed - r->tight_mean > WS_CHECK_FOCAL_GAIN) {
        r->cause = WS_CAUSE_FOCAL;
        r->focal_scale = r->focal_estimate;
        r->fixed_mean = r->tight_fixed;
    }
    if (inconsistent && r->cause == WS_CAUSE_NONE) {
        r->cause = WS_CAUSE_UNKNOWN;
        r->fixed_mean = r->mean;
    }
    free(trial);
    return rc;
}

/* One line for the first inconsistent split. It names the split's file
 * (ws_scene_file) and its frames by their index there; where that file
 * holds every split (nerfstudio), it also names the split. */
static void explain(const ws_scene *scene, int s, const ws_check_split *r, char *line, size_t size) {
    const char *split = ws_split_names[s], *file = ws_scene_file(scene, s);
    char views[32] = "", whose[32] = ""; /* "train ", "the train views' " */
    if (scene->layout == WS_LAYOUT_NERFSTUDIO) {
        snprintf(views, sizeof views, "%s ", split);
        snprintf(whose, sizeof whose, "the %s views' ", split);
    }
    switch (r->cause) {
    case WS_CAUSE_NONE:
        line[0] = 0;
        break;
    case WS_CAUSE_SHIFT:
        snprintf(line, size,
                 "%.300s/%s: the image of frame k belongs to the camera listed for frame k%+d "
                 "(%sagreement %.2f, re-paired %.2f); write a corrected copy with "
                 "`wiresketch check %.300s --write-fixed DIR`",
                 scene->dir, file, r->shift, whose, r->mean, r->fixed_mean, scene->dir);
        break;
    case WS_CAUSE_OPENCV:
        snprintf(line, size,
                 "%.300s/%s: the cameras are in the OpenCV convention (y down, z "
                 "forward; %sagreement %.2f, flipped %.2f); negate the second and third columns of "
                 "every transform_matrix, or write a corrected copy with "
                 "`wiresketch check %.300s --write-fixed DIR`",
                 scene->dir, file, whose, r->mean, r->fixed_mean, scene->dir);
        break;
    case WS_CAUSE_FOCAL: {
        if (scene->layout == WS_LAYOUT_NERFSTUDIO) { /* focal lengths in pixels, one file */
            snprintf(line, size,
                     "%.300s/%s: fl_x and fl_y do not fit the %s images; about %.3g times "
                     "them does (tight-hull agreement %.3f, corrected %.3f); multiply fl_x and fl_y "
                     "by %.3g, or write a corrected copy with `wiresketch check %.300s --write-fixed DIR`",
                     scene->dir, file, split, r->focal_scale, r->tight_mean, r->tight_fixed,
                     r->focal_scale, scene->dir);
            break;
        }
        double listed = 2 * atan(0.5 * scene->split[s].views[0].cam.width /
                                 scene->split[s].views[0].cam.focal);
        double fixed = 2 * atan(tan(0.5 * listed) / r->focal_scale);
        snprintf(line, size,
                 "%.300s/%s: camera_angle_x %.4g does not fit the images; about %.4g "
                 "does (focal x%.3g; tight-hull agreement %.3f, corrected %.3f); fix camera_angle_x, "
                 "or write a corrected copy with `wiresketch check %.300s --write-fixed DIR`",
                 scene->dir, file, listed, fixed, r->focal_scale, r->tight_mean, r->tight_fixed,
                 scene->dir);
        break;
    }
    case WS_CAUSE_BAD_FRAMES: {
        int at = snprintf(line, size, "%.300s/%s: frame%s", scene->dir, file, r->ndisagree > 1 ? "s" : "");
        for (int d = 0; d < r->ndisagree && at > 0 && (size_t)at < size; d++) {
            const ws_view *v = &scene->split[s].views[r->disagree[d]];
            at += snprintf(line + at, size - at, "%s %d (%s, agreement %.2f)", d ? "," : "", v->frame,
                           v->name, r->agreement[r->disagree[d]]);
        }
        if (at > 0 && (size_t)at < size)
            snprintf(line + at, size - at,
                     " disagree%s with the other %sviews (mean %.2f): fix %s transform_matrix or "
                     "image, or remove %s",
                     r->ndisagree > 1 ? "" : "s", views, r->fixed_mean, r->ndisagree > 1 ? "their" : "its",
                     r->ndisagree > 1 ? "them" : "it");
        break;
    }
    case WS_CAUSE_UNKNOWN:
        snprintf(line, size,
                 "%.300s/%s: the %sviews do not agree with each other (mean agreement "
                 "%.2f, worst %.2f) and no frame shift, OpenCV flip or field of view explains it; "
                 "check the cameras and the images",
                 scene->dir, file, views, r->mean, r->worst);
        break;
    }
}

/* The hypothesis a split's cause names (shift, OpenCV or focal). */
static int hypothesis_cause(ws_check_cause cause) {
    return cause == WS_CAUSE_SHIFT || cause == WS_CAUSE_OPENCV || cause == WS_CAUSE_FOCAL;
}

/* A cause found in one split is usually in every split, though not every
 * split shows it: a split whose cameras form a regular orbit or spiral
 * cannot show a shift (shifting such cameras by a frame turns them all
 * alike, which keeps them consistent), and a split of a few views can
 * agree under more than one hypothesis. So the hypothesis of one split,
 * *from, is measured on the others:
 * - each split its own file (NeRF-synthetic): the first split's shift, on
 *   the consistent splits, which the fix re-pairs when they agree as well
 *   re-paired;
 * - one file for every split (nerfstudio): that of the split with the most
 *   views whose cause is a hypothesis, on every split with another cause:
 *   one that agrees under it has that cause (a consistent one keeps its
 *   verdict, and a shift re-pairs it too), since the file's frame order,
 *   convention and focal are those of all its splits. */
static int cause_elsewhere(const ws_scene *scene, const ws_silhouette *const sil[WS_NSPLITS], int resolution,
                           ws_check_report *r, int *from, ws_status *st) {
    const int one_file = scene->layout == WS_LAYOUT_NERFSTUDIO;
    *from = -1;
    for (int s = 0; s < WS_NSPLITS; s++) {
        const ws_check_split *c = &r->split[s];
        if (one_file ? hypothesis_cause(c->cause) && (*from < 0 || c->n > r->split[*from].n)
                     : c->cause == WS_CAUSE_SHIFT && *from < 0)
            *from = s;
    }
    if (*from < 0) return WS_OK;
    const ws_check_split *e = &r->split[*from];
    const hypothesis h = {e->cause == WS_CAUSE_SHIFT ? e->shift : 0, e->cause == WS_CAUSE_OPENCV,
                          e->cause == WS_CAUSE_FOCAL ? e->focal_scale : 1.0, 1};
    for (int s = 0; s < WS_NSPLITS; s++) {
        ws_check_split *c = &r->split[s];
        const int same = c->cause == e->cause && c->shift == e->shift && c->focal_scale == e->focal_scale;
        if (s == *from || c->n == 0 || (one_file ? same : c->cause != WS_CAUSE_NONE)) continue;
        double *trial = ws_malloc(sizeof *trial * c->n, "check agreement", st);
        int rc = trial ? WS_OK : st->code;
        double mean = 0;
        if (!rc) rc = agreement_under(scene, s, sil[s], resolution, &h, 0, trial, &mean, st);
        if (!rc && mean >= WS_CHECK_MEAN_OK) {
            c->repair_shift = h.shift;
            if (c->cause != WS_CAUSE_NONE) {
                c->cause = e->cause;
                c->shift = e->shift;
                c->focal_scale = e->focal_scale;
                c->fixed_mean = mean;
            }
        }
        free(trial);
        if (rc) return rc;
    }
    return WS_OK;
}

int ws_check_scene(const ws_scene *scene, const ws_silhouette *const sil[WS_NSPLITS], int resolution,
                   ws_check_report *r, ws_status *st) {
    memset(r, 0, sizeof *r);
    for (int s = 0; s < WS_NSPLITS; s++) {
        if (check_split(scene, s, sil[s], resolution, &r->split[s], st)) {
            ws_check_report_free(r);
            return st->code;
        }
        if (r->split[s].cause == WS_CAUSE_SHIFT) r->split[s].repair_shift = r->split[s].shift;
    }
    int from;
    if (cause_elsewhere(scene, sil, resolution, r, &from, st)) {
        ws_check_report_free(r);
        return st->code;
    }
    /* The line explains the first inconsistent split; in one file, the
     * split whose cause the others were measured under. */
    r->explained = -1;
    for (int s = WS_NSPLITS - 1; s >= 0; s--)
        if (r->split[s].cause != WS_CAUSE_NONE) r->explained = s;
    if (scene->layout == WS_LAYOUT_NERFSTUDIO && from >= 0) r->explained = from;
    r->consistent = r->explained < 0;
    if (!r->consistent) explain(scene, r->explained, &r->split[r->explained], r->line, sizeof r->line);
    return WS_OK;
}

int ws_check_focal_only(const ws_check_report *r) {
    if (r->consistent) return 0;
    for (int s = 0; s < WS_NSPLITS; s++) {
        const ws_check_split *c = &r->split[s];
        if (c->n > 0 && c->cause != WS_CAUSE_NONE &&
            (c->cause != WS_CAUSE_FOCAL || c->mean < WS_CHECK_MEAN_OK || c->ndisagree > 0))
            return 0;
    }
    return 1;
}

void ws_check_report_free(ws_check_report *r) {
    for (int s = 0; s < WS_NSPLITS; s++) {
        free(r->split[s].agreement);
        free(r->split[s].disagree);
        r->split[s].agreement = NULL;
        r->split[s].disagree = NULL;
    }
}
