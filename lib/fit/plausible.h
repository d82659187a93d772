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

/* The cheap bounds of bf_plausible_bounds(st, 0) at the shape at st->p,
 * one per linear parameter (HUGE_VAL: none) into bound, before they are
 * set; 0 (bound untouched) where plausibility sets none. They depend on
 * the shape alone: a batch computes them once per scan point
 * (many_scan.h). */
int bf_plausible_cheap(const bf_stage *st, double *bound);

/* Set the upper bounds of every free colour entry from bound (the cheap
 * ones or the integrals), as bf_plausible_bounds() does. */
void bf_plausible_apply(bf_stage *st, const double *bound);

/* Whether every colour of `params` lies within the bounds last set (to
 * 1e-9 relative). */
int bf_plausible_within(const bf_stage *st, const double *params);

/* Clamp every colour of `params` into the bounds last set. */
void bf_plausible_clamp(const bf_stage *st, double *params);

#endif
