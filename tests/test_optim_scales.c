/* What a run does must not depend on the units or the origin of the
 * parameters. Every NIST StRD problem from both certified starts is run
 * again in two changed coordinates whose certified minimum is known
 * exactly from NIST's:
 *
 * - mixed magnitudes: the first parameter is multiplied so that its
 *   certified value is 1e6 (the others keep theirs, some below 1e-3). A
 *   step test on the norm of the whole vector (|step| <= xtol |x|) stops
 *   such runs while the small parameters still move (measured: Kirby2
 *   from start 2 after 2 iterations, Hahn1 from start 1 and Nelson from
 *   start 2 after 7 and 10, all reported converged at LRE 0 to 1);
 * - through zero: every parameter is shifted by the midpoint of its start
 *   and its certified value, so that each one changes sign on the way.
 *
 * Each run must reach LRE >= 6 in the changed coordinates and report
 * convergence, except the known gaps listed with each case (docs/
 * nist-strd.md, "Changed coordinates"): runs the optimizer of this
 * version gets wrong in those coordinates. Most of them are reported as
 * converged far from the minimum, so the lists say what a caller cannot
 * yet trust; a run that leaves a list is a fix, and the list shrinks.  */
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <setjmp.h>

#include <cmocka.h>

#include "nist_problems.h"

#define MAX_OBS 256

typedef struct changed {
    const nist_problem *p;
    double scale[NIST_MAX_PARAMS], shift[NIST_MAX_PARAMS]; /* b = scale * c + shift */
} changed;

static void to_original(const changed *c, const double *x, double *b)
{
    size_t j;
    for (j = 0; j < c->p->n_params; j++) b[j] = c->scale[j] * x[j] + c->shift[j];
}

static brdffit_status changed_residuals(const double *x, double *r, double *jac, void *user)
{
    const changed *c = user;
    size_t i, j, np = c->p->n_params;
    double b[NIST_MAX_PARAMS];
    brdffit_status st;
    to_original(c, x, b);
    st = nist_residuals(b, r, jac, (void *)c->p);
    if (st != BRDFFIT_OK || jac == NULL) return st;
    for (i = 0; i < c->p->n_obs; i++)
        for (j = 0; j < np; j++) jac[i * np + j] *= c->scale[j];
    return BRDFFIT_OK;
}

/* Run from start s in the changed coordinates; returns the worst LRE
 * against the certified values mapped into them. */
static double run_changed(const changed *c, size_t s, int *converged, size_t *iterations,
                          brdffit_stop_reason *stop)
{
    const nist_problem *p = c->p;
    brdffit_optimizer *opt = NULL;
    double x[NIST_MAX_PARAMS], lre = 15.0;
    size_t j;
    assert_true(p->n_obs <= MAX_OBS);
    for (j = 0; j < p->n_params; j++) x[j] = (p->start[s][j] - c->shift[j]) / c->scale[j];
    assert_int_equal(brdffit_optimizer_create(&opt, p->n_params, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set_residuals(opt, p->n_obs, changed_residuals, (void *)c),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
    *converged = brdffit_optimizer_converged(opt);
    *stop = brdffit_optimizer_stop_reason(opt);
    *iterations = brdffit_optimizer_iterations(opt);
    for (j = 0; j < p->n_params; j++) {
        double cert = (p->certified[j] - c->shift[j]) / c->scale[j];
        lre = fmin(lre, nist_lre(x[j], cert));
    }
    brdffit_optimizer_destroy(opt);
    return lre;
}

typedef void (*make_fn)(const nist_problem *p, size_t s, changed *c);

static void make_mixed(const nist_problem *p, size_t s, changed *c)
{
    size_t j;
    (void)s;
    c->p = p;
    for (j = 0; j < p->n_params; j++) {
        c->scale[j] = 1.0;
        c->shift[j] = 0.0;
    }
    c->scale[0] = fabs(p->certified[0]) / 1e6;
}

static void make_through_zero(const nist_problem *p, size_t s, changed *c)
{
    size_t j;
    c->p = p;
    for (j = 0; j < p->n_params; j++) {
        c->scale[j] = 1.0;
        c->shift[j] = 0.5 * (p->start[s][j] + p->certified[j]);
    }
}

static void run_all(make_fn make, const char *label, const char *gaps)
{
    size_t n, k, s, solved = 0, listed = 0;
    const nist_problem *ps = nist_problems(&n);
    printf("NIST StRD, %s: problem start iterations converged LRE\n", label);
    for (k = 0; k < n; k++)
        for (s = 0; s < 2; s++) {
            changed c;
            char key[32];
            int converged;
            size_t iterations;
            brdffit_stop_reason stop;
            double lre;
            make(&ps[k], s, &c);
            lre = run_changed(&c, s, &converged, &iterations, &stop);
            printf("  %-9s %zu %5zu %d %5.1f %s\n", ps[k].name, s + 1, iterations, converged, lre,
                   brdffit_stop_reason_string(stop));
            snprintf(key, sizeof key, "%s/%zu ", ps[k].name, s + 1);
            if (lre >= 6.0 && converged)
                solved++;
            else if (strstr(gaps, key) != NULL)
                listed++;
            else
                print_error("%s start %zu: LRE %.1f, converged %d\n", ps[k].name, s + 1, lre,
                            converged);
        }
    printf("  %zu of 54 runs converged at LRE >= 6, %zu known gaps\n", solved, listed);
    assert_int_equal(solved + listed, 54);
}

static void test_mixed_magnitudes(void **state)
{
    (void)state;
    /* The floor of the scaling D (DIAG_FLOOR times the largest diagonal of
     * J^T J, docs/optimizer.md) compares columns in the parameters' units,
     * so the large first parameter raises the damping of the others. */
    run_all(make_mixed, "first parameter at 1e6",
            "Lanczos3/1 Hahn1/2 Nelson/1 Lanczos1/1 Lanczos2/1 Roszman1/1 ");
}

static void test_through_zero(void **state)
{
    (void)state;
    /* The step test is relative to |x_j|, so it depends on the origin:
     * slow runs stop on a small damped step (MGH10 from start 1, reported
     * stalled), others a digit or two early (Gauss3/1, ENSO/2, Bennett5/1
     * at LRE 5.1 to 5.7). */
    run_all(make_through_zero, "every parameter through zero",
            "Gauss3/1 ENSO/2 MGH10/1 Bennett5/1 ");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mixed_magnitudes),
        cmocka_unit_test(test_through_zero),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
