/* Residual weights (docs/definitions.md, Weights, eq. 4.25) and the angle cap: the
 * streaming weight plan and brdffit_grid_weights() built on it. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "core/core.h"
#include "grid/grid_internal.h"

/* Angle cap comparisons accept theta <= cap + BF_CAP_TOL. */
#define BF_CAP_TOL 1e-9

static int cap_ok(double cap)
{
    return cap >= 0.0 && cap <= BF_HALF_PI; /* false for NaN */
}

/* Number of leading axis values within the cap (axes increase strictly). */
static size_t axis_active(const double *x, size_t n, double cap)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (x[mid] <= cap + BF_CAP_TOL)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

size_t brdffit_grid_active_count(const brdffit_grid *grid, double cap)
{
    size_t n_ti, n_to;
    if (!bf_grid_ok(grid) || !cap_ok(cap)) return 0;
    if (grid->kind == BRDFFIT_GRID_SCATTERED)
        return axis_active(grid->max_theta, grid->n_samples, cap);
    n_ti = axis_active(grid->axis[0], grid->n_axis[0], cap);
    n_to = axis_active(grid->axis[1], grid->n_axis[1], cap);
    return n_ti * n_to * grid->n_axis[2];
}

/* ---- regular grids -------------------------------------------------------- */

static double mid(const double *x, size_t j)
{
    return 0.5 * (x[j] + x[j + 1]);
}

/* Polar extent of view cell j; `last` is the index of the last active value. */
static void theta_cell(const double *x, size_t n, size_t j, size_t last, double cap, double *lo,
                       double *hi)
{
    *lo = j == 0 ? x[0] : mid(x, j - 1);
    if (j < last)
        *hi = mid(x, j);
    else if (j + 1 < n)
        *hi = fmin(cap, mid(x, j));
    else
        *hi = x[j];
    if (*hi < *lo) *hi = *lo;
}

static double phi_width(const double *x, size_t n, size_t k)
{
    double lo = k == 0 ? x[0] : mid(x, k - 1);
    double hi = k + 1 == n ? x[k] : mid(x, k);
    return hi - lo;
}

/* Per-axis factors; returns the sum of the active cells' solid angles. */
static double regular_factors(bf_weight_plan *p, double cap)
{
    const brdffit_grid *g = p->grid;
    size_t i, j, k;
    double sum_to = 0.0, sum_po = 0.0;
    int solid = (p->flags & BRDFFIT_WEIGHT_SOLID_ANGLE) != 0;
    int cosine = (p->flags & BRDFFIT_WEIGHT_COSINE) != 0;
    for (i = 0; i < p->n_ti_act; i++)
        p->w_ti[i] = cosine ? fmax(bf_cos_polar(g->axis[0][i]), 0.0) : 1.0;
    for (j = 0; j < p->n_to_act; j++) {
        double lo, hi;
        theta_cell(g->axis[1], g->n_axis[1], j, p->n_to_act - 1, cap, &lo, &hi);
        p->w_to[j] = solid ? cos(lo) - cos(hi) : 1.0;
        if (p->w_to[j] < 0.0) p->w_to[j] = 0.0;
        sum_to += p->w_to[j];
    }
    for (k = 0; k < g->n_axis[2]; k++) {
        p->w_po[k] = solid ? phi_width(g->axis[2], g->n_axis[2], k) : 1.0;
        sum_po += p->w_po[k];
    }
    return sum_to * sum_po;
}

/* Divides the n factors by their largest and returns their new sum (>= 1
 * when any factor is > 0), so that 1 / sum cannot overflow. */
static double rescale(double *w, size_t n)
{
    double top = 0.0, sum = 0.0;
    size_t j;
    for (j = 0; j < n; j++) top = fmax(top, w[j]);
    if (!(top > 0.0)) return 0.0;
    for (j = 0; j < n; j++) sum += w[j] /= top;
    return sum;
}

static brdffit_status plan_regular(bf_weight_plan *p, double cap, const brdffit_allocator *a,
                                   brdffit_error *err)
{
    const brdffit_grid *g = p->grid;
    size_t n_po = g->n_axis[2], row;
    double sum;
    p->n_ti_act = axis_active(g->axis[0], g->n_axis[0], cap);
    p->n_to_act = axis_active(g->axis[1], g->n_axis[1], cap);
    if (p->n_ti_act == 0 || p->n_to_act == 0)
        return bf_fail(err, BRDFFIT_E_NO_DATA, "no sample lies within the cap of %g rad", cap);
    p->w_ti = bf_calloc(a, p->n_ti_act + p->n_to_act + n_po, sizeof(double));
    if (p->w_ti == NULL)
        return bf_fail(err, BRDFFIT_E_OUT_OF_MEMORY, "out of memory for the weight plan");
    p->w_to = p->w_ti + p->n_ti_act;
    p->w_po = p->w_to + p->n_to_act;
    sum = regular_factors(p, cap);
    if (p->flags & BRDFFIT_WEIGHT_SOLID_ANGLE) {
        /* Cells so small that the total is subnormal (1 / sum would
         * overflow): scale each axis's factors to a largest of 1 first. */
        if (!(sum >= DBL_MIN)) sum = rescale(p->w_to, p->n_to_act) * rescale(p->w_po, n_po);
        if (!(sum > 0.0))
            return bf_fail(err, BRDFFIT_E_NO_DATA,
                           "the view cells within the cap of %g rad have no solid angle (the "
                           "theta_o or phi_o axis has a single value there, or its values are "
                           "too close together); weigh without the solid angle",
                           cap);
        p->scale = 1.0 / sum;
    }
    row = p->n_to_act * n_po;
    p->chunks_per_ti = (row + BF_CHUNK - 1) / BF_CHUNK;
    p->n_chunks = p->n_ti_act * p->chunks_per_ti;
    p->n_active = p->n_ti_act * row;
    return BRDFFIT_OK;
}

/* The weight of sample (i, j, k) is ((w_ti[i] w_to[j]) w_po[k]) scale; the
 * chunk is walked one theta_o row segment at a time, so the loop over phi_o
 * vectorises and no index is carried per sample. */
static void chunk_regular(const bf_weight_plan *p, size_t index, size_t *first, size_t *count,
                          double *weights)
{
    const brdffit_grid *g = p->grid;
    size_t n_po = g->n_axis[2], row = p->n_to_act * n_po;
    size_t i = index / p->chunks_per_ti, start = index % p->chunks_per_ti * BF_CHUNK;
    size_t n = row - start < BF_CHUNK ? row - start : BF_CHUNK, t = 0, q;
    size_t j = start / n_po, k = start % n_po;
    const double wi = p->w_ti[i], scale = p->scale;
    *first = i * g->n_axis[1] * n_po + start;
    *count = n;
    for (; t < n; j++, k = 0) {
        const double wij = wi * p->w_to[j];
        const double *restrict wpo = p->w_po + k;
        double *restrict out = weights + t;
        size_t len = n - t < n_po - k ? n - t : n_po - k;
        for (q = 0; q < len; q++) out[q] = wij * wpo[q] * scale;
        t += len;
    }
}

/* ---- scattered grids ------------------------------------------------------- */

static brdffit_status plan_scattered(bf_weight_plan *p, double cap, brdffit_error *err)
{
    const brdffit_grid *g = p->grid;
    size_t s;
    p->n_active = axis_active(g->max_theta, g->n_samples, cap);
    if (p->n_active == 0)
        return bf_fail(err, BRDFFIT_E_NO_DATA, "no sample lies within the cap of %g rad", cap);
    p->n_chunks = (p->n_active + BF_CHUNK - 1) / BF_CHUNK;
    if ((p->flags & BRDFFIT_WEIGHT_SOLID_ANGLE) && g->sample_weight != NULL) {
        double sum = 0.0, top = 0.0;
        for (s = 0; s < p->n_active; s++) sum += g->sample_weight[s];
        if (!(sum >= DBL_MIN && sum <= DBL_MAX)) {
            /* Subnormal or overflowing: sum the weights divided by the largest. */
            for (s = 0; s < p->n_active; s++) top = fmax(top, g->sample_weight[s]);
            if (!(top > 0.0))
                return bf_fail(err, BRDFFIT_E_NO_DATA,
                               "every sample weight within the cap of %g rad is 0", cap);
            for (s = 0, sum = 0.0; s < p->n_active; s++) sum += g->sample_weight[s] / top;
            p->divisor = top;
        }
        p->scale = 1.0 / sum;
    } else if (p->flags & BRDFFIT_WEIGHT_SOLID_ANGLE) {
        p->scale = 1.0 / (double)p->n_active;
    }
    return BRDFFIT_OK;
}

static void chunk_scattered(const bf_weight_plan *p, size_t index, size_t *first, size_t *count,
                            double *weights)
{
    const brdffit_grid *g = p->grid;
    size_t start = index * BF_CHUNK, t;
    size_t n = p->n_active - start < BF_CHUNK ? p->n_active - start : BF_CHUNK;
    int solid = (p->flags & BRDFFIT_WEIGHT_SOLID_ANGLE) != 0;
    int cosine = (p->flags & BRDFFIT_WEIGHT_COSINE) != 0;
    *first = start;
    *count = n;
    for (t = 0; t < n; t++)
        weights[t] =
            solid ? (g->sample_weight != NULL ? g->sample_weight[start + t] / p->divisor : 1.0) *
                        p->scale
                  : 1.0;
    if (cosine)
        for (t = 0; t < n; t++) {
            double c = g->geo.lz[start + t];
            weights[t] *= c > 0.0 ? c : 0.0;
        }
}

/* ---- the plan ---------------------------------------------------------------- */

brdffit_status bf_weight_plan_init(bf_weight_plan *p, const brdffit_grid *g, double cap,
                                   unsigned flags, const brdffit_allocator *a, brdffit_error *err)
{
    brdffit_status st;
    memset(p, 0, sizeof *p);
    if (!bf_grid_ok(g))
        return bf_fail(err, g == NULL ? BRDFFIT_E_INVALID_ARGUMENT : BRDFFIT_E_BAD_HANDLE,
                       "grid is NULL, invalid or destroyed");
    if (!cap_ok(cap))
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "cap %g is outside [0, pi/2]", cap);
    if (flags & ~(unsigned)BRDFFIT_WEIGHT_DEFAULT)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "unknown weighting flags 0x%x", flags);
    p->grid = g;
    p->flags = flags;
    p->scale = 1.0;
    p->divisor = 1.0;
    st = g->kind == BRDFFIT_GRID_REGULAR ? plan_regular(p, cap, a, err)
                                         : plan_scattered(p, cap, err);
    if (st != BRDFFIT_OK) bf_weight_plan_free(p, a);
    return st;
}

void bf_weight_plan_free(bf_weight_plan *p, const brdffit_allocator *a)
{
    bf_free(a, p->w_ti);
    memset(p, 0, sizeof *p);
}

/* Where chunk `index` lies, as chunk_regular() and chunk_scattered() say. */
static void chunk_place(const bf_weight_plan *p, size_t index, size_t *first, size_t *count)
{
    const brdffit_grid *g = p->grid;
    size_t start, n_all;
    if (g->kind == BRDFFIT_GRID_REGULAR) {
        size_t n_po = g->n_axis[2], row = p->n_to_act * n_po;
        start = index % p->chunks_per_ti * BF_CHUNK;
        *first = index / p->chunks_per_ti * g->n_axis[1] * n_po + start;
        n_all = row;
    } else {
        start = *first = index * BF_CHUNK;
        n_all = p->n_active;
    }
    *count = n_all - start < BF_CHUNK ? n_all - start : BF_CHUNK;
}

void bf_weight_plan_chunk(const bf_weight_plan *p, size_t index, size_t *first, size_t *count,
                          double *weights)
{
    if (p->cached != NULL) {
        chunk_place(p, index, first, count);
        memcpy(weights, p->cached + index * BF_CHUNK, *count * sizeof *weights);
    } else if (p->grid->kind == BRDFFIT_GRID_REGULAR)
        chunk_regular(p, index, first, count, weights);
    else
        chunk_scattered(p, index, first, count, weights);
}

void bf_weight_plan_fill(const bf_weight_plan *p, double *out)
{
    size_t i, first, count;
    for (i = 0; i < p->n_chunks; i++) {
        double *w = out + i * BF_CHUNK;
        bf_weight_plan_chunk(p, i, &first, &count, w);
        memset(w + count, 0, (BF_CHUNK - count) * sizeof *w);
    }
}

brdffit_status brdffit_grid_weights(const brdffit_grid *grid, double cap, unsigned flags,
                                    double *out, brdffit_error *err)
{
    bf_weight_plan plan;
    double w[BF_CHUNK];
    size_t c, first, count;
    if (grid == NULL || out == NULL)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "grid or out is NULL");
    BF_RETURN_IF_ERROR(bf_weight_plan_init(&plan, grid, cap, flags, &grid->alloc, err));
    memset(out, 0, grid->n_samples * sizeof(double));
    for (c = 0; c < plan.n_chunks; c++) {
        bf_weight_plan_chunk(&plan, c, &first, &count, w);
        memcpy(out + first, w, count * sizeof(double));
    }
    bf_weight_plan_free(&plan, &grid->alloc);
    return BRDFFIT_OK;
}
