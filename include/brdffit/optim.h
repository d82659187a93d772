/**
 * @file optim.h
 * @brief A general Levenberg-Marquardt optimizer for nonlinear least squares,
 *        with pluggable damping policies, box bounds and fixed parameters.
 *
 * The optimizer minimises cost(x) = sum_i r_i(x)^2 (no factor 1/2) over
 * x in R^p. The problem is given either as residuals plus Jacobian, or, for
 * problems with many rows, directly in normal-equation form (J^T J, J^T r
 * and the cost accumulated by the callback in one pass), so the Jacobian
 * never has to be stored.
 *
 * Each step solves (J^T J + lambda D) delta = -J^T r with D = diag(J^T J)
 * (Marquardt scaling, default: the running maximum of diag(J^T J), each
 * entry from its own column, so that the steps do not depend on the
 * parameters' units) or a multiple of the identity (Levenberg), by
 * Cholesky; when the damped matrix is not positive
 * definite or is badly conditioned, by a symmetric eigen-decomposition
 * (pseudo-inverse), and the run records that it fell back.
 *
 * In the residual form, trial points are evaluated for the residuals alone
 * (jac NULL) and the Jacobian once per accepted step, at the new point. In
 * the normal-equation form every evaluation asks for J^T J and J^T r with
 * the cost (one pass over the rows gives all three), so an accepted step
 * costs one evaluation and a rejected one discards them.
 * A trial point the problem cannot evaluate (a failing callback, NaN or
 * Inf anywhere) is a rejected step, never a result.
 *
 * Box bounds are handled by an active-set projected step: a parameter on a
 * bound whose gradient points out of the box is held for that step, the
 * step of the others is solved for, the trial point is projected onto the
 * box, and the gain ratio uses the reduction the model predicts for the
 * projected step. The problem is never evaluated outside the box.
 * docs/optimizer.md describes the algorithm in full.
 *
 * An optimizer handle is not thread-safe: use one per thread. The only
 * exception is brdffit_optimizer_cancel(), which any thread may call while
 * another runs the optimizer. Two optimizers in two threads do not share
 * any state. Functions that change the optimizer fail with
 * ::BRDFFIT_E_INVALID_ARGUMENT when called from its own callbacks during a
 * run; functions given a destroyed handle return ::BRDFFIT_E_BAD_HANDLE
 * where that is detectable. The library never prints.
 */
#ifndef BRDFFIT_OPTIM_H
#define BRDFFIT_OPTIM_H

#include <stddef.h>

#include "brdffit/alloc.h"
#include "brdffit/export.h"
#include "brdffit/status.h"

/** @defgroup optim Levenberg-Marquardt optimizer
 * @{ */

/** @brief Opaque optimizer. */
typedef struct brdffit_optimizer brdffit_optimizer;

/**
 * @brief Residual form of a problem.
 * @param x        The p parameters.
 * @param[out] r   n_rows residuals.
 * @param[out] jac NULL when only residuals are wanted; otherwise the
 *                 n_rows x p Jacobian dr_i/dx_j, row-major: jac[i * p + j].
 * @param user     The user pointer given with the callback.
 * @return ::BRDFFIT_OK, or an error status; a failure at a trial point
 *         rejects that step, a failure at the start point ends the run with
 *         ::BRDFFIT_E_CALLBACK_FAILED.
 */
typedef brdffit_status (*brdffit_residual_fn)(const double *x, double *r, double *jac,
                                              void *user);

/**
 * @brief Normal-equation form of a problem.
 * @param x        The p parameters.
 * @param[out] cost sum of squared residuals at x (set to 0 before the call).
 * @param[out] jtj NULL when only the cost is wanted (the optimizer always
 *                 wants J^T J and J^T r with the cost; other callers of
 *                 the callback may not); otherwise J^T J, p x p,
 *                 row-major (both triangles; the optimizer averages the
 *                 two), set to 0 before the call so the callback may
 *                 accumulate into it.
 * @param[out] jtr NULL when only the cost is wanted; otherwise J^T r, p
 *                 values, set to 0 before the call.
 * @param user     The user pointer given with the callback.
 * @return As ::brdffit_residual_fn. A negative cost counts as a failure.
 */
typedef brdffit_status (*brdffit_normal_fn)(const double *x, double *cost, double *jtj,
                                            double *jtr, void *user);

/**
 * @brief A damping policy: how lambda starts and how it reacts to accepted
 *        and rejected steps. A versioned vtable: initialise with
 *        ::BRDFFIT_DAMPING_INIT, fields are only ever appended.
 *
 * The optimizer allocates @c state_size bytes of state (aligned for any
 * type, zeroed) per run and passes them to every callback. @c init sets the
 * start lambda; @c accept receives the gain ratio rho (actual over
 * predicted cost reduction, > 0) and updates lambda; @c reject updates
 * lambda after a step that did not lower the cost (rho <= 0, or a trial
 * point the problem could not evaluate, then rho is NaN; or a projected step
 * the linear model predicts no decrease for, which is not evaluated, then
 * rho is 0). lambda must stay finite and > 0; the optimizer clamps it to
 * [1e-300, 1e300] and keeps the previous value when a callback leaves NaN.
 * lambda is relative to the scaling D, so the same policy suits both
 * scalings. When @c reject does not raise lambda (a policy at its cap),
 * the optimizer halves the next step itself, so every iteration tries a
 * new point and the run ends.
 *
 * A versioned struct: fields are only ever appended. The optimizer and the
 * fit accept any @c struct_size from the size of the first version
 * (everything up to and including @c user) upwards, so a program built
 * against a newer header keeps working (fields unknown to this library are
 * ignored); a smaller size is refused with ::BRDFFIT_E_INVALID_ARGUMENT.
 */
typedef struct brdffit_damping {
    size_t struct_size; /**< sizeof(brdffit_damping) of the caller's header. */
    const char *name;   /**< Short name, for reports. */
    size_t state_size;  /**< Bytes of per-run state; may be 0. */
    void (*init)(void *state, double *lambda, void *user);              /**< Start a run. */
    void (*accept)(void *state, double rho, double *lambda, void *user); /**< After an accepted step. */
    void (*reject)(void *state, double rho, double *lambda, void *user); /**< After a rejected step. */
    void *user;         /**< Passed last to the callbacks. */
} brdffit_damping;

/** @brief The @c struct_size of the first version of ::brdffit_damping
 *         (everything up to and including @c user): the smallest size the
 *         optimizer and the fit accept. Fixed forever. */
#define BRDFFIT_DAMPING_SIZE_V1 (offsetof(brdffit_damping, user) + sizeof(void *))

/** @brief Static initialiser for ::brdffit_damping. */
#define BRDFFIT_DAMPING_INIT { sizeof(brdffit_damping), NULL, 0, NULL, NULL, NULL, NULL }

/** @brief Numeric settings for brdffit_optimizer_set(). Values are fixed forever. */
typedef enum brdffit_optim_setting {
    BRDFFIT_OPT_GTOL = 1,           /**< Stop when max_j |g_j| / sqrt(A_jj * cost) <= gtol, g = J^T r, A = J^T J, over the parameters that may move (not fixed, not pushing out of a bound): the cosine between the residual vector and each Jacobian column, independent of the units of parameters and residuals; default 1e-13. */
    BRDFFIT_OPT_XTOL = 2,           /**< Stop when the step (after projection onto the box) has |step_j| <= xtol * (|x_j| + xtol) for every parameter j, before it is evaluated; default 1e-10. */
    BRDFFIT_OPT_FTOL = 3,           /**< Stop when an accepted step lowers the cost by at most ftol * cost and the model predicted no more; default 1e-15. */
    BRDFFIT_OPT_MAX_ITERATIONS = 4, /**< Accepted plus rejected steps; default 10000; at most 2^53. */
    BRDFFIT_OPT_MAX_EVALUATIONS = 5,/**< Problem evaluations, the start point included; a step is only tried while two remain (the trial, and the derivatives if it is accepted); default 24000; at most 2^53. */
    BRDFFIT_OPT_SCALING = 6,        /**< 1 = Marquardt, D = diag(J^T J) (default); 0 = Levenberg, D = d0 I with d0 the largest diagonal entry of J^T J at the start point. */
    BRDFFIT_OPT_DIAG_FLOOR = 7,     /**< Marquardt scaling without the scale memory (::BRDFFIT_OPT_SCALE_MEMORY 0): each entry of D is diag(J^T J)_jj floored at this value times the largest that entry had in the attempt, its own column's, never another's, so rescaling a parameter changes nothing (and never below 1e-300); 0 < value <= 1; default 1e-12. */
    BRDFFIT_OPT_STEP_BOUND = 8,     /**< Largest change of a parameter in one step, relative to the largest magnitude it has had in the run (start included): a longer step is shortened along its direction; a parameter that has only been 0 sets no bound; default 1e300 (no bound). */
    BRDFFIT_OPT_RESTART_BOUND = 9,  /**< When a run stalls (::BRDFFIT_STOP_STALLED) it starts once more from the start point with this step bound (see ::BRDFFIT_OPT_STEP_BOUND) and returns the better of the two attempts; only when the value is below the step bound; default 1 (at most doubling a parameter's scale per step). Iterations, history and last improvement describe the attempt returned; evaluations count both. Set it to 1e300 to turn the restart off. */
    BRDFFIT_OPT_COVARIANCE = 10     /**< The covariance brdffit_optimizer_covariance() and brdffit_optimizer_std_errors() report: 0 = classic s^2 (J^T J)^+ (default; assumes independent errors of one common variance, or residuals already divided by their standard deviations); 1 = sandwich (heteroscedasticity-robust, HC3): (J^T J)^+ (sum_i (r_i / (1 - h_i))^2 J_i J_i^T) (J^T J)^+ with the leverages h_i = J_i (J^T J)^+ J_i^T, which assumes only independent errors; residual form only (one more evaluation at the returned point). Recommended when the noise level varies between rows and the residuals are not weighted by it (multiplicative noise). */,
    BRDFFIT_OPT_SCALE_MEMORY = 11,  /**< Marquardt scaling only: 1 = each entry of D is the largest diag(J^T J)_jj met since the start of the attempt, as MINPACK and GSL keep the running maximum of the column norms, so a parameter whose column shrinks on the way (one passing through zero) keeps its scale; when every free entry exceeds its diag(J^T J)_jj by more than 1e8 (the scale of the whole problem has changed, as on the way from a far start) all entries are divided by the smallest such ratio, keeping their proportions (default); 0 = diag(J^T J) at the current point, floored (::BRDFFIT_OPT_DIAG_FLOOR; the BRDF fits set 0). Either way each entry depends on its own column alone. */
    BRDFFIT_OPT_STEP_TEST = 12,     /**< Which step test ::BRDFFIT_OPT_XTOL applies: 0 = per parameter, |step_j| <= xtol * (|x_j| + xtol) for every j (default); 1 = in the scaling D, as MINPACK's xtol: ||D^1/2 step|| <= xtol * ||D^1/2 x||. */
    BRDFFIT_OPT_STEP_CONTROL = 13,  /**< 0 = lambda is the damping policy's alone (default); 1 = Moré's rules as well (MINPACK's lmder): after a rejected step whose cost is known, lambda rises at least until the step is no longer than the minimiser of the quadratic through the cost, its slope and the trial's cost (0.1 to 0.5 of the rejected step, lengths in the scaling D); after a step with gain ratio above 0.75, lambda falls by factors of 10 while the next step stays within twice the length of the last. Fewer evaluations where the start needs damping and the end none (the BRDF fits set 1, with ::BRDFFIT_OPT_START_RADIUS and ::BRDFFIT_OPT_COST_LOOKAHEAD; docs/nist-strd.md); not the default, as it solves fewer certified runs (MGH 91 -> 90: two lost, one gained). */
    BRDFFIT_OPT_START_RADIUS = 14,  /**< 0 = lambda starts where the damping policy puts it (default); > 0 = Moré's initial trust region (MINPACK's factor): the policy's start lambda is raised, if need be, until the first step is no longer than this value times the start point's length ||D^1/2 x0||, both in the scaling D and over the parameters that are not 0 at the start (a parameter at 0 has no length to compare its step with; when all are 0 the policy's start stands). Every attempt starts so. */
    BRDFFIT_OPT_COST_LOOKAHEAD = 15 /**< 0 = the small-reduction test (::BRDFFIT_OPT_FTOL) judges the step just taken (default); 1 = also the step about to be tried: when the model promises a reduction of at most ftol * cost for it, the run ends with ::BRDFFIT_STOP_COST without evaluating it. Saves the last evaluation of a converging run; the default keeps it, which a certified run's last digits may need. */
} brdffit_optim_setting;

/** @brief Why a run ended. Values are fixed forever. */
typedef enum brdffit_stop_reason {
    BRDFFIT_STOP_NONE = 0,          /**< No run yet, or the run failed with an error. */
    BRDFFIT_STOP_GRADIENT = 1,      /**< Small gradient (BRDFFIT_OPT_GTOL). */
    BRDFFIT_STOP_STEP = 2,          /**< Small step (BRDFFIT_OPT_XTOL). */
    BRDFFIT_STOP_COST = 3,          /**< Small relative cost reduction (BRDFFIT_OPT_FTOL). */
    BRDFFIT_STOP_MAX_ITERATIONS = 4,/**< Iteration limit reached. */
    BRDFFIT_STOP_MAX_EVALUATIONS = 5,/**< Evaluation limit reached. */
    BRDFFIT_STOP_CANCELLED = 6,     /**< brdffit_optimizer_cancel() was called. */
    BRDFFIT_STOP_CALLBACK = 7,      /**< The iteration callback asked to stop. */
    BRDFFIT_STOP_ZERO_COST = 8,     /**< The cost reached zero (below DBL_MIN). */
    BRDFFIT_STOP_STALLED = 9        /**< Not converged: the run ended on a small step, reduction or gradient, or a zero cost, at a point that is no solution: the problem no longer depends on a free parameter (its Jacobian column is zero, or fell below DBL_EPSILON of the largest it had in the run, and times the largest magnitude the parameter had it is below DBL_EPSILON of the largest such column): a plateau where a parameter ran away; or, after a small step or reduction, the point is not stationary (the undamped step still moves a parameter by more than 1e-6 of its scale and promises more than 1e-6 of the cost). The point returned is the best one found (see ::BRDFFIT_OPT_RESTART_BOUND). */
} brdffit_stop_reason;

/**
 * @brief What the iteration callback sees. Valid only during the callback;
 *        fields are only ever appended.
 */
typedef struct brdffit_iteration {
    size_t struct_size;  /**< sizeof the struct as the library knows it. */
    size_t iteration;    /**< 1-based iteration number, counted across a restart (::BRDFFIT_OPT_RESTART_BOUND): it can exceed brdffit_optimizer_iterations(), which counts the returned attempt only. */
    int accepted;        /**< 1 if the step was accepted. */
    double cost;         /**< Cost at the current (accepted) point. */
    double lambda;       /**< Damping after this iteration. */
    double rho;          /**< Gain ratio of the step (NaN if not evaluable). */
    const double *x;     /**< Current parameters. */
    size_t n_params;     /**< Number of parameters. */
} brdffit_iteration;

/**
 * @brief Called after every iteration. Return non-zero to stop the run
 *        (::BRDFFIT_STOP_CALLBACK).
 */
typedef int (*brdffit_iteration_fn)(const brdffit_iteration *info, void *user);

#ifdef __cplusplus
extern "C" {
#endif

/** @brief The thesis's policy: start 1e-3, double on rejection up to 1, halve on acceptance down to 1e-4. Static; thread-safe. */
BRDFFIT_API const brdffit_damping *brdffit_damping_thesis(void);
/** @brief Marquardt's policy: start 1e-3, x10 on rejection, /10 on acceptance. Static; thread-safe. */
BRDFFIT_API const brdffit_damping *brdffit_damping_marquardt(void);
/** @brief Nielsen's policy (levmar, GSL): on acceptance lambda *= max(1/3, 1 - (2 rho - 1)^3), nu = 2; on rejection lambda *= nu, nu *= 2. Start 1e-3. The default. Static; thread-safe. */
BRDFFIT_API const brdffit_damping *brdffit_damping_nielsen(void);

/**
 * @brief Create an optimizer for @p n_params parameters.
 * @param[out] out Receives the optimizer (owned by the caller).
 * @param n_params Number of parameters, 1 .. 4096.
 * @param alloc    Allocator, or NULL.
 * @param[out] err NULL, or the detail on failure.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT;
 *         ::BRDFFIT_E_OUT_OF_MEMORY. Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_optimizer_create(brdffit_optimizer **out, size_t n_params,
                                                    const brdffit_allocator *alloc,
                                                    brdffit_error *err);

/** @brief Destroy an optimizer. NULL is a no-op. */
BRDFFIT_API void brdffit_optimizer_destroy(brdffit_optimizer *opt);

/** @brief Number of parameters; 0 for NULL. */
BRDFFIT_API size_t brdffit_optimizer_param_count(const brdffit_optimizer *opt);

/**
 * @brief The message of the last failed call on @p opt, owned by the
 *        optimizer and valid until the next call on it; "" after success.
 *        Never NULL.
 */
BRDFFIT_API const char *brdffit_optimizer_message(const brdffit_optimizer *opt);

/**
 * @brief Give the problem in residual form (replaces any earlier problem).
 * @param opt    The optimizer.
 * @param n_rows Number of residuals, >= 1.
 * @param fn     The callback.
 * @param user   Passed to @p fn; borrowed.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT;
 *         ::BRDFFIT_E_OUT_OF_MEMORY (the optimizer keeps room for n_rows
 *         residuals and the n_rows x p Jacobian; on failure the earlier
 *         problem stays).
 */
BRDFFIT_API brdffit_status brdffit_optimizer_set_residuals(brdffit_optimizer *opt,
                                                           size_t n_rows,
                                                           brdffit_residual_fn fn, void *user);

/**
 * @brief Give the problem in normal-equation form (replaces any earlier
 *        problem).
 * @param opt    The optimizer.
 * @param n_rows Number of residual rows the sums run over (used for the
 *               residual variance in the covariance), >= 1.
 * @param fn     The callback.
 * @param user   Passed to @p fn; borrowed.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT.
 */
BRDFFIT_API brdffit_status brdffit_optimizer_set_normal(brdffit_optimizer *opt, size_t n_rows,
                                                        brdffit_normal_fn fn, void *user);

/**
 * @brief Set the damping policy (copied; its @c user is borrowed).
 *        NULL restores the default, brdffit_damping_nielsen(). The
 *        policy's state (@c state_size bytes) is allocated here and zeroed
 *        at the start of every run.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT for an incomplete policy
 *         (@c struct_size too small, or @c init, @c accept or @c reject
 *         NULL); ::BRDFFIT_E_OUT_OF_MEMORY when the state cannot be
 *         allocated (the earlier policy stays).
 */
BRDFFIT_API brdffit_status brdffit_optimizer_set_damping(brdffit_optimizer *opt,
                                                         const brdffit_damping *policy);

/**
 * @brief Set a numeric setting (see ::brdffit_optim_setting for meaning and
 *        default). A value of 0 restores the default, except for the
 *        settings that take 0 or 1 (::BRDFFIT_OPT_SCALING,
 *        ::BRDFFIT_OPT_COVARIANCE, ::BRDFFIT_OPT_SCALE_MEMORY,
 *        ::BRDFFIT_OPT_STEP_TEST, ::BRDFFIT_OPT_STEP_CONTROL), where 0
 *        selects the first choice.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT for an unknown setting
 *         or a negative, non-finite or non-integral (for limits) value.
 */
BRDFFIT_API brdffit_status brdffit_optimizer_set(brdffit_optimizer *opt,
                                                 brdffit_optim_setting setting, double value);

/** @brief Read a numeric setting. @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT. */
BRDFFIT_API brdffit_status brdffit_optimizer_get(const brdffit_optimizer *opt,
                                                 brdffit_optim_setting setting, double *value);

/**
 * @brief Set box bounds (copied). Either pointer may be NULL for no bound on
 *        that side; entries may be -HUGE_VAL / HUGE_VAL. lower == upper
 *        pins a parameter.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT when lower > upper,
 *         an entry is NaN, a lower bound is +HUGE_VAL or an upper bound
 *         -HUGE_VAL (nothing changes then).
 */
BRDFFIT_API brdffit_status brdffit_optimizer_set_bounds(brdffit_optimizer *opt,
                                                        const double *lower,
                                                        const double *upper);

/**
 * @brief Hold parameters fixed (copied): non-zero entries of @p mask keep
 *        that parameter at its start value (moved onto the box first, if
 *        outside). NULL frees all.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT.
 */
BRDFFIT_API brdffit_status brdffit_optimizer_set_fixed(brdffit_optimizer *opt,
                                                       const unsigned char *mask);

/**
 * @brief Set the per-iteration callback (NULL removes it); @p user borrowed.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT.
 */
BRDFFIT_API brdffit_status brdffit_optimizer_set_callback(brdffit_optimizer *opt,
                                                          brdffit_iteration_fn fn, void *user);

/**
 * @brief Ask a run to stop. Any thread may call this at any time; the run in
 *        progress (or the next one, if none is) stops before its next
 *        iteration with ::BRDFFIT_STOP_CANCELLED. The request is consumed
 *        when a run ends.
 */
BRDFFIT_API void brdffit_optimizer_cancel(brdffit_optimizer *opt);

/**
 * @brief Run the optimizer.
 *
 * @param opt The optimizer.
 * @param[in,out] x The p start values in; the best point found out (also
 *                  when a limit, a cancel or the callback ended the run).
 *                  Start values outside the bounds are moved onto them.
 * @return ::BRDFFIT_OK when the run ended for one of the reasons of
 *         ::brdffit_stop_reason (read it with brdffit_optimizer_stop_reason());
 *         ::BRDFFIT_E_NOT_READY when no problem was set;
 *         ::BRDFFIT_E_NONFINITE when a start value is NaN (or infinite
 *         after projection onto the box), or the start point gives NaN or
 *         Inf, the message naming the quantity and index;
 *         ::BRDFFIT_E_CALLBACK_FAILED when the problem fails at the start
 *         point (the message names the callback's status) or returns a
 *         negative cost; ::BRDFFIT_E_INVALID_ARGUMENT;
 *         ::BRDFFIT_E_OUT_OF_MEMORY when the iteration history cannot be
 *         allocated (it starts with room for min(max iterations + 1, 1024)
 *         entries, kept between runs, and doubles when needed).
 *         On error @p x is unchanged and brdffit_optimizer_message() says why.
 *         Any pending cancel request is consumed when the run ends.
 */
BRDFFIT_API brdffit_status brdffit_optimizer_run(brdffit_optimizer *opt, double *x);

/** @brief Why the last run ended; ::BRDFFIT_STOP_NONE before a run or after a failed one. */
BRDFFIT_API brdffit_stop_reason brdffit_optimizer_stop_reason(const brdffit_optimizer *opt);

/**
 * @brief Whether the last run converged: it ended with
 *        ::BRDFFIT_STOP_GRADIENT, ::BRDFFIT_STOP_STEP, ::BRDFFIT_STOP_COST or
 *        ::BRDFFIT_STOP_ZERO_COST. 0 for a run that stalled
 *        (::BRDFFIT_STOP_STALLED), hit a limit, was cancelled or stopped by
 *        its callback; 0 before a run, after a failed one and for NULL or a
 *        destroyed handle. Only the returned point's standing as a solution
 *        is judged, not whether it is the global minimum.
 */
BRDFFIT_API int brdffit_optimizer_converged(const brdffit_optimizer *opt);

/** @brief A short static description of a stop reason. Never NULL. Thread-safe. */
BRDFFIT_API const char *brdffit_stop_reason_string(brdffit_stop_reason reason);

/** @brief Cost at the start point of the last run; NaN before a run. */
BRDFFIT_API double brdffit_optimizer_initial_cost(const brdffit_optimizer *opt);

/** @brief Cost at the returned point of the last run; NaN before a run. */
BRDFFIT_API double brdffit_optimizer_final_cost(const brdffit_optimizer *opt);

/** @brief Iterations (accepted and rejected steps) of the last run; after a
 *         restart (::BRDFFIT_OPT_RESTART_BOUND) those of the attempt
 *         returned only, so the iteration callback, called after every
 *         iteration of both attempts, may have been called more often. */
BRDFFIT_API size_t brdffit_optimizer_iterations(const brdffit_optimizer *opt);

/** @brief Problem evaluations of the last run: exactly the number of calls
 *         of the problem callback during brdffit_optimizer_run(), in either
 *         form. They are the start point, each trial point, the
 *         derivatives at each accepted point (residual form), after a
 *         restart (::BRDFFIT_OPT_RESTART_BOUND) the second start and, when
 *         the first attempt is returned, one more at its point, and the
 *         sandwich covariance's evaluation (::BRDFFIT_OPT_COVARIANCE 1,
 *         residual form); both attempts of a restarted run count. */
BRDFFIT_API size_t brdffit_optimizer_evaluations(const brdffit_optimizer *opt);

/** @brief The last iteration that lowered the cost; 0 if none did. */
BRDFFIT_API size_t brdffit_optimizer_last_improvement(const brdffit_optimizer *opt);

/** @brief Whether any step of the last run fell back from Cholesky to the eigen-decomposition. */
BRDFFIT_API int brdffit_optimizer_used_fallback(const brdffit_optimizer *opt);

/**
 * @brief Cost and lambda per iteration of the last run.
 * @param opt      The optimizer.
 * @param[out] cost NULL, or brdffit_optimizer_iterations() + 1 values: the
 *                 start cost, then the cost after each iteration.
 * @param[out] lambda NULL, or brdffit_optimizer_iterations() + 1 values: the
 *                 start lambda, then lambda after each iteration.
 * @return The number of values (iterations + 1); 0 before a run.
 */
BRDFFIT_API size_t brdffit_optimizer_history(const brdffit_optimizer *opt, double *cost,
                                             double *lambda);

/**
 * @brief Estimate of the 2-norm condition number of J^T J at the returned
 *        point, over the parameters neither fixed nor on a bound: the ratio
 *        of its extreme eigenvalues (Jacobi, computed on demand, O(p^3));
 *        HUGE_VAL when singular, 1 when no parameter is free, NaN before a
 *        run or after a failed one.
 */
BRDFFIT_API double brdffit_optimizer_condition(const brdffit_optimizer *opt);

/**
 * @brief Covariance of the parameters at the returned point, over the free
 *        parameters; rows and columns of fixed parameters, and of
 *        parameters on a bound, are 0.
 *
 * Classic (::BRDFFIT_OPT_COVARIANCE 0, the default): s^2 (J^T J)^+ with
 * s^2 = cost / (n_rows - n_free). It assumes independent residuals of one
 * common variance (or residuals already divided by their standard
 * deviations, as a weighted fit provides): it is wrong when the noise
 * level varies between rows, e.g. multiplicative noise on unweighted
 * residuals; when n_rows <= n_free, s^2 = 1. Sandwich (1, HC3):
 * (J^T J)^+ (sum_i (r_i / (1 - h_i))^2 J_i J_i^T) (J^T J)^+ with the
 * leverages h_i = J_i (J^T J)^+ J_i^T, which assumes only independent
 * residuals (residual form only). docs/optimizer.md shows which one
 * covers the true values as often as it claims for which noise.
 *
 * The pseudo-inverse is taken after scaling J^T J to unit diagonal
 * (it equals the inverse when J^T J is nonsingular) and drops eigenvalues
 * below 1e-14 of the largest. A free parameter the data do not determine
 * (a zero or vanished Jacobian column, or a direction at least 1 % of
 * which lies in the dropped eigenspace) has variance HUGE_VAL and 0
 * covariance with the others; never 0, never NaN.
 * Computed on demand, O(p^3); the classic covariance of a J^T J made of
 * small blocks coupled only through a few parameters (a fit of many
 * channels) in linear time, with the same result (docs/optimizer.md).
 * @param opt The optimizer.
 * @param[out] cov p x p values, row-major.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_NOT_READY before a successful run;
 *         ::BRDFFIT_E_INVALID_ARGUMENT for NULL, or when the run was asked
 *         for the sandwich but had the normal-equation form (or its rows
 *         could not be evaluated at the returned point).
 */
BRDFFIT_API brdffit_status brdffit_optimizer_covariance(const brdffit_optimizer *opt,
                                                        double *cov);

/**
 * @brief Standard errors: the square roots of the covariance diagonal;
 *        HUGE_VAL for a parameter the data do not determine, 0 for fixed
 *        ones and those on a bound.
 * @param opt The optimizer.
 * @param[out] se p values.
 * @return As brdffit_optimizer_covariance().
 */
BRDFFIT_API brdffit_status brdffit_optimizer_std_errors(const brdffit_optimizer *opt,
                                                        double *se);

#ifdef __cplusplus
}
#endif

/** @} */

#endif /* BRDFFIT_OPTIM_H */
