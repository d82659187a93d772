/* A line plot of a series into a pixel buffer: axes, tick marks, faint
 * grid lines and the curve. No text. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "image/image_internal.h"

/* The plot area and the value range it shows. */
typedef struct plot_frame {
    unsigned char *pixels;
    size_t stride;
    long x0, x1, y0, y1;     /* axes at x0 (left) and y1 (bottom) */
    long dx0, dx1, dy0, dy1; /* where data points go */
    double lo, hi;           /* value range, log10 with log_y */
    int log_y;
} plot_frame;

static void put(const plot_frame *f, long x, long y, const unsigned char rgb[3])
{
    memcpy(f->pixels + (size_t)y * f->stride + 3 * (size_t)x, rgb, 3);
}

/* A step of 1, 2 or 5 times a power of ten giving at most max_ticks ticks. */
static double nice_step(double range, double max_ticks)
{
    double base = pow(10.0, floor(log10(range / max_ticks)));
    if (range / base <= max_ticks) return base;
    if (range / (2.0 * base) <= max_ticks) return 2.0 * base;
    if (range / (5.0 * base) <= max_ticks) return 5.0 * base;
    return 10.0 * base;
}

static double scaled(const plot_frame *f, double v)
{
    if (!f->log_y) return v;
    return v > 0.0 ? log10(v) : f->lo;
}

static long y_pixel(const plot_frame *f, double t)
{
    /* halves keep the differences finite for values near DBL_MAX */
    double span = 0.5 * f->hi - 0.5 * f->lo;
    double frac = span > 0.0 ? (0.5 * t - 0.5 * f->lo) / span : 0.5;
    return f->dy1 - (long)floor(frac * (double)(f->dy1 - f->dy0) + 0.5);
}

static long x_pixel(const plot_frame *f, size_t i, size_t count)
{
    if (count < 2) return (f->dx0 + f->dx1) / 2;
    return f->dx0 + (long)floor((double)i * (double)(f->dx1 - f->dx0) / (double)(count - 1) + 0.5);
}

static void value_range(plot_frame *f, const double *v, size_t count)
{
    size_t i;
    int any = 0;
    f->lo = 0.0;
    f->hi = 0.0;
    for (i = 0; i < count; i++) {
        double t;
        if (f->log_y && !(v[i] > 0.0)) continue;
        t = f->log_y ? log10(v[i]) : v[i];
        if (!any || t < f->lo) f->lo = t;
        if (!any || t > f->hi) f->hi = t;
        any = 1;
    }
    if (f->log_y && any) { /* whole decades */
        f->lo = floor(f->lo);
        f->hi = ceil(f->hi);
        if (f->hi == f->lo) f->hi = f->lo + 1.0;
    }
}

static void mix(unsigned char out[3], const unsigned char a[3], const unsigned char b[3])
{
    size_t c;
    for (c = 0; c < 3; c++) out[c] = (unsigned char)((3 * a[c] + b[c]) / 4);
}

static void y_ticks(const plot_frame *f, const brdffit_image_options *o)
{
    unsigned char faint[3];
    double span = 0.5 * f->hi - 0.5 * f->lo, step, first, n_ticks, n;
    long x, k;
    if (!(span > 0.0)) return;
    step = f->log_y ? ceil(span / 5.0) : 2.0 * nice_step(span, 3.0);
    if (!(step > 0.0) || !isfinite(step)) return;
    first = ceil(f->lo / step);
    n_ticks = floor(f->hi / step + 1e-9) - first + 1.0;
    if (!(n_ticks >= 1.0 && n_ticks <= 16.0)) return; /* rounding trouble: no ticks */
    mix(faint, o->background, o->foreground);
    for (n = 0.0; n < n_ticks; n += 1.0) {
        long y = y_pixel(f, (first + n) * step);
        if (y < f->y0 || y > f->y1) continue;
        for (x = f->x0 + 1; x <= f->x1; x++) put(f, x, y, faint);
        for (k = 1; k <= 3; k++) put(f, f->x0 - k, y, o->foreground);
    }
}

static void x_ticks(const plot_frame *f, size_t count, const unsigned char rgb[3])
{
    double step;
    size_t i;
    long k;
    if (count < 2) return;
    step = nice_step((double)(count - 1), 10.0);
    if (step < 1.0) step = 1.0;
    for (i = 0; i < count; i += (size_t)step)
        for (k = 1; k <= 3; k++) put(f, x_pixel(f, i, count), f->y1 + k, rgb);
}

static void axes(const plot_frame *f, const unsigned char rgb[3])
{
    long x, y;
    for (y = f->y0; y <= f->y1; y++) put(f, f->x0, y, rgb);
    for (x = f->x0; x <= f->x1; x++) put(f, x, f->y1, rgb);
}

/* A 2 x 2 stamp at (x, y). */
static void stamp(const plot_frame *f, long x, long y, const unsigned char rgb[3])
{
    put(f, x, y, rgb);
    put(f, x + 1, y, rgb);
    put(f, x, y + 1, rgb);
    put(f, x + 1, y + 1, rgb);
}

/* Bresenham's line from (xa, ya) to (xb, yb). */
static void line(const plot_frame *f, long xa, long ya, long xb, long yb,
                 const unsigned char rgb[3])
{
    long dx = labs(xb - xa), dy = -labs(yb - ya);
    long sx = xa < xb ? 1 : -1, sy = ya < yb ? 1 : -1, e = dx + dy;
    for (;;) {
        long e2 = 2 * e;
        stamp(f, xa, ya, rgb);
        if (xa == xb && ya == yb) return;
        if (e2 >= dy) {
            e += dy;
            xa += sx;
        }
        if (e2 <= dx) {
            e += dx;
            ya += sy;
        }
    }
}

static void curve(const plot_frame *f, const double *v, size_t count, const unsigned char rgb[3])
{
    long px = 0, py = 0;
    size_t i;
    for (i = 0; i < count; i++) {
        long x = x_pixel(f, i, count), y = y_pixel(f, scaled(f, v[i]));
        if (i == 0)
            stamp(f, x, y, rgb);
        else
            line(f, px, py, x, y, rgb);
        px = x;
        py = y;
    }
}

static brdffit_status check_series(const double *values, size_t count, brdffit_error *err)
{
    size_t i;
    if (count > 0 && values == NULL)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "values is NULL");
    for (i = 0; i < count; i++)
        if (!isfinite(values[i]))
            return bf_fail(err, BRDFFIT_E_NONFINITE, "value %zu of the series is not finite", i);
    return BRDFFIT_OK;
}

static void frame_init(plot_frame *f, unsigned char *pixels, size_t stride, size_t width,
                       size_t height)
{
    size_t side = width < height ? width : height;
    long m = (long)(side / 16 > 4 ? side / 16 : 4);
    f->pixels = pixels;
    f->stride = stride;
    f->x0 = m;
    f->x1 = (long)width - 1 - m;
    f->y0 = m;
    f->y1 = (long)height - 1 - m;
    f->dx0 = f->x0 + 2;
    f->dx1 = f->x1 - 1;
    f->dy0 = f->y0;
    f->dy1 = f->y1 - 2;
}

brdffit_status brdffit_image_plot(unsigned char *pixels, size_t stride, size_t width, size_t height,
                                  const double *values, size_t count,
                                  const brdffit_image_options *opts, brdffit_error *err)
{
    brdffit_image_options o;
    plot_frame f;
    BF_RETURN_IF_ERROR(bf_image_options(&o, opts, err));
    BF_RETURN_IF_ERROR(bf_image_check_buffer(pixels, stride, width, height, 16, err));
    BF_RETURN_IF_ERROR(check_series(values, count, err));
    frame_init(&f, pixels, stride, width, height);
    f.log_y = o.log_y != 0;
    value_range(&f, values, count);
    bf_image_fill(pixels, stride, 0, 0, width, height, o.background);
    y_ticks(&f, &o);
    axes(&f, o.foreground);
    x_ticks(&f, count, o.foreground);
    curve(&f, values, count, o.curve);
    return BRDFFIT_OK;
}
