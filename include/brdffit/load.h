/**
 * @file load.h
 * @brief The loaders: CSV, MERL binary, ASTM E1392 text and RGL .bsdf
 *        (docs/formats.md, with each format's published source). The
 *        library's only file I/O.
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
 * @brief Load a CSV file in either of its two forms (docs/formats.md).
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
 *   value. Negative values are data (measurement noise) and kept. Numbers are [+-]digits[.digits][(e|E)[+-]digits] (".5" and
 *   "5." too), read exactly as written (correctly rounded, whatever the
 *   C locale says): a value printed with %.17g loads back unchanged.
 * - Angles: theta in [0, 90]; phi in [-360, 360] in the scattered form and
 *   phi_o in [0, 180] in the grid form.
 * - Weights: the scattered form may have a column named "weight" right
 *   after phi_o (theta_i,phi_i,theta_o,phi_o,weight,...). Each of its
 *   fields must be a finite number >= 0 (never missing); they become the
 *   samples' given weights (brdffit_grid_create_scattered(), used by
 *   ::BRDFFIT_WEIGHT_SOLID_ANGLE), and the weight is no channel. Without
 *   the column every sample weighs the same. A "weight" header anywhere
 *   else, or in the grid form (whose weights follow from the axes), is an
 *   error.
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
 *         wrong column count, malformed number, missing angle or weight,
 *         a misplaced weight column);
 *         ::BRDFFIT_E_RANGE (infinite value, negative or infinite weight,
 *         angle out of range, two axis values in degrees that coincide in
 *         radians);
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
 * @brief Load a MERL binary file (docs/formats.md).
 *
 * The file: three little-endian int32 (90, 90, 180), then 3 x 90 x 90 x
 * 180 little-endian doubles (red, green, blue), 34,992,012 bytes in all.
 * Values are scaled by 1/1500, 1.15/1500 and 1.66/1500; a negative value
 * marks an unmeasured cell.
 *
 * With @p axes NULL the result is a scattered grid holding one sample per
 * MERL cell with at least one measured channel whose light and view both
 * lie above the horizon (1,096,216 for a complete file; about 136 bytes of
 * grid per sample), directions at the cell centres (theta_h = ((i + 0.5) /
 * 90)^2 pi/2, theta_d = (j + 0.5) / 90 pi/2, phi_d = (k + 0.5) / 180 pi,
 * phi_h = 0), three channels, unmeasured channels missing. Each sample's
 * given weight (brdffit_grid_create_scattered()) is the measure, in sr^2,
 * of its cell in light x view space: every pair of directions above the
 * horizon whose half/difference angles lie in the cell, over all phi_h and
 * both phi_d and phi_d + pi (docs/measure.md derives it). The weights of a
 * complete file add up to 39.2173 sr^2, 0.66 % short of (2 pi)^2 (the
 * cells whose centre lies below the horizon are left out); a highlight
 * cell is about 10^-6 of a wide one. With @p axes the
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

/**
 * @brief Load an ASTM E1392 file (the text format of ASTM E1392, "Standard
 *        Practice for Angle Resolved Optical Scatter Measurements on
 *        Specular or Diffuse Surfaces", used by the Cornell
 *        gonioreflectometer measurements). See docs/formats.md.
 *
 * The result is a scattered grid, one sample per data row, in file order.
 * The format in detail:
 * - Lines end in '\n' or "\r\n"; blank lines are ignored anywhere.
 * - The header: lines that start with a keyword (an upper-case letter,
 *   then letters, digits or '_'), such as SOURCE, SAMPLE, NUM_POINTS. Only
 *   two are read: NUM_POINTS (if given, the number of data rows must
 *   equal it) and VARS, which ends the header and names the columns,
 *   separated by commas (names may then hold blanks) or by blanks.
 * - Columns: theta_i, phi_i (optional; 0 when absent), theta_s and phi_s
 *   (theta_r/phi_r and theta_o/phi_o are accepted too), any case, in any
 *   order; every other column is a channel (R, G, B, spectral bands such
 *   as "550nm", ...), in the order of VARS. At least one channel.
 * - Data rows: one value per VARS name, separated by commas, blanks or
 *   both; numbers as for brdffit_load_csv(). A value that is "nan" or
 *   empty (two commas) is missing; negative values are data; infinite
 *   values are refused.
 * - Angles are degrees, as the standard has them. A file whose every polar
 *   angle is within pi/2 and every azimuth within 2 pi in magnitude is read
 *   as radians (the convention of some public files and readers; no real
 *   measurement in degrees stays within 1.6 degrees). |theta| <= 90
 *   degrees and |phi| <= 360 degrees, each with 1e-4 radians allowed for
 *   rounding (1.5708 for pi/2; theta is then clamped to pi/2); a negative
 *   polar angle is the direction on the other side of the normal,
 *   (|theta|, phi + 180 degrees).
 * Messages name the line and, for a field, the column with its VARS name,
 * for example "line 14, column 5 (R): malformed number '0.1x'".
 *
 * @param[out] out Receives the grid; NULL on failure.
 * @param path     File name.
 * @param alloc    Allocator for the grid, or NULL.
 * @param[out] err NULL, or the detail on failure.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_IO; ::BRDFFIT_E_PARSE (no header, no
 *         VARS, an angle column missing or named twice, no channel, a row
 *         with the wrong number of values, a malformed number, a missing
 *         angle, a row count other than NUM_POINTS); ::BRDFFIT_E_RANGE
 *         (an infinite value or angle, an angle out of range);
 *         ::BRDFFIT_E_TOO_LARGE (more than 2^31 values);
 *         ::BRDFFIT_E_OUT_OF_MEMORY; ::BRDFFIT_E_INVALID_ARGUMENT for NULL
 *         arguments or an incomplete allocator. Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_load_astm(brdffit_grid **out, const char *path,
                                             const brdffit_allocator *alloc,
                                             brdffit_error *err);

/**
 * @brief Load ASTM E1392 text from memory; as brdffit_load_astm() otherwise.
 * @param[out] out Receives the grid; NULL on failure.
 * @param data     Text, not necessarily NUL-terminated (borrowed for the
 *                 call); exactly @p size bytes are read.
 * @param size     Bytes of @p data.
 * @param alloc    Allocator for the grid, or NULL.
 * @param[out] err NULL, or the detail on failure.
 * @return As brdffit_load_astm(), without ::BRDFFIT_E_IO.
 */
BRDFFIT_API brdffit_status brdffit_load_astm_buffer(brdffit_grid **out, const char *data,
                                                    size_t size,
                                                    const brdffit_allocator *alloc,
                                                    brdffit_error *err);

/**
 * @brief Load a BRDF of the RGL material database (a `.bsdf` tensor file;
 *        Dupuy and Jakob 2018, "An Adaptive Parameterization for Efficient
 *        Material Acquisition and Rendering"), the format of Mitsuba's
 *        `measured` plugin. See docs/formats.md.
 *
 * The file is a "tensor_file" container of named float32 fields: theta_i
 * and phi_i (the light directions, radians), vndf (the warp of every light
 * direction), ndf and sigma, the uint8 jacobian flag, and the values:
 * "rgb" (3 channels) when present, else "spectra" with one channel per
 * entry of "wavelengths". The stored values are f_r cos theta_o; the grid
 * holds f_r in 1/sr (values whose view has cos theta_o <= 1e-6 are left
 * out, or marked missing when resampled).
 *
 * With @p axes NULL the result is a scattered grid of the samples as
 * measured: every stored sample of every light direction, at the view the
 * format's warp gives it, with its solid angle (its cell of the warp's
 * unit square times the warp's d omega / d s) as the sample weight, in the
 * input order light by light. With @p axes the BRDF is evaluated at every
 * sample of the axes (light at azimuth pi) as the reference reader
 * evaluates it: the inverse warp of the half vector, the values
 * interpolated bilinearly there and linearly between the file's light
 * directions.
 *
 * @param[out] out Receives the grid; NULL on failure.
 * @param path     File name.
 * @param axes     NULL for the samples as measured, or the axes to
 *                 resample onto (brdffit_axes_default() for the thesis's
 *                 layout).
 * @param alloc    Allocator for the grid and the temporary arrays, or NULL.
 * @param[out] err NULL, or the detail on failure.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_IO; ::BRDFFIT_E_FORMAT (not a tensor
 *         file, a field missing, of the wrong type or shape, or lying
 *         outside the file, naming it); ::BRDFFIT_E_RANGE (non-finite
 *         values, a negative density, light angles out of range, naming
 *         the field and index); ::BRDFFIT_E_NO_DATA (no sample with its
 *         view above the horizon); ::BRDFFIT_E_UNSUPPORTED (resampling an
 *         anisotropic file measured over a fraction of the light
 *         azimuths, which the reference reader does not evaluate either);
 *         ::BRDFFIT_E_INVALID_ARGUMENT (NULL arguments, empty axes);
 *         ::BRDFFIT_E_TOO_LARGE (more than 2^31 values);
 *         ::BRDFFIT_E_OUT_OF_MEMORY. Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_load_rgl(brdffit_grid **out, const char *path,
                                            const brdffit_axes *axes,
                                            const brdffit_allocator *alloc,
                                            brdffit_error *err);

/**
 * @brief Load an RGL `.bsdf` file from memory; as brdffit_load_rgl()
 *        otherwise.
 * @param[out] out Receives the grid; NULL on failure.
 * @param data     The file's bytes (borrowed for the call).
 * @param size     Number of bytes.
 * @param axes     NULL for the samples as measured, or the axes to
 *                 resample onto.
 * @param alloc    Allocator, or NULL.
 * @param[out] err NULL, or the detail on failure.
 * @return As brdffit_load_rgl(), without ::BRDFFIT_E_IO.
 */
BRDFFIT_API brdffit_status brdffit_load_rgl_buffer(brdffit_grid **out, const void *data,
                                                   size_t size, const brdffit_axes *axes,
                                                   const brdffit_allocator *alloc,
                                                   brdffit_error *err);

#ifdef __cplusplus
}
#endif

/** @} */

#endif /* BRDFFIT_LOAD_H */
