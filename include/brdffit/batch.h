/**
 * @file batch.h
 * @brief The geometry of a batch of samples as models see it
 *        (::brdffit_batch). Included by model.h; a header of its own so
 *        that the grid layer, which makes batches, needs nothing from the
 *        model layer.
 */
#ifndef BRDFFIT_BATCH_H
#define BRDFFIT_BATCH_H

#include <stddef.h>

/** @addtogroup model
 * @{ */

/**
 * @brief Geometry of a batch of samples, structure of arrays, owned by the
 *        library and valid only during the callback that receives it.
 *
 * Every array holds @c n entries. Directions are unit vectors in the frame
 * with normal +z. The dot products are clamped to [1e-4, 1] so that models
 * may divide by them and take their logarithm; @c rv is not clamped.
 * New fields are only ever appended; @c struct_size tells which exist.
 */
typedef struct brdffit_batch {
    size_t struct_size;       /**< sizeof the struct as the library knows it. */
    size_t n;                 /**< Number of samples in the batch. */
    const double *lx;         /**< Light direction, x. */
    const double *ly;         /**< Light direction, y. */
    const double *lz;         /**< Light direction, z (unclamped n.l). */
    const double *vx;         /**< View direction, x. */
    const double *vy;         /**< View direction, y. */
    const double *vz;         /**< View direction, z (unclamped n.v). */
    const double *nl;         /**< n.l, clamped to [1e-4, 1]. */
    const double *nv;         /**< n.v, clamped to [1e-4, 1]. */
    const double *nh;         /**< n.h, h = normalize(l + v), clamped to [1e-4, 1]. */
    const double *hv;         /**< h.v, clamped to [1e-4, 1]. */
    const double *log_nh;     /**< ln of the clamped n.h (finite, <= 0). */
    const double *rv;         /**< r.v, r the mirror of l about n; in [-1, 1]. */
} brdffit_batch;

/** @} */

#endif /* BRDFFIT_BATCH_H */
