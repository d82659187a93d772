/* The naive reference: the fused normal-equation pass written the way a
 * first implementation would write it, to measure the library against.
 *
 * For every active sample it recomputes the geometry from the four angles
 * (sin, cos, normalising the half vector, clamped dot products); for every
 * channel of it (one residual row) it evaluates the model from scratch,
 * calling pow() and the other transcendental functions per row, fills the
 * whole derivative row over the parameter vector and adds the full p x p
 * outer product of the row to J^T J. No blocking, no structure-of-arrays,
 * no use of the zeros in the row.
 *
 * The results equal the library's BF_PASS_NORMAL accumulator up to
 * rounding: the same model formulas (docs/models.md), dot products clamped
 * to [1e-4, 1], residual r = w (M - R). */
#ifndef BRDFFIT_BENCH_NAIVE_H
#define BRDFFIT_BENCH_NAIVE_H

#include <stddef.h>

/* Light and view directions of one sample and the clamped dot products. */
typedef struct naive_geom {
    double l[3], v[3];
    double nl, nv, nh, hv, rv; /* rv = r.v, r the mirror of l about n; not clamped */
} naive_geom;

/* Value of channel c and, when row is not NULL, the derivative row over all
 * n_vec parameters of a built-in model's vector layout [shape..., lin0 (nc),
 * lin1 (nc), ...]. */
typedef void (*naive_row_fn)(const naive_geom *g, const double *params, size_t nc, size_t c,
                             size_t n_vec, double *value, double *row);

typedef struct naive_model {
    const char *name; /* the built-in model it mirrors */
    naive_row_fn row;
} naive_model;

/* The naive version of a built-in model, or NULL when there is none. */
const naive_model *naive_find(const char *name);

/* The data of one pass: the active samples, their residual weights and the
 * measured values. */
typedef struct naive_data {
    size_t n;                                        /* active samples */
    size_t nc;                                       /* channels */
    const double *theta_i, *phi_i, *theta_o, *phi_o; /* n each, radians */
    const double *weight;                            /* n: residual weight factor */
    const double *meas;                              /* nc * n: [c * n + s] */
} naive_data;

/* Geometry of one direction pair. */
void naive_geometry(double theta_i, double phi_i, double theta_o, double phi_o, naive_geom *g);

/* Values only: values[c * n + s]. */
void naive_value_pass(const naive_model *m, const naive_data *d, const double *params, size_t n_vec,
                      double *values);

/* Values and the dense Jacobian, one row of n_vec derivatives per residual
 * row i = c * n + s: jac[i * n_vec + k]. */
void naive_jacobian_pass(const naive_model *m, const naive_data *d, const double *params,
                         size_t n_vec, double *values, double *jac);

/* The normal-equation pass: acc receives [cost, J^T r (n_vec), J^T J
 * (n_vec * n_vec)] as BF_PASS_NORMAL; row is scratch for n_vec doubles. */
void naive_normal_pass(const naive_model *m, const naive_data *d, const double *params,
                       size_t n_vec, double *acc, double *row);

#endif /* BRDFFIT_BENCH_NAIVE_H */
