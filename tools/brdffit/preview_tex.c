/* The texture panel of the preview: for each shown theta_i one row of
 * three blocks (measured, difference, model) from brdffit_image_texture(),
 * labelled with theta_i and with theta_o and phi_o ticks; rows in groups
 * side by side; below, the colour scales of the textures and the colour of
 * missing cells. Dense grids are shown as at most MAX_SHOWN theta_i rows,
 * each block shrunk to at most MAX_DW pixels wide, so the panel stays a
 * few thousand pixels at most whatever the grid. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "preview.h"

#define MAX_SHOWN 19
#define MIN_DW 140.0
#define MAX_DW 280.0
#define MIN_DH 40.0
#define MAX_DH 240.0
#define MAX_H 1000.0
#define STRIP 100.0
#define COLGAP 10.0
#define ROWGAP 8.0
#define HEADER 36.0
#define FOOT 40.0
#define LEGEND_H 128.0
#define MIN_W 440.0
#define MAX_TEX 32000 /* rows of one rendered texture (the library allows 32768) */

static const char *const kind_names[3] = {"measured", "difference", "model"};
static const brdffit_texture_kind kinds[3] = {BRDFFIT_TEXTURE_MEASURED,
                                              BRDFFIT_TEXTURE_DIFFERENCE, BRDFFIT_TEXTURE_MODEL};

static double group_width(const pv_textures *t)
{
    return STRIP + 3.0 * t->dw + 2.0 * COLGAP;
}

static void choose_shown(pv_textures *t)
{
    size_t k;
    t->n_shown = t->n_ti <= MAX_SHOWN ? t->n_ti : MAX_SHOWN;
    for (k = 0; k < t->n_shown; k++)
        t->shown[k] = t->n_shown == t->n_ti
                          ? k
                          : (size_t)floor((double)k * (double)(t->n_ti - 1) /
                                              (double)(t->n_shown - 1) + 0.5);
}

static void choose_size(pv_textures *t)
{
    double bw = (double)t->block_w, sx;
    if (bw < MIN_DW)
        t->dw = bw * ceil(MIN_DW / bw);
    else
        t->dw = bw <= MAX_DW ? bw : MAX_DW;
    sx = t->dw / bw;
    t->dh = (double)t->block_h * sx;
    if (t->dh < MIN_DH) t->dh = MIN_DH;
    if (t->dh > MAX_DH) t->dh = MAX_DH;
    t->rows = (size_t)(MAX_H / (t->dh + ROWGAP));
    if (t->rows < 1) t->rows = 1;
    t->groups = (t->n_shown + t->rows - 1) / t->rows;
    t->rows = (t->n_shown + t->groups - 1) / t->groups;
}

int pv_textures_layout(const brdffit_grid *grid, pv_textures *t, char *msg, size_t msg_size)
{
    const double *v[3];
    size_t n[3];
    int a;
    for (a = 0; a < 3; a++)
        if (brdffit_grid_axis(grid, (brdffit_axis)a, &v[a], &n[a]) != BRDFFIT_OK || n[a] == 0) {
            cli_format(msg, msg_size, "the grid has no axes");
            return -1;
        }
    t->n_ti = n[0];
    t->n_to = n[1];
    t->n_po = n[2];
    t->block_w = 2 * n[2] - (v[2][0] == 0.0 ? 1 : 0);
    t->block_h = n[1];
    choose_shown(t);
    choose_size(t);
    t->width = (double)t->groups * group_width(t) + (double)(t->groups - 1) * PV_GAP;
    if (t->width < MIN_W) t->width = MIN_W;
    t->height = HEADER + (double)t->rows * (t->dh + ROWGAP) + FOOT + LEGEND_H;
    return 0;
}

/* --- the three textures, rendered whole by the library ------------------------ */

typedef struct rendered {
    unsigned char *px[3];
    size_t w, h, columns; /* texture size, blocks per row of blocks */
} rendered;

static int render_all(const cli_preview_input *in, const pv_textures *t,
                      const brdffit_image_options *base, rendered *r, char *msg, size_t msg_size)
{
    brdffit_image_options o = *base;
    brdffit_error err;
    size_t k;
    memset(r, 0, sizeof *r);
    o.block_gap = 0;
    o.scale = 1;
    o.block_columns = (t->n_ti * t->block_h + MAX_TEX - 1) / MAX_TEX;
    r->columns = o.block_columns;
    if (brdffit_image_texture_size(in->grid, &o, &r->w, &r->h, &err) != BRDFFIT_OK) {
        cli_format(msg, msg_size, "%s", err.message);
        return -1;
    }
    for (k = 0; k < 3; k++) {
        r->px[k] = malloc(3 * r->w * r->h);
        if (r->px[k] == NULL) {
            cli_format(msg, msg_size, "out of memory (textures of %zu x %zu pixels)", r->w,
                       r->h);
            return -1;
        }
        if (brdffit_image_texture(r->px[k], 3 * r->w, kinds[k], in->grid, in->model, in->params,
                                  &o, NULL, &err) != BRDFFIT_OK) {
            cli_format(msg, msg_size, "%s", err.message);
            return -1;
        }
    }
    return 0;
}

/* --- labels ----------------------------------------------------------------------- */

static void deg_text(char *buf, size_t size, double rad)
{
    cli_format(buf, size, "%g\u00b0", floor(rad * 180.0 / PV_PI * 100.0 + 0.5) / 100.0);
}

static void headers(cairo_t *cr, const pv_textures *t, double gx, double y)
{
    size_t k;
    draw_grey(cr, 0.95);
    for (k = 0; k < 3; k++)
        draw_text(cr, gx + STRIP + k * (t->dw + COLGAP) + t->dw / 2, y, DRAW_TEXT, 1, 0.5,
                  kind_names[k]);
    draw_grey(cr, 0.7);
    draw_text(cr, gx, y + 17, DRAW_SMALL, 0, 0.0, "\u03b8i (light)");
    draw_text(cr, gx + STRIP - 6, y + 17, DRAW_SMALL, 0, 1.0, "\u03b8o \u2193");
}

static void row_labels(cairo_t *cr, const brdffit_grid *grid, size_t ti, double gx, double by,
                       double dh)
{
    const double *v;
    size_t n;
    char text[64], a[32];
    brdffit_grid_axis(grid, BRDFFIT_AXIS_THETA_I, &v, &n);
    deg_text(a, sizeof a, v[ti]);
    cli_format(text, sizeof text, "\u03b8i = %s", a);
    draw_grey(cr, 0.95);
    draw_text(cr, gx, by + dh / 2 - 7, DRAW_TEXT, 1, 0.0, text);
    brdffit_grid_axis(grid, BRDFFIT_AXIS_THETA_O, &v, &n);
    draw_grey(cr, 0.75);
    deg_text(a, sizeof a, v[0]);
    draw_text(cr, gx + STRIP - 6, by, DRAW_SMALL, 0, 1.0, a);
    deg_text(a, sizeof a, v[n - 1]);
    draw_text(cr, gx + STRIP - 6, by + dh - DRAW_SMALL - 2, DRAW_SMALL, 0, 1.0, a);
}

/* phi_o ticks under one block: -phi_last, 0 (the mirror direction) and
 * +phi_last at their column centres. */
static void phi_ticks(cairo_t *cr, const brdffit_grid *grid, const pv_textures *t, double bx,
                      double y)
{
    const double *v;
    size_t n;
    char a[32], b[40];
    double sx = t->dw / (double)t->block_w;
    double xs[3] = {bx + 0.5 * sx, bx + t->dw / 2, bx + t->dw - 0.5 * sx};
    size_t k;
    brdffit_grid_axis(grid, BRDFFIT_AXIS_PHI_O, &v, &n);
    deg_text(a, sizeof a, v[n - 1]);
    draw_grey(cr, 0.75);
    for (k = 0; k < 3; k++) {
        cairo_move_to(cr, xs[k], y);
        cairo_line_to(cr, xs[k], y + 4);
        cairo_stroke(cr);
        cli_format(b, sizeof b, "%s%s", k == 0 ? "\u2212" : "", k == 1 ? "0" : a);
        draw_text(cr, xs[k], y + 5, DRAW_SMALL, 0, k == 0 ? 0.0 : k == 2 ? 1.0 : 0.5, b);
    }
}

static void group_foot(cairo_t *cr, const brdffit_grid *grid, const pv_textures *t, double gx,
                       double y)
{
    size_t k;
    cairo_set_line_width(cr, 1.0);
    for (k = 0; k < 3; k++) phi_ticks(cr, grid, t, gx + STRIP + k * (t->dw + COLGAP), y);
    draw_grey(cr, 0.7);
    draw_text(cr, gx + STRIP + 1.5 * t->dw + COLGAP, y + 20, DRAW_SMALL, 0, 0.5,
              "\u03c6o (view azimuth), mirror direction in the middle");
}

/* --- colour scales ------------------------------------------------------------------ */

#define BAR_W 256.0
#define BAR_H 12.0

static double encode(double v, double gamma)
{
    v = v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v;
    return pow(v, 1.0 / gamma);
}

/* A bar from -range (signed) or 0 to +range with three numbered ticks. */
static void scale_bar(cairo_t *cr, double x, double y, double range, int is_signed,
                      const brdffit_image_options *o)
{
    int i;
    char t[48];
    for (i = 0; i < (int)BAR_W; i++) {
        double f = (i + 0.5) / BAR_W, v = is_signed ? (2.0 * f - 1.0) * range : f * range;
        double gv = is_signed ? o->difference_gain : o->gain, c = encode(fabs(v) * gv, o->gamma);
        if (is_signed)
            cairo_set_source_rgb(cr, v > 0 ? c : 0.0, 0.0, v < 0 ? c : 0.0);
        else
            draw_grey(cr, c);
        cairo_rectangle(cr, x + i, y, 1.0, BAR_H);
        cairo_fill(cr);
    }
    draw_grey(cr, 0.75);
    for (i = 0; i <= 2; i++) {
        double v = is_signed ? (i - 1) * range : i * range / 2.0;
        cli_format(t, sizeof t, "%s%.3g%s", v < 0 ? "\u2212" : v > 0 && is_signed ? "+" : "",
                   fabs(v), i == 2 ? " or more" : i == 0 && is_signed ? " or less" : "");
        draw_text(cr, x + i * BAR_W / 2, y + BAR_H + 2, DRAW_SMALL, 0, i == 0 ? 0.0 : 0.5, t);
    }
    if (is_signed)
        draw_text(cr, x + BAR_W + 10, y, DRAW_SMALL, 0, 0.0, "red: model above, blue: below");
}

static void legend(cairo_t *cr, const cli_preview_input *in, const pv_textures *t, double x,
                   double y, const brdffit_image_options *o)
{
    char text[160];
    draw_grey(cr, 0.9);
    draw_text(cr, x, y, DRAW_TEXT, 0, 0.0,
              brdffit_grid_channel_count(in->grid) == 3
                  ? "measured, model: BRDF value per channel (1/sr), red, green, blue"
                  : brdffit_grid_channel_count(in->grid) == 1
                        ? "measured, model: BRDF value (1/sr)"
                        : "measured, model: BRDF value, mean over the channels (1/sr)");
    scale_bar(cr, x, y + 16, o->gain > 0 ? 1.0 / o->gain : 1.0, 0, o);
    draw_grey(cr, 0.9);
    draw_text(cr, x, y + 46, DRAW_TEXT, 0, 0.0,
              "difference: model \u2212 measured, mean over the channels (1/sr)");
    scale_bar(cr, x, y + 62, o->difference_gain > 0 ? 1.0 / o->difference_gain : 1.0, 1, o);
    draw_rgb(cr, o->missing);
    cairo_rectangle(cr, x, y + 94, 24, 12);
    cairo_fill(cr);
    draw_grey(cr, 0.9);
    cli_format(text, sizeof text, "missing measurement (%zu values missing)",
               brdffit_grid_missing_count(in->grid));
    draw_text(cr, x + 32, y + 93, DRAW_TEXT, 0, 0.0, text);
    if (t->n_shown < t->n_ti) {
        cli_format(text, sizeof text, "%zu of the %zu \u03b8i blocks shown, evenly spaced",
                   t->n_shown, t->n_ti);
        draw_text(cr, x, y + 111, DRAW_TEXT, 0, 0.0, text);
    }
}

/* --- the panel ------------------------------------------------------------------------ */

static void one_row(cairo_t *cr, const cli_preview_input *in, const pv_textures *t,
                    const rendered *r, size_t ti, double gx, double by)
{
    size_t k, sx = (ti % r->columns) * t->block_w, sy = (ti / r->columns) * t->block_h;
    row_labels(cr, in->grid, ti, gx, by, t->dh);
    for (k = 0; k < 3; k++)
        draw_pixels(cr, r->px[k] + sy * 3 * r->w + 3 * sx, 3 * r->w, t->block_w, t->block_h,
                    gx + STRIP + k * (t->dw + COLGAP), by, t->dw, t->dh);
}

int pv_textures_draw(cairo_t *cr, const cli_preview_input *in, const pv_textures *t, double x,
                     double y, const brdffit_image_options *o, char *msg, size_t msg_size)
{
    rendered r;
    size_t j, g, k;
    int rc = render_all(in, t, o, &r, msg, msg_size);
    for (j = 0; rc == 0 && j < t->n_shown; j++) {
        double gx = x + (double)(j / t->rows) * (group_width(t) + PV_GAP);
        double by = y + HEADER + (double)(j % t->rows) * (t->dh + ROWGAP);
        one_row(cr, in, t, &r, t->shown[j], gx, by);
    }
    for (g = 0; rc == 0 && g < t->groups; g++) {
        double gx = x + (double)g * (group_width(t) + PV_GAP);
        headers(cr, t, gx, y);
        group_foot(cr, in->grid, t, gx, y + HEADER + (double)t->rows * (t->dh + ROWGAP) - 4);
    }
    if (rc == 0)
        legend(cr, in, t, x, y + HEADER + (double)t->rows * (t->dh + ROWGAP) + FOOT, o);
    for (k = 0; k < 3; k++) free(r.px[k]);
    return rc;
}
