/* The Levenberg-Marquardt run loop (docs/optimizer.md).
 *
 * One iteration: compute the damped, bounded step (step.c); if it is
 * small, stop; evaluate the cost alone at the trial point; if it is lower,
 * evaluate J^T J and J^T r there and move (accepted), else stay
 * (rejected); let the damping policy update lambda; record the history;
 * call the iteration callback; test the relative reduction. A trial point
 * the problem cannot evaluate (callback failure, NaN or Inf) is a rejected
 * step with rho = NaN. When a rejection leaves lambda where it was (a
 * policy at its cap), the next step is halved, so that every iteration
 * tries a new point and the step test ends the run eventually. With the
 * step control setting, lambda also follows the step's length after a
 * rejected or a very successful step (Moré's rules). A run
 * that ends stalled (classify.c) starts once more from the start with
 * bounded steps, and the better attempt is returned. Nothing
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
    double cost_trial;  /* cost at the last trial point (NaN if not evaluable) */
    double last_len;    /* scaled length of the last step */
    size_t iterations, evaluations, last_improvement, history_len;
    double bound; /* step bound, relative to the parameter scales */
    int accepted, bounded, fallback;
} lm_run;

static double clamp_lambda(double lambda, double previous)
{
    if (isnan(lambda)) return previous;
    if (lambda < BF_LAMBDA_MIN) return BF_LAMBDA_MIN;
    if (lambda > BF_LAMBDA_MAX) return BF_LAMBDA_MAX;
    return lambda;
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
    size_t i = run->history_len;
    BF_RETURN_IF_ERROR(history_reserve(opt, i + 1));
    opt->history[i] = run->cost;
    opt->history[opt->history_cap + i] = run->lambda;
    run->history_len = i + 1;
    return BRDFFIT_OK;
}

/* --- stopping tests ----------------------------------------------------------- */

static brdffit_stop_reason check_before(const lm_run *run)
{
    const brdffit_optimizer *opt = run->opt;
    if (bf_optim_stopped(run->opt)) return BRDFFIT_STOP_CANCELLED;
    if (run->cost < DBL_MIN) return BRDFFIT_STOP_ZERO_COST;
    if (bf_optim_gradient_small(opt, run->cost)) return BRDFFIT_STOP_GRADIENT;
    if (run->iterations >= opt->settings.max_iterations) return BRDFFIT_STOP_MAX_ITERATIONS;
    /* a step needs room for the trial and the derivatives there */
    if (run->evaluations + 2 > opt->settings.max_evaluations) return BRDFFIT_STOP_MAX_EVALUATIONS;
    return BRDFFIT_STOP_NONE;
}

/* Step test 0: every parameter's step is small against its own
 * magnitude, so a large parameter does not hide the others' progress;
 * near 0, against xtol times its scale (the largest magnitude it had in
 * the run), so that runs converging to 0 end and the test does not depend
 * on the parameters' units. Step test 1 (MINPACK's xtol): ||D^1/2 step||
 * <= xtol ||D^1/2 x||, the step and the point measured in the scaling D. */
static int step_small(const brdffit_optimizer *opt)
{
    const bf_optim_work *w = &opt->w;
    size_t j, p = opt->n_params;
    double xtol = opt->settings.xtol, ds = 0.0, dx = 0.0;
    if (opt->settings.step_test == 0) {
        for (j = 0; j < p; j++)
            if (!(fabs(w->step[j]) <= xtol * (fabs(w->x[j]) + xtol * w->xscale[j]))) return 0;
        return 1;
    }
    for (j = 0; j < p; j++) {
        double s = sqrt(w->d[j]);
        ds = hypot(ds, s * w->step[j]);
        dx = hypot(dx, s * w->x[j]);
    }
    return ds <= xtol * dx;
}

/* The accepted step lowered the cost by at most ftol * cost, and the
 * model did not promise more. */
static int reduction_small(const lm_run *run)
{
    double limit = run->opt->settings.ftol * run->cost_before;
    return run->actual <= limit && run->pred <= limit;
}

/* The cost lookahead (BRDFFIT_OPT_COST_LOOKAHEAD): the step about to be
 * tried promises a reduction, but at most ftol * cost. */
static int gain_small(const lm_run *run)
{
    return run->pred > 0.0 && run->pred <= run->opt->settings.ftol * run->cost;
}

/* --- one iteration -------------------------------------------------------------- */

static void swap(double **a, double **b)
{
    double *t = *a;
    *a = *b;
    *b = t;
}

/* The parameter scales: the largest magnitudes so far, the trial point's
 * included (it is about to become the current point). */
static void note_scale(bf_optim_work *w, size_t p)
{
    size_t j;
    for (j = 0; j < p; j++) w->xscale[j] = fmax(w->xscale[j], fabs(w->trial[j]));
}

/* Evaluate the trial point; move there when the cost is lower and the
 * derivatives there can be computed. Returns whether the step was
 * accepted; sets run->rho. The normal-equation form evaluates the trial
 * with J^T J and J^T r at once: one pass over the caller's data gives them
 * for little more than the cost alone (the fit's fused pass), so an
 * accepted step costs one evaluation, not two. The residual form
 * evaluates the cost first (its Jacobian is a callback of its own). */
static int try_step(lm_run *run)
{
    brdffit_optimizer *opt = run->opt;
    bf_optim_work *w = &opt->w;
    int fused = opt->form == BF_FORM_NORMAL;
    double cost_trial, cost_new;
    run->rho = 0.0;
    run->cost_trial = NAN;
    if (!(run->pred > 0.0)) return 0; /* the model sees no gain: not evaluated */
    run->evaluations++;
    if (bf_optim_eval(opt, w->trial, fused, &cost_trial, w->jtj_new, w->g_new, NULL, 0) !=
        BRDFFIT_OK) {
        run->rho = NAN;
        return 0;
    }
    run->cost_trial = cost_trial;
    run->rho = (run->cost - cost_trial) / run->pred;
    if (!(cost_trial < run->cost)) return 0;
    cost_new = cost_trial;
    if (!fused) run->evaluations++;
    if (!fused &&
        bf_optim_eval(opt, w->trial, 1, &cost_new, w->jtj_new, w->g_new, NULL, 0) != BRDFFIT_OK) {
        run->rho = NAN;
        return 0;
    }
    note_scale(w, opt->n_params);
    swap(&w->x, &w->trial);
    swap(&w->jtj, &w->jtj_new);
    swap(&w->g, &w->g_new);
    run->cost_before = run->cost;
    run->actual = run->cost - cost_new;
    run->cost = cost_new;
    bf_optim_update_scaling(opt, 0);
    return 1;
}

/* The length of the last step in the scaling D; with nonzero, over the
 * parameters that are not 0 at the current point only. */
static double masked_length(const bf_optim_work *w, size_t p, int nonzero)
{
    double s = 0.0;
    size_t j;
    for (j = 0; j < p; j++)
        if (!nonzero || w->x[j] != 0.0) s += w->d[j] * w->step[j] * w->step[j];
    return sqrt(s);
}

static double scaled_length(const bf_optim_work *w, size_t p)
{
    return masked_length(w, p, 0);
}

/* lambda raised (by at least 2, else by the ratio of the lengths) until
 * the step is no longer than target in the scaling D (with nonzero, over
 * the parameters not at 0). Returns the new lambda, at least lambda. */
static double raise_lambda(lm_run *run, double lambda, double target, int nonzero)
{
    brdffit_optimizer *opt = run->opt;
    const bf_optim_work *w = &opt->w;
    size_t k, p = opt->n_params;
    int bounded = 0, fallback = 0;
    if (!(target > 0.0)) return lambda;
    for (k = 0; k < 60; k++) {
        double len;
        bf_optim_step_only(opt, lambda, 1.0, run->bound, &bounded, &fallback);
        len = masked_length(w, p, nonzero);
        if (!(len > target) || lambda >= BF_LAMBDA_MAX) break;
        lambda = fmin(BF_LAMBDA_MAX, lambda * fmax(2.0, len / target));
    }
    return lambda;
}

/* Step control (BRDFFIT_OPT_STEP_CONTROL), after a rejected step whose
 * trial cost is known: the share alpha of
 * the step at which the quadratic through the cost, its slope along the
 * step and the trial's cost has its minimum, kept in [0.1, 0.5] (Moré's
 * rule in MINPACK's lmder); then lambda is raised until the step is no
 * longer than alpha times the rejected one. Returns the new lambda, at
 * least lambda. */
static double shrink_lambda(lm_run *run, double lambda)
{
    const bf_optim_work *w = &run->opt->w;
    size_t j, p = run->opt->n_params;
    double gs = 0.0, curv, alpha = 0.5;
    for (j = 0; j < p; j++) gs += w->g[j] * w->step[j];
    curv = run->cost_trial - run->cost - 2.0 * gs; /* phi(1) - phi(0) - phi'(0) */
    if (curv > 0.0 && gs < 0.0) alpha = fmin(0.5, fmax(0.1, -gs / curv));
    return raise_lambda(run, lambda, alpha * scaled_length(w, p), 0);
}

/* The start radius (BRDFFIT_OPT_START_RADIUS): the policy's start lambda
 * raised until the first step is no longer than the setting times the
 * start point's length, both in the scaling D (Moré's initial trust
 * region, MINPACK's factor) and over the parameters that are not 0: a
 * parameter at 0 has no length to compare its step with (the step bound
 * treats it so too). */
static double start_lambda(lm_run *run, double lambda)
{
    const bf_optim_work *w = &run->opt->w;
    double radius = run->opt->settings.start_radius, len = 0.0;
    size_t j;
    if (!(radius > 0.0)) return lambda;
    for (j = 0; j < run->opt->n_params; j++)
        if (!w->fixed[j]) len += w->d[j] * w->x[j] * w->x[j];
    if (!(len > 0.0)) return lambda;
    return raise_lambda(run, lambda, radius * sqrt(len), 1);
}

/* The margin of reaches_all(): relative to the lengths, and the smallest
 * pivot of the equilibrated factor (at most 1) it trusts. */
#define BF_GROW_MARGIN 1e-6
#define BF_GROW_PIVOT 1e-6

/* Whether every lambda from low up to the current one gives a step no
 * longer than limit, known from the step at low alone: that step is the
 * damped system's own solution, from a well-conditioned factor, shorter
 * than limit by the margin; and no step of length up to its own can meet
 * the box or the step bound, nor can a parameter on a bound be held by
 * the sign of its step. Then every step for a larger lambda is the
 * damped system's solution too, and no longer (the length of the
 * solution of (A + lambda D) delta = -g in the scaling D falls as lambda
 * grows), so each of them passes the test as the step at low does. */
static int reaches_all(lm_run *run, double low, double limit)
{
    brdffit_optimizer *opt = run->opt;
    const bf_optim_work *w = &opt->w;
    size_t j, p = opt->n_params;
    int bounded = 0, fallback = 0;
    double len, reach;
    bf_optim_step_only(opt, low, 1.0, run->bound, &bounded, &fallback);
    len = scaled_length(w, p);
    if (!(opt->memo.pivot >= BF_GROW_PIVOT) || !(len <= limit * (1.0 - BF_GROW_MARGIN))) return 0;
    for (j = 0; j < p; j++) {
        double x = w->x[j], g = w->g[j];
        if (w->fixed[j] || (x <= w->lower[j] && g > 0.0) || (x >= w->upper[j] && g < 0.0))
            continue;                                         /* held whatever lambda */
        reach = len * (1.0 + BF_GROW_MARGIN) / sqrt(w->d[j]); /* the most |step_j| can be */
        if (!(x - reach > w->lower[j] && x + reach < w->upper[j])) return 0;
        if (w->xscale[j] > 0.0 && !(reach <= run->bound * (1.0 - BF_GROW_MARGIN) * w->xscale[j]))
            return 0;
    }
    return 1;
}

/* Step control (BRDFFIT_OPT_STEP_CONTROL), after a very successful step
 * (rho > 0.75): lower lambda by factors of 10 while the step from the new
 * point stays within twice the scaled length of the step just taken
 * (MINPACK doubles its trust radius so), at most 16 times. When the
 * lowest lambda that walk can reach is known to pass with every one
 * above it (reaches_all(), near a minimum: one solve in place of 16), it
 * is taken at once. Once a tenth of lambda leaves every damped diagonal
 * as it was, the step is the last one solved and is not solved again
 * (bf_optim_step_only() keeps it for the next iteration too). Returns
 * the new lambda, at most lambda. */
static double grow_lambda(lm_run *run, double lambda, double last_len)
{
    brdffit_optimizer *opt = run->opt;
    const bf_optim_work *w = &opt->w;
    size_t k, p = opt->n_params;
    int bounded = 0, fallback = 0;
    double low = lambda;
    for (k = 0; k < 16 && low > BF_LAMBDA_MIN * 10.0; k++) low *= 0.1;
    if (k > 1 && reaches_all(run, low, 2.0 * last_len)) return low;
    for (k = 0; k < 16 && lambda > BF_LAMBDA_MIN * 10.0; k++) {
        bf_optim_step_only(opt, lambda * 0.1, 1.0, run->bound, &bounded, &fallback);
        if (scaled_length(w, p) > 2.0 * last_len) break;
        lambda *= 0.1;
    }
    return lambda;
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
    if (run->opt->settings.step_control && !run->accepted && isfinite(run->cost_trial))
        lambda = shrink_lambda(run, lambda);
    if (run->opt->settings.step_control && run->accepted && run->rho > 0.75)
        lambda = grow_lambda(run, lambda, run->last_len);
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
    run->pred = bf_optim_step(opt, run->lambda, run->t, run->bound, &run->bounded, &run->fallback);
    run->last_len = scaled_length(&opt->w, opt->n_params);
    if (bf_optim_stopped(opt)) { /* maybe inside the step's solve: no step */
        *stop = BRDFFIT_STOP_CANCELLED;
        return BRDFFIT_OK;
    }
    if (step_small(opt)) {
        *stop = BRDFFIT_STOP_STEP;
        return BRDFFIT_OK;
    }
    if (opt->settings.cost_lookahead && gain_small(run)) {
        *stop = BRDFFIT_STOP_COST;
        return BRDFFIT_OK;
    }
    run->iterations++;
    run->accepted = try_step(run);
#ifdef BF_EXP_GROWB
    if (run->accepted && run->bounded && run->rho > 0.75) run->bound *= BF_EXP_GROWB;
#endif
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
    bf_optim_forget_step(opt);
    for (j = 0; j < opt->n_params; j++) {
        double v = x[j];
        if (v < w->lower[j]) v = w->lower[j];
        if (v > w->upper[j]) v = w->upper[j];
        if (!isfinite(v))
            return bf_optim_fail(opt, BRDFFIT_E_NONFINITE, "run: start value x[%zu] is %g", j, v);
        w->x[j] = v;
        w->xscale[j] = fabs(v);
    }
    return BRDFFIT_OK;
}

/* Begin an attempt at the caller's start point x with step bound bound:
 * fresh damping, the start evaluated with derivatives. */
static brdffit_status begin(lm_run *run, const double *x, double bound, char *what, size_t size)
{
    brdffit_optimizer *opt = run->opt;
    brdffit_status st;
    BF_RETURN_IF_ERROR(load_start(opt, x));
    if (opt->policy.state_size > 0) memset(opt->policy_state, 0, opt->policy.state_size);
    run->lambda = 1e-3;
    opt->policy.init(opt->policy_state, &run->lambda, opt->policy.user);
    run->lambda = clamp_lambda(run->lambda, 1e-3);
    run->t = 1.0;
    run->bound = bound;
    run->evaluations++;
    st = bf_optim_eval(opt, opt->w.x, 1, &run->cost, opt->w.jtj, opt->w.g, what, size);
    if (st != BRDFFIT_OK) return st;
    bf_optim_update_scaling(opt, 1);
    run->lambda = start_lambda(run, run->lambda);
    return history_push(run);
}

static brdffit_status start(lm_run *run, const double *x)
{
    brdffit_optimizer *opt = run->opt;
    char what[160];
    brdffit_status st;
    size_t cap = opt->settings.max_iterations + 1;
    BF_RETURN_IF_ERROR(history_reserve(opt, cap < BF_HISTORY_START ? cap : BF_HISTORY_START));
    opt->res.evaluations = 1;
    what[0] = '\0';
    st = begin(run, x, opt->settings.step_bound, what, sizeof what);
    if (st != BRDFFIT_OK && what[0] != '\0')
        return bf_optim_fail(opt, st, "run: %s at the start point", what);
    BF_RETURN_IF_ERROR(st);
    opt->res.initial_cost = run->cost;
    return BRDFFIT_OK;
}

/* Iterate until a stop; the stop as classified at the point reached. */
static brdffit_status attempt(lm_run *run, brdffit_stop_reason *stop)
{
    *stop = BRDFFIT_STOP_NONE;
    while (*stop == BRDFFIT_STOP_NONE) {
        *stop = check_before(run);
        if (*stop != BRDFFIT_STOP_NONE) break;
        BF_RETURN_IF_ERROR(iterate(run, stop));
    }
    bf_optim_mark_analysed(run->opt);
    *stop = bf_optim_classify(run->opt, *stop, run->cost);
    return BRDFFIT_OK;
}

/* The second attempt wins: its iterations and history, from its start,
 * become the run's; h1 and it1 are the first attempt's history length and
 * iteration count. */
static void keep_second(lm_run *run, size_t h1, size_t it1)
{
    brdffit_optimizer *opt = run->opt;
    size_t n = run->history_len - h1;
    memmove(opt->history, opt->history + h1, n * sizeof *opt->history);
    memmove(opt->history + opt->history_cap, opt->history + opt->history_cap + h1,
            n * sizeof *opt->history);
    run->history_len = n;
    run->iterations -= it1;
    run->last_improvement = run->last_improvement > it1 ? run->last_improvement - it1 : 0;
}

/* After a stalled attempt: once more from the start, with the restart
 * bound on the steps, so that a parameter cannot run away onto the
 * plateau again. Keeps the better attempt (the second when it is not
 * stalled or ends lower), with its iterations and history; the first
 * is evaluated again when it wins, so that J^T J and J^T r belong to the
 * point returned. Evaluations count both. */
static brdffit_status retry(lm_run *run, const double *x, brdffit_stop_reason *stop)
{
    brdffit_optimizer *opt = run->opt;
    bf_optim_work *w = &opt->w;
    brdffit_stop_reason first = *stop;
    double first_cost = run->cost;
    size_t h1 = run->history_len, it1 = run->iterations, li1 = run->last_improvement;
    memcpy(w->best, w->x, opt->n_params * sizeof *w->best);
    if (begin(run, x, opt->settings.restart_bound, NULL, 0) != BRDFFIT_OK) return BRDFFIT_OK;
    BF_RETURN_IF_ERROR(attempt(run, stop));
    if (*stop != BRDFFIT_STOP_STALLED || run->cost < first_cost) {
        keep_second(run, h1, it1);
        return BRDFFIT_OK;
    }
    memcpy(w->x, w->best, opt->n_params * sizeof *w->x);
    bf_optim_forget_step(opt);
    run->evaluations++;
    (void)bf_optim_eval(opt, w->x, 1, &run->cost, w->jtj, w->g, NULL, 0); /* as before */
    bf_optim_mark_analysed(opt);
    run->history_len = h1;
    run->iterations = it1;
    run->last_improvement = li1;
    *stop = first;
    return BRDFFIT_OK;
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
    res->history_len = run->history_len;
    res->n_rows = opt->n_rows;
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
    BF_RETURN_IF_ERROR(attempt(&run, &stop));
    if (stop == BRDFFIT_STOP_STALLED && opt->settings.restart_bound < opt->settings.step_bound)
        BF_RETURN_IF_ERROR(retry(&run, x, &stop));
    opt->res.want_sandwich = opt->settings.sandwich;
    if (opt->settings.sandwich && opt->form == BF_FORM_RESIDUALS) {
        run.evaluations++;
        opt->res.sandwich = bf_optim_prepare_sandwich(opt);
    }
    opt->res.evaluations = run.evaluations;
    finish(&run, stop, x);
    return BRDFFIT_OK;
}
