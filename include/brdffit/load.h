/**
 * @file load.h
 * @brief The minimal loader: CSV (SPEC section 2b) and MERL binary (SPEC
 *        section 9). The library's only file I/O.
 *
 * Every loader returns a new grid owned by the caller, or an error with a
 * message naming what is wrong and where (line and column for CSV). No
 * partial grid is ever returned. All loaders are thread-safe and
 * locale-independent.
 */
#ifndef BRDFFIT_LOAD_H
#define BRDFFIT_LOAD_H

#include <stddef.h>

#include "brdffit/alloc.h"
#include "brdffit/export.h"
#include "brdffit/grid.h"
#include "brdffit/status.h"

/** @defgroup load Loaders
 * @{ */

#ifdef __cplusplus
extern "C" {
#endif

/**
 * @brief Load a CSV file in either form of SPEC section 2b.
 *
 * The grid form (header theta_i,theta_o,phi_o,...) gives a regular grid,
 * the scattered form (theta_i,phi_i,theta_o,phi_o,...) a scattered grid.
 * Angles in the file are degrees; the grid holds radians.
 *
 * @param[out] out Receives the grid; NULL on failure.
 * @param path     File name.
 * @param alloc    Allocator for the grid, or NULL.
 * @param[out] err NULL, or the detail on failure.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_IO (missing or unreadable file);
 *         ::BRDFFIT_E_PARSE (empty file, no data rows, unknown header,
 *         wrong column count, malformed number); ::BRDFFIT_E_RANGE
 *         (negative or infinite value, angle out of range);
 *         ::BRDFFIT_E_INCOMPLETE_GRID; ::BRDFFIT_E_DUPLICATE;
 *         ::BRDFFIT_E_TOO_LARGE; ::BRDFFIT_E_OUT_OF_MEMORY;
 *         ::BRDFFIT_E_INVALID_ARGUMENT for NULL arguments.
 */
BRDFFIT_API brdffit_status brdffit_load_csv(brdffit_grid **out, const char *path,
                                            const brdffit_allocator *alloc,
                                            brdffit_error *err);

/**
 * @brief Load CSV text from memory; as brdffit_load_csv() otherwise.
 * @param data Text, not necessarily NUL-terminated (borrowed for the call).
 * @param size Bytes of @p data.
 */
BRDFFIT_API brdffit_status brdffit_load_csv_buffer(brdffit_grid **out, const char *data,
                                                   size_t size,
                                                   const brdffit_allocator *alloc,
                                                   brdffit_error *err);

/**
 * @brief Load a MERL binary file (SPEC section 9).
 *
 * With @p axes NULL the result is a scattered grid holding one sample per
 * measured MERL cell whose light and view both lie above the horizon (about
 * 1.11 million for a complete file), directions at the cell centres, values
 * scaled by MERL's channel factors, three channels. With @p axes the file is
 * resampled onto a regular grid with those axes (brdffit_axes_default() for
 * the thesis's layout): each grid sample takes the value of the MERL cell
 * holding its half/difference angles; samples whose cell is unmeasured are
 * marked missing.
 *
 * @param[out] out Receives the grid; NULL on failure.
 * @param path     File name.
 * @param axes     NULL for scattered, or the axes to resample onto.
 * @param alloc    Allocator for the grid, or NULL.
 * @param[out] err NULL, or the detail on failure.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_IO; ::BRDFFIT_E_FORMAT (truncated or
 *         oversized file, wrong dimensions); ::BRDFFIT_E_RANGE (infinite or
 *         NaN values); ::BRDFFIT_E_NO_DATA (no measured cell);
 *         ::BRDFFIT_E_INVALID_ARGUMENT; ::BRDFFIT_E_OUT_OF_MEMORY.
 */
BRDFFIT_API brdffit_status brdffit_load_merl(brdffit_grid **out, const char *path,
                                             const brdffit_axes *axes,
                                             const brdffit_allocator *alloc,
                                             brdffit_error *err);

/**
 * @brief Load MERL binary data from memory; as brdffit_load_merl() otherwise.
 * @param data The file's bytes (borrowed for the call).
 * @param size Number of bytes.
 */
BRDFFIT_API brdffit_status brdffit_load_merl_buffer(brdffit_grid **out, const void *data,
                                                    size_t size, const brdffit_axes *axes,
                                                    const brdffit_allocator *alloc,
                                                    brdffit_error *err);

#ifdef __cplusplus
}
#endif

/** @} */

#endif /* BRDFFIT_LOAD_H */
