/* The table of built-in models and their creation by name. */
#include <string.h>

#include "core/core.h"
#include "models/kernel.h"
#include "models/model_internal.h"

static const bf_builtin *const builtins[] = {
    &bf_builtin_lambert,
    &bf_builtin_phong,
    &bf_builtin_blinn_phong,
    &bf_builtin_ashikhmin_shirley,
    &bf_builtin_ashikhmin_shirley_fresnel,
    &bf_builtin_ashikhmin_shirley_2,
    &bf_builtin_cook_torrance,
    &bf_builtin_cook_torrance_2,
    &bf_builtin_ggx,
    &bf_builtin_ggx_2,
    &bf_builtin_ward,
    &bf_builtin_ward_duer,
    &bf_builtin_lafortune,
    &bf_builtin_gltf,
    &bf_builtin_gltf_clearcoat,
    &bf_builtin_openpbr,
    &bf_builtin_openpbr_coat,
};

enum { BF_N_BUILTINS = sizeof builtins / sizeof builtins[0] };

size_t brdffit_model_builtin_count(void)
{
    return BF_N_BUILTINS;
}

const char *brdffit_model_builtin_name(size_t index)
{
    return index < BF_N_BUILTINS ? builtins[index]->name : NULL;
}

static const bf_builtin *find_builtin(const char *name)
{
    size_t i;
    for (i = 0; i < BF_N_BUILTINS; i++)
        if (strcmp(builtins[i]->name, name) == 0) return builtins[i];
    return NULL;
}

brdffit_status brdffit_model_create(brdffit_model **out, const char *name,
                                    const brdffit_allocator *alloc, brdffit_error *err)
{
    brdffit_model_def def = BRDFFIT_MODEL_DEF_INIT;
    const bf_builtin *b;
    if (out == NULL) return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "out is NULL");
    *out = NULL;
    if (name == NULL) return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "model name is NULL");
    b = find_builtin(name);
    if (b == NULL) return bf_fail(err, BRDFFIT_E_NOT_FOUND, "no built-in model named \"%s\"", name);
    def.name = b->name;
    def.n_params = b->n_params;
    def.params = b->params;
    def.eval = b->eval;
    BF_RETURN_IF_ERROR(brdffit_model_create_custom(out, &def, alloc, err));
    (*out)->kernel = b->kernel;
    (*out)->lobes = bf_builtin_lobes(b);
    (*out)->coat = bf_builtin_coat(b);
    (*out)->affine = b->affine;
    return BRDFFIT_OK;
}
