/* bench_fit: whole fits on the default grid. Models "ashikhmin-shirley" and
 * "ashikhmin-shirley-fresnel"; pipelines auto (no start values), joint and
 * two-stage from the thesis's starts (ns = 25, cd = cs = 0.2; Rs of the
 * Fresnel form at the model default 0.2); data sets P1 and P2
 * (datasets.h), and auto under the cube-root objective ("auto-cbrt", for
 * ashikhmin-shirley: its median against squares auto's in the same run).
 * Per fit: LM iterations of the final run, passes over the
 * samples, final cost, median / min / max time of repeated runs (create,
 * configure, run, destroy), and the peak bytes the fit allocated through a
 * counting allocator handed to brdffit_fit_create() (the grid and the model
 * have their own allocators, so this is the memory beyond the grid). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "datasets.h"
#include "harness.h"

#define N_MODELS 2
#define N_PIPELINES 3
#define FIT_REPEATS 11
#define AUTO_TARGET_NS 5e6
#define MEMORY_TARGET_BYTES 8192

static const char *const models[N_MODELS] = {"ashikhmin-shirley", "ashikhmin-shirley-fresnel"};
static const brdffit_pipeline pipelines[N_PIPELINES] = {
    BRDFFIT_PIPELINE_AUTO, BRDFFIT_PIPELINE_JOINT, BRDFFIT_PIPELINE_TWO_STAGE};

typedef struct fit_case {
    bd_fit_job job;
    bd_fit_result res;
    bh_counter counter;
    double start[BD_MAX_PARAMS];
    bh_stats st;
    size_t rows;
} fit_case;

static int run_fit(void *ctx)
{
    fit_case *fc = ctx;
    return bd_fit_run(&fc->job, &fc->res) != BRDFFIT_OK;
}

static const char *stop_name(brdffit_stop_reason r)
{
    switch (r) {
    case BRDFFIT_STOP_GRADIENT: return "gradient";
    case BRDFFIT_STOP_STEP: return "step";
    case BRDFFIT_STOP_COST: return "cost";
    case BRDFFIT_STOP_MAX_ITERATIONS: return "max-iter";
    case BRDFFIT_STOP_MAX_EVALUATIONS: return "max-eval";
    case BRDFFIT_STOP_ZERO_COST: return "zero-cost";
    case BRDFFIT_STOP_STALLED: return "stalled";
    default: return "other";
    }
}

/* The row's pipeline column: the pipeline, and the objective when it is
 * not the squares ("auto-cbrt": auto under the cube-root objective). */
static const char *pipe_label(const fit_case *fc)
{
    if (fc->job.objective == BRDFFIT_OBJECTIVE_CUBE_ROOT) return "auto-cbrt";
    return bd_pipeline_name(fc->job.pipeline);
}

static void record(bh_output *out, const fit_case *fc, bd_dataset data)
{
    const char *model = brdffit_model_name(fc->job.model);
    const char *pipe = pipe_label(fc);
    char name[128];
    bh_record r;
    bh_table(out, "%-25s %-4s %-9s %5zu %6zu %-9s %12.6e %8.3f %9.3f %8.3f %8.3f %8.3f %7zu %6zu\n",
             model, bd_name(data), pipe, fc->res.iterations, fc->res.passes,
             stop_name(fc->res.stop), fc->res.cost, fc->res.params[0], fc->st.median_ns / 1e6,
             fc->st.min_ns / 1e6, fc->st.max_ns / 1e6, fc->st.median_cpu_ns / 1e6,
             fc->res.peak_bytes, fc->res.alloc_calls);
    snprintf(name, sizeof name, "%s/%s/%s", model, bd_name(data), pipe);
    bh_rec_begin(&r, out, name);
    bh_rec_str(&r, "model", model);
    bh_rec_str(&r, "data", bd_name(data));
    bh_rec_str(&r, "pipeline", pipe);
    bh_rec_stats(&r, &fc->st, fc->rows);
    bh_rec_int(&r, "iterations", fc->res.iterations);
    bh_rec_int(&r, "passes", fc->res.passes);
    bh_rec_num(&r, "ns_per_pass", fc->st.median_ns / (double)fc->res.passes);
    bh_rec_str(&r, "stop", stop_name(fc->res.stop));
    bh_rec_num(&r, "cost", fc->res.cost);
    bh_rec_num(&r, "ns_fitted", fc->res.params[0]);
    bh_rec_int(&r, "fit_peak_bytes", fc->res.peak_bytes);
    bh_rec_int(&r, "fit_alloc_calls", fc->res.alloc_calls);
    bh_rec_end(&r, out);
}

/* Checks that hold on any machine: the fit succeeded, freed everything, and
 * on the noise-free P1 the simplified model comes back. */
static void check(bh_output *out, const fit_case *fc, bd_dataset data)
{
    const char *model = brdffit_model_name(fc->job.model);
    const char *pipe = pipe_label(fc);
    if (fc->res.leaked != 0)
        bh_fail(out, "%s/%s/%s: %zu bytes still allocated after destroy", model, bd_name(data),
                pipe, fc->res.leaked);
    if (data == BD_P1 && strcmp(model, "ashikhmin-shirley") == 0 &&
        !(fabs(fc->res.params[0] / 120.0 - 1.0) < 1e-6))
        bh_fail(out, "%s/P1/%s: ns = %.9g, expected 120", model, pipe, fc->res.params[0]);
}

typedef struct summary {
    double auto_worst_ns;  /* slowest median of an auto fit of ashikhmin-shirley */
    double auto_worst_cpu; /* its CPU time */
    size_t peak_worst;     /* largest fit peak over all fits */
    double auto_ns[2];     /* median of the squares auto fit of ashikhmin-shirley per data set */
    double cbrt_ns[2];     /* and of its cube-root auto fit */
} summary;

static void summarise(summary *sm, const fit_case *fc, bd_dataset data)
{
    int as = strcmp(brdffit_model_name(fc->job.model), "ashikhmin-shirley") == 0;
    if (fc->res.peak_bytes > sm->peak_worst) sm->peak_worst = fc->res.peak_bytes;
    if (as && fc->job.pipeline == BRDFFIT_PIPELINE_AUTO)
        (fc->job.objective == BRDFFIT_OBJECTIVE_CUBE_ROOT ? sm->cbrt_ns : sm->auto_ns)[data] =
            fc->st.median_ns;
    if (fc->job.objective != BRDFFIT_OBJECTIVE_SQUARES) return; /* the target is the squares' */
    if (fc->job.pipeline == BRDFFIT_PIPELINE_AUTO &&
        strcmp(brdffit_model_name(fc->job.model), "ashikhmin-shirley") == 0 &&
        fc->st.median_ns > sm->auto_worst_ns) {
        sm->auto_worst_ns = fc->st.median_ns;
        sm->auto_worst_cpu = fc->st.median_cpu_ns;
    }
}

static void run_one(bh_output *out, const brdffit_grid *grid, const brdffit_model *model,
                    bd_dataset data, brdffit_pipeline pipe, brdffit_objective obj, summary *sm)
{
    fit_case fc;
    size_t reps = bh_repeats(out->opt, FIT_REPEATS);
    char label[128];
    memset(&fc, 0, sizeof fc);
    fc.job.pipeline = pipe;
    fc.job.objective = obj;
    snprintf(label, sizeof label, "%s/%s/%s", brdffit_model_name(model), bd_name(data),
             pipe_label(&fc));
    if (!bh_selected(out->opt, label)) return;
    bh_counter_init(&fc.counter);
    fc.job.grid = grid;
    fc.job.model = model;
    fc.job.pipeline = pipe;
    fc.job.threads = 1;
    fc.job.counter = &fc.counter;
    fc.rows = brdffit_grid_active_count(grid, BRDFFIT_DEFAULT_CAP) * BD_CHANNELS;
    if (pipe != BRDFFIT_PIPELINE_AUTO) {
        bd_thesis_start(model, BD_CHANNELS, fc.start);
        fc.job.start = fc.start;
    }
    if (bh_measure(run_fit, &fc, out->opt->smoke ? 0 : 1, reps, &fc.st) != 0) {
        bh_fail(out, "%s/%s/%s: %s: %s", brdffit_model_name(model), bd_name(data), pipe_label(&fc),
                brdffit_status_name(fc.res.status), fc.res.message);
        return;
    }
    record(out, &fc, data);
    check(out, &fc, data);
    summarise(sm, &fc, data);
}

static void report_targets(bh_output *out, const summary *sm)
{
    char measured[64], limit[64];
    int d;
    bh_table(out, "\n");
    for (d = 0; d < 2; d++)
        if (sm->auto_ns[d] > 0.0 && sm->cbrt_ns[d] > 0.0)
            bh_table(out, "ashikhmin-shirley %s: cube-root auto / squares auto median = %.2f\n",
                     bd_name((bd_dataset)d), sm->cbrt_ns[d] / sm->auto_ns[d]);
    snprintf(measured, sizeof measured, "%.2f ms (cpu %.2f; slower of P1, P2)",
             sm->auto_worst_ns / 1e6, sm->auto_worst_cpu / 1e6);
    bh_target(out, "auto fit of ashikhmin-shirley on P1 and P2, median", measured, "< 5 ms",
              sm->auto_worst_ns < AUTO_TARGET_NS);
    bh_target(out, "auto fit of ashikhmin-shirley on P1 and P2, median (issue 16)", measured,
              "< 2 ms", sm->auto_worst_ns < 2e6);
    snprintf(measured, sizeof measured, "%zu bytes (largest)", sm->peak_worst);
    snprintf(limit, sizeof limit, "<= %d bytes, 'a few kB'", MEMORY_TARGET_BYTES);
    bh_target(out, "peak bytes a fit allocates beyond the grid", measured, limit,
              sm->peak_worst <= MEMORY_TARGET_BYTES);
}

static int make_grids(bh_output *out, brdffit_grid **grids)
{
    brdffit_error err;
    int d;
    for (d = 0; d < 2; d++)
        if (bd_default_grid(&grids[d], (bd_dataset)d, BD_SEED, NULL, &err) != BRDFFIT_OK) {
            bh_fail(out, "creating %s: %s", bd_name((bd_dataset)d), err.message);
            return 0;
        }
    return 1;
}

int main(int argc, char **argv)
{
    bh_options opt;
    bh_output out;
    brdffit_grid *grids[2] = {NULL, NULL};
    summary sm = {0.0, 0.0, 0, {0.0, 0.0}, {0.0, 0.0}};
    size_t m, p;
    int code, d;
    if (!bh_parse_args(argc, argv, "Whole fits: auto, joint and two-stage on P1 and P2.", &opt,
                       &code))
        return code;
    if (!bh_output_open(&out, &opt, "whole fits on the default grid (cap 75, 1 thread)")) return 1;
    bh_table(&out,
             "joint and two-stage start from ns = 25, cd = cs = 0.2 (Rs = 0.2, the model "
             "default); %zu timed runs each\n",
             bh_repeats(&opt, FIT_REPEATS));
    bh_table(&out, "%-25s %-4s %-9s %5s %6s %-9s %12s %8s %9s %8s %8s %8s %7s %6s\n", "model",
             "data", "pipeline", "iters", "passes", "stop", "cost", "ns", "median ms", "min ms",
             "max ms", "cpu ms", "peak B", "allocs");
    if (make_grids(&out, grids))
        for (m = 0; m < N_MODELS; m++) {
            brdffit_model *model = NULL;
            if (brdffit_model_create(&model, models[m], NULL, NULL) != BRDFFIT_OK) continue;
            for (d = 0; d < 2; d++) {
                for (p = 0; p < N_PIPELINES; p++)
                    run_one(&out, grids[d], model, (bd_dataset)d, pipelines[p],
                            BRDFFIT_OBJECTIVE_SQUARES, &sm);
                if (m == 0) /* the cube-root auto row (issue 13): its ratio to squares auto */
                    run_one(&out, grids[d], model, (bd_dataset)d, BRDFFIT_PIPELINE_AUTO,
                            BRDFFIT_OBJECTIVE_CUBE_ROOT, &sm);
            }
            brdffit_model_destroy(model);
        }
    if (opt.filter == NULL) report_targets(&out, &sm);
    brdffit_grid_destroy(grids[0]);
    brdffit_grid_destroy(grids[1]);
    return bh_output_close(&out);
}
