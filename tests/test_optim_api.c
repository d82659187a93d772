/* The optimizer's interface: arguments and settings with exact codes,
 * failures and NaN at the start and at trial points, stopping tests, the
 * iteration callback, damping policies, history, covariance and
 * condition against closed forms, allocation failures. */
#include <math.h>
#include <string.h>

#include "optim_problems.h"
#include "test_support.h"

static brdffit_optimizer *make(size_t p)
{
    brdffit_optimizer *opt = NULL;
    assert_int_equal(brdffit_optimizer_create(&opt, p, NULL, NULL), BRDFFIT_OK);
    assert_non_null(opt);
    return opt;
}

static void assert_message_has(const brdffit_optimizer *opt, const char *part)
{
    const char *msg = brdffit_optimizer_message(opt);
    if (strstr(msg, part) == NULL) fail_msg("message \"%s\" does not contain \"%s\"", msg, part);
}

/* --- creation ----------------------------------------------------------------------- */

static void *no_alloc(size_t size, void *ctx)
{
    (void)size;
    (void)ctx;
    return NULL;
}

static void test_create_invalid(void **state)
{
    brdffit_optimizer *opt = (brdffit_optimizer *)&opt;
    brdffit_error err;
    brdffit_allocator half = {no_alloc, NULL, NULL};
    (void)state;
    assert_int_equal(brdffit_optimizer_create(NULL, 2, NULL, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(err.status, BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_optimizer_create(&opt, 0, NULL, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_null(opt);
    assert_non_null(strstr(err.message, "n_params"));
    assert_int_equal(brdffit_optimizer_create(&opt, 4097, NULL, NULL), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_optimizer_create(&opt, 2, &half, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "allocator"));
    assert_int_equal(brdffit_optimizer_create(&opt, 4096, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_param_count(opt), 4096);
    brdffit_optimizer_destroy(opt);
    brdffit_optimizer_destroy(NULL);
    assert_int_equal(brdffit_optimizer_param_count(NULL), 0);
    assert_non_null(brdffit_optimizer_message(NULL));
}

/* --- settings ------------------------------------------------------------------------- */

static double get(const brdffit_optimizer *opt, brdffit_optim_setting s)
{
    double v = -1.0;
    assert_int_equal(brdffit_optimizer_get(opt, s, &v), BRDFFIT_OK);
    return v;
}

static void test_settings_defaults_and_restore(void **state)
{
    brdffit_optimizer *opt = make(2);
    (void)state;
    assert_true(get(opt, BRDFFIT_OPT_GTOL) == 1e-13);
    assert_true(get(opt, BRDFFIT_OPT_XTOL) == 1e-10);
    assert_true(get(opt, BRDFFIT_OPT_FTOL) == 1e-15);
    assert_true(get(opt, BRDFFIT_OPT_MAX_ITERATIONS) == 10000);
    assert_true(get(opt, BRDFFIT_OPT_MAX_EVALUATIONS) == 24000);
    assert_true(get(opt, BRDFFIT_OPT_SCALE_MEMORY) == 1);
    assert_true(get(opt, BRDFFIT_OPT_STEP_TEST) == 0);
    assert_true(get(opt, BRDFFIT_OPT_SCALING) == 1);
    assert_true(get(opt, BRDFFIT_OPT_DIAG_FLOOR) == 1e-12);
    assert_true(get(opt, BRDFFIT_OPT_STEP_BOUND) == 1e300);
    assert_true(get(opt, BRDFFIT_OPT_RESTART_BOUND) == 1.0);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_STEP_BOUND, 3.0), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_RESTART_BOUND, 0.5), BRDFFIT_OK);
    assert_true(get(opt, BRDFFIT_OPT_STEP_BOUND) == 3.0);
    assert_true(get(opt, BRDFFIT_OPT_RESTART_BOUND) == 0.5);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_STEP_BOUND, 0), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_RESTART_BOUND, 0), BRDFFIT_OK);
    assert_true(get(opt, BRDFFIT_OPT_STEP_BOUND) == 1e300);
    assert_true(get(opt, BRDFFIT_OPT_RESTART_BOUND) == 1.0);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_GTOL, 1e-6), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_MAX_ITERATIONS, 17), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_SCALING, 0), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_DIAG_FLOOR, 1.0), BRDFFIT_OK);
    assert_true(get(opt, BRDFFIT_OPT_GTOL) == 1e-6);
    assert_true(get(opt, BRDFFIT_OPT_MAX_ITERATIONS) == 17);
    assert_true(get(opt, BRDFFIT_OPT_SCALING) == 0);
    assert_true(get(opt, BRDFFIT_OPT_DIAG_FLOOR) == 1.0);
    /* 0 restores the default (scaling: 0 is Levenberg) */
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_GTOL, 0), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_MAX_ITERATIONS, 0), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_DIAG_FLOOR, 0), BRDFFIT_OK);
    assert_true(get(opt, BRDFFIT_OPT_GTOL) == 1e-13);
    assert_true(get(opt, BRDFFIT_OPT_MAX_ITERATIONS) == 10000);
    assert_true(get(opt, BRDFFIT_OPT_DIAG_FLOOR) == 1e-12);
    assert_true(get(opt, BRDFFIT_OPT_SCALING) == 0);
    brdffit_optimizer_destroy(opt);
}

static void expect_bad_setting(brdffit_optimizer *opt, brdffit_optim_setting s, double v)
{
    double before = 0.0, after = 0.0;
    int known = brdffit_optimizer_get(opt, s, &before) == BRDFFIT_OK;
    assert_int_equal(brdffit_optimizer_set(opt, s, v), BRDFFIT_E_INVALID_ARGUMENT);
    assert_true(brdffit_optimizer_message(opt)[0] != '\0');
    if (known) {
        assert_int_equal(brdffit_optimizer_get(opt, s, &after), BRDFFIT_OK);
        assert_true(before == after);
    }
}

static void test_settings_invalid(void **state)
{
    brdffit_optimizer *opt = make(2);
    double v;
    (void)state;
    expect_bad_setting(opt, BRDFFIT_OPT_GTOL, -1e-3);
    expect_bad_setting(opt, BRDFFIT_OPT_XTOL, NAN);
    expect_bad_setting(opt, BRDFFIT_OPT_FTOL, HUGE_VAL);
    expect_bad_setting(opt, BRDFFIT_OPT_MAX_ITERATIONS, 2.5);
    expect_bad_setting(opt, BRDFFIT_OPT_MAX_ITERATIONS, -1);
    expect_bad_setting(opt, BRDFFIT_OPT_MAX_EVALUATIONS, 1e300);
    expect_bad_setting(opt, BRDFFIT_OPT_SCALING, 2);
    expect_bad_setting(opt, BRDFFIT_OPT_SCALING, 0.5);
    expect_bad_setting(opt, BRDFFIT_OPT_DIAG_FLOOR, 1.5);
    expect_bad_setting(opt, (brdffit_optim_setting)0, 1.0);
    expect_bad_setting(opt, (brdffit_optim_setting)99, 1.0);
    assert_int_equal(brdffit_optimizer_get(opt, BRDFFIT_OPT_GTOL, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_optimizer_get(opt, (brdffit_optim_setting)42, &v),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_optimizer_set(NULL, BRDFFIT_OPT_GTOL, 1), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_optimizer_get(NULL, BRDFFIT_OPT_GTOL, &v), BRDFFIT_E_INVALID_ARGUMENT);
    /* a success clears the message */
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_GTOL, 1e-8), BRDFFIT_OK);
    assert_string_equal(brdffit_optimizer_message(opt), "");
    brdffit_optimizer_destroy(opt);
}

/* --- arguments ------------------------------------------------------------------------ */

static void nop_init(void *s, double *l, void *u)
{
    (void)s;
    (void)u;
    *l = 1.0;
}

static void nop_update(void *s, double rho, double *l, void *u)
{
    (void)s;
    (void)rho;
    (void)l;
    (void)u;
}

static brdffit_status normal_nop(const double *x, double *cost, double *jtj, double *jtr, void *u)
{
    (void)x;
    (void)jtj;
    (void)jtr;
    (void)u;
    *cost = 1.0;
    return BRDFFIT_OK;
}

static void test_invalid_arguments(void **state)
{
    brdffit_optimizer *opt = make(2);
    brdffit_damping pol = BRDFFIT_DAMPING_INIT;
    double x[2] = {0, 0}, cov[4], lo[2] = {0, 0}, hi[2] = {1, 1};
    (void)state;
    assert_int_equal(brdffit_optimizer_set_residuals(opt, 2, NULL, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_message_has(opt, "fn");
    assert_int_equal(brdffit_optimizer_set_residuals(opt, 0, optim_rosenbrock, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_optimizer_set_residuals(opt, (size_t)-1, optim_rosenbrock, NULL),
                     BRDFFIT_E_OUT_OF_MEMORY);
    assert_int_equal(brdffit_optimizer_set_normal(opt, 2, NULL, NULL), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_optimizer_set_normal(opt, 0, normal_nop, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    /* incomplete policies */
    assert_int_equal(brdffit_optimizer_set_damping(opt, &pol), BRDFFIT_E_INVALID_ARGUMENT);
    pol.init = nop_init;
    pol.accept = nop_update;
    assert_int_equal(brdffit_optimizer_set_damping(opt, &pol), BRDFFIT_E_INVALID_ARGUMENT);
    pol.reject = nop_update;
    pol.struct_size = sizeof pol - 1;
    assert_int_equal(brdffit_optimizer_set_damping(opt, &pol), BRDFFIT_E_INVALID_ARGUMENT);
    assert_message_has(opt, "struct_size");
    pol.struct_size = sizeof pol;
    assert_int_equal(brdffit_optimizer_set_damping(opt, &pol), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set_damping(opt, NULL), BRDFFIT_OK);
    /* bounds */
    lo[1] = 2.0;
    assert_int_equal(brdffit_optimizer_set_bounds(opt, lo, hi), BRDFFIT_E_INVALID_ARGUMENT);
    assert_message_has(opt, "parameter 1");
    lo[1] = NAN;
    assert_int_equal(brdffit_optimizer_set_bounds(opt, lo, hi), BRDFFIT_E_INVALID_ARGUMENT);
    lo[1] = HUGE_VAL;
    assert_int_equal(brdffit_optimizer_set_bounds(opt, lo, NULL), BRDFFIT_E_INVALID_ARGUMENT);
    hi[0] = -HUGE_VAL;
    assert_int_equal(brdffit_optimizer_set_bounds(opt, NULL, hi), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_optimizer_set_bounds(opt, NULL, NULL), BRDFFIT_OK);
    /* run */
    assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_E_NOT_READY);
    assert_message_has(opt, "no problem");
    assert_int_equal(brdffit_optimizer_set_residuals(opt, 2, optim_rosenbrock, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_run(opt, NULL), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_optimizer_covariance(opt, cov), BRDFFIT_E_NOT_READY);
    assert_int_equal(brdffit_optimizer_std_errors(opt, cov), BRDFFIT_E_NOT_READY);
    assert_int_equal(brdffit_optimizer_converged(opt), 0);
    assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_converged(opt), 1);
    assert_string_equal(brdffit_optimizer_message(opt), "");
    assert_int_equal(brdffit_optimizer_covariance(opt, NULL), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_optimizer_std_errors(opt, NULL), BRDFFIT_E_INVALID_ARGUMENT);
    /* NULL handles */
    assert_int_equal(brdffit_optimizer_set_residuals(NULL, 2, optim_rosenbrock, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_optimizer_set_normal(NULL, 2, normal_nop, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_optimizer_set_damping(NULL, NULL), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_optimizer_set_bounds(NULL, NULL, NULL), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_optimizer_set_fixed(NULL, NULL), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_optimizer_set_callback(NULL, NULL, NULL), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_optimizer_run(NULL, x), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_optimizer_covariance(NULL, cov), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_optimizer_std_errors(NULL, cov), BRDFFIT_E_INVALID_ARGUMENT);
    brdffit_optimizer_cancel(NULL);
    assert_int_equal(brdffit_optimizer_stop_reason(NULL), BRDFFIT_STOP_NONE);
    assert_int_equal(brdffit_optimizer_converged(NULL), 0);
    assert_true(isnan(brdffit_optimizer_final_cost(NULL)));
    assert_int_equal(brdffit_optimizer_history(NULL, NULL, NULL), 0);
    brdffit_optimizer_destroy(opt);
}

static void test_results_before_run(void **state)
{
    brdffit_optimizer *opt = make(3);
    double cov[9];
    (void)state;
    assert_int_equal(brdffit_optimizer_stop_reason(opt), BRDFFIT_STOP_NONE);
    assert_true(isnan(brdffit_optimizer_initial_cost(opt)));
    assert_true(isnan(brdffit_optimizer_final_cost(opt)));
    assert_true(isnan(brdffit_optimizer_condition(opt)));
    assert_int_equal(brdffit_optimizer_iterations(opt), 0);
    assert_int_equal(brdffit_optimizer_evaluations(opt), 0);
    assert_int_equal(brdffit_optimizer_last_improvement(opt), 0);
    assert_int_equal(brdffit_optimizer_used_fallback(opt), 0);
    assert_int_equal(brdffit_optimizer_history(opt, NULL, NULL), 0);
    assert_int_equal(brdffit_optimizer_covariance(opt, cov), BRDFFIT_E_NOT_READY);
    assert_string_equal(brdffit_optimizer_message(opt), "");
    brdffit_optimizer_destroy(opt);
}

static void test_stop_reason_strings(void **state)
{
    int r;
    (void)state;
    assert_int_equal(BRDFFIT_STOP_NONE, 0);
    assert_int_equal(BRDFFIT_STOP_ZERO_COST, 8);
    for (r = 0; r <= 8; r++) {
        const char *s = brdffit_stop_reason_string((brdffit_stop_reason)r);
        assert_non_null(s);
        assert_string_not_equal(s, "unknown stop reason");
    }
    assert_string_equal(brdffit_stop_reason_string(BRDFFIT_STOP_CANCELLED), "cancelled");
    assert_string_equal(brdffit_stop_reason_string((brdffit_stop_reason)77), "unknown stop reason");
}

/* --- NaN and failures at the start point ---------------------------------------------- */

typedef struct faulty {
    int mode; /* what goes wrong, see faulty_fn */
    size_t calls;
    size_t fail_from; /* fail from this call on (1-based), 0: never */
    size_t fail_only; /* fail on this call only */
    size_t failures;
} faulty;

/* Rosenbrock with faults: mode 1 NaN residual 1, 2 Inf Jacobian (0, 1),
 * 3 callback failure, 4 NaN in both residuals. */
static brdffit_status faulty_fn(const double *x, double *r, double *jac, void *user)
{
    faulty *f = user;
    int bad;
    f->calls++;
    bad = (f->fail_from && f->calls >= f->fail_from) || f->calls == f->fail_only;
    optim_rosenbrock(x, r, jac, NULL);
    if (!bad) return BRDFFIT_OK;
    f->failures++;
    switch (f->mode) {
    case 1: r[1] = NAN; break;
    case 2:
        if (jac != NULL) jac[1] = HUGE_VAL;
        break;
    case 3: return BRDFFIT_E_MODEL_FAILED;
    default: r[0] = r[1] = NAN; break;
    }
    return BRDFFIT_OK;
}

static void expect_start_failure(int mode, brdffit_status code, const char *part)
{
    brdffit_optimizer *opt = make(2);
    faulty f;
    double x[2] = {-1.2, 1.0}, cov[4];
    memset(&f, 0, sizeof f);
    f.mode = mode;
    f.fail_from = 1;
    assert_int_equal(brdffit_optimizer_set_residuals(opt, 2, faulty_fn, &f), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_run(opt, x), code);
    assert_message_has(opt, part);
    assert_message_has(opt, "start point");
    assert_true(x[0] == -1.2 && x[1] == 1.0);
    assert_int_equal(brdffit_optimizer_stop_reason(opt), BRDFFIT_STOP_NONE);
    assert_int_equal(brdffit_optimizer_covariance(opt, cov), BRDFFIT_E_NOT_READY);
    assert_true(isnan(brdffit_optimizer_final_cost(opt)));
    assert_int_equal(f.calls, 1);
    brdffit_optimizer_destroy(opt);
}

static void test_nan_and_failure_at_start_residual_form(void **state)
{
    (void)state;
    expect_start_failure(1, BRDFFIT_E_NONFINITE, "residual 1 is nan");
    expect_start_failure(2, BRDFFIT_E_NONFINITE, "Jacobian entry (0, 1) is inf");
    expect_start_failure(3, BRDFFIT_E_CALLBACK_FAILED, "BRDFFIT_E_MODEL_FAILED");
}

typedef struct bad_normal {
    int mode;
} bad_normal;

static brdffit_status bad_normal_fn(const double *x, double *cost, double *jtj, double *jtr,
                                    void *user)
{
    const bad_normal *b = user;
    (void)x;
    *cost = b->mode == 1 ? NAN : b->mode == 4 ? -1.0 : 2.0;
    if (jtj != NULL) {
        jtj[0] = jtj[3] = 1.0;
        if (b->mode == 2) jtj[2] = NAN;
        if (b->mode == 3) jtr[1] = -HUGE_VAL;
    }
    return b->mode == 5 ? BRDFFIT_E_IO : BRDFFIT_OK;
}

static void expect_normal_start_failure(int mode, brdffit_status code, const char *part)
{
    brdffit_optimizer *opt = make(2);
    bad_normal b = {mode};
    double x[2] = {1.0, 2.0};
    assert_int_equal(brdffit_optimizer_set_normal(opt, 5, bad_normal_fn, &b), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_run(opt, x), code);
    assert_message_has(opt, part);
    assert_true(x[0] == 1.0 && x[1] == 2.0);
    brdffit_optimizer_destroy(opt);
}

static void test_nan_and_failure_at_start_normal_form(void **state)
{
    brdffit_optimizer *opt = make(2);
    double x[2] = {NAN, 0.0};
    (void)state;
    expect_normal_start_failure(1, BRDFFIT_E_NONFINITE, "cost is nan");
    expect_normal_start_failure(2, BRDFFIT_E_NONFINITE, "J^T J entry (1, 0) is nan");
    expect_normal_start_failure(3, BRDFFIT_E_NONFINITE, "J^T r entry 1 is -inf");
    expect_normal_start_failure(4, BRDFFIT_E_CALLBACK_FAILED, "negative cost");
    expect_normal_start_failure(5, BRDFFIT_E_CALLBACK_FAILED, "BRDFFIT_E_IO");
    /* a NaN start value is reported before the problem is called */
    assert_int_equal(brdffit_optimizer_set_normal(opt, 5, normal_nop, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_E_NONFINITE);
    assert_message_has(opt, "x[0]");
    brdffit_optimizer_destroy(opt);
}

/* --- failures at trial points are rejected steps ---------------------------------------- */

/* The exponential fit, undefined for a negative rate b: mode 0 fails,
 * mode 1 returns NaN there. */
typedef struct positive_rate {
    optim_fit_data d;
    int mode;
    size_t failures;
} positive_rate;

static brdffit_status positive_rate_fn(const double *x, double *r, double *jac, void *user)
{
    positive_rate *pr = user;
    if (x[1] < 0.0) {
        pr->failures++;
        if (pr->mode == 0) return BRDFFIT_E_MODEL_FAILED;
        optim_exp_fit(x, r, jac, &pr->d);
        r[pr->failures % pr->d.n] = NAN;
        return BRDFFIT_OK;
    }
    return optim_exp_fit(x, r, jac, &pr->d);
}

static int record_rho(const brdffit_iteration *info, void *user)
{
    size_t *nan_rejections = user;
    if (!info->accepted && isnan(info->rho)) (*nan_rejections)++;
    return 0;
}

static void test_failure_at_trial_points(void **state)
{
    positive_rate pr;
    int mode, normal;
    (void)state;
    optim_make_exp_data(&pr.d);
    for (mode = 0; mode < 2; mode++) {
        for (normal = 0; normal < 2; normal++) {
            brdffit_optimizer *opt = make(3);
            optim_normal_adapter ad;
            double x[3] = {1.0, 3.0, 0.0}, lambda[256];
            size_t nan_rejections = 0, n;
            pr.mode = mode;
            pr.failures = 0;
            if (normal) {
                optim_normal_adapter_init(&ad, positive_rate_fn, &pr, pr.d.n, 3);
                assert_int_equal(
                    brdffit_optimizer_set_normal(opt, pr.d.n, optim_normal_adapter_fn, &ad),
                    BRDFFIT_OK);
            } else {
                assert_int_equal(
                    brdffit_optimizer_set_residuals(opt, pr.d.n, positive_rate_fn, &pr),
                    BRDFFIT_OK);
            }
            assert_int_equal(brdffit_optimizer_set_callback(opt, record_rho, &nan_rejections),
                             BRDFFIT_OK);
            assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
            assert_true(pr.failures > 0);
            assert_int_equal(nan_rejections, pr.failures);
            assert_close(x[0], 5.0, 0.01);
            assert_close(x[1], 0.7, 0.01);
            assert_close(x[2], 1.0, 0.01);
            assert_true(isfinite(brdffit_optimizer_final_cost(opt)));
            /* the first step failed: lambda grew (Nielsen: x2) */
            n = brdffit_optimizer_history(opt, NULL, lambda);
            assert_true(n >= 2 && n <= 256);
            assert_close(lambda[1], 2.0 * lambda[0], 1e-15);
            brdffit_optimizer_destroy(opt);
        }
    }
}

/* Fails on the first trial, NaN on the second; the run still converges. */
static void test_failure_then_nan_by_call_count(void **state)
{
    int mode;
    (void)state;
    for (mode = 3; mode <= 4; mode++) {
        brdffit_optimizer *opt = make(2);
        faulty f;
        double x[2] = {-1.2, 1.0};
        memset(&f, 0, sizeof f);
        f.mode = mode;
        f.fail_only = 2;
        assert_int_equal(brdffit_optimizer_set_residuals(opt, 2, faulty_fn, &f), BRDFFIT_OK);
        assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
        assert_int_equal(f.failures, 1);
        assert_close(x[0], 1.0, 1e-8);
        assert_close(x[1], 1.0, 1e-8);
        assert_int_equal(brdffit_optimizer_evaluations(opt), f.calls);
        brdffit_optimizer_destroy(opt);
    }
}

/* --- stopping ----------------------------------------------------------------------------- */

typedef struct cb_log {
    size_t calls, stop_at;
    size_t iteration[16];
    double cost[16];
    int bad_info;
} cb_log;

static int stop_at(const brdffit_iteration *info, void *user)
{
    cb_log *log = user;
    if (info->struct_size != sizeof *info || info->n_params != 2 || info->x == NULL ||
        !(info->lambda > 0.0))
        log->bad_info = 1;
    if (log->calls < 16) {
        log->iteration[log->calls] = info->iteration;
        log->cost[log->calls] = info->cost;
    }
    log->calls++;
    return log->calls == log->stop_at;
}

static void test_iteration_callback_stops(void **state)
{
    brdffit_optimizer *opt = make(2);
    cb_log log;
    double x[2] = {-1.2, 1.0}, cost[8], r[2];
    size_t i;
    (void)state;
    memset(&log, 0, sizeof log);
    log.stop_at = 3;
    assert_int_equal(brdffit_optimizer_set_residuals(opt, 2, optim_rosenbrock, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set_callback(opt, stop_at, &log), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_stop_reason(opt), BRDFFIT_STOP_CALLBACK);
    assert_int_equal(brdffit_optimizer_iterations(opt), 3);
    assert_int_equal(log.calls, 3);
    assert_false(log.bad_info);
    assert_int_equal(brdffit_optimizer_history(opt, cost, NULL), 4);
    for (i = 0; i < 3; i++) {
        assert_int_equal(log.iteration[i], i + 1);
        assert_true(log.cost[i] == cost[i + 1]);
    }
    /* the returned point is the best one and has the final cost */
    optim_rosenbrock(x, r, NULL, NULL);
    assert_close(r[0] * r[0] + r[1] * r[1], brdffit_optimizer_final_cost(opt), 1e-14);
    assert_true(brdffit_optimizer_final_cost(opt) <= brdffit_optimizer_initial_cost(opt));
    /* removing the callback */
    assert_int_equal(brdffit_optimizer_set_callback(opt, NULL, NULL), BRDFFIT_OK);
    x[0] = -1.2;
    x[1] = 1.0;
    assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
    assert_int_not_equal(brdffit_optimizer_stop_reason(opt), BRDFFIT_STOP_CALLBACK);
    brdffit_optimizer_destroy(opt);
}

static void test_limits(void **state)
{
    brdffit_optimizer *opt = make(3);
    double x[3];
    const double x0[3] = {0.02, 4000.0, 250.0};
    (void)state;
    assert_int_equal(brdffit_optimizer_set_residuals(opt, 16, optim_meyer, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_MAX_ITERATIONS, 5), BRDFFIT_OK);
    memcpy(x, x0, sizeof x);
    assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_stop_reason(opt), BRDFFIT_STOP_MAX_ITERATIONS);
    assert_int_equal(brdffit_optimizer_iterations(opt), 5);
    assert_int_equal(brdffit_optimizer_history(opt, NULL, NULL), 6);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_MAX_ITERATIONS, 0), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_MAX_EVALUATIONS, 12), BRDFFIT_OK);
    memcpy(x, x0, sizeof x);
    assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_stop_reason(opt), BRDFFIT_STOP_MAX_EVALUATIONS);
    assert_true(brdffit_optimizer_evaluations(opt) <= 12);
    assert_true(brdffit_optimizer_evaluations(opt) >= 11);
    brdffit_optimizer_destroy(opt);
}

/* A straight line through five points that it cannot pass through
 * (non-zero residuals), with the parameters in units `xs` (the model sees
 * x / xs) and the residuals in units `rs`. */
typedef struct units {
    double xs, rs;
} units;

static brdffit_status scaled_line(const double *x, double *r, double *jac, void *user)
{
    static const double t[5] = {0.0, 1.0, 2.0, 3.0, 4.0}, y[5] = {1.0, 2.9, 5.2, 6.8, 9.3};
    const units *u = user;
    size_t i;
    for (i = 0; i < 5; i++) {
        r[i] = u->rs * (x[0] / u->xs + x[1] / u->xs * t[i] - y[i]);
        if (jac == NULL) continue;
        jac[2 * i] = u->rs / u->xs;
        jac[2 * i + 1] = u->rs * t[i] / u->xs;
    }
    return BRDFFIT_OK;
}

/* The gradient test is the cosine between the residuals and each Jacobian
 * column: the same run, with the same stop, in any units. */
static void test_gradient_test_scale_free(void **state)
{
    static const units cases[] = {{1.0, 1.0}, {1e6, 1.0}, {1.0, 1e-6}, {1e-4, 1e5}};
    size_t k, iterations = 0;
    (void)state;
    for (k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        brdffit_optimizer *opt = make(2);
        double x[2] = {0.0, 0.0};
        assert_int_equal(brdffit_optimizer_set_residuals(opt, 5, scaled_line, (void *)&cases[k]),
                         BRDFFIT_OK);
        assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_GTOL, 1e-8), BRDFFIT_OK);
        assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
        assert_int_equal(brdffit_optimizer_stop_reason(opt), BRDFFIT_STOP_GRADIENT);
        if (k == 0) iterations = brdffit_optimizer_iterations(opt);
        assert_int_equal(brdffit_optimizer_iterations(opt), iterations);
        /* least squares: intercept 0.94, slope 2.05 */
        assert_close(x[0] / cases[k].xs, 0.94, 1e-9);
        assert_close(x[1] / cases[k].xs, 2.05, 1e-9);
        brdffit_optimizer_destroy(opt);
    }
}

/* x - 3 = 0 has zero cost at its start. */
static brdffit_status shifted(const double *x, double *r, double *jac, void *user)
{
    (void)user;
    r[0] = x[0] - 3.0;
    if (jac != NULL) jac[0] = 1.0;
    return BRDFFIT_OK;
}

static void test_zero_cost(void **state)
{
    brdffit_optimizer *opt = make(1);
    double x = 3.0, cov;
    (void)state;
    assert_int_equal(brdffit_optimizer_set_residuals(opt, 1, shifted, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_run(opt, &x), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_stop_reason(opt), BRDFFIT_STOP_ZERO_COST);
    assert_int_equal(brdffit_optimizer_iterations(opt), 0);
    assert_true(x == 3.0);
    /* n_rows = n_free: s^2 = 1, cov = (J^T J)^-1 = 1 */
    assert_int_equal(brdffit_optimizer_covariance(opt, &cov), BRDFFIT_OK);
    assert_close(cov, 1.0, 1e-14);
    brdffit_optimizer_destroy(opt);
}

/* --- damping policies ------------------------------------------------------------------- */

typedef struct policy_state {
    int initialised;
    size_t accepts, rejects;
} policy_state;

typedef struct policy_log {
    size_t inits, state_was_dirty, accepts, rejects, bad_rho;
} policy_log;

static void my_init(void *state, double *lambda, void *user)
{
    policy_state *s = state;
    policy_log *log = user;
    log->inits++;
    if (s->initialised || s->accepts || s->rejects) log->state_was_dirty++;
    s->initialised = 1;
    *lambda = 0.5;
}

static void my_accept(void *state, double rho, double *lambda, void *user)
{
    policy_state *s = state;
    policy_log *log = user;
    s->accepts++;
    log->accepts++;
    if (!(rho > 0.0)) log->bad_rho++;
    *lambda *= 0.2;
}

static void my_reject(void *state, double rho, double *lambda, void *user)
{
    policy_state *s = state;
    policy_log *log = user;
    s->rejects++;
    log->rejects++;
    if (rho > 0.0) log->bad_rho++;
    *lambda *= 5.0;
}

static int count_accepted(const brdffit_iteration *info, void *user)
{
    size_t *accepted = user;
    if (info->accepted) (*accepted)++;
    return 0;
}

static void test_user_damping_policy(void **state)
{
    brdffit_optimizer *opt = make(3);
    policy_log log;
    brdffit_damping pol = BRDFFIT_DAMPING_INIT;
    double x[3] = {0.02, 4000.0, 250.0}, lambda[1024], cost[1024];
    size_t n, i, accepted = 0, run, total_iterations = 0;
    (void)state;
    memset(&log, 0, sizeof log);
    pol.name = "test";
    pol.state_size = sizeof(policy_state);
    pol.init = my_init;
    pol.accept = my_accept;
    pol.reject = my_reject;
    pol.user = &log;
    assert_int_equal(brdffit_optimizer_set_residuals(opt, 16, optim_meyer, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set_damping(opt, &pol), BRDFFIT_OK);
    pol.accept = NULL; /* the optimizer keeps its own copy */
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_MAX_ITERATIONS, 1000), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_MAX_EVALUATIONS, 3000), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set_callback(opt, count_accepted, &accepted), BRDFFIT_OK);
    for (run = 0; run < 2; run++) {
        x[0] = 0.02;
        x[1] = 4000.0;
        x[2] = 250.0;
        accepted = 0;
        assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
        assert_close(brdffit_optimizer_final_cost(opt), 87.9458551708511, 1e-9);
        total_iterations += brdffit_optimizer_iterations(opt);
    }
    assert_int_equal(log.inits, 2);
    assert_int_equal(log.state_was_dirty, 0);
    assert_int_equal(log.bad_rho, 0);
    n = brdffit_optimizer_history(opt, cost, lambda);
    assert_true(n <= 1024);
    assert_true(lambda[0] == 0.5);
    for (i = 1; i < n; i++) {
        double factor = cost[i] < cost[i - 1] ? 0.2 : 5.0;
        assert_close(lambda[i], lambda[i - 1] * factor, 1e-15);
    }
    assert_int_equal(log.accepts + log.rejects, total_iterations);
    assert_int_equal(brdffit_optimizer_iterations(opt), n - 1);
    assert_true(accepted > 0 && accepted < n);
    brdffit_optimizer_destroy(opt);
}

static void test_builtin_policies(void **state)
{
    const brdffit_damping *p[3];
    double lambda;
    int k;
    (void)state;
    p[0] = brdffit_damping_thesis();
    p[1] = brdffit_damping_marquardt();
    p[2] = brdffit_damping_nielsen();
    assert_string_equal(p[0]->name, "thesis");
    assert_string_equal(p[1]->name, "marquardt");
    assert_string_equal(p[2]->name, "nielsen");
    for (k = 0; k < 3; k++) {
        double buf[4] = {0, 0, 0, 0};
        assert_int_equal(p[k]->struct_size, sizeof(brdffit_damping));
        assert_true(p[k]->state_size <= sizeof buf);
        p[k]->init(buf, &lambda, p[k]->user);
        assert_true(lambda == 1e-3);
    }
    /* thesis: doubling capped at 1, halving floored at 1e-4 */
    lambda = 0.6;
    p[0]->reject(NULL, 0.0, &lambda, NULL);
    assert_true(lambda == 1.0);
    lambda = 1.5e-4;
    p[0]->accept(NULL, 0.5, &lambda, NULL);
    assert_true(lambda == 1e-4);
    lambda = 0.25;
    p[0]->accept(NULL, 0.5, &lambda, NULL);
    assert_true(lambda == 0.125);
    /* Marquardt */
    lambda = 1.0;
    p[1]->reject(NULL, -1.0, &lambda, NULL);
    assert_true(lambda == 10.0);
    p[1]->accept(NULL, 0.9, &lambda, NULL);
    assert_close(lambda, 1.0, 1e-15);
    {
        double st[1];
        p[2]->init(st, &lambda, NULL);
        lambda = 1.0;
        p[2]->reject(st, NAN, &lambda, NULL);  /* x2 */
        p[2]->reject(st, -1.0, &lambda, NULL); /* x4 */
        assert_true(lambda == 8.0);
        p[2]->accept(st, 0.5, &lambda, NULL); /* factor max(1/3, 1 - 0) = 1 */
        assert_true(lambda == 8.0);
        p[2]->reject(st, 0.0, &lambda, NULL); /* nu back to 2 */
        assert_true(lambda == 16.0);
        p[2]->accept(st, 1.0, &lambda, NULL); /* factor max(1/3, 0) */
        assert_close(lambda, 16.0 / 3.0, 1e-15);
        p[2]->accept(st, 0.25, &lambda, NULL); /* 1 - (-0.5)^3 = 1.125 */
        assert_close(lambda, 6.0, 1e-15);
    }
}

/* A policy that never moves lambda (and one that returns garbage): the
 * run still ends, by shortening the step. */
static void stuck_init(void *s, double *l, void *u)
{
    (void)s;
    *l = *(const double *)u;
}

static void garbage_update(void *s, double rho, double *l, void *u)
{
    (void)s;
    (void)rho;
    *l = *(const double *)u;
}

static void test_stuck_policy_terminates(void **state)
{
    static const double values[4] = {1e-3, 0.0, NAN, HUGE_VAL};
    int k;
    (void)state;
    for (k = 0; k < 4; k++) {
        brdffit_optimizer *opt = make(3);
        brdffit_damping pol = BRDFFIT_DAMPING_INIT;
        double x[3] = {0.02, 4000.0, 250.0}, *lambda;
        size_t n, i;
        pol.init = stuck_init;
        pol.accept = garbage_update;
        pol.reject = garbage_update;
        pol.user = (void *)&values[k];
        assert_int_equal(brdffit_optimizer_set_residuals(opt, 16, optim_meyer, NULL), BRDFFIT_OK);
        assert_int_equal(brdffit_optimizer_set_damping(opt, &pol), BRDFFIT_OK);
        assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_MAX_ITERATIONS, 100000),
                         BRDFFIT_OK);
        assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_MAX_EVALUATIONS, 300000),
                         BRDFFIT_OK);
        assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
        assert_int_not_equal(brdffit_optimizer_stop_reason(opt), BRDFFIT_STOP_MAX_ITERATIONS);
        assert_int_not_equal(brdffit_optimizer_stop_reason(opt), BRDFFIT_STOP_MAX_EVALUATIONS);
        assert_true(brdffit_optimizer_final_cost(opt) <= brdffit_optimizer_initial_cost(opt));
        n = brdffit_optimizer_history(opt, NULL, NULL);
        lambda = test_malloc(n * sizeof *lambda);
        assert_int_equal(brdffit_optimizer_history(opt, NULL, lambda), n);
        /* clamped into [1e-300, 1e300]; NaN keeps the previous value */
        for (i = 0; i < n; i++) assert_true(lambda[i] >= 1e-300 && lambda[i] <= 1e300);
        if (k == 2) assert_true(lambda[n - 1] == 1e-3);
        test_free(lambda);
        brdffit_optimizer_destroy(opt);
    }
}

/* --- history, fallback ------------------------------------------------------------------- */

static void test_history_and_last_improvement(void **state)
{
    brdffit_optimizer *opt = make(2);
    double x[2] = {-1.2, 1.0}, cost[256], lambda[256];
    size_t n, i, last = 0, accepted = 0;
    (void)state;
    assert_int_equal(brdffit_optimizer_set_residuals(opt, 2, optim_rosenbrock, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set_callback(opt, count_accepted, &accepted), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
    n = brdffit_optimizer_history(opt, cost, lambda);
    assert_int_equal(n, brdffit_optimizer_iterations(opt) + 1);
    assert_true(cost[0] == brdffit_optimizer_initial_cost(opt));
    assert_close(cost[0], 24.2, 1e-14);
    assert_true(lambda[0] == 1e-3);
    assert_true(cost[n - 1] == brdffit_optimizer_final_cost(opt));
    for (i = 1; i < n; i++)
        if (cost[i] < cost[i - 1]) last = i;
    assert_int_equal(brdffit_optimizer_last_improvement(opt), last);
    /* evaluations: the start, one per trial, one more per accepted step */
    assert_true(brdffit_optimizer_evaluations(opt) <= 1 + (n - 1) + accepted);
    assert_true(brdffit_optimizer_evaluations(opt) >= 1 + accepted * 2);
    brdffit_optimizer_destroy(opt);
}

static void test_used_fallback(void **state)
{
    brdffit_optimizer *opt = make(4);
    double x[4] = {3.0, -1.0, 0.0, 1.0};
    (void)state;
    /* Powell singular: J^T J is singular at the solution; once lambda is
     * tiny the damped matrix is too badly conditioned for Cholesky */
    assert_int_equal(brdffit_optimizer_set_residuals(opt, 4, optim_powell_singular, NULL),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
    assert_true(brdffit_optimizer_used_fallback(opt));
    assert_true(brdffit_optimizer_final_cost(opt) < 1e-24);
    assert_true(brdffit_optimizer_condition(opt) > 1e10);
    brdffit_optimizer_destroy(opt);
    /* Rosenbrock under the thesis's policy (lambda >= 1e-4): never */
    opt = make(2);
    x[0] = -1.2;
    x[1] = 1.0;
    assert_int_equal(brdffit_optimizer_set_residuals(opt, 2, optim_rosenbrock, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set_damping(opt, brdffit_damping_thesis()), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
    assert_false(brdffit_optimizer_used_fallback(opt));
    brdffit_optimizer_destroy(opt);
}

/* --- covariance and condition against closed forms ----------------------------------------- */

typedef struct linear {
    size_t n, p;
    double x[32 * 3]; /* design matrix, row-major */
    double y[32];
} linear;

static brdffit_status linear_fn(const double *b, double *r, double *jac, void *user)
{
    const linear *l = user;
    size_t i, j;
    for (i = 0; i < l->n; i++) {
        double s = -l->y[i];
        for (j = 0; j < l->p; j++) s += l->x[i * l->p + j] * b[j];
        r[i] = s;
        if (jac != NULL)
            for (j = 0; j < l->p; j++) jac[i * l->p + j] = l->x[i * l->p + j];
    }
    return BRDFFIT_OK;
}

static void test_covariance_linear_regression(void **state)
{
    linear l;
    brdffit_optimizer *opt = make(2);
    unsigned long long s = 4242;
    double b[2] = {0.0, 0.0}, cov[4], se[2], st = 0.0, stt = 0.0, sy = 0.0, sty = 0.0;
    double det, a_hat, b_hat, cost = 0.0, s2;
    size_t i;
    (void)state;
    l.n = 25;
    l.p = 2;
    for (i = 0; i < l.n; i++) {
        double t = 0.4 * (double)i;
        l.x[2 * i] = 1.0;
        l.x[2 * i + 1] = t;
        l.y[i] = 0.5 - 1.5 * t + 0.3 * (optim_uniform(&s) - 0.5);
        st += t;
        stt += t * t;
        sy += l.y[i];
        sty += t * l.y[i];
    }
    det = (double)l.n * stt - st * st;
    a_hat = (stt * sy - st * sty) / det;
    b_hat = ((double)l.n * sty - st * sy) / det;
    for (i = 0; i < l.n; i++) {
        double r = a_hat + b_hat * l.x[2 * i + 1] - l.y[i];
        cost += r * r;
    }
    s2 = cost / (double)(l.n - 2);
    assert_int_equal(brdffit_optimizer_set_residuals(opt, l.n, linear_fn, &l), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_FTOL, 1e-15), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_run(opt, b), BRDFFIT_OK);
    assert_close(b[0], a_hat, 1e-9);
    assert_close(b[1], b_hat, 1e-9);
    assert_close(brdffit_optimizer_final_cost(opt), cost, 1e-12);
    /* s^2 (X^T X)^-1, X^T X = [[n, st], [st, stt]] */
    assert_int_equal(brdffit_optimizer_covariance(opt, cov), BRDFFIT_OK);
    assert_close(cov[0], s2 * stt / det, 1e-8);
    assert_close(cov[1], -s2 * st / det, 1e-8);
    assert_close(cov[2], -s2 * st / det, 1e-8);
    assert_close(cov[3], s2 * (double)l.n / det, 1e-8);
    assert_int_equal(brdffit_optimizer_std_errors(opt, se), BRDFFIT_OK);
    assert_close(se[0], sqrt(s2 * stt / det), 1e-8);
    assert_close(se[1], sqrt(s2 * (double)l.n / det), 1e-8);
    /* condition of X^T X: ratio of its eigenvalues */
    {
        double tr = (double)l.n + stt, disc = sqrt(tr * tr - 4.0 * det);
        assert_close(brdffit_optimizer_condition(opt), (tr + disc) / (tr - disc), 1e-8);
    }
    brdffit_optimizer_destroy(opt);
}

/* As many rows as parameters: no degrees of freedom, s^2 = 1. */
static void test_covariance_without_degrees_of_freedom(void **state)
{
    linear l;
    brdffit_optimizer *opt = make(2);
    double b[2] = {0.0, 0.0}, cov[4];
    (void)state;
    l.n = 2;
    l.p = 2;
    l.x[0] = 1.0;
    l.x[1] = 1.0;
    l.y[0] = 3.0;
    l.x[2] = 1.0;
    l.x[3] = 2.0;
    l.y[1] = 5.0;
    assert_int_equal(brdffit_optimizer_set_residuals(opt, 2, linear_fn, &l), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_run(opt, b), BRDFFIT_OK);
    assert_close(b[0], 1.0, 1e-6);
    assert_close(b[1], 2.0, 1e-6);
    /* (X^T X)^-1 with X^T X = [[2, 3], [3, 5]]: [[5, -3], [-3, 2]] */
    assert_int_equal(brdffit_optimizer_covariance(opt, cov), BRDFFIT_OK);
    assert_close(cov[0], 5.0, 1e-8);
    assert_close(cov[1], -3.0, 1e-8);
    assert_close(cov[3], 2.0, 1e-8);
    brdffit_optimizer_destroy(opt);
}

static void test_condition_known_matrices(void **state)
{
    linear l;
    brdffit_optimizer *opt = make(2);
    double b[2];
    (void)state;
    /* J rows (1, 1), (1, 0), (0, 1): J^T J = [[2, 1], [1, 2]], eigenvalues 3 and 1 */
    l.n = 3;
    l.p = 2;
    l.x[0] = 1;
    l.x[1] = 1;
    l.y[0] = 2.0;
    l.x[2] = 1;
    l.x[3] = 0;
    l.y[1] = 1.0;
    l.x[4] = 0;
    l.x[5] = 1;
    l.y[2] = 1.5;
    assert_int_equal(brdffit_optimizer_set_residuals(opt, 3, linear_fn, &l), BRDFFIT_OK);
    b[0] = b[1] = 0.0;
    assert_int_equal(brdffit_optimizer_run(opt, b), BRDFFIT_OK);
    assert_close(brdffit_optimizer_condition(opt), 3.0, 1e-12);
    /* diag(1, 1e6): condition 1e6 */
    l.x[0] = 1;
    l.x[1] = 0;
    l.x[2] = 0;
    l.x[3] = 1000;
    l.x[4] = 0;
    l.x[5] = 0;
    b[0] = b[1] = 0.0;
    assert_int_equal(brdffit_optimizer_run(opt, b), BRDFFIT_OK);
    assert_close(brdffit_optimizer_condition(opt), 1e6, 1e-12);
    /* equal columns: singular */
    l.x[0] = 1;
    l.x[1] = 1;
    l.x[2] = 2;
    l.x[3] = 2;
    l.x[4] = 3;
    l.x[5] = 3;
    b[0] = b[1] = 0.0;
    assert_int_equal(brdffit_optimizer_run(opt, b), BRDFFIT_OK);
    assert_true(brdffit_optimizer_condition(opt) > 1e15);
    brdffit_optimizer_destroy(opt);
}

/* --- calls from inside a run ---------------------------------------------------------------- */

typedef struct reentry {
    brdffit_optimizer *opt;
    int tried;
    brdffit_status set_status, run_status, damping_status;
} reentry;

static int reenter(const brdffit_iteration *info, void *user)
{
    reentry *re = user;
    double x[2] = {0, 0};
    (void)info;
    if (re->tried) return 0;
    re->tried = 1;
    re->set_status = brdffit_optimizer_set(re->opt, BRDFFIT_OPT_GTOL, 1.0);
    re->run_status = brdffit_optimizer_run(re->opt, x);
    re->damping_status = brdffit_optimizer_set_damping(re->opt, NULL);
    return 0;
}

static void test_changes_during_run_rejected(void **state)
{
    brdffit_optimizer *opt = make(2);
    reentry re;
    double x[2] = {-1.2, 1.0};
    (void)state;
    memset(&re, 0, sizeof re);
    re.opt = opt;
    assert_int_equal(brdffit_optimizer_set_residuals(opt, 2, optim_rosenbrock, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set_callback(opt, reenter, &re), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
    assert_int_equal(re.set_status, BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(re.run_status, BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(re.damping_status, BRDFFIT_E_INVALID_ARGUMENT);
    assert_close(x[0], 1.0, 1e-8);
    assert_true(get(opt, BRDFFIT_OPT_GTOL) == 1e-13);
    brdffit_optimizer_destroy(opt);
}

/* The same run twice on one handle gives the same bits. */
static void test_run_is_repeatable(void **state)
{
    brdffit_optimizer *opt = make(3);
    double x1[3] = {0.02, 4000.0, 250.0}, x2[3] = {0.02, 4000.0, 250.0}, h1[300], h2[300];
    size_t n1, n2;
    (void)state;
    assert_int_equal(brdffit_optimizer_set_residuals(opt, 16, optim_meyer, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_run(opt, x1), BRDFFIT_OK);
    n1 = brdffit_optimizer_history(opt, h1, NULL);
    assert_int_equal(brdffit_optimizer_run(opt, x2), BRDFFIT_OK);
    n2 = brdffit_optimizer_history(opt, h2, NULL);
    assert_int_equal(n1, n2);
    assert_memory_equal(x1, x2, sizeof x1);
    assert_memory_equal(h1, h2, n1 * sizeof(double));
    brdffit_optimizer_destroy(opt);
}

/* --- allocation failures -------------------------------------------------------------------- */

static void test_allocation_failures(void **state)
{
    size_t n;
    int created = 0, set = 0, ran = 0, damped = 0;
    brdffit_damping pol = BRDFFIT_DAMPING_INIT;
    (void)state;
    pol.state_size = 64;
    pol.init = nop_init;
    pol.accept = nop_update;
    pol.reject = nop_update;
    for (n = 1; n < 64 && !(created && set && ran && damped); n++) {
        counting_alloc ca;
        brdffit_optimizer *opt = NULL;
        brdffit_status st;
        double x[2] = {-1.2, 1.0};
        /* create */
        counting_alloc_init(&ca, created ? 0 : n);
        st = brdffit_optimizer_create(&opt, 2, &ca.hook, NULL);
        if (st != BRDFFIT_OK) {
            assert_int_equal(st, BRDFFIT_E_OUT_OF_MEMORY);
            assert_null(opt);
            assert_int_equal(ca.live, 0);
            continue;
        }
        created = 1;
        /* set_residuals */
        ca.fail_at = set ? 0 : ca.allocs + n;
        st = brdffit_optimizer_set_residuals(opt, 2, optim_rosenbrock, NULL);
        if (st == BRDFFIT_OK) {
            set = 1;
            /* run */
            ca.fail_at = ran ? 0 : ca.allocs + n;
            st = brdffit_optimizer_run(opt, x);
            if (st == BRDFFIT_OK) {
                ran = 1;
                assert_close(x[0], 1.0, 1e-8);
            } else {
                assert_int_equal(st, BRDFFIT_E_OUT_OF_MEMORY);
                assert_true(x[0] == -1.2);
                assert_message_has(opt, "history");
            }
            /* set_damping with state */
            ca.fail_at = damped ? 0 : ca.allocs + n;
            st = brdffit_optimizer_set_damping(opt, &pol);
            if (st == BRDFFIT_OK)
                damped = 1;
            else
                assert_int_equal(st, BRDFFIT_E_OUT_OF_MEMORY);
        } else {
            assert_int_equal(st, BRDFFIT_E_OUT_OF_MEMORY);
            assert_message_has(opt, "cannot allocate");
        }
        brdffit_optimizer_destroy(opt);
        assert_int_equal(ca.live, 0);
    }
    assert_true(created && set && ran && damped);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_create_invalid),
        cmocka_unit_test(test_settings_defaults_and_restore),
        cmocka_unit_test(test_settings_invalid),
        cmocka_unit_test(test_invalid_arguments),
        cmocka_unit_test(test_results_before_run),
        cmocka_unit_test(test_stop_reason_strings),
        cmocka_unit_test(test_nan_and_failure_at_start_residual_form),
        cmocka_unit_test(test_nan_and_failure_at_start_normal_form),
        cmocka_unit_test(test_failure_at_trial_points),
        cmocka_unit_test(test_failure_then_nan_by_call_count),
        cmocka_unit_test(test_iteration_callback_stops),
        cmocka_unit_test(test_limits),
        cmocka_unit_test(test_gradient_test_scale_free),
        cmocka_unit_test(test_zero_cost),
        cmocka_unit_test(test_user_damping_policy),
        cmocka_unit_test(test_builtin_policies),
        cmocka_unit_test(test_stuck_policy_terminates),
        cmocka_unit_test(test_history_and_last_improvement),
        cmocka_unit_test(test_used_fallback),
        cmocka_unit_test(test_covariance_linear_regression),
        cmocka_unit_test(test_covariance_without_degrees_of_freedom),
        cmocka_unit_test(test_condition_known_matrices),
        cmocka_unit_test(test_changes_during_run_rejected),
        cmocka_unit_test(test_run_is_repeatable),
        cmocka_unit_test(test_allocation_failures),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
