/* The fit handle: options, run and results (fit.h). */
#include <math.h>
#include <stdatomic.h>
#include <string.h>

#include "core/core.h"
#include "fit/fit_internal.h"
#include "fit/run.h"
#include "grid/grid_internal.h"
#include "models/models.h"

#define BF_FIT_MAX_THREADS 64

static int fit_ok(const brdffit_fit *fit)
{
    return fit != NULL && fit->magic == BF_MAGIC_FIT;
}

static brdffit_status fit_fail(brdffit_fit *fit, brdffit_status status, const char *what)
{
    return bf_say(fit->message, status, "%s", what);
}

static void fit_free_arrays(brdffit_fit *fit)
{
    bf_free(&fit->alloc, fit->start);
    bf_free(&fit->alloc, fit->fixed);
    bf_free(&fit->alloc, fit->result.params);
    bf_free(&fit->alloc, fit->result.cov);
    bf_free(&fit->alloc, fit->result.history);
    bf_trace_free(&fit->result.trace, &fit->alloc);
}

static brdffit_status fit_alloc_arrays(brdffit_fit *fit)
{
    size_t np = brdffit_model_param_count(fit->model);
    bf_result *r = &fit->result;
    fit->start = bf_calloc(&fit->alloc, fit->n_vec, sizeof(double));
    fit->fixed = bf_calloc(&fit->alloc, np, 1);
    r->params = bf_calloc(&fit->alloc, 2 * fit->n_vec + 4 * fit->nc, sizeof(double));
    /* the covariance's storage, where it is kept: made here, so that
     * every run allocates the same */
    if (fit->n_vec <= BRDFFIT_FIT_MAX_PARAMS) {
        r->cov = bf_calloc(&fit->alloc, fit->n_vec * fit->n_vec, sizeof(double));
        if (r->cov == NULL) return BRDFFIT_E_OUT_OF_MEMORY;
    }
    if (fit->start == NULL || fit->fixed == NULL || r->params == NULL)
        return BRDFFIT_E_OUT_OF_MEMORY;
    r->std_errors = r->params + fit->n_vec;
    r->metrics = r->params + 2 * fit->n_vec;
    return BRDFFIT_OK;
}

static void fit_defaults(brdffit_fit *fit)
{
    size_t k;
    fit->pipeline = BRDFFIT_PIPELINE_AUTO;
    fit->cap = BRDFFIT_DEFAULT_CAP;
    fit->weighting = BRDFFIT_WEIGHT_DEFAULT;
    fit->clearcoat = 0.0;
    fit->threads = 1;
    fit->max_iterations = 200;
    /* cube-root: its fits render closest to the measurement (docs/fitting.md,
     * Choosing the objective) */
    fit->objective = BRDFFIT_OBJECTIVE_CUBE_ROOT;
    fit->plausible = 1;
    fit->sandwich = 0;
    fit->damping = *brdffit_damping_nielsen();
    brdffit_model_default_params(fit->model, fit->nc, fit->start);
    for (k = 0; k < brdffit_model_param_count(fit->model); k++)
        fit->fixed[k] = (brdffit_model_param(fit->model, k)->flags & BRDFFIT_PARAM_FIXED) != 0;
    atomic_init(&fit->cancel, 0);
}

brdffit_status brdffit_fit_create(brdffit_fit **out, const brdffit_grid *grid,
                                  const brdffit_model *model, const brdffit_allocator *alloc,
                                  brdffit_error *err)
{
    brdffit_allocator a;
    brdffit_fit *fit;
    if (out == NULL) return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "out is NULL");
    *out = NULL;
    if (grid == NULL || model == NULL)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "grid or model is NULL");
    if (!bf_grid_ok(grid) || !bf_model_ok(model))
        return bf_fail(err, BRDFFIT_E_BAD_HANDLE, "grid or model is invalid or was destroyed");
    if (!bf_alloc_init(&a, alloc))
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "allocator lacks alloc or free");
    fit = bf_calloc(&a, 1, sizeof *fit);
    if (fit == NULL) return bf_fail(err, BRDFFIT_E_OUT_OF_MEMORY, "out of memory for the fit");
    fit->alloc = a;
    fit->grid = grid;
    fit->model = model;
    fit->nc = brdffit_grid_channel_count(grid);
    fit->n_vec = brdffit_model_vector_size(model, fit->nc);
    if (fit_alloc_arrays(fit) != BRDFFIT_OK) {
        fit_free_arrays(fit);
        bf_free(&a, fit);
        return bf_fail(err, BRDFFIT_E_OUT_OF_MEMORY, "out of memory for the fit");
    }
    fit_defaults(fit);
    fit->magic = BF_MAGIC_FIT;
    *out = fit;
    return BRDFFIT_OK;
}

void brdffit_fit_destroy(brdffit_fit *fit)
{
    brdffit_allocator a;
    if (!fit_ok(fit)) return;
    a = fit->alloc;
    fit_free_arrays(fit);
    fit->magic = BF_MAGIC_DEAD;
    bf_free(&a, fit);
}

const char *brdffit_fit_message(const brdffit_fit *fit)
{
    if (fit == NULL) return "fit is NULL";
    if (!fit_ok(fit)) return "fit is invalid or was destroyed";
    return fit->message;
}

#define BF_CHECK_FIT(fit)                                     \
    do {                                                      \
        if ((fit) == NULL) return BRDFFIT_E_INVALID_ARGUMENT; \
        if (!fit_ok(fit)) return BRDFFIT_E_BAD_HANDLE;        \
        (fit)->message[0] = '\0';                             \
    } while (0)

/* For calls that change the fit: not from inside its own run (its
 * callbacks, a user model), where the run would mix old and new settings. */
static brdffit_status check_mutable(brdffit_fit *fit, const char *what)
{
    BF_CHECK_FIT(fit);
    if (fit->running)
        return bf_say(fit->message, BRDFFIT_E_INVALID_ARGUMENT,
                      "%s: the fit cannot be changed while it runs", what);
    return BRDFFIT_OK;
}

static int is_whole(double v, double lo, double hi)
{
    return v >= lo && v <= hi && v == floor(v);
}

brdffit_status brdffit_fit_set(brdffit_fit *fit, brdffit_fit_setting setting, double value)
{
    BF_RETURN_IF_ERROR(check_mutable(fit, "brdffit_fit_set"));
    switch (setting) {
    case BRDFFIT_FIT_PIPELINE:
        if (!is_whole(value, 0, 2)) break;
        fit->pipeline = (brdffit_pipeline)(int)value;
        return BRDFFIT_OK;
    case BRDFFIT_FIT_CAP:
        if (!(value >= 0.0 && value <= BF_HALF_PI + 1e-12)) break;
        fit->cap = value > BF_HALF_PI ? BF_HALF_PI : value;
        return BRDFFIT_OK;
    case BRDFFIT_FIT_WEIGHTING:
        if (!is_whole(value, 0, 3)) break;
        fit->weighting = (unsigned)value;
        return BRDFFIT_OK;
    case BRDFFIT_FIT_CLEARCOAT:
        if (!(value >= 0.0 && value < 1.0)) break;
        fit->clearcoat = value;
        return BRDFFIT_OK;
    case BRDFFIT_FIT_THREADS:
        if (!is_whole(value, 1, BF_FIT_MAX_THREADS)) break;
        fit->threads = (size_t)value;
        return BRDFFIT_OK;
    case BRDFFIT_FIT_MAX_ITERATIONS:
        if (!is_whole(value, 1, 1e6)) break;
        fit->max_iterations = (size_t)value;
        return BRDFFIT_OK;
    case BRDFFIT_FIT_OBJECTIVE:
        if (!is_whole(value, 0, BRDFFIT_OBJECTIVE_RELATIVE)) break;
        fit->objective = (brdffit_objective)(int)value;
        return BRDFFIT_OK;
    case BRDFFIT_FIT_PLAUSIBLE:
        if (!is_whole(value, 0, 2)) break;
        fit->plausible = (int)value;
        return BRDFFIT_OK;
    case BRDFFIT_FIT_COVARIANCE:
        if (!is_whole(value, 0, 1)) break;
        fit->sandwich = (int)value;
        return BRDFFIT_OK;
    default: return fit_fail(fit, BRDFFIT_E_INVALID_ARGUMENT, "unknown fit setting");
    }
    return bf_say(fit->message, BRDFFIT_E_INVALID_ARGUMENT,
                  "value %g out of range for fit setting %d", value, (int)setting);
}

brdffit_status brdffit_fit_get(const brdffit_fit *fit, brdffit_fit_setting setting, double *value)
{
    if (fit == NULL || value == NULL) return BRDFFIT_E_INVALID_ARGUMENT;
    if (!fit_ok(fit)) return BRDFFIT_E_BAD_HANDLE;
    switch (setting) {
    case BRDFFIT_FIT_PIPELINE: *value = (double)fit->pipeline; return BRDFFIT_OK;
    case BRDFFIT_FIT_CAP: *value = fit->cap; return BRDFFIT_OK;
    case BRDFFIT_FIT_WEIGHTING: *value = (double)fit->weighting; return BRDFFIT_OK;
    case BRDFFIT_FIT_CLEARCOAT: *value = fit->clearcoat; return BRDFFIT_OK;
    case BRDFFIT_FIT_THREADS: *value = (double)fit->threads; return BRDFFIT_OK;
    case BRDFFIT_FIT_MAX_ITERATIONS: *value = (double)fit->max_iterations; return BRDFFIT_OK;
    case BRDFFIT_FIT_OBJECTIVE: *value = (double)fit->objective; return BRDFFIT_OK;
    case BRDFFIT_FIT_PLAUSIBLE: *value = (double)fit->plausible; return BRDFFIT_OK;
    case BRDFFIT_FIT_COVARIANCE: *value = (double)fit->sandwich; return BRDFFIT_OK;
    }
    return BRDFFIT_E_INVALID_ARGUMENT;
}

brdffit_status brdffit_fit_set_damping(brdffit_fit *fit, const brdffit_damping *policy)
{
    BF_RETURN_IF_ERROR(check_mutable(fit, "brdffit_fit_set_damping"));
    if (policy == NULL) policy = brdffit_damping_nielsen();
    /* Any size from the first version's up (a newer header's larger struct
     * included); fields the caller's size lacks keep the built-in's. */
    if (policy->struct_size < BRDFFIT_DAMPING_SIZE_V1 || policy->init == NULL ||
        policy->accept == NULL || policy->reject == NULL)
        return fit_fail(fit, BRDFFIT_E_INVALID_ARGUMENT,
                        "damping policy needs struct_size, init, accept and reject");
    fit->damping = *brdffit_damping_nielsen();
    memcpy(&fit->damping, policy,
           policy->struct_size < sizeof fit->damping ? policy->struct_size : sizeof fit->damping);
    fit->damping.struct_size = sizeof fit->damping;
    return BRDFFIT_OK;
}

brdffit_status brdffit_fit_set_start(brdffit_fit *fit, const double *params)
{
    size_t k, c;
    BF_RETURN_IF_ERROR(check_mutable(fit, "brdffit_fit_set_start"));
    if (params == NULL) {
        brdffit_model_default_params(fit->model, fit->nc, fit->start);
        return BRDFFIT_OK;
    }
    for (k = 0; k < brdffit_model_param_count(fit->model); k++) {
        const brdffit_param_info *info = brdffit_model_param(fit->model, k);
        for (c = 0; c < fit->nc; c++) {
            double v = params[brdffit_model_vector_index(fit->model, k, c, fit->nc)];
            if (!isfinite(v))
                return bf_say(fit->message, BRDFFIT_E_INVALID_ARGUMENT, "start value of %s is %g",
                              info->name, v);
            if (v < info->lower || v > info->upper)
                return bf_say(fit->message, BRDFFIT_E_RANGE,
                              "start value %g of %s is outside [%g, %g]", v, info->name,
                              info->lower, info->upper);
        }
    }
    memcpy(fit->start, params, fit->n_vec * sizeof *params);
    return BRDFFIT_OK;
}

brdffit_status brdffit_fit_set_fixed(brdffit_fit *fit, size_t param, int fixed)
{
    BF_RETURN_IF_ERROR(check_mutable(fit, "brdffit_fit_set_fixed"));
    if (param >= brdffit_model_param_count(fit->model))
        return fit_fail(fit, BRDFFIT_E_INVALID_ARGUMENT, "parameter index out of range");
    fit->fixed[param] = fixed != 0;
    return BRDFFIT_OK;
}

brdffit_status brdffit_fit_set_callback(brdffit_fit *fit, brdffit_iteration_fn fn, void *user)
{
    BF_RETURN_IF_ERROR(check_mutable(fit, "brdffit_fit_set_callback"));
    fit->callback = fn;
    fit->callback_user = user;
    return BRDFFIT_OK;
}

void brdffit_fit_cancel(brdffit_fit *fit)
{
    if (fit_ok(fit)) atomic_store(&fit->cancel, 1);
}

/* Take the result of a run (its arrays and message are the handle's own). */
static void keep_result(brdffit_fit *fit, const bf_result *r, brdffit_status status)
{
    bf_free(&fit->alloc, fit->result.history);
    bf_trace_free(&fit->result.trace, &fit->alloc);
    fit->result = *r;
    fit->has_result = status == BRDFFIT_OK;
}

brdffit_status brdffit_fit_run(brdffit_fit *fit)
{
    bf_result r;
    brdffit_status status;
    BF_RETURN_IF_ERROR(check_mutable(fit, "brdffit_fit_run"));
    if (!bf_grid_ok(fit->grid) || !bf_model_ok(fit->model)) {
        atomic_store(&fit->cancel, 0);
        return fit_fail(fit, BRDFFIT_E_BAD_HANDLE, "grid or model was destroyed");
    }
    fit->has_result = 0;
    if (fit->pipeline != BRDFFIT_PIPELINE_TWO_STAGE && fit->n_vec > BRDFFIT_FIT_MAX_PARAMS) {
        atomic_store(&fit->cancel, 0);
        return bf_say(fit->message, BRDFFIT_E_TOO_LARGE,
                      "the %s pipeline fits every channel at once: model '%s' has %zu parameters "
                      "for %zu channels, more than its limit of %d (BRDFFIT_FIT_MAX_PARAMS); the "
                      "two-stage pipeline fits each channel alone",
                      fit->pipeline == BRDFFIT_PIPELINE_AUTO ? "auto" : "joint",
                      brdffit_model_name(fit->model), fit->n_vec, fit->nc, BRDFFIT_FIT_MAX_PARAMS);
    }
    if (fit->result.cov != NULL)
        memset(fit->result.cov, 0, fit->n_vec * fit->n_vec * sizeof *fit->result.cov);
    memset(&r, 0, sizeof r);
    r.params = fit->result.params;
    r.std_errors = fit->result.std_errors;
    r.cov = fit->result.cov;
    r.metrics = fit->result.metrics;
    r.message = fit->message;
    fit->running = 1;
    status = bf_run_fit(fit, &r);
    fit->running = 0;
    /* a call refused during the run may have left its message */
    if (status == BRDFFIT_OK) fit->message[0] = '\0';
    keep_result(fit, &r, status);
    atomic_store(&fit->cancel, 0);
    return status;
}

size_t brdffit_fit_param_count(const brdffit_fit *fit)
{
    return fit_ok(fit) ? fit->n_vec : 0;
}

static brdffit_status result_ready(const brdffit_fit *fit, const void *out)
{
    if (fit == NULL || out == NULL) return BRDFFIT_E_INVALID_ARGUMENT;
    if (!fit_ok(fit)) return BRDFFIT_E_BAD_HANDLE;
    return fit->has_result ? BRDFFIT_OK : BRDFFIT_E_NOT_READY;
}

brdffit_status brdffit_fit_params(const brdffit_fit *fit, double *params)
{
    BF_RETURN_IF_ERROR(result_ready(fit, params));
    memcpy(params, fit->result.params, fit->n_vec * sizeof *params);
    return BRDFFIT_OK;
}

brdffit_status brdffit_fit_std_errors(const brdffit_fit *fit, double *se)
{
    BF_RETURN_IF_ERROR(result_ready(fit, se));
    memcpy(se, fit->result.std_errors, fit->n_vec * sizeof *se);
    return BRDFFIT_OK;
}

brdffit_status brdffit_fit_covariance(const brdffit_fit *fit, double *cov)
{
    BF_RETURN_IF_ERROR(result_ready(fit, cov));
    if (fit->result.cov == NULL) return BRDFFIT_E_TOO_LARGE;
    memcpy(cov, fit->result.cov, fit->n_vec * fit->n_vec * sizeof *cov);
    return BRDFFIT_OK;
}

/* One metric from the per-channel sums [sum d^2, sum a (cos d)^2, sum a, cost]. */
static double metric_of(brdffit_fit_metric metric, const double *sums)
{
    switch (metric) {
    case BRDFFIT_METRIC_RMS: return sqrt(sums[0]);
    case BRDFFIT_METRIC_NGAN: return sums[2] > 0.0 ? sqrt(sums[1] / sums[2]) : 0.0;
    case BRDFFIT_METRIC_COST: return sums[3];
    }
    return 0.0;
}

brdffit_status brdffit_fit_error(const brdffit_fit *fit, brdffit_fit_metric metric, size_t channel,
                                 double *value)
{
    double sums[4] = {0.0, 0.0, 0.0, 0.0};
    size_t c, i;
    BF_RETURN_IF_ERROR(result_ready(fit, value));
    if ((unsigned)metric > BRDFFIT_METRIC_COST) return BRDFFIT_E_INVALID_ARGUMENT;
    if (channel != BRDFFIT_ALL_CHANNELS && channel >= fit->nc) return BRDFFIT_E_INVALID_ARGUMENT;
    for (c = 0; c < fit->nc; c++)
        if (channel == BRDFFIT_ALL_CHANNELS || channel == c)
            for (i = 0; i < 4; i++) sums[i] += fit->result.metrics[4 * c + i];
    *value = metric_of(metric, sums);
    return BRDFFIT_OK;
}

static int find_param(const brdffit_model *model, const char *name, size_t *k)
{
    return brdffit_model_param_find(model, name, k) == BRDFFIT_OK;
}

brdffit_status brdffit_fit_shader(const brdffit_fit *fit, double *rs, double *cd, double *cs)
{
    size_t kd, ks, kr, c, nc;
    double max_cs = 0.0;
    BF_RETURN_IF_ERROR(result_ready(fit, rs));
    if (cd == NULL || cs == NULL) return BRDFFIT_E_INVALID_ARGUMENT;
    if (!find_param(fit->model, "cd", &kd) || !find_param(fit->model, "cs", &ks))
        return BRDFFIT_E_UNSUPPORTED;
    nc = fit->nc;
    for (c = 0; c < nc; c++) {
        cd[c] = fit->result.params[brdffit_model_vector_index(fit->model, kd, c, nc)];
        cs[c] = fit->result.params[brdffit_model_vector_index(fit->model, ks, c, nc)];
        max_cs = fmax(max_cs, cs[c]);
    }
    if (find_param(fit->model, "Rs", &kr)) {
        *rs = fit->result.params[brdffit_model_vector_index(fit->model, kr, 0, nc)];
        return BRDFFIT_OK;
    }
    if (max_cs >= 1.0) return BRDFFIT_E_RANGE;
    *rs = max_cs;
    for (c = 0; c < nc; c++) {
        cs[c] = max_cs > 0.0 ? cs[c] / max_cs : 0.0;
        cd[c] = cd[c] / (1.0 - max_cs);
    }
    return BRDFFIT_OK;
}

brdffit_stop_reason brdffit_fit_stop_reason(const brdffit_fit *fit)
{
    return fit_ok(fit) && fit->has_result ? fit->result.stop : BRDFFIT_STOP_NONE;
}

size_t brdffit_fit_iterations(const brdffit_fit *fit)
{
    return fit_ok(fit) && fit->has_result ? fit->result.iterations : 0;
}

size_t brdffit_fit_history(const brdffit_fit *fit, double *cost, double *lambda)
{
    size_t n;
    if (!fit_ok(fit) || !fit->has_result) return 0;
    n = fit->result.history_len;
    if (cost != NULL && n > 0) memcpy(cost, fit->result.history, n * sizeof *cost);
    if (lambda != NULL && n > 0) memcpy(lambda, fit->result.history + n, n * sizeof *lambda);
    return n;
}

size_t brdffit_fit_passes(const brdffit_fit *fit)
{
    return fit_ok(fit) ? fit->result.passes : 0;
}
