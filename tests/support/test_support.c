#include "test_support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* Each block carries its size in front so live bytes can be counted. */
typedef union header { size_t size; max_align_t align; } header;

static void *ca_alloc(size_t size, void *ctx)
{
    counting_alloc *ca = ctx;
    header *h;
    ca->allocs++;
    if (ca->fail_at != 0 && ca->allocs == ca->fail_at) return NULL;
    h = malloc(sizeof(header) + size);
    if (h == NULL) return NULL;
    h->size = size;
    ca->live++;
    ca->live_bytes += size;
    if (ca->live_bytes > ca->peak_bytes) ca->peak_bytes = ca->live_bytes;
    return h + 1;
}

static void ca_free(void *ptr, void *ctx)
{
    counting_alloc *ca = ctx;
    header *h = (header *)ptr - 1;
    ca->frees++;
    ca->live--;
    ca->live_bytes -= h->size;
    free(h);
}

void counting_alloc_init(counting_alloc *ca, size_t fail_at)
{
    ca->hook.alloc = ca_alloc;
    ca->hook.free = ca_free;
    ca->hook.ctx = ca;
    ca->allocs = ca->frees = ca->live = ca->live_bytes = ca->peak_bytes = 0;
    ca->fail_at = fail_at;
}

void assert_close_impl(double a, double b, double tol, const char *what, const char *file,
                       int line)
{
    double scale = fabs(b) > 1.0 ? fabs(b) : 1.0;
    if (!(fabs(a - b) <= tol * scale)) {
        print_error("%s = %.17g, expected %.17g (tol %g)\n", what, a, b, tol);
        _fail(file, line);
    }
}

int test_quick(void)
{
    return getenv("BRDFFIT_TEST_QUICK") != NULL;
}
