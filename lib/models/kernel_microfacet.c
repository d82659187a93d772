/* Microfacet lobes: Cook-Torrance (Beckmann D, V-cavity G) and GGX
 * (Trowbridge-Reitz D, height-correlated Smith G), both with Schlick's
 * Fresnel term, in one- and two-lobe models. Formulas as implemented are in
 * docs/models.md.
 *
 * Every lobe is D G F / (4 (n.l)(n.v)) with clamped dot products. The terms
 * that depend only on the geometry are computed once per sample and shared
 * by the lobes; the forms below never overflow for roughness in [1e-4, 1]:
 * tan^2 <= 1e8, the Beckmann exponential underflows to 0 harmlessly, and
 * the GGX denominator q is at least min(1, a^2). */
#include <math.h>

#include "core/core.h"
#include "core/fastmath.h"
#include "models/kernel.h"

#define LINEAR_FLAGS (BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR)

/* F0 is held fixed by default: away from grazing angles it trades off
 * almost exactly against cs (docs/models.md). */
#define FRESNEL_F0_FLAGS BRDFFIT_PARAM_FIXED
#define FRESNEL_F0_START 0.04

/* Outputs of one lobe: value, d/d(roughness), d/dF0. */
typedef struct lobe_out {
    double *restrict b, *restrict d_rough, *restrict d_f0;
} lobe_out;

/* Per-sample terms that do not depend on the shape parameters, shared by
 * the lobes of a block. */
typedef struct mf_geometry {
    double t[BF_KERNEL_BLOCK];  /* CT: tan^2 theta_h; GGX: sin^2 theta_h */
    double c2[BF_KERNEL_BLOCK]; /* GGX: cos^2 theta_h */
    /* CT: G / (pi cos^4 theta_h 4 (n.l)(n.v)); GGX: 1 / (4 (n.l)(n.v)) */
    double w[BF_KERNEL_BLOCK];
    double tl[BF_KERNEL_BLOCK]; /* GGX: tan^2 theta_l */
    double tv[BF_KERNEL_BLOCK]; /* GGX: tan^2 theta_v */
    double f5[BF_KERNEL_BLOCK]; /* (1 - h.v)^5 */
} mf_geometry;

static double pow5(double x)
{
    const double x2 = x * x;
    return x2 * x2 * x;
}

/* tan^2 of the angle whose cosine is c (c >= 1e-4: at most 1e8). */
static double tan2(double c)
{
    return (1.0 - c) * (1.0 + c) / (c * c);
}

/* --- Cook-Torrance lobe ---------------------------------------------------- */

/* G = min(1, 2 (n.h) min(n.l, n.v) / (h.v)). */
static void ct_geometry(const brdffit_batch *batch, size_t first, size_t count, mf_geometry *g)
{
    const double *restrict nh = batch->nh + first;
    const double *restrict hv = batch->hv + first;
    const double *restrict nl = batch->nl + first;
    const double *restrict nv = batch->nv + first;
    double *restrict t = g->t, *restrict w = g->w, *restrict f5 = g->f5;
    size_t i;
    for (i = 0; i < count; i++) {
        const double c2 = nh[i] * nh[i];
        const double gg = bf_min(1.0, 2.0 * nh[i] * bf_min(nl[i], nv[i]) / hv[i]);
        t[i] = tan2(nh[i]);
        w[i] = gg / (4.0 * BF_PI * c2 * c2 * nl[i] * nv[i]);
        f5[i] = pow5(1.0 - hv[i]);
    }
}

/* D G / (4 (n.l)(n.v)) = exp(-x) / m^2 w, x = tan^2 theta_h / m^2 (exp(-x) <= 1
 * underflows harmlessly; w <= 1e24 / pi); d/dm = lobe (2/m) (x - 1). */
static void ct_lobe(const mf_geometry *g, size_t count, double m, double f0, lobe_out o)
{
    const double inv_m2 = 1.0 / (m * m), two_over_m = 2.0 / m;
    const double *restrict t = g->t, *restrict w = g->w, *restrict f5 = g->f5;
    size_t i;
    for (i = 0; i < count; i++) {
        const double x = t[i] * inv_m2;
        const double dgs = bf_exp(-x) * inv_m2 * w[i];
        const double b = dgs * (f0 + (1.0 - f0) * f5[i]);
        o.b[i] = b;
        o.d_rough[i] = b * two_over_m * (x - 1.0);
        o.d_f0[i] = dgs * (1.0 - f5[i]);
    }
}

/* --- GGX lobe ------------------------------------------------------------- */

static void ggx_geometry(const brdffit_batch *batch, size_t first, size_t count, mf_geometry *g)
{
    const double *restrict nh = batch->nh + first;
    const double *restrict hv = batch->hv + first;
    const double *restrict nl = batch->nl + first;
    const double *restrict nv = batch->nv + first;
    double *restrict t = g->t, *restrict w = g->w, *restrict tl = g->tl, *restrict tv = g->tv;
    double *restrict c2 = g->c2, *restrict f5 = g->f5;
    size_t i;
    for (i = 0; i < count; i++) {
        t[i] = (1.0 - nh[i]) * (1.0 + nh[i]);
        c2[i] = nh[i] * nh[i];
        w[i] = 1.0 / (4.0 * nl[i] * nv[i]);
        tl[i] = tan2(nl[i]);
        tv[i] = tan2(nv[i]);
        f5[i] = pow5(1.0 - hv[i]);
    }
}

/* D = a^2 / (pi q^2), q = sin^2 theta_h + a^2 cos^2 theta_h >= min(1, a^2),
 * dD/da = D (2/a - 4 a cos^2 theta_h / q).
 * With s_w = sqrt(1 + a^2 tan^2 theta_w), L(w) = (s_w - 1)/2, so
 * G = 1 / (1 + L(l) + L(v)) = 2 / (s_l + s_v) and, as ds_w/da = a tan^2 theta_w / s_w,
 * dG/da = -2 a (t_l s_v + t_v s_l) s_l s_v r^2 with r = 1 / ((s_l + s_v) s_l s_v). */
static void ggx_lobe(const mf_geometry *g, size_t count, double a, double f0, lobe_out o)
{
    const double a2 = a * a, two_over_a = 2.0 / a;
    const double *restrict t = g->t, *restrict c2 = g->c2, *restrict w = g->w;
    const double *restrict tl = g->tl, *restrict tv = g->tv, *restrict f5 = g->f5;
    size_t i;
    for (i = 0; i < count; i++) {
        const double iq = 1.0 / (t[i] + a2 * c2[i]);
        const double d = a2 * iq * iq / BF_PI;
        const double dd = d * (two_over_a - 4.0 * a * c2[i] * iq);
        const double sl = sqrt(1.0 + a2 * tl[i]), sv = sqrt(1.0 + a2 * tv[i]);
        const double r = 1.0 / ((sl + sv) * sl * sv);
        const double gg = 2.0 * sl * sv * r;
        const double dg = -2.0 * a * (tl[i] * sv + tv[i] * sl) * sl * sv * r * r;
        const double dgs = d * gg * w[i];
        o.b[i] = dgs * (f0 + (1.0 - f0) * f5[i]);
        o.d_rough[i] = (dd * gg + d * dg) * w[i] * (f0 + (1.0 - f0) * f5[i]);
        o.d_f0[i] = dgs * (1.0 - f5[i]);
    }
}

/* --- models ---------------------------------------------------------------- */

static void fill_diffuse(double *restrict out, size_t count)
{
    size_t i;
    for (i = 0; i < count; i++) out[i] = 1.0 / BF_PI;
}

/* One lobe: shape (rough, F0), linear (cd, cs). */
static lobe_out one_lobe_out(bf_basis *out)
{
    lobe_out o;
    o.b = out->b[1];
    o.d_rough = out->db[0][1];
    o.d_f0 = out->db[1][1];
    return o;
}

/* Two lobes: shape (rough1, rough2, F0), linear (cd, cs1, cs2). Both lobes
 * share F0: its derivative is cs1 dB_1/dF0 + cs2 dB_2/dF0. */
static lobe_out two_lobe_out(bf_basis *out, size_t lobe)
{
    lobe_out o;
    o.b = out->b[1 + lobe];
    o.d_rough = out->db[lobe][1 + lobe];
    o.d_f0 = out->db[2][1 + lobe];
    return o;
}

BF_VECTOR_CLONES
static void ct_basis(const brdffit_batch *batch, size_t first, size_t count, const double *shape,
                     bf_basis *out)
{
    mf_geometry g;
    fill_diffuse(out->b[0], count);
    ct_geometry(batch, first, count, &g);
    ct_lobe(&g, count, shape[0], shape[1], one_lobe_out(out));
}

BF_VECTOR_CLONES
static void ggx_basis(const brdffit_batch *batch, size_t first, size_t count, const double *shape,
                      bf_basis *out)
{
    mf_geometry g;
    fill_diffuse(out->b[0], count);
    ggx_geometry(batch, first, count, &g);
    ggx_lobe(&g, count, shape[0], shape[1], one_lobe_out(out));
}

BF_VECTOR_CLONES
static void ct2_basis(const brdffit_batch *batch, size_t first, size_t count, const double *shape,
                      bf_basis *out)
{
    mf_geometry g;
    fill_diffuse(out->b[0], count);
    ct_geometry(batch, first, count, &g);
    ct_lobe(&g, count, shape[0], shape[2], two_lobe_out(out, 0));
    ct_lobe(&g, count, shape[1], shape[2], two_lobe_out(out, 1));
}

BF_VECTOR_CLONES
static void ggx2_basis(const brdffit_batch *batch, size_t first, size_t count, const double *shape,
                       bf_basis *out)
{
    mf_geometry g;
    fill_diffuse(out->b[0], count);
    ggx_geometry(batch, first, count, &g);
    ggx_lobe(&g, count, shape[0], shape[2], two_lobe_out(out, 0));
    ggx_lobe(&g, count, shape[1], shape[2], two_lobe_out(out, 1));
}

/* The microfacet form (basis.h): the fit's fused loop (fit/pass_lanes.h,
 * lane_mf_basis(), and its vector copy) computes ggx_geometry() and
 * ggx_lobe(), ct_geometry() and ct_lobe() lane by lane with the same
 * operations in the same order; change them together (test_fused.c
 * checks that they agree). */
/* rough -> cs; F0 -> cs. */
static const bf_kernel ct_kernel = {2, 2, {2u, 2u}, ct_basis, NULL, BF_MF_CT};
static const bf_kernel ggx_kernel = {2, 2, {2u, 2u}, ggx_basis, NULL, BF_MF_GGX};
/* rough1 -> cs1; rough2 -> cs2; F0 -> cs1, cs2. */
static const bf_kernel ct2_kernel = {3, 3, {2u, 4u, 6u}, ct2_basis, NULL, BF_MF_CT};
static const bf_kernel ggx2_kernel = {3, 3, {2u, 4u, 6u}, ggx2_basis, NULL, BF_MF_GGX};

static brdffit_status ct_eval(const brdffit_batch *batch, const double *params, size_t n_channels,
                              double *values, double *jacobian, void *user)
{
    (void)user;
    return bf_kernel_run(&ct_kernel, batch, params, n_channels, values, jacobian);
}

static brdffit_status ggx_eval(const brdffit_batch *batch, const double *params, size_t n_channels,
                               double *values, double *jacobian, void *user)
{
    (void)user;
    return bf_kernel_run(&ggx_kernel, batch, params, n_channels, values, jacobian);
}

static brdffit_status ct2_eval(const brdffit_batch *batch, const double *params, size_t n_channels,
                               double *values, double *jacobian, void *user)
{
    (void)user;
    return bf_kernel_run(&ct2_kernel, batch, params, n_channels, values, jacobian);
}

static brdffit_status ggx2_eval(const brdffit_batch *batch, const double *params, size_t n_channels,
                                double *values, double *jacobian, void *user)
{
    (void)user;
    return bf_kernel_run(&ggx2_kernel, batch, params, n_channels, values, jacobian);
}

static const brdffit_param_info ct_params[] = {
    {"m", BRDFFIT_PARAM_LOG_SCALE, BF_ROUGH_LO, BF_ROUGH_HI, 0.2},
    {"F0", FRESNEL_F0_FLAGS, 0.0, 1.0, FRESNEL_F0_START},
    {"cd", LINEAR_FLAGS, 0.0, HUGE_VAL, 0.2},
    {"cs", LINEAR_FLAGS, 0.0, HUGE_VAL, 1.0},
};

static const brdffit_param_info ggx_params[] = {
    {"a", BRDFFIT_PARAM_LOG_SCALE, BF_ROUGH_LO, BF_ROUGH_HI, 0.2},
    {"F0", FRESNEL_F0_FLAGS, 0.0, 1.0, FRESNEL_F0_START},
    {"cd", LINEAR_FLAGS, 0.0, HUGE_VAL, 0.2},
    {"cs", LINEAR_FLAGS, 0.0, HUGE_VAL, 1.0},
};

static const brdffit_param_info ct2_params[] = {
    {"m1", BRDFFIT_PARAM_LOG_SCALE, BF_ROUGH_LO, BF_ROUGH_HI, 0.3},
    {"m2", BRDFFIT_PARAM_LOG_SCALE, BF_ROUGH_LO, BF_ROUGH_HI, 0.1},
    {"F0", FRESNEL_F0_FLAGS, 0.0, 1.0, FRESNEL_F0_START},
    {"cd", LINEAR_FLAGS, 0.0, HUGE_VAL, 0.2},
    {"cs1", LINEAR_FLAGS, 0.0, HUGE_VAL, 1.0},
    {"cs2", LINEAR_FLAGS, 0.0, HUGE_VAL, 1.0},
};

static const brdffit_param_info ggx2_params[] = {
    {"a1", BRDFFIT_PARAM_LOG_SCALE, BF_ROUGH_LO, BF_ROUGH_HI, 0.3},
    {"a2", BRDFFIT_PARAM_LOG_SCALE, BF_ROUGH_LO, BF_ROUGH_HI, 0.1},
    {"F0", FRESNEL_F0_FLAGS, 0.0, 1.0, FRESNEL_F0_START},
    {"cd", LINEAR_FLAGS, 0.0, HUGE_VAL, 0.2},
    {"cs1", LINEAR_FLAGS, 0.0, HUGE_VAL, 1.0},
    {"cs2", LINEAR_FLAGS, 0.0, HUGE_VAL, 1.0},
};

const bf_builtin bf_builtin_cook_torrance = {"cook-torrance", 4, ct_params, ct_eval, &ct_kernel,
                                             0};
const bf_builtin bf_builtin_ggx = {"ggx", 4, ggx_params, ggx_eval, &ggx_kernel, 0};
const bf_builtin bf_builtin_cook_torrance_2 = {"cook-torrance-2", 6, ct2_params, ct2_eval,
                                               &ct2_kernel, 0};
const bf_builtin bf_builtin_ggx_2 = {"ggx-2", 6, ggx2_params, ggx2_eval, &ggx2_kernel, 0};
