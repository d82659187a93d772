/* Shared helpers for the CMocka tests. */
#ifndef BRDFFIT_TEST_SUPPORT_H
#define BRDFFIT_TEST_SUPPORT_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "brdffit/brdffit.h"

/* An allocator that counts, and fails the Nth allocation (fail_at = N,
 * 1-based; 0 never fails). */
typedef struct counting_alloc {
    brdffit_allocator hook; /* pass &ca.hook to the library */
    size_t allocs, frees, live, fail_at, live_bytes, peak_bytes;
} counting_alloc;

void counting_alloc_init(counting_alloc *ca, size_t fail_at);

/* Assert |a - b| <= tol * max(1, |b|). */
#define assert_close(a, b, tol) assert_close_impl((a), (b), (tol), #a, __FILE__, __LINE__)
void assert_close_impl(double a, double b, double tol, const char *what, const char *file,
                       int line);

/* Nonzero when BRDFFIT_TEST_QUICK is set (the valgrind runs): the slowest
 * tests then sample fewer points, keeping every code path and assertion. */
int test_quick(void);

#define DEG(x) ((x) * 3.14159265358979323846 / 180.0)

#endif
