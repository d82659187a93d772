/* Drawing helpers of the preview on cairo (draw.h). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "draw.h"

static void set_font(cairo_t *cr, double size, int bold)
{
    cairo_select_font_face(cr, DRAW_FONT, CAIRO_FONT_SLANT_NORMAL,
                           bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, size);
}

double draw_text_width(cairo_t *cr, double size, int bold, const char *text)
{
    cairo_text_extents_t te;
    set_font(cr, size, bold);
    cairo_text_extents(cr, text, &te);
    return te.x_advance;
}

void draw_text(cairo_t *cr, double x, double y, double size, int bold, double align,
               const char *text)
{
    cairo_font_extents_t fe;
    double w = draw_text_width(cr, size, bold, text);
    cairo_font_extents(cr, &fe);
    cairo_move_to(cr, x - align * w, y + fe.ascent);
    cairo_show_text(cr, text);
    cairo_new_path(cr);
}

void draw_text_fit(cairo_t *cr, double x, double y, double size, int bold, double max_w,
                   const char *text)
{
    double w = draw_text_width(cr, size, bold, text);
    /* hinted widths do not shrink exactly in proportion: 5 % to spare */
    draw_text(cr, x, y, w > max_w ? size * 0.95 * max_w / w : size, bold, 0.0, text);
}

void draw_rgb(cairo_t *cr, const unsigned char rgb[3])
{
    cairo_set_source_rgb(cr, rgb[0] / 255.0, rgb[1] / 255.0, rgb[2] / 255.0);
}

void draw_grey(cairo_t *cr, double v)
{
    cairo_set_source_rgb(cr, v, v, v);
}

int draw_pixels(cairo_t *cr, const unsigned char *px, size_t stride, size_t w, size_t h,
                double x, double y, double dw, double dh)
{
    cairo_surface_t *s;
    unsigned char *dst;
    int ds;
    size_t i, j;
    if (w == 0 || h == 0 || w > 32767 || h > 32767) return -1;
    s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, (int)w, (int)h);
    if (cairo_surface_status(s) != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(s);
        return -1;
    }
    cairo_surface_flush(s);
    dst = cairo_image_surface_get_data(s);
    ds = cairo_image_surface_get_stride(s);
    for (j = 0; j < h; j++) {
        uint32_t *row = (uint32_t *)(void *)(dst + j * (size_t)ds);
        const unsigned char *src = px + j * stride;
        for (i = 0; i < w; i++)
            row[i] = (uint32_t)src[3 * i] << 16 | (uint32_t)src[3 * i + 1] << 8 | src[3 * i + 2];
    }
    cairo_surface_mark_dirty(s);
    cairo_save(cr);
    cairo_rectangle(cr, x, y, dw, dh);
    cairo_clip(cr);
    cairo_translate(cr, x, y);
    cairo_scale(cr, dw / (double)w, dh / (double)h);
    cairo_set_source_surface(cr, s, 0, 0);
    cairo_pattern_set_filter(cairo_get_source(cr), dw >= (double)w && dh >= (double)h
                                                       ? CAIRO_FILTER_NEAREST
                                                       : CAIRO_FILTER_GOOD);
    cairo_pattern_set_extend(cairo_get_source(cr), CAIRO_EXTEND_PAD);
    cairo_paint(cr);
    cairo_restore(cr);
    cairo_surface_destroy(s);
    return 0;
}

/* --- axes -------------------------------------------------------------------- */

static double nice_step(double range, int want)
{
    double raw = range / want, p = pow(10.0, floor(log10(raw))), m = raw / p;
    return (m < 1.5 ? 1.0 : m < 3.5 ? 2.0 : m < 7.5 ? 5.0 : 10.0) * p;
}

void draw_axis_linear(draw_axis *a, double lo, double hi)
{
    double pad;
    if (!(hi > lo)) {
        double d = lo != 0.0 ? fabs(lo) * 0.05 : 1.0;
        lo -= d;
        hi += d;
    }
    pad = 0.05 * (hi - lo);
    a->lo = lo - pad;
    a->hi = hi + pad;
    a->log = 0;
}

void draw_axis_decades(draw_axis *a, double lo, double hi)
{
    double l = floor(log10(lo)), h = ceil(log10(hi));
    if (h <= l) h = l + 1.0;
    a->lo = pow(10.0, l);
    a->hi = pow(10.0, h);
    a->log = 1;
}

static double axis_pos(const draw_axis *a, double v)
{
    double t;
    if (a->log)
        t = v > 0.0 ? (log10(v) - log10(a->lo)) / (log10(a->hi) - log10(a->lo)) : 0.0;
    else
        t = (v - a->lo) / (a->hi - a->lo);
    return t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
}

double draw_fx(const draw_frame *f, double v)
{
    return f->px + axis_pos(&f->ax, v) * f->pw;
}

double draw_fy(const draw_frame *f, double v)
{
    return f->py + f->ph - axis_pos(&f->ay, v) * f->ph;
}

/* A tick number with as many digits as the step needs. */
static void tick_label(char *buf, size_t size, double v, double step, int log_axis)
{
    int decimals = (int)-floor(log10(step) + 1e-9);
    if (log_axis) {
        long e = lround(log10(v));
        if (e >= 0 && e <= 3)
            cli_format(buf, size, "%.0f", pow(10.0, (double)e));
        else if (e < 0 && e >= -3)
            cli_format(buf, size, "%.*f", (int)-e, pow(10.0, (double)e));
        else
            cli_format(buf, size, "1e%ld", e);
        return;
    }
    if (fabs(v) < step * 1e-6) v = 0.0;
    if (decimals < 0) decimals = 0;
    if (step >= 1e-3 && fabs(v) < 1e6)
        cli_format(buf, size, "%.*f", decimals, v);
    else
        cli_format(buf, size, "%.*e", v == 0.0 ? 0 : (int)floor(log10(fabs(v))) + decimals, v);
}

/* Calls fn for every tick of the axis: value, step. */
typedef void (*tick_fn)(cairo_t *cr, const draw_frame *f, double v, double step);

static void each_tick(cairo_t *cr, const draw_frame *f, const draw_axis *a, double len, tick_fn fn)
{
    double v, step;
    if (a->log) {
        double e, e0 = log10(a->lo), e1 = log10(a->hi);
        double every = ceil((e1 - e0) / 8.0);
        for (e = e0; e <= e1 + 1e-9; e += every) fn(cr, f, pow(10.0, e), every);
        return;
    }
    step = nice_step(a->hi - a->lo, len > 300 ? 6 : 4);
    if (a->integer && step < 1.0) step = 1.0;
    for (v = ceil(a->lo / step) * step; v <= a->hi + step * 1e-9; v += step) fn(cr, f, v, step);
}

static void x_tick(cairo_t *cr, const draw_frame *f, double v, double step)
{
    char t[48];
    double x = draw_fx(f, v);
    cairo_set_source_rgba(cr, 1, 1, 1, 0.12);
    cairo_move_to(cr, x, f->py);
    cairo_line_to(cr, x, f->py + f->ph);
    cairo_stroke(cr);
    draw_grey(cr, 0.8);
    cairo_move_to(cr, x, f->py + f->ph);
    cairo_line_to(cr, x, f->py + f->ph + 4);
    cairo_stroke(cr);
    tick_label(t, sizeof t, v, step, f->ax.log);
    draw_text(cr, x, f->py + f->ph + 6, DRAW_SMALL, 0, 0.5, t);
}

static void y_tick(cairo_t *cr, const draw_frame *f, double v, double step)
{
    char t[48];
    double y = draw_fy(f, v);
    cairo_set_source_rgba(cr, 1, 1, 1, 0.12);
    cairo_move_to(cr, f->px, y);
    cairo_line_to(cr, f->px + f->pw, y);
    cairo_stroke(cr);
    draw_grey(cr, 0.8);
    cairo_move_to(cr, f->px - 4, y);
    cairo_line_to(cr, f->px, y);
    cairo_stroke(cr);
    tick_label(t, sizeof t, v, step, f->ay.log);
    draw_text(cr, f->px - 6, y - DRAW_SMALL * 0.6, DRAW_SMALL, 0, 1.0, t);
}

void draw_frame_axes(cairo_t *cr, draw_frame *f)
{
    double left = 62.0, bottom = 36.0;
    f->px = f->x + left;
    f->py = f->y + 6.0;
    f->pw = f->w - left - 10.0;
    f->ph = f->h - bottom - 6.0;
    cairo_set_source_rgb(cr, 0.19, 0.19, 0.19);
    cairo_rectangle(cr, f->px, f->py, f->pw, f->ph);
    cairo_fill(cr);
    cairo_set_line_width(cr, 1.0);
    each_tick(cr, f, &f->ax, f->pw, x_tick);
    each_tick(cr, f, &f->ay, f->ph, y_tick);
    draw_grey(cr, 0.8);
    cairo_rectangle(cr, f->px + 0.5, f->py + 0.5, f->pw - 1, f->ph - 1);
    cairo_stroke(cr);
    draw_text(cr, f->px + f->pw / 2, f->y + f->h - DRAW_TEXT - 2, DRAW_TEXT, 0, 0.5, f->ax.title);
    cairo_save(cr);
    cairo_translate(cr, f->x + 2, f->py + f->ph / 2);
    cairo_rotate(cr, -3.14159265358979323846 / 2);
    draw_text(cr, 0, 0, DRAW_TEXT, 0, 0.5, f->ay.title);
    cairo_restore(cr);
}

/* --- PNG --------------------------------------------------------------------- */

static cairo_status_t to_file(void *closure, const unsigned char *data, unsigned int length)
{
    return fwrite(data, 1, length, closure) == length ? CAIRO_STATUS_SUCCESS
                                                      : CAIRO_STATUS_WRITE_ERROR;
}

static int write_png(FILE *f, void *ctx, char *msg, size_t msg_size)
{
    cairo_status_t st = cairo_surface_write_to_png_stream(ctx, to_file, f);
    if (st == CAIRO_STATUS_SUCCESS) return 0;
    cli_format(msg, msg_size, "cairo: %s", cairo_status_to_string(st));
    return -1;
}

int draw_write_png(cairo_surface_t *s, const char *path, char *msg, size_t msg_size)
{
    return cli_write_atomic(path, write_png, s, msg, msg_size);
}

static cairo_status_t to_buf(void *closure, const unsigned char *data, unsigned int length)
{
    cli_buf *b = closure;
    cli_buf_write(b, (const char *)data, length);
    return b->failed ? CAIRO_STATUS_NO_MEMORY : CAIRO_STATUS_SUCCESS;
}

int draw_png_bytes(cairo_surface_t *s, cli_buf *out)
{
    return cairo_surface_write_to_png_stream(s, to_buf, out) == CAIRO_STATUS_SUCCESS ? 0 : -1;
}
