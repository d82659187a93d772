/* The canonical order of a two-lobe result: the sharper lobe first.
 * Not installed. */
#ifndef BRDFFIT_FIT_CANONICAL_H
#define BRDFFIT_FIT_CANONICAL_H

#include "fit/stage.h"

/* For a model with shape parameters "<x>1", "<x>2" (consecutive) and
 * colours "cs1", "cs2" whose two lobes are the same function (the built-in
 * two-lobe models), swap the lobes of run->result (values and standard
 * errors) unless lobe 1 is already the sharper: the larger exponent for a
 * shape named "ns<i>", the smaller roughness otherwise. Nothing changes
 * when either lobe's parameters are held fixed. */
void bf_canonical_lobes(bf_run *run);

#endif
