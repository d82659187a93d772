/* Small dense bounded least squares, for the linear (colour) parameters of
 * variable projection: minimise c^T G c - 2 b^T c over lower <= c <= upper,
 * G symmetric positive semi-definite (K x K, K small). */
#ifndef BRDFFIT_FIT_LSQ_H
#define BRDFFIT_FIT_LSQ_H

#include <stddef.h>

#define BF_LSQ_MAX 16

/* Writes the minimiser to c and returns the value of c^T G c - 2 b^T c
 * (add r^T W r for the cost). Exact (active-set enumeration) for K <= 6,
 * projected Gauss-Seidel beyond. Never fails: a singular G is regularised. */
double bf_bounded_lsq(size_t K, const double *G, const double *b, const double *lower,
                      const double *upper, double *c);

/* bf_bounded_lsq(), but when every variable's unconstrained minimiser lies
 * inside the bounds it is returned without trying the other active sets
 * (the full enumeration could prefer one of those only by rounding: the
 * problem is convex), and two variables are solved in closed form (the
 * boundary's minimum edge by edge): the same minimum up to rounding. For
 * the many scan points of a batch (varpro.h). */
double bf_bounded_lsq_quick(size_t K, const double *G, const double *b, const double *lower,
                            const double *upper, double *c);

#endif
