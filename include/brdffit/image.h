/**
 * @file image.h
 * @brief Pictures of a measurement and of a fit (docs/definitions.md, Textures), rendered
 *        into caller-owned 8-bit RGB buffers: the texture of a regular grid
 *        (measured values, model values, their difference), a sphere lit by
 *        a point light, and a line plot of a series such as the cost per
 *        iteration.
 *
 * Nothing here reads or writes files; writing a picture to disk is the
 * caller's business (the `brdffit` command writes PNG).
 *
 * Pixel buffers are row-major, top row first, 3 bytes per pixel in the
 * order red, green, blue; consecutive rows start @p stride bytes apart
 * (stride >= 3 * width). A function writes exactly the width x height
 * pixels of its picture and leaves any padding between rows alone. The
 * caller owns the buffer; a function never keeps a pointer to it. After a
 * failure the buffer contents are unspecified.
 *
 * Colour encoding: a linear value v becomes the byte
 * round(255 * min(max(v, 0), 1)^(1 / gamma)); gamma is an option (2.2 by
 * default, 1 leaves values linear). Which linear value a picture shows is
 * said with each function.
 *
 * Channels map to colours as follows: 3 channels are red, green and blue;
 * any other count (1 channel, 2 channels, spectral data) is shown as grey,
 * the mean over all channels.
 *
 * Every function is thread-safe: it only reads its inputs, and several
 * threads may render from the same grid and model at once. Functions that
 * take an allocator use it for temporary memory only and free it before
 * they return.
 */
#ifndef BRDFFIT_IMAGE_H
#define BRDFFIT_IMAGE_H

#include <stddef.h>

#include "brdffit/alloc.h"
#include "brdffit/export.h"
#include "brdffit/grid.h"
#include "brdffit/model.h"
#include "brdffit/status.h"

/** @defgroup image Pictures
 * @{ */

/**
 * @brief Options of every picture. A versioned struct: initialise it with
 *        ::BRDFFIT_IMAGE_OPTIONS_INIT or brdffit_image_options_init(), then
 *        change fields. Fields are only ever appended; @c struct_size tells
 *        the library which exist.
 *
 * The library accepts any @c struct_size from the size of the first version
 * (everything up to and including @c log_y) upwards: a program built
 * against a newer header passes a larger struct, whose fields unknown to
 * this library are ignored; fields the caller's size does not cover keep
 * their defaults. A smaller size is refused with
 * ::BRDFFIT_E_INVALID_ARGUMENT.
 *
 * Each field says which pictures use it; the others ignore it. Passing
 * NULL instead of options selects the defaults.
 */
typedef struct brdffit_image_options {
    /** sizeof(brdffit_image_options) of the caller's header. */
    size_t struct_size;
    /** Textures: measured and model values are multiplied by it before
     *  encoding; finite, >= 0; default 3. */
    double gain;
    /** Difference texture: the difference is multiplied by it; finite,
     *  >= 0; default 3 (the scale of the other textures). */
    double difference_gain;
    /** Spheres: radiance multiplier (light intensity times exposure);
     *  finite, >= 0; default pi, so a white Lambertian surface (cd = 1)
     *  lit head-on shows full white. */
    double exposure;
    /** Textures and spheres: encoding gamma, 0.1 .. 10; default 2.2. */
    double gamma;
    /** Sphere surroundings, gaps between texture blocks, plot background;
     *  default (48, 48, 48). */
    unsigned char background[3];
    /** Missing measured values in textures and spheres; default
     *  (255, 0, 255). */
    unsigned char missing[3];
    /** Plot axes and tick marks; default (200, 200, 200). */
    unsigned char foreground[3];
    /** Plot curve; default (255, 190, 40). */
    unsigned char curve[3];
    /** Textures: every sample becomes a scale x scale square of pixels,
     *  1 .. 64; default 1. */
    size_t scale;
    /** Textures: theta_i blocks per row of blocks, >= 1; default 1 (all
     *  blocks stacked top to bottom). */
    size_t block_columns;
    /** Textures: background pixels between blocks, 0 .. 64; default 0. */
    size_t block_gap;
    /** Plot: non-zero for a log10 y axis; default 0. */
    int log_y;
} brdffit_image_options;

/** @brief Static initialiser of ::brdffit_image_options with the defaults. */
#define BRDFFIT_IMAGE_OPTIONS_INIT                                                          \
    {                                                                                       \
        sizeof(brdffit_image_options), 3.0, 3.0, 3.14159265358979323846, 2.2, {48, 48, 48}, \
            {255, 0, 255}, {200, 200, 200}, {255, 190, 40}, 1, 1, 0, 0                      \
    }

/** @brief What a texture shows. Values are fixed forever. */
typedef enum brdffit_texture_kind {
    BRDFFIT_TEXTURE_MEASURED = 0,  /**< The grid's values times the gain. */
    BRDFFIT_TEXTURE_MODEL = 1,     /**< The model at the grid's samples, times the gain. */
    BRDFFIT_TEXTURE_DIFFERENCE = 2 /**< Model minus measured, signed, times the difference gain. */
} brdffit_texture_kind;

/** @brief Largest width or height of any picture, in pixels. */
#define BRDFFIT_IMAGE_MAX_SIZE 32768

#ifdef __cplusplus
extern "C" {
#endif

/**
 * @brief Fill @p opts with the defaults of ::BRDFFIT_IMAGE_OPTIONS_INIT.
 *        NULL is a no-op. Thread-safe.
 */
BRDFFIT_API void brdffit_image_options_init(brdffit_image_options *opts);

/**
 * @brief The size of the texture of a regular grid.
 *
 * One block per theta_i; inside a block one pixel row per theta_o (the
 * first, usually 0 deg, at the top) and one pixel column per signed view
 * azimuth: the stored azimuths phi_o mirrored to show the whole
 * hemisphere, from -phi_o[last] at the left through the mirror direction
 * phi_o = 0 in the middle to +phi_o[last] at the right. When the first
 * azimuth is 0 its column is shared by both halves, so a block is
 * 2 n_phi_o - 1 columns wide, otherwise 2 n_phi_o. Blocks are laid out in
 * rows of @c block_columns blocks (theta_i ascending, left to right, then
 * top to bottom), @c block_gap background pixels apart, and every sample
 * is a @c scale x @c scale square.
 *
 * @param grid        A regular grid.
 * @param opts        Options, or NULL for the defaults.
 * @param[out] width  Receives the width in pixels.
 * @param[out] height Receives the height in pixels.
 * @param[out] err    NULL, or the detail on failure.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT for NULL arguments or
 *         bad options; ::BRDFFIT_E_BAD_HANDLE for a destroyed grid;
 *         ::BRDFFIT_E_UNSUPPORTED for a scattered grid;
 *         ::BRDFFIT_E_TOO_LARGE when a side would exceed
 *         ::BRDFFIT_IMAGE_MAX_SIZE. Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_image_texture_size(const brdffit_grid *grid,
                                                      const brdffit_image_options *opts,
                                                      size_t *width, size_t *height,
                                                      brdffit_error *err);

/**
 * @brief Render the texture of a regular grid (layout: see
 *        brdffit_image_texture_size()).
 *
 * - ::BRDFFIT_TEXTURE_MEASURED shows gain * value per channel (mapped to
 *   colours as in the file comment). A sample with any channel missing is
 *   drawn in the @c missing colour.
 * - ::BRDFFIT_TEXTURE_MODEL shows gain * model value at every sample of the
 *   grid (missing or not).
 * - ::BRDFFIT_TEXTURE_DIFFERENCE shows d = difference_gain * the mean over
 *   channels of (model - measured): red with intensity d where the model
 *   lies above the measurement, blue with intensity -d where below, black
 *   where they agree; samples with a missing channel in the @c missing
 *   colour.
 *
 * @param[out] pixels Buffer of at least (height - 1) * stride + 3 * width
 *                    bytes, sizes from brdffit_image_texture_size() with
 *                    the same options (caller-owned).
 * @param stride      Bytes from one row to the next, >= 3 * width.
 * @param kind        What to show.
 * @param grid        A regular grid.
 * @param model       The model; ignored (may be NULL) for
 *                    ::BRDFFIT_TEXTURE_MEASURED. Its channel count is the
 *                    grid's.
 * @param params      brdffit_model_vector_size(model, channels of the grid)
 *                    parameters; ignored for ::BRDFFIT_TEXTURE_MEASURED.
 * @param opts        Options, or NULL for the defaults.
 * @param alloc       Allocator for temporary memory, or NULL for malloc().
 * @param[out] err    NULL, or the detail on failure.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT for NULL arguments, an
 *         unknown kind, a short stride or bad options;
 *         ::BRDFFIT_E_BAD_HANDLE; ::BRDFFIT_E_UNSUPPORTED for a scattered
 *         grid; ::BRDFFIT_E_TOO_LARGE; ::BRDFFIT_E_OUT_OF_MEMORY; the
 *         model's failures (::BRDFFIT_E_MODEL_FAILED,
 *         ::BRDFFIT_E_NONFINITE). Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_image_texture(
    unsigned char *pixels, size_t stride, brdffit_texture_kind kind, const brdffit_grid *grid,
    const brdffit_model *model, const double *params, const brdffit_image_options *opts,
    const brdffit_allocator *alloc, brdffit_error *err);

/**
 * @brief Render a sphere with the measured BRDF of a regular grid, lit by a
 *        point light.
 *
 * The picture is @p size x @p size pixels. It shows a unit sphere in
 * orthographic view from +z: the pixel centre (x + 0.5, y + 0.5) maps to
 * u = (2x + 1) / size - 1 (right), w = 1 - (2y + 1) / size (up); pixels
 * with u^2 + w^2 > 1 show the @c background colour, the others the point
 * with normal n = (u, w, sqrt(1 - u^2 - w^2)). The viewer looks from
 * v = (0, 0, 1); the light comes from l = (sin(light_theta)
 * cos(light_phi), sin(light_theta) sin(light_phi), cos(light_theta)), so
 * light_theta = 0 lights the sphere from the viewer and light_phi = 0
 * from the right. At each point l and v are expressed in a tangent frame
 * around n (its orientation is arbitrary, which an isotropic BRDF does not
 * notice) and the pixel shows exposure * f(l, v) * max(n.l, 0) per channel,
 * f interpolated from the grid by brdffit_grid_eval(). Points where that
 * interpolation has no data (every neighbouring value of a channel
 * missing) show the @c missing colour.
 *
 * @param[out] pixels Buffer of at least (size - 1) * stride + 3 * size
 *                    bytes (caller-owned).
 * @param stride      Bytes from one row to the next, >= 3 * size.
 * @param size        Width and height, 1 .. ::BRDFFIT_IMAGE_MAX_SIZE.
 * @param grid        A regular grid.
 * @param light_theta Polar angle of the light from the view axis, radians,
 *                    0 .. pi.
 * @param light_phi   Azimuth of the light, radians, finite.
 * @param opts        Options, or NULL for the defaults.
 * @param alloc       Allocator for temporary memory, or NULL for malloc().
 * @param[out] err    NULL, or the detail on failure.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT for NULL arguments, a
 *         short stride, angles out of range or bad options;
 *         ::BRDFFIT_E_TOO_LARGE; ::BRDFFIT_E_BAD_HANDLE;
 *         ::BRDFFIT_E_UNSUPPORTED for a scattered grid;
 *         ::BRDFFIT_E_OUT_OF_MEMORY. Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_image_sphere_measured(unsigned char *pixels, size_t stride,
                                                         size_t size, const brdffit_grid *grid,
                                                         double light_theta, double light_phi,
                                                         const brdffit_image_options *opts,
                                                         const brdffit_allocator *alloc,
                                                         brdffit_error *err);

/**
 * @brief Render a sphere with a model BRDF, lit by a point light; as
 *        brdffit_image_sphere_measured() with f from
 *        brdffit_model_eval_angles().
 *
 * @param[out] pixels Buffer of at least (size - 1) * stride + 3 * size
 *                    bytes (caller-owned).
 * @param stride      Bytes from one row to the next, >= 3 * size.
 * @param size        Width and height, 1 .. ::BRDFFIT_IMAGE_MAX_SIZE.
 * @param model       The model.
 * @param params      brdffit_model_vector_size(model, n_channels) parameters.
 * @param n_channels  Channels to evaluate, >= 1.
 * @param light_theta Polar angle of the light from the view axis, radians,
 *                    0 .. pi.
 * @param light_phi   Azimuth of the light, radians, finite.
 * @param opts        Options, or NULL for the defaults.
 * @param alloc       Allocator for temporary memory, or NULL for malloc().
 * @param[out] err    NULL, or the detail on failure.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT for NULL arguments, a
 *         short stride, zero channels, angles out of range or bad options;
 *         ::BRDFFIT_E_TOO_LARGE; ::BRDFFIT_E_BAD_HANDLE;
 *         ::BRDFFIT_E_OUT_OF_MEMORY; the model's failures
 *         (::BRDFFIT_E_MODEL_FAILED, ::BRDFFIT_E_NONFINITE). Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_image_sphere_model(
    unsigned char *pixels, size_t stride, size_t size, const brdffit_model *model,
    const double *params, size_t n_channels, double light_theta, double light_phi,
    const brdffit_image_options *opts, const brdffit_allocator *alloc, brdffit_error *err);

/**
 * @brief Plot a series as a line (for example the cost per iteration from
 *        brdffit_fit_history()).
 *
 * The picture is filled with the @c background colour. The plot area is
 * inset by a margin of max(4, min(width, height) / 16) pixels; its left and
 * bottom edges are drawn as axes in the @c foreground colour, with tick
 * marks below the x axis at round steps of the index and left of the y
 * axis at round steps of the value (with @c log_y: at every power of 10).
 * Point i lies at x = i / (count - 1) of the plot area's width (a single
 * point in the middle); the y axis spans the smallest to the largest value
 * (a constant series lies in the middle), or with @c log_y the whole
 * decades around them: from 10^floor(log10 min) to 10^ceil(log10 max), at
 * least one decade, over the positive values; values <= 0 are drawn at
 * the bottom of a log axis.
 * Consecutive points are joined by straight lines 2 pixels wide in the
 * @c curve colour. No text is drawn. The gamma option does not apply.
 *
 * @param[out] pixels Buffer of at least (height - 1) * stride + 3 * width
 *                    bytes (caller-owned).
 * @param stride      Bytes from one row to the next, >= 3 * width.
 * @param width       Width, 16 .. ::BRDFFIT_IMAGE_MAX_SIZE.
 * @param height      Height, 16 .. ::BRDFFIT_IMAGE_MAX_SIZE.
 * @param values      The series (borrowed for the call); may be NULL when
 *                    @p count is 0, which draws the axes only.
 * @param count       Number of values.
 * @param opts        Options, or NULL for the defaults.
 * @param[out] err    NULL, or the detail on failure.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT for NULL arguments, a
 *         short stride, a size below 16 or bad options;
 *         ::BRDFFIT_E_TOO_LARGE for a size above ::BRDFFIT_IMAGE_MAX_SIZE;
 *         ::BRDFFIT_E_NONFINITE for a NaN or infinite value. Thread-safe;
 *         allocates nothing.
 */
BRDFFIT_API brdffit_status brdffit_image_plot(unsigned char *pixels, size_t stride, size_t width,
                                              size_t height, const double *values, size_t count,
                                              const brdffit_image_options *opts,
                                              brdffit_error *err);

#ifdef __cplusplus
}
#endif

/** @} */

#endif /* BRDFFIT_IMAGE_H */
