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
 * linear colours.
 *
 * A model handle is immutable: every function taking a const model is
 * thread-safe, provided the evaluation callback of a user model is.
 */
#ifndef BRDFFIT_MODEL_H
#define BRDFFIT_MODEL_H

#include <stddef.h>

#include "brdffit/alloc.h"
#include "brdffit/export.h"
#include "brdffit/grid.h"
#include "brdffit/status.h"

/** @defgroup model Models
 * @{ */

/** @brief Opaque, immutable model. */
typedef struct brdffit_model brdffit_model;

/**
 * @brief Geometry of a batch of samples, structure of arrays, owned by the
 *        library and valid only during the callback that receives it.
 *
 * Every array holds @c n entries. Directions are unit vectors in the frame
 * with normal +z. The dot products are clamped to [1e-4, 1] so that models
 * may divide by them and take their logarithm; @c rv is not clamped.
 * New fields are only ever appended; @c struct_size tells which exist.
 */
typedef struct brdffit_batch {
    size_t struct_size;       /**< sizeof the struct as the library knows it. */
    size_t n;                 /**< Number of samples in the batch. */
    const double *lx;         /**< Light direction, x. */
    const double *ly;         /**< Light direction, y. */
    const double *lz;         /**< Light direction, z (unclamped n.l). */
    const double *vx;         /**< View direction, x. */
    const double *vy;         /**< View direction, y. */
    const double *vz;         /**< View direction, z (unclamped n.v). */
    const double *nl;         /**< n.l, clamped to [1e-4, 1]. */
    const double *nv;         /**< n.v, clamped to [1e-4, 1]. */
    const double *nh;         /**< n.h, h = normalize(l + v), clamped to [1e-4, 1]. */
    const double *hv;         /**< h.v, clamped to [1e-4, 1]. */
    const double *log_nh;     /**< ln of the clamped n.h (finite, <= 0). */
    const double *rv;         /**< r.v, r the mirror of l about n; in [-1, 1]. */
} brdffit_batch;

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
 *         returned status.
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

#ifdef __cplusplus
}
#endif

/** @} */

#endif /* BRDFFIT_MODEL_H */
