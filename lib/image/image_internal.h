/* Internal helpers of the picture functions: resolved options, colour
 * encoding, buffer checks and rectangle filling. Not installed. */
#ifndef BRDFFIT_IMAGE_INTERNAL_H
#define BRDFFIT_IMAGE_INTERNAL_H

#include <stddef.h>

#include "brdffit/image.h"

/* Copy the caller's options (or the defaults for NULL) into *out and check
 * every field. */
brdffit_status bf_image_options(brdffit_image_options *out, const brdffit_image_options *in,
                                brdffit_error *err);

/* Check a picture's pixel buffer, size and stride. min_side is the
 * smallest width and height accepted. */
brdffit_status bf_image_check_buffer(const unsigned char *pixels, size_t stride, size_t width,
                                     size_t height, size_t min_side, brdffit_error *err);

/* Encode a linear value as a byte: round(255 * clamp(v, 0, 1)^(1/gamma)). */
unsigned char bf_image_encode(double v, double gamma);

/* Map n channel values (v[c * step]) to linear red, green, blue: three
 * channels as they are, any other count as grey (the mean). */
void bf_image_channels_to_rgb(const double *v, size_t n, size_t step, double rgb[3]);

/* Encode a linear colour times gain into out[3]. */
void bf_image_encode_rgb(const double rgb[3], double gain, double gamma, unsigned char out[3]);

/* Fill a w x h rectangle at (x, y) with one colour. */
void bf_image_fill(unsigned char *pixels, size_t stride, size_t x, size_t y, size_t w, size_t h,
                   const unsigned char rgb[3]);

#endif /* BRDFFIT_IMAGE_INTERNAL_H */
