/* The gradient test, and how a run that stopped on a small step,
 * reduction or gradient ended: converged, or stalled on a plateau. The
 * stopping tests look at the last step; this one looks at the point: a
 * free parameter whose Jacobian column vanished (an exponential
 * underflowed and the parameter ran away, so the problem no longer
 * depends on it) is no solution, however small the steps; nor, after a
 * small step or reduction, is a point where the undamped step still
 * promises a real gain. docs/optimizer.md describes the tests. */
#include <float.h>
#include <math.h>

#include "optim/optim_internal.h"

/* Not stationary (see not_stationary()): the Gauss-Newton step changes a
 * parameter by more than this share of its scale, and the model promises
 * more than this share of the cost for it. */
#define BF_LEFT_STEP 1e-6
#define BF_LEFT_GAIN 1e-6

static int pushes_out(const bf_optim_work *w, size_t j)
{
    double x = w->x[j], g = w->g[j];
    return (x <= w->lower[j] && g > 0.0) || (x >= w->upper[j] && g < 0.0);
}

/* max_j |g_j| / sqrt(A_jj cost) <= gtol, over the components that may move
 * (not fixed, not pushing out of a bound): the cosine of the angle between
 * the residual vector and each Jacobian column, which neither the units of
 * the parameters nor those of the residuals change. A zero column never
 * passes; with no component free to move the test passes. */
int bf_optim_gradient_small(const brdffit_optimizer *opt, double cost)
{
    const bf_optim_work *w = &opt->w;
    const double scale = opt->settings.gtol * sqrt(cost);
    size_t j, p = opt->n_params;
    for (j = 0; j < p; j++) {
        double g = w->g[j], a = w->jtj[j * p + j];
        if (w->fixed[j] || pushes_out(w, j)) continue;
        if (!(a > 0.0) || !(fabs(g) <= scale * sqrt(a))) return 0;
    }
    return 1;
}

/* The model's sensitivity to a relative change of parameter j: |J_j|
 * times its scale (the largest magnitude it had in the run). */
static double sensitivity(const bf_optim_work *w, size_t p, size_t j)
{
    return sqrt(w->jtj[j * p + j]) * w->xscale[j];
}

/* Parameter j's Jacobian column vanished: its norm fell below
 * DBL_EPSILON times the largest it had in the attempt (an exponential
 * underflowed as the parameter ran away), and the model's sensitivity to
 * a relative change of it is below DBL_EPSILON times the largest such
 * sensitivity of the analysed parameters. The first alone would take a
 * column that was huge on the way (MGH10's amplitude) for a vanished one,
 * the second alone a parameter that stays near zero (the centre of MGH's
 * Gaussian). A zero column counts as vanished: the problem does not
 * depend on that parameter (a start on a plateau, or a parameter the
 * model ignores). */
int bf_optim_vanished(const brdffit_optimizer *opt, size_t j)
{
    const bf_optim_work *w = &opt->w;
    size_t k, p = opt->n_params;
    double a = w->jtj[j * p + j], top = 0.0;
    if (a > 0.0 && a > DBL_EPSILON * DBL_EPSILON * w->amax[j]) return 0;
    if (!(w->xscale[j] > 0.0)) return 0;
    for (k = 0; k < p; k++)
        if (w->analysed[k]) top = fmax(top, sensitivity(w, p, k));
    return !(sensitivity(w, p, j) > DBL_EPSILON * top);
}

static int column_vanished(const brdffit_optimizer *opt)
{
    size_t j;
    for (j = 0; j < opt->n_params; j++)
        if (opt->w.analysed[j] && bf_optim_vanished(opt, j)) return 1;
    return 0;
}

/* The point is not stationary: the undamped (Gauss-Newton) step, with the
 * bounds and fixed parameters as a step would have them, still changes
 * some free parameter by more than BF_LEFT_STEP of its scale (its
 * magnitude, or the largest it had in the run) and the linear model
 * promises more than BF_LEFT_GAIN of the cost for it. A damped step can
 * be small because the damping is large, far from any minimum; this
 * looks at the point itself. At a zero-residual solution the step is
 * small; at a minimum with residuals the gain is. Overwrites the step's
 * scratch (w.trial, w.step). */
static int not_stationary(brdffit_optimizer *opt, double cost)
{
    const bf_optim_work *w = &opt->w;
    size_t j;
    int bounded = 0, fallback = 0, moves = 0;
    double pred = bf_optim_step(opt, BF_LAMBDA_MIN, 1.0, HUGE_VAL, &bounded, &fallback);
    for (j = 0; j < opt->n_params; j++)
        if (fabs(w->step[j]) > BF_LEFT_STEP * fmax(fabs(w->x[j]), w->xscale[j])) moves = 1;
    return moves && pred > BF_LEFT_GAIN * cost;
}

brdffit_stop_reason bf_optim_classify(brdffit_optimizer *opt, brdffit_stop_reason stop, double cost)
{
    if (stop != BRDFFIT_STOP_STEP && stop != BRDFFIT_STOP_COST && stop != BRDFFIT_STOP_GRADIENT &&
        stop != BRDFFIT_STOP_ZERO_COST)
        return stop;
    if (column_vanished(opt)) return BRDFFIT_STOP_STALLED;
    if (stop == BRDFFIT_STOP_ZERO_COST) return stop; /* a zero cost is a minimum */
    if (stop != BRDFFIT_STOP_GRADIENT && not_stationary(opt, cost)) return BRDFFIT_STOP_STALLED;
    return stop;
}
