/* The --preview picture (docs/cli.md), drawn with cairo: a title and the
 * fit's figures; on the left the measured, difference and model textures
 * of a regular grid with their axes and colour scales (preview_tex.c), or
 * for a scattered measurement its values against the half-angle; on the
 * right spheres lit at 0, 30 and 60 deg (measured above, model below), the
 * cost per iteration and, for a regular grid, the values against the
 * half-angle (preview_plot.c). The library renders the pixels of textures
 * and spheres (image.h); text, axes and legends are cairo's. */
#include <stdlib.h>
#include <string.h>

#include "preview.h"

#if defined(BRDFFIT_CLI_FONTCONFIG)
#include <fontconfig/fontconfig.h>
#endif

#define SPHERE 150
#define RIGHT_W (3.0 * SPHERE + 2.0 * PV_GAP)
#define LABEL 18.0
#define HEAD 54.0
#define COST_H 240.0
#define HALF_H 300.0
#define SCATTER_W 720.0
#define SCATTER_H 540.0

static const double light_deg[3] = {0.0, 30.0, 60.0};

typedef struct page {
    int regular;
    pv_textures tex;
    double left_w, left_h, right_x, width, height;
} page;

int cli_png_available(void)
{
    return 1;
}

void cli_preview_cleanup(void)
{
    cairo_debug_reset_static_data();
#if defined(BRDFFIT_CLI_FONTCONFIG)
    FcFini();
#endif
}

static brdffit_image_options base_options(const cli_preview_input *in)
{
    brdffit_image_options o = BRDFFIT_IMAGE_OPTIONS_INIT;
    o.gain = in->gain;
    o.difference_gain = in->gain;
    o.exposure = PV_PI * in->gain / 3.0;
    o.gamma = in->gamma;
    return o;
}

static double right_height(const page *p)
{
    double rows = p->regular ? 2.0 : 1.0;
    return rows * (LABEL + SPHERE + PV_GAP) + COST_H + PV_GAP + (p->regular ? HALF_H : 40.0);
}

static int compute_page(const cli_preview_input *in, page *p, char *msg, size_t msg_size)
{
    double right_h;
    p->regular = brdffit_grid_get_kind(in->grid) == BRDFFIT_GRID_REGULAR;
    if (p->regular) {
        if (pv_textures_layout(in->grid, &p->tex, msg, msg_size) != 0) return -1;
        p->left_w = p->tex.width;
        p->left_h = p->tex.height;
    } else {
        p->left_w = SCATTER_W;
        p->left_h = SCATTER_H;
    }
    right_h = right_height(p);
    p->right_x = PV_GAP + p->left_w + PV_GAP;
    p->width = p->right_x + RIGHT_W + PV_GAP;
    p->height = HEAD + (p->left_h > right_h ? p->left_h : right_h) + PV_GAP;
    return 0;
}

/* The title (shrunk to fit the width) and a line with the figures. */
static void title(cairo_t *cr, const cli_preview_input *in, const page *p)
{
    char line[512];
    draw_grey(cr, 0.95);
    draw_text_fit(cr, PV_GAP, 8, DRAW_TITLE, 1, p->width - 2 * PV_GAP, in->title);
    cli_format(line, sizeof line,
               "e = %.4g (root of the summed squared differences)    E = %.4g (Ngan et al. "
               "error)    cost %.4g    cap %g\u00b0    gain %g, gamma %g",
               in->rms, in->ngan, in->cost, in->cap * 180.0 / PV_PI, in->gain, in->gamma);
    draw_grey(cr, 0.8);
    draw_text_fit(cr, PV_GAP, 30, DRAW_TEXT, 0, p->width - 2 * PV_GAP, line);
}

static int one_sphere(cairo_t *cr, const cli_preview_input *in, int measured, double theta,
                      double x, double y, const brdffit_image_options *o, brdffit_error *err)
{
    unsigned char *px = malloc(3 * SPHERE * SPHERE);
    brdffit_status st;
    if (px == NULL) {
        cli_format(err->message, sizeof err->message, "out of memory");
        return -1;
    }
    st = measured ? brdffit_image_sphere_measured(px, 3 * SPHERE, SPHERE, in->grid, theta, 0.0,
                                                  o, NULL, err)
                  : brdffit_image_sphere_model(px, 3 * SPHERE, SPHERE, in->model, in->params,
                                               brdffit_grid_channel_count(in->grid), theta, 0.0,
                                               o, NULL, err);
    if (st == BRDFFIT_OK) draw_pixels(cr, px, 3 * SPHERE, SPHERE, SPHERE, x, y, SPHERE, SPHERE);
    free(px);
    return st == BRDFFIT_OK ? 0 : -1;
}

static int spheres(cairo_t *cr, const cli_preview_input *in, const page *p,
                   const brdffit_image_options *o, brdffit_error *err)
{
    int row, k, rows = p->regular ? 2 : 1;
    for (row = 0; row < rows; row++) {
        int measured = p->regular && row == 0;
        double y = HEAD + row * (LABEL + SPHERE + PV_GAP);
        for (k = 0; k < 3; k++) {
            char text[64];
            double x = p->right_x + k * (SPHERE + PV_GAP);
            cli_format(text, sizeof text, "%s, light %g\u00b0", measured ? "measured" : "model",
                       light_deg[k]);
            draw_grey(cr, 0.9);
            draw_text(cr, x + SPHERE / 2.0, y, DRAW_TEXT, 0, 0.5, text);
            if (one_sphere(cr, in, measured, light_deg[k] * PV_PI / 180.0, x, y + LABEL, o,
                           err) != 0)
                return -1;
        }
    }
    return 0;
}

static int draw_page(cairo_t *cr, const cli_preview_input *in, const page *p, char *msg,
                     size_t msg_size)
{
    brdffit_image_options o = base_options(in);
    brdffit_error err;
    double y = HEAD + (p->regular ? 2.0 : 1.0) * (LABEL + SPHERE + PV_GAP);
    cairo_set_source_rgb(cr, 24 / 255.0, 24 / 255.0, 24 / 255.0);
    cairo_paint(cr);
    title(cr, in, p);
    if (p->regular &&
        pv_textures_draw(cr, in, &p->tex, PV_GAP, HEAD, &o, msg, msg_size) != 0)
        return -1;
    if (!p->regular && pv_half_angle_plot(cr, in, PV_GAP, HEAD, SCATTER_W, SCATTER_H, msg,
                                          msg_size) != 0)
        return -1;
    if (spheres(cr, in, p, &o, &err) != 0) {
        cli_format(msg, msg_size, "%s", err.message);
        return -1;
    }
    pv_cost_plot(cr, in, p->right_x, y, RIGHT_W, COST_H);
    if (!p->regular) {
        draw_grey(cr, 0.7);
        draw_text(cr, p->right_x, y + COST_H + 4, DRAW_TEXT, 0, 0.0,
                  "scattered samples: no textures and no measured spheres (both need a");
        draw_text(cr, p->right_x, y + COST_H + 20, DRAW_TEXT, 0, 0.0,
                  "regular grid); the plot on the left shows every measured value");
    }
    if (p->regular && pv_half_angle_plot(cr, in, p->right_x, y + COST_H + PV_GAP, RIGHT_W,
                                         HALF_H - PV_GAP, msg, msg_size) != 0)
        return -1;
    return 0;
}

/* The drawn page, or NULL with a message. */
static cairo_surface_t *render(const cli_preview_input *in, char *msg, size_t msg_size)
{
    page p;
    cairo_surface_t *s;
    cairo_t *cr;
    int rc;
    if (compute_page(in, &p, msg, msg_size) != 0) return NULL;
    s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, (int)p.width, (int)p.height);
    cr = cairo_create(s);
    if (cairo_status(cr) != CAIRO_STATUS_SUCCESS) {
        cli_format(msg, msg_size, "cairo: %s", cairo_status_to_string(cairo_status(cr)));
        rc = -1;
    } else
        rc = draw_page(cr, in, &p, msg, msg_size);
    cairo_destroy(cr);
    if (rc == 0) {
        cairo_surface_flush(s);
        return s;
    }
    cairo_surface_destroy(s);
    return NULL;
}

int cli_preview_write(const cli_preview_input *in, const char *path, char *msg,
                      size_t msg_size)
{
    cairo_surface_t *s = render(in, msg, msg_size);
    int rc = s != NULL ? draw_write_png(s, path, msg, msg_size) : -1;
    cairo_surface_destroy(s);
    return rc;
}

int cli_preview_png(const cli_preview_input *in, cli_buf *out, char *msg, size_t msg_size)
{
    cairo_surface_t *s = render(in, msg, msg_size);
    int rc = s != NULL ? draw_png_bytes(s, out) : -1;
    if (s != NULL && rc != 0) cli_format(msg, msg_size, "out of memory");
    cairo_surface_destroy(s);
    return rc;
}
