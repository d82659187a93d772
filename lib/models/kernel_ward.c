/* Isotropic Ward lobes: Ward's normalisation (with the square root) and
 * Duer's (without). Formulas as implemented are in docs/models.md. */
#include <math.h>

#include "core/core.h"
#include "core/fastmath.h"
#include "models/kernel.h"

#define LINEAR_FLAGS (BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR)

/* lobe = exp(-x) / (4 pi a^2 N), x = tan^2 theta_h / a^2, N = sqrt((n.l)(n.v))
 * (Ward) or (n.l)(n.v) (Duer); d lobe/da = lobe (2/a) (x - 1). exp(-x) <= 1
 * and N >= 1e-8, so nothing overflows for a in [1e-4, 1]. */
static void ward_basis_common(const brdffit_batch *batch, size_t first, size_t count,
                              const double *shape, bf_basis *out, int duer)
{
    const double a = shape[0], inv_a2 = 1.0 / (a * a);
    const double k = inv_a2 / (4.0 * BF_PI), two_over_a = 2.0 / a;
    const double *restrict nh = batch->nh + first;
    const double *restrict nl = batch->nl + first;
    const double *restrict nv = batch->nv + first;
    double *restrict bd = out->b[0], *restrict bs = out->b[1], *restrict dbs = out->db[0][1];
    double inv_n[BF_KERNEL_BLOCK];
    size_t i;
    if (duer)
        for (i = 0; i < count; i++) inv_n[i] = k / (nl[i] * nv[i]);
    else
        for (i = 0; i < count; i++) inv_n[i] = k / sqrt(nl[i] * nv[i]);
    for (i = 0; i < count; i++) {
        const double c = nh[i];
        const double x = (1.0 - c) * (1.0 + c) / (c * c) * inv_a2;
        const double b = bf_exp(-x) * inv_n[i];
        bd[i] = 1.0 / BF_PI;
        bs[i] = b;
        dbs[i] = b * two_over_a * (x - 1.0);
    }
}

BF_VECTOR_CLONES
static void ward_basis(const brdffit_batch *batch, size_t first, size_t count, const double *shape,
                       bf_basis *out)
{
    ward_basis_common(batch, first, count, shape, out, 0);
}

BF_VECTOR_CLONES
static void ward_duer_basis(const brdffit_batch *batch, size_t first, size_t count,
                            const double *shape, bf_basis *out)
{
    ward_basis_common(batch, first, count, shape, out, 1);
}

/* Of the microfacet form's frame (basis.h): the fit's fused loop
 * (fit/pass_lanes.h, lane_mf_basis(), and its vector copy) computes
 * ward_basis_common() lane by lane with the same operations in the same
 * order; change them together (test_fused.c checks that they agree). */
static const bf_kernel ward_kernel = {1, 2, {2u}, ward_basis, NULL, BF_MF_WARD};
static const bf_kernel ward_duer_kernel = {1, 2, {2u}, ward_duer_basis, NULL, BF_MF_WARD_DUER};

static brdffit_status ward_eval(const brdffit_batch *batch, const double *params, size_t n_channels,
                                double *values, double *jacobian, void *user)
{
    (void)user;
    return bf_kernel_run(&ward_kernel, batch, params, n_channels, values, jacobian);
}

static brdffit_status ward_duer_eval(const brdffit_batch *batch, const double *params,
                                     size_t n_channels, double *values, double *jacobian,
                                     void *user)
{
    (void)user;
    return bf_kernel_run(&ward_duer_kernel, batch, params, n_channels, values, jacobian);
}

static const brdffit_param_info ward_params[] = {
    {"a", BRDFFIT_PARAM_LOG_SCALE, BF_ROUGH_LO, BF_ROUGH_HI, 0.2},
    {"cd", LINEAR_FLAGS, 0.0, HUGE_VAL, 0.2},
    {"cs", LINEAR_FLAGS, 0.0, HUGE_VAL, 0.2},
};

const bf_builtin bf_builtin_ward = {"ward", 3, ward_params, ward_eval, &ward_kernel, 0};
const bf_builtin bf_builtin_ward_duer = {"ward-duer", 3, ward_params, ward_duer_eval,
                                         &ward_duer_kernel, 0};
