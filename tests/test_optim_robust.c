/* Robustness of the optimizer's scaling and step-test settings
 * (BRDFFIT_OPT_SCALE_MEMORY, BRDFFIT_OPT_STEP_TEST) on certified problems:
 * the 54 NIST StRD runs and Moré-Garbow-Hillstrom problems (ACM TOMS 7,
 * 1981) from their standard start x0 and from 10 x0 and 100 x0, as MGH
 * and MINPACK's test driver run them, for every built-in damping policy.
 * A run is solved when it ends at one of the problem's published minima
 * (relative 1e-6, or 1e-10 absolute for a zero minimum), reported
 * converged or not. The tables are printed; the assertions hold the
 * default's counts, which docs/nist-strd.md quotes. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "nist_problems.h"
#include "optim_problems.h"
#include "test_support.h"

#define TWO_PI 6.28318530717958647692

/* --- further MGH problems ------------------------------------------------------ */

/* #4 Brown badly scaled: minimum 0 at (1e6, 2e-6). */
static brdffit_status brown_badly_scaled(const double *x, double *r, double *jac, void *user)
{
    (void)user;
    r[0] = x[0] - 1e6;
    r[1] = x[1] - 2e-6;
    r[2] = x[0] * x[1] - 2.0;
    if (jac != NULL) {
        jac[0] = 1.0, jac[1] = 0.0;
        jac[2] = 0.0, jac[3] = 1.0;
        jac[4] = x[1], jac[5] = x[0];
    }
    return BRDFFIT_OK;
}

/* #5 Beale: minimum 0 at (3, 0.5). */
static brdffit_status beale(const double *x, double *r, double *jac, void *user)
{
    static const double y[3] = {1.5, 2.25, 2.625};
    size_t i;
    (void)user;
    for (i = 0; i < 3; i++) {
        double k = (double)(i + 1), pk = pow(x[1], k);
        r[i] = y[i] - x[0] * (1.0 - pk);
        if (jac != NULL) {
            jac[2 * i] = -(1.0 - pk);
            jac[2 * i + 1] = x[0] * k * pow(x[1], k - 1.0);
        }
    }
    return BRDFFIT_OK;
}

/* #7 Helical valley: minimum 0 at (1, 0, 0). theta as MGH define it. */
static brdffit_status helical_valley(const double *x, double *r, double *jac, void *user)
{
    double rr = x[0] * x[0] + x[1] * x[1], n = sqrt(rr), theta;
    (void)user;
    if (x[0] == 0.0) return BRDFFIT_E_NONFINITE;
    theta = atan(x[1] / x[0]) / TWO_PI + (x[0] < 0.0 ? 0.5 : 0.0);
    r[0] = 10.0 * (x[2] - 10.0 * theta);
    r[1] = 10.0 * (n - 1.0);
    r[2] = x[2];
    if (jac != NULL) {
        jac[0] = 100.0 * x[1] / (TWO_PI * rr);
        jac[1] = -100.0 * x[0] / (TWO_PI * rr);
        jac[2] = 10.0;
        jac[3] = 10.0 * x[0] / n;
        jac[4] = 10.0 * x[1] / n;
        jac[5] = 0.0;
        jac[6] = 0.0, jac[7] = 0.0, jac[8] = 1.0;
    }
    return BRDFFIT_OK;
}

/* #8 Bard: minimum 8.21487e-3 (and 17.4286933 with x2, x3 at infinity:
 * the spread of y about its mean). */
static brdffit_status bard(const double *x, double *r, double *jac, void *user)
{
    static const double y[15] = {0.14, 0.18, 0.22, 0.25, 0.29, 0.32, 0.35, 0.39,
                                 0.37, 0.58, 0.73, 0.96, 1.34, 2.10, 4.39};
    size_t i;
    (void)user;
    for (i = 0; i < 15; i++) {
        double u = (double)(i + 1), v = 16.0 - u, w = fmin(u, v), d = v * x[1] + w * x[2];
        r[i] = y[i] - (x[0] + u / d);
        if (jac != NULL) {
            jac[3 * i] = -1.0;
            jac[3 * i + 1] = u * v / (d * d);
            jac[3 * i + 2] = u * w / (d * d);
        }
    }
    return BRDFFIT_OK;
}

/* #15 Kowalik-Osborne: minimum 3.07505e-4 (and 1.02734e-3 at infinity). */
static brdffit_status kowalik_osborne(const double *x, double *r, double *jac, void *user)
{
    static const double y[11] = {0.1957, 0.1947, 0.1735, 0.1600, 0.0844, 0.0627,
                                 0.0456, 0.0342, 0.0323, 0.0235, 0.0246};
    static const double u[11] = {4.0,   2.0, 1.0,    0.5,    0.25,  0.167,
                                 0.125, 0.1, 0.0833, 0.0714, 0.0625};
    size_t i;
    (void)user;
    for (i = 0; i < 11; i++) {
        double nu = u[i] * (u[i] + x[1]), de = u[i] * (u[i] + x[2]) + x[3];
        r[i] = y[i] - x[0] * nu / de;
        if (jac != NULL) {
            jac[4 * i] = -nu / de;
            jac[4 * i + 1] = -x[0] * u[i] / de;
            jac[4 * i + 2] = x[0] * nu * u[i] / (de * de);
            jac[4 * i + 3] = x[0] * nu / (de * de);
        }
    }
    return BRDFFIT_OK;
}

/* --- the set: problem, published minima -------------------------------------- */

typedef struct mgh_case {
    optim_problem pb;
    double minima[2]; /* published minima (sum of squares); a second one or -1 */
} mgh_case;

static mgh_case cases[11];
static size_t n_cases;

static void add_case(const optim_problem *pb, double m0, double m1)
{
    cases[n_cases].pb = *pb;
    cases[n_cases].minima[0] = m0;
    cases[n_cases].minima[1] = m1;
    n_cases++;
}

static void build_cases(void)
{
    static const optim_problem extra[5] = {
        {"brown_badly_scaled", 2, 3, {1.0, 1.0}, brown_badly_scaled},
        {"beale", 2, 3, {1.0, 1.0}, beale},
        {"helical_valley", 3, 3, {-1.0, 0.0, 0.0}, helical_valley},
        {"bard", 3, 15, {1.0, 1.0, 1.0}, bard},
        {"kowalik_osborne", 4, 11, {0.25, 0.39, 0.415, 0.39}, kowalik_osborne},
    };
    /* MGH's minima, the local ones they list included */
    static const double m6[6][2] = {{0.0, -1.0},           {0.0, -1.0}, {48.9842536792400, 0.0},
                                    {87.9458551704, -1.0}, {0.0, -1.0}, {124.362182355, -1.0}};
    static const double m5[5][2] = {{0.0, -1.0},
                                    {0.0, -1.0},
                                    {0.0, -1.0},
                                    {8.21487730657e-3, 17.4286933333},
                                    {3.07505603849e-4, 1.02734e-3}};
    size_t n, k;
    const optim_problem *pb = optim_mgh_problems(&n);
    if (n_cases > 0) return;
    assert_int_equal(n, 6);
    for (k = 0; k < 6; k++) add_case(&pb[k], m6[k][0], m6[k][1]);
    for (k = 0; k < 5; k++) add_case(&extra[k], m5[k][0], m5[k][1]);
}

static int at_minimum(const mgh_case *c, double cost)
{
    size_t i;
    for (i = 0; i < 2; i++) {
        double m = c->minima[i];
        if (m < 0.0) continue;
        if (m == 0.0 ? cost <= 1e-10 : fabs(cost - m) <= 1e-6 * m) return 1;
    }
    return 0;
}

/* Analytic Jacobians of the added problems against central differences. */
static void test_added_jacobians(void **state)
{
    size_t k, i, j;
    (void)state;
    build_cases();
    for (k = 6; k < n_cases; k++) {
        const optim_problem *pb = &cases[k].pb;
        double x[OPTIM_MAX_PARAMS], r[OPTIM_MAX_ROWS], jac[OPTIM_MAX_ROWS * OPTIM_MAX_PARAMS];
        double rp[OPTIM_MAX_ROWS], rm[OPTIM_MAX_ROWS];
        for (j = 0; j < pb->n_params; j++) x[j] = pb->x0[j] * 1.3 + 0.1;
        assert_int_equal(pb->fn(x, r, jac, NULL), BRDFFIT_OK);
        for (j = 0; j < pb->n_params; j++) {
            double h = 1e-6 * fmax(fabs(x[j]), 1.0), keep = x[j];
            x[j] = keep + h;
            assert_int_equal(pb->fn(x, rp, NULL, NULL), BRDFFIT_OK);
            x[j] = keep - h;
            assert_int_equal(pb->fn(x, rm, NULL, NULL), BRDFFIT_OK);
            x[j] = keep;
            for (i = 0; i < pb->n_rows; i++) {
                double fd = (rp[i] - rm[i]) / (2.0 * h), an = jac[i * pb->n_params + j];
                /* truncation, and the rounding of residuals of the size of r */
                double tol = 1e-6 * (fabs(an) + 1.0) + 16.0 * DBL_EPSILON * (fabs(r[i]) + 1.0) / h;
                if (!(fabs(fd - an) <= tol))
                    print_error("%s: d r%zu / d x%zu analytic %.10g, differences %.10g\n", pb->name,
                                i, j, an, fd);
                assert_true(fabs(fd - an) <= tol);
            }
        }
    }
}

/* --- runs under a configuration ------------------------------------------------ */

typedef struct config {
    const char *label;
    double scale_memory, step_test; /* the settings' values */
} config;

static const config configs[4] = {
    {"memory 0, step 0", 0.0, 0.0},
    {"memory 1, step 0", 1.0, 0.0},
    {"memory 0, step 1", 0.0, 1.0},
    {"memory 1, step 1", 1.0, 1.0},
};

typedef struct tally {
    size_t solved, evaluations;
} tally;

static brdffit_optimizer *make(size_t p, const config *cf, const brdffit_damping *policy)
{
    brdffit_optimizer *opt = NULL;
    assert_int_equal(brdffit_optimizer_create(&opt, p, NULL, NULL), BRDFFIT_OK);
    if (policy) assert_int_equal(brdffit_optimizer_set_damping(opt, policy), BRDFFIT_OK);
    if (cf) {
        assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_SCALE_MEMORY, cf->scale_memory),
                         BRDFFIT_OK);
        assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_STEP_TEST, cf->step_test),
                         BRDFFIT_OK);
    }
    return opt;
}

/* The 54 StRD runs: LRE >= 6 on every parameter. */
static tally nist_tally(const config *cf, const brdffit_damping *policy, int verbose)
{
    size_t n, k, s, j;
    const nist_problem *ps = nist_problems(&n);
    tally t = {0, 0};
    for (k = 0; k < n; k++) {
        for (s = 0; s < 2; s++) {
            const nist_problem *p = &ps[k];
            brdffit_optimizer *opt = make(p->n_params, cf, policy);
            double x[NIST_MAX_PARAMS], lre = 15.0;
            assert_int_equal(
                brdffit_optimizer_set_residuals(opt, p->n_obs, nist_residuals, (void *)p),
                BRDFFIT_OK);
            memcpy(x, p->start[s], sizeof x);
            assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
            for (j = 0; j < p->n_params; j++) lre = fmin(lre, nist_lre(x[j], p->certified[j]));
            if (lre >= 6.0)
                t.solved++;
            else if (verbose)
                printf("    unsolved: %s start %zu, LRE %.1f, %s\n", p->name, s + 1, lre,
                       brdffit_stop_reason_string(brdffit_optimizer_stop_reason(opt)));
            t.evaluations += brdffit_optimizer_evaluations(opt);
            brdffit_optimizer_destroy(opt);
        }
    }
    return t;
}

/* The MGH cases from x0, 10 x0 and 100 x0 (33 runs). */
static tally mgh_tally(const config *cf, const brdffit_damping *policy, int verbose)
{
    static const double factor[3] = {1.0, 10.0, 100.0};
    size_t k, f, j;
    tally t = {0, 0};
    build_cases();
    for (k = 0; k < n_cases; k++) {
        for (f = 0; f < 3; f++) {
            const mgh_case *c = &cases[k];
            brdffit_optimizer *opt = make(c->pb.n_params, cf, policy);
            double x[OPTIM_MAX_PARAMS], cost;
            brdffit_status st;
            assert_int_equal(brdffit_optimizer_set_residuals(opt, c->pb.n_rows, c->pb.fn, NULL),
                             BRDFFIT_OK);
            for (j = 0; j < c->pb.n_params; j++) x[j] = factor[f] * c->pb.x0[j];
            st = brdffit_optimizer_run(opt, x);
            cost = st == BRDFFIT_OK ? brdffit_optimizer_final_cost(opt) : HUGE_VAL;
            if (at_minimum(c, cost))
                t.solved++;
            else if (verbose)
                printf("    unsolved: %s %gx, cost %.6g, %s\n", c->pb.name, factor[f], cost,
                       st == BRDFFIT_OK
                           ? brdffit_stop_reason_string(brdffit_optimizer_stop_reason(opt))
                           : "start failed");
            if (st == BRDFFIT_OK) t.evaluations += brdffit_optimizer_evaluations(opt);
            brdffit_optimizer_destroy(opt);
        }
    }
    return t;
}

/* Every configuration under every policy, as a table (docs/nist-strd.md
 * quotes it). BRDFFIT_TEST_QUICK (the valgrind runs): the default policy
 * only. The default settings keep all 54 StRD runs and 27 of the 33 MGH
 * runs (measured: the unsolved ones are Box 3-D from 10 and 100 x0,
 * stalled; Jennrich-Sampson from 100 x0, whose start overflows; Beale
 * from 10 and 100 x0 and Bard from 100 x0, at other stationary points).
 * The running maximum of the scaling loses MGH10 (Meyer) from its first
 * start; the scaled step test stops Brown's badly scaled problem early
 * (x2 = 2e-6 is invisible next to x1 = 1e6 in the norm). */
static void test_table(void **state)
{
    static const char *names[3] = {"nielsen", "marquardt", "thesis"};
    const brdffit_damping *pol[3];
    size_t c, k, n_pol = getenv("BRDFFIT_TEST_QUICK") ? 1 : 3;
    tally def_nist = {0, 0}, def_mgh = {0, 0};
    (void)state;
    pol[0] = brdffit_damping_nielsen();
    pol[1] = brdffit_damping_marquardt();
    pol[2] = brdffit_damping_thesis();
    printf("policy     settings            StRD solved/54 (evals)   MGH solved/33 (evals)\n");
    for (k = 0; k < n_pol; k++) {
        for (c = 0; c < 4; c++) {
            tally a = nist_tally(&configs[c], pol[k], k == 0);
            tally b = mgh_tally(&configs[c], pol[k], k == 0);
            printf("%-10s %-18s %8zu (%6zu)          %8zu (%6zu)\n", names[k], configs[c].label,
                   a.solved, a.evaluations, b.solved, b.evaluations);
            if (k == 0 && c == 0) def_nist = a, def_mgh = b;
        }
    }
    /* the defaults are configuration 0 under Nielsen's policy */
    {
        tally a = nist_tally(NULL, NULL, 0), b = mgh_tally(NULL, NULL, 0);
        assert_int_equal(a.solved, def_nist.solved);
        assert_int_equal(a.evaluations, def_nist.evaluations);
        assert_int_equal(b.solved, def_mgh.solved);
        assert_int_equal(b.evaluations, def_mgh.evaluations);
    }
    assert_int_equal(def_nist.solved, 54);
    assert_true(def_mgh.solved >= 27);
}

/* The two settings take 0 and 1 only, and read back what was set. */
static void test_settings(void **state)
{
    brdffit_optimizer *opt = make(2, NULL, NULL);
    double v = -1.0;
    (void)state;
    assert_int_equal(brdffit_optimizer_get(opt, BRDFFIT_OPT_SCALE_MEMORY, &v), BRDFFIT_OK);
    assert_true(v == 0.0);
    assert_int_equal(brdffit_optimizer_get(opt, BRDFFIT_OPT_STEP_TEST, &v), BRDFFIT_OK);
    assert_true(v == 0.0);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_SCALE_MEMORY, 1.0), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_STEP_TEST, 1.0), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_get(opt, BRDFFIT_OPT_SCALE_MEMORY, &v), BRDFFIT_OK);
    assert_true(v == 1.0);
    assert_int_equal(brdffit_optimizer_get(opt, BRDFFIT_OPT_STEP_TEST, &v), BRDFFIT_OK);
    assert_true(v == 1.0);
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_SCALE_MEMORY, 2.0),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_non_null(strstr(brdffit_optimizer_message(opt), "scale memory"));
    assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_STEP_TEST, 0.5),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_non_null(strstr(brdffit_optimizer_message(opt), "step test"));
    assert_int_equal(brdffit_optimizer_get(opt, BRDFFIT_OPT_STEP_TEST, &v), BRDFFIT_OK);
    assert_true(v == 1.0); /* a refused value changes nothing */
    brdffit_optimizer_destroy(opt);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_added_jacobians),
        cmocka_unit_test(test_settings),
        cmocka_unit_test(test_table),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
