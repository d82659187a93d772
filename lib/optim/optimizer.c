/* The optimizer handle: creation, the problem, the damping policy and the
 * entry to a run. Settings and bounds are in settings.c, the results of a
 * run in results.c, the run loop in lm.c. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "core/core.h"
#include "optim/optim_internal.h"

enum { BF_WORK_VECTORS = 15, BF_WORK_MATRICES = 5 };

brdffit_status bf_optim_fail(brdffit_optimizer *opt, brdffit_status status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    bf_vfail(&opt->err, status, fmt, ap);
    va_end(ap);
    return status;
}

brdffit_status bf_optim_ok(brdffit_optimizer *opt)
{
    opt->err.status = BRDFFIT_OK;
    opt->err.message[0] = '\0';
    return BRDFFIT_OK;
}

brdffit_status bf_optim_check_handle(const brdffit_optimizer *opt)
{
    if (opt == NULL) return BRDFFIT_E_INVALID_ARGUMENT;
    if (opt->magic != BF_MAGIC_OPTIMIZER) return BRDFFIT_E_BAD_HANDLE;
    return BRDFFIT_OK;
}

/* For calls that change the optimizer: not from inside its own run. */
brdffit_status bf_optim_check_mutable(brdffit_optimizer *opt, const char *what)
{
    BF_RETURN_IF_ERROR(bf_optim_check_handle(opt));
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
    double **vectors[BF_WORK_VECTORS] = {&w->x,     &w->trial, &w->g,      &w->g_new, &w->step,
                                         &w->delta, &w->d,     &w->scale,  &w->w,     &w->tmp,
                                         &w->lower, &w->upper, &w->xscale, &w->best,  &w->amax};
    double **matrices[BF_WORK_MATRICES] = {&w->jtj, &w->jtj_new, &w->m, &w->v, &w->meat};
    /* matrices first, then vectors, indices and flags; p <= 4096: no
     * overflow. The matrices are always written before they are read and
     * are not touched here, so a large optimizer costs no memory it does
     * not use. */
    small = BF_WORK_VECTORS * p * sizeof(double) + 4 * p * sizeof(size_t) + 3 * p;
    bytes = BF_WORK_MATRICES * pp * sizeof(double) + small;
    opt->block = bf_malloc(&opt->alloc, bytes);
    if (opt->block == NULL) return 0;
    d = opt->block;
    for (i = 0; i < BF_WORK_MATRICES; i++, d += pp) *matrices[i] = d;
    memset(d, 0, small);
    for (i = 0; i < BF_WORK_VECTORS; i++, d += p) *vectors[i] = d;
    w->free_idx = (size_t *)(void *)d;
    w->order = w->free_idx + p;
    w->group = w->order + p;
    w->pos = w->group + p;
    w->fixed = (unsigned char *)(w->pos + p);
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
    bf_optim_default_settings(&opt->settings);
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
    if (bf_optim_check_handle(opt) != BRDFFIT_OK) return;
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
    return bf_optim_check_handle(opt) == BRDFFIT_OK ? opt->n_params : 0;
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
    BF_RETURN_IF_ERROR(bf_optim_check_mutable(opt, "set_residuals"));
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
    return bf_optim_ok(opt);
}

brdffit_status brdffit_optimizer_set_normal(brdffit_optimizer *opt, size_t n_rows,
                                            brdffit_normal_fn fn, void *user)
{
    BF_RETURN_IF_ERROR(bf_optim_check_mutable(opt, "set_normal"));
    if (fn == NULL) return bf_optim_fail(opt, BRDFFIT_E_INVALID_ARGUMENT, "set_normal: fn is NULL");
    if (n_rows < 1)
        return bf_optim_fail(opt, BRDFFIT_E_INVALID_ARGUMENT, "set_normal: n_rows is 0");
    drop_problem(opt);
    opt->form = BF_FORM_NORMAL;
    opt->n_rows = n_rows;
    opt->normal_fn = fn;
    opt->user = user;
    return bf_optim_ok(opt);
}

brdffit_status brdffit_optimizer_set_damping(brdffit_optimizer *opt, const brdffit_damping *policy)
{
    BF_RETURN_IF_ERROR(bf_optim_check_mutable(opt, "set_damping"));
    if (policy == NULL) policy = brdffit_damping_nielsen();
    /* The first version's size, frozen: a larger struct (a newer header) is
     * accepted, its later fields ignored. */
    if (policy->struct_size < BRDFFIT_DAMPING_SIZE_V1)
        return bf_optim_fail(opt, BRDFFIT_E_INVALID_ARGUMENT,
                             "set_damping: struct_size is %zu, expected at least %zu "
                             "(initialise with BRDFFIT_DAMPING_INIT)",
                             policy->struct_size, BRDFFIT_DAMPING_SIZE_V1);
    if (policy->init == NULL || policy->accept == NULL || policy->reject == NULL)
        return bf_optim_fail(opt, BRDFFIT_E_INVALID_ARGUMENT,
                             "set_damping: the policy needs init, accept and reject");
    BF_RETURN_IF_ERROR(install_policy(opt, policy));
    return bf_optim_ok(opt);
}

/* --- the run ------------------------------------------------------------------------ */

brdffit_status brdffit_optimizer_run(brdffit_optimizer *opt, double *x)
{
    brdffit_status st;
    BF_RETURN_IF_ERROR(bf_optim_check_mutable(opt, "run"));
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
    return bf_optim_ok(opt);
}
