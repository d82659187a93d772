/* The RGL .bsdf loader: small files written here (tests/support/
 * rgl_writer.c) from an analytic, reciprocal BRDF through a warp with a
 * closed form, loaded in both forms and checked against the analytic
 * values, the analytic solid angles, and reciprocity; every format error;
 * the file form. The round-trip errors are printed. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "grid_fixtures.h"
#include "rgl_writer.h"
#include "test_support.h"

#define PI 3.14159265358979323846

/* Lambert plus a broad normalised Blinn-Phong lobe: reciprocal. */
static double material(const double wi[3], const double wo[3], size_t c)
{
    static const double kd[4] = {0.2, 0.4, 0.6, 0.3};
    double h[3] = {wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]};
    double len = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    return kd[c] / PI + 0.5 * 10.0 / (8.0 * PI) * pow(h[2] / len, 8.0);
}

static void spec_init(fx_rgl_spec *sp, int rgb)
{
    size_t k;
    memset(sp, 0, sizeof *sp);
    sp->n_theta = 5, sp->n_phi = 1;
    for (k = 0; k < sp->n_theta; k++) sp->theta_i[k] = DEG(15.0 * (double)k);
    sp->phi_i[0] = 0.0;
    sp->nx = 17, sp->ny = 15;
    sp->rgb = rgb, sp->nc = rgb ? 3 : 4;
    sp->jacobian = 1;
    sp->brdf = material;
}

static void dir(double theta, double phi, double d[3])
{
    d[0] = sin(theta) * cos(phi), d[1] = sin(theta) * sin(phi), d[2] = cos(theta);
}

static brdffit_grid *load(const unsigned char *data, size_t size, const brdffit_axes *axes)
{
    brdffit_grid *g = NULL;
    brdffit_error err;
    brdffit_status st = brdffit_load_rgl_buffer(&g, data, size, axes, NULL, &err);
    if (st != BRDFFIT_OK) fail_msg("load: %s", err.message);
    return g;
}

/* The view of sample (k, l) of light b, and whether it is kept. */
static int node_view(const fx_rgl_spec *sp, size_t b, size_t k, size_t l, double wo[3])
{
    double s[2], u[2], wi[3], m[3], d;
    size_t j;
    s[0] = (double)k / (double)(sp->nx - 1), s[1] = (double)l / (double)(sp->ny - 1);
    fx_rgl_warp(sp, b, s, u);
    dir(sp->theta_i[b], sp->phi_i[0], wi);
    fx_rgl_normal(u, sp->phi_i[0], m);
    d = wi[0] * m[0] + wi[1] * m[1] + wi[2] * m[2];
    for (j = 0; j < 3; j++) wo[j] = 2.0 * d * m[j] - wi[j];
    return wo[2] > 1e-6;
}

/* Light index of a theta_i value of the file. */
static size_t light_of(const fx_rgl_spec *sp, double theta_i)
{
    size_t b;
    for (b = 0; b < sp->n_theta; b++)
        if (fabs((double)(float)sp->theta_i[b] - theta_i) < 1e-12) return b;
    fail_msg("theta_i %g is no light of the file", theta_i);
    return 0;
}

/* The analytic solid angle of a stored sample, from its directions. */
static double analytic_weight(const fx_rgl_spec *sp, const double a[4])
{
    double wi[3], wo[3], h[3], len, u[2], s[2], pdf, tm, d, cell;
    size_t b = light_of(sp, a[0]), k, l, j;
    dir(a[0], a[1], wi);
    dir(a[2], a[3], wo);
    for (j = 0; j < 3; j++) h[j] = wi[j] + wo[j];
    len = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    for (j = 0; j < 3; j++) h[j] /= len;
    tm = atan2(sqrt(h[0] * h[0] + h[1] * h[1]), h[2]);
    u[0] = sqrt(tm / (PI / 2.0));
    u[1] = (atan2(h[1], h[0]) - a[1] + PI) / (2.0 * PI);
    u[1] -= floor(u[1]);
    fx_rgl_warp_inverse(sp, b, u, s);
    k = (size_t)floor(s[0] * (double)(sp->nx - 1) + 0.5);
    l = (size_t)floor(s[1] * (double)(sp->ny - 1) + 0.5);
    pdf = fx_rgl_warp(sp, b, s, u);
    d = wi[0] * h[0] + wi[1] * h[1] + wi[2] * h[2];
    cell = (k == 0 || k == sp->nx - 1 ? 0.5 : 1.0) * (l == 0 || l == sp->ny - 1 ? 0.5 : 1.0) /
           ((double)(sp->nx - 1) * (double)(sp->ny - 1));
    return cell * 8.0 * PI * PI * u[0] * sin(tm) * d / pdf;
}

static size_t expected_count(const fx_rgl_spec *sp)
{
    size_t b, k, l, n = 0;
    double wo[3];
    for (b = 0; b < sp->n_theta; b++)
        for (l = 0; l < sp->ny; l++)
            for (k = 0; k < sp->nx; k++) n += (size_t)node_view(sp, b, k, l, wo);
    return n;
}

/* Every stored sample against the analytic BRDF at its own directions,
 * and its weight against the analytic solid angle. */
static void check_scattered(const fx_rgl_spec *sp, const unsigned char *file, size_t size)
{
    brdffit_grid *g = load(file, size, NULL);
    size_t n = brdffit_grid_sample_count(g), s, c;
    double *w = malloc(n * sizeof(double)), *wa = malloc(n * sizeof(double));
    double sum = 0.0, max_v = 0.0, max_w = 0.0, top = 0.0;
    assert_non_null(w), assert_non_null(wa);
    assert_int_equal(brdffit_grid_get_kind(g), BRDFFIT_GRID_SCATTERED);
    assert_int_equal(n, expected_count(sp));
    assert_int_equal(brdffit_grid_channel_count(g), sp->nc);
    assert_int_equal(brdffit_grid_missing_count(g), 0);
    assert_int_equal(brdffit_grid_weights(g, PI / 2, BRDFFIT_WEIGHT_SOLID_ANGLE, w, NULL),
                     BRDFFIT_OK);
    for (s = 0; s < n; s++) {
        double a[4], wi[3], wo[3];
        assert_int_equal(brdffit_grid_sample_angles(g, s, &a[0], &a[1], &a[2], &a[3]),
                         BRDFFIT_OK);
        dir(a[0], a[1], wi), dir(a[2], a[3], wo);
        for (c = 0; c < sp->nc; c++) {
            const double *v;
            double want = material(wi, wo, c);
            assert_int_equal(brdffit_grid_values(g, c, &v), BRDFFIT_OK);
            max_v = fmax(max_v, fabs(v[s] - want) / want);
        }
        wa[s] = analytic_weight(sp, a);
        sum += wa[s];
    }
    for (s = 0; s < n; s++) top = fmax(top, wa[s] / sum);
    for (s = 0; s < n; s++) max_w = fmax(max_w, fabs(w[s] - wa[s] / sum) / top);
    printf("RGL %s scattered: %zu samples, max relative error %.3g (values), max weight error %.3g of the largest\n",
           sp->rgb ? "rgb" : "spectral", n, max_v, max_w);
    assert_true(max_v < 1e-5); /* the file stores float32 */
    assert_true(max_w < 1e-5);
    free(w), free(wa);
    brdffit_grid_destroy(g);
}

static void test_scattered_rgb(void **state)
{
    fx_rgl_spec sp;
    size_t size = 0;
    unsigned char *file;
    (void)state;
    spec_init(&sp, 1);
    file = fx_rgl_file(&sp, &size);
    assert_non_null(file);
    check_scattered(&sp, file, size);
    free(file);
}

static void test_scattered_spectral_no_jacobian(void **state)
{
    fx_rgl_spec sp;
    size_t size = 0;
    unsigned char *file;
    (void)state;
    spec_init(&sp, 0);
    sp.jacobian = 0;
    file = fx_rgl_file(&sp, &size);
    assert_non_null(file);
    check_scattered(&sp, file, size);
    free(file);
}

/* Resampled onto axes whose theta_i are the file's lights: the analytic
 * values to within the bilinear interpolation of 33 x 33 samples, and
 * reciprocity (theta_i and theta_o swapped) to the same order. */
static void test_resampled(void **state)
{
    static const double deg[5] = {0, 15, 30, 45, 60}, po[7] = {0, 30, 60, 90, 120, 150, 180};
    fx_rgl_spec sp;
    fx_axes ax;
    size_t size = 0, i, j, k, c, nc;
    unsigned char *file;
    brdffit_grid *g;
    double max_err = 0.0, max_rec = 0.0;
    (void)state;
    spec_init(&sp, 0);
    sp.nx = sp.ny = 33; /* the error falls 4-fold per doubling: 0.027 at 17, 0.0017 at 65 */
    file = fx_rgl_file(&sp, &size);
    assert_non_null(file);
    fx_axes_set(&ax, deg, 5, deg, 5, po, 7);
    for (i = 0; i < 5; i++) ax.rad[0][i] = (double)(float)sp.theta_i[i];
    g = load(file, size, &ax.axes);
    nc = brdffit_grid_channel_count(g);
    assert_int_equal(brdffit_grid_get_kind(g), BRDFFIT_GRID_REGULAR);
    assert_int_equal(nc, 4);
    assert_int_equal(brdffit_grid_missing_count(g), 0);
    for (c = 0; c < nc; c++) {
        const double *v;
        assert_int_equal(brdffit_grid_values(g, c, &v), BRDFFIT_OK);
        for (i = 0; i < 5; i++)
            for (j = 0; j < 5; j++)
                for (k = 0; k < 7; k++) {
                    double wi[3], wo[3], want, got = v[(i * 5 + j) * 7 + k];
                    double swapped = v[(j * 5 + i) * 7 + k];
                    dir(ax.rad[0][i], PI, wi);
                    dir(ax.rad[1][j], ax.rad[2][k], wo);
                    want = material(wi, wo, c);
                    max_err = fmax(max_err, fabs(got - want) / want);
                    max_rec = fmax(max_rec, fabs(got - swapped) / want);
                }
    }
    printf("RGL resampled: max relative error %.3g, reciprocity %.3g\n", max_err, max_rec);
    assert_true(max_err < 0.01);
    assert_true(max_rec < 0.012);
    brdffit_grid_destroy(g);
    free(file);
}

static double nan_green(const double wi[3], const double wo[3], size_t c)
{
    return c == 1 ? NAN : material(wi, wo, c);
}

static void expect_error(const unsigned char *data, size_t size, const brdffit_axes *axes,
                         brdffit_status want, const char *fragment)
{
    brdffit_grid *g = (brdffit_grid *)&g;
    brdffit_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(brdffit_load_rgl_buffer(&g, data, size, axes, NULL, &err), want);
    assert_null(g);
    assert_int_equal(err.status, want);
    if (strstr(err.message, fragment) == NULL) fail_msg("'%s' lacks '%s'", err.message, fragment);
}

/* The header of the field `name`: its name-length bytes. */
static unsigned char *field_header(unsigned char *file, size_t size, const char *name)
{
    size_t n = strlen(name), k;
    for (k = 18; k + 2 + n <= size; k++)
        if (file[k] == n && file[k + 1] == 0 && memcmp(file + k + 2, name, n) == 0)
            return file + k;
    fail_msg("no field %s", name);
    return NULL;
}

static void test_format_errors(void **state)
{
    fx_rgl_spec sp;
    size_t size = 0;
    unsigned char *file, *copy, *h;
    (void)state;
    spec_init(&sp, 1);
    file = fx_rgl_file(&sp, &size);
    copy = malloc(size);
    assert_non_null(file), assert_non_null(copy);
#define FRESH() memcpy(copy, file, size)
    FRESH(), copy[0] = 'T';
    expect_error(copy, size, NULL, BRDFFIT_E_FORMAT, "not a tensor file");
    FRESH(), copy[12] = 2;
    expect_error(copy, size, NULL, BRDFFIT_E_FORMAT, "version 2.0");
    expect_error(file, 17, NULL, BRDFFIT_E_FORMAT, "not a tensor file");
    expect_error(file, 40, NULL, BRDFFIT_E_FORMAT, "truncated tensor file");
    expect_error(file, size - 1, NULL, BRDFFIT_E_FORMAT, "lies outside the file");
    FRESH(), h = field_header(copy, size, "vndf"), h[5] = 'x';
    expect_error(copy, size, NULL, BRDFFIT_E_FORMAT, "no field 'vndf'");
    FRESH(), h = field_header(copy, size, "ndf"), h[2 + 3 + 2] = 11;
    expect_error(copy, size, NULL, BRDFFIT_E_FORMAT, "'ndf' has type code 11");
    FRESH(), h = field_header(copy, size, "ndf"), h[2 + 3 + 2] = 0;
    expect_error(copy, size, NULL, BRDFFIT_E_FORMAT, "unknown type code 0");
    FRESH(), h = field_header(copy, size, "sigma"), h[2 + 5] = 9;
    expect_error(copy, size, NULL, BRDFFIT_E_FORMAT, "more than the 8 allowed");
    FRESH(), h = field_header(copy, size, "rgb"), h[2] = 'n', h[3] = 'd', h[4] = 'f';
    expect_error(copy, size, NULL, BRDFFIT_E_FORMAT, "field 'ndf' is given twice");
    free(copy), free(file);
    sp.theta_i[4] = DEG(95.0);
    file = fx_rgl_file(&sp, &size);
    expect_error(file, size, NULL, BRDFFIT_E_RANGE, "theta_i[4]");
    free(file);
    spec_init(&sp, 1);
    sp.brdf = nan_green;
    file = fx_rgl_file(&sp, &size);
    expect_error(file, size, NULL, BRDFFIT_E_RANGE, "RGL rgb value");
    free(file);
#undef FRESH
}

/* Anisotropic, measured over a quarter of the light azimuths: scattered
 * loads, resampling is refused as by the reference reader. */
static void test_reduced_anisotropic(void **state)
{
    fx_rgl_spec sp;
    size_t size = 0;
    unsigned char *file;
    brdffit_grid *g;
    (void)state;
    spec_init(&sp, 1);
    sp.n_phi = 3, sp.phi_i[1] = PI / 4, sp.phi_i[2] = PI / 2;
    file = fx_rgl_file(&sp, &size);
    g = load(file, size, NULL);
    assert_true(brdffit_grid_sample_count(g) > 0);
    brdffit_grid_destroy(g);
    expect_error(file, size, brdffit_axes_default(), BRDFFIT_E_UNSUPPORTED, "1/4");
    free(file);
    /* light azimuths 1e-40 apart (float32 denormals): the reduction factor
     * 2 pi / span overflows an int; it is capped, not converted blindly */
    sp.phi_i[1] = 1e-40, sp.phi_i[2] = 2e-40;
    file = fx_rgl_file(&sp, &size);
    expect_error(file, size, brdffit_axes_default(), BRDFFIT_E_UNSUPPORTED, "1/1000000");
    free(file);
}

static void test_file_and_arguments(void **state)
{
    static const char *const names[] = {"m.bsdf"};
    fx_rgl_spec sp;
    fx_tempdir dir;
    char path[512];
    size_t size = 0;
    unsigned char *file;
    brdffit_grid *g = NULL, *h;
    brdffit_error err;
    brdffit_allocator bad = {NULL, NULL, NULL};
    brdffit_axes empty = *brdffit_axes_default();
    (void)state;
    spec_init(&sp, 1);
    file = fx_rgl_file(&sp, &size);
    assert_true(fx_tempdir_make(&dir));
    fx_tempdir_path(&dir, names[0], path, sizeof path);
    assert_true(fx_write_file(path, file, size));
    assert_int_equal(brdffit_load_rgl(&g, path, NULL, NULL, &err), BRDFFIT_OK);
    h = load(file, size, NULL);
    assert_int_equal(brdffit_grid_sample_count(g), brdffit_grid_sample_count(h));
    brdffit_grid_destroy(g), brdffit_grid_destroy(h);
    fx_tempdir_remove(&dir, names, 1);
    assert_int_equal(brdffit_load_rgl(&g, path, NULL, NULL, &err), BRDFFIT_E_IO);
    assert_null(g);
    assert_int_equal(brdffit_load_rgl(NULL, path, NULL, NULL, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_load_rgl(&g, NULL, NULL, NULL, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_load_rgl_buffer(&g, NULL, 0, NULL, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_load_rgl_buffer(&g, file, size, NULL, &bad, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    empty.n_phi_o = 0;
    assert_int_equal(brdffit_load_rgl_buffer(&g, file, size, &empty, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_null(g);
    free(file);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scattered_rgb),
        cmocka_unit_test(test_scattered_spectral_no_jacobian),
        cmocka_unit_test(test_resampled),
        cmocka_unit_test(test_format_errors),
        cmocka_unit_test(test_reduced_anisotropic),
        cmocka_unit_test(test_file_and_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
