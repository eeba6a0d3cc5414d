/* report.c: report.html (see report.h). */
#include <math.h>
#include <stdlib.h>
#include "base/outfile.h"
#include "io/html.h"
#include "io/report.h"

/* Two columns, or four (with the unit and scale and the verdict) when
 * any item has a scale. */
static void put_table(FILE *f, const ws_report_item *items, int n) {
    int scaled = 0;
    for (int k = 0; k < n; k++) scaled |= items[k].scale != NULL;
    fputs("<table>\n", f);
    if (scaled) fputs("<tr><th>metric</th><th>value</th><th>unit and scale</th><th>verdict</th></tr>\n", f);
    for (int k = 0; k < n; k++) {
        fputs("<tr><th>", f);
        ws_html_text(f, items[k].key);
        fputs("</th><td>", f);
        ws_html_text(f, items[k].value);
        if (scaled) {
            fputs("</td><td class=\"scale\">", f);
            ws_html_text(f, items[k].scale ? items[k].scale : "");
            fputs("</td><td class=\"verdict\">", f);
            if (items[k].verdict) {
                fputs("<span class=\"", f);
                ws_html_text(f, items[k].verdict);
                fputs("\">", f);
                ws_html_text(f, items[k].verdict);
                fputs("</span>", f);
            }
        }
        fputs("</td></tr>\n", f);
    }
    fputs("</table>\n", f);
}

/* "12.3 s", "2 min 3 s (123.4 s)", "1 h 2 min 3 s (3723.0 s)". */
static void put_duration(FILE *f, double seconds) {
    long s = lround(seconds);
    if (s < 60)
        fprintf(f, "%.1f s", seconds);
    else if (s < 3600)
        fprintf(f, "%ld min %ld s (%.1f s)", s / 60, s % 60, seconds);
    else
        fprintf(f, "%ld h %ld min %ld s (%.1f s)", s / 3600, s / 60 % 60, s % 60, seconds);
}

/* ---- the loss plot (inline SVG) ------------------------------------- */

enum { PLOT_W = 760, PLOT_H = 340, PLOT_LEFT = 72, PLOT_RIGHT = 20, PLOT_TOP = 16,
       PLOT_BOTTOM = 46 };

/* One axis: the data range [lo, hi] (log10 of the value on a log axis)
 * maps linearly onto the pixels [px_lo, px_hi]. */
typedef struct {
    double lo, hi, px_lo, px_hi;
    int log;
} plot_axis;

static double axis_px(const plot_axis *a, double u) {
    return a->px_lo + (u - a->lo) / (a->hi - a->lo) * (a->px_hi - a->px_lo);
}

/* A loss in axis units, or NaN where it cannot be drawn (non-finite, or
 * not positive on a log axis). */
static double loss_unit(const plot_axis *a, double v) {
    if (!isfinite(v) || (a->log && !(v > 0))) return NAN;
    return a->log ? log10(v) : v;
}

/* A round step (1, 2 or 5 times a power of 10) that cuts `range` into
 * about `target` intervals. */
static double nice_step(double range, int target) {
    double raw = range / target, mag = pow(10, floor(log10(raw))), m = raw / mag;
    return (m < 1.5 ? 1 : m < 3 ? 2 : m < 7 ? 5 : 10) * mag;
}

/* An SVG path drawn point by point; a gap starts a new subpath. */
typedef struct {
    FILE *f;
    int open;
} plot_pen;

static void pen_to(plot_pen *p, double x, double y) {
    if (isnan(y)) {
        p->open = 0;
        return;
    }
    fprintf(p->f, "%s%.1f %.1f", p->open ? " L" : " M", x, y);
    p->open = 1;
}

static void pen_start(plot_pen *p, FILE *f, const char *attrs) {
    *p = (plot_pen){.f = f};
    fprintf(f, "<path fill=\"none\" %s d=\"", attrs);
}

static void pen_end(plot_pen *p) {
    fputs("\"/>\n", p->f);
}

static void put_y_tick(FILE *f, const plot_axis *y, double u, const char *label) {
    double py = axis_px(y, u);
    fprintf(f, "<line class=\"grid\" x1=\"%d\" x2=\"%d\" y1=\"%.1f\" y2=\"%.1f\"/>"
               "<text class=\"tick\" x=\"%d\" y=\"%.1f\" text-anchor=\"end\">%s</text>\n",
            PLOT_LEFT, PLOT_W - PLOT_RIGHT, py, py, PLOT_LEFT - 6, py + 4, label);
}

static void put_y_ticks(FILE *f, const plot_axis *y) {
    char label[64];
    if (y->log) {
        /* Decades; with 1-2-5 between them when few decades are shown. */
        static const double fine[3] = {1, 2, 5}, coarse[1] = {1};
        double span = y->hi - y->lo;
        const double *mant = span < 3 ? fine : coarse;
        int nmant = span < 3 ? 3 : 1, stride = span > 10 ? (int)ceil(span / 8) : 1;
        for (int e = (int)floor(y->lo); e <= (int)ceil(y->hi); e++) {
            if (e % stride) continue;
            for (int k = 0; k < nmant; k++) {
                double u = e + log10(mant[k]);
                if (u < y->lo || u > y->hi) continue;
                snprintf(label, sizeof label, "%g", mant[k] * pow(10, e));
                put_y_tick(f, y, u, label);
            }
        }
        return;
    }
    double step = nice_step(y->hi - y->lo, 5);
    int decimals = step < 1 ? (int)ceil(-log10(step) - 1e-9) : 0;
    for (double k = ceil(y->lo / step); k * step <= y->hi + 1e-9 * step; k++) {
        double v = fabs(k) < 0.5 ? 0 : k * step; /* no "-0.00" */
        if (fabs(v) >= 1e6 || decimals > 6)
            snprintf(label, sizeof label, "%.3g", v);
        else
            snprintf(label, sizeof label, "%.*f", decimals, v);
        put_y_tick(f, y, v, label);
    }
}

static void put_x_ticks(FILE *f, const plot_axis *x) {
    double step = fmax(1, nice_step(x->hi - x->lo, 8));
    int y0 = PLOT_H - PLOT_BOTTOM;
    for (double k = ceil(x->lo / step); k * step <= x->hi + 1e-9 * step; k++) {
        double px = axis_px(x, k * step);
        fprintf(f, "<line class=\"axis\" x1=\"%.1f\" x2=\"%.1f\" y1=\"%d\" y2=\"%d\"/>"
                   "<text class=\"tick\" x=\"%.1f\" y=\"%d\" text-anchor=\"middle\">%.0f</text>\n",
                px, px, y0, y0 + 5, px, y0 + 18, k * step);
    }
}

/* Steps in the moving mean of the train loss: 1/30 of the run, none when
 * that is under 3 steps. */
static int mean_window(int n) {
    return n / 30 >= 3 ? n / 30 : 0;
}

/* The train loss: every point when there are few, else the minimum and
 * maximum of each pixel column (the envelope of the noise); then its
 * moving mean. */
static int put_train(FILE *f, const ws_report *r, const plot_axis *x, const plot_axis *y,
                     ws_status *st) {
    int n = r->n_train, cols = PLOT_W - PLOT_LEFT - PLOT_RIGHT;
    plot_pen pen;
    pen_start(&pen, f, "class=\"train\"");
    if (n <= 2 * cols) {
        for (int k = 0; k < n; k++)
            pen_to(&pen, axis_px(x, r->train_step[k]), axis_px(y, loss_unit(y, r->train_loss[k])));
    } else {
        for (int c = 0; c < cols; c++) {
            int k0 = (int)((long)c * n / cols), k1 = (int)((long)(c + 1) * n / cols);
            double lo = INFINITY, hi = -INFINITY;
            for (int k = k0; k < k1; k++) {
                double u = loss_unit(y, r->train_loss[k]);
                if (!isnan(u)) lo = fmin(lo, u), hi = fmax(hi, u);
            }
            double px = axis_px(x, r->train_step[k0]);
            pen_to(&pen, px, lo <= hi ? axis_px(y, hi) : NAN);
            pen_to(&pen, px, lo <= hi ? axis_px(y, lo) : NAN);
        }
    }
    pen_end(&pen);
    int window = mean_window(n);
    if (!window) return WS_OK;
    /* Prefix sums of the drawable losses and of their count. */
    double *sum = ws_malloc(2 * (size_t)(n + 1) * sizeof *sum, "loss plot", st);
    if (!sum) return st->code;
    double *cnt = sum + n + 1;
    sum[0] = cnt[0] = 0;
    for (int k = 0; k < n; k++) {
        int ok = !isnan(loss_unit(y, r->train_loss[k]));
        sum[k + 1] = sum[k] + (ok ? r->train_loss[k] : 0);
        cnt[k + 1] = cnt[k] + ok;
    }
    int stride = n / cols > 1 ? n / cols : 1;
    pen_start(&pen, f, "class=\"mean\"");
    for (int k = 0; k < n; k += stride) {
        int a = k - window / 2 > 0 ? k - window / 2 : 0;
        int b = k + window / 2 + 1 < n ? k + window / 2 + 1 : n;
        double c = cnt[b] - cnt[a];
        pen_to(&pen, axis_px(x, r->train_step[k]),
               c > 0 ? axis_px(y, loss_unit(y, (sum[b] - sum[a]) / c)) : NAN);
    }
    pen_end(&pen);
    free(sum);
    return WS_OK;
}

static void put_val(FILE *f, const ws_report *r, const plot_axis *x, const plot_axis *y) {
    plot_pen pen;
    pen_start(&pen, f, "class=\"val\"");
    for (int k = 0; k < r->n_val; k++)
        pen_to(&pen, axis_px(x, r->val_step[k]), axis_px(y, loss_unit(y, r->val_loss[k])));
    pen_end(&pen);
    for (int k = 0; k < r->n_val; k++) {
        double u = loss_unit(y, r->val_loss[k]);
        if (isnan(u)) continue;
        fprintf(f, "<circle class=\"val\" cx=\"%.1f\" cy=\"%.1f\" r=\"3\"><title>step %ld: %.6g</title></circle>\n",
                axis_px(x, r->val_step[k]), axis_px(y, u), r->val_step[k], r->val_loss[k]);
    }
}

/* The schedule's phases: a dashed line where each begins, its label above. */
static void put_phases(FILE *f, const ws_report *r, const plot_axis *x) {
    for (int k = 0; k < r->n_phases; k++) {
        if (r->phase_step[k] < x->lo || r->phase_step[k] > x->hi) continue;
        double px = axis_px(x, r->phase_step[k]);
        fprintf(f, "<line class=\"phase\" x1=\"%.1f\" x2=\"%.1f\" y1=\"%d\" y2=\"%d\"/>"
                   "<text class=\"tick\" x=\"%.1f\" y=\"%d\">", px, px, PLOT_TOP, PLOT_H - PLOT_BOTTOM, px + 3,
                PLOT_TOP + 12 + 12 * (k % 2));
        ws_html_text(f, r->phase_label[k]);
        fputs("</text>\n", f);
    }
}

static void put_legend(FILE *f, const ws_report *r, int mean_drawn) {
    const char *names[3] = {"train", "train, moving mean", "validation"};
    const char *classes[3] = {"train", "mean", "val"};
    int shown[3] = {r->n_train > 0, mean_drawn, r->n_val > 0};
    int row = 0;
    for (int k = 0; k < 3; k++) {
        if (!shown[k]) continue;
        int x0 = PLOT_W - PLOT_RIGHT - 170, y0 = PLOT_TOP + 14 + 16 * row++;
        fprintf(f, "<line class=\"%s\" x1=\"%d\" x2=\"%d\" y1=\"%d\" y2=\"%d\"/>"
                   "<text class=\"tick\" x=\"%d\" y=\"%d\">%s</text>\n",
                classes[k], x0, x0 + 22, y0, y0, x0 + 28, y0 + 4, names[k]);
    }
}

static int put_loss_plot(FILE *f, const ws_report *r, ws_status *st) {
    /* The ranges of the drawable points decide the axes. */
    double xlo = INFINITY, xhi = -INFINITY, vlo = INFINITY, vhi = -INFINITY, pos_lo = INFINITY;
    int nonpositive = 0;
    for (int s = 0; s < 2; s++) {
        int n = s ? r->n_val : r->n_train;
        const long *step = s ? r->val_step : r->train_step;
        const double *loss = s ? r->val_loss : r->train_loss;
        for (int k = 0; k < n; k++) {
            if (!isfinite(loss[k])) continue;
            xlo = fmin(xlo, step[k]), xhi = fmax(xhi, step[k]);
            vlo = fmin(vlo, loss[k]), vhi = fmax(vhi, loss[k]);
            if (loss[k] > 0) pos_lo = fmin(pos_lo, loss[k]);
            else nonpositive = 1;
        }
    }
    if (!(xlo <= xhi)) {
        fputs("<p>No finite loss values were recorded.</p>\n", f);
        return WS_OK;
    }
    plot_axis x = {.lo = xlo, .hi = xhi, .px_lo = PLOT_LEFT, .px_hi = PLOT_W - PLOT_RIGHT};
    if (x.hi == x.lo) x.lo -= 1, x.hi += 1;
    plot_axis y = {.log = !nonpositive && vhi > 10 * pos_lo, .px_lo = PLOT_H - PLOT_BOTTOM,
                   .px_hi = PLOT_TOP};
    y.lo = y.log ? log10(vlo) : vlo;
    y.hi = y.log ? log10(vhi) : vhi;
    double pad = y.hi > y.lo ? 0.05 * (y.hi - y.lo) : y.log ? 0.5 : fabs(y.lo) > 0 ? 0.1 * fabs(y.lo) : 1;
    y.lo -= pad, y.hi += pad;

    fprintf(f, "<svg class=\"plot\" viewBox=\"0 0 %d %d\" role=\"img\" aria-label=\"loss per step\">\n",
            PLOT_W, PLOT_H);
    put_y_ticks(f, &y);
    put_x_ticks(f, &x);
    fprintf(f, "<rect class=\"frame\" x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\"/>\n", PLOT_LEFT,
            PLOT_TOP, PLOT_W - PLOT_LEFT - PLOT_RIGHT, PLOT_H - PLOT_TOP - PLOT_BOTTOM);
    fprintf(f, "<text class=\"label\" x=\"%d\" y=\"%d\" text-anchor=\"middle\">step</text>\n",
            (PLOT_LEFT + PLOT_W - PLOT_RIGHT) / 2, PLOT_H - 8);
    fprintf(f, "<text class=\"label\" transform=\"translate(16 %d) rotate(-90)\" text-anchor=\"middle\">"
               "loss%s</text>\n", (PLOT_TOP + PLOT_H - PLOT_BOTTOM) / 2, y.log ? " (log scale)" : "");
    put_phases(f, r, &x);
    if (r->n_train > 0 && put_train(f, r, &x, &y, st)) return st->code;
    if (r->n_val > 0) put_val(f, r, &x, &y);
    put_legend(f, r, mean_window(r->n_train) > 0);
    fputs("</svg>\n", f);
    if (r->n_phases && r->phase_note) {
        fputs("<p class=\"hint\">", f);
        ws_html_text(f, r->phase_note);
        fputs("</p>\n", f);
    }
    return WS_OK;
}

/* ---- images and curves ---------------------------------------------- */

static void put_img(FILE *f, const char *path, const char *alt) {
    fputs("<img src=\"", f);
    ws_html_url(f, path);
    fputs("\" alt=\"", f);
    ws_html_text(f, alt);
    fputs("\">", f);
}

/* A test view's image shown cropped to v->crop in a CROP_PX square: the
 * image scaled so that the crop fills the box, the rest clipped. */
#define CROP_PX 224
static void put_cropped(FILE *f, const ws_report_view *v, const char *path, const char *alt) {
    if (v->crop[2] <= 0 || v->width <= 0) {
        put_img(f, path, alt);
        return;
    }
    double scale = (double)CROP_PX / v->crop[2];
    fprintf(f, "<div class=\"crop\"><img style=\"width:%.1fpx;margin:%.1fpx 0 0 %.1fpx\" src=\"",
            v->width * scale, -v->crop[1] * scale, -v->crop[0] * scale);
    ws_html_url(f, path);
    fputs("\" alt=\"", f);
    ws_html_text(f, alt);
    fputs("\"></div>", f);
}

static void put_tests(FILE *f, const ws_report *r) {
    if (r->n_tests == 0) {
        fputs("<p>The scene has no test views.</p>\n", f);
        return;
    }
    fputs("<p>Each view: the sketch render (left) and the photo (right), both cropped to the object.</p>\n"
          "<div class=\"views\">\n", f);
    for (int k = 0; k < r->n_tests; k++) {
        const ws_report_view *v = &r->tests[k];
        fputs("<figure><div class=\"pair\">", f);
        put_cropped(f, v, v->render_path, "sketch render");
        if (v->photo_path) put_cropped(f, v, v->photo_path, "photo");
        fputs("</div><figcaption>", f);
        ws_html_text(f, v->name);
        if (isfinite(v->loss)) fprintf(f, " &middot; loss %.4g", v->loss);
        fputs("</figcaption></figure>\n", f);
    }
    fputs("</div>\n", f);
}

static void put_images(FILE *f, const ws_report *r) {
    fputs("<div class=\"views\">\n", f);
    for (int k = 0; k < r->n_images; k++) {
        fputs("<figure>", f);
        put_img(f, r->images[k].path, r->images[k].caption);
        fputs("<figcaption>", f);
        ws_html_text(f, r->images[k].caption);
        fputs("</figcaption></figure>\n", f);
    }
    fputs("</div>\n", f);
}

/* Points per curve in the 3D view: 64, fewer when there are so many curves
 * that the page would pass about 100000 points. */
static int curve_points(int ncurves) {
    int k = ncurves > 0 ? 100000 / ncurves : 64;
    return k > 64 ? 64 : k < 8 ? 8 : k;
}

/* {"curves": [[[x, y, z], ...], ...]}: numbers only, so the JSON cannot
 * end the <script> element it sits in. */
static void put_curves_json(FILE *f, const ws_curves *c, const double *cameras, int n_cameras) {
    fputs("{\"cameras\": [", f);
    for (int k = 0; k < n_cameras; k++) {
        const double *cam = cameras + 6 * k;
        int finite = 1;
        for (int i = 0; i < 6; i++) finite &= isfinite(cam[i]) != 0;
        if (finite)
            fprintf(f, "%s[%.6g,%.6g,%.6g,%.6g,%.6g,%.6g]", k ? "," : "", cam[0], cam[1], cam[2], cam[3], cam[4],
                    cam[5]);
    }
    fputs("],\n\"curves\": [", f);
    int npts = curve_points(c->n), written = 0;
    for (int ci = 0; ci < c->n; ci++) {
        int finite = 1;
        for (int k = 0; k < WS_CURVE_FLOATS; k++) finite &= isfinite(c->P[ci * WS_CURVE_FLOATS + k]) != 0;
        if (!finite) continue;
        fputs(written++ ? ",\n[" : "\n[", f);
        for (int k = 0; k < npts; k++) {
            double p[3];
            ws_curve_point(c, ci, (double)k / (npts - 1), p);
            fprintf(f, "%s[%.6g,%.6g,%.6g]", k ? "," : "", p[0], p[1], p[2]);
        }
        fputc(']', f);
    }
    fputs("]}", f);
}

/* ---- the page --------------------------------------------------------- */

static const char report_css[] =
    "body{margin:0;background:#f6f6f4;color:#222;"
    "font:15px/1.45 system-ui,-apple-system,'Segoe UI',Roboto,Helvetica,Arial,sans-serif}\n"
    "main{max-width:1100px;margin:0 auto;padding:8px 24px 48px}\n"
    "h1{font-size:1.6em;margin:.7em 0 .2em}\n"
    "h2{font-size:1.2em;margin:1.6em 0 .6em;padding-bottom:.2em;border-bottom:1px solid #ddd}\n"
    ".sub{color:#555;margin:0}\n"
    "code{font:13px ui-monospace,SFMono-Regular,Menlo,Consolas,monospace;background:#e9e9e6;"
    "padding:1px 4px;border-radius:3px;word-break:break-all}\n"
    "nav a{margin-right:1em;color:#2a5db0}\n"
    "table{border-collapse:collapse;font-size:14px;background:#fff}\n"
    "th,td{border:1px solid #ddd;padding:3px 10px;text-align:left;vertical-align:top}\n"
    "th{background:#f0f0ee;font-weight:600}\n"
    "td{font-family:ui-monospace,SFMono-Regular,Menlo,Consolas,monospace;font-size:13px;"
    "white-space:pre-wrap;word-break:break-all}\n"
    ".views{display:flex;flex-wrap:wrap;gap:14px}\n"
    "figure{margin:0;background:#fff;border:1px solid #ddd;padding:6px}\n"
    ".pair{display:flex;gap:4px}\n"
    "figure img{width:224px;height:auto;display:block;outline:1px solid #e2e2e2}\n"
    ".crop{width:224px;height:224px;overflow:hidden;outline:1px solid #e2e2e2}\n"
    ".crop img{max-width:none;outline:none}\n"
    "td.scale{font-family:inherit;color:#555}\n"
    ".verdict .good{color:#1a7f37;font-weight:600}.verdict .fair{color:#9a6700;font-weight:600}"
    ".verdict .poor{color:#cf222e;font-weight:600}\n"
    ".warning{background:#fff4d6;border:1px solid #e0c060;padding:6px 10px}\n"
    "figcaption{font-size:13px;color:#555;margin-top:4px}\n"
    "svg.plot{width:100%;max-width:900px;height:auto;background:#fff;border:1px solid #ddd}\n"
    "svg.plot .grid{stroke:#eee}\n"
    "svg.plot .axis{stroke:#444}\n"
    "svg.plot .frame{fill:none;stroke:#444}\n"
    "svg.plot .tick{font-size:12px;fill:#444}\n"
    "svg.plot .label{font-size:13px;fill:#222}\n"
    "svg.plot .train{stroke:#9ecae1;stroke-width:1}\n"
    "svg.plot .mean{stroke:#2166ac;stroke-width:2}\n"
    "svg.plot .val{stroke:#e6550d;stroke-width:2;fill:#e6550d}\n"
    "svg.plot .phase{stroke:#888;stroke-dasharray:4 3}\n"
    "svg.plot path.val{fill:none}\n"
    "#view3d{display:block;width:100%;height:560px;background:#fff;border:1px solid #ddd;"
    "cursor:grab;touch-action:none}\n"
    ".hint{color:#666;font-size:13px}\n";

/* The 3D viewer: an orbit camera around the centre of the curves' bounding
 * box, perspective projection, segments drawn far to near with darkness
 * falling off with depth. */
static const char report_js[] =
    "(function () {\n"
    "  var canvas = document.getElementById('view3d');\n"
    "  var data = JSON.parse(document.getElementById('curve-data').textContent);\n"
    "  var curves = data.curves, cameras = data.cameras || [];\n"
    "  var ctx = canvas.getContext('2d');\n"
    "  var lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];\n"
    "  curves.forEach(function (c) {\n"
    "    c.forEach(function (p) {\n"
    "      for (var k = 0; k < 3; k++) { lo[k] = Math.min(lo[k], p[k]); hi[k] = Math.max(hi[k], p[k]); }\n"
    "    });\n"
    "  });\n"
    "  var centre = [0, 0, 0], radius = 0;\n"
    "  if (curves.length) centre = [0, 1, 2].map(function (k) { return (lo[k] + hi[k]) / 2; });\n"
    "  curves.forEach(function (c) {\n"
    "    c.forEach(function (p) {\n"
    "      radius = Math.max(radius, Math.hypot(p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]));\n"
    "    });\n"
    "  });\n"
    "  if (!(radius > 0)) radius = 1;\n"
    "  /* the cameras in the frame too; each drawn as a pyramid of the sketch's scale */\n"
    "  var camSize = 0.12 * radius;\n"
    "  cameras.forEach(function (c) {\n"
    "    radius = Math.max(radius, Math.hypot(c[0] - centre[0], c[1] - centre[1], c[2] - centre[2]) + camSize);\n"
    "  });\n"
    "  var fov = 35 * Math.PI / 180;\n"
    "  var home = { yaw: -Math.PI / 2, pitch: 0.35, dist: radius / Math.sin(fov / 2) };\n"
    "  var view = Object.assign({}, home);\n"
    "  var pending = false;\n"
    "  function redraw() {\n"
    "    if (!pending) { pending = true; requestAnimationFrame(draw); }\n"
    "  }\n"
    "  function draw() {\n"
    "    pending = false;\n"
    "    var dpr = window.devicePixelRatio || 1;\n"
    "    var w = Math.round(canvas.clientWidth * dpr), h = Math.round(canvas.clientHeight * dpr);\n"
    "    if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }\n"
    "    ctx.fillStyle = '#fff';\n"
    "    ctx.fillRect(0, 0, w, h);\n"
    "    /* Orbit camera around the centre, world +z up, as in the scene files. */\n"
    "    var cp = Math.cos(view.pitch), sp = Math.sin(view.pitch);\n"
    "    var cy = Math.cos(view.yaw), sy = Math.sin(view.yaw);\n"
    "    var back = [cp * cy, cp * sy, sp], right = [-sy, cy, 0];\n"
    "    var up = [back[1] * right[2] - back[2] * right[1], back[2] * right[0] - back[0] * right[2],\n"
    "              back[0] * right[1] - back[1] * right[0]];\n"
    "    var f = Math.min(w, h) / 2 / Math.tan(fov / 2), near = 0.02 * radius;\n"
    "    function project(p) {\n"
    "      var d = [p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]];\n"
    "      var depth = view.dist - (d[0] * back[0] + d[1] * back[1] + d[2] * back[2]);\n"
    "      return [w / 2 + f * (d[0] * right[0] + d[1] * right[1]) / depth,\n"
    "              h / 2 - f * (d[0] * up[0] + d[1] * up[1] + d[2] * up[2]) / depth, depth];\n"
    "    }\n"
    "    var segs = [];\n"
    "    curves.forEach(function (c) {\n"
    "      var prev = null;\n"
    "      c.forEach(function (p) {\n"
    "        var q = project(p);\n"
    "        if (prev && prev[2] > near && q[2] > near) segs.push([prev, q, (prev[2] + q[2]) / 2]);\n"
    "        prev = q;\n"
    "      });\n"
    "    });\n"
    "    /* Far segments first, so that near strokes are drawn over them; depth\n"
    "     * cue: the nearest point of the sketch is black, the farthest light gray. */\n"
    "    segs.sort(function (a, b) { return b[2] - a[2]; });\n"
    "    ctx.lineCap = 'round';\n"
    "    segs.forEach(function (s) {\n"
    "      var t = Math.min(1, Math.max(0, (s[2] - (view.dist - radius)) / (2 * radius)));\n"
    "      var g = Math.round(190 * t);\n"
    "      ctx.strokeStyle = 'rgb(' + g + ',' + g + ',' + g + ')';\n"
    "      ctx.lineWidth = dpr * Math.max(0.75, Math.min(6, 2.5 * view.dist / s[2]));\n"
    "      ctx.beginPath();\n"
    "      ctx.moveTo(s[0][0], s[0][1]);\n"
    "      ctx.lineTo(s[1][0], s[1][1]);\n"
    "      ctx.stroke();\n"
    "    });\n"
    "    /* Cameras: lines from the centre to the corners of a square that\n"
    "     * faces the viewing direction. */\n"
    "    ctx.strokeStyle = '#3b7dd8';\n"
    "    ctx.lineWidth = dpr;\n"
    "    cameras.forEach(function (c) {\n"
    "      var d = [c[3], c[4], c[5]], n = Math.hypot(d[0], d[1], d[2]) || 1;\n"
    "      d = d.map(function (v) { return v / n; });\n"
    "      var a = Math.abs(d[2]) < 0.9 ? [0, 0, 1] : [1, 0, 0];\n"
    "      var u = [d[1] * a[2] - d[2] * a[1], d[2] * a[0] - d[0] * a[2], d[0] * a[1] - d[1] * a[0]];\n"
    "      var nu = Math.hypot(u[0], u[1], u[2]);\n"
    "      u = u.map(function (v) { return v / nu; });\n"
    "      var v = [d[1] * u[2] - d[2] * u[1], d[2] * u[0] - d[0] * u[2], d[0] * u[1] - d[1] * u[0]];\n"
    "      var apex = project(c), corners = [[1, 1], [-1, 1], [-1, -1], [1, -1]].map(function (s) {\n"
    "        return project([0, 1, 2].map(function (k) {\n"
    "          return c[k] + camSize * (d[k] + 0.5 * (s[0] * u[k] + s[1] * v[k]));\n"
    "        }));\n"
    "      });\n"
    "      if (apex[2] <= near || corners.some(function (q) { return q[2] <= near; })) return;\n"
    "      ctx.beginPath();\n"
    "      corners.forEach(function (q, k) {\n"
    "        ctx.moveTo(apex[0], apex[1]);\n"
    "        ctx.lineTo(q[0], q[1]);\n"
    "        ctx.lineTo(corners[(k + 1) % 4][0], corners[(k + 1) % 4][1]);\n"
    "      });\n"
    "      ctx.stroke();\n"
    "    });\n"
    "    /* Axis gizmo: the world axes as seen from the current direction. */\n"
    "    var gx = 44 * dpr, gy = h - 44 * dpr, gl = 30 * dpr;\n"
    "    ctx.font = (12 * dpr) + 'px sans-serif';\n"
    "    ctx.lineWidth = 2 * dpr;\n"
    "    [['x', '#d62728'], ['y', '#2ca02c'], ['z', '#1f77b4']].forEach(function (a, k) {\n"
    "      var e = [0, 0, 0];\n"
    "      e[k] = 1;\n"
    "      var ex = e[0] * right[0] + e[1] * right[1], ey = e[0] * up[0] + e[1] * up[1] + e[2] * up[2];\n"
    "      ctx.strokeStyle = ctx.fillStyle = a[1];\n"
    "      ctx.beginPath();\n"
    "      ctx.moveTo(gx, gy);\n"
    "      ctx.lineTo(gx + gl * ex, gy - gl * ey);\n"
    "      ctx.stroke();\n"
    "      ctx.fillText(a[0], gx + (gl + 6 * dpr) * ex - 3 * dpr, gy - (gl + 6 * dpr) * ey + 4 * dpr);\n"
    "    });\n"
    "    if (!curves.length) {\n"
    "      ctx.fillStyle = '#888';\n"
    "      ctx.fillText('no curves', w / 2 - 25 * dpr, h / 2);\n"
    "    }\n"
    "  }\n"
    "  var drag = null;\n"
    "  canvas.addEventListener('pointerdown', function (e) {\n"
    "    drag = [e.clientX, e.clientY];\n"
    "    canvas.setPointerCapture(e.pointerId);\n"
    "    canvas.style.cursor = 'grabbing';\n"
    "  });\n"
    "  canvas.addEventListener('pointermove', function (e) {\n"
    "    if (!drag) return;\n"
    "    view.yaw -= 0.01 * (e.clientX - drag[0]);\n"
    "    view.pitch = Math.max(-1.55, Math.min(1.55, view.pitch + 0.01 * (e.clientY - drag[1])));\n"
    "    drag = [e.clientX, e.clientY];\n"
    "    redraw();\n"
    "  });\n"
    "  function release() { drag = null; canvas.style.cursor = ''; }\n"
    "  canvas.addEventListener('pointerup', release);\n"
    "  canvas.addEventListener('pointercancel', release);\n"
    "  canvas.addEventListener('wheel', function (e) {\n"
    "    e.preventDefault();\n"
    "    view.dist = Math.max(0.3 * radius, Math.min(50 * radius, view.dist * Math.exp(0.0015 * e.deltaY)));\n"
    "    redraw();\n"
    "  }, { passive: false });\n"
    "  canvas.addEventListener('dblclick', function () { view = Object.assign({}, home); redraw(); });\n"
    "  window.addEventListener('resize', redraw);\n"
    "  redraw();\n"
    "})();\n"
    ;

int ws_report_write(const char *path, const ws_report *r, ws_status *st) {
    ws_outfile out;
    if (ws_outfile_open(&out, path, st)) return st->code;
    FILE *f = out.fp;
    const char *title = r->title ? r->title : "wiresketch fit";
    fputs("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
          "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>", f);
    ws_html_text(f, title);
    fprintf(f, "</title>\n<style>\n%s</style>\n</head>\n<body>\n<main>\n<h1>", report_css);
    ws_html_text(f, title);
    fputs("</h1>\n", f);
    if (r->scene_path) {
        fputs("<p class=\"sub\">Scene <code>", f);
        ws_html_text(f, r->scene_path);
        fputs("</code></p>\n", f);
    }
    if (isfinite(r->wall_seconds)) {
        fputs("<p class=\"sub\" id=\"wall-time\">Wall time ", f);
        put_duration(f, r->wall_seconds);
        fputs("</p>\n", f);
    }
    fputs("<nav><p><a href=\"#metrics\">Metrics</a><a href=\"#loss\">Loss</a>"
          "<a href=\"#test-views\">Test views</a>", f);
    if (r->curves) fputs("<a href=\"#curves-3d\">3D view</a>", f);
    if (r->n_images) fputs("<a href=\"#images\">Animations</a>", f);
    fputs("<a href=\"#settings\">Settings</a></p></nav>\n", f);

    fputs("<section id=\"metrics\">\n<h2>Metrics</h2>\n", f);
    if (r->warning) {
        fputs("<p class=\"warning\" id=\"gt-warning\">Warning: ", f);
        ws_html_text(f, r->warning);
        fputs("</p>\n", f);
    }
    put_table(f, r->metrics, r->n_metrics);
    fputs("</section>\n<section id=\"loss\">\n<h2>Loss</h2>\n", f);
    if (put_loss_plot(f, r, st)) {
        ws_outfile_abort(&out);
        return st->code;
    }
    fputs("</section>\n<section id=\"test-views\">\n<h2>Test views</h2>\n", f);
    put_tests(f, r);
    fputs("</section>\n", f);
    if (r->curves) {
        fputs("<section id=\"curves-3d\">\n<h2>3D view</h2>\n<canvas id=\"view3d\"></canvas>\n"
              "<p class=\"hint\">The 3D curves alone. Drag to rotate, scroll to zoom, double-click to reset. "
              "Nearer strokes are darker; the training cameras are the blue pyramids, each pointing where "
              "it looks.</p>\n"
              "<script type=\"application/json\" id=\"curve-data\">", f);
        put_curves_json(f, r->curves, r->cameras, r->n_cameras);
        fprintf(f, "</script>\n<script>\n%s</script>\n</section>\n", report_js);
    }
    if (r->n_images) {
        fputs("<section id=\"images\">\n<h2>Animations</h2>\n", f);
        put_images(f, r);
        fputs("</section>\n", f);
    }
    fputs("<section id=\"settings\">\n<h2>Settings</h2>\n", f);
    put_table(f, r->settings, r->n_settings);
    fputs("</section>\n</main>\n</body>\n</html>\n", f);
    return ws_outfile_commit(&out, st);
}
