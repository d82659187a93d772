/* Line plots (image.h): a monotone series gives a monotone curve that spans
 * the plot area, a log axis spaces powers of ten evenly, a constant series
 * is a level line, the frame around the plot is background, bad arguments
 * give exact codes. The curve is found by its colour. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "test_support.h"

#define W 200
#define H 100
/* Margin max(4, min(W, H) / 16) = 6: axes at x = 6 and y = H - 7; data
 * from x = 8 to W - 8 and from y = 6 to H - 9, each point a 2 x 2 stamp. */
#define M 6

typedef struct curve_rows {
    int top[W];    /* topmost curve pixel per column, -1 if none */
    int bottom[W]; /* lowest curve pixel per column */
    size_t pixels;
} curve_rows;

static curve_rows find_curve(const unsigned char *px, const unsigned char rgb[3])
{
    curve_rows r;
    size_t x, y;
    r.pixels = 0;
    for (x = 0; x < W; x++) {
        r.top[x] = -1;
        r.bottom[x] = -1;
        for (y = 0; y < H; y++) {
            if (memcmp(px + y * 3 * W + 3 * x, rgb, 3) != 0) continue;
            if (r.top[x] < 0) r.top[x] = (int)y;
            r.bottom[x] = (int)y;
            r.pixels++;
        }
    }
    return r;
}

static curve_rows plot(const double *v, size_t n, int log_y, unsigned char *px)
{
    brdffit_image_options o = BRDFFIT_IMAGE_OPTIONS_INIT;
    o.log_y = log_y;
    assert_int_equal(brdffit_image_plot(px, 3 * W, W, H, v, n, &o, NULL), BRDFFIT_OK);
    return find_curve(px, o.curve);
}

/* Columns with curve pixels form one run from first to last. */
static void assert_spans(const curve_rows *r, int first, int last)
{
    int x;
    for (x = 0; x < W; x++) {
        if (x >= first && x <= last)
            assert_true(r->top[x] >= 0);
        else
            assert_int_equal(r->top[x], -1);
    }
}

static void test_monotone_series(void **state)
{
    double dec[25], inc[25];
    unsigned char px[W * H * 3];
    size_t i;
    int log_y, x;
    (void)state;
    for (i = 0; i < 25; i++) {
        dec[i] = 100.0 * pow(0.6, (double)i) + 0.01 * (double)(25 - i);
        inc[i] = 3.0 + sqrt((double)i);
    }
    for (log_y = 0; log_y <= 1; log_y++) {
        curve_rows r = plot(dec, 25, log_y, px);
        assert_spans(&r, M + 2, W - M - 1);
        for (x = M + 3; x <= W - M - 1; x++) assert_true(r.top[x] >= r.top[x - 1]);
        if (!log_y) {                          /* a linear axis spans exactly the values */
            assert_int_equal(r.top[M + 2], M); /* the largest at the top */
            assert_int_equal(r.bottom[W - M - 1], H - M - 2); /* the smallest at the bottom */
        } else { /* a log axis spans whole decades: 0.01 .. 1000 */
            double lo = floor(log10(dec[24])), hi = ceil(log10(dec[0]));
            assert_close(lo, -2.0, 0.0);
            assert_close(hi, 3.0, 0.0);
            assert_int_equal(
                r.top[M + 2],
                H - M - 3 - (int)floor((log10(dec[0]) - lo) / (hi - lo) * (H - 2 * M - 3) + 0.5));
        }
        r = plot(inc, 25, log_y, px);
        assert_spans(&r, M + 2, W - M - 1);
        for (x = M + 3; x <= W - M - 1; x++) assert_true(r.top[x] <= r.top[x - 1]);
        if (!log_y) assert_int_equal(r.top[W - M - 1], M);
    }
}

/* 1, 0.1, ..., 1e-4 on a log axis: the points are evenly spaced in y. */
static void test_log_axis_spacing(void **state)
{
    double v[5] = {1.0, 0.1, 0.01, 1e-3, 1e-4};
    unsigned char px[W * H * 3];
    curve_rows r = plot(v, 5, 1, px);
    int dy0 = M, dy1 = H - M - 3, k;
    (void)state;
    for (k = 0; k < 5; k++) {
        /* point k: x = 8 + 46 k; y = dy1 - round((4 - k) / 4 * (dy1 - dy0)) */
        size_t x = (size_t)(M + 2 + k * (W - 2 * M - 4) / 4);
        size_t y = (size_t)(dy1 - (int)floor((4 - k) * (dy1 - dy0) / 4.0 + 0.5));
        brdffit_image_options o = BRDFFIT_IMAGE_OPTIONS_INIT;
        assert_memory_equal(px + y * 3 * W + 3 * x, o.curve, 3);
        assert_true(abs((int)y - (dy0 + k * (dy1 - dy0) / 4)) <= 1); /* even steps */
    }
    /* On a linear axis the same series hugs the bottom after the first point. */
    r = plot(v, 5, 0, px);
    assert_true(r.top[M + 2 + (W - 2 * M - 4) / 2] >= H - M - 4);
}

static void test_constant_and_single(void **state)
{
    double v[10];
    unsigned char px[W * H * 3];
    curve_rows r;
    size_t i;
    int x, mid = (M + H - M - 3) / 2;
    (void)state;
    for (i = 0; i < 10; i++) v[i] = 2.5;
    r = plot(v, 10, 0, px);
    for (x = M + 2; x <= W - M - 1; x++) {
        assert_true(abs(r.top[x] - mid) <= 1);
        assert_int_equal(r.bottom[x] - r.top[x], 1);
    }
    r = plot(v, 1, 1, px);
    assert_int_equal(r.pixels, 4);
    /* Non-positive values on a log axis lie at the bottom. */
    v[0] = 10.0;
    v[1] = 0.0;
    v[2] = -3.0;
    v[3] = 1.0;
    r = plot(v, 4, 1, px);
    assert_int_equal(r.top[M + 2], M);
    assert_int_equal(r.bottom[M + 2 + (W - 2 * M - 4) / 3], H - M - 2);
}

static void test_frame_and_axes(void **state)
{
    brdffit_image_options o = BRDFFIT_IMAGE_OPTIONS_INIT;
    double v[3] = {3.0, 2.0, 1.0};
    unsigned char px[W * H * 3];
    size_t x, y;
    (void)state;
    assert_int_equal(brdffit_image_plot(px, 3 * W, W, H, v, 3, &o, NULL), BRDFFIT_OK);
    /* The outer band (beyond tick marks) is background. */
    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++)
            if (x < 2 || y < 2 || x >= W - 2 || y >= H - 2)
                assert_memory_equal(px + y * 3 * W + 3 * x, o.background, 3);
    /* Axes: the left edge and the bottom edge of the plot area. */
    for (y = M; y <= H - M - 1; y++) assert_memory_equal(px + y * 3 * W + 3 * M, o.foreground, 3);
    for (x = M; x <= W - M - 1; x++)
        assert_memory_equal(px + (H - M - 1) * 3 * W + 3 * x, o.foreground, 3);
    /* No values: axes only, no curve. */
    assert_int_equal(brdffit_image_plot(px, 3 * W, W, H, NULL, 0, &o, NULL), BRDFFIT_OK);
    assert_int_equal(find_curve(px, o.curve).pixels, 0);
}

static void test_bad_arguments(void **state)
{
    brdffit_image_options o = BRDFFIT_IMAGE_OPTIONS_INIT;
    brdffit_error err;
    double v[3] = {1.0, NAN, 2.0};
    unsigned char px[W * H * 3];
    (void)state;
    assert_int_equal(brdffit_image_plot(px, 3 * W, W, H, v, 3, NULL, &err), BRDFFIT_E_NONFINITE);
    assert_int_equal(err.status, BRDFFIT_E_NONFINITE);
    v[1] = INFINITY;
    assert_int_equal(brdffit_image_plot(px, 3 * W, W, H, v, 3, NULL, NULL), BRDFFIT_E_NONFINITE);
    v[1] = 1.5;
    assert_int_equal(brdffit_image_plot(NULL, 3 * W, W, H, v, 3, NULL, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_image_plot(px, 3 * W, W, H, NULL, 3, NULL, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_image_plot(px, 3 * W - 1, W, H, v, 3, NULL, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_image_plot(px, 3 * W, 15, H, v, 3, NULL, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_image_plot(px, 3 * W, W, 15, v, 3, NULL, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_image_plot(px, (size_t)3 * 40000, 40000, H, v, 3, NULL, NULL),
                     BRDFFIT_E_TOO_LARGE);
    o.struct_size = 8;
    assert_int_equal(brdffit_image_plot(px, 3 * W, W, H, v, 3, &o, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    /* Extreme but finite values do not hang or crash. */
    v[0] = 1e300;
    v[1] = 1e300 * (1.0 + 1e-15);
    v[2] = 5e-324;
    assert_int_equal(brdffit_image_plot(px, 3 * W, W, H, v, 3, NULL, NULL), BRDFFIT_OK);
    o.struct_size = sizeof o;
    o.log_y = 1;
    assert_int_equal(brdffit_image_plot(px, 3 * W, W, H, v, 3, &o, NULL), BRDFFIT_OK);
    v[0] = -1e308;
    v[1] = 1e308;
    assert_int_equal(brdffit_image_plot(px, 3 * W, W, H, v, 3, NULL, NULL), BRDFFIT_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_monotone_series),     cmocka_unit_test(test_log_axis_spacing),
        cmocka_unit_test(test_constant_and_single), cmocka_unit_test(test_frame_and_axes),
        cmocka_unit_test(test_bad_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
