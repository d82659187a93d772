/* API misuse across every public header: NULL handles and outputs, zero
 * and mismatched sizes, destroyed and foreign handles, values out of range,
 * unknown enum values, NaN and Inf in setters, failing callbacks. Every
 * case asserts the exact status and, where the function has one, that a
 * message was written (brdffit_error, brdffit_fit_message(),
 * brdffit_optimizer_message()). A failed call changes nothing.
 *
 * Destroyed handles are made with an allocator that keeps every block
 * until the test ends, so reading a destroyed handle is well defined (the
 * library marks it dead before it frees it) and AddressSanitizer-clean. */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fit_fixtures.h"
#include "grid_fixtures.h"
#include "test_support.h"

/* ---- an allocator that never really frees ------------------------------- */

typedef struct keep_alloc {
    brdffit_allocator hook;
    void **blocks;
    size_t n, cap;
    size_t allocs, frees;
} keep_alloc;

static void *keep_alloc_fn(size_t size, void *ctx)
{
    keep_alloc *ka = ctx;
    void *p;
    if (ka->n == ka->cap) {
        size_t cap = ka->cap ? 2 * ka->cap : 64;
        void **b = realloc(ka->blocks, cap * sizeof *b);
        if (b == NULL) return NULL;
        ka->blocks = b;
        ka->cap = cap;
    }
    p = malloc(size);
    if (p == NULL) return NULL;
    ka->blocks[ka->n++] = p;
    ka->allocs++;
    return p;
}

static void keep_free_fn(void *ptr, void *ctx)
{
    keep_alloc *ka = ctx;
    (void)ptr;
    ka->frees++;
}

static void keep_init(keep_alloc *ka)
{
    memset(ka, 0, sizeof *ka);
    ka->hook.alloc = keep_alloc_fn;
    ka->hook.free = keep_free_fn;
    ka->hook.ctx = ka;
}

/* Every block, at the end of the test. */
static void keep_release(keep_alloc *ka)
{
    size_t i;
    for (i = 0; i < ka->n; i++) free(ka->blocks[i]);
    free(ka->blocks);
    memset(ka, 0, sizeof *ka);
}

/* A non-NULL address that a failing creation function must overwrite with
 * NULL. */
static max_align_t sentinel_storage;
#define SENTINEL ((void *)&sentinel_storage)

/* An allocator that refuses blocks above 1 GiB (so huge requests fail the
 * same way in sanitizer builds, whose malloc would abort instead). */
static void *limited_alloc(size_t size, void *ctx)
{
    (void)ctx;
    return size > ((size_t)1 << 30) ? NULL : malloc(size);
}

static void limited_free(void *ptr, void *ctx)
{
    (void)ctx;
    free(ptr);
}

static const brdffit_allocator LIMITED_ALLOC = {limited_alloc, limited_free, NULL};

/* ---- expectations ------------------------------------------------------------ */

static void reset_err(brdffit_error *e)
{
    e->status = (brdffit_status)-1;
    memset(e->message, 'x', sizeof e->message);
    e->message[0] = '\0';
}

static void check_err_impl(brdffit_status want, brdffit_status got, const brdffit_error *e,
                           const char *call, int line)
{
    if (got != want || e->status != want || e->message[0] == '\0' ||
        strlen(e->message) >= sizeof e->message) {
        print_error("line %d: %s\n  returned %s, error record %s \"%s\", expected %s\n", line, call,
                    brdffit_status_name(got), brdffit_status_name(e->status), e->message,
                    brdffit_status_name(want));
        _fail(__FILE__, line);
    }
}

/* A call that takes `&err` last: the exact status, recorded in err, with a
 * non-empty message. */
#define EXPECT_ERR(code, call)                                 \
    do {                                                       \
        reset_err(&err);                                       \
        check_err_impl((code), (call), &err, #call, __LINE__); \
    } while (0)

/* A status-only call. */
#define EXPECT(code, call) assert_int_equal((call), (code))

/* A call on a live fit or optimizer: the exact status and a message on the
 * handle. */
#define EXPECT_FIT(code, fit, call)                            \
    do {                                                       \
        assert_int_equal((call), (code));                      \
        assert_string_not_equal(brdffit_fit_message(fit), ""); \
    } while (0)
#define EXPECT_OPT(code, opt, call)                                  \
    do {                                                             \
        assert_int_equal((call), (code));                            \
        assert_string_not_equal(brdffit_optimizer_message(opt), ""); \
    } while (0)

/* ---- fixtures ----------------------------------------------------------------- */

static const double TI[] = {0, 30, 60}, TO[] = {0, 20, 40, 60}, PO[] = {0, 60, 120, 180};

static fx_axes axes3;

static const brdffit_axes *small_axes(void)
{
    fx_axes_set(&axes3, TI, 3, TO, 4, PO, 4);
    return &axes3.axes;
}

/* 3 x 4 x 4 = 48 samples, `nc` channels of a smooth positive function. */
static brdffit_grid *small_grid(size_t nc, const brdffit_allocator *alloc)
{
    double *v = fx_values(small_axes(), nc);
    brdffit_grid *grid = NULL;
    assert_non_null(v);
    assert_int_equal(brdffit_grid_create_regular(&grid, small_axes(), nc, v, NULL, alloc, NULL),
                     BRDFFIT_OK);
    free(v);
    return grid;
}

static brdffit_grid *scattered_grid(void)
{
    const double ti[2] = {0.1, 0.2}, pi_[2] = {0.0, 1.0}, to[2] = {0.3, 0.4}, po[2] = {2.0, 3.0};
    const double v[2] = {0.1, 0.2};
    brdffit_grid *grid = NULL;
    assert_int_equal(
        brdffit_grid_create_scattered(&grid, 2, ti, pi_, to, po, 1, v, NULL, NULL, NULL, NULL),
        BRDFFIT_OK);
    return grid;
}

static brdffit_model *model_of(const char *name, const brdffit_allocator *alloc)
{
    brdffit_model *model = NULL;
    assert_int_equal(brdffit_model_create(&model, name, alloc, NULL), BRDFFIT_OK);
    return model;
}

/* An allocator that lacks its free function. */
static void *plain_alloc(size_t size, void *ctx)
{
    (void)ctx;
    return malloc(size);
}

static const brdffit_allocator HALF_ALLOC = {plain_alloc, NULL, NULL};

/* ---- status.h ------------------------------------------------------------------- */

static void test_status_unknown_values(void **state)
{
    (void)state;
    assert_string_equal(brdffit_status_string((brdffit_status)-1), "unknown status");
    assert_string_equal(brdffit_status_string(BRDFFIT_STATUS_MAX_), "unknown status");
    assert_string_equal(brdffit_status_string((brdffit_status)9999), "unknown status");
    assert_string_equal(brdffit_status_name((brdffit_status)-1), "BRDFFIT_UNKNOWN");
    assert_string_equal(brdffit_status_name(BRDFFIT_STATUS_MAX_), "BRDFFIT_UNKNOWN");
    assert_non_null(brdffit_stop_reason_string((brdffit_stop_reason)99));
    assert_non_null(brdffit_stop_reason_string((brdffit_stop_reason)-1));
}

/* ---- grid.h ---------------------------------------------------------------------- */

static void test_grid_create_misuse(void **state)
{
    const brdffit_axes *ax = small_axes();
    double *v = fx_values(ax, 2), bad_axis[4], nan_axis[4];
    brdffit_axes a = *ax;
    brdffit_grid *g = SENTINEL;
    brdffit_error err;
    const double ti[1] = {0.1}, pi_[1] = {0.0}, to[1] = {0.2}, po[1] = {0.5}, one[1] = {0.3};
    const double nan1[1] = {NAN};
    double w[1];
    (void)state;
    assert_non_null(v);
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_grid_create_regular(NULL, ax, 2, v, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_grid_create_regular(&g, NULL, 2, v, NULL, NULL, &err));
    assert_null(g);
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_grid_create_regular(&g, ax, 0, v, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_grid_create_regular(&g, ax, 2, NULL, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_grid_create_regular(&g, ax, 2, v, NULL, &HALF_ALLOC, &err));
    a.n_phi_o = 0;
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_grid_create_regular(&g, &a, 2, v, NULL, NULL, &err));
    a = *ax;
    a.theta_o = NULL;
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_grid_create_regular(&g, &a, 2, v, NULL, NULL, &err));
    /* not strictly increasing; out of range; NaN */
    a = *ax;
    memcpy(bad_axis, ax->theta_o, 4 * sizeof(double));
    bad_axis[2] = bad_axis[1];
    a.theta_o = bad_axis;
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_grid_create_regular(&g, &a, 2, v, NULL, NULL, &err));
    bad_axis[2] = 2.0;
    bad_axis[3] = 2.1;
    EXPECT_ERR(BRDFFIT_E_RANGE, brdffit_grid_create_regular(&g, &a, 2, v, NULL, NULL, &err));
    memcpy(nan_axis, ax->theta_o, 4 * sizeof(double));
    nan_axis[1] = NAN;
    a.theta_o = nan_axis;
    EXPECT_ERR(BRDFFIT_E_RANGE, brdffit_grid_create_regular(&g, &a, 2, v, NULL, NULL, &err));
    /* sizes that overflow are refused before any array is read */
    a = *ax;
    a.n_theta_i = a.n_theta_o = a.n_phi_o = (size_t)1 << 30;
    EXPECT_ERR(BRDFFIT_E_TOO_LARGE, brdffit_grid_create_regular(&g, &a, 1, v, NULL, NULL, &err));
    a = *ax;
    EXPECT_ERR(BRDFFIT_E_TOO_LARGE,
               brdffit_grid_create_regular(&g, &a, SIZE_MAX / 8, v, NULL, NULL, &err));
    /* values: NaN, Inf (negative values are data); the message names the
     * sample and channel */
    v[5] = NAN;
    EXPECT_ERR(BRDFFIT_E_RANGE, brdffit_grid_create_regular(&g, ax, 2, v, NULL, NULL, &err));
    assert_non_null(strstr(err.message, "sample 2, channel 1"));
    v[5] = HUGE_VAL;
    EXPECT_ERR(BRDFFIT_E_RANGE, brdffit_grid_create_regular(&g, ax, 2, v, NULL, NULL, &err));
    v[5] = -HUGE_VAL;
    EXPECT_ERR(BRDFFIT_E_RANGE, brdffit_grid_create_regular(&g, ax, 2, v, NULL, NULL, &err));
    assert_null(g);

    /* scattered */
    EXPECT_ERR(
        BRDFFIT_E_INVALID_ARGUMENT,
        brdffit_grid_create_scattered(&g, 0, ti, pi_, to, po, 1, one, NULL, NULL, NULL, &err));
    EXPECT_ERR(
        BRDFFIT_E_INVALID_ARGUMENT,
        brdffit_grid_create_scattered(&g, 1, ti, NULL, to, po, 1, one, NULL, NULL, NULL, &err));
    EXPECT_ERR(
        BRDFFIT_E_INVALID_ARGUMENT,
        brdffit_grid_create_scattered(&g, 1, ti, pi_, to, po, 0, one, NULL, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_grid_create_scattered(&g, 1, ti, pi_, to, po, 1, one, NULL, NULL,
                                             &HALF_ALLOC, &err));
    EXPECT_ERR(BRDFFIT_E_RANGE, brdffit_grid_create_scattered(&g, 1, ti, pi_, nan1, po, 1, one,
                                                              NULL, NULL, NULL, &err));
    w[0] = -1.0;
    EXPECT_ERR(BRDFFIT_E_RANGE,
               brdffit_grid_create_scattered(&g, 1, ti, pi_, to, po, 1, one, NULL, w, NULL, &err));
    w[0] = NAN;
    EXPECT_ERR(BRDFFIT_E_RANGE,
               brdffit_grid_create_scattered(&g, 1, ti, pi_, to, po, 1, one, NULL, w, NULL, &err));
    w[0] = 7.0; /* phi beyond 2 pi */
    EXPECT_ERR(BRDFFIT_E_RANGE,
               brdffit_grid_create_scattered(&g, 1, ti, w, to, po, 1, one, NULL, NULL, NULL, &err));
    assert_null(g);
    free(v);
}

static void test_grid_functions_misuse(void **state)
{
    brdffit_grid *g = small_grid(2, NULL), *sc = scattered_grid(), *out = SENTINEL;
    brdffit_error err;
    const double *values;
    size_t count = 77;
    double w[48], e[2], ang = 0.0;
    (void)state;
    /* NULL handles */
    assert_int_equal(brdffit_grid_get_kind(NULL), 0);
    assert_int_equal(brdffit_grid_sample_count(NULL), 0);
    assert_int_equal(brdffit_grid_channel_count(NULL), 0);
    assert_int_equal(brdffit_grid_missing_count(NULL), 0);
    assert_int_equal(brdffit_grid_is_missing(NULL, 0, 0), 0);
    assert_int_equal(brdffit_grid_active_count(NULL, 1.0), 0);
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT,
           brdffit_grid_axis(NULL, BRDFFIT_AXIS_THETA_I, &values, &count));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_sample_angles(NULL, 0, &ang, NULL, NULL, NULL));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_values(NULL, 0, &values));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_weights(NULL, 1.0, 3, w, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_eval(NULL, 0, 0, 0, 0, e, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_channel_mean(&out, NULL, NULL, &err));
    assert_null(out);
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_clearcoat(&out, NULL, 0.1, NULL, &err));
    brdffit_grid_destroy(NULL);
    /* NULL outputs */
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_axis(g, BRDFFIT_AXIS_THETA_I, NULL, &count));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_axis(g, BRDFFIT_AXIS_THETA_I, &values, NULL));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_values(g, 0, NULL));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_weights(g, 1.0, 3, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_eval(g, 0, 0, 0, 0, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_channel_mean(NULL, g, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_clearcoat(NULL, g, 0.1, NULL, &err));
    /* indices and enums out of range: outputs untouched */
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_axis(g, (brdffit_axis)3, &values, &count));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_axis(g, (brdffit_axis)-1, &values, &count));
    assert_int_equal(count, 77);
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_sample_angles(g, 48, &ang, NULL, NULL, NULL));
    assert_true(ang == 0.0);
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_values(g, 2, &values));
    assert_int_equal(brdffit_grid_is_missing(g, 48, 0), 0);
    assert_int_equal(brdffit_grid_is_missing(g, 0, 2), 0);
    /* caps, flags and angles */
    assert_int_equal(brdffit_grid_active_count(g, NAN), 0);
    assert_int_equal(brdffit_grid_active_count(g, -0.1), 0);
    assert_int_equal(brdffit_grid_active_count(g, 1.6), 0);
    assert_int_equal(brdffit_grid_active_count(g, HUGE_VAL), 0);
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_weights(g, NAN, 3, w, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_weights(g, -1.0, 3, w, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_weights(g, HUGE_VAL, 3, w, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_weights(g, 1.0, 4, w, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_eval(g, NAN, 0, 0, 0, e, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_eval(g, 0, HUGE_VAL, 0, 0, e, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_clearcoat(&out, g, 1.0, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_clearcoat(&out, g, -0.1, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_clearcoat(&out, g, NAN, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_channel_mean(&out, g, &HALF_ALLOC, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_grid_clearcoat(&out, g, 0.1, &HALF_ALLOC, &err));
    assert_null(out);
    /* operations a scattered grid does not support */
    EXPECT(BRDFFIT_E_UNSUPPORTED, brdffit_grid_axis(sc, BRDFFIT_AXIS_PHI_O, &values, &count));
    EXPECT_ERR(BRDFFIT_E_UNSUPPORTED, brdffit_grid_eval(sc, 0.1, 0, 0.1, 0, e, &err));
    /* a success leaves the error record untouched */
    reset_err(&err);
    assert_int_equal(brdffit_grid_weights(g, 1.0, 3, w, &err), BRDFFIT_OK);
    assert_int_equal(err.status, (brdffit_status)-1);
    brdffit_grid_destroy(sc);
    brdffit_grid_destroy(g);
}

/* Destroyed and foreign handles: BRDFFIT_E_BAD_HANDLE (or 0 / NULL), and a
 * second destroy frees nothing. */
static void test_grid_destroyed_handle(void **state)
{
    keep_alloc ka;
    brdffit_grid *g, *out = NULL;
    brdffit_model *m = model_of("lambert", NULL);
    brdffit_error err;
    const double *values;
    size_t count, frees;
    double w[48], e[2], p[2] = {0.5, 0.5};
    unsigned char px[3 * 16 * 16];
    (void)state;
    keep_init(&ka);
    g = small_grid(2, &ka.hook);
    brdffit_grid_destroy(g);
    frees = ka.frees;
    assert_true(frees > 0 && frees == ka.allocs);
    brdffit_grid_destroy(g); /* ignored */
    assert_int_equal(ka.frees, frees);
    assert_int_equal(brdffit_grid_get_kind(g), 0);
    assert_int_equal(brdffit_grid_sample_count(g), 0);
    assert_int_equal(brdffit_grid_channel_count(g), 0);
    assert_int_equal(brdffit_grid_missing_count(g), 0);
    assert_int_equal(brdffit_grid_is_missing(g, 0, 0), 0);
    assert_int_equal(brdffit_grid_active_count(g, 1.0), 0);
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_grid_axis(g, BRDFFIT_AXIS_THETA_I, &values, &count));
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_grid_sample_angles(g, 0, NULL, NULL, NULL, NULL));
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_grid_values(g, 0, &values));
    EXPECT_ERR(BRDFFIT_E_BAD_HANDLE, brdffit_grid_weights(g, 1.0, 3, w, &err));
    EXPECT_ERR(BRDFFIT_E_BAD_HANDLE, brdffit_grid_eval(g, 0, 0, 0, 0, e, &err));
    EXPECT_ERR(BRDFFIT_E_BAD_HANDLE, brdffit_grid_channel_mean(&out, g, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_BAD_HANDLE, brdffit_grid_clearcoat(&out, g, 0.1, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_BAD_HANDLE, brdffit_model_eval_grid(m, g, 0, 1, p, e, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_BAD_HANDLE, brdffit_image_texture_size(g, NULL, &count, &count, &err));
    EXPECT_ERR(BRDFFIT_E_BAD_HANDLE, brdffit_image_texture(px, 48, BRDFFIT_TEXTURE_MEASURED, g,
                                                           NULL, NULL, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_BAD_HANDLE,
               brdffit_image_sphere_measured(px, 48, 16, g, 0.0, 0.0, NULL, NULL, &err));
    {
        brdffit_fit *fit = NULL;
        EXPECT_ERR(BRDFFIT_E_BAD_HANDLE, brdffit_fit_create(&fit, g, m, NULL, &err));
        assert_null(fit);
    }
    /* a model handle is not a grid */
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_grid_values((const brdffit_grid *)m, 0, &values));
    assert_int_equal(brdffit_grid_sample_count((const brdffit_grid *)m), 0);
    assert_null(out);
    brdffit_model_destroy(m);
    keep_release(&ka);
}

/* ---- load.h ------------------------------------------------------------------------ */

static void test_load_misuse(void **state)
{
    static const char csv[] = "theta_i,theta_o,phi_o,r\n0,0,0,0.5\n";
    brdffit_grid *g = SENTINEL;
    brdffit_error err;
    brdffit_axes bad = *brdffit_axes_default();
    (void)state;
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_load_csv(NULL, "x.csv", NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_load_csv(&g, NULL, NULL, &err));
    assert_null(g);
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_load_csv(&g, BRDFFIT_TEST_DATA_DIR "/sample_grid.csv", &HALF_ALLOC, &err));
    EXPECT_ERR(BRDFFIT_E_IO,
               brdffit_load_csv(&g, BRDFFIT_TEST_DATA_DIR "/no_such_file.csv", NULL, &err));
    assert_non_null(strstr(err.message, "no_such_file.csv"));
    EXPECT_ERR(BRDFFIT_E_IO,
               brdffit_load_csv(&g, BRDFFIT_TEST_DATA_DIR, NULL, &err)); /* a directory */
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_load_csv_buffer(NULL, csv, 10, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_load_csv_buffer(&g, NULL, 10, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_load_csv_buffer(&g, csv, sizeof csv - 1, &HALF_ALLOC, &err));
    EXPECT_ERR(BRDFFIT_E_PARSE, brdffit_load_csv_buffer(&g, csv, 0, NULL, &err));
    /* the size is honoured: the header alone has no data rows */
    EXPECT_ERR(BRDFFIT_E_PARSE, brdffit_load_csv_buffer(&g, csv, 24, NULL, &err));
    assert_null(g);
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_load_merl(NULL, "x.binary", NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_load_merl(&g, NULL, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_IO,
               brdffit_load_merl(&g, BRDFFIT_TEST_DATA_DIR "/no_such.binary", NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_load_merl_buffer(&g, NULL, 12, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_load_merl_buffer(NULL, csv, 12, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_load_merl_buffer(&g, csv, 12, NULL, &HALF_ALLOC, &err));
    EXPECT_ERR(BRDFFIT_E_FORMAT, brdffit_load_merl_buffer(&g, csv, 0, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_FORMAT, brdffit_load_merl_buffer(&g, csv, sizeof csv, NULL, NULL, &err));
    /* invalid axes are refused before any byte is read: the argument error,
     * not the file's */
    bad.n_phi_o = 0;
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_load_merl_buffer(&g, csv, sizeof csv, &bad, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_load_merl(&g, BRDFFIT_TEST_DATA_DIR "/no_such.binary", &bad, NULL, &err));
    bad = *brdffit_axes_default();
    bad.theta_o = NULL;
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_load_merl_buffer(&g, csv, sizeof csv, &bad, NULL, &err));
    bad = *brdffit_axes_default();
    bad.n_theta_i = bad.n_theta_o = bad.n_phi_o = (size_t)1 << 22;
    EXPECT_ERR(BRDFFIT_E_TOO_LARGE,
               brdffit_load_merl_buffer(&g, csv, sizeof csv, &bad, NULL, &err));
    assert_null(g);
}

/* ---- model.h ----------------------------------------------------------------------- */

static int destroyed;

static void count_destroy(void *user)
{
    (void)user;
    destroyed++;
}

static brdffit_status failing_eval(const brdffit_batch *b, const double *p, size_t nc,
                                   double *values, double *jac, void *user)
{
    (void)b;
    (void)p;
    (void)nc;
    (void)values;
    (void)jac;
    (void)user;
    return BRDFFIT_E_RANGE;
}

static brdffit_status nan_eval(const brdffit_batch *b, const double *p, size_t nc, double *values,
                               double *jac, void *user)
{
    size_t i;
    (void)p;
    (void)user;
    for (i = 0; i < nc * b->n; i++) values[i] = i == 3 ? NAN : 0.1;
    if (jac != NULL)
        for (i = 0; i < 2 * nc * b->n; i++) jac[i] = 0.0;
    return BRDFFIT_OK;
}

static const brdffit_param_info GOOD_PARAMS[2] = {
    {"k", BRDFFIT_PARAM_LOG_SCALE, 1e-3, 1e3, 1.0},
    {"c", BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR, 0.0, HUGE_VAL, 0.1},
};

/* A definition with one thing wrong: parameter `which` gets `bad`. */
static void expect_bad_param(brdffit_model_def *def, size_t which, brdffit_param_info bad)
{
    brdffit_param_info params[2];
    brdffit_model *m = SENTINEL;
    brdffit_error err;
    memcpy(params, GOOD_PARAMS, sizeof params);
    params[which] = bad;
    def->params = params;
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_create_custom(&m, def, NULL, &err));
    assert_null(m);
    def->params = GOOD_PARAMS;
}

static void test_model_create_misuse(void **state)
{
    brdffit_model_def def = BRDFFIT_MODEL_DEF_INIT;
    brdffit_model *m = SENTINEL;
    brdffit_error err;
    brdffit_param_info p;
    (void)state;
    brdffit_model_def_init(NULL);
    assert_null(brdffit_model_builtin_name(brdffit_model_builtin_count()));
    assert_null(brdffit_model_builtin_name((size_t)-1));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_create(NULL, "ggx", NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_create(&m, NULL, NULL, &err));
    assert_null(m);
    EXPECT_ERR(BRDFFIT_E_NOT_FOUND, brdffit_model_create(&m, "GGX", NULL, &err));
    EXPECT_ERR(BRDFFIT_E_NOT_FOUND, brdffit_model_create(&m, "", NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_create(&m, "ggx", &HALF_ALLOC, &err));

    def.name = "user";
    def.n_params = 2;
    def.params = GOOD_PARAMS;
    def.eval = failing_eval;
    def.user = &def;
    def.destroy = count_destroy;
    destroyed = 0;
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_create_custom(NULL, &def, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_create_custom(&m, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_model_create_custom(&m, &def, &HALF_ALLOC, &err));
    def.struct_size = sizeof def - 1;
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_create_custom(&m, &def, NULL, &err));
    def.struct_size = 0;
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_create_custom(&m, &def, NULL, &err));
    def.struct_size = sizeof def;
    def.name = NULL;
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_create_custom(&m, &def, NULL, &err));
    def.name = "";
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_create_custom(&m, &def, NULL, &err));
    def.name = "user";
    def.n_params = 0;
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_create_custom(&m, &def, NULL, &err));
    def.n_params = 1025;
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_create_custom(&m, &def, NULL, &err));
    def.n_params = 2;
    def.params = NULL;
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_create_custom(&m, &def, NULL, &err));
    def.params = GOOD_PARAMS;
    def.eval = NULL;
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_create_custom(&m, &def, NULL, &err));
    def.eval = failing_eval;
    p = GOOD_PARAMS[0];
    p.name = NULL;
    expect_bad_param(&def, 0, p);
    p.name = "";
    expect_bad_param(&def, 0, p);
    p.name = "c"; /* duplicate */
    expect_bad_param(&def, 0, p);
    p = GOOD_PARAMS[0];
    p.lower = NAN;
    expect_bad_param(&def, 0, p);
    p = GOOD_PARAMS[0];
    p.upper = NAN;
    expect_bad_param(&def, 0, p);
    p = GOOD_PARAMS[0];
    p.start = NAN;
    expect_bad_param(&def, 0, p);
    p.start = HUGE_VAL;
    expect_bad_param(&def, 0, p);
    p.start = 1e4; /* above upper */
    expect_bad_param(&def, 0, p);
    p = GOOD_PARAMS[0];
    p.lower = 0.0; /* log scale needs lower > 0 */
    expect_bad_param(&def, 0, p);
    p = GOOD_PARAMS[0];
    p.flags |= 64u; /* unknown flag bit */
    expect_bad_param(&def, 0, p);
    p = GOOD_PARAMS[1];
    p.flags = BRDFFIT_PARAM_LINEAR; /* linear but shared */
    expect_bad_param(&def, 1, p);
    /* no failure called the destroy callback or kept the user pointer */
    assert_int_equal(destroyed, 0);
    assert_null(m);
}

static void test_model_functions_misuse(void **state)
{
    brdffit_model *as = model_of("ashikhmin-shirley", NULL), *user = NULL;
    brdffit_grid *g = small_grid(3, NULL);
    brdffit_model_def def = BRDFFIT_MODEL_DEF_INIT;
    brdffit_error err;
    brdffit_jacobian_report rep;
    double p[7], v[3 * 48], jac[3 * 3 * 48], th[2] = {0.1, 0.2}, ph[2] = {0.0, 1.0};
    size_t idx = 99;
    (void)state;
    assert_int_equal(brdffit_model_default_params(as, 3, p), BRDFFIT_OK);
    /* NULL handles and outputs */
    assert_null(brdffit_model_name(NULL));
    assert_int_equal(brdffit_model_param_count(NULL), 0);
    assert_null(brdffit_model_param(NULL, 0));
    assert_null(brdffit_model_param(as, 3));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_param_find(NULL, "ns", &idx));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_param_find(as, NULL, &idx));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_param_find(as, "ns", NULL));
    EXPECT(BRDFFIT_E_NOT_FOUND, brdffit_model_param_find(as, "NS", &idx));
    assert_int_equal(idx, 99);
    assert_int_equal(brdffit_model_vector_size(NULL, 3), 0);
    assert_int_equal(brdffit_model_vector_size(as, 0), 0);
    assert_int_equal(brdffit_model_vector_index(NULL, 0, 0, 3), (size_t)-1);
    assert_int_equal(brdffit_model_vector_index(as, 0, 0, 0), (size_t)-1);
    assert_int_equal(brdffit_model_vector_index(as, 3, 0, 3), (size_t)-1);
    assert_int_equal(brdffit_model_vector_index(as, 1, 3, 3), (size_t)-1);
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_default_params(NULL, 3, p));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_default_params(as, 0, p));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_default_params(as, 3, NULL));
    brdffit_model_destroy(NULL);

    /* evaluation on a grid */
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_model_eval_grid(NULL, g, 0, 1, p, v, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_model_eval_grid(as, NULL, 0, 1, p, v, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_model_eval_grid(as, g, 0, 1, NULL, v, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_model_eval_grid(as, g, 0, 1, p, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_eval_grid(as, g, 40, 9, p, v, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_model_eval_grid(as, g, 1, SIZE_MAX, p, v, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_eval_grid(as, g, 49, 0, p, v, NULL, &err));
    p[0] = NAN;
    EXPECT_ERR(BRDFFIT_E_NONFINITE, brdffit_model_eval_grid(as, g, 0, 48, p, v, jac, &err));
    assert_non_null(strstr(err.message, "ns"));
    p[0] = 50.0;
    p[4] = HUGE_VAL;
    EXPECT_ERR(BRDFFIT_E_NONFINITE, brdffit_model_eval_grid(as, g, 0, 48, p, v, jac, &err));
    assert_non_null(strstr(err.message, "cs"));
    p[4] = 0.2;

    /* evaluation at angles */
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_model_eval_angles(as, 2, th, ph, th, ph, 0, p, v, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_model_eval_angles(as, 2, th, NULL, th, ph, 3, p, v, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_model_eval_angles(NULL, 2, th, ph, th, ph, 3, p, v, NULL, &err));
    th[1] = 1.6;
    EXPECT_ERR(BRDFFIT_E_RANGE,
               brdffit_model_eval_angles(as, 2, th, ph, th, ph, 3, p, v, NULL, &err));
    th[1] = -0.1;
    EXPECT_ERR(BRDFFIT_E_RANGE,
               brdffit_model_eval_angles(as, 2, th, ph, th, ph, 3, p, v, NULL, &err));
    th[1] = 0.2;
    ph[1] = NAN;
    EXPECT_ERR(BRDFFIT_E_RANGE,
               brdffit_model_eval_angles(as, 2, th, ph, th, ph, 3, p, v, NULL, &err));
    ph[1] = HUGE_VAL;
    EXPECT_ERR(BRDFFIT_E_RANGE,
               brdffit_model_eval_angles(as, 2, th, ph, th, ph, 3, p, v, NULL, &err));
    ph[1] = 1.0;

    /* the Jacobian check */
    rep.struct_size = sizeof rep;
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_check_jacobian(as, g, p, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_check_jacobian(as, g, NULL, &rep, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_check_jacobian(NULL, g, p, &rep, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_check_jacobian(as, NULL, p, &rep, &err));
    rep.struct_size = sizeof rep - 1;
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_check_jacobian(as, g, p, &rep, &err));
    rep.struct_size = sizeof rep;
    p[0] = 1e7; /* above the exponent's upper bound */
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_check_jacobian(as, g, p, &rep, &err));
    p[0] = NAN;
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_check_jacobian(as, g, p, &rep, &err));
    p[0] = 50.0;
    p[1] = -0.5; /* a colour below 0 */
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_model_check_jacobian(as, g, p, &rep, &err));
    p[1] = 0.2;

    /* user models whose callback fails or gives NaN */
    def.name = "failing";
    def.n_params = 2;
    def.params = GOOD_PARAMS;
    def.eval = failing_eval;
    assert_int_equal(brdffit_model_create_custom(&user, &def, NULL, NULL), BRDFFIT_OK);
    EXPECT_ERR(BRDFFIT_E_MODEL_FAILED, brdffit_model_eval_grid(user, g, 0, 48, p, v, NULL, &err));
    assert_non_null(strstr(err.message, "failing"));
    assert_non_null(strstr(err.message, "BRDFFIT_E_RANGE"));
    EXPECT_ERR(BRDFFIT_E_MODEL_FAILED,
               brdffit_model_eval_angles(user, 2, th, ph, th, ph, 3, p, v, NULL, &err));
    brdffit_model_destroy(user);
    def.name = "nan-maker";
    def.eval = nan_eval;
    assert_int_equal(brdffit_model_create_custom(&user, &def, NULL, NULL), BRDFFIT_OK);
    EXPECT_ERR(BRDFFIT_E_NONFINITE, brdffit_model_eval_grid(user, g, 0, 48, p, v, NULL, &err));
    assert_non_null(strstr(err.message, "nan-maker"));
    brdffit_model_destroy(user);
    brdffit_grid_destroy(g);
    brdffit_model_destroy(as);
}

static void test_model_destroyed_handle(void **state)
{
    keep_alloc ka;
    brdffit_model_def def = BRDFFIT_MODEL_DEF_INIT;
    brdffit_model *m = NULL;
    brdffit_grid *g = small_grid(1, NULL);
    brdffit_error err;
    brdffit_jacobian_report rep;
    double p[2] = {1.0, 0.1}, v[48], th[1] = {0.1}, ph[1] = {0.0};
    size_t idx, frees;
    unsigned char px[3 * 16 * 16];
    (void)state;
    keep_init(&ka);
    def.name = "kept";
    def.n_params = 2;
    def.params = GOOD_PARAMS;
    def.eval = nan_eval;
    def.destroy = count_destroy;
    destroyed = 0;
    assert_int_equal(brdffit_model_create_custom(&m, &def, &ka.hook, NULL), BRDFFIT_OK);
    brdffit_model_destroy(m);
    assert_int_equal(destroyed, 1);
    frees = ka.frees;
    brdffit_model_destroy(m); /* ignored: the callback is not called again */
    assert_int_equal(destroyed, 1);
    assert_int_equal(ka.frees, frees);
    assert_null(brdffit_model_name(m));
    assert_int_equal(brdffit_model_param_count(m), 0);
    assert_null(brdffit_model_param(m, 0));
    assert_int_equal(brdffit_model_vector_size(m, 1), 0);
    assert_int_equal(brdffit_model_vector_index(m, 0, 0, 1), (size_t)-1);
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_model_param_find(m, "k", &idx));
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_model_default_params(m, 1, p));
    EXPECT_ERR(BRDFFIT_E_BAD_HANDLE, brdffit_model_eval_grid(m, g, 0, 48, p, v, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_BAD_HANDLE,
               brdffit_model_eval_angles(m, 1, th, ph, th, ph, 1, p, v, NULL, &err));
    rep.struct_size = sizeof rep;
    EXPECT_ERR(BRDFFIT_E_BAD_HANDLE, brdffit_model_check_jacobian(m, g, p, &rep, &err));
    EXPECT_ERR(BRDFFIT_E_BAD_HANDLE,
               brdffit_image_texture(px, 3 * 7, BRDFFIT_TEXTURE_MODEL, g, m, p, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_BAD_HANDLE,
               brdffit_image_sphere_model(px, 48, 16, m, p, 1, 0.0, 0.0, NULL, NULL, &err));
    {
        brdffit_fit *fit = NULL;
        EXPECT_ERR(BRDFFIT_E_BAD_HANDLE, brdffit_fit_create(&fit, g, m, NULL, &err));
        assert_null(fit);
    }
    /* a grid handle is not a model */
    assert_null(brdffit_model_name((const brdffit_model *)g));
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_model_param_find((const brdffit_model *)g, "k", &idx));
    brdffit_grid_destroy(g);
    keep_release(&ka);
}

/* ---- optim.h ------------------------------------------------------------------------ */

static brdffit_status line_residuals(const double *x, double *r, double *jac, void *user)
{
    (void)user;
    r[0] = x[0] - 1.0;
    r[1] = 2.0 * (x[0] - 3.0);
    if (jac != NULL) {
        jac[0] = 1.0;
        jac[1] = 2.0;
    }
    return BRDFFIT_OK;
}

static brdffit_status failing_residuals(const double *x, double *r, double *jac, void *user)
{
    (void)x;
    (void)r;
    (void)jac;
    (void)user;
    return BRDFFIT_E_RANGE;
}

static brdffit_status nan_residuals(const double *x, double *r, double *jac, void *user)
{
    (void)x;
    (void)user;
    r[0] = NAN;
    r[1] = 0.0;
    if (jac != NULL) jac[0] = jac[1] = 1.0;
    return BRDFFIT_OK;
}

static brdffit_status negative_cost(const double *x, double *cost, double *jtj, double *jtr,
                                    void *user)
{
    (void)x;
    (void)jtj;
    (void)jtr;
    (void)user;
    *cost = -1.0;
    return BRDFFIT_OK;
}

static void damp_init(void *s, double *lambda, void *user)
{
    (void)s;
    (void)user;
    *lambda = 1e-3;
}

static void damp_step(void *s, double rho, double *lambda, void *user)
{
    (void)s;
    (void)rho;
    (void)lambda;
    (void)user;
}

/* The iteration callback tries to change and to rerun the optimizer during
 * its run; both must be refused (returning 1 would stop the run). */
static int meddling_callback(const brdffit_iteration *it, void *user)
{
    brdffit_optimizer *opt = user;
    double x[1];
    x[0] = it->x[0];
    if (brdffit_optimizer_set(opt, BRDFFIT_OPT_GTOL, 1e-3) != BRDFFIT_E_INVALID_ARGUMENT) return 1;
    if (brdffit_optimizer_set_callback(opt, NULL, NULL) != BRDFFIT_E_INVALID_ARGUMENT) return 1;
    return brdffit_optimizer_run(opt, x) == BRDFFIT_E_INVALID_ARGUMENT ? 0 : 1;
}

static void test_optimizer_misuse(void **state)
{
    brdffit_optimizer *opt = SENTINEL;
    brdffit_error err;
    brdffit_damping pol = BRDFFIT_DAMPING_INIT;
    double x[1] = {0.0}, v = -1.0, lo[1], hi[1], cov[1];
    (void)state;
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_optimizer_create(NULL, 1, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_optimizer_create(&opt, 0, NULL, &err));
    assert_null(opt);
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_optimizer_create(&opt, 4097, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_optimizer_create(&opt, 1, &HALF_ALLOC, &err));
    brdffit_optimizer_destroy(NULL);
    brdffit_optimizer_cancel(NULL);
    assert_non_null(brdffit_optimizer_message(NULL));
    assert_int_equal(brdffit_optimizer_param_count(NULL), 0);
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_optimizer_set(NULL, BRDFFIT_OPT_GTOL, 1e-8));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_optimizer_run(NULL, x));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT,
           brdffit_optimizer_set_residuals(NULL, 2, line_residuals, NULL));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_optimizer_covariance(NULL, cov));
    assert_int_equal(brdffit_optimizer_stop_reason(NULL), BRDFFIT_STOP_NONE);
    assert_true(isnan(brdffit_optimizer_final_cost(NULL)));

    assert_int_equal(brdffit_optimizer_create(&opt, 1, NULL, NULL), BRDFFIT_OK);
    /* no problem yet */
    EXPECT_OPT(BRDFFIT_E_NOT_READY, opt, brdffit_optimizer_run(opt, x));
    EXPECT(BRDFFIT_E_NOT_READY, brdffit_optimizer_covariance(opt, cov));
    EXPECT(BRDFFIT_E_NOT_READY, brdffit_optimizer_std_errors(opt, cov));
    assert_true(isnan(brdffit_optimizer_condition(opt)));
    /* problems */
    EXPECT_OPT(BRDFFIT_E_INVALID_ARGUMENT, opt,
               brdffit_optimizer_set_residuals(opt, 2, NULL, NULL));
    EXPECT_OPT(BRDFFIT_E_INVALID_ARGUMENT, opt,
               brdffit_optimizer_set_residuals(opt, 0, line_residuals, NULL));
    EXPECT_OPT(BRDFFIT_E_OUT_OF_MEMORY, opt,
               brdffit_optimizer_set_residuals(opt, SIZE_MAX / 2, line_residuals, NULL));
    EXPECT_OPT(BRDFFIT_E_INVALID_ARGUMENT, opt, brdffit_optimizer_set_normal(opt, 2, NULL, NULL));
    EXPECT_OPT(BRDFFIT_E_INVALID_ARGUMENT, opt,
               brdffit_optimizer_set_normal(opt, 0, negative_cost, NULL));
    /* damping policies */
    pol.init = damp_init;
    pol.accept = damp_step;
    pol.reject = damp_step;
    pol.struct_size = sizeof pol - 1;
    EXPECT_OPT(BRDFFIT_E_INVALID_ARGUMENT, opt, brdffit_optimizer_set_damping(opt, &pol));
    pol.struct_size = sizeof pol;
    pol.reject = NULL;
    EXPECT_OPT(BRDFFIT_E_INVALID_ARGUMENT, opt, brdffit_optimizer_set_damping(opt, &pol));
    pol.reject = damp_step;
    {
        brdffit_optimizer *limited = NULL;
        assert_int_equal(brdffit_optimizer_create(&limited, 1, &LIMITED_ALLOC, NULL), BRDFFIT_OK);
        pol.state_size = SIZE_MAX;
        EXPECT_OPT(BRDFFIT_E_OUT_OF_MEMORY, limited, brdffit_optimizer_set_damping(limited, &pol));
        brdffit_optimizer_destroy(limited);
        pol.state_size = 0;
    }
    /* settings: unknown, NaN, Inf, negative, not whole, out of range;
     * nothing changes */
    EXPECT_OPT(BRDFFIT_E_INVALID_ARGUMENT, opt,
               brdffit_optimizer_set(opt, (brdffit_optim_setting)99, 1.0));
    EXPECT_OPT(BRDFFIT_E_INVALID_ARGUMENT, opt,
               brdffit_optimizer_set(opt, (brdffit_optim_setting)0, 1.0));
    EXPECT_OPT(BRDFFIT_E_INVALID_ARGUMENT, opt, brdffit_optimizer_set(opt, BRDFFIT_OPT_GTOL, NAN));
    EXPECT_OPT(BRDFFIT_E_INVALID_ARGUMENT, opt,
               brdffit_optimizer_set(opt, BRDFFIT_OPT_XTOL, HUGE_VAL));
    EXPECT_OPT(BRDFFIT_E_INVALID_ARGUMENT, opt,
               brdffit_optimizer_set(opt, BRDFFIT_OPT_FTOL, -1e-9));
    EXPECT_OPT(BRDFFIT_E_INVALID_ARGUMENT, opt,
               brdffit_optimizer_set(opt, BRDFFIT_OPT_MAX_ITERATIONS, 10.5));
    EXPECT_OPT(BRDFFIT_E_INVALID_ARGUMENT, opt,
               brdffit_optimizer_set(opt, BRDFFIT_OPT_MAX_EVALUATIONS, 1e300));
    EXPECT_OPT(BRDFFIT_E_INVALID_ARGUMENT, opt,
               brdffit_optimizer_set(opt, BRDFFIT_OPT_SCALING, 0.5));
    EXPECT_OPT(BRDFFIT_E_INVALID_ARGUMENT, opt,
               brdffit_optimizer_set(opt, BRDFFIT_OPT_DIAG_FLOOR, 2.0));
    EXPECT(BRDFFIT_OK, brdffit_optimizer_get(opt, BRDFFIT_OPT_GTOL, &v));
    assert_true(v == 1e-13);
    EXPECT(BRDFFIT_OK, brdffit_optimizer_get(opt, BRDFFIT_OPT_MAX_ITERATIONS, &v));
    assert_true(v == 10000.0);
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_optimizer_get(opt, BRDFFIT_OPT_GTOL, NULL));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_optimizer_get(opt, (brdffit_optim_setting)99, &v));
    /* bounds: lower > upper, NaN, empty boxes; nothing changes */
    lo[0] = 1.0;
    hi[0] = 0.0;
    EXPECT_OPT(BRDFFIT_E_INVALID_ARGUMENT, opt, brdffit_optimizer_set_bounds(opt, lo, hi));
    lo[0] = NAN;
    EXPECT_OPT(BRDFFIT_E_INVALID_ARGUMENT, opt, brdffit_optimizer_set_bounds(opt, lo, NULL));
    lo[0] = HUGE_VAL;
    EXPECT_OPT(BRDFFIT_E_INVALID_ARGUMENT, opt, brdffit_optimizer_set_bounds(opt, lo, NULL));
    hi[0] = -HUGE_VAL;
    EXPECT_OPT(BRDFFIT_E_INVALID_ARGUMENT, opt, brdffit_optimizer_set_bounds(opt, NULL, hi));
    /* runs: NULL x, NaN or infinite start, failing or NaN problem, negative cost */
    assert_int_equal(brdffit_optimizer_set_residuals(opt, 2, line_residuals, NULL), BRDFFIT_OK);
    EXPECT_OPT(BRDFFIT_E_INVALID_ARGUMENT, opt, brdffit_optimizer_run(opt, NULL));
    x[0] = NAN;
    EXPECT_OPT(BRDFFIT_E_NONFINITE, opt, brdffit_optimizer_run(opt, x));
    x[0] = HUGE_VAL;
    EXPECT_OPT(BRDFFIT_E_NONFINITE, opt, brdffit_optimizer_run(opt, x));
    assert_true(x[0] == HUGE_VAL); /* unchanged on error */
    assert_int_equal(brdffit_optimizer_stop_reason(opt), BRDFFIT_STOP_NONE);
    x[0] = 0.0;
    assert_int_equal(brdffit_optimizer_set_residuals(opt, 2, failing_residuals, NULL), BRDFFIT_OK);
    EXPECT_OPT(BRDFFIT_E_CALLBACK_FAILED, opt, brdffit_optimizer_run(opt, x));
    assert_non_null(strstr(brdffit_optimizer_message(opt), "BRDFFIT_E_RANGE"));
    assert_int_equal(brdffit_optimizer_set_residuals(opt, 2, nan_residuals, NULL), BRDFFIT_OK);
    EXPECT_OPT(BRDFFIT_E_NONFINITE, opt, brdffit_optimizer_run(opt, x));
    assert_int_equal(brdffit_optimizer_set_normal(opt, 2, negative_cost, NULL), BRDFFIT_OK);
    EXPECT_OPT(BRDFFIT_E_CALLBACK_FAILED, opt, brdffit_optimizer_run(opt, x));
    EXPECT(BRDFFIT_E_NOT_READY, brdffit_optimizer_covariance(opt, cov));
    /* changing the optimizer from its own callback during a run */
    assert_int_equal(brdffit_optimizer_set_residuals(opt, 2, line_residuals, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set_callback(opt, meddling_callback, opt), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
    assert_int_not_equal(brdffit_optimizer_stop_reason(opt), BRDFFIT_STOP_CALLBACK);
    assert_close(x[0], 2.6, 1e-9);
    EXPECT(BRDFFIT_OK, brdffit_optimizer_get(opt, BRDFFIT_OPT_GTOL, &v));
    assert_true(v == 1e-13);
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_optimizer_covariance(opt, NULL));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_optimizer_std_errors(opt, NULL));
    brdffit_optimizer_destroy(opt);
}

static void test_optimizer_destroyed_handle(void **state)
{
    keep_alloc ka;
    brdffit_optimizer *opt = NULL;
    double x[2] = {0.0, 0.0}, v, cov[4];
    size_t frees;
    (void)state;
    keep_init(&ka);
    assert_int_equal(brdffit_optimizer_create(&opt, 2, &ka.hook, NULL), BRDFFIT_OK);
    brdffit_optimizer_destroy(opt);
    frees = ka.frees;
    assert_int_equal(frees, ka.allocs);
    brdffit_optimizer_destroy(opt);
    assert_int_equal(ka.frees, frees);
    brdffit_optimizer_cancel(opt);
    assert_non_null(brdffit_optimizer_message(opt));
    assert_string_not_equal(brdffit_optimizer_message(opt), "");
    assert_int_equal(brdffit_optimizer_param_count(opt), 0);
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_optimizer_set_residuals(opt, 2, line_residuals, NULL));
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_optimizer_set_normal(opt, 2, negative_cost, NULL));
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_optimizer_set_damping(opt, NULL));
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_optimizer_set(opt, BRDFFIT_OPT_GTOL, 1e-8));
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_optimizer_get(opt, BRDFFIT_OPT_GTOL, &v));
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_optimizer_set_bounds(opt, NULL, NULL));
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_optimizer_set_fixed(opt, NULL));
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_optimizer_set_callback(opt, NULL, NULL));
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_optimizer_run(opt, x));
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_optimizer_covariance(opt, cov));
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_optimizer_std_errors(opt, cov));
    assert_int_equal(brdffit_optimizer_stop_reason(opt), BRDFFIT_STOP_NONE);
    assert_int_equal(brdffit_optimizer_iterations(opt), 0);
    assert_int_equal(brdffit_optimizer_evaluations(opt), 0);
    assert_int_equal(brdffit_optimizer_history(opt, NULL, NULL), 0);
    assert_true(isnan(brdffit_optimizer_initial_cost(opt)));
    assert_true(isnan(brdffit_optimizer_condition(opt)));
    assert_int_equal(ka.frees, frees);
    keep_release(&ka);
}

/* ---- fit.h ------------------------------------------------------------------------------ */

/* brdffit_fit_set with a bad value: the exact status, a message, and the
 * option keeps its value. */
static void expect_bad_setting(brdffit_fit *fit, brdffit_fit_setting setting, double value)
{
    double before = -1.0, after = -2.0;
    assert_int_equal(brdffit_fit_get(fit, setting, &before), BRDFFIT_OK);
    if (brdffit_fit_set(fit, setting, value) != BRDFFIT_E_INVALID_ARGUMENT) {
        print_error("setting %d = %g was not refused\n", (int)setting, value);
        fail();
    }
    assert_string_not_equal(brdffit_fit_message(fit), "");
    assert_int_equal(brdffit_fit_get(fit, setting, &after), BRDFFIT_OK);
    assert_true(after == before);
}

static void test_fit_misuse(void **state)
{
    brdffit_grid *g = small_grid(3, NULL);
    brdffit_model *as = model_of("ashikhmin-shirley", NULL), *lambert = model_of("lambert", NULL);
    brdffit_fit *fit = SENTINEL, *lf = NULL;
    brdffit_error err;
    brdffit_damping pol = BRDFFIT_DAMPING_INIT;
    double p[7], v, rs, cd[3], cs[3];
    (void)state;
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_create(NULL, g, as, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_create(&fit, NULL, as, NULL, &err));
    assert_null(fit);
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_create(&fit, g, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_create(&fit, g, as, &HALF_ALLOC, &err));
    /* NULL fit */
    brdffit_fit_destroy(NULL);
    brdffit_fit_cancel(NULL);
    assert_non_null(brdffit_fit_message(NULL));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_set(NULL, BRDFFIT_FIT_CAP, 1.0));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_get(NULL, BRDFFIT_FIT_CAP, &v));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_set_damping(NULL, NULL));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_set_start(NULL, NULL));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_set_fixed(NULL, 0, 1));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_set_callback(NULL, NULL, NULL));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_run(NULL));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_params(NULL, p));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_std_errors(NULL, p));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_error(NULL, BRDFFIT_METRIC_RMS, 0, &v));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_shader(NULL, &rs, cd, cs));
    assert_int_equal(brdffit_fit_param_count(NULL), 0);
    assert_int_equal(brdffit_fit_stop_reason(NULL), BRDFFIT_STOP_NONE);
    assert_int_equal(brdffit_fit_iterations(NULL), 0);
    assert_int_equal(brdffit_fit_history(NULL, NULL, NULL), 0);
    assert_int_equal(brdffit_fit_passes(NULL), 0);

    assert_int_equal(brdffit_fit_create(&fit, g, as, NULL, NULL), BRDFFIT_OK);
    /* settings: unknown, NaN, Inf, out of range, not whole */
    assert_int_equal(brdffit_fit_set(fit, (brdffit_fit_setting)99, 1.0),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_string_not_equal(brdffit_fit_message(fit), "");
    assert_int_equal(brdffit_fit_set(fit, (brdffit_fit_setting)0, 1.0), BRDFFIT_E_INVALID_ARGUMENT);
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_get(fit, (brdffit_fit_setting)99, &v));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_get(fit, BRDFFIT_FIT_CAP, NULL));
    expect_bad_setting(fit, BRDFFIT_FIT_PIPELINE, 3.0);
    expect_bad_setting(fit, BRDFFIT_FIT_PIPELINE, -1.0);
    expect_bad_setting(fit, BRDFFIT_FIT_PIPELINE, 0.5);
    expect_bad_setting(fit, BRDFFIT_FIT_PIPELINE, NAN);
    expect_bad_setting(fit, BRDFFIT_FIT_CAP, NAN);
    expect_bad_setting(fit, BRDFFIT_FIT_CAP, HUGE_VAL);
    expect_bad_setting(fit, BRDFFIT_FIT_CAP, -1e-9);
    expect_bad_setting(fit, BRDFFIT_FIT_CAP, 1.6);
    expect_bad_setting(fit, BRDFFIT_FIT_WEIGHTING, 4.0);
    expect_bad_setting(fit, BRDFFIT_FIT_WEIGHTING, 1.5);
    expect_bad_setting(fit, BRDFFIT_FIT_WEIGHTING, NAN);
    expect_bad_setting(fit, BRDFFIT_FIT_CLEARCOAT, 1.0);
    expect_bad_setting(fit, BRDFFIT_FIT_CLEARCOAT, -0.1);
    expect_bad_setting(fit, BRDFFIT_FIT_CLEARCOAT, NAN);
    expect_bad_setting(fit, BRDFFIT_FIT_THREADS, 0.0);
    expect_bad_setting(fit, BRDFFIT_FIT_THREADS, 65.0);
    expect_bad_setting(fit, BRDFFIT_FIT_THREADS, HUGE_VAL);
    expect_bad_setting(fit, BRDFFIT_FIT_MAX_ITERATIONS, 0.0);
    expect_bad_setting(fit, BRDFFIT_FIT_MAX_ITERATIONS, 2.5);
    expect_bad_setting(fit, BRDFFIT_FIT_MAX_ITERATIONS, HUGE_VAL);
    expect_bad_setting(fit, BRDFFIT_FIT_MAX_ITERATIONS, NAN);
    /* damping, start values, fixed parameters */
    pol.struct_size = sizeof pol;
    EXPECT_FIT(BRDFFIT_E_INVALID_ARGUMENT, fit, brdffit_fit_set_damping(fit, &pol));
    assert_int_equal(brdffit_model_default_params(as, 3, p), BRDFFIT_OK);
    p[0] = NAN;
    EXPECT_FIT(BRDFFIT_E_INVALID_ARGUMENT, fit, brdffit_fit_set_start(fit, p));
    p[0] = 0.0; /* below the exponent's lower bound */
    EXPECT_FIT(BRDFFIT_E_RANGE, fit, brdffit_fit_set_start(fit, p));
    p[0] = 50.0;
    p[2] = -0.1;
    EXPECT_FIT(BRDFFIT_E_RANGE, fit, brdffit_fit_set_start(fit, p));
    p[2] = 0.2;
    EXPECT_FIT(BRDFFIT_E_INVALID_ARGUMENT, fit, brdffit_fit_set_fixed(fit, 3, 1));
    EXPECT_FIT(BRDFFIT_E_INVALID_ARGUMENT, fit, brdffit_fit_set_fixed(fit, SIZE_MAX, 0));
    /* results before a run */
    EXPECT(BRDFFIT_E_NOT_READY, brdffit_fit_params(fit, p));
    EXPECT(BRDFFIT_E_NOT_READY, brdffit_fit_std_errors(fit, p));
    EXPECT(BRDFFIT_E_NOT_READY, brdffit_fit_error(fit, BRDFFIT_METRIC_RMS, 0, &v));
    EXPECT(BRDFFIT_E_NOT_READY, brdffit_fit_shader(fit, &rs, cd, cs));
    assert_int_equal(brdffit_fit_stop_reason(fit), BRDFFIT_STOP_NONE);
    assert_int_equal(brdffit_fit_history(fit, NULL, NULL), 0);
    /* after a run: NULL outputs, unknown metric, channel out of range */
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, BRDFFIT_PIPELINE_JOINT),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
    assert_string_equal(brdffit_fit_message(fit), "");
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_params(fit, NULL));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_std_errors(fit, NULL));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_error(fit, BRDFFIT_METRIC_RMS, 0, NULL));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_error(fit, (brdffit_fit_metric)3, 0, &v));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_error(fit, (brdffit_fit_metric)-1, 0, &v));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_error(fit, BRDFFIT_METRIC_RMS, 3, &v));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_shader(fit, NULL, cd, cs));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_shader(fit, &rs, NULL, cs));
    EXPECT(BRDFFIT_E_INVALID_ARGUMENT, brdffit_fit_shader(fit, &rs, cd, NULL));
    /* a model without a specular colour has no shader form */
    assert_int_equal(brdffit_fit_create(&lf, g, lambert, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_run(lf), BRDFFIT_OK);
    EXPECT(BRDFFIT_E_UNSUPPORTED, brdffit_fit_shader(lf, &rs, cd, cs));
    brdffit_fit_destroy(lf);
    brdffit_fit_destroy(fit);
    brdffit_model_destroy(lambert);
    brdffit_model_destroy(as);
    brdffit_grid_destroy(g);
}

/* Start values must be finite: an infinite colour start is inside the
 * bounds [0, HUGE_VAL] of a colour, but no fit can start there. */
static void test_fit_start_infinite(void **state)
{
    brdffit_grid *g = small_grid(3, NULL);
    brdffit_model *as = model_of("ashikhmin-shirley", NULL);
    brdffit_fit *fit = NULL;
    double p[7];
    brdffit_status st;
    (void)state;
    assert_int_equal(brdffit_fit_create(&fit, g, as, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, BRDFFIT_PIPELINE_JOINT),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_model_default_params(as, 3, p), BRDFFIT_OK);
    p[4] = HUGE_VAL;
    st = brdffit_fit_set_start(fit, p);
    if (st == BRDFFIT_OK) {
        /* accepted: the run must then fail clearly, not return a result */
        st = brdffit_fit_run(fit);
        print_message("infinite start accepted by brdffit_fit_set_start; the run gives %s: %s\n",
                      brdffit_status_name(st), brdffit_fit_message(fit));
        assert_int_not_equal(st, BRDFFIT_OK);
        assert_string_not_equal(brdffit_fit_message(fit), "");
        brdffit_fit_destroy(fit);
        brdffit_model_destroy(as);
        brdffit_grid_destroy(g);
        fail_msg("brdffit_fit_set_start accepted an infinite start value");
    }
    assert_int_equal(st, BRDFFIT_E_INVALID_ARGUMENT);
    assert_string_not_equal(brdffit_fit_message(fit), "");
    brdffit_fit_destroy(fit);
    brdffit_model_destroy(as);
    brdffit_grid_destroy(g);
}

/* Failures of user callbacks inside a fit: a model whose evaluation fails
 * gives BRDFFIT_E_MODEL_FAILED naming the model and its status; one that
 * gives NaN gives BRDFFIT_E_NONFINITE; no result is kept. */
static void test_fit_callback_failures(void **state)
{
    brdffit_grid *g = small_grid(3, NULL);
    brdffit_model_def def = BRDFFIT_MODEL_DEF_INIT;
    brdffit_model *m = NULL;
    brdffit_fit *fit = NULL;
    double p[7];
    size_t pl;
    (void)state;
    def.name = "failing";
    def.n_params = 2;
    def.params = GOOD_PARAMS;
    def.eval = failing_eval;
    assert_int_equal(brdffit_model_create_custom(&m, &def, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_create(&fit, g, m, NULL, NULL), BRDFFIT_OK);
    for (pl = 0; pl < 3; pl++) {
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, (double)pl), BRDFFIT_OK);
        EXPECT_FIT(BRDFFIT_E_MODEL_FAILED, fit, brdffit_fit_run(fit));
        assert_non_null(strstr(brdffit_fit_message(fit), "failing"));
        assert_non_null(strstr(brdffit_fit_message(fit), "BRDFFIT_E_RANGE"));
        EXPECT(BRDFFIT_E_NOT_READY, brdffit_fit_params(fit, p));
        assert_int_equal(brdffit_fit_stop_reason(fit), BRDFFIT_STOP_NONE);
    }
    brdffit_fit_destroy(fit);
    brdffit_model_destroy(m);
    def.name = "nan";
    def.eval = nan_eval;
    assert_int_equal(brdffit_model_create_custom(&m, &def, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_create(&fit, g, m, NULL, NULL), BRDFFIT_OK);
    for (pl = 0; pl < 3; pl++) {
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, (double)pl), BRDFFIT_OK);
        EXPECT_FIT(BRDFFIT_E_NONFINITE, fit, brdffit_fit_run(fit));
        EXPECT(BRDFFIT_E_NOT_READY, brdffit_fit_params(fit, p));
    }
    brdffit_fit_destroy(fit);
    brdffit_model_destroy(m);
    brdffit_grid_destroy(g);
}

/* Calls that change a fit, made from its own iteration callback (setters
 * and a nested run): every one is refused with BRDFFIT_E_INVALID_ARGUMENT
 * and a message, nothing changes, and the run goes on to its normal end
 * with the settings it started with. */
enum { N_DURING = 8 };
typedef struct during_run {
    brdffit_fit *fit;
    int calls;
    brdffit_status status[N_DURING];
    int named[N_DURING]; /* the message says the fit is running */
} during_run;

static int change_from_callback(const brdffit_iteration *it, void *user)
{
    during_run *d = user;
    brdffit_fit *fit = d->fit;
    double start[7] = {100, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1};
    size_t i;
    (void)it;
    if (d->calls++ > 0) return 0;
    for (i = 0; i < N_DURING; i++) {
        switch (i) {
        case 0: d->status[i] = brdffit_fit_set(fit, BRDFFIT_FIT_CLEARCOAT, 0.04); break;
        case 1: d->status[i] = brdffit_fit_set(fit, BRDFFIT_FIT_CAP, 1.0); break;
        case 2: d->status[i] = brdffit_fit_set_start(fit, start); break;
        case 3: d->status[i] = brdffit_fit_set_fixed(fit, 0, 1); break;
        case 4: d->status[i] = brdffit_fit_set_damping(fit, NULL); break;
        case 5: d->status[i] = brdffit_fit_set_callback(fit, NULL, NULL); break;
        case 6: d->status[i] = brdffit_fit_run(fit); break;
        default: d->status[i] = brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, 1.0); break;
        }
        d->named[i] = strstr(brdffit_fit_message(fit), "while it runs") != NULL;
    }
    return 0;
}

static void test_fit_changes_during_run(void **state)
{
    brdffit_grid *g = small_grid(3, NULL);
    brdffit_model *as = model_of("ashikhmin-shirley", NULL);
    brdffit_fit *fit = NULL;
    double v, p[7];
    size_t pl, i;
    (void)state;
    assert_int_equal(brdffit_fit_create(&fit, g, as, NULL, NULL), BRDFFIT_OK);
    for (pl = 0; pl < 3; pl++) {
        during_run d;
        memset(&d, 0, sizeof d);
        d.fit = fit;
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, (double)pl), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_set_callback(fit, change_from_callback, &d), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
        assert_string_equal(brdffit_fit_message(fit), "");
        assert_true(d.calls > 1); /* the callback stayed */
        for (i = 0; i < N_DURING; i++) {
            if (d.status[i] != BRDFFIT_E_INVALID_ARGUMENT || !d.named[i])
                print_error("pipeline %zu, call %zu: %s\n", pl, i,
                            brdffit_status_name(d.status[i]));
            assert_int_equal(d.status[i], BRDFFIT_E_INVALID_ARGUMENT);
            assert_true(d.named[i]);
        }
        assert_int_equal(brdffit_fit_get(fit, BRDFFIT_FIT_CLEARCOAT, &v), BRDFFIT_OK);
        assert_true(v == 0.0);
        assert_int_equal(brdffit_fit_get(fit, BRDFFIT_FIT_PIPELINE, &v), BRDFFIT_OK);
        assert_true(v == (double)pl);
        assert_int_equal(brdffit_fit_params(fit, p), BRDFFIT_OK);
        /* after the run every call works again */
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_CLEARCOAT, 0.0), BRDFFIT_OK);
    }
    brdffit_fit_destroy(fit);
    brdffit_model_destroy(as);
    brdffit_grid_destroy(g);
}

/* NaN from a user model: the fit's message names the model, the sample,
 * the channel (the channel mean in the two-stage pipeline's first stage)
 * and, for a derivative, the parameter. */
static brdffit_status nan_derivative_eval(const brdffit_batch *b, const double *p, size_t nc,
                                          double *values, double *jac, void *user)
{
    size_t i;
    (void)p;
    (void)user;
    for (i = 0; i < nc * b->n; i++) values[i] = 0.1;
    if (jac != NULL)
        for (i = 0; i < 2 * nc * b->n; i++) jac[i] = i == 5 ? NAN : 0.01;
    return BRDFFIT_OK;
}

/* Finite values whose squares overflow. */
static brdffit_status huge_eval(const brdffit_batch *b, const double *p, size_t nc, double *values,
                                double *jac, void *user)
{
    size_t i;
    (void)p;
    (void)user;
    for (i = 0; i < nc * b->n; i++) values[i] = i == 7 ? 1e200 : 0.1;
    if (jac != NULL)
        for (i = 0; i < 2 * nc * b->n; i++) jac[i] = 0.01;
    return BRDFFIT_OK;
}

static void test_fit_nonfinite_messages(void **state)
{
    static const char *const where[3] = {"sample 3, channel 0", "sample 3, channel 0",
                                         "sample 3 of the channel mean"};
    brdffit_grid *g = small_grid(3, NULL);
    brdffit_model_def def = BRDFFIT_MODEL_DEF_INIT;
    brdffit_model *m = NULL;
    brdffit_fit *fit = NULL;
    size_t pl;
    (void)state;
    def.name = "nan";
    def.n_params = 2;
    def.params = GOOD_PARAMS;
    def.eval = nan_eval;
    assert_int_equal(brdffit_model_create_custom(&m, &def, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_create(&fit, g, m, NULL, NULL), BRDFFIT_OK);
    for (pl = 0; pl < 3; pl++) {
        const char *msg;
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, (double)pl), BRDFFIT_OK);
        EXPECT_FIT(BRDFFIT_E_NONFINITE, fit, brdffit_fit_run(fit));
        msg = brdffit_fit_message(fit);
        if (strstr(msg, where[pl]) == NULL) print_error("pipeline %zu: %s\n", pl, msg);
        assert_non_null(strstr(msg, "\"nan\""));
        assert_non_null(strstr(msg, where[pl]));
    }
    brdffit_fit_destroy(fit);
    brdffit_model_destroy(m);
    def.name = "nan-derivative";
    def.eval = nan_derivative_eval;
    assert_int_equal(brdffit_model_create_custom(&m, &def, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_create(&fit, g, m, NULL, NULL), BRDFFIT_OK);
    for (pl = 0; pl < 3; pl++) {
        const char *msg;
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, (double)pl), BRDFFIT_OK);
        EXPECT_FIT(BRDFFIT_E_NONFINITE, fit, brdffit_fit_run(fit));
        msg = brdffit_fit_message(fit);
        if (strstr(msg, "\"k\"") == NULL) print_error("pipeline %zu: %s\n", pl, msg);
        assert_non_null(strstr(msg, "derivative"));
        assert_non_null(strstr(msg, "\"k\""));
        assert_non_null(strstr(msg, "sample 5"));
    }
    brdffit_fit_destroy(fit);
    brdffit_model_destroy(m);
    def.name = "huge";
    def.eval = huge_eval;
    assert_int_equal(brdffit_model_create_custom(&m, &def, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_create(&fit, g, m, NULL, NULL), BRDFFIT_OK);
    /* under the squares the residual of sample 7 itself overflows when
     * squared; under the default (cube-root) its transformed residual is
     * finite, and the error figures' sums overflow */
    for (pl = 1; pl < 3; pl++) {
        const char *msg;
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, (double)pl), BRDFFIT_OK);
        EXPECT_FIT(BRDFFIT_E_NONFINITE, fit, brdffit_fit_run(fit));
        msg = brdffit_fit_message(fit);
        if (strstr(msg, "overflow") == NULL) print_error("pipeline %zu: %s\n", pl, msg);
        assert_non_null(strstr(msg, "\"huge\""));
        assert_non_null(strstr(msg, "overflow"));
    }
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, BRDFFIT_OBJECTIVE_SQUARES),
                     BRDFFIT_OK);
    for (pl = 1; pl < 3; pl++) {
        const char *msg;
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, (double)pl), BRDFFIT_OK);
        EXPECT_FIT(BRDFFIT_E_NONFINITE, fit, brdffit_fit_run(fit));
        msg = brdffit_fit_message(fit);
        if (strstr(msg, "sample 7") == NULL) print_error("pipeline %zu: %s\n", pl, msg);
        assert_non_null(strstr(msg, "overflows when squared"));
        assert_non_null(strstr(msg, "sample 7"));
    }
    brdffit_fit_destroy(fit);
    brdffit_model_destroy(m);
    brdffit_grid_destroy(g);
}

/* A destroyed fit, and a live fit whose grid or model was destroyed. */
static void test_fit_destroyed_handles(void **state)
{
    keep_alloc ka;
    brdffit_grid *g;
    brdffit_model *m;
    brdffit_fit *fit = NULL, *orphan = NULL;
    double p[7], v, rs, cd[3], cs[3];
    size_t frees;
    (void)state;
    keep_init(&ka);
    g = small_grid(3, &ka.hook);
    m = model_of("ashikhmin-shirley", &ka.hook);
    assert_int_equal(brdffit_fit_create(&fit, g, m, &ka.hook, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_create(&orphan, g, m, &ka.hook, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
    brdffit_fit_destroy(fit);
    frees = ka.frees;
    brdffit_fit_destroy(fit);
    assert_int_equal(ka.frees, frees);
    brdffit_fit_cancel(fit);
    assert_string_not_equal(brdffit_fit_message(fit), "");
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_fit_set(fit, BRDFFIT_FIT_CAP, 1.0));
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_fit_get(fit, BRDFFIT_FIT_CAP, &v));
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_fit_set_damping(fit, NULL));
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_fit_set_start(fit, NULL));
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_fit_set_fixed(fit, 0, 1));
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_fit_set_callback(fit, NULL, NULL));
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_fit_run(fit));
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_fit_params(fit, p));
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_fit_std_errors(fit, p));
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_fit_error(fit, BRDFFIT_METRIC_RMS, 0, &v));
    EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_fit_shader(fit, &rs, cd, cs));
    assert_int_equal(brdffit_fit_param_count(fit), 0);
    assert_int_equal(brdffit_fit_stop_reason(fit), BRDFFIT_STOP_NONE);
    assert_int_equal(brdffit_fit_iterations(fit), 0);
    assert_int_equal(brdffit_fit_history(fit, NULL, NULL), 0);
    assert_int_equal(brdffit_fit_passes(fit), 0);
    {
        brdffit_fit_stage stage;
        EXPECT(BRDFFIT_E_BAD_HANDLE, brdffit_fit_stage_info(fit, 0, &stage, sizeof stage));
        assert_int_equal(brdffit_fit_converged(fit), 0);
        assert_int_equal(brdffit_fit_stage_count(fit), 0);
        assert_int_equal(brdffit_fit_history_all(fit, NULL, NULL, NULL), 0);
    }
    /* the grid goes first, then the model: the fit that borrowed them refuses to run */
    brdffit_grid_destroy(g);
    EXPECT_FIT(BRDFFIT_E_BAD_HANDLE, orphan, brdffit_fit_run(orphan));
    brdffit_model_destroy(m);
    EXPECT_FIT(BRDFFIT_E_BAD_HANDLE, orphan, brdffit_fit_run(orphan));
    EXPECT(BRDFFIT_E_NOT_READY, brdffit_fit_params(orphan, p));
    brdffit_fit_destroy(orphan);
    assert_int_equal(ka.frees, ka.allocs);
    keep_release(&ka);
}

/* ---- image.h ------------------------------------------------------------------------ */

/* Options with one field wrong are refused by every picture function. */
static void expect_bad_options(const brdffit_grid *g, const brdffit_image_options *o)
{
    brdffit_error err;
    unsigned char px[3 * 64 * 64];
    size_t w, h;
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_image_texture_size(g, o, &w, &h, &err));
    EXPECT_ERR(
        BRDFFIT_E_INVALID_ARGUMENT,
        brdffit_image_texture(px, 3 * 64, BRDFFIT_TEXTURE_MEASURED, g, NULL, NULL, o, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_image_sphere_measured(px, 3 * 16, 16, g, 0.0, 0.0, o, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_image_plot(px, 3 * 64, 64, 64, NULL, 0, o, &err));
}

static void test_image_options_misuse(void **state)
{
    brdffit_grid *g = small_grid(3, NULL);
    brdffit_image_options o;
    (void)state;
    brdffit_image_options_init(NULL);
#define BAD_OPTION(field, value)        \
    do {                                \
        brdffit_image_options_init(&o); \
        o.field = (value);              \
        expect_bad_options(g, &o);      \
    } while (0)
    BAD_OPTION(struct_size, 0);
    BAD_OPTION(struct_size, offsetof(brdffit_image_options, log_y));
    BAD_OPTION(gain, NAN);
    BAD_OPTION(gain, HUGE_VAL);
    BAD_OPTION(gain, -1.0);
    BAD_OPTION(difference_gain, NAN);
    BAD_OPTION(exposure, -HUGE_VAL);
    BAD_OPTION(gamma, 0.0);
    BAD_OPTION(gamma, NAN);
    BAD_OPTION(gamma, 11.0);
    BAD_OPTION(scale, 0);
    BAD_OPTION(scale, 65);
    BAD_OPTION(block_columns, 0);
    BAD_OPTION(block_gap, 65);
#undef BAD_OPTION
    brdffit_grid_destroy(g);
}

/* Versioned structs from an older or a newer header: a struct of the first
 * version's size and one with fields appended (a newer header) are both
 * read as documented; one byte less than the first version is refused. */
struct newer_options {
    brdffit_image_options o;
    double appended[4];
};

struct newer_damping {
    brdffit_damping d;
    void *appended[2];
};

static void texture_of(const brdffit_grid *g, const brdffit_image_options *o, brdffit_status want,
                       unsigned char *px)
{
    size_t w = 0, h = 0;
    assert_int_equal(brdffit_image_texture_size(g, o, &w, &h, NULL), want);
    if (want == BRDFFIT_OK)
        assert_int_equal(brdffit_image_texture(px, 3 * w, BRDFFIT_TEXTURE_MEASURED, g, NULL, NULL,
                                               o, NULL, NULL),
                         want);
}

static void test_versioned_struct_sizes(void **state)
{
    const size_t v1_options = offsetof(brdffit_image_options, log_y) + sizeof(int);
    const size_t v1_damping = BRDFFIT_DAMPING_SIZE_V1;
    brdffit_grid *g = small_grid(3, NULL);
    unsigned char ref[3 * 64 * 64], px[3 * 64 * 64];
    struct newer_options n;
    struct newer_damping nd;
    brdffit_optimizer *opt = NULL;
    brdffit_fit *fit = NULL;
    brdffit_model *m = NULL;
    (void)state;
    memset(ref, 0, sizeof ref);
    memset(px, 0, sizeof px);
    brdffit_image_options_init(&n.o);
    n.o.gain = 0.5;
    texture_of(g, &n.o, BRDFFIT_OK, ref);
    memset(n.appended, 0xff, sizeof n.appended);
    n.o.struct_size = sizeof n; /* newer header: accepted, the tail ignored */
    texture_of(g, &n.o, BRDFFIT_OK, px);
    assert_memory_equal(px, ref, sizeof ref);
    n.o.struct_size = v1_options; /* first version, without tail padding */
    texture_of(g, &n.o, BRDFFIT_OK, px);
    assert_memory_equal(px, ref, sizeof ref);
    n.o.struct_size = v1_options - 1;
    texture_of(g, &n.o, BRDFFIT_E_INVALID_ARGUMENT, px);
    /* damping: the optimizer and the fit */
    memset(&nd, 0, sizeof nd);
    nd.d = *brdffit_damping_thesis();
    nd.d.struct_size = sizeof nd;
    assert_int_equal(brdffit_optimizer_create(&opt, 2, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_optimizer_set_damping(opt, &nd.d), BRDFFIT_OK);
    nd.d.struct_size = v1_damping;
    assert_int_equal(brdffit_optimizer_set_damping(opt, &nd.d), BRDFFIT_OK);
    nd.d.struct_size = v1_damping - 1;
    EXPECT_OPT(BRDFFIT_E_INVALID_ARGUMENT, opt, brdffit_optimizer_set_damping(opt, &nd.d));
    assert_int_equal(brdffit_model_create(&m, "lambert", NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_create(&fit, g, m, NULL, NULL), BRDFFIT_OK);
    nd.d.struct_size = sizeof nd;
    assert_int_equal(brdffit_fit_set_damping(fit, &nd.d), BRDFFIT_OK);
    nd.d.struct_size = v1_damping;
    assert_int_equal(brdffit_fit_set_damping(fit, &nd.d), BRDFFIT_OK);
    nd.d.struct_size = v1_damping - 1;
    EXPECT_FIT(BRDFFIT_E_INVALID_ARGUMENT, fit, brdffit_fit_set_damping(fit, &nd.d));
    brdffit_fit_destroy(fit);
    brdffit_model_destroy(m);
    brdffit_optimizer_destroy(opt);
    brdffit_grid_destroy(g);
}

static void test_image_functions_misuse(void **state)
{
    brdffit_grid *g = small_grid(3, NULL), *sc = scattered_grid(), *big;
    brdffit_model *as = model_of("ashikhmin-shirley", NULL);
    brdffit_image_options o = BRDFFIT_IMAGE_OPTIONS_INIT;
    brdffit_error err;
    size_t w = 0, h = 0;
    double p[7], series[3] = {1.0, 2.0, 3.0};
    unsigned char *px = malloc(3 * 64 * 64);
    (void)state;
    assert_non_null(px);
    assert_int_equal(brdffit_model_default_params(as, 3, p), BRDFFIT_OK);
    /* texture size */
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_image_texture_size(NULL, NULL, &w, &h, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_image_texture_size(g, NULL, NULL, &h, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_image_texture_size(g, NULL, &w, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_UNSUPPORTED, brdffit_image_texture_size(sc, NULL, &w, &h, &err));
    big = fx_grid_from_named("lambert", p, 1, NULL, 0.0, 1);
    assert_non_null(big);
    o.scale = 64; /* 37 x 19 rows of 64 pixels: 44992 > 32768 */
    EXPECT_ERR(BRDFFIT_E_TOO_LARGE, brdffit_image_texture_size(big, &o, &w, &h, &err));
    brdffit_grid_destroy(big);
    assert_int_equal(brdffit_image_texture_size(g, NULL, &w, &h, NULL), BRDFFIT_OK);
    assert_int_equal(w, 7);
    assert_int_equal(h, 12);
    /* textures */
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_image_texture(NULL, 3 * w, BRDFFIT_TEXTURE_MEASURED, g, NULL, NULL, NULL,
                                     NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_image_texture(px, 3 * w - 1, BRDFFIT_TEXTURE_MEASURED, g, NULL, NULL, NULL,
                                     NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_image_texture(px, 3 * w, (brdffit_texture_kind)3,
                                                                 g, as, p, NULL, NULL, &err));
    EXPECT_ERR(
        BRDFFIT_E_INVALID_ARGUMENT,
        brdffit_image_texture(px, 3 * w, (brdffit_texture_kind)-1, g, as, p, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_image_texture(px, 3 * w, BRDFFIT_TEXTURE_MODEL,
                                                                 g, NULL, p, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_image_texture(px, 3 * w, BRDFFIT_TEXTURE_DIFFERENCE, g, as, NULL, NULL, NULL,
                                     &err));
    EXPECT_ERR(
        BRDFFIT_E_INVALID_ARGUMENT,
        brdffit_image_texture(px, 3 * w, BRDFFIT_TEXTURE_MODEL, g, as, p, NULL, &HALF_ALLOC, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_image_texture(px, 3 * w, BRDFFIT_TEXTURE_MEASURED, NULL, NULL, NULL, NULL,
                                     NULL, &err));
    EXPECT_ERR(BRDFFIT_E_UNSUPPORTED, brdffit_image_texture(px, 3 * w, BRDFFIT_TEXTURE_MEASURED, sc,
                                                            NULL, NULL, NULL, NULL, &err));
    p[0] = NAN;
    EXPECT_ERR(BRDFFIT_E_NONFINITE,
               brdffit_image_texture(px, 3 * w, BRDFFIT_TEXTURE_MODEL, g, as, p, NULL, NULL, &err));
    /* spheres */
    EXPECT_ERR(BRDFFIT_E_NONFINITE,
               brdffit_image_sphere_model(px, 3 * 16, 16, as, p, 3, 0.0, 0.0, NULL, NULL, &err));
    p[0] = 50.0;
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_image_sphere_measured(NULL, 48, 16, g, 0.0, 0.0, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_image_sphere_measured(px, 47, 16, g, 0.0, 0.0, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_image_sphere_measured(px, 48, 0, g, 0.0, 0.0, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_TOO_LARGE,
               brdffit_image_sphere_measured(px, 3 * 32769, 32769, g, 0.0, 0.0, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_image_sphere_measured(px, 48, 16, g, NAN, 0.0, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_image_sphere_measured(px, 48, 16, g, 3.2, 0.0, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_image_sphere_measured(px, 48, 16, g, 0.5, HUGE_VAL, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_image_sphere_measured(px, 48, 16, g, 0.5, 0.0, NULL, &HALF_ALLOC, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_image_sphere_measured(px, 48, 16, NULL, 0.5, 0.0, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_UNSUPPORTED,
               brdffit_image_sphere_measured(px, 48, 16, sc, 0.5, 0.0, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_image_sphere_model(px, 48, 16, NULL, p, 3, 0.0, 0.0, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_image_sphere_model(px, 48, 16, as, NULL, 3, 0.0, 0.0, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_image_sphere_model(px, 48, 16, as, p, 0, 0.0, 0.0, NULL, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_image_sphere_model(px, 48, 16, as, p, 3, -0.1, 0.0, NULL, NULL, &err));
    /* plots */
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_image_plot(NULL, 48, 16, 16, series, 3, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_image_plot(px, 45, 15, 16, series, 3, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_image_plot(px, 48, 16, 15, series, 3, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT,
               brdffit_image_plot(px, 47, 16, 16, series, 3, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_TOO_LARGE,
               brdffit_image_plot(px, 3 * 32769, 32769, 16, series, 3, NULL, &err));
    EXPECT_ERR(BRDFFIT_E_INVALID_ARGUMENT, brdffit_image_plot(px, 48, 16, 16, NULL, 3, NULL, &err));
    series[1] = NAN;
    EXPECT_ERR(BRDFFIT_E_NONFINITE, brdffit_image_plot(px, 48, 16, 16, series, 3, NULL, &err));
    series[1] = -HUGE_VAL;
    EXPECT_ERR(BRDFFIT_E_NONFINITE, brdffit_image_plot(px, 48, 16, 16, series, 3, NULL, &err));
    assert_int_equal(brdffit_image_plot(px, 48, 16, 16, NULL, 0, NULL, NULL), BRDFFIT_OK);
    free(px);
    brdffit_model_destroy(as);
    brdffit_grid_destroy(sc);
    brdffit_grid_destroy(g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_status_unknown_values),
        cmocka_unit_test(test_grid_create_misuse),
        cmocka_unit_test(test_grid_functions_misuse),
        cmocka_unit_test(test_grid_destroyed_handle),
        cmocka_unit_test(test_load_misuse),
        cmocka_unit_test(test_model_create_misuse),
        cmocka_unit_test(test_model_functions_misuse),
        cmocka_unit_test(test_model_destroyed_handle),
        cmocka_unit_test(test_optimizer_misuse),
        cmocka_unit_test(test_optimizer_destroyed_handle),
        cmocka_unit_test(test_fit_misuse),
        cmocka_unit_test(test_fit_start_infinite),
        cmocka_unit_test(test_fit_callback_failures),
        cmocka_unit_test(test_fit_changes_during_run),
        cmocka_unit_test(test_fit_nonfinite_messages),
        cmocka_unit_test(test_fit_destroyed_handles),
        cmocka_unit_test(test_image_options_misuse),
        cmocka_unit_test(test_image_functions_misuse),
        cmocka_unit_test(test_versioned_struct_sizes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
