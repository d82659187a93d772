/* The canonical lobe order: see canonical.h. The model's value is the same
 * with the lobes swapped, so the cost, the error figures and the verdict
 * do not change; only where each lobe is reported does. */
#include "fit/canonical.h"

#include "models/lobes.h"

/* Swap rows a and b, then columns a and b, of the n x n covariance. */
static void swap_covariance(double *cov, size_t n, size_t a, size_t b)
{
    size_t i;
    double t;
    for (i = 0; i < n; i++) {
        t = cov[a * n + i];
        cov[a * n + i] = cov[b * n + i];
        cov[b * n + i] = t;
    }
    for (i = 0; i < n; i++) {
        t = cov[i * n + a];
        cov[i * n + a] = cov[i * n + b];
        cov[i * n + b] = t;
    }
}

static void swap_entries(bf_result *r, size_t n, size_t a, size_t b)
{
    double t = r->params[a];
    r->params[a] = r->params[b];
    r->params[b] = t;
    t = r->std_errors[a];
    r->std_errors[a] = r->std_errors[b];
    r->std_errors[b] = t;
    if (r->cov != NULL) swap_covariance(r->cov, n, a, b);
}

/* Swap declared parameters k and l in every channel. */
static void swap_params(const bf_run *run, size_t k, size_t l)
{
    const brdffit_model *model = run->fit->model;
    size_t c, nc = run->fit->nc;
    int per = (brdffit_model_param(model, k)->flags & BRDFFIT_PARAM_PER_CHANNEL) != 0;
    for (c = 0; c < (per ? nc : 1); c++)
        swap_entries(run->result, run->fit->n_vec, brdffit_model_vector_index(model, k, c, nc),
                     brdffit_model_vector_index(model, l, c, nc));
}

void bf_canonical_lobes(bf_run *run)
{
    const brdffit_fit *fit = run->fit;
    const brdffit_model *model = fit->model;
    const bf_lobes *lobes = bf_model_lobes(model);
    const bf_lobe_desc *a, *b;
    double x1, x2;
    /* a user model's lobes need not be the same function: described ones only */
    if (lobes == NULL || lobes->n != 2 || !lobes->interchangeable) return;
    a = &lobes->lobe[0];
    b = &lobes->lobe[1];
    if (fit->fixed[a->shape] || fit->fixed[b->shape] || fit->fixed[a->colour] ||
        fit->fixed[b->colour])
        return;
    x1 = run->result->params[brdffit_model_vector_index(model, a->shape, 0, fit->nc)];
    x2 = run->result->params[brdffit_model_vector_index(model, b->shape, 0, fit->nc)];
    if (a->sharper_larger ? x1 >= x2 : x1 <= x2) return;
    swap_params(run, a->shape, b->shape);
    swap_params(run, a->colour, b->colour);
}
