/* The optimizer on classic hard problems with known minima (Moré, Garbow,
 * Hillstrom, ACM TOMS 7, 1981) and on two curve fits with data made from
 * known parameters: every built-in damping policy, the residual and the
 * normal-equation form, Marquardt and Levenberg scaling. */
#include <math.h>
#include <string.h>

#include "optim_problems.h"
#include "test_support.h"

enum { N_POLICIES = 3, MAX_CALLBACKS = 1024 };

static const brdffit_damping *policy(int k)
{
    if (k == 0) return brdffit_damping_thesis();
    if (k == 1) return brdffit_damping_marquardt();
    return brdffit_damping_nielsen();
}

typedef struct run_out {
    brdffit_status status;
    brdffit_stop_reason stop;
    double x[OPTIM_MAX_PARAMS];
    double cost, initial_cost;
    size_t iterations, evaluations, accepted, callback_calls;
    size_t calls, derivative_calls; /* problem callback calls, both forms */
    int normal, sandwich;
    double se[OPTIM_MAX_PARAMS];
    double seen_cost[MAX_CALLBACKS]; /* the cost each iteration callback saw */
} run_out;

typedef struct run_cfg {
    int policy, normal, marquardt;
    size_t max_iterations; /* 0: default */
    double lambda0;        /* 0: the policy's own start lambda */
    int sandwich;          /* BRDFFIT_OPT_COVARIANCE */
    int point_scaling;     /* BRDFFIT_OPT_SCALE_MEMORY 0 (set for the thesis's policy too) */
} run_cfg;

static int count_accepted(const brdffit_iteration *info, void *user)
{
    run_out *out = user;
    if (out->callback_calls < MAX_CALLBACKS) out->seen_cost[out->callback_calls] = info->cost;
    out->callback_calls++;
    if (info->accepted) out->accepted++;
    return 0;
}

/* The residual form's problem, counting its calls. */
typedef struct counted_residuals {
    brdffit_residual_fn fn;
    void *user;
    size_t calls, derivative_calls;
} counted_residuals;

static brdffit_status counted_fn(const double *x, double *r, double *jac, void *user)
{
    counted_residuals *c = user;
    c->calls++;
    if (jac != NULL) c->derivative_calls++;
    return c->fn(x, r, jac, c->user);
}

/* A built-in policy with another start lambda: the base policy's
 * callbacks, then lambda0 in place of its start. */
typedef struct started_policy {
    const brdffit_damping *base;
    double lambda0;
} started_policy;

static void started_init(void *state, double *lambda, void *user)
{
    const started_policy *s = user;
    s->base->init(state, lambda, s->base->user);
    *lambda = s->lambda0;
}

static void started_accept(void *state, double rho, double *lambda, void *user)
{
    const started_policy *s = user;
    s->base->accept(state, rho, lambda, s->base->user);
}

static void started_reject(void *state, double rho, double *lambda, void *user)
{
    const started_policy *s = user;
    s->base->reject(state, rho, lambda, s->base->user);
}

static int is_convergence(brdffit_stop_reason s)
{
    return s == BRDFFIT_STOP_GRADIENT || s == BRDFFIT_STOP_STEP || s == BRDFFIT_STOP_COST ||
           s == BRDFFIT_STOP_ZERO_COST;
}

/* Checks that hold for every run: history consistent with the results,
 * cost never rising, the returned x giving the reported cost. */
static void check_run_invariants(brdffit_optimizer *opt, const optim_problem *pb, void *user,
                                 const run_out *out)
{
    double hist_cost[8192], hist_lambda[8192], r[OPTIM_MAX_ROWS], cost = 0.0;
    size_t n = brdffit_optimizer_history(opt, NULL, NULL), i;
    assert_int_equal(n, out->iterations + 1);
    assert_true(n <= 8192);
    assert_int_equal(brdffit_optimizer_history(opt, hist_cost, hist_lambda), n);
    assert_true(hist_cost[0] == out->initial_cost);
    assert_true(hist_cost[n - 1] == out->cost);
    for (i = 1; i < n; i++) {
        assert_true(hist_cost[i] <= hist_cost[i - 1]);
        assert_true(hist_lambda[i] > 0.0 && isfinite(hist_lambda[i]));
    }
    /* The iteration callback sees every iteration of both attempts of a
     * restarted run, the iteration count only those of the attempt
     * returned (docs/optimizer.md): its history is then the first or the
     * last of the costs the callback saw. */
    assert_true(out->callback_calls >= out->iterations);
    if (out->callback_calls > out->iterations) {
        size_t skip = out->callback_calls - out->iterations, k;
        int first = 1, second = 1;
        assert_true(out->callback_calls <= MAX_CALLBACKS);
        for (k = 0; k < out->iterations; k++) {
            if (!(out->seen_cost[k] == hist_cost[k + 1])) first = 0;
            if (!(out->seen_cost[skip + k] == hist_cost[k + 1])) second = 0;
        }
        assert_true(first || second);
    }
    /* Every call of the problem callback is an evaluation, and only those:
     * the start (twice after a restart), the trials, the derivatives at an
     * accepted point (residual form), the re-evaluation of the first
     * attempt's point when it wins, the sandwich's pass. */
    assert_int_equal(out->calls, out->evaluations);
    if (out->normal) { /* the sums with every evaluation (docs/optimizer.md) */
        assert_int_equal(out->derivative_calls, out->evaluations);
        if (out->callback_calls == out->iterations)
            assert_true(out->evaluations <= 1 + out->iterations);
        else
            assert_true(out->evaluations <= 3 + out->callback_calls);
    } else {
        size_t restarts = out->callback_calls > out->iterations;
        assert_true(out->derivative_calls <= 1 + restarts * 2 + out->accepted + out->sandwich);
        assert_true(out->evaluations <=
                    1 + restarts * 2 + out->callback_calls + out->accepted + out->sandwich);
    }
    assert_int_equal(pb->fn(out->x, r, NULL, user), BRDFFIT_OK);
    for (i = 0; i < pb->n_rows; i++) cost += r[i] * r[i];
    assert_close(cost, out->cost, 1e-12);
}

static void run_problem(const optim_problem *pb, void *user, const run_cfg *cfg, run_out *out)
{
    brdffit_optimizer *opt = NULL;
    optim_normal_adapter ad;
    counted_residuals cr = {NULL, NULL, 0, 0};
    started_policy sp;
    brdffit_damping started = BRDFFIT_DAMPING_INIT;
    size_t max_it = cfg->max_iterations ? cfg->max_iterations : 200;
    memset(out, 0, sizeof *out);
    out->normal = cfg->normal;
    out->sandwich = cfg->sandwich && !cfg->normal;
    assert_int_equal(brdffit_optimizer_create(&opt, pb->n_params, NULL, NULL), BRDFFIT_OK);
    if (cfg->normal) {
        optim_normal_adapter_init(&ad, pb->fn, user, pb->n_rows, pb->n_params);
        assert_int_equal(
            brdffit_optimizer_set_normal(opt, pb->n_rows, optim_normal_adapter_fn, &ad),
            BRDFFIT_OK);
    } else {
        cr.fn = pb->fn;
        cr.user = user;
        assert_int_equal(brdffit_optimizer_set_residuals(opt, pb->n_rows, counted_fn, &cr),
                         BRDFFIT_OK);
    }
    if (cfg->lambda0 > 0.0) {
        sp.base = policy(cfg->policy);
        sp.lambda0 = cfg->lambda0;
        started.name = sp.base->name;
        started.state_size = sp.base->state_size;
        started.init = started_init;
        started.accept = started_accept;
        started.reject = started_reject;
        started.user = &sp;
        assert_int_equal(brdffit_optimizer_set_damping(opt, &started), BRDFFIT_OK);
    } else {
        assert_int_equal(brdffit_optimizer_set_damping(opt, policy(cfg->policy)), BRDFFIT_OK);
    }
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_COVARIANCE, out->sandwich), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_SCALING, cfg->marquardt), BRDFFIT_OK);
    /* The thesis's floor on lambda (1e-4) is relative to D: against the
     * running maximum of diag(J^T J) (the default) it keeps the steps of
     * Freudenstein-Roth and Meyer so short that they reach no minimum in
     * the iterations allowed here, so that policy runs with the scaling
     * of the current point, as it was designed. */
    if (cfg->point_scaling || cfg->policy == 0)
        assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_SCALE_MEMORY, 0.0), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_MAX_ITERATIONS, (double)max_it),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_MAX_EVALUATIONS, 2.0 * max_it + 1),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set_callback(opt, count_accepted, out), BRDFFIT_OK);
    memcpy(out->x, pb->x0, pb->n_params * sizeof(double));
    out->status = brdffit_optimizer_run(opt, out->x);
    assert_int_equal(out->status, BRDFFIT_OK);
    assert_string_equal(brdffit_optimizer_message(opt), "");
    out->stop = brdffit_optimizer_stop_reason(opt);
    out->cost = brdffit_optimizer_final_cost(opt);
    out->initial_cost = brdffit_optimizer_initial_cost(opt);
    out->iterations = brdffit_optimizer_iterations(opt);
    out->evaluations = brdffit_optimizer_evaluations(opt);
    assert_int_equal(brdffit_optimizer_std_errors(opt, out->se), BRDFFIT_OK);
    if (cfg->normal) {
        out->calls = ad.calls;
        out->derivative_calls = ad.derivative_calls;
    } else {
        out->calls = cr.calls;
        out->derivative_calls = cr.derivative_calls;
    }
    check_run_invariants(opt, pb, user, out);
    brdffit_optimizer_destroy(opt);
}

/* Visit every policy x form x scaling combination. */
typedef void (*combo_fn)(const optim_problem *pb, void *user, const run_cfg *cfg);

static void for_each_combo(const optim_problem *pb, void *user, size_t max_it, combo_fn fn)
{
    run_cfg cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.max_iterations = max_it;
    for (cfg.policy = 0; cfg.policy < N_POLICIES; cfg.policy++)
        for (cfg.normal = 0; cfg.normal < 2; cfg.normal++)
            for (cfg.marquardt = 0; cfg.marquardt < 2; cfg.marquardt++) fn(pb, user, &cfg);
}

static const optim_problem *mgh(const char *name)
{
    size_t n, i;
    const optim_problem *pb = optim_mgh_problems(&n);
    for (i = 0; i < n; i++)
        if (strcmp(pb[i].name, name) == 0) return &pb[i];
    fail_msg("no problem %s", name);
    return NULL;
}

/* --- Rosenbrock: minimum 0 at (1, 1) ---------------------------------------------- */

static void rosenbrock_combo(const optim_problem *pb, void *user, const run_cfg *cfg)
{
    run_out out;
    run_problem(pb, user, cfg, &out);
    assert_true(is_convergence(out.stop));
    assert_true(out.cost < 1e-18);
    assert_close(out.x[0], 1.0, 1e-8);
    assert_close(out.x[1], 1.0, 1e-8);
}

static void test_rosenbrock(void **state)
{
    (void)state;
    for_each_combo(mgh("rosenbrock"), NULL, 0, rosenbrock_combo);
}

/* --- Powell singular: minimum 0 at the origin, J singular there ---------------------- */

static void powell_combo(const optim_problem *pb, void *user, const run_cfg *cfg)
{
    run_out out;
    size_t j;
    run_problem(pb, user, cfg, &out);
    if (cfg->policy == 0) {
        /* The thesis's policy never lets lambda fall below 1e-4: in the
         * directions where J^T J vanishes at the solution the step is
         * then a damped gradient step and convergence is sublinear
         * (|x| ~ k^-1/2). It only gets close within the limit. */
        assert_int_equal(out.stop, BRDFFIT_STOP_MAX_ITERATIONS);
        assert_true(out.cost < 1e-9);
        for (j = 0; j < 4; j++) assert_true(fabs(out.x[j]) < 1e-2);
        return;
    }
    assert_true(is_convergence(out.stop));
    assert_true(out.cost < 1e-24);
    for (j = 0; j < 4; j++) assert_true(fabs(out.x[j]) < 1e-5);
}

static void test_powell_singular(void **state)
{
    (void)state;
    for_each_combo(mgh("powell_singular"), NULL, 0, powell_combo);
}

/* --- Freudenstein-Roth: global 0 at (5, 4), local 48.98425367924 at
 * (11.41277898690, -0.8968052532745) -------------------------------------------------- */

static void freudenstein_combo(const optim_problem *pb, void *user, const run_cfg *cfg)
{
    run_out out;
    run_problem(pb, user, cfg, &out);
    assert_true(is_convergence(out.stop));
    if (out.cost < 1e-10) {
        assert_close(out.x[0], 5.0, 1e-6);
        assert_close(out.x[1], 4.0, 1e-6);
    } else {
        assert_close(out.cost, 48.98425367924, 1e-10);
        assert_close(out.x[0], 11.41277898690, 1e-5);
        assert_close(out.x[1], -0.8968052532745, 1e-5);
    }
    /* From (0.5, -2) the damped Gauss-Newton path stays on the x2 < 0
     * side of the ridge around x2 = 0.7: every policy ends in the local
     * minimum, as MINPACK's lmder does from this start. */
    assert_true(out.x[1] < 0.0);
}

static void test_freudenstein_roth(void **state)
{
    (void)state;
    for_each_combo(mgh("freudenstein_roth"), NULL, 0, freudenstein_combo);
}

/* --- Meyer: 87.9458551708511 at (0.005609636471, 6181.346346, 345.2236346) ------------ */

static void meyer_combo(const optim_problem *pb, void *user, const run_cfg *cfg)
{
    run_out out;
    /* Levenberg scaling with the thesis's lambda in [1e-4, 1] (relative to
     * the largest diagonal entry of J^T J, ~1e13 times the smallest) damps
     * x2 and x3 so much that they hardly move: not a sensible pairing. */
    if (cfg->policy == 0 && !cfg->marquardt) return;
    run_problem(pb, user, cfg, &out);
    assert_true(is_convergence(out.stop));
    assert_close(out.cost, 87.9458551708511, 1e-9);
    assert_close(out.x[0], 0.005609636471028, 1e-5);
    assert_close(out.x[1], 6181.346346286, 1e-5);
    assert_close(out.x[2], 345.2236346241, 1e-5);
}

static void test_meyer(void **state)
{
    (void)state;
    for_each_combo(mgh("meyer"), NULL, 5000, meyer_combo);
}

/* Meyer from the far start (2, 4e5, 2.5e4), with nothing but the defaults
 * (Nielsen's policy, Marquardt scaling, the default limits and
 * tolerances): a few thousand iterations down a narrow valley, which the
 * default iteration limit leaves room for. */
static void test_meyer_far_start_defaults(void **state)
{
    brdffit_optimizer *opt = NULL;
    double x[3] = {2.0, 400000.0, 25000.0};
    (void)state;
    assert_int_equal(brdffit_optimizer_create(&opt, 3, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set_residuals(opt, 16, optim_meyer, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
    assert_true(is_convergence(brdffit_optimizer_stop_reason(opt)));
    assert_close(brdffit_optimizer_final_cost(opt), 87.9458551708511, 1e-9);
    assert_close(x[0], 0.005609636471028, 1e-6);
    assert_close(x[1], 6181.346346286, 1e-6);
    assert_close(x[2], 345.2236346241, 1e-6);
    brdffit_optimizer_destroy(opt);
}

/* --- Box 3-D: minimum 0 at (1, 10, 1), (10, 1, -1) and on x1 = x2, x3 = 0 ------------- */

static void box3d_combo(const optim_problem *pb, void *user, const run_cfg *cfg)
{
    run_out out;
    run_problem(pb, user, cfg, &out);
    assert_true(is_convergence(out.stop));
    assert_true(out.cost < 1e-18);
    if (fabs(out.x[0] - 1.0) < 1e-6) {
        assert_close(out.x[1], 10.0, 1e-6);
        assert_close(out.x[2], 1.0, 1e-6);
    } else if (fabs(out.x[0] - 10.0) < 1e-6) {
        assert_close(out.x[1], 1.0, 1e-6);
        assert_close(out.x[2], -1.0, 1e-6);
    } else {
        assert_close(out.x[0], out.x[1], 1e-6);
        assert_true(fabs(out.x[2]) < 1e-6);
    }
}

static void test_box3d(void **state)
{
    (void)state;
    for_each_combo(mgh("box3d"), NULL, 0, box3d_combo);
}

/* --- Jennrich-Sampson: 124.362182355615 at x1 = x2 = 0.2578252136704 ------------------- */

static void jennrich_combo(const optim_problem *pb, void *user, const run_cfg *cfg)
{
    run_out out;
    run_problem(pb, user, cfg, &out);
    assert_true(is_convergence(out.stop));
    assert_close(out.cost, 124.362182355615, 1e-10);
    assert_close(out.x[0], 0.2578252136704, 1e-6);
    assert_close(out.x[1], 0.2578252136704, 1e-6);
}

static void test_jennrich_sampson(void **state)
{
    (void)state;
    for_each_combo(mgh("jennrich_sampson"), NULL, 0, jennrich_combo);
}

/* --- curve fits: recover the parameters the data were made from --------------------- */

static void check_recovery(const run_out *out, const optim_fit_data *d, size_t p, double rel)
{
    size_t j;
    assert_true(is_convergence(out->stop));
    for (j = 0; j < p; j++) {
        double err = fabs(out->x[j] - d->truth[j]);
        assert_true(out->se[j] > 0.0);
        if (!(err <= 4.0 * out->se[j]) || !(err <= rel * fabs(d->truth[j])))
            fail_msg("parameter %zu = %.9g, truth %.9g, standard error %.3g", j, out->x[j],
                     d->truth[j], out->se[j]);
    }
    /* the residual standard deviation estimates the noise */
    assert_close(sqrt(out->cost / (double)(d->n - p)), d->noise, 0.3);
}

static void exp_combo(const optim_problem *pb, void *user, const run_cfg *cfg)
{
    run_out out;
    run_problem(pb, user, cfg, &out);
    check_recovery(&out, user, 3, 0.02);
}

static void test_exp_fit(void **state)
{
    optim_fit_data d;
    optim_problem pb = {"exp", 3, 0, {1.0, 0.1, 0.0}, optim_exp_fit, 0, {-1.0, -1.0}};
    (void)state;
    optim_make_exp_data(&d);
    pb.n_rows = d.n;
    for_each_combo(&pb, &d, 0, exp_combo);
    /* a start on the far side: the first trial points have b < 0 */
    pb.x0[1] = 3.0;
    for_each_combo(&pb, &d, 0, exp_combo);
}

static void rational_combo(const optim_problem *pb, void *user, const run_cfg *cfg)
{
    run_out out;
    run_problem(pb, user, cfg, &out);
    check_recovery(&out, user, 4, 0.05);
}

static void test_rational_fit(void **state)
{
    optim_fit_data d;
    optim_problem pb = {"rational",         4, 0,           {1.0, 1.0, 0.1, 0.1},
                        optim_rational_fit, 0, {-1.0, -1.0}};
    (void)state;
    optim_make_rational_data(&d);
    pb.n_rows = d.n;
    /* the thesis's lambda floor makes Levenberg scaling slow here */
    for_each_combo(&pb, &d, 1000, rational_combo);
}

/* All combinations of one fit land on the same minimum. */
static void test_fits_agree_across_combinations(void **state)
{
    optim_fit_data d;
    optim_problem pb = {"rational",         4, 0,           {1.0, 1.0, 0.1, 0.1},
                        optim_rational_fit, 0, {-1.0, -1.0}};
    run_cfg cfg = {2, 0, 1, 1000, 0.0, 0, 0};
    run_out ref, out;
    size_t j;
    (void)state;
    optim_make_rational_data(&d);
    pb.n_rows = d.n;
    run_problem(&pb, &d, &cfg, &ref);
    for (cfg.policy = 0; cfg.policy < N_POLICIES; cfg.policy++) {
        for (cfg.normal = 0; cfg.normal < 2; cfg.normal++) {
            for (cfg.marquardt = 0; cfg.marquardt < 2; cfg.marquardt++) {
                run_problem(&pb, &d, &cfg, &out);
                assert_close(out.cost, ref.cost, 1e-9);
                for (j = 0; j < 4; j++) assert_close(out.x[j], ref.x[j], 1e-4);
            }
        }
    }
}

/* The evaluation count is the number of problem callback calls, in both
 * forms, for every policy and both scale memories, with start lambdas
 * that make the MGH problems reject steps and stall into the restart
 * (Box 3-D from lambda 3e-2 in the normal form with the scaling of the
 * current point: 25 iterations over two attempts, 9 in the one
 * returned). check_run_invariants() compares the counts; this test makes
 * sure the set really exercises rejections, restarts and the sandwich. */
static void test_evaluation_counts(void **state)
{
    static const double lambda0[] = {3e-2, 1e2};
    size_t n_pb, k, l, rejected = 0, restarted[2] = {0, 0}, sandwiches = 0;
    const optim_problem *pb = optim_mgh_problems(&n_pb);
    run_cfg cfg;
    run_out out;
    (void)state;
    memset(&cfg, 0, sizeof cfg);
    for (k = 0; k < n_pb; k++) {
        for (l = 0; l < sizeof lambda0 / sizeof lambda0[0]; l++) {
            cfg.lambda0 = lambda0[l];
            for (cfg.policy = 0; cfg.policy < N_POLICIES; cfg.policy++) {
                for (cfg.normal = 0; cfg.normal < 2; cfg.normal++) {
                    for (cfg.marquardt = 0; cfg.marquardt < 2; cfg.marquardt++) {
                        for (cfg.sandwich = 0; cfg.sandwich <= !cfg.normal; cfg.sandwich++) {
                            for (cfg.point_scaling = 0; cfg.point_scaling < 2;
                                 cfg.point_scaling++) {
                                run_problem(&pb[k], NULL, &cfg, &out);
                                assert_true(out.calls > 0);
                                if (out.accepted < out.callback_calls) rejected++;
                                if (out.callback_calls > out.iterations) restarted[cfg.normal]++;
                                sandwiches += (size_t)out.sandwich;
                            }
                        }
                    }
                }
            }
        }
    }
    assert_true(rejected > 0);
    assert_true(restarted[0] > 0 && restarted[1] > 0);
    assert_true(sandwiches > 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rosenbrock),
        cmocka_unit_test(test_powell_singular),
        cmocka_unit_test(test_freudenstein_roth),
        cmocka_unit_test(test_meyer),
        cmocka_unit_test(test_meyer_far_start_defaults),
        cmocka_unit_test(test_box3d),
        cmocka_unit_test(test_jennrich_sampson),
        cmocka_unit_test(test_exp_fit),
        cmocka_unit_test(test_rational_fit),
        cmocka_unit_test(test_fits_agree_across_combinations),
        cmocka_unit_test(test_evaluation_counts),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
