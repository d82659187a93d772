/* The sandwich covariance for a problem in normal-equation form, whose
 * rows the optimizer never sees: the layer above (the fit) reads the
 * pseudo-inverse of J^T J at the returned point, computes the meat
 * sum_i (r_i / (1 - h_i))^2 J_i J_i^T from its own rows with the
 * leverages h_i = J_i (J^T J)^+ J_i^T, and hands it back; the covariance
 * and standard errors of the handle are then the sandwich's, with the
 * same analysed set, cut-off and undetermined parameters as the
 * optimizer's own (analysis.c). Also the standard errors and covariance
 * of a run at once (the fit takes both after every LM run). Not
 * installed. */
#ifndef BRDFFIT_OPTIM_SANDWICH_H
#define BRDFFIT_OPTIM_SANDWICH_H

#include "brdffit/optim.h"

/* (J^T J)^+ over the analysed set (neither fixed nor on a bound) at the
 * point a successful run returned, p x p row-major, 0 in the rows and
 * columns of the other parameters; the pseudo-inverse the covariance
 * uses (after scaling to unit diagonal, eigenvalues below 1e-14 of the
 * largest dropped). Returns 0 (bread untouched or partly written) when
 * the watched flag (watch.h) stopped it. Overwrites the handle's scratch
 * arrays (as the covariance accessors do). */
int bf_optim_bread(const brdffit_optimizer *opt, double *bread);

/* Make meat (p x p, row-major, in the optimizer's parameters; copied)
 * the middle of the covariance of the last successful run:
 * brdffit_optimizer_covariance() and brdffit_optimizer_std_errors() then
 * give (J^T J)^+ meat (J^T J)^+ until the next run. */
void bf_optim_set_meat(brdffit_optimizer *opt, const double *meat);

/* brdffit_optimizer_std_errors() and brdffit_optimizer_covariance() at
 * once, the sandwich's or the classic ones: the same values bit for bit
 * and the same statuses, from one pseudo-inverse of J^T J instead of
 * two. */
brdffit_status bf_optim_std_errors_covariance(const brdffit_optimizer *opt, double *se,
                                              double *cov);

#endif /* BRDFFIT_OPTIM_SANDWICH_H */
