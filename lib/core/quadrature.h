/* Gauss-Legendre quadrature nodes, shared by the MERL cell measure and
 * the directional albedo. Not installed. */
#ifndef BRDFFIT_CORE_QUADRATURE_H
#define BRDFFIT_CORE_QUADRATURE_H

#include <stddef.h>

/* Largest rule bf_gauss_legendre() computes. */
#define BF_GAUSS_MAX 32

/* The n-point Gauss-Legendre rule on [-1, 1] (1 <= n <= BF_GAUSS_MAX):
 * nodes x[0..n) ascending and their weights w[0..n), exact for
 * polynomials of degree 2n - 1. Nodes and weights are correct to a few
 * units in the last place. */
void bf_gauss_legendre(size_t n, double *x, double *w);

#endif /* BRDFFIT_CORE_QUADRATURE_H */
