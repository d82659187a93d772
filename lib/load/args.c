/* Argument checks shared by the loaders. */
#include "core/core.h"
#include "load/load_internal.h"

/* One axis as brdffit_grid_create_regular() checks it (same statuses), so
 * that bad axes are refused before the file is opened. */
static brdffit_status check_axis_values(const double *x, size_t n, const char *name, double hi,
                                        brdffit_error *err)
{
    size_t k;
    for (k = 0; k < n; k++) {
        if (!(x[k] >= 0.0 && x[k] <= hi))
            return bf_fail(err, BRDFFIT_E_RANGE, "%s[%zu] = %g is outside [0, %.17g]", name, k,
                           x[k], hi);
        if (k > 0 && !(x[k] > x[k - 1]))
            return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT,
                           "%s is not strictly increasing at index %zu (%.17g after %.17g)", name,
                           k, x[k], x[k - 1]);
    }
    return BRDFFIT_OK;
}

brdffit_status bf_load_axes_count(const brdffit_axes *axes, size_t n_channels, size_t *n_samples,
                                  brdffit_error *err)
{
    size_t n;
    if (axes->theta_i == NULL || axes->theta_o == NULL || axes->phi_o == NULL ||
        axes->n_theta_i == 0 || axes->n_theta_o == 0 || axes->n_phi_o == 0)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "an axis is NULL or empty");
    if (!bf_mul_size(axes->n_theta_i, axes->n_theta_o, &n) || !bf_mul_size(n, axes->n_phi_o, &n) ||
        n > BF_LOAD_MAX_VALUES / n_channels)
        return bf_fail(err, BRDFFIT_E_TOO_LARGE, "axes of %zu x %zu x %zu are too large",
                       axes->n_theta_i, axes->n_theta_o, axes->n_phi_o);
    BF_RETURN_IF_ERROR(check_axis_values(axes->theta_i, axes->n_theta_i, "theta_i",
                                         BF_HALF_PI, err));
    BF_RETURN_IF_ERROR(check_axis_values(axes->theta_o, axes->n_theta_o, "theta_o",
                                         BF_HALF_PI, err));
    BF_RETURN_IF_ERROR(check_axis_values(axes->phi_o, axes->n_phi_o, "phi_o", BF_PI, err));
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
    return axes != NULL ? bf_load_axes_count(axes, 1, &n, err) : BRDFFIT_OK;
}
