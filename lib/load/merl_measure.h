/* The measure of a MERL cell in light x view space (docs/measure.md). Not
 * installed. */
#ifndef BRDFFIT_LOAD_MERL_MEASURE_H
#define BRDFFIT_LOAD_MERL_MEASURE_H

#include <stddef.h>

/* Points per dimension of the rule used on cells the horizon cuts. */
#define BF_MERL_MEASURE_POINTS 6

/* The quadrature rule, computed once per load. */
typedef struct bf_merl_measure {
    double x[BF_MERL_MEASURE_POINTS], w[BF_MERL_MEASURE_POINTS];
} bf_merl_measure;

void bf_merl_measure_init(bf_merl_measure *m);

/* The measure (sr^2) of the pairs of directions (l, v), both above the
 * horizon, whose half/difference angles lie in MERL cell (ih, id, ip) of
 * the 90 x 90 x 180 layout: over every phi_h (isotropy) and over both
 * phi_d and phi_d + pi (reciprocity). The cells of all indices partition
 * the pairs above the horizon, so their measures add up to (2 pi)^2. */
double bf_merl_cell_measure(const bf_merl_measure *m, size_t ih, size_t id, size_t ip);

#endif /* BRDFFIT_LOAD_MERL_MEASURE_H */
