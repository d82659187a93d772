/* Options of the picture functions, colour encoding and buffer helpers. */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "core/core.h"
#include "image/image_internal.h"

/* The size of the first version of the options struct (frozen: fields are
 * only appended). A caller built against a newer header passes a larger
 * size; the fields this library does not know are ignored. */
#define BF_IMAGE_OPTIONS_V1_SIZE (offsetof(brdffit_image_options, log_y) + sizeof(int))

void brdffit_image_options_init(brdffit_image_options *opts)
{
    const brdffit_image_options init = BRDFFIT_IMAGE_OPTIONS_INIT;
    if (opts != NULL) *opts = init;
}

static int finite_nonneg(double x)
{
    return isfinite(x) && x >= 0.0;
}

static brdffit_status check_gains(const brdffit_image_options *o, brdffit_error *err)
{
    const brdffit_status bad = BRDFFIT_E_INVALID_ARGUMENT;
    if (!finite_nonneg(o->gain))
        return bf_fail(err, bad, "image option gain must be finite and >= 0 (got %g)", o->gain);
    if (!finite_nonneg(o->difference_gain))
        return bf_fail(err, bad, "image option difference_gain must be finite and >= 0 (got %g)",
                       o->difference_gain);
    if (!finite_nonneg(o->exposure))
        return bf_fail(err, bad, "image option exposure must be finite and >= 0 (got %g)",
                       o->exposure);
    if (!(o->gamma >= 0.1 && o->gamma <= 10.0))
        return bf_fail(err, bad, "image option gamma must lie in [0.1, 10] (got %g)", o->gamma);
    return BRDFFIT_OK;
}

static brdffit_status check_layout(const brdffit_image_options *o, brdffit_error *err)
{
    const brdffit_status bad = BRDFFIT_E_INVALID_ARGUMENT;
    if (o->scale < 1 || o->scale > 64)
        return bf_fail(err, bad, "image option scale must lie in [1, 64] (got %zu)", o->scale);
    if (o->block_columns < 1) return bf_fail(err, bad, "image option block_columns must be >= 1");
    if (o->block_gap > 64)
        return bf_fail(err, bad, "image option block_gap must lie in [0, 64] (got %zu)",
                       o->block_gap);
    return BRDFFIT_OK;
}

brdffit_status bf_image_options(brdffit_image_options *out, const brdffit_image_options *in,
                                brdffit_error *err)
{
    brdffit_image_options_init(out);
    if (in == NULL) return BRDFFIT_OK;
    if (in->struct_size < BF_IMAGE_OPTIONS_V1_SIZE)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT,
                       "image options: struct_size %zu is too small (at least %zu); initialise "
                       "with BRDFFIT_IMAGE_OPTIONS_INIT",
                       in->struct_size, (size_t)BF_IMAGE_OPTIONS_V1_SIZE);
    /* Only the fields both sides know; a later field the caller's struct
     * lacks keeps its default. */
    memcpy(out, in, in->struct_size < sizeof *out ? in->struct_size : sizeof *out);
    out->struct_size = sizeof *out;
    BF_RETURN_IF_ERROR(check_gains(out, err));
    return check_layout(out, err);
}

brdffit_status bf_image_check_buffer(const unsigned char *pixels, size_t stride, size_t width,
                                     size_t height, size_t min_side, brdffit_error *err)
{
    if (pixels == NULL) return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "pixels is NULL");
    if (width < min_side || height < min_side)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT,
                       "picture size %zu x %zu is below the minimum %zu x %zu", width, height,
                       min_side, min_side);
    if (width > BRDFFIT_IMAGE_MAX_SIZE || height > BRDFFIT_IMAGE_MAX_SIZE)
        return bf_fail(err, BRDFFIT_E_TOO_LARGE, "picture size %zu x %zu exceeds %d pixels", width,
                       height, BRDFFIT_IMAGE_MAX_SIZE);
    if (stride < 3 * width)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "stride %zu is below 3 * width = %zu bytes",
                       stride, 3 * width);
    return BRDFFIT_OK;
}

unsigned char bf_image_encode(double v, double gamma)
{
    double x;
    if (!(v > 0.0)) return 0; /* also NaN */
    if (v >= 1.0) return 255;
    x = gamma == 1.0 ? v : pow(v, 1.0 / gamma);
    return (unsigned char)floor(255.0 * x + 0.5);
}

void bf_image_channels_to_rgb(const double *v, size_t n, size_t step, double rgb[3])
{
    double sum = 0.0;
    size_t c;
    if (n == 3) {
        for (c = 0; c < 3; c++) rgb[c] = v[c * step];
        return;
    }
    for (c = 0; c < n; c++) sum += v[c * step];
    rgb[0] = rgb[1] = rgb[2] = n > 0 ? sum / (double)n : 0.0;
}

void bf_image_encode_rgb(const double rgb[3], double gain, double gamma, unsigned char out[3])
{
    size_t c;
    for (c = 0; c < 3; c++) out[c] = bf_image_encode(gain * rgb[c], gamma);
}

void bf_image_fill(unsigned char *pixels, size_t stride, size_t x, size_t y, size_t w, size_t h,
                   const unsigned char rgb[3])
{
    size_t r, i;
    for (r = 0; r < h; r++) {
        unsigned char *p = pixels + (y + r) * stride + 3 * x;
        for (i = 0; i < w; i++, p += 3) memcpy(p, rgb, 3);
    }
}
