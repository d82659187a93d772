/* The specular lobes of the built-in models: see lobes.h. Each built-in
 * model with a lobe of a linear colour describes it here, next to no
 * other property, so that the fit finds every lobe's parameters from the
 * model's description rather than from its name. */
#include "models/lobes.h"

#include <math.h>

#include "core/core.h"
#include "models/kernel.h"
#include "models/model_internal.h"

#define NO BF_NO_PARAM

/* Parameters (declared order): phong, blinn-phong, ashikhmin-shirley: ns,
 * cd, cs; ward, ward-duer: a, cd, cs; ashikhmin-shirley-fresnel: ns, Rs, cd,
 * cs; cook-torrance, ggx: m (a), F0, cd, cs; lafortune: n, cz, cd, cs;
 * ashikhmin-shirley-2: ns1, ns2, cd, cs1, cs2; cook-torrance-2, ggx-2: m1
 * (a1), m2 (a2), F0, cd, cs1, cs2. Every lobe but Lafortune's has a table
 * over its sharpness (and its Fresnel parameter). */
static const bf_lobes phong = {1, 0, {{2, 0, 1, NO, &bf_albedo_phong, NULL}}};
static const bf_lobes blinn_phong = {1, 0, {{2, 0, 1, NO, &bf_albedo_blinn_phong, NULL}}};
static const bf_lobes as = {1, 0, {{2, 0, 1, NO, &bf_albedo_ashikhmin, NULL}}};
static const bf_lobes as_fresnel = {1, 0, {{3, 0, 1, 1, &bf_albedo_ashikhmin, NULL}}};
static const bf_lobes as_2 = {
    2, 1, {{3, 0, 1, NO, &bf_albedo_ashikhmin, NULL}, {4, 1, 1, NO, &bf_albedo_ashikhmin, NULL}}};
static const bf_lobes ct = {1, 0, {{3, 0, 0, 1, &bf_albedo_cook_torrance, NULL}}};
static const bf_lobes ct_2 = {
    2,
    1,
    {{4, 0, 0, 2, &bf_albedo_cook_torrance, NULL}, {5, 1, 0, 2, &bf_albedo_cook_torrance, NULL}}};
static const bf_lobes ggx = {1, 0, {{3, 0, 0, 1, &bf_albedo_ggx, NULL}}};
static const bf_lobes ggx_2 = {
    2, 1, {{4, 0, 0, 2, &bf_albedo_ggx, NULL}, {5, 1, 0, 2, &bf_albedo_ggx, NULL}}};
static const bf_lobes ward = {1, 0, {{2, 0, 0, NO, &bf_albedo_ward, NULL}}};
static const bf_lobes ward_duer = {1, 0, {{2, 0, 0, NO, &bf_albedo_ward_duer, NULL}}};
/* Lafortune's albedo depends on n and cz alike: the table of its axial
 * form, cz (declared index 1) as the bound's second parameter. */
static const bf_lobes lafortune = {1, 0, {{3, 0, 1, 1, NULL, &bf_albedo_lafortune}}};

/* Built-ins without an entry (lambert, the glTF and OpenPBR models) have no
 * lobe with a linear colour: their colours are not linear parameters, and
 * the coats of gltf-clearcoat and openpbr-coat are lobes of their own kind,
 * not interchangeable with the base's. */
static const struct {
    const bf_builtin *model;
    const bf_lobes *lobes;
} TABLE[] = {
    {&bf_builtin_phong, &phong},
    {&bf_builtin_blinn_phong, &blinn_phong},
    {&bf_builtin_ashikhmin_shirley, &as},
    {&bf_builtin_ashikhmin_shirley_fresnel, &as_fresnel},
    {&bf_builtin_ashikhmin_shirley_2, &as_2},
    {&bf_builtin_cook_torrance, &ct},
    {&bf_builtin_cook_torrance_2, &ct_2},
    {&bf_builtin_ggx, &ggx},
    {&bf_builtin_ggx_2, &ggx_2},
    {&bf_builtin_ward, &ward},
    {&bf_builtin_ward_duer, &ward_duer},
    {&bf_builtin_lafortune, &lafortune},
};

const bf_lobes *bf_builtin_lobes(const bf_builtin *b)
{
    size_t i;
    for (i = 0; i < sizeof TABLE / sizeof TABLE[0]; i++)
        if (TABLE[i].model == b) return TABLE[i].lobes;
    return NULL;
}

const bf_lobes *bf_model_lobes(const brdffit_model *m)
{
    return m != NULL ? m->lobes : NULL;
}

/* gltf-clearcoat: roughness, metallic, clearcoat, clearcoatRoughness,
 * baseColor; openpbr-coat: specular_roughness, base_metalness,
 * specular_ior, coat_weight, coat_roughness, base_color. */
static const bf_coat gltf_coat = {2, 3, 0};
static const bf_coat openpbr_coat = {3, 4, 0};

const bf_coat *bf_builtin_coat(const bf_builtin *b)
{
    if (b == &bf_builtin_gltf_clearcoat) return &gltf_coat;
    if (b == &bf_builtin_openpbr_coat) return &openpbr_coat;
    return NULL;
}

const bf_coat *bf_model_coat(const brdffit_model *m)
{
    return m != NULL ? m->coat : NULL;
}

/* The albedo at node i and angle t for Fresnel parameter f. */
static double node(const bf_albedo_table *a, size_t i, size_t t, double f)
{
    const double *v = a->values + 2 * i * BF_ALBEDO_ANGLES;
    return f * v[t] + (1.0 - f) * v[BF_ALBEDO_ANGLES + t];
}

/* The cell of coordinate x (in nodes) of a table of n nodes, and the
 * weight of its upper node; 0 when x lies outside the table. */
static int cell(double x, size_t n, size_t *i, double *w)
{
    if (!(n >= 2 && x >= -1e-9 && x <= (double)(n - 1) + 1e-9)) return 0;
    x = fmin(fmax(x, 0.0), (double)(n - 1));
    *i = x >= (double)(n - 1) ? n - 2 : (size_t)x;
    *w = x - (double)*i;
    return 1;
}

/* Lafortune's lobe max(0, base)^n, base = cz l_z v_z - (l_x v_x + l_y v_y)
 * = u.v, u = (-l_x, -l_y, cz l_z): m^n max(0, a.v)^n with m = |u| and
 * a = u / m, so its albedo at theta_i is m^n H(n, a_z) (lobes.h). */
static double axial_bound(const bf_axial_table *a, double n, double cz)
{
    static const double deg[BF_ALBEDO_ANGLES] = BF_ALBEDO_ANGLES_DEG;
    const double lnc_lo = a->log10_c_lo * 2.302585092994046, *h = a->log_h;
    const size_t nc = a->n_c;
    double w, top = 0.0;
    size_t i, t;
    if (!(cz >= 0.0 && cz <= 1.0) || !(n > 0.0) ||
        !cell((log10(n) - a->log10_lo) * a->per_decade, a->n, &i, &w))
        return 0.0;
    for (t = 0; t < BF_ALBEDO_ANGLES; t++) {
        const double cti = cos(deg[t] * (BF_PI / 180.0));
        const double m2 = 1.0 - (1.0 - cz * cz) * cti * cti;
        double lnc = lnc_lo, v, lnh;
        size_t j;
        if (!(m2 > 0.0)) continue; /* normal incidence, cz = 0: base = 0 everywhere */
        /* ln c, c = cz ct / m, at least the table's first node */
        if (cz > 0.0) lnc = fmax(log(cz * cti) - 0.5 * log(m2), lnc_lo);
        if (!cell((lnc - lnc_lo) / 2.302585092994046 * a->c_per_decade, nc, &j, &v)) continue;
        lnh = (1.0 - w) * ((1.0 - v) * h[i * nc + j] + v * h[i * nc + j + 1]) +
              w * ((1.0 - v) * h[(i + 1) * nc + j] + v * h[(i + 1) * nc + j + 1]) +
              2.0 * a->excess[i * (nc - 1) + j];
        top = fmax(top, exp(0.5 * n * log(m2) + lnh));
    }
    return top * (1.0 + 1e-3);
}

double bf_lobe_albedo_bound(const bf_lobe_desc *lobe, double shape, double fresnel)
{
    const bf_albedo_table *a = lobe->albedo;
    double w, f = lobe->fresnel == NO ? 1.0 : fmin(fmax(fresnel, 0.0), 1.0);
    double top = 0.0, col[2] = {0.0, 0.0};
    size_t i, t;
    if (lobe->axial != NULL) return axial_bound(lobe->axial, shape, fresnel);
    /* outside the table (bounds wider than the declared ones): no bound */
    if (a == NULL || !(shape > 0.0) ||
        !cell((log10(shape) - a->log10_lo) * a->per_decade, a->n, &i, &w))
        return 0.0;
    for (t = 0; t < BF_ALBEDO_ANGLES; t++) {
        top = fmax(top, (1.0 - w) * node(a, i, t, f) + w * node(a, i + 1, t, f));
        col[0] = fmax(col[0], (1.0 - w) * node(a, i, t, 1.0) + w * node(a, i + 1, t, 1.0));
        col[1] = fmax(col[1], (1.0 - w) * node(a, i, t, 0.0) + w * node(a, i + 1, t, 0.0));
    }
    return top * (1.0 + 1e-3) +
           2.0 * (f * a->excess[2 * i] * col[0] + (1.0 - f) * a->excess[2 * i + 1] * col[1]);
}
