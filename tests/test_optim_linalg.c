/* The internal dense linear algebra (lib/core/linalg.h) that the optimizer
 * and the fit code share: Cholesky with its conditioning check, the Jacobi
 * eigen-solver, the pseudo-inverse and the condition number, against
 * matrices with known answers. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/linalg.h"
#include "optim_problems.h"
#include "test_support.h"

static void matvec(const double *a, size_t n, const double *x, double *y)
{
    size_t i, j;
    for (i = 0; i < n; i++) {
        y[i] = 0.0;
        for (j = 0; j < n; j++) y[i] += a[i * n + j] * x[j];
    }
}

static void test_cholesky_solves(void **state)
{
    const double a[9] = {4.0, 2.0, 0.4, 2.0, 5.0, 1.0, 0.4, 1.0, 3.0};
    const double b[3] = {1.0, -2.0, 0.5};
    double l[9], x[3], y[3];
    size_t i, j, k;
    (void)state;
    memcpy(l, a, sizeof l);
    assert_true(bf_cholesky(l, 3, BF_LINALG_RTOL));
    /* L L^T reproduces A (lower triangle of l holds L) */
    for (i = 0; i < 3; i++)
        for (j = 0; j <= i; j++) {
            double s = 0.0;
            for (k = 0; k <= j; k++) s += l[i * 3 + k] * l[j * 3 + k];
            assert_close(s, a[i * 3 + j], 1e-15);
        }
    memcpy(x, b, sizeof x);
    bf_cholesky_solve(l, 3, x);
    matvec(a, 3, x, y);
    for (i = 0; i < 3; i++) assert_close(y[i], b[i], 1e-14);
    assert_true(bf_cholesky(l, 0, BF_LINALG_RTOL));
}

static void test_cholesky_rejects(void **state)
{
    double indefinite[4] = {1.0, 2.0, 2.0, 1.0};
    double with_nan[4] = {1.0, 0.0, 0.0, NAN};
    double ill[4] = {1.0, 0.0, 0.0, 1e-15};
    double ill2[4] = {1.0, 0.0, 0.0, 1e-15};
    double zero[4] = {0.0, 0.0, 0.0, 0.0};
    (void)state;
    assert_false(bf_cholesky(indefinite, 2, BF_LINALG_RTOL));
    assert_false(bf_cholesky(with_nan, 2, BF_LINALG_RTOL));
    assert_false(bf_cholesky(zero, 2, BF_LINALG_RTOL));
    /* positive definite, but the pivot ratio 1e-15 is below 1e-14 */
    assert_false(bf_cholesky(ill, 2, BF_LINALG_RTOL));
    assert_true(bf_cholesky(ill2, 2, 1e-16));
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void check_decomposition(const double *a, size_t n, const double *w, const double *v)
{
    size_t i, j, k;
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++) {
            double vtv = 0.0, rec = 0.0;
            for (k = 0; k < n; k++) {
                vtv += v[k * n + i] * v[k * n + j];
                rec += v[i * n + k] * w[k] * v[j * n + k];
            }
            assert_close(vtv, i == j ? 1.0 : 0.0, 1e-14);
            assert_close(rec, a[i * n + j], 1e-13);
        }
}

static void test_jacobi_known_eigenvalues(void **state)
{
    const double a[9] = {2.0, -1.0, 0.0, -1.0, 2.0, -1.0, 0.0, -1.0, 2.0};
    double m[9], w[3], v[9], w2[3];
    (void)state;
    memcpy(m, a, sizeof m);
    assert_true(bf_sym_eigen(m, 3, w, v));
    check_decomposition(a, 3, w, v);
    qsort(w, 3, sizeof *w, cmp_double);
    assert_close(w[0], 2.0 - sqrt(2.0), 1e-15);
    assert_close(w[1], 2.0, 1e-15);
    assert_close(w[2], 2.0 + sqrt(2.0), 1e-15);
    /* eigenvalues only */
    memcpy(m, a, sizeof m);
    assert_true(bf_sym_eigen(m, 3, w2, NULL));
    qsort(w2, 3, sizeof *w2, cmp_double);
    assert_close(w2[0], w[0], 1e-15);
    assert_close(w2[2], w[2], 1e-15);
}

static void test_jacobi_random_symmetric(void **state)
{
    enum { N = 12 };
    double a[N * N], m[N * N], w[N], v[N * N], trace = 0.0, sum = 0.0;
    unsigned long long s = 2024;
    size_t i, j;
    (void)state;
    for (i = 0; i < N; i++)
        for (j = 0; j <= i; j++) a[i * N + j] = a[j * N + i] = optim_uniform(&s) - 0.5;
    memcpy(m, a, sizeof m);
    assert_true(bf_sym_eigen(m, N, w, v));
    check_decomposition(a, N, w, v);
    for (i = 0; i < N; i++) {
        trace += a[i * N + i];
        sum += w[i];
    }
    assert_close(sum, trace, 1e-13);
}

static void test_pinv_rank_one(void **state)
{
    /* A = u u^T, u = (1, 2, 3): A^+ = u u^T / |u|^4 */
    const double u[3] = {1.0, 2.0, 3.0};
    double a[9], m[9], w[3], v[9], p[9], b[3], x[3], tmp[3];
    size_t i, j;
    (void)state;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) a[i * 3 + j] = u[i] * u[j];
    memcpy(m, a, sizeof m);
    bf_sym_eigen(m, 3, w, v);
    assert_true(bf_eigen_pinv(w, v, 3, BF_LINALG_RTOL, p, NULL));
    for (i = 0; i < 9; i++) assert_close(p[i], a[i] / 196.0, 1e-14);
    /* pseudo-inverse solve, in place: A^+ b = u (u.b) / |u|^4 */
    b[0] = 1.0;
    b[1] = -1.0;
    b[2] = 2.0;
    memcpy(x, b, sizeof x);
    bf_eigen_pinv_solve(w, v, 3, BF_LINALG_RTOL, x, x, tmp);
    for (i = 0; i < 3; i++) assert_close(x[i], u[i] * 5.0 / 196.0, 1e-14);
    assert_true(bf_eigen_condition(w, 3) > 1e14); /* rank 1: zero eigenvalues up to rounding */
}

static void test_condition_values(void **state)
{
    const double w[3] = {1.0, 4.0, 2.0}, singular[2] = {0.0, 1.0}, negative[2] = {-1e-17, 1.0};
    (void)state;
    assert_close(bf_eigen_condition(w, 3), 4.0, 1e-15);
    assert_true(bf_eigen_condition(singular, 2) == HUGE_VAL);
    assert_true(bf_eigen_condition(negative, 2) == HUGE_VAL);
    assert_true(bf_eigen_condition(w, 0) == 1.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cholesky_solves),
        cmocka_unit_test(test_cholesky_rejects),
        cmocka_unit_test(test_jacobi_known_eigenvalues),
        cmocka_unit_test(test_jacobi_random_symmetric),
        cmocka_unit_test(test_pinv_rank_one),
        cmocka_unit_test(test_condition_values),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
