/* Argument checks shared by the loaders. */
#include "core/core.h"
#include "load/load_internal.h"

brdffit_status bf_load_axes_count(const brdffit_axes *axes, size_t *n_samples, brdffit_error *err)
{
    size_t n;
    if (axes->theta_i == NULL || axes->theta_o == NULL || axes->phi_o == NULL ||
        axes->n_theta_i == 0 || axes->n_theta_o == 0 || axes->n_phi_o == 0)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "an axis is NULL or empty");
    if (!bf_mul_size(axes->n_theta_i, axes->n_theta_o, &n) || !bf_mul_size(n, axes->n_phi_o, &n) ||
        n > BF_LOAD_MAX_VALUES)
        return bf_fail(err, BRDFFIT_E_TOO_LARGE, "axes of %zu x %zu x %zu are too large",
                       axes->n_theta_i, axes->n_theta_o, axes->n_phi_o);
    *n_samples = n;
    return BRDFFIT_OK;
}

brdffit_status bf_load_begin(brdffit_grid **out, const void *in, const brdffit_axes *axes,
                             const brdffit_allocator *alloc, brdffit_allocator *a,
                             brdffit_error *err)
{
    size_t n;
    if (out == NULL) return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "out is NULL");
    *out = NULL;
    if (in == NULL) return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "path or data is NULL");
    if (!bf_alloc_init(a, alloc))
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "allocator lacks alloc or free");
    return axes != NULL ? bf_load_axes_count(axes, &n, err) : BRDFFIT_OK;
}
