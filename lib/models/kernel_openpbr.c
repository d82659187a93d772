/* OpenPBR Surface 1.1 (Academy Software Foundation): its dielectric/metal
 * base, and the same under its coat, as far as the specification gives
 * closed forms, in its own parameter names and ranges:
 *
 *     base       = mix(dielectric, metal, base_metalness)
 *     dielectric = F(h.v, specular_ior) S + (1 - F(n.l)) (1 - F(n.v)) base_color / pi
 *     metal      = (base_color + (1 - base_color) (1 - h.v)^5) S
 *     S          = D Vis, GGX D, height-correlated Smith Vis, alpha = specular_roughness^2
 *
 * with F the exact unpolarised Fresnel reflectance of a dielectric; the
 * metal is OpenPBR's F82-tint Fresnel with a white specular_color, which is
 * Schlick's. Under the coat (coat_weight C, coat_roughness rc, coat_ior
 * 1.6, OpenPBR's default):
 *
 *     coated = C Fc(h.v) Sc + (1 - C + C (1 - Fc(n.l)) (1 - Fc(n.v))) base
 *
 * whose base lobe is roughened as the specification says:
 * r' = mix(r, min(1, r^4 + 2 rc^4)^(1/4), C). Where this is an
 * approximation of OpenPBR (the layers' energy terms, the base's IOR under
 * the coat, no coat darkening) is in docs/models.md.
 *
 * Affine, not linear, in base_color (as glTF's BRDF), so no basis form;
 * the affine form is declared (bf_builtin.affine) for the auto fit. */
#include <math.h>

#include "core/core.h"
#include "models/kernel.h"

/* OpenPBR's default coat IOR. */
#define OPENPBR_COAT_IOR 1.6
/* The floors of glTF's models (kernel_gltf.c says why). */
#define OPENPBR_ROUGH_LO 1e-2
#define OPENPBR_COAT_LO 1e-2
/* Smallest specular_ior: at 1 the Fresnel reflectance and its derivative
 * in the IOR both vanish (F grows as (ior - 1)^2), a stationary point
 * where the scan's lower edge lands and LM cannot leave (a tinted metal
 * then imitates the dielectric's reflection); 1.1 (F0 = 0.0023) is below
 * every common dielectric (water 1.33). */
#define OPENPBR_IOR_LO 1.1

/* Fresnel reflectance of a dielectric and its derivative in the IOR. */
typedef struct op_fresnel {
    double f, df;
} op_fresnel;

/* Unpolarised Fresnel reflectance at cosine c from a medium of index 1
 * into one of index eta >= 1: with g = sqrt(eta^2 - 1 + c^2),
 * A = (g - c) / (g + c), B = (c (g + c) - 1) / (c (g - c) + 1),
 * F = A^2 (1 + B^2) / 2 (Cook and Torrance 1982); dg/deta = eta / g. */
static op_fresnel op_dielectric(double c, double eta)
{
    const double cc = c < 1e-9 ? 1e-9 : (c > 1.0 ? 1.0 : c);
    const double g = sqrt(eta * eta - 1.0 + cc * cc);
    const double gp = g + cc, bd = cc * (g - cc) + 1.0;
    const double a = (g - cc) / gp, b = (cc * gp - 1.0) / bd;
    const double da = 2.0 * cc / (gp * gp), db = 2.0 * cc * (1.0 - cc * cc) / (bd * bd);
    op_fresnel o;
    o.f = 0.5 * a * a * (1.0 + b * b);
    o.df = (a * (1.0 + b * b) * da + a * a * b * db) * eta / g;
    return o;
}

/* What every channel of one sample shares: the base lobe at the
 * effective roughness, F(h.v) and the diffuse transmission
 * T = (1 - F(n.l)) (1 - F(n.v)), each with its derivative in the IOR. */
typedef struct op_sample {
    bf_ggx_lobe g;
    double fh, dfh, t, dt;
} op_sample;

static op_sample op_prepare(const brdffit_batch *batch, size_t s, double r, double eta)
{
    const op_fresnel fh = op_dielectric(batch->hv[s], eta), fl = op_dielectric(batch->nl[s], eta);
    const op_fresnel fv = op_dielectric(batch->nv[s], eta);
    op_sample o;
    o.g = bf_ggx_shape(batch->nl[s], batch->nv[s], batch->nh[s], batch->hv[s], r);
    o.fh = fh.f;
    o.dfh = fh.df;
    o.t = (1.0 - fl.f) * (1.0 - fv.f);
    o.dt = -fl.df * (1.0 - fv.f) - (1.0 - fl.f) * fv.df;
    return o;
}

/* The base of one channel: out = value, d/d(roughness), d/d(metalness),
 * d/d(ior), d/d(base_color). */
static void op_base(const op_sample *p, double m, double b, double out[5])
{
    const double diel = p->fh * p->g.s + p->t * b / BF_PI;
    const double fm = b + (1.0 - b) * p->g.f5, metal = fm * p->g.s;
    out[0] = (1.0 - m) * diel + m * metal;
    out[1] = ((1.0 - m) * p->fh + m * fm) * p->g.ds;
    out[2] = metal - diel;
    out[3] = (1.0 - m) * (p->dfh * p->g.s + p->dt * b / BF_PI);
    out[4] = (1.0 - m) * p->t / BF_PI + m * (1.0 - p->g.f5) * p->g.s;
}

/* Parameters: specular_roughness, base_metalness, specular_ior,
 * base_color (per channel). */
static brdffit_status openpbr_eval(const brdffit_batch *batch, const double *params,
                                   size_t n_channels, double *values, double *jacobian, void *user)
{
    const size_t n = batch->n, nc = n_channels;
    size_t s, c, k;
    (void)user;
    for (s = 0; s < n; s++) {
        const op_sample p = op_prepare(batch, s, params[0], params[2]);
        for (c = 0; c < nc; c++) {
            double b[5];
            op_base(&p, params[1], params[3 + c], b);
            values[c * n + s] = b[0];
            if (jacobian == NULL) continue;
            for (k = 0; k < 4; k++) jacobian[(k * nc + c) * n + s] = b[k + 1];
        }
    }
    return BRDFFIT_OK;
}

/* The coat's roughening of the base: r' = (1 - C) r + C q with
 * q = min(1, r^4 + 2 rc^4)^(1/4); d[] = dr'/dr, dr'/drc, dr'/dC. */
static double op_roughen(double r, double rc, double cw, double d[3])
{
    const double r2 = r * r, rc2 = rc * rc, s4 = r2 * r2 + 2.0 * rc2 * rc2;
    double q = 1.0, dq_r = 0.0, dq_rc = 0.0;
    if (s4 < 1.0) {
        q = sqrt(sqrt(s4));
        dq_r = r2 * r / (q * q * q);
        dq_rc = 2.0 * rc2 * rc / (q * q * q);
    }
    d[0] = (1.0 - cw) + cw * dq_r;
    d[1] = cw * dq_rc;
    d[2] = q - r;
    return (1.0 - cw) * r + cw * q;
}

/* The coat's own terms at one sample: its lobe Sc (and dSc/drc) times
 * Fc(h.v), and the base's weight's transmission Tc. */
typedef struct op_coat {
    double lobe, dlobe, tc;
} op_coat;

static op_coat op_coat_terms(const brdffit_batch *batch, size_t s, double rc)
{
    const bf_ggx_lobe g = bf_ggx_shape(batch->nl[s], batch->nv[s], batch->nh[s], batch->hv[s], rc);
    const double fh = op_dielectric(batch->hv[s], OPENPBR_COAT_IOR).f;
    op_coat o;
    o.lobe = fh * g.s;
    o.dlobe = fh * g.ds;
    o.tc = (1.0 - op_dielectric(batch->nl[s], OPENPBR_COAT_IOR).f) *
           (1.0 - op_dielectric(batch->nv[s], OPENPBR_COAT_IOR).f);
    return o;
}

/* Parameters: specular_roughness, base_metalness, specular_ior,
 * coat_weight, coat_roughness, base_color (per channel). With the base's
 * weight w = 1 - C + C Tc: f = C Fc Sc + w base, df/dC = Fc Sc + (Tc - 1)
 * base + w dbase/dr' dr'/dC, and the base's derivatives times w. */
static brdffit_status openpbr_coat_eval(const brdffit_batch *batch, const double *params,
                                        size_t n_channels, double *values, double *jacobian,
                                        void *user)
{
    const size_t n = batch->n, nc = n_channels;
    const double cw = params[3];
    double d[3];
    const double re = op_roughen(params[0], params[4], cw, d);
    size_t s, c;
    (void)user;
    for (s = 0; s < n; s++) {
        const op_sample p = op_prepare(batch, s, re, params[2]);
        const op_coat k = op_coat_terms(batch, s, params[4]);
        const double w = 1.0 - cw + cw * k.tc;
        for (c = 0; c < nc; c++) {
            double b[5];
            op_base(&p, params[1], params[5 + c], b);
            values[c * n + s] = cw * k.lobe + w * b[0];
            if (jacobian == NULL) continue;
            jacobian[c * n + s] = w * b[1] * d[0];
            jacobian[(nc + c) * n + s] = w * b[2];
            jacobian[(2 * nc + c) * n + s] = w * b[3];
            jacobian[(3 * nc + c) * n + s] = k.lobe + (k.tc - 1.0) * b[0] + w * b[1] * d[2];
            jacobian[(4 * nc + c) * n + s] = cw * k.dlobe + w * b[1] * d[1];
            jacobian[(5 * nc + c) * n + s] = w * b[4];
        }
    }
    return BRDFFIT_OK;
}

static const brdffit_param_info openpbr_params[] = {
    {"specular_roughness", BRDFFIT_PARAM_LOG_SCALE, OPENPBR_ROUGH_LO, 1.0, 0.5},
    {"base_metalness", 0, 0.0, 1.0, 0.5},
    {"specular_ior", 0, OPENPBR_IOR_LO, 3.0, 1.5},
    {"base_color", BRDFFIT_PARAM_PER_CHANNEL, 0.0, 1.0, 0.5},
};

/* Under the coat the IOR is held at OpenPBR's default 1.5 (freed on
 * request): the coat's Fresnel and the base's overlap, and the scan stays
 * at four dimensions. The coat starts glossier than the base. */
static const brdffit_param_info openpbr_coat_params[] = {
    {"specular_roughness", BRDFFIT_PARAM_LOG_SCALE, OPENPBR_ROUGH_LO, 1.0, 0.5},
    {"base_metalness", 0, 0.0, 1.0, 0.5},
    {"specular_ior", BRDFFIT_PARAM_FIXED, OPENPBR_IOR_LO, 3.0, 1.5},
    {"coat_weight", BRDFFIT_PARAM_LOG_SCALE, OPENPBR_COAT_LO, 1.0, 0.5},
    {"coat_roughness", BRDFFIT_PARAM_LOG_SCALE, OPENPBR_ROUGH_LO, 1.0, 0.1},
    {"base_color", BRDFFIT_PARAM_PER_CHANNEL, 0.0, 1.0, 0.5},
};

/* Affine in base_color: op_base() is b out[4] plus a colourless rest, and
 * the coat adds a colourless lobe and scales the base by w. */
const bf_builtin bf_builtin_openpbr = {"openpbr", 4, openpbr_params, openpbr_eval, NULL, 1 + 3};
const bf_builtin bf_builtin_openpbr_coat = {"openpbr-coat", 6, openpbr_coat_params,
                                            openpbr_coat_eval, NULL, 1 + 5};
