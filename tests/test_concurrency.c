/* Fits and readers across threads: many fits of different grids at once,
 * many fits sharing one grid and one model, fits that themselves use
 * threads (BRDFFIT_FIT_THREADS = 2) inside threads, read-only functions on
 * shared handles while fits run, loaders in parallel, and a cancel request
 * from another thread arriving in the middle of a fit. Every parallel
 * result must equal the same work done sequentially, bit for bit.
 *
 * The suite also runs under ThreadSanitizer (docs/guarantees.md gives the
 * commands), where it must report no race. */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit_fixtures.h"
#include "grid_fixtures.h"
#include "test_support.h"

#define MAXV 160
#define HIST 2048
#define MAX_JOBS 8

/* A small grid (6 x 16 x 10 = 960 samples, four chunks) keeps the suite
 * quick also under ThreadSanitizer. */
static const double TI_DEG[] = {0, 15, 30, 45, 60, 75};
static const double TO_DEG[] = {0, 5, 10, 15, 20, 25, 30, 35, 40, 45, 50, 55, 60, 65, 70, 75};
static const double PO_DEG[] = {0, 20, 40, 60, 80, 100, 120, 140, 160, 180};

static const brdffit_axes *small_axes(void)
{
    static fx_axes a;
    fx_axes_set(&a, TI_DEG, 6, TO_DEG, 16, PO_DEG, 10);
    return &a.axes;
}

static brdffit_model *make_model(const char *name)
{
    brdffit_model *model = NULL;
    assert_int_equal(brdffit_model_create(&model, name, NULL, NULL), BRDFFIT_OK);
    return model;
}

/* Data from a one-lobe model `name`: its first shape parameter `shape`, a
 * Fresnel term 0.04, colours 0.1 + 0.05 (parameter + channel). */
static brdffit_grid *grid_of(const char *name, double shape, double noise, uint64_t seed)
{
    double v[6][8], p[MAXV];
    brdffit_model *model = make_model(name);
    brdffit_grid *grid;
    size_t np = brdffit_model_param_count(model), k, c;
    memset(v, 0, sizeof v);
    for (k = 0; k < np; k++) {
        const brdffit_param_info *info = brdffit_model_param(model, k);
        for (c = 0; c < 8; c++) {
            if (info->flags & BRDFFIT_PARAM_LINEAR)
                v[k][c] = 0.1 + 0.05 * (double)(k + c);
            else
                v[k][c] = k == 0 ? shape : 0.04;
        }
    }
    fx_vector(model, 3, (const double(*)[8])v, p);
    grid = fx_grid_from_model(model, p, 3, small_axes(), noise, seed);
    assert_non_null(grid);
    brdffit_model_destroy(model);
    return grid;
}

/* ---- one fit, everything it reports ------------------------------------ */

typedef struct job {
    const brdffit_grid *grid;
    const brdffit_model *model;
    int pipeline;
    unsigned weighting;
    double cap;
    size_t threads;
    /* results */
    brdffit_status status;
    size_t n, n_history, iterations, passes;
    brdffit_stop_reason stop;
    double params[MAXV], se[MAXV], errors[3 * 4];
    double cost[HIST], lambda[HIST];
    int ok;
} job;

static void job_set(job *j, const brdffit_grid *grid, const brdffit_model *model, int pipeline,
                    unsigned weighting, double cap, size_t threads)
{
    memset(j, 0, sizeof *j);
    j->grid = grid;
    j->model = model;
    j->pipeline = pipeline;
    j->weighting = weighting;
    j->cap = cap;
    j->threads = threads;
}

/* No CMocka assertions here: this runs in worker threads. */
static void job_run(job *j)
{
    brdffit_fit *fit = NULL;
    size_t c, m;
    j->ok = 0;
    if (brdffit_fit_create(&fit, j->grid, j->model, NULL, NULL) != BRDFFIT_OK) return;
    if (brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, j->pipeline) != BRDFFIT_OK ||
        brdffit_fit_set(fit, BRDFFIT_FIT_WEIGHTING, j->weighting) != BRDFFIT_OK ||
        brdffit_fit_set(fit, BRDFFIT_FIT_CAP, j->cap) != BRDFFIT_OK ||
        brdffit_fit_set(fit, BRDFFIT_FIT_THREADS, (double)j->threads) != BRDFFIT_OK) {
        brdffit_fit_destroy(fit);
        return;
    }
    j->status = brdffit_fit_run(fit);
    j->n = brdffit_fit_param_count(fit);
    if (j->status == BRDFFIT_OK && j->n <= MAXV && brdffit_fit_history(fit, NULL, NULL) <= HIST) {
        brdffit_fit_params(fit, j->params);
        brdffit_fit_std_errors(fit, j->se);
        for (m = 0; m < 3; m++)
            for (c = 0; c < 4; c++)
                brdffit_fit_error(fit, (brdffit_fit_metric)m, c == 3 ? BRDFFIT_ALL_CHANNELS : c,
                                  &j->errors[m * 4 + c]);
        j->n_history = brdffit_fit_history(fit, j->cost, j->lambda);
        j->iterations = brdffit_fit_iterations(fit);
        j->passes = brdffit_fit_passes(fit);
        j->stop = brdffit_fit_stop_reason(fit);
        j->ok = 1;
    }
    brdffit_fit_destroy(fit);
}

static void *job_thread(void *arg)
{
    job_run(arg);
    return NULL;
}

/* Run every job in its own thread, all at once. */
static void run_parallel(job *jobs, size_t n)
{
    pthread_t tid[MAX_JOBS];
    size_t i;
    assert_true(n <= MAX_JOBS);
    for (i = 0; i < n; i++) assert_int_equal(pthread_create(&tid[i], NULL, job_thread, &jobs[i]), 0);
    for (i = 0; i < n; i++) assert_int_equal(pthread_join(tid[i], NULL), 0);
}

/* Bit-identical results. */
static void assert_same_job(const job *a, const job *b)
{
    assert_true(a->ok && b->ok);
    assert_int_equal(a->status, BRDFFIT_OK);
    assert_int_equal(b->status, BRDFFIT_OK);
    assert_int_equal(a->n, b->n);
    assert_memory_equal(a->params, b->params, a->n * sizeof(double));
    assert_memory_equal(a->se, b->se, a->n * sizeof(double));
    assert_memory_equal(a->errors, b->errors, sizeof a->errors);
    assert_int_equal(a->n_history, b->n_history);
    assert_memory_equal(a->cost, b->cost, a->n_history * sizeof(double));
    assert_memory_equal(a->lambda, b->lambda, a->n_history * sizeof(double));
    assert_int_equal(a->iterations, b->iterations);
    assert_int_equal(a->passes, b->passes);
    assert_int_equal(a->stop, b->stop);
}

/* Sequential reference, then everything in parallel, then compare. */
static void check_parallel_equals_sequential(job *jobs, size_t n)
{
    job *ref = malloc(n * sizeof *ref);
    size_t i;
    assert_non_null(ref);
    for (i = 0; i < n; i++) {
        ref[i] = jobs[i];
        job_run(&ref[i]);
        assert_true(ref[i].ok);
        assert_true(ref[i].passes > 0);
    }
    run_parallel(jobs, n);
    for (i = 0; i < n; i++) assert_same_job(&jobs[i], &ref[i]);
    free(ref);
}

/* ---- fits in parallel ------------------------------------------------------- */

/* Six threads, each fitting its own grid with its own model. */
static void test_different_grids_in_parallel(void **state)
{
    static const char *names[] = {"ashikhmin-shirley", "ggx", "ward", "blinn-phong",
                                  "cook-torrance", "phong"};
    static const double shape[] = {120.0, 0.2, 0.15, 80.0, 0.15, 40.0};
    static job jobs[6];
    brdffit_grid *grids[6];
    brdffit_model *models[6];
    size_t i;
    (void)state;
    for (i = 0; i < 6; i++) {
        grids[i] = grid_of(names[i], shape[i], 0.01, 10 + i);
        models[i] = make_model(names[i]);
        job_set(&jobs[i], grids[i], models[i], BRDFFIT_PIPELINE_AUTO, BRDFFIT_WEIGHT_DEFAULT,
                BRDFFIT_DEFAULT_CAP, 1);
    }
    check_parallel_equals_sequential(jobs, 6);
    for (i = 0; i < 6; i++) {
        brdffit_grid_destroy(grids[i]);
        brdffit_model_destroy(models[i]);
    }
}

/* Eight fits sharing one grid and one model: every pipeline, several
 * weightings and caps, and two pairs of identical fits. */
static void test_shared_grid_and_model(void **state)
{
    static job jobs[8];
    brdffit_grid *grid = grid_of("cook-torrance", 0.15, 0.01, 3);
    brdffit_model *model = make_model("ashikhmin-shirley");
    (void)state;
    job_set(&jobs[0], grid, model, BRDFFIT_PIPELINE_AUTO, BRDFFIT_WEIGHT_DEFAULT, DEG(75), 1);
    job_set(&jobs[1], grid, model, BRDFFIT_PIPELINE_AUTO, BRDFFIT_WEIGHT_DEFAULT, DEG(75), 1);
    job_set(&jobs[2], grid, model, BRDFFIT_PIPELINE_JOINT, BRDFFIT_WEIGHT_DEFAULT, DEG(75), 1);
    job_set(&jobs[3], grid, model, BRDFFIT_PIPELINE_JOINT, BRDFFIT_WEIGHT_DEFAULT, DEG(75), 1);
    job_set(&jobs[4], grid, model, BRDFFIT_PIPELINE_TWO_STAGE, BRDFFIT_WEIGHT_DEFAULT, DEG(75), 1);
    job_set(&jobs[5], grid, model, BRDFFIT_PIPELINE_AUTO, BRDFFIT_WEIGHT_NONE, DEG(60), 1);
    job_set(&jobs[6], grid, model, BRDFFIT_PIPELINE_AUTO, BRDFFIT_WEIGHT_COSINE, DEG(45), 1);
    job_set(&jobs[7], grid, model, BRDFFIT_PIPELINE_JOINT, BRDFFIT_WEIGHT_SOLID_ANGLE, DEG(90), 1);
    check_parallel_equals_sequential(jobs, 8);
    /* identical fits agree with each other, different options differ */
    assert_memory_equal(jobs[0].params, jobs[1].params, jobs[0].n * sizeof(double));
    assert_memory_equal(jobs[2].params, jobs[3].params, jobs[2].n * sizeof(double));
    assert_memory_not_equal(jobs[0].params, jobs[5].params, jobs[0].n * sizeof(double));
    brdffit_model_destroy(model);
    brdffit_grid_destroy(grid);
}

/* Fits with two pass threads each, four of them at once on one grid: the
 * same bits as the same fits one after the other (a pass is deterministic
 * for a given thread count), and the same result as one pass thread up to
 * rounding. */
static void test_fit_threads_inside_threads(void **state)
{
    static job jobs[4], single;
    brdffit_grid *grid = grid_of("ggx", 0.2, 0.01, 5);
    brdffit_model *ggx = make_model("ggx"), *as = make_model("ashikhmin-shirley");
    size_t i;
    (void)state;
    job_set(&jobs[0], grid, ggx, BRDFFIT_PIPELINE_AUTO, BRDFFIT_WEIGHT_DEFAULT, DEG(75), 2);
    job_set(&jobs[1], grid, ggx, BRDFFIT_PIPELINE_JOINT, BRDFFIT_WEIGHT_DEFAULT, DEG(75), 2);
    job_set(&jobs[2], grid, as, BRDFFIT_PIPELINE_AUTO, BRDFFIT_WEIGHT_DEFAULT, DEG(75), 2);
    job_set(&jobs[3], grid, as, BRDFFIT_PIPELINE_TWO_STAGE, BRDFFIT_WEIGHT_DEFAULT, DEG(75), 2);
    check_parallel_equals_sequential(jobs, 4);
    job_set(&single, grid, ggx, BRDFFIT_PIPELINE_AUTO, BRDFFIT_WEIGHT_DEFAULT, DEG(75), 1);
    job_run(&single);
    assert_true(single.ok);
    for (i = 0; i < single.n; i++) assert_close(jobs[0].params[i], single.params[i], 1e-8);
    brdffit_model_destroy(ggx);
    brdffit_model_destroy(as);
    brdffit_grid_destroy(grid);
}

/* ---- readers of shared handles while fits run ------------------------------ */

typedef struct reader {
    const brdffit_grid *grid;
    const brdffit_model *model;
    const double *params;
    double weights[960], eval[3], values[3 * 960];
    unsigned char pixels[3 * 19 * 96];
    double worst_jacobian;
    brdffit_status st[5];
} reader;

static void reader_run(reader *r)
{
    brdffit_jacobian_report rep;
    size_t w = 0, h = 0;
    rep.struct_size = sizeof rep;
    r->st[0] = brdffit_grid_weights(r->grid, DEG(60), BRDFFIT_WEIGHT_DEFAULT, r->weights, NULL);
    r->st[1] = brdffit_grid_eval(r->grid, DEG(20), DEG(170), DEG(33), DEG(10), r->eval, NULL);
    r->st[2] = brdffit_model_eval_grid(r->model, r->grid, 0, 960, r->params, r->values, NULL,
                                       NULL);
    r->st[3] = brdffit_image_texture_size(r->grid, NULL, &w, &h, NULL);
    if (r->st[3] == BRDFFIT_OK && 3 * w * h <= sizeof r->pixels)
        r->st[3] = brdffit_image_texture(r->pixels, 3 * w, BRDFFIT_TEXTURE_DIFFERENCE, r->grid,
                                         r->model, r->params, NULL, NULL, NULL);
    r->st[4] = brdffit_model_check_jacobian(r->model, r->grid, r->params, &rep, NULL);
    r->worst_jacobian = rep.worst_error;
}

static void *reader_thread(void *arg)
{
    reader_run(arg);
    return NULL;
}

/* Grid and model readers (weights, interpolation, evaluation, textures,
 * the Jacobian check) in three threads next to two fits on the same
 * handles: every reader sees exactly what it sees alone. */
static void test_readers_while_fitting(void **state)
{
    static reader ref, rd[3];
    static job jobs[2];
    pthread_t tid[3], fit_tid[2];
    brdffit_grid *grid = grid_of("ashikhmin-shirley", 120.0, 0.0, 1);
    brdffit_model *model = make_model("ashikhmin-shirley");
    double p[7] = {120.0, 0.1, 0.15, 0.2, 0.2, 0.25, 0.3};
    size_t i, k;
    (void)state;
    assert_int_equal(brdffit_grid_sample_count(grid), 960);
    memset(&ref, 0, sizeof ref);
    ref.grid = grid;
    ref.model = model;
    ref.params = p;
    reader_run(&ref);
    for (k = 0; k < 5; k++) assert_int_equal(ref.st[k], BRDFFIT_OK);
    for (i = 0; i < 3; i++) {
        memset(&rd[i], 0, sizeof rd[i]);
        rd[i].grid = grid;
        rd[i].model = model;
        rd[i].params = p;
    }
    job_set(&jobs[0], grid, model, BRDFFIT_PIPELINE_AUTO, BRDFFIT_WEIGHT_DEFAULT, DEG(75), 2);
    job_set(&jobs[1], grid, model, BRDFFIT_PIPELINE_JOINT, BRDFFIT_WEIGHT_DEFAULT, DEG(75), 1);
    for (i = 0; i < 2; i++)
        assert_int_equal(pthread_create(&fit_tid[i], NULL, job_thread, &jobs[i]), 0);
    for (i = 0; i < 3; i++) assert_int_equal(pthread_create(&tid[i], NULL, reader_thread, &rd[i]), 0);
    for (i = 0; i < 3; i++) assert_int_equal(pthread_join(tid[i], NULL), 0);
    for (i = 0; i < 2; i++) assert_int_equal(pthread_join(fit_tid[i], NULL), 0);
    for (i = 0; i < 3; i++) {
        for (k = 0; k < 5; k++) assert_int_equal(rd[i].st[k], BRDFFIT_OK);
        assert_memory_equal(rd[i].weights, ref.weights, sizeof ref.weights);
        assert_memory_equal(rd[i].eval, ref.eval, sizeof ref.eval);
        assert_memory_equal(rd[i].values, ref.values, sizeof ref.values);
        assert_memory_equal(rd[i].pixels, ref.pixels, sizeof ref.pixels);
        assert_true(rd[i].worst_jacobian == ref.worst_jacobian);
    }
    /* the fits recovered the data's parameters */
    for (i = 0; i < 2; i++) {
        assert_true(jobs[i].ok);
        assert_close(jobs[i].params[0], 120.0, 1e-6);
    }
    brdffit_model_destroy(model);
    brdffit_grid_destroy(grid);
}

/* ---- loaders in parallel ------------------------------------------------------ */

typedef struct loader {
    const char *text;
    size_t size;
    brdffit_grid *grid;
    brdffit_status status;
} loader;

static void *loader_thread(void *arg)
{
    loader *l = arg;
    l->status = brdffit_load_csv_buffer(&l->grid, l->text, l->size, NULL, NULL);
    return NULL;
}

/* Four threads load the same CSV text at once; each grid holds exactly the
 * values of a grid loaded alone. */
static void test_loaders_in_parallel(void **state)
{
    static const double ti[] = {0, 30, 60}, to[] = {0, 20, 40, 60}, po[] = {0, 90, 180};
    fx_axes a;
    double *values;
    char *text;
    loader ref, ld[4];
    pthread_t tid[4];
    size_t i, c;
    (void)state;
    fx_axes_set(&a, ti, 3, to, 4, po, 3);
    values = fx_values(&a.axes, 3);
    assert_non_null(values);
    text = fx_csv_regular(&a, 3, values, NULL, "nan", 1);
    assert_non_null(text);
    memset(&ref, 0, sizeof ref);
    ref.text = text;
    ref.size = strlen(text);
    loader_thread(&ref);
    assert_int_equal(ref.status, BRDFFIT_OK);
    for (i = 0; i < 4; i++) {
        ld[i] = ref;
        ld[i].grid = NULL;
        assert_int_equal(pthread_create(&tid[i], NULL, loader_thread, &ld[i]), 0);
    }
    for (i = 0; i < 4; i++) assert_int_equal(pthread_join(tid[i], NULL), 0);
    for (i = 0; i < 4; i++) {
        assert_int_equal(ld[i].status, BRDFFIT_OK);
        assert_int_equal(brdffit_grid_sample_count(ld[i].grid), 36);
        for (c = 0; c < 3; c++) {
            const double *x, *y;
            assert_int_equal(brdffit_grid_values(ld[i].grid, c, &x), BRDFFIT_OK);
            assert_int_equal(brdffit_grid_values(ref.grid, c, &y), BRDFFIT_OK);
            assert_memory_equal(x, y, 36 * sizeof(double));
        }
        brdffit_grid_destroy(ld[i].grid);
    }
    brdffit_grid_destroy(ref.grid);
    free(text);
    free(values);
}

/* ---- cancel from another thread --------------------------------------------- */

/* The iteration callback blocks on its first call until the main thread has
 * called brdffit_fit_cancel(), so the request arrives in the middle of a
 * run, between two iterations. */
typedef struct gate {
    pthread_mutex_t mutex;
    pthread_cond_t cond;
    int reached, cancelled;
    size_t calls;
    brdffit_fit *fit;
    brdffit_status status;
} gate;

static void gate_init(gate *g, brdffit_fit *fit)
{
    memset(g, 0, sizeof *g);
    pthread_mutex_init(&g->mutex, NULL);
    pthread_cond_init(&g->cond, NULL);
    g->fit = fit;
}

static void gate_free(gate *g)
{
    pthread_cond_destroy(&g->cond);
    pthread_mutex_destroy(&g->mutex);
}

static int blocking_callback(const brdffit_iteration *it, void *user)
{
    gate *g = user;
    (void)it;
    pthread_mutex_lock(&g->mutex);
    if (g->calls++ == 0) {
        g->reached = 1;
        pthread_cond_broadcast(&g->cond);
        while (!g->cancelled) pthread_cond_wait(&g->cond, &g->mutex);
    }
    pthread_mutex_unlock(&g->mutex);
    return 0;
}

static void *fit_thread(void *arg)
{
    gate *g = arg;
    g->status = brdffit_fit_run(g->fit);
    return NULL;
}

/* Wait until the fit thread is inside the gate, cancel, open the gate. */
static void cancel_at_gate(gate *g)
{
    pthread_t tid;
    assert_int_equal(pthread_create(&tid, NULL, fit_thread, g), 0);
    pthread_mutex_lock(&g->mutex);
    while (!g->reached) pthread_cond_wait(&g->cond, &g->mutex);
    pthread_mutex_unlock(&g->mutex);
    brdffit_fit_cancel(g->fit);
    pthread_mutex_lock(&g->mutex);
    g->cancelled = 1;
    pthread_cond_broadcast(&g->cond);
    pthread_mutex_unlock(&g->mutex);
    assert_int_equal(pthread_join(tid, NULL), 0);
}

static void assert_params_in_bounds(const brdffit_fit *fit, const brdffit_model *model, size_t nc)
{
    double p[MAXV];
    size_t k, c, np = brdffit_model_param_count(model);
    assert_int_equal(brdffit_fit_params(fit, p), BRDFFIT_OK);
    for (k = 0; k < np; k++) {
        const brdffit_param_info *info = brdffit_model_param(model, k);
        for (c = 0; c < nc; c++) {
            double v = p[brdffit_model_vector_index(model, k, c, nc)];
            assert_true(isfinite(v) && v >= info->lower && v <= info->upper);
        }
    }
}

static int count_calls(const brdffit_iteration *it, void *user)
{
    (void)it;
    (*(size_t *)user)++;
    return 0;
}

/* A long fit (a two-lobe model on data from another model) in each
 * pipeline: the cancel stops it after at most one more iteration, with
 * BRDFFIT_STOP_CANCELLED and a usable result; the request is consumed, so
 * the next run goes to its end, which takes many more iterations. */
static void test_fit_cancel_from_another_thread(void **state)
{
    static const int pipelines[] = {BRDFFIT_PIPELINE_JOINT, BRDFFIT_PIPELINE_AUTO,
                                    BRDFFIT_PIPELINE_TWO_STAGE};
    brdffit_grid *grid = grid_of("ggx", 0.12, 0.02, 9);
    brdffit_model *model = make_model("ashikhmin-shirley-2");
    size_t i;
    (void)state;
    for (i = 0; i < 3; i++) {
        brdffit_fit *fit = NULL;
        size_t calls = 0;
        gate g;
        assert_int_equal(brdffit_fit_create(&fit, grid, model, NULL, NULL), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, pipelines[i]), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_MAX_ITERATIONS, 5000), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_THREADS, 2), BRDFFIT_OK);
        gate_init(&g, fit);
        assert_int_equal(brdffit_fit_set_callback(fit, blocking_callback, &g), BRDFFIT_OK);
        cancel_at_gate(&g);
        assert_int_equal(g.status, BRDFFIT_OK);
        assert_int_equal(brdffit_fit_stop_reason(fit), BRDFFIT_STOP_CANCELLED);
        /* the iteration that was blocked, and at most one more */
        assert_true(brdffit_fit_iterations(fit) >= 1);
        assert_true(brdffit_fit_iterations(fit) <= 2);
        assert_true(g.calls <= 2);
        assert_params_in_bounds(fit, model, 3);

        /* consumed: the same fit now runs to its end, through many more
         * iterations (counted over all its LM runs) */
        assert_int_equal(brdffit_fit_set_callback(fit, count_calls, &calls), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
        assert_int_not_equal(brdffit_fit_stop_reason(fit), BRDFFIT_STOP_CANCELLED);
        assert_true(calls > 5);
        brdffit_fit_destroy(fit);
        gate_free(&g);
    }
    brdffit_model_destroy(model);
    brdffit_grid_destroy(grid);
}

/* ---- cancel during the global scan of the auto pipeline ------------------ */

/* A user model value = cd / pi + cs exp(-k (1 - n.h)) that records every
 * k it is evaluated at and, on the first evaluation at the `block_at`-th
 * distinct k (the scan's points come one after the other), blocks until the
 * main thread has cancelled. */
typedef struct scan_gate {
    gate g;
    size_t evals, distinct, block_at, evals_at_cancel;
    double k_seen[4096];
} scan_gate;

static brdffit_status gated_gauss(const brdffit_batch *b, const double *p, size_t nc,
                                  double *values, double *jac, void *user)
{
    scan_gate *sg = user;
    size_t s, c, n = b->n;
    double k = p[0];
    pthread_mutex_lock(&sg->g.mutex);
    if (sg->evals == 0 || k != sg->k_seen[(sg->evals - 1) % 4096]) sg->distinct++;
    sg->k_seen[sg->evals % 4096] = k;
    sg->evals++;
    if (sg->block_at != 0 && sg->distinct == sg->block_at && !sg->g.reached) {
        sg->g.reached = 1;
        pthread_cond_broadcast(&sg->g.cond);
        while (!sg->g.cancelled) pthread_cond_wait(&sg->g.cond, &sg->g.mutex);
        sg->evals_at_cancel = sg->evals;
    }
    pthread_mutex_unlock(&sg->g.mutex);
    for (s = 0; s < n; s++) {
        double e = exp(-k * (1.0 - b->nh[s]));
        for (c = 0; c < nc; c++) {
            values[c * n + s] = p[1 + c] / 3.14159265358979323846 + p[1 + nc + c] * e;
            if (jac != NULL) {
                jac[(0 * nc + c) * n + s] = -p[1 + nc + c] * (1.0 - b->nh[s]) * e;
                jac[(1 * nc + c) * n + s] = 1.0 / 3.14159265358979323846;
                jac[(2 * nc + c) * n + s] = e;
            }
        }
    }
    return BRDFFIT_OK;
}

/* The auto pipeline cancelled in the middle of its scan returns the best
 * point it had evaluated before the cancel, with that point's colours, and
 * evaluates the model only to finish the pass in progress, to solve those
 * colours and for the error figures: at most three passes. A pass hands
 * the model its samples chunk by chunk, so one pass is as many
 * evaluations as the first scan point took. */
static void test_fit_cancel_during_scan(void **state)
{
    static const brdffit_param_info params[] = {
        {"k", BRDFFIT_PARAM_LOG_SCALE, 1e-2, 1e5, 10.0},
        {"cd", BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR, 0.0, HUGE_VAL, 0.1},
        {"cs", BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR, 0.0, HUGE_VAL, 0.1},
    };
    static const double ti[] = {30},
                        to[] = {0, 5, 10, 15, 20, 25, 30, 35, 40, 45, 50, 55, 60, 65, 70},
                        po[] = {0, 15, 30, 45, 60, 75, 90, 105, 120, 135, 150, 165, 180};
    static scan_gate sg;
    const double truth[7] = {300.0, 0.1, 0.2, 0.3, 0.4, 0.35, 0.3};
    brdffit_model_def def = BRDFFIT_MODEL_DEF_INIT;
    brdffit_model *model = NULL;
    brdffit_grid *grid;
    brdffit_fit *fit = NULL;
    fx_axes a;
    double got[7];
    size_t i, n_scanned, per_pass = 0;
    int seen = 0;
    (void)state;
    def.name = "gated-gauss";
    def.n_params = 3;
    def.params = params;
    def.eval = gated_gauss;
    def.user = &sg;
    memset(&sg, 0, sizeof sg);
    gate_init(&sg.g, NULL);
    assert_int_equal(brdffit_model_create_custom(&model, &def, NULL, NULL), BRDFFIT_OK);
    fx_axes_set(&a, ti, 1, to, 15, po, 13);
    grid = fx_grid_from_model(model, truth, 3, &a.axes, 0.0, 1);
    assert_non_null(grid);
    assert_int_equal(brdffit_fit_create(&fit, grid, model, NULL, NULL), BRDFFIT_OK);
    sg.g.fit = fit;
    sg.evals = sg.distinct = 0;
    sg.block_at = 3; /* the third of the scan's 22 points */
    cancel_at_gate(&sg.g);
    assert_int_equal(sg.g.status, BRDFFIT_OK);
    assert_int_equal(brdffit_fit_stop_reason(fit), BRDFFIT_STOP_CANCELLED);
    /* after the cancel: the colours at the chosen point and the error figures */
    /* one pass is as many evaluations as the first scan point took */
    while (per_pass < sg.evals && sg.k_seen[per_pass] == sg.k_seen[0]) per_pass++;
    assert_true(per_pass >= 1 && sg.evals < 4096);
    assert_true(sg.evals - sg.evals_at_cancel <= 3 * per_pass);
    assert_params_in_bounds(fit, model, 3);
    assert_int_equal(brdffit_fit_params(fit, got), BRDFFIT_OK);
    /* the k returned is one the scan had evaluated before the cancel */
    n_scanned = sg.evals_at_cancel;
    for (i = 0; i < n_scanned; i++) seen |= sg.k_seen[i] == got[0];
    brdffit_fit_destroy(fit);
    gate_free(&sg.g);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
    if (!seen)
        print_error("cancelled scan returned k = %.17g, which was not evaluated before the "
                    "cancel (%zu evaluations)\n",
                    got[0], n_scanned);
    assert_true(seen);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_different_grids_in_parallel),
        cmocka_unit_test(test_shared_grid_and_model),
        cmocka_unit_test(test_fit_threads_inside_threads),
        cmocka_unit_test(test_readers_while_fitting),
        cmocka_unit_test(test_loaders_in_parallel),
        cmocka_unit_test(test_fit_cancel_from_another_thread),
        cmocka_unit_test(test_fit_cancel_during_scan),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
