/* The RGL .bsdf loader: the fields of a file of the RGL material database
 * (Dupuy and Jakob 2018, "An Adaptive Parameterization for Efficient
 * Material Acquisition and Rendering"), as the database's reference reader
 * and Mitsuba's `measured` plugin read them, checked before any use
 * (docs/formats.md). The grids are made in rgl_grid.c. */
#include <math.h>
#include <string.h>

#include "brdffit/load.h"
#include "core/core.h"
#include "load/load_internal.h"
#include "load/rgl_internal.h"

/* The field `name` with that type, rank and, where want[k] != 0, size. */
static brdffit_status get_field(const bf_tensor *t, const char *name, int dtype, size_t ndim,
                                const size_t *want, const bf_tensor_field **out,
                                brdffit_error *err)
{
    int twice;
    const bf_tensor_field *f = bf_tensor_find(t, name, &twice);
    size_t k;
    if (f == NULL) return bf_fail(err, BRDFFIT_E_FORMAT, "RGL file has no field '%s'", name);
    if (twice) return bf_fail(err, BRDFFIT_E_FORMAT, "RGL field '%s' is given twice", name);
    if (f->dtype != dtype)
        return bf_fail(err, BRDFFIT_E_FORMAT, "RGL field '%s' has type code %d, expected %d (%s)",
                       name, f->dtype, dtype, dtype == BF_DTYPE_UINT8 ? "uint8" : "float32");
    if (f->ndim != ndim)
        return bf_fail(err, BRDFFIT_E_FORMAT, "RGL field '%s' has %zu dimensions, expected %zu",
                       name, f->ndim, ndim);
    for (k = 0; k < ndim; k++) {
        if (want != NULL && want[k] != 0 && f->shape[k] != want[k])
            return bf_fail(err, BRDFFIT_E_FORMAT,
                           "RGL field '%s' has %zu entries in dimension %zu, expected %zu", name,
                           f->shape[k], k + 1, want[k]);
        if (f->shape[k] == 0)
            return bf_fail(err, BRDFFIT_E_FORMAT, "RGL field '%s' is empty", name);
    }
    *out = f;
    return BRDFFIT_OK;
}

/* An axis of light angles: finite, strictly increasing, inside [lo, hi]. */
static brdffit_status check_angles(const bf_tensor_field *f, const char *name, double lo,
                                   double hi, brdffit_error *err)
{
    size_t k;
    for (k = 0; k < f->count; k++) {
        double v = bf_tensor_f32(f, k);
        if (!(v >= lo && v <= hi))
            return bf_fail(err, BRDFFIT_E_RANGE, "RGL %s[%zu] = %g is outside [%g, %g] radians",
                           name, k, v, lo, hi);
        if (k > 0 && !(v > bf_tensor_f32(f, k - 1)))
            return bf_fail(err, BRDFFIT_E_FORMAT, "RGL %s is not strictly increasing at index %zu",
                           name, k);
    }
    return BRDFFIT_OK;
}

static brdffit_status check_finite(const bf_tensor_field *f, const char *name, int positive,
                                   brdffit_error *err)
{
    size_t k;
    for (k = 0; k < f->count; k++) {
        double v = bf_tensor_f32(f, k);
        if (!isfinite(v) || (positive && v < 0.0))
            return bf_fail(err, BRDFFIT_E_RANGE, "RGL %s value %zu is %g", name, k, v);
    }
    return BRDFFIT_OK;
}

/* The light axes and the 2D fields (ndf, sigma, jacobian). */
static brdffit_status read_light(rgl_file *f, brdffit_error *err)
{
    const size_t one = 1;
    const size_t min2[2] = {0, 0};
    const bf_tensor_field *jac;
    BF_RETURN_IF_ERROR(get_field(&f->t, "theta_i", BF_DTYPE_FLOAT32, 1, NULL, &f->theta_i, err));
    BF_RETURN_IF_ERROR(get_field(&f->t, "phi_i", BF_DTYPE_FLOAT32, 1, NULL, &f->phi_i, err));
    BF_RETURN_IF_ERROR(check_angles(f->theta_i, "theta_i", 0.0, BF_HALF_PI, err));
    BF_RETURN_IF_ERROR(check_angles(f->phi_i, "phi_i", -2.0 * BF_PI, 2.0 * BF_PI, err));
    f->n_theta = f->theta_i->count, f->n_phi = f->phi_i->count;
    BF_RETURN_IF_ERROR(get_field(&f->t, "ndf", BF_DTYPE_FLOAT32, 2, min2, &f->ndf, err));
    BF_RETURN_IF_ERROR(get_field(&f->t, "sigma", BF_DTYPE_FLOAT32, 2, min2, &f->sigma, err));
    BF_RETURN_IF_ERROR(get_field(&f->t, "jacobian", BF_DTYPE_UINT8, 1, &one, &jac, err));
    if (f->ndf->shape[0] < 2 || f->ndf->shape[1] < 2 || f->sigma->shape[0] < 2 ||
        f->sigma->shape[1] < 2)
        return bf_fail(err, BRDFFIT_E_FORMAT, "RGL ndf and sigma need at least 2 x 2 values");
    BF_RETURN_IF_ERROR(check_finite(f->ndf, "ndf", 1, err));
    BF_RETURN_IF_ERROR(check_finite(f->sigma, "sigma", 1, err));
    f->jacobian = jac->data[0] != 0;
    f->isotropic = f->n_phi <= 2;
    f->reduction = 1;
    if (!f->isotropic) {
        double span = bf_tensor_f32(f->phi_i, f->n_phi - 1) - bf_tensor_f32(f->phi_i, 0);
        double r = floor(2.0 * BF_PI / span + 0.5); /* span > 0: the axis increases */
        f->reduction = r > 1e6 ? 1000000 : (int)r;
    }
    return BRDFFIT_OK;
}

/* The values: "rgb" (3 channels) if present, else "spectra" with one
 * channel per entry of "wavelengths"; and the vndf. */
static brdffit_status read_values(rgl_file *f, const brdffit_allocator *a, brdffit_error *err)
{
    size_t want[5] = {0, 0, 3, 0, 0};
    const bf_tensor_field *wl;
    const char *name = "rgb";
    int twice;
    want[0] = f->n_phi, want[1] = f->n_theta;
    if (bf_tensor_find(&f->t, "rgb", &twice) == NULL) {
        name = "spectra";
        BF_RETURN_IF_ERROR(get_field(&f->t, "wavelengths", BF_DTYPE_FLOAT32, 1, NULL, &wl, err));
        want[2] = wl->count;
    }
    BF_RETURN_IF_ERROR(get_field(&f->t, name, BF_DTYPE_FLOAT32, 5, want, &f->values, err));
    f->nc = f->values->shape[2], f->ny = f->values->shape[3], f->nx = f->values->shape[4];
    if (f->nx < 2 || f->ny < 2)
        return bf_fail(err, BRDFFIT_E_FORMAT, "RGL %s needs at least 2 x 2 samples per light",
                       name);
    if (f->values->count > BF_LOAD_MAX_VALUES)
        return bf_fail(err, BRDFFIT_E_TOO_LARGE, "RGL %s has %zu values, more than the %zu "
                       "allowed", name, f->values->count, BF_LOAD_MAX_VALUES);
    BF_RETURN_IF_ERROR(check_finite(f->values, name, 0, err));
    want[2] = 0;
    BF_RETURN_IF_ERROR(get_field(&f->t, "vndf", BF_DTYPE_FLOAT32, 4, want, &f->vndf, err));
    f->warp.ny = f->vndf->shape[2], f->warp.nx = f->vndf->shape[3];
    if (f->warp.nx < 2 || f->warp.ny < 2)
        return bf_fail(err, BRDFFIT_E_FORMAT, "RGL vndf needs at least 2 x 2 values per light");
    return bf_warp_build(&f->warp, f->vndf, f->n_phi * f->n_theta, a, err);
}

brdffit_status bf_rgl_open(rgl_file *f, const unsigned char *data, size_t size,
                           const brdffit_allocator *a, brdffit_error *err)
{
    brdffit_status st;
    memset(f, 0, sizeof *f);
    BF_RETURN_IF_ERROR(bf_tensor_parse(&f->t, data, size, a, err));
    st = read_light(f, err);
    if (st == BRDFFIT_OK) st = read_values(f, a, err);
    if (st != BRDFFIT_OK) bf_rgl_close(f, a);
    return st;
}

void bf_rgl_close(rgl_file *f, const brdffit_allocator *a)
{
    bf_warp_free(&f->warp, a);
    bf_tensor_free(&f->t, a);
}

/* ---- entry points ----------------------------------------------------------------- */

static brdffit_status decode(brdffit_grid **out, const unsigned char *data, size_t size,
                             const brdffit_axes *axes, const brdffit_allocator *a,
                             brdffit_error *err)
{
    rgl_file f;
    brdffit_status st;
    BF_RETURN_IF_ERROR(bf_rgl_open(&f, data, size, a, err));
    st = axes == NULL ? bf_rgl_scattered(out, &f, a, err) : bf_rgl_regular(out, &f, axes, a, err);
    bf_rgl_close(&f, a);
    return st;
}

brdffit_status brdffit_load_rgl_buffer(brdffit_grid **out, const void *data, size_t size,
                                       const brdffit_axes *axes, const brdffit_allocator *alloc,
                                       brdffit_error *err)
{
    brdffit_allocator a;
    BF_RETURN_IF_ERROR(bf_load_begin(out, data, axes, alloc, &a, err));
    return decode(out, data, size, axes, &a, err);
}

brdffit_status brdffit_load_rgl(brdffit_grid **out, const char *path, const brdffit_axes *axes,
                                const brdffit_allocator *alloc, brdffit_error *err)
{
    brdffit_allocator a;
    char *data = NULL;
    size_t size = 0;
    brdffit_status st;
    BF_RETURN_IF_ERROR(bf_load_begin(out, path, axes, alloc, &a, err));
    BF_RETURN_IF_ERROR(bf_file_read_all(path, (size_t)-1 >> 1, &a, &data, &size, err));
    st = decode(out, (const unsigned char *)data, size, axes, &a, err);
    bf_free(&a, data);
    return st;
}
