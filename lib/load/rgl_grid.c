/* The two grid forms of an RGL file (docs/formats.md).
 *
 * Scattered: every stored sample of every light direction, at the view
 * the format's warp gives it: the sample's point s of the unit square goes
 * through the VNDF warp to u = (sqrt(theta_m / (pi/2)), (phi_m - phi_i) /
 * (2 pi) + 1/2) (phi_m absolute for anisotropic files), the microfacet
 * normal m, and the view wo = 2 (wi . m) m - wi. The stored value is
 * f_r cos theta_o (times 4 sigma(wi) / D(m) when the jacobian flag is
 * set), so f_r = value D(u) / (4 sigma(u_i)) / cos theta_o. The solid
 * angle of the sample is its cell in s (a trapezoid-rule weight) times
 * d omega_o / d s = 4 (wi . m) 2 pi^2 u_x sin theta_m / pdf(u).
 *
 * Regular: each sample of the axes is evaluated like the reference reader
 * does: u from the half vector, s from the inverse warp (interpolated
 * between the file's light directions), the values bilinear in s. */
#include <math.h>
#include <string.h>

#include "brdffit/load.h"
#include "core/core.h"
#include "load/load_internal.h"
#include "load/rgl_internal.h"

static void direction(double theta, double phi, double d[3])
{
    d[0] = sin(theta) * cos(phi), d[1] = sin(theta) * sin(phi), d[2] = cos(theta);
}

static double polar_of(const double d[3])
{
    return atan2(sqrt(d[0] * d[0] + d[1] * d[1]), d[2]);
}

/* D(u) / (4 sigma(u_i)) with the light at (theta_i, phi_i), or 1 without
 * the jacobian flag; 0 when sigma is 0. */
static double jacobian_scale(const rgl_file *f, const double u[2], double theta_i, double phi_i)
{
    double ui[2], s;
    if (!f->jacobian) return 1.0;
    ui[0] = sqrt(theta_i / BF_HALF_PI), ui[1] = (phi_i + BF_PI) / (2.0 * BF_PI);
    s = 4.0 * bf_bilinear(f->sigma, 0, f->sigma->shape[1], f->sigma->shape[0], ui);
    if (!(s > 0.0)) return 0.0;
    return bf_bilinear(f->ndf, 0, f->ndf->shape[1], f->ndf->shape[0], u) / s;
}

/* ---- scattered -------------------------------------------------------------------- */

typedef struct rgl_arrays {
    double *angles, *values, *weights; /* 4 n, nc n, n; angles owns the block */
    unsigned char *missing;
    size_t n, used;
} rgl_arrays;

static brdffit_status arrays_alloc(rgl_arrays *r, size_t n, size_t nc, const brdffit_allocator *a,
                                   brdffit_error *err)
{
    memset(r, 0, sizeof *r);
    r->n = n;
    r->angles = bf_calloc(a, n, (5 + nc) * sizeof(double));
    r->missing = bf_calloc(a, n, nc);
    if (r->angles == NULL || r->missing == NULL) {
        bf_free(a, r->angles);
        bf_free(a, r->missing);
        return bf_fail(err, BRDFFIT_E_OUT_OF_MEMORY, "out of memory while loading RGL data");
    }
    r->weights = r->angles + 4 * n;
    r->values = r->weights + n;
    return BRDFFIT_OK;
}

/* Light (a, b), sample node (k, l): stored as sample r->used unless its
 * view lies at the horizon or below. */
static void keep_sample(const rgl_file *f, size_t a, size_t b, size_t k, size_t l, rgl_arrays *r)
{
    double ti = bf_tensor_f32(f->theta_i, b), pi = bf_tensor_f32(f->phi_i, a);
    double s[2], u[2], wi[3], m[3], wo[3], pdf, dot, tm, scale, cell;
    size_t c, i = r->used, nc = f->nc, slice = a * f->n_theta + b;
    s[0] = (double)k / (double)(f->nx - 1), s[1] = (double)l / (double)(f->ny - 1);
    pdf = bf_warp_sample(&f->warp, slice, s, u);
    tm = u[0] * u[0] * BF_HALF_PI;
    direction(ti, pi, wi);
    direction(tm, (2.0 * u[1] - 1.0) * BF_PI + (f->isotropic ? pi : 0.0), m);
    dot = wi[0] * m[0] + wi[1] * m[1] + wi[2] * m[2];
    for (c = 0; c < 3; c++) wo[c] = 2.0 * dot * m[c] - wi[c];
    if (!(wo[2] > BF_RGL_MIN_COS)) return;
    scale = jacobian_scale(f, u, ti, pi) / wo[2];
    for (c = 0; c < nc; c++) {
        size_t v = ((slice * nc + c) * f->ny + l) * f->nx + k;
        r->values[i * nc + c] = bf_tensor_f32(f->values, v) * scale;
        r->missing[i * nc + c] = (unsigned char)!(scale > 0.0);
    }
    cell = (k == 0 || k == f->nx - 1 ? 0.5 : 1.0) * (l == 0 || l == f->ny - 1 ? 0.5 : 1.0) /
           ((double)(f->nx - 1) * (double)(f->ny - 1));
    r->weights[i] = pdf > 0.0 ? cell * 8.0 * BF_PI * BF_PI * u[0] * sin(tm) * dot / pdf : 0.0;
    if (!(r->weights[i] >= 0.0 && isfinite(r->weights[i]))) r->weights[i] = 0.0;
    r->angles[i] = ti, r->angles[r->n + i] = pi;
    r->angles[2 * r->n + i] = polar_of(wo), r->angles[3 * r->n + i] = atan2(wo[1], wo[0]);
    r->used++;
}

brdffit_status bf_rgl_scattered(brdffit_grid **out, const rgl_file *f, const brdffit_allocator *a,
                                brdffit_error *err)
{
    rgl_arrays r;
    size_t n = f->n_phi * f->n_theta * f->nx * f->ny, i, k, l; /* < the file's value count */
    brdffit_status st;
    BF_RETURN_IF_ERROR(arrays_alloc(&r, n, f->nc, a, err));
    for (i = 0; i < f->n_phi * f->n_theta; i++)
        for (l = 0; l < f->ny; l++)
            for (k = 0; k < f->nx; k++) keep_sample(f, i / f->n_theta, i % f->n_theta, k, l, &r);
    if (r.used == 0)
        st = bf_fail(err, BRDFFIT_E_NO_DATA, "no RGL sample has its view above the horizon");
    else
        st = brdffit_grid_create_scattered(out, r.used, r.angles, r.angles + n, r.angles + 2 * n,
                                           r.angles + 3 * n, f->nc, r.values, r.missing,
                                           r.weights, a, err);
    bf_free(a, r.angles);
    bf_free(a, r.missing);
    return st;
}

/* ---- regular ---------------------------------------------------------------------- */

/* Index and weights of p between the values of an axis field (clamped). */
static void param_weights(const bf_tensor_field *x, double p, size_t *i0, double *w1)
{
    size_t lo = 0, hi = x->count - 1;
    double p0, p1;
    *i0 = 0, *w1 = 0.0;
    if (x->count == 1) return;
    while (hi - lo > 1) {
        size_t mid = lo + (hi - lo) / 2;
        if (bf_tensor_f32(x, mid) <= p)
            lo = mid;
        else
            hi = mid;
    }
    p0 = bf_tensor_f32(x, lo), p1 = bf_tensor_f32(x, lo + 1);
    *i0 = lo;
    *w1 = (p - p0) / (p1 - p0);
    *w1 = *w1 < 0.0 ? 0.0 : *w1 > 1.0 ? 1.0 : *w1;
}

static void corners(const rgl_file *f, double phi_i, double theta_i, bf_corners *c)
{
    size_t ia, ib, ja, jb;
    double wa, wb;
    param_weights(f->phi_i, phi_i, &ia, &wa);
    param_weights(f->theta_i, theta_i, &ib, &wb);
    ja = f->n_phi > 1 ? ia + 1 : ia, jb = f->n_theta > 1 ? ib + 1 : ib;
    c->slice[0] = ia * f->n_theta + ib, c->w[0] = (1.0 - wa) * (1.0 - wb);
    c->slice[1] = ia * f->n_theta + jb, c->w[1] = (1.0 - wa) * wb;
    c->slice[2] = ja * f->n_theta + ib, c->w[2] = wa * (1.0 - wb);
    c->slice[3] = ja * f->n_theta + jb, c->w[3] = wa * wb;
}

/* f_r of every channel for the light at (theta_i, pi) and the view at
 * (theta_o, phi_o); returns 0 (missing) at the horizon. */
static int eval_pair(const rgl_file *f, double theta_i, double theta_o, double phi_o, double *out)
{
    double wi[3], wo[3], h[3], len, u[2], s[2], pi, scale;
    bf_corners cn;
    size_t c, k;
    direction(theta_i, BF_PI, wi);
    direction(theta_o, phi_o, wo);
    if (!(wi[2] > 0.0 && wo[2] > BF_RGL_MIN_COS)) return 0;
    for (c = 0; c < 3; c++) h[c] = wi[c] + wo[c];
    len = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    for (c = 0; c < 3; c++) h[c] /= len;
    pi = atan2(wi[1], wi[0]);
    u[0] = sqrt(polar_of(h) / BF_HALF_PI);
    u[1] = (atan2(h[1], h[0]) - (f->isotropic ? pi : 0.0) + BF_PI) / (2.0 * BF_PI);
    u[1] -= floor(u[1]);
    corners(f, pi, theta_i, &cn);
    bf_warp_invert(&f->warp, &cn, u, s);
    scale = jacobian_scale(f, u, theta_i, pi) / wo[2];
    if (!(scale > 0.0)) return 0;
    for (c = 0; c < f->nc; c++) {
        double v = 0.0;
        for (k = 0; k < 4; k++)
            if (cn.w[k] != 0.0)
                v += cn.w[k] * bf_bilinear(f->values, (cn.slice[k] * f->nc + c) * f->nx * f->ny,
                                           f->nx, f->ny, s);
        out[c] = v * scale;
    }
    return 1;
}

static int resample(const rgl_file *f, const brdffit_axes *ax, double *values,
                    unsigned char *missing)
{
    size_t i, j, k, c, s = 0, nc = f->nc;
    int any = 0;
    for (i = 0; i < ax->n_theta_i; i++)
        for (j = 0; j < ax->n_theta_o; j++)
            for (k = 0; k < ax->n_phi_o; k++, s++) {
                int ok = eval_pair(f, ax->theta_i[i], ax->theta_o[j], ax->phi_o[k],
                                   values + s * nc);
                for (c = 0; c < nc; c++) missing[s * nc + c] = (unsigned char)!ok;
                any |= ok;
            }
    return any;
}

brdffit_status bf_rgl_regular(brdffit_grid **out, const rgl_file *f, const brdffit_axes *axes,
                              const brdffit_allocator *a, brdffit_error *err)
{
    size_t n = 0, nv;
    double *values;
    unsigned char *missing;
    brdffit_status st;
    BF_RETURN_IF_ERROR(bf_load_axes_count(axes, 1, &n, err));
    if (!f->isotropic && f->reduction != 1)
        return bf_fail(err, BRDFFIT_E_UNSUPPORTED,
                       "resampling an anisotropic RGL file measured over 1/%d of the light "
                       "azimuths is not supported; load it scattered (axes NULL)",
                       f->reduction);
    if (!bf_mul_size(n, f->nc, &nv) || nv > BF_LOAD_MAX_VALUES)
        return bf_fail(err, BRDFFIT_E_TOO_LARGE, "%zu samples of %zu channels are too many", n,
                       f->nc);
    values = bf_calloc(a, nv, sizeof(double));
    missing = bf_calloc(a, nv, 1);
    if (values == NULL || missing == NULL)
        st = bf_fail(err, BRDFFIT_E_OUT_OF_MEMORY, "out of memory while loading RGL data");
    else if (!resample(f, axes, values, missing))
        st = bf_fail(err, BRDFFIT_E_NO_DATA, "no sample of the axes has a view above the horizon");
    else
        st = brdffit_grid_create_regular(out, axes, f->nc, values, missing, a, err);
    bf_free(a, values);
    bf_free(a, missing);
    return st;
}
