#include "model_fixtures.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

double mf_uniform(uint64_t *state)
{
    /* splitmix64 */
    uint64_t z = (*state += UINT64_C(0x9e3779b97f4a7c15));
    z = (z ^ (z >> 30)) * UINT64_C(0xbf58476d1ce4e5b9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94d049bb133111eb);
    z ^= z >> 31;
    return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}

brdffit_grid *mf_default_grid(size_t nc)
{
    const brdffit_axes *axes = brdffit_axes_default();
    size_t n = axes->n_theta_i * axes->n_theta_o * axes->n_phi_o;
    double *values = calloc(n * nc, sizeof(double));
    brdffit_grid *grid = NULL;
    if (values == NULL) return NULL;
    if (brdffit_grid_create_regular(&grid, axes, nc, values, NULL, NULL, NULL) != BRDFFIT_OK)
        grid = NULL;
    free(values);
    return grid;
}

static double log_uniform(uint64_t *rng, double lo, double hi)
{
    return exp(log(lo) + (log(hi) - log(lo)) * mf_uniform(rng));
}

static double random_value(const brdffit_param_info *p, uint64_t *rng)
{
    if (p->flags & BRDFFIT_PARAM_LINEAR) return 0.01 + 0.99 * mf_uniform(rng);
    if (p->flags & BRDFFIT_PARAM_LOG_SCALE) {
        if (p->upper > 10.0) return log_uniform(rng, strcmp(p->name, "n") == 0 ? 3.0 : 1.0, 1e4);
        return log_uniform(rng, fmax(p->lower, 1e-3), fmin(p->upper, 1.0));
    }
    {
        const double margin = 0.01 * (p->upper - p->lower);
        return p->lower + margin + (p->upper - p->lower - 2.0 * margin) * mf_uniform(rng);
    }
}

void mf_random_params(const brdffit_model *m, size_t nc, uint64_t *rng, double *x)
{
    size_t k, c, j = 0;
    for (k = 0; k < brdffit_model_param_count(m); k++) {
        const brdffit_param_info *p = brdffit_model_param(m, k);
        const size_t width = (p->flags & BRDFFIT_PARAM_PER_CHANNEL) ? nc : 1;
        for (c = 0; c < width; c++) x[j++] = random_value(p, rng);
    }
}

/* Values of the whole grid with entry j of x moved by delta. */
static int eval_moved(const brdffit_model *m, const brdffit_grid *grid, double *x, size_t j,
                      double delta, double *out)
{
    const double keep = x[j];
    brdffit_status st;
    x[j] = keep + delta;
    st = brdffit_model_eval_grid(m, grid, 0, brdffit_grid_sample_count(grid), x, out, NULL, NULL);
    x[j] = keep;
    return st == BRDFFIT_OK;
}

/* Worst error of entry j (parameter k, channels [c0, c1)); -1 on a
 * cross-channel effect. A central difference of values f+, f- is exact to
 * within about r = 16 eps (|f+| + |f-|) / (2 h); only the part of a
 * difference beyond r counts, relative to max(|numeric|, 1e-6 s), s the
 * largest |numeric| - r of the parameter and channel. */
static double entry_error(const double *jac, const double *fa, const double *fb, size_t n,
                          size_t nc, size_t k, size_t c0, size_t c1, double h, double *raw)
{
    const double rounding = 16.0 * DBL_EPSILON / (2.0 * h);
    double worst = 0.0;
    size_t c, s;
    for (c = 0; c < nc; c++) {
        const double *a = fa + c * n, *b = fb + c * n, *an = jac + (k * nc + c) * n;
        double scale = 0.0;
        if (c < c0 || c >= c1) {
            if (memcmp(a, b, n * sizeof(double)) != 0) return -1.0;
            continue;
        }
        for (s = 0; s < n; s++) {
            const double num = (a[s] - b[s]) / (2.0 * h);
            scale = fmax(scale, fabs(num) - rounding * (fabs(a[s]) + fabs(b[s])));
        }
        for (s = 0; s < n; s++) {
            const double num = (a[s] - b[s]) / (2.0 * h);
            const double r = rounding * (fabs(a[s]) + fabs(b[s]));
            const double den = fmax(fabs(num), 1e-6 * scale);
            const double d = fmax(fabs(an[s] - num) - r, 0.0);
            const double e = den > 0.0 ? d / den : d;
            if (e > worst) worst = e;
            if (r <= 1e-5 * den && fabs(an[s] - num) / den > *raw) *raw = fabs(an[s] - num) / den;
        }
    }
    return worst;
}

double mf_independent_jacobian_error(const brdffit_model *m, const brdffit_grid *grid,
                                     const double *x0, double *raw)
{
    const size_t nc = brdffit_grid_channel_count(grid), n = brdffit_grid_sample_count(grid);
    const size_t nv = brdffit_model_vector_size(m, nc), np = brdffit_model_param_count(m);
    double *x = malloc(nv * sizeof(double)), *v = malloc(n * nc * sizeof(double));
    double *jac = malloc(n * nc * np * sizeof(double));
    double *fa = malloc(n * nc * sizeof(double)), *fb = malloc(n * nc * sizeof(double));
    double worst = -1.0, raw_worst = 0.0;
    size_t k, e, j = 0;
    if (x == NULL || v == NULL || jac == NULL || fa == NULL || fb == NULL) goto done;
    memcpy(x, x0, nv * sizeof(double));
    if (brdffit_model_eval_grid(m, grid, 0, n, x, v, jac, NULL) != BRDFFIT_OK) goto done;
    worst = 0.0;
    for (k = 0; k < np; k++) {
        const int per = (brdffit_model_param(m, k)->flags & BRDFFIT_PARAM_PER_CHANNEL) != 0;
        for (e = 0; e < (per ? nc : 1); e++, j++) {
            const double h = 1e-6 * fmax(fabs(x[j]), 1e-3);
            double err;
            if (!eval_moved(m, grid, x, j, h, fa) || !eval_moved(m, grid, x, j, -h, fb)) {
                worst = -1.0;
                goto done;
            }
            err = entry_error(jac, fa, fb, n, nc, k, per ? e : 0, per ? e + 1 : nc, h, &raw_worst);
            if (err < 0.0) {
                worst = -1.0;
                goto done;
            }
            if (err > worst) worst = err;
        }
    }
done:
    if (raw != NULL) *raw = raw_worst;
    free(x);
    free(v);
    free(jac);
    free(fa);
    free(fb);
    return worst;
}
