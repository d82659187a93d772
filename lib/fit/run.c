/* One fit run: see run.h. */
#include "fit/run.h"

#include <math.h>
#include <string.h>

#include "core/core.h"
#include "fit/canonical.h"
#include "fit/many_scan.h"
#include "fit/pipelines.h"
#include "fit/summary.h"

/* Indexed by brdffit_pipeline. */
static const bf_pipeline_fn pipelines[] = {bf_pipeline_auto, bf_pipeline_joint,
                                           bf_pipeline_two_stage};

/* The solid-angle plan of the error figure E and of the log and cube-root
 * objectives. Cells without solid angle (one theta_o or one phi_o inside
 * the cap) are no reason to refuse a fit whose own weights do not use it:
 * the samples then count alike. */
static brdffit_status make_plan_sa(const brdffit_fit *fit, bf_weight_plan *plan_sa,
                                   brdffit_error *err)
{
    brdffit_status status = bf_weight_plan_init(plan_sa, fit->grid, fit->cap,
                                                BRDFFIT_WEIGHT_SOLID_ANGLE, &fit->alloc, err);
    if (status == BRDFFIT_E_NO_DATA && !(fit->weighting & BRDFFIT_WEIGHT_SOLID_ANGLE))
        status = bf_weight_plan_init(plan_sa, fit->grid, fit->cap, 0, &fit->alloc, err);
    return status;
}

brdffit_status bf_run_plans(const brdffit_fit *fit, bf_weight_plan *plan, bf_weight_plan *plan_sa,
                            brdffit_error *err)
{
    brdffit_status status =
        bf_weight_plan_init(plan, fit->grid, fit->cap, fit->weighting, &fit->alloc, err);
    if (status == BRDFFIT_OK) {
        status = make_plan_sa(fit, plan_sa, err);
        if (status != BRDFFIT_OK) bf_weight_plan_free(plan, &fit->alloc);
    }
    return status;
}

/* The run's plans: a batch's shared ones (many_scan.h), read over this
 * fit's grid, or the fit's own. */
static brdffit_status make_plans(bf_run *run)
{
    const brdffit_fit *fit = run->fit;
    brdffit_error err;
    brdffit_status status;
    if (bf_batch_plans(fit, &run->plan, &run->plan_sa)) return BRDFFIT_OK;
    status = bf_run_plans(fit, &run->plan, &run->plan_sa, &err);
    if (status != BRDFFIT_OK)
        bf_say(run->result->message, status, "%s",
               status == BRDFFIT_E_OUT_OF_MEMORY ? "out of memory" : err.message);
    return status;
}

static void free_plans(bf_run *run)
{
    if (run->plan.cached != NULL) return; /* the batch's */
    bf_weight_plan_free(&run->plan, &run->fit->alloc);
    bf_weight_plan_free(&run->plan_sa, &run->fit->alloc);
}

/* The fit squares the measured values: keep them where their squares
 * neither underflow nor overflow. */
#define BF_FIT_VALUE_MIN 1e-100
#define BF_FIT_VALUE_MAX 1e100

static brdffit_status check_scale(bf_run *run)
{
    double top = run->summary.top;
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
    if (run->summary.rows[0] > 0) return BRDFFIT_OK;
    return bf_say(run->result->message, BRDFFIT_E_NO_DATA,
                  "no measured value inside the cap: every value with a non-zero weight there "
                  "is missing");
}

/* The plan whose weights the objective uses (as stage.c sets it). */
static const bf_weight_plan *objective_plan(const bf_run *run)
{
    brdffit_objective o = run->fit->objective;
    return o == BRDFFIT_OBJECTIVE_LOG || o == BRDFFIT_OBJECTIVE_CUBE_ROOT ? &run->plan_sa
                                                                          : &run->plan;
}

/* Sum of ln |R| and count over chunk ci's fitted non-zero values; 0, or
 * -1 with the first value whose log the log objective cannot take in
 * *bad. */
static int chunk_values(const bf_run *run, size_t ci, double *sum, double *count, double *bad)
{
    const brdffit_fit *fit = run->fit;
    double w[BF_CHUNK], meas[BF_CHUNK], pres[BF_CHUNK];
    size_t first, n, c, s;
    brdffit_batch batch;
    bf_weight_plan_chunk(objective_plan(run), ci, &first, &n, w);
    bf_grid_batch(fit->grid, first, n, &batch);
    for (c = 0; c < fit->nc; c++) {
        bf_grid_load_channel(fit->grid, c, first, n, meas, pres);
        for (s = 0; s < n; s++) {
            double cz = batch.lz[s] > 0.0 ? batch.lz[s] : 0.0, r = meas[s];
            if (w[s] == 0.0 || pres[s] == 0.0) continue;
            if (fit->clearcoat > 0.0) r /= bf_grid_coat_divisor(fit->clearcoat, batch.lz[s]);
            if (meas[s] != 0.0) {
                *sum += log(fabs(meas[s]));
                *count += 1.0;
            }
            if (fit->objective == BRDFFIT_OBJECTIVE_LOG && !(1.0 + cz * r > 0.0)) {
                *bad = r;
                return -1;
            }
        }
    }
    return 0;
}

/* The objective's floor delta (brdffit_objective: 1e-3 of the geometric
 * mean of the non-zero |R|, which one grazing spike cannot move: with the
 * arithmetic mean, a single value of 1e8 among thousands of order 0.1 set
 * delta above most values, and the cube root's floored slope then
 * disagreed with its residual almost everywhere, so the fit stalled), and
 * the log objective's check that every 1 + cos(theta_i) R > 0. */
static brdffit_status prepare_objective(bf_run *run)
{
    double sum = 0.0, count = 0.0, bad = 0.0;
    size_t ci;
    if (run->fit->objective == BRDFFIT_OBJECTIVE_SQUARES) return BRDFFIT_OK;
    for (ci = 0; ci < objective_plan(run)->n_chunks; ci++)
        if (chunk_values(run, ci, &sum, &count, &bad) != 0)
            return bf_say(run->result->message, BRDFFIT_E_RANGE,
                          "the log objective needs 1 + cos(theta_i) R > 0 for every measured "
                          "value R inside the cap, and R = %g is not: use another objective",
                          bad);
    run->delta = count > 0.0 ? 1e-3 * exp(sum / count) : 0.0;
    if (!(run->delta > 0.0)) run->delta = BF_FIT_VALUE_MIN;
    return BRDFFIT_OK;
}

/* Helper threads for the run: one per pass block beyond the caller's. */
static size_t helper_count(const bf_run *run)
{
    size_t blocks = run->fit->threads < BF_MAX_THREADS ? run->fit->threads : BF_MAX_THREADS;
    if (blocks > run->plan.n_chunks) blocks = run->plan.n_chunks;
    return blocks > 1 ? blocks - 1 : 0;
}

/* Error figures of the final parameters (BF_PASS_METRICS) over nc
 * channels from channel c on (every channel, or channel c alone). */
static brdffit_status metrics_of(bf_run *run, size_t nc, size_t c)
{
    const brdffit_fit *fit = run->fit;
    bf_result *r = run->result;
    bf_stage st;
    size_t k;
    brdffit_status status = bf_stage_init(
        &st, run, nc, nc == fit->nc ? BF_SOURCE_CHANNELS : BF_SOURCE_ONE_CHANNEL, c, 0);
    if (status != BRDFFIT_OK) return status;
    if (nc == fit->nc)
        memcpy(st.p, r->params, st.n * sizeof *st.p);
    else
        for (k = 0; k < st.pb.ly.n_params; k++)
            st.p[st.vindex[k]] = r->params[brdffit_model_vector_index(fit->model, k, c, fit->nc)];
    status = bf_stage_pass(&st, BF_PASS_METRICS);
    if (status == BRDFFIT_OK)
        memcpy(r->metrics + 4 * c, st.acc, 4 * nc * sizeof(double));
    else
        status = bf_stage_fail(&st, status, "error figures");
    bf_stage_free(&st);
    return status;
}

/* All channels in one pass; channel by channel where the parameters of
 * all of them are too many for one stage (the two-stage pipeline). */
static brdffit_status final_metrics(bf_run *run)
{
    size_t c;
    if (run->fit->n_vec <= BRDFFIT_FIT_MAX_PARAMS) return metrics_of(run, run->fit->nc, 0);
    for (c = 0; c < run->fit->nc; c++) BF_RETURN_IF_ERROR(metrics_of(run, 1, c));
    return BRDFFIT_OK;
}

/* The pipeline and the error figures (the mean's from the summary). */
static brdffit_status run_stages(bf_run *run)
{
    brdffit_status status = pipelines[run->fit->pipeline](run);
    if (status == BRDFFIT_OK) bf_canonical_lobes(run); /* sharper lobe first */
    if (status == BRDFFIT_OK) status = final_metrics(run);
    if (status == BRDFFIT_OK) {
        run->result->mean_error = run->summary.mean_error;
        run->result->mean_plain = run->summary.mean_plain;
        run->result->mean_cost = run->summary.mean_cost;
    }
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
    bf_pool_start(&run.pool, helper_count(&run));
    bf_summary_make(&run);
    status = check_scale(&run);
    if (status == BRDFFIT_OK) status = check_rows(&run);
    if (status == BRDFFIT_OK) status = prepare_objective(&run);
    if (status == BRDFFIT_OK) status = run_stages(&run);
    bf_pool_stop(&run.pool);
    free_plans(&run);
    if (status == BRDFFIT_E_OUT_OF_MEMORY) bf_say(out->message, status, "out of memory");
    return status;
}
