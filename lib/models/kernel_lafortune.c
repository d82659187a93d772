/* One isotropic Lafortune lobe. Formulas as implemented, and the reason for
 * the parameterisation, are in docs/models.md.
 *
 * value = cd/pi + cs max(0, base)^n, base = -(lx vx + ly vy) + cz lz vz,
 * i.e. Cxy = -1 and Cz = cz in [0, 1]. Scaling (Cxy, Cz) by s scales the
 * lobe by s^n, which cs absorbs; fixing Cxy = -1 removes that freedom while
 * keeping base <= 1 (so base^n never overflows, whatever n), and cz = 1 is
 * the unnormalised Phong lobe (r.v)^n. */
#include <math.h>

#include "core/core.h"
#include "core/fastmath.h"
#include "models/kernel.h"

#define LINEAR_FLAGS (BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR)

/* Positive bases below this are raised to it: base^(n-1), which the cz
 * derivative needs, is unbounded near 0 for n < 1. */
#define BASE_FLOOR 1e-12

/* P = base^n = exp(n ln base) where base > 0, else 0;
 * dP/dn = P ln base; dP/dcz = n P / base lz vz (0 where base <= floor). */
BF_VECTOR_CLONES
static void lafortune_basis(const brdffit_batch *batch, size_t first, size_t count,
                            const double *shape, bf_basis *out)
{
    const double n = shape[0], cz = shape[1];
    const double *restrict lx = batch->lx + first, *restrict ly = batch->ly + first;
    const double *restrict lz = batch->lz + first, *restrict vx = batch->vx + first;
    const double *restrict vy = batch->vy + first, *restrict vz = batch->vz + first;
    double *restrict bd = out->b[0], *restrict bs = out->b[1];
    double *restrict dn = out->db[0][1], *restrict dcz = out->db[1][1];
    size_t i;
    for (i = 0; i < count; i++) {
        const double zz = lz[i] * vz[i];
        const double base = cz * zz - (lx[i] * vx[i] + ly[i] * vy[i]);
        const double bb = bf_max(base, BASE_FLOOR);
        const double lb = log(bb);
        const double p = base > 0.0 ? bf_exp(n * lb) : 0.0;
        bd[i] = 1.0 / BF_PI;
        bs[i] = p;
        dn[i] = p * lb;
        dcz[i] = base > BASE_FLOOR ? n * (p / bb) * zz : 0.0;
    }
}

/* n -> cs; cz -> cs. */
static const bf_kernel lafortune_kernel = {2, 2, {2u, 2u}, lafortune_basis, NULL, BF_MF_NONE};

static brdffit_status lafortune_eval(const brdffit_batch *batch, const double *params,
                                     size_t n_channels, double *values, double *jacobian,
                                     void *user)
{
    (void)user;
    return bf_kernel_run(&lafortune_kernel, batch, params, n_channels, values, jacobian);
}

static const brdffit_param_info lafortune_params[] = {
    {"n", BRDFFIT_PARAM_LOG_SCALE, BF_EXP_LO, BF_EXP_HI, 50.0},
    {"cz", 0u, 0.0, 1.0, 0.9},
    {"cd", LINEAR_FLAGS, 0.0, HUGE_VAL, 0.2},
    {"cs", LINEAR_FLAGS, 0.0, HUGE_VAL, 1.0},
};

const bf_builtin bf_builtin_lafortune = {"lafortune", 4, lafortune_params, lafortune_eval,
                                         &lafortune_kernel, 0};
