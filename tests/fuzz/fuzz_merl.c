/* libFuzzer harness for the MERL loader (brdffit_load_merl_buffer), in
 * both forms.
 *
 * A complete MERL file has 35 MB, far beyond what a fuzzer mutates, so an
 * input that starts with 'S' is a sparse description instead: a mode byte
 * (bit 0 selects the regular form, bit 1 adds a run with a failing
 * allocation), then records of 12 bytes (a little-endian uint32 value index
 * into the 3 x 90 x 90 x 180 values, then the 8 bytes of a double) written
 * into a complete file whose other values are -1 (unmeasured). Any other
 * input goes to the loader as it is, in both forms, which exercises the
 * header and size checks. */
#include "fuzz_common.h"

#define MERL_CELLS ((size_t)90 * 90 * 180)
#define MERL_SIZE ((size_t)12 + 3 * MERL_CELLS * 8)
#define MAX_RECORDS 4096

/* The file image is built once and restored after every sparse input. */
static unsigned char *image;

static void put_value(size_t index, const unsigned char bytes[8])
{
    memcpy(image + 12 + index * 8, bytes, 8);
}

static void unmeasured(unsigned char bytes[8])
{
    double v = -1.0;
    unsigned long long u;
    int k;
    memcpy(&u, &v, sizeof u);
    for (k = 0; k < 8; k++) bytes[k] = (unsigned char)(u >> (8 * k));
}

static int image_init(void)
{
    unsigned char neg[8];
    size_t k;
    if (image != NULL) return 1;
    image = malloc(MERL_SIZE);
    if (image == NULL) return 0;
    image[0] = 90, image[1] = image[2] = image[3] = 0;
    image[4] = 90, image[5] = image[6] = image[7] = 0;
    image[8] = 180, image[9] = image[10] = image[11] = 0;
    unmeasured(neg);
    for (k = 0; k < 3 * MERL_CELLS; k++) put_value(k, neg);
    return 1;
}

/* Load in one form; with `oom`, load again failing one of the allocations. */
static void load_form(const unsigned char *data, size_t size, int regular, int oom,
                      size_t fail_seed)
{
    const brdffit_axes *axes = regular ? brdffit_axes_default() : NULL;
    brdffit_grid *g = NULL;
    brdffit_error err;
    fuzz_alloc fa;
    brdffit_status st;
    size_t allocs;
    fuzz_alloc_init(&fa, 0);
    st = brdffit_load_merl_buffer(&g, data, size, axes, &fa.hook, &err);
    allocs = fa.allocs;
    if (st == BRDFFIT_OK) {
        fuzz_require(brdffit_grid_channel_count(g) == 3);
        fuzz_check_grid(g);
        brdffit_grid_destroy(g);
    } else {
        fuzz_check_failure(st, g, &err);
    }
    fuzz_require(fa.live == 0);
    if (!oom || allocs == 0) return;
    fuzz_alloc_init(&fa, 1 + fail_seed % allocs);
    g = NULL;
    st = brdffit_load_merl_buffer(&g, data, size, axes, &fa.hook, &err);
    fuzz_require(st == BRDFFIT_E_OUT_OF_MEMORY);
    fuzz_check_failure(st, g, &err);
    fuzz_require(fa.live == 0);
}

static size_t record_index(const unsigned char *r)
{
    unsigned long u = (unsigned long)r[0] | (unsigned long)r[1] << 8 | (unsigned long)r[2] << 16 |
                      (unsigned long)r[3] << 24;
    return (size_t)(u % (3 * MERL_CELLS));
}

/* 'S', a mode byte (bit 0: regular form, bit 1: also fail an allocation),
 * then the records. */
static void sparse_input(const unsigned char *data, size_t size)
{
    size_t n = size < 2 ? 0 : (size - 2) / 12, k;
    unsigned char neg[8];
    const unsigned char *rec = data + 2;
    if (size < 2) return;
    if (n > MAX_RECORDS) n = MAX_RECORDS;
    if (!image_init()) return;
    for (k = 0; k < n; k++) put_value(record_index(rec + 12 * k), rec + 12 * k + 4);
    load_form(image, MERL_SIZE, data[1] & 1, (data[1] & 2) != 0, size);
    unmeasured(neg);
    for (k = 0; k < n; k++) put_value(record_index(rec + 12 * k), neg);
}

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size)
{
    if (size >= 1 && data[0] == 'S') {
        sparse_input(data, size);
        return 0;
    }
    load_form(data, size, 0, 1, size);
    load_form(data, size, 1, 1, size);
    return 0;
}
