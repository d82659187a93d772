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

/* A parameter neither fixed nor on a bound whose column vanished: the
 * model's sensitivity to a relative change of it, |J_j| times its scale
 * (the largest magnitude it had in the run), is below DBL_EPSILON times
 * the largest such sensitivity. A parameter that has only been 0 has no
 * scale and is not judged. */
static int column_vanished(const bf_optim_work *w, size_t p)
{
    size_t j;
    double top = 0.0;
    for (j = 0; j < p; j++)
        if (w->analysed[j]) top = fmax(top, sqrt(w->jtj[j * p + j]) * w->xscale[j]);
    for (j = 0; j < p; j++) {
        double s = sqrt(w->jtj[j * p + j]) * w->xscale[j];
        if (w->analysed[j] && w->xscale[j] > 0.0 && !(s > DBL_EPSILON * top)) return 1;
    }
    return 0;
}

brdffit_stop_reason bf_optim_classify(const brdffit_optimizer *opt, brdffit_stop_reason stop)
{
    if (stop != BRDFFIT_STOP_STEP && stop != BRDFFIT_STOP_COST && stop != BRDFFIT_STOP_GRADIENT)
        return stop;
    return column_vanished(&opt->w, opt->n_params) ? BRDFFIT_STOP_STALLED : stop;
}
