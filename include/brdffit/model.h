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
 * @c struct_size tells the library which exist.
 *
 * A parameter flagged ::BRDFFIT_PARAM_LINEAR must be per-channel, and the
 * model's value must be a sum of such parameters times terms that depend
 * only on the geometry and on the non-linear parameters (so the value is
 * the sum over linear parameters of parameter times derivative). Fits use
 * this to solve for those parameters exactly.
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

/** @brief Fill @p def with the defaults of ::BRDFFIT_MODEL_DEF_INIT. NULL is a no-op. */
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
 * @param[out] out Receives the model (owned by the caller); NULL on failure.
 * @param name     A name from brdffit_model_builtin_name().
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
 *        copied except @c user, which the model keeps and hands to
 *        @c destroy when the model is destroyed. On failure @c destroy is
 *        not called and @c user stays the caller's.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT for a NULL or
 *         inconsistent definition (unknown struct size, no parameters,
 *         duplicate names, bad bounds or flags); ::BRDFFIT_E_OUT_OF_MEMORY.
 *         Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_model_create_custom(brdffit_model **out,
                                                       const brdffit_model_def *def,
                                                       const brdffit_allocator *alloc,
                                                       brdffit_error *err);

/** @brief Destroy a model; calls its destroy callback. NULL is a no-op. */
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
 * @brief Find a parameter by name.
 * @return ::BRDFFIT_OK and its index in @p index; ::BRDFFIT_E_NOT_FOUND;
 *         ::BRDFFIT_E_INVALID_ARGUMENT. Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_model_param_find(const brdffit_model *model,
                                                    const char *name, size_t *index);

/** @brief Length of the parameter vector for @p n_channels channels; 0 on bad input. */
BRDFFIT_API size_t brdffit_model_vector_size(const brdffit_model *model, size_t n_channels);

/**
 * @brief Position of parameter @p param, channel @p channel, in the
 *        parameter vector. @p channel is ignored for shared parameters.
 * @return The index, or (size_t)-1 on bad input. Thread-safe.
 */
BRDFFIT_API size_t brdffit_model_vector_index(const brdffit_model *model, size_t param,
                                              size_t channel, size_t n_channels);

/**
 * @brief Fill @p params with every parameter's default start value.
 * @param params brdffit_model_vector_size() doubles.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT. Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_model_default_params(const brdffit_model *model,
                                                        size_t n_channels, double *params);

/**
 * @brief Evaluate a model over grid samples [first, first + count).
 *
 * The grid's channel count is the model's; output layouts as in
 * ::brdffit_model_eval_fn with batch->n = @p count.
 * @param values   count * n_channels doubles.
 * @param jacobian NULL, or n_params * n_channels * count doubles.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT (NULL, range outside
 *         the grid); ::BRDFFIT_E_MODEL_FAILED; ::BRDFFIT_E_NONFINITE when
 *         the model produced NaN or Inf; ::BRDFFIT_E_OUT_OF_MEMORY.
 *         Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_model_eval_grid(const brdffit_model *model,
                                                   const brdffit_grid *grid, size_t first,
                                                   size_t count, const double *params,
                                                   double *values, double *jacobian,
                                                   brdffit_error *err);

/**
 * @brief Evaluate a model at arbitrary directions (radians).
 *
 * Angle arrays hold @p count entries each; layouts as in
 * ::brdffit_model_eval_fn with batch->n = @p count.
 * @return As brdffit_model_eval_grid(); also ::BRDFFIT_E_RANGE for polar
 *         angles outside [0, pi/2] or non-finite angles. Thread-safe.
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
 * The relative error of one entry is |analytic - numeric| / max(|numeric|,
 * 1e-6 * s), s the largest |numeric| of that parameter and channel over the
 * grid; the step for parameter x is 1e-6 * max(|x|, 1e-3). The worst entry
 * is reported.
 * @param grid   Geometry to check on; its channel count is used.
 * @param params brdffit_model_vector_size() values.
 * @param[out] report Receives the worst entry; set its struct_size first.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT;
 *         ::BRDFFIT_E_MODEL_FAILED; ::BRDFFIT_E_NONFINITE;
 *         ::BRDFFIT_E_OUT_OF_MEMORY. Thread-safe.
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
