/* The record of a fit run's stages (fit.h, brdffit_fit_stage_info()): one
 * entry per stage (the auto scan, each LM run) with its label and report,
 * and the run's whole history, every entry labelled with its stage. Filled
 * by the stages as they run (scan.c, stage.c), owned by the run's result.
 * Not installed. */
#ifndef BRDFFIT_FIT_TRACE_H
#define BRDFFIT_FIT_TRACE_H

#include <stddef.h>

#include "brdffit/fit.h"

typedef struct bf_trace_entry {
    double cost, lambda;
    size_t stage;
} bf_trace_entry;

typedef struct bf_trace {
    brdffit_fit_stage *stages;
    size_t n_stages, cap_stages;
    bf_trace_entry *entries;
    size_t n_entries, cap_entries;
} bf_trace;

void bf_trace_free(bf_trace *t, const brdffit_allocator *a);

/* One profile evaluation of auto's scan at cost `cost`: the entry is the
 * lowest cost of the scan so far (a scan stage opens when the last stage is
 * not one). */
brdffit_status bf_trace_scan(bf_trace *t, const brdffit_allocator *a, double cost);

/* The report and history of the LM run `opt` as a stage of kind `kind`
 * (label `index`), kept (brdffit_fit_stage.kept) until bf_trace_keep()
 * says otherwise; its stage number into *stage. */
brdffit_status bf_trace_lm(bf_trace *t, const brdffit_allocator *a, brdffit_fit_stage_kind kind,
                           size_t index, const brdffit_optimizer *opt, size_t *stage);

/* Mark whether stage `stage`'s result is part of the returned parameters. */
void bf_trace_keep(bf_trace *t, size_t stage, int kept);

/* Whether the record shows a converged fit: some LM stage is kept and every
 * kept one converged. */
int bf_trace_converged(const bf_trace *t);

#endif /* BRDFFIT_FIT_TRACE_H */
