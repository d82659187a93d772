/**
 * @file fit.h
 * @brief Fitting a model to a measured grid: the pipelines (auto, joint,
 *        two-stage), their options and their results.
 *
 * A fit binds a grid and a model (both borrowed: they must outlive the fit
 * and may be shared with other fits and threads) and options; brdffit_fit_run()
 * computes the parameters that minimise the fit's objective (::brdffit_objective,
 * ::BRDFFIT_FIT_OBJECTIVE): by default the squared differences of the cube
 * roots of cosine-weighted values, whose fits render closest to the
 * measurement; under ::BRDFFIT_OBJECTIVE_SQUARES the thesis's weighted cost
 * (docs/definitions.md, Cost and error figures),
 *
 *     cost = sum over active samples s and channels c of
 *            (w_s * (M_c(s; p) - R_c(s)))^2,
 *
 * w_s the residual weight of brdffit_grid_weights(), R the measured value
 * (divided by 1 - F(theta_i) with clear-coat compensation), M the model.
 *
 * Pipelines:
 * - ::BRDFFIT_PIPELINE_AUTO (default): no start values. The parameters that
 *   enter linearly (colours) are solved exactly, non-negative, for any value
 *   of the others (variable projection); the other parameters are searched
 *   globally over their whole range (a log-spaced scan for exponents and
 *   roughness, refined around every local minimum), and every parameter is
 *   then polished by Levenberg-Marquardt under the model's bounds. The result
 *   is deterministic and does not depend on any start value.
 * - ::BRDFFIT_PIPELINE_JOINT: one Levenberg-Marquardt run over all
 *   parameters of all channels from the start values.
 * - ::BRDFFIT_PIPELINE_TWO_STAGE: the thesis's method (with
 *   ::BRDFFIT_OBJECTIVE_SQUARES): the shape and mean colours fitted to the
 *   channel mean from the start values, then each channel's colours with
 *   the shape held fixed.
 *
 * Every pipeline keeps parameters inside the model's bounds (colours >= 0,
 * Fresnel terms in [0, 1], exponents and roughness in range) and optimises
 * logarithmic-scale parameters in log space.
 *
 * A fit handle is not thread-safe: use each from one thread at a time
 * (brdffit_fit_cancel() excepted). Different fits may run in parallel, also
 * on the same grid and model. The setters and brdffit_fit_run() called
 * during a run (from the fit's iteration callback or a user model) refuse
 * with ::BRDFFIT_E_INVALID_ARGUMENT and change nothing.
 */
#ifndef BRDFFIT_FIT_H
#define BRDFFIT_FIT_H

#include <stddef.h>

#include "brdffit/alloc.h"
#include "brdffit/export.h"
#include "brdffit/grid.h"
#include "brdffit/model.h"
#include "brdffit/optim.h"
#include "brdffit/status.h"

/** @defgroup fit Fitting
 * @{ */

/** @brief Opaque fit. */
typedef struct brdffit_fit brdffit_fit;

/**
 * @brief The most parameters the auto and joint pipelines fit at once (the
 *        optimizer's limit): every channel's colours and the shared shape,
 *        brdffit_model_vector_size() for the grid's channels. Beyond it
 *        brdffit_fit_run() refuses with ::BRDFFIT_E_TOO_LARGE before
 *        allocating anything of that size (Ashikhmin-Shirley: 2048
 *        channels or more); the two-stage pipeline fits each channel alone
 *        and has no such limit.
 */
#define BRDFFIT_FIT_MAX_PARAMS 4096

/** @brief Fit pipelines. Values are fixed forever. */
typedef enum brdffit_pipeline {
    BRDFFIT_PIPELINE_AUTO = 0,      /**< Global search with linear colours, then LM polish. */
    BRDFFIT_PIPELINE_JOINT = 1,     /**< One LM run over everything from the start values. */
    BRDFFIT_PIPELINE_TWO_STAGE = 2  /**< The thesis's channel-mean stage, then per-channel colours. */
} brdffit_pipeline;

/** @brief Numeric fit settings for brdffit_fit_set(). Values are fixed forever. */
typedef enum brdffit_fit_setting {
    BRDFFIT_FIT_PIPELINE = 1,       /**< A ::brdffit_pipeline; default ::BRDFFIT_PIPELINE_AUTO. */
    BRDFFIT_FIT_CAP = 2,            /**< Angle cap in radians, 0 .. pi/2; default ::BRDFFIT_DEFAULT_CAP (75 deg). */
    BRDFFIT_FIT_WEIGHTING = 3,      /**< ::brdffit_weighting flags; default ::BRDFFIT_WEIGHT_DEFAULT. */
    BRDFFIT_FIT_CLEARCOAT = 4,      /**< Clear-coat R0 in [0, 1); 0 (default) switches compensation off. */
    BRDFFIT_FIT_THREADS = 5,        /**< Threads for each pass over the samples, 1 .. 64; default 1. */
    BRDFFIT_FIT_MAX_ITERATIONS = 6, /**< Iteration limit of each LM run; default 200. */
    BRDFFIT_FIT_OBJECTIVE = 7,      /**< A ::brdffit_objective; default ::BRDFFIT_OBJECTIVE_CUBE_ROOT. */
    BRDFFIT_FIT_PLAUSIBLE = 8,      /**< 0, 1 (default) or 2: how the auto pipeline bounds the colours by energy conservation (see below). */
    BRDFFIT_FIT_COVARIANCE = 9      /**< The estimator of brdffit_fit_std_errors() and brdffit_fit_covariance(): 0 classic (default), 1 sandwich (HC3); see brdffit_fit_covariance() for the noise each assumes. */
} brdffit_fit_setting;

/**
 * @brief Physical plausibility (::BRDFFIT_FIT_PLAUSIBLE, 1 by default).
 *
 * 1 (the default): the auto pipeline keeps, in every channel, in its scan
 * and its polish, the diffuse colour "cd" at most 1 (the albedo of a
 * Lambertian cd) and the colour of each specular lobe of a built-in model
 * (phong, blinn-phong, ashikhmin-shirley and its -fresnel and -2 forms,
 * cook-torrance, ggx and their -2 forms, ward, ward-duer, lafortune) at
 * most 1 / A, A an upper bound on the largest directional albedo of the
 * lobe with colour 1 over incidence angles 0, 30, 50, 65, 75 and 85
 * degrees at the current shape: read from a table of the lobe's albedo
 * over its sharpness (Lafortune's: of its form as a cosine lobe about its
 * axis, over n and the axis's polar cosine) computed offline and
 * interpolated, with a margin for the interpolation and the quadrature,
 * so it is never below the integral and at most 3 % above it (1 % or
 * less on the tested shapes; tests/test_model_albedo.c). A polished
 * result is bounded again at its own shape and polished once more if it
 * broke the bound (up to 4 times, then clamped). The table look-ups cost
 * nothing measurable. User models get the cd bound alone.
 *
 * 2: the same, but at the shape of every polished candidate and result
 * each colour (linear parameter) is bounded by the integral itself:
 * colour <= 1 / A, A the largest directional albedo of its term with
 * colour 1 (the others 0) over the same angles (brdffit_model_albedo(),
 * default quality), for every term of every model with linear colours
 * (Lafortune's and user models' included). The scan keeps the cheap
 * bounds of 1. Each integral costs more than the whole fit's passes on a
 * grid of the bundled sample's size: 2 makes an auto fit an order of
 * magnitude slower.
 *
 * A model with a Fresnel term "Rs" (ashikhmin-shirley-fresnel) has
 * cd the substrate's diffuse reflectance (Ashikhmin and Shirley 2000), so
 * cd <= 1 is its physical range too and closes the valley of the cost
 * where Rs -> 1 and cd grows without bound. Colours held fixed are not
 * bounded. Joint and two-stage fits ignore the setting. 0 turns it off
 * (the cost's optimum over the model's own bounds).
 */

/**
 * @brief What a fit minimises (::BRDFFIT_FIT_OBJECTIVE). Values are fixed
 *        forever.
 *
 * Every objective is a sum of squared residuals r over the active samples s
 * and channels c inside the cap; M is the model, R the measured value (as
 * in the cost above), c_s = max(cos theta_i, 0), a_s the solid-angle weight
 * alone (::BRDFFIT_WEIGHT_SOLID_ANGLE) and w_s the fit's residual weight
 * (::BRDFFIT_FIT_WEIGHTING):
 * - SQUARES: r = w_s (M - R), the cost above.
 * - LOG: r = a_s (ln(1 + c_s M) - ln(1 + c_s R)). A measured value with
 *   1 + c_s R <= 0 (a negative value at grazing light) has no logarithm:
 *   brdffit_fit_run() refuses the data with ::BRDFFIT_E_RANGE.
 * - CUBE_ROOT: r = a_s (cbrt(c_s M) - cbrt(c_s R)), the real cube root, so
 *   negative measured values are fitted as they are. The derivative
 *   c_s^(1/3) / (3 |M|^(2/3)) grows without bound as M -> 0; the Jacobian
 *   uses max(|M|, delta) in its place (delta below), so it is exact wherever
 *   |M| >= delta and finite everywhere; the cost is always exact.
 * - RELATIVE: r = w_s (M - R) / (|R| + delta); a negative R counts by its
 *   size.
 *
 * delta = 10^-3 times the geometric mean of the non-zero |R| over the
 * present values of every channel with a non-zero weight inside the cap
 * (as stored, before any clear-coat division); the geometric mean, so that
 * a few grazing spikes cannot lift delta above most values.
 * The error figures e and E do not change with the objective; the cost
 * (::BRDFFIT_METRIC_COST) is the objective's sum of r^2.
 * CUBE_ROOT is the default: of the four, its fits render closest to the
 * measurement (sphere PSNR of the fitted model against the measured data,
 * docs/fitting.md, Choosing the objective; Sun, Jensen and Ramamoorthi
 * 2018 found the same over 100 MERL materials). SQUARES, the thesis's
 * cost, lets the few brightest samples at the highlight dominate; set it
 * to reproduce the thesis's method (joint or two-stage) or figures.
 * The auto pipeline under LOG, CUBE_ROOT or RELATIVE scans the shape
 * parameters on the objective's own profile: at every shape point the
 * colours solved exactly for squared values are carried to the objective's
 * optimum by a few projected Gauss-Newton steps of the small bounded colour
 * problem, so shapes are compared by their true objective cost; every
 * competing minimum is then polished by Levenberg-Marquardt under the
 * objective (docs/fitting.md).
 */
typedef enum brdffit_objective {
    BRDFFIT_OBJECTIVE_SQUARES = 0,   /**< Weighted squares of values (the thesis's cost). */
    BRDFFIT_OBJECTIVE_LOG = 1,       /**< Compressive log of cosine-weighted values. */
    BRDFFIT_OBJECTIVE_CUBE_ROOT = 2, /**< Cube root of cosine-weighted values (the default). */
    BRDFFIT_OBJECTIVE_RELATIVE = 3   /**< Differences relative to the measured value. */
} brdffit_objective;

/** @brief Error figures reported by brdffit_fit_error(). Values are fixed forever. */
typedef enum brdffit_fit_metric {
    BRDFFIT_METRIC_RMS = 0,  /**< e of eq. 4.1: sqrt of the sum of squared unweighted differences inside the cap. */
    BRDFFIT_METRIC_NGAN = 1, /**< E of eq. 3.5: sqrt(sum w (R cos - M cos)^2 / sum w), w the solid-angle weight. */
    BRDFFIT_METRIC_COST = 2  /**< The cost the fit minimises: the objective's sum of squared residuals (::brdffit_objective). */
} brdffit_fit_metric;

/** @brief Channel index meaning "all channels together" in brdffit_fit_error(). */
#define BRDFFIT_ALL_CHANNELS ((size_t)-1)

#ifdef __cplusplus
extern "C" {
#endif

/**
 * @brief Create a fit of @p model to @p grid with default options.
 * @param[out] out Receives the fit (owned by the caller).
 * @param grid     The measurement (borrowed; must outlive the fit).
 * @param model    The model (borrowed; must outlive the fit).
 * @param alloc    Allocator for the fit's own memory, or NULL.
 * @param[out] err NULL, or the detail on failure.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT;
 *         ::BRDFFIT_E_BAD_HANDLE for a destroyed grid or model;
 *         ::BRDFFIT_E_OUT_OF_MEMORY. Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_fit_create(brdffit_fit **out, const brdffit_grid *grid,
                                              const brdffit_model *model,
                                              const brdffit_allocator *alloc,
                                              brdffit_error *err);

/** @brief Destroy a fit. NULL is a no-op. The grid and model are not touched. */
BRDFFIT_API void brdffit_fit_destroy(brdffit_fit *fit);

/**
 * @brief The message of the last failed call on @p fit, owned by the fit and
 *        valid until the next call on it; "" after success. Never NULL.
 */
BRDFFIT_API const char *brdffit_fit_message(const brdffit_fit *fit);

/**
 * @brief Set a numeric option (see ::brdffit_fit_setting for ranges and
 *        defaults).
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT for an unknown setting
 *         or a value out of range (the message says which).
 */
BRDFFIT_API brdffit_status brdffit_fit_set(brdffit_fit *fit, brdffit_fit_setting setting,
                                           double value);

/** @brief Read a numeric option. @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT. */
BRDFFIT_API brdffit_status brdffit_fit_get(const brdffit_fit *fit, brdffit_fit_setting setting,
                                           double *value);

/**
 * @brief Set the damping policy of every LM run (copied; its @c user is
 *        borrowed). NULL restores the default, brdffit_damping_nielsen().
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT for an incomplete policy.
 */
BRDFFIT_API brdffit_status brdffit_fit_set_damping(brdffit_fit *fit,
                                                   const brdffit_damping *policy);

/**
 * @brief Set start values for the joint and two-stage pipelines (copied);
 *        NULL restores the model's defaults. The auto pipeline ignores
 *        them, except for parameters held fixed.
 * @param fit    The fit.
 * @param params brdffit_model_vector_size(model, n_channels of the grid) values.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT (also for NaN or Inf);
 *         ::BRDFFIT_E_RANGE for a value outside the model's bounds.
 */
BRDFFIT_API brdffit_status brdffit_fit_set_start(brdffit_fit *fit, const double *params);

/**
 * @brief Hold a parameter fixed at its start value (@p fixed non-zero) or
 *        let the fit change it (@p fixed zero). By default, parameters the
 *        model flags ::BRDFFIT_PARAM_FIXED are held and the others are free.
 *
 * Every pipeline honours it for every kind of parameter (shape, colour,
 * Fresnel term): a held parameter comes back as exactly its start value in
 * every channel, with standard error 0 (docs/fitting.md).
 * @param fit   The fit.
 * @param param Parameter index in declaration order.
 * @param fixed Non-zero to hold the parameter, zero to free it.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT.
 */
BRDFFIT_API brdffit_status brdffit_fit_set_fixed(brdffit_fit *fit, size_t param, int fixed);

/**
 * @brief Set a callback called after every iteration of every LM run
 *        (NULL removes it); returning non-zero stops the fit
 *        (::BRDFFIT_STOP_CALLBACK). @p user is borrowed.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT.
 */
BRDFFIT_API brdffit_status brdffit_fit_set_callback(brdffit_fit *fit, brdffit_iteration_fn fn,
                                                    void *user);

/**
 * @brief Ask a running fit to stop. Any thread may call this at any time;
 *        the fit stops within one iteration (or one scan step) with
 *        ::BRDFFIT_STOP_CANCELLED, also from inside a step's linear solve
 *        or the standard errors (which may then be 0). The request is
 *        consumed when the run ends.
 */
BRDFFIT_API void brdffit_fit_cancel(brdffit_fit *fit);

/**
 * @brief Run the fit with the current options.
 *
 * @return ::BRDFFIT_OK when parameters were found (also when a limit, a
 *         cancel or the callback ended the last LM run early: see
 *         brdffit_fit_stop_reason()); ::BRDFFIT_E_NO_DATA when no sample
 *         lies inside the cap or every value there is missing;
 *         ::BRDFFIT_E_RANGE when the largest measured value inside the cap
 *         lies outside [1e-100, 1e100] (its square would under- or
 *         overflow: rescale the data);
 *         ::BRDFFIT_E_MODEL_FAILED; ::BRDFFIT_E_NONFINITE when the model or
 *         the data give NaN or Inf at the start; ::BRDFFIT_E_TOO_LARGE when
 *         the auto or joint pipeline would fit more than
 *         ::BRDFFIT_FIT_MAX_PARAMS parameters at once;
 *         ::BRDFFIT_E_OUT_OF_MEMORY;
 *         ::BRDFFIT_E_BAD_HANDLE. brdffit_fit_message() says more.
 */
BRDFFIT_API brdffit_status brdffit_fit_run(brdffit_fit *fit);

/** @brief Length of the parameter vector (brdffit_model_vector_size() for the grid's channels). */
BRDFFIT_API size_t brdffit_fit_param_count(const brdffit_fit *fit);

/**
 * @brief The fitted parameter vector (layout of model.h).
 * @param fit         The fit.
 * @param[out] params brdffit_fit_param_count() values.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_NOT_READY before a successful run;
 *         ::BRDFFIT_E_INVALID_ARGUMENT.
 */
BRDFFIT_API brdffit_status brdffit_fit_params(const brdffit_fit *fit, double *params);

/**
 * @brief Standard errors of the fitted parameters from the final LM run's
 *        covariance (log-scale parameters converted by the delta method;
 *        the estimator of ::BRDFFIT_FIT_COVARIANCE, see
 *        brdffit_fit_covariance()); 0 for parameters held fixed or at a
 *        bound; HUGE_VAL for a parameter the data do not determine (its
 *        Jacobian column is zero or vanished, or it lies in a direction of
 *        J^T J that the pseudo-inverse drops, see
 *        brdffit_optimizer_std_errors()); never NaN. After a cancelled
 *        auto fit (the scan's best point, not polished) all are 0. Like
 *        every call on the handle, from one thread at a time.
 * @param fit     The fit.
 * @param[out] se brdffit_fit_param_count() values.
 * @return As brdffit_fit_params().
 */
BRDFFIT_API brdffit_status brdffit_fit_std_errors(const brdffit_fit *fit, double *se);

/**
 * @brief The covariance of the fitted parameters: the matrix whose
 *        diagonal's square roots are brdffit_fit_std_errors().
 *
 * p x p values, p = brdffit_fit_param_count(), row-major, rows and columns
 * in the parameter layout of model.h (the channel's colours, the shared
 * shape: brdffit_model_vector_index()). It is the final LM run's
 * covariance at the result, over the parameters that are neither held
 * fixed nor at a bound, in natural units: a log-scale parameter's rows
 * and columns are converted by the delta method (multiplied by the
 * parameter's value, as its standard error is), and the canonical lobe
 * order of a two-lobe model swaps rows and columns with the values.
 * - Fixed or at a bound: the parameter's row and column are 0.
 * - Not determined by the data (standard error HUGE_VAL): HUGE_VAL on the
 *   diagonal, 0 elsewhere in its row and column (its covariance with the
 *   others is unknown, and 0 keeps every product with the matrix finite
 *   for the determined ones).
 * - Never NaN. The diagonal equals the standard errors squared up to
 *   rounding, except that a variance beyond the double range (a standard
 *   error above about 1e154) is HUGE_VAL while the standard error is
 *   finite.
 * - After a cancelled auto fit (not polished), or a cancel during the
 *   final LM run's covariance: all 0, like the standard errors.
 *
 * Pipelines: auto and joint give the full matrix of one LM run over every
 * parameter of every channel. Two-stage gives each stage's own: the
 * shared parameters' block from the channel-mean stage, each channel's
 * per-channel block from that channel's stage (which holds the shape
 * fixed, so its block is conditional on it), and 0 between the blocks
 * (covariances the stages do not estimate); channels a cancel left at
 * the first stage's values have 0 rows, as their standard errors.
 *
 * The estimator (::BRDFFIT_FIT_COVARIANCE), with r_i the fit's residuals
 * (weights and objective included, ::brdffit_objective), J their
 * Jacobian at the result, m the number of rows with a value and q the
 * free parameters:
 * - 0, classic (default): s^2 (J^T J)^+, s^2 = cost / (m - q). It assumes
 *   independent residual errors of one common variance: the noise of
 *   every value, times its residual weight (and through the objective's
 *   transform), has the same spread. Right for additive noise of one
 *   level with ::BRDFFIT_WEIGHT_NONE under the squares objective; not for
 *   noise that grows with the value (multiplicative noise, photon noise)
 *   nor for weights that do not follow the noise (the default
 *   solid-angle and cosine weights with noise of one level), where its
 *   intervals are too narrow for some parameters and too wide for others
 *   (docs/fitting.md, Standard errors, gives measured coverages).
 * - 1, sandwich (heteroscedasticity-robust, HC3; MacKinnon and White
 *   1985): (J^T J)^+ (sum_i (r_i / (1 - h_i))^2 J_i^T J_i) (J^T J)^+ with
 *   the leverages h_i = J_i (J^T J)^+ J_i^T (1 - h_i floored at 1e-8). It
 *   assumes only independent errors of zero mean, of any spread per
 *   value: the choice for multiplicative noise, for weights that are not
 *   the inverse noise levels, or when the noise model is unknown. It
 *   costs one more pass over the samples per LM run (the generic route,
 *   evaluating each row's Jacobian) and an O(p^3) pseudo-inverse even
 *   where the classic one of many channels is linear in them. HC3 rather
 *   than HC0: the leverages undo the shrinking of residuals at the rows
 *   that pull the fit towards themselves, which makes HC0's intervals
 *   too narrow with few samples per parameter (Long and Ervin 2000); the
 *   optimizer's sandwich (::BRDFFIT_OPT_COVARIANCE) is the same.
 * Both hold for every objective: they are computed from the objective's
 * own residuals. Both are first-order (linearised) estimates at the
 * result; neither knows about correlated errors between samples.
 *
 * brdffit_fit_many() does not return covariances (::brdffit_many_out has
 * standard errors only); fit an item alone for its covariance.
 * Memory: the fit keeps p * p doubles for the matrix from its creation
 * when p <= ::BRDFFIT_FIT_MAX_PARAMS (49 for a 3-channel
 * Ashikhmin-Shirley fit; 128 MiB at the limit), none above it.
 * Like every call on the handle, from one thread at a time; the values
 * are copied into the caller's array, which the fit does not keep.
 * @param fit      The fit.
 * @param[out] cov p * p values.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_NOT_READY before a successful run;
 *         ::BRDFFIT_E_INVALID_ARGUMENT for NULL; ::BRDFFIT_E_BAD_HANDLE
 *         for a destroyed fit; ::BRDFFIT_E_TOO_LARGE when p exceeds
 *         ::BRDFFIT_FIT_MAX_PARAMS (two-stage fits of very many channels:
 *         the matrix is not kept; the standard errors are).
 */
BRDFFIT_API brdffit_status brdffit_fit_covariance(const brdffit_fit *fit, double *cov);

/**
 * @brief An error figure of the fitted parameters.
 * @param fit     The fit.
 * @param metric  Which figure.
 * @param channel A channel index, or ::BRDFFIT_ALL_CHANNELS.
 * @param[out] value Receives it.
 * @return As brdffit_fit_params().
 */
BRDFFIT_API brdffit_status brdffit_fit_error(const brdffit_fit *fit, brdffit_fit_metric metric,
                                             size_t channel, double *value);

/**
 * @brief The renderer form (docs/definitions.md) for models with diffuse and
 *        specular colours "cd" and "cs".
 *
 * For a model with a Fresnel parameter "Rs" the fitted Rs, cd and cs are
 * the shader's. Otherwise Rs = max over channels of cs, cs / Rs and
 * cd / (1 - Rs) (cs = 0 when Rs = 0).
 * @param fit    The fit.
 * @param[out] rs Receives Rs.
 * @param[out] cd n_channels shader diffuse colours.
 * @param[out] cs n_channels shader specular colours.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_NOT_READY; ::BRDFFIT_E_UNSUPPORTED for
 *         a model without "cd" and "cs"; ::BRDFFIT_E_RANGE when max(cs) >= 1
 *         (no shader form exists); ::BRDFFIT_E_INVALID_ARGUMENT.
 */
BRDFFIT_API brdffit_status brdffit_fit_shader(const brdffit_fit *fit, double *rs, double *cd,
                                              double *cs);

/**
 * @brief Why the final LM run ended; ::BRDFFIT_STOP_NONE before a run.
 *
 * The final run is, for auto, the polish whose result is returned (the
 * best of them); for joint, its run; for two-stage, the last channel's
 * second stage (the mean stage when a cancel came before any channel).
 * ::BRDFFIT_STOP_CANCELLED whenever the fit was cancelled. Every stage's
 * own reason: brdffit_fit_stage_info(); whether the whole answer
 * converged: brdffit_fit_converged().
 */
BRDFFIT_API brdffit_stop_reason brdffit_fit_stop_reason(const brdffit_fit *fit);

/** @brief Iterations of the final LM run (as brdffit_fit_stop_reason()). */
BRDFFIT_API size_t brdffit_fit_iterations(const brdffit_fit *fit);

/**
 * @brief Cost and lambda per iteration of the final LM run (as
 *        brdffit_fit_stop_reason()), as brdffit_optimizer_history(); the
 *        whole run's: brdffit_fit_history_all().
 * @return The number of values written to each non-NULL array.
 */
BRDFFIT_API size_t brdffit_fit_history(const brdffit_fit *fit, double *cost, double *lambda);

/** @brief Passes over the samples the last run made (scan and LM together). */
BRDFFIT_API size_t brdffit_fit_passes(const brdffit_fit *fit);

/**
 * @brief Whether the last run's answer converged: 1 when the last run
 *        succeeded, was neither cancelled nor stopped by its callback, and
 *        every Levenberg-Marquardt run whose result is part of the returned
 *        parameters converged in the sense of brdffit_optimizer_converged()
 *        (it ended with ::BRDFFIT_STOP_GRADIENT, ::BRDFFIT_STOP_STEP,
 *        ::BRDFFIT_STOP_COST or ::BRDFFIT_STOP_ZERO_COST).
 *
 * The runs judged are those the stages mark @c kept
 * (brdffit_fit_stage_info()): auto, the polish whose result is returned;
 * joint, its run; two-stage, the channel-mean stage and every channel's
 * second stage. 0 when any of them stalled (::BRDFFIT_STOP_STALLED), hit
 * its iteration or evaluation limit or was stopped by the callback, when
 * the fit was cancelled (also during auto's scan, before any polish),
 * before a run, after a failed one, and for NULL or a destroyed handle.
 * Only the
 * returned point's standing as a stationary point is judged, not whether
 * it is the global minimum. Thread-safe for concurrent readers of a fit
 * that is not running.
 */
BRDFFIT_API int brdffit_fit_converged(const brdffit_fit *fit);

/** @brief The stages of a fit run (brdffit_fit_stage_info()). Values are fixed forever. */
typedef enum brdffit_fit_stage_kind {
    BRDFFIT_STAGE_SCAN = 0,   /**< Auto: the global scan of the profile cost, with its refinement. */
    BRDFFIT_STAGE_POLISH = 1, /**< Auto: the LM polish of one scan candidate. */
    BRDFFIT_STAGE_JOINT = 2,  /**< Joint: the LM run over every parameter. */
    BRDFFIT_STAGE_MEAN = 3,   /**< Two-stage: the LM run on the channel mean (stage 1). */
    BRDFFIT_STAGE_CHANNEL = 4 /**< Two-stage: one channel's LM run with the shape held (stage 2). */
} brdffit_fit_stage_kind;

/**
 * @brief One stage of the last run, as brdffit_fit_stage_info() reports it.
 *        Fields are only ever appended.
 */
typedef struct brdffit_fit_stage {
    brdffit_fit_stage_kind kind; /**< What the stage is. */
    size_t index;       /**< Polish: below the number of scan candidates, the candidate's rank in the
                             scan (0 the best); from it on, the further starts, numbered as
                             docs/fitting.md (Stages and the whole history) lists them; channel:
                             the channel; else 0. */
    size_t first;       /**< Its first entry in brdffit_fit_history_all(). */
    size_t length;      /**< Its number of entries there. */
    brdffit_stop_reason stop; /**< Why an LM stage ended; ::BRDFFIT_STOP_NONE for the scan. */
    size_t iterations;  /**< LM iterations (accepted and rejected steps); 0 for the scan. */
    size_t evaluations; /**< Evaluations of the LM problem, or the scan's profile evaluations. */
    int converged;      /**< brdffit_optimizer_converged() of an LM stage; 0 for the scan. */
    int kept;           /**< Non-zero when the stage's result is part of the returned parameters (never the scan). */
} brdffit_fit_stage;

/** @brief The smallest size brdffit_fit_stage_info() accepts: the first
 *         version of ::brdffit_fit_stage. */
#define BRDFFIT_FIT_STAGE_SIZE_V1 (offsetof(brdffit_fit_stage, kept) + sizeof(int))

/**
 * @brief Number of stages of the last successful run, in the order they ran
 *        (auto: the scan, then one polish per competing candidate; joint:
 *        one; two-stage: the mean stage, then one per channel); 0 before
 *        one. Thread-safe as brdffit_fit_converged().
 */
BRDFFIT_API size_t brdffit_fit_stage_count(const brdffit_fit *fit);

/**
 * @brief The label and report of stage @p stage of the last successful run.
 * @param fit   The fit.
 * @param stage 0 .. brdffit_fit_stage_count() - 1.
 * @param[out] info Receives the first @p size bytes of the stage's
 *                  ::brdffit_fit_stage (pass sizeof(brdffit_fit_stage); a
 *                  caller built against an older header passes its smaller
 *                  size and gets the fields it knows).
 * @param size  Bytes of @p info, at least ::BRDFFIT_FIT_STAGE_SIZE_V1;
 *              bytes beyond the library's struct are left as they are.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_NOT_READY before a successful run;
 *         ::BRDFFIT_E_INVALID_ARGUMENT for NULL, a stage out of range or a
 *         size too small; ::BRDFFIT_E_BAD_HANDLE. Thread-safe as
 *         brdffit_fit_converged().
 */
BRDFFIT_API brdffit_status brdffit_fit_stage_info(const brdffit_fit *fit, size_t stage,
                                                  brdffit_fit_stage *info, size_t size);

/**
 * @brief The short name of a stage kind ("scan", "polish", "joint", "mean",
 *        "channel"), as the command's JSON output uses them; NULL for an
 *        unknown kind. The strings are static. Thread-safe.
 */
BRDFFIT_API const char *brdffit_fit_stage_name(brdffit_fit_stage_kind kind);

/**
 * @brief The whole history of the last successful run, every stage in turn,
 *        each entry labelled with its stage.
 *
 * An LM stage contributes its brdffit_optimizer_history(): the start cost
 * and lambda, then the cost and lambda after each iteration. The scan
 * contributes one entry per profile evaluation: the lowest profile cost of
 * the scan so far, lambda 0. Costs are in the fit's objective; a
 * two-stage mean stage's cost is that of the channel mean, a channel
 * stage's that of its channel alone. brdffit_fit_history() is the part of
 * the stage it reports (brdffit_fit_stop_reason()).
 * @param fit  The fit.
 * @param[out] cost   NULL, or the returned number of values.
 * @param[out] lambda NULL, or as many.
 * @param[out] stage  NULL, or as many: each entry's stage number
 *                    (brdffit_fit_stage_info()).
 * @return The number of entries (call with three NULLs to size the arrays);
 *         0 before a successful run. Thread-safe as brdffit_fit_converged().
 */
BRDFFIT_API size_t brdffit_fit_history_all(const brdffit_fit *fit, double *cost, double *lambda,
                                           size_t *stage);

/**
 * @brief Warnings about a fitted result: signs that the parameters, although
 *        the optimum of the cost, may not describe the material. Bit values
 *        are fixed forever; new ones are only ever added.
 *
 * brdffit_fit_warnings() tests the result of the last successful run:
 * - ::BRDFFIT_WARN_AT_BOUND: a free shape parameter (not colour, not held)
 *   lies on a finite bound of its range, to 1e-6 relative (in log terms for
 *   logarithmic parameters); the data may want a value outside it.
 * - ::BRDFFIT_WARN_NO_DIFFUSE: a model with a diffuse colour "cd" and other
 *   terms fitted cd = 0 in every channel.
 * - ::BRDFFIT_WARN_ALBEDO: the diffuse albedo, cd (times 1 - Rs for a model
 *   with "Rs"), exceeds 1 in some channel: more light out than in; or a
 *   specular lobe of a built-in model with a tabulated lobe albedo
 *   (docs/fitting.md, Physical plausibility) reflects more than 1 at some
 *   incidence angle of the tables by its colour times the tabulated bound,
 *   by more than the tables' 3 % margin (so a lobe flagged is above 1 for
 *   certain; one between 1 and 1.03 may pass unflagged).
 * - ::BRDFFIT_WARN_FRESNEL_VALLEY: a free Fresnel term "Rs" or "F0" above
 *   0.99 while some colour exceeds 1: the valley of the cost where the
 *   Fresnel term tends to 1 and the colours grow without bound.
 * - ::BRDFFIT_WARN_ITERATION_LIMIT: the final optimizer run ended at its
 *   iteration or evaluation limit.
 * - ::BRDFFIT_WARN_STOPPED_EARLY: the fit was cancelled or stopped by its
 *   callback.
 * - ::BRDFFIT_WARN_LOBES_MERGED: a two-lobe model (shape parameters "x1"
 *   and "x2", colours "cs1" and "cs2") whose lobes differ by less than a
 *   factor 1.25 in shape, or one of whose lobes has colour 0 everywhere.
 * - ::BRDFFIT_WARN_DEGREES_AS_RADIANS: every polar angle of the grid is at
 *   most pi/2 degrees (but not all 0): angles given in radians where
 *   degrees were expected look like this.
 * - ::BRDFFIT_WARN_STALLED: the final optimizer run ended with
 *   ::BRDFFIT_STOP_STALLED, at a point that is not converged.
 * - ::BRDFFIT_WARN_NO_BETTER_THAN_MEAN: the fit is no better than the
 *   best constant value of each channel: under the squares objective in
 *   the cost it minimised; under the others in both Ngan's measure (the
 *   numerator of ::BRDFFIT_METRIC_NGAN) and the plain sum of squares
 *   (::BRDFFIT_METRIC_RMS squared), summed over channels. The model then
 *   explains nothing of the data's variation.
 */
typedef enum brdffit_warning {
    BRDFFIT_WARN_AT_BOUND = 1,             /**< A free shape parameter on a bound. */
    BRDFFIT_WARN_NO_DIFFUSE = 2,           /**< No diffuse term in any channel. */
    BRDFFIT_WARN_ALBEDO = 4,               /**< A diffuse or lobe albedo above 1. */
    BRDFFIT_WARN_FRESNEL_VALLEY = 8,       /**< Fresnel term -> 1 with colours above 1. */
    BRDFFIT_WARN_ITERATION_LIMIT = 16,     /**< The final LM run hit a limit. */
    BRDFFIT_WARN_STOPPED_EARLY = 32,       /**< Cancelled or stopped by the callback. */
    BRDFFIT_WARN_LOBES_MERGED = 64,        /**< Two lobes that are one. */
    BRDFFIT_WARN_DEGREES_AS_RADIANS = 128, /**< Angles that look like radians read as degrees. */
    BRDFFIT_WARN_STALLED = 256,            /**< The final LM run stalled (::BRDFFIT_STOP_STALLED). */
    BRDFFIT_WARN_NO_BETTER_THAN_MEAN = 512 /**< The fit's error E is no smaller than a constant's. */
} brdffit_warning;

/**
 * @brief The warnings (::brdffit_warning bits) about the last successful
 *        run's result; 0 when there is none or no result.
 *
 * Reads the result and the grid's angles (O(samples) for a scattered grid,
 * O(1) for a regular one); allocates nothing. Thread-safe for concurrent
 * readers of a fit that is not running.
 */
BRDFFIT_API unsigned brdffit_fit_warnings(const brdffit_fit *fit);

/**
 * @brief One sentence on warning @p warning, naming the parameter, channel
 *        and values concerned, e.g. "ns = 1e+06 is at a bound of its range
 *        [0.001, 1e+06]".
 * @param fit     The fit.
 * @param warning Exactly one ::brdffit_warning bit.
 * @param[out] buf Receives the NUL-terminated sentence (cut to @p size);
 *                 the empty string on failure.
 * @param size    Size of @p buf, at least 1.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_NOT_FOUND when the result does not
 *         carry that warning; ::BRDFFIT_E_NOT_READY before a successful
 *         run; ::BRDFFIT_E_INVALID_ARGUMENT for NULL, size 0 or not exactly
 *         one known bit; ::BRDFFIT_E_BAD_HANDLE. Thread-safe as
 *         brdffit_fit_warnings().
 */
BRDFFIT_API brdffit_status brdffit_fit_warning_text(const brdffit_fit *fit, unsigned warning,
                                                    char *buf, size_t size);

/**
 * @brief The short name of one warning bit ("at-bound", "no-diffuse",
 *        "albedo-above-1", "fresnel-valley", "iteration-limit",
 *        "stopped-early", "lobes-merged", "radians-as-degrees", "stalled",
 *        "no-better-than-mean"), as the
 *        command's JSON output uses them; NULL unless @p warning is exactly
 *        one known bit. The strings are static. Thread-safe.
 */
BRDFFIT_API const char *brdffit_warning_name(unsigned warning);

#ifdef __cplusplus
}
#endif

/** @} */

#endif /* BRDFFIT_FIT_H */
