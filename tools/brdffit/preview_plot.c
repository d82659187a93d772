/* The plots of the preview, drawn with cairo on numbered axes: the cost
 * of the whole fit, stage by stage (brdffit_fit_history_all(): the scan's
 * best-so-far, then each Levenberg-Marquardt run), and measured and model values against
 * the half-angle theta_h (the angle between the surface normal and the
 * half vector of light and view), which also pictures scattered data. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "preview.h"

#define LABEL 18.0
#define MAX_POINTS 20000

static const double orange[3] = {1.0, 0.75, 0.16};

static void range_of(const double *v, size_t n, int positive, double *lo, double *hi)
{
    size_t i;
    int any = 0;
    for (i = 0; i < n; i++) {
        if (positive && !(v[i] > 0.0)) continue;
        if (!any || v[i] < *lo) *lo = v[i];
        if (!any || v[i] > *hi) *hi = v[i];
        any = 1;
    }
    if (!any) *lo = *hi = positive ? 1.0 : 0.0;
}

/* One colour per stage, the stage whose result is returned drawn thicker. */
static const double stage_rgb[4][3] = {
    {1.0, 0.75, 0.16}, {0.45, 0.62, 1.0}, {0.55, 0.85, 0.45}, {0.95, 0.45, 0.75}};

static void stage_label(const brdffit_fit_stage *s, char *text, size_t size)
{
    const char *name = brdffit_fit_stage_name(s->kind);
    if (s->kind == BRDFFIT_STAGE_POLISH || s->kind == BRDFFIT_STAGE_CHANNEL)
        cli_format(text, size, "%s %zu%s", name, s->index, s->kept ? " (kept)" : "");
    else
        cli_format(text, size, "%s%s", name, s->kept ? " (kept)" : "");
}

/* Stage k's entries as a line with dots, and its label in the legend. */
static void cost_stage(cairo_t *cr, const cli_preview_input *in, const draw_frame *f, size_t k,
                       double *legend_x)
{
    const brdffit_fit_stage *s = &in->stages[k];
    const double *rgb = stage_rgb[k % 4];
    size_t i, end = s->first + s->length;
    char text[64];
    if (end > in->n_history) end = in->n_history;
    cairo_set_source_rgb(cr, rgb[0], rgb[1], rgb[2]);
    cairo_set_line_width(cr, s->kept ? 2.5 : 1.2);
    for (i = s->first; i < end; i++) {
        double px = draw_fx(f, (double)i), py = draw_fy(f, in->history[i]);
        if (i == s->first)
            cairo_move_to(cr, px, py);
        else
            cairo_line_to(cr, px, py);
    }
    cairo_stroke(cr);
    if (s->length <= 60)
        for (i = s->first; i < end; i++) {
            cairo_arc(cr, draw_fx(f, (double)i), draw_fy(f, in->history[i]), 2.2, 0, 2 * PV_PI);
            cairo_fill(cr);
        }
    stage_label(s, text, sizeof text);
    if (*legend_x + draw_text_width(cr, DRAW_SMALL, 0, text) + 20 > f->px + f->pw) return;
    cairo_rectangle(cr, *legend_x, f->py + 6, 9, 9);
    cairo_fill(cr);
    draw_grey(cr, 0.85);
    draw_text(cr, *legend_x + 12, f->py + 4, DRAW_SMALL, 0, 0.0, text);
    *legend_x += draw_text_width(cr, DRAW_SMALL, 0, text) + 24;
}

void pv_cost_plot(cairo_t *cr, const cli_preview_input *in, double x, double y, double w,
                  double h)
{
    draw_frame f;
    char text[200];
    double lo = 0, hi = 0, legend_x;
    size_t k, n = in->n_history;
    range_of(in->history, n, 1, &lo, &hi);
    if (n == 0)
        cli_format(text, sizeof text, "cost of the fit: none recorded");
    else
        cli_format(text, sizeof text, "cost of the whole fit, %zu stage%s: %.4g \u2192 %.4g",
                   in->n_stages, in->n_stages == 1 ? "" : "s", in->history[0],
                   in->history[n - 1]);
    draw_grey(cr, 0.9);
    draw_text_fit(cr, x, y, DRAW_TEXT, 0, w, text);
    memset(&f, 0, sizeof f);
    f.x = x;
    f.y = y + LABEL;
    f.w = w;
    f.h = h - LABEL;
    f.ax.title = "step (scan: profile evaluations; LM: iterations)";
    f.ay.title = hi / lo >= 10.0 ? "cost (log)" : "cost";
    draw_axis_linear(&f.ax, 0.0, n > 1 ? (double)(n - 1) : 1.0);
    f.ax.integer = 1;
    if (hi / lo >= 10.0)
        draw_axis_decades(&f.ay, lo, hi);
    else
        draw_axis_linear(&f.ay, lo, hi);
    draw_frame_axes(cr, &f);
    /* the legend at the top right, where costs have fallen */
    legend_x = f.px + f.pw - 6;
    for (k = 0; k < in->n_stages; k++) {
        stage_label(&in->stages[k], text, sizeof text);
        legend_x -= draw_text_width(cr, DRAW_SMALL, 0, text) + 24;
    }
    if (legend_x < f.px + 6) legend_x = f.px + 6;
    for (k = 0; k < in->n_stages; k++) cost_stage(cr, in, &f, k, &legend_x);
}

/* --- values against the half-angle ------------------------------------------------ */

typedef struct points {
    size_t n, total, missing, n_inside;
    double *ti, *pi, *to, *po, *th, *measured, *model, *values;
    unsigned char *outside; /* beyond the cap: not fitted */
} points;

static void points_free(points *p)
{
    free(p->ti);
    free(p->values);
    free(p->outside);
}

static double half_angle(double ti, double pi, double to, double po)
{
    double hx = sin(ti) * cos(pi) + sin(to) * cos(po);
    double hy = sin(ti) * sin(pi) + sin(to) * sin(po), hz = cos(ti) + cos(to);
    double len = sqrt(hx * hx + hy * hy + hz * hz);
    return len > 1e-12 ? acos(hz / len > 1.0 ? 1.0 : hz / len) * 180.0 / PV_PI : 90.0;
}

/* Every stride-th sample with all channels present. */
static int gather(const cli_preview_input *in, points *p, char *msg, size_t msg_size)
{
    size_t nc = brdffit_grid_channel_count(in->grid), s, c, stride;
    memset(p, 0, sizeof *p);
    p->total = brdffit_grid_sample_count(in->grid);
    stride = p->total / MAX_POINTS + 1;
    p->ti = malloc(7 * (p->total / stride + 1) * sizeof(double));
    p->values = malloc((p->total / stride + 1) * nc * sizeof(double));
    p->outside = malloc(p->total / stride + 1);
    if (p->ti == NULL || p->values == NULL || p->outside == NULL) {
        cli_format(msg, msg_size, "out of memory");
        return -1;
    }
    p->pi = p->ti + (p->total / stride + 1);
    p->to = p->pi + (p->total / stride + 1);
    p->po = p->to + (p->total / stride + 1);
    p->th = p->po + (p->total / stride + 1);
    p->measured = p->th + (p->total / stride + 1);
    p->model = p->measured + (p->total / stride + 1);
    for (s = 0; s < p->total; s += stride) {
        size_t k = p->n;
        double sum = 0.0;
        for (c = 0; c < nc; c++) {
            const double *v;
            if (brdffit_grid_is_missing(in->grid, s, c)) break;
            brdffit_grid_values(in->grid, c, &v);
            sum += v[s];
        }
        if (c < nc) {
            p->missing++;
            continue;
        }
        brdffit_grid_sample_angles(in->grid, s, &p->ti[k], &p->pi[k], &p->to[k], &p->po[k]);
        p->th[k] = half_angle(p->ti[k], p->pi[k], p->to[k], p->po[k]);
        p->measured[k] = sum / (double)nc;
        p->outside[k] = p->ti[k] > in->cap + 1e-9 || p->to[k] > in->cap + 1e-9;
        p->n_inside += !p->outside[k];
        p->n++;
    }
    return 0;
}

static int model_values(const cli_preview_input *in, points *p, char *msg, size_t msg_size)
{
    size_t nc = brdffit_grid_channel_count(in->grid), k, c;
    brdffit_error err;
    if (p->n == 0) return 0;
    if (brdffit_model_eval_angles(in->model, p->n, p->ti, p->pi, p->to, p->po, nc, in->params,
                                  p->values, NULL, &err) != BRDFFIT_OK) {
        cli_format(msg, msg_size, "%s", err.message);
        return -1;
    }
    for (k = 0; k < p->n; k++) {
        double sum = 0.0;
        for (c = 0; c < nc; c++) sum += p->values[c * p->n + k];
        p->model[k] = sum / (double)nc;
    }
    return 0;
}

/* Squares of half-size r * scale at the points (which: 0 inside the cap,
 * 1 beyond it, -1 all). */
static void dots(cairo_t *cr, const draw_frame *f, const points *p, const double *v, int which,
                 double scale)
{
    size_t k;
    double r = scale * (p->n > 5000 ? 1.0 : p->n > 500 ? 1.6 : 2.4);
    for (k = 0; k < p->n; k++) {
        if (which >= 0 && p->outside[k] != which) continue;
        cairo_rectangle(cr, draw_fx(f, p->th[k]) - r, draw_fy(f, v[k]) - r, 2 * r, 2 * r);
    }
    cairo_fill(cr);
}

static void key(cairo_t *cr, double x, double y, double r, double g, double b, const char *t)
{
    cairo_set_source_rgb(cr, r, g, b);
    cairo_rectangle(cr, x, y + 3, 8, 8);
    cairo_fill(cr);
    draw_grey(cr, 0.9);
    draw_text(cr, x + 13, y, DRAW_SMALL, 0, 0.0, t);
}

/* The y range: the positive values inside the cap (the fitted ones; a
 * model can grow without bound at grazing angles), at most 6 decades. */
static void value_range(const points *p, double *lo, double *hi)
{
    size_t k;
    int any = 0;
    for (k = 0; k < p->n; k++) {
        double v[2] = {p->measured[k], p->model[k]};
        int j;
        for (j = 0; j < 2 && (!p->outside[k] || p->n_inside == 0); j++) {
            if (!(v[j] > 0.0)) continue;
            if (!any || v[j] < *lo) *lo = v[j];
            if (!any || v[j] > *hi) *hi = v[j];
            any = 1;
        }
    }
    if (!any) *lo = 0.1, *hi = 1.0;
    if (*lo < *hi * 1e-6) *lo = *hi * 1e-6;
}

static void half_angle_draw(cairo_t *cr, const points *p, double cap, draw_frame *f)
{
    double lo = 0, hi = 0;
    char t[96];
    value_range(p, &lo, &hi);
    f->ax.lo = 0.0;
    f->ax.hi = 90.0;
    f->ax.title = "\u03b8h (half-angle, degrees)";
    f->ay.title = "BRDF (1/sr, log)";
    if (hi / lo >= 10.0)
        draw_axis_decades(&f->ay, lo, hi);
    else {
        draw_axis_linear(&f->ay, lo, hi);
        f->ay.title = "BRDF (1/sr)";
    }
    draw_frame_axes(cr, f);
    /* measured larger and below, so that a model on top of it leaves a rim */
    cairo_set_source_rgba(cr, 0.45, 0.55, 0.85, 0.6);
    dots(cr, f, p, p->measured, 1, 1.5);
    cairo_set_source_rgba(cr, 0.92, 0.92, 0.92, 0.6);
    dots(cr, f, p, p->measured, 0, 1.5);
    cairo_set_source_rgba(cr, orange[0], orange[1], orange[2], 0.8);
    dots(cr, f, p, p->model, -1, 0.7);
    key(cr, f->x + 62, f->y - 16, 0.92, 0.92, 0.92, "measured");
    cli_format(t, sizeof t, "measured beyond the %g\u00b0 cap (not fitted)", cap * 180 / PV_PI);
    key(cr, f->x + 132, f->y - 16, 0.45, 0.55, 0.85, t);
    key(cr, f->x + 132 + 24 + draw_text_width(cr, DRAW_SMALL, 0, t), f->y - 16, orange[0],
        orange[1], orange[2], "model");
}

int pv_half_angle_plot(cairo_t *cr, const cli_preview_input *in, double x, double y, double w,
                       double h, char *msg, size_t msg_size)
{
    points p;
    draw_frame f;
    char text[200];
    int rc = gather(in, &p, msg, msg_size);
    if (rc == 0) rc = model_values(in, &p, msg, msg_size);
    if (rc == 0) {
        size_t every = p.total / MAX_POINTS + 1;
        if (every > 1)
            cli_format(text, sizeof text, "BRDF (channel mean) against \u03b8h: 1 in %zu of %zu samples",
                       every, p.total);
        else
            cli_format(text, sizeof text, "BRDF (channel mean) against \u03b8h: all %zu samples",
                       p.total);
        if (p.missing > 0)
            cli_format(text + strlen(text), sizeof text - strlen(text), "; %zu incomplete left out",
                       p.missing);
        draw_grey(cr, 0.9);
        draw_text_fit(cr, x, y, DRAW_TEXT, 0, w, text);
        memset(&f, 0, sizeof f);
        f.x = x;
        f.y = y + 2 * LABEL;
        f.w = w;
        f.h = h - 2 * LABEL;
        half_angle_draw(cr, &p, in->cap, &f);
    }
    points_free(&p);
    return rc;
}
