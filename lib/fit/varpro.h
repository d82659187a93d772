/* Variable projection: the profile cost of the shape parameters, the
 * linear (colour) parameters solved exactly and inside their bounds for
 * every channel (fit/lsq.h). Not installed. */
#ifndef BRDFFIT_FIT_VARPRO_H
#define BRDFFIT_FIT_VARPRO_H

#include "fit/stage.h"

/* The profile cost at the natural point st->p (shape entries set, free
 * linear entries ignored): the best bounded colours of every channel are
 * written into st->p and the cost into *cost. Held linear entries
 * (st->fixed) are constants at their values in st->p and only the free
 * ones are solved. `kind` is the pass of the sums: BF_PASS_VARPRO, or
 * BF_PASS_COLOUR_VARPRO from the shape cache filled at st->p's shape
 * (fit/pass.h). Needs bf_layout_projectable(). */
brdffit_status bf_varpro_profile(bf_stage *st, bf_pass_kind kind, double *cost);

/* The solve of bf_varpro_profile() alone, from a VARPRO pass's sums
 * already in st->acc (a batch's shared scan basis gives them without a
 * pass, many_scan.h), with bf_bounded_lsq_quick(): the same colours up
 * to rounding, for the scan's many points. */
void bf_varpro_solve(bf_stage *st, double *cost);

#endif
