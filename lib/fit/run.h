/* One fit run: the plan of the run (weights, scale check, helper threads,
 * the pipeline's stages, the error figures) from the handle's options to
 * one result. Not installed. */
#ifndef BRDFFIT_FIT_RUN_H
#define BRDFFIT_FIT_RUN_H

#include "fit/fit_internal.h"
#include "fit/result.h"
#include "grid/grid_internal.h"

/* Run the selected pipeline of `fit` (only read) into *out, whose params,
 * std_errors and metrics point to storage for the results and whose other
 * fields start zeroed. On failure out->message says why; out->passes and
 * out->history are set either way (the history owned by the caller). */
brdffit_status bf_run_fit(brdffit_fit *fit, bf_result *out);

/* The weight plans of a fit of `fit`'s options over its grid: the
 * residual weights and the solid angle alone (of the error figure E and
 * the log and cube-root objectives; without the solid angle where the
 * cells have none and the fit's weights do not use it). On failure
 * neither is left allocated and err says why. */
brdffit_status bf_run_plans(const brdffit_fit *fit, bf_weight_plan *plan, bf_weight_plan *plan_sa,
                            brdffit_error *err);

#endif
