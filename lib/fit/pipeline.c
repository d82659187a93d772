/* The fit pipelines: auto (variable projection, global scan, LM polish),
 * joint and two-stage, and the final error figures. */
#include <math.h>
#include <stdatomic.h>
#include <string.h>

#include "core/core.h"
#include "fit/fit_internal.h"
#include "fit/lsq.h"
#include "fit/stage.h"
#include "models/model_internal.h"

/* ---- variable projection ------------------------------------------------ */

/* The profile cost at the natural point st->p (shape entries set, linear
 * entries ignored): the best bounded colours for every channel are written
 * into st->p and the cost is returned in *cost. */
static brdffit_status profile(bf_stage *st, double *cost)
{
    const bf_problem *pb = &st->pb;
    size_t K = pb->n_linear, stride = 1 + K + K * K, m, q;
    double lo[BF_LSQ_MAX], hi[BF_LSQ_MAX], c[BF_LSQ_MAX], total = 0.0;
    brdffit_status status;
    for (q = 0; q < K; q++) {
        lo[q] = pb->model->params[pb->linear[q]].lower;
        hi[q] = pb->model->params[pb->linear[q]].upper;
    }
    st->run->passes++;
    status = bf_pass(pb, BF_PASS_VARPRO, st->p, st->acc, &st->err);
    if (status != BRDFFIT_OK) {
        st->status = status;
        return status;
    }
    for (m = 0; m < pb->nc; m++) {
        const double *acc = st->acc + m * stride;
        double f = bf_bounded_lsq(K, acc + 1 + K, acc + 1, lo, hi, c);
        total += fmax(acc[0] + f, 0.0);
        for (q = 0; q < K; q++) st->p[st->vindex[pb->linear[q] * pb->nc + m]] = c[q];
    }
    *cost = total;
    return BRDFFIT_OK;
}

/* ---- the global scan ------------------------------------------------------ */

#define BF_MAX_DIMS 8
#define BF_MAX_CANDIDATES 3

typedef struct scan_dim {
    size_t entry; /* vector entry */
    int log;      /* scanned in log space */
    double lo, hi;/* scan coordinates */
    size_t count; /* grid points */
} scan_dim;

typedef struct candidate {
    double cost;
    double u[BF_MAX_DIMS];
} candidate;

/* Scan coordinates of a shared, free, non-linear parameter's range. */
static void dim_range(const bf_stage *st, size_t e, scan_dim *d)
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

static size_t find_dims(const bf_stage *st, scan_dim *dims)
{
    const brdffit_model *model = st->run->fit->model;
    size_t e, nd = 0;
    for (e = 0; e < st->n && nd < BF_MAX_DIMS; e++) {
        unsigned flags = model->params[st->decl[e]].flags;
        if (st->fixed[e] || (flags & (BRDFFIT_PARAM_LINEAR | BRDFFIT_PARAM_PER_CHANNEL))) continue;
        dim_range(st, e, &dims[nd++]);
    }
    return nd;
}

/* Grid points per dimension: two per decade over a logarithmic range (a
 * profile minimum is broad in log space, and LM polishes it from anywhere
 * in its basin), eleven (one dimension) or six (several) over a linear
 * range, at most ~2000 in all. */
static void choose_counts(scan_dim *dims, size_t nd)
{
    size_t d, total;
    double per_decade = 2.0;
    for (d = 0; d < nd; d++) {
        double decades = (dims[d].hi - dims[d].lo) / log(10.0);
        size_t n = dims[d].log ? (size_t)ceil(decades * per_decade) + 1 : (nd == 1 ? 11 : 6);
        dims[d].count = n < 5 ? 5 : (n > 49 ? 49 : n);
    }
    for (;;) {
        total = 1;
        for (d = 0; d < nd; d++) total *= dims[d].count;
        if (total <= 2000) break;
        for (d = 0; d < nd; d++)
            if (dims[d].count > 5) dims[d].count--;
    }
}

static double grid_coord(const scan_dim *d, size_t i)
{
    return d->lo + (d->hi - d->lo) * (double)i / (double)(d->count - 1);
}

static void set_point(bf_stage *st, const scan_dim *dims, size_t nd, const double *u)
{
    size_t d;
    memcpy(st->p, st->base, st->n * sizeof *st->p);
    for (d = 0; d < nd; d++) st->p[dims[d].entry] = bf_stage_natural(st, dims[d].entry, u[d]);
}

static brdffit_status profile_at(bf_stage *st, const scan_dim *dims, size_t nd, const double *u,
                                 double *cost)
{
    if (atomic_load(&st->run->fit->cancel)) {
        st->run->cancelled = 1;
        *cost = HUGE_VAL; /* not evaluated: never chosen */
        return BRDFFIT_OK;
    }
    set_point(st, dims, nd, u);
    return profile(st, cost);
}

/* Keep the best BF_MAX_CANDIDATES local minima, best first. */
static void keep_candidate(candidate *best, size_t *n_best, double cost, const double *u,
                           size_t nd)
{
    size_t i;
    if (*n_best == BF_MAX_CANDIDATES) {
        if (cost >= best[BF_MAX_CANDIDATES - 1].cost) return;
        i = BF_MAX_CANDIDATES - 1;
    } else {
        i = (*n_best)++;
    }
    while (i > 0 && best[i - 1].cost > cost) {
        best[i] = best[i - 1];
        i--;
    }
    best[i].cost = cost;
    memcpy(best[i].u, u, nd * sizeof *u);
}

/* Whether grid point `flat` is no worse than its neighbours along every axis. */
static int is_local_min(const double *f, const scan_dim *dims, size_t nd, size_t flat)
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

static void flat_to_u(const scan_dim *dims, size_t nd, size_t flat, double *u)
{
    size_t d;
    for (d = 0; d < nd; d++) {
        u[d] = grid_coord(&dims[d], flat % dims[d].count);
        flat /= dims[d].count;
    }
}

static brdffit_status scan_grid(bf_stage *st, const scan_dim *dims, size_t nd, double *f,
                                size_t total)
{
    double u[BF_MAX_DIMS];
    size_t flat;
    for (flat = 0; flat < total && !st->run->cancelled; flat++) {
        flat_to_u(dims, nd, flat, u);
        BF_RETURN_IF_ERROR(profile_at(st, dims, nd, u, &f[flat]));
    }
    return BRDFFIT_OK;
}

/* Golden-section refinement of a one-dimensional minimum bracketed by the
 * neighbouring grid points. */
static brdffit_status refine_1d(bf_stage *st, const scan_dim *dim, candidate *c)
{
    const double g = 0.3819660112501051;
    double step = (dim->hi - dim->lo) / (double)(dim->count - 1);
    double a = fmax(dim->lo, c->u[0] - step), b = fmin(dim->hi, c->u[0] + step);
    double x1 = a + g * (b - a), x2 = b - g * (b - a), f1, f2;
    int it;
    BF_RETURN_IF_ERROR(profile_at(st, dim, 1, &x1, &f1));
    BF_RETURN_IF_ERROR(profile_at(st, dim, 1, &x2, &f2));
    for (it = 0; it < 10 && !st->run->cancelled; it++) {
        if (f1 <= f2) {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = a + g * (b - a);
            BF_RETURN_IF_ERROR(profile_at(st, dim, 1, &x1, &f1));
        } else {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = b - g * (b - a);
            BF_RETURN_IF_ERROR(profile_at(st, dim, 1, &x2, &f2));
        }
    }
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

static brdffit_status find_candidates(bf_stage *st, scan_dim *dims, size_t nd, candidate *best,
                                      size_t *n_best)
{
    size_t total = 1, d, flat;
    double *f, u[BF_MAX_DIMS];
    brdffit_status status;
    choose_counts(dims, nd);
    for (d = 0; d < nd; d++) total *= dims[d].count;
    f = bf_calloc(&st->run->fit->alloc, total, sizeof *f);
    if (f == NULL) return BRDFFIT_E_OUT_OF_MEMORY;
    for (flat = 0; flat < total; flat++) f[flat] = HUGE_VAL; /* points a cancel leaves out */
    status = scan_grid(st, dims, nd, f, total);
    *n_best = 0;
    for (flat = 0; status == BRDFFIT_OK && flat < total; flat++) {
        if (!(f[flat] < HUGE_VAL) || !is_local_min(f, dims, nd, flat)) continue;
        flat_to_u(dims, nd, flat, u);
        keep_candidate(best, n_best, f[flat], u, nd);
    }
    bf_free(&st->run->fit->alloc, f);
    return status;
}

/* Polish one candidate with LM over every free parameter. */
static brdffit_status polish(bf_stage *st, const scan_dim *dims, size_t nd, const candidate *c,
                             double *best_cost, double *best, double *best_se)
{
    double cost;
    BF_RETURN_IF_ERROR(profile_at(st, dims, nd, c->u, &cost));
    memcpy(best + st->n, st->p, st->n * sizeof *best); /* start, kept aside */
    BF_RETURN_IF_ERROR(bf_stage_lm(st, best + st->n));
    if (st->cost < *best_cost) {
        *best_cost = st->cost;
        memcpy(best, st->result, st->n * sizeof *best);
        memcpy(best_se, st->se, st->n * sizeof *best_se);
    }
    return BRDFFIT_OK;
}

/* A cancel during the scan: the best point seen so far, unpolished. */
static brdffit_status cancelled_result(bf_stage *st, const scan_dim *dims, size_t nd,
                                       const candidate *best, size_t n_best, double *params,
                                       double *se)
{
    double cost;
    if (n_best == 0) memcpy(st->p, st->base, st->n * sizeof *st->p);
    else set_point(st, dims, nd, best[0].u);
    BF_RETURN_IF_ERROR(profile(st, &cost));
    memcpy(params, st->p, st->n * sizeof *params);
    memset(se, 0, st->n * sizeof *se);
    return BRDFFIT_OK;
}

static brdffit_status run_auto(bf_stage *st, double *params, double *se)
{
    scan_dim dims[BF_MAX_DIMS];
    candidate best[BF_MAX_CANDIDATES];
    size_t nd = find_dims(st, dims), n_best = 0, i, n_polish;
    double best_cost = HUGE_VAL, *work;
    brdffit_status status;
    if (st->pb.n_linear > BF_LSQ_MAX) return BRDFFIT_E_UNSUPPORTED;
    if (nd == 0) {
        best[0].cost = 0.0;
        n_best = 1;
        status = BRDFFIT_OK;
    } else {
        status = find_candidates(st, dims, nd, best, &n_best);
    }
    if (status != BRDFFIT_OK) return status;
    /* Polish the best minimum and every other one whose scan cost is within
     * a factor 2 of it (the profile cost comes from normal equations and
     * can mislead by rounding when minima are close). Competing minima of
     * one shape parameter are refined first; a single one needs no
     * refinement: LM converges from anywhere in its basin. */
    n_polish = 1;
    while (n_polish < n_best && best[n_polish].cost <= 2.0 * best[0].cost) n_polish++;
    for (i = 0; nd == 1 && n_polish > 1 && i < n_polish && status == BRDFFIT_OK; i++)
        status = refine_1d(st, &dims[0], &best[i]);
    if (status != BRDFFIT_OK) return status;
    if (st->run->cancelled) return cancelled_result(st, dims, nd, best, n_best, params, se);
    work = bf_calloc(&st->run->fit->alloc, 3 * st->n, sizeof *work);
    if (work == NULL) return BRDFFIT_E_OUT_OF_MEMORY;
    for (i = 0; i < n_polish && status == BRDFFIT_OK && !st->run->cancelled; i++)
        status = polish(st, dims, nd, &best[i], &best_cost, work, work + 2 * st->n);
    if (status == BRDFFIT_OK && best_cost < HUGE_VAL) {
        memcpy(params, work, st->n * sizeof *params);
        memcpy(se, work + 2 * st->n, st->n * sizeof *se);
    } else if (status == BRDFFIT_OK) {
        status = BRDFFIT_E_NOT_READY; /* cancelled before any polish */
    }
    bf_free(&st->run->fit->alloc, work);
    return status;
}

/* ---- the pipelines -------------------------------------------------------- */

/* Keep the final LM run's report on the fit. */
static brdffit_status keep_report(brdffit_fit *fit, const bf_stage *st)
{
    size_t n;
    bf_free(&fit->alloc, fit->history);
    fit->history = NULL;
    fit->history_len = 0;
    fit->stop = BRDFFIT_STOP_CANCELLED;
    fit->iterations = 0;
    if (st->opt == NULL) return BRDFFIT_OK; /* cancelled before any LM run */
    n = brdffit_optimizer_history(st->opt, NULL, NULL);
    fit->stop = brdffit_optimizer_stop_reason(st->opt);
    fit->iterations = brdffit_optimizer_iterations(st->opt);
    if (n == 0) return BRDFFIT_OK;
    fit->history = bf_calloc(&fit->alloc, 2 * n, sizeof(double));
    if (fit->history == NULL) return BRDFFIT_E_OUT_OF_MEMORY;
    brdffit_optimizer_history(st->opt, fit->history, fit->history + n);
    fit->history_len = n;
    return BRDFFIT_OK;
}

static brdffit_status pipeline_auto(bf_run *run, double *params, double *se)
{
    bf_stage st;
    brdffit_status status = bf_stage_init(&st, run, run->fit->nc, BF_SOURCE_CHANNELS, 0, 0);
    if (status != BRDFFIT_OK) return status;
    status = run_auto(&st, params, se);
    if (status == BRDFFIT_OK) status = keep_report(run->fit, &st);
    else if (status == BRDFFIT_E_UNSUPPORTED)
        bf_format(run->fit->message, sizeof run->fit->message,
                  "the auto pipeline supports at most %d linear parameters", BF_LSQ_MAX);
    else if (status != BRDFFIT_E_OUT_OF_MEMORY || st.status != BRDFFIT_OK)
        status = bf_stage_fail(&st, status, "auto fit");
    bf_stage_free(&st);
    return status;
}

static brdffit_status pipeline_joint(bf_run *run, double *params, double *se)
{
    bf_stage st;
    brdffit_status status = bf_stage_init(&st, run, run->fit->nc, BF_SOURCE_CHANNELS, 0, 0);
    if (status != BRDFFIT_OK) return status;
    status = bf_stage_lm(&st, st.base);
    if (status == BRDFFIT_OK) {
        memcpy(params, st.result, st.n * sizeof *params);
        memcpy(se, st.se, st.n * sizeof *se);
        status = keep_report(run->fit, &st);
    }
    bf_stage_free(&st);
    return status;
}

/* Stage 2 of the thesis: channel c's per-channel parameters with the shape
 * of stage 1 held. */
static brdffit_status second_stage(bf_run *run, const bf_stage *first, size_t c, double *params,
                                   double *se, int last)
{
    brdffit_fit *fit = run->fit;
    const brdffit_model *model = fit->model;
    bf_stage st;
    size_t k;
    brdffit_status status = bf_stage_init(&st, run, 1, BF_SOURCE_ONE_CHANNEL, c, 1);
    if (status != BRDFFIT_OK) return status;
    status = bf_stage_lm(&st, first->result);
    for (k = 0; status == BRDFFIT_OK && k < model->n_params; k++) {
        size_t to = brdffit_model_vector_index(model, k, c, fit->nc), from = st.vindex[k];
        int per = (model->params[k].flags & BRDFFIT_PARAM_PER_CHANNEL) != 0;
        params[to] = per ? st.result[from] : first->result[from];
        se[to] = per ? st.se[from] : first->se[from];
    }
    if (status == BRDFFIT_OK && last) status = keep_report(fit, &st);
    bf_stage_free(&st);
    return status;
}

static brdffit_status pipeline_two_stage(bf_run *run, double *params, double *se)
{
    bf_stage first;
    size_t c;
    brdffit_status status = bf_stage_init(&first, run, 1, BF_SOURCE_MEAN, 0, 0);
    if (status != BRDFFIT_OK) return status;
    status = bf_stage_lm(&first, first.base);
    for (c = 0; status == BRDFFIT_OK && c < run->fit->nc && !run->cancelled; c++)
        status = second_stage(run, &first, c, params, se, c + 1 == run->fit->nc);
    if (status == BRDFFIT_OK && run->cancelled && c < run->fit->nc) {
        /* cancelled between stages: report stage 1 for the channels not reached */
        for (; c < run->fit->nc; c++) {
            size_t k;
            for (k = 0; k < run->fit->model->n_params; k++) {
                size_t to = brdffit_model_vector_index(run->fit->model, k, c, run->fit->nc);
                params[to] = first.result[first.vindex[k]];
                se[to] = 0.0;
            }
        }
        status = keep_report(run->fit, &first);
    }
    bf_stage_free(&first);
    return status;
}

/* Error figures of the final parameters (BF_PASS_METRICS). */
static brdffit_status final_metrics(bf_run *run, const double *params)
{
    brdffit_fit *fit = run->fit;
    bf_stage st;
    brdffit_status status = bf_stage_init(&st, run, fit->nc, BF_SOURCE_CHANNELS, 0, 0);
    if (status != BRDFFIT_OK) return status;
    status = bf_pass(&st.pb, BF_PASS_METRICS, params, st.acc, &st.err);
    run->passes++;
    if (status == BRDFFIT_OK) memcpy(fit->metrics, st.acc, 4 * fit->nc * sizeof(double));
    else status = bf_stage_fail(&st, status, "error figures");
    bf_stage_free(&st);
    return status;
}

static brdffit_status make_plans(bf_run *run)
{
    brdffit_fit *fit = run->fit;
    brdffit_error err;
    brdffit_status status =
        bf_weight_plan_init(&run->plan, fit->grid, fit->cap, fit->weighting, &fit->alloc, &err);
    if (status == BRDFFIT_OK) {
        status = bf_weight_plan_init(&run->plan_sa, fit->grid, fit->cap,
                                     BRDFFIT_WEIGHT_SOLID_ANGLE, &fit->alloc, &err);
        if (status != BRDFFIT_OK) bf_weight_plan_free(&run->plan, &fit->alloc);
    }
    if (status != BRDFFIT_OK)
        bf_format(fit->message, sizeof fit->message, "%s",
                  status == BRDFFIT_E_OUT_OF_MEMORY ? "out of memory" : err.message);
    return status;
}

/* The fit squares the measured values: keep them where their squares
 * neither underflow nor overflow. */
#define BF_FIT_VALUE_MIN 1e-100
#define BF_FIT_VALUE_MAX 1e100

/* Largest measured value inside the cap (missing values are stored as 0). */
static double largest_value(const bf_run *run)
{
    const brdffit_grid *g = run->fit->grid;
    double w[BF_CHUNK], top = 0.0;
    size_t ci, first, n, c, s;
    for (ci = 0; ci < run->plan.n_chunks; ci++) {
        bf_weight_plan_chunk(&run->plan, ci, &first, &n, w);
        for (c = 0; c < g->n_channels; c++)
            for (s = first; s < first + n; s++) top = fmax(top, g->values[c * g->n_samples + s]);
    }
    return top;
}

static brdffit_status check_scale(bf_run *run)
{
    double top = largest_value(run);
    if (top == 0.0 || (top >= BF_FIT_VALUE_MIN && top <= BF_FIT_VALUE_MAX)) return BRDFFIT_OK;
    bf_format(run->fit->message, sizeof run->fit->message,
              "the largest measured value inside the cap, %g, lies outside [%g, %g]; "
              "rescale the data (the colours scale with it)",
              top, BF_FIT_VALUE_MIN, BF_FIT_VALUE_MAX);
    return BRDFFIT_E_RANGE;
}

/* Helper threads for the run: one per pass block beyond the caller's. */
static size_t helper_count(const bf_run *run)
{
    size_t blocks = run->fit->threads < BF_MAX_THREADS ? run->fit->threads : BF_MAX_THREADS;
    if (blocks > run->plan.n_chunks) blocks = run->plan.n_chunks;
    return blocks > 1 ? blocks - 1 : 0;
}

brdffit_status bf_fit_execute(brdffit_fit *fit)
{
    bf_run run;
    brdffit_status status;
    memset(&run, 0, sizeof run);
    run.fit = fit;
    BF_RETURN_IF_ERROR(make_plans(&run));
    status = check_scale(&run);
    if (status != BRDFFIT_OK) {
        bf_weight_plan_free(&run.plan, &fit->alloc);
        bf_weight_plan_free(&run.plan_sa, &fit->alloc);
        return status;
    }
    bf_pool_start(&run.pool, helper_count(&run));
    switch (fit->pipeline) {
    case BRDFFIT_PIPELINE_JOINT: status = pipeline_joint(&run, fit->params, fit->std_errors); break;
    case BRDFFIT_PIPELINE_TWO_STAGE:
        status = pipeline_two_stage(&run, fit->params, fit->std_errors);
        break;
    default: status = pipeline_auto(&run, fit->params, fit->std_errors); break;
    }
    if (status == BRDFFIT_OK) status = final_metrics(&run, fit->params);
    bf_pool_stop(&run.pool);
    if (status == BRDFFIT_OK && run.cancelled) fit->stop = BRDFFIT_STOP_CANCELLED;
    fit->passes = run.passes;
    bf_weight_plan_free(&run.plan, &fit->alloc);
    bf_weight_plan_free(&run.plan_sa, &fit->alloc);
    if (status == BRDFFIT_E_OUT_OF_MEMORY)
        bf_format(fit->message, sizeof fit->message, "out of memory");
    return status;
}
