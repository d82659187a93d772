/* Stages: problem binding, parameter mapping and LM runs. See stage.h. */
#include "fit/stage.h"

#include <math.h>
#include <stdatomic.h>
#include <string.h>

#include "core/core.h"
#include "optim/sandwich.h"
#include "optim/watch.h"

static brdffit_status stage_alloc(bf_stage *st, size_t n, size_t n_index, size_t n_acc,
                                  size_t n_work)
{
    const brdffit_allocator *a = &st->run->fit->alloc;
    st->vindex = bf_calloc(a, n_index, sizeof(size_t));
    st->decl = bf_calloc(a, n, sizeof(size_t));
    st->logs = bf_calloc(a, n, 2);
    st->lower = bf_calloc(a, 8 * n + n_acc, sizeof(double));
    st->pb.work = bf_calloc(a, n_work, sizeof(double));
    if (bf_pass_terms_size(&st->pb) > 0)
        st->terms = bf_calloc(a, bf_pass_terms_size(&st->pb), sizeof(double));
    if (!st->vindex || !st->decl || !st->logs || !st->lower || !st->pb.work ||
        (bf_pass_terms_size(&st->pb) > 0 && !st->terms))
        return BRDFFIT_E_OUT_OF_MEMORY;
    bf_pass_terms(&st->pb, st->terms);
    st->pb.terms = st->terms;
    st->fixed = st->logs + n;
    st->upper = st->lower + n;
    st->olower = st->lower + 2 * n;
    st->oupper = st->lower + 3 * n;
    st->base = st->lower + 4 * n;
    st->p = st->lower + 5 * n;
    st->x = st->lower + 6 * n;
    st->shown = st->lower + 7 * n;
    st->acc = st->lower + 8 * n;
    return BRDFFIT_OK;
}

static void fill_problem(bf_stage *st, size_t nc, bf_source source, size_t source_channel)
{
    brdffit_fit *fit = st->run->fit;
    memset(&st->pb, 0, sizeof st->pb);
    st->pb.grid = fit->grid;
    st->pb.model = fit->model;
    st->pb.plan = &st->run->plan;
    st->pb.plan_sa = &st->run->plan_sa;
    st->pb.nc = nc;
    st->pb.source = source;
    st->pb.source_channel = source_channel;
    st->pb.clearcoat = fit->clearcoat;
    st->pb.objective = fit->objective;
    st->pb.delta = st->run->delta;
    /* the log and cube-root objectives carry cos(theta_i) inside: their
     * weight is the solid angle alone */
    if (fit->objective == BRDFFIT_OBJECTIVE_LOG || fit->objective == BRDFFIT_OBJECTIVE_CUBE_ROOT)
        st->pb.plan = &st->run->plan_sa;
    bf_layout_init(&st->pb.ly, fit->model, nc);
    st->pb.threads = fit->threads;
    st->pb.pool = &st->run->pool;
    st->pb.sandwich = fit->sandwich;
    bf_pass_prepare(&st->pb);
    /* auto's profile takes colour passes under every objective but the
     * squares, and under the squares for a model affine in its colour
     * (profile_gn.h) */
    st->pb.colour = bf_pass_shape_size(&st->pb) > 0 &&
                    (fit->objective != BRDFFIT_OBJECTIVE_SQUARES || st->pb.ly.offset);
}

/* The fit's start value of declared k in the fit's channel c. */
static double fit_start(const brdffit_fit *fit, size_t k, size_t c)
{
    return fit->start[brdffit_model_vector_index(fit->model, k, c, fit->nc)];
}

/* The start value of declared k in model channel m: the fit's own for the
 * fit's channels, one channel of it or a shared parameter, else the mean
 * over its channels. */
static double start_value(const bf_stage *st, size_t k, size_t m, size_t nc)
{
    const brdffit_fit *fit = st->run->fit;
    int per = (brdffit_model_param(fit->model, k)->flags & BRDFFIT_PARAM_PER_CHANNEL) != 0;
    size_t c;
    double sum = 0.0;
    if (nc == fit->nc) return fit_start(fit, k, m);
    if (st->pb.source == BF_SOURCE_ONE_CHANNEL || !per)
        return fit_start(fit, k, st->pb.source_channel);
    for (c = 0; c < fit->nc; c++) sum += fit_start(fit, k, c);
    return sum / (double)fit->nc;
}

static void fill_mapping(bf_stage *st, size_t nc, int fix_shared)
{
    brdffit_fit *fit = st->run->fit;
    size_t k, m;
    bf_layout_entries(&st->pb.ly, fit->model, st->vindex, st->decl);
    for (k = 0; k < st->pb.ly.n_params; k++) {
        const brdffit_param_info *info = brdffit_model_param(fit->model, k);
        int per = (info->flags & BRDFFIT_PARAM_PER_CHANNEL) != 0;
        for (m = 0; m < nc; m++) {
            size_t e = st->vindex[k * nc + m];
            st->logs[e] = (info->flags & BRDFFIT_PARAM_LOG_SCALE) != 0;
            st->fixed[e] = fit->fixed[k] || (fix_shared && !per);
            st->lower[e] = info->lower;
            st->upper[e] = info->upper;
            st->olower[e] = st->logs[e] ? log(info->lower) : info->lower;
            st->oupper[e] = st->logs[e] ? log(info->upper) : info->upper;
            st->base[e] = start_value(st, k, m, nc);
        }
    }
    st->pb.vindex = st->vindex;
}

brdffit_status bf_stage_init(bf_stage *st, bf_run *run, size_t nc, bf_source source,
                             size_t source_channel, int fix_shared)
{
    size_t n, n_acc;
    memset(st, 0, sizeof *st);
    st->run = run;
    st->scan_point = (size_t)-1;
    fill_problem(st, nc, source, source_channel);
    n = st->pb.ly.n_vec;
    st->n = n;
    /* brdffit_fit_run() keeps larger problems from the pipelines that fit
     * all channels at once; the accumulators below grow with n^2 */
    if (n > BRDFFIT_FIT_MAX_PARAMS)
        return bf_say(run->result->message, BRDFFIT_E_TOO_LARGE,
                      "%zu parameters at once, more than the limit of %d", n,
                      BRDFFIT_FIT_MAX_PARAMS);
    n_acc = bf_pass_acc_size(&st->pb, BF_PASS_NORMAL);
    if (bf_pass_acc_size(&st->pb, BF_PASS_VARPRO) > n_acc)
        n_acc = bf_pass_acc_size(&st->pb, BF_PASS_VARPRO);
    if (bf_pass_acc_size(&st->pb, BF_PASS_METRICS) > n_acc)
        n_acc = bf_pass_acc_size(&st->pb, BF_PASS_METRICS);
    if (stage_alloc(st, n, st->pb.ly.n_params * nc, n_acc, bf_pass_work_size(&st->pb)) !=
        BRDFFIT_OK) {
        bf_stage_free(st);
        return BRDFFIT_E_OUT_OF_MEMORY;
    }
    fill_mapping(st, nc, fix_shared);
    return BRDFFIT_OK;
}

void bf_stage_free(bf_stage *st)
{
    const brdffit_allocator *a;
    if (st->run == NULL) return;
    a = &st->run->fit->alloc;
    brdffit_optimizer_destroy(st->opt);
    bf_free(a, st->vindex);
    bf_free(a, st->decl);
    bf_free(a, st->logs);
    bf_free(a, st->lower);
    bf_free(a, st->pb.work);
    bf_free(a, st->terms);
    bf_free(a, st->shape);
    bf_free(a, st->cov);
    memset(st, 0, sizeof *st);
}

brdffit_status bf_stage_fail(bf_stage *st, brdffit_status status, const char *what)
{
    char *message = st->run->result->message;
    if (st->status != BRDFFIT_OK)
        return bf_say(message, st->status, "%s: %s", what, st->err.message);
    if (status == BRDFFIT_E_OUT_OF_MEMORY)
        return bf_say(message, status, "%s: out of memory", what);
    return bf_say(message, status, "%s: %s", what,
                  st->opt ? brdffit_optimizer_message(st->opt) : brdffit_status_string(status));
}

double bf_stage_natural(const bf_stage *st, size_t e, double x)
{
    double v = st->logs[e] ? exp(x) : x;
    /* exp(log(bound)) may miss the bound by an ulp */
    return v < st->lower[e] ? st->lower[e] : (v > st->upper[e] ? st->upper[e] : v);
}

/* Parameters the fit holds are their start values exactly (exp(log(v))
 * need not give v back). */
static void to_natural(const bf_stage *st, const double *x, double *p)
{
    const unsigned char *held = st->run->fit->fixed;
    size_t e;
    for (e = 0; e < st->n; e++)
        p[e] = held[st->decl[e]] ? st->base[e] : bf_stage_natural(st, e, x[e]);
}

static void to_optimiser(const bf_stage *st, const double *p, double *x)
{
    size_t e;
    for (e = 0; e < st->n; e++) {
        double v = p[e];
        if (v < st->lower[e]) v = st->lower[e];
        if (v > st->upper[e]) v = st->upper[e];
        x[e] = st->logs[e] ? log(v) : v;
    }
}

brdffit_status bf_stage_pass(bf_stage *st, bf_pass_kind kind)
{
    brdffit_status status;
    st->run->result->passes++;
    status = bf_pass(&st->pb, kind, st->p, st->acc, &st->err);
    if (status != BRDFFIT_OK) st->status = status;
    return status;
}

/* The optimizer's normal-equation callback: a fused pass with the chain
 * rule of the log mapping applied. */
static brdffit_status stage_normal(const double *x, double *cost, double *jtj, double *jtr,
                                   void *user)
{
    bf_stage *st = user;
    size_t n = st->n, a, b;
    brdffit_status status;
    to_natural(st, x, st->p);
    status = bf_stage_pass(st, jtj ? BF_PASS_NORMAL : BF_PASS_COST);
    if (status != BRDFFIT_OK) return status;
    *cost = st->acc[0];
    if (jtj == NULL) return BRDFFIT_OK;
    for (a = 0; a < n; a++) {
        double fa = st->logs[a] ? st->p[a] : 1.0;
        jtr[a] = st->acc[1 + a] * fa;
        for (b = 0; b < n; b++) {
            double fb = st->logs[b] ? st->p[b] : 1.0;
            jtj[a * n + b] = st->acc[1 + n + a * n + b] * fa * fb;
        }
    }
    return BRDFFIT_OK;
}

/* The optimizer's iteration callback: cancel requests, then the user's
 * callback with natural parameters. */
static int stage_iteration(const brdffit_iteration *it, void *user)
{
    bf_stage *st = user;
    brdffit_fit *fit = st->run->fit;
    brdffit_iteration copy;
    if (atomic_load(&fit->cancel)) {
        st->run->cancelled = 1;
        return 1;
    }
    if (fit->callback == NULL) return 0;
    copy = *it;
    to_natural(st, it->x, st->shown);
    copy.x = st->shown;
    return fit->callback(&copy, fit->callback_user);
}

static brdffit_status configure(bf_stage *st, size_t rows)
{
    brdffit_fit *fit = st->run->fit;
    brdffit_optimizer *opt = st->opt;
    BF_RETURN_IF_ERROR(brdffit_optimizer_set_normal(opt, rows, stage_normal, st));
    BF_RETURN_IF_ERROR(brdffit_optimizer_set_bounds(opt, st->olower, st->oupper));
    BF_RETURN_IF_ERROR(brdffit_optimizer_set_fixed(opt, st->fixed));
    BF_RETURN_IF_ERROR(brdffit_optimizer_set_damping(opt, &fit->damping));
    BF_RETURN_IF_ERROR(
        brdffit_optimizer_set(opt, BRDFFIT_OPT_MAX_ITERATIONS, (double)fit->max_iterations));
    BF_RETURN_IF_ERROR(brdffit_optimizer_set(opt, BRDFFIT_OPT_MAX_EVALUATIONS,
                                             (double)(5 * fit->max_iterations + 10)));
    /* the fits keep the scaling of the current point: under the
     * optimizer's default running maximum, the curvature of the colours
     * at a start of 0 under the cube-root objective (its floored slope)
     * is remembered and damps them for the rest of the run
     * (test_fit_objectives: 200 iterations, not converged;
     * docs/nist-strd.md) */
    BF_RETURN_IF_ERROR(brdffit_optimizer_set(opt, BRDFFIT_OPT_SCALE_MEMORY, 0.0));
    /* a fit's start is a generic guess (the thesis's), so its first step
     * may change the parameters by at most half their length in the
     * scaling D, and lambda follows Moré's rules: a rejected step costs
     * one evaluation, and once the model is good the steps are
     * Gauss-Newton's. A step promising at most FTOL of the cost is not
     * evaluated; a BRDF fit needs no more than that (its parameters are
     * then far inside their standard errors), and 1e-13 rather than 1e-12
     * because the lookahead stops one step sooner (at 1e-12 the basis and
     * generic paths of cook-torrance-2 then differ by 1.6e-5 in a poorly
     * determined parameter, test_fit_paths). The joint fit of
     * bench_peers: P1 12 -> 5 iterations (14 -> 7 passes), P2 7 -> 7
     * (9 -> 9); docs/nist-strd.md has the measurements. */
    BF_RETURN_IF_ERROR(brdffit_optimizer_set(opt, BRDFFIT_OPT_FTOL, 1e-13));
    BF_RETURN_IF_ERROR(brdffit_optimizer_set(opt, BRDFFIT_OPT_START_RADIUS, 0.5));
    BF_RETURN_IF_ERROR(brdffit_optimizer_set(opt, BRDFFIT_OPT_STEP_CONTROL, 1.0));
    BF_RETURN_IF_ERROR(brdffit_optimizer_set(opt, BRDFFIT_OPT_COST_LOOKAHEAD, 1.0));
    return brdffit_optimizer_set_callback(opt, stage_iteration, st);
}

/* The factor of entry e from the optimiser's space to natural units at
 * natural params: d p / d x, p for a log-scale entry (the delta method). */
static double natural_factor(const bf_stage *st, const double *params, size_t e)
{
    return st->logs[e] ? params[e] : 1.0;
}

/* The sandwich's meat at the run's result (natural params) handed to the
 * optimizer: its (J^T J)^+ in natural units as the pass's bread, one
 * SANDWICH pass over the fit's own rows (weights and objective
 * included), the meat back in the optimiser's space. 1 when it is set,
 * 0 when a cancel stopped the pseudo-inverse; a pass failure is returned
 * in *status. Works in st->cov and st->acc. */
static int prepare_sandwich(bf_stage *st, const double *params, brdffit_status *status)
{
    size_t n = st->n, a, b;
    double *bread = st->cov;
    *status = BRDFFIT_OK;
    if (!bf_optim_bread(st->opt, bread)) return 0;
    for (a = 0; a < n; a++)
        for (b = 0; b < n; b++)
            bread[a * n + b] *= natural_factor(st, params, a) * natural_factor(st, params, b);
    memcpy(st->p, params, n * sizeof *st->p);
    st->pb.bread = bread;
    *status = bf_stage_pass(st, BF_PASS_SANDWICH);
    st->pb.bread = NULL;
    if (*status != BRDFFIT_OK) return 0;
    for (a = 0; a < n; a++)
        for (b = 0; b < n; b++)
            st->acc[a * n + b] *= natural_factor(st, params, a) * natural_factor(st, params, b);
    bf_optim_set_meat(st->opt, st->acc);
    return 1;
}

/* The natural result, standard errors and covariance of the run ending
 * at x: the optimizer's, in natural units by the delta method; all 0 when
 * a cancel stopped them or the fit does not want them. A failure of the
 * sandwich's pass is returned. */
static brdffit_status collect(bf_stage *st, const double *x, double *params, double *se)
{
    size_t n = st->n, a, b;
    brdffit_status status = BRDFFIT_OK;
    int ok = !st->run->fit->no_errors;
    to_natural(st, x, params);
    st->cost = brdffit_optimizer_final_cost(st->opt);
    if (ok && st->run->fit->sandwich) ok = prepare_sandwich(st, params, &status);
    if (status != BRDFFIT_OK) return status;
    ok = ok && bf_optim_std_errors_covariance(st->opt, se, st->cov) == BRDFFIT_OK;
    if (!ok) {
        memset(se, 0, n * sizeof *se);
        memset(st->cov, 0, n * n * sizeof *st->cov);
        return BRDFFIT_OK;
    }
    /* symmetric to the bit (the pseudo-inverse's product of eigenvectors
     * need not be) */
    for (a = 0; a < n; a++) {
        double fa = natural_factor(st, params, a);
        se[a] *= fa;
        st->cov[a * n + a] *= fa * fa;
        for (b = 0; b < a; b++) {
            double v = 0.5 * (st->cov[a * n + b] + st->cov[b * n + a]);
            st->cov[a * n + b] = st->cov[b * n + a] = v * (fa * natural_factor(st, params, b));
        }
    }
    return BRDFFIT_OK;
}

/* Parameters the fit holds stay at their start values whatever point the
 * run starts from (two-stage's second stage starts from the first's
 * result, where a held colour has the channels' mean). */
static void hold_at_start(bf_stage *st)
{
    size_t e;
    for (e = 0; e < st->n; e++)
        if (st->run->fit->fixed[st->decl[e]])
            st->x[e] = st->logs[e] ? log(st->base[e]) : st->base[e];
}

/* The stage's channel has no value to fit (the run checked that some
 * channel has). */
static brdffit_status no_rows(bf_stage *st)
{
    char *message = st->run->result->message;
    if (st->pb.source == BF_SOURCE_ONE_CHANNEL)
        return bf_say(message, BRDFFIT_E_NO_DATA,
                      "channel %zu has no measured value inside the cap", st->pb.source_channel);
    return bf_say(message, BRDFFIT_E_NO_DATA, "no measured value inside the cap");
}

brdffit_status bf_stage_lm(bf_stage *st, const double *start, double *params, double *se)
{
    brdffit_fit *fit = st->run->fit;
    size_t rows;
    brdffit_status status;
    brdffit_optimizer_destroy(st->opt);
    st->opt = NULL;
    st->status = BRDFFIT_OK;
    status = brdffit_optimizer_create(&st->opt, st->n, &fit->alloc, NULL);
    if (status != BRDFFIT_OK) return bf_stage_fail(st, status, "creating the optimizer");
    /* the fit's cancel stops the optimizer inside a step's solve and the
     * standard errors too */
    bf_optim_watch(st->opt, &fit->cancel);
    rows = bf_summary_rows(st->run, &st->pb);
    if (rows == 0) return no_rows(st);
    if (st->cov == NULL) st->cov = bf_calloc(&fit->alloc, st->n * st->n, sizeof *st->cov);
    if (st->cov == NULL) return bf_stage_fail(st, BRDFFIT_E_OUT_OF_MEMORY, "the covariance");
    status = configure(st, rows);
    if (status != BRDFFIT_OK) return bf_stage_fail(st, status, "configuring the optimizer");
    to_optimiser(st, start, st->x);
    hold_at_start(st);
    status = brdffit_optimizer_run(st->opt, st->x);
    if (status != BRDFFIT_OK) return bf_stage_fail(st, status, "Levenberg-Marquardt");
    status = collect(st, st->x, params, se);
    if (status != BRDFFIT_OK) return bf_stage_fail(st, status, "the sandwich covariance");
    if (atomic_load(&fit->cancel)) st->run->cancelled = 1;
    return bf_trace_lm(&st->run->result->trace, &fit->alloc, st->kind, st->label, st->opt,
                       &st->traced);
}
