/* The 27 NIST StRD nonlinear regression problems from both certified
 * starts (54 runs) through the optimizer, for every built-in damping
 * policy. First the data and the models are checked against NIST's
 * certified residual sums of squares and the analytic Jacobians against
 * finite differences; then every run is scored by the log relative error
 * (LRE) of its worst parameter against the certified values. */
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <setjmp.h>

#include <cmocka.h>

#include "core/linalg.h"
#include "nist_problems.h"

#define MAX_OBS 256

static double rss_at(const nist_problem *p, const double *b)
{
    double r[MAX_OBS], s = 0.0;
    size_t i;
    assert_true(p->n_obs <= MAX_OBS);
    assert_int_equal(nist_residuals(b, r, NULL, (void *)p), BRDFFIT_OK);
    for (i = 0; i < p->n_obs; i++) s += r[i] * r[i];
    return s;
}

/* The residual sum of squares at the certified parameters is the certified
 * one to 1e-9. The parameters are published to 11 digits, so the residuals
 * at them carry an error of about 1e-11 of the response; the comparison
 * allows n (1e-10 max |y|)^2 besides, which matters only for Lanczos1,
 * whose certified RSS (1.4e-25) is below that. */
static void test_data_match_certified_rss(void **state)
{
    size_t n, k, i;
    const nist_problem *ps = nist_problems(&n);
    (void)state;
    assert_int_equal(n, 27);
    for (k = 0; k < n; k++) {
        const nist_problem *p = &ps[k];
        double rss = rss_at(p, p->certified), ymax = 0.0, x[2], floor_abs;
        for (i = 0; i < p->n_obs; i++) ymax = fmax(ymax, fabs(nist_response(p, i, x)));
        floor_abs = (double)p->n_obs * (1e-10 * ymax) * (1e-10 * ymax);
        if (!(fabs(rss - p->certified_rss) <= 1e-9 * p->certified_rss + floor_abs))
            print_error("%s: RSS %.12e, certified %.12e\n", p->name, rss, p->certified_rss);
        assert_true(fabs(rss - p->certified_rss) <= 1e-9 * p->certified_rss + floor_abs);
    }
}

/* Analytic Jacobian against central differences at one point. */
static void check_jacobian(const nist_problem *p, const double *b)
{
    double r[MAX_OBS], jac[MAX_OBS * NIST_MAX_PARAMS], rp[MAX_OBS], rm[MAX_OBS];
    double bp[NIST_MAX_PARAMS];
    size_t i, j, np = p->n_params;
    assert_int_equal(nist_residuals(b, r, jac, (void *)p), BRDFFIT_OK);
    for (j = 0; j < np; j++) {
        double h = 1e-6 * fmax(fabs(b[j]), 1e-6), colmax = 0.0;
        memcpy(bp, b, np * sizeof *bp);
        bp[j] = b[j] + h;
        assert_int_equal(nist_residuals(bp, rp, NULL, (void *)p), BRDFFIT_OK);
        bp[j] = b[j] - h;
        assert_int_equal(nist_residuals(bp, rm, NULL, (void *)p), BRDFFIT_OK);
        for (i = 0; i < p->n_obs; i++) colmax = fmax(colmax, fabs(jac[i * np + j]));
        for (i = 0; i < p->n_obs; i++) {
            double fd = (rp[i] - rm[i]) / (2.0 * h), an = jac[i * np + j], x[2];
            /* truncation, and the rounding of residuals of the size of
             * the response and the model */
            double y = fabs(nist_response(p, i, x)), tol;
            tol = 1e-6 * (fabs(an) + colmax) + 16.0 * DBL_EPSILON * (fabs(r[i]) + 2.0 * y) / h;
            if (!(fabs(fd - an) <= tol))
                print_error("%s: d r%zu / d b%zu analytic %.10g, differences %.10g\n", p->name, i,
                            j + 1, an, fd);
            assert_true(fabs(fd - an) <= tol);
        }
    }
}

static void test_jacobians_match_differences(void **state)
{
    size_t n, k;
    const nist_problem *ps = nist_problems(&n);
    (void)state;
    for (k = 0; k < n; k++) {
        check_jacobian(&ps[k], ps[k].start[0]);
        check_jacobian(&ps[k], ps[k].start[1]);
        check_jacobian(&ps[k], ps[k].certified);
    }
}

typedef struct nist_run {
    brdffit_stop_reason stop;
    int converged;
    size_t iterations, evaluations;
    double lre, cost;
} nist_run;

/* One run with the defaults except the damping policy (NULL: default). */
static void run_one(const nist_problem *p, size_t start, const brdffit_damping *policy,
                    nist_run *out)
{
    brdffit_optimizer *opt = NULL;
    double x[NIST_MAX_PARAMS];
    size_t j;
    assert_int_equal(brdffit_optimizer_create(&opt, p->n_params, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set_residuals(opt, p->n_obs, nist_residuals, (void *)p),
                     BRDFFIT_OK);
    if (policy) assert_int_equal(brdffit_optimizer_set_damping(opt, policy), BRDFFIT_OK);
    memcpy(x, p->start[start], sizeof x);
    assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
    out->stop = brdffit_optimizer_stop_reason(opt);
    out->converged = brdffit_optimizer_converged(opt);
    out->iterations = brdffit_optimizer_iterations(opt);
    out->evaluations = brdffit_optimizer_evaluations(opt);
    out->cost = brdffit_optimizer_final_cost(opt);
    assert_true(out->cost == rss_at(p, x));
    /* a restarted run reports the attempt it returns */
    assert_int_equal(brdffit_optimizer_history(opt, NULL, NULL), out->iterations + 1);
    assert_true(brdffit_optimizer_last_improvement(opt) <= out->iterations);
    out->lre = 15.0;
    for (j = 0; j < p->n_params; j++) out->lre = fmin(out->lre, nist_lre(x[j], p->certified[j]));
    brdffit_optimizer_destroy(opt);
}

/* Every run of a policy, printed as a table; returns how many reached
 * LRE >= 6. A run reported as converged must end at the certified minimum
 * (its RSS to 1e-6), except the runs listed in allowed (name and start). */
static size_t run_policy(const brdffit_damping *policy, const char *label, const char *allowed)
{
    size_t n, k, s, solved = 0;
    const nist_problem *ps = nist_problems(&n);
    printf("NIST StRD, policy %s: problem start iterations evaluations stop LRE\n", label);
    for (k = 0; k < n; k++) {
        for (s = 0; s < 2; s++) {
            const nist_problem *p = &ps[k];
            char key[32];
            nist_run r;
            run_one(p, s, policy, &r);
            printf("  %-9s %zu %5zu %5zu %-26s %5.1f\n", p->name, s + 1, r.iterations,
                   r.evaluations, brdffit_stop_reason_string(r.stop), r.lre);
            if (r.lre >= 6.0) solved++;
            snprintf(key, sizeof key, "%s/%zu ", p->name, s + 1);
            if (r.converged && strstr(allowed, key) == NULL) {
                if (!(fabs(r.cost - p->certified_rss) <= 1e-6 * p->certified_rss + 1e-20))
                    print_error("%s start %zu: reported converged at RSS %.10e, certified %.10e\n",
                                p->name, s + 1, r.cost, p->certified_rss);
                assert_true(fabs(r.cost - p->certified_rss) <= 1e-6 * p->certified_rss + 1e-20);
            }
        }
    }
    printf("  %zu of 54 runs at LRE >= 6\n", solved);
    return solved;
}

/* The default (Nielsen's policy and the default settings) solves all 54. */
static void test_default_solves_all(void **state)
{
    (void)state;
    assert_int_equal(run_policy(NULL, "default (nielsen)", ""), 54);
}

/* Marquardt's policy misses only Meyer (MGH10) from its far start, at the
 * iteration limit, which is not reported as converged. */
static void test_marquardt(void **state)
{
    (void)state;
    assert_true(run_policy(brdffit_damping_marquardt(), "marquardt", "") >= 53);
}

/* The thesis's policy (lambda kept in [1e-4, 1]) is slow on the
 * ill-conditioned problems and ends many of them at the iteration limit.
 * From MGH17's first start it ends where the two exponentials have merged
 * (RSS 8.0e-5 against 5.5e-5): J^T J is singular there but no column
 * vanished, so the stop is not recognised as a stall. */
static void test_thesis(void **state)
{
    (void)state;
    assert_true(run_policy(brdffit_damping_thesis(), "thesis", "MGH17/1 ") >= 40);
}

/* The plateaus: MGH17 from start 1 (an exponential's rate runs away and
 * zeroes two columns) and BoxBOD from start 1 (the rate runs to 114.8,
 * the model becomes the constant b1). With the scaling of the current
 * point (SCALE_MEMORY 0; the default's running maximum does not run onto
 * them) and without the restart (RESTART_BOUND turned off) the run ends
 * there, and says it stalled. */
static void test_plateaus_reported_stalled(void **state)
{
    static const char *names[2] = {"MGH17", "BoxBOD"};
    size_t n, k, i;
    const nist_problem *ps = nist_problems(&n);
    (void)state;
    for (i = 0; i < 2; i++) {
        for (k = 0; k < n && strcmp(ps[k].name, names[i]) != 0; k++) continue;
        assert_true(k < n);
        {
            const nist_problem *p = &ps[k];
            brdffit_optimizer *opt = NULL;
            double x[NIST_MAX_PARAMS];
            assert_int_equal(brdffit_optimizer_create(&opt, p->n_params, NULL, NULL), BRDFFIT_OK);
            assert_int_equal(
                brdffit_optimizer_set_residuals(opt, p->n_obs, nist_residuals, (void *)p),
                BRDFFIT_OK);
            assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_RESTART_BOUND, 1e300),
                             BRDFFIT_OK);
            assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_SCALE_MEMORY, 0.0), BRDFFIT_OK);
            memcpy(x, p->start[0], sizeof x);
            assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
            assert_true(brdffit_optimizer_final_cost(opt) > 1.5 * p->certified_rss);
            assert_int_equal(brdffit_optimizer_stop_reason(opt), BRDFFIT_STOP_STALLED);
            assert_false(brdffit_optimizer_converged(opt));
            brdffit_optimizer_destroy(opt);
        }
    }
}

/* Where two of Lanczos1's exponentials merge (b4 = b6, reached in mixed
 * units when the scaling's floor compared the columns in the parameters'
 * units): the fit of two exponentials, cost 4.29e-6 against the
 * certified 1.4e-25. It is a genuine local minimum, not a saddle the
 * stationarity test misses: the gradient vanishes, and the Hessian of the
 * cost (differences of the analytic gradient, scaled to unit diagonal of
 * J^T J) has no negative eigenvalue, one zero for the exact invariance
 * b3 + b5 = const. So the run is reported converged, as Jennrich-Sampson's
 * minimum (two merged exponentials too), and the standard errors report
 * the four parameters of the merged terms as undetermined. */
static void test_merged_exponentials(void **state)
{
    static const double b0[6] = {0.4440129982, 1.872465649,  3.506087652,
                                 4.639643155,  -1.437306977, 4.639643178};
    size_t n, k, i, j, m;
    const nist_problem *ps = nist_problems(&n);
    const nist_problem *p;
    brdffit_optimizer *opt = NULL;
    double x[6], se[6], h[36], w[6], v[36], sc[6], r[MAX_OBS], jac[MAX_OBS * 6];
    (void)state;
    for (k = 0; k < n && strcmp(ps[k].name, "Lanczos1") != 0; k++) continue;
    assert_true(k < n);
    p = &ps[k];
    m = p->n_obs;
    memcpy(x, b0, sizeof x);
    assert_int_equal(brdffit_optimizer_create(&opt, 6, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set_residuals(opt, m, nist_residuals, (void *)p),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
    assert_true(brdffit_optimizer_converged(opt));
    assert_true(fabs(brdffit_optimizer_final_cost(opt) - 4.2906e-6) <= 1e-3 * 4.2906e-6);
    assert_int_equal(brdffit_optimizer_std_errors(opt, se), BRDFFIT_OK);
    for (j = 0; j < 6; j++) assert_true(j < 2 ? isfinite(se[j]) : se[j] == HUGE_VAL);
    brdffit_optimizer_destroy(opt);
    /* the Hessian of cost / 2 at the point reached */
    assert_int_equal(nist_residuals(x, r, jac, (void *)p), BRDFFIT_OK);
    for (j = 0; j < 6; j++) {
        double a = 0.0;
        for (i = 0; i < m; i++) a += jac[i * 6 + j] * jac[i * 6 + j];
        sc[j] = 1.0 / sqrt(a);
    }
    for (j = 0; j < 6; j++) {
        double xp[6], xm[6], gp[6], gm[6], step = 1e-6 * fabs(x[j]);
        memcpy(xp, x, sizeof xp);
        memcpy(xm, x, sizeof xm);
        xp[j] += step;
        xm[j] -= step;
        for (k = 0; k < 2; k++) {
            double *g = k ? gm : gp;
            size_t l;
            assert_int_equal(nist_residuals(k ? xm : xp, r, jac, (void *)p), BRDFFIT_OK);
            for (l = 0; l < 6; l++)
                for (g[l] = 0.0, i = 0; i < m; i++) g[l] += jac[i * 6 + l] * r[i];
        }
        for (i = 0; i < 6; i++) h[i * 6 + j] = (gp[i] - gm[i]) / (2.0 * step) * sc[i] * sc[j];
    }
    for (i = 0; i < 6; i++)
        for (j = 0; j < i; j++) h[i * 6 + j] = h[j * 6 + i] = 0.5 * (h[i * 6 + j] + h[j * 6 + i]);
    bf_sym_eigen(h, 6, w, v);
    for (j = 0; j < 6; j++) {
        printf("merged exponentials: Hessian eigenvalue %.3e\n", w[j]);
        assert_true(w[j] > -1e-9);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_data_match_certified_rss),
        cmocka_unit_test(test_jacobians_match_differences),
        cmocka_unit_test(test_plateaus_reported_stalled),
        cmocka_unit_test(test_merged_exponentials),
        cmocka_unit_test(test_default_solves_all),
        cmocka_unit_test(test_marquardt),
        cmocka_unit_test(test_thesis),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
