/* The ASTM E1392 loader: files written here from a known function of the
 * directions, in degrees and in radians, with commas and with blanks, in
 * the four- and three-angle forms; negative polar angles; data as
 * measured (negative and missing values); every error with its line and
 * column; the file form. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "grid_fixtures.h"
#include "test_support.h"

#define PI 3.14159265358979323846

/* A smooth test function of the light and view directions. */
static double value(double ti, double pi, double to, double po, size_t c)
{
    /* the azimuths matter only off the normal, where they are defined */
    return 0.1 + 0.05 * (double)c + 0.3 * cos(ti) * cos(to) +
           0.2 * sin(ti) * sin(to) * cos(po - pi) - 0.01;
}

/* ASTM text of a scan: theta_i 0..60 step 20, phi_i 0 or 30, theta_s
 * 0..80 step 10, phi_s -180..150 step 30, three channels, in degrees or
 * radians, with commas or blanks (malloc'ed). */
static char *astm_text(int radians, int commas, size_t *rows)
{
    size_t cap = 1 << 20, len = 0, n = 0;
    char *t = malloc(cap);
    const char *sep = commas ? "," : "  ";
    double u = radians ? PI / 180.0 : 1.0;
    int ti, pi, to, po;
    assert_non_null(t);
    len += (size_t)snprintf(t + len, cap - len,
                            "SOURCE \"libbrdffit tests\"\nSAMPLE \"analytic\"\n\nNUM_POINTS %d\n"
                            "VARS theta_i%sphi_i%stheta_s%sphi_s%sR%sG%sB\r\n",
                            4 * 2 * 9 * 12, sep, sep, sep, sep, sep, sep);
    for (ti = 0; ti <= 60; ti += 20)
        for (pi = 0; pi <= 30; pi += 30)
            for (to = 0; to <= 80; to += 10)
                for (po = -180; po < 180; po += 30, n++) {
                    size_t c;
                    len += (size_t)snprintf(t + len, cap - len, "%.17g%s%.17g%s%.17g%s%.17g",
                                            ti * u, sep, pi * u, sep, to * u, sep, po * u);
                    for (c = 0; c < 3; c++)
                        len += (size_t)snprintf(t + len, cap - len, "%s%.17g", sep,
                                                value(DEG(ti), DEG(pi), DEG(to), DEG(po), c));
                    len += (size_t)snprintf(t + len, cap - len, "\n");
                }
    *rows = n;
    return t;
}

static brdffit_grid *load_ok(const char *text)
{
    brdffit_grid *g = NULL;
    brdffit_error err;
    if (brdffit_load_astm_buffer(&g, text, strlen(text), NULL, &err) != BRDFFIT_OK)
        fail_msg("load: %s", err.message);
    return g;
}

/* Every sample against the function at its own directions. */
static void check_values(const brdffit_grid *g, size_t rows)
{
    size_t s, c;
    assert_int_equal(brdffit_grid_get_kind(g), BRDFFIT_GRID_SCATTERED);
    assert_int_equal(brdffit_grid_sample_count(g), rows);
    assert_int_equal(brdffit_grid_channel_count(g), 3);
    for (s = 0; s < rows; s++) {
        double a[4];
        assert_int_equal(brdffit_grid_sample_angles(g, s, &a[0], &a[1], &a[2], &a[3]), BRDFFIT_OK);
        for (c = 0; c < 3; c++) {
            const double *v;
            assert_int_equal(brdffit_grid_values(g, c, &v), BRDFFIT_OK);
            assert_close(v[s], value(a[0], a[1], a[2], a[3], c), 1e-12);
        }
    }
}

static void test_degrees_radians_commas_blanks(void **state)
{
    int radians, commas;
    (void)state;
    for (radians = 0; radians < 2; radians++)
        for (commas = 0; commas < 2; commas++) {
            size_t rows;
            char *t = astm_text(radians, commas, &rows);
            brdffit_grid *g = load_ok(t);
            check_values(g, rows);
            brdffit_grid_destroy(g);
            free(t);
        }
}

static void test_three_angles_and_bands(void **state)
{
    const char *text = "VARS theta_i theta_s phi_s 450nm 550nm\n"
                       "30 20 0 0.5 0.25\n30 -20 0 0.75 1e-3\n";
    brdffit_grid *g = load_ok(text);
    double a[4];
    const double *v;
    (void)state;
    assert_int_equal(brdffit_grid_sample_count(g), 2);
    assert_int_equal(brdffit_grid_channel_count(g), 2);
    /* theta_s = -20, phi_s = 0 is theta_s = 20, phi_s = 180 */
    assert_int_equal(brdffit_grid_sample_angles(g, 1, &a[0], &a[1], &a[2], &a[3]), BRDFFIT_OK);
    assert_close(a[0], DEG(30.0), 1e-12);
    assert_close(a[1], 0.0, 1e-12);
    assert_close(a[2], DEG(20.0), 1e-12);
    assert_close(fabs(a[3]), PI, 1e-12);
    assert_int_equal(brdffit_grid_values(g, 1, &v), BRDFFIT_OK);
    assert_true(v[0] == 0.25 && v[1] == 1e-3);
    brdffit_grid_destroy(g);
    /* radians printed with four decimals: 1.5708 is pi/2, not 1.57 degrees */
    g = load_ok("VARS theta_i,phi_i,theta_s,phi_s,R\n0.5236,0,1.5708,3.1416,0.1\n");
    assert_int_equal(brdffit_grid_sample_angles(g, 0, &a[0], &a[1], &a[2], &a[3]), BRDFFIT_OK);
    assert_close(a[0], 0.5236, 1e-12);
    assert_close(a[2], PI / 2, 1e-12);
    brdffit_grid_destroy(g);
    /* beyond pi/2 + 1e-4 the file is degrees */
    g = load_ok("VARS theta_i,phi_i,theta_s,phi_s,R\n0.5,0,1.5710,0,0.1\n");
    assert_int_equal(brdffit_grid_sample_angles(g, 0, &a[0], &a[1], &a[2], &a[3]), BRDFFIT_OK);
    assert_close(a[2], DEG(1.5710), 1e-12);
    brdffit_grid_destroy(g);
}

static void test_data_as_measured(void **state)
{
    const char *text = "VARS theta_i,phi_i,theta_s,phi_s,R,G,B\n"
                       "10,0,20,180,-0.002,nan,0.5\n10,0,30,180,0.1,,0.25\n";
    brdffit_grid *g = load_ok(text);
    const double *v;
    (void)state;
    assert_int_equal(brdffit_grid_missing_count(g), 2);
    assert_int_equal(brdffit_grid_values(g, 0, &v), BRDFFIT_OK);
    assert_true(v[0] == -0.002 && v[1] == 0.1);
    assert_true(brdffit_grid_is_missing(g, 0, 1) && brdffit_grid_is_missing(g, 1, 1));
    brdffit_grid_destroy(g);
}

static void expect_error(const char *text, brdffit_status want, const char *fragment)
{
    brdffit_grid *g = (brdffit_grid *)&g;
    brdffit_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(brdffit_load_astm_buffer(&g, text, strlen(text), NULL, &err), want);
    assert_null(g);
    assert_int_equal(err.status, want);
    if (strstr(err.message, fragment) == NULL) fail_msg("'%s' lacks '%s'", err.message, fragment);
}

#define VARS "VARS theta_i,phi_i,theta_s,phi_s,R\n"

static void test_errors(void **state)
{
    (void)state;
    expect_error("", BRDFFIT_E_PARSE, "empty file");
    expect_error("SOURCE x\nNUM_POINTS 2\n", BRDFFIT_E_PARSE, "no VARS line");
    expect_error("theta_i,theta_o,phi_o,r\n0,0,0,1\n", BRDFFIT_E_PARSE,
                 "line 1: expected a header keyword");
    expect_error("SOURCE x\n0,0,0,0,1\n", BRDFFIT_E_PARSE, "line 2: expected a header keyword");
    expect_error("VARS theta_i,phi_i,phi_s,R\n", BRDFFIT_E_PARSE, "line 1: VARS lacks theta_s");
    expect_error("VARS theta_i,phi_i,theta_s,phi_s\n", BRDFFIT_E_PARSE, "names no value column");
    expect_error("VARS theta_i,theta_i,theta_s,phi_s,R\n", BRDFFIT_E_PARSE,
                 "names 'theta_i' twice");
    expect_error("VARS theta_i,,theta_s,phi_s,R\n", BRDFFIT_E_PARSE, "VARS name 2 is empty");
    expect_error(VARS, BRDFFIT_E_PARSE, "line 1: VARS but no data rows");
    expect_error("NUM_POINTS two\n" VARS, BRDFFIT_E_PARSE, "line 1: NUM_POINTS 'two'");
    expect_error("NUM_POINTS 2\n" VARS "0,0,0,0,1\n", BRDFFIT_E_PARSE,
                 "NUM_POINTS is 2 but the file has 1 data rows");
    expect_error(VARS "0,0,0,0,1\n\n0,0,0,1\n", BRDFFIT_E_PARSE,
                 "line 4: expected 5 values (as VARS names), found 4");
    expect_error(VARS "0,0,0,0,1,2\n", BRDFFIT_E_PARSE, "found 6");
    expect_error(VARS "0,0,0,0,0.1x\n", BRDFFIT_E_PARSE,
                 "line 2, column 5 (R): malformed number '0.1x'");
    expect_error(VARS "0,0,nan,0,1\n", BRDFFIT_E_PARSE, "line 2, column 3 (theta_s): missing angle");
    expect_error(VARS "0,0,0,0,inf\n", BRDFFIT_E_RANGE, "line 2, column 5 (R): infinite value");
    expect_error(VARS "0,0,0,-inf,1\n", BRDFFIT_E_RANGE, "column 4 (phi_s): infinite angle");
    expect_error(VARS "10,0,0,0,1\n95,0,0,0,1\n", BRDFFIT_E_RANGE,
                 "line 3, column 1: angle outside [-90, 90] degrees");
    expect_error(VARS "10,0,0,400,1\n", BRDFFIT_E_RANGE,
                 "line 2, column 4: angle outside [-360, 360] degrees");
}

static void test_file_and_arguments(void **state)
{
    static const char *const names[] = {"scan.astm"};
    fx_tempdir dir;
    char path[512];
    size_t rows;
    char *t = astm_text(0, 1, &rows);
    brdffit_grid *g = NULL;
    brdffit_error err;
    brdffit_allocator bad = {NULL, NULL, NULL};
    (void)state;
    assert_true(fx_tempdir_make(&dir));
    fx_tempdir_path(&dir, names[0], path, sizeof path);
    assert_true(fx_write_file(path, t, strlen(t)));
    assert_int_equal(brdffit_load_astm(&g, path, NULL, &err), BRDFFIT_OK);
    check_values(g, rows);
    brdffit_grid_destroy(g);
    fx_tempdir_remove(&dir, names, 1);
    assert_int_equal(brdffit_load_astm(&g, path, NULL, &err), BRDFFIT_E_IO);
    assert_null(g);
    assert_int_equal(brdffit_load_astm(NULL, path, NULL, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_load_astm(&g, NULL, NULL, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_load_astm_buffer(&g, NULL, 0, NULL, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_load_astm_buffer(&g, t, strlen(t), &bad, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    free(t);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_degrees_radians_commas_blanks),
        cmocka_unit_test(test_three_angles_and_bands),
        cmocka_unit_test(test_data_as_measured),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_file_and_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
