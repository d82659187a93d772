/* Lambert, normalised Phong (3.2) and Blinn-Phong (3.3): the cosine-power
 * lobes. Formulas as implemented are in docs/models.md. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "core/core.h"
#include "core/fastmath.h"
#include "models/kernel.h"

#define LINEAR_FLAGS (BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR)

static void fill_diffuse(double *restrict out, size_t count)
{
    size_t i;
    for (i = 0; i < count; i++) out[i] = 1.0 / BF_PI;
}

/* --- Lambert: cd / pi ------------------------------------------------------ */

BF_VECTOR_CLONES
static void lambert_basis(const brdffit_batch *batch, size_t first, size_t count,
                          const double *shape, bf_basis *out)
{
    (void)batch;
    (void)first;
    (void)shape;
    fill_diffuse(out->b[0], count);
}

/* Lambert is the lobe form without lobes (basis.h): this is never called. */
static void lambert_lobe_form(double theta, bf_lobe *out)
{
    (void)theta;
    memset(out, 0, sizeof *out);
}

static const bf_kernel lambert_kernel = {0, 1, {0}, lambert_basis, lambert_lobe_form, BF_MF_NONE};

static brdffit_status lambert_eval(const brdffit_batch *batch, const double *params,
                                   size_t n_channels, double *values, double *jacobian, void *user)
{
    (void)user;
    return bf_kernel_run(&lambert_kernel, batch, params, n_channels, values, jacobian);
}

static const brdffit_param_info lambert_params[] = {
    {"cd", LINEAR_FLAGS, 0.0, HUGE_VAL, 0.2},
};

const bf_builtin bf_builtin_lambert = {"lambert", 1, lambert_params, lambert_eval, &lambert_kernel,
                                       0};

/* --- Phong, normalised: cd/pi + (ns+2)/(2 pi) cs max(0, r.v)^ns ----------- */

/* max(0, r.v)^ns is exp(ns ln r.v) where r.v > 0 and exactly 0 elsewhere;
 * the logarithm is taken of max(r.v, DBL_MIN), so it stays finite and the
 * derivative P ln(r.v) is finite too (and 0 where P is 0). */
BF_VECTOR_CLONES
static void phong_basis(const brdffit_batch *batch, size_t first, size_t count, const double *shape,
                        bf_basis *out)
{
    const double ns = shape[0];
    const double k = (ns + 2.0) / (2.0 * BF_PI), dk = 1.0 / (2.0 * BF_PI);
    const double *restrict rv = batch->rv + first;
    double *restrict bs = out->b[1], *restrict dbs = out->db[0][1];
    size_t i;
    fill_diffuse(out->b[0], count);
    for (i = 0; i < count; i++) {
        const double lr = log(bf_min(bf_max(rv[i], DBL_MIN), 1.0));
        const double p = rv[i] > 0.0 ? bf_exp(ns * lr) : 0.0;
        bs[i] = k * p;
        dbs[i] = (dk + k * lr) * p;
    }
}

/* The lobe above as the fused pass computes it, from the grid's ln r.v. */
static void phong_lobe_form(double ns, bf_lobe *out)
{
    out->x = BF_LOBE_X_LOG_RV;
    out->g = BF_LOBE_G_RV_POSITIVE;
    out->k = (ns + 2.0) / (2.0 * BF_PI);
    out->dk = 1.0 / (2.0 * BF_PI);
}

static const bf_kernel phong_kernel = {1, 2, {2u}, phong_basis, phong_lobe_form, BF_MF_NONE};

static brdffit_status phong_eval(const brdffit_batch *batch, const double *params,
                                 size_t n_channels, double *values, double *jacobian, void *user)
{
    (void)user;
    return bf_kernel_run(&phong_kernel, batch, params, n_channels, values, jacobian);
}

static const brdffit_param_info cosine_lobe_params[] = {
    {"ns", BRDFFIT_PARAM_LOG_SCALE, BF_EXP_LO, BF_EXP_HI, 50.0},
    {"cd", LINEAR_FLAGS, 0.0, HUGE_VAL, 0.2},
    {"cs", LINEAR_FLAGS, 0.0, HUGE_VAL, 0.2},
};

const bf_builtin bf_builtin_phong = {"phong", 3, cosine_lobe_params, phong_eval, &phong_kernel,
                                     0};

/* --- Blinn-Phong: cd/pi + (ns+8)/(8 pi) cs (n.h)^ns ----------------------- */

BF_VECTOR_CLONES
static void blinn_basis(const brdffit_batch *batch, size_t first, size_t count, const double *shape,
                        bf_basis *out)
{
    const double ns = shape[0];
    const double k = (ns + 8.0) / (8.0 * BF_PI), dk = 1.0 / (8.0 * BF_PI);
    const double *restrict lnh = batch->log_nh + first;
    double *restrict bs = out->b[1], *restrict dbs = out->db[0][1];
    size_t i;
    fill_diffuse(out->b[0], count);
    for (i = 0; i < count; i++) {
        const double p = bf_exp(ns * lnh[i]);
        bs[i] = k * p;
        dbs[i] = (dk + k * lnh[i]) * p;
    }
}

static void blinn_lobe_form(double ns, bf_lobe *out)
{
    out->x = BF_LOBE_X_LOG_NH;
    out->g = BF_LOBE_G_ONE;
    out->k = (ns + 8.0) / (8.0 * BF_PI);
    out->dk = 1.0 / (8.0 * BF_PI);
}

static const bf_kernel blinn_kernel = {1, 2, {2u}, blinn_basis, blinn_lobe_form, BF_MF_NONE};

static brdffit_status blinn_eval(const brdffit_batch *batch, const double *params,
                                 size_t n_channels, double *values, double *jacobian, void *user)
{
    (void)user;
    return bf_kernel_run(&blinn_kernel, batch, params, n_channels, values, jacobian);
}

const bf_builtin bf_builtin_blinn_phong = {"blinn-phong", 3, cosine_lobe_params, blinn_eval,
                                           &blinn_kernel, 0};
