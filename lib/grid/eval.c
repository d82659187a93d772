/* Trilinear interpolation of a regular grid at an arbitrary light/view
 * pair, using isotropy, mirror symmetry and reciprocity. */
#include <math.h>
#include <string.h>

#include "core/core.h"
#include "grid/grid_internal.h"

/* One axis bracket: lower index, upper index and the upper weight t. */
typedef struct bracket {
    size_t lo, hi;
    double t;
} bracket;

/* Clamp x to the axis and find the bracketing values. */
static bracket find_bracket(const double *x, size_t n, double v)
{
    bracket b = {0, 0, 0.0};
    size_t lo = 0, hi = n - 1;
    if (n == 1 || !(v > x[0])) return b;
    if (v >= x[n - 1]) {
        b.lo = b.hi = n - 1;
        return b;
    }
    while (hi - lo > 1) { /* invariant x[lo] < v < x[hi] or v == x[lo] */
        size_t m = lo + (hi - lo) / 2;
        if (x[m] <= v)
            lo = m;
        else
            hi = m;
    }
    b.lo = lo;
    b.hi = hi;
    b.t = (v - x[lo]) / (x[hi] - x[lo]);
    return b;
}

/* Fold an azimuth, relative to a light at azimuth pi, into [0, pi]. */
static double fold_azimuth(double x)
{
    x = fmod(x, 2.0 * BF_PI);
    if (x < 0.0) x = -x;
    if (x > BF_PI) x = 2.0 * BF_PI - x;
    return x;
}

static int within(const double *x, size_t n, double v)
{
    return v >= x[0] && v <= x[n - 1];
}

typedef struct corner_sum {
    double wsum, mean;
} corner_sum;

/* The weighted mean of the present values of one channel over the corners,
 * kept as a running mean: a convex update, which cannot overflow where the
 * sum of weighted values near DBL_MAX would. */
static corner_sum channel_sum(const brdffit_grid *g, size_t c, const bracket b[3])
{
    corner_sum r = {0.0, 0.0};
    size_t n_to = g->n_axis[1], n_po = g->n_axis[2], n = g->n_samples;
    unsigned corner;
    for (corner = 0; corner < 8; corner++) {
        int ui = corner & 1, uj = (corner >> 1) & 1, uk = (corner >> 2) & 1;
        double w = (ui ? b[0].t : 1.0 - b[0].t) * (uj ? b[1].t : 1.0 - b[1].t) *
                   (uk ? b[2].t : 1.0 - b[2].t);
        size_t i = ui ? b[0].hi : b[0].lo, j = uj ? b[1].hi : b[1].lo;
        size_t k = uk ? b[2].hi : b[2].lo, s = (i * n_to + j) * n_po + k;
        if (!(w > 0.0)) continue;
        if (g->missing != NULL && g->missing[c * n + s]) continue;
        r.wsum += w;
        r.mean += w / r.wsum * (g->values[c * n + s] - r.mean);
    }
    return r;
}

brdffit_status brdffit_grid_eval(const brdffit_grid *grid, double theta_i, double phi_i,
                                 double theta_o, double phi_o, double *out, brdffit_error *err)
{
    bracket b[3];
    size_t c, n_empty = 0, first_empty = 0;
    const double *ti;
    if (grid == NULL || out == NULL)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "grid or out is NULL");
    if (grid->magic != BF_MAGIC_GRID)
        return bf_fail(err, BRDFFIT_E_BAD_HANDLE, "grid handle is invalid or destroyed");
    if (grid->kind != BRDFFIT_GRID_REGULAR)
        return bf_fail(err, BRDFFIT_E_UNSUPPORTED, "interpolation needs a regular grid");
    if (!isfinite(theta_i) || !isfinite(phi_i) || !isfinite(theta_o) || !isfinite(phi_o))
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "an angle is not finite");
    ti = grid->axis[0];
    if (!within(ti, grid->n_axis[0], theta_i) && within(ti, grid->n_axis[0], theta_o)) {
        double t = theta_i;
        theta_i = theta_o;
        theta_o = t;
    }
    b[0] = find_bracket(ti, grid->n_axis[0], theta_i);
    b[1] = find_bracket(grid->axis[1], grid->n_axis[1], theta_o);
    b[2] = find_bracket(grid->axis[2], grid->n_axis[2], fold_azimuth(phi_o - (phi_i - BF_PI)));
    for (c = 0; c < grid->n_channels; c++) {
        corner_sum r = channel_sum(grid, c, b);
        out[c] = r.wsum > 0.0 ? r.mean : 0.0;
        if (r.wsum > 0.0) continue;
        if (n_empty++ == 0) first_empty = c;
    }
    if (n_empty > 0)
        return bf_fail(err, BRDFFIT_E_NO_DATA,
                       "every neighbour of the requested directions is missing in %zu "
                       "channel(s), first channel %zu",
                       n_empty, first_empty);
    return BRDFFIT_OK;
}
