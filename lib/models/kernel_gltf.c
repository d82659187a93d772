/* The glTF 2.0 metallic-roughness BRDF, exactly as the glTF 2.0
 * specification (Khronos, appendix B, "BRDF Implementation") composes it:
 *
 *     material   = mix(dielectric, metal, metallic)
 *     dielectric = fresnel_mix(ior 1.5: f0 0.04, base = baseColor / pi, layer = S)
 *     metal      = conductor_fresnel(f0 = baseColor, S)
 *     S          = D Vis, GGX D and height-correlated Smith Vis, alpha = roughness^2
 *
 * with Schlick's Fresnel term of h.v; and the same under the white coat of
 * the KHR_materials_clearcoat extension (Khronos). Formulas as implemented,
 * and why the colour is not a LINEAR parameter, are in docs/models.md.
 *
 * The model is affine, not linear, in baseColor (the specular layer of the
 * dielectric and the grazing part of the metal carry no colour), so it has
 * no basis form (models/kernel.h) and is evaluated through its callback;
 * it declares its affine form (bf_builtin.affine), through which the auto
 * fit's profile solves baseColor exactly (fit/varpro.h). */
#include <math.h>

#include "core/core.h"
#include "models/kernel.h"

/* glTF's fixed dielectric reflectance at normal incidence (ior 1.5). */
#define GLTF_F0 0.04

/* Smallest roughness: alpha = roughness^2 = 1e-4, the floor of the other
 * microfacet models (BF_ROUGH_LO), where every term stays finite. */
#define GLTF_ROUGH_LO 1e-2

/* Smallest clearcoat: at clearcoat 0 the coat's roughness has no effect at
 * all, a flat direction in which the fit's scan finds spurious minima (no
 * coat, any coat roughness) and LM cannot leave; uncoated materials are the
 * gltf model. A coat of 1 % changes a value by at most 0.04 % of the coat
 * lobe. */
#define GLTF_COAT_LO 1e-2

/* D = a2 / (pi q^2), q = (n.h)^2 (a2 - 1) + 1 written as
 * (1 - nh^2) + a2 nh^2 (no cancellation; q >= min(1, a2)), and
 * Vis = 1 / (2 (nv g_l + nl g_v)), g_w = sqrt(a2 + (1 - a2) (n.w)^2).
 * With a = alpha: dD/da = D (2/a - 4 a nh^2 / q), dg_w/da = a (1 - nw^2) / g_w,
 * dVis/da = -2 Vis^2 (nv dg_l + nl dg_v); d/d(roughness) = 2 r d/da. */
bf_ggx_lobe bf_ggx_shape(double nl, double nv, double nh, double hv, double r)
{
    const double a = r * r, a2 = a * a, nh2 = nh * nh;
    const double iq = 1.0 / ((1.0 - nh) * (1.0 + nh) + a2 * nh2);
    const double d = a2 * iq * iq / BF_PI;
    const double dd = d * (2.0 / a - 4.0 * a * nh2 * iq);
    const double gl = sqrt(a2 + (1.0 - a2) * nl * nl), gv = sqrt(a2 + (1.0 - a2) * nv * nv);
    const double dgl = a * (1.0 - nl) * (1.0 + nl) / gl, dgv = a * (1.0 - nv) * (1.0 + nv) / gv;
    const double vis = 0.5 / (nv * gl + nl * gv);
    const double dvis = -2.0 * vis * vis * (nv * dgl + nl * dgv);
    const double x = 1.0 - hv, x2 = x * x;
    bf_ggx_lobe o;
    o.s = d * vis;
    o.ds = (dd * vis + d * dvis) * 2.0 * r;
    o.f5 = x2 * x2 * x;
    return o;
}

/* One channel of one sample: f = b A + S W with
 * A = (1 - m)(1 - Fd) / pi + m S (1 - f5)   (= df/db),
 * W = (1 - m) Fd + m f5,  Fd = F0 + (1 - F0) f5. */
static void gltf_channel(const bf_ggx_lobe *g, double m, double b, double *f, double *df_dr,
                         double *df_dm, double *df_db)
{
    const double fd = GLTF_F0 + (1.0 - GLTF_F0) * g->f5;
    const double diff = (1.0 - fd) / BF_PI, spec = g->s * (1.0 - g->f5);
    const double w = (1.0 - m) * fd + m * g->f5;
    const double a = (1.0 - m) * diff + m * spec;
    *f = b * a + g->s * w;
    *df_db = a;
    *df_dm = b * (spec - diff) + g->s * (g->f5 - fd);
    *df_dr = g->ds * (b * m * (1.0 - g->f5) + w);
}

/* Parameters: roughness, metallic, baseColor (per channel). */
static brdffit_status gltf_eval(const brdffit_batch *batch, const double *params, size_t n_channels,
                                double *values, double *jacobian, void *user)
{
    const size_t n = batch->n, nc = n_channels;
    const double r = params[0], m = params[1];
    size_t s, c;
    (void)user;
    for (s = 0; s < n; s++) {
        const bf_ggx_lobe g = bf_ggx_shape(batch->nl[s], batch->nv[s], batch->nh[s], batch->hv[s], r);
        for (c = 0; c < nc; c++) {
            double f, dr, dm, db;
            gltf_channel(&g, m, params[2 + c], &f, &dr, &dm, &db);
            values[c * n + s] = f;
            if (jacobian == NULL) continue;
            jacobian[c * n + s] = dr;
            jacobian[(nc + c) * n + s] = dm;
            jacobian[(2 * nc + c) * n + s] = db;
        }
    }
    return BRDFFIT_OK;
}

/* KHR_materials_clearcoat: coated = mix(material, Sc, k Fc), a white GGX
 * lobe Sc of roughness rc on top, Fc = F(0.04, n.v) (the coat's normal is
 * the surface normal). With t = 1 - k Fc: f = t f_base + k Fc Sc,
 * df/dk = Fc (Sc - f_base), df/drc = k Fc dSc/drc, the base's derivatives
 * times t. Parameters: roughness, metallic, clearcoat, clearcoatRoughness,
 * baseColor (per channel). */
static brdffit_status gltf_coat_eval(const brdffit_batch *batch, const double *params,
                                     size_t n_channels, double *values, double *jacobian,
                                     void *user)
{
    const size_t n = batch->n, nc = n_channels;
    const double r = params[0], m = params[1], k = params[2], rc = params[3];
    size_t s, c;
    (void)user;
    for (s = 0; s < n; s++) {
        const double nl = batch->nl[s], nv = batch->nv[s], nh = batch->nh[s], hv = batch->hv[s];
        const bf_ggx_lobe g = bf_ggx_shape(nl, nv, nh, hv, r), coat = bf_ggx_shape(nl, nv, nh, hv, rc);
        const double x = 1.0 - nv, x2 = x * x;
        const double fc = GLTF_F0 + (1.0 - GLTF_F0) * x2 * x2 * x, t = 1.0 - k * fc;
        for (c = 0; c < nc; c++) {
            double f, dr, dm, db;
            gltf_channel(&g, m, params[4 + c], &f, &dr, &dm, &db);
            values[c * n + s] = t * f + k * fc * coat.s;
            if (jacobian == NULL) continue;
            jacobian[c * n + s] = t * dr;
            jacobian[(nc + c) * n + s] = t * dm;
            jacobian[(2 * nc + c) * n + s] = fc * (coat.s - f);
            jacobian[(3 * nc + c) * n + s] = k * fc * coat.ds;
            jacobian[(4 * nc + c) * n + s] = t * db;
        }
    }
    return BRDFFIT_OK;
}

static const brdffit_param_info gltf_params[] = {
    {"roughness", BRDFFIT_PARAM_LOG_SCALE, GLTF_ROUGH_LO, 1.0, 0.5},
    {"metallic", 0, 0.0, 1.0, 0.5},
    {"baseColor", BRDFFIT_PARAM_PER_CHANNEL, 0.0, 1.0, 0.5},
};

/* The coat starts glossier than the base, so that a fit from the defaults
 * separates the two lobes. */
static const brdffit_param_info gltf_coat_params[] = {
    {"roughness", BRDFFIT_PARAM_LOG_SCALE, GLTF_ROUGH_LO, 1.0, 0.5},
    {"metallic", 0, 0.0, 1.0, 0.5},
    {"clearcoat", BRDFFIT_PARAM_LOG_SCALE, GLTF_COAT_LO, 1.0, 0.5},
    {"clearcoatRoughness", BRDFFIT_PARAM_LOG_SCALE, GLTF_ROUGH_LO, 1.0, 0.1},
    {"baseColor", BRDFFIT_PARAM_PER_CHANNEL, 0.0, 1.0, 0.5},
};

/* Affine in baseColor: f = A b + B with A = df/db of gltf_channel(), times
 * t under the coat, and B the rest (the colourless specular and coat). */
const bf_builtin bf_builtin_gltf = {"gltf", 3, gltf_params, gltf_eval, NULL, 1 + 2};
const bf_builtin bf_builtin_gltf_clearcoat = {"gltf-clearcoat", 5, gltf_coat_params, gltf_coat_eval,
                                              NULL, 1 + 4};
