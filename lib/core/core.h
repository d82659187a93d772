/* Internal helpers shared by every module: allocation through the
 * per-handle allocator, checked size arithmetic, error reporting and
 * handle magic numbers. Not installed. */
#ifndef BRDFFIT_CORE_H
#define BRDFFIT_CORE_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include "brdffit/alloc.h"
#include "brdffit/status.h"

/* Handle magic numbers: the first member of every handle, cleared on
 * destroy, so that a destroyed or foreign handle is detected where
 * possible. */
#define BF_MAGIC_GRID UINT32_C(0x47524944)      /* "GRID" */
#define BF_MAGIC_MODEL UINT32_C(0x4d4f444c)     /* "MODL" */
#define BF_MAGIC_OPTIMIZER UINT32_C(0x4f50544d) /* "OPTM" */
#define BF_MAGIC_FIT UINT32_C(0x46495454)       /* "FITT" */
#define BF_MAGIC_DEAD UINT32_C(0xdeadbeef)

/* Copy *src into *dst, or the malloc/free default when src is NULL.
 * Returns 0 when src is incomplete (one of alloc/free missing). */
int bf_alloc_init(brdffit_allocator *dst, const brdffit_allocator *src);

/* Allocate through the allocator; size 0 allocates 1 byte. NULL on failure. */
void *bf_malloc(const brdffit_allocator *a, size_t size);
/* Allocate n * size zeroed bytes; NULL on overflow or failure. */
void *bf_calloc(const brdffit_allocator *a, size_t n, size_t size);
/* Free; NULL is a no-op. */
void bf_free(const brdffit_allocator *a, void *ptr);
/* Duplicate a string; NULL on failure. */
char *bf_strdup(const brdffit_allocator *a, const char *s);

/* *out = a * b; returns 0 on overflow. */
int bf_mul_size(size_t a, size_t b, size_t *out);
/* *out = a + b; returns 0 on overflow. */
int bf_add_size(size_t a, size_t b, size_t *out);
/* Whether x[0 .. n) are all finite: one branch-free sweep over the
 * exponent bits, which vectorises (a check of every output of a model). */
int bf_all_finite(const double *x, size_t n);

/* Record an error in err (may be NULL) and return status. */
brdffit_status bf_fail(brdffit_error *err, brdffit_status status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
/* Same with a va_list. */
brdffit_status bf_vfail(brdffit_error *err, brdffit_status status, const char *fmt,
                        va_list ap);

/* Format into a fixed buffer (always NUL-terminated). */
void bf_format(char *buf, size_t size, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* Early returns. */
#define BF_RETURN_IF_ERROR(expr)                 \
    do {                                         \
        brdffit_status bf_st_ = (expr);          \
        if (bf_st_ != BRDFFIT_OK) return bf_st_; \
    } while (0)

/* Hot sample loops (with everything they call inlined) are compiled twice
 * on x86-64, for the baseline (SSE2) and for AVX2,
 * and the better one is picked when the library is loaded. The AVX2 clone
 * does not use FMA, so both give bit-identical results. BF_WIDE_CLONES adds
 * an AVX-512 clone, also without FMA, for loops bound by the latency of
 * long per-row chains, which twice the lanes halve (the objective's rows,
 * fit/pass_generic.c; tests/test_pass_objectives.c checks the version the
 * machine runs against plain C); loops of short sums stay on
 * BF_VECTOR_CLONES, whose AVX-512 clones ran slower. Not under
 * ThreadSanitizer: it instruments the clone resolvers, which run while the
 * program is loaded, before its runtime is set up, and crash there. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__ELF__) && \
    !defined(BRDFFIT_NO_CLONES) && !defined(__SANITIZE_THREAD__)
#define BF_VECTOR_CLONES __attribute__((flatten, target_clones("avx2", "default")))
#define BF_WIDE_CLONES __attribute__((flatten, target_clones("avx512f", "avx2", "default")))
#else
#define BF_VECTOR_CLONES
#define BF_WIDE_CLONES
#endif

#define BF_PI 3.14159265358979323846
#define BF_HALF_PI 1.57079632679489661923
/* Floor of every clamped dot product (docs/definitions.md, Geometry). */
#define BF_DOT_FLOOR 1e-4

#endif /* BRDFFIT_CORE_H */
