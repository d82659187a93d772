/* After a run: condition number of J^T J and covariance of the parameters
 * at the returned point, over the parameters that are neither fixed nor
 * on a bound (the analysed set C, fixed when the run ends). Computed on
 * demand, in the workspace's scratch arrays, so that runs whose caller
 * does not ask for them do not pay the O(p^3) eigen-decompositions. */
#include <math.h>
#include <string.h>

#include "core/linalg.h"
#include "optim/optim_internal.h"

void bf_optim_mark_analysed(brdffit_optimizer *opt)
{
    bf_optim_work *w = &opt->w;
    size_t j;
    for (j = 0; j < opt->n_params; j++)
        w->analysed[j] = !w->fixed[j] && !bf_optim_on_bound(opt, j, w->x);
}

static size_t gather_analysed(const bf_optim_work *w, size_t p)
{
    size_t j, n = 0;
    for (j = 0; j < p; j++)
        if (w->analysed[j]) w->free_idx[n++] = j;
    return n;
}

/* Eigenvalue ratio of the unscaled J^T J over C; 1 when C is empty. */
double bf_optim_condition(const brdffit_optimizer *opt)
{
    const bf_optim_work *w = &opt->w;
    size_t a, b, p = opt->n_params, n = gather_analysed(w, p);
    for (a = 0; a < n; a++)
        for (b = 0; b < n; b++) w->m[a * n + b] = w->jtj[w->free_idx[a] * p + w->free_idx[b]];
    bf_sym_eigen(w->m, n, w->w, NULL);
    return bf_eigen_condition(w->w, n);
}

/* cov = s^2 S (S A S)^+ S over C, S = diag(A)^-1/2, zero elsewhere; the
 * scaling makes the pseudo-inverse's cut-off independent of the units of
 * the parameters. A parameter the problem does not depend on (zero
 * diagonal) gets 0. s^2 = cost / (n_rows - |C|), or 1 when n_rows <= |C|
 * (no degrees of freedom left: the residuals are taken as already scaled
 * by their standard deviations). This leaves (S A S)^+ in w->m, S in
 * w->scale, and returns |C| and s^2. */
static size_t scaled_pinv(const brdffit_optimizer *opt, double *s2)
{
    const bf_optim_work *w = &opt->w;
    size_t a, b, p = opt->n_params, n = gather_analysed(w, p);
    size_t rows = opt->res.n_rows;
    *s2 = rows > n ? opt->res.final_cost / (double)(rows - n) : 1.0;
    for (a = 0; a < n; a++) {
        double ajj = w->jtj[w->free_idx[a] * p + w->free_idx[a]];
        w->scale[a] = ajj > 0.0 ? 1.0 / sqrt(ajj) : 0.0;
    }
    for (a = 0; a < n; a++) {
        const double *row = w->jtj + w->free_idx[a] * p;
        for (b = 0; b < n; b++) w->m[a * n + b] = row[w->free_idx[b]] * w->scale[a] * w->scale[b];
    }
    bf_sym_eigen(w->m, n, w->w, w->v);
    bf_eigen_pinv(w->w, w->v, n, BF_LINALG_RTOL, w->m);
    return n;
}

void bf_optim_covariance(const brdffit_optimizer *opt, double *cov)
{
    const bf_optim_work *w = &opt->w;
    size_t a, b, p = opt->n_params, n;
    double s2;
    memset(cov, 0, p * p * sizeof *cov);
    n = scaled_pinv(opt, &s2);
    for (a = 0; a < n; a++) {
        double *crow = cov + w->free_idx[a] * p;
        for (b = 0; b < n; b++)
            crow[w->free_idx[b]] = s2 * w->scale[a] * w->m[a * n + b] * w->scale[b];
    }
}

/* The square roots of the covariance diagonal, taken factor by factor: a
 * parameter the data barely determine (a tiny diagonal of A) has a
 * variance beyond the double range but a standard error within it. */
void bf_optim_std_errors(const brdffit_optimizer *opt, double *se)
{
    const bf_optim_work *w = &opt->w;
    size_t a, n;
    double s2;
    memset(se, 0, opt->n_params * sizeof *se);
    n = scaled_pinv(opt, &s2);
    for (a = 0; a < n; a++)
        se[w->free_idx[a]] = sqrt(s2) * w->scale[a] * sqrt(fmax(w->m[a * n + a], 0.0));
}
