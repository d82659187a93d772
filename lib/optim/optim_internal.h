/* The optimizer handle and the internal interface between its files:
 * optimizer.c (the handle, the problem, the policy), settings.c (settings,
 * bounds, fixed parameters, callback), results.c (results of a run),
 * lm.c (the run loop), classify.c (gradient test, converged or stalled),
 * eval.c (problem evaluation), step.c (the damped, bounded step) and
 * analysis.c (condition and covariance at the end of a run). */
#ifndef BRDFFIT_OPTIM_INTERNAL_H
#define BRDFFIT_OPTIM_INTERNAL_H

#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>

#include "brdffit/optim.h"

#define BF_OPTIM_MAX_PARAMS 4096
/* Damping is clamped to this range after every policy call. */
#define BF_LAMBDA_MIN 1e-300
#define BF_LAMBDA_MAX 1e300
/* Absolute floor of the diagonal scaling entries. */
#define BF_SCALE_ABS_FLOOR 1e-300
/* The scale memory starts again when every free entry of D exceeds its
 * diag(J^T J) by more than this factor (step.c). */
#define BF_SCALE_RESET 1e8

typedef enum bf_form { BF_FORM_NONE = 0, BF_FORM_RESIDUALS = 1, BF_FORM_NORMAL = 2 } bf_form;

typedef struct bf_optim_settings {
    double gtol, xtol, ftol, diag_floor, step_bound, restart_bound;
    double start_radius; /* > 0: the first step within it times |D^1/2 x0| (lm.c) */
    size_t max_iterations, max_evaluations;
    int marquardt;    /* 1: D = diag(J^T J), 0: D = d0 I */
    int sandwich;     /* covariance: 1 sandwich, 0 classic */
    int scale_memory; /* 1: D keeps the largest diag(J^T J) of the run, 0: the current one */
    int step_test;    /* 0: per parameter, 1: ||D^1/2 step|| against ||D^1/2 x|| */
    int step_control; /* 1: lambda also follows the step length (lm.c) */
    int cost_lookahead; /* 1: a step promising at most ftol * cost ends the run untried */
} bf_optim_settings;

typedef struct bf_optim_result {
    int valid; /* the last run ended with BRDFFIT_OK */
    brdffit_stop_reason stop;
    double initial_cost, final_cost;
    size_t iterations, evaluations, last_improvement, history_len;
    size_t n_rows; /* of the problem the run solved */
    int used_fallback;
    int want_sandwich; /* the run was asked for the sandwich covariance */
    int sandwich;      /* and prepared it (w.meat) */
} bf_optim_result;

/* Workspace sized by n_params, carved from one block made at create.
 * After a run, jtj (J^T J at the returned point) and analysed stay valid
 * until the next run; the scratch arrays (trial, step, delta, scale, w,
 * tmp, jtj_new, m, v, free_idx, held) may then be overwritten by the
 * result accessors, even through a const handle. */
typedef struct bf_optim_work {
    /* p values each */
    double *x;     /* current (best) point */
    double *trial; /* trial point */
    double *g;     /* J^T r at x */
    double *g_new; /* J^T r at an accepted trial point, before the swap */
    double *step;  /* step actually taken, trial - x */
    double *delta; /* solution of the reduced damped system */
    double *d;     /* diagonal scaling D */
    double *scale; /* equilibration 1 / sqrt(diag) of the reduced system */
    double *w;     /* eigenvalues */
    double *tmp;   /* scratch */
    double *lower, *upper;
    double *xscale; /* largest |x_j| of the run so far (the start included) */
    double *amax;   /* largest diag(J^T J)_jj of the attempt so far (the start included) */
    double *best;   /* the point a stalled attempt ended at */
    /* p x p values each */
    double *jtj;     /* J^T J at x */
    double *jtj_new; /* J^T J at an accepted trial point */
    double *m;       /* reduced damped matrix and its factor */
    double *v;       /* eigenvectors */
    double *meat;    /* after a run: sum r_i^2 J_i J_i^T, for the sandwich */
    size_t *free_idx;
    size_t *order, *group, *pos; /* after a run: the block structure (blocks.c) */
    unsigned char *fixed, *held;
    unsigned char *analysed; /* after a run: neither fixed nor on a bound */
} bf_optim_work;

/* The last step computed (step.c): its arguments, and what it reported;
 * valid until the point, J^T J, J^T r or the scaling D change
 * (bf_optim_forget_step()). */
typedef struct bf_step_memo {
    double lambda, t, bound;
    int valid, bounded, fallback;
    /* the smallest pivot of the equilibrated Cholesky factor when the
     * step is the damped system's solution itself (no parameter held on
     * a bound by its sign, no bound on the step, no projection onto the
     * box, no eigen fallback); else 0 */
    double pivot;
} bf_step_memo;

struct brdffit_optimizer {
    uint32_t magic;
    brdffit_allocator alloc;
    size_t n_params;

    bf_form form;
    size_t n_rows;
    brdffit_residual_fn residual_fn;
    brdffit_normal_fn normal_fn;
    void *user;
    double *r, *jac; /* residual form: n_rows, and n_rows x p values */

    brdffit_damping policy;
    void *policy_state; /* policy.state_size bytes, zeroed at every run */

    bf_optim_settings settings;
    brdffit_iteration_fn callback;
    void *callback_user;

    atomic_int cancel;       /* set by brdffit_optimizer_cancel(), any thread */
    const atomic_int *watch; /* bf_optim_watch(): another cancel flag, or NULL */
    int running;             /* a run is in progress (calls from callbacks) */

    void *block; /* the workspace block */
    bf_optim_work w;
    bf_step_memo memo; /* the step in w.trial and w.step */
    double *history; /* cost[history_cap] then lambda[history_cap] */
    size_t history_cap;

    bf_optim_result res;
    brdffit_error err; /* message of the last failed call; "" after success */
};

/* optimizer.c: BRDFFIT_OK after clearing the handle's message. */
brdffit_status bf_optim_ok(brdffit_optimizer *opt);
/* optimizer.c: BRDFFIT_E_INVALID_ARGUMENT for NULL, BRDFFIT_E_BAD_HANDLE
 * for a destroyed or foreign handle. */
brdffit_status bf_optim_check_handle(const brdffit_optimizer *opt);
/* optimizer.c: as above, and not from inside the optimizer's own run
 * (what names the call in the message). */
brdffit_status bf_optim_check_mutable(brdffit_optimizer *opt, const char *what);
/* settings.c: the default settings. */
void bf_optim_default_settings(bf_optim_settings *s);

/* optimizer.c: record a failure on the handle and return status. */
brdffit_status bf_optim_fail(brdffit_optimizer *opt, brdffit_status status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* lm.c: the run behind brdffit_optimizer_run() (arguments checked). */
brdffit_status bf_lm_run(brdffit_optimizer *opt, double *x);

/* eval.c: evaluate the problem at x. Always the cost; with derivs also
 * J^T J (jtj, both triangles, symmetric) and J^T r (g). Returns BRDFFIT_OK;
 * BRDFFIT_E_CALLBACK_FAILED when the callback failed or broke its contract
 * (a negative cost); BRDFFIT_E_NONFINITE for NaN or Inf. When what is not
 * NULL a failure is described there (which quantity, which index). */
brdffit_status bf_optim_eval(brdffit_optimizer *opt, const double *x, int derivs, double *cost,
                             double *jtj, double *g, char *what, size_t what_size);

/* step.c: the diagonal scaling D for the current J^T J (Marquardt) or the
 * constant d0 (Levenberg, set_d0 at the start of an attempt). With the
 * scale memory, Marquardt's entries keep the largest value they had since
 * the start of the attempt (set_d0). Also keeps w.amax, the largest
 * diag(J^T J) of the attempt, whatever the scaling. */
void bf_optim_update_scaling(brdffit_optimizer *opt, int set_d0);

/* step.c: the step for damping lambda, shortened by factor t, with
 * parameters at a bound held where they would leave the box. Fills
 * w.trial (inside the box) and w.step = trial - x, and returns the
 * reduction of the cost the linear model predicts for that step. Sets
 * *fallback when the eigen-decomposition replaced Cholesky. */
double bf_optim_step(brdffit_optimizer *opt, double lambda, double t, double bound, int *bounded,
                     int *fallback);

/* step.c: bf_optim_step() without the predicted reduction (the step
 * searches of lm.c look at the step's length only). A step asked for
 * again with the same arguments (a lambda of the same damping,
 * bf_optim_same_damping()) is not solved again: the step searches leave
 * the one for the lambda they choose, which the next iteration takes. */
void bf_optim_step_only(brdffit_optimizer *opt, double lambda, double t, double bound,
                        int *bounded, int *fallback);

/* step.c: lambdas l1 and l2 give every parameter that is not fixed the
 * same diagonal of A + lambda D, to the bit, and so the same step (at a
 * small lambda against diag(A) a tenth of it changes nothing). */
int bf_optim_same_damping(const brdffit_optimizer *opt, double l1, double l2);

/* step.c: the point, J^T J, J^T r or D changed: the step in w.trial and
 * w.step is no longer the one for the current arguments. */
void bf_optim_forget_step(brdffit_optimizer *opt);

/* step.c: whether parameter j sits on its lower or upper bound. */
int bf_optim_on_bound(const brdffit_optimizer *opt, size_t j, const double *x);

/* classify.c: the gradient test at the current point (see lm.c). */
int bf_optim_gradient_small(const brdffit_optimizer *opt, double cost);

/* classify.c: parameter j's Jacobian column vanished at the current point:
 * it is zero, or its norm is below DBL_EPSILON times the largest of the
 * attempt, and its sensitivity to a relative change of the parameter is
 * below DBL_EPSILON times the largest of the analysed parameters (needs
 * bf_optim_mark_analysed()). */
int bf_optim_vanished(const brdffit_optimizer *opt, size_t j);

/* classify.c: the stop reason to report for a run that ended with stop at
 * the current point (cost the cost there): BRDFFIT_STOP_STALLED instead
 * of a small step, reduction or gradient where a free parameter's
 * Jacobian column vanished, and instead of a small step or reduction
 * where the point is not stationary. Needs bf_optim_mark_analysed()
 * first; overwrites the step's scratch. */
brdffit_stop_reason bf_optim_classify(brdffit_optimizer *opt, brdffit_stop_reason stop,
                                      double cost);

/* analysis.c: at the end of a run, mark the parameters the condition
 * number and the covariance are taken over. */
void bf_optim_mark_analysed(brdffit_optimizer *opt);

/* analysis.c: condition number of J^T J at the returned point. */
double bf_optim_condition(const brdffit_optimizer *opt);

/* analysis.c: covariance (p x p) at the returned point into cov. */
int bf_optim_covariance(const brdffit_optimizer *opt, double *cov);
/* analysis.c: the rows' outer products at the returned point into w.meat
 * (residual form; one more evaluation); 0 when it cannot be evaluated. */
int bf_optim_prepare_sandwich(brdffit_optimizer *opt);
/* analysis.c: standard errors (p) at the returned point into se. Both
 * return 0 when the watched flag (bf_optim_watch()) stopped them. */
int bf_optim_std_errors(const brdffit_optimizer *opt, double *se);
/* analysis.c: both of the above from one pseudo-inverse (the same
 * values, bit for bit); 0 when the watched flag stopped it (se then 0). */
int bf_optim_errors(const brdffit_optimizer *opt, double *se, double *cov);
/* analysis.c: the factor s^2 of the classic covariance over n analysed
 * parameters. */
double bf_optim_classic_factor(const brdffit_optimizer *opt, size_t n);

/* blocks.c: the classic covariance and standard errors from the block
 * structure of J^T J (many channels) in linear time; 0 (nothing written)
 * when there is no such structure or the result could differ from the
 * dense path's, which the caller then takes. */
int bf_blocks_covariance(const brdffit_optimizer *opt, double *cov);
int bf_blocks_std_errors(const brdffit_optimizer *opt, double *se);

/* watch.c: whether a run should stop (brdffit_optimizer_cancel() or the
 * watched flag), and whether the watched flag alone is set. */
int bf_optim_stopped(const brdffit_optimizer *opt);
int bf_optim_watched_stop(const brdffit_optimizer *opt);

#endif /* BRDFFIT_OPTIM_INTERNAL_H */
