/* The global scan of the auto pipeline: see scan.h. */
#include "fit/scan.h"

#include <math.h>
#include <stdatomic.h>
#include <string.h>

#include "core/core.h"
#include "fit/many_scan.h"
#include "fit/plausible.h"
#include "fit/profile_gn.h"
#include "fit/varpro.h"

/* Scan coordinates of a shared, free, non-linear parameter's range. */
static void dim_range(const bf_stage *st, size_t e, bf_scan_dim *d)
{
    double lo = st->lower[e], hi = st->upper[e], s = st->base[e];
    d->entry = e;
    d->log = st->logs[e];
    if (d->log) {
        d->lo = log(lo);
        d->hi = isfinite(hi) ? log(hi) : log(lo) + log(1e12);
        return;
    }
    if (!isfinite(lo)) lo = s - 10.0 * fmax(fabs(s), 1.0);
    if (!isfinite(hi)) hi = s + 10.0 * fmax(fabs(s), 1.0);
    d->lo = lo;
    d->hi = hi;
}

static size_t find_dims(const bf_stage *st, bf_scan_dim *dims)
{
    const brdffit_model *model = st->pb.model;
    size_t e, nd = 0;
    for (e = 0; e < st->n && nd < BF_MAX_DIMS; e++) {
        unsigned flags = brdffit_model_param(model, st->decl[e])->flags;
        if (st->fixed[e] || (flags & (BRDFFIT_PARAM_LINEAR | BRDFFIT_PARAM_PER_CHANNEL))) continue;
        dim_range(st, e, &dims[nd++]);
    }
    return nd;
}

/* Grid points per dimension: two per decade over a logarithmic range (a
 * profile minimum is broad in log space, and LM polishes it from anywhere
 * in its basin), eleven (one dimension) or six (several) over a linear
 * range, at most ~2000 in all: counts fall one at a time, but none below
 * floor(2000^(1/nd)) (at least 2), so that many dimensions end too. */
static void choose_counts(bf_scan_dim *dims, size_t nd)
{
    size_t d, total, least = (size_t)floor(pow(2000.0, 1.0 / (double)nd) + 1e-9);
    double per_decade = 2.0;
    int fell = 1;
    if (least > 5) least = 5;
    if (least < 2) least = 2;
    for (d = 0; d < nd; d++) {
        double decades = (dims[d].hi - dims[d].lo) / log(10.0);
        size_t n = dims[d].log ? (size_t)ceil(decades * per_decade) + 1 : (nd == 1 ? 11 : 6);
        dims[d].count = n < least ? least : (n > 49 ? 49 : n);
    }
    while (fell) {
        total = 1;
        for (d = 0; d < nd; d++) total *= dims[d].count;
        if (total <= 2000) break;
        fell = 0;
        for (d = 0; d < nd; d++)
            if (dims[d].count > least) {
                dims[d].count--;
                fell = 1;
            }
    }
}

double bf_scan_coord(const bf_scan_dim *d, size_t i)
{
    return d->lo + (d->hi - d->lo) * (double)i / (double)(d->count - 1);
}

void bf_scan_set_point(bf_stage *st, const bf_scan *sc, const double *u)
{
    size_t d;
    memcpy(st->p, st->base, st->n * sizeof *st->p);
    for (d = 0; d < sc->nd; d++)
        st->p[sc->dims[d].entry] = bf_stage_natural(st, sc->dims[d].entry, u[d]);
}

/* bf_scan_profile_at() with the objective's colour steps started from
 * `warm` when that is better (bf_profile_point()); warm may be NULL.
 * `flat` is the grid point u is (its number in the flat order), or
 * BF_SCAN_OFF_GRID: under the squares objective a grid point's sums come
 * from a batch's shared scan basis when the fit has one (many_scan.h). */
static brdffit_status profile_point(bf_stage *st, const bf_scan *sc, const double *u, size_t flat,
                                    const double *warm, double *cost)
{
    brdffit_status status;
    if (atomic_load(&st->run->fit->cancel)) {
        st->run->cancelled = 1;
        *cost = HUGE_VAL; /* not evaluated: never chosen */
        return BRDFFIT_OK;
    }
    bf_scan_set_point(st, sc, u);
    if (flat == BF_SCAN_OFF_GRID || !bf_batch_scan_bounds(st, flat))
        BF_RETURN_IF_ERROR(bf_plausible_bounds(st, 0)); /* the cheap colour bounds */
    st->scan_point = flat; /* the colour steps may read the point's basis (many_scan.h) */
    if (flat != BF_SCAN_OFF_GRID && st->pb.objective == BRDFFIT_OBJECTIVE_SQUARES &&
        !st->pb.colour && bf_batch_scan_sums(st, flat)) {
        bf_varpro_solve(st, cost); /* the squares' profile, from the batch's sums */
        status = BRDFFIT_OK;
    } else {
        status = bf_profile_point(st, warm, 0, cost);
    }
    st->scan_point = BF_SCAN_OFF_GRID;
    /* a point the model cannot evaluate (a domain error, NaN) is left out,
     * as the optimizer rejects such a trial step; st->status keeps why; it
     * is not recorded in the trace, which holds the costs evaluated */
    if (status == BRDFFIT_E_MODEL_FAILED || status == BRDFFIT_E_NONFINITE) {
        *cost = HUGE_VAL;
        return BRDFFIT_OK;
    }
    BF_RETURN_IF_ERROR(status);
    return bf_trace_scan(&st->run->result->trace, &st->run->fit->alloc, *cost);
}

brdffit_status bf_scan_profile_at(bf_stage *st, const bf_scan *sc, const double *u, double *cost)
{
    return profile_point(st, sc, u, BF_SCAN_OFF_GRID, NULL, cost);
}

/* Keep the best BF_MAX_CANDIDATES local minima, best first. */
static void keep_candidate(bf_scan *sc, double cost, const double *u)
{
    bf_candidate *best = sc->best;
    size_t i;
    if (sc->n_best == BF_MAX_CANDIDATES) {
        if (cost >= best[BF_MAX_CANDIDATES - 1].cost) return;
        i = BF_MAX_CANDIDATES - 1;
    } else {
        i = sc->n_best++;
    }
    while (i > 0 && best[i - 1].cost > cost) {
        best[i] = best[i - 1];
        i--;
    }
    best[i].cost = cost;
    memcpy(best[i].u, u, sc->nd * sizeof *u);
}

/* Whether grid point `flat` is no worse than its neighbours along every axis. */
static int is_local_min(const double *f, const bf_scan_dim *dims, size_t nd, size_t flat)
{
    size_t d, stride = 1, rest = flat;
    for (d = 0; d < nd; d++) {
        size_t i = rest % dims[d].count;
        if (i > 0 && f[flat - stride] < f[flat]) return 0;
        if (i + 1 < dims[d].count && f[flat + stride] < f[flat]) return 0;
        rest /= dims[d].count;
        stride *= dims[d].count;
    }
    return 1;
}

static void flat_to_u(const bf_scan_dim *dims, size_t nd, size_t flat, double *u)
{
    size_t d;
    for (d = 0; d < nd; d++) {
        u[d] = bf_scan_coord(&dims[d], flat % dims[d].count);
        flat /= dims[d].count;
    }
}

/* The grid in its flat order; under a non-squares objective each point's
 * colour steps may start from the previous point's colours (`warm`, n
 * doubles), a neighbour along the first dimension. */
static brdffit_status scan_grid(bf_stage *st, const bf_scan *sc, double *f, size_t total,
                                double *warm)
{
    double u[BF_MAX_DIMS];
    size_t flat;
    int have = 0;
    for (flat = 0; flat < total && !st->run->cancelled; flat++) {
        flat_to_u(sc->dims, sc->nd, flat, u);
        BF_RETURN_IF_ERROR(profile_point(st, sc, u, flat, have ? warm : NULL, &f[flat]));
        have = f[flat] < HUGE_VAL;
        if (have) memcpy(warm, st->p, st->n * sizeof *warm);
    }
    return BRDFFIT_OK;
}

/* The profile cost at every grid point, and the best local minima. */
static brdffit_status find_candidates(bf_stage *st, bf_scan *sc)
{
    const brdffit_allocator *a = &st->run->fit->alloc;
    size_t total = bf_scan_points(sc), flat;
    double *f, u[BF_MAX_DIMS];
    brdffit_status status;
    f = bf_calloc(a, total + st->n, sizeof *f); /* the costs, then the warm start */
    if (f == NULL) return BRDFFIT_E_OUT_OF_MEMORY;
    for (flat = 0; flat < total; flat++) f[flat] = HUGE_VAL; /* points a cancel leaves out */
    status = scan_grid(st, sc, f, total, f + total);
    sc->n_best = 0;
    for (flat = 0; status == BRDFFIT_OK && flat < total; flat++) {
        if (!(f[flat] < HUGE_VAL) || !is_local_min(f, sc->dims, sc->nd, flat)) continue;
        flat_to_u(sc->dims, sc->nd, flat, u);
        keep_candidate(sc, f[flat], u);
    }
    bf_free(a, f);
    if (status != BRDFFIT_OK) return status;
    /* every point failed: the last failure is the fit's */
    if (sc->n_best == 0 && !st->run->cancelled && st->status != BRDFFIT_OK) return st->status;
    st->status = BRDFFIT_OK;
    return BRDFFIT_OK;
}

size_t bf_scan_layout(const bf_stage *st, bf_scan *sc)
{
    sc->nd = find_dims(st, sc->dims);
    sc->n_best = 0;
    if (sc->nd == 0) return 0;
    choose_counts(sc->dims, sc->nd);
    return bf_scan_points(sc);
}

size_t bf_scan_points(const bf_scan *sc)
{
    size_t total = 1, d;
    for (d = 0; d < sc->nd; d++) total *= sc->dims[d].count;
    return sc->nd > 0 ? total : 0;
}

void bf_scan_grid_point(const bf_scan *sc, size_t flat, double *u)
{
    flat_to_u(sc->dims, sc->nd, flat, u);
}

brdffit_status bf_scan_run(bf_stage *st, bf_scan *sc)
{
    if (bf_scan_layout(st, sc) > 0) return find_candidates(st, sc);
    sc->best[0].cost = 0.0;
    sc->n_best = 1;
    return BRDFFIT_OK;
}

/* One golden-section step on [a, b] with interior points x1 < x2: the
 * bracket shrinks towards the lower of f1, f2 and one new point is
 * evaluated. */
static brdffit_status golden_step(bf_stage *st, const bf_scan *sc, double *a, double *b,
                                  double *x1, double *x2, double *f1, double *f2)
{
    const double g = 0.3819660112501051;
    if (*f1 <= *f2) {
        *b = *x2;
        *x2 = *x1;
        *f2 = *f1;
        *x1 = *a + g * (*b - *a);
        return bf_scan_profile_at(st, sc, x1, f1);
    }
    *a = *x1;
    *x1 = *x2;
    *f1 = *f2;
    *x2 = *b - g * (*b - *a);
    return bf_scan_profile_at(st, sc, x2, f2);
}

/* Golden-section refinement of a one-dimensional minimum bracketed by the
 * neighbouring grid points. */
static brdffit_status refine_1d(bf_stage *st, const bf_scan *sc, bf_candidate *c)
{
    const double g = 0.3819660112501051;
    const bf_scan_dim *dim = &sc->dims[0];
    double step = (dim->hi - dim->lo) / (double)(dim->count - 1);
    double a = fmax(dim->lo, c->u[0] - step), b = fmin(dim->hi, c->u[0] + step);
    double x1 = a + g * (b - a), x2 = b - g * (b - a), f1, f2;
    int it;
    BF_RETURN_IF_ERROR(bf_scan_profile_at(st, sc, &x1, &f1));
    BF_RETURN_IF_ERROR(bf_scan_profile_at(st, sc, &x2, &f2));
    for (it = 0; it < 10 && !st->run->cancelled; it++)
        BF_RETURN_IF_ERROR(golden_step(st, sc, &a, &b, &x1, &x2, &f1, &f2));
    if (f1 < c->cost) {
        c->cost = f1;
        c->u[0] = x1;
    }
    if (f2 < c->cost) {
        c->cost = f2;
        c->u[0] = x2;
    }
    return BRDFFIT_OK;
}

brdffit_status bf_scan_refine(bf_stage *st, bf_scan *sc, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++) BF_RETURN_IF_ERROR(refine_1d(st, sc, &sc->best[i]));
    return BRDFFIT_OK;
}
