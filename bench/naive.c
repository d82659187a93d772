/* The naive reference pass: see naive.h. Deliberately straightforward. */
#include "naive.h"

#include <math.h>
#include <string.h>

#define NAIVE_PI 3.14159265358979323846
#define NAIVE_FLOOR 1e-4

static double clamp_dot(double x)
{
    if (!(x >= NAIVE_FLOOR)) return NAIVE_FLOOR;
    return x > 1.0 ? 1.0 : x;
}

void naive_geometry(double theta_i, double phi_i, double theta_o, double phi_o, naive_geom *g)
{
    double h[3], len;
    int k;
    g->l[0] = sin(theta_i) * cos(phi_i);
    g->l[1] = sin(theta_i) * sin(phi_i);
    g->l[2] = cos(theta_i);
    g->v[0] = sin(theta_o) * cos(phi_o);
    g->v[1] = sin(theta_o) * sin(phi_o);
    g->v[2] = cos(theta_o);
    for (k = 0; k < 3; k++) h[k] = g->l[k] + g->v[k];
    len = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    if (len > 1e-12) {
        for (k = 0; k < 3; k++) h[k] /= len;
    } else {
        h[0] = 0.0, h[1] = 0.0, h[2] = 1.0;
    }
    g->nl = clamp_dot(g->l[2]);
    g->nv = clamp_dot(g->v[2]);
    g->nh = clamp_dot(h[2]);
    g->hv = clamp_dot(h[0] * g->v[0] + h[1] * g->v[1] + h[2] * g->v[2]);
    g->rv = -g->l[0] * g->v[0] - g->l[1] * g->v[1] + g->l[2] * g->v[2];
}

/* ---- models -----------------------------------------------------------------
 * Each computes the value of channel c and, when row is not NULL, the whole
 * derivative row. */

static void lambert_row(const naive_geom *g, const double *p, size_t nc, size_t c, size_t n_vec,
                        double *value, double *row)
{
    (void)g;
    (void)nc;
    *value = p[c] / NAIVE_PI;
    if (row == NULL) return;
    memset(row, 0, n_vec * sizeof *row);
    row[c] = 1.0 / NAIVE_PI;
}

/* Models of the form cd/pi + cs * lobe(s), s one shape parameter. */
static void diffuse_plus_lobe(const double *p, size_t nc, size_t c, size_t n_vec, double lobe,
                              double dlobe, double *row)
{
    memset(row, 0, n_vec * sizeof *row);
    row[0] = p[1 + nc + c] * dlobe;
    row[1 + c] = 1.0 / NAIVE_PI;
    row[1 + nc + c] = lobe;
}

static double diffuse_value(const double *p, size_t nc, size_t c, double lobe)
{
    return p[1 + c] / NAIVE_PI + p[1 + nc + c] * lobe;
}

static void phong_row(const naive_geom *g, const double *p, size_t nc, size_t c, size_t n_vec,
                      double *value, double *row)
{
    double ns = p[0], k = (ns + 2.0) / (2.0 * NAIVE_PI), pw = g->rv > 0.0 ? pow(g->rv, ns) : 0.0;
    *value = diffuse_value(p, nc, c, k * pw);
    if (row == NULL) return;
    diffuse_plus_lobe(p, nc, c, n_vec, k * pw,
                      g->rv > 0.0 ? pw / (2.0 * NAIVE_PI) + k * pw * log(g->rv) : 0.0, row);
}

static void blinn_row(const naive_geom *g, const double *p, size_t nc, size_t c, size_t n_vec,
                      double *value, double *row)
{
    double ns = p[0], k = (ns + 8.0) / (8.0 * NAIVE_PI), pw = pow(g->nh, ns);
    *value = diffuse_value(p, nc, c, k * pw);
    if (row == NULL) return;
    diffuse_plus_lobe(p, nc, c, n_vec, k * pw, pw / (8.0 * NAIVE_PI) + k * pw * log(g->nh), row);
}

/* The Ashikhmin-Shirley lobe (ns+1)/(8 pi) (n.h)^ns / ((h.v) max(n.l, n.v))
 * and, when dlobe is not NULL, its derivative (4.29). */
static double as_lobe(const naive_geom *g, double ns, double *dlobe)
{
    double pw = pow(g->nh, ns);
    double den = 8.0 * NAIVE_PI * g->hv * fmax(g->nl, g->nv);
    if (dlobe != NULL) *dlobe = (pw + (ns + 1.0) * pw * log(g->nh)) / den;
    return (ns + 1.0) * pw / den;
}

static void as_row(const naive_geom *g, const double *p, size_t nc, size_t c, size_t n_vec,
                   double *value, double *row)
{
    double dlobe, lobe = as_lobe(g, p[0], row ? &dlobe : NULL);
    *value = diffuse_value(p, nc, c, lobe);
    if (row == NULL) return;
    diffuse_plus_lobe(p, nc, c, n_vec, lobe, dlobe, row);
}

/* ns, Rs; cd; cs. */
static void asf_row(const naive_geom *g, const double *p, size_t nc, size_t c, size_t n_vec,
                    double *value, double *row)
{
    double rs = p[1], cd = p[2 + c], cs = p[2 + nc + c], dlobe;
    double lobe = as_lobe(g, p[0], row ? &dlobe : NULL);
    double fd = 28.0 / (23.0 * NAIVE_PI) * (1.0 - pow(1.0 - g->nl / 2.0, 5.0)) *
                (1.0 - pow(1.0 - g->nv / 2.0, 5.0));
    double f5 = pow(1.0 - g->hv, 5.0), fresnel = rs + (1.0 - rs) * f5;
    *value = (1.0 - rs) * fd * cd + lobe * fresnel * cs;
    if (row == NULL) return;
    memset(row, 0, n_vec * sizeof *row);
    row[0] = cs * dlobe * fresnel;
    row[1] = -fd * cd + cs * lobe * (1.0 - f5);
    row[2 + c] = (1.0 - rs) * fd;
    row[2 + nc + c] = lobe * fresnel;
}

/* Microfacet models: rough, F0; cd; cs. */
static void microfacet_row(const double *p, size_t nc, size_t c, size_t n_vec, double spec,
                           double dspec_rough, double dspec_f0, double *row)
{
    memset(row, 0, n_vec * sizeof *row);
    row[0] = p[2 + nc + c] * dspec_rough;
    row[1] = p[2 + nc + c] * dspec_f0;
    row[2 + c] = 1.0 / NAIVE_PI;
    row[2 + nc + c] = spec;
}

static double microfacet_value(const double *p, size_t nc, size_t c, double spec)
{
    return p[2 + c] / NAIVE_PI + p[2 + nc + c] * spec;
}

static double tan2_of(double cos_theta)
{
    return (1.0 - cos_theta * cos_theta) / (cos_theta * cos_theta);
}

static void ct_row(const naive_geom *g, const double *p, size_t nc, size_t c, size_t n_vec,
                   double *value, double *row)
{
    double m = p[0], f0 = p[1], t2 = tan2_of(g->nh);
    double d = exp(-t2 / (m * m)) / (NAIVE_PI * m * m * pow(g->nh, 4.0));
    double gg = fmin(1.0, fmin(2.0 * g->nh * g->nv / g->hv, 2.0 * g->nh * g->nl / g->hv));
    double f5 = pow(1.0 - g->hv, 5.0), fresnel = f0 + (1.0 - f0) * f5;
    double spec = d * gg * fresnel / (4.0 * g->nl * g->nv);
    *value = microfacet_value(p, nc, c, spec);
    if (row == NULL) return;
    microfacet_row(p, nc, c, n_vec, spec, spec * (2.0 * t2 / (m * m * m) - 2.0 / m),
                   d * gg * (1.0 - f5) / (4.0 * g->nl * g->nv), row);
}

static void ggx_row(const naive_geom *g, const double *p, size_t nc, size_t c, size_t n_vec,
                    double *value, double *row)
{
    double a = p[0], f0 = p[1], c2 = g->nh * g->nh;
    double q = c2 * (a * a - 1.0) + 1.0;
    double d = a * a / (NAIVE_PI * q * q);
    double tl = tan2_of(g->nl), tv = tan2_of(g->nv);
    double sl = sqrt(1.0 + a * a * tl), sv = sqrt(1.0 + a * a * tv);
    double gg = 1.0 / (1.0 + (sl - 1.0) / 2.0 + (sv - 1.0) / 2.0);
    double f5 = pow(1.0 - g->hv, 5.0), fresnel = f0 + (1.0 - f0) * f5;
    double s = 1.0 / (4.0 * g->nl * g->nv), dd, dg;
    *value = microfacet_value(p, nc, c, d * gg * fresnel * s);
    if (row == NULL) return;
    dd = 2.0 * a / (NAIVE_PI * q * q) - 4.0 * a * a * a * c2 / (NAIVE_PI * q * q * q);
    dg = -gg * gg * (a * tl / (2.0 * sl) + a * tv / (2.0 * sv));
    microfacet_row(p, nc, c, n_vec, d * gg * fresnel * s, (dd * gg + d * dg) * fresnel * s,
                   d * gg * (1.0 - f5) * s, row);
}

static void ward_common(const naive_geom *g, const double *p, size_t nc, size_t c, size_t n_vec,
                        double norm, double *value, double *row)
{
    double a = p[0], t2 = tan2_of(g->nh);
    double lobe = exp(-t2 / (a * a)) / (4.0 * NAIVE_PI * a * a * norm);
    *value = diffuse_value(p, nc, c, lobe);
    if (row == NULL) return;
    diffuse_plus_lobe(p, nc, c, n_vec, lobe, lobe * (2.0 * t2 / (a * a * a) - 2.0 / a), row);
}

static void ward_row(const naive_geom *g, const double *p, size_t nc, size_t c, size_t n_vec,
                     double *value, double *row)
{
    ward_common(g, p, nc, c, n_vec, sqrt(g->nl * g->nv), value, row);
}

static void ward_duer_row(const naive_geom *g, const double *p, size_t nc, size_t c, size_t n_vec,
                          double *value, double *row)
{
    ward_common(g, p, nc, c, n_vec, g->nl * g->nv, value, row);
}

static const naive_model naive_models[] = {
    {"lambert", lambert_row},
    {"phong", phong_row},
    {"blinn-phong", blinn_row},
    {"ashikhmin-shirley", as_row},
    {"ashikhmin-shirley-fresnel", asf_row},
    {"cook-torrance", ct_row},
    {"ggx", ggx_row},
    {"ward", ward_row},
    {"ward-duer", ward_duer_row},
};

const naive_model *naive_find(const char *name)
{
    size_t i;
    for (i = 0; i < sizeof naive_models / sizeof naive_models[0]; i++)
        if (strcmp(naive_models[i].name, name) == 0) return &naive_models[i];
    return NULL;
}

/* ---- the passes ---------------------------------------------------------------- */

void naive_value_pass(const naive_model *m, const naive_data *d, const double *params, size_t n_vec,
                      double *values)
{
    size_t s, c;
    for (s = 0; s < d->n; s++) {
        naive_geom g;
        naive_geometry(d->theta_i[s], d->phi_i[s], d->theta_o[s], d->phi_o[s], &g);
        for (c = 0; c < d->nc; c++)
            m->row(&g, params, d->nc, c, n_vec, &values[c * d->n + s], NULL);
    }
}

void naive_jacobian_pass(const naive_model *m, const naive_data *d, const double *params,
                         size_t n_vec, double *values, double *jac)
{
    size_t s, c;
    for (s = 0; s < d->n; s++) {
        naive_geom g;
        naive_geometry(d->theta_i[s], d->phi_i[s], d->theta_o[s], d->phi_o[s], &g);
        for (c = 0; c < d->nc; c++) {
            size_t i = c * d->n + s;
            m->row(&g, params, d->nc, c, n_vec, &values[i], &jac[i * n_vec]);
        }
    }
}

void naive_normal_pass(const naive_model *m, const naive_data *d, const double *params,
                       size_t n_vec, double *acc, double *row)
{
    double *jtr = acc + 1, *jtj = acc + 1 + n_vec;
    size_t s, c, a, b;
    memset(acc, 0, (1 + n_vec + n_vec * n_vec) * sizeof *acc);
    for (s = 0; s < d->n; s++) {
        naive_geom g;
        double w = d->weight[s];
        naive_geometry(d->theta_i[s], d->phi_i[s], d->theta_o[s], d->phi_o[s], &g);
        for (c = 0; c < d->nc; c++) {
            double value, r;
            m->row(&g, params, d->nc, c, n_vec, &value, row);
            r = w * (value - d->meas[c * d->n + s]);
            acc[0] += r * r;
            for (a = 0; a < n_vec; a++) {
                jtr[a] += w * row[a] * r;
                for (b = 0; b < n_vec; b++) jtj[a * n_vec + b] += w * row[a] * w * row[b];
            }
        }
    }
}
