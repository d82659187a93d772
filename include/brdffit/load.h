/**
 * @file load.h
 * @brief The minimal loader: CSV (SPEC section 2b) and MERL binary (SPEC
 *        section 9). The library's only file I/O.
 *
 * Every loader returns a new grid owned by the caller, or an error with a
 * message naming what is wrong and where (line and column for CSV). No
 * partial grid is ever returned. All loaders are thread-safe and
 * locale-independent. Every allocation, the file buffer included, goes
 * through the given allocator; memory stays proportional to the input (no
 * allocation is sized by an unchecked number from the file). A file is
 * read whole, after its size has been checked.
 *
 * Only regular files are read (symbolic links to them are followed): a
 * FIFO, a device, a socket or a directory gives ::BRDFFIT_E_IO at once
 * (a FIFO is never waited on), and so does a file that reports a size of 0
 * but has content (as files of /proc do). An ::BRDFFIT_E_IO message names
 * the file and the reason (e.g. "too many levels of symbolic links").
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
 * Angles in the file are degrees; the grid holds radians, converted as
 * deg * pi / 180.
 *
 * The format in detail:
 * - Lines end in '\n' or "\r\n"; a UTF-8 byte order mark at the start is
 *   skipped. Blank lines (spaces and tabs only) and lines whose first
 *   non-blank character is '#' are ignored anywhere.
 * - The first other line is the header. Its fields are trimmed of spaces
 *   and tabs; the angle names must match exactly (lower case). At least
 *   one channel column follows; channel names are free but not empty.
 * - Every data line has as many fields as the header. Fields are trimmed.
 *   A channel field that is empty or "nan" (any case) marks a missing
 *   value. Numbers are [+-]digits[.digits][(e|E)[+-]digits] (".5" and
 *   "5." too), read exactly as written (correctly rounded, whatever the
 *   C locale says): a value printed with %.17g loads back unchanged.
 * - Angles: theta in [0, 90]; phi in [-360, 360] in the scattered form and
 *   phi_o in [0, 180] in the grid form.
 * - Grid form: the distinct values of each angle column (compared exactly
 *   as parsed) form the axes; the rows, in any order, must hold every
 *   combination exactly once.
 * - At most 2^31 values (grid combinations times channels).
 * Messages name the line (1-based, counting every line) and the column
 * (the 1-based field number, with its header name), for example
 * "line 12, column 3 (phi_o): malformed number 'x.5'".
 *
 * @param[out] out Receives the grid; NULL on failure.
 * @param path     File name.
 * @param alloc    Allocator for the grid, or NULL.
 * @param[out] err NULL, or the detail on failure.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_IO (missing or unreadable file);
 *         ::BRDFFIT_E_PARSE (empty file, no data rows, unknown header,
 *         wrong column count, malformed number, missing angle);
 *         ::BRDFFIT_E_RANGE (negative or infinite value, angle out of
 *         range, two axis values in degrees that coincide in radians);
 *         ::BRDFFIT_E_INCOMPLETE_GRID (naming one missing combination in
 *         degrees); ::BRDFFIT_E_DUPLICATE (naming the combination and both
 *         lines); ::BRDFFIT_E_TOO_LARGE (more than 2^31 values, or axes
 *         whose combinations would exceed that);
 *         ::BRDFFIT_E_OUT_OF_MEMORY; ::BRDFFIT_E_INVALID_ARGUMENT for NULL
 *         arguments or an incomplete allocator.
 */
BRDFFIT_API brdffit_status brdffit_load_csv(brdffit_grid **out, const char *path,
                                            const brdffit_allocator *alloc,
                                            brdffit_error *err);

/**
 * @brief Load CSV text from memory; as brdffit_load_csv() otherwise.
 * @param[out] out Receives the grid; NULL on failure.
 * @param data     Text, not necessarily NUL-terminated (borrowed for the
 *                 call); exactly @p size bytes are read.
 * @param size     Bytes of @p data.
 * @param alloc    Allocator for the grid, or NULL.
 * @param[out] err NULL, or the detail on failure.
 * @return As brdffit_load_csv(), without ::BRDFFIT_E_IO.
 */
BRDFFIT_API brdffit_status brdffit_load_csv_buffer(brdffit_grid **out, const char *data,
                                                   size_t size,
                                                   const brdffit_allocator *alloc,
                                                   brdffit_error *err);

/**
 * @brief Load a MERL binary file (SPEC section 9).
 *
 * The file: three little-endian int32 (90, 90, 180), then 3 x 90 x 90 x
 * 180 little-endian doubles (red, green, blue), 34,992,012 bytes in all.
 * Values are scaled by 1/1500, 1.15/1500 and 1.66/1500; a negative value
 * marks an unmeasured cell.
 *
 * With @p axes NULL the result is a scattered grid holding one sample per
 * MERL cell with at least one measured channel whose light and view both
 * lie above the horizon (1,096,216 for a complete file; about 128 bytes of
 * grid per sample), directions at the cell centres (theta_h = ((i + 0.5) /
 * 90)^2 pi/2, theta_d = (j + 0.5) / 90 pi/2, phi_d = (k + 0.5) / 180 pi,
 * phi_h = 0), three channels, unmeasured channels missing. With @p axes the
 * file is resampled onto a regular grid with those axes
 * (brdffit_axes_default() for the thesis's layout): each grid sample (light
 * at azimuth pi) takes the value of the MERL cell holding its
 * half/difference angles (theta_h index floor(sqrt(theta_h / (pi/2)) 90),
 * theta_d index floor(theta_d / (pi/2) 90), phi_d folded into [0, pi) by
 * reciprocity, index floor(phi_d / pi 180), each clamped to its range);
 * samples whose cell is unmeasured are marked missing.
 *
 * @param[out] out Receives the grid; NULL on failure.
 * @param path     File name.
 * @param axes     NULL for scattered, or the axes to resample onto.
 * @param alloc    Allocator for the grid, or NULL.
 * @param[out] err NULL, or the detail on failure.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_IO; ::BRDFFIT_E_FORMAT (wrong
 *         dimensions, naming them; truncated or oversized file, stating the
 *         expected and the actual size; an oversized file is refused from
 *         its size without being read); ::BRDFFIT_E_RANGE (infinite or NaN
 *         values, naming the channel and cell; axis values out of range);
 *         ::BRDFFIT_E_NO_DATA (no measured cell, or none that the result
 *         would use);
 *         ::BRDFFIT_E_INVALID_ARGUMENT (NULL arguments, empty or invalid
 *         axes); ::BRDFFIT_E_TOO_LARGE (axes with more than 2^31 values);
 *         ::BRDFFIT_E_OUT_OF_MEMORY.
 */
BRDFFIT_API brdffit_status brdffit_load_merl(brdffit_grid **out, const char *path,
                                             const brdffit_axes *axes,
                                             const brdffit_allocator *alloc,
                                             brdffit_error *err);

/**
 * @brief Load MERL binary data from memory; as brdffit_load_merl() otherwise.
 * @param[out] out Receives the grid; NULL on failure.
 * @param data     The file's bytes (borrowed for the call).
 * @param size     Number of bytes.
 * @param axes     NULL for scattered, or the axes to resample onto.
 * @param alloc    Allocator for the grid, or NULL.
 * @param[out] err NULL, or the detail on failure.
 * @return As brdffit_load_merl(), without ::BRDFFIT_E_IO.
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
