/* The baseline of the verdict's "no better than the mean" warning: the
 * error, in Ngan's measure E and in the plain e (brdffit_fit_metric), of
 * the best constant value per channel. Not installed. */
#ifndef BRDFFIT_FIT_BASELINE_H
#define BRDFFIT_FIT_BASELINE_H

#include "fit/stage.h"

/* Into run->result->mean_error: the sum over channels c of
 * min over mu of sum_s a_s cos^2(theta_i) (R_cs - mu)^2 over the active,
 * present samples, a_s the solid-angle weight (the same sum as the
 * numerator of E, with the model replaced by the best constant); into
 * mean_plain the same unweighted (e's sum), into mean_cost weighted by the
 * fit's residual weights (the squares objective's cost). */
void bf_baseline_mean_error(bf_run *run);

#endif
