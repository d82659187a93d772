/* Standard errors and covariance of block-structured problems (lib/optim/
 * blocks.c): a linear least-squares problem shaped like a fit of many
 * channels (a few shared parameters, small per-channel blocks) against
 * the inverse of J^T J computed here by Gauss-Jordan elimination; the time
 * they take for 400 channels; the fit's one call for both
 * (bf_optim_std_errors_covariance()) against the two accessors, bit for
 * bit; and the stop requests of the O(n^3) linear
 * algebra (the fit's cancel reaches them through optim/watch.h). */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/linalg.h"
#include "fit_fixtures.h"
#include "grid_fixtures.h"
#include "optim/sandwich.h"
#include "test_support.h"


typedef struct arrow {
    size_t h, k, nc, p, rows, rpc; /* rpc rows per channel */
    double *j; /* rows x (h + k): hub columns, then the row's channel's */
    double *y;
    size_t dead; /* a channel whose columns are all 0, or nc for none */
} arrow;

static double uniform(uint64_t *s)
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*s >> 11) / 9007199254740992.0;
}

static void arrow_make(arrow *a, size_t h, size_t k, size_t nc, size_t dead)
{
    uint64_t rng = 12345;
    size_t i, q, w = h + k;
    a->h = h;
    a->k = k;
    a->nc = nc;
    a->p = h + k * nc;
    a->rpc = k < 6 ? 12 : 2 * k;
    a->rows = nc * a->rpc;
    a->dead = dead;
    a->j = malloc(a->rows * w * sizeof *a->j);
    a->y = malloc(a->rows * sizeof *a->y);
    assert_non_null(a->j);
    assert_non_null(a->y);
    for (i = 0; i < a->rows; i++) {
        for (q = 0; q < w; q++) {
            double v = uniform(&rng) - 0.5;
            a->j[i * w + q] = q >= h && i / a->rpc == dead ? 0.0 : v;
        }
        a->y[i] = uniform(&rng);
    }
}

static size_t column(const arrow *a, size_t row, size_t q)
{
    return q < a->h ? q : a->h + (row / a->rpc) * a->k + (q - a->h);
}

static brdffit_status arrow_normal(const double *x, double *cost, double *jtj, double *jtr,
                                   void *user)
{
    const arrow *a = user;
    size_t i, q, s, w = a->h + a->k;
    *cost = 0.0;
    if (jtj != NULL) {
        memset(jtj, 0, a->p * a->p * sizeof *jtj);
        memset(jtr, 0, a->p * sizeof *jtr);
    }
    for (i = 0; i < a->rows; i++) {
        const double *row = a->j + i * w;
        double r = -a->y[i];
        for (q = 0; q < w; q++) r += row[q] * x[column(a, i, q)];
        *cost += r * r;
        if (jtj == NULL) continue;
        for (q = 0; q < w; q++) {
            jtr[column(a, i, q)] += row[q] * r;
            for (s = 0; s < w; s++)
                jtj[column(a, i, q) * a->p + column(a, i, s)] += row[q] * row[s];
        }
    }
    return BRDFFIT_OK;
}

/* Inverse of the n x n matrix m in place (Gauss-Jordan, partial pivoting). */
static void invert(double *m, size_t n)
{
    double *aug = calloc(n * 2 * n, sizeof *aug);
    size_t i, j, c, r;
    assert_non_null(aug);
    for (i = 0; i < n; i++) {
        memcpy(aug + i * 2 * n, m + i * n, n * sizeof *m);
        aug[i * 2 * n + n + i] = 1.0;
    }
    for (c = 0; c < n; c++) {
        size_t piv = c;
        for (r = c + 1; r < n; r++)
            if (fabs(aug[r * 2 * n + c]) > fabs(aug[piv * 2 * n + c])) piv = r;
        for (j = 0; j < 2 * n; j++) {
            double t = aug[c * 2 * n + j];
            aug[c * 2 * n + j] = aug[piv * 2 * n + j];
            aug[piv * 2 * n + j] = t;
        }
        for (r = 0; r < n; r++) {
            double f = aug[r * 2 * n + c] / aug[c * 2 * n + c];
            if (r == c) continue;
            for (j = 0; j < 2 * n; j++) aug[r * 2 * n + j] -= f * aug[c * 2 * n + j];
        }
    }
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++) m[i * n + j] = aug[i * 2 * n + n + j] / aug[i * 2 * n + i];
    free(aug);
}

/* Whether parameter j belongs to the dead channel. */
static int is_dead(const arrow *a, size_t j)
{
    return a->dead < a->nc && j >= a->h + a->dead * a->k && j < a->h + (a->dead + 1) * a->k;
}

/* Fit the problem, then compare the optimizer's standard errors and
 * covariance with s^2 (J^T J)^-1 over the live parameters. */
static void check_arrow(size_t h, size_t k, size_t nc, size_t dead)
{
    arrow a;
    brdffit_optimizer *opt = NULL;
    double *x, *se, *cov, *jtj, *jtr, *inv, cost, f;
    size_t *live, n = 0, i, j;
    arrow_make(&a, h, k, nc, dead);
    x = calloc(a.p, sizeof *x);
    se = calloc(a.p, sizeof *se);
    cov = calloc(a.p * a.p, sizeof *cov);
    jtj = calloc(a.p * a.p, sizeof *jtj);
    jtr = calloc(a.p, sizeof *jtr);
    live = calloc(a.p, sizeof *live);
    inv = calloc(a.p * a.p, sizeof *inv);
    assert_true(x && se && cov && jtj && jtr && live && inv);
    assert_int_equal(brdffit_optimizer_create(&opt, a.p, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set_normal(opt, a.rows, arrow_normal, &a), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_std_errors(opt, se), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_covariance(opt, cov), BRDFFIT_OK);
    /* both at once, as the fit takes them: the same bits */
    assert_int_equal(bf_optim_std_errors_covariance(opt, jtr, inv), BRDFFIT_OK);
    assert_memory_equal(jtr, se, a.p * sizeof *se);
    assert_memory_equal(inv, cov, a.p * a.p * sizeof *cov);
    assert_int_equal(arrow_normal(x, &cost, jtj, jtr, &a), BRDFFIT_OK);
    f = brdffit_optimizer_final_cost(opt) / (double)(a.rows - a.p);
    for (j = 0; j < a.p; j++)
        if (!is_dead(&a, j)) live[n++] = j;
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++) inv[i * n + j] = jtj[live[i] * a.p + live[j]];
    invert(inv, n);
    for (j = 0; j < a.p; j++)
        if (is_dead(&a, j)) {
            assert_true(se[j] == HUGE_VAL);
            assert_true(cov[j * a.p + j] == HUGE_VAL);
        }
    for (i = 0; i < n; i++) {
        double want = sqrt(f * inv[i * n + i]);
        if (!(fabs(se[live[i]] - want) <= 1e-9 * want))
            print_error("h %zu k %zu nc %zu: se[%zu] %.17g, want %.17g\n", h, k, nc, live[i],
                        se[live[i]], want);
        assert_true(fabs(se[live[i]] - want) <= 1e-9 * want);
        for (j = 0; j < n; j++) {
            double c = cov[live[i] * a.p + live[j]], cw = f * inv[i * n + j];
            double scale = sqrt(f * inv[i * n + i] * f * inv[j * n + j]);
            assert_true(fabs(c - cw) <= 1e-9 * scale);
        }
    }
    brdffit_optimizer_destroy(opt);
    free(a.j);
    free(a.y);
    free(x);
    free(se);
    free(cov);
    free(jtj);
    free(jtr);
    free(live);
    free(inv);
}

/* One shared parameter and two colours per channel (Ashikhmin-Shirley's
 * shape), with one channel without data; three shared and three per
 * channel; blocks of 17 (beyond the block limit: the dense path) and a
 * small problem (dense too): the same answer every way. */
static void test_block_structure_matches_the_inverse(void **state)
{
    (void)state;
    check_arrow(1, 2, 100, 7);
    check_arrow(3, 3, 60, 60);
    check_arrow(1, 17, 10, 10);
    check_arrow(1, 2, 20, 3);
}

static double seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* 400 channels (801 parameters): the standard errors take far less than
 * the O(p^3) eigen-decomposition's tens of seconds. */
static void test_block_structure_is_fast(void **state)
{
    arrow a;
    brdffit_optimizer *opt = NULL;
    double *x, *se, t0, elapsed;
    size_t j;
    (void)state;
    arrow_make(&a, 1, 2, 400, 400);
    x = calloc(a.p, sizeof *x);
    se = calloc(a.p, sizeof *se);
    assert_true(x && se);
    assert_int_equal(brdffit_optimizer_create(&opt, a.p, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set_normal(opt, a.rows, arrow_normal, &a), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_MAX_ITERATIONS, 1.0), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
    t0 = seconds();
    assert_int_equal(brdffit_optimizer_std_errors(opt, se), BRDFFIT_OK);
    elapsed = seconds() - t0;
    for (j = 0; j < a.p; j++) assert_true(se[j] > 0.0 && isfinite(se[j]));
    if (elapsed > 1.0) print_error("standard errors of 801 parameters took %g s\n", elapsed);
    assert_true(elapsed < 1.0);
    brdffit_optimizer_destroy(opt);
    free(a.j);
    free(a.y);
    free(x);
    free(se);
}

/* A joint fit of 400 channels cancelled from its first iteration callback
 * returns at once (before: the O(p^3) standard errors, 801 parameters,
 * tens of seconds, never looked at the cancel), with the stop reason
 * BRDFFIT_STOP_CANCELLED. */
typedef struct cancel_clock {
    brdffit_fit *fit;
    double at;
} cancel_clock;

static int cancel_and_note(const brdffit_iteration *it, void *user)
{
    cancel_clock *cc = user;
    (void)it;
    if (cc->at == 0.0) {
        cc->at = seconds();
        brdffit_fit_cancel(cc->fit);
    }
    return 0;
}

static void test_fit_cancel_with_many_channels(void **state)
{
    static const double ti[] = {0, 30, 60}, to[] = {0, 20, 40, 60}, po[] = {0, 45, 90, 135, 180};
    brdffit_model *model = NULL;
    brdffit_grid *grid;
    brdffit_fit *fit = NULL;
    cancel_clock cc = {NULL, 0.0};
    fx_axes axes;
    double *p, delay;
    size_t nc = 400, n;
    (void)state;
    assert_int_equal(brdffit_model_create(&model, "ashikhmin-shirley", NULL, NULL), BRDFFIT_OK);
    n = brdffit_model_vector_size(model, nc);
    p = calloc(n, sizeof *p);
    assert_non_null(p);
    assert_int_equal(brdffit_model_default_params(model, nc, p), BRDFFIT_OK);
    fx_axes_set(&axes, ti, 3, to, 4, po, 5);
    grid = fx_grid_from_model(model, p, nc, &axes.axes, 0.05, 3);
    assert_non_null(grid);
    assert_int_equal(brdffit_fit_create(&fit, grid, model, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, BRDFFIT_PIPELINE_JOINT),
                     BRDFFIT_OK);
    cc.fit = fit;
    assert_int_equal(brdffit_fit_set_callback(fit, cancel_and_note, &cc), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
    delay = seconds() - cc.at;
    assert_true(cc.at > 0.0);
    assert_int_equal(brdffit_fit_stop_reason(fit), BRDFFIT_STOP_CANCELLED);
    if (delay > 2.0) print_error("the cancel took effect after %g s\n", delay);
    assert_true(delay < 2.0);
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
    free(p);
}

/* The O(n^3) routines give up when asked: after the stop function's
 * third call. */
static int third_call(const void *ctx)
{
    int *calls = (int *)(uintptr_t)ctx;
    return ++*calls >= 3;
}

static void test_linear_algebra_stops(void **state)
{
    enum { N = 64 };
    static double m[N * N], v[N * N], w[N], out[N * N];
    int calls = 0;
    bf_stop stop;
    size_t i, j;
    (void)state;
    stop.fn = third_call;
    stop.ctx = (const void *)(uintptr_t)&calls;
    for (i = 0; i < N; i++)
        for (j = 0; j < N; j++) m[i * N + j] = i == j ? 2.0 : 1.0 / (double)(1 + i + j);
    assert_int_equal(bf_cholesky_until(m, N, BF_LINALG_RTOL, &stop), -1);
    for (i = 0; i < N; i++)
        for (j = 0; j < N; j++) m[i * N + j] = i == j ? 2.0 : 1.0 / (double)(1 + i + j);
    calls = 0;
    assert_int_equal(bf_sym_eigen_until(m, N, w, v, &stop), -1);
    for (i = 0; i < N; i++)
        for (j = 0; j < N; j++) m[i * N + j] = i == j ? 2.0 : 1.0 / (double)(1 + i + j);
    assert_int_equal(bf_sym_eigen_until(m, N, w, v, NULL), 1);
    calls = 0;
    assert_int_equal(bf_eigen_pinv(w, v, N, BF_LINALG_RTOL, out, &stop), 0);
    assert_int_equal(bf_eigen_pinv(w, v, N, BF_LINALG_RTOL, out, NULL), 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_block_structure_matches_the_inverse),
        cmocka_unit_test(test_block_structure_is_fast),
        cmocka_unit_test(test_linear_algebra_stops),
        cmocka_unit_test(test_fit_cancel_with_many_channels),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
