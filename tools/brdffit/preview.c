/* The --preview picture (docs/cli.md): a title line; measured, difference
 * and model textures side by side on the left; on the right spheres with
 * the measured BRDF (top row) and the fitted model (bottom row) under
 * light at 0, 30 and 60 deg, and the cost per iteration on a log scale.
 * Every panel has a label above it. Drawn with image.h. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

#define PI 3.14159265358979323846
#define GAP 8
#define LABEL_H (CLI_GLYPH_HEIGHT + 4)
#define SPHERE 140
#define PLOT_H 200
#define MAX_TEXTURE_H 1000

static const double light_deg[3] = {0.0, 30.0, 60.0};
static const unsigned char page[3] = {24, 24, 24};
static const unsigned char ink[3] = {220, 220, 220};

typedef struct layout {
    size_t tex_w, tex_h; /* one texture; 0 when the grid is scattered */
    size_t top;          /* first row below the title */
    size_t right_x;      /* left edge of the sphere and plot column */
    size_t width, height;
} layout;

typedef struct canvas {
    unsigned char *px;
    size_t stride, width, height;
} canvas;

static unsigned char *at(const canvas *c, size_t x, size_t y)
{
    return c->px + y * c->stride + 3 * x;
}

static void label(const canvas *c, size_t x, size_t y, const char *text)
{
    cli_draw_text(c->px, c->stride, c->width, c->height, x, y, text, ink);
}

static brdffit_image_options base_options(const cli_preview_input *in)
{
    brdffit_image_options o = BRDFFIT_IMAGE_OPTIONS_INIT;
    o.gain = in->gain;
    o.difference_gain = in->gain;
    o.exposure = PI * in->gain / 3.0;
    o.gamma = in->gamma;
    return o;
}

/* Texture options: blocks stacked, 1 pixel apart, wrapped into columns of
 * blocks when the stack would be taller than MAX_TEXTURE_H. */
static int texture_options(const cli_preview_input *in, brdffit_image_options *o, layout *l,
                           char *msg, size_t msg_size)
{
    brdffit_error err;
    o->block_gap = 1;
    l->tex_w = l->tex_h = 0;
    if (brdffit_grid_get_kind(in->grid) != BRDFFIT_GRID_REGULAR) return 0;
    if (brdffit_image_texture_size(in->grid, o, &l->tex_w, &l->tex_h, &err) == BRDFFIT_OK &&
        l->tex_h > MAX_TEXTURE_H) {
        o->block_columns = (l->tex_h + MAX_TEXTURE_H - 1) / MAX_TEXTURE_H;
        if (brdffit_image_texture_size(in->grid, o, &l->tex_w, &l->tex_h, &err) == BRDFFIT_OK)
            return 0;
    } else if (l->tex_w > 0)
        return 0;
    cli_format(msg, msg_size, "%s", err.message);
    return -1;
}

static void compute_layout(layout *l)
{
    size_t right_w = 3 * SPHERE + 2 * GAP;
    size_t right_h = 3 * LABEL_H + 2 * SPHERE + 2 * GAP + PLOT_H;
    size_t left_w = l->tex_w > 0 ? 3 * l->tex_w + 3 * GAP : 0;
    size_t left_h = l->tex_w > 0 ? LABEL_H + l->tex_h : 0;
    l->top = GAP + LABEL_H + GAP / 2;
    l->right_x = GAP + left_w;
    l->width = l->right_x + right_w + GAP;
    l->height = l->top + (left_h > right_h ? left_h : right_h) + GAP;
}

static int textures(const cli_preview_input *in, const canvas *c, const layout *l,
                    const brdffit_image_options *o, brdffit_error *err)
{
    static const brdffit_texture_kind kinds[3] = {
        BRDFFIT_TEXTURE_MEASURED, BRDFFIT_TEXTURE_DIFFERENCE, BRDFFIT_TEXTURE_MODEL};
    static const char *const names[3] = {"MEASURED", "DIFFERENCE", "MODEL"};
    size_t k;
    for (k = 0; k < 3 && l->tex_w > 0; k++) {
        size_t x = GAP + k * (l->tex_w + GAP);
        label(c, x, l->top, names[k]);
        if (brdffit_image_texture(at(c, x, l->top + LABEL_H), c->stride, kinds[k], in->grid,
                                  in->model, in->params, o, NULL, err) != BRDFFIT_OK)
            return -1;
    }
    return 0;
}

static int spheres(const cli_preview_input *in, const canvas *c, const layout *l,
                   const brdffit_image_options *o, brdffit_error *err)
{
    size_t k, nc = brdffit_grid_channel_count(in->grid);
    size_t y1 = l->top + LABEL_H, y2 = y1 + SPHERE + GAP + LABEL_H;
    int regular = brdffit_grid_get_kind(in->grid) == BRDFFIT_GRID_REGULAR;
    for (k = 0; k < 3; k++) {
        size_t x = l->right_x + k * (SPHERE + GAP);
        double theta = light_deg[k] * PI / 180.0;
        char text[64];
        cli_format(text, sizeof text, "%s, LIGHT %g DEG", regular ? "MEASURED" : "(NO GRID)",
                   light_deg[k]);
        label(c, x, y1 - LABEL_H, text);
        cli_format(text, sizeof text, "MODEL, LIGHT %g DEG", light_deg[k]);
        label(c, x, y2 - LABEL_H, text);
        if (regular && brdffit_image_sphere_measured(at(c, x, y1), c->stride, SPHERE, in->grid,
                                                     theta, 0.0, o, NULL, err) != BRDFFIT_OK)
            return -1;
        if (brdffit_image_sphere_model(at(c, x, y2), c->stride, SPHERE, in->model, in->params, nc,
                                       theta, 0.0, o, NULL, err) != BRDFFIT_OK)
            return -1;
    }
    return 0;
}

static void plot_label(const cli_preview_input *in, const canvas *c, size_t x, size_t y)
{
    double lo = 0.0, hi = 0.0;
    size_t i;
    char text[128];
    for (i = 0; i < in->n_history; i++) {
        if (i == 0 || in->history[i] < lo) lo = in->history[i];
        if (i == 0 || in->history[i] > hi) hi = in->history[i];
    }
    if (in->n_history == 0)
        cli_format(text, sizeof text, "COST PER ITERATION: NONE");
    else
        cli_format(text, sizeof text, "COST PER ITERATION (LOG): %.4E .. %.4E, %zu ITERATIONS", lo,
                   hi, in->n_history - 1);
    label(c, x, y, text);
}

static int plot(const cli_preview_input *in, const canvas *c, const layout *l,
                brdffit_image_options o, brdffit_error *err)
{
    size_t y = l->top + 2 * (LABEL_H + SPHERE + GAP);
    o.log_y = 1;
    plot_label(in, c, l->right_x, y);
    return brdffit_image_plot(at(c, l->right_x, y + LABEL_H), c->stride, 3 * SPHERE + 2 * GAP,
                              PLOT_H, in->history, in->n_history, &o, err) == BRDFFIT_OK
               ? 0
               : -1;
}

static void fill(const canvas *c, const unsigned char rgb[3])
{
    size_t x, y;
    for (y = 0; y < c->height; y++)
        for (x = 0; x < c->width; x++) memcpy(at(c, x, y), rgb, 3);
}

int cli_preview_render(const cli_preview_input *in, cli_picture *out, char *msg, size_t msg_size)
{
    brdffit_image_options o = base_options(in), tex = o;
    brdffit_error err;
    layout l;
    canvas c;
    out->pixels = NULL;
    if (texture_options(in, &tex, &l, msg, msg_size) != 0) return -1;
    compute_layout(&l);
    c.width = l.width;
    c.height = l.height;
    c.stride = 3 * l.width;
    if (l.height > SIZE_MAX / c.stride) {
        cli_format(msg, msg_size, "picture of %zu x %zu pixels too large", l.width, l.height);
        return -1;
    }
    c.px = malloc(c.stride * l.height);
    if (c.px == NULL) {
        cli_format(msg, msg_size, "out of memory");
        return -1;
    }
    fill(&c, page);
    label(&c, GAP, GAP, in->title);
    if (textures(in, &c, &l, &tex, &err) != 0 || spheres(in, &c, &l, &o, &err) != 0 ||
        plot(in, &c, &l, o, &err) != 0) {
        cli_format(msg, msg_size, "%s", err.message);
        free(c.px);
        return -1;
    }
    out->pixels = c.px;
    out->width = l.width;
    out->height = l.height;
    return 0;
}
