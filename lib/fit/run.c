/* One fit run: see run.h. */
#include "fit/run.h"

#include <math.h>
#include <string.h>

#include "core/core.h"
#include "fit/pipelines.h"

/* Indexed by brdffit_pipeline. */
static const bf_pipeline_fn pipelines[] = {bf_pipeline_auto, bf_pipeline_joint,
                                           bf_pipeline_two_stage};

static brdffit_status make_plans(bf_run *run)
{
    const brdffit_fit *fit = run->fit;
    brdffit_error err;
    brdffit_status status =
        bf_weight_plan_init(&run->plan, fit->grid, fit->cap, fit->weighting, &fit->alloc, &err);
    if (status == BRDFFIT_OK) {
        status = bf_weight_plan_init(&run->plan_sa, fit->grid, fit->cap,
                                     BRDFFIT_WEIGHT_SOLID_ANGLE, &fit->alloc, &err);
        if (status != BRDFFIT_OK) bf_weight_plan_free(&run->plan, &fit->alloc);
    }
    if (status != BRDFFIT_OK)
        bf_say(run->result->message, status, "%s",
               status == BRDFFIT_E_OUT_OF_MEMORY ? "out of memory" : err.message);
    return status;
}

/* The fit squares the measured values: keep them where their squares
 * neither underflow nor overflow. */
#define BF_FIT_VALUE_MIN 1e-100
#define BF_FIT_VALUE_MAX 1e100

/* Largest measured value inside the cap (missing values are stored as 0). */
static double largest_value(const bf_run *run)
{
    double w[BF_CHUNK], top = 0.0;
    size_t ci, first, n;
    for (ci = 0; ci < run->plan.n_chunks; ci++) {
        bf_weight_plan_chunk(&run->plan, ci, &first, &n, w);
        top = fmax(top, bf_grid_largest_value(run->fit->grid, first, n));
    }
    return top;
}

static brdffit_status check_scale(bf_run *run)
{
    double top = largest_value(run);
    if (top == 0.0 || (top >= BF_FIT_VALUE_MIN && top <= BF_FIT_VALUE_MAX)) return BRDFFIT_OK;
    return bf_say(run->result->message, BRDFFIT_E_RANGE,
                  "the largest measured value inside the cap, %g, lies outside [%g, %g]; "
                  "rescale the data (the colours scale with it)",
                  top, BF_FIT_VALUE_MIN, BF_FIT_VALUE_MAX);
}

/* Nothing to fit: every value with a non-zero weight inside the cap is
 * missing (or the cap leaves no sample). */
static brdffit_status check_rows(bf_run *run)
{
    if (bf_grid_has_rows(&run->plan)) return BRDFFIT_OK;
    return bf_say(run->result->message, BRDFFIT_E_NO_DATA,
                  "no measured value inside the cap: every value with a non-zero weight there "
                  "is missing");
}

/* Helper threads for the run: one per pass block beyond the caller's. */
static size_t helper_count(const bf_run *run)
{
    size_t blocks = run->fit->threads < BF_MAX_THREADS ? run->fit->threads : BF_MAX_THREADS;
    if (blocks > run->plan.n_chunks) blocks = run->plan.n_chunks;
    return blocks > 1 ? blocks - 1 : 0;
}

/* Error figures of the final parameters (BF_PASS_METRICS). */
static brdffit_status final_metrics(bf_run *run)
{
    bf_result *r = run->result;
    bf_stage st;
    brdffit_status status = bf_stage_init(&st, run, run->fit->nc, BF_SOURCE_CHANNELS, 0, 0);
    if (status != BRDFFIT_OK) return status;
    memcpy(st.p, r->params, st.n * sizeof *st.p);
    status = bf_stage_pass(&st, BF_PASS_METRICS);
    if (status == BRDFFIT_OK) memcpy(r->metrics, st.acc, 4 * run->fit->nc * sizeof(double));
    else status = bf_stage_fail(&st, status, "error figures");
    bf_stage_free(&st);
    return status;
}

/* The pipeline and the error figures, with the run's helper threads. */
static brdffit_status run_stages(bf_run *run)
{
    brdffit_status status;
    bf_pool_start(&run->pool, helper_count(run));
    status = pipelines[run->fit->pipeline](run);
    if (status == BRDFFIT_OK) status = final_metrics(run);
    bf_pool_stop(&run->pool);
    if (status == BRDFFIT_OK && run->cancelled) run->result->stop = BRDFFIT_STOP_CANCELLED;
    return status;
}

brdffit_status bf_run_fit(brdffit_fit *fit, bf_result *out)
{
    bf_run run;
    brdffit_status status;
    memset(&run, 0, sizeof run);
    run.fit = fit;
    run.result = out;
    BF_RETURN_IF_ERROR(make_plans(&run));
    status = check_scale(&run);
    if (status == BRDFFIT_OK) status = check_rows(&run);
    if (status == BRDFFIT_OK) status = run_stages(&run);
    bf_weight_plan_free(&run.plan, &fit->alloc);
    bf_weight_plan_free(&run.plan_sa, &fit->alloc);
    if (status == BRDFFIT_E_OUT_OF_MEMORY) bf_say(out->message, status, "out of memory");
    return status;
}
