/* Derived per-sample geometry (docs/definitions.md, Geometry): light, view and half
 * vectors and the guarded dot products the model kernels stream. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "core/core.h"
#include "grid/grid_internal.h"

/* Doubles of the arrays of the batch, then floats of the fused passes'. */
#define BF_GEOMETRY_DOUBLES 13
#define BF_GEOMETRY_FLOATS 3

size_t bf_geometry_bytes(size_t n)
{
    size_t d, f;
    if (!bf_mul_size(n, BF_GEOMETRY_DOUBLES * sizeof(double), &d) ||
        !bf_mul_size(n, BF_GEOMETRY_FLOATS * sizeof(float), &f) || d > (size_t)-1 - f)
        return 0;
    return d + f;
}

int bf_geometry_alloc(bf_geometry *g, const brdffit_allocator *a, size_t n)
{
    size_t bytes = bf_geometry_bytes(n);
    double *p;
    float *f;
    memset(g, 0, sizeof *g);
    if (bytes == 0) return 0;
    p = bf_calloc(a, bytes, 1);
    if (p == NULL) return 0;
    g->block = p;
    g->lx = p;
    g->ly = p + n;
    g->lz = p + 2 * n;
    g->vx = p + 3 * n;
    g->vy = p + 4 * n;
    g->vz = p + 5 * n;
    g->nl = p + 6 * n;
    g->nv = p + 7 * n;
    g->nh = p + 8 * n;
    g->hv = p + 9 * n;
    g->log_nh = p + 10 * n;
    g->rv = p + 11 * n;
    g->log_rv = p + 12 * n;
    f = (float *)(void *)(p + BF_GEOMETRY_DOUBLES * n);
    g->as_g = f;
    g->w_base[BF_BASE_DEFAULT] = f + n;
    g->w_base[BF_BASE_SOLID_ANGLE] = f + 2 * n;
    return 1;
}

void bf_geometry_free(bf_geometry *g, const brdffit_allocator *a)
{
    bf_free(a, g->block);
    memset(g, 0, sizeof *g);
}

static double clamp_dot(double x)
{
    if (!(x >= BF_DOT_FLOOR)) return BF_DOT_FLOOR; /* also catches NaN */
    return x > 1.0 ? 1.0 : x;
}

/* Rounding can push a cosine of unit vectors just past +-1. */
static double clamp_unit(double x)
{
    return x > 1.0 ? 1.0 : (x < -1.0 ? -1.0 : x);
}

/* Below this |cos theta| a polar angle is 90 degrees: a few ulps of pi/2. */
#define BF_HORIZON_COS 1e-15

double bf_cos_polar(double theta)
{
    double c = cos(theta);
    return fabs(c) <= BF_HORIZON_COS ? 0.0 : c;
}

void bf_geometry_set(bf_geometry *g, size_t s, double theta_i, double phi_i, double theta_o,
                     double phi_o)
{
    double lx = sin(theta_i) * cos(phi_i), ly = sin(theta_i) * sin(phi_i),
           lz = bf_cos_polar(theta_i);
    double vx = sin(theta_o) * cos(phi_o), vy = sin(theta_o) * sin(phi_o),
           vz = bf_cos_polar(theta_o);
    double hx = lx + vx, hy = ly + vy, hz = lz + vz;
    double len = sqrt(hx * hx + hy * hy + hz * hz);
    if (len > 1e-12) {
        hx /= len;
        hy /= len;
        hz /= len;
    } else { /* light and view exactly opposite: no half vector, use n */
        hx = 0.0;
        hy = 0.0;
        hz = 1.0;
    }
    g->lx[s] = lx;
    g->ly[s] = ly;
    g->lz[s] = lz;
    g->vx[s] = vx;
    g->vy[s] = vy;
    g->vz[s] = vz;
    g->nl[s] = clamp_dot(lz);
    g->nv[s] = clamp_dot(vz);
    g->nh[s] = clamp_dot(hz);
    g->hv[s] = clamp_dot(hx * vx + hy * vy + hz * vz);
    g->log_nh[s] = log(g->nh[s]);
    g->rv[s] = clamp_unit(-lx * vx - ly * vy + lz * vz);
    /* the parameter-independent factors of the fit's fused passes (the
     * kernels' expressions; the lobe's geometry rounded once to single
     * precision) */
    g->log_rv[s] = g->rv[s] > 0.0 ? log(fmin(fmax(g->rv[s], DBL_MIN), 1.0)) : BF_LOG_RV_NONE;
    g->as_g[s] =
        (float)(1.0 / (8.0 * BF_PI * g->hv[s] * (g->nl[s] > g->nv[s] ? g->nl[s] : g->nv[s])));
}

void bf_geometry_batch(const bf_geometry *g, size_t first, size_t count, brdffit_batch *out)
{
    out->struct_size = sizeof *out;
    out->n = count;
    out->lx = g->lx + first;
    out->ly = g->ly + first;
    out->lz = g->lz + first;
    out->vx = g->vx + first;
    out->vy = g->vy + first;
    out->vz = g->vz + first;
    out->nl = g->nl + first;
    out->nv = g->nv + first;
    out->nh = g->nh + first;
    out->hv = g->hv + first;
    out->log_nh = g->log_nh + first;
    out->rv = g->rv + first;
}
