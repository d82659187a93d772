/* Ceres Solver as a peer of the benchmarks (bench_ceres.cc, C++): its
 * Levenberg-Marquardt on a problem given as libbrdffit's residual
 * callback. Built only when CMake finds Ceres; the programs that use it
 * define BENCH_HAVE_CERES then. */
#ifndef BRDFFIT_BENCH_CERES_H
#define BRDFFIT_BENCH_CERES_H

#include <stddef.h>

#include "brdffit/optim.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct bench_ceres_settings {
    int max_iterations;
    double function_tolerance, gradient_tolerance, parameter_tolerance;
} bench_ceres_settings;

typedef struct bench_ceres_result {
    int converged;     /* Ceres ended with CONVERGENCE */
    size_t iterations; /* successful plus unsuccessful steps */
} bench_ceres_result;

/* Minimise sum r^2 of fn's n_rows = m residuals over x (n values, start
 * in, result out). fn is called with jac NULL for residuals alone and
 * with the m x n row-major Jacobian otherwise. Returns 0 when Ceres ran. */
int bench_ceres_solve(brdffit_residual_fn fn, void *user, size_t n, size_t m,
                      const bench_ceres_settings *settings, double *x, bench_ceres_result *result);

#ifdef __cplusplus
}
#endif

#endif
