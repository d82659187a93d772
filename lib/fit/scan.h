/* The auto pipeline's global scan: the profile cost (varpro.h) over a grid
 * of the shared, free, non-linear parameters (log-spaced for log-scale
 * ones), its local minima kept as candidates, and a golden-section
 * refinement of competing minima of one parameter. Not installed. */
#ifndef BRDFFIT_FIT_SCAN_H
#define BRDFFIT_FIT_SCAN_H

#include <stddef.h>

#include "fit/stage.h"

#define BF_MAX_DIMS 8
#define BF_MAX_CANDIDATES 3

typedef struct bf_scan_dim {
    size_t entry; /* vector entry */
    int log;      /* scanned in log space */
    double lo, hi;/* scan coordinates */
    size_t count; /* grid points */
} bf_scan_dim;

typedef struct bf_candidate {
    double cost;
    double u[BF_MAX_DIMS]; /* scan coordinates */
} bf_candidate;

typedef struct bf_scan {
    bf_scan_dim dims[BF_MAX_DIMS];
    size_t nd;
    bf_candidate best[BF_MAX_CANDIDATES]; /* best first */
    size_t n_best;
} bf_scan;

/* A scan coordinate that is no grid point (golden-section refinement). */
#define BF_SCAN_OFF_GRID ((size_t)-1)

/* The scan's dimensions and grid counts for the stage (what
 * bf_scan_run() scans), no candidate yet; returns bf_scan_points(). */
size_t bf_scan_layout(const bf_stage *st, bf_scan *sc);

/* Scan coordinate of grid point i of dimension d. */
double bf_scan_coord(const bf_scan_dim *d, size_t i);

/* Grid points of the scan: the product of its counts, 0 without a
 * dimension. */
size_t bf_scan_points(const bf_scan *sc);

/* The scan coordinates of grid point `flat` (its number in the scan's
 * flat order, the first dimension fastest) into u. */
void bf_scan_grid_point(const bf_scan *sc, size_t flat, double *u);

/* Scan the stage's shared free non-linear entries and keep the best local
 * minima in sc->best (with no such entry, one candidate of cost 0 at the
 * start values). A cancel leaves the points not reached out; points the
 * model cannot evaluate are left out too, and when none could be, their
 * failure is returned. */
brdffit_status bf_scan_run(bf_stage *st, bf_scan *sc);

/* Refine candidates [0, n) along the single scan dimension. */
brdffit_status bf_scan_refine(bf_stage *st, bf_scan *sc, size_t n);

/* Set st->p to the start values with the scan entries at coordinates u. */
void bf_scan_set_point(bf_stage *st, const bf_scan *sc, const double *u);

/* The profile cost at scan coordinates u, st->p set to the point with its
 * best colours, recorded in the run's trace (trace.h); HUGE_VAL without
 * evaluating when the fit is cancelled, and HUGE_VAL (st->status and
 * st->err saying why, not traced) where the model fails or gives NaN or
 * Inf: such points are left out of the scan. */
brdffit_status bf_scan_profile_at(bf_stage *st, const bf_scan *sc, const double *u,
                                  double *cost);

#endif
