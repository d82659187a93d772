/* Physical plausibility of the auto pipeline (BRDFFIT_FIT_PLAUSIBLE in
 * fit.h): box bounds on the colours that keep each term's directional
 * albedo at most 1 at the current shape. Not installed. */
#ifndef BRDFFIT_FIT_PLAUSIBLE_H
#define BRDFFIT_FIT_PLAUSIBLE_H

#include "fit/stage.h"

/* With plausibility on, set the upper bounds (natural and optimiser space)
 * of every free colour entry for the shape at st->p: the model's bound,
 * cd <= 1 for a colour named "cd", and with `full` also 1 / A when lower,
 * A the term's largest directional albedo per unit colour (an integral per
 * term: the polish's bounds; the scan takes the cheap ones alone). Off, or
 * for a model without colours, nothing changes. */
brdffit_status bf_plausible_bounds(bf_stage *st, int full);

/* Whether every colour of `params` lies within the bounds last set (to
 * 1e-9 relative). */
int bf_plausible_within(const bf_stage *st, const double *params);

/* Clamp every colour of `params` into the bounds last set. */
void bf_plausible_clamp(const bf_stage *st, double *params);

#endif
