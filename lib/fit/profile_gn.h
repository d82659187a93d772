/* The profile under an objective other than the squares: the colours of a
 * shape point carried from the squared-value solution (varpro.h) to the
 * objective's own optimum by a few projected Gauss-Newton steps of the
 * small bounded colour problem, so the auto scan compares shapes by their
 * true objective cost. Not installed. */
#ifndef BRDFFIT_FIT_PROFILE_GN_H
#define BRDFFIT_FIT_PROFILE_GN_H

#include "fit/stage.h"

/* At most this many Gauss-Newton steps per shape point. */
#define BF_PROFILE_GN_STEPS 8

/* st->p holds a shape point and feasible colours (bf_varpro_profile()'s):
 * under the squares objective nothing changes; otherwise the colours of
 * every channel (entries held fixed stay) are moved by projected
 * Gauss-Newton steps with step halving, each step lowering the
 * objective's cost, and *cost becomes the objective's cost at the final
 * st->p. */
brdffit_status bf_profile_gn(bf_stage *st, double *cost);

/* As bf_profile_gn(), but the steps start from the colours of `warm` (a
 * parameter vector of the stage, e.g. the previous scan point's result;
 * clamped into st's bounds) when their objective cost is lower than the
 * squared-value colours'; warm NULL is bf_profile_gn(). */
brdffit_status bf_profile_gn_from(bf_stage *st, const double *warm, double *cost);

#endif
