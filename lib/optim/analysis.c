/* After a run: condition number of J^T J and covariance of the parameters
 * at the returned point, over the parameters that are neither fixed nor
 * on a bound (the analysed set C, fixed when the run ends). Computed on
 * demand, in the workspace's scratch arrays, so that runs whose caller
 * does not ask for them do not pay the O(p^3) eigen-decompositions.
 * docs/optimizer.md gives the formulas and their assumptions. */
#include <math.h>
#include <string.h>

#include "core/linalg.h"
#include "optim/optim_internal.h"
#include "optim/sandwich.h"

/* A parameter whose direction lies mostly in the dropped eigenspace (this
 * much of its unit vector or more) is not determined by the data. */
#define BF_NULL_WEIGHT 0.01

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

/* held[a] (by position in C) = parameter a is undetermined: its column is
 * zero or vanished (classify.c), or most of it lies in the eigenspace the
 * pseudo-inverse drops. Needs the eigen-decomposition in w and v. */
static void mark_undetermined(const brdffit_optimizer *opt, size_t n)
{
    const bf_optim_work *w = &opt->w;
    double wmax = 0.0;
    size_t a, k;
    for (k = 0; k < n; k++) wmax = fmax(wmax, w->w[k]);
    for (a = 0; a < n; a++) {
        double null_weight = 0.0;
        for (k = 0; k < n; k++)
            if (!(w->w[k] > BF_LINALG_RTOL * wmax))
                null_weight += w->v[a * n + k] * w->v[a * n + k];
        w->held[a] = w->scale[a] == 0.0 || null_weight >= BF_NULL_WEIGHT ||
                     bf_optim_vanished(opt, w->free_idx[a]);
    }
}

static int watched(const void *ctx)
{
    return bf_optim_watched_stop(ctx);
}

/* (S A S)^+ over C into w->m, S = diag(A)^-1/2 in w->scale (0 for a zero
 * diagonal), the undetermined parameters in w->held; |C| into *count.
 * The scaling makes the pseudo-inverse's cut-off independent of the
 * units. Returns 0 when the watched flag stopped it. */
static int scaled_pinv(const brdffit_optimizer *opt, size_t *count)
{
    const bf_stop stop = {watched, opt};
    const bf_optim_work *w = &opt->w;
    size_t a, b, p = opt->n_params, n = gather_analysed(w, p);
    for (a = 0; a < n; a++) {
        double ajj = w->jtj[w->free_idx[a] * p + w->free_idx[a]];
        w->scale[a] = ajj > 0.0 ? 1.0 / sqrt(ajj) : 0.0;
    }
    for (a = 0; a < n; a++) {
        const double *row = w->jtj + w->free_idx[a] * p;
        for (b = 0; b < n; b++) w->m[a * n + b] = row[w->free_idx[b]] * w->scale[a] * w->scale[b];
    }
    *count = n;
    if (bf_sym_eigen_until(w->m, n, w->w, w->v, &stop) < 0) return 0;
    mark_undetermined(opt, n);
    return bf_eigen_pinv(w->w, w->v, n, BF_LINALG_RTOL, w->m, &stop);
}

double bf_optim_classic_factor(const brdffit_optimizer *opt, size_t n)
{
    size_t rows = opt->res.n_rows;
    double dof = rows > n ? (double)(rows - n) : 0.0;
    return dof > 0.0 ? opt->res.final_cost / dof : 1.0;
}

/* out = x y (n x n, row stride n); 0 when the watched flag stopped it. */
static int multiply(const brdffit_optimizer *opt, const double *x, const double *y, size_t n,
                    double *out)
{
    size_t a, b, k;
    for (a = 0; a < n; a++) {
        if (bf_optim_watched_stop(opt)) return 0;
        for (b = 0; b < n; b++) {
            double s = 0.0;
            for (k = 0; k < n; k++) s += x[a * n + k] * y[k * n + b];
            out[a * n + b] = s;
        }
    }
    return 1;
}

/* The middle of the covariance over C, the factor before it returned:
 * classic: s^2 (S A S)^+, s^2 = cost / (n_rows - |C|) (1 when
 * n_rows <= |C|); sandwich: (S A S)^+ (S B S) (S A S)^+ with B from
 * bf_optim_prepare_sandwich() in w->meat, in w->v. NULL when the watched
 * flag stopped it. */
static const double *middle(const brdffit_optimizer *opt, size_t n, double *factor)
{
    const bf_optim_work *w = &opt->w;
    size_t a, b, p = opt->n_params;
    if (!opt->res.sandwich) {
        *factor = bf_optim_classic_factor(opt, n);
        return w->m;
    }
    *factor = 1.0;
    for (a = 0; a < n; a++)
        for (b = 0; b < n; b++)
            w->v[a * n + b] =
                w->meat[w->free_idx[a] * p + w->free_idx[b]] * w->scale[a] * w->scale[b];
    if (!multiply(opt, w->m, w->v, n, w->jtj_new) || !multiply(opt, w->jtj_new, w->m, n, w->v))
        return NULL;
    return w->v;
}

int bf_optim_covariance(const brdffit_optimizer *opt, double *cov)
{
    const bf_optim_work *w = &opt->w;
    size_t a, b, p = opt->n_params, n;
    const double *mid;
    double f;
    memset(cov, 0, p * p * sizeof *cov);
    if (bf_blocks_covariance(opt, cov)) return 1;
    if (!scaled_pinv(opt, &n) || (mid = middle(opt, n, &f)) == NULL) return 0;
    for (a = 0; a < n; a++) {
        double *crow = cov + w->free_idx[a] * p;
        if (w->held[a]) {
            crow[w->free_idx[a]] = HUGE_VAL;
            continue;
        }
        for (b = 0; b < n; b++)
            if (!w->held[b]) crow[w->free_idx[b]] = f * w->scale[a] * mid[a * n + b] * w->scale[b];
    }
    return 1;
}

/* The square roots of the covariance diagonal, taken factor by factor: a
 * parameter the data barely determine (a tiny diagonal of A) has a
 * variance beyond the double range but a standard error within it. */
int bf_optim_std_errors(const brdffit_optimizer *opt, double *se)
{
    const bf_optim_work *w = &opt->w;
    size_t a, n;
    const double *mid;
    double f;
    memset(se, 0, opt->n_params * sizeof *se);
    if (bf_blocks_std_errors(opt, se)) return 1;
    if (!scaled_pinv(opt, &n) || (mid = middle(opt, n, &f)) == NULL) {
        memset(se, 0, opt->n_params * sizeof *se);
        return 0;
    }
    for (a = 0; a < n; a++)
        se[w->free_idx[a]] =
            w->held[a] ? HUGE_VAL : sqrt(f) * w->scale[a] * sqrt(fmax(mid[a * n + a], 0.0));
    return 1;
}

int bf_optim_errors(const brdffit_optimizer *opt, double *se, double *cov)
{
    const bf_optim_work *w = &opt->w;
    size_t a, b, p = opt->n_params, n;
    const double *mid;
    double f;
    memset(se, 0, p * sizeof *se);
    memset(cov, 0, p * p * sizeof *cov);
    if (bf_blocks_std_errors(opt, se)) return bf_blocks_covariance(opt, cov);
    if (!scaled_pinv(opt, &n) || (mid = middle(opt, n, &f)) == NULL) {
        memset(se, 0, p * sizeof *se);
        return 0;
    }
    /* as bf_optim_std_errors() and bf_optim_covariance() give them */
    for (a = 0; a < n; a++) {
        double *crow = cov + w->free_idx[a] * p;
        if (w->held[a]) {
            se[w->free_idx[a]] = crow[w->free_idx[a]] = HUGE_VAL;
            continue;
        }
        se[w->free_idx[a]] = sqrt(f) * w->scale[a] * sqrt(fmax(mid[a * n + a], 0.0));
        for (b = 0; b < n; b++)
            if (!w->held[b]) crow[w->free_idx[b]] = f * w->scale[a] * mid[a * n + b] * w->scale[b];
    }
    return 1;
}

/* Leverage h_i = J_i A^+ J_i^T of row i over C, with (S A S)^+ in w->m. */
static double leverage(const brdffit_optimizer *opt, const double *row, size_t n)
{
    const bf_optim_work *w = &opt->w;
    size_t a, b;
    double h = 0.0;
    for (a = 0; a < n; a++) {
        double s = 0.0, ja = row[w->free_idx[a]] * w->scale[a];
        for (b = 0; b < n; b++) s += w->m[a * n + b] * row[w->free_idx[b]] * w->scale[b];
        h += ja * s;
    }
    return h;
}

/* B = sum_i (r_i / (1 - h_i))^2 J_i J_i^T at the returned point into
 * w->meat, for the sandwich (HC3: the leverage h_i corrects the residuals
 * of rows that pull the fit towards themselves): one more evaluation of
 * the residual form. Returns 0 when the problem cannot be evaluated there
 * (it could before). Needs bf_optim_mark_analysed(). */
int bf_optim_prepare_sandwich(brdffit_optimizer *opt)
{
    bf_optim_work *w = &opt->w;
    size_t i, j, k, p = opt->n_params, n;
    double cost;
    if (bf_optim_eval(opt, w->x, 1, &cost, w->jtj_new, w->g_new, NULL, 0) != BRDFFIT_OK) return 0;
    if (!scaled_pinv(opt, &n)) return 0;
    memset(w->meat, 0, p * p * sizeof *w->meat);
    for (i = 0; i < opt->n_rows; i++) {
        const double *row = opt->jac + i * p;
        double q = fmax(1.0 - leverage(opt, row, n), 1e-8), r2 = opt->r[i] * opt->r[i] / (q * q);
        for (j = 0; j < p; j++)
            for (k = 0; k < p; k++) w->meat[j * p + k] += r2 * row[j] * row[k];
    }
    return 1;
}

int bf_optim_bread(const brdffit_optimizer *opt, double *bread)
{
    const bf_optim_work *w = &opt->w;
    size_t a, b, p = opt->n_params, n;
    if (!scaled_pinv(opt, &n)) return 0;
    memset(bread, 0, p * p * sizeof *bread);
    for (a = 0; a < n; a++)
        for (b = 0; b < n; b++)
            bread[w->free_idx[a] * p + w->free_idx[b]] =
                w->scale[a] * w->m[a * n + b] * w->scale[b];
    return 1;
}

void bf_optim_set_meat(brdffit_optimizer *opt, const double *meat)
{
    memcpy(opt->w.meat, meat, opt->n_params * opt->n_params * sizeof *meat);
    opt->res.want_sandwich = 1;
    opt->res.sandwich = 1;
}
