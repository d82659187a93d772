/* The CSV loader: both forms, round trips through text and files, every
 * error with its status and where it points, allocation failures. */
#define _POSIX_C_SOURCE 200809L /* mkfifo, symlink */
#include <locale.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "grid_fixtures.h"
#include "test_support.h"

#define PI 3.14159265358979323846

static brdffit_status load(const char *text, brdffit_grid **g, brdffit_error *err)
{
    memset(err, 0, sizeof *err);
    *g = (brdffit_grid *)g;
    return brdffit_load_csv_buffer(g, text, strlen(text), NULL, err);
}

/* Load, expect a status, and expect every fragment in the message. */
static void expect_error(const char *text, brdffit_status want, const char *frag1,
                         const char *frag2)
{
    brdffit_grid *g;
    brdffit_error err;
    brdffit_status st = load(text, &g, &err);
    if (st != want) {
        print_error("status %s (%s), expected %s\n", brdffit_status_name(st), err.message,
                    brdffit_status_name(want));
        fail();
    }
    assert_null(g);
    assert_int_equal(err.status, want);
    if (frag1 != NULL && strstr(err.message, frag1) == NULL) {
        print_error("message '%s' lacks '%s'\n", err.message, frag1);
        fail();
    }
    if (frag2 != NULL && strstr(err.message, frag2) == NULL) {
        print_error("message '%s' lacks '%s'\n", err.message, frag2);
        fail();
    }
}

static brdffit_grid *load_ok(const char *text)
{
    brdffit_grid *g;
    brdffit_error err;
    brdffit_status st = load(text, &g, &err);
    if (st != BRDFFIT_OK) {
        print_error("%s: %s\n", brdffit_status_name(st), err.message);
        fail();
    }
    return g;
}

/* ---- round trips ------------------------------------------------------------ */

static const double ti_deg[] = {0.0, 7.5, 40.0, 90.0};
static const double to_deg[] = {0.0, 2.5, 33.3, 60.0, 89.99};
enum { N_TI = 4, N_TO = 5, N_PO = 7, N = N_TI * N_TO * N_PO, NC = 3 };

static void round_trip_axes(fx_axes *a)
{
    double po[N_PO];
    size_t k;
    for (k = 0; k < N_PO; k++) po[k] = 180.0 * k / (N_PO - 1) / 1.0;
    po[3] = 100.0 / 3.0 + 60.0; /* not representable in decimal */
    fx_axes_set(a, ti_deg, N_TI, to_deg, N_TO, po, N_PO);
}

static void compare_grid(const brdffit_grid *g, const fx_axes *a, const double *v,
                         const unsigned char *mask)
{
    const double *x, *vals;
    size_t k, n, s, c, n_missing = 0;
    assert_int_equal(brdffit_grid_get_kind(g), BRDFFIT_GRID_REGULAR);
    assert_int_equal(brdffit_grid_channel_count(g), NC);
    assert_int_equal(brdffit_grid_sample_count(g), N);
    for (k = 0; k < 3; k++) {
        assert_int_equal(brdffit_grid_axis(g, (brdffit_axis)k, &x, &n), BRDFFIT_OK);
        assert_int_equal(n, k == 0 ? N_TI : (k == 1 ? N_TO : N_PO));
        assert_memory_equal(x, a->rad[k], n * sizeof(double)); /* exactly DEG(degrees) */
    }
    for (c = 0; c < NC; c++) {
        brdffit_grid_values(g, c, &vals);
        for (s = 0; s < N; s++) {
            int miss = mask != NULL && mask[s * NC + c];
            n_missing += (size_t)miss;
            assert_int_equal(brdffit_grid_is_missing(g, s, c), miss);
            assert_true(vals[s] == (miss ? 0.0 : v[s * NC + c])); /* exact */
        }
    }
    assert_int_equal(brdffit_grid_missing_count(g), n_missing);
}

static double *round_trip_values(const fx_axes *a)
{
    double *v = fx_values(&a->axes, NC);
    size_t k;
    /* awkward values: tiny, huge, denormal, many digits */
    v[0] = 1e-300, v[1] = 4.9406564584124654e-324, v[2] = 1.7976931348623157e308;
    for (k = 3; k < N * NC; k += 7) v[k] = v[k] / 3.0 * 1e-5;
    return v;
}

static void test_round_trip_buffer(void **state)
{
    fx_axes a;
    double *v;
    unsigned char mask[N * NC] = {0};
    static const char *const missing_text[] = {"nan", "", "NaN", " NAN "};
    size_t k;
    (void)state;
    round_trip_axes(&a);
    v = round_trip_values(&a);
    mask[10] = mask[11] = mask[12] = mask[50] = mask[N * NC - 1] = 1;
    for (k = 0; k < 4; k++) {
        char *text = fx_csv_regular(&a, NC, v, mask, missing_text[k], (int)k & 1);
        brdffit_grid *g = load_ok(text);
        compare_grid(g, &a, v, mask);
        brdffit_grid_destroy(g);
        free(text);
    }
    free(v);
}

/* Turn "\n" into "\r\n" and sprinkle comments and blank lines. */
static char *decorate(const char *text)
{
    size_t n = strlen(text), k, o = 0;
    char *out = malloc(3 * n + 64);
    int line = 0;
    o += (size_t)sprintf(out, "\xEF\xBB\xBF# comment\r\n\r\n   \t\r\n");
    for (k = 0; k < n; k++) {
        if (text[k] != '\n') {
            out[o++] = text[k];
            continue;
        }
        out[o++] = '\r', out[o++] = '\n';
        if (++line % 5 == 0) o += (size_t)sprintf(out + o, "  # note %d\r\n\r\n", line);
    }
    if (o >= 2) o -= 2; /* no line end after the last row */
    out[o] = '\0';
    return out;
}

static void test_round_trip_crlf_comments(void **state)
{
    fx_axes a;
    double *v;
    char *text, *deco;
    brdffit_grid *g;
    (void)state;
    round_trip_axes(&a);
    v = round_trip_values(&a);
    text = fx_csv_regular(&a, NC, v, NULL, "", 1);
    deco = decorate(text);
    g = load_ok(deco);
    compare_grid(g, &a, v, NULL);
    brdffit_grid_destroy(g);
    free(deco);
    free(text);
    free(v);
}

static void test_round_trip_file(void **state)
{
    static const char *const names[] = {"grid.csv"};
    fx_axes a;
    fx_tempdir dir;
    char path[512], *text;
    double *v;
    unsigned char mask[N * NC] = {0};
    brdffit_grid *g = NULL;
    brdffit_error err;
    (void)state;
    round_trip_axes(&a);
    v = round_trip_values(&a);
    mask[7] = 1;
    text = fx_csv_regular(&a, NC, v, mask, "nan", 1);
    assert_true(fx_tempdir_make(&dir));
    fx_tempdir_path(&dir, names[0], path, sizeof path);
    assert_true(fx_write_file(path, text, strlen(text)));
    assert_int_equal(brdffit_load_csv(&g, path, NULL, &err), BRDFFIT_OK);
    compare_grid(g, &a, v, mask);
    brdffit_grid_destroy(g);
    fx_tempdir_remove(&dir, names, 1);
    free(text);
    free(v);
}

static void test_round_trip_decimal_comma_locale(void **state)
{
    static const char *const names[] = {"de_DE.UTF-8", "de_DE.utf8", "fr_FR.UTF-8", "fr_FR.utf8"};
    fx_axes a;
    double *v;
    char *text;
    brdffit_grid *g;
    size_t k;
    int found = 0;
    (void)state;
    round_trip_axes(&a);
    v = round_trip_values(&a);
    text = fx_csv_regular(&a, NC, v, NULL, "", 0); /* written in the C locale */
    for (k = 0; k < sizeof names / sizeof names[0] && !found; k++)
        found = setlocale(LC_NUMERIC, names[k]) != NULL;
    if (!found) {
        free(text);
        free(v);
        skip();
    }
    g = load_ok(text);
    setlocale(LC_NUMERIC, "C");
    compare_grid(g, &a, v, NULL);
    brdffit_grid_destroy(g);
    free(text);
    free(v);
}

/* ---- the scattered form ----------------------------------------------------------- */

static void test_scattered_form(void **state)
{
    /* rows in ascending max(theta_i, theta_o), so stored order = file order */
    static const char text[] = "theta_i,phi_i,theta_o,phi_o,400nm,550nm\n"
                               "0,0,0,0,0.5,0.25\n"
                               "10,-360,5,360,1e-3,\n"
                               "20, 45 ,20,-90.5,nan,2\n"
                               "90,180,30,10,3,4\n";
    static const double ang[4][4] = {
        {0, 0, 0, 0}, {10, -360, 5, 360}, {20, 45, 20, -90.5}, {90, 180, 30, 10}};
    static const double val[4][2] = {{0.5, 0.25}, {1e-3, 0}, {0, 2}, {3, 4}};
    brdffit_grid *g = load_ok(text);
    const double *v0, *v1;
    size_t s;
    (void)state;
    assert_int_equal(brdffit_grid_get_kind(g), BRDFFIT_GRID_SCATTERED);
    assert_int_equal(brdffit_grid_sample_count(g), 4);
    assert_int_equal(brdffit_grid_channel_count(g), 2);
    assert_int_equal(brdffit_grid_missing_count(g), 2);
    assert_int_equal(brdffit_grid_is_missing(g, 1, 1), 1);
    assert_int_equal(brdffit_grid_is_missing(g, 2, 0), 1);
    brdffit_grid_values(g, 0, &v0);
    brdffit_grid_values(g, 1, &v1);
    for (s = 0; s < 4; s++) {
        double t[4], l[3], e[3];
        brdffit_grid_sample_angles(g, s, &t[0], &t[1], &t[2], &t[3]);
        assert_close(t[0], DEG(ang[s][0]), 1e-12);
        assert_close(t[2], DEG(ang[s][2]), 1e-12);
        fx_dir(t[2], t[3], l);
        fx_dir(DEG(ang[s][2]), DEG(ang[s][3]), e);
        assert_close(l[0], e[0], 1e-12);
        assert_close(l[1], e[1], 1e-12);
        assert_true(v0[s] == val[s][0] && v1[s] == val[s][1]);
    }
    brdffit_grid_destroy(g);
}

/* ---- headers and layout ----------------------------------------------------------------- */

static void test_header_forms(void **state)
{
    brdffit_grid *g;
    (void)state;
    g = load_ok(" theta_i , theta_o ,\tphi_o,r , g\n0,0,0,1,2\n");
    assert_int_equal(brdffit_grid_channel_count(g), 2);
    assert_int_equal(brdffit_grid_sample_count(g), 1);
    brdffit_grid_destroy(g);
    g = load_ok("theta_i,theta_o,phi_o,only\n5,5,5,1\n5,5,6,2"); /* no final newline */
    assert_int_equal(brdffit_grid_sample_count(g), 2);
    brdffit_grid_destroy(g);
    expect_error("Theta_i,theta_o,phi_o,r\n0,0,0,1\n", BRDFFIT_E_PARSE, "line 1, column 1",
                 "Theta_i");
    expect_error("theta_i,theta_o,phi,r\n0,0,0,1\n", BRDFFIT_E_PARSE, "line 1, column 3", "'phi'");
    expect_error("theta_i,phi_i,theta_o,phi_x,r\n0,0,0,0,1\n", BRDFFIT_E_PARSE, "column 4",
                 "phi_x");
    expect_error("theta_i,theta_o,phi_o\n0,0,0\n", BRDFFIT_E_PARSE, "line 1", "channel");
    expect_error("# only\ntheta_i,phi_i,theta_o,phi_o\n0,0,0,0\n", BRDFFIT_E_PARSE, "line 2",
                 "channel");
    expect_error("theta_i,theta_o,phi_o,r,\n0,0,0,1,2\n", BRDFFIT_E_PARSE, "column 5",
                 "empty channel name");
    expect_error("theta_i\n", BRDFFIT_E_PARSE, "line 1", NULL);
    expect_error("r,g,b\n1,2,3\n", BRDFFIT_E_PARSE, "unknown header", NULL);
}

static void test_empty_inputs(void **state)
{
    brdffit_grid *g = (brdffit_grid *)&g;
    brdffit_error err;
    (void)state;
    expect_error("", BRDFFIT_E_PARSE, "empty", NULL);
    expect_error("# nothing\n\n   \n", BRDFFIT_E_PARSE, "empty", NULL);
    expect_error("\xEF\xBB\xBF", BRDFFIT_E_PARSE, "empty", NULL);
    expect_error("theta_i,theta_o,phi_o,r\n", BRDFFIT_E_PARSE, "line 1", "no data rows");
    expect_error("theta_i,theta_o,phi_o,r\n# c\n\n", BRDFFIT_E_PARSE, "no data", NULL);
    /* the size is honoured: text after it is not read */
    assert_int_equal(
        brdffit_load_csv_buffer(&g, "theta_i,theta_o,phi_o,r\n0,0,0,1", 24, NULL, &err),
        BRDFFIT_E_PARSE);
    assert_null(g);
    assert_int_equal(brdffit_load_csv_buffer(&g, "", 0, NULL, &err), BRDFFIT_E_PARSE);
}

/* ---- row errors ---------------------------------------------------------------------------- */

#define HDR "theta_i,theta_o,phi_o,r\n"

static void test_row_errors(void **state)
{
    (void)state;
    expect_error(HDR "0,0,0,1\n0,0,1\n", BRDFFIT_E_PARSE, "line 3", "expected 4 columns, found 3");
    expect_error(HDR "0,0,0,1,2\n", BRDFFIT_E_PARSE, "line 2", "found 5");
    expect_error("# c\n" HDR "0,0,0,1\n\n0,0,x.5,1\n", BRDFFIT_E_PARSE, "line 5, column 3 (phi_o)",
                 "malformed number 'x.5'");
    expect_error(HDR "0,0,0,1..2\n", BRDFFIT_E_PARSE, "line 2, column 4 (r)", "'1..2'");
    expect_error(HDR "0,0,0,0x1p3\n", BRDFFIT_E_PARSE, "column 4", NULL);
    expect_error(HDR "0,0,0,1\xff\xfe\n", BRDFFIT_E_PARSE, "line 2, column 4", "'1?\?'");
    expect_error(HDR "0,0,0,inf\n", BRDFFIT_E_RANGE, "line 2, column 4 (r)", "infinite value");
    expect_error(HDR "0,0,0,1e999\n", BRDFFIT_E_RANGE, "column 4", "infinite");
    expect_error(HDR "0,-Infinity,0,1\n", BRDFFIT_E_RANGE, "line 2, column 2 (theta_o)",
                 "infinite angle");
    expect_error(HDR "0,90.000001,0,1\n", BRDFFIT_E_RANGE, "line 2, column 2 (theta_o)",
                 "outside [0, 90]");
    expect_error(HDR "-1,0,0,1\n", BRDFFIT_E_RANGE, "line 2, column 1 (theta_i)", "'-1'");
    expect_error(HDR "0,0,180.5,1\n", BRDFFIT_E_RANGE, "column 3 (phi_o)", "[0, 180]");
    expect_error(HDR "0,0,-10,1\n", BRDFFIT_E_RANGE, "column 3 (phi_o)", NULL);
    expect_error(HDR "0,,0,1\n", BRDFFIT_E_PARSE, "line 2, column 2 (theta_o)", "missing angle");
    expect_error(HDR "0,nan,0,1\n", BRDFFIT_E_PARSE, "column 2", "missing angle");
    expect_error("theta_i,phi_i,theta_o,phi_o,r\n0,360.5,0,0,1\n", BRDFFIT_E_RANGE,
                 "line 2, column 2 (phi_i)", "[-360, 360]");
    expect_error("theta_i,phi_i,theta_o,phi_o,r\n0,0,0,-400,1\n", BRDFFIT_E_RANGE,
                 "column 4 (phi_o)", NULL);
    expect_error("theta_i,phi_i,theta_o,phi_o,r\n91,0,0,0,1\n", BRDFFIT_E_RANGE,
                 "column 1 (theta_i)", NULL);
    /* a lone carriage return inside a line is not a line end */
    expect_error(HDR "0,0,0,1\r2\n", BRDFFIT_E_PARSE, "line 2, column 4", NULL);
}

/* Slightly negative values (background subtraction noise) are data: kept
 * exactly as written, in both forms. */
static void test_negative_values_are_data(void **state)
{
    const double *v;
    brdffit_grid *g;
    (void)state;
    g = load_ok(HDR "0,0,0,-0.5\n0,0,10,1e-3\n");
    assert_int_equal(brdffit_grid_values(g, 0, &v), BRDFFIT_OK);
    assert_true(v[0] == -0.5 && v[1] == 1e-3);
    brdffit_grid_destroy(g);
    g = load_ok("theta_i,phi_i,theta_o,phi_o,r\n0,0,0,0,-1e-300\n");
    assert_int_equal(brdffit_grid_values(g, 0, &v), BRDFFIT_OK);
    assert_true(v[0] == -1e-300);
    brdffit_grid_destroy(g);
}

/* ---- grid coverage -------------------------------------------------------------------------- */

static void test_incomplete_and_duplicate(void **state)
{
    (void)state;
    expect_error(HDR "0,0,0,1\n0,0,90,1\n0,20,0,1\n10,0,0,1\n10,0,90,1\n10,20,0,1\n10,20,90,1\n",
                 BRDFFIT_E_INCOMPLETE_GRID, "theta_i = 0, theta_o = 20, phi_o = 90", NULL);
    expect_error(HDR "0,0,0,1\n0,0,90,1\n0,20,0,1\n0,20,90,1\n10,0,0,1\n10,0,90,1\n10,20,0,1\n",
                 BRDFFIT_E_INCOMPLETE_GRID, "theta_i = 10, theta_o = 20, phi_o = 90", NULL);
    expect_error(HDR "0,0,0,1\n# x\n0,0,90,1\n0,0,0.0,2\n", BRDFFIT_E_DUPLICATE,
                 "theta_i = 0, theta_o = 0, phi_o = 0", "lines 2 and 5");
    expect_error(HDR "0,0,0,1\n5,0,0,1\n5,0,0,1\n0,0,0,1\n", BRDFFIT_E_DUPLICATE, "lines 2 and 5",
                 NULL);
    /* degree values that differ yet map onto the same radian value */
    expect_error(HDR "0,57.299999999999997,0,1\n0,57.300000000000004,0,1\n", BRDFFIT_E_RANGE,
                 "theta_o values 57.299999999999997 and 57.300000000000004", "too close");
}

static void test_axis_values_compare_exactly(void **state)
{
    /* values that differ in the last digit are different axis values */
    brdffit_grid *g = load_ok(HDR "0,0,0,1\n0,0,1.0000000000000002,1\n0,0,1,1\n");
    const double *x;
    size_t n;
    (void)state;
    assert_int_equal(brdffit_grid_axis(g, BRDFFIT_AXIS_PHI_O, &x, &n), BRDFFIT_OK);
    assert_int_equal(n, 3);
    assert_true(x[0] == 0.0 && x[1] == DEG(1.0) && x[2] == DEG(1.0000000000000002));
    brdffit_grid_destroy(g);
}

static void test_too_large(void **state)
{
    /* 1300 rows with distinct angles span 1300^3 > 2^31 combinations */
    size_t k, n = 1300, len = 0;
    char *text = malloc(n * 40 + 64);
    (void)state;
    len += (size_t)sprintf(text, HDR);
    for (k = 0; k < n; k++)
        len += (size_t)sprintf(text + len, "%.6f,%.6f,%.6f,1\n", k * 0.05, k * 0.06, k * 0.1);
    expect_error(text, BRDFFIT_E_TOO_LARGE, "1300 x 1300 x 1300", NULL);
    free(text);
}

static void test_any_row_order(void **state)
{
    brdffit_grid *g = load_ok(HDR "10,20,90,8\n0,0,0,1\n10,0,0,5\n0,20,90,4\n0,0,90,2\n"
                                  "10,20,0,7\n0,20,0,3\n10,0,90,6\n");
    const double *v;
    size_t s;
    (void)state;
    brdffit_grid_values(g, 0, &v);
    for (s = 0; s < 8; s++) assert_true(v[s] == (double)(s + 1));
    brdffit_grid_destroy(g);
}

/* ---- the sample files in tests/data ------------------------------------------------------- */

static void test_sample_files(void **state)
{
    brdffit_grid *g = NULL;
    brdffit_error err;
    const double *v, *x;
    size_t s, c, n;
    (void)state;
    assert_int_equal(brdffit_load_csv(&g, BRDFFIT_TEST_DATA_DIR "/sample_grid.csv", NULL, &err),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_grid_get_kind(g), BRDFFIT_GRID_REGULAR);
    assert_int_equal(brdffit_grid_sample_count(g), 3 * 4 * 4);
    assert_int_equal(brdffit_grid_axis(g, BRDFFIT_AXIS_THETA_O, &x, &n), BRDFFIT_OK);
    assert_int_equal(n, 4);
    assert_true(x[3] == DEG(70.0));
    assert_int_equal(brdffit_grid_missing_count(g), 1);
    assert_int_equal(brdffit_grid_is_missing(g, 47, 2), 1);
    for (c = 0; c < 3; c++) {
        brdffit_grid_values(g, c, &v);
        for (s = 0; s < 47 + (c < 2); s++)
            assert_true(v[s] ==
                        0.125 * (s / 16 + 1) + 0.0625 * (s / 4 % 4) + (s % 4) / 64.0 + c / 256.0);
    }
    brdffit_grid_destroy(g);
    assert_int_equal(
        brdffit_load_csv(&g, BRDFFIT_TEST_DATA_DIR "/sample_scattered.csv", NULL, &err),
        BRDFFIT_OK);
    assert_int_equal(brdffit_grid_get_kind(g), BRDFFIT_GRID_SCATTERED);
    assert_int_equal(brdffit_grid_sample_count(g), 5);
    brdffit_grid_values(g, 0, &v);
    assert_true(v[0] == 0.5 && v[4] == 0.125);
    brdffit_grid_destroy(g);
}

/* ---- files and arguments --------------------------------------------------------------------- */

static void test_file_errors(void **state)
{
    fx_tempdir dir;
    char path[512];
    brdffit_grid *g = (brdffit_grid *)&g;
    brdffit_error err;
    static const char *const names[] = {"empty.csv"};
    (void)state;
    assert_true(fx_tempdir_make(&dir));
    fx_tempdir_path(&dir, "does-not-exist.csv", path, sizeof path);
    assert_int_equal(brdffit_load_csv(&g, path, NULL, &err), BRDFFIT_E_IO);
    assert_null(g);
    assert_non_null(strstr(err.message, "does-not-exist.csv"));
    assert_int_equal(brdffit_load_csv(&g, dir.path, NULL, &err), BRDFFIT_E_IO);
    fx_tempdir_path(&dir, names[0], path, sizeof path);
    assert_true(fx_write_file(path, "", 0));
    assert_int_equal(brdffit_load_csv(&g, path, NULL, &err), BRDFFIT_E_PARSE);
    fx_tempdir_remove(&dir, names, 1);
}

/* Files that are not regular: refused at once (a FIFO without a writer
 * must not block), each with its reason; never called an "empty file". */
static void expect_refused(const char *path, const char *reason)
{
    brdffit_grid *g = (brdffit_grid *)&g;
    brdffit_error err;
    assert_int_equal(brdffit_load_csv(&g, path, NULL, &err), BRDFFIT_E_IO);
    assert_null(g);
    assert_non_null(strstr(err.message, path));
    assert_non_null(strstr(err.message, reason));
    assert_null(strstr(err.message, "empty file"));
    g = (brdffit_grid *)&g;
    assert_int_equal(brdffit_load_merl(&g, path, NULL, NULL, &err), BRDFFIT_E_IO);
    assert_non_null(strstr(err.message, reason));
}

static void test_special_files(void **state)
{
    static const char *const names[] = {"fifo", "loop-a", "loop-b"};
    fx_tempdir dir;
    char fifo[512], a[512], b[512];
    (void)state;
    assert_true(fx_tempdir_make(&dir));
    fx_tempdir_path(&dir, names[0], fifo, sizeof fifo);
    fx_tempdir_path(&dir, names[1], a, sizeof a);
    fx_tempdir_path(&dir, names[2], b, sizeof b);
    assert_int_equal(mkfifo(fifo, 0600), 0);
    expect_refused(fifo, "FIFO");
    assert_int_equal(symlink(b, a), 0);
    assert_int_equal(symlink(a, b), 0);
    expect_refused(a, "symbolic links");
    expect_refused(dir.path, "directory");
    if (access("/dev/zero", R_OK) == 0) expect_refused("/dev/zero", "character device");
    if (access("/proc/self/status", R_OK) == 0) expect_refused("/proc/self/status", "size of 0");
    fx_tempdir_remove(&dir, names, 3);
}

static void test_null_arguments(void **state)
{
    brdffit_grid *g = (brdffit_grid *)&g;
    brdffit_error err;
    brdffit_allocator bad = {NULL, NULL, NULL};
    (void)state;
    assert_int_equal(brdffit_load_csv_buffer(NULL, "x", 1, NULL, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_load_csv_buffer(&g, NULL, 1, NULL, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_null(g);
    assert_int_equal(brdffit_load_csv(&g, NULL, NULL, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_load_csv(NULL, "x.csv", NULL, NULL), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_load_csv_buffer(&g, HDR "0,0,0,1\n", 32, &bad, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
}

/* ---- allocation failures ------------------------------------------------------------------------ */

typedef brdffit_status (*load_fn)(brdffit_grid **out, const brdffit_allocator *a, const char *arg);

static void check_oom(load_fn fn, const char *arg)
{
    size_t n;
    for (n = 1;; n++) {
        counting_alloc ca;
        brdffit_grid *g = (brdffit_grid *)&g;
        brdffit_status st;
        counting_alloc_init(&ca, n);
        st = fn(&g, &ca.hook, arg);
        if (st == BRDFFIT_OK) {
            assert_true(n > 2 && ca.allocs < n);
            brdffit_grid_destroy(g);
            assert_int_equal(ca.live, 0);
            return;
        }
        assert_int_equal(st, BRDFFIT_E_OUT_OF_MEMORY);
        assert_null(g);
        assert_int_equal(ca.live, 0);
        assert_true(n < 100);
    }
}

static brdffit_status oom_buffer(brdffit_grid **out, const brdffit_allocator *a, const char *text)
{
    return brdffit_load_csv_buffer(out, text, strlen(text), a, NULL);
}

static brdffit_status oom_file(brdffit_grid **out, const brdffit_allocator *a, const char *path)
{
    return brdffit_load_csv(out, path, a, NULL);
}

static void test_allocation_failures(void **state)
{
    static const char *const names[] = {"g.csv"};
    fx_tempdir dir;
    char path[512];
    const char *grid = HDR "0,0,0,1\n0,0,90,\n10,0,0,2\n10,0,90,3\n";
    (void)state;
    check_oom(oom_buffer, grid);
    check_oom(oom_buffer, "theta_i,phi_i,theta_o,phi_o,r,g\n0,0,0,0,1,nan\n5,5,5,5,1,1\n");
    assert_true(fx_tempdir_make(&dir));
    fx_tempdir_path(&dir, names[0], path, sizeof path);
    assert_true(fx_write_file(path, grid, strlen(grid)));
    check_oom(oom_file, path);
    fx_tempdir_remove(&dir, names, 1);
}

/* ---- the weight column of the scattered form ----------------------------------------------- */

#define WHDR "theta_i,phi_i,theta_o,phi_o,weight,r,g\n"

static void test_weight_column(void **state)
{
    /* rows in descending max(theta_i, theta_o): the weights follow their
     * samples into the stored order */
    static const char text[] = WHDR "40,0,10,180,3,0.5,0.25\n"
                                    "# a comment\n"
                                    "20,0,20,180, 1.5 ,1,\n"
                                    "5,0,0,0,0,2,3\n"
                                    "0,0,1,0,-0,4,5\n";
    static const double weight[4] = {0, 0, 1.5, 3}, red[4] = {4, 2, 1, 0.5};
    brdffit_grid *g = load_ok(text);
    double w[4];
    const double *v;
    size_t s;
    (void)state;
    assert_int_equal(brdffit_grid_channel_count(g), 2); /* the weight is no channel */
    assert_int_equal(brdffit_grid_sample_count(g), 4);
    assert_int_equal(brdffit_grid_missing_count(g), 1);
    brdffit_grid_values(g, 0, &v);
    assert_int_equal(brdffit_grid_weights(g, PI / 2, BRDFFIT_WEIGHT_SOLID_ANGLE, w, NULL),
                     BRDFFIT_OK);
    for (s = 0; s < 4; s++) {
        assert_true(v[s] == red[s]);
        assert_close(w[s], weight[s] / 4.5, 1e-15);
    }
    /* within a cap of 15 degrees only weight 0 samples remain */
    assert_int_equal(brdffit_grid_weights(g, DEG(15.0), BRDFFIT_WEIGHT_SOLID_ANGLE, w, NULL),
                     BRDFFIT_E_NO_DATA);
    brdffit_grid_destroy(g);
    /* without the column every sample weighs the same */
    g = load_ok("theta_i,phi_i,theta_o,phi_o,r\n0,0,0,0,1\n10,0,10,180,1\n");
    assert_int_equal(brdffit_grid_weights(g, PI / 2, BRDFFIT_WEIGHT_SOLID_ANGLE, w, NULL),
                     BRDFFIT_OK);
    assert_true(w[0] == 0.5 && w[1] == 0.5);
    brdffit_grid_destroy(g);
    check_oom(oom_buffer, WHDR "0,0,0,0,1,1,nan\n5,5,5,5,2,1,1\n");
}

static void test_weight_column_errors(void **state)
{
    (void)state;
    expect_error(WHDR "0,0,0,0,1,1,1\n0,0,0,0,nan,1,1\n", BRDFFIT_E_PARSE,
                 "line 3, column 5 (weight)", "missing weight 'nan'");
    expect_error(WHDR "0,0,0,0, ,1,1\n", BRDFFIT_E_PARSE, "line 2, column 5 (weight)",
                 "missing weight");
    expect_error(WHDR "0,0,0,0,-1e-300,1,1\n", BRDFFIT_E_RANGE, "line 2, column 5 (weight)",
                 "negative weight '-1e-300'");
    expect_error(WHDR "0,0,0,0,inf,1,1\n", BRDFFIT_E_RANGE, "line 2, column 5 (weight)",
                 "infinite weight");
    expect_error(WHDR "0,0,0,0,1e400,1,1\n", BRDFFIT_E_RANGE, "column 5 (weight)", "infinite");
    expect_error(WHDR "0,0,0,0,1w,1,1\n", BRDFFIT_E_PARSE, "line 2, column 5 (weight)",
                 "malformed number '1w'");
    /* the channels after it keep their own checks and column numbers */
    expect_error(WHDR "0,0,0,0,1,1,inf\n", BRDFFIT_E_RANGE, "line 2, column 7 (g)",
                 "infinite value");
    expect_error(WHDR "0,0,0,0,1,1\n", BRDFFIT_E_PARSE, "line 2", "expected 7 columns, found 6");
    /* where the column may stand */
    expect_error("theta_i,phi_i,theta_o,phi_o,r,weight\n0,0,0,0,1,1\n", BRDFFIT_E_PARSE,
                 "line 1, column 6", "must directly follow phi_o");
    expect_error("theta_i,theta_o,phi_o,weight,r\n0,0,0,1,1\n", BRDFFIT_E_PARSE, "line 1, column 4",
                 "grid form has no weight column");
    expect_error("theta_i,phi_i,theta_o,phi_o,weight\n0,0,0,0,1\n", BRDFFIT_E_PARSE, "line 1",
                 "the weight and at least one channel");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip_buffer),
        cmocka_unit_test(test_round_trip_crlf_comments),
        cmocka_unit_test(test_round_trip_file),
        cmocka_unit_test(test_round_trip_decimal_comma_locale),
        cmocka_unit_test(test_scattered_form),
        cmocka_unit_test(test_header_forms),
        cmocka_unit_test(test_empty_inputs),
        cmocka_unit_test(test_row_errors),
        cmocka_unit_test(test_negative_values_are_data),
        cmocka_unit_test(test_incomplete_and_duplicate),
        cmocka_unit_test(test_axis_values_compare_exactly),
        cmocka_unit_test(test_too_large),
        cmocka_unit_test(test_any_row_order),
        cmocka_unit_test(test_sample_files),
        cmocka_unit_test(test_file_errors),
        cmocka_unit_test(test_special_files),
        cmocka_unit_test(test_null_arguments),
        cmocka_unit_test(test_allocation_failures),
        cmocka_unit_test(test_weight_column),
        cmocka_unit_test(test_weight_column_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
