/* Helpers for the tests of one pass (lib/fit/pass.h): the default axes
 * with known measurements, and a problem's fields as a stage sets them. */
#ifndef BRDFFIT_PASS_FIXTURES_H
#define BRDFFIT_PASS_FIXTURES_H

#include <stddef.h>

#include "fit/pass.h"

/* The default axes with fx_value() measurements on nc channels (asserts). */
brdffit_grid *fx_pass_grid(size_t nc);

/* Zero *pb and set what a stage sets before bf_pass_prepare(): grid,
 * model, the plan as both weight plans, channels, source, clear coat, one
 * thread and the model's layout for nc channels. */
void fx_pass_problem(bf_problem *pb, const brdffit_grid *grid, const brdffit_model *model,
                     const bf_weight_plan *plan, size_t nc, bf_source source, double coat);

/* Each declared parameter of the problem's model at its start value, a
 * per-channel one 10 % apart per channel (a start of 0 becomes 0.05 plus
 * 0.02 per channel), inside its bounds, into params at pb->vindex. */
void fx_pass_start(const bf_problem *pb, double *params);

#endif /* BRDFFIT_PASS_FIXTURES_H */
