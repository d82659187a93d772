/* What the items of a batch (brdffit_fit_many(), many.c) share: computed
 * once per batch from the prototype's geometry and options, then read by
 * every item on every thread, never written.
 *
 * - The weight plans (run.h) with every chunk's weights computed once
 *   (bf_weight_plan.cached), so no item builds a plan or computes a
 *   weight again.
 * - For the auto pipeline of a model in basis form (models/basis.h): the
 *   scan basis, the values of the basis functions B_q at every grid point
 *   of auto's scan (scan.h) on every active sample, their weighted Gram
 *   matrices B^T W B, W = diag(w^2), and the point's cheap plausibility
 *   bounds (plausible.h). Only the values differ between
 *   items, so an item's VARPRO sums at a grid point (pass.h: R^T W R,
 *   B^T W R, B^T W B per channel) come from one product of its values with
 *   the basis, (W R)^T B for every grid point at once, computed once per
 *   item, and the shared Gram: no pass per grid point. A column equal at
 *   several grid points (a diffuse term that no shape parameter moves) is
 *   stored and multiplied once.
 *
 * The sums equal a pass's up to the order of summation (the basis values
 * are the kernel's, the same bits as the passes'; the weights and values
 * are those the pass reads, in single precision where the fused loop
 * takes it, pass_fused.h): the scan's costs agree with a single fit's to
 * rounding, and an item's result is the single
 * fit's unless two scan points' costs lie within that rounding of each
 * other (docs/fitting.md, Many fits over one geometry). An item with a
 * missing value, a grid point whose basis is not finite and every other
 * pipeline take the passes as a single fit does. Not installed. */
#ifndef BRDFFIT_FIT_MANY_SCAN_H
#define BRDFFIT_FIT_MANY_SCAN_H

#include <stddef.h>

#include "fit/stage.h"

/* Largest scan basis a batch keeps, in bytes (a model with more scan
 * points or samples takes the passes). */
#define BF_BATCH_SCAN_MAX ((size_t)4 << 20)

/* Columns of the basis multiplied at once (an item's product). */
#define BF_BATCH_COLS 8

typedef struct bf_batch {
    int has_plans;
    bf_weight_plan plan, plan_sa; /* over the first private fit's view, weights cached */
    double *weights;              /* both plans' cached weights, one block */
    /* the scan basis; n_points 0 when there is none */
    size_t n_points;       /* the scan's grid points, flat order */
    size_t n_rows;         /* the plan's chunks x BF_CHUNK (rows past a chunk's end: 0) */
    size_t nc, L;          /* channels, basis functions (linear parameters) */
    size_t n_cols;         /* distinct columns */
    size_t *col;           /* n_points * L: the column of B_q at point j */
    size_t stride;         /* n_cols rounded up to BF_BATCH_COLS */
    double *basis;         /* n_rows * stride, row-major: B, unweighted (padding 0) */
    int single;            /* the stage's VARPRO passes take the fused loop (pass_fused.h):
                            * w2 from the plan's single-precision base weights, an
                            * item's values rounded to single precision as the loop
                            * reads them */
    double *w2;            /* n_rows: w^2 of the stage's plan */
    double *coat;          /* n_rows: 1 / the clear coat's divisor, 1 without a coat */
    double *gram;          /* n_points * L * L: B^T W B */
    double *bounds;        /* n_points * L: the cheap plausibility bounds (plausible.h) */
    int has_bounds;        /* plausibility sets them */
    unsigned char *usable; /* n_points: 1 where the basis is finite */
    size_t work_size;      /* doubles of one thread's scratch (fit->batch_work) */
} bf_batch;

/* Compute what the batch shares from `fit`, a private fit over a view of
 * the prototype's geometry with the prototype's options (values not yet
 * set). Only BRDFFIT_E_OUT_OF_MEMORY fails it; a plan that cannot be made
 * (nothing inside the cap) or a model without a basis form leaves that part
 * out, and the items then do as a single fit does (and fail as it fails). */
brdffit_status bf_batch_init(bf_batch *b, brdffit_fit *fit);
void bf_batch_free(bf_batch *b, const brdffit_allocator *a);

/* The batch's plans, read over fit's own grid, into plan and plan_sa
 * (borrowed: never freed by the run) when fit has a batch with plans;
 * else 0. */
int bf_batch_plans(const brdffit_fit *fit, bf_weight_plan *plan, bf_weight_plan *plan_sa);

/* The VARPRO sums of auto's stage st at scan grid point `flat` into
 * st->acc from the batch's scan basis, when the fit has one and it serves
 * the point (the item has no missing value, the point's basis and the
 * sums are finite); else 0, and the caller runs the pass. The first call
 * of a run computes the item's product with the basis. */
int bf_batch_scan_sums(bf_stage *st, size_t flat);

/* The scan basis at auto's grid point `flat`, for the colour steps of a
 * non-squares objective (profile_gn.h; st->scan_point names the point
 * while they run): B_q at row r is basis[r * *stride + col[q]], for the
 * q < L linear parameters, rows r of the stage's plan (chunk r / BF_CHUNK,
 * its sample r % BF_CHUNK; rows past a chunk's end hold 0); NULL when the
 * batch has no basis serving the point (then the steps take passes). The
 * steps' rows are w (f(B c) - f(R)) with w the plan's weights and R the
 * item's values (times 1 / the coat's divisor), so a step needs no
 * model evaluation. */
const double *bf_batch_point_basis(const bf_stage *st, size_t flat, const size_t **col,
                                   size_t *stride, size_t *n_rows);

/* The cheap plausibility bounds of grid point `flat` (what
 * bf_plausible_bounds(st, 0) sets there, computed once per batch) set in
 * st, when the fit has a scan basis that serves the point; else 0, and the
 * caller computes them. */
int bf_batch_scan_bounds(bf_stage *st, size_t flat);

#endif
