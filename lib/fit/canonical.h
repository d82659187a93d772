/* The canonical order of a two-lobe result: the sharper lobe first.
 * Not installed. */
#ifndef BRDFFIT_FIT_CANONICAL_H
#define BRDFFIT_FIT_CANONICAL_H

#include "fit/stage.h"

/* For a model whose description has two interchangeable lobes (the
 * built-in two-lobe models; models/lobes.h), swap the lobes of run->result
 * (their sharpness and colours: values, standard errors and the rows and
 * columns of the covariance) unless lobe 1
 * is already the sharper: the larger value of a sharpness that grows with
 * it (an exponent), the smaller otherwise (a roughness). Nothing changes
 * when either lobe's parameters are held fixed. */
void bf_canonical_lobes(bf_run *run);

#endif
