/* The vector layout of a model: see layout.h. */
#include "fit/layout.h"

#include "models/basis.h"

void bf_layout_init(bf_layout *ly, const brdffit_model *model, size_t nc)
{
    size_t k, colour;
    ly->nc = nc;
    ly->n_params = brdffit_model_param_count(model);
    ly->n_vec = brdffit_model_vector_size(model, nc);
    ly->n_linear = 0;
    for (k = 0; k < ly->n_params; k++) {
        if (!(brdffit_model_param(model, k)->flags & BRDFFIT_PARAM_LINEAR)) continue;
        if (ly->n_linear < BF_LSQ_MAX) ly->linear[ly->n_linear] = k;
        ly->n_linear++;
    }
    ly->offset = ly->n_linear == 0 && bf_model_affine(model, &colour);
    if (ly->offset) {
        ly->linear[0] = colour;
        ly->n_linear = 1;
    }
}

void bf_layout_entries(const bf_layout *ly, const brdffit_model *model, size_t *vindex,
                       size_t *decl)
{
    size_t k, m;
    for (k = 0; k < ly->n_params; k++)
        for (m = 0; m < ly->nc; m++) {
            size_t e = brdffit_model_vector_index(model, k, m, ly->nc);
            vindex[k * ly->nc + m] = e;
            if (decl != NULL) decl[e] = k;
        }
}

int bf_layout_projectable(const bf_layout *ly)
{
    return ly->n_linear <= BF_LSQ_MAX;
}
