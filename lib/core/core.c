#include "core.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void *default_alloc(size_t size, void *ctx)
{
    (void)ctx;
    return malloc(size);
}

static void default_free(void *ptr, void *ctx)
{
    (void)ctx;
    free(ptr);
}

int bf_alloc_init(brdffit_allocator *dst, const brdffit_allocator *src)
{
    if (src == NULL) {
        dst->alloc = default_alloc;
        dst->free = default_free;
        dst->ctx = NULL;
        return 1;
    }
    if (src->alloc == NULL || src->free == NULL) return 0;
    *dst = *src;
    return 1;
}

void *bf_malloc(const brdffit_allocator *a, size_t size)
{
    return a->alloc(size ? size : 1, a->ctx);
}

void *bf_calloc(const brdffit_allocator *a, size_t n, size_t size)
{
    size_t total;
    void *p;
    if (!bf_mul_size(n, size, &total)) return NULL;
    p = bf_malloc(a, total);
    if (p != NULL) memset(p, 0, total ? total : 1);
    return p;
}

void bf_free(const brdffit_allocator *a, void *ptr)
{
    if (ptr != NULL) a->free(ptr, a->ctx);
}

char *bf_strdup(const brdffit_allocator *a, const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = bf_malloc(a, n);
    if (d != NULL) memcpy(d, s, n);
    return d;
}

int bf_mul_size(size_t a, size_t b, size_t *out)
{
    if (a != 0 && b > SIZE_MAX / a) return 0;
    *out = a * b;
    return 1;
}

BF_VECTOR_CLONES
int bf_all_finite(const double *x, size_t n)
{
    /* the exponent field plus one carries into the top bit exactly when it
     * is all ones (an infinity or a NaN): adds, ands and ors alone, which
     * vectorise with the baseline instruction set */
    const uint64_t exponent = UINT64_C(0x7ff0000000000000), one = UINT64_C(1) << 52;
    uint64_t bad = 0;
    size_t i;
    for (i = 0; i < n; i++) {
        uint64_t u;
        memcpy(&u, &x[i], sizeof u);
        bad |= (u & exponent) + one;
    }
    return (bad >> 63) == 0;
}

int bf_add_size(size_t a, size_t b, size_t *out)
{
    if (b > SIZE_MAX - a) return 0;
    *out = a + b;
    return 1;
}

brdffit_status bf_vfail(brdffit_error *err, brdffit_status status, const char *fmt, va_list ap)
{
    if (err != NULL) {
        err->status = status;
        vsnprintf(err->message, sizeof err->message, fmt, ap);
    }
    return status;
}

brdffit_status bf_fail(brdffit_error *err, brdffit_status status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    bf_vfail(err, status, fmt, ap);
    va_end(ap);
    return status;
}

void bf_format(char *buf, size_t size, const char *fmt, ...)
{
    va_list ap;
    if (size == 0) return;
    va_start(ap, fmt);
    vsnprintf(buf, size, fmt, ap);
    va_end(ap);
}
