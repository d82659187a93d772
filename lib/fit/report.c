/* The handle's report of its last run beyond the parameters (fit.h):
 * whether the answer converged, the stages and the whole history, read
 * from the trace the run recorded (trace.h). */
#include <string.h>

#include "core/core.h"
#include "fit/fit_internal.h"

static const bf_trace *trace_of(const brdffit_fit *fit)
{
    if (fit == NULL || fit->magic != BF_MAGIC_FIT || !fit->has_result) return NULL;
    return &fit->result.trace;
}

int brdffit_fit_converged(const brdffit_fit *fit)
{
    const bf_trace *t = trace_of(fit);
    if (t == NULL || fit->result.stop == BRDFFIT_STOP_CANCELLED) return 0;
    return bf_trace_converged(t);
}

size_t brdffit_fit_stage_count(const brdffit_fit *fit)
{
    const bf_trace *t = trace_of(fit);
    return t != NULL ? t->n_stages : 0;
}

brdffit_status brdffit_fit_stage_info(const brdffit_fit *fit, size_t stage,
                                      brdffit_fit_stage *info, size_t size)
{
    const bf_trace *t;
    if (fit == NULL || info == NULL || size < BRDFFIT_FIT_STAGE_SIZE_V1)
        return BRDFFIT_E_INVALID_ARGUMENT;
    if (fit->magic != BF_MAGIC_FIT) return BRDFFIT_E_BAD_HANDLE;
    t = trace_of(fit);
    if (t == NULL) return BRDFFIT_E_NOT_READY;
    if (stage >= t->n_stages) return BRDFFIT_E_INVALID_ARGUMENT;
    memcpy(info, &t->stages[stage], size < sizeof *info ? size : sizeof *info);
    return BRDFFIT_OK;
}

const char *brdffit_fit_stage_name(brdffit_fit_stage_kind kind)
{
    switch (kind) {
    case BRDFFIT_STAGE_SCAN: return "scan";
    case BRDFFIT_STAGE_POLISH: return "polish";
    case BRDFFIT_STAGE_JOINT: return "joint";
    case BRDFFIT_STAGE_MEAN: return "mean";
    case BRDFFIT_STAGE_CHANNEL: return "channel";
    }
    return NULL;
}

size_t brdffit_fit_history_all(const brdffit_fit *fit, double *cost, double *lambda,
                               size_t *stage)
{
    const bf_trace *t = trace_of(fit);
    size_t i;
    if (t == NULL) return 0;
    for (i = 0; i < t->n_entries; i++) {
        if (cost != NULL) cost[i] = t->entries[i].cost;
        if (lambda != NULL) lambda[i] = t->entries[i].lambda;
        if (stage != NULL) stage[i] = t->entries[i].stage;
    }
    return t->n_entries;
}
