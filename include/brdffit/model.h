/**
 * @file model.h
 * @brief BRDF models: the pluggable model interface (value + Jacobian over a
 *        batch of samples) and the built-in models.
 *
 * A model maps a light/view pair and a parameter vector to one value per
 * channel, and gives the derivatives with respect to every parameter.
 *
 * Parameters are described by ::brdffit_param_info. A parameter is either
 * shared by all channels (shape parameters: exponents, roughness, Fresnel
 * coefficients) or has one value per channel (::BRDFFIT_PARAM_PER_CHANNEL,
 * colours). For n_channels channels the parameter vector holds, in the order
 * the parameters are declared, one entry per shared parameter and
 * n_channels consecutive entries per per-channel parameter
 * (brdffit_model_vector_index()).
 *
 * Models are evaluated over a batch of samples in structure-of-arrays form
 * (::brdffit_batch), never one sample per call.
 *
 * Handles: functions given a NULL model or grid return
 * ::BRDFFIT_E_INVALID_ARGUMENT; a non-NULL handle that is not a live model
 * (or grid) is detected where possible and gives ::BRDFFIT_E_BAD_HANDLE.
 *
 * The built-in models, their formulas as implemented, parameters, ranges,
 * defaults and flags are listed in docs/models.md. All built-in models
 * declare their shared shape parameters first, then their per-channel
 * colours; the colours are linear in every built-in model except "gltf" and
 * "gltf-clearcoat" (affine in their baseColor, see docs/models.md).
 *
 * A model handle is immutable: every function taking a const model is
 * thread-safe, provided the evaluation callback of a user model is.
 */
#ifndef BRDFFIT_MODEL_H
#define BRDFFIT_MODEL_H

#include <stddef.h>

#include "brdffit/alloc.h"
#include "brdffit/batch.h"
#include "brdffit/export.h"
#include "brdffit/grid.h"
#include "brdffit/status.h"

/** @defgroup model Models
 * @{ */

/** @brief Opaque, immutable model. */
typedef struct brdffit_model brdffit_model;

/** @brief Parameter flags. Values are fixed forever. */
typedef enum brdffit_param_flags {
    BRDFFIT_PARAM_PER_CHANNEL = 1, /**< One value per channel (else shared). */
    BRDFFIT_PARAM_LINEAR = 2,      /**< The model is linear in it (see ::brdffit_model_def). */
    BRDFFIT_PARAM_LOG_SCALE = 4,   /**< Natural scale is logarithmic (exponents, roughness). */
    BRDFFIT_PARAM_FIXED = 8        /**< Held at its start value unless a fit frees it. */
} brdffit_param_flags;

/**
 * @brief Metadata of one model parameter. The layout is fixed forever.
 *
 * lower <= start <= upper; bounds may be -HUGE_VAL / HUGE_VAL. A
 * ::BRDFFIT_PARAM_LOG_SCALE parameter needs lower > 0.
 */
typedef struct brdffit_param_info {
    const char *name; /**< Name, unique within the model, e.g. "ns". */
    unsigned flags;   /**< A combination of ::brdffit_param_flags. */
    double lower;     /**< Lower bound. */
    double upper;     /**< Upper bound. */
    double start;     /**< A sensible default start value. */
} brdffit_param_info;

/**
 * @brief Evaluate a model over a batch.
 *
 * @param batch      Geometry of the samples.
 * @param params     The parameter vector (layout in the file comment).
 * @param n_channels Number of channels.
 * @param[out] values n_channels * batch->n values; value of channel c at
 *                   sample s goes to values[c * batch->n + s].
 * @param[out] jacobian NULL when only values are wanted; otherwise
 *                   n_params * n_channels * batch->n derivatives: the
 *                   derivative of channel c's value at sample s with
 *                   respect to parameter k (its channel-c entry for a
 *                   per-channel parameter) goes to
 *                   jacobian[(k * n_channels + c) * batch->n + s]. A
 *                   per-channel parameter must not influence other channels.
 * @param user       The model's user pointer.
 * @return ::BRDFFIT_OK, or any error status (for example
 *         ::BRDFFIT_E_RANGE for a domain error); the library reports a
 *         failure as ::BRDFFIT_E_MODEL_FAILED and names the model and the
 *         returned status. A fit leaves out a point where the model fails
 *         (a rejected trial step, a skipped point of the auto pipeline's
 *         scan) and fails only when no point can be evaluated or the
 *         start point cannot.
 */
typedef brdffit_status (*brdffit_model_eval_fn)(const brdffit_batch *batch,
                                                const double *params, size_t n_channels,
                                                double *values, double *jacobian, void *user);

/**
 * @brief Definition of a user model: a versioned vtable.
 *
 * Initialise with ::BRDFFIT_MODEL_DEF_INIT (or brdffit_model_def_init())
 * and then set the fields; fields are only ever appended, and
 * @c struct_size tells the library which exist (it must cover at least
 * every field of this version; a larger size from a newer header is
 * accepted and the unknown fields are ignored).
 *
 * A parameter flagged ::BRDFFIT_PARAM_LINEAR must also be flagged
 * ::BRDFFIT_PARAM_PER_CHANNEL (brdffit_model_create_custom() rejects it
 * otherwise), and the model's value must be a sum of such parameters times
 * terms that depend only on the geometry and on the non-linear parameters
 * (so the value is the sum over linear parameters of parameter times
 * derivative). Fits use this to solve for those parameters exactly; the
 * library cannot verify it, so a wrong LINEAR flag gives wrong fits.
 *
 * Limits: 1 .. 1024 parameters with unique, non-empty names; no NaN
 * bounds; a finite start with lower <= start <= upper; only the flag bits
 * of ::brdffit_param_flags.
 */
typedef struct brdffit_model_def {
    size_t struct_size;              /**< sizeof(brdffit_model_def). */
    const char *name;                /**< Model name (copied). */
    size_t n_params;                 /**< Number of parameters, >= 1. */
    const brdffit_param_info *params; /**< n_params entries (copied, names too). */
    brdffit_model_eval_fn eval;      /**< The evaluation callback. */
    void *user;                      /**< Passed to @c eval, last. */
    void (*destroy)(void *user);     /**< NULL, or called with @c user when the model is destroyed. */
} brdffit_model_def;

/** @brief Static initialiser for ::brdffit_model_def. */
#define BRDFFIT_MODEL_DEF_INIT { sizeof(brdffit_model_def), NULL, 0, NULL, NULL, NULL, NULL }

/**
 * @brief Result of brdffit_model_check_jacobian(). New fields are only ever
 *        appended; set @c struct_size before the call.
 */
typedef struct brdffit_jacobian_report {
    size_t struct_size;   /**< sizeof(brdffit_jacobian_report). */
    double worst_error;   /**< Worst relative error found. */
    size_t param;         /**< Parameter index (declaration order) where it occurred. */
    size_t channel;       /**< Channel where it occurred. */
    size_t sample;        /**< Grid sample where it occurred. */
    double analytic;      /**< Analytic derivative there. */
    double numeric;       /**< Central-difference derivative there. */
} brdffit_jacobian_report;

#ifdef __cplusplus
extern "C" {
#endif

/**
 * @brief Fill @p def with the defaults of ::BRDFFIT_MODEL_DEF_INIT. NULL is
 *        a no-op. Thread-safe.
 */
BRDFFIT_API void brdffit_model_def_init(brdffit_model_def *def);

/** @brief Number of built-in models. Thread-safe. */
BRDFFIT_API size_t brdffit_model_builtin_count(void);

/**
 * @brief Name of built-in model @p index (0 .. brdffit_model_builtin_count() - 1).
 * @return A static string, or NULL when out of range. Thread-safe.
 */
BRDFFIT_API const char *brdffit_model_builtin_name(size_t index);

/**
 * @brief Create a built-in model by name ("ashikhmin-shirley", "ggx", ...).
 * @param[out] out Receives the model (owned by the caller, release it with
 *                 brdffit_model_destroy()); NULL on failure.
 * @param name     A name from brdffit_model_builtin_name() (exact,
 *                 case-sensitive).
 * @param alloc    Allocator, or NULL.
 * @param[out] err NULL, or the detail on failure.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_NOT_FOUND for an unknown name;
 *         ::BRDFFIT_E_INVALID_ARGUMENT; ::BRDFFIT_E_OUT_OF_MEMORY.
 *         Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_model_create(brdffit_model **out, const char *name,
                                                const brdffit_allocator *alloc,
                                                brdffit_error *err);

/**
 * @brief Create a model from a user definition. Everything in @p def is
 *        copied (the name and the parameter table with its names) except
 *        @c user, which the model keeps and hands to @c destroy when the
 *        model is destroyed. On failure @c destroy is not called and
 *        @c user stays the caller's.
 * @param[out] out Receives the model (owned by the caller); NULL on failure.
 * @param def      The definition (see ::brdffit_model_def for the rules).
 * @param alloc    Allocator for the model's whole life, or NULL.
 * @param[out] err NULL, or the detail on failure.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT for a NULL or
 *         inconsistent definition (struct size too small, no name, no or
 *         too many parameters, NULL params or eval, missing or duplicate
 *         parameter names, NaN bounds, a start outside its bounds or not
 *         finite, a log-scale parameter with lower <= 0, a linear parameter
 *         that is not per-channel, unknown flag bits) or an incomplete
 *         allocator; ::BRDFFIT_E_OUT_OF_MEMORY. Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_model_create_custom(brdffit_model **out,
                                                       const brdffit_model_def *def,
                                                       const brdffit_allocator *alloc,
                                                       brdffit_error *err);

/**
 * @brief Destroy a model; calls its destroy callback exactly once. NULL (or
 *        a handle that is not a live model) is a no-op.
 * @note Not thread-safe with respect to other uses of the same model.
 */
BRDFFIT_API void brdffit_model_destroy(brdffit_model *model);

/** @brief The model's name, owned by the model; NULL for NULL. Thread-safe. */
BRDFFIT_API const char *brdffit_model_name(const brdffit_model *model);

/** @brief Number of declared parameters; 0 for NULL. Thread-safe. */
BRDFFIT_API size_t brdffit_model_param_count(const brdffit_model *model);

/**
 * @brief Metadata of parameter @p index, owned by the model.
 * @return NULL when out of range. Thread-safe.
 */
BRDFFIT_API const brdffit_param_info *brdffit_model_param(const brdffit_model *model,
                                                          size_t index);

/**
 * @brief Find a parameter by name (exact, case-sensitive).
 * @return ::BRDFFIT_OK and its index in @p index (left untouched
 *         otherwise); ::BRDFFIT_E_NOT_FOUND; ::BRDFFIT_E_INVALID_ARGUMENT
 *         for NULL arguments; ::BRDFFIT_E_BAD_HANDLE. Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_model_param_find(const brdffit_model *model,
                                                    const char *name, size_t *index);

/**
 * @brief Length of the parameter vector for @p n_channels channels: one
 *        entry per shared parameter, n_channels per per-channel one.
 * @return The length; 0 for a NULL model, n_channels = 0 or overflow.
 *         Thread-safe.
 */
BRDFFIT_API size_t brdffit_model_vector_size(const brdffit_model *model, size_t n_channels);

/**
 * @brief Position of parameter @p param, channel @p channel, in the
 *        parameter vector. @p channel is ignored for shared parameters.
 *
 * The entries of the declared parameters follow one another in
 * declaration order; a per-channel parameter's channel c is at its first
 * entry + c.
 * @return The index, or (size_t)-1 on bad input (NULL model, n_channels =
 *         0, param out of range, or channel >= n_channels for a
 *         per-channel parameter). Thread-safe.
 */
BRDFFIT_API size_t brdffit_model_vector_index(const brdffit_model *model, size_t param,
                                              size_t channel, size_t n_channels);

/**
 * @brief Fill @p params with every parameter's default start value (every
 *        channel of a per-channel parameter gets the same value).
 * @param model      The model.
 * @param n_channels Number of channels, 1 or more.
 * @param[out] params brdffit_model_vector_size() doubles.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT;
 *         ::BRDFFIT_E_BAD_HANDLE. Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_model_default_params(const brdffit_model *model,
                                                        size_t n_channels, double *params);

/**
 * @brief Evaluate a model over grid samples [first, first + count).
 *
 * The grid's channel count is the model's; output layouts as in
 * ::brdffit_model_eval_fn with batch->n = @p count. The whole range is
 * handed to the model in one call, writing straight into the caller's
 * arrays; nothing is allocated. count = 0 does nothing.
 * @param model    The model.
 * @param grid     The grid whose samples' geometry is used.
 * @param first    First sample.
 * @param count    Number of samples; first + count <= the grid's sample count.
 * @param params   brdffit_model_vector_size() values for the grid's channels.
 * @param[out] values   count * n_channels doubles.
 * @param[out] jacobian NULL, or n_params * n_channels * count doubles.
 * @param[out] err NULL, or the detail on failure.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT (NULL, range outside
 *         the grid); ::BRDFFIT_E_BAD_HANDLE; ::BRDFFIT_E_MODEL_FAILED when
 *         the callback returned an error (the message names the model and
 *         the status it returned); ::BRDFFIT_E_NONFINITE when a parameter
 *         is NaN or infinite, or the model produced NaN or Inf (the message
 *         names the model, the grid sample, the channel and, for a
 *         derivative, the parameter); ::BRDFFIT_E_TOO_LARGE when the sizes
 *         overflow. Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_model_eval_grid(const brdffit_model *model,
                                                   const brdffit_grid *grid, size_t first,
                                                   size_t count, const double *params,
                                                   double *values, double *jacobian,
                                                   brdffit_error *err);

/**
 * @brief Evaluate a model at arbitrary directions (radians).
 *
 * Angle arrays hold @p count entries each (polar angles in [0, pi/2],
 * azimuths any finite value); layouts as in ::brdffit_model_eval_fn with
 * batch->n = @p count. The geometry of the batch is derived as for a grid
 * and allocated through the model's allocator for the duration of the call.
 * @param model         The model.
 * @param count         Number of direction pairs.
 * @param theta_i,phi_i Light directions.
 * @param theta_o,phi_o View directions.
 * @param n_channels    Number of channels, 1 or more.
 * @param params        brdffit_model_vector_size() values for n_channels.
 * @param[out] values   count * n_channels doubles.
 * @param[out] jacobian NULL, or n_params * n_channels * count doubles.
 * @param[out] err      NULL, or the detail on failure.
 * @return As brdffit_model_eval_grid() (sample numbers in messages are
 *         array indices); also ::BRDFFIT_E_RANGE for polar angles outside
 *         [0, pi/2] or non-finite angles; ::BRDFFIT_E_INVALID_ARGUMENT for
 *         n_channels = 0; ::BRDFFIT_E_OUT_OF_MEMORY. Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_model_eval_angles(const brdffit_model *model, size_t count,
                                                     const double *theta_i, const double *phi_i,
                                                     const double *theta_o, const double *phi_o,
                                                     size_t n_channels, const double *params,
                                                     double *values, double *jacobian,
                                                     brdffit_error *err);

/**
 * @brief Compare a model's analytic Jacobian with central differences over
 *        every sample of a grid at one parameter vector.
 *
 * The step for a parameter entry x is h = 1e-6 * max(|x|, 1e-3). The
 * numeric derivative is the central difference (f(x+h) - f(x-h)) / 2h
 * when x - h and x + h lie within the parameter's bounds; near a bound it
 * is the second-order one-sided difference on the side with room for two
 * steps, (-3 f(x) + 4 f(x+h) - f(x+2h)) / 2h or its mirror image, so the
 * model is never evaluated outside its bounds. Near DBL_MAX a stencil point
 * that would overflow counts as outside the bounds, and a stencil at whose
 * points the model's values overflow to infinity (while they are finite at
 * x) gives way to the next one; such overflow of the check's own steps is
 * never reported as the model's fault. An entry that no stencil can check
 * is not checked. A per-channel entry is compared on its own channel only.
 *
 * A numeric derivative is only as exact as the values it is made from: it
 * carries a rounding error of about r = 16 eps sum|w_i f_i| / 2h (eps the
 * double epsilon, w_i and f_i the stencil's weights and values), which
 * dominates where values are large (grazing samples). The relative error
 * of one entry is therefore
 * max(0, |analytic - numeric| - r) / max(|numeric|, 1e-6 * s),
 * s the largest |numeric| - r of that parameter and channel over the grid
 * (the absolute excess when the denominator is 0). The worst entry is
 * reported. The grid is walked in chunks, so memory use does not grow with
 * its size; allocation goes through the model's allocator.
 * @param model  The model.
 * @param grid   Geometry to check on; its channel count is used.
 * @param params brdffit_model_vector_size() values, each finite and
 *               within its parameter's bounds.
 * @param[out] report Receives the worst entry; set its struct_size first.
 *               Unspecified on failure.
 * @param[out] err NULL, or the detail on failure.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT (NULL arguments, a
 *         report struct_size too small, a parameter outside its bounds or
 *         not finite); ::BRDFFIT_E_BAD_HANDLE; ::BRDFFIT_E_MODEL_FAILED;
 *         ::BRDFFIT_E_NONFINITE; ::BRDFFIT_E_OUT_OF_MEMORY;
 *         ::BRDFFIT_E_TOO_LARGE. Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_model_check_jacobian(const brdffit_model *model,
                                                        const brdffit_grid *grid,
                                                        const double *params,
                                                        brdffit_jacobian_report *report,
                                                        brdffit_error *err);

/**
 * @brief Directional albedo: for each incidence angle, the fraction of the
 *        light the model reflects, the integral over the view hemisphere of
 *        f(l, v) cos(theta_o) d(omega_o), per channel.
 *
 * The light lies at (theta_i[t], phi = pi), as in a regular grid. The
 * integral is taken in the half vector h (v = 2 (l.h) h - l,
 * d(omega_o) = 4 (l.h) d(omega_h)) over exactly the h whose view lies
 * above the horizon, where the integrand is smooth for a smooth model: in
 * the azimuth of h a midpoint rule of 64 q s points, s = ceil(1 /
 * cos(theta_i)) up to 16 (a lobe around the mirror direction is s times
 * longer across the plane of incidence in h than along it); in the polar
 * angle of h 25 panels whose widths halve towards h = n (down to 2^-24 of
 * the range, so lobes of any width around the mirror direction are
 * resolved), split where n.v = n.l (the kink of max(n.l, n.v)), each in q
 * parts of 8 Gauss-Legendre points; q = @p quality. That is about
 * 13,300 q^2 s model evaluations per angle, in blocks of up to 208 q
 * samples; the result is deterministic. The model's own clamping (n.l,
 * n.v >= 1e-4, model.h) applies as in a fit; cos(theta_o) is exact.
 *
 * Accuracy at the default quality, measured against closed forms
 * (test_model_albedo) and against quality 4 for every built-in model with
 * exponents 1 .. 10^6 and roughness 10^-4 .. 1:
 * - a Lambertian term: exact to 1e-14 at every angle;
 * - cosine-power lobes (phong with ns >= 10, blinn-phong,
 *   ashikhmin-shirley) and near-mirror microfacet and Ward lobes
 *   (roughness <= 1e-3): within 1e-6 relative up to theta_i = 88 degrees
 *   (the closed forms of the test, to 1e-10, exponents up to 10^6);
 * - broad lobes that are not smooth at the horizon (ward, ggx with
 *   roughness near 1: the floor of n.v): within 4e-5 up to 88 degrees;
 * - models with a kink inside the hemisphere (cook-torrance's min() in its
 *   shadowing, phong with ns near 1): within 2e-3;
 * - beyond 88 degrees about 1e-3, and much worse at theta_i = pi/2 itself
 *   for the sharpest lobes.
 * Lobes far from the mirror direction (lafortune with cz < 1 leans towards
 * grazing) are resolved only as finely as the rule is there: compare with
 * a higher @p quality.
 *
 * @param model      The model.
 * @param params     brdffit_model_vector_size() values for @p n_channels
 *                   (borrowed for the call).
 * @param n_channels Number of channels, 1 or more.
 * @param theta_i    @p count incidence angles in [0, pi/2], radians.
 * @param count      Number of angles; 0 does nothing.
 * @param quality    0 or 1 for the default rule, up to 16 for finer ones.
 * @param[out] albedo count * n_channels values: channel c at angle t goes
 *                   to albedo[t * n_channels + c]. Unspecified on failure.
 * @param[out] err   NULL, or the detail on failure.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT (NULL model, params,
 *         theta_i or albedo, n_channels = 0, quality above 16);
 *         ::BRDFFIT_E_BAD_HANDLE; ::BRDFFIT_E_RANGE for an angle outside
 *         [0, pi/2] or NaN (naming its index); ::BRDFFIT_E_NONFINITE for a
 *         parameter that is NaN or infinite, or a model that produced
 *         NaN or Inf; ::BRDFFIT_E_MODEL_FAILED; ::BRDFFIT_E_TOO_LARGE;
 *         ::BRDFFIT_E_OUT_OF_MEMORY (two blocks, (n_channels + 13) x 208 q
 *         doubles in all, through the model's allocator, freed before
 *         returning).
 * @note Thread-safe, provided the model's evaluation callback is.
 */
BRDFFIT_API brdffit_status brdffit_model_albedo(const brdffit_model *model,
                                                const double *params, size_t n_channels,
                                                const double *theta_i, size_t count,
                                                unsigned quality, double *albedo,
                                                brdffit_error *err);

/**
 * @brief The look error: the compressive log error of a model against a
 *        grid's measured values over every sample within a cap.
 *
 *     E = sqrt(sum a_s d_sc^2 / sum a_s),
 *     d_sc = ln(1 + cos(theta_i) M_c(s)) - ln(1 + cos(theta_i) R_c(s)),
 *
 * M the model with @p params, R the grid's value, theta_i the light's
 * polar angle of sample s (its cosine taken as 0 below the horizon), a_s
 * the sample's ::BRDFFIT_WEIGHT_SOLID_ANGLE weight of
 * brdffit_grid_weights() (the solid angle of its view cell, or its given
 * weight, normalised within the cap), both sums over the samples within
 * the cap and the present (not missing) values of the channels asked for.
 * The logarithm compresses the highlight, so E says how well the model
 * looks like the measurement everywhere, not only at the peak; it does
 * not depend on how the parameters were found. E = 0 exactly when the
 * model matches every value used.
 *
 * @param model    The model.
 * @param grid     The measurement; its channel count is the model's.
 * @param params   brdffit_model_vector_size() values for the grid's
 *                 channels.
 * @param cap      Angle cap in radians, 0 .. pi/2 (grid.h).
 * @param channel  A channel index, or (size_t)-1 (::BRDFFIT_ALL_CHANNELS
 *                 of fit.h) for every channel together.
 * @param[out] out Receives E; untouched on failure.
 * @param[out] err NULL, or the detail on failure.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT (NULL arguments, a
 *         cap out of range, a channel out of range);
 *         ::BRDFFIT_E_BAD_HANDLE; ::BRDFFIT_E_NO_DATA when no sample lies
 *         within the cap or the weights of the present values there sum
 *         to 0; ::BRDFFIT_E_RANGE when the model is negative at a sample
 *         used (naming it); ::BRDFFIT_E_NONFINITE, ::BRDFFIT_E_MODEL_FAILED
 *         as brdffit_model_eval_grid(); ::BRDFFIT_E_OUT_OF_MEMORY (one
 *         block of 64 values per channel, and for a regular grid a few
 *         per-axis values, through the model's allocator).
 * @note One pass over the samples within the cap. Thread-safe, provided
 *       the model's evaluation callback is.
 */
BRDFFIT_API brdffit_status brdffit_model_log_error(const brdffit_model *model,
                                                   const brdffit_grid *grid,
                                                   const double *params, double cap,
                                                   size_t channel, double *out,
                                                   brdffit_error *err);

#ifdef __cplusplus
}
#endif

/** @} */

#endif /* BRDFFIT_MODEL_H */
