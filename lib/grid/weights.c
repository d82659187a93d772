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

/* The factors of the three axes: light cosine, view cell's polar extent
 * (cells ending at `cap` after index `last`) and azimuthal width. */
static double ti_factor(const brdffit_grid *g, size_t i, int cosine)
{
    return cosine ? fmax(bf_cos_polar(g->axis[0][i]), 0.0) : 1.0;
}

static double to_factor(const brdffit_grid *g, size_t j, size_t last, double cap, int solid)
{
    double lo, hi;
    if (!solid) return 1.0;
    theta_cell(g->axis[1], g->n_axis[1], j, last, cap, &lo, &hi);
    return fmax(cos(lo) - cos(hi), 0.0);
}

static double po_factor(const brdffit_grid *g, size_t k, int solid)
{
    return solid ? phi_width(g->axis[2], g->n_axis[2], k) : 1.0;
}

/* Per-axis factors; returns the sum of the active cells' solid angles. */
static double regular_factors(bf_weight_plan *p, double cap)
{
    const brdffit_grid *g = p->grid;
    size_t i, j, k;
    double sum_to = 0.0, sum_po = 0.0;
    int solid = (p->flags & BRDFFIT_WEIGHT_SOLID_ANGLE) != 0;
    int cosine = (p->flags & BRDFFIT_WEIGHT_COSINE) != 0;
    for (i = 0; i < p->n_ti_act; i++) p->w_ti[i] = ti_factor(g, i, cosine);
    for (j = 0; j < p->n_to_act; j++) {
        p->w_to[j] = to_factor(g, j, p->n_to_act - 1, cap, solid);
        sum_to += p->w_to[j];
    }
    for (k = 0; k < g->n_axis[2]; k++) {
        p->w_po[k] = po_factor(g, k, solid);
        sum_po += p->w_po[k];
    }
    return sum_to * sum_po;
}

/* Divides the n factors by their largest (into *top) and returns their
 * new sum (>= 1 when any factor is > 0), so that 1 / sum cannot overflow. */
static double rescale(double *w, size_t n, double *top)
{
    double sum = 0.0;
    size_t j;
    *top = 0.0;
    for (j = 0; j < n; j++) *top = fmax(*top, w[j]);
    if (!(*top > 0.0)) return 0.0;
    for (j = 0; j < n; j++) sum += w[j] /= *top;
    return sum;
}

/* The largest of the n values of f(g, index), at least 0. */
static double largest_of(const brdffit_grid *g, size_t n,
                         double (*f)(const brdffit_grid *, size_t, int), int flag)
{
    double top = 0.0;
    size_t k;
    for (k = 0; k < n; k++) top = fmax(top, f(g, k, flag));
    return top;
}

static double to_factor_uncapped(const brdffit_grid *g, size_t j, int solid)
{
    return to_factor(g, j, g->n_axis[1] - 1, BF_HALF_PI, solid);
}

/* Regular grids: the weight of sample (i, j, k) before the cap's
 * normalisation is (w_ti w_to) w_po, with the view cells of the whole
 * axes; the base weight is the product of the three factors each divided
 * by the largest of its axis (into m[3]: the products of such tiny or
 * huge factors would leave the double range). */
static void regular_maxima(const brdffit_grid *g, int b, double m[3])
{
    m[0] = largest_of(g, g->n_axis[0], ti_factor, b == BF_BASE_DEFAULT);
    m[1] = largest_of(g, g->n_axis[1], to_factor_uncapped, 1);
    m[2] = largest_of(g, g->n_axis[2], po_factor, 1);
}

static void regular_base(brdffit_grid *g, int b)
{
    const size_t n_ti = g->n_axis[0], n_to = g->n_axis[1], n_po = g->n_axis[2];
    const int cosine = b == BF_BASE_DEFAULT;
    float *out = g->geo.w_base[b];
    double m[3];
    size_t i, j, k;
    regular_maxima(g, b, m);
    for (i = 0; i < n_ti; i++) {
        const double fi = m[0] > 0.0 ? ti_factor(g, i, cosine) / m[0] : 0.0;
        for (j = 0; j < n_to; j++) {
            const double fij = fi * (m[1] > 0.0 ? to_factor_uncapped(g, j, 1) / m[1] : 0.0);
            for (k = 0; k < n_po; k++)
                *out++ = (float)(fij * (m[2] > 0.0 ? po_factor(g, k, 1) / m[2] : 0.0));
        }
    }
    g->geo.w_norm[b] = 0.0; /* the plan takes the axes' largest factors */
}

/* Scattered grids: the weight before normalisation is the sample's given
 * weight (1 without) times cos(theta_i) for the default weighting; the
 * base weight is it divided by its largest, w_norm. */
static double scattered_raw(const brdffit_grid *g, size_t s, int b)
{
    const double sw = g->sample_weight != NULL ? g->sample_weight[s] : 1.0;
    const double c = g->geo.lz[s];
    return b == BF_BASE_DEFAULT ? sw * (c > 0.0 ? c : 0.0) : sw;
}

static void scattered_base(brdffit_grid *g, int b)
{
    double top = 0.0;
    size_t s, n = g->n_samples;
    for (s = 0; s < n; s++) top = fmax(top, scattered_raw(g, s, b));
    for (s = 0; s < n; s++)
        g->geo.w_base[b][s] = top > 0.0 ? (float)(scattered_raw(g, s, b) / top) : 0.0f;
    g->geo.w_norm[b] = top;
}

void bf_grid_base_weights(brdffit_grid *g)
{
    int b;
    for (b = 0; b < 2; b++) {
        if (g->kind == BRDFFIT_GRID_REGULAR)
            regular_base(g, b);
        else
            scattered_base(g, b);
    }
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
        if (!(sum >= DBL_MIN))
            sum = rescale(p->w_to, p->n_to_act, &p->top_to) * rescale(p->w_po, n_po, &p->top_po);
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

/* The base form of a regular plan: w = base * factor with factor
 * scale m_ti m_to m_po / (top_to top_po) (the capped view factors equal
 * the uncapped ones but in the last active row, whose own factor
 * follows), the quotients formed first. */
static void regular_base_form(bf_weight_plan *p, int b, double cap)
{
    const brdffit_grid *g = p->grid;
    const size_t last = p->n_to_act - 1;
    const double capped = to_factor(g, last, last, cap, 1), whole = to_factor_uncapped(g, last, 1);
    double m[3];
    regular_maxima(g, b, m);
    p->base_factor = p->scale * (m[1] / p->top_to) * (m[2] / p->top_po) * m[0];
    p->base_last = whole > 0.0 ? p->base_factor * (capped / whole) : p->base_factor;
    p->base_split = last * g->n_axis[2];
}

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

/* The plan's weights as the grid's base weights times factors, for the
 * weightings with the solid angle; none (base NULL) for the others or
 * when a factor is not a finite positive number (axes or sample weights
 * spanning more than the double range). */
static void base_form(bf_weight_plan *p, double cap)
{
    const brdffit_grid *g = p->grid;
    int b = p->flags == BRDFFIT_WEIGHT_DEFAULT       ? BF_BASE_DEFAULT
            : p->flags == BRDFFIT_WEIGHT_SOLID_ANGLE ? BF_BASE_SOLID_ANGLE
                                                     : -1;
    p->base = NULL;
    if (b < 0) return;
    if (g->kind == BRDFFIT_GRID_REGULAR) {
        regular_base_form(p, b, cap);
    } else {
        p->base_factor = g->geo.w_norm[b] / p->divisor * p->scale;
        p->base_last = p->base_factor;
        p->base_split = 0;
    }
    if (isfinite(p->base_factor) && p->base_factor > 0.0 && isfinite(p->base_last) &&
        p->base_last >= 0.0)
        p->base = g->geo.w_base[b];
}

size_t bf_weight_plan_base(const bf_weight_plan *p, size_t index, bf_weight_piece piece[2])
{
    const brdffit_grid *g = p->grid;
    size_t n_po, i, start, count, before;
    if (p->base == NULL) return 0;
    if (g->kind != BRDFFIT_GRID_REGULAR) {
        start = index * BF_CHUNK;
        piece[0].first = start;
        piece[0].count = p->n_active - start < BF_CHUNK ? p->n_active - start : BF_CHUNK;
        piece[0].factor = p->base_factor;
        return 1;
    }
    /* chunk_regular()'s samples: those before the last active view row of
     * the theta_i block, then those in it */
    n_po = g->n_axis[2];
    i = index / p->chunks_per_ti;
    start = index % p->chunks_per_ti * BF_CHUNK;
    count = p->n_to_act * n_po - start < BF_CHUNK ? p->n_to_act * n_po - start : BF_CHUNK;
    before = start >= p->base_split ? 0 : p->base_split - start;
    if (before > count) before = count;
    piece[0].first = i * g->n_axis[1] * n_po + start;
    if (p->base_last == p->base_factor || before == 0 || before == count) {
        piece[0].count = count;
        piece[0].factor = before > 0 ? p->base_factor : p->base_last;
        return 1;
    }
    piece[0].count = before;
    piece[0].factor = p->base_factor;
    piece[1].first = piece[0].first + before;
    piece[1].count = count - before;
    piece[1].factor = p->base_last;
    return 2;
}

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
    p->top_to = p->top_po = 1.0;
    st = g->kind == BRDFFIT_GRID_REGULAR ? plan_regular(p, cap, a, err)
                                         : plan_scattered(p, cap, err);
    if (st != BRDFFIT_OK) {
        bf_weight_plan_free(p, a);
        return st;
    }
    base_form(p, cap);
    return BRDFFIT_OK;
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
