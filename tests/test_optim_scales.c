/* What a run does must not depend on the units or the origin of the
 * parameters. Every NIST StRD problem from both certified starts is run
 * in its own coordinates and again in two changed ones whose certified
 * minimum is known exactly from NIST's (optim_changed in
 * optim_problems.h):
 *
 * - mixed magnitudes: the first parameter in units that make its
 *   certified value 1e6 (the others keep theirs, some below 1e-3). The
 *   scaling D takes each entry from its own column only, and the step
 *   test compares each parameter with its own magnitude, so these runs
 *   take the steps of the runs in their own coordinates up to rounding
 *   (which decides how many steps the end takes, where the cost no longer
 *   resolves them): every one must converge at LRE >= 6. (A floor of D relative to the
 *   largest entry compared the columns in the parameters' units and
 *   damped the others by the large one's: six runs failed, three of them
 *   reported converged at LRE 0; a step test on the norm of the whole
 *   vector stopped three more after 2 to 10 iterations.)
 * - through zero: every parameter shifted by the midpoint of its start
 *   and its certified value, so that each one changes sign on the way.
 *   The shift leaves the Jacobian as it is; only relative tests and the
 *   representable digits change. Each run must reach LRE >= 6 in the
 *   changed coordinates and report convergence, except the known gaps:
 *   Gauss3/1, ENSO/2 and Bennett5/1 end where the cost no longer resolves
 *   a step (the next step promises 1e-15 of the cost), which is LRE >= 6
 *   in the problem's own coordinates but not against the much smaller
 *   shifted certified values (Gauss3's b6, 73.7 in its own, is -0.047
 *   there); MGH10 from start 1 runs through b1 ~ 1e-45 on its way, which
 *   b1 = x1 + 1.0028 cannot represent, and reaches its iteration limit.
 *
 * The MGH set in mixed magnitudes (the first parameter's start at 1e6)
 * must solve as many runs as bench_certified's best peer there.
 *
 * The table printed is docs/nist-strd.md's ("Changed coordinates"). */
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <setjmp.h>

#include <cmocka.h>

#include "nist_problems.h"
#include "optim_problems.h"

#define MAX_OBS 256
#define N_RUNS 54

/* The frames of the StRD runs. */
enum { OWN, MIXED, ZERO, N_FRAMES };

typedef struct outcome {
    size_t iterations;
    int converged;
    double lre, own_lre; /* in the run's coordinates, and mapped back into the problem's */
} outcome;

static outcome results[N_FRAMES][N_RUNS];

static void make(const nist_problem *p, size_t s, int frame, optim_changed *c)
{
    optim_changed_init(c, nist_residuals, (void *)p, p->n_obs, p->n_params);
    if (frame == MIXED) optim_changed_mixed(c, p->certified[0]);
    if (frame == ZERO) optim_changed_through_zero(c, p->start[s], p->certified);
}

/* Run problem p from start s in frame's coordinates. */
static outcome run_changed(const nist_problem *p, size_t s, int frame)
{
    brdffit_optimizer *opt = NULL;
    optim_changed c;
    double x[NIST_MAX_PARAMS], b[NIST_MAX_PARAMS], cert[NIST_MAX_PARAMS];
    outcome o = {0, 0, 15.0, 15.0};
    size_t j;
    assert_true(p->n_obs <= MAX_OBS);
    make(p, s, frame, &c);
    optim_changed_from_problem(&c, p->start[s], x);
    optim_changed_from_problem(&c, p->certified, cert);
    assert_int_equal(brdffit_optimizer_create(&opt, p->n_params, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set_residuals(opt, p->n_obs, optim_changed_fn, &c),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
    o.converged = brdffit_optimizer_converged(opt);
    o.iterations = brdffit_optimizer_iterations(opt);
    optim_changed_to_problem(&c, x, b);
    for (j = 0; j < p->n_params; j++) {
        o.lre = fmin(o.lre, nist_lre(x[j], cert[j]));
        o.own_lre = fmin(o.own_lre, nist_lre(b[j], p->certified[j]));
    }
    brdffit_optimizer_destroy(opt);
    return o;
}

/* Every run of frame; the runs neither converged at LRE >= 6 nor listed
 * in gaps fail the test. Returns the number converged at LRE >= 6. */
static size_t run_frame(int frame, const char *gaps)
{
    size_t n, k, s, solved = 0, listed = 0;
    const nist_problem *ps = nist_problems(&n);
    assert_int_equal(2 * n, N_RUNS);
    for (k = 0; k < n; k++)
        for (s = 0; s < 2; s++) {
            outcome o = run_changed(&ps[k], s, frame);
            char key[32];
            results[frame][2 * k + s] = o;
            snprintf(key, sizeof key, "%s/%zu ", ps[k].name, s + 1);
            if (o.lre >= 6.0 && o.converged)
                solved++;
            else if (strstr(gaps, key) != NULL)
                listed++;
            else
                print_error("%s start %zu: LRE %.1f, converged %d\n", ps[k].name, s + 1, o.lre,
                            o.converged);
        }
    printf("frame %d: %zu of 54 runs converged at LRE >= 6, %zu known gaps\n", frame, solved,
           listed);
    assert_int_equal(solved + listed, N_RUNS);
    return solved;
}

static void test_own_coordinates(void **state)
{
    (void)state;
    assert_int_equal(run_frame(OWN, ""), N_RUNS);
}

static void test_mixed_magnitudes(void **state)
{
    (void)state;
    assert_int_equal(run_frame(MIXED, ""), N_RUNS);
}

static void test_through_zero(void **state)
{
    size_t i;
    (void)state;
    assert_int_equal(run_frame(ZERO, "Gauss3/1 ENSO/2 MGH10/1 Bennett5/1 "), 50);
    /* the runs reported converged short of LRE 6 in the shifted
     * coordinates are at the certified minimum in the problem's own */
    for (i = 0; i < N_RUNS; i++)
        if (results[ZERO][i].converged) assert_true(results[ZERO][i].own_lre >= 6.0);
}

/* The table of docs/nist-strd.md. */
static void test_print_table(void **state)
{
    static const char *yes[2] = {"no", "yes"};
    size_t n, k, s;
    const nist_problem *ps = nist_problems(&n);
    (void)state;
    printf("| problem | start | own: iterations | LRE | mixed: iterations | LRE | converged | "
           "through zero: iterations | LRE | converged |\n|---|---|---|---|---|---|---|---|---|---|"
           "\n");
    for (k = 0; k < n; k++)
        for (s = 0; s < 2; s++) {
            const outcome *a = &results[OWN][2 * k + s], *b = &results[MIXED][2 * k + s],
                          *c = &results[ZERO][2 * k + s];
            printf("| %s | %zu | %zu | %.1f | %zu | %.1f | %s | %zu | %.1f | %s |\n", ps[k].name,
                   s + 1, a->iterations, a->lre, b->iterations, b->lre, yes[b->converged],
                   c->iterations, c->lre, yes[c->converged]);
        }
}

/* The 105 MGH runs with the first parameter's start at 1e6, judged by the
 * cost (which the change leaves as it is). */
static void test_mgh_mixed(void **state)
{
    static const double factor[3] = {1.0, 10.0, 100.0};
    size_t n, k, f, j, solved = 0;
    const optim_problem *set = optim_mgh_set(&n);
    (void)state;
    for (k = 0; k < n; k++)
        for (f = 0; f < 3; f++) {
            const optim_problem *pb = &set[k];
            brdffit_optimizer *opt = NULL;
            optim_changed c;
            double b[OPTIM_MAX_PARAMS], x[OPTIM_MAX_PARAMS];
            brdffit_status st;
            for (j = 0; j < pb->n_params; j++) b[j] = factor[f] * pb->x0[j];
            optim_changed_init(&c, pb->fn, (void *)pb, pb->n_rows, pb->n_params);
            optim_changed_mixed(&c, b[0]);
            optim_changed_from_problem(&c, b, x);
            assert_int_equal(brdffit_optimizer_create(&opt, pb->n_params, NULL, NULL), BRDFFIT_OK);
            assert_int_equal(brdffit_optimizer_set_residuals(opt, pb->n_rows, optim_changed_fn, &c),
                             BRDFFIT_OK);
            st = brdffit_optimizer_run(opt, x);
            if (st == BRDFFIT_OK && optim_mgh_solved(pb, brdffit_optimizer_final_cost(opt)))
                solved++;
            brdffit_optimizer_destroy(opt);
        }
    printf("MGH, first parameter at 1e6: %zu of 105 runs solved\n", solved);
    /* 87 for MINPACK, the best peer (bench_certified); 91 in the
     * problems' own coordinates, where Chebyquad from 10 and 100 x0 take
     * thousands of iterations that rounding decides */
    assert_true(solved >= 89);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_own_coordinates), cmocka_unit_test(test_mixed_magnitudes),
        cmocka_unit_test(test_through_zero),    cmocka_unit_test(test_print_table),
        cmocka_unit_test(test_mgh_mixed),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
