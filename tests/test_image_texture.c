/* The texture of a regular grid (image.h): size and layout, colour
 * encoding, mirroring, row and block order, model and difference
 * textures, missing values, channel mapping, bad arguments and allocation
 * failure. Expected colours are computed here from the documented
 * encoding, round(255 * clamp(gain * v, 0, 1)^(1 / gamma)). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "test_support.h"

#define PI 3.14159265358979323846

/* Axes of the small test grid, degrees. */
static const double ti_deg[] = {0.0, 30.0, 60.0};
static const double to_deg[] = {0.0, 20.0, 40.0, 70.0};
static const double po_deg[] = {0.0, 45.0, 90.0, 135.0, 180.0};
enum { N_TI = 3, N_TO = 4, N_PO = 5, N = N_TI * N_TO * N_PO };

typedef double (*value_fn)(size_t i, size_t j, size_t k, size_t c);

static double rad_ti[N_TI], rad_to[N_TO], rad_po[300];

static brdffit_axes test_axes(const double *po, size_t n_po)
{
    brdffit_axes a;
    size_t i;
    for (i = 0; i < N_TI; i++) rad_ti[i] = DEG(ti_deg[i]);
    for (i = 0; i < N_TO; i++) rad_to[i] = DEG(to_deg[i]);
    for (i = 0; i < n_po; i++) rad_po[i] = DEG(po[i]);
    a.theta_i = rad_ti;
    a.n_theta_i = N_TI;
    a.theta_o = rad_to;
    a.n_theta_o = N_TO;
    a.phi_o = rad_po;
    a.n_phi_o = n_po;
    return a;
}

static brdffit_grid *make_grid(value_fn f, size_t nc, const unsigned char *mask)
{
    brdffit_axes a = test_axes(po_deg, N_PO);
    double v[N * 3];
    brdffit_grid *g = NULL;
    size_t s, c;
    for (s = 0; s < N; s++)
        for (c = 0; c < nc; c++) v[s * nc + c] = f(s / (N_TO * N_PO), s / N_PO % N_TO, s % N_PO, c);
    assert_int_equal(brdffit_grid_create_regular(&g, &a, nc, v, mask, NULL, NULL), BRDFFIT_OK);
    return g;
}

static double constant(size_t i, size_t j, size_t k, size_t c)
{
    (void)i, (void)j, (void)k, (void)c;
    return 0.1;
}

/* Distinct in every index, below 1/3 so that gain 3 never clips. */
static double varying(size_t i, size_t j, size_t k, size_t c)
{
    return 0.01 + 0.08 * (double)i + 0.015 * (double)j + 0.004 * (double)k + 0.001 * (double)c;
}

static unsigned char encode(double v, double gain, double gamma)
{
    double x = gain * v;
    if (!(x > 0.0)) return 0;
    if (x >= 1.0) return 255;
    return (unsigned char)floor(255.0 * pow(x, 1.0 / gamma) + 0.5);
}

typedef struct picture {
    unsigned char *px;
    size_t w, h, stride;
} picture;

static picture render(brdffit_texture_kind kind, const brdffit_grid *g, const brdffit_model *m,
                      const double *params, const brdffit_image_options *o)
{
    picture p;
    assert_int_equal(brdffit_image_texture_size(g, o, &p.w, &p.h, NULL), BRDFFIT_OK);
    p.stride = 3 * p.w;
    p.px = malloc(p.stride * p.h);
    assert_non_null(p.px);
    assert_int_equal(brdffit_image_texture(p.px, p.stride, kind, g, m, params, o, NULL, NULL),
                     BRDFFIT_OK);
    return p;
}

static const unsigned char *at(const picture *p, size_t x, size_t y)
{
    return p->px + y * p->stride + 3 * x;
}

static void test_options_init(void **state)
{
    brdffit_image_options a = BRDFFIT_IMAGE_OPTIONS_INIT, b;
    (void)state;
    memset(&b, 0xab, sizeof b);
    brdffit_image_options_init(&b);
    assert_int_equal(b.struct_size, sizeof b);
    assert_true(a.gain == b.gain && a.difference_gain == b.difference_gain);
    assert_true(a.exposure == b.exposure && a.gamma == b.gamma);
    assert_memory_equal(a.background, b.background, 3);
    assert_memory_equal(a.missing, b.missing, 3);
    assert_int_equal(a.scale, 1);
    assert_int_equal(a.block_columns, 1);
    assert_int_equal(b.block_gap, 0);
    assert_int_equal(b.log_y, 0);
    assert_close(a.gain, 3.0, 0.0);
    assert_close(a.gamma, 2.2, 0.0);
    brdffit_image_options_init(NULL); /* no crash */
}

static void test_size(void **state)
{
    brdffit_grid *g = make_grid(constant, 1, NULL), *g2 = NULL;
    brdffit_image_options o = BRDFFIT_IMAGE_OPTIONS_INIT;
    brdffit_axes a;
    double v[N_TI * N_TO * 4];
    static const double po_no_zero[] = {10.0, 60.0, 120.0, 170.0};
    size_t w, h;
    (void)state;
    /* Defaults: stacked blocks, 2 n_phi - 1 columns when phi starts at 0. */
    assert_int_equal(brdffit_image_texture_size(g, NULL, &w, &h, NULL), BRDFFIT_OK);
    assert_int_equal(w, 2 * N_PO - 1);
    assert_int_equal(h, N_TI * N_TO);
    /* Two blocks per row, gap 1, scale 2: 2 rows of blocks. */
    o.scale = 2;
    o.block_columns = 2;
    o.block_gap = 1;
    assert_int_equal(brdffit_image_texture_size(g, &o, &w, &h, NULL), BRDFFIT_OK);
    assert_int_equal(w, 2 * (2 * (2 * N_PO - 1)) + 1);
    assert_int_equal(h, 2 * (2 * N_TO) + 1);
    /* More block columns than blocks: one row. */
    o.block_columns = 10;
    assert_int_equal(brdffit_image_texture_size(g, &o, &w, &h, NULL), BRDFFIT_OK);
    assert_int_equal(w, N_TI * 2 * (2 * N_PO - 1) + (N_TI - 1));
    assert_int_equal(h, 2 * N_TO);
    /* Azimuths not starting at 0: 2 n_phi columns. */
    a = test_axes(po_no_zero, 4);
    memset(v, 0, sizeof v);
    assert_int_equal(brdffit_grid_create_regular(&g2, &a, 1, v, NULL, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_image_texture_size(g2, NULL, &w, &h, NULL), BRDFFIT_OK);
    assert_int_equal(w, 8);
    assert_int_equal(h, N_TI * N_TO);
    brdffit_grid_destroy(g2);
    brdffit_grid_destroy(g);
}

static void test_constant_is_uniform(void **state)
{
    brdffit_grid *g = make_grid(constant, 3, NULL);
    brdffit_image_options o = BRDFFIT_IMAGE_OPTIONS_INIT;
    unsigned char expect = encode(0.1, 3.0, 2.2);
    picture p;
    size_t x, y, c;
    (void)state;
    o.scale = 3;
    p = render(BRDFFIT_TEXTURE_MEASURED, g, NULL, NULL, &o);
    assert_true(expect > 100 && expect < 200); /* 0.3^(1/2.2) * 255 = 148 */
    for (y = 0; y < p.h; y++)
        for (x = 0; x < p.w; x++)
            for (c = 0; c < 3; c++) assert_int_equal(at(&p, x, y)[c], expect);
    free(p.px);
    /* gamma 1, gain 2: linear. */
    o.gamma = 1.0;
    o.gain = 2.0;
    p = render(BRDFFIT_TEXTURE_MEASURED, g, NULL, NULL, &o);
    assert_int_equal(at(&p, 0, 0)[0], 51);
    assert_int_equal(at(&p, p.w - 1, p.h - 1)[2], 51);
    free(p.px);
    brdffit_grid_destroy(g);
}

/* Column of signed azimuth index: k >= 0 right of the middle, mirrored left. */
static void test_mirror_and_order(void **state)
{
    brdffit_grid *g = make_grid(varying, 1, NULL);
    picture p = render(BRDFFIT_TEXTURE_MEASURED, g, NULL, NULL, NULL);
    size_t i, j, k, mid = N_PO - 1;
    (void)state;
    for (i = 0; i < N_TI; i++)
        for (j = 0; j < N_TO; j++)
            for (k = 0; k < N_PO; k++) {
                size_t y = i * N_TO + j;
                unsigned char e = encode(varying(i, j, k, 0), 3.0, 2.2);
                assert_int_equal(at(&p, mid + k, y)[0], e);
                assert_int_equal(at(&p, mid - k, y)[0], e);
                assert_int_equal(at(&p, mid + k, y)[1], e); /* one channel: grey */
                assert_int_equal(at(&p, mid - k, y)[2], e);
            }
    /* The layout is not trivially uniform: azimuth, theta_o and theta_i all
     * change the picture, in the documented directions. */
    assert_true(at(&p, 0, 0)[0] > at(&p, mid, 0)[0]);
    assert_true(at(&p, mid, 1)[0] > at(&p, mid, 0)[0]);
    assert_true(at(&p, mid, N_TO)[0] > at(&p, mid, N_TO - 1)[0]);
    free(p.px);
    brdffit_grid_destroy(g);
}

static void test_block_grid_layout(void **state)
{
    brdffit_grid *g = make_grid(varying, 1, NULL);
    brdffit_image_options o = BRDFFIT_IMAGE_OPTIONS_INIT;
    picture p;
    size_t bw = 2 * N_PO - 1, i, j, k;
    (void)state;
    o.block_columns = 2;
    o.block_gap = 2;
    o.background[0] = 7;
    o.background[1] = 8;
    o.background[2] = 9;
    p = render(BRDFFIT_TEXTURE_MEASURED, g, NULL, NULL, &o);
    assert_int_equal(p.w, 2 * bw + 2);
    assert_int_equal(p.h, 2 * N_TO + 2);
    for (i = 0; i < N_TI; i++)
        for (j = 0; j < N_TO; j++)
            for (k = 0; k < N_PO; k++) {
                size_t x = (i % 2) * (bw + 2) + N_PO - 1 + k, y = (i / 2) * (N_TO + 2) + j;
                assert_int_equal(at(&p, x, y)[0], encode(varying(i, j, k, 0), 3.0, 2.2));
            }
    /* Gap columns and the empty fourth block slot show the background. */
    assert_int_equal(at(&p, bw, 0)[0], 7);
    assert_int_equal(at(&p, bw + 1, N_TO - 1)[2], 9);
    assert_int_equal(at(&p, bw + 2, N_TO + 2)[1], 8);
    assert_int_equal(at(&p, p.w - 1, p.h - 1)[0], 7);
    free(p.px);
    brdffit_grid_destroy(g);
}

static void test_channel_mapping(void **state)
{
    brdffit_grid *g3 = make_grid(varying, 3, NULL), *g2 = make_grid(varying, 2, NULL);
    picture p3 = render(BRDFFIT_TEXTURE_MEASURED, g3, NULL, NULL, NULL);
    picture p2 = render(BRDFFIT_TEXTURE_MEASURED, g2, NULL, NULL, NULL);
    size_t x = N_PO + 1, y = N_TO + 2, k = 2, j = 2, i = 1, c;
    (void)state;
    for (c = 0; c < 3; c++)
        assert_int_equal(at(&p3, x, y)[c], encode(varying(i, j, k, c), 3.0, 2.2));
    for (c = 0; c < 3; c++)
        assert_int_equal(at(&p2, x, y)[c],
                         encode(0.5 * (varying(i, j, k, 0) + varying(i, j, k, 1)), 3.0, 2.2));
    free(p3.px);
    free(p2.px);
    brdffit_grid_destroy(g3);
    brdffit_grid_destroy(g2);
}

/* A grid holding a model's own values at its samples. */
static brdffit_grid *model_grid(const brdffit_model *m, const double *params, size_t nc)
{
    brdffit_grid *base = make_grid(constant, nc, NULL), *g = NULL;
    brdffit_axes a = test_axes(po_deg, N_PO);
    double chan[N * 3], inter[N * 3];
    size_t s, c;
    assert_int_equal(brdffit_model_eval_grid(m, base, 0, N, params, chan, NULL, NULL), BRDFFIT_OK);
    for (s = 0; s < N; s++)
        for (c = 0; c < nc; c++) inter[s * nc + c] = chan[c * N + s];
    assert_int_equal(brdffit_grid_create_regular(&g, &a, nc, inter, NULL, NULL, NULL), BRDFFIT_OK);
    brdffit_grid_destroy(base);
    return g;
}

static void test_model_and_difference(void **state)
{
    brdffit_model *m = NULL;
    double params[7] = {40.0, 0.05, 0.08, 0.11, 0.02, 0.03, 0.04}, more[7], less[7];
    brdffit_grid *g;
    picture meas, model, diff;
    size_t x, y, i, c;
    (void)state;
    assert_int_equal(brdffit_model_create(&m, "ashikhmin-shirley", NULL, NULL), BRDFFIT_OK);
    g = model_grid(m, params, 3);
    meas = render(BRDFFIT_TEXTURE_MEASURED, g, NULL, NULL, NULL);
    model = render(BRDFFIT_TEXTURE_MODEL, g, m, params, NULL);
    diff = render(BRDFFIT_TEXTURE_DIFFERENCE, g, m, params, NULL);
    assert_memory_equal(meas.px, model.px, meas.stride * meas.h);
    for (y = 0; y < diff.h; y++)
        for (x = 0; x < diff.w; x++)
            for (c = 0; c < 3; c++) assert_int_equal(at(&diff, x, y)[c], 0);
    free(diff.px);
    /* A brighter model is red everywhere, a darker one blue. */
    memcpy(more, params, sizeof params);
    memcpy(less, params, sizeof params);
    for (i = 1; i <= 3; i++) {
        more[i] += 0.02;
        less[i] -= 0.02;
    }
    diff = render(BRDFFIT_TEXTURE_DIFFERENCE, g, m, more, NULL);
    /* d = 3 * 0.02 / pi per pixel, the diffuse term alone. */
    for (y = 0; y < diff.h; y++)
        for (x = 0; x < diff.w; x++) {
            assert_int_equal(at(&diff, x, y)[0], encode(0.02 / PI, 3.0, 2.2));
            assert_int_equal(at(&diff, x, y)[1], 0);
            assert_int_equal(at(&diff, x, y)[2], 0);
        }
    free(diff.px);
    diff = render(BRDFFIT_TEXTURE_DIFFERENCE, g, m, less, NULL);
    assert_int_equal(at(&diff, 3, 5)[0], 0);
    assert_int_equal(at(&diff, 3, 5)[2], encode(0.02 / PI, 3.0, 2.2));
    free(diff.px);
    free(meas.px);
    free(model.px);
    brdffit_grid_destroy(g);
    brdffit_model_destroy(m);
}

static void test_missing(void **state)
{
    unsigned char mask[N * 2];
    brdffit_model *m = NULL;
    double params[5] = {0.2, 0.3};
    brdffit_grid *g;
    brdffit_image_options o = BRDFFIT_IMAGE_OPTIONS_INIT;
    picture meas, diff, model;
    size_t s = (1 * N_TO + 2) * N_PO + 3; /* i = 1, j = 2, k = 3 */
    size_t y = N_TO + 2, mid = N_PO - 1;
    (void)state;
    memset(mask, 0, sizeof mask);
    mask[s * 2 + 1] = 1; /* one channel missing marks the sample */
    g = make_grid(constant, 2, mask);
    assert_int_equal(brdffit_model_create(&m, "lambert", NULL, NULL), BRDFFIT_OK);
    o.missing[0] = 1;
    o.missing[1] = 2;
    o.missing[2] = 3;
    meas = render(BRDFFIT_TEXTURE_MEASURED, g, NULL, NULL, &o);
    diff = render(BRDFFIT_TEXTURE_DIFFERENCE, g, m, params, &o);
    model = render(BRDFFIT_TEXTURE_MODEL, g, m, params, &o);
    assert_memory_equal(at(&meas, mid + 3, y), o.missing, 3);
    assert_memory_equal(at(&meas, mid - 3, y), o.missing, 3);
    assert_memory_equal(at(&diff, mid + 3, y), o.missing, 3);
    assert_int_equal(at(&meas, mid + 2, y)[0], encode(0.1, 3.0, 2.2));
    /* The model texture has no missing samples. */
    assert_int_equal(at(&model, mid + 3, y)[0], encode(0.25 / PI, 3.0, 2.2));
    free(meas.px);
    free(diff.px);
    free(model.px);
    brdffit_grid_destroy(g);
    brdffit_model_destroy(m);
}

static void test_stride_padding_untouched(void **state)
{
    brdffit_grid *g = make_grid(varying, 3, NULL);
    size_t w, h, stride, y, x;
    unsigned char *px;
    (void)state;
    assert_int_equal(brdffit_image_texture_size(g, NULL, &w, &h, NULL), BRDFFIT_OK);
    stride = 3 * w + 5;
    px = malloc(stride * h);
    assert_non_null(px);
    memset(px, 0xee, stride * h);
    assert_int_equal(brdffit_image_texture(px, stride, BRDFFIT_TEXTURE_MEASURED, g, NULL, NULL,
                                           NULL, NULL, NULL),
                     BRDFFIT_OK);
    for (y = 0; y < h; y++)
        for (x = 3 * w; x < stride; x++) assert_int_equal(px[y * stride + x], 0xee);
    free(px);
    brdffit_grid_destroy(g);
}

static void test_bad_arguments(void **state)
{
    brdffit_grid *g = make_grid(constant, 1, NULL), *sc = NULL, *wide = NULL;
    brdffit_model *m = NULL;
    brdffit_image_options o = BRDFFIT_IMAGE_OPTIONS_INIT;
    brdffit_error err;
    unsigned char px[3 * 9 * 12];
    double params[2] = {0.1, 0.1}, th = 0.1, v = 0.5, wide_po[300], wv[N_TI * N_TO * 300];
    brdffit_axes a;
    size_t w, h, k;
    const size_t stride = 3 * 9;
    (void)state;
    assert_int_equal(brdffit_model_create(&m, "lambert", NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_image_texture_size(NULL, NULL, &w, &h, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(err.status, BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_image_texture_size(g, NULL, NULL, &h, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_image_texture(NULL, stride, BRDFFIT_TEXTURE_MEASURED, g, NULL, NULL,
                                           NULL, NULL, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_image_texture(px, stride - 1, BRDFFIT_TEXTURE_MEASURED, g, NULL, NULL,
                                           NULL, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "stride"));
    assert_int_equal(
        brdffit_image_texture(px, stride, (brdffit_texture_kind)7, g, NULL, NULL, NULL, NULL, NULL),
        BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(
        brdffit_image_texture(px, stride, BRDFFIT_TEXTURE_MODEL, g, NULL, params, NULL, NULL, NULL),
        BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(
        brdffit_image_texture(px, stride, BRDFFIT_TEXTURE_DIFFERENCE, g, m, NULL, NULL, NULL, NULL),
        BRDFFIT_E_INVALID_ARGUMENT);
    /* Options: too small a size, gamma, scale, gain. */
    o.struct_size = sizeof(size_t);
    assert_int_equal(brdffit_image_texture_size(g, &o, &w, &h, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "struct_size"));
    brdffit_image_options_init(&o);
    o.gamma = 0.0;
    assert_int_equal(brdffit_image_texture_size(g, &o, &w, &h, NULL), BRDFFIT_E_INVALID_ARGUMENT);
    brdffit_image_options_init(&o);
    o.scale = 0;
    assert_int_equal(brdffit_image_texture_size(g, &o, &w, &h, NULL), BRDFFIT_E_INVALID_ARGUMENT);
    brdffit_image_options_init(&o);
    o.gain = NAN;
    assert_int_equal(
        brdffit_image_texture(px, stride, BRDFFIT_TEXTURE_MEASURED, g, NULL, NULL, &o, NULL, NULL),
        BRDFFIT_E_INVALID_ARGUMENT);
    brdffit_image_options_init(&o);
    o.block_columns = 0;
    assert_int_equal(brdffit_image_texture_size(g, &o, &w, &h, NULL), BRDFFIT_E_INVALID_ARGUMENT);
    /* Scattered grid. */
    assert_int_equal(
        brdffit_grid_create_scattered(&sc, 1, &th, &th, &th, &th, 1, &v, NULL, NULL, NULL, NULL),
        BRDFFIT_OK);
    assert_int_equal(brdffit_image_texture_size(sc, NULL, &w, &h, &err), BRDFFIT_E_UNSUPPORTED);
    assert_int_equal(brdffit_image_texture(px, stride, BRDFFIT_TEXTURE_MEASURED, sc, NULL, NULL,
                                           NULL, NULL, NULL),
                     BRDFFIT_E_UNSUPPORTED);
    /* Too large: 599 columns times scale 64. */
    for (k = 0; k < 300; k++) wide_po[k] = 0.6 * (double)k;
    a = test_axes(wide_po, 300);
    memset(wv, 0, sizeof wv);
    assert_int_equal(brdffit_grid_create_regular(&wide, &a, 1, wv, NULL, NULL, NULL), BRDFFIT_OK);
    brdffit_image_options_init(&o);
    o.scale = 64;
    assert_int_equal(brdffit_image_texture_size(wide, &o, &w, &h, NULL), BRDFFIT_E_TOO_LARGE);
    o.scale = 27;
    assert_int_equal(brdffit_image_texture_size(wide, &o, &w, &h, NULL), BRDFFIT_OK);
    assert_int_equal(w, 599 * 27);
    /* Model failures come through: a colour vector with NaN. */
    params[0] = NAN;
    assert_int_not_equal(
        brdffit_image_texture(px, stride, BRDFFIT_TEXTURE_MODEL, g, m, params, NULL, NULL, &err),
        BRDFFIT_OK);
    brdffit_grid_destroy(wide);
    brdffit_grid_destroy(sc);
    brdffit_grid_destroy(g);
    brdffit_model_destroy(m);
}

static void test_allocation_failure(void **state)
{
    brdffit_grid *g = make_grid(varying, 3, NULL);
    brdffit_model *m = NULL;
    double params[6] = {0.1, 0.2, 0.3, 0.0, 0.0, 0.0};
    unsigned char px[3 * 9 * 12], ref[3 * 9 * 12];
    counting_alloc ca;
    brdffit_allocator broken = {NULL, NULL, NULL};
    brdffit_texture_kind kinds[3] = {BRDFFIT_TEXTURE_MEASURED, BRDFFIT_TEXTURE_MODEL,
                                     BRDFFIT_TEXTURE_DIFFERENCE};
    size_t k;
    (void)state;
    assert_int_equal(brdffit_model_create(&m, "lambert", NULL, NULL), BRDFFIT_OK);
    for (k = 0; k < 3; k++) {
        brdffit_error err;
        counting_alloc_init(&ca, 1);
        assert_int_equal(
            brdffit_image_texture(px, 27, kinds[k], g, m, params, NULL, &ca.hook, &err),
            BRDFFIT_E_OUT_OF_MEMORY);
        assert_int_equal(err.status, BRDFFIT_E_OUT_OF_MEMORY);
        assert_int_equal(ca.live, 0);
        counting_alloc_init(&ca, 0);
        assert_int_equal(
            brdffit_image_texture(px, 27, kinds[k], g, m, params, NULL, &ca.hook, NULL),
            BRDFFIT_OK);
        assert_true(ca.allocs >= 1);
        assert_int_equal(ca.live, 0);
        assert_int_equal(brdffit_image_texture(ref, 27, kinds[k], g, m, params, NULL, NULL, NULL),
                         BRDFFIT_OK);
        assert_memory_equal(px, ref, sizeof px);
    }
    assert_int_equal(
        brdffit_image_texture(px, 27, BRDFFIT_TEXTURE_MEASURED, g, NULL, NULL, NULL, &broken, NULL),
        BRDFFIT_E_INVALID_ARGUMENT);
    brdffit_grid_destroy(g);
    brdffit_model_destroy(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_options_init),
        cmocka_unit_test(test_size),
        cmocka_unit_test(test_constant_is_uniform),
        cmocka_unit_test(test_mirror_and_order),
        cmocka_unit_test(test_block_grid_layout),
        cmocka_unit_test(test_channel_mapping),
        cmocka_unit_test(test_model_and_difference),
        cmocka_unit_test(test_missing),
        cmocka_unit_test(test_stride_padding_untouched),
        cmocka_unit_test(test_bad_arguments),
        cmocka_unit_test(test_allocation_failure),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
