/* The profile cost of auto at one shape point, under every objective: the
 * colours solved exactly for the squares of values (varpro.h), then, under
 * an objective other than the squares, carried to the objective's own
 * optimum by a few projected Gauss-Newton steps of the small bounded
 * colour problem, so the auto scan compares shapes by their true
 * objective cost. Not installed. */
#ifndef BRDFFIT_FIT_PROFILE_GN_H
#define BRDFFIT_FIT_PROFILE_GN_H

#include "fit/stage.h"

/* At most this many Gauss-Newton steps per shape point. */
#define BF_PROFILE_GN_STEPS 8

/* The profile at st->p's shape (its free colours ignored): the colours
 * into st->p and the objective's cost there into *cost; colours held fixed
 * stay. The colours are solved exactly for the squares of values, then,
 * under another objective, moved by Gauss-Newton steps with step halving,
 * each lowering the objective's cost, until the next step would lower it
 * by less than 1e-6 of itself (1e-12 when `start`: the start of a polish).
 * - A model with a shape cache (bf_pass_shape_size() of fit/pass.h; a
 *   model affine in its colour under every objective, one in basis form
 *   under all but the squares) takes one SHAPE pass (the cache made at the
 *   stage's first call, kept in st->shape) and colour passes over the
 *   cache: under an objective other than the squares the colours are
 *   solved for the objective linearised at the measured values
 *   (COLOUR_VARPRO) and the steps start there.
 * - Any other model takes one VARPRO pass and, for the steps, NORMAL and
 *   COST passes from the squared-value colours, or from those of `warm`
 *   (a parameter vector of the stage, e.g. the previous scan point's
 *   result; clamped into st's bounds) when their objective cost is lower.
 *   warm may be NULL. */
brdffit_status bf_profile_point(bf_stage *st, const double *warm, int start, double *cost);

#endif
