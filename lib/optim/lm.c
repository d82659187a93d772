/* The Levenberg-Marquardt run loop (docs/definitions.md, The damped step).
 *
 * One iteration: compute the damped, bounded step (step.c); if it is
 * small, stop; evaluate the cost alone at the trial point; if it is lower,
 * evaluate J^T J and J^T r there and move (accepted), else stay
 * (rejected); let the damping policy update lambda; record the history;
 * call the iteration callback; test the relative reduction. A trial point
 * the problem cannot evaluate (callback failure, NaN or Inf) is a rejected
 * step with rho = NaN. When a rejection leaves lambda where it was (a
 * policy at its cap), the next step is halved, so that every iteration
 * tries a new point and the step test ends the run eventually. Nothing
 * here allocates except the history, and that only when a run needs more
 * than the capacity it started with. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "core/core.h"
#include "optim/optim_internal.h"

enum { BF_HISTORY_START = 1024 };

typedef struct lm_run {
    brdffit_optimizer *opt;
    double cost; /* at the current point */
    double lambda;
    double t;           /* step factor, < 1 only while rejections leave lambda unchanged */
    double rho;         /* gain ratio of the last step */
    double actual;      /* cost reduction of the last accepted step */
    double pred;        /* predicted reduction of the last step */
    double cost_before; /* cost before the last accepted step */
    size_t iterations, evaluations, last_improvement;
    int accepted, fallback;
} lm_run;

static double clamp_lambda(double lambda, double previous)
{
    if (isnan(lambda)) return previous;
    if (lambda < BF_LAMBDA_MIN) return BF_LAMBDA_MIN;
    if (lambda > BF_LAMBDA_MAX) return BF_LAMBDA_MAX;
    return lambda;
}

/* Euclidean norm without overflow for large entries. */
static double norm2(const double *v, size_t n)
{
    double m = 0.0, s = 0.0;
    size_t i;
    for (i = 0; i < n; i++)
        if (fabs(v[i]) > m) m = fabs(v[i]);
    if (m == 0.0 || !isfinite(m)) return m;
    for (i = 0; i < n; i++) s += (v[i] / m) * (v[i] / m);
    return m * sqrt(s);
}

/* --- history ---------------------------------------------------------------- */

static brdffit_status history_reserve(brdffit_optimizer *opt, size_t need)
{
    size_t cap, bytes;
    double *h;
    if (need <= opt->history_cap) return BRDFFIT_OK;
    cap = opt->history_cap * 2;
    if (cap < need) cap = need;
    if (cap > opt->settings.max_iterations + 1 && need <= opt->settings.max_iterations + 1)
        cap = opt->settings.max_iterations + 1;
    if (!bf_mul_size(cap, 2 * sizeof(double), &bytes) ||
        (h = bf_malloc(&opt->alloc, bytes)) == NULL)
        return bf_optim_fail(opt, BRDFFIT_E_OUT_OF_MEMORY,
                             "run: cannot allocate the history of %zu iterations", cap);
    if (opt->history != NULL) {
        memcpy(h, opt->history, opt->history_cap * sizeof *h);
        memcpy(h + cap, opt->history + opt->history_cap, opt->history_cap * sizeof *h);
    }
    bf_free(&opt->alloc, opt->history);
    opt->history = h;
    opt->history_cap = cap;
    return BRDFFIT_OK;
}

static brdffit_status history_push(lm_run *run)
{
    brdffit_optimizer *opt = run->opt;
    size_t i = run->iterations;
    BF_RETURN_IF_ERROR(history_reserve(opt, i + 1));
    opt->history[i] = run->cost;
    opt->history[opt->history_cap + i] = run->lambda;
    return BRDFFIT_OK;
}

/* --- stopping tests ----------------------------------------------------------- */

/* max_j |g_j| / sqrt(A_jj cost) <= gtol, over the components that may move
 * (not fixed, not pushing out of a bound): the cosine of the angle between
 * the residual vector and each Jacobian column, which neither the units of
 * the parameters nor those of the residuals change. A zero column never
 * passes; with no component free to move the test passes. */
static int gradient_small(const lm_run *run)
{
    const brdffit_optimizer *opt = run->opt;
    const bf_optim_work *w = &opt->w;
    const double scale = opt->settings.gtol * sqrt(run->cost);
    size_t j, p = opt->n_params;
    for (j = 0; j < p; j++) {
        double x = w->x[j], g = w->g[j], a = w->jtj[j * p + j];
        if (w->fixed[j] || (x <= w->lower[j] && g > 0.0) || (x >= w->upper[j] && g < 0.0)) continue;
        if (!(a > 0.0) || !(fabs(g) <= scale * sqrt(a))) return 0;
    }
    return 1;
}

static brdffit_stop_reason check_before(const lm_run *run)
{
    const brdffit_optimizer *opt = run->opt;
    if (atomic_load(&run->opt->cancel)) return BRDFFIT_STOP_CANCELLED;
    if (run->cost < DBL_MIN) return BRDFFIT_STOP_ZERO_COST;
    if (gradient_small(run)) return BRDFFIT_STOP_GRADIENT;
    if (run->iterations >= opt->settings.max_iterations) return BRDFFIT_STOP_MAX_ITERATIONS;
    /* a step needs room for the trial and the derivatives there */
    if (run->evaluations + 2 > opt->settings.max_evaluations) return BRDFFIT_STOP_MAX_EVALUATIONS;
    return BRDFFIT_STOP_NONE;
}

static int step_small(const brdffit_optimizer *opt)
{
    size_t p = opt->n_params;
    double xtol = opt->settings.xtol;
    return norm2(opt->w.step, p) <= xtol * (norm2(opt->w.x, p) + xtol);
}

/* The accepted step lowered the cost by at most ftol * cost, and the
 * model did not promise more. */
static int reduction_small(const lm_run *run)
{
    double limit = run->opt->settings.ftol * run->cost_before;
    return run->actual <= limit && run->pred <= limit;
}

/* --- one iteration -------------------------------------------------------------- */

static void swap(double **a, double **b)
{
    double *t = *a;
    *a = *b;
    *b = t;
}

/* Evaluate the trial point; move there when the cost is lower and the
 * derivatives there can be computed. Returns whether the step was
 * accepted; sets run->rho. */
static int try_step(lm_run *run)
{
    brdffit_optimizer *opt = run->opt;
    bf_optim_work *w = &opt->w;
    double cost_trial, cost_new;
    run->rho = 0.0;
    if (!(run->pred > 0.0)) return 0; /* the model sees no gain: not evaluated */
    run->evaluations++;
    if (bf_optim_eval(opt, w->trial, 0, &cost_trial, NULL, NULL, NULL, 0) != BRDFFIT_OK) {
        run->rho = NAN;
        return 0;
    }
    run->rho = (run->cost - cost_trial) / run->pred;
    if (!(cost_trial < run->cost)) return 0;
    run->evaluations++;
    if (bf_optim_eval(opt, w->trial, 1, &cost_new, w->jtj_new, w->g_new, NULL, 0) != BRDFFIT_OK) {
        run->rho = NAN;
        return 0;
    }
    swap(&w->x, &w->trial);
    swap(&w->jtj, &w->jtj_new);
    swap(&w->g, &w->g_new);
    run->cost_before = run->cost;
    run->actual = run->cost - cost_new;
    run->cost = cost_new;
    bf_optim_update_scaling(opt, 0);
    return 1;
}

static void update_lambda(lm_run *run)
{
    const brdffit_damping *policy = &run->opt->policy;
    double old = run->lambda, lambda = old;
    if (run->accepted)
        policy->accept(run->opt->policy_state, run->rho, &lambda, policy->user);
    else
        policy->reject(run->opt->policy_state, run->rho, &lambda, policy->user);
    lambda = clamp_lambda(lambda, old);
    if (run->accepted || lambda > old)
        run->t = 1.0;
    else
        run->t *= 0.5;
    run->lambda = lambda;
}

static int callback_stops(const lm_run *run)
{
    const brdffit_optimizer *opt = run->opt;
    brdffit_iteration info;
    if (opt->callback == NULL) return 0;
    memset(&info, 0, sizeof info);
    info.struct_size = sizeof info;
    info.iteration = run->iterations;
    info.accepted = run->accepted;
    info.cost = run->cost;
    info.lambda = run->lambda;
    info.rho = run->rho;
    info.x = opt->w.x;
    info.n_params = opt->n_params;
    return opt->callback(&info, opt->callback_user) != 0;
}

/* One iteration; BRDFFIT_STOP_NONE to go on. */
static brdffit_status iterate(lm_run *run, brdffit_stop_reason *stop)
{
    brdffit_optimizer *opt = run->opt;
    *stop = BRDFFIT_STOP_NONE;
    run->pred = bf_optim_step(opt, run->lambda, run->t, &run->fallback);
    if (step_small(opt)) {
        *stop = BRDFFIT_STOP_STEP;
        return BRDFFIT_OK;
    }
    run->iterations++;
    run->accepted = try_step(run);
    if (run->accepted) run->last_improvement = run->iterations;
    update_lambda(run);
    BF_RETURN_IF_ERROR(history_push(run));
    if (callback_stops(run))
        *stop = BRDFFIT_STOP_CALLBACK;
    else if (run->accepted && reduction_small(run))
        *stop = BRDFFIT_STOP_COST;
    return BRDFFIT_OK;
}

/* --- the run ----------------------------------------------------------------------- */

/* x projected onto the box into w.x; every value must be finite. */
static brdffit_status load_start(brdffit_optimizer *opt, const double *x)
{
    bf_optim_work *w = &opt->w;
    size_t j;
    for (j = 0; j < opt->n_params; j++) {
        double v = x[j];
        if (v < w->lower[j]) v = w->lower[j];
        if (v > w->upper[j]) v = w->upper[j];
        if (!isfinite(v))
            return bf_optim_fail(opt, BRDFFIT_E_NONFINITE, "run: start value x[%zu] is %g", j, v);
        w->x[j] = v;
    }
    return BRDFFIT_OK;
}

static brdffit_status start(lm_run *run, const double *x)
{
    brdffit_optimizer *opt = run->opt;
    char what[160];
    brdffit_status st;
    size_t cap = opt->settings.max_iterations + 1;
    BF_RETURN_IF_ERROR(load_start(opt, x));
    BF_RETURN_IF_ERROR(history_reserve(opt, cap < BF_HISTORY_START ? cap : BF_HISTORY_START));
    if (opt->policy.state_size > 0) memset(opt->policy_state, 0, opt->policy.state_size);
    run->lambda = 1e-3;
    opt->policy.init(opt->policy_state, &run->lambda, opt->policy.user);
    run->lambda = clamp_lambda(run->lambda, 1e-3);
    run->t = 1.0;
    run->evaluations = 1;
    opt->res.evaluations = 1;
    st = bf_optim_eval(opt, opt->w.x, 1, &run->cost, opt->w.jtj, opt->w.g, what, sizeof what);
    if (st != BRDFFIT_OK) return bf_optim_fail(opt, st, "run: %s at the start point", what);
    opt->res.initial_cost = run->cost;
    bf_optim_update_scaling(opt, 1);
    return history_push(run);
}

static void finish(lm_run *run, brdffit_stop_reason stop, double *x)
{
    brdffit_optimizer *opt = run->opt;
    bf_optim_result *res = &opt->res;
    res->stop = stop;
    res->final_cost = run->cost;
    res->iterations = run->iterations;
    res->evaluations = run->evaluations;
    res->last_improvement = run->last_improvement;
    res->used_fallback = run->fallback;
    res->history_len = run->iterations + 1;
    res->n_rows = opt->n_rows;
    bf_optim_mark_analysed(opt);
    memcpy(x, opt->w.x, opt->n_params * sizeof *x);
    res->valid = 1;
}

brdffit_status bf_lm_run(brdffit_optimizer *opt, double *x)
{
    lm_run run;
    brdffit_stop_reason stop = BRDFFIT_STOP_NONE;
    memset(&run, 0, sizeof run);
    run.opt = opt;
    BF_RETURN_IF_ERROR(start(&run, x));
    while (stop == BRDFFIT_STOP_NONE) {
        stop = check_before(&run);
        if (stop != BRDFFIT_STOP_NONE) break;
        BF_RETURN_IF_ERROR(iterate(&run, &stop));
    }
    opt->res.evaluations = run.evaluations;
    finish(&run, stop, x);
    return BRDFFIT_OK;
}
