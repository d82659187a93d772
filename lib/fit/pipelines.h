/* The fit pipelines, each a sequence of stages over one run: it writes
 * the natural parameters and standard errors into run->result and keeps
 * the report of its final LM run there (bf_result_keep_report). Not
 * installed.
 *   auto.c    variable projection (varpro.c), the global scan (scan.c) and
 *             an LM polish of the best minima
 *   joint.c   one LM run over everything, and the thesis's two stages
 * A new pipeline is one more function here and one more line in the table
 * of run.c. */
#ifndef BRDFFIT_FIT_PIPELINES_H
#define BRDFFIT_FIT_PIPELINES_H

#include "fit/stage.h"

typedef brdffit_status (*bf_pipeline_fn)(bf_run *run);

brdffit_status bf_pipeline_auto(bf_run *run);
brdffit_status bf_pipeline_joint(bf_run *run);
brdffit_status bf_pipeline_two_stage(bf_run *run);

#endif
