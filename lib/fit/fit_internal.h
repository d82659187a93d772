/* Internal layout of a fit handle and the pipelines. Not installed. */
#ifndef BRDFFIT_FIT_INTERNAL_H
#define BRDFFIT_FIT_INTERNAL_H

#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>

#include "brdffit/fit.h"

#define BF_FIT_MESSAGE_SIZE 512

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
    brdffit_damping damping;
    double *start;              /* n_vec: start values (model defaults unless set) */
    unsigned char *fixed;       /* per declared parameter */
    brdffit_iteration_fn callback;
    void *callback_user;
    atomic_int cancel;

    /* results of the last successful run */
    int has_result;
    double *params;             /* n_vec */
    double *std_errors;         /* n_vec */
    double *metrics;            /* 4 * nc: see BF_PASS_METRICS */
    brdffit_stop_reason stop;
    size_t iterations;
    size_t passes;
    double *history;            /* 2 * history_len: costs then lambdas */
    size_t history_len;
};

/* Run the selected pipeline; fills the result fields. */
brdffit_status bf_fit_execute(brdffit_fit *fit);

#endif
