/* Box bounds and fixed parameters: solutions on a bound, starts on and
 * outside the box, steps that leave the box, closed-form constrained
 * answers, and the covariance over the parameters left free. */
#include <math.h>
#include <string.h>

#include "optim_problems.h"
#include "test_support.h"

static const brdffit_damping *policy(int k)
{
    if (k == 0) return brdffit_damping_thesis();
    if (k == 1) return brdffit_damping_marquardt();
    return brdffit_damping_nielsen();
}

static int is_convergence(brdffit_stop_reason s)
{
    return s == BRDFFIT_STOP_GRADIENT || s == BRDFFIT_STOP_STEP || s == BRDFFIT_STOP_COST ||
           s == BRDFFIT_STOP_ZERO_COST;
}

/* A residual problem that records where it was evaluated. */
typedef struct box_probe {
    brdffit_residual_fn fn;
    void *user;
    size_t p;
    const double *lower, *upper; /* NULL: unbounded */
    size_t evaluations, outside;
    size_t touched_lower[OPTIM_MAX_PARAMS]; /* evaluations with x_j exactly on a bound */
    size_t touched_upper[OPTIM_MAX_PARAMS];
} box_probe;

static brdffit_status probe_fn(const double *x, double *r, double *jac, void *user)
{
    box_probe *b = user;
    size_t j;
    b->evaluations++;
    for (j = 0; j < b->p; j++) {
        if ((b->lower && x[j] < b->lower[j]) || (b->upper && x[j] > b->upper[j])) b->outside++;
        if (b->lower && x[j] == b->lower[j]) b->touched_lower[j]++;
        if (b->upper && x[j] == b->upper[j]) b->touched_upper[j]++;
    }
    return b->fn(x, r, jac, b->user);
}

typedef struct bounded_run {
    /* in */
    brdffit_residual_fn fn;
    void *user;
    size_t p, n_rows;
    const double *x0, *lower, *upper;
    const unsigned char *fixed;
    int policy, normal, marquardt;
    /* out */
    double x[OPTIM_MAX_PARAMS];
    double cov[OPTIM_MAX_PARAMS * OPTIM_MAX_PARAMS];
    double cost, initial_cost;
    brdffit_stop_reason stop;
    box_probe probe;
} bounded_run;

static void run_bounded(bounded_run *b)
{
    brdffit_optimizer *opt = NULL;
    optim_normal_adapter ad;
    memset(&b->probe, 0, sizeof b->probe);
    b->probe.fn = b->fn;
    b->probe.user = b->user;
    b->probe.p = b->p;
    b->probe.lower = b->lower;
    b->probe.upper = b->upper;
    assert_int_equal(brdffit_optimizer_create(&opt, b->p, NULL, NULL), BRDFFIT_OK);
    if (b->normal) {
        optim_normal_adapter_init(&ad, probe_fn, &b->probe, b->n_rows, b->p);
        assert_int_equal(brdffit_optimizer_set_normal(opt, b->n_rows, optim_normal_adapter_fn, &ad),
                         BRDFFIT_OK);
    } else {
        assert_int_equal(brdffit_optimizer_set_residuals(opt, b->n_rows, probe_fn, &b->probe),
                         BRDFFIT_OK);
    }
    assert_int_equal(brdffit_optimizer_set_damping(opt, policy(b->policy)), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_SCALING, b->marquardt), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_MAX_ITERATIONS, 1000), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_MAX_EVALUATIONS, 3000), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set_bounds(opt, b->lower, b->upper), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set_fixed(opt, b->fixed), BRDFFIT_OK);
    memcpy(b->x, b->x0, b->p * sizeof(double));
    assert_int_equal(brdffit_optimizer_run(opt, b->x), BRDFFIT_OK);
    b->stop = brdffit_optimizer_stop_reason(opt);
    b->cost = brdffit_optimizer_final_cost(opt);
    b->initial_cost = brdffit_optimizer_initial_cost(opt);
    assert_int_equal(brdffit_optimizer_covariance(opt, b->cov), BRDFFIT_OK);
    brdffit_optimizer_destroy(opt);
    /* the problem is never evaluated outside the box */
    assert_int_equal(b->probe.outside, 0);
}

typedef void (*bounded_check)(bounded_run *b);

/* Every policy, both forms, both scalings. */
static void for_each_combo(bounded_run *b, bounded_check check)
{
    for (b->policy = 0; b->policy < 3; b->policy++)
        for (b->normal = 0; b->normal < 2; b->normal++)
            for (b->marquardt = 0; b->marquardt < 2; b->marquardt++) {
                run_bounded(b);
                check(b);
            }
}

/* --- Rosenbrock with x1 <= 0.5: minimum 0.25 at (0.5, 0.25) -------------------------- */

static void check_rosenbrock_bound(bounded_run *b)
{
    assert_true(is_convergence(b->stop));
    assert_true(b->x[0] == 0.5);
    assert_close(b->x[1], 0.25, 1e-8);
    assert_close(b->cost, 0.25, 1e-12);
}

static void test_rosenbrock_solution_on_bound(void **state)
{
    const double x0[2] = {-1.2, 1.0}, upper[2] = {0.5, HUGE_VAL};
    bounded_run b;
    (void)state;
    memset(&b, 0, sizeof b);
    b.fn = optim_rosenbrock;
    b.p = b.n_rows = 2;
    b.x0 = x0;
    b.upper = upper;
    for_each_combo(&b, check_rosenbrock_bound);
}

static void test_rosenbrock_start_on_bound(void **state)
{
    const double x0[2] = {0.5, 1.0}, upper[2] = {0.5, HUGE_VAL};
    bounded_run b;
    (void)state;
    memset(&b, 0, sizeof b);
    b.fn = optim_rosenbrock;
    b.p = b.n_rows = 2;
    b.x0 = x0;
    b.upper = upper;
    for_each_combo(&b, check_rosenbrock_bound);
}

/* Start on a lower bound that the solution (1, 1) lies away from. */
static void check_rosenbrock_leaves_bound(bounded_run *b)
{
    assert_true(is_convergence(b->stop));
    assert_true(b->cost < 1e-18);
    assert_close(b->x[0], 1.0, 1e-8);
    assert_close(b->x[1], 1.0, 1e-8);
}

static void test_rosenbrock_start_on_bound_solution_inside(void **state)
{
    const double x0[2] = {-1.2, 1.0}, lower[2] = {-1.2, -HUGE_VAL};
    bounded_run b;
    (void)state;
    memset(&b, 0, sizeof b);
    b.fn = optim_rosenbrock;
    b.p = b.n_rows = 2;
    b.x0 = x0;
    b.lower = lower;
    for_each_combo(&b, check_rosenbrock_leaves_bound);
}

/* --- straight line y = a + b t: closed-form constrained answers ---------------------- */

typedef struct line_data {
    size_t n;
    double t[20], y[20];
} line_data;

static void make_line(line_data *d)
{
    unsigned long long s = 99;
    size_t i;
    d->n = 20;
    for (i = 0; i < d->n; i++) {
        d->t[i] = 0.5 * (double)i;
        d->y[i] = 1.0 + 2.0 * d->t[i] + 0.2 * (optim_uniform(&s) - 0.5);
    }
}

static brdffit_status line_fn(const double *x, double *r, double *jac, void *user)
{
    const line_data *d = user;
    size_t i;
    for (i = 0; i < d->n; i++) {
        r[i] = x[0] + x[1] * d->t[i] - d->y[i];
        if (jac != NULL) {
            jac[2 * i] = 1.0;
            jac[2 * i + 1] = d->t[i];
        }
    }
    return BRDFFIT_OK;
}

static double line_cost(const line_data *d, double a, double b)
{
    double c = 0.0;
    size_t i;
    for (i = 0; i < d->n; i++) c += (a + b * d->t[i] - d->y[i]) * (a + b * d->t[i] - d->y[i]);
    return c;
}

static line_data g_line; /* read-only after make_line in each test */

/* Slope held at its upper bound 1.5 (unconstrained ~2): a = mean(y - 1.5 t);
 * covariance only for a: s^2 / n with s^2 = cost / (n - 1). */
static void check_line_slope_bound(bounded_run *b)
{
    const line_data *d = &g_line;
    double a = 0.0, cost, s2;
    size_t i;
    for (i = 0; i < d->n; i++) a += d->y[i] - 1.5 * d->t[i];
    a /= (double)d->n;
    cost = line_cost(d, a, 1.5);
    assert_true(is_convergence(b->stop));
    assert_true(b->x[1] == 1.5);
    assert_close(b->x[0], a, 1e-7);
    assert_close(b->cost, cost, 1e-9);
    s2 = cost / (double)(d->n - 1);
    assert_close(b->cov[0], s2 / (double)d->n, 1e-6);
    assert_true(b->cov[1] == 0.0 && b->cov[2] == 0.0 && b->cov[3] == 0.0);
}

static void test_line_solution_on_upper_bound(void **state)
{
    const double x0[2] = {0.0, 0.0}, upper[2] = {HUGE_VAL, 1.5};
    bounded_run b;
    (void)state;
    make_line(&g_line);
    memset(&b, 0, sizeof b);
    b.fn = line_fn;
    b.user = &g_line;
    b.p = 2;
    b.n_rows = g_line.n;
    b.x0 = x0;
    b.upper = upper;
    for_each_combo(&b, check_line_slope_bound);
}

/* Start outside the box: moved onto it first, same answer. */
static void test_line_start_outside_projected(void **state)
{
    const double x0[2] = {-7.0, 5.0}, lower[2] = {-3.0, -HUGE_VAL}, upper[2] = {HUGE_VAL, 1.5};
    bounded_run b;
    (void)state;
    make_line(&g_line);
    memset(&b, 0, sizeof b);
    b.fn = line_fn;
    b.user = &g_line;
    b.p = 2;
    b.n_rows = g_line.n;
    b.x0 = x0;
    b.lower = lower;
    b.upper = upper;
    for_each_combo(&b, check_line_slope_bound);
    /* the start point evaluated was the projection (-3, 1.5) */
    b.policy = 2;
    b.normal = 0;
    b.marquardt = 1;
    run_bounded(&b);
    assert_close(b.initial_cost, line_cost(&g_line, -3.0, 1.5), 1e-14);
    assert_true(b.probe.touched_lower[0] >= 1);
}

/* Intercept held at its lower bound 2 (unconstrained ~1):
 * b = sum((y - 2) t) / sum(t^2). */
static void check_line_intercept_bound(bounded_run *b)
{
    const line_data *d = &g_line;
    double num = 0.0, den = 0.0, slope, cost, s2;
    size_t i;
    for (i = 0; i < d->n; i++) {
        num += (d->y[i] - 2.0) * d->t[i];
        den += d->t[i] * d->t[i];
    }
    slope = num / den;
    cost = line_cost(d, 2.0, slope);
    assert_true(is_convergence(b->stop));
    assert_true(b->x[0] == 2.0);
    assert_close(b->x[1], slope, 1e-7);
    assert_close(b->cost, cost, 1e-9);
    s2 = cost / (double)(d->n - 1);
    assert_close(b->cov[3], s2 / den, 1e-6);
    assert_true(b->cov[0] == 0.0 && b->cov[1] == 0.0 && b->cov[2] == 0.0);
}

static void test_line_solution_on_lower_bound(void **state)
{
    const double x0[2] = {5.0, 0.0}, lower[2] = {2.0, -HUGE_VAL};
    bounded_run b;
    (void)state;
    make_line(&g_line);
    memset(&b, 0, sizeof b);
    b.fn = line_fn;
    b.user = &g_line;
    b.p = 2;
    b.n_rows = g_line.n;
    b.x0 = x0;
    b.lower = lower;
    for_each_combo(&b, check_line_intercept_bound);
}

/* --- a step leaving the box: exponential decay with the rate in [0.05, 2] --------- */

static optim_fit_data g_exp;
static double g_exp_free[3]; /* the unbounded answer */

static void check_exp_inside(bounded_run *b)
{
    size_t j;
    assert_true(is_convergence(b->stop));
    for (j = 0; j < 3; j++) assert_close(b->x[j], g_exp_free[j], 1e-6);
    /* the first steps overshoot to b < 0 (see test_optim_problems); here
     * they are cut at the bound */
    assert_true(b->probe.touched_lower[1] >= 1);
}

static void test_step_leaving_box(void **state)
{
    const double x0[3] = {1.0, 1.9, 0.0};
    const double lower[3] = {-HUGE_VAL, 0.05, -HUGE_VAL}, upper[3] = {HUGE_VAL, 2.0, HUGE_VAL};
    bounded_run b;
    (void)state;
    optim_make_exp_data(&g_exp);
    memset(&b, 0, sizeof b);
    b.fn = optim_exp_fit;
    b.user = &g_exp;
    b.p = 3;
    b.n_rows = g_exp.n;
    b.x0 = x0;
    b.policy = 2;
    b.marquardt = 1;
    run_bounded(&b);
    memcpy(g_exp_free, b.x, sizeof g_exp_free);
    b.lower = lower;
    b.upper = upper;
    for_each_combo(&b, check_exp_inside);
}

/* --- fixed parameters ---------------------------------------------------------------- */

static const double fixed_c = 0.9;

/* The exponential model with c held at fixed_c, as a two-parameter problem. */
static brdffit_status exp_fit_ab(const double *x, double *r, double *jac, void *user)
{
    double x3[3] = {x[0], x[1], fixed_c}, jac3[3 * OPTIM_MAX_ROWS];
    const optim_fit_data *d = user;
    size_t i;
    if (optim_exp_fit(x3, r, jac ? jac3 : NULL, user) != BRDFFIT_OK) return BRDFFIT_E_MODEL_FAILED;
    if (jac != NULL)
        for (i = 0; i < d->n; i++) {
            jac[2 * i] = jac3[3 * i];
            jac[2 * i + 1] = jac3[3 * i + 1];
        }
    return BRDFFIT_OK;
}

static double g_ab[2]; /* the two-parameter answer */

static void check_fixed(bounded_run *b)
{
    size_t j;
    assert_true(is_convergence(b->stop));
    assert_true(b->x[2] == fixed_c);
    assert_close(b->x[0], g_ab[0], 1e-6);
    assert_close(b->x[1], g_ab[1], 1e-6);
    for (j = 0; j < 3; j++) {
        assert_true(b->cov[2 * 3 + j] == 0.0);
        assert_true(b->cov[j * 3 + 2] == 0.0);
    }
    assert_true(b->cov[0] > 0.0 && b->cov[4] > 0.0);
}

static void test_fixed_parameter(void **state)
{
    const double x0[3] = {1.0, 0.1, fixed_c}, x0_ab[2] = {1.0, 0.1};
    const unsigned char fixed[3] = {0, 0, 1};
    bounded_run b;
    (void)state;
    optim_make_exp_data(&g_exp);
    memset(&b, 0, sizeof b);
    b.fn = exp_fit_ab;
    b.user = &g_exp;
    b.p = 2;
    b.n_rows = g_exp.n;
    b.x0 = x0_ab;
    b.policy = 2;
    b.marquardt = 1;
    run_bounded(&b);
    memcpy(g_ab, b.x, sizeof g_ab);
    assert_true(fabs(g_ab[0] - 5.0) < 0.5); /* not the truth: c is off by 0.1 */
    memset(&b, 0, sizeof b);
    b.fn = optim_exp_fit;
    b.user = &g_exp;
    b.p = 3;
    b.n_rows = g_exp.n;
    b.x0 = x0;
    b.fixed = fixed;
    for_each_combo(&b, check_fixed);
}

/* A fixed parameter outside the box is moved onto it, then held there. */
static void test_fixed_outside_box_projected(void **state)
{
    const double x0[3] = {1.0, 0.1, 3.0}, upper[3] = {HUGE_VAL, HUGE_VAL, fixed_c};
    const unsigned char fixed[3] = {0, 0, 1};
    bounded_run b;
    (void)state;
    optim_make_exp_data(&g_exp);
    memset(&b, 0, sizeof b);
    b.fn = optim_exp_fit;
    b.user = &g_exp;
    b.p = 3;
    b.n_rows = g_exp.n;
    b.x0 = x0;
    b.upper = upper;
    b.fixed = fixed;
    b.policy = 2;
    b.marquardt = 1;
    run_bounded(&b);
    assert_true(b.x[2] == fixed_c);
    assert_true(is_convergence(b.stop));
}

/* Everything fixed: nothing can move; the run ends at once. */
static void test_all_fixed(void **state)
{
    const double x0[2] = {-1.2, 1.0};
    const unsigned char fixed[2] = {1, 1};
    double cov[4];
    bounded_run b;
    (void)state;
    memset(&b, 0, sizeof b);
    b.fn = optim_rosenbrock;
    b.p = b.n_rows = 2;
    b.x0 = x0;
    b.fixed = fixed;
    b.policy = 2;
    run_bounded(&b);
    assert_int_equal(b.stop, BRDFFIT_STOP_GRADIENT);
    assert_true(b.x[0] == -1.2 && b.x[1] == 1.0);
    assert_close(b.cost, 24.2, 1e-12);
    memset(cov, 0, sizeof cov);
    assert_memory_equal(b.cov, cov, sizeof cov);
    assert_int_equal(b.probe.evaluations, 1);
}

/* lower == upper pins a parameter like the fixed mask. */
static void test_equal_bounds_pin(void **state)
{
    const double x0[3] = {1.0, 0.1, 0.0};
    const double lower[3] = {-HUGE_VAL, -HUGE_VAL, fixed_c},
                 upper[3] = {HUGE_VAL, HUGE_VAL, fixed_c};
    bounded_run b;
    (void)state;
    optim_make_exp_data(&g_exp);
    memset(&b, 0, sizeof b);
    b.fn = exp_fit_ab;
    b.user = &g_exp;
    b.p = 2;
    b.n_rows = g_exp.n;
    b.x0 = x0;
    b.policy = 2;
    b.marquardt = 1;
    run_bounded(&b);
    memcpy(g_ab, b.x, sizeof g_ab);
    memset(&b, 0, sizeof b);
    b.fn = optim_exp_fit;
    b.user = &g_exp;
    b.p = 3;
    b.n_rows = g_exp.n;
    b.x0 = x0;
    b.lower = lower;
    b.upper = upper;
    for_each_combo(&b, check_fixed);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rosenbrock_solution_on_bound),
        cmocka_unit_test(test_rosenbrock_start_on_bound),
        cmocka_unit_test(test_rosenbrock_start_on_bound_solution_inside),
        cmocka_unit_test(test_line_solution_on_upper_bound),
        cmocka_unit_test(test_line_start_outside_projected),
        cmocka_unit_test(test_line_solution_on_lower_bound),
        cmocka_unit_test(test_step_leaving_box),
        cmocka_unit_test(test_fixed_parameter),
        cmocka_unit_test(test_fixed_outside_box_projected),
        cmocka_unit_test(test_all_fixed),
        cmocka_unit_test(test_equal_bounds_pin),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
