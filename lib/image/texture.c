/* The texture of a regular grid (docs/definitions.md, Textures): one block per theta_i,
 * one row per theta_o, one column per signed view azimuth (the stored
 * quarter sphere mirrored); measured values, model values or their
 * difference. */
#include <string.h>

#include "core/core.h"
#include "image/image_internal.h"

/* Samples whose model values are computed in one call. */
#define BF_TEXTURE_CHUNK 512

typedef struct tex_layout {
    size_t n_ti, n_to, n_po; /* axis lengths */
    size_t shared;           /* 1 when the first azimuth is 0 (its column is shared) */
    size_t block_w, block_h; /* block size in pixels */
    size_t cols;             /* blocks per row of blocks */
    size_t scale, gap;
    size_t width, height;
} tex_layout;

static brdffit_status check_regular(const brdffit_grid *grid, brdffit_error *err)
{
    brdffit_grid_kind kind;
    if (grid == NULL) return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "grid is NULL");
    kind = brdffit_grid_get_kind(grid);
    if (kind == 0) return bf_fail(err, BRDFFIT_E_BAD_HANDLE, "grid handle is invalid or destroyed");
    if (kind != BRDFFIT_GRID_REGULAR)
        return bf_fail(err, BRDFFIT_E_UNSUPPORTED, "a texture needs a regular grid");
    return BRDFFIT_OK;
}

/* n blocks of size px with gap pixels between them; 0 on overflow. */
static int span(size_t n, size_t px, size_t gap, size_t *out)
{
    size_t a, b;
    return bf_mul_size(n, px, &a) && bf_mul_size(n - 1, gap, &b) && bf_add_size(a, b, out);
}

static brdffit_status compute_layout(tex_layout *t, const brdffit_grid *grid,
                                     const brdffit_image_options *o, brdffit_error *err)
{
    const double *polar, *phi;
    size_t rows, w_samples;
    BF_RETURN_IF_ERROR(check_regular(grid, err));
    (void)brdffit_grid_axis(grid, BRDFFIT_AXIS_THETA_I, &polar, &t->n_ti);
    (void)brdffit_grid_axis(grid, BRDFFIT_AXIS_THETA_O, &polar, &t->n_to);
    (void)brdffit_grid_axis(grid, BRDFFIT_AXIS_PHI_O, &phi, &t->n_po);
    t->shared = phi[0] == 0.0 ? 1 : 0;
    t->scale = o->scale;
    t->gap = o->block_gap;
    t->cols = o->block_columns < t->n_ti ? o->block_columns : t->n_ti;
    rows = (t->n_ti + t->cols - 1) / t->cols;
    w_samples = 2 * t->n_po - t->shared; /* n_po is far below SIZE_MAX / 2 */
    if (!bf_mul_size(w_samples, t->scale, &t->block_w) ||
        !bf_mul_size(t->n_to, t->scale, &t->block_h) ||
        !span(t->cols, t->block_w, t->gap, &t->width) ||
        !span(rows, t->block_h, t->gap, &t->height) || t->width > BRDFFIT_IMAGE_MAX_SIZE ||
        t->height > BRDFFIT_IMAGE_MAX_SIZE)
        return bf_fail(err, BRDFFIT_E_TOO_LARGE, "the texture would exceed %d pixels a side",
                       BRDFFIT_IMAGE_MAX_SIZE);
    return BRDFFIT_OK;
}

brdffit_status brdffit_image_texture_size(const brdffit_grid *grid,
                                          const brdffit_image_options *opts, size_t *width,
                                          size_t *height, brdffit_error *err)
{
    brdffit_image_options o;
    tex_layout t;
    if (width == NULL || height == NULL)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "width or height is NULL");
    BF_RETURN_IF_ERROR(bf_image_options(&o, opts, err));
    BF_RETURN_IF_ERROR(compute_layout(&t, grid, &o, err));
    *width = t.width;
    *height = t.height;
    return BRDFFIT_OK;
}

/* --- painting ------------------------------------------------------------------ */

typedef struct tex_job {
    const tex_layout *t;
    const brdffit_image_options *o;
    brdffit_texture_kind kind;
    const brdffit_grid *grid;
    size_t n_channels;
    unsigned char *pixels;
    size_t stride;
    double *measured; /* n_channels values of the current sample */
} tex_job;

/* Paint sample s (both mirrored columns) in one colour. */
static void paint_sample(const tex_job *job, size_t s, const unsigned char rgb[3])
{
    const tex_layout *t = job->t;
    size_t k = s % t->n_po, j = (s / t->n_po) % t->n_to, i = s / (t->n_po * t->n_to);
    size_t x0 = (i % t->cols) * (t->block_w + t->gap);
    size_t y = (i / t->cols) * (t->block_h + t->gap) + j * t->scale;
    size_t c_minus = t->n_po - 1 - k, c_plus = t->n_po - t->shared + k;
    bf_image_fill(job->pixels, job->stride, x0 + c_minus * t->scale, y, t->scale, t->scale, rgb);
    if (c_plus != c_minus)
        bf_image_fill(job->pixels, job->stride, x0 + c_plus * t->scale, y, t->scale, t->scale, rgb);
}

/* Read the measured values of sample s; 0 when any channel is missing. */
static int read_measured(const tex_job *job, size_t s)
{
    size_t c;
    for (c = 0; c < job->n_channels; c++) {
        const double *v;
        if (brdffit_grid_is_missing(job->grid, s, c)) return 0;
        (void)brdffit_grid_values(job->grid, c, &v);
        job->measured[c] = v[s];
    }
    return 1;
}

static void difference_colour(const double *m, size_t step, const double *r, size_t n,
                              const brdffit_image_options *o, unsigned char out[3])
{
    double d = 0.0;
    size_t c;
    for (c = 0; c < n; c++) d += m[c * step] - r[c];
    d = o->difference_gain * d / (double)n;
    out[0] = d > 0.0 ? bf_image_encode(d, o->gamma) : 0;
    out[1] = 0;
    out[2] = d < 0.0 ? bf_image_encode(-d, o->gamma) : 0;
}

/* The colour of sample s; model holds its model values at model[c * step]
 * (NULL for the measured texture). */
static void sample_colour(const tex_job *job, size_t s, const double *model, size_t step,
                          unsigned char out[3])
{
    double rgb[3];
    int present = job->kind == BRDFFIT_TEXTURE_MODEL || read_measured(job, s);
    if (!present) {
        memcpy(out, job->o->missing, 3);
        return;
    }
    if (job->kind == BRDFFIT_TEXTURE_DIFFERENCE) {
        difference_colour(model, step, job->measured, job->n_channels, job->o, out);
        return;
    }
    if (job->kind == BRDFFIT_TEXTURE_MODEL)
        bf_image_channels_to_rgb(model, job->n_channels, step, rgb);
    else
        bf_image_channels_to_rgb(job->measured, job->n_channels, 1, rgb);
    bf_image_encode_rgb(rgb, job->o->gain, job->o->gamma, out);
}

static brdffit_status paint_with_model(const tex_job *job, const brdffit_model *model,
                                       const double *params, double *scratch, brdffit_error *err)
{
    size_t n = brdffit_grid_sample_count(job->grid), first, s;
    for (first = 0; first < n; first += BF_TEXTURE_CHUNK) {
        size_t count = n - first < BF_TEXTURE_CHUNK ? n - first : BF_TEXTURE_CHUNK;
        BF_RETURN_IF_ERROR(
            brdffit_model_eval_grid(model, job->grid, first, count, params, scratch, NULL, err));
        for (s = 0; s < count; s++) {
            unsigned char rgb[3];
            sample_colour(job, first + s, scratch + s, count, rgb);
            paint_sample(job, first + s, rgb);
        }
    }
    return BRDFFIT_OK;
}

static void paint_measured(const tex_job *job)
{
    size_t n = brdffit_grid_sample_count(job->grid), s;
    for (s = 0; s < n; s++) {
        unsigned char rgb[3];
        sample_colour(job, s, NULL, 0, rgb);
        paint_sample(job, s, rgb);
    }
}

static brdffit_status check_texture_args(brdffit_texture_kind kind, const brdffit_model *model,
                                         const double *params, brdffit_error *err)
{
    if (kind != BRDFFIT_TEXTURE_MEASURED && kind != BRDFFIT_TEXTURE_MODEL &&
        kind != BRDFFIT_TEXTURE_DIFFERENCE)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "unknown texture kind %d", (int)kind);
    if (kind != BRDFFIT_TEXTURE_MEASURED && (model == NULL || params == NULL))
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT,
                       "model and params are needed for a model or difference texture");
    return BRDFFIT_OK;
}

/* Scratch: the current sample's measured values, then one chunk of model
 * values. */
static double *alloc_scratch(const brdffit_allocator *a, size_t n_channels, int with_model)
{
    size_t n = n_channels;
    if (with_model && !bf_add_size(n, (size_t)BF_TEXTURE_CHUNK * n_channels, &n)) return NULL;
    return bf_calloc(a, n, sizeof(double));
}

brdffit_status brdffit_image_texture(unsigned char *pixels, size_t stride,
                                     brdffit_texture_kind kind, const brdffit_grid *grid,
                                     const brdffit_model *model, const double *params,
                                     const brdffit_image_options *opts,
                                     const brdffit_allocator *alloc, brdffit_error *err)
{
    brdffit_image_options o;
    brdffit_allocator a;
    tex_layout t;
    tex_job job;
    brdffit_status st = BRDFFIT_OK;
    int with_model = kind != BRDFFIT_TEXTURE_MEASURED;
    BF_RETURN_IF_ERROR(check_texture_args(kind, model, params, err));
    BF_RETURN_IF_ERROR(bf_image_options(&o, opts, err));
    if (!bf_alloc_init(&a, alloc))
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "allocator lacks alloc or free");
    BF_RETURN_IF_ERROR(compute_layout(&t, grid, &o, err));
    BF_RETURN_IF_ERROR(bf_image_check_buffer(pixels, stride, t.width, t.height, 1, err));
    job.t = &t;
    job.o = &o;
    job.kind = kind;
    job.grid = grid;
    job.n_channels = brdffit_grid_channel_count(grid);
    job.pixels = pixels;
    job.stride = stride;
    job.measured = alloc_scratch(&a, job.n_channels, with_model);
    if (job.measured == NULL)
        return bf_fail(err, BRDFFIT_E_OUT_OF_MEMORY, "out of memory rendering a texture");
    bf_image_fill(pixels, stride, 0, 0, t.width, t.height, o.background);
    if (with_model)
        st = paint_with_model(&job, model, params, job.measured + job.n_channels, err);
    else
        paint_measured(&job);
    bf_free(&a, job.measured);
    return st;
}
