/* Spheres lit by a point light (image.h): background outside the disc,
 * the centre pixel against the formula written out here, the Lambert
 * cosine falloff across the disc, symmetry (the tangent frame must not
 * show with an isotropic BRDF), unlit and missing regions, bad arguments
 * and allocation failure. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "test_support.h"

#define PI 3.14159265358979323846
#define SIZE 41

static unsigned char encode(double v, double gamma)
{
    if (!(v > 0.0)) return 0;
    if (v >= 1.0) return 255;
    return (unsigned char)floor(255.0 * pow(v, 1.0 / gamma) + 0.5);
}

/* Pixel centre to disc coordinates, as documented. */
static void disc(size_t x, size_t y, size_t size, double *u, double *w)
{
    *u = (2.0 * (double)x + 1.0) / (double)size - 1.0;
    *w = 1.0 - (2.0 * (double)y + 1.0) / (double)size;
}

static const unsigned char *at(const unsigned char *px, size_t x, size_t y)
{
    return px + y * 3 * SIZE + 3 * x;
}

typedef double (*value_fn)(double ti, double to, double po, size_t c);

static const double *const_value;

static double constant(double ti, double to, double po, size_t c)
{
    (void)ti, (void)to, (void)po;
    return const_value[c];
}

/* Peaked toward the mirror direction, so that azimuth matters. */
static double glossy(double ti, double to, double po, size_t c)
{
    return 0.05 + 0.02 * (double)c + 0.3 * exp(-2.0 * (ti - to) * (ti - to)) * (1.0 + cos(po));
}

/* A regular grid on coarse axes holding f. */
static brdffit_grid *grid_of(value_fn f, size_t nc, int all_missing)
{
    static const double deg_t[] = {0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 90.0};
    static const double deg_p[] = {0.0, 30.0, 60.0, 90.0, 120.0, 150.0, 180.0};
    enum { NA = 7, NS = NA * NA * NA };
    double t[NA], p[NA], v[NS * 3];
    unsigned char mask[NS * 3];
    brdffit_axes a;
    brdffit_grid *g = NULL;
    size_t s, c;
    for (s = 0; s < NA; s++) {
        t[s] = DEG(deg_t[s]);
        p[s] = DEG(deg_p[s]);
    }
    a.theta_i = t;
    a.n_theta_i = NA;
    a.theta_o = t;
    a.n_theta_o = NA;
    a.phi_o = p;
    a.n_phi_o = NA;
    for (s = 0; s < NS; s++)
        for (c = 0; c < nc; c++) v[s * nc + c] = f(t[s / (NA * NA)], t[s / NA % NA], p[s % NA], c);
    memset(mask, all_missing ? 1 : 0, sizeof mask);
    assert_int_equal(brdffit_grid_create_regular(&g, &a, nc, v, mask, NULL, NULL), BRDFFIT_OK);
    return g;
}

static brdffit_grid *constant_grid(const double *value, size_t nc, int all_missing)
{
    const_value = value;
    return grid_of(constant, nc, all_missing);
}

static void test_background_outside(void **state)
{
    brdffit_model *m = NULL;
    brdffit_image_options o = BRDFFIT_IMAGE_OPTIONS_INIT;
    double params[3] = {0.5, 0.4, 0.3};
    unsigned char px[SIZE * SIZE * 3];
    size_t x, y, inside = 0;
    (void)state;
    assert_int_equal(brdffit_model_create(&m, "lambert", NULL, NULL), BRDFFIT_OK);
    o.background[0] = 1;
    o.background[1] = 2;
    o.background[2] = 3;
    assert_int_equal(
        brdffit_image_sphere_model(px, 3 * SIZE, SIZE, m, params, 3, 0.0, 0.0, &o, NULL, NULL),
        BRDFFIT_OK);
    for (y = 0; y < SIZE; y++)
        for (x = 0; x < SIZE; x++) {
            double u, w;
            disc(x, y, SIZE, &u, &w);
            if (u * u + w * w > 1.0) {
                assert_int_equal(at(px, x, y)[0], 1);
                assert_int_equal(at(px, x, y)[1], 2);
                assert_int_equal(at(px, x, y)[2], 3);
            } else {
                inside++;
                assert_true(at(px, x, y)[0] != 1 || at(px, x, y)[2] != 3);
            }
        }
    /* The disc covers about pi/4 of the square. */
    assert_true(fabs((double)inside / (SIZE * SIZE) - PI / 4.0) < 0.03);
    brdffit_model_destroy(m);
}

/* Centre pixel: n = v = +z, theta_o = 0, theta_i = light angle. The
 * Ashikhmin-Shirley value there, written out: h bisects l and v, so
 * n.h = h.v = cos(theta_i / 2), max(n.l, n.v) = 1. */
static void test_centre_matches_formula(void **state)
{
    brdffit_model *m = NULL;
    brdffit_image_options o = BRDFFIT_IMAGE_OPTIONS_INIT;
    double params[7] = {60.0, 0.05, 0.10, 0.15, 0.30, 0.20, 0.10};
    double angles[3] = {0.0, DEG(20.0), DEG(50.0)};
    unsigned char px[SIZE * SIZE * 3];
    size_t a, c;
    (void)state;
    assert_int_equal(brdffit_model_create(&m, "ashikhmin-shirley", NULL, NULL), BRDFFIT_OK);
    o.exposure = 0.8;
    o.gamma = 2.0;
    for (a = 0; a < 3; a++) {
        double ti = angles[a], ch = cos(ti / 2.0), ns = params[0];
        assert_int_equal(
            brdffit_image_sphere_model(px, 3 * SIZE, SIZE, m, params, 3, ti, 1.0, &o, NULL, NULL),
            BRDFFIT_OK);
        for (c = 0; c < 3; c++) {
            double f =
                params[1 + c] / PI + (ns + 1.0) / (8.0 * PI) * pow(ch, ns) / ch * params[4 + c];
            int expect = encode(0.8 * f * cos(ti), 2.0);
            int got = at(px, SIZE / 2, SIZE / 2)[c];
            assert_true(abs(got - expect) <= 1);
            assert_true(expect > 20 && expect < 250); /* a meaningful comparison */
        }
    }
    brdffit_model_destroy(m);
}

/* A constant measured BRDF k: every lit pixel is encode(exposure k n.l). */
static void test_measured_constant_is_lambert(void **state)
{
    double k[1] = {0.2};
    brdffit_grid *g = constant_grid(k, 1, 0);
    brdffit_image_options o = BRDFFIT_IMAGE_OPTIONS_INIT;
    unsigned char px[SIZE * SIZE * 3];
    double lt = DEG(40.0), lp = DEG(200.0);
    double l[3] = {sin(lt) * cos(lp), sin(lt) * sin(lp), cos(lt)};
    size_t x, y, lit = 0, dark = 0;
    (void)state;
    assert_int_equal(brdffit_image_sphere_measured(px, 3 * SIZE, SIZE, g, lt, lp, &o, NULL, NULL),
                     BRDFFIT_OK);
    for (y = 0; y < SIZE; y++)
        for (x = 0; x < SIZE; x++) {
            double u, w, nz, nl;
            int expect;
            disc(x, y, SIZE, &u, &w);
            if (u * u + w * w > 1.0) continue;
            nz = sqrt(1.0 - u * u - w * w);
            nl = u * l[0] + w * l[1] + nz * l[2];
            expect = nl > 0.0 ? encode(PI * 0.2 * nl, 2.2) : 0;
            assert_true(abs(at(px, x, y)[0] - expect) <= 1);
            assert_int_equal(at(px, x, y)[0], at(px, x, y)[1]); /* grey */
            if (nl > 0.0)
                lit++;
            else
                dark++;
        }
    assert_true(lit > 0 && dark > 0);
    brdffit_grid_destroy(g);
}

static void assert_symmetric(const unsigned char *px, int transpose, int flip_x, int flip_y)
{
    size_t x, y, c;
    for (y = 0; y < SIZE; y++)
        for (x = 0; x < SIZE; x++)
            for (c = 0; c < 3; c++) {
                int p = at(px, x, y)[c];
                if (flip_x) assert_true(abs(p - at(px, SIZE - 1 - x, y)[c]) <= 1);
                if (flip_y) assert_true(abs(p - at(px, x, SIZE - 1 - y)[c]) <= 1);
                if (transpose) assert_true(abs(p - at(px, y, x)[c]) <= 1);
            }
}

/* The picture has the symmetry of the lighting (up to one step of
 * rounding), whichever tangent frame each pixel gets: head-on light gives
 * the symmetry of the square, light from the right (phi 0) a mirror image
 * top to bottom. */
static void test_isotropy_symmetry(void **state)
{
    brdffit_model *m = NULL;
    double params[7] = {30.0, 0.05, 0.10, 0.15, 0.30, 0.20, 0.10};
    brdffit_grid *g = grid_of(glossy, 3, 0);
    unsigned char px[SIZE * SIZE * 3];
    (void)state;
    assert_int_equal(brdffit_model_create(&m, "ashikhmin-shirley", NULL, NULL), BRDFFIT_OK);
    assert_int_equal(
        brdffit_image_sphere_model(px, 3 * SIZE, SIZE, m, params, 3, 0.0, 0.0, NULL, NULL, NULL),
        BRDFFIT_OK);
    assert_symmetric(px, 1, 1, 1);
    assert_int_equal(
        brdffit_image_sphere_measured(px, 3 * SIZE, SIZE, g, 0.0, 0.0, NULL, NULL, NULL),
        BRDFFIT_OK);
    assert_symmetric(px, 1, 1, 1);
    assert_int_equal(brdffit_image_sphere_model(px, 3 * SIZE, SIZE, m, params, 3, DEG(60.0), 0.0,
                                                NULL, NULL, NULL),
                     BRDFFIT_OK);
    assert_symmetric(px, 0, 0, 1);
    assert_true(at(px, SIZE - 8, SIZE / 2)[2] > at(px, 8, SIZE / 2)[2]);
    assert_int_equal(
        brdffit_image_sphere_measured(px, 3 * SIZE, SIZE, g, DEG(60.0), 0.0, NULL, NULL, NULL),
        BRDFFIT_OK);
    assert_symmetric(px, 0, 0, 1);
    assert_true(at(px, SIZE - 8, SIZE / 2)[2] > at(px, 8, SIZE / 2)[2]);
    brdffit_grid_destroy(g);
    brdffit_model_destroy(m);
}

static void test_unlit_and_missing(void **state)
{
    double k[2] = {0.3, 0.3};
    brdffit_grid *g = constant_grid(k, 2, 1);
    brdffit_model *m = NULL;
    brdffit_image_options o = BRDFFIT_IMAGE_OPTIONS_INIT;
    double params[2] = {0.5, 0.5};
    unsigned char px[SIZE * SIZE * 3];
    size_t x, y;
    (void)state;
    assert_int_equal(brdffit_model_create(&m, "lambert", NULL, NULL), BRDFFIT_OK);
    o.missing[0] = 9;
    o.missing[1] = 8;
    o.missing[2] = 7;
    /* Light from behind: the whole disc is dark. */
    assert_int_equal(
        brdffit_image_sphere_model(px, 3 * SIZE, SIZE, m, params, 2, PI, 0.0, &o, NULL, NULL),
        BRDFFIT_OK);
    assert_int_equal(at(px, SIZE / 2, SIZE / 2)[0], 0);
    assert_int_equal(at(px, SIZE / 2 + 5, SIZE / 2 - 7)[1], 0);
    assert_int_equal(at(px, 0, 0)[0], o.background[0]);
    /* Every value missing: lit pixels show the missing colour. */
    assert_int_equal(brdffit_image_sphere_measured(px, 3 * SIZE, SIZE, g, 0.0, 0.0, &o, NULL, NULL),
                     BRDFFIT_OK);
    for (y = 0; y < SIZE; y++)
        for (x = 0; x < SIZE; x++) {
            double u, w;
            disc(x, y, SIZE, &u, &w);
            if (u * u + w * w < 0.99) assert_memory_equal(at(px, x, y), o.missing, 3);
        }
    brdffit_grid_destroy(g);
    brdffit_model_destroy(m);
}

static void test_bad_arguments(void **state)
{
    double k[1] = {0.2}, params[1] = {0.5}, th = 0.2, v = 0.1;
    brdffit_grid *g = constant_grid(k, 1, 0), *sc = NULL;
    brdffit_model *m = NULL;
    brdffit_image_options o = BRDFFIT_IMAGE_OPTIONS_INIT;
    brdffit_error err;
    unsigned char px[SIZE * SIZE * 3];
    (void)state;
    assert_int_equal(brdffit_model_create(&m, "lambert", NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_image_sphere_measured(NULL, 3 * SIZE, SIZE, g, 0, 0, NULL, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(err.status, BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(
        brdffit_image_sphere_measured(px, 3 * SIZE, SIZE, NULL, 0, 0, NULL, NULL, NULL),
        BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_image_sphere_measured(px, 3 * SIZE, 0, g, 0, 0, NULL, NULL, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(
        brdffit_image_sphere_measured(px, 3 * SIZE - 1, SIZE, g, 0, 0, NULL, NULL, NULL),
        BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(
        brdffit_image_sphere_measured(px, (size_t)3 * 40000, 40000, g, 0, 0, NULL, NULL, NULL),
        BRDFFIT_E_TOO_LARGE);
    assert_int_equal(
        brdffit_image_sphere_measured(px, 3 * SIZE, SIZE, g, -0.1, 0, NULL, NULL, NULL),
        BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_image_sphere_measured(px, 3 * SIZE, SIZE, g, NAN, 0, NULL, NULL, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_image_sphere_model(px, 3 * SIZE, SIZE, m, params, 1, 0.0, INFINITY,
                                                NULL, NULL, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(
        brdffit_image_sphere_model(px, 3 * SIZE, SIZE, m, params, 0, 0, 0, NULL, NULL, NULL),
        BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(
        brdffit_image_sphere_model(px, 3 * SIZE, SIZE, NULL, params, 1, 0, 0, NULL, NULL, NULL),
        BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(
        brdffit_image_sphere_model(px, 3 * SIZE, SIZE, m, NULL, 1, 0, 0, NULL, NULL, NULL),
        BRDFFIT_E_INVALID_ARGUMENT);
    o.exposure = -1.0;
    assert_int_equal(
        brdffit_image_sphere_model(px, 3 * SIZE, SIZE, m, params, 1, 0, 0, &o, NULL, &err),
        BRDFFIT_E_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "exposure"));
    assert_int_equal(
        brdffit_grid_create_scattered(&sc, 1, &th, &th, &th, &th, 1, &v, NULL, NULL, NULL, NULL),
        BRDFFIT_OK);
    assert_int_equal(brdffit_image_sphere_measured(px, 3 * SIZE, SIZE, sc, 0, 0, NULL, NULL, &err),
                     BRDFFIT_E_UNSUPPORTED);
    /* A model failure comes through with the model's status. */
    params[0] = NAN;
    assert_int_not_equal(
        brdffit_image_sphere_model(px, 3 * SIZE, SIZE, m, params, 1, 0, 0, NULL, NULL, &err),
        BRDFFIT_OK);
    brdffit_grid_destroy(sc);
    brdffit_grid_destroy(g);
    brdffit_model_destroy(m);
}

static void test_allocation_failure(void **state)
{
    double k[3] = {0.2, 0.1, 0.05}, params[3] = {0.5, 0.4, 0.3};
    brdffit_grid *g = constant_grid(k, 3, 0);
    brdffit_model *m = NULL;
    unsigned char px[SIZE * SIZE * 3];
    counting_alloc ca;
    size_t fail;
    (void)state;
    assert_int_equal(brdffit_model_create(&m, "lambert", NULL, NULL), BRDFFIT_OK);
    for (fail = 1; fail <= 2; fail++) {
        brdffit_error err;
        counting_alloc_init(&ca, fail);
        assert_int_equal(
            brdffit_image_sphere_measured(px, 3 * SIZE, SIZE, g, 0.3, 0.0, NULL, &ca.hook, &err),
            BRDFFIT_E_OUT_OF_MEMORY);
        assert_int_equal(err.status, BRDFFIT_E_OUT_OF_MEMORY);
        assert_int_equal(ca.live, 0);
        counting_alloc_init(&ca, fail);
        assert_int_equal(brdffit_image_sphere_model(px, 3 * SIZE, SIZE, m, params, 3, 0.3, 0.0,
                                                    NULL, &ca.hook, NULL),
                         BRDFFIT_E_OUT_OF_MEMORY);
        assert_int_equal(ca.live, 0);
    }
    counting_alloc_init(&ca, 3);
    assert_int_equal(brdffit_image_sphere_model(px, 3 * SIZE, SIZE, m, params, 3, 0.3, 0.0, NULL,
                                                &ca.hook, NULL),
                     BRDFFIT_OK);
    assert_int_equal(ca.allocs, 2);
    assert_int_equal(ca.live, 0);
    brdffit_grid_destroy(g);
    brdffit_model_destroy(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_background_outside),
        cmocka_unit_test(test_centre_matches_formula),
        cmocka_unit_test(test_measured_constant_is_lambert),
        cmocka_unit_test(test_isotropy_symmetry),
        cmocka_unit_test(test_unlit_and_missing),
        cmocka_unit_test(test_bad_arguments),
        cmocka_unit_test(test_allocation_failure),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
