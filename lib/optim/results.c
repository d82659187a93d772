/* The results of the last run: stop reason, costs, counts, history, and
 * the condition number and covariance computed on demand (analysis.c). */
#include <math.h>
#include <string.h>

#include "core/core.h"
#include "optim/optim_internal.h"
#include "optim/sandwich.h"

brdffit_stop_reason brdffit_optimizer_stop_reason(const brdffit_optimizer *opt)
{
    return bf_optim_check_handle(opt) == BRDFFIT_OK ? opt->res.stop : BRDFFIT_STOP_NONE;
}

int brdffit_optimizer_converged(const brdffit_optimizer *opt)
{
    brdffit_stop_reason s;
    if (bf_optim_check_handle(opt) != BRDFFIT_OK || !opt->res.valid) return 0;
    s = opt->res.stop;
    return s == BRDFFIT_STOP_GRADIENT || s == BRDFFIT_STOP_STEP || s == BRDFFIT_STOP_COST ||
           s == BRDFFIT_STOP_ZERO_COST;
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
    case BRDFFIT_STOP_STALLED: return "stalled where the data do not determine the parameters";
    }
    return "unknown stop reason";
}

double brdffit_optimizer_initial_cost(const brdffit_optimizer *opt)
{
    return bf_optim_check_handle(opt) == BRDFFIT_OK && opt->res.valid ? opt->res.initial_cost : NAN;
}

double brdffit_optimizer_final_cost(const brdffit_optimizer *opt)
{
    return bf_optim_check_handle(opt) == BRDFFIT_OK && opt->res.valid ? opt->res.final_cost : NAN;
}

size_t brdffit_optimizer_iterations(const brdffit_optimizer *opt)
{
    return bf_optim_check_handle(opt) == BRDFFIT_OK && opt->res.valid ? opt->res.iterations : 0;
}

size_t brdffit_optimizer_evaluations(const brdffit_optimizer *opt)
{
    return bf_optim_check_handle(opt) == BRDFFIT_OK ? opt->res.evaluations : 0;
}

size_t brdffit_optimizer_last_improvement(const brdffit_optimizer *opt)
{
    return bf_optim_check_handle(opt) == BRDFFIT_OK && opt->res.valid ? opt->res.last_improvement
                                                                      : 0;
}

int brdffit_optimizer_used_fallback(const brdffit_optimizer *opt)
{
    return bf_optim_check_handle(opt) == BRDFFIT_OK && opt->res.valid ? opt->res.used_fallback : 0;
}

size_t brdffit_optimizer_history(const brdffit_optimizer *opt, double *cost, double *lambda)
{
    size_t n;
    if (bf_optim_check_handle(opt) != BRDFFIT_OK || !opt->res.valid) return 0;
    n = opt->res.history_len;
    if (cost != NULL) memcpy(cost, opt->history, n * sizeof *cost);
    if (lambda != NULL) memcpy(lambda, opt->history + opt->history_cap, n * sizeof *lambda);
    return n;
}

double brdffit_optimizer_condition(const brdffit_optimizer *opt)
{
    return bf_optim_check_handle(opt) == BRDFFIT_OK && opt->res.valid ? bf_optim_condition(opt)
                                                                      : NAN;
}

/* A successful run; for the sandwich, one in residual form whose rows
 * could be evaluated at the returned point. */
static brdffit_status covariance_ready(const brdffit_optimizer *opt)
{
    if (!opt->res.valid) return BRDFFIT_E_NOT_READY;
    if (opt->res.want_sandwich && !opt->res.sandwich) return BRDFFIT_E_INVALID_ARGUMENT;
    return BRDFFIT_OK;
}

brdffit_status brdffit_optimizer_covariance(const brdffit_optimizer *opt, double *cov)
{
    BF_RETURN_IF_ERROR(bf_optim_check_handle(opt));
    if (cov == NULL) return BRDFFIT_E_INVALID_ARGUMENT;
    BF_RETURN_IF_ERROR(covariance_ready(opt));
    if (!bf_optim_covariance(opt, cov)) return BRDFFIT_E_NOT_READY; /* watched flag */
    return BRDFFIT_OK;
}

brdffit_status brdffit_optimizer_std_errors(const brdffit_optimizer *opt, double *se)
{
    BF_RETURN_IF_ERROR(bf_optim_check_handle(opt));
    if (se == NULL) return BRDFFIT_E_INVALID_ARGUMENT;
    BF_RETURN_IF_ERROR(covariance_ready(opt));
    if (!bf_optim_std_errors(opt, se)) return BRDFFIT_E_NOT_READY; /* watched flag */
    return BRDFFIT_OK;
}

brdffit_status bf_optim_std_errors_covariance(const brdffit_optimizer *opt, double *se, double *cov)
{
    BF_RETURN_IF_ERROR(bf_optim_check_handle(opt));
    if (se == NULL || cov == NULL) return BRDFFIT_E_INVALID_ARGUMENT;
    BF_RETURN_IF_ERROR(covariance_ready(opt));
    if (!bf_optim_errors(opt, se, cov)) return BRDFFIT_E_NOT_READY; /* watched flag */
    return BRDFFIT_OK;
}
