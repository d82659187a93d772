/* Dense symmetric linear algebra shared by the optimizer and the fit code:
 * Cholesky with a conditioning check, a cyclic Jacobi eigen-solver, and
 * pseudo-inverses built from the eigen-decomposition. All matrices are
 * n x n, row-major, contiguous (row stride n). Nothing here allocates. */
#ifndef BRDFFIT_CORE_LINALG_H
#define BRDFFIT_CORE_LINALG_H

#include <stddef.h>

/* A stop request for the O(n^3) routines below: fn(ctx) != 0 asks them to
 * give up (they look at it about every n^2 operations). NULL: never. */
typedef struct bf_stop {
    int (*fn)(const void *ctx);
    const void *ctx;
} bf_stop;

/* Sum of a[k] * b[k] with four independent partial sums in a fixed order,
 * so the compiler can keep the loop in vector registers without
 * reassociating anything: the same result on every machine and clone. */
double bf_dot(const double *restrict a, const double *restrict b, size_t n);

/* Relative threshold shared by the Cholesky conditioning check (smallest
 * squared pivot over the largest) and the pseudo-inverse (eigenvalues at
 * or below this fraction of the largest count as zero). */
#define BF_LINALG_RTOL 1e-14

/* Factor the symmetric matrix a = L L^T in place: the lower triangle of a
 * receives L, the strict upper triangle is not touched. Returns 1 on
 * success; 0 when a pivot is not positive and finite, or when the smallest
 * squared pivot is below rtol times the largest (too badly conditioned to
 * trust). a is garbage after a 0 return. */
int bf_cholesky(double *a, size_t n, double rtol);

/* bf_cholesky() that returns -1 when `stop` asks it to (a is garbage). */
int bf_cholesky_until(double *a, size_t n, double rtol, const bf_stop *stop);

/* Solve L L^T x = b in place (b becomes x), L from bf_cholesky(). */
void bf_cholesky_solve(const double *l, size_t n, double *b);

/* Eigen-decomposition a = V diag(w) V^T of the symmetric matrix a by cyclic
 * Jacobi rotations. a is destroyed (its diagonal ends up holding w). w
 * receives the n eigenvalues, unsorted. v, when not NULL, receives the
 * eigenvectors as columns: v[i * n + k] is component i of vector k.
 * Returns 1 when the off-diagonal part vanished, 0 when the sweep limit
 * was hit first (the result is then still a close approximation). */
int bf_sym_eigen(double *a, size_t n, double *w, double *v);

/* bf_sym_eigen() that returns -1 when `stop` asks it to (w and v are then
 * garbage). */
int bf_sym_eigen_until(double *a, size_t n, double *w, double *v, const bf_stop *stop);

/* x = A^+ b from w and v of bf_sym_eigen(); eigenvalues at or below
 * rtol times the largest one count as zero. tmp holds n values. x and b
 * may be the same array. */
void bf_eigen_pinv_solve(const double *w, const double *v, size_t n, double rtol, const double *b,
                         double *x, double *tmp);

/* out = A^+ (n x n) from w and v of bf_sym_eigen(), same rule as above.
 * Returns 0 when `stop` (may be NULL) asked it to give up, else 1. */
int bf_eigen_pinv(const double *w, const double *v, size_t n, double rtol, double *out,
                  const bf_stop *stop);

/* Ratio of the largest to the smallest eigenvalue: HUGE_VAL when the
 * smallest is not positive, 1 when n is 0. */
double bf_eigen_condition(const double *w, size_t n);

#endif /* BRDFFIT_CORE_LINALG_H */
