/* The routes of a pass: how one chunk of samples is accumulated. The
 * driver (pass.c) loads the weights and the measured values of a chunk and
 * hands them to the problem's route: the generic route (pass_generic.c,
 * any model, through its evaluation callback) or the basis route
 * (pass_basis.c, models in basis form). A new route is one more bf_route
 * and one more line in the table of pass.c. Not installed. */
#ifndef BRDFFIT_FIT_PASS_ROUTE_H
#define BRDFFIT_FIT_PASS_ROUTE_H

#include <stddef.h>

#include "fit/pass.h"

/* Per-thread scratch, carved out of one allocation. */
typedef struct bf_scratch {
    double *w, *wsa, *ww, *d;  /* BF_CHUNK each */
    double *meas, *pres;       /* nc * BF_CHUNK: measured value, 1 if present else 0 */
    double *vals;              /* nc * BF_CHUNK */
    double *own;               /* the route's scratch_size() doubles */
    double *acc;               /* the thread's accumulator, acc_size() doubles */
    size_t first;              /* the chunk's first sample */
    size_t chunk;              /* the chunk's index in the weight plan */
} bf_scratch;

typedef struct bf_route {
    /* bit (1 << kind): the kinds of pass this route accumulates; the
     * generic route takes the others */
    unsigned kinds;
    /* whether the route can serve the problem */
    int (*serves)(const bf_problem *pb);
    /* doubles of the route's per-thread accumulator and own scratch */
    size_t (*acc_size)(const bf_problem *pb, bf_pass_kind kind);
    size_t (*scratch_size)(const bf_problem *pb);
    /* accumulate the chunk of `batch` (weights and measured values in sc) */
    brdffit_status (*chunk)(const bf_problem *pb, bf_pass_kind kind, const double *params,
                            bf_scratch *sc, const brdffit_batch *batch, brdffit_error *err);
    /* turn the summed accumulators into the layout of pass.h */
    void (*finish)(const bf_problem *pb, bf_pass_kind kind, const double *params,
                   const double *part, double *acc);
    /* optional (NULL: none): accumulate chunks [c0, c1) of the plan at
     * once, the driver loading neither weights nor measured values;
     * returns 0, having done nothing, when it does not take the pass (the
     * driver then hands it the chunks one by one) */
    int (*block)(const bf_problem *pb, bf_pass_kind kind, const double *params, bf_scratch *sc,
                 size_t c0, size_t c1);
} bf_route;

extern const bf_route bf_route_generic; /* pass_generic.c */
extern const bf_route bf_route_basis;   /* pass_basis.c */
extern const bf_route bf_route_colour;  /* pass_colour.c: SHAPE and the colour passes */

/* Whether the driver leaves the chunk's measured values unloaded because
 * the basis route reads them in place (pass_fused.h). */
int bf_basis_in_place(const bf_problem *pb, bf_pass_kind kind);

/* Whether the driver leaves the chunk's measured values and presence
 * unloaded because the colour route reads none (pass_colour.c): SHAPE,
 * and the colour passes under an objective that takes the measured values
 * from the terms alone on a grid without missing values. */
int bf_colour_in_place(const bf_problem *pb, bf_pass_kind kind);

/* Whether the driver leaves the chunk's measured values and presence
 * unloaded because the generic route reads them in place
 * (pass_generic.c): METRICS on a grid without missing values, the values
 * neither clear-coat compensated nor averaged over the channels. */
int bf_generic_in_place(const bf_problem *pb, bf_pass_kind kind);

/* The objective's terms of n samples that depend on the measured values
 * and the geometry alone (pb->terms, pass.h), c = max(lz, 0): log
 * tm = log(1 + c M); cube-root tm = cbrt(c M) and, when tc is not NULL,
 * tc = cbrt(c); relative tm = 1 / (|M| + delta). */
void bf_objective_terms(const bf_problem *pb, const double *meas, const double *lz, size_t n,
                        double *tm, double *tc);

/* Objective residuals rd = rw r(val, meas) of channel m's n rows from
 * sample `first` (brdffit_objective in fit.h), and the row factors
 * rw dr/dR into rw (in place); lz is the rows' cos theta_i, the terms come
 * from pb->terms. rw holds each row's weight on entry; a row of weight 0
 * (outside the fit or missing) gives 0. Under the squares objective the
 * rows are rw (val - meas) and rw stays. The generic route and the basis
 * route both transform their rows with it (pass_generic.c). */
void bf_objective_rows(const bf_problem *pb, size_t m, size_t first, const double *meas,
                       const double *val, const double *lz, size_t n, double *rd, double *rw);

/* The row factors of bf_objective_rows() at val = meas, from the terms
 * alone (no transcendental function): rw *= dT/dM at M = meas, rw holding
 * each row's weight on entry, for the colour route's linearised VARPRO
 * (pass_colour.c). Under the relative objective the rows are linear in M
 * and the factors exact; under the squares rw stays. */
void bf_objective_slopes(const bf_problem *pb, size_t m, size_t first, const double *meas,
                         const double *lz, size_t n, double *rw);

/* The passes' dot product is bf_dot() of core/linalg.h. */

#endif /* BRDFFIT_FIT_PASS_ROUTE_H */
