/**
 * @file status.h
 * @brief Status codes returned by every fallible function, and the error
 *        record that creation functions fill in.
 *
 * Every fallible function returns a ::brdffit_status. The values are fixed
 * forever: a code is never renumbered or reused, and new codes are only
 * appended. ::BRDFFIT_OK is zero, so `if (status)` tests for failure.
 *
 * Where the detailed message goes:
 * - functions that create a handle, and functions that read from the
 *   immutable, shareable handles (grid, model), write it into an optional
 *   caller-owned ::brdffit_error;
 * - functions that work on a mutable handle (optimizer, fit) keep it on the
 *   handle, readable through that handle's `_message` function.
 * There is no global error state.
 */
#ifndef BRDFFIT_STATUS_H
#define BRDFFIT_STATUS_H

#include "brdffit/export.h"

/** @defgroup status Status codes and errors
 * @{ */

/**
 * @brief The status list: X(name, value, description). The single source of
 *        the enum and of brdffit_status_string().
 */
#define BRDFFIT_STATUS_LIST(X)                                                      \
    X(BRDFFIT_OK, 0, "success")                                                     \
    X(BRDFFIT_E_INVALID_ARGUMENT, 1, "invalid argument")                            \
    X(BRDFFIT_E_OUT_OF_MEMORY, 2, "out of memory")                                  \
    X(BRDFFIT_E_IO, 3, "file could not be opened or read")                          \
    X(BRDFFIT_E_PARSE, 4, "malformed input")                                        \
    X(BRDFFIT_E_RANGE, 5, "value out of its valid range")                           \
    X(BRDFFIT_E_INCOMPLETE_GRID, 6, "grid combination missing")                     \
    X(BRDFFIT_E_DUPLICATE, 7, "grid combination given twice")                       \
    X(BRDFFIT_E_FORMAT, 8, "binary file has the wrong size or layout")              \
    X(BRDFFIT_E_TOO_LARGE, 9, "size too large")                                     \
    X(BRDFFIT_E_UNSUPPORTED, 10, "operation not supported for this object")        \
    X(BRDFFIT_E_MODEL_FAILED, 11, "model evaluation failed")                        \
    X(BRDFFIT_E_NONFINITE, 12, "non-finite number where a finite one is required")  \
    X(BRDFFIT_E_NO_DATA, 13, "no usable samples")                                   \
    X(BRDFFIT_E_CALLBACK_FAILED, 14, "user callback failed")                        \
    X(BRDFFIT_E_BAD_HANDLE, 15, "handle is invalid or was destroyed")               \
    X(BRDFFIT_E_NOT_FOUND, 16, "no such name")                                      \
    X(BRDFFIT_E_NUMERICAL, 17, "numerical failure")                                 \
    X(BRDFFIT_E_NOT_READY, 18, "no result available yet")

/** @cond BRDFFIT_INTERNAL */
#define BRDFFIT_STATUS_ENUM_ENTRY_(name, value, text) name = value,
/** @endcond */

/** @brief Status of a call: ::BRDFFIT_OK (0) or an error code. */
typedef enum brdffit_status {
    BRDFFIT_STATUS_LIST(BRDFFIT_STATUS_ENUM_ENTRY_)
    BRDFFIT_STATUS_MAX_ /**< One past the largest code; not a status. */
} brdffit_status;

/** @brief Size of the message buffer in ::brdffit_error, terminator included. */
#define BRDFFIT_ERROR_MESSAGE_SIZE 256

/**
 * @brief Detailed error record filled in by creation functions and by
 *        functions that read shared handles.
 *
 * Caller-owned; pass NULL where the detail is not wanted. On failure the
 * function sets @c status to the code it returns and writes a NUL-terminated
 * message (truncated to fit) naming what is wrong and where (for example a
 * file's line and column). On success the record is left untouched. The
 * layout of this struct is fixed forever.
 */
typedef struct brdffit_error {
    brdffit_status status;                      /**< The code returned. */
    char message[BRDFFIT_ERROR_MESSAGE_SIZE];   /**< What went wrong, and where. */
} brdffit_error;

#ifdef __cplusplus
extern "C" {
#endif

/**
 * @brief A short static description of a status code.
 * @param status Any value; unknown values give "unknown status".
 * @return A static string; never NULL; the caller must not free it.
 *         Thread-safe.
 */
BRDFFIT_API const char *brdffit_status_string(brdffit_status status);

/**
 * @brief The symbolic name of a status code, such as "BRDFFIT_E_PARSE".
 * @param status Any value; unknown values give "BRDFFIT_UNKNOWN".
 * @return A static string; never NULL; the caller must not free it.
 *         Thread-safe.
 */
BRDFFIT_API const char *brdffit_status_name(brdffit_status status);

#ifdef __cplusplus
}
#endif

/** @} */

#endif /* BRDFFIT_STATUS_H */
