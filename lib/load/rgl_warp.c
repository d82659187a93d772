/* The warp of the RGL format (Dupuy and Jakob 2018, section 5): a density
 * given at the nodes of a regular grid over [0, 1]^2, interpolated
 * bilinearly, sampled by inverting first the marginal CDF over rows, then
 * the conditional CDF over columns; each inversion solves the quadratic of
 * a linear density. The CDFs are the exact integrals of the interpolant
 * (trapezoids). Samples are kept off the border by the format's clamp to
 * [2^-24, 1 - 2^-24] (docs/formats.md). */
#include <math.h>
#include <string.h>

#include "core/core.h"
#include "load/rgl_internal.h"

#define ONE_MINUS_EPS 0.999999940395355225

static brdffit_status build_slice(bf_warp *w, const bf_tensor_field *f, size_t slice,
                                  brdffit_error *err)
{
    size_t nx = w->nx, ny = w->ny, x, y, base = slice * nx * ny;
    double *d = w->data + base, *c = w->cond + base, *m = w->marg + slice * ny, norm;
    for (x = 0; x < nx * ny; x++) {
        d[x] = bf_tensor_f32(f, base + x);
        if (!isfinite(d[x]) || d[x] < 0.0)
            return bf_fail(err, BRDFFIT_E_RANGE,
                           "RGL vndf value %zu of light %zu is %g (a density must be finite "
                           "and >= 0)",
                           x, slice, d[x]);
    }
    for (y = 0; y < ny; y++) {
        c[y * nx] = 0.0;
        for (x = 0; x + 1 < nx; x++)
            c[y * nx + x + 1] = c[y * nx + x] + 0.5 * (d[y * nx + x] + d[y * nx + x + 1]);
    }
    m[0] = 0.0;
    for (y = 0; y + 1 < ny; y++) m[y + 1] = m[y] + 0.5 * (c[y * nx + nx - 1] + c[(y + 2) * nx - 1]);
    if (!(m[ny - 1] > 0.0 && isfinite(m[ny - 1])))
        return bf_fail(err, BRDFFIT_E_RANGE, "RGL vndf of light %zu integrates to %g", slice,
                       m[ny - 1]);
    norm = 1.0 / m[ny - 1];
    for (x = 0; x < nx * ny; x++) d[x] *= norm, c[x] *= norm;
    for (y = 0; y < ny; y++) m[y] *= norm;
    return BRDFFIT_OK;
}

brdffit_status bf_warp_build(bf_warp *w, const bf_tensor_field *f, size_t n_slices,
                             const brdffit_allocator *a, brdffit_error *err)
{
    size_t n = n_slices * w->nx * w->ny, k; /* sizes checked against the file */
    brdffit_status st = BRDFFIT_OK;
    w->n_slices = n_slices;
    w->data = bf_calloc(a, 2 * n + n_slices * w->ny, sizeof(double));
    if (w->data == NULL)
        return bf_fail(err, BRDFFIT_E_OUT_OF_MEMORY, "out of memory while loading RGL data");
    w->cond = w->data + n;
    w->marg = w->cond + n;
    for (k = 0; st == BRDFFIT_OK && k < n_slices; k++) st = build_slice(w, f, k, err);
    if (st != BRDFFIT_OK) bf_warp_free(w, a);
    return st;
}

void bf_warp_free(bf_warp *w, const brdffit_allocator *a)
{
    bf_free(a, w->data);
    w->data = w->cond = w->marg = NULL;
}

/* Last i in [0, n - 2] with (1 - t) a[i] + t b[i] < v (0 if none). */
static size_t interval(const double *a, const double *b, double t, size_t n, double v)
{
    size_t lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        size_t mid = lo + (hi - lo) / 2;
        if ((1.0 - t) * a[mid] + t * b[mid] < v)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* The t in [0, 1] where the integral of the linear density from c0 to c1
 * reaches v. */
static double solve_linear(double c0, double c1, double v)
{
    double t;
    if (!(c0 + c1 > 0.0)) return 0.0;
    if (fabs(c0 - c1) < 1e-4 * (c0 + c1))
        t = 2.0 * v / (c0 + c1);
    else
        t = (c0 - sqrt(fmax(c0 * c0 - 2.0 * v * (c0 - c1), 0.0))) / (c0 - c1);
    return t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
}

static double clamp_unit(double s)
{
    return s < 1.0 - ONE_MINUS_EPS ? 1.0 - ONE_MINUS_EPS : s > ONE_MINUS_EPS ? ONE_MINUS_EPS : s;
}

double bf_warp_sample(const bf_warp *w, size_t slice, const double s[2], double u[2])
{
    size_t nx = w->nx, ny = w->ny, row, col;
    const double *d = w->data + slice * nx * ny, *c = w->cond + slice * nx * ny;
    const double *m = w->marg + slice * ny;
    double sx = clamp_unit(s[0]), sy = clamp_unit(s[1]), fy, fx, r0, r1, c0, c1;
    const double *ra, *rb;
    row = interval(m, m, 0.0, ny, sy);
    r0 = c[row * nx + nx - 1], r1 = c[(row + 1) * nx + nx - 1];
    fy = solve_linear(r0, r1, sy - m[row]);
    sx *= (1.0 - fy) * r0 + fy * r1;
    ra = c + row * nx, rb = ra + nx;
    col = interval(ra, rb, fy, nx, sx);
    sx -= (1.0 - fy) * ra[col] + fy * rb[col];
    d += row * nx + col;
    c0 = (1.0 - fy) * d[0] + fy * d[nx];
    c1 = (1.0 - fy) * d[1] + fy * d[nx + 1];
    fx = solve_linear(c0, c1, sx);
    u[0] = ((double)col + fx) / (double)(nx - 1);
    u[1] = ((double)row + fy) / (double)(ny - 1);
    return ((1.0 - fx) * c0 + fx * c1) * (double)(nx - 1) * (double)(ny - 1);
}

/* sum_k w_k a[slice_k * stride + i] */
static double lookup(const double *a, const bf_corners *c, size_t stride, size_t i)
{
    return c->w[0] * a[c->slice[0] * stride + i] + c->w[1] * a[c->slice[1] * stride + i] +
           c->w[2] * a[c->slice[2] * stride + i] + c->w[3] * a[c->slice[3] * stride + i];
}

static size_t cell_of(double p, size_t n, double *frac)
{
    double x = p * (double)(n - 1);
    size_t i;
    if (!(x > 0.0)) x = 0.0;
    if (x > (double)(n - 1)) x = (double)(n - 1);
    i = (size_t)x;
    if (i > n - 2) i = n - 2;
    *frac = x - (double)i;
    return i;
}

double bf_warp_invert(const bf_warp *w, const bf_corners *c, const double u[2], double s[2])
{
    size_t nx = w->nx, ny = w->ny, sz = nx * ny, ix, iy, off;
    double fx, fy, v00, v10, v01, v11, c0, c1, r0, r1, den;
    ix = cell_of(u[0], nx, &fx);
    iy = cell_of(u[1], ny, &fy);
    off = iy * nx + ix;
    v00 = lookup(w->data, c, sz, off), v10 = lookup(w->data, c, sz, off + 1);
    v01 = lookup(w->data, c, sz, off + nx), v11 = lookup(w->data, c, sz, off + nx + 1);
    c0 = (1.0 - fy) * v00 + fy * v01;
    c1 = (1.0 - fy) * v10 + fy * v11;
    s[0] = fx * (c0 + 0.5 * fx * (c1 - c0)) + (1.0 - fy) * lookup(w->cond, c, sz, off) +
           fy * lookup(w->cond, c, sz, off + nx);
    r0 = lookup(w->cond, c, sz, iy * nx + nx - 1);
    r1 = lookup(w->cond, c, sz, (iy + 1) * nx + nx - 1);
    den = (1.0 - fy) * r0 + fy * r1;
    s[0] = den > 0.0 ? s[0] / den : 0.0;
    s[1] = fy * (r0 + 0.5 * fy * (r1 - r0)) + lookup(w->marg, c, ny, iy);
    return ((1.0 - fx) * c0 + fx * c1) * (double)(nx - 1) * (double)(ny - 1);
}

double bf_bilinear(const bf_tensor_field *f, size_t base, size_t nx, size_t ny,
                   const double pos[2])
{
    double fx, fy;
    size_t ix = cell_of(pos[0], nx, &fx), iy = cell_of(pos[1], ny, &fy);
    size_t i = base + iy * nx + ix;
    double v00 = bf_tensor_f32(f, i), v10 = bf_tensor_f32(f, i + 1);
    double v01 = bf_tensor_f32(f, i + nx), v11 = bf_tensor_f32(f, i + nx + 1);
    return (1.0 - fy) * ((1.0 - fx) * v00 + fx * v10) + fy * ((1.0 - fx) * v01 + fx * v11);
}
