/* Evaluating the problem: calling the residual or normal-equation callback,
 * forming J^T J and J^T r for the residual form, and checking that every
 * number that comes back is finite. */
#include <math.h>
#include <string.h>

#include "core/core.h"
#include "optim/optim_internal.h"

static brdffit_status callback_failed(brdffit_status st, char *what, size_t size)
{
    if (what != NULL)
        bf_format(what, size, "the problem callback returned %s (%d)", brdffit_status_name(st),
                  (int)st);
    return BRDFFIT_E_CALLBACK_FAILED;
}

/* --- residual form ---------------------------------------------------------- */

static double sum_squares(const double *r, size_t n)
{
    double s = 0.0;
    size_t i;
    for (i = 0; i < n; i++) s += r[i] * r[i];
    return s;
}

static brdffit_status bad_residuals(const double *r, size_t n, char *what, size_t size)
{
    size_t i;
    if (what == NULL) return BRDFFIT_E_NONFINITE;
    for (i = 0; i < n; i++) {
        if (!isfinite(r[i])) {
            bf_format(what, size, "residual %zu is %g", i, r[i]);
            return BRDFFIT_E_NONFINITE;
        }
    }
    bf_format(what, size, "the cost (sum of squared residuals) overflows");
    return BRDFFIT_E_NONFINITE;
}

static brdffit_status bad_jacobian(const double *jac, size_t n, size_t p, char *what, size_t size)
{
    size_t i;
    if (what == NULL) return BRDFFIT_E_NONFINITE;
    for (i = 0; i < n * p; i++) {
        if (!isfinite(jac[i])) {
            bf_format(what, size, "Jacobian entry (%zu, %zu) is %g", i / p, i % p, jac[i]);
            return BRDFFIT_E_NONFINITE;
        }
    }
    bf_format(what, size, "J^T J overflows");
    return BRDFFIT_E_NONFINITE;
}

/* jtj = J^T J (both triangles), g = J^T r. */
static void form_normal(const double *jac, const double *r, size_t n, size_t p, double *jtj,
                        double *g)
{
    size_t i, j, k;
    memset(jtj, 0, p * p * sizeof *jtj);
    memset(g, 0, p * sizeof *g);
    for (i = 0; i < n; i++) {
        const double *row = jac + i * p;
        for (j = 0; j < p; j++) {
            double a = row[j];
            double *out = jtj + j * p;
            if (a == 0.0) continue;
            for (k = j; k < p; k++) out[k] += a * row[k];
            g[j] += a * r[i];
        }
    }
    for (j = 0; j < p; j++)
        for (k = 0; k < j; k++) jtj[j * p + k] = jtj[k * p + j];
}

static int all_finite(const double *v, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        if (!isfinite(v[i])) return 0;
    return 1;
}

static brdffit_status eval_residuals(brdffit_optimizer *opt, const double *x, int derivs,
                                     double *cost, double *jtj, double *g, char *what, size_t size)
{
    size_t n = opt->n_rows, p = opt->n_params;
    brdffit_status st;
    double c;
    memset(opt->r, 0, n * sizeof *opt->r);
    if (derivs) memset(opt->jac, 0, n * p * sizeof *opt->jac);
    st = opt->residual_fn(x, opt->r, derivs ? opt->jac : NULL, opt->user);
    if (st != BRDFFIT_OK) return callback_failed(st, what, size);
    c = sum_squares(opt->r, n);
    if (!isfinite(c)) return bad_residuals(opt->r, n, what, size);
    *cost = c;
    if (!derivs) return BRDFFIT_OK;
    form_normal(opt->jac, opt->r, n, p, jtj, g);
    if (!all_finite(jtj, p * p) || !all_finite(g, p))
        return bad_jacobian(opt->jac, n, p, what, size);
    return BRDFFIT_OK;
}

/* --- normal-equation form ----------------------------------------------------- */

static brdffit_status bad_normal(const double *jtj, const double *g, size_t p, char *what,
                                 size_t size)
{
    size_t i;
    if (what == NULL) return BRDFFIT_E_NONFINITE;
    for (i = 0; i < p * p; i++) {
        if (!isfinite(jtj[i])) {
            bf_format(what, size, "J^T J entry (%zu, %zu) is %g", i / p, i % p, jtj[i]);
            return BRDFFIT_E_NONFINITE;
        }
    }
    for (i = 0; i < p; i++) {
        if (!isfinite(g[i])) {
            bf_format(what, size, "J^T r entry %zu is %g", i, g[i]);
            return BRDFFIT_E_NONFINITE;
        }
    }
    return BRDFFIT_E_NONFINITE;
}

static void symmetrise(double *a, size_t p)
{
    size_t j, k;
    for (j = 0; j < p; j++) {
        for (k = j + 1; k < p; k++) {
            double s = 0.5 * (a[j * p + k] + a[k * p + j]);
            a[j * p + k] = a[k * p + j] = s;
        }
    }
}

static brdffit_status eval_normal(brdffit_optimizer *opt, const double *x, int derivs, double *cost,
                                  double *jtj, double *g, char *what, size_t size)
{
    size_t p = opt->n_params;
    brdffit_status st;
    double c = 0.0;
    if (derivs) {
        memset(jtj, 0, p * p * sizeof *jtj);
        memset(g, 0, p * sizeof *g);
    }
    st = opt->normal_fn(x, &c, derivs ? jtj : NULL, derivs ? g : NULL, opt->user);
    if (st != BRDFFIT_OK) return callback_failed(st, what, size);
    if (!isfinite(c)) {
        if (what != NULL) bf_format(what, size, "the cost is %g", c);
        return BRDFFIT_E_NONFINITE;
    }
    if (c < 0.0) {
        if (what != NULL) bf_format(what, size, "the problem returned a negative cost (%g)", c);
        return BRDFFIT_E_CALLBACK_FAILED;
    }
    *cost = c;
    if (!derivs) return BRDFFIT_OK;
    if (!all_finite(jtj, p * p) || !all_finite(g, p)) return bad_normal(jtj, g, p, what, size);
    symmetrise(jtj, p);
    return BRDFFIT_OK;
}

brdffit_status bf_optim_eval(brdffit_optimizer *opt, const double *x, int derivs, double *cost,
                             double *jtj, double *g, char *what, size_t what_size)
{
    if (opt->form == BF_FORM_RESIDUALS)
        return eval_residuals(opt, x, derivs, cost, jtj, g, what, what_size);
    return eval_normal(opt, x, derivs, cost, jtj, g, what, what_size);
}
