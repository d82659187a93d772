/* Internal layout of a model handle. Not installed. */
#ifndef BRDFFIT_MODEL_INTERNAL_H
#define BRDFFIT_MODEL_INTERNAL_H

#include <stdint.h>

#include "brdffit/model.h"

struct brdffit_model {
    uint32_t magic; /* BF_MAGIC_MODEL */
    brdffit_allocator alloc;
    char *name;
    size_t n_params;
    brdffit_param_info *params; /* names owned */
    brdffit_model_eval_fn eval;
    void *user;
    void (*destroy)(void *user);
    /* Built-in models: their basis form (models/kernel.h), which lets fits
     * accumulate the normal equations from channel-independent sums. NULL
     * for user models. */
    const struct bf_kernel *kernel;
};

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

#endif /* BRDFFIT_MODEL_INTERNAL_H */
