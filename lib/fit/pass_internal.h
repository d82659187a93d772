/* What the two implementations of a pass share: the generic one (pass.c,
 * any model, through its evaluation callback) and the basis one
 * (pass_basis.c, built-in models). Not installed. */
#ifndef BRDFFIT_FIT_PASS_INTERNAL_H
#define BRDFFIT_FIT_PASS_INTERNAL_H

#include <stddef.h>

#include "fit/pass.h"
#include "models/kernel.h"

/* Per-thread scratch, carved out of one allocation. */
typedef struct scratch {
    double *w, *wsa, *ww, *d;  /* BF_CHUNK each */
    double *meas, *pres;       /* nc * BF_CHUNK: measured value, 1 if present else 0 */
    double *vals;              /* nc * BF_CHUNK */
    double *jac;               /* n_params * nc * BF_CHUNK (generic), or NULL */
    double *basis;             /* bf_basis_scratch_size() doubles (basis pass) */
    double *acc;               /* the thread's accumulator */
} scratch;

/* Sum of a[s] * b[s] in a fixed order (four partial sums). */
double bf_pass_dot(const double *restrict a, const double *restrict b, size_t n);

/* Measured values and presence of samples [first, first + n) into sc. */
void bf_pass_load_measured(const bf_problem *pb, size_t first, size_t n, scratch *sc);

/* ---- the basis pass --------------------------------------------------------- */

/* Whether the basis pass can serve this problem (a built-in model and no
 * missing values: then every channel's rows share one set of weights). */
int bf_basis_usable(const bf_problem *pb);

/* Doubles of the basis pass's per-thread accumulator and scratch. */
size_t bf_basis_acc_size(const bf_problem *pb, bf_pass_kind kind);
size_t bf_basis_scratch_size(const bf_problem *pb);

/* Accumulate chunk [first, first + n) (weights and measured values already
 * in sc) into sc->acc in the basis layout. `work` has
 * bf_basis_scratch_size() doubles. */
void bf_basis_chunk(const bf_problem *pb, bf_pass_kind kind, const double *params, scratch *sc,
                    const brdffit_batch *batch, double *work);

/* Turn summed basis accumulators into the layout of pass.h. */
void bf_basis_finish(const bf_problem *pb, bf_pass_kind kind, const double *params,
                     const double *basis_acc, double *acc);

#endif
