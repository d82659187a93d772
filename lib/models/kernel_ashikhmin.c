/* Ashikhmin-Shirley: the simplified form (4.28), the shader form with
 * Fresnel (4.17, 4.18, 4.12) and a two-lobe variant. Formulas as
 * implemented are in docs/models.md. */
#include <math.h>

#include "core/core.h"
#include "core/fastmath.h"
#include "models/kernel.h"

#define LINEAR_FLAGS (BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR)

/* 1 / (8 pi (h.v) max(n.l, n.v)): the geometry of the specular lobe; at
 * most 1/(8 pi 1e-8) with clamped dot products. */
static void as_geometry(const brdffit_batch *batch, size_t first, size_t count,
                        double *restrict inv_den)
{
    const double *restrict hv = batch->hv + first;
    const double *restrict nl = batch->nl + first;
    const double *restrict nv = batch->nv + first;
    size_t i;
    for (i = 0; i < count; i++) inv_den[i] = 1.0 / (8.0 * BF_PI * hv[i] * bf_max(nl[i], nv[i]));
}

/* The specular lobe (ns+1) (n.h)^ns inv_den and its derivative with respect
 * to ns, [1 + (ns+1) ln(n.h)] (n.h)^ns inv_den (4.29). (n.h)^ns =
 * exp(ns ln(n.h)) <= 1 never overflows. */
static void as_lobe(const brdffit_batch *batch, size_t first, size_t count, double ns,
                    const double *restrict inv_den, double *restrict lobe, double *restrict dlobe)
{
    const double *restrict lnh = batch->log_nh + first;
    size_t i;
    for (i = 0; i < count; i++) {
        const double p = bf_exp(ns * lnh[i]) * inv_den[i];
        lobe[i] = (ns + 1.0) * p;
        dlobe[i] = (1.0 + (ns + 1.0) * lnh[i]) * p;
    }
}

static void fill_diffuse(double *restrict out, size_t count)
{
    size_t i;
    for (i = 0; i < count; i++) out[i] = 1.0 / BF_PI;
}

/* --- simplified (4.28): cd/pi + cs lobe(ns) -------------------------------- */

BF_VECTOR_CLONES
static void as_basis(const brdffit_batch *batch, size_t first, size_t count, const double *shape,
                     bf_basis *out)
{
    double inv_den[BF_KERNEL_BLOCK] = {0.0};
    fill_diffuse(out->b[0], count);
    as_geometry(batch, first, count, inv_den);
    as_lobe(batch, first, count, shape[0], inv_den, out->b[1], out->db[0][1]);
}

/* The lobe above as the fused pass computes it: k = ns + 1, dk = 1. */
static void as_lobe_form(double ns, bf_lobe *out)
{
    out->x = BF_LOBE_X_LOG_NH;
    out->g = BF_LOBE_G_AS;
    out->k = ns + 1.0;
    out->dk = 1.0;
}

static const bf_kernel as_kernel = {1, 2, {2u}, as_basis, as_lobe_form, BF_MF_NONE};

static brdffit_status as_eval(const brdffit_batch *batch, const double *params, size_t n_channels,
                              double *values, double *jacobian, void *user)
{
    (void)user;
    return bf_kernel_run(&as_kernel, batch, params, n_channels, values, jacobian);
}

static const brdffit_param_info as_params[] = {
    {"ns", BRDFFIT_PARAM_LOG_SCALE, BF_EXP_LO, BF_EXP_HI, 50.0},
    {"cd", LINEAR_FLAGS, 0.0, HUGE_VAL, 0.2},
    {"cs", LINEAR_FLAGS, 0.0, HUGE_VAL, 0.2},
};

const bf_builtin bf_builtin_ashikhmin_shirley = {"ashikhmin-shirley", 3, as_params, as_eval,
                                                 &as_kernel, 0};

/* --- with Fresnel, shader form --------------------------------------------- */

static double pow5(double x)
{
    const double x2 = x * x;
    return x2 * x2 * x;
}

/* Diffuse: 28/(23 pi) (1-Rs) (1-(1-n.l/2)^5) (1-(1-n.v/2)^5) cd.
 * Specular: lobe(ns) F(h.v) cs, F(x) = Rs + (1-Rs)(1-x)^5. */
BF_VECTOR_CLONES
static void asf_basis(const brdffit_batch *batch, size_t first, size_t count, const double *shape,
                      bf_basis *out)
{
    const double rs = shape[1], kd = 28.0 / (23.0 * BF_PI);
    const double *restrict nl = batch->nl + first;
    const double *restrict nv = batch->nv + first;
    const double *restrict hv = batch->hv + first;
    double *restrict bd = out->b[0], *restrict dbd = out->db[1][0];
    double *restrict bs = out->b[1], *restrict dbs_ns = out->db[0][1];
    double *restrict dbs_rs = out->db[1][1];
    double inv_den[BF_KERNEL_BLOCK] = {0.0};
    size_t i;
    as_geometry(batch, first, count, inv_den);
    as_lobe(batch, first, count, shape[0], inv_den, bs, dbs_ns);
    for (i = 0; i < count; i++) {
        const double fd = kd * (1.0 - pow5(1.0 - 0.5 * nl[i])) * (1.0 - pow5(1.0 - 0.5 * nv[i]));
        const double f5 = pow5(1.0 - hv[i]);
        const double fresnel = rs + (1.0 - rs) * f5;
        bd[i] = (1.0 - rs) * fd;
        dbd[i] = -fd;
        dbs_rs[i] = bs[i] * (1.0 - f5);
        bs[i] *= fresnel;
        dbs_ns[i] *= fresnel;
    }
}

/* ns -> cs; Rs -> cd, cs. The fused pass computes the expressions above
 * (models/basis.h, BF_MF_AS_FRESNEL). */
static const bf_kernel asf_kernel = {2, 2, {2u, 3u}, asf_basis, NULL, BF_MF_AS_FRESNEL};

static brdffit_status asf_eval(const brdffit_batch *batch, const double *params, size_t n_channels,
                               double *values, double *jacobian, void *user)
{
    (void)user;
    return bf_kernel_run(&asf_kernel, batch, params, n_channels, values, jacobian);
}

static const brdffit_param_info asf_params[] = {
    {"ns", BRDFFIT_PARAM_LOG_SCALE, BF_EXP_LO, BF_EXP_HI, 50.0},
    {"Rs", 0u, 0.0, 1.0, 0.2},
    {"cd", LINEAR_FLAGS, 0.0, HUGE_VAL, 0.2},
    {"cs", LINEAR_FLAGS, 0.0, HUGE_VAL, 0.2},
};

const bf_builtin bf_builtin_ashikhmin_shirley_fresnel = {"ashikhmin-shirley-fresnel", 4, asf_params,
                                                         asf_eval, &asf_kernel, 0};

/* --- two lobes: cd/pi + cs1 lobe(ns1) + cs2 lobe(ns2) ---------------------- */

BF_VECTOR_CLONES
static void as2_basis(const brdffit_batch *batch, size_t first, size_t count, const double *shape,
                      bf_basis *out)
{
    double inv_den[BF_KERNEL_BLOCK] = {0.0};
    fill_diffuse(out->b[0], count);
    as_geometry(batch, first, count, inv_den);
    as_lobe(batch, first, count, shape[0], inv_den, out->b[1], out->db[0][1]);
    as_lobe(batch, first, count, shape[1], inv_den, out->b[2], out->db[1][2]);
}

/* ns1 -> cs1; ns2 -> cs2; each lobe as as_lobe_form() says. */
static const bf_kernel as2_kernel = {2, 3, {2u, 4u}, as2_basis, as_lobe_form, BF_MF_NONE};

static brdffit_status as2_eval(const brdffit_batch *batch, const double *params, size_t n_channels,
                               double *values, double *jacobian, void *user)
{
    (void)user;
    return bf_kernel_run(&as2_kernel, batch, params, n_channels, values, jacobian);
}

static const brdffit_param_info as2_params[] = {
    {"ns1", BRDFFIT_PARAM_LOG_SCALE, BF_EXP_LO, BF_EXP_HI, 20.0},
    {"ns2", BRDFFIT_PARAM_LOG_SCALE, BF_EXP_LO, BF_EXP_HI, 500.0},
    {"cd", LINEAR_FLAGS, 0.0, HUGE_VAL, 0.2},
    {"cs1", LINEAR_FLAGS, 0.0, HUGE_VAL, 0.2},
    {"cs2", LINEAR_FLAGS, 0.0, HUGE_VAL, 0.2},
};

const bf_builtin bf_builtin_ashikhmin_shirley_2 = {"ashikhmin-shirley-2", 5, as2_params, as2_eval,
                                                   &as2_kernel, 0};
