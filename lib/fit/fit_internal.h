/* Internal layout of a fit handle: its options and the result of its last
 * run. Not installed. */
#ifndef BRDFFIT_FIT_INTERNAL_H
#define BRDFFIT_FIT_INTERNAL_H

#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>

#include "brdffit/fit.h"
#include "fit/result.h"

struct brdffit_fit {
    uint32_t magic; /* BF_MAGIC_FIT */
    brdffit_allocator alloc;
    const brdffit_grid *grid;
    const brdffit_model *model;
    size_t nc;     /* grid channels */
    size_t n_vec;  /* model vector size for nc */
    char message[BF_FIT_MESSAGE_SIZE];

    /* options */
    brdffit_pipeline pipeline;
    double cap;
    unsigned weighting;
    double clearcoat;
    size_t threads;
    size_t max_iterations;
    brdffit_objective objective;
    int plausible;              /* BRDFFIT_FIT_PLAUSIBLE */
    int sandwich;               /* BRDFFIT_FIT_COVARIANCE: 1 sandwich (HC3), 0 classic */
    brdffit_damping damping;
    double *start;              /* n_vec: start values (model defaults unless set) */
    unsigned char *fixed;       /* per declared parameter */
    brdffit_iteration_fn callback;
    void *callback_user;
    atomic_int cancel;
    int running; /* inside brdffit_fit_run(): changes are refused */

    /* brdffit_fit_many()'s private fits: what every item of the batch
     * shares, read only, and this thread's scratch for it (many_scan.h);
     * NULL for every other fit */
    const struct bf_batch *batch;
    double *batch_work;
    /* no standard errors or covariance: their eigen-decomposition (and the
     * sandwich's pass) skipped, both left 0; set by brdffit_fit_many()
     * when its caller asks for no standard errors, 0 for every other fit */
    int no_errors;

    /* the last run's result (valid when has_result; passes always) */
    int has_result;
    bf_result result;
};

#endif
