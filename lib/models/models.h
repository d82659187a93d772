/* What lib/models offers the library's other layers besides the public
 * model.h: handle checks and evaluation with the library's error reports.
 * Not installed. The basis form of the built-in models is in
 * models/basis.h. */
#ifndef BRDFFIT_MODELS_MODELS_H
#define BRDFFIT_MODELS_MODELS_H

#include <stddef.h>

#include "brdffit/model.h"

/* Validate a model handle (non-NULL, magic). */
int bf_model_ok(const brdffit_model *m);

/* Evaluate over a batch; maps a callback failure to
 * BRDFFIT_E_MODEL_FAILED with a message naming the model and the status it
 * returned. Does not check the outputs for NaN. */
brdffit_status bf_model_eval(const brdffit_model *m, const brdffit_batch *batch,
                             const double *params, size_t n_channels, double *values,
                             double *jacobian, brdffit_error *err);

/* Check the outputs of an evaluation of n samples for NaN and Inf:
 * BRDFFIT_E_NONFINITE with a message naming the model, the parameter (for
 * a derivative), the sample (its index plus `offset`) and the channel. */
brdffit_status bf_model_check_outputs(const brdffit_model *m, size_t n, size_t n_channels,
                                      const double *values, const double *jacobian,
                                      size_t offset, brdffit_error *err);

#endif /* BRDFFIT_MODELS_MODELS_H */
