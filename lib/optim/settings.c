/* The optimizer's settings, bounds, fixed parameters, iteration callback
 * and cancel request. */
#include <math.h>
#include <stdint.h>

#include "core/core.h"
#include "optim/optim_internal.h"

/* Limits are doubles in the setter; larger values are not integers any
 * more in double precision. */
#define BF_MAX_LIMIT 9007199254740992.0 /* 2^53 */

static const bf_optim_settings default_settings = {
    1e-13, 1e-10, 1e-15, 1e-12, 1e300, 1.0, 0.0, 10000, 24000, 1, 0, 1, 0, 0, 0};

void bf_optim_default_settings(bf_optim_settings *s)
{
    *s = default_settings;
}

static brdffit_status set_tolerance(brdffit_optimizer *opt, double *field, double value, double def)
{
    *field = value == 0.0 ? def : value;
    return bf_optim_ok(opt);
}

static brdffit_status set_limit(brdffit_optimizer *opt, size_t *field, double value, size_t def,
                                const char *name)
{
    if (value != floor(value) || value > BF_MAX_LIMIT || value > (double)(SIZE_MAX / 4))
        return bf_optim_fail(opt, BRDFFIT_E_INVALID_ARGUMENT,
                             "%s must be a whole number up to 2^53, got %g", name, value);
    *field = value == 0.0 ? def : (size_t)value;
    return bf_optim_ok(opt);
}

/* A setting that is 0 or 1. */
static brdffit_status set_switch(brdffit_optimizer *opt, int *field, double value, const char *what)
{
    if (value != 0.0 && value != 1.0)
        return bf_optim_fail(opt, BRDFFIT_E_INVALID_ARGUMENT, "%s, got %g", what, value);
    *field = value == 1.0;
    return bf_optim_ok(opt);
}

brdffit_status brdffit_optimizer_set(brdffit_optimizer *opt, brdffit_optim_setting setting,
                                     double value)
{
    bf_optim_settings *s;
    const bf_optim_settings *d = &default_settings;
    BF_RETURN_IF_ERROR(bf_optim_check_mutable(opt, "set"));
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
        return set_switch(opt, &s->marquardt, value,
                          "scaling must be 0 (Levenberg) or 1 (Marquardt)");
    case BRDFFIT_OPT_DIAG_FLOOR:
        if (value > 1.0)
            return bf_optim_fail(opt, BRDFFIT_E_INVALID_ARGUMENT,
                                 "diagonal floor must be at most 1, got %g", value);
        return set_tolerance(opt, &s->diag_floor, value, d->diag_floor);
    case BRDFFIT_OPT_STEP_BOUND: return set_tolerance(opt, &s->step_bound, value, d->step_bound);
    case BRDFFIT_OPT_RESTART_BOUND:
        return set_tolerance(opt, &s->restart_bound, value, d->restart_bound);
    case BRDFFIT_OPT_COVARIANCE:
        return set_switch(opt, &s->sandwich, value,
                          "covariance must be 0 (classic) or 1 (sandwich)");
    case BRDFFIT_OPT_SCALE_MEMORY:
        return set_switch(opt, &s->scale_memory, value,
                          "scale memory must be 0 (current point) or 1 (running maximum)");
    case BRDFFIT_OPT_STEP_TEST:
        return set_switch(opt, &s->step_test, value,
                          "step test must be 0 (per parameter) or 1 (scaled norm)");
    case BRDFFIT_OPT_STEP_CONTROL:
        return set_switch(opt, &s->step_control, value,
                          "step control must be 0 (the policy alone) or 1 (Moré's rules too)");
    case BRDFFIT_OPT_START_RADIUS:
        return set_tolerance(opt, &s->start_radius, value, d->start_radius);
    case BRDFFIT_OPT_COST_LOOKAHEAD:
        return set_switch(opt, &s->cost_lookahead, value,
                          "cost lookahead must be 0 (the step taken) or 1 (the next step too)");
    }
    return bf_optim_fail(opt, BRDFFIT_E_INVALID_ARGUMENT, "unknown setting %d", (int)setting);
}

brdffit_status brdffit_optimizer_get(const brdffit_optimizer *opt, brdffit_optim_setting setting,
                                     double *value)
{
    const bf_optim_settings *s;
    BF_RETURN_IF_ERROR(bf_optim_check_handle(opt));
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
    case BRDFFIT_OPT_STEP_BOUND: *value = s->step_bound; return BRDFFIT_OK;
    case BRDFFIT_OPT_RESTART_BOUND: *value = s->restart_bound; return BRDFFIT_OK;
    case BRDFFIT_OPT_COVARIANCE: *value = s->sandwich ? 1.0 : 0.0; return BRDFFIT_OK;
    case BRDFFIT_OPT_SCALE_MEMORY: *value = s->scale_memory ? 1.0 : 0.0; return BRDFFIT_OK;
    case BRDFFIT_OPT_STEP_TEST: *value = s->step_test ? 1.0 : 0.0; return BRDFFIT_OK;
    case BRDFFIT_OPT_STEP_CONTROL: *value = s->step_control ? 1.0 : 0.0; return BRDFFIT_OK;
    case BRDFFIT_OPT_START_RADIUS: *value = s->start_radius; return BRDFFIT_OK;
    case BRDFFIT_OPT_COST_LOOKAHEAD: *value = s->cost_lookahead ? 1.0 : 0.0; return BRDFFIT_OK;
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
    BF_RETURN_IF_ERROR(bf_optim_check_mutable(opt, "set_bounds"));
    BF_RETURN_IF_ERROR(check_bounds(opt, lower, upper));
    for (j = 0; j < opt->n_params; j++) {
        opt->w.lower[j] = lower ? lower[j] : -HUGE_VAL;
        opt->w.upper[j] = upper ? upper[j] : HUGE_VAL;
    }
    return bf_optim_ok(opt);
}

brdffit_status brdffit_optimizer_set_fixed(brdffit_optimizer *opt, const unsigned char *mask)
{
    size_t j;
    BF_RETURN_IF_ERROR(bf_optim_check_mutable(opt, "set_fixed"));
    for (j = 0; j < opt->n_params; j++) opt->w.fixed[j] = mask != NULL && mask[j] != 0;
    return bf_optim_ok(opt);
}

brdffit_status brdffit_optimizer_set_callback(brdffit_optimizer *opt, brdffit_iteration_fn fn,
                                              void *user)
{
    BF_RETURN_IF_ERROR(bf_optim_check_mutable(opt, "set_callback"));
    opt->callback = fn;
    opt->callback_user = fn != NULL ? user : NULL;
    return bf_optim_ok(opt);
}

void brdffit_optimizer_cancel(brdffit_optimizer *opt)
{
    if (bf_optim_check_handle(opt) == BRDFFIT_OK) atomic_store(&opt->cancel, 1);
}
