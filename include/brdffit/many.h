/**
 * @file many.h
 * @brief Many small independent fits in one call: one geometry, N value
 *        sets (per-texel SVBRDF maps, material libraries measured on one
 *        layout), the same model and options.
 *
 * brdffit_fit_many() takes a prototype fit (fit.h): its grid gives the
 * geometry (directions, axes, sample weights; its values are not used), its
 * model and options (pipeline, objective, cap, weighting, clear coat,
 * iteration limit, damping policy, start values, fixed parameters, the
 * standard errors' estimator ::BRDFFIT_FIT_COVARIANCE) apply to
 * every item, and its thread count (::BRDFFIT_FIT_THREADS) is the number of
 * threads the call runs on. Each thread fits whole items, one after
 * another, on a private fit over a view of the prototype's geometry whose
 * values are replaced per item: no handle and no copy of the geometry is
 * made per item. Results go into the caller's arrays (::brdffit_many_out).
 *
 * What depends on the geometry and options alone is computed once per
 * call and shared by every item: the weights and, for the auto pipeline of
 * a built-in model, the model's basis at every point of auto's scan, so
 * that an item's scan needs no pass over the samples (docs/fitting.md,
 * Many fits over one geometry).
 *
 * Item i's result is bit for bit what brdffit_fit_run() gives for a fit with
 * the prototype's options and ::BRDFFIT_FIT_THREADS 1, on a grid made by the
 * same constructor from the same directions (and sample weights) with
 * item i's values: it depends neither on the thread count nor on which
 * thread ran the item. One exception: the shared scan sums in another
 * order than a pass, so where two points of auto's scan have costs equal
 * to within rounding (~1e-15 relative) the batch may polish from the
 * neighbouring point; when both polishes reach the same minimum the
 * results agree to the polish's tolerance. No such tie has been seen in
 * the tests or benchmarks. The prototype's iteration callback
 * (brdffit_fit_set_callback()) is not called; the batch has a progress
 * callback of its own.
 */
#ifndef BRDFFIT_MANY_H
#define BRDFFIT_MANY_H

#include <stddef.h>

#include "brdffit/export.h"
#include "brdffit/fit.h"
#include "brdffit/optim.h"
#include "brdffit/status.h"

/** @defgroup many Batch fits
 * @{ */

/**
 * @brief Where brdffit_fit_many() writes the result of every item: caller
 *        arrays, each NULL when not wanted. New fields are only ever
 *        appended; set @c struct_size to sizeof(brdffit_many_out).
 *
 * An item that failed or was not run has NaN parameters, standard errors
 * and error figures, stop reason ::BRDFFIT_STOP_NONE, 0 iterations and no
 * warnings.
 */
typedef struct brdffit_many_out {
    size_t struct_size;         /**< sizeof(brdffit_many_out) as the caller knows it. */
    brdffit_status *status;     /**< n_items: ::BRDFFIT_OK, or why the item failed (below). */
    double *params;             /**< n_items * brdffit_fit_param_count(): parameter vectors. */
    double *std_errors;         /**< n_items * brdffit_fit_param_count(): standard errors (no covariances: see brdffit_fit_covariance()); when NULL they are not computed at all, which saves about a tenth of a small item's fit and changes no other output. */
    double *cost;               /**< n_items: ::BRDFFIT_METRIC_COST, all channels. */
    double *rms;                /**< n_items: ::BRDFFIT_METRIC_RMS, all channels. */
    double *ngan;               /**< n_items: ::BRDFFIT_METRIC_NGAN, all channels. */
    brdffit_stop_reason *stop;  /**< n_items: brdffit_fit_stop_reason(). */
    size_t *iterations;         /**< n_items: brdffit_fit_iterations(). */
    unsigned *warnings;         /**< n_items: brdffit_fit_warnings() (::brdffit_warning bits). */
    size_t n_run;               /**< Set by the call: items run (n_items unless cancelled). */
} brdffit_many_out;

/**
 * @brief Progress of brdffit_fit_many(): @p done items of @p total are
 *        finished. Return non-zero to cancel the items not yet started.
 *        Called on the thread that called brdffit_fit_many(), never
 *        concurrently with itself.
 */
typedef int (*brdffit_many_progress_fn)(void *user, size_t done, size_t total);

#ifdef __cplusplus
extern "C" {
#endif

/**
 * @brief Fit every one of @p n_items value sets on the geometry of
 *        @p prototype's grid, with its model and options.
 *
 * @param prototype The fit whose grid, model and options every item uses
 *                  (see the file comment). Only read: its options, result
 *                  and message stay as they were, except that the message
 *                  says why the call failed and a pending brdffit_fit_cancel()
 *                  request is consumed.
 * @param n_items   Number of value sets; 0 does nothing.
 * @param values    n_items * n_samples * n_channels values (the prototype
 *                  grid's counts): item i's values start at
 *                  i * n_samples * n_channels, interleaved and in the sample
 *                  order the prototype's grid was created with, exactly as
 *                  brdffit_grid_create_regular() and
 *                  brdffit_grid_create_scattered() take them (borrowed for
 *                  the call).
 * @param missing   NULL, or one byte per value in the same layout; non-zero
 *                  marks the value missing (borrowed for the call).
 * @param out       The caller's result arrays (see ::brdffit_many_out);
 *                  @c n_run is written.
 * @param progress  NULL, or called on the calling thread when an item it
 *                  ran finishes and at least ceil(n_items / 256) more items
 *                  are done than it last reported, and once at the end with
 *                  the final count (unless the last call had it); a
 *                  non-zero return cancels (see ::brdffit_many_progress_fn).
 * @param user      Passed to @p progress.
 *
 * Per-item statuses (out->status), as brdffit_grid_create_*() and
 * brdffit_fit_run() would give them: ::BRDFFIT_E_RANGE for a present value
 * that is not finite, or any status of brdffit_fit_run()
 * (::BRDFFIT_E_NO_DATA, ::BRDFFIT_E_RANGE, ::BRDFFIT_E_NONFINITE,
 * ::BRDFFIT_E_MODEL_FAILED, ::BRDFFIT_E_OUT_OF_MEMORY, ...);
 * ::BRDFFIT_E_NOT_READY for an item not run because the call was cancelled.
 * A failed item does not stop the others.
 *
 * Cancelling: @p progress returning non-zero, or brdffit_fit_cancel() on
 * @p prototype from any thread, stops the call after the items already
 * started: they finish with their full result, the others are not run.
 * The call then still returns ::BRDFFIT_OK, with out->n_run below
 * @p n_items.
 *
 * @return ::BRDFFIT_OK when every item was run or the call was cancelled
 *         (each item's status says how it went);
 *         ::BRDFFIT_E_INVALID_ARGUMENT for a NULL prototype or @p out,
 *         NULL @p values with @p n_items > 0, or an @c out->struct_size
 *         smaller than the first version's; ::BRDFFIT_E_BAD_HANDLE for a
 *         prototype, grid or model that is not live;
 *         ::BRDFFIT_E_TOO_LARGE when n_items * n_samples * n_channels
 *         overflows; ::BRDFFIT_E_OUT_OF_MEMORY when the per-thread state
 *         cannot be allocated (nothing is run). On failure no item is run
 *         and brdffit_fit_message(prototype) says why.
 *
 * Memory: per thread, one private fit, n_samples * n_channels doubles
 * and bytes and a scratch of the scan's products; per call, the shared
 * weights and scan basis (8 bytes per active sample and basis column, at
 * most 4 MB); all through the prototype's allocator and freed before the
 * call returns.
 *
 * Thread safety: @p prototype must not be used by another thread during
 * the call, except for brdffit_fit_cancel(); its grid and model may be
 * shared with other fits as usual. @p progress runs on the calling thread.
 */
BRDFFIT_API brdffit_status brdffit_fit_many(brdffit_fit *prototype, size_t n_items,
                                            const double *values, const unsigned char *missing,
                                            brdffit_many_out *out,
                                            brdffit_many_progress_fn progress, void *user);

#ifdef __cplusplus
}
#endif

/** @} */

#endif /* BRDFFIT_MANY_H */
