/* Grid views: the geometry of one grid with other values (grid_internal.h),
 * for fits of many value sets over one geometry (brdffit_fit_many()). */
#include "core/core.h"
#include "grid/grid_internal.h"

void bf_grid_view_init(brdffit_grid *view, const brdffit_grid *geometry, double *values)
{
    *view = *geometry; /* geometry, axes, sample weights, order: borrowed */
    view->values = values;
    view->fvalues = (float *)(void *)(values + geometry->n_samples * geometry->n_channels);
    view->fscale = 0.0;
    view->missing = NULL;
    view->n_missing = 0;
}

/* Whether every value is finite: x - x is 0 for a finite x, NaN for inf
 * and NaN, so the sum of them all is 0 exactly when every value is;
 * added in four independent sums, so that no one chain of additions
 * holds the sweep up. */
static int all_finite(const double *values, size_t n)
{
    double s[4] = {0.0, 0.0, 0.0, 0.0};
    size_t v = 0, k;
    for (; v + 4 <= n; v += 4)
        for (k = 0; k < 4; k++) s[k] += values[v + k] - values[v + k];
    for (; v < n; v++) s[0] += values[v] - values[v];
    return (s[0] + s[1]) + (s[2] + s[3]) == 0.0;
}

/* bf_grid_store_values() with no value missing and no mask: each sample's
 * channels from its input row. */
static void store_present(brdffit_grid *view, const double *values)
{
    const size_t n = view->n_samples, nc = view->n_channels, *order = view->order;
    size_t s, c;
    for (s = 0; s < n; s++) {
        const double *row = values + (order != NULL ? order[s] : s) * nc;
        for (c = 0; c < nc; c++) view->values[c * n + s] = row[c] + 0.0;
    }
}

brdffit_status bf_grid_view_set(brdffit_grid *view, const double *values,
                                const unsigned char *missing, unsigned char *mask,
                                brdffit_error *err)
{
    size_t n_missing = 0;
    brdffit_status st;
    view->missing = NULL;
    view->n_missing = 0;
    if (missing == NULL && all_finite(values, view->n_samples * view->n_channels)) {
        store_present(view, values);
        bf_grid_store_float_values(view);
        return BRDFFIT_OK;
    }
    st = bf_grid_check_values(values, missing, view->n_samples, view->n_channels, &n_missing, err);
    if (st != BRDFFIT_OK) return st;
    /* as a grid made from these values: a mask only when a value is missing */
    view->n_missing = n_missing;
    if (n_missing > 0) view->missing = mask;
    bf_grid_store_values(view, values, missing, view->order);
    bf_grid_store_float_values(view);
    return BRDFFIT_OK;
}
