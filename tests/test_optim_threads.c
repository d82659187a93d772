/* The optimizer across threads: cancelling a run from another thread, and
 * two optimizers in two threads giving the same bits as one after the
 * other. */
#include <math.h>
#include <pthread.h>
#include <string.h>

#include "optim_problems.h"
#include "test_support.h"

/* --- cancel ------------------------------------------------------------------------------ */

/* Meyer's problem whose evaluation number block_at waits until the main
 * thread has called brdffit_optimizer_cancel(). */
typedef struct gate {
    pthread_mutex_t mutex;
    pthread_cond_t cond;
    size_t calls, block_at;
    size_t completed;          /* iterations finished, from the iteration callback */
    size_t completed_at_block; /* ... when the evaluation blocked */
    int reached, cancelled;
} gate;

static brdffit_status gated_meyer(const double *x, double *r, double *jac, void *user)
{
    gate *g = user;
    pthread_mutex_lock(&g->mutex);
    g->calls++;
    if (g->calls == g->block_at) {
        g->completed_at_block = g->completed;
        g->reached = 1;
        pthread_cond_broadcast(&g->cond);
        while (!g->cancelled) pthread_cond_wait(&g->cond, &g->mutex);
    }
    pthread_mutex_unlock(&g->mutex);
    return optim_meyer(x, r, jac, NULL);
}

static int count_iterations(const brdffit_iteration *info, void *user)
{
    gate *g = user;
    (void)info;
    pthread_mutex_lock(&g->mutex);
    g->completed++;
    pthread_mutex_unlock(&g->mutex);
    return 0;
}

typedef struct worker {
    brdffit_optimizer *opt;
    double x[3];
    brdffit_status status;
} worker;

static void *run_worker(void *arg)
{
    worker *w = arg;
    w->status = brdffit_optimizer_run(w->opt, w->x);
    return NULL;
}

static void test_cancel_from_another_thread(void **state)
{
    brdffit_optimizer *opt = NULL;
    pthread_t thread;
    gate g;
    worker w;
    double r[16], cost = 0.0;
    size_t i;
    (void)state;
    memset(&g, 0, sizeof g);
    pthread_mutex_init(&g.mutex, NULL);
    pthread_cond_init(&g.cond, NULL);
    g.block_at = 20; /* well inside the run (Meyer needs ~140 iterations) */
    assert_int_equal(brdffit_optimizer_create(&opt, 3, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set_residuals(opt, 16, gated_meyer, &g), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set_callback(opt, count_iterations, &g), BRDFFIT_OK);
    w.opt = opt;
    w.x[0] = 0.02;
    w.x[1] = 4000.0;
    w.x[2] = 250.0;
    assert_int_equal(pthread_create(&thread, NULL, run_worker, &w), 0);
    pthread_mutex_lock(&g.mutex);
    while (!g.reached) pthread_cond_wait(&g.cond, &g.mutex);
    brdffit_optimizer_cancel(opt);
    g.cancelled = 1;
    pthread_cond_broadcast(&g.cond);
    pthread_mutex_unlock(&g.mutex);
    assert_int_equal(pthread_join(thread, NULL), 0);

    assert_int_equal(w.status, BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_stop_reason(opt), BRDFFIT_STOP_CANCELLED);
    /* stopped within the iteration that was running */
    assert_true(brdffit_optimizer_iterations(opt) <= g.completed_at_block + 1);
    assert_true(brdffit_optimizer_iterations(opt) >= g.completed_at_block);
    /* the best point so far, with its cost */
    optim_meyer(w.x, r, NULL, NULL);
    for (i = 0; i < 16; i++) cost += r[i] * r[i];
    assert_close(cost, brdffit_optimizer_final_cost(opt), 1e-12);
    assert_true(brdffit_optimizer_final_cost(opt) < brdffit_optimizer_initial_cost(opt));

    /* the request was consumed: the next run goes to the end */
    g.block_at = 0;
    w.x[0] = 0.02;
    w.x[1] = 4000.0;
    w.x[2] = 250.0;
    assert_int_equal(brdffit_optimizer_run(opt, w.x), BRDFFIT_OK);
    assert_int_not_equal(brdffit_optimizer_stop_reason(opt), BRDFFIT_STOP_CANCELLED);
    assert_close(brdffit_optimizer_final_cost(opt), 87.9458551708511, 1e-9);
    brdffit_optimizer_destroy(opt);
    pthread_cond_destroy(&g.cond);
    pthread_mutex_destroy(&g.mutex);
}

/* A cancel with no run in progress stops the next run before its first
 * iteration, and only that one. */
static void test_cancel_before_run(void **state)
{
    brdffit_optimizer *opt = NULL;
    double x[2] = {-1.2, 1.0};
    (void)state;
    assert_int_equal(brdffit_optimizer_create(&opt, 2, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set_residuals(opt, 2, optim_rosenbrock, NULL), BRDFFIT_OK);
    brdffit_optimizer_cancel(opt);
    brdffit_optimizer_cancel(opt);
    assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_stop_reason(opt), BRDFFIT_STOP_CANCELLED);
    assert_int_equal(brdffit_optimizer_iterations(opt), 0);
    assert_true(x[0] == -1.2 && x[1] == 1.0);
    assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
    assert_int_not_equal(brdffit_optimizer_stop_reason(opt), BRDFFIT_STOP_CANCELLED);
    assert_close(x[0], 1.0, 1e-8);
    brdffit_optimizer_destroy(opt);
}

/* --- determinism across threads ----------------------------------------------------------- */

enum { N_JOBS = 3, HIST = 512 };

typedef struct job_result {
    double x[N_JOBS][OPTIM_MAX_PARAMS];
    double history[N_JOBS][HIST];
    double cov[N_JOBS][OPTIM_MAX_PARAMS * OPTIM_MAX_PARAMS];
    size_t n_history[N_JOBS];
    int ok;
} job_result;

/* Meyer (residual form), the exponential and the rational fit (normal
 * form), each with its own optimizer and data. */
static void *run_jobs(void *arg)
{
    job_result *res = arg;
    optim_fit_data exp_data, rat_data;
    optim_normal_adapter ad;
    int k;
    res->ok = 1;
    optim_make_exp_data(&exp_data);
    optim_make_rational_data(&rat_data);
    for (k = 0; k < N_JOBS; k++) {
        brdffit_optimizer *opt = NULL;
        size_t p = k == 0 ? 3 : k == 1 ? 3 : 4;
        double *x = res->x[k];
        memset(x, 0, OPTIM_MAX_PARAMS * sizeof *x);
        if (brdffit_optimizer_create(&opt, p, NULL, NULL) != BRDFFIT_OK) {
            res->ok = 0;
            return NULL;
        }
        if (k == 0) {
            x[0] = 0.02;
            x[1] = 4000.0;
            x[2] = 250.0;
            brdffit_optimizer_set_residuals(opt, 16, optim_meyer, NULL);
        } else if (k == 1) {
            x[0] = 1.0;
            x[1] = 3.0;
            optim_normal_adapter_init(&ad, optim_exp_fit, &exp_data, exp_data.n, 3);
            brdffit_optimizer_set_normal(opt, exp_data.n, optim_normal_adapter_fn, &ad);
        } else {
            x[0] = x[1] = 1.0;
            x[2] = x[3] = 0.1;
            optim_normal_adapter_init(&ad, optim_rational_fit, &rat_data, rat_data.n, 4);
            brdffit_optimizer_set_normal(opt, rat_data.n, optim_normal_adapter_fn, &ad);
            brdffit_optimizer_set_damping(opt, brdffit_damping_marquardt());
        }
        if (brdffit_optimizer_run(opt, x) != BRDFFIT_OK ||
            brdffit_optimizer_history(opt, NULL, NULL) > HIST)
            res->ok = 0;
        else
            res->n_history[k] = brdffit_optimizer_history(opt, res->history[k], NULL);
        brdffit_optimizer_covariance(opt, res->cov[k]);
        brdffit_optimizer_destroy(opt);
    }
    return NULL;
}

static void assert_same(const job_result *a, const job_result *b)
{
    int k;
    assert_true(a->ok && b->ok);
    for (k = 0; k < N_JOBS; k++) {
        assert_int_equal(a->n_history[k], b->n_history[k]);
        assert_memory_equal(a->x[k], b->x[k], sizeof a->x[k]);
        assert_memory_equal(a->history[k], b->history[k], a->n_history[k] * sizeof(double));
        assert_memory_equal(a->cov[k], b->cov[k], sizeof a->cov[k]);
    }
}

static void test_two_threads_bit_identical(void **state)
{
    static job_result serial, t1, t2;
    pthread_t a, b;
    (void)state;
    memset(&serial, 0, sizeof serial);
    memset(&t1, 0, sizeof t1);
    memset(&t2, 0, sizeof t2);
    run_jobs(&serial);
    assert_true(serial.ok);
    assert_close(serial.x[0][0], 0.005609636471028, 1e-5);
    assert_int_equal(pthread_create(&a, NULL, run_jobs, &t1), 0);
    assert_int_equal(pthread_create(&b, NULL, run_jobs, &t2), 0);
    assert_int_equal(pthread_join(a, NULL), 0);
    assert_int_equal(pthread_join(b, NULL), 0);
    assert_same(&serial, &t1);
    assert_same(&serial, &t2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cancel_from_another_thread),
        cmocka_unit_test(test_cancel_before_run),
        cmocka_unit_test(test_two_threads_bit_identical),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
