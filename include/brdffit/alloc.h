/**
 * @file alloc.h
 * @brief The per-handle allocator hook.
 *
 * Every function that creates a handle takes an optional allocator. The
 * handle keeps a copy of it and uses it for every allocation it ever makes,
 * including the ones made later by functions working on that handle, and
 * for freeing them. NULL selects the C library's malloc() and free().
 * There is no process-wide allocator.
 */
#ifndef BRDFFIT_ALLOC_H
#define BRDFFIT_ALLOC_H

#include <stddef.h>

#include "brdffit/export.h"

/** @defgroup alloc Allocator hook
 * @{ */

/**
 * @brief A user allocator. The layout of this struct is fixed forever.
 *
 * @c alloc returns memory aligned for any object type (as malloc() does),
 * or NULL on failure, which the library reports as
 * ::BRDFFIT_E_OUT_OF_MEMORY. @c free releases a pointer returned by
 * @c alloc and is never called with NULL. Both receive @c ctx last. If
 * handles made with one allocator are used from several threads, the
 * allocator must be thread-safe.
 */
typedef struct brdffit_allocator {
    void *(*alloc)(size_t size, void *ctx); /**< Allocate @p size bytes (size > 0). */
    void (*free)(void *ptr, void *ctx);     /**< Release memory from @c alloc. */
    void *ctx;                              /**< Passed to both, last. */
} brdffit_allocator;

/** @} */

#endif /* BRDFFIT_ALLOC_H */
