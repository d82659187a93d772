/* The result of one fit run, and the one way the fit words its error
 * messages. A run (run.c) fills one bf_result and hands it to the handle
 * (fit.c); the pipelines write into the run's result, never into the
 * handle. Not installed. */
#ifndef BRDFFIT_FIT_RESULT_H
#define BRDFFIT_FIT_RESULT_H

#include <stddef.h>

#include "brdffit/optim.h"
#include "fit/trace.h"

#define BF_FIT_MESSAGE_SIZE 512

typedef struct bf_result {
    /* natural units, vector layout; storage lent by the handle */
    double *params;             /* n_vec */
    double *std_errors;         /* n_vec */
    double *cov;                /* n_vec * n_vec, the std errors' covariance; NULL when
                                 * n_vec > BRDFFIT_FIT_MAX_PARAMS (two-stage only) */
    double *metrics;            /* 4 * nc: see BF_PASS_METRICS */
    brdffit_stop_reason stop;   /* of the final LM run */
    size_t iterations;          /* of the final LM run */
    size_t passes;              /* over the samples, the whole run */
    double mean_error;          /* E's sum for each channel's best constant (fit/summary.h) */
    double mean_plain;          /* e's sum for the same */
    double mean_cost;           /* the squares cost of the same */
    double *history;            /* 2 * history_len: costs then lambdas; owned */
    size_t history_len;
    bf_trace trace;             /* every stage and the whole history; owned */
    char *message;              /* BF_FIT_MESSAGE_SIZE bytes (lent): why the run failed */
} bf_result;

/* Write the message (printf format) into `message` (BF_FIT_MESSAGE_SIZE
 * bytes) and return `status`: every error message of the fit is made
 * here. */
brdffit_status bf_say(char *message, brdffit_status status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* Keep the report of the final LM run `opt` (NULL: cancelled before any
 * LM run) in r: stop reason, iterations and a copy of the history. */
brdffit_status bf_result_keep_report(bf_result *r, const brdffit_optimizer *opt,
                                     const brdffit_allocator *a);

#endif /* BRDFFIT_FIT_RESULT_H */
