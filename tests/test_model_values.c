/* Values of every built-in model against formulas written out here from
 * the angles (docs/models.md), independently of the library's kernels. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "test_support.h"

#define PI 3.14159265358979323846
#define FLOOR 1e-4

/* ---- geometry from angles, the textbook way ------------------------------ */

typedef struct dirs {
    double ti, pi, to, po;
} dirs;

typedef struct geo {
    double l[3], v[3], h[3];
    double nl, nv, nh, hv, rv;
} geo;

static double clamp_dot(double x)
{
    return x < FLOOR ? FLOOR : (x > 1.0 ? 1.0 : x);
}

static void unit(double theta, double phi, double out[3])
{
    out[0] = sin(theta) * cos(phi);
    out[1] = sin(theta) * sin(phi);
    out[2] = cos(theta);
}

static geo make_geo(dirs d)
{
    geo g;
    double len;
    int i;
    unit(d.ti, d.pi, g.l);
    unit(d.to, d.po, g.v);
    for (i = 0; i < 3; i++) g.h[i] = g.l[i] + g.v[i];
    len = sqrt(g.h[0] * g.h[0] + g.h[1] * g.h[1] + g.h[2] * g.h[2]);
    for (i = 0; i < 3; i++) g.h[i] /= len;
    if (len <= 1e-12) { /* l and v opposite: the half vector is taken as n */
        g.h[0] = g.h[1] = 0.0;
        g.h[2] = 1.0;
    }
    g.nl = clamp_dot(g.l[2]);
    g.nv = clamp_dot(g.v[2]);
    g.nh = clamp_dot(g.h[2]);
    g.hv = clamp_dot(g.h[0] * g.v[0] + g.h[1] * g.v[1] + g.h[2] * g.v[2]);
    /* r = 2 (n.l) n - l, the mirror of l */
    g.rv = -g.l[0] * g.v[0] - g.l[1] * g.v[1] + g.l[2] * g.v[2];
    return g;
}

/* ---- the models, one channel, parameters in declaration order ------------ */

static double schlick(double f0, double x)
{
    return f0 + (1.0 - f0) * pow(1.0 - x, 5.0);
}

static double as_lobe(double ns, const geo *g)
{
    return (ns + 1.0) / (8.0 * PI) * pow(g->nh, ns) / (g->hv * fmax(g->nl, g->nv));
}

static double beckmann_ct(double m, double f0, const geo *g)
{
    const double th = acos(g->nh), t = tan(th);
    const double d = exp(-t * t / (m * m)) / (PI * m * m * pow(cos(th), 4.0));
    const double gg = fmin(1.0, fmin(2.0 * g->nh * g->nv / g->hv, 2.0 * g->nh * g->nl / g->hv));
    return d * gg * schlick(f0, g->hv) / (4.0 * g->nl * g->nv);
}

static double smith_lambda(double a, double cos_theta)
{
    const double t = tan(acos(cos_theta));
    return (-1.0 + sqrt(1.0 + a * a * t * t)) / 2.0;
}

static double ggx(double a, double f0, const geo *g)
{
    const double q = g->nh * g->nh * (a * a - 1.0) + 1.0;
    const double d = a * a / (PI * q * q);
    const double gg = 1.0 / (1.0 + smith_lambda(a, g->nl) + smith_lambda(a, g->nv));
    return d * gg * schlick(f0, g->hv) / (4.0 * g->nl * g->nv);
}

static double ward_lobe(double a, const geo *g, int duer)
{
    const double t = tan(acos(g->nh));
    const double e = exp(-t * t / (a * a));
    const double norm = duer ? g->nl * g->nv : sqrt(g->nl * g->nv);
    return e / (4.0 * PI * a * a * norm);
}

/* glTF 2.0 metallic-roughness, composed as the specification writes it:
 * mix(fresnel_mix(0.04, diffuse, specular), conductor_fresnel(baseColor,
 * specular), metallic), with G in its height-correlated form over
 * 4 |n.l| |n.v|. p = roughness, metallic, baseColor. */
static double gltf(const double *p, const geo *g)
{
    const double alpha = p[0] * p[0], a2 = alpha * alpha, m = p[1], base = p[2];
    const double q = g->nh * g->nh * (a2 - 1.0) + 1.0;
    const double d = a2 / (PI * q * q);
    const double gg = 2.0 * g->nl * g->nv /
                      (g->nv * sqrt(a2 + (1.0 - a2) * g->nl * g->nl) +
                       g->nl * sqrt(a2 + (1.0 - a2) * g->nv * g->nv));
    const double specular = gg * d / (4.0 * g->nl * g->nv);
    const double fr = schlick(0.04, g->hv);
    const double dielectric = (1.0 - fr) * base / PI + fr * specular;
    const double metal = specular * schlick(base, g->hv);
    return (1.0 - m) * dielectric + m * metal;
}

/* KHR_materials_clearcoat on top: mix(material, coat lobe, k F(0.04, n.v)),
 * the coat lobe being gltf's specular with its own roughness: gltf's white
 * metal, whose F(1, h.v) is 1. p = roughness, metallic, clearcoat,
 * clearcoatRoughness, baseColor. */
static double gltf_clearcoat(const double *p, const geo *g)
{
    const double base[3] = {p[0], p[1], p[4]}, coat[3] = {p[3], 1.0, 1.0};
    const double fc = p[2] * schlick(0.04, g->nv);
    return (1.0 - fc) * gltf(base, g) + fc * gltf(coat, g);
}

/* GGX with height-correlated Smith over 4 n.l n.v, alpha = r^2 (as in
 * gltf() above). */
static double ggx_correlated(double r, const geo *g)
{
    const double a2 = r * r * r * r;
    const double q = g->nh * g->nh * (a2 - 1.0) + 1.0;
    const double gg = 2.0 * g->nl * g->nv /
                      (g->nv * sqrt(a2 + (1.0 - a2) * g->nl * g->nl) +
                       g->nl * sqrt(a2 + (1.0 - a2) * g->nv * g->nv));
    return a2 / (PI * q * q) * gg / (4.0 * g->nl * g->nv);
}

/* Unpolarised Fresnel reflectance of a dielectric from its s and p
 * amplitude coefficients (Snell's law for the refracted cosine). */
static double fresnel_sp(double c, double eta)
{
    const double ct = sqrt(1.0 - (1.0 - c * c) / (eta * eta));
    const double rs = (c - eta * ct) / (c + eta * ct), rp = (eta * c - ct) / (eta * c + ct);
    return 0.5 * (rs * rs + rp * rp);
}

/* OpenPBR's base as docs/models.md writes it: mix(dielectric, metal,
 * base_metalness), the dielectric's diffuse through both interface
 * transmissions, the metal's Fresnel Schlick's of base_color (F82 with a
 * white specular_color). p = specular_roughness, base_metalness,
 * specular_ior, base_color. */
static double openpbr(const double *p, const geo *g)
{
    const double spec = ggx_correlated(p[0], g), eta = p[2], b = p[3];
    const double dielectric = fresnel_sp(g->hv, eta) * spec +
                              (1.0 - fresnel_sp(g->nl, eta)) * (1.0 - fresnel_sp(g->nv, eta)) * b / PI;
    return (1.0 - p[1]) * dielectric + p[1] * spec * schlick(b, g->hv);
}

/* Its coat (IOR 1.6) over the roughened base: mix(base, coat lobe +
 * transmitted base, coat_weight). p = specular_roughness, base_metalness,
 * specular_ior, coat_weight, coat_roughness, base_color. */
static double openpbr_coat(const double *p, const geo *g)
{
    const double r = p[0], k = p[3], rc = p[4];
    const double rough = fmin(1.0, pow(pow(r, 4.0) + 2.0 * pow(rc, 4.0), 0.25));
    const double base_p[4] = {(1.0 - k) * r + k * rough, p[1], p[2], p[5]};
    const double base = openpbr(base_p, g);
    const double layer = fresnel_sp(g->hv, 1.6) * ggx_correlated(rc, g) +
                         (1.0 - fresnel_sp(g->nl, 1.6)) * (1.0 - fresnel_sp(g->nv, 1.6)) * base;
    return (1.0 - k) * base + k * layer;
}

static double reference(const char *name, const double *p, const geo *g)
{
    if (strcmp(name, "lambert") == 0) return p[0] / PI;
    if (strcmp(name, "phong") == 0)
        return p[1] / PI + (p[0] + 2.0) / (2.0 * PI) * p[2] * pow(fmax(0.0, g->rv), p[0]);
    if (strcmp(name, "blinn-phong") == 0)
        return p[1] / PI + (p[0] + 8.0) / (8.0 * PI) * p[2] * pow(g->nh, p[0]);
    if (strcmp(name, "ashikhmin-shirley") == 0) return p[1] / PI + as_lobe(p[0], g) * p[2];
    if (strcmp(name, "ashikhmin-shirley-fresnel") == 0) {
        const double rs = p[1];
        const double diffuse = 28.0 / (23.0 * PI) * (1.0 - rs) *
                               (1.0 - pow(1.0 - g->nl / 2.0, 5.0)) *
                               (1.0 - pow(1.0 - g->nv / 2.0, 5.0));
        return diffuse * p[2] + as_lobe(p[0], g) * schlick(rs, g->hv) * p[3];
    }
    if (strcmp(name, "ashikhmin-shirley-2") == 0)
        return p[2] / PI + as_lobe(p[0], g) * p[3] + as_lobe(p[1], g) * p[4];
    if (strcmp(name, "cook-torrance") == 0) return p[2] / PI + p[3] * beckmann_ct(p[0], p[1], g);
    if (strcmp(name, "cook-torrance-2") == 0)
        return p[3] / PI + p[4] * beckmann_ct(p[0], p[2], g) + p[5] * beckmann_ct(p[1], p[2], g);
    if (strcmp(name, "ggx") == 0) return p[2] / PI + p[3] * ggx(p[0], p[1], g);
    if (strcmp(name, "ggx-2") == 0)
        return p[3] / PI + p[4] * ggx(p[0], p[2], g) + p[5] * ggx(p[1], p[2], g);
    if (strcmp(name, "ward") == 0) return p[1] / PI + p[2] * ward_lobe(p[0], g, 0);
    if (strcmp(name, "ward-duer") == 0) return p[1] / PI + p[2] * ward_lobe(p[0], g, 1);
    if (strcmp(name, "lafortune") == 0) {
        const double base = -(g->l[0] * g->v[0] + g->l[1] * g->v[1]) + p[1] * g->l[2] * g->v[2];
        return p[2] / PI + p[3] * pow(fmax(0.0, base), p[0]);
    }
    if (strcmp(name, "gltf") == 0) return gltf(p, g);
    if (strcmp(name, "gltf-clearcoat") == 0) return gltf_clearcoat(p, g);
    if (strcmp(name, "openpbr") == 0) return openpbr(p, g);
    if (strcmp(name, "openpbr-coat") == 0) return openpbr_coat(p, g);
    fail_msg("no reference for model %s", name);
    return 0.0;
}

/* ---- helpers ------------------------------------------------------------- */

static void assert_rel(double got, double want, double tol, const char *what)
{
    if (!(fabs(got - want) <= tol * fabs(want) + 1e-300))
        fail_msg("%s: got %.17g, expected %.17g (relative tolerance %g)", what, got, want, tol);
}

static brdffit_model *create(const char *name)
{
    brdffit_model *m = NULL;
    assert_int_equal(brdffit_model_create(&m, name, NULL, NULL), BRDFFIT_OK);
    return m;
}

/* Model vector for two channels from declared-order values; channel 1's
 * per-channel values are 0.5 p + 0.1. pc receives each channel's values. */
static void two_channel_vector(const brdffit_model *m, const double *p, double *x, double pc[2][8])
{
    size_t k, j = 0;
    for (k = 0; k < brdffit_model_param_count(m); k++) {
        const int per = (brdffit_model_param(m, k)->flags & BRDFFIT_PARAM_PER_CHANNEL) != 0;
        pc[0][k] = p[k];
        pc[1][k] = per ? 0.5 * p[k] + 0.1 : p[k];
        x[j++] = pc[0][k];
        if (per) x[j++] = pc[1][k];
    }
}

/* Evaluate one model at one direction (two channels). */
static void eval_at(const brdffit_model *m, dirs d, const double *x, double out[2])
{
    brdffit_error err;
    brdffit_status st =
        brdffit_model_eval_angles(m, 1, &d.ti, &d.pi, &d.to, &d.po, 2, x, out, NULL, &err);
    if (st != BRDFFIT_OK) fail_msg("%s: %s", brdffit_model_name(m), err.message);
}

/* ---- hand-derived values --------------------------------------------------- */

/* At normal light and view n.l = n.v = n.h = h.v = 1, theta_h = 0 and
 * r.v = 1, so every lobe reduces to its normalisation; the values below
 * are those reductions worked out by hand. */
static void test_normal_incidence(void **state)
{
    const dirs d = {0.0, 0.0, 0.0, 0.0};
    const double cd = 0.4, cs = 0.3, ns = 12.0, m = 0.25, f0 = 0.05, rs = 0.3;
    const double half5 = 1.0 - 1.0 / 32.0; /* 1 - (1 - 1/2)^5 */
    struct {
        const char *name;
        double p[6];
        double want;
    } cases[] = {
        {"lambert", {cd}, cd / PI},
        {"phong", {ns, cd, cs}, cd / PI + (ns + 2.0) / (2.0 * PI) * cs},
        {"blinn-phong", {ns, cd, cs}, cd / PI + (ns + 8.0) / (8.0 * PI) * cs},
        {"ashikhmin-shirley", {ns, cd, cs}, cd / PI + (ns + 1.0) / (8.0 * PI) * cs},
        {"ashikhmin-shirley-fresnel",
         {ns, rs, cd, cs},
         28.0 / (23.0 * PI) * (1.0 - rs) * half5 * half5 * cd + (ns + 1.0) / (8.0 * PI) * rs * cs},
        {"ashikhmin-shirley-2",
         {ns, 3.0 * ns, cd, cs, 2.0 * cs},
         cd / PI + (ns + 1.0) / (8.0 * PI) * cs + (3.0 * ns + 1.0) / (8.0 * PI) * 2.0 * cs},
        {"cook-torrance", {m, f0, cd, cs}, cd / PI + cs * f0 / (4.0 * PI * m * m)},
        {"ggx", {m, f0, cd, cs}, cd / PI + cs * f0 / (4.0 * PI * m * m)},
        {"cook-torrance-2",
         {m, 2.0 * m, f0, cd, cs, cs},
         cd / PI + cs * f0 / (4.0 * PI * m * m) + cs * f0 / (16.0 * PI * m * m)},
        {"ggx-2",
         {m, 2.0 * m, f0, cd, cs, cs},
         cd / PI + cs * f0 / (4.0 * PI * m * m) + cs * f0 / (16.0 * PI * m * m)},
        {"ward", {m, cd, cs}, cd / PI + cs / (4.0 * PI * m * m)},
        {"ward-duer", {m, cd, cs}, cd / PI + cs / (4.0 * PI * m * m)},
        {"lafortune", {ns, 0.8, cd, cs}, cd / PI + cs * pow(0.8, ns)},
        /* D = 1 / (pi alpha^2), Vis = 1/4, F = F0; alpha^2 = 0.5^4 = 0.0625 */
        {"gltf",
         {0.5, 0.3, cd},
         0.7 * (0.96 * cd / PI + 0.04 / (4.0 * PI * 0.0625)) +
             0.3 * cd / (4.0 * PI * 0.0625)},
        /* coat: n.v = 1, so F = 0.04; its lobe 1 / (4 pi 0.2^4) */
        {"gltf-clearcoat",
         {0.5, 0.3, 0.5, 0.2, cd},
         0.98 * (0.7 * (0.96 * cd / PI + 0.04 / (4.0 * PI * 0.0625)) +
                 0.3 * cd / (4.0 * PI * 0.0625)) +
             0.02 / (4.0 * PI * 0.0016)},
        /* ior 1.5: F0 = 0.04 at h.v = n.l = n.v = 1; the diffuse passes the
         * interface twice, 0.96^2 = 0.9216 */
        {"openpbr",
         {0.5, 0.3, 1.5, cd},
         0.7 * (0.04 / (4.0 * PI * 0.0625) + 0.9216 * cd / PI) + 0.3 * cd / (4.0 * PI * 0.0625)},
        /* coat F0 (0.6 / 2.6)^2, weight 0.5, base roughness
         * 0.25 + 0.5 (0.5^4 + 2 0.2^4)^(1/4) */
        {"openpbr-coat",
         {0.5, 0.3, 1.5, 0.5, 0.2, cd},
         0.5 * pow(0.6 / 2.6, 2.0) / (4.0 * PI * 0.0016) +
             (0.5 + 0.5 * pow(1.0 - pow(0.6 / 2.6, 2.0), 2.0)) *
                 (0.7 * (0.04 / (4.0 * PI * pow(0.25 + 0.5 * pow(0.0657, 0.25), 4.0)) +
                         0.9216 * cd / PI) +
                  0.3 * cd / (4.0 * PI * pow(0.25 + 0.5 * pow(0.0657, 0.25), 4.0)))},
    };
    size_t i;
    (void)state;
    assert_int_equal(sizeof cases / sizeof cases[0], brdffit_model_builtin_count());
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        brdffit_model *model = create(cases[i].name);
        double x[16], pc[2][8], out[2];
        two_channel_vector(model, cases[i].p, x, pc);
        eval_at(model, d, x, out);
        assert_rel(out[0], cases[i].want, 1e-13, cases[i].name);
        brdffit_model_destroy(model);
    }
}

/* At the mirror configuration (theta_i = theta_o, opposite azimuths) r.v = 1
 * and n.h = 1, h.v = n.l = n.v = cos theta. */
static void test_mirror_direction(void **state)
{
    const double th = 40.0 * PI / 180.0, c = cos(th);
    const dirs d = {th, PI, th, 0.0};
    const double cd = 0.1, cs = 0.7, ns = 30.0, m = 0.3, f0 = 0.04;
    const double f = f0 + (1.0 - f0) * pow(1.0 - c, 5.0);
    double x[16], pc[2][8], out[2];
    brdffit_model *model;
    (void)state;

    model = create("phong");
    two_channel_vector(model, (const double[]){ns, cd, cs}, x, pc);
    eval_at(model, d, x, out);
    assert_rel(out[0], cd / PI + (ns + 2.0) / (2.0 * PI) * cs, 1e-13, "phong mirror");
    brdffit_model_destroy(model);

    model = create("ashikhmin-shirley");
    two_channel_vector(model, (const double[]){ns, cd, cs}, x, pc);
    eval_at(model, d, x, out);
    assert_rel(out[0], cd / PI + (ns + 1.0) / (8.0 * PI) * cs / (c * c), 1e-13, "AS mirror");
    brdffit_model_destroy(model);

    /* Beckmann D = 1/(pi m^2); V-cavity G = min(1, 2 c/c, ...) = 1 */
    model = create("cook-torrance");
    two_channel_vector(model, (const double[]){m, f0, cd, cs}, x, pc);
    eval_at(model, d, x, out);
    assert_rel(out[0], cd / PI + cs * f / (PI * m * m * 4.0 * c * c), 1e-12, "CT mirror");
    brdffit_model_destroy(model);

    /* Lafortune with cz = 1 is the unnormalised Phong lobe: (r.v)^n = 1 */
    model = create("lafortune");
    two_channel_vector(model, (const double[]){ns, 1.0, cd, cs}, x, pc);
    eval_at(model, d, x, out);
    assert_rel(out[0], cd / PI + cs, 1e-13, "lafortune mirror");
    brdffit_model_destroy(model);
}

/* gltf's specular lobe S is ggx's lobe with a = roughness^2: a white metal
 * (metallic 1, baseColor 1, so F = 1) equals ggx with cd 0, cs 1, F0 1. */
static void test_gltf_lobe_is_ggx(void **state)
{
    const dirs d = {0.7, PI, 0.5, 0.3};
    const double r = 0.4;
    double xg[4] = {r, 1.0, 1.0, 1.0}, xx[6] = {r * r, 1.0, 0.0, 0.0, 1.0, 1.0};
    double vg[2], vx[2];
    brdffit_model *g = create("gltf"), *x = create("ggx");
    eval_at(g, d, xg, vg);
    eval_at(x, d, xx, vx);
    assert_rel(vg[0], vx[0], 1e-13, "gltf white metal against ggx");
    assert_rel(vg[1], vx[1], 1e-13, "gltf white metal against ggx, channel 1");
    brdffit_model_destroy(g);
    brdffit_model_destroy(x);
    (void)state;
}

/* ---- every model at many directions against the written-out formulas ----- */

#define DEGR(x) ((x)*PI / 180.0)

static const dirs directions[] = {
    {0.0, 0.0, 0.0, 0.0},
    {DEGR(30), PI, DEGR(30), 0.0},
    {DEGR(45), PI, DEGR(20), DEGR(40)},
    {DEGR(10), 1.0, DEGR(60), 2.5},
    {DEGR(60), 0.3, DEGR(50), -2.0},
    {DEGR(70), PI, DEGR(70), DEGR(5)},
    {DEGR(20), PI, DEGR(80), PI},
    {DEGR(85), 2.0, DEGR(85), 5.0},
    {DEGR(35), PI, DEGR(38), DEGR(3)},
    {DEGR(75), PI, DEGR(15), DEGR(170)},
};

/* Parameter sets per model, declaration order. */
typedef struct model_case {
    const char *name;
    double p[3][6];
} model_case;

static const model_case model_cases[] = {
    {"lambert", {{0.3}, {0.05}, {0.9}}},
    {"phong", {{5.0, 0.3, 0.2}, {120.0, 0.05, 0.8}, {0.7, 0.6, 0.1}}},
    {"blinn-phong", {{5.0, 0.3, 0.2}, {400.0, 0.05, 0.8}, {0.7, 0.6, 0.1}}},
    {"ashikhmin-shirley", {{5.0, 0.3, 0.2}, {800.0, 0.05, 0.8}, {0.7, 0.6, 0.1}}},
    {"ashikhmin-shirley-fresnel",
     {{5.0, 0.1, 0.3, 0.2}, {800.0, 0.6, 0.05, 0.8}, {0.7, 0.95, 0.6, 0.1}}},
    {"ashikhmin-shirley-2",
     {{5.0, 300.0, 0.3, 0.2, 0.1}, {50.0, 2000.0, 0.05, 0.8, 0.4}, {0.7, 20.0, 0.6, 0.1, 0.9}}},
    {"cook-torrance", {{0.2, 0.04, 0.3, 0.9}, {0.05, 0.5, 0.05, 0.3}, {0.9, 0.9, 0.6, 2.0}}},
    {"cook-torrance-2",
     {{0.3, 0.08, 0.04, 0.3, 0.9, 0.4},
      {0.6, 0.02, 0.5, 0.05, 0.3, 1.0},
      {1.0, 0.5, 0.9, 0.6, 2.0, 0.1}}},
    {"ggx", {{0.2, 0.04, 0.3, 0.9}, {0.05, 0.5, 0.05, 0.3}, {0.9, 0.9, 0.6, 2.0}}},
    {"ggx-2",
     {{0.3, 0.08, 0.04, 0.3, 0.9, 0.4},
      {0.6, 0.02, 0.5, 0.05, 0.3, 1.0},
      {1.0, 0.5, 0.9, 0.6, 2.0, 0.1}}},
    {"ward", {{0.2, 0.3, 0.1}, {0.05, 0.05, 0.3}, {0.9, 0.6, 0.7}}},
    {"ward-duer", {{0.2, 0.3, 0.1}, {0.05, 0.05, 0.3}, {0.9, 0.6, 0.7}}},
    {"lafortune", {{10.0, 0.9, 0.3, 0.5}, {200.0, 0.5, 0.05, 2.0}, {1.5, 0.1, 0.6, 0.3}}},
    {"gltf", {{0.5, 0.0, 0.8}, {0.15, 1.0, 0.9}, {0.9, 0.4, 0.3}}},
    {"gltf-clearcoat",
     {{0.5, 0.0, 1.0, 0.05, 0.8}, {0.15, 1.0, 0.3, 0.4, 0.9}, {0.9, 0.4, 0.7, 0.02, 0.3}}},
    {"openpbr", {{0.5, 0.0, 1.5, 0.8}, {0.15, 1.0, 2.0, 0.9}, {0.9, 0.4, 1.2, 0.3}}},
    {"openpbr-coat",
     {{0.5, 0.0, 1.5, 1.0, 0.05, 0.8},
      {0.15, 1.0, 1.5, 0.3, 0.4, 0.9},
      {0.9, 0.4, 2.2, 0.7, 0.02, 0.3}}},
};

static void test_reference_formulas(void **state)
{
    size_t i, set, di;
    char what[160];
    (void)state;
    assert_int_equal(sizeof model_cases / sizeof model_cases[0], brdffit_model_builtin_count());
    for (i = 0; i < sizeof model_cases / sizeof model_cases[0]; i++) {
        brdffit_model *model = create(model_cases[i].name);
        for (set = 0; set < 3; set++) {
            double x[16], pc[2][8], out[2];
            two_channel_vector(model, model_cases[i].p[set], x, pc);
            for (di = 0; di < sizeof directions / sizeof directions[0]; di++) {
                const geo g = make_geo(directions[di]);
                eval_at(model, directions[di], x, out);
                snprintf(what, sizeof what, "%s set %zu direction %zu channel 0",
                         model_cases[i].name, set, di);
                assert_rel(out[0], reference(model_cases[i].name, pc[0], &g), 1e-9, what);
                what[strlen(what) - 1] = '1';
                assert_rel(out[1], reference(model_cases[i].name, pc[1], &g), 1e-9, what);
            }
        }
        brdffit_model_destroy(model);
    }
}

/* Grazing directions: the library clamps n.l, n.v, n.h and h.v to 1e-4 (as
 * does make_geo here), and the values stay finite. */
static void test_grazing_clamped(void **state)
{
    const dirs grazing[] = {
        {PI / 2, PI, PI / 2, 0.0},
        {PI / 2, PI, DEGR(30), DEGR(90)},
        {DEGR(10), 0.0, PI / 2, PI},
        {PI / 2, PI, PI / 2, PI}, /* l = v: h.v = 1, n.h = n.l = 0 */
    };
    size_t i, set, di;
    char what[160];
    (void)state;
    for (i = 0; i < sizeof model_cases / sizeof model_cases[0]; i++) {
        brdffit_model *model = create(model_cases[i].name);
        for (set = 0; set < 3; set++) {
            double x[16], pc[2][8], out[2];
            two_channel_vector(model, model_cases[i].p[set], x, pc);
            for (di = 0; di < sizeof grazing / sizeof grazing[0]; di++) {
                const geo g = make_geo(grazing[di]);
                eval_at(model, grazing[di], x, out);
                snprintf(what, sizeof what, "%s set %zu grazing %zu", model_cases[i].name, set, di);
                assert_true(isfinite(out[0]) && isfinite(out[1]));
                assert_rel(out[0], reference(model_cases[i].name, pc[0], &g), 1e-8, what);
            }
        }
        brdffit_model_destroy(model);
    }
}

/* The thesis's derivative of the simplified model (4.29):
 * d/dns = [(ns+1) nh^ns ln(nh) + nh^ns] cs / (8 pi hv max(nl, nv)). */
static void test_thesis_ns_derivative(void **state)
{
    const double p[3] = {40.0, 0.2, 0.6};
    brdffit_model *model = create("ashikhmin-shirley");
    double x[16], pc[2][8], out[2], jac[3 * 2];
    size_t di;
    (void)state;
    two_channel_vector(model, p, x, pc);
    for (di = 0; di < sizeof directions / sizeof directions[0]; di++) {
        const dirs d = directions[di];
        const geo g = make_geo(d);
        const double nh_ns = pow(g.nh, p[0]);
        const double want = ((p[0] + 1.0) * nh_ns * log(g.nh) + nh_ns) * p[2] /
                            (8.0 * PI * g.hv * fmax(g.nl, g.nv));
        assert_int_equal(
            brdffit_model_eval_angles(model, 1, &d.ti, &d.pi, &d.to, &d.po, 2, x, out, jac, NULL),
            BRDFFIT_OK);
        /* jacobian[(k * nc + c) * n + s], n = 1: ns, channel 0 */
        assert_rel(jac[0], want, 1e-9, "d/dns");
        /* d/dcd = 1/pi, d/dcs = the lobe */
        assert_rel(jac[2], 1.0 / PI, 1e-15, "d/dcd");
        assert_rel(jac[4], as_lobe(p[0], &g), 1e-9, "d/dcs");
    }
    brdffit_model_destroy(model);
}

/* Isotropy: rotating light and view together about the normal leaves
 * every model unchanged. */
static void test_isotropy(void **state)
{
    size_t i, di;
    (void)state;
    for (i = 0; i < sizeof model_cases / sizeof model_cases[0]; i++) {
        brdffit_model *model = create(model_cases[i].name);
        double x[16], pc[2][8], a[2], b[2];
        two_channel_vector(model, model_cases[i].p[0], x, pc);
        for (di = 0; di < sizeof directions / sizeof directions[0]; di++) {
            dirs d = directions[di];
            eval_at(model, d, x, a);
            d.pi += 1.234;
            d.po += 1.234;
            eval_at(model, d, x, b);
            assert_rel(b[0], a[0], 1e-10, model_cases[i].name);
            assert_rel(b[1], a[1], 1e-10, model_cases[i].name);
        }
        brdffit_model_destroy(model);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_normal_incidence),     cmocka_unit_test(test_mirror_direction),
        cmocka_unit_test(test_reference_formulas),   cmocka_unit_test(test_grazing_clamped),
        cmocka_unit_test(test_thesis_ns_derivative), cmocka_unit_test(test_isotropy),
        cmocka_unit_test(test_gltf_lobe_is_ggx),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
