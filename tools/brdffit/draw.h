/* Drawing helpers of the preview (preview*.c), on cairo: text in a real
 * font, library pixel buffers placed and scaled on the page, plot frames
 * with numbered axes, and PNG output. Internal to the command. */
#ifndef BRDFFIT_CLI_DRAW_H
#define BRDFFIT_CLI_DRAW_H

#include <cairo.h>
#include <stddef.h>

#include "cli.h"

#define DRAW_FONT "DejaVu Sans"
#define DRAW_TEXT 12.0  /* body text, px */
#define DRAW_SMALL 10.0 /* tick numbers, px */
#define DRAW_TITLE 15.0 /* the title line, px */

/* Text with its top-left (align 0), top-centre (0.5) or top-right (1)
 * corner at (x, y), in the current source colour. */
void draw_text(cairo_t *cr, double x, double y, double size, int bold, double align,
               const char *text);
double draw_text_width(cairo_t *cr, double size, int bold, const char *text);
/* draw_text() left-aligned, the size reduced so that it fits max_w. */
void draw_text_fit(cairo_t *cr, double x, double y, double size, int bold, double max_w,
                   const char *text);
void draw_rgb(cairo_t *cr, const unsigned char rgb[3]);
void draw_grey(cairo_t *cr, double v);

/* Paints a w x h RGB buffer (stride bytes per row, as image.h makes them)
 * into the rectangle (x, y, dw, dh); nearest-neighbour when enlarged in
 * both directions, filtered when shrunk. 0 on success. */
int draw_pixels(cairo_t *cr, const unsigned char *px, size_t stride, size_t w, size_t h,
                double x, double y, double dw, double dh);

/* One plot axis: lo .. hi, linear or log10 (then lo > 0). */
typedef struct draw_axis {
    double lo, hi;
    int log;
    int integer; /* ticks at whole numbers only */
    const char *title;
} draw_axis;

/* A plot: the outer rectangle (x, y, w, h) holds the tick numbers and axis
 * titles; the data area is computed by draw_frame(). */
typedef struct draw_frame {
    double x, y, w, h;         /* outer rectangle */
    double px, py, pw, ph;     /* data area (set by draw_frame) */
    draw_axis ax, ay;
} draw_frame;

/* Background, axes, ticks with numbers, grid lines and titles. */
void draw_frame_axes(cairo_t *cr, draw_frame *f);
/* Data coordinates to page coordinates (clamped to the data area). */
double draw_fx(const draw_frame *f, double v);
double draw_fy(const draw_frame *f, double v);
/* A linear axis around lo .. hi with a little room (hi > lo afterwards),
 * or whole decades around the positive range lo .. hi. */
void draw_axis_linear(draw_axis *a, double lo, double hi);
void draw_axis_decades(draw_axis *a, double lo, double hi);

/* Writes the surface as PNG, atomically (cli_write_atomic): 0 on success. */
int draw_write_png(cairo_surface_t *s, const char *path, char *msg, size_t msg_size);
/* The PNG bytes of the surface in a cli_buf (for data URLs): 0 on success. */
int draw_png_bytes(cairo_surface_t *s, cli_buf *out);

#endif /* BRDFFIT_CLI_DRAW_H */
