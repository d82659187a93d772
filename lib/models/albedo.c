/* Directional albedo of a model: the integral over the view hemisphere of
 * f(l, v) cos(theta_o), by a deterministic quadrature in the half vector.
 *
 * For a fixed light l, v = 2 (l.h) h - l and d(omega_o) = 4 (l.h)
 * d(omega_h). With h at polar angles (theta, phi) and l in the xz plane,
 * v_z = A sin(2 theta) + B cos(2 theta), A = l_x cos(phi), B = l_z, so for
 * each phi the view lies above the horizon exactly for theta in
 * [0, theta_max), theta_max = atan2(A, B) / 2 + pi/4 (which also keeps
 * l.h > 0). The integrand is therefore smooth on the whole integration
 * domain and vanishes at its edge:
 *
 *     albedo = integral over phi of integral from 0 to theta_max of
 *              f(l, v) v_z 4 (l.h) sin(theta) d(theta) d(phi).
 *
 * phi takes the midpoint rule (exponentially accurate for a smooth
 * periodic integrand), with more nodes towards grazing light. theta takes
 * Gauss-Legendre panels whose widths halve towards theta = 0, where every
 * lobe around the mirror direction (h = n) lives, however sharp: a lobe of
 * width w is resolved by the panels of width ~w. The accuracy is stated
 * and measured in model.h and test_model_albedo. */
#include <math.h>
#include <string.h>

#include "core/core.h"
#include "core/quadrature.h"
#include "grid/grid_internal.h"
#include "models/model_internal.h"

#define GAUSS_POINTS 8   /* per theta panel */
#define PANELS 25        /* theta panels: widths theta_max 2^-1 .. 2^-24, then the rest */
#define PHI_POINTS 64    /* per quality step */
#define MAX_STRETCH 16.0 /* most phi nodes per quality step: PHI_POINTS times this */
#define MAX_QUALITY 16u

/* The rule: Gauss-Legendre nodes on [-1, 1] and the sizes. */
typedef struct albedo_rule {
    double x[GAUSS_POINTS], w[GAUSS_POINTS];
    size_t sub;   /* sub-panels per panel (the quality) */
    size_t n_phi; /* phi nodes at normal incidence */
    size_t n_row; /* most theta nodes per phi node */
} albedo_rule;

typedef struct albedo_work {
    bf_geometry geo;
    double *values;  /* n_channels * n_row */
    double *weights; /* n_row */
} albedo_work;

static brdffit_status check_args(const brdffit_model *m, const double *params, size_t n_channels,
                                 const double *theta_i, size_t count, unsigned quality,
                                 const double *albedo, brdffit_error *err)
{
    size_t j, n = brdffit_model_vector_size(m, n_channels);
    if (params == NULL || theta_i == NULL || albedo == NULL)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "params, theta_i or albedo is NULL");
    if (n_channels == 0) return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "n_channels is 0");
    if (quality > MAX_QUALITY)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "quality %u is above %u", quality,
                       MAX_QUALITY);
    if (n == 0 ||
        n_channels > ((size_t)-1 / sizeof(double)) / ((PANELS + 1) * GAUSS_POINTS * MAX_QUALITY))
        return bf_fail(err, BRDFFIT_E_TOO_LARGE, "%zu channels are too many", n_channels);
    for (j = 0; j < n; j++)
        if (!isfinite(params[j]))
            return bf_fail(err, BRDFFIT_E_NONFINITE,
                           "model \"%s\": parameter vector entry %zu is %g", m->name, j, params[j]);
    for (j = 0; j < count; j++)
        if (!(theta_i[j] >= 0.0 && theta_i[j] <= BF_HALF_PI))
            return bf_fail(err, BRDFFIT_E_RANGE, "theta_i[%zu] = %g lies outside [0, pi/2]", j,
                           theta_i[j]);
    return BRDFFIT_OK;
}

/* Adds the nodes of [lo, hi] in theta (r->sub parts of GAUSS_POINTS) for
 * the half-vector azimuth phi: their geometry, and as weight the rule's
 * weight times v_z 4 (l.h) sin(theta) times dphi. */
static void add_panel(const albedo_rule *r, double ti, double phi, double dphi, double lo,
                      double hi, albedo_work *w, size_t *k)
{
    const double lx = -sin(ti), lz = cos(ti), half = 0.5 * (hi - lo) / (double)r->sub;
    size_t s, g;
    for (s = 0; s < r->sub; s++) {
        double a0 = lo + (hi - lo) * (double)s / (double)r->sub;
        for (g = 0; g < GAUSS_POINTS; g++, (*k)++) {
            double t = a0 + half * (1.0 + r->x[g]), st = sin(t), ct = cos(t);
            double hx = st * cos(phi), hy = st * sin(phi), lh = lx * hx + lz * ct;
            double vx = 2.0 * lh * hx - lx, vy = 2.0 * lh * hy, vz = 2.0 * lh * ct - lz;
            vz = vz > 0.0 ? vz : 0.0;
            bf_geometry_set(&w->geo, *k, ti, BF_PI, atan2(sqrt(vx * vx + vy * vy), vz),
                            atan2(vy, vx));
            w->weights[*k] = dphi * half * r->w[g] * vz * 4.0 * (lh > 0.0 ? lh : 0.0) * st;
        }
    }
}

/* The theta nodes of one phi: [0, theta_max) in panels halving towards 0.
 * Where psi = atan2(A, B) > 0 the view at theta = psi has n.v = n.l,
 * where models with max(n.l, n.v) or min(...) have a kink: the panel
 * holding psi is split there. Returns the number of nodes. */
static size_t fill_row(const albedo_rule *r, double ti, double phi, double dphi, albedo_work *w)
{
    const double psi = atan2(-sin(ti) * cos(phi), cos(ti)), top = 0.5 * psi + 0.25 * BF_PI;
    size_t p, k = 0;
    for (p = 0; p < PANELS; p++) {
        double hi = ldexp(top, -(int)p), lo = p + 1 < PANELS ? 0.5 * hi : 0.0;
        if (lo < psi && psi < hi) {
            add_panel(r, ti, phi, dphi, lo, psi, w, &k);
            add_panel(r, ti, phi, dphi, psi, hi, w, &k);
        } else {
            add_panel(r, ti, phi, dphi, lo, hi, w, &k);
        }
    }
    return k;
}

/* The albedo of every channel at one incidence angle. In h space a lobe
 * around the mirror direction is 1 / cos(theta_i) times longer across the
 * plane of incidence than along it, so the phi nodes grow with it. */
static brdffit_status albedo_at(const brdffit_model *m, const albedo_rule *r, const double *params,
                                size_t nc, double ti, albedo_work *w, double *out,
                                brdffit_error *err)
{
    const double stretch = ceil(1.0 / fmax(cos(ti), 1.0 / MAX_STRETCH));
    const size_t n_phi = r->n_phi * (size_t)stretch;
    const double dphi = 2.0 * BF_PI / (double)n_phi;
    brdffit_batch batch;
    size_t j, c, k, n;
    for (c = 0; c < nc; c++) out[c] = 0.0;
    for (j = 0; j < n_phi; j++) {
        n = fill_row(r, ti, dphi * ((double)j + 0.5), dphi, w);
        bf_geometry_batch(&w->geo, 0, n, &batch);
        BF_RETURN_IF_ERROR(bf_model_eval(m, &batch, params, nc, w->values, NULL, err));
        BF_RETURN_IF_ERROR(bf_model_check_outputs(m, n, nc, w->values, NULL, 0, err));
        for (c = 0; c < nc; c++) {
            const double *v = w->values + c * n;
            double sum = 0.0;
            for (k = 0; k < n; k++) sum += w->weights[k] * v[k];
            out[c] += sum;
        }
    }
    return BRDFFIT_OK;
}

brdffit_status brdffit_model_albedo(const brdffit_model *model, const double *params,
                                    size_t n_channels, const double *theta_i, size_t count,
                                    unsigned quality, double *albedo, brdffit_error *err)
{
    albedo_rule r;
    albedo_work w;
    brdffit_status st = BRDFFIT_OK;
    size_t t;
    if (model == NULL) return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "model is NULL");
    if (!bf_model_ok(model))
        return bf_fail(err, BRDFFIT_E_BAD_HANDLE, "model handle is invalid or was destroyed");
    BF_RETURN_IF_ERROR(check_args(model, params, n_channels, theta_i, count, quality, albedo, err));
    if (count == 0) return BRDFFIT_OK;
    bf_gauss_legendre(GAUSS_POINTS, r.x, r.w);
    r.sub = quality == 0 ? 1 : quality;
    r.n_phi = PHI_POINTS * r.sub;
    r.n_row = (PANELS + 1) * r.sub * GAUSS_POINTS;
    memset(&w, 0, sizeof w);
    w.values = bf_calloc(&model->alloc, r.n_row * (n_channels + 1), sizeof(double));
    if (w.values == NULL || !bf_geometry_alloc(&w.geo, &model->alloc, r.n_row)) {
        bf_free(&model->alloc, w.values);
        return bf_fail(err, BRDFFIT_E_OUT_OF_MEMORY, "out of memory for the albedo of \"%s\"",
                       model->name);
    }
    w.weights = w.values + r.n_row * n_channels;
    for (t = 0; t < count && st == BRDFFIT_OK; t++)
        st = albedo_at(model, &r, params, n_channels, theta_i[t], &w, albedo + t * n_channels, err);
    bf_geometry_free(&w.geo, &model->alloc);
    bf_free(&model->alloc, w.values);
    return st;
}
