/* The optimizer handle: creation, problem and settings, results. The run
 * loop is in lm.c. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "core/core.h"
#include "optim/optim_internal.h"

/* Limits are doubles in the setter; larger values are not integers any
 * more in double precision. */
#define BF_MAX_LIMIT 9007199254740992.0 /* 2^53 */

enum { BF_WORK_VECTORS = 12, BF_WORK_MATRICES = 4 };

static const bf_optim_settings default_settings = {1e-13, 1e-10, 1e-15, 1e-12, 5000, 12000, 1};

brdffit_status bf_optim_fail(brdffit_optimizer *opt, brdffit_status status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    bf_vfail(&opt->err, status, fmt, ap);
    va_end(ap);
    return status;
}

static brdffit_status ok(brdffit_optimizer *opt)
{
    opt->err.status = BRDFFIT_OK;
    opt->err.message[0] = '\0';
    return BRDFFIT_OK;
}

static brdffit_status check_handle(const brdffit_optimizer *opt)
{
    if (opt == NULL) return BRDFFIT_E_INVALID_ARGUMENT;
    if (opt->magic != BF_MAGIC_OPTIMIZER) return BRDFFIT_E_BAD_HANDLE;
    return BRDFFIT_OK;
}

/* For calls that change the optimizer: not from inside its own run. */
static brdffit_status check_mutable(brdffit_optimizer *opt, const char *what)
{
    BF_RETURN_IF_ERROR(check_handle(opt));
    if (opt->running)
        return bf_optim_fail(opt, BRDFFIT_E_INVALID_ARGUMENT,
                             "%s: the optimizer cannot be changed while it runs", what);
    return BRDFFIT_OK;
}

static void reset_result(bf_optim_result *res)
{
    memset(res, 0, sizeof *res);
    res->stop = BRDFFIT_STOP_NONE;
    res->initial_cost = NAN;
    res->final_cost = NAN;
}

/* --- creation -------------------------------------------------------------- */

static int alloc_work(brdffit_optimizer *opt)
{
    size_t p = opt->n_params, pp = p * p, small, bytes, i;
    bf_optim_work *w = &opt->w;
    double *d;
    double **vectors[BF_WORK_VECTORS] = {&w->x, &w->trial, &w->g, &w->g_new, &w->step,  &w->delta,
                                         &w->d, &w->scale, &w->w, &w->tmp,   &w->lower, &w->upper};
    double **matrices[BF_WORK_MATRICES] = {&w->jtj, &w->jtj_new, &w->m, &w->v};
    /* matrices first, then vectors, indices and flags; p <= 4096: no
     * overflow. The matrices are always written before they are read and
     * are not touched here, so a large optimizer costs no memory it does
     * not use. */
    small = BF_WORK_VECTORS * p * sizeof(double) + p * sizeof(size_t) + 3 * p;
    bytes = BF_WORK_MATRICES * pp * sizeof(double) + small;
    opt->block = bf_malloc(&opt->alloc, bytes);
    if (opt->block == NULL) return 0;
    d = opt->block;
    for (i = 0; i < BF_WORK_MATRICES; i++, d += pp) *matrices[i] = d;
    memset(d, 0, small);
    for (i = 0; i < BF_WORK_VECTORS; i++, d += p) *vectors[i] = d;
    w->free_idx = (size_t *)(void *)d;
    w->fixed = (unsigned char *)(w->free_idx + p);
    w->held = w->fixed + p;
    w->analysed = w->held + p;
    for (i = 0; i < p; i++) {
        w->lower[i] = -HUGE_VAL;
        w->upper[i] = HUGE_VAL;
    }
    return 1;
}

/* Copy a policy (already checked) and give it fresh state. */
static brdffit_status install_policy(brdffit_optimizer *opt, const brdffit_damping *policy)
{
    void *state = NULL;
    if (policy->state_size > 0) {
        state = bf_calloc(&opt->alloc, 1, policy->state_size);
        if (state == NULL)
            return bf_optim_fail(opt, BRDFFIT_E_OUT_OF_MEMORY,
                                 "cannot allocate %zu bytes of state for damping policy '%s'",
                                 policy->state_size, policy->name ? policy->name : "(unnamed)");
    }
    bf_free(&opt->alloc, opt->policy_state);
    opt->policy_state = state;
    memcpy(&opt->policy, policy, sizeof opt->policy);
    opt->policy.struct_size = sizeof opt->policy;
    return BRDFFIT_OK;
}

brdffit_status brdffit_optimizer_create(brdffit_optimizer **out, size_t n_params,
                                        const brdffit_allocator *alloc, brdffit_error *err)
{
    brdffit_allocator a;
    brdffit_optimizer *opt;
    if (out == NULL) return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "out is NULL");
    *out = NULL;
    if (n_params < 1 || n_params > BF_OPTIM_MAX_PARAMS)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "n_params is %zu; it must be 1 .. %d",
                       n_params, BF_OPTIM_MAX_PARAMS);
    if (!bf_alloc_init(&a, alloc))
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "the allocator needs both alloc and free");
    opt = bf_calloc(&a, 1, sizeof *opt);
    if (opt == NULL) return bf_fail(err, BRDFFIT_E_OUT_OF_MEMORY, "cannot allocate the optimizer");
    opt->alloc = a;
    opt->n_params = n_params;
    opt->settings = default_settings;
    atomic_init(&opt->cancel, 0);
    reset_result(&opt->res);
    if (!alloc_work(opt) || install_policy(opt, brdffit_damping_nielsen()) != BRDFFIT_OK) {
        bf_free(&a, opt->block);
        bf_free(&a, opt);
        return bf_fail(err, BRDFFIT_E_OUT_OF_MEMORY,
                       "cannot allocate the workspace for %zu parameters", n_params);
    }
    opt->magic = BF_MAGIC_OPTIMIZER;
    *out = opt;
    return BRDFFIT_OK;
}

void brdffit_optimizer_destroy(brdffit_optimizer *opt)
{
    brdffit_allocator a;
    if (check_handle(opt) != BRDFFIT_OK) return;
    a = opt->alloc;
    opt->magic = BF_MAGIC_DEAD;
    bf_free(&a, opt->r);
    bf_free(&a, opt->policy_state);
    bf_free(&a, opt->history);
    bf_free(&a, opt->block);
    bf_free(&a, opt);
}

size_t brdffit_optimizer_param_count(const brdffit_optimizer *opt)
{
    return check_handle(opt) == BRDFFIT_OK ? opt->n_params : 0;
}

const char *brdffit_optimizer_message(const brdffit_optimizer *opt)
{
    if (opt == NULL) return "optimizer is NULL";
    if (opt->magic != BF_MAGIC_OPTIMIZER) return "optimizer handle is invalid or was destroyed";
    return opt->err.message;
}

/* --- the problem ------------------------------------------------------------- */

static void drop_problem(brdffit_optimizer *opt)
{
    bf_free(&opt->alloc, opt->r);
    opt->r = NULL;
    opt->jac = NULL;
    opt->form = BF_FORM_NONE;
    opt->residual_fn = NULL;
    opt->normal_fn = NULL;
    opt->user = NULL;
    opt->n_rows = 0;
}

brdffit_status brdffit_optimizer_set_residuals(brdffit_optimizer *opt, size_t n_rows,
                                               brdffit_residual_fn fn, void *user)
{
    size_t cells, total;
    double *r;
    BF_RETURN_IF_ERROR(check_mutable(opt, "set_residuals"));
    if (fn == NULL)
        return bf_optim_fail(opt, BRDFFIT_E_INVALID_ARGUMENT, "set_residuals: fn is NULL");
    if (n_rows < 1)
        return bf_optim_fail(opt, BRDFFIT_E_INVALID_ARGUMENT, "set_residuals: n_rows is 0");
    if (!bf_mul_size(n_rows, opt->n_params, &cells) || !bf_add_size(cells, n_rows, &total) ||
        !bf_mul_size(total, sizeof(double), &total))
        return bf_optim_fail(opt, BRDFFIT_E_OUT_OF_MEMORY,
                             "set_residuals: %zu rows x %zu parameters do not fit in memory",
                             n_rows, opt->n_params);
    r = bf_malloc(&opt->alloc, total);
    if (r == NULL)
        return bf_optim_fail(opt, BRDFFIT_E_OUT_OF_MEMORY,
                             "set_residuals: cannot allocate %zu bytes for residuals and Jacobian",
                             total);
    drop_problem(opt);
    opt->r = r;
    opt->jac = r + n_rows;
    opt->form = BF_FORM_RESIDUALS;
    opt->n_rows = n_rows;
    opt->residual_fn = fn;
    opt->user = user;
    return ok(opt);
}

brdffit_status brdffit_optimizer_set_normal(brdffit_optimizer *opt, size_t n_rows,
                                            brdffit_normal_fn fn, void *user)
{
    BF_RETURN_IF_ERROR(check_mutable(opt, "set_normal"));
    if (fn == NULL) return bf_optim_fail(opt, BRDFFIT_E_INVALID_ARGUMENT, "set_normal: fn is NULL");
    if (n_rows < 1)
        return bf_optim_fail(opt, BRDFFIT_E_INVALID_ARGUMENT, "set_normal: n_rows is 0");
    drop_problem(opt);
    opt->form = BF_FORM_NORMAL;
    opt->n_rows = n_rows;
    opt->normal_fn = fn;
    opt->user = user;
    return ok(opt);
}

brdffit_status brdffit_optimizer_set_damping(brdffit_optimizer *opt, const brdffit_damping *policy)
{
    BF_RETURN_IF_ERROR(check_mutable(opt, "set_damping"));
    if (policy == NULL) policy = brdffit_damping_nielsen();
    /* The first version's size, frozen: a larger struct (a newer header) is
     * accepted, its later fields ignored. */
    if (policy->struct_size < offsetof(brdffit_damping, user) + sizeof(void *))
        return bf_optim_fail(opt, BRDFFIT_E_INVALID_ARGUMENT,
                             "set_damping: struct_size is %zu, expected at least %zu "
                             "(initialise with BRDFFIT_DAMPING_INIT)",
                             policy->struct_size, offsetof(brdffit_damping, user) + sizeof(void *));
    if (policy->init == NULL || policy->accept == NULL || policy->reject == NULL)
        return bf_optim_fail(opt, BRDFFIT_E_INVALID_ARGUMENT,
                             "set_damping: the policy needs init, accept and reject");
    BF_RETURN_IF_ERROR(install_policy(opt, policy));
    return ok(opt);
}

/* --- settings ------------------------------------------------------------------ */

static brdffit_status set_tolerance(brdffit_optimizer *opt, double *field, double value, double def)
{
    *field = value == 0.0 ? def : value;
    return ok(opt);
}

static brdffit_status set_limit(brdffit_optimizer *opt, size_t *field, double value, size_t def,
                                const char *name)
{
    if (value != floor(value) || value > BF_MAX_LIMIT || value > (double)(SIZE_MAX / 4))
        return bf_optim_fail(opt, BRDFFIT_E_INVALID_ARGUMENT,
                             "%s must be a whole number up to 2^53, got %g", name, value);
    *field = value == 0.0 ? def : (size_t)value;
    return ok(opt);
}

brdffit_status brdffit_optimizer_set(brdffit_optimizer *opt, brdffit_optim_setting setting,
                                     double value)
{
    bf_optim_settings *s;
    const bf_optim_settings *d = &default_settings;
    BF_RETURN_IF_ERROR(check_mutable(opt, "set"));
    s = &opt->settings;
    if (!isfinite(value) || value < 0.0)
        return bf_optim_fail(opt, BRDFFIT_E_INVALID_ARGUMENT,
                             "setting %d: the value must be finite and >= 0, got %g", (int)setting,
                             value);
    switch (setting) {
    case BRDFFIT_OPT_GTOL: return set_tolerance(opt, &s->gtol, value, d->gtol);
    case BRDFFIT_OPT_XTOL: return set_tolerance(opt, &s->xtol, value, d->xtol);
    case BRDFFIT_OPT_FTOL: return set_tolerance(opt, &s->ftol, value, d->ftol);
    case BRDFFIT_OPT_MAX_ITERATIONS:
        return set_limit(opt, &s->max_iterations, value, d->max_iterations, "max iterations");
    case BRDFFIT_OPT_MAX_EVALUATIONS:
        return set_limit(opt, &s->max_evaluations, value, d->max_evaluations, "max evaluations");
    case BRDFFIT_OPT_SCALING:
        if (value != 0.0 && value != 1.0)
            return bf_optim_fail(opt, BRDFFIT_E_INVALID_ARGUMENT,
                                 "scaling must be 0 (Levenberg) or 1 (Marquardt), got %g", value);
        s->marquardt = value == 1.0;
        return ok(opt);
    case BRDFFIT_OPT_DIAG_FLOOR:
        if (value > 1.0)
            return bf_optim_fail(opt, BRDFFIT_E_INVALID_ARGUMENT,
                                 "diagonal floor must be at most 1, got %g", value);
        return set_tolerance(opt, &s->diag_floor, value, d->diag_floor);
    }
    return bf_optim_fail(opt, BRDFFIT_E_INVALID_ARGUMENT, "unknown setting %d", (int)setting);
}

brdffit_status brdffit_optimizer_get(const brdffit_optimizer *opt, brdffit_optim_setting setting,
                                     double *value)
{
    const bf_optim_settings *s;
    BF_RETURN_IF_ERROR(check_handle(opt));
    if (value == NULL) return BRDFFIT_E_INVALID_ARGUMENT;
    s = &opt->settings;
    switch (setting) {
    case BRDFFIT_OPT_GTOL: *value = s->gtol; return BRDFFIT_OK;
    case BRDFFIT_OPT_XTOL: *value = s->xtol; return BRDFFIT_OK;
    case BRDFFIT_OPT_FTOL: *value = s->ftol; return BRDFFIT_OK;
    case BRDFFIT_OPT_MAX_ITERATIONS: *value = (double)s->max_iterations; return BRDFFIT_OK;
    case BRDFFIT_OPT_MAX_EVALUATIONS: *value = (double)s->max_evaluations; return BRDFFIT_OK;
    case BRDFFIT_OPT_SCALING: *value = s->marquardt ? 1.0 : 0.0; return BRDFFIT_OK;
    case BRDFFIT_OPT_DIAG_FLOOR: *value = s->diag_floor; return BRDFFIT_OK;
    }
    return BRDFFIT_E_INVALID_ARGUMENT;
}

/* --- bounds, fixed parameters, callback, cancel --------------------------------- */

static brdffit_status check_bounds(brdffit_optimizer *opt, const double *lower, const double *upper)
{
    size_t j;
    for (j = 0; j < opt->n_params; j++) {
        double lo = lower ? lower[j] : -HUGE_VAL, hi = upper ? upper[j] : HUGE_VAL;
        if (isnan(lo) || isnan(hi))
            return bf_optim_fail(opt, BRDFFIT_E_INVALID_ARGUMENT,
                                 "set_bounds: the bound of parameter %zu is NaN", j);
        if (lo > hi)
            return bf_optim_fail(opt, BRDFFIT_E_INVALID_ARGUMENT,
                                 "set_bounds: parameter %zu has lower %g > upper %g", j, lo, hi);
        if (lo == HUGE_VAL || hi == -HUGE_VAL)
            return bf_optim_fail(opt, BRDFFIT_E_INVALID_ARGUMENT,
                                 "set_bounds: no finite value of parameter %zu lies in [%g, %g]", j,
                                 lo, hi);
    }
    return BRDFFIT_OK;
}

brdffit_status brdffit_optimizer_set_bounds(brdffit_optimizer *opt, const double *lower,
                                            const double *upper)
{
    size_t j;
    BF_RETURN_IF_ERROR(check_mutable(opt, "set_bounds"));
    BF_RETURN_IF_ERROR(check_bounds(opt, lower, upper));
    for (j = 0; j < opt->n_params; j++) {
        opt->w.lower[j] = lower ? lower[j] : -HUGE_VAL;
        opt->w.upper[j] = upper ? upper[j] : HUGE_VAL;
    }
    return ok(opt);
}

brdffit_status brdffit_optimizer_set_fixed(brdffit_optimizer *opt, const unsigned char *mask)
{
    size_t j;
    BF_RETURN_IF_ERROR(check_mutable(opt, "set_fixed"));
    for (j = 0; j < opt->n_params; j++) opt->w.fixed[j] = mask != NULL && mask[j] != 0;
    return ok(opt);
}

brdffit_status brdffit_optimizer_set_callback(brdffit_optimizer *opt, brdffit_iteration_fn fn,
                                              void *user)
{
    BF_RETURN_IF_ERROR(check_mutable(opt, "set_callback"));
    opt->callback = fn;
    opt->callback_user = fn != NULL ? user : NULL;
    return ok(opt);
}

void brdffit_optimizer_cancel(brdffit_optimizer *opt)
{
    if (check_handle(opt) == BRDFFIT_OK) atomic_store(&opt->cancel, 1);
}

/* --- the run ------------------------------------------------------------------------ */

brdffit_status brdffit_optimizer_run(brdffit_optimizer *opt, double *x)
{
    brdffit_status st;
    BF_RETURN_IF_ERROR(check_mutable(opt, "run"));
    if (x == NULL) return bf_optim_fail(opt, BRDFFIT_E_INVALID_ARGUMENT, "run: x is NULL");
    reset_result(&opt->res);
    if (opt->form == BF_FORM_NONE) {
        st = bf_optim_fail(opt, BRDFFIT_E_NOT_READY,
                           "run: no problem set (call set_residuals or set_normal first)");
    } else {
        opt->running = 1;
        st = bf_lm_run(opt, x);
        opt->running = 0;
    }
    atomic_store(&opt->cancel, 0);
    if (st != BRDFFIT_OK) {
        opt->res.valid = 0;
        opt->res.stop = BRDFFIT_STOP_NONE;
        return st;
    }
    return ok(opt);
}

/* --- results ---------------------------------------------------------------------------- */

brdffit_stop_reason brdffit_optimizer_stop_reason(const brdffit_optimizer *opt)
{
    return check_handle(opt) == BRDFFIT_OK ? opt->res.stop : BRDFFIT_STOP_NONE;
}

const char *brdffit_stop_reason_string(brdffit_stop_reason reason)
{
    switch (reason) {
    case BRDFFIT_STOP_NONE: return "no run, or the run failed";
    case BRDFFIT_STOP_GRADIENT: return "small gradient";
    case BRDFFIT_STOP_STEP: return "small step";
    case BRDFFIT_STOP_COST: return "small relative cost reduction";
    case BRDFFIT_STOP_MAX_ITERATIONS: return "iteration limit reached";
    case BRDFFIT_STOP_MAX_EVALUATIONS: return "evaluation limit reached";
    case BRDFFIT_STOP_CANCELLED: return "cancelled";
    case BRDFFIT_STOP_CALLBACK: return "stopped by the iteration callback";
    case BRDFFIT_STOP_ZERO_COST: return "cost reached zero";
    }
    return "unknown stop reason";
}

double brdffit_optimizer_initial_cost(const brdffit_optimizer *opt)
{
    return check_handle(opt) == BRDFFIT_OK && opt->res.valid ? opt->res.initial_cost : NAN;
}

double brdffit_optimizer_final_cost(const brdffit_optimizer *opt)
{
    return check_handle(opt) == BRDFFIT_OK && opt->res.valid ? opt->res.final_cost : NAN;
}

size_t brdffit_optimizer_iterations(const brdffit_optimizer *opt)
{
    return check_handle(opt) == BRDFFIT_OK && opt->res.valid ? opt->res.iterations : 0;
}

size_t brdffit_optimizer_evaluations(const brdffit_optimizer *opt)
{
    return check_handle(opt) == BRDFFIT_OK ? opt->res.evaluations : 0;
}

size_t brdffit_optimizer_last_improvement(const brdffit_optimizer *opt)
{
    return check_handle(opt) == BRDFFIT_OK && opt->res.valid ? opt->res.last_improvement : 0;
}

int brdffit_optimizer_used_fallback(const brdffit_optimizer *opt)
{
    return check_handle(opt) == BRDFFIT_OK && opt->res.valid ? opt->res.used_fallback : 0;
}

size_t brdffit_optimizer_history(const brdffit_optimizer *opt, double *cost, double *lambda)
{
    size_t n;
    if (check_handle(opt) != BRDFFIT_OK || !opt->res.valid) return 0;
    n = opt->res.history_len;
    if (cost != NULL) memcpy(cost, opt->history, n * sizeof *cost);
    if (lambda != NULL) memcpy(lambda, opt->history + opt->history_cap, n * sizeof *lambda);
    return n;
}

double brdffit_optimizer_condition(const brdffit_optimizer *opt)
{
    return check_handle(opt) == BRDFFIT_OK && opt->res.valid ? bf_optim_condition(opt) : NAN;
}

brdffit_status brdffit_optimizer_covariance(const brdffit_optimizer *opt, double *cov)
{
    BF_RETURN_IF_ERROR(check_handle(opt));
    if (cov == NULL) return BRDFFIT_E_INVALID_ARGUMENT;
    if (!opt->res.valid) return BRDFFIT_E_NOT_READY;
    bf_optim_covariance(opt, cov);
    return BRDFFIT_OK;
}

brdffit_status brdffit_optimizer_std_errors(const brdffit_optimizer *opt, double *se)
{
    BF_RETURN_IF_ERROR(check_handle(opt));
    if (se == NULL) return BRDFFIT_E_INVALID_ARGUMENT;
    if (!opt->res.valid) return BRDFFIT_E_NOT_READY;
    bf_optim_std_errors(opt, se);
    return BRDFFIT_OK;
}
