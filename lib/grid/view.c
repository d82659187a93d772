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

brdffit_status bf_grid_view_set(brdffit_grid *view, const double *values,
                                const unsigned char *missing, unsigned char *mask,
                                brdffit_error *err)
{
    size_t n_missing = 0;
    brdffit_status st;
    view->missing = NULL;
    view->n_missing = 0;
    st = bf_grid_check_values(values, missing, view->n_samples, view->n_channels, &n_missing, err);
    if (st != BRDFFIT_OK) return st;
    /* as a grid made from these values: a mask only when a value is missing */
    view->n_missing = n_missing;
    if (n_missing > 0) view->missing = mask;
    bf_grid_store_values(view, values, missing, view->order);
    bf_grid_store_float_values(view);
    return BRDFFIT_OK;
}
