/* The layout of a model's parameter vector for a number of channels, as
 * every part of a fit sees it: computed once per stage by bf_layout_init().
 * Not installed. */
#ifndef BRDFFIT_FIT_LAYOUT_H
#define BRDFFIT_FIT_LAYOUT_H

#include <stddef.h>

#include "brdffit/model.h"
#include "fit/lsq.h"

typedef struct bf_layout {
    size_t nc;                 /* channels */
    size_t n_params;           /* declared parameters */
    size_t n_vec;              /* vector entries: shared ones once, per-channel ones nc times */
    size_t n_linear;           /* declared linear parameters, all of them */
    size_t linear[BF_LSQ_MAX]; /* the declared indices of the first BF_LSQ_MAX of them */
    int offset;                /* the model is affine in its one colour (models/basis.h,
                                * bf_model_affine()): it is linear[0] (n_linear 1), and
                                * the values carry a colour-free offset B */
} bf_layout;

/* The layout of `model` for `nc` channels. A model affine in one colour
 * and with no LINEAR parameter has that colour as its one linear
 * parameter, with the offset flag set: variable projection (varpro.h)
 * solves it with the offset moved to the right-hand side. */
void bf_layout_init(bf_layout *ly, const brdffit_model *model, size_t nc);

/* The entries of the layout: vindex receives n_params * nc values,
 * [k * nc + m] the vector index of declared parameter k in channel m (a
 * shared parameter has one entry, repeated for every m); decl (NULL, or
 * n_vec values) the declared parameter of each vector entry. */
void bf_layout_entries(const bf_layout *ly, const brdffit_model *model, size_t *vindex,
                       size_t *decl);

/* Whether variable projection can solve the linear parameters exactly:
 * at most BF_LSQ_MAX of them. */
int bf_layout_projectable(const bf_layout *ly);

#endif /* BRDFFIT_FIT_LAYOUT_H */
