/* Internal layout of a model handle, for lib/models only (the other layers
 * use models/models.h and models/basis.h). Not installed. */
#ifndef BRDFFIT_MODEL_INTERNAL_H
#define BRDFFIT_MODEL_INTERNAL_H

#include <stdint.h>

#include "brdffit/model.h"
#include "models/models.h"

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
    /* Built-in models: their specular lobes (models/lobes.h); NULL for user
     * models and built-ins without a lobe of a linear colour. */
    const struct bf_lobes *lobes;
    /* Built-in models with a coat over their base lobe (models/lobes.h);
     * NULL for the others. */
    const struct bf_coat *coat;
    /* Built-in models affine in one per-channel colour: 1 + its declared
     * index (bf_builtin.affine in models/kernel.h); 0 for the others. */
    size_t affine;
};

/* The lobes of built-in model b (lobes.c), NULL when it has none. */
struct bf_builtin;
const struct bf_lobes *bf_builtin_lobes(const struct bf_builtin *b);
/* The coat of built-in model b (lobes.c), NULL when it has none. */
const struct bf_coat *bf_builtin_coat(const struct bf_builtin *b);

#endif /* BRDFFIT_MODEL_INTERNAL_H */
