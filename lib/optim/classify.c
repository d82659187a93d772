/* The gradient test, and how a run that stopped on a small step,
 * reduction or gradient ended: converged, or stalled on a plateau. The
 * stopping tests look at the last step; this one looks at the point: a
 * free parameter whose Jacobian column vanished (an exponential
 * underflowed and the parameter ran away, so the problem no longer
 * depends on it) is no solution, however small the steps. docs/optimizer.md
 * describes the test. */
#include <float.h>
#include <math.h>

#include "optim/optim_internal.h"

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

/* Parameter j's column vanished: its sensitivity is below DBL_EPSILON
 * times the largest sensitivity of the analysed parameters. A parameter
 * that has only been 0 has no scale and is not judged. */
int bf_optim_vanished(const brdffit_optimizer *opt, size_t j)
{
    const bf_optim_work *w = &opt->w;
    size_t k, p = opt->n_params;
    double top = 0.0;
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

brdffit_stop_reason bf_optim_classify(const brdffit_optimizer *opt, brdffit_stop_reason stop)
{
    if (stop != BRDFFIT_STOP_STEP && stop != BRDFFIT_STOP_COST && stop != BRDFFIT_STOP_GRADIENT)
        return stop;
    return column_vanished(opt) ? BRDFFIT_STOP_STALLED : stop;
}
