/* A second cancel flag for an optimizer, for the layers above (the fit
 * forwards its own cancel request with it). Not installed. */
#ifndef BRDFFIT_OPTIM_WATCH_H
#define BRDFFIT_OPTIM_WATCH_H

#include <stdatomic.h>

#include "brdffit/optim.h"

/* Make opt stop also while *flag is non-zero: its runs (before every
 * iteration and inside the step solves, with BRDFFIT_STOP_CANCELLED) and
 * brdffit_optimizer_covariance() and brdffit_optimizer_std_errors()
 * (which then give BRDFFIT_E_NOT_READY). The flag is only read, never
 * consumed; it must outlive opt's use of it. NULL stops watching. */
void bf_optim_watch(brdffit_optimizer *opt, const atomic_int *flag);

#endif /* BRDFFIT_OPTIM_WATCH_H */
