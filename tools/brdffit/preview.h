/* The parts of the --preview picture (preview.c, preview_tex.c,
 * preview_plot.c). Internal to the command. */
#ifndef BRDFFIT_CLI_PREVIEW_H
#define BRDFFIT_CLI_PREVIEW_H

#include "draw.h"

#define PV_GAP 12.0
#define PV_PI 3.14159265358979323846

/* The texture panel of a regular grid: which theta_i blocks are shown and
 * how large, in groups of rows side by side. */
typedef struct pv_textures {
    size_t n_ti, n_to, n_po;  /* axis sizes */
    size_t block_w, block_h;  /* one block of the library's texture, px */
    size_t shown[32], n_shown; /* theta_i indices shown */
    double dw, dh;            /* one block on the page */
    size_t rows, groups;      /* rows per group, groups */
    double width, height;     /* the whole panel with headers and legend */
} pv_textures;

/* 0 and the layout for a regular grid; -1 with a message otherwise. */
int pv_textures_layout(const brdffit_grid *grid, pv_textures *t, char *msg, size_t msg_size);
/* Draws the panel with its top-left corner at (x, y). */
int pv_textures_draw(cairo_t *cr, const cli_preview_input *in, const pv_textures *t, double x,
                     double y, const brdffit_image_options *o, char *msg, size_t msg_size);

/* The cost per iteration in the rectangle. */
void pv_cost_plot(cairo_t *cr, const cli_preview_input *in, double x, double y, double w,
                  double h);
/* Measured and model values against the half-angle theta_h, in the
 * rectangle. 0, or -1 with a message. */
int pv_half_angle_plot(cairo_t *cr, const cli_preview_input *in, double x, double y, double w,
                       double h, char *msg, size_t msg_size);

#endif /* BRDFFIT_CLI_PREVIEW_H */
