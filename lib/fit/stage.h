/* A stage: one binding of the fit's grid and model in one channel layout,
 * with the mapping between natural parameters and the optimiser's space
 * (log for logarithmic-scale parameters), and one Levenberg-Marquardt run
 * over it: natural units in, natural units out, into the caller's arrays.
 * Every pipeline is a sequence of stages. Not installed. */
#ifndef BRDFFIT_FIT_STAGE_H
#define BRDFFIT_FIT_STAGE_H

#include <stddef.h>

#include "fit/fit_internal.h"
#include "fit/pass.h"
#include "fit/result.h"
#include "fit/summary.h"

/* What one fit run shares between its stages. The handle is only read
 * (options, start values, cancel flag); everything the run produces goes
 * to *result. */
typedef struct bf_run {
    brdffit_fit *fit;
    bf_weight_plan plan, plan_sa;
    bf_pool pool; /* fit->threads - 1 helpers for every pass of the run */
    bf_result *result;
    bf_summary summary; /* what the run needs of the data alone (summary.h) */
    double delta; /* the objective's floor (brdffit_objective) */
    int cancelled;
    int batch_ready; /* a batch's item products are in fit->batch_work (many_scan.h) */
} bf_run;

typedef struct bf_stage {
    bf_run *run;
    bf_problem pb;
    size_t n;               /* vector size */
    size_t *vindex;         /* n_params * nc */
    size_t *decl;           /* n: declared parameter of each entry */
    unsigned char *logs;    /* n: optimised in log space */
    unsigned char *fixed;   /* n: held */
    double *lower, *upper;  /* n: natural bounds */
    double *olower, *oupper;/* n: optimiser-space bounds */
    double *base;           /* n: natural start / held values */
    double *p;              /* n: natural point of the next pass */
    double *x;              /* n: optimiser-space point of the LM run */
    double *shown;          /* n: natural point shown to the user's callback */
    double *acc;            /* accumulator of any pass */
    double *terms;          /* the objective's terms (pb.terms), NULL under squares */
    double *shape;          /* the shape cache (pb.shape) of auto's colour passes, made
                             * by its first profile (profile_gn.h), else NULL */
    double *cov;            /* n * n: covariance of the last LM run's result (natural
                             * units, as its standard errors); made by bf_stage_lm */
    double cost;            /* final cost of the last LM run */
    brdffit_fit_stage_kind kind; /* the label of its LM runs in the trace: */
    size_t label;           /* kind and index (brdffit_fit_stage) */
    size_t traced;          /* the trace's stage number of the last LM run */
    brdffit_optimizer *opt; /* the last LM run's optimizer */
    size_t scan_point;      /* auto's scan: the grid point whose colours are being solved
                             * (scan.h), else (size_t)-1 */
    brdffit_status status;  /* last pass failure, for the message */
    brdffit_error err;
} bf_stage;

/* Set up a stage over `nc` model channels fed by `source`. Fixed entries
 * follow the fit's per-parameter flags; `fix_shared` also holds every
 * shared parameter (the thesis's second stage). */
brdffit_status bf_stage_init(bf_stage *st, bf_run *run, size_t nc, bf_source source,
                             size_t source_channel, int fix_shared);
void bf_stage_free(bf_stage *st);

/* Entry e in natural units from optimiser space (exp for log-scale
 * entries), clamped into its bounds. */
double bf_stage_natural(const bf_stage *st, size_t e, double x);

/* Count a pass of the run and run it at st->p into st->acc; a failure is
 * kept in st->status and st->err for the message. */
brdffit_status bf_stage_pass(bf_stage *st, bf_pass_kind kind);

/* One LM run from natural `start` (clamped into the bounds): the natural
 * result into params and its standard errors into se (n each, the
 * caller's), their covariance into st->cov (the fit's estimator,
 * BRDFFIT_FIT_COVARIANCE; the sandwich's meat from one SANDWICH pass),
 * the final cost into st->cost; st->opt is kept for the
 * history, and the run is recorded in the run's trace as a kept stage
 * labelled st->kind, st->label (its number in st->traced). */
brdffit_status bf_stage_lm(bf_stage *st, const double *start, double *params, double *se);

/* Word a failure of the stage (`what` failed) into the run's message and
 * return the status it reports. */
brdffit_status bf_stage_fail(bf_stage *st, brdffit_status status, const char *what);

#endif
