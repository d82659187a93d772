/**
 * @file grid.h
 * @brief The measurement grid: measured BRDF values and everything derived
 *        from their geometry.
 *
 * A grid is immutable once created. Every function here only reads it, so a
 * grid may be shared by any number of threads without locking, for as long
 * as no thread destroys it.
 *
 * Conventions (docs/definitions.md, Geometry):
 * - Angles are in radians everywhere in the API (file formats and the
 *   command-line tool use degrees). Polar angles theta lie in [0, pi/2],
 *   measured from the normal n = +z; azimuths phi are measured from +x.
 * - A regular grid follows the isotropic layout of the measurement: the light
 *   lies at azimuth pi, l = (-sin theta_i, 0, cos theta_i); the camera at
 *   (theta_o, phi_o), phi_o in [0, pi] (phi_o = 0 is the mirror side).
 *   Sample s of a regular grid has axis indices (i, j, k) with
 *   s = (i * n_theta_o + j) * n_phi_o + k.
 * - A scattered grid holds a list of samples, each with its own light and
 *   view direction. It stores them sorted by max(theta_i, theta_o),
 *   ascending and stable, so that every angle cap selects a prefix; sample
 *   indices of a scattered grid refer to that stored order, and
 *   brdffit_grid_sample_angles() gives each sample's directions back.
 * - Values are BRDF values in 1/sr, n_channels per sample. A value may be
 *   slightly negative (background subtraction noise of a measurement): it
 *   is data, kept and fitted as given. Input arrays are
 *   interleaved: value (s, c) at [s * n_channels + c]. The grid stores them
 *   per channel (brdffit_grid_values()).
 * - A value may be marked missing. Missing values are kept out of fits and
 *   weights; their stored value is 0.
 * - The grid copies everything it is given; the caller's arrays may be
 *   freed as soon as a creation function returns.
 * - Angle caps: a sample is within a cap when theta_i <= cap + 1e-9 and
 *   theta_o <= cap + 1e-9 (radians), so a cap computed from degrees still
 *   includes the axis value it names.
 * - Handles: functions given NULL return ::BRDFFIT_E_INVALID_ARGUMENT (or 0);
 *   a handle whose magic number is wrong (destroyed, or not a grid) gives
 *   ::BRDFFIT_E_BAD_HANDLE (or 0) where this can be detected.
 */
#ifndef BRDFFIT_GRID_H
#define BRDFFIT_GRID_H

#include <stddef.h>

#include "brdffit/alloc.h"
#include "brdffit/export.h"
#include "brdffit/status.h"

/** @defgroup grid Measurement grid
 * @{ */

/** @brief Opaque, immutable measurement grid. */
typedef struct brdffit_grid brdffit_grid;

/** @brief The two forms of grid. Values are fixed forever. */
typedef enum brdffit_grid_kind {
    BRDFFIT_GRID_REGULAR = 1,   /**< Regular isotropic (theta_i, theta_o, phi_o) grid. */
    BRDFFIT_GRID_SCATTERED = 2  /**< A list of samples with their own directions. */
} brdffit_grid_kind;

/** @brief Names of the three axes of a regular grid. Values are fixed forever. */
typedef enum brdffit_axis {
    BRDFFIT_AXIS_THETA_I = 0, /**< Light polar angle. */
    BRDFFIT_AXIS_THETA_O = 1, /**< View polar angle. */
    BRDFFIT_AXIS_PHI_O = 2    /**< View azimuth, 0 .. pi. */
} brdffit_axis;

/** @brief Flags selecting the residual weights (docs/definitions.md, Weights). */
typedef enum brdffit_weighting {
    BRDFFIT_WEIGHT_NONE = 0,        /**< Every sample weighs 1. */
    BRDFFIT_WEIGHT_SOLID_ANGLE = 1, /**< Solid angle of the view cell (regular) or the given sample weight (scattered). */
    BRDFFIT_WEIGHT_COSINE = 2,      /**< cos theta_i. */
    BRDFFIT_WEIGHT_DEFAULT = 3      /**< Both, as in the thesis. */
} brdffit_weighting;

/**
 * @brief The three axes of a regular grid, in radians. Caller-owned; the
 *        layout of this struct is fixed forever.
 *
 * Each axis is strictly increasing. Polar axes lie in [0, pi/2], the
 * azimuth axis in [0, pi].
 */
typedef struct brdffit_axes {
    const double *theta_i; /**< Light polar angles. */
    size_t n_theta_i;      /**< Number of light polar angles (>= 1). */
    const double *theta_o; /**< View polar angles. */
    size_t n_theta_o;      /**< Number of view polar angles (>= 1). */
    const double *phi_o;   /**< View azimuths. */
    size_t n_phi_o;        /**< Number of view azimuths (>= 1). */
} brdffit_axes;

/** @brief The default angle cap, 75 degrees, in radians. */
#define BRDFFIT_DEFAULT_CAP 1.3089969389957472

#ifdef __cplusplus
extern "C" {
#endif

/**
 * @brief The thesis's measurement layout: theta_i = 0..90 deg step 5
 *        (19 values), theta_o = 0..90 deg step 2.5 (37), phi_o = 0..180 deg
 *        in 35 steps (36 values).
 * @return A pointer to static, read-only data; never NULL. Thread-safe.
 */
BRDFFIT_API const brdffit_axes *brdffit_axes_default(void);

/**
 * @brief Create a regular grid from memory.
 *
 * @param[out] out        Receives the new grid; set to NULL on failure.
 * @param axes            The three axes (copied).
 * @param n_channels      Channels per sample, 1 or more.
 * @param values          n_samples * n_channels values, interleaved, sample
 *                        order as in the file comment (copied). Each must be
 *                        finite unless marked missing; negative values
 *                        (measurement noise) are kept as data.
 * @param missing         NULL, or one byte per value (same layout as
 *                        @p values); non-zero marks the value missing
 *                        (copied).
 * @param alloc           Allocator for the grid's whole life, or NULL.
 * @param[out] err        NULL, or receives the detail on failure.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT for NULL pointers, zero
 *         sizes, an allocator lacking a function, or axes that are not
 *         strictly increasing; ::BRDFFIT_E_RANGE for angles out of range
 *         or (non-missing) values that are not finite; the
 *         message names the axis index or the sample and channel;
 *         ::BRDFFIT_E_TOO_LARGE when the sizes overflow (checked before any
 *         array is read); ::BRDFFIT_E_OUT_OF_MEMORY.
 * @note Every derived quantity (directions, half vector, clamped dot
 *       products) is computed once here and stays finite at grazing angles.
 *       Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_grid_create_regular(brdffit_grid **out,
                                                       const brdffit_axes *axes,
                                                       size_t n_channels,
                                                       const double *values,
                                                       const unsigned char *missing,
                                                       const brdffit_allocator *alloc,
                                                       brdffit_error *err);

/**
 * @brief Create a scattered grid from memory.
 *
 * @param[out] out        Receives the new grid; set to NULL on failure.
 * @param n_samples       Number of samples, 1 or more.
 * @param theta_i,phi_i   Light direction of each sample (copied).
 * @param theta_o,phi_o   View direction of each sample (copied). Polar
 *                        angles in [0, pi/2], azimuths in [-2 pi, 2 pi].
 * @param n_channels      Channels per sample, 1 or more.
 * @param values          n_samples * n_channels values, interleaved (copied).
 * @param missing         NULL, or one byte per value; non-zero = missing.
 * @param weights         NULL for uniform solid-angle weights, or one
 *                        finite weight >= 0 per sample (copied), in the
 *                        input order.
 * @param alloc           Allocator for the grid's whole life, or NULL.
 * @param[out] err        NULL, or receives the detail on failure.
 * @return As brdffit_grid_create_regular().
 * @note The samples are stored sorted by max(theta_i, theta_o), ascending
 *       and stable (samples with equal keys keep their input order); see
 *       the file comment. The angles themselves are not stored: they are
 *       recovered from the directions (brdffit_grid_sample_angles()).
 *       O(n) work besides the per-sample geometry. Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_grid_create_scattered(brdffit_grid **out,
                                                         size_t n_samples,
                                                         const double *theta_i,
                                                         const double *phi_i,
                                                         const double *theta_o,
                                                         const double *phi_o,
                                                         size_t n_channels,
                                                         const double *values,
                                                         const unsigned char *missing,
                                                         const double *weights,
                                                         const brdffit_allocator *alloc,
                                                         brdffit_error *err);

/**
 * @brief Destroy a grid and free all its memory through its allocator.
 *        NULL, and a handle that is not a live grid, are ignored.
 * @note Not thread-safe with respect to other uses of the same grid.
 */
BRDFFIT_API void brdffit_grid_destroy(brdffit_grid *grid);

/** @brief The grid's form; 0 for a NULL or invalid handle. Thread-safe. */
BRDFFIT_API brdffit_grid_kind brdffit_grid_get_kind(const brdffit_grid *grid);

/** @brief Number of samples (direction pairs); 0 for NULL. Thread-safe. */
BRDFFIT_API size_t brdffit_grid_sample_count(const brdffit_grid *grid);

/** @brief Number of channels per sample; 0 for NULL. Thread-safe. */
BRDFFIT_API size_t brdffit_grid_channel_count(const brdffit_grid *grid);

/** @brief Number of values marked missing; 0 for NULL. Thread-safe. */
BRDFFIT_API size_t brdffit_grid_missing_count(const brdffit_grid *grid);

/**
 * @brief One axis of a regular grid.
 * @param grid       A regular grid.
 * @param axis       Which axis.
 * @param[out] values Receives a pointer to the axis values (radians), owned
 *                   by the grid and valid until it is destroyed.
 * @param[out] count Receives the number of values.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT for NULL arguments or an
 *         unknown axis; ::BRDFFIT_E_BAD_HANDLE; ::BRDFFIT_E_UNSUPPORTED for
 *         a scattered grid.
 * @note Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_grid_axis(const brdffit_grid *grid, brdffit_axis axis,
                                             const double **values, size_t *count);

/**
 * @brief The light and view directions of one sample, in radians.
 *
 * For a regular grid these are exactly the axis values, and phi_i is pi.
 * For a scattered grid they are recovered from the stored unit vectors:
 * theta = atan2(sqrt(x^2 + y^2), z), phi = atan2(y, x), so they describe
 * the same directions as the input (to rounding), with phi in [-pi, pi].
 * Any output pointer may be NULL.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT for a NULL grid or a
 *         sample index out of range; ::BRDFFIT_E_BAD_HANDLE. Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_grid_sample_angles(const brdffit_grid *grid, size_t sample,
                                                      double *theta_i, double *phi_i,
                                                      double *theta_o, double *phi_o);

/**
 * @brief The stored values of one channel.
 * @param grid        The grid.
 * @param channel     Channel index, below brdffit_grid_channel_count().
 * @param[out] values Receives a pointer to brdffit_grid_sample_count()
 *                    values in sample order (missing ones read 0), owned by
 *                    the grid and valid until it is destroyed.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT;
 *         ::BRDFFIT_E_BAD_HANDLE. Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_grid_values(const brdffit_grid *grid, size_t channel,
                                               const double **values);

/**
 * @brief Whether one value is missing.
 * @return 1 if missing, 0 if present or if the arguments are out of range.
 *         Thread-safe.
 */
BRDFFIT_API int brdffit_grid_is_missing(const brdffit_grid *grid, size_t sample,
                                        size_t channel);

/**
 * @brief Number of samples with theta_i <= cap and theta_o <= cap (with
 *        the tolerance of the file comment).
 *
 * For a scattered grid these are the first samples in stored order.
 * @param grid The grid.
 * @param cap  Angle cap in radians, 0 .. pi/2.
 * @return The count; 0 for NULL or a cap outside its range. O(log n).
 *         Thread-safe.
 */
BRDFFIT_API size_t brdffit_grid_active_count(const brdffit_grid *grid, double cap);

/**
 * @brief The residual weight of every sample (docs/definitions.md, Weights, eq. 4.25).
 *
 * out[s] is the factor that multiplies (measured - model) in the residual,
 * the product of two factors, each 1 when switched off by @p flags:
 * - ::BRDFFIT_WEIGHT_SOLID_ANGLE, regular grid: the solid angle of the
 *   sample's view cell divided by the sum of the cells within the cap of
 *   one view hemisphere (one theta_i). The cell of (theta_o[j], phi_o[k])
 *   spans (phi_hi - phi_lo) * (cos theta_lo - cos theta_hi): in theta from
 *   theta_o[0] (j = 0) or the midpoint to the previous value, to the
 *   midpoint to the next value; the last value within the cap ends at
 *   min(cap, midpoint to the next value), or at itself when it is the last
 *   axis value. In phi likewise from phi_o[0] to phi_o[last] with midpoints
 *   between. So border cells are halves and corners quarters, and a full
 *   0..pi/2 x 0..pi axis set with a cap c on or below the midpoint after an
 *   axis value sums to exactly pi (1 - cos c).
 * - ::BRDFFIT_WEIGHT_SOLID_ANGLE, scattered grid: the given weight of the
 *   sample (or 1) divided by the sum of the given weights of the samples
 *   within the cap.
 * - ::BRDFFIT_WEIGHT_COSINE: max(cos theta_i, 0).
 * Samples beyond the cap get 0. Missing values do not change the weights.
 *
 * @param grid     The grid.
 * @param cap      Angle cap in radians, 0 .. pi/2.
 * @param flags    A combination of ::brdffit_weighting flags.
 * @param[out] out brdffit_grid_sample_count() doubles.
 * @param[out] err NULL, or the detail on failure.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT for NULL arguments, a
 *         cap out of range or unknown flags; ::BRDFFIT_E_BAD_HANDLE;
 *         ::BRDFFIT_E_NO_DATA when no sample lies within the cap, or when
 *         the solid-angle weights within it sum to 0 (for example a cap
 *         of 0, or given weights that are all 0); ::BRDFFIT_E_OUT_OF_MEMORY
 *         (a few per-axis values are allocated through the grid's
 *         allocator). Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_grid_weights(const brdffit_grid *grid, double cap,
                                                unsigned flags, double *out,
                                                brdffit_error *err);

/**
 * @brief A new single-channel grid holding the mean over channels (the
 *        thesis's monochrome stage, eq. 4.26).
 *
 * Missing values are left out of each mean; a sample whose values are all
 * missing is missing in the result. Everything else (axes, sample order,
 * directions, given sample weights) is copied from @p grid.
 * @param[out] out Receives the new grid (owned by the caller); NULL on
 *                 failure.
 * @param grid     The source grid.
 * @param alloc    Allocator for the new grid, or NULL.
 * @param[out] err NULL, or the detail on failure.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT;
 *         ::BRDFFIT_E_BAD_HANDLE; ::BRDFFIT_E_OUT_OF_MEMORY. Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_grid_channel_mean(brdffit_grid **out,
                                                     const brdffit_grid *grid,
                                                     const brdffit_allocator *alloc,
                                                     brdffit_error *err);

/**
 * @brief A new grid with clear-coat compensation (docs/definitions.md, eq. 4.20):
 *        every value divided by (1 - F(theta_i)), F the Schlick Fresnel
 *        term F = r0 + (1 - r0) (1 - cos theta_i)^5.
 *
 * The Fresnel angle is the light's polar angle theta_i of each sample.
 * cos theta_i is clamped to at least 1e-4, so the divisor stays positive at
 * grazing light. Missing values stay missing; everything but the values is
 * copied from @p grid.
 * @param[out] out Receives the new grid (owned by the caller); NULL on
 *                 failure.
 * @param grid     The source grid.
 * @param r0       Reflection coefficient of the coat at normal incidence,
 *                 0 <= r0 < 1.
 * @param alloc    Allocator for the new grid, or NULL.
 * @param[out] err NULL, or the detail on failure.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT (also for r0 outside
 *         [0, 1)); ::BRDFFIT_E_BAD_HANDLE; ::BRDFFIT_E_RANGE when a
 *         compensated value overflows; ::BRDFFIT_E_OUT_OF_MEMORY.
 *         Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_grid_clearcoat(brdffit_grid **out, const brdffit_grid *grid,
                                                  double r0, const brdffit_allocator *alloc,
                                                  brdffit_error *err);

/**
 * @brief The measured BRDF at an arbitrary light/view pair, interpolated
 *        from a regular grid.
 *
 * Isotropy reduces the pair to (theta_i, theta_o, d), d = |phi_o - phi_i|
 * wrapped into [0, pi]; with the light at azimuth pi the stored azimuth is
 * pi - d (so phi_i = pi and a stored phi_o address the node exactly).
 * Reciprocity swaps light and view when theta_i lies outside the theta_i
 * axis range and theta_o inside it. Values are interpolated trilinearly;
 * neighbours with zero weight or a missing value are left out and the
 * others renormalised, so a node returns its stored value exactly; angles
 * beyond an axis are clamped to its end.
 *
 * @param grid        A regular grid.
 * @param theta_i,phi_i Light direction, radians.
 * @param theta_o,phi_o View direction, radians.
 * @param[out] out    brdffit_grid_channel_count() values.
 * @param[out] err    NULL, or the detail on failure.
 * @return ::BRDFFIT_OK; ::BRDFFIT_E_INVALID_ARGUMENT for NULL arguments or
 *         non-finite angles; ::BRDFFIT_E_BAD_HANDLE;
 *         ::BRDFFIT_E_UNSUPPORTED for a scattered grid; ::BRDFFIT_E_NO_DATA
 *         when every neighbour of some channel is missing: those channels
 *         read 0, the others are still interpolated. Thread-safe.
 */
BRDFFIT_API brdffit_status brdffit_grid_eval(const brdffit_grid *grid, double theta_i,
                                             double phi_i, double theta_o, double phi_o,
                                             double *out, brdffit_error *err);

#ifdef __cplusplus
}
#endif

/** @} */

#endif /* BRDFFIT_GRID_H */
