/* Batch fits (brdffit_fit_many(), many.h) of SVBRDF-like texels: 200
 * scattered samples, 3 channels, Ashikhmin-Shirley, auto pipeline, against
 * the reference of one grid and one fit handle per texel, measured in the
 * same run, on one and two threads, under the squares objective (the
 * target's) and under cube-root. Also checks that the batch's results
 * agree with the one-handle fits' (docs/fitting.md, Many fits over one
 * geometry) and reports how many batch fits the run made, so that a
 * callgrind count of the run gives instructions per fit (one thread only:
 * the toggle follows the calling thread, not the pool's helpers):
 *   valgrind --tool=callgrind --toggle-collect=brdffit_fit_many \
 *       bench_many --smoke --repeats=3 --filter="fit_many, squares, 1 thread" */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"

#define NS 200
#define NC 3
#define NV 7
#define TEXELS 2000
#define SMOKE_TEXELS 16
#define REPEATS 7

typedef struct texels {
    size_t n;
    double ti[NS], pi[NS], to[NS], po[NS];
    double *values; /* n * NS * NC, interleaved per texel */
    brdffit_model *model;
    brdffit_grid *grid; /* the geometry (texel 0's values) */
} texels;

/* Random directions up to 80 deg; per texel an exponent from 20 to 2000
 * and colours varying, 2 % noise. */
static int make_texels(texels *t, size_t n)
{
    bh_rng rng;
    double ch[NS * NC], p[NV];
    size_t i, s, c;
    bh_rng_seed(&rng, 16);
    t->n = n;
    for (s = 0; s < NS; s++) {
        t->ti[s] = 1.396 * bh_rng_uniform(&rng);
        t->pi[s] = 3.14159265358979;
        t->to[s] = 1.396 * bh_rng_uniform(&rng);
        t->po[s] = 3.14159265358979 * bh_rng_uniform(&rng);
    }
    if (brdffit_model_create(&t->model, "ashikhmin-shirley", NULL, NULL) != BRDFFIT_OK) return 0;
    t->values = malloc(n * NS * NC * sizeof *t->values);
    if (t->values == NULL) return 0;
    for (i = 0; i < n; i++) {
        p[0] = 20.0 * pow(100.0, bh_rng_uniform(&rng));
        for (c = 0; c < NC; c++) {
            p[1 + c] = 0.05 + 0.3 * bh_rng_uniform(&rng);
            p[4 + c] = 0.02 + 0.1 * bh_rng_uniform(&rng);
        }
        if (brdffit_model_eval_angles(t->model, NS, t->ti, t->pi, t->to, t->po, NC, p, ch, NULL,
                                      NULL) != BRDFFIT_OK)
            return 0;
        for (s = 0; s < NS; s++)
            for (c = 0; c < NC; c++)
                t->values[(i * NS + s) * NC + c] =
                    ch[c * NS + s] * (1.0 + 0.02 * bh_rng_normal(&rng));
    }
    return brdffit_grid_create_scattered(&t->grid, NS, t->ti, t->pi, t->to, t->po, NC, t->values,
                                         NULL, NULL, NULL, NULL) == BRDFFIT_OK;
}

static void free_texels(texels *t)
{
    brdffit_grid_destroy(t->grid);
    brdffit_model_destroy(t->model);
    free(t->values);
}

/* ---- the reference: one grid and one fit handle per texel ---------------------------------- */

typedef struct handles_job {
    const texels *t;
    size_t first, end;
    brdffit_objective objective;
    double *params; /* t->n * NV */
    double *cost;   /* t->n */
    int failed;
} handles_job;

static void *handles_range(void *arg)
{
    handles_job *j = arg;
    const texels *t = j->t;
    size_t i;
    for (i = j->first; i < j->end; i++) {
        brdffit_grid *g = NULL;
        brdffit_fit *fit = NULL;
        if (brdffit_grid_create_scattered(&g, NS, t->ti, t->pi, t->to, t->po, NC,
                                          t->values + i * NS * NC, NULL, NULL, NULL,
                                          NULL) != BRDFFIT_OK ||
            brdffit_fit_create(&fit, g, t->model, NULL, NULL) != BRDFFIT_OK ||
            brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, (double)j->objective) != BRDFFIT_OK ||
            brdffit_fit_run(fit) != BRDFFIT_OK || brdffit_fit_params(fit, j->params + i * NV) ||
            brdffit_fit_error(fit, BRDFFIT_METRIC_COST, BRDFFIT_ALL_CHANNELS, j->cost + i))
            j->failed = 1;
        brdffit_fit_destroy(fit);
        brdffit_grid_destroy(g);
    }
    return NULL;
}

typedef struct run_ctx {
    const texels *t;
    size_t threads;
    brdffit_objective objective;
    double *params;
    double *cost;       /* t->n final costs */
    size_t *iterations; /* batch runs: t->n LM iterations */
    brdffit_fit *proto; /* batch runs */
    brdffit_status *status;
    size_t fits; /* batch fits made, all runs */
} run_ctx;

/* The texels split in `threads` contiguous ranges, one pthread each. */
static int run_handles(void *arg)
{
    run_ctx *c = arg;
    handles_job jobs[2];
    pthread_t tid[2];
    size_t k, n = c->threads;
    for (k = 0; k < n; k++) {
        jobs[k].t = c->t;
        jobs[k].first = c->t->n * k / n;
        jobs[k].end = c->t->n * (k + 1) / n;
        jobs[k].objective = c->objective;
        jobs[k].params = c->params;
        jobs[k].cost = c->cost;
        jobs[k].failed = 0;
    }
    for (k = 1; k < n; k++)
        if (pthread_create(&tid[k], NULL, handles_range, &jobs[k]) != 0) return 1;
    handles_range(&jobs[0]);
    for (k = 1; k < n; k++) pthread_join(tid[k], NULL);
    for (k = 0; k < n; k++)
        if (jobs[k].failed) return 1;
    return 0;
}

/* ---- the batch ------------------------------------------------------------------------------------ */

static int run_many(void *arg)
{
    run_ctx *c = arg;
    brdffit_many_out out;
    size_t i;
    memset(&out, 0, sizeof out);
    out.struct_size = sizeof out;
    out.params = c->params;
    out.cost = c->cost;
    out.iterations = c->iterations;
    out.status = c->status;
    if (brdffit_fit_many(c->proto, c->t->n, c->t->values, NULL, &out, NULL, NULL) != BRDFFIT_OK)
        return 1;
    c->fits += out.n_run;
    for (i = 0; i < c->t->n; i++)
        if (c->status[i] != BRDFFIT_OK) return 1;
    return 0;
}

typedef struct figures {
    double handles[2], many[2]; /* fits per second, 1 and 2 threads */
    size_t fits;                /* batch fits made on one thread */
} figures;

static void record(bh_output *out, const char *name, const bh_stats *st, size_t n, size_t threads,
                   double *fps)
{
    bh_record r;
    double per_cpu = st->median_cpu_ns > 0.0 ? (double)n / (st->median_cpu_ns * 1e-9) : 0.0;
    *fps = (double)n / (st->median_ns * 1e-9);
    bh_table(out, "%-40s %7zu %7zu %10.1f %10.0f %13.0f %12.0f\n", name, threads, n,
             st->median_ns * 1e-6, *fps, *fps / (double)threads, per_cpu);
    bh_rec_begin(&r, out, name);
    bh_rec_int(&r, "threads", threads);
    bh_rec_int(&r, "fits", n);
    bh_rec_stats(&r, st, 0);
    bh_rec_num(&r, "fits_per_second", *fps);
    bh_rec_num(&r, "fits_per_second_per_thread", *fps / (double)threads);
    bh_rec_num(&r, "fits_per_cpu_second", per_cpu);
    bh_rec_end(&r, out);
}

/* How the batch's results compare with the one-handle fits': texels whose
 * parameters are equal bit for bit, the largest relative excess of the
 * batch's final cost over the reference's (negative: the batch's is
 * lower), and the mean LM iterations of the batch. */
static void compare(bh_output *out, const char *name, const texels *t, const double *ref,
                    const double *got, const double *ref_cost, const double *cost,
                    const size_t *iterations)
{
    size_t i, same = 0, iters = 0;
    double worst = -HUGE_VAL;
    bh_record r;
    for (i = 0; i < t->n; i++) {
        same += memcmp(ref + i * NV, got + i * NV, NV * sizeof *ref) == 0;
        worst = fmax(worst, (cost[i] - ref_cost[i]) / ref_cost[i]);
        iters += iterations[i];
    }
    bh_table(out,
             "  %s: %zu of %zu texels equal bit for bit, batch cost at most %.2e above "
             "(relative), %.2f LM iterations per batch fit\n",
             name, same, t->n, worst, (double)iters / (double)t->n);
    bh_rec_begin(&r, out, "agreement");
    bh_rec_str(&r, "objective", name);
    bh_rec_int(&r, "bitwise_equal", same);
    bh_rec_num(&r, "largest_relative_cost_excess", worst);
    bh_rec_num(&r, "batch_iterations", (double)iters / (double)t->n);
    bh_rec_end(&r, out);
    /* the batch is the single fit up to the scan's rounding and the
     * polish's tolerance: never a worse minimum than 1e-6 */
    if (!(worst <= 1e-6)) bh_fail(out, "batch costs exceed the one-handle fits' (%s)", name);
}

typedef struct buffers {
    double *ref, *got, *ref_cost, *cost;
    size_t *iterations;
    brdffit_status *status;
} buffers;

static int make_buffers(buffers *b, size_t n)
{
    b->ref = calloc(n * NV, sizeof(double));
    b->got = calloc(n * NV, sizeof(double));
    b->ref_cost = calloc(n, sizeof(double));
    b->cost = calloc(n, sizeof(double));
    b->iterations = calloc(n, sizeof(size_t));
    b->status = calloc(n, sizeof(brdffit_status));
    return b->ref && b->got && b->ref_cost && b->cost && b->iterations && b->status;
}

static void free_buffers(buffers *b)
{
    free(b->ref), free(b->got), free(b->ref_cost), free(b->cost), free(b->iterations);
    free(b->status);
}

/* One objective: the reference and the batch on 1 and 2 threads. */
static void measure_objective(bh_output *out, const texels *t, brdffit_objective objective,
                              const char *oname, figures *fg, buffers *b)
{
    size_t reps = bh_repeats(out->opt, REPEATS), th;
    char name[96];
    bh_stats st;
    double fps;
    for (th = 1; th <= 2; th++) {
        run_ctx c = {t, th, objective, b->ref, b->ref_cost, NULL, NULL, b->status, 0};
        int have_ref = 0;
        snprintf(name, sizeof name, "one handle per fit, %s, %s", oname,
                 th == 2 ? "2 threads" : "1 thread");
        if (bh_selected(out->opt, name)) {
            have_ref = 1;
            if (bh_measure(run_handles, &c, 1, reps, &st) != 0)
                bh_fail(out, "one-handle fits failed");
            record(out, name, &st, t->n, th,
                   objective == BRDFFIT_OBJECTIVE_SQUARES ? &fg->handles[th - 1] : &fps);
        }
        snprintf(name, sizeof name, "brdffit_fit_many, %s, %s", oname,
                 th == 2 ? "2 threads" : "1 thread");
        if (!bh_selected(out->opt, name)) continue;
        c.params = b->got;
        c.cost = b->cost;
        c.iterations = b->iterations;
        if (brdffit_fit_create(&c.proto, t->grid, t->model, NULL, NULL) != BRDFFIT_OK ||
            brdffit_fit_set(c.proto, BRDFFIT_FIT_THREADS, (double)th) != BRDFFIT_OK ||
            brdffit_fit_set(c.proto, BRDFFIT_FIT_OBJECTIVE, (double)objective) != BRDFFIT_OK ||
            bh_measure(run_many, &c, 1, reps, &st) != 0)
            bh_fail(out, "brdffit_fit_many failed");
        brdffit_fit_destroy(c.proto);
        if (th == 1) fg->fits += c.fits;
        record(out, name, &st, t->n, th,
               objective == BRDFFIT_OBJECTIVE_SQUARES ? &fg->many[th - 1] : &fps);
        if (have_ref) compare(out, oname, t, b->ref, b->got, b->ref_cost, b->cost, b->iterations);
    }
}

static void measure(bh_output *out, const texels *t, figures *fg)
{
    buffers b;
    if (make_buffers(&b, t->n)) {
        measure_objective(out, t, BRDFFIT_OBJECTIVE_SQUARES, "squares", fg, &b);
        measure_objective(out, t, BRDFFIT_OBJECTIVE_CUBE_ROOT, "cube-root", fg, &b);
    } else {
        bh_fail(out, "out of memory");
    }
    free_buffers(&b);
}

/* Mean passes over the samples and LM iterations per fit (first texels)
 * under one objective. */
static void passes_per_fit(bh_output *out, const texels *t, brdffit_objective objective,
                           const char *name)
{
    size_t i, n = t->n < 50 ? t->n : 50, passes = 0, iters = 0;
    bh_record r;
    for (i = 0; i < n; i++) {
        brdffit_grid *g = NULL;
        brdffit_fit *fit = NULL;
        if (brdffit_grid_create_scattered(&g, NS, t->ti, t->pi, t->to, t->po, NC,
                                          t->values + i * NS * NC, NULL, NULL, NULL,
                                          NULL) == BRDFFIT_OK &&
            brdffit_fit_create(&fit, g, t->model, NULL, NULL) == BRDFFIT_OK &&
            brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, (double)objective) == BRDFFIT_OK &&
            brdffit_fit_run(fit) == BRDFFIT_OK) {
            passes += brdffit_fit_passes(fit);
            iters += brdffit_fit_iterations(fit);
        }
        brdffit_fit_destroy(fit);
        brdffit_grid_destroy(g);
    }
    bh_table(out,
             "%s, per fit (mean of %zu): %.1f passes over the samples, %.1f LM iterations, "
             "%zu samples inside the cap\n",
             name, n, (double)passes / (double)n, (double)iters / (double)n,
             brdffit_grid_active_count(t->grid, BRDFFIT_DEFAULT_CAP));
    bh_rec_begin(&r, out, "passes per fit");
    bh_rec_str(&r, "objective", name);
    bh_rec_num(&r, "passes", (double)passes / (double)n);
    bh_rec_num(&r, "iterations", (double)iters / (double)n);
    bh_rec_int(&r, "active_samples", brdffit_grid_active_count(t->grid, BRDFFIT_DEFAULT_CAP));
    bh_rec_end(&r, out);
}

static void targets(bh_output *out, const figures *fg)
{
    char m[128];
    double scale = fg->many[1] / fg->many[0];
    snprintf(m, sizeof m, "%.0f fits/s (one handle per fit: %.0f, %.2fx)", fg->many[0],
             fg->handles[0], fg->many[0] / fg->handles[0]);
    bh_target(out, "batch auto fits per second on one core, 200 samples x 3 channels", m,
              ">= 100000", fg->many[0] >= 100000.0);
    snprintf(m, sizeof m, "%.2fx (%.0f fits/s; one handle per fit: %.2fx)", scale, fg->many[1],
             fg->handles[1] / fg->handles[0]);
    bh_target(out, "batch scaling on two threads", m, ">= 1.8x", scale >= 1.8);
}

int main(int argc, char **argv)
{
    bh_options opt;
    bh_output out;
    texels t;
    figures fg;
    int code;
    if (!bh_parse_args(argc, argv,
                       "Batch fits of 200-sample 3-channel texels against one handle per fit.",
                       &opt, &code))
        return code;
    if (!bh_output_open(&out, &opt, "batch fits (ashikhmin-shirley, auto, cap 75)")) return 1;
    memset(&t, 0, sizeof t);
    memset(&fg, 0, sizeof fg);
    if (!make_texels(&t, opt.smoke ? SMOKE_TEXELS : TEXELS)) {
        bh_fail(&out, "could not make the texels");
    } else {
        bh_table(&out, "%zu texels of %d scattered samples x %d channels; %zu timed runs each\n",
                 t.n, NS, NC, bh_repeats(&opt, REPEATS));
        bh_table(&out, "%-40s %7s %7s %10s %10s %13s %12s\n", "how", "threads", "fits", "median ms",
                 "fits/s", "fits/s/thread", "fits/cpu-s");
        measure(&out, &t, &fg);
        bh_table(&out,
                 "batch fits made on one thread: %zu (divide a callgrind count of "
                 "brdffit_fit_many under --filter=\"fit_many, squares, 1 thread\" by it: "
                 "a helper thread's work is not counted)\n",
                 fg.fits);
        passes_per_fit(&out, &t, BRDFFIT_OBJECTIVE_SQUARES, "squares");
        passes_per_fit(&out, &t, BRDFFIT_OBJECTIVE_CUBE_ROOT, "cube-root");
        if (!opt.smoke && opt.filter == NULL) targets(&out, &fg);
    }
    free_texels(&t);
    return bh_output_close(&out);
}
