/* check.c: the scene check (see check.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "geometry/check.h"
#include "geometry/hull.h"

#define MAX_SHIFT 2
/* The focal search (check.h): log2 of the scale over [-FOCAL_RANGE,
 * FOCAL_RANGE] in steps of FOCAL_COARSE on a tight hull of the check's
 * resolution, then, on one FOCAL_REFINE times finer, the listed focal and
 * around the coarse best by halving the step down to FOCAL_FINE; on every
 * k-th image so that at most FOCAL_VIEWS take part (its cost grows with
 * the views, and that many give the verdicts of all: docs/RESULTS.md,
 * "Numbers behind the code's constants"). The finer hull is what makes the
 * estimate right: at the check's resolution a voxel spans pixels, and a
 * tight hull that coarse covers more of every view the shorter the focal,
 * so the peak leans to short focals (docs/RESULTS.md, "check: false
 * alarms, principal points, crops and busy backgrounds"). The coarse pass
 * still lands within a coarse step of the peak, which the refinement
 * searches; where the listed focal wins the coarse pass there is nothing
 * to refine. */
#define FOCAL_RANGE 1.0
#define FOCAL_COARSE 0.25
#define FOCAL_FINE (FOCAL_COARSE / 4)
#define FOCAL_REFINE 2
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
    /* The principal point as listed: a crop's is anywhere (scene.h). */
    return ws_camera_init_pinhole(out, c2w, listed->focal * h->focal_scale, listed->cx, listed->cy, listed->width,
                                  listed->height, "check", st);
}

/* The views of split s under hypothesis h (a view of each image that has
 * a camera under it, every h->every-th; with `bad`, the bad frames of that
 * verdict left out): hv[m], image[m] its index in the split, a[m] its
 * agreement once measured. */
typedef struct {
    ws_camera *cams;
    ws_hull_view *hv;
    int *image;
    double *a;
    int m;
} view_set;

static void view_set_free(view_set *v) {
    free(v->cams);
    free(v->hv);
    free(v->image);
    free(v->a);
}

static int view_set_make(const ws_scene *scene, int s, const ws_silhouette *sil, const hypothesis *h,
                         const ws_check_split *bad, view_set *v, ws_status *st) {
    const ws_split *sp = &scene->split[s];
    *v = (view_set){0};
    v->cams = ws_malloc(sizeof *v->cams * sp->n, "check cameras", st);
    v->hv = v->cams ? ws_malloc(sizeof *v->hv * sp->n, "check views", st) : NULL;
    v->image = v->hv ? ws_malloc(sizeof *v->image * sp->n, "check pairs", st) : NULL;
    v->a = v->image ? ws_malloc(sizeof *v->a * sp->n, "check agreement", st) : NULL;
    int rc = v->a ? WS_OK : st->code;
    for (int k = 0, d = 0; k < sp->n && !rc; k++) {
        if (bad && d < bad->ndisagree && bad->disagree[d] == k) {
            d++;
            continue;
        }
        const ws_camera *listed = listed_camera(scene, s, sp->views[k].frame + h->shift);
        if (!listed || k % h->every) continue;
        rc = make_camera(listed, h, &v->cams[v->m], st);
        v->hv[v->m] = (ws_hull_view){.cam = &v->cams[v->m], .sil = &sil[k]};
        v->image[v->m++] = k;
    }
    if (rc) view_set_free(v);
    return rc;
}

/* The mean agreement of a view set measured: over its views, 0 for none. */
static double view_set_mean(const view_set *v) {
    double mean = 0;
    for (int k = 0; k < v->m; k++) mean += v->a[k] / v->m;
    return mean;
}

/* Carves the hull of a view set (empty: no hull) and measures each view's
 * agreement with the hull of the others into v->a. */
static int carve_measure(const ws_scene *scene, view_set *v, int resolution, int tight, ws_hull *hull,
                         ws_status *st) {
    *hull = (ws_hull){0};
    int rc = WS_OK;
    if (v->m > 0)
        rc = ws_hull_carve(v->hv, v->m, scene->center, resolution, ws_hull_default_tolerance(v->m), tight, hull,
                           st);
    if (!rc && v->m > 0) rc = ws_hull_agreement(v->hv, v->m, 1, hull, v->a, st);
    return rc;
}

/* Agreement of every image of split s with the others under hypothesis
 * h, on a conservative or a tight hull (hull.h); images without a camera
 * under it get NAN. Returns the mean over the images that have one in
 * *mean. */
static int agreement_under(const ws_scene *scene, int s, const ws_silhouette *sil, int resolution,
                           const hypothesis *h, int tight, double *agreement, double *mean,
                           ws_status *st) {
    view_set v;
    ws_hull hull;
    int rc = view_set_make(scene, s, sil, h, NULL, &v, st);
    if (rc) return rc;
    rc = carve_measure(scene, &v, resolution, tight, &hull, st);
    for (int k = 0; k < scene->split[s].n; k++) agreement[k] = NAN;
    for (int k = 0; k < v.m && !rc; k++) agreement[v.image[k]] = v.a[k];
    *mean = rc ? 0 : view_set_mean(&v);
    ws_hull_free(&hull);
    view_set_free(&v);
    return rc;
}

/* The focal scale whose tight hull agrees best with the split's images
 * (the listed focal wins ties): *scale, the tight mean agreement at the
 * listed focal in *listed and at *scale in *best, both on the finer hull
 * unless the listed focal wins the coarse pass (then on the coarse one,
 * with *scale 1: a correct scene costs no finer hull). */
static int focal_search(const ws_scene *scene, int s, const ws_silhouette *sil, int resolution,
                        double *trial, double *scale, double *listed, double *best, ws_status *st) {
    const ws_split *sp = &scene->split[s];
    const int every = (sp->n + FOCAL_VIEWS - 1) / FOCAL_VIEWS;
    const hypothesis one = {0, 0, 1.0, every};
    double at = 0, coarse_best;
    int rc = agreement_under(scene, s, sil, resolution, &one, 1, trial, &coarse_best, st);
    for (double x = -FOCAL_RANGE; x <= FOCAL_RANGE + 1e-9 && !rc; x += FOCAL_COARSE) {
        if (fabs(x) < 1e-9) continue;
        const hypothesis h = {0, 0, exp2(x), every};
        double mean;
        rc = agreement_under(scene, s, sil, resolution, &h, 1, trial, &mean, st);
        if (!rc && mean > coarse_best) coarse_best = mean, at = x;
    }
    *scale = 1;
    *listed = *best = coarse_best;
    if (rc || at == 0) return rc; /* the listed focal wins: nothing to refine */
    const int fine = FOCAL_REFINE * resolution;
    rc = agreement_under(scene, s, sil, fine, &one, 1, trial, listed, st);
    *best = *listed;
    const double coarse_at = at;
    at = 0;
    if (!rc) {
        const hypothesis h = {0, 0, exp2(coarse_at), every};
        double mean;
        rc = agreement_under(scene, s, sil, fine, &h, 1, trial, &mean, st);
        if (!rc && mean > *best) *best = mean, at = coarse_at;
    }
    for (double step = FOCAL_COARSE / 2; step >= FOCAL_FINE - 1e-12 && !rc; step /= 2) {
        const double around = at;
        for (int side = -1; side <= 1 && !rc; side += 2) {
            const hypothesis h = {0, 0, exp2(around + side * step), every};
            double mean;
            rc = agreement_under(scene, s, sil, fine, &h, 1, trial, &mean, st);
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
        r->tight_fixed - r->tight_mean > WS_CHECK_FOCAL_GAIN &&
        r->tight_fixed - r->tight_mean >= WS_CHECK_FOCAL_EXPLAINS * (1 - r->tight_mean)) {
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

/* explain's line for a focal the images do not fit (split s, r its
 * report): the corrected value in the file's own terms, and the agreement
 * `tight` before and after. */
static void explain_focal(const ws_scene *scene, const ws_check_split *r, int s, const char *tight,
                          double tight_before, double tight_after, char *line, size_t size) {
    const char *file = ws_scene_file(scene, s);
    if (scene->layout == WS_LAYOUT_NERFSTUDIO) { /* focal lengths in pixels, one file */
        snprintf(line, size,
                 "%.300s/%s: fl_x and fl_y do not fit the %s images; about %.3g times "
                 "them does (%s %.3f, corrected %.3f); multiply fl_x and fl_y "
                 "by %.3g, or write a corrected copy with `wiresketch check %.300s --write-fixed DIR`",
                 scene->dir, file, ws_split_names[s], r->focal_scale, tight, tight_before, tight_after,
                 r->focal_scale, scene->dir);
        return;
    }
    double listed = 2 * atan(0.5 * scene->split[s].views[0].cam.width / scene->split[s].views[0].cam.focal);
    double fixed = 2 * atan(tan(0.5 * listed) / r->focal_scale);
    snprintf(line, size,
             "%.300s/%s: camera_angle_x %.4g does not fit the images; about %.4g "
             "does (focal x%.3g; %s %.3f, corrected %.3f); fix camera_angle_x, "
             "or write a corrected copy with `wiresketch check %.300s --write-fixed DIR`",
             scene->dir, file, listed, fixed, r->focal_scale, tight, tight_before, tight_after, scene->dir);
}

/* explain's line for frames of split s that disagree with the others
 * (views: "train " in a nerfstudio file, else ""). */
static void explain_frames(const ws_scene *scene, const ws_check_split *r, int s, const char *views, char *line,
                           size_t size) {
    int at = snprintf(line, size, "%.300s/%s: frame%s", scene->dir, ws_scene_file(scene, s),
                      r->ndisagree > 1 ? "s" : "");
    for (int d = 0; d < r->ndisagree && at > 0 && (size_t)at < size; d++) {
        const ws_view *v = &scene->split[s].views[r->disagree[d]];
        at += snprintf(line + at, size - at, "%s %d (%s, agreement %.2f)", d ? "," : "", v->frame, v->name,
                       r->agreement[r->disagree[d]]);
    }
    if (at > 0 && (size_t)at < size)
        snprintf(line + at, size - at,
                 " disagree%s with the other %sviews (mean %.2f): fix %s transform_matrix or "
                 "image, or remove %s",
                 r->ndisagree > 1 ? "" : "s", views, r->fixed_mean, r->ndisagree > 1 ? "their" : "its",
                 r->ndisagree > 1 ? "them" : "it");
}

/* One line for the first inconsistent split. It names the split's file
 * (ws_scene_file) and its frames by their index there; where that file
 * holds every split (nerfstudio), it also names the split. A cause the
 * cross-split test found is told by the agreement it measured: that of the
 * other splits' views with the split's hull (the reference), or of the
 * split's views with the reference's hull. */
static void explain(const ws_scene *scene, const ws_check_report *rep, int s, char *line, size_t size) {
    const ws_check_split *r = &rep->split[s];
    const char *split = ws_split_names[s], *file = ws_scene_file(scene, s);
    char views[32] = "", whose[32] = ""; /* "train ", "the train views' " */
    if (scene->layout == WS_LAYOUT_NERFSTUDIO) {
        snprintf(views, sizeof views, "%s ", split);
        snprintf(whose, sizeof whose, "the %s views' ", split);
    }
    char measure[96], tight[96] = "tight-hull agreement", who[48] = "";
    int digits = 2; /* of the agreement; 3 for the cross-split test's, whose threshold is finer */
    double before = r->mean, after = r->fixed_mean, tight_before = r->tight_mean, tight_after = r->tight_fixed;
    snprintf(measure, sizeof measure, "%sagreement", whose);
    if (r->by_cross) {
        for (int t = 0, n = 0, at = 0; t < WS_NSPLITS && s == rep->reference; t++)
            if (t != s && rep->split[t].n > 0)
                at += snprintf(who + at, sizeof who - at, "%s%s", n++ ? " and " : "", ws_split_names[t]);
        snprintf(measure, sizeof measure, "the %s views' agreement with the %s views' hull",
                 s == rep->reference ? who : split, ws_split_names[rep->reference]);
        memcpy(tight, measure, sizeof tight);
        digits = 3;
        before = tight_before = r->cross_before;
        after = tight_after = r->cross_after;
    }
    switch (r->cause) {
    case WS_CAUSE_NONE:
        line[0] = 0;
        break;
    case WS_CAUSE_SHIFT:
        snprintf(line, size,
                 "%.300s/%s: the image of frame k belongs to the camera listed for frame k%+d "
                 "(%s %.*f, re-paired %.*f); write a corrected copy with "
                 "`wiresketch check %.300s --write-fixed DIR`",
                 scene->dir, file, r->shift, measure, digits, before, digits, after, scene->dir);
        break;
    case WS_CAUSE_OPENCV:
        snprintf(line, size,
                 "%.300s/%s: the cameras are in the OpenCV convention (y down, z "
                 "forward; %s %.*f, flipped %.*f); negate the second and third columns of "
                 "every transform_matrix, or write a corrected copy with "
                 "`wiresketch check %.300s --write-fixed DIR`",
                 scene->dir, file, measure, digits, before, digits, after, scene->dir);
        break;
    case WS_CAUSE_FOCAL:
        explain_focal(scene, r, s, tight, tight_before, tight_after, line, size);
        break;
    case WS_CAUSE_BAD_FRAMES:
        explain_frames(scene, r, s, views, line, size);
        break;
    case WS_CAUSE_UNKNOWN:
        if (r->by_cross)
            snprintf(line, size,
                     "%.300s/%s: the %s views do not agree with the hull of the %s views (mean agreement "
                     "%.3f, worst %.3f) and no frame shift, OpenCV flip or field of view of either file "
                     "explains it; check the cameras and the images",
                     scene->dir, file, split, ws_split_names[rep->reference], r->cross, r->cross_worst);
        else
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

/* In a nerfstudio scene one file holds every split, and its frame order,
 * convention and focal are those of all of them, though not every split
 * shows a fault: a split whose cameras form a regular orbit or spiral
 * cannot show a shift (shifting such cameras by a frame turns them all
 * alike, which keeps them consistent), and a split of a few views can
 * agree under more than one hypothesis. So the hypothesis of the split
 * with the most views whose cause is one, *from, is measured on every
 * split with another cause: one that agrees under it has that cause (a
 * consistent one keeps its verdict, and a shift re-pairs it too). (Where
 * each split has its own file, the cross-split test below weighs each
 * file's hypotheses instead.) */
static int cause_elsewhere(const ws_scene *scene, const ws_silhouette *const sil[WS_NSPLITS], int resolution,
                           ws_check_report *r, int *from, ws_status *st) {
    *from = -1;
    for (int s = 0; s < WS_NSPLITS && scene->layout == WS_LAYOUT_NERFSTUDIO; s++) {
        const ws_check_split *c = &r->split[s];
        if (hypothesis_cause(c->cause) && (*from < 0 || c->n > r->split[*from].n)) *from = s;
    }
    if (*from < 0) return WS_OK;
    const ws_check_split *e = &r->split[*from];
    const hypothesis h = {e->cause == WS_CAUSE_SHIFT ? e->shift : 0, e->cause == WS_CAUSE_OPENCV,
                          e->cause == WS_CAUSE_FOCAL ? e->focal_scale : 1.0, 1};
    for (int s = 0; s < WS_NSPLITS; s++) {
        ws_check_split *c = &r->split[s];
        if (s == *from || c->n == 0 ||
            (c->cause == e->cause && c->shift == e->shift && c->focal_scale == e->focal_scale))
            continue;
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

/* The fix the check has found for a split, as a hypothesis of the
 * cross-split test: its shift or flip; the focal as listed, since the test
 * cannot weigh a focal (nth_hypothesis) and each split's own verdict on it
 * stands. */
static hypothesis fix_of(const ws_check_split *c) {
    return (hypothesis){c->repair_shift, c->cause == WS_CAUSE_OPENCV, 1.0, 1};
}

/* The hypotheses of the cross-split test for a split whose found fix is
 * `found`, in a fixed order (ties keep the first): the cameras as listed,
 * shifts -MAX_SHIFT .. MAX_SHIFT, the OpenCV flip, each but the found fix.
 * No focal: the agreement is the share of a silhouette the hull covers,
 * and a focal that enlarges the hull covers more of any view, so the
 * cross test cannot weigh one (each split's tight-hull estimate does).
 * *h: hypothesis `i`; returns 0 past the last. */
static int nth_hypothesis(const hypothesis *found, int i, hypothesis *h) {
    static const hypothesis all[] = {{0, 0, 1.0, 1}, {-2, 0, 1.0, 1}, {-1, 0, 1.0, 1}, {1, 0, 1.0, 1},
                                     {2, 0, 1.0, 1}, {0, 1, 1.0, 1}};
    for (int k = 0, n = 0; k < (int)(sizeof all / sizeof all[0]); k++) {
        if (all[k].shift == found->shift && all[k].flip == found->flip) continue;
        if (n++ == i) {
            *h = all[k];
            return 1;
        }
    }
    return 0;
}

/* Split t's agreement with the hull `ref` of another split, its views
 * under ht (bad: the bad frames of its verdict left out): *mean, *worst. */
static int held_out(const ws_scene *scene, int t, const ws_silhouette *sil, const hypothesis *ht,
                    const ws_check_split *bad, const ws_hull *ref, double *mean, double *worst,
                    ws_status *st) {
    view_set v;
    int rc = view_set_make(scene, t, sil, ht, bad, &v, st);
    if (!rc && v.m > 0 && ref->outside) rc = ws_hull_agreement(v.hv, v.m, 0, ref, v.a, st);
    if (!rc && v.m > 0 && !ref->outside)
        for (int k = 0; k < v.m; k++) v.a[k] = 0; /* an empty hull covers nothing */
    *mean = rc ? 0 : view_set_mean(&v);
    *worst = 1;
    for (int k = 0; k < v.m && !rc; k++) *worst = fmin(*worst, v.a[k]);
    view_set_free(&v);
    return rc;
}

/* One assignment of fixes the cross-split test weighs: the reference's
 * hypothesis and each other split's, how many of those splits no
 * hypothesis brings to agree, how many fixes differ from the found ones,
 * and the other splits' agreement pooled over their views. */
typedef struct {
    hypothesis h[WS_NSPLITS];
    int changed[WS_NSPLITS];
    double before[WS_NSPLITS], worst[WS_NSPLITS]; /* mean and worst agreement under the found fix */
    double after[WS_NSPLITS];                      /* mean agreement under h */
    int disagrees[WS_NSPLITS];                     /* under every hypothesis tried */
    int unexplained, changes;
    double pooled, self;
} assignment;

/* Fewer splits left disagreeing, then fewer changes, then the higher
 * pooled agreement, with no margin: a frame shift either way along an
 * orbit can agree nearly as well (docs/METHOD.md section 12, "Across
 * splits"). */
static int better(const assignment *a, const assignment *b) {
    if (a->unexplained != b->unexplained) return a->unexplained < b->unexplained;
    if (a->changes != b->changes) return a->changes < b->changes;
    return a->pooled > b->pooled;
}

/* Applies hypothesis h to split c as the cross test's verdict. */
static void apply_cross(ws_check_split *c, const hypothesis *h, double before, double after) {
    c->by_cross = 1;
    c->cross_before = before;
    c->cross_after = after;
    c->repair_shift = h->shift;
    if (h->shift || h->flip) {
        c->cause = h->shift ? WS_CAUSE_SHIFT : WS_CAUSE_OPENCV;
        c->shift = h->shift;
        c->focal_scale = 1;
        c->fixed_mean = NAN;
    } else if (hypothesis_cause(c->cause)) {
        c->cause = WS_CAUSE_NONE; /* the cameras as listed agree across the splits */
    }
}

/* Whether views of another split agree with the reference hull: as the
 * reference's own views do (a mean WS_CHECK_MEAN_OK, no view below
 * WS_CHECK_VIEW_OK), and on average no less than the reference's own
 * views agree with it (`self`) by more than WS_CHECK_CROSS_GAP: a near-
 * symmetric solid on turned cameras still covers most of a view. */
static int agrees_across(double mean, double worst, double self) {
    return mean >= WS_CHECK_MEAN_OK && worst >= WS_CHECK_VIEW_OK && mean >= self - WS_CHECK_CROSS_GAP;
}

/* The other splits against the reference hull `hull` (carved under
 * a->h[R], whose own views agree with it a->self): each split's found fix
 * first, then where that disagrees the other hypotheses of its file (none
 * in a nerfstudio file: R's hypothesis is every split's there). */
static int weigh(const ws_scene *scene, const ws_silhouette *const sil[WS_NSPLITS], const ws_check_report *r,
                 int R, int one_file, const ws_hull *hull, assignment *a, ws_status *st) {
    int rc = WS_OK, views = 0;
    a->pooled = 0;
    for (int t = 0; t < WS_NSPLITS && !rc; t++) {
        const ws_check_split *c = &r->split[t];
        if (t == R || c->n == 0) continue;
        const hypothesis found = one_file && a->changed[R] ? a->h[R] : fix_of(c);
        double mean, worst;
        rc = held_out(scene, t, sil[t], &found, c->cause == WS_CAUSE_BAD_FRAMES ? c : NULL, hull, &mean, &worst, st);
        a->h[t] = found;
        a->changed[t] = 0;
        a->before[t] = a->after[t] = mean;
        a->worst[t] = worst;
        double best = mean + WS_CHECK_GAIN;
        const int agrees = agrees_across(mean, worst, a->self);
        hypothesis h;
        for (int i = 0; !rc && !agrees && !one_file && nth_hypothesis(&found, i, &h); i++) {
            rc = held_out(scene, t, sil[t], &h, NULL, hull, &mean, &worst, st);
            if (!rc && agrees_across(mean, worst, a->self) && mean > best)
                best = a->after[t] = mean, a->h[t] = h, a->changed[t] = 1;
        }
        a->disagrees[t] = !agrees && !a->changed[t] && c->cause != WS_CAUSE_FOCAL; /* its own line explains it */
        a->unexplained += a->disagrees[t];
        a->changes += a->changed[t];
        a->pooled += a->after[t] * c->n;
        views += c->n;
    }
    a->pooled /= views;
    return rc;
}

/* The cross-split test (check.h): every other split's views against the
 * hull of the reference split R, each split with the fix found for it.
 * Where one disagrees, R's hull is carved again under each hypothesis of
 * its file (nth_hypothesis; in a nerfstudio file, whose frame order and
 * convention are every split's, for every split alike) under which R
 * still agrees with itself, and each other split that disagrees with a
 * hull tries the hypotheses of its own file. A hypothesis of R's file
 * counts only where every other split then agrees (a focal that differs
 * between the files, which the test cannot weigh, lifts the agreement a
 * little under some shift, docs/RESULTS.md "Numbers behind the code's
 * constants"); the assignment that leaves the fewest splits disagreeing, then
 * changes the fewest fixes, then agrees best wins, and a split it leaves
 * disagreeing has an unknown cause. */
static int cross_check(const ws_scene *scene, const ws_silhouette *const sil[WS_NSPLITS], int resolution,
                       ws_check_report *r, ws_status *st) {
    const int one_file = scene->layout == WS_LAYOUT_NERFSTUDIO;
    int R = -1, others = 0;
    for (int s = 0; s < WS_NSPLITS; s++) {
        r->split[s].cross = r->split[s].cross_worst = NAN;
        if (r->split[s].n > 0 && (R < 0 || r->split[s].n > r->split[R].n)) R = s;
    }
    for (int s = 0; s < WS_NSPLITS; s++) others += s != R && r->split[s].n > 0;
    r->reference = others ? R : -1;
    if (!others) return WS_OK;
    ws_check_split *ref = &r->split[R];
    const hypothesis found = fix_of(ref);
    assignment best = {0}, trial;
    best.h[R] = found;
    /* how the reference's own views agree under that fix */
    best.self = ref->cause == WS_CAUSE_SHIFT || ref->cause == WS_CAUSE_OPENCV || ref->cause == WS_CAUSE_BAD_FRAMES
                    ? ref->fixed_mean
                    : ref->mean;
    view_set v;
    ws_hull hull = {0};
    int rc = view_set_make(scene, R, sil[R], &found, ref->cause == WS_CAUSE_BAD_FRAMES ? ref : NULL, &v, st);
    if (!rc) {
        if (v.m > 0)
            rc = ws_hull_carve(v.hv, v.m, scene->center, resolution, ws_hull_default_tolerance(v.m), 0, &hull, st);
        view_set_free(&v);
    }
    if (!rc) rc = weigh(scene, sil, r, R, one_file, &hull, &best, st);
    ws_hull_free(&hull);
    for (int t = 0; t < WS_NSPLITS && !rc; t++)
        if (t != R && r->split[t].n > 0) r->split[t].cross = best.before[t], r->split[t].cross_worst = best.worst[t];
    const int settled = !rc && !best.unexplained && !best.changes;
    hypothesis h;
    for (int i = 0; !rc && !settled && nth_hypothesis(&found, i, &h); i++) {
        trial = (assignment){.changes = 1};
        trial.h[R] = h;
        trial.changed[R] = 1;
        rc = view_set_make(scene, R, sil[R], &h, NULL, &v, st);
        if (rc) break;
        rc = carve_measure(scene, &v, resolution, 0, &hull, st);
        trial.self = rc ? 0 : view_set_mean(&v);
        view_set_free(&v);
        if (!rc && trial.self >= WS_CHECK_MEAN_OK && hull.outside) rc = weigh(scene, sil, r, R, one_file, &hull, &trial, st);
        if (!rc && trial.self >= WS_CHECK_MEAN_OK && hull.outside && !trial.unexplained && better(&trial, &best))
            best = trial;
        ws_hull_free(&hull);
    }
    if (rc) return rc;
    double pooled_before = 0;
    int views = 0;
    for (int t = 0; t < WS_NSPLITS; t++)
        if (t != R && r->split[t].n > 0) pooled_before += r->split[t].cross * r->split[t].n, views += r->split[t].n;
    if (best.changed[R]) {
        apply_cross(ref, &best.h[R], pooled_before / views, best.pooled);
        ref->fixed_mean = best.self;
    }
    for (int t = 0; t < WS_NSPLITS; t++) {
        ws_check_split *c = &r->split[t];
        if (t == R || c->n == 0) continue;
        if (best.changed[t] || (one_file && best.changed[R]))
            apply_cross(c, &best.h[t], c->cross, best.after[t]);
        else if (best.disagrees[t] && c->cause == WS_CAUSE_NONE) {
            c->cause = WS_CAUSE_UNKNOWN;
            c->by_cross = 1;
            c->cross_before = c->cross_after = c->cross;
        }
    }
    return WS_OK;
}

/* The share of a silhouette's pixels on the frame's edge that it holds. */
static double edge_share(const ws_silhouette *s) {
    const int W = s->width, H = s->height;
    long in = 0, all = 0;
    for (int j = 0; j < W; j++) in += s->in[j] + s->in[(size_t)(H - 1) * W + j], all += 2;
    for (int i = 1; i + 1 < H; i++) in += s->in[(size_t)i * W] + s->in[(size_t)i * W + W - 1], all += 2;
    return all ? (double)in / all : 0;
}

int ws_check_silhouettes_usable(const ws_silhouette *sil, int n, int *empty, int *edge) {
    *empty = *edge = 0;
    for (int k = 0; k < n; k++) {
        *empty += sil[k].area == 0;
        *edge += sil[k].area > 0 && edge_share(&sil[k]) >= WS_CHECK_SILHOUETTE_EDGE;
    }
    return n == 0 || 2 * (*empty + *edge) <= n;
}

/* The first split more than half of whose views have an empty silhouette
 * or one holding WS_CHECK_SILHOUETTE_EDGE of the frame's edge or more
 * (check.h): says so in r->line and returns 1; 0 when every split has
 * silhouettes. */
static int no_silhouette(const ws_scene *scene, const ws_silhouette *const sil[WS_NSPLITS], ws_check_report *r) {
    for (int s = 0; s < WS_NSPLITS; s++) {
        const int n = scene->split[s].n;
        int empty, edge;
        if (ws_check_silhouettes_usable(sil[s], n, &empty, &edge)) continue;
        double share = 0;
        for (int k = 0; k < n; k++) share += (double)sil[s][k].area / ((double)sil[s][k].width * sil[s][k].height) / n;
        r->no_silhouette = 1;
        r->explained = s;
        snprintf(r->line, sizeof r->line,
                 "%.300s/%s: no usable silhouette: %d of the %d %s views find no object (%d hold %.0f%% or more "
                 "of the frame's edge, where the background colour is read, as over a busy background; %d "
                 "none; %.1f%% of the frame on average); give a mask per frame (mask_path, white = object) "
                 "to check the cameras",
                 scene->dir, ws_scene_file(scene, s), empty + edge, n, ws_split_names[s], edge,
                 100 * WS_CHECK_SILHOUETTE_EDGE, empty, 100 * share);
        return 1;
    }
    return 0;
}

int ws_check_scene(const ws_scene *scene, const ws_silhouette *const sil[WS_NSPLITS], int resolution,
                   ws_check_report *r, ws_status *st) {
    memset(r, 0, sizeof *r);
    r->reference = -1;
    if (no_silhouette(scene, sil, r)) return WS_OK;
    for (int s = 0; s < WS_NSPLITS; s++) {
        if (check_split(scene, s, sil[s], resolution, &r->split[s], st)) {
            ws_check_report_free(r);
            return st->code;
        }
        if (r->split[s].cause == WS_CAUSE_SHIFT) r->split[s].repair_shift = r->split[s].shift;
    }
    int from;
    if (cause_elsewhere(scene, sil, resolution, r, &from, st) || cross_check(scene, sil, resolution, r, st)) {
        ws_check_report_free(r);
        return st->code;
    }
    /* The line explains the first inconsistent split; in one file, the
     * split whose cause the others were measured under; the reference
     * split where the cross-split test found its cause. */
    r->explained = -1;
    for (int s = WS_NSPLITS - 1; s >= 0; s--)
        if (r->split[s].cause != WS_CAUSE_NONE) r->explained = s;
    if (scene->layout == WS_LAYOUT_NERFSTUDIO && from >= 0) r->explained = from;
    if (r->reference >= 0 && r->split[r->reference].by_cross) r->explained = r->reference;
    r->consistent = r->explained < 0;
    if (!r->consistent) explain(scene, r, r->explained, r->line, sizeof r->line);
    return WS_OK;
}

int ws_check_warning_only(const ws_check_report *r) {
    if (r->consistent) return 0;
    if (r->no_silhouette) return 1;
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
