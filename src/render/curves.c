/* curves.c: cubic Bezier curves, their Gaussians and curve files (see curves.h). */
#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "nn/base/bytes.h"
#include "render/curves.h"
#include "base/limits.h"
#include "base/outfile.h"

int ws_curves_alloc(ws_curves *c, int n, ws_status *st) {
    c->n = 0;
    c->P = NULL;
    c->thickness = 0.02;
    c->overlap = 0.6;
    if (n < 0) return ws_fail(st, WS_EINTERNAL, "curves: negative curve count %d", n);
    c->P = ws_calloc((size_t)n * WS_CURVE_FLOATS, sizeof(double), "control points", st);
    if (!c->P) return st->code;
    c->n = n;
    return WS_OK;
}

void ws_curves_free(ws_curves *c) {
    free(c->P);
    c->P = NULL;
    c->n = 0;
}

void ws_bernstein(double t, double B[4]) {
    double s = 1.0 - t;
    B[0] = s * s * s;
    B[1] = 3.0 * t * s * s;
    B[2] = 3.0 * t * t * s;
    B[3] = t * t * t;
}

void ws_curve_point(const ws_curves *c, int ci, double t, double p[3]) {
    double B[4];
    ws_bernstein(t, B);
    const double *P = c->P + (size_t)ci * WS_CURVE_FLOATS;
    for (int x = 0; x < 3; x++)
        p[x] = B[0] * P[x] + B[1] * P[3 + x] + B[2] * P[6 + x] + B[3] * P[9 + x];
}

static int valid_shape(double thickness, double overlap, ws_status *st) {
    if (!(isfinite(thickness) && thickness > 0))
        return ws_fail(st, WS_EINPUT, "curves: thickness %g is not a positive number", thickness);
    if (!(overlap >= 0 && overlap < 1))
        return ws_fail(st, WS_EINPUT, "curves: overlap %g is not in [0, 1)", overlap);
    return WS_OK;
}

/* An isotropic normal draw projected onto the plane is isotropic in the
 * plane, so normalising it gives a uniform direction. */
void ws_random_direction(ws_rng *rng, const double normal[3], double out[3]) {
    for (;;) {
        double g[3] = {ws_rng_normal(rng), ws_rng_normal(rng), ws_rng_normal(rng)};
        double along = g[0] * normal[0] + g[1] * normal[1] + g[2] * normal[2];
        for (int x = 0; x < 3; x++) g[x] -= along * normal[x];
        double len = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
        if (len > 1e-12) {
            for (int x = 0; x < 3; x++) out[x] = g[x] / len;
            return;
        }
    }
}

int ws_curves_init_random(ws_curves *c, int n, const double center[3], double radius,
                          double length, double thickness, double overlap, ws_rng *rng,
                          ws_status *st) {
    c->n = 0;
    c->P = NULL;
    if (valid_shape(thickness, overlap, st)) return st->code;
    if (!(isfinite(radius) && radius >= 0 && isfinite(length) && length >= 0))
        return ws_fail(st, WS_EINPUT, "curves: radius %g and length %g must be finite and >= 0",
                       radius, length);
    if (ws_curves_alloc(c, n, st)) return st->code;
    c->thickness = thickness;
    c->overlap = overlap;
    const double any[3] = {0, 0, 0};
    for (int ci = 0; ci < n; ci++) {
        double dir[3], tangent[3];
        ws_random_direction(rng, any, dir);
        ws_random_direction(rng, dir, tangent);
        double mid[3] = {center[0] + radius * dir[0], center[1] + radius * dir[1],
                         center[2] + radius * dir[2]};
        ws_curve_set_segment(c, ci, mid, tangent, length);
    }
    return WS_OK;
}

void ws_curve_set_segment(ws_curves *c, int ci, const double mid[3], const double dir[3],
                          double length) {
    static const double offsets[4] = {-0.5, -1.0 / 6.0, 1.0 / 6.0, 0.5};
    double *P = c->P + (size_t)ci * WS_CURVE_FLOATS;
    for (int j = 0; j < 4; j++)
        for (int x = 0; x < 3; x++) P[j * 3 + x] = mid[x] + offsets[j] * length * dir[x];
}

/* ---- sampling ---------------------------------------------------------- */

void ws_gaussians_free(ws_gaussians *g) {
    free(g->mu);
    free(g->t);
    free(g->curve);
    memset(g, 0, sizeof *g);
}

static int gaussians_reserve(ws_gaussians *g, int need, ws_status *st) {
    if (need <= g->cap) return WS_OK;
    int cap = g->cap * 2 > need ? g->cap * 2 : need;
    if (cap < 1024) cap = 1024;
    double *mu = realloc(g->mu, (size_t)cap * 3 * sizeof *mu);
    if (mu) g->mu = mu;
    double *t = realloc(g->t, (size_t)cap * sizeof *t);
    if (t) g->t = t;
    int *curve = realloc(g->curve, (size_t)cap * sizeof *curve);
    if (curve) g->curve = curve;
    if (!mu || !t || !curve)
        return ws_fail(st, WS_ENOMEM, "out of memory for %d Gaussians", cap);
    g->cap = cap;
    return WS_OK;
}

/* Cumulative arc length at t = i / (WS_ARC_SAMPLES - 1). A curve whose
 * control points are all equal has length exactly 0 (the rounding of the
 * Bernstein sums would otherwise give it a length of about 1e-16). */
static void arc_length_table(const ws_curves *c, int ci, double cum[WS_ARC_SAMPLES]) {
    const double *P = c->P + (size_t)ci * WS_CURVE_FLOATS;
    if (!memcmp(P, P + 3, 3 * sizeof *P) && !memcmp(P, P + 6, 3 * sizeof *P) &&
        !memcmp(P, P + 9, 3 * sizeof *P)) {
        memset(cum, 0, WS_ARC_SAMPLES * sizeof *cum);
        return;
    }
    double prev[3], p[3];
    ws_curve_point(c, ci, 0.0, prev);
    cum[0] = 0;
    for (int i = 1; i < WS_ARC_SAMPLES; i++) {
        ws_curve_point(c, ci, (double)i / (WS_ARC_SAMPLES - 1), p);
        double dx = p[0] - prev[0], dy = p[1] - prev[1], dz = p[2] - prev[2];
        cum[i] = cum[i - 1] + sqrt(dx * dx + dy * dy + dz * dz);
        memcpy(prev, p, sizeof p);
    }
}

double ws_curve_length(const ws_curves *c, int ci) {
    double cum[WS_ARC_SAMPLES];
    arc_length_table(c, ci, cum);
    return cum[WS_ARC_SAMPLES - 1];
}

/* The parameter at arc length `a` (0 <= a <= L), by linear interpolation in
 * the table. *seg is the search start (targets come in increasing order);
 * it stops at the first sample at or beyond `a`, whose segment has positive
 * length unless a = 0, so the division is guarded for that case only. */
static double arc_to_t(const double cum[WS_ARC_SAMPLES], double a, int *seg) {
    int i = *seg;
    while (i < WS_ARC_SAMPLES - 2 && cum[i + 1] < a) i++;
    *seg = i;
    double len = cum[i + 1] - cum[i];
    double frac = len > 0 ? (a - cum[i]) / len : 0.0;
    if (frac > 1) frac = 1;
    return (i + frac) / (WS_ARC_SAMPLES - 1);
}

int ws_curves_sample(const ws_curves *c, ws_gaussians *g, ws_status *st) {
    if (valid_shape(c->thickness, c->overlap, st)) return st->code;
    double spacing = 2.0 * c->thickness * (1.0 - c->overlap);
    int capped = 0;
    g->n = 0;
    for (int ci = 0; ci < c->n; ci++) {
        for (int k = 0; k < WS_CURVE_FLOATS; k++)
            if (!isfinite(c->P[(size_t)ci * WS_CURVE_FLOATS + k]))
                return ws_fail(st, WS_ENUMERIC, "curves: curve %d has a non-finite control point",
                               ci);
        double cum[WS_ARC_SAMPLES];
        arc_length_table(c, ci, cum);
        double L = cum[WS_ARC_SAMPLES - 1];
        if (!isfinite(L))
            return ws_fail(st, WS_ENUMERIC, "curves: curve %d is too long to measure", ci);
        double m = ceil(L / spacing);
        if (m < 1) m = 1;
        if (m > WS_MAX_GAUSSIANS_PER_CURVE) {
            m = WS_MAX_GAUSSIANS_PER_CURVE;
            capped++;
        }
        int M = (int)m;
        /* checked before the memory is taken: the sum stays far below INT_MAX */
        if (g->n + M > WS_MAX_GAUSSIANS)
            return ws_fail(st, WS_ENUMERIC,
                           "curves: more than %d Gaussians, the most one view takes (%d curves of thickness "
                           "%g); use fewer, shorter or thicker curves",
                           WS_MAX_GAUSSIANS, c->n, c->thickness);
        if (gaussians_reserve(g, g->n + M, st)) return st->code;
        int seg = 0;
        for (int k = 0; k < M; k++) {
            double t;
            if (M == 1)
                t = L > 0 ? arc_to_t(cum, 0.5 * L, &seg) : 0.5;
            else if (k == 0)
                t = 0.0;
            else if (k == M - 1)
                t = 1.0;
            else
                t = arc_to_t(cum, L * k / (M - 1), &seg);
            int gi = g->n++;
            g->t[gi] = t;
            g->curve[gi] = ci;
            ws_curve_point(c, ci, t, g->mu + (size_t)gi * 3);
        }
    }
    if (capped && capped != g->capped)
        fprintf(stderr,
                "wiresketch: warning: %d curve%s too long for %d Gaussians: capped, spaced wider\n",
                capped, capped == 1 ? " is" : "s are", WS_MAX_GAUSSIANS_PER_CURVE);
    g->capped = capped;
    return WS_OK;
}

void ws_curves_backward(const ws_curves *c, const ws_gaussians *g, const double *dmu, double *dP) {
    memset(dP, 0, (size_t)c->n * WS_CURVE_FLOATS * sizeof *dP);
    for (int k = 0; k < g->n; k++) {
        double B[4];
        ws_bernstein(g->t[k], B);
        double *d = dP + (size_t)g->curve[k] * WS_CURVE_FLOATS;
        for (int j = 0; j < 4; j++)
            for (int x = 0; x < 3; x++) d[j * 3 + x] += B[j] * dmu[(size_t)k * 3 + x];
    }
}

/* ---- curve files --------------------------------------------------------- */

/* A curve file's bytes at the most: WS_MAX_CURVES curves of 12 numbers of
 * up to 25 characters (%.17g), with room for indentation. */
#define MAX_FILE_BYTES ((size_t)WS_MAX_CURVES * WS_CURVE_FLOATS * 48)

/* 1-based line of byte `offset` in text. */
static int line_of(const char *text, size_t offset) {
    int line = 1;
    for (size_t i = 0; i < offset && text[i]; i++) line += text[i] == '\n';
    return line;
}

/* A finite number field of obj, or a failure naming it. */
static int number_field(const cJSON *obj, const char *name, const char *path, double *out,
                        ws_status *st) {
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, name);
    if (!item) return ws_fail(st, WS_EINPUT, "%s: missing \"%s\"", path, name);
    if (!cJSON_IsNumber(item) || !isfinite(item->valuedouble))
        return ws_fail(st, WS_EINPUT, "%s: \"%s\" is not a finite number", path, name);
    *out = item->valuedouble;
    return WS_OK;
}

static int parse_curves(const cJSON *root, const char *path, ws_curves *c, ws_status *st) {
    if (!cJSON_IsObject(root)) return ws_fail(st, WS_EINPUT, "%s: not a JSON object", path);
    double thickness, overlap;
    if (number_field(root, "thickness", path, &thickness, st)) return st->code;
    if (number_field(root, "overlap", path, &overlap, st)) return st->code;
    if (!(thickness > 0))
        return ws_fail(st, WS_EINPUT, "%s: thickness %g is not positive", path, thickness);
    if (!(overlap >= 0 && overlap < 1))
        return ws_fail(st, WS_EINPUT, "%s: overlap %g is not in [0, 1)", path, overlap);
    const cJSON *curves = cJSON_GetObjectItemCaseSensitive(root, "curves");
    if (!curves) return ws_fail(st, WS_EINPUT, "%s: missing \"curves\"", path);
    if (!cJSON_IsArray(curves))
        return ws_fail(st, WS_EINPUT, "%s: \"curves\" is not an array", path);
    int count = cJSON_GetArraySize(curves);
    if (count > WS_MAX_CURVES)
        return ws_fail(st, WS_EINPUT, "%s: %d curves, more than the %d a curve file may hold", path, count,
                       WS_MAX_CURVES);
    if (ws_curves_alloc(c, count, st)) return st->code;
    c->thickness = thickness;
    c->overlap = overlap;
    int ci = 0;
    const cJSON *curve;
    cJSON_ArrayForEach(curve, curves) {
        if (!cJSON_IsArray(curve) || cJSON_GetArraySize(curve) != 4)
            return ws_fail(st, WS_EINPUT, "%s: curve %d is not 4 points", path, ci);
        int j = 0;
        const cJSON *point;
        cJSON_ArrayForEach(point, curve) {
            if (!cJSON_IsArray(point) || cJSON_GetArraySize(point) != 3)
                return ws_fail(st, WS_EINPUT, "%s: curve %d: point %d is not 3 numbers", path, ci, j);
            int x = 0;
            const cJSON *num;
            cJSON_ArrayForEach(num, point) {
                if (!cJSON_IsNumber(num))
                    return ws_fail(st, WS_EINPUT, "%s: curve %d: point %d is not 3 numbers", path,
                                   ci, j);
                if (!isfinite(num->valuedouble))
                    return ws_fail(st, WS_EINPUT, "%s: curve %d: point %d is not finite", path, ci,
                                   j);
                c->P[(size_t)ci * WS_CURVE_FLOATS + j * 3 + x++] = num->valuedouble;
            }
            j++;
        }
        /* Every reader samples the curves next: one it could not measure
         * is refused here, where the file can be named. */
        if (!isfinite(ws_curve_length(c, ci)))
            return ws_fail(st, WS_EINPUT, "%s: curve %d is too long to measure", path, ci);
        ci++;
    }
    return WS_OK;
}

int ws_curves_load(const char *path, ws_curves *c, ws_status *st) {
    c->n = 0;
    c->P = NULL;
    unsigned char *text;
    size_t len;
    if (ws_read_file(path, MAX_FILE_BYTES, &text, &len, st)) return st->code;
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts((const char *)text, len, &end, 0);
    /* Text after the JSON value is an error too (cJSON stops silently). */
    size_t at = end ? (size_t)(end - (const char *)text) : 0;
    while (root && at < len && strchr(" \t\r\n", text[at]) && text[at]) at++;
    int rc;
    if (!root || at < len) {
        rc = ws_fail(st, WS_EINPUT, "%s: JSON syntax error near line %d", path,
                     line_of((const char *)text, at < len ? at : len));
    } else {
        rc = parse_curves(root, path, c, st);
        if (rc) ws_curves_free(c);
    }
    cJSON_Delete(root);
    free(text);
    return rc;
}

int ws_curves_check_finite(const char *path, const ws_curves *c, ws_status *st) {
    for (size_t k = 0; k < (size_t)c->n * WS_CURVE_FLOATS; k++)
        if (!isfinite(c->P[k]))
            return ws_fail(st, WS_ENUMERIC, "%s: curve %zu has a non-finite control point", path,
                           k / WS_CURVE_FLOATS);
    return WS_OK;
}

int ws_curves_save(const char *path, const ws_curves *c, ws_status *st) {
    ws_outfile f;
    if (ws_curves_check_finite(path, c, st) || ws_outfile_open(&f, path, st)) return st->code;
    fprintf(f.fp, "{\n  \"thickness\": %.17g,\n  \"overlap\": %.17g,\n  \"curves\": [", c->thickness,
            c->overlap);
    for (int ci = 0; ci < c->n; ci++) {
        const double *P = c->P + (size_t)ci * WS_CURVE_FLOATS;
        fprintf(f.fp, "%s\n    [", ci ? "," : "");
        for (int j = 0; j < 4; j++)
            fprintf(f.fp, "%s[%.17g, %.17g, %.17g]", j ? ", " : "", P[j * 3], P[j * 3 + 1],
                    P[j * 3 + 2]);
        fputc(']', f.fp);
    }
    fprintf(f.fp, "%s]\n}\n", c->n ? "\n  " : "");
    return ws_outfile_commit(&f, st);
}
