/* Interpolation of a regular grid: nodes, trilinear interpolation, folding
 * by isotropy, mirror symmetry and reciprocity, missing neighbours. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "grid_fixtures.h"
#include "test_support.h"

#define PI 3.14159265358979323846

static const double ti_deg[] = {0.0, 15.0, 40.0, 60.0};
static const double to_deg[] = {0.0, 10.0, 30.0, 45.0, 80.0, 90.0};
static const double po_deg[] = {0.0, 20.0, 90.0, 135.0, 180.0};
enum { N_TI = 4, N_TO = 6, N_PO = 5, N = N_TI * N_TO * N_PO };

/* Trilinear in (theta_i, theta_o, phi_o): interpolation reproduces it. */
static double trilinear(double ti, double to, double po, size_t c)
{
    return 1.0 + c + 0.5 * ti + 0.25 * to + 0.125 * po + 0.3 * ti * to - 0.1 * to * po +
           0.05 * ti * to * po;
}

static brdffit_grid *make(double (*f)(double, double, double, size_t), size_t nc,
                          const unsigned char *mask, fx_axes *a)
{
    double v[N * 3];
    size_t s, c;
    brdffit_grid *g = NULL;
    fx_axes_set(a, ti_deg, N_TI, to_deg, N_TO, po_deg, N_PO);
    for (s = 0; s < N; s++)
        for (c = 0; c < nc; c++)
            v[s * nc + c] =
                f(a->rad[0][s / (N_TO * N_PO)], a->rad[1][s / N_PO % N_TO], a->rad[2][s % N_PO], c);
    assert_int_equal(brdffit_grid_create_regular(&g, &a->axes, nc, v, mask, NULL, NULL),
                     BRDFFIT_OK);
    return g;
}

static double eval1(const brdffit_grid *g, double ti, double pi_, double to, double po)
{
    double out[3];
    assert_int_equal(brdffit_grid_eval(g, ti, pi_, to, po, out, NULL), BRDFFIT_OK);
    return out[0];
}

static void test_nodes_exact(void **state)
{
    fx_axes a;
    brdffit_grid *g = make(fx_value, 3, NULL, &a);
    const double *vals[3];
    double out[3];
    size_t s, c;
    (void)state;
    for (c = 0; c < 3; c++) brdffit_grid_values(g, c, &vals[c]);
    for (s = 0; s < N; s++) {
        double ti = a.rad[0][s / (N_TO * N_PO)], to = a.rad[1][s / N_PO % N_TO];
        double po = a.rad[2][s % N_PO];
        assert_int_equal(brdffit_grid_eval(g, ti, PI, to, po, out, NULL), BRDFFIT_OK);
        for (c = 0; c < 3; c++) assert_true(out[c] == vals[c][s]);
    }
    brdffit_grid_destroy(g);
}

static void test_trilinear_between_nodes(void **state)
{
    fx_axes a;
    brdffit_grid *g = make(trilinear, 2, NULL, &a);
    double out[2];
    int k;
    (void)state;
    for (k = 0; k < 200; k++) {
        double ti = DEG(fmod(k * 7.77, 60.0)), to = DEG(fmod(k * 13.1, 90.0));
        double po = DEG(fmod(k * 29.3, 180.0));
        assert_int_equal(brdffit_grid_eval(g, ti, PI, to, po, out, NULL), BRDFFIT_OK);
        assert_close(out[0], trilinear(ti, to, po, 0), 1e-12);
        assert_close(out[1], trilinear(ti, to, po, 1), 1e-12);
    }
    brdffit_grid_destroy(g);
    /* a non-linear function is interpolated linearly between two nodes */
    g = make(fx_value, 1, NULL, &a);
    {
        double v0 = fx_value(a.rad[0][1], a.rad[1][2], a.rad[2][3], 0);
        double v1 = fx_value(a.rad[0][1], a.rad[1][3], a.rad[2][3], 0);
        double t = 0.3, to = a.rad[1][2] + t * (a.rad[1][3] - a.rad[1][2]);
        assert_close(eval1(g, a.rad[0][1], PI, to, a.rad[2][3]), (1 - t) * v0 + t * v1, 1e-14);
    }
    brdffit_grid_destroy(g);
}

static void test_isotropy_and_mirror(void **state)
{
    fx_axes a;
    brdffit_grid *g = make(trilinear, 1, NULL, &a);
    int k;
    (void)state;
    for (k = 0; k < 50; k++) {
        double ti = DEG(fmod(k * 7.77, 60.0)), to = DEG(fmod(k * 13.1, 90.0));
        double rel = DEG(fmod(k * 29.3, 180.0)); /* relative azimuth from the light */
        double stored = PI - rel;
        double ref = trilinear(ti, to, stored, 0);
        double rot = DEG(k * 41.0) - 3.0;
        /* rotating both directions together changes nothing */
        assert_close(eval1(g, ti, rot, to, rot + rel), ref, 1e-12);
        /* the mirror image (view on the other side of the plane of incidence) */
        assert_close(eval1(g, ti, rot, to, rot - rel), ref, 1e-12);
        /* azimuths beyond one turn */
        assert_close(eval1(g, ti, rot + 4 * PI, to, rot + rel - 6 * PI), ref, 1e-11);
    }
    /* light at azimuth 0: the view at azimuth 0 is backscatter, stored phi_o = pi */
    assert_close(eval1(g, DEG(30), 0.0, DEG(20), 0.0), trilinear(DEG(30), DEG(20), PI, 0), 1e-12);
    assert_close(eval1(g, DEG(30), 0.0, DEG(20), PI), trilinear(DEG(30), DEG(20), 0.0, 0), 1e-12);
    brdffit_grid_destroy(g);
}

static void test_reciprocity(void **state)
{
    fx_axes a;
    brdffit_grid *g = make(trilinear, 1, NULL, &a);
    (void)state;
    /* theta_i = 80 lies beyond the theta_i axis (max 60), theta_o = 30 within:
     * light and view swap; the relative azimuth stays. */
    assert_close(eval1(g, DEG(80), PI, DEG(30), DEG(50)), trilinear(DEG(30), DEG(80), DEG(50), 0),
                 1e-12);
    assert_close(eval1(g, DEG(85), 1.0, DEG(12), 1.0 + DEG(100)),
                 trilinear(DEG(12), DEG(85), DEG(80), 0), 1e-12);
    /* both outside: no swap, theta_i clamps to 60 */
    assert_close(eval1(g, DEG(80), PI, DEG(70), DEG(50)), trilinear(DEG(60), DEG(70), DEG(50), 0),
                 1e-12);
    brdffit_grid_destroy(g);
}

static void test_clamping(void **state)
{
    static const double t[] = {10.0, 50.0};
    static const double p[] = {30.0, 120.0};
    fx_axes a;
    brdffit_grid *g = NULL;
    double v[8];
    size_t s;
    (void)state;
    fx_axes_set(&a, t, 2, t, 2, p, 2);
    for (s = 0; s < 8; s++) v[s] = (double)(s + 1);
    assert_int_equal(brdffit_grid_create_regular(&g, &a.axes, 1, v, NULL, NULL, NULL), BRDFFIT_OK);
    /* below and above every axis: the corner values */
    assert_true(eval1(g, DEG(10), PI, DEG(0), DEG(0)) == 1.0);
    assert_true(eval1(g, DEG(50), PI, DEG(90), DEG(180)) == 8.0);
    /* theta_i beyond its axis and theta_o beyond too: no swap, clamp */
    assert_true(eval1(g, DEG(89), PI, DEG(88), DEG(150)) == 8.0);
    assert_close(eval1(g, DEG(10), PI, DEG(10), DEG(75)), 1.5, 1e-12);
    brdffit_grid_destroy(g);
}

static void test_single_value_axes(void **state)
{
    static const double t1[] = {30.0};
    static const double t2[] = {0.0, 60.0};
    static const double p1[] = {90.0};
    fx_axes a;
    brdffit_grid *g = NULL;
    double v[2] = {2.0, 4.0};
    (void)state;
    fx_axes_set(&a, t1, 1, t2, 2, p1, 1);
    assert_int_equal(brdffit_grid_create_regular(&g, &a.axes, 1, v, NULL, NULL, NULL), BRDFFIT_OK);
    assert_close(eval1(g, DEG(30), PI, DEG(30), DEG(10)), 3.0, 1e-12);
    assert_close(eval1(g, DEG(0), 0.0, DEG(45), 1.0), 3.5, 1e-12);
    brdffit_grid_destroy(g);
}

/* Values at DBL_MAX: the weighted mean stays finite and between its
 * neighbours everywhere (a plain sum of weighted values overflows where
 * the weights add up to a little more than 1 by rounding). */
static void test_huge_values(void **state)
{
    static const double t1[] = {30.0};
    static const double t2[] = {0.0, 60.0};
    static const double p2[] = {0.0, 180.0};
    fx_axes a;
    brdffit_grid *g = NULL;
    double v[4] = {DBL_MAX, DBL_MAX, DBL_MAX, DBL_MAX};
    int i, j;
    (void)state;
    fx_axes_set(&a, t1, 1, t2, 2, p2, 2);
    assert_int_equal(brdffit_grid_create_regular(&g, &a.axes, 1, v, NULL, NULL, NULL), BRDFFIT_OK);
    for (i = 0; i <= 60; i++)
        for (j = 0; j <= 60; j++) {
            double x = eval1(g, DEG(30), PI, DEG(i), DEG(3 * j) + 1e-3 * i);
            if (x != DBL_MAX) print_error("theta_o %d, phi_o %d: %g\n", i, 3 * j, x);
            assert_true(x == DBL_MAX);
        }
    brdffit_grid_destroy(g);
    v[1] = 0.5 * DBL_MAX;
    assert_int_equal(brdffit_grid_create_regular(&g, &a.axes, 1, v, NULL, NULL, NULL), BRDFFIT_OK);
    assert_close(eval1(g, DEG(30), PI, DEG(30), DEG(90)), 0.875 * DBL_MAX, 1e-12);
    assert_close(eval1(g, DEG(30), PI, DEG(30), PI), 0.75 * DBL_MAX, 1e-12);
    brdffit_grid_destroy(g);
}

static void test_missing_neighbours(void **state)
{
    fx_axes a;
    unsigned char mask[N * 2] = {0};
    brdffit_grid *g;
    brdffit_error err;
    double out[2], ti, to, po, t = 0.25;
    size_t s0, s1;
    (void)state;
    /* between nodes (1,2,3) and (1,3,3) along theta_o; node (1,3,3) of channel 1 missing */
    s0 = (1 * N_TO + 2) * N_PO + 3, s1 = (1 * N_TO + 3) * N_PO + 3;
    mask[s1 * 2 + 1] = 1;
    g = make(trilinear, 2, mask, &a);
    ti = a.rad[0][1], po = a.rad[2][3];
    to = a.rad[1][2] + t * (a.rad[1][3] - a.rad[1][2]);
    assert_int_equal(brdffit_grid_eval(g, ti, PI, to, po, out, NULL), BRDFFIT_OK);
    assert_close(out[0], trilinear(ti, to, po, 0), 1e-12);
    assert_close(out[1], trilinear(ti, a.rad[1][2], po, 1), 1e-12); /* only the other node */
    /* at the missing node itself: no data in channel 1, channel 0 still served */
    memset(&err, 0, sizeof err);
    out[1] = 42.0;
    assert_int_equal(brdffit_grid_eval(g, ti, PI, a.rad[1][3], po, out, &err), BRDFFIT_E_NO_DATA);
    assert_true(out[1] == 0.0);
    assert_close(out[0], trilinear(ti, a.rad[1][3], po, 0), 1e-12);
    assert_non_null(strstr(err.message, "channel 1"));
    brdffit_grid_destroy(g);
    /* every neighbour missing in both channels: all zero */
    memset(mask, 1, sizeof mask);
    mask[s0 * 2] = 0; /* far away from the query below */
    g = make(trilinear, 2, mask, &a);
    assert_int_equal(brdffit_grid_eval(g, DEG(50), PI, DEG(85), DEG(30), out, &err),
                     BRDFFIT_E_NO_DATA);
    assert_true(out[0] == 0.0 && out[1] == 0.0);
    brdffit_grid_destroy(g);
}

static void test_eval_errors(void **state)
{
    fx_axes a;
    brdffit_grid *g = make(trilinear, 1, NULL, &a), *sg = NULL;
    brdffit_error err;
    double out[3], t = 0.1, v = 1.0;
    (void)state;
    assert_int_equal(brdffit_grid_eval(NULL, 0, 0, 0, 0, out, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_grid_eval(g, 0, 0, 0, 0, NULL, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_grid_eval(g, NAN, 0, 0, 0, out, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_grid_eval(g, 0, INFINITY, 0, 0, out, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_grid_eval(g, 0, 0, 0, -INFINITY, out, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "finite"));
    assert_int_equal(
        brdffit_grid_create_scattered(&sg, 1, &t, &t, &t, &t, 1, &v, NULL, NULL, NULL, NULL),
        BRDFFIT_OK);
    assert_int_equal(brdffit_grid_eval(sg, 0, 0, 0, 0, out, &err), BRDFFIT_E_UNSUPPORTED);
    assert_int_equal(err.status, BRDFFIT_E_UNSUPPORTED);
    brdffit_grid_destroy(sg);
    brdffit_grid_destroy(g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_nodes_exact),
        cmocka_unit_test(test_trilinear_between_nodes),
        cmocka_unit_test(test_isotropy_and_mirror),
        cmocka_unit_test(test_reciprocity),
        cmocka_unit_test(test_clamping),
        cmocka_unit_test(test_single_value_axes),
        cmocka_unit_test(test_huge_values),
        cmocka_unit_test(test_missing_neighbours),
        cmocka_unit_test(test_eval_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
