/* The MERL loader: a file written here from a known function of the
 * half/difference angles, loaded in both forms from memory and from a
 * file, checked at known directions; every format error; allocation
 * failures. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "grid_fixtures.h"
#include "test_support.h"

#define PI 3.14159265358979323846

static const double scale[3] = {1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};

/* The test material. Unmeasured: blue beyond theta_d = 80 degrees, and every
 * channel where theta_h > 85 and theta_d > 60 degrees. */
static double material(double th, double td, double pd, int c)
{
    if (c == 2 && td > DEG(80.0)) return -1.0;
    if (th > DEG(85.0) && td > DEG(60.0)) return -2.0;
    return (1.0 + 2.0 * pow(cos(th), 8.0)) * (1.0 + td) * (1.0 + 0.3 * sin(pd)) * (1.0 + 0.1 * c);
}

/* Only a few cells measured: keeps loads in the allocation-failure loops small. */
static double sparse(double th, double td, double pd, int c)
{
    (void)pd;
    if (th < DEG(3.0) && td < DEG(3.0)) return 0.5 + c;
    return -1.0;
}

static double nothing(double th, double td, double pd, int c)
{
    (void)th, (void)td, (void)pd, (void)c;
    return -1.0;
}

typedef struct fixture {
    unsigned char *image;
    fx_tempdir dir;
    char path[512];
} fixture;

static const char *const file_names[] = {"material.binary", "short.binary", "long.binary",
                                         "dims.binary", "tiny.binary"};

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    if (f == NULL) return -1;
    f->image = fx_merl_image(material, 90, 90, 180);
    if (f->image == NULL || !fx_tempdir_make(&f->dir)) return -1;
    fx_tempdir_path(&f->dir, file_names[0], f->path, sizeof f->path);
    if (!fx_write_file(f->path, f->image, FX_MERL_SIZE)) return -1;
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    fx_tempdir_remove(&f->dir, file_names, sizeof file_names / sizeof file_names[0]);
    free(f->image);
    free(f);
    return 0;
}

/* Value the test expects for a direction pair, from its own half/difference
 * angles; returns 0 when the position lies on a cell border (ambiguous). */
static int expected_value(const double l[3], const double v[3], int c, double *out)
{
    double th, td, pd, pos[3];
    size_t idx[3], n[3] = {90, 90, 180}, k;
    fx_half_diff(l, v, &th, &td, &pd);
    fx_merl_coords(th, td, pd, pos);
    /* phi_d is undefined when theta_d = 0, and depends on the rounding of a
     * nearly normal half vector when theta_h = 0 */
    if (pos[0] < 1e-3 || pos[1] < 1e-3) return 0;
    for (k = 0; k < 3; k++) {
        double r = floor(pos[k] + 0.5);
        if (fabs(pos[k] - r) < 1e-6 && r >= 1 && r <= n[k] - 1) return 0;
        idx[k] = pos[k] <= 0 ? 0 : (pos[k] >= n[k] - 1 ? n[k] - 1 : (size_t)pos[k]);
    }
    /* phi_d = 0 and pi are the same fold point; the material is symmetric in
     * phi_d about pi/2, so cells 0 and 179 hold the same value */
    if (pos[2] > 179.5) idx[2] = 0;
    *out = material(fx_merl_theta_h(idx[0]), fx_merl_theta_d(idx[1]), fx_merl_phi_d(idx[2]), c);
    if (*out >= 0.0) *out *= scale[c];
    return 1;
}

/* ---- the scattered form ---------------------------------------------------------- */

static size_t expected_scattered_count(void)
{
    size_t ih, id, ip, count = 0;
    for (ih = 0; ih < 90; ih++)
        for (id = 0; id < 90; id++)
            for (ip = 0; ip < 180; ip++) {
                double th = fx_merl_theta_h(ih), td = fx_merl_theta_d(id);
                double pd = fx_merl_phi_d(ip);
                double lz = cos(td) * cos(th) - sin(td) * cos(pd) * sin(th);
                double vz = cos(td) * cos(th) + sin(td) * cos(pd) * sin(th);
                int measured = material(th, td, pd, 0) >= 0.0;
                count += (size_t)(measured && lz > 0.0 && vz > 0.0);
            }
    return count;
}

static void check_scattered(const brdffit_grid *g)
{
    size_t n = brdffit_grid_sample_count(g), s, c, n_missing = 0;
    const double *vals[3];
    unsigned char *seen = calloc(FX_MERL_CELLS, 1);
    assert_int_equal(brdffit_grid_get_kind(g), BRDFFIT_GRID_SCATTERED);
    assert_int_equal(brdffit_grid_channel_count(g), 3);
    assert_int_equal(n, expected_scattered_count());
    for (c = 0; c < 3; c++) brdffit_grid_values(g, c, &vals[c]);
    for (s = 0; s < n; s++) {
        double ti, pi_, to, po, l[3], v[3], th, td, pd, pos[3];
        size_t cell;
        brdffit_grid_sample_angles(g, s, &ti, &pi_, &to, &po);
        fx_dir(ti, pi_, l);
        fx_dir(to, po, v);
        assert_true(l[2] > 0.0 && v[2] > 0.0);
        fx_half_diff(l, v, &th, &td, &pd);
        fx_merl_coords(th, td, pd, pos);
        /* every sample sits at a cell centre */
        assert_close(pos[0] - floor(pos[0]), 0.5, 1e-6);
        assert_close(pos[1] - floor(pos[1]), 0.5, 1e-6);
        assert_close(pos[2] - floor(pos[2]), 0.5, 1e-6);
        cell = ((size_t)pos[0] * 90 + (size_t)pos[1]) * 180 + (size_t)pos[2];
        assert_int_equal(seen[cell], 0); /* one sample per cell */
        seen[cell] = 1;
        for (c = 0; c < 3; c++) {
            double want = material(fx_merl_theta_h((size_t)pos[0]), fx_merl_theta_d((size_t)pos[1]),
                                   fx_merl_phi_d((size_t)pos[2]), (int)c);
            if (want < 0.0) {
                assert_int_equal(brdffit_grid_is_missing(g, s, c), 1);
                assert_true(vals[c][s] == 0.0);
                n_missing++;
                continue;
            }
            assert_int_equal(brdffit_grid_is_missing(g, s, c), 0);
            assert_close(vals[c][s], want * scale[c], 1e-14);
        }
    }
    assert_true(n_missing > 0);
    assert_int_equal(brdffit_grid_missing_count(g), n_missing);
    free(seen);
}

static void test_scattered_from_file_and_buffer(void **state)
{
    fixture *f = *state;
    brdffit_grid *g = NULL, *gb = NULL;
    brdffit_error err;
    const double *a, *b;
    size_t c;
    assert_int_equal(brdffit_load_merl(&g, f->path, NULL, NULL, &err), BRDFFIT_OK);
    check_scattered(g);
    assert_int_equal(brdffit_load_merl_buffer(&gb, f->image, FX_MERL_SIZE, NULL, NULL, &err),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_grid_sample_count(gb), brdffit_grid_sample_count(g));
    for (c = 0; c < 3; c++) {
        brdffit_grid_values(g, c, &a);
        brdffit_grid_values(gb, c, &b);
        assert_memory_equal(a, b, brdffit_grid_sample_count(g) * sizeof(double));
    }
    brdffit_grid_destroy(gb);
    brdffit_grid_destroy(g);
}

/* ---- the regular form ---------------------------------------------------------------- */

static size_t check_regular(const brdffit_grid *g, const brdffit_axes *axes)
{
    size_t i, j, k, c, s = 0, checked = 0;
    const double *vals[3];
    for (c = 0; c < 3; c++) brdffit_grid_values(g, c, &vals[c]);
    for (i = 0; i < axes->n_theta_i; i++)
        for (j = 0; j < axes->n_theta_o; j++)
            for (k = 0; k < axes->n_phi_o; k++, s++) {
                double l[3], v[3], want;
                fx_dir(axes->theta_i[i], PI, l);
                fx_dir(axes->theta_o[j], axes->phi_o[k], v);
                l[1] = 0.0; /* the light lies in the x-z plane */
                for (c = 0; c < 3; c++) {
                    if (!expected_value(l, v, (int)c, &want)) continue;
                    checked++;
                    if (want < 0.0) {
                        assert_int_equal(brdffit_grid_is_missing(g, s, c), 1);
                        continue;
                    }
                    assert_int_equal(brdffit_grid_is_missing(g, s, c), 0);
                    assert_close(vals[c][s], want, 1e-14);
                }
            }
    return checked;
}

static void test_regular_default_axes(void **state)
{
    fixture *f = *state;
    const brdffit_axes *axes = brdffit_axes_default();
    brdffit_grid *g = NULL, *gb = NULL;
    brdffit_error err;
    const double *a, *b;
    size_t checked;
    assert_int_equal(brdffit_load_merl(&g, f->path, axes, NULL, &err), BRDFFIT_OK);
    assert_int_equal(brdffit_grid_get_kind(g), BRDFFIT_GRID_REGULAR);
    assert_int_equal(brdffit_grid_sample_count(g), 19 * 37 * 36);
    checked = check_regular(g, axes);
    assert_true(checked > 19 * 37 * 36 * 3 / 2); /* most samples are unambiguous */
    assert_true(brdffit_grid_missing_count(g) > 0);
    assert_int_equal(brdffit_load_merl_buffer(&gb, f->image, FX_MERL_SIZE, axes, NULL, &err),
                     BRDFFIT_OK);
    brdffit_grid_values(g, 2, &a);
    brdffit_grid_values(gb, 2, &b);
    assert_memory_equal(a, b, 19 * 37 * 36 * sizeof(double));
    brdffit_grid_destroy(gb);
    brdffit_grid_destroy(g);
}

/* Whether value is the scaled value of one of the cells (ih, id, *). */
static int in_phi_row(double value, size_t ih, size_t id, int c)
{
    size_t ip;
    for (ip = 0; ip < 180; ip++) {
        double m = material(fx_merl_theta_h(ih), fx_merl_theta_d(id), fx_merl_phi_d(ip), c);
        if (fabs(m * scale[c] - value) <= 1e-14 * fabs(value)) return 1;
    }
    return 0;
}

static void test_regular_known_directions(void **state)
{
    fixture *f = *state;
    static const double ti[] = {0.0, 12.7, 31.3, 62.2};
    static const double to[] = {0.0, 21.1, 31.3, 47.1, 88.7};
    static const double po[] = {0.0, 33.3, 77.7, 151.9, 180.0};
    fx_axes a;
    brdffit_grid *g = NULL;
    const double *vals;
    double want;
    fx_axes_set(&a, ti, 4, to, 5, po, 5);
    assert_int_equal(brdffit_load_merl_buffer(&g, f->image, FX_MERL_SIZE, &a.axes, NULL, NULL),
                     BRDFFIT_OK);
    assert_true(check_regular(g, &a.axes) >= 4 * 5 * 5 * 3 / 2);
    brdffit_grid_values(g, 0, &vals);
    /* normal light and view: h = n, theta_h = theta_d = 0: a cell of the
     * first theta_h and theta_d row (phi_d is undefined there) */
    assert_true(in_phi_row(vals[0], 0, 0, 0));
    /* mirror direction at 31.3 degrees: h = n exactly, theta_h index 0,
     * theta_d index 31, phi_d = pi folds to 0 */
    want = material(fx_merl_theta_h(0), fx_merl_theta_d(31), fx_merl_phi_d(0), 0) / 1500.0;
    assert_close(vals[(2 * 5 + 2) * 5 + 0], want, 1e-14);
    /* backscatter (view = light) at 31.3: theta_h = 31.3 (index 53), theta_d = 0 */
    assert_true(fabs(sqrt(31.3 / 90.0) * 90.0 - 53.0) > 0.01); /* not on a border */
    assert_true(in_phi_row(vals[(2 * 5 + 2) * 5 + 4], 53, 0, 0));
    assert_false(in_phi_row(vals[(2 * 5 + 2) * 5 + 4], 52, 0, 0));
    brdffit_grid_destroy(g);
}

/* ---- format errors ------------------------------------------------------------------------ */

static void expect_buffer_error(const unsigned char *data, size_t size, const brdffit_axes *axes,
                                brdffit_status want, const char *frag1, const char *frag2)
{
    brdffit_grid *g = (brdffit_grid *)&g;
    brdffit_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(brdffit_load_merl_buffer(&g, data, size, axes, NULL, &err), want);
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

static void test_format_errors(void **state)
{
    fixture *f = *state;
    unsigned char *big = malloc(FX_MERL_SIZE + 8), hdr[12];
    const brdffit_axes *axes = brdffit_axes_default();
    int form;
    memcpy(big, f->image, FX_MERL_SIZE);
    memset(big + FX_MERL_SIZE, 0, 8);
    for (form = 0; form < 2; form++) {
        const brdffit_axes *ax = form ? axes : NULL;
        expect_buffer_error(f->image, FX_MERL_SIZE - 8, ax, BRDFFIT_E_FORMAT, "truncated",
                            "expected 34992012 bytes, found 34992004");
        expect_buffer_error(big, FX_MERL_SIZE + 8, ax, BRDFFIT_E_FORMAT, "oversized",
                            "expected 34992012 bytes, found 34992020");
        expect_buffer_error(f->image, 11, ax, BRDFFIT_E_FORMAT, "truncated", "11 bytes");
        expect_buffer_error(f->image, 0, ax, BRDFFIT_E_FORMAT, "truncated", NULL);
        memcpy(hdr, f->image, 12);
        fx_put_le32(hdr + 8, 360);
        expect_buffer_error(hdr, 12, ax, BRDFFIT_E_FORMAT, "90 x 90 x 360", NULL);
        fx_put_le32(hdr, -1);
        expect_buffer_error(hdr, 12, ax, BRDFFIT_E_FORMAT, "-1 x 90 x 360", NULL);
        fx_put_le32(hdr, 2147483647);
        fx_put_le32(hdr + 4, 2147483647);
        expect_buffer_error(hdr, 12, ax, BRDFFIT_E_FORMAT, "2147483647 x 2147483647", NULL);
    }
    /* wrong dimensions in an otherwise complete file: the dimensions are named */
    fx_put_le32(big + 4, 91);
    expect_buffer_error(big, FX_MERL_SIZE, NULL, BRDFFIT_E_FORMAT, "90 x 91 x 180", NULL);
    free(big);
}

static void put_value(unsigned char *img, size_t c, size_t ih, size_t id, size_t ip, double v)
{
    fx_put_le64(img + 12 + (c * FX_MERL_CELLS + (ih * 90 + id) * 180 + ip) * 8, v);
}

static void test_value_errors(void **state)
{
    fixture *f = *state;
    unsigned char *img = malloc(FX_MERL_SIZE);
    memcpy(img, f->image, FX_MERL_SIZE);
    put_value(img, 1, 3, 4, 5, NAN);
    expect_buffer_error(img, FX_MERL_SIZE, NULL, BRDFFIT_E_RANGE, "green",
                        "theta_h 3, theta_d 4, phi_d 5");
    expect_buffer_error(img, FX_MERL_SIZE, brdffit_axes_default(), BRDFFIT_E_RANGE, "NaN", NULL);
    put_value(img, 1, 3, 4, 5, 1.0);
    put_value(img, 0, 89, 89, 179, -INFINITY);
    expect_buffer_error(img, FX_MERL_SIZE, NULL, BRDFFIT_E_RANGE, "red",
                        "theta_h 89, theta_d 89, phi_d 179");
    free(img);
}

static void test_no_data(void **state)
{
    unsigned char *img = fx_merl_image(nothing, 90, 90, 180);
    static const double zero[] = {0.0};
    fx_axes a;
    (void)state;
    expect_buffer_error(img, FX_MERL_SIZE, NULL, BRDFFIT_E_NO_DATA, "no measured", NULL);
    expect_buffer_error(img, FX_MERL_SIZE, brdffit_axes_default(), BRDFFIT_E_NO_DATA, NULL, NULL);
    free(img);
    /* measured cells exist, but none is hit by the requested axes */
    img = fx_merl_image(sparse, 90, 90, 180);
    fx_axes_set(&a, (const double[]){60.0}, 1, (const double[]){60.0}, 1, zero, 1);
    expect_buffer_error(img, FX_MERL_SIZE, &a.axes, BRDFFIT_E_NO_DATA, "no grid sample", NULL);
    free(img);
}

static void test_file_errors(void **state)
{
    fixture *f = *state;
    brdffit_grid *g = (brdffit_grid *)&g;
    brdffit_error err;
    char path[512];
    FILE *fp;
    unsigned char hdr[12];
    fx_tempdir_path(&f->dir, "missing.binary", path, sizeof path);
    assert_int_equal(brdffit_load_merl(&g, path, NULL, NULL, &err), BRDFFIT_E_IO);
    assert_null(g);
    assert_non_null(strstr(err.message, "missing.binary"));
    assert_int_equal(brdffit_load_merl(&g, f->dir.path, NULL, NULL, &err), BRDFFIT_E_IO);
    /* truncated */
    fx_tempdir_path(&f->dir, file_names[1], path, sizeof path);
    assert_true(fx_write_file(path, f->image, 4096));
    assert_int_equal(brdffit_load_merl(&g, path, NULL, NULL, &err), BRDFFIT_E_FORMAT);
    assert_non_null(strstr(err.message, "expected 34992012 bytes, found 4096"));
    /* oversized: refused from its size, never read in full */
    fx_tempdir_path(&f->dir, file_names[2], path, sizeof path);
    fp = fopen(path, "wb");
    assert_non_null(fp);
    assert_int_equal(fwrite(f->image, 1, 12, fp), 12);
    assert_int_equal(fseek(fp, 1L << 30, SEEK_SET), 0); /* a sparse 1 GiB file */
    assert_int_equal(fputc(0, fp), 0);
    assert_int_equal(fclose(fp), 0);
    assert_int_equal(brdffit_load_merl(&g, path, brdffit_axes_default(), NULL, &err),
                     BRDFFIT_E_FORMAT);
    assert_non_null(strstr(err.message, "oversized"));
    assert_non_null(strstr(err.message, "found 1073741825"));
    /* wrong dimensions */
    memcpy(hdr, f->image, 12);
    fx_put_le32(hdr, 45);
    fx_tempdir_path(&f->dir, file_names[3], path, sizeof path);
    assert_true(fx_write_file(path, hdr, 12));
    assert_int_equal(brdffit_load_merl(&g, path, NULL, NULL, &err), BRDFFIT_E_FORMAT);
    assert_non_null(strstr(err.message, "45 x 90 x 180"));
    /* shorter than the header */
    fx_tempdir_path(&f->dir, file_names[4], path, sizeof path);
    assert_true(fx_write_file(path, hdr, 7));
    assert_int_equal(brdffit_load_merl(&g, path, NULL, NULL, &err), BRDFFIT_E_FORMAT);
    assert_non_null(strstr(err.message, "7 bytes"));
    assert_null(g);
}

static void test_null_arguments(void **state)
{
    fixture *f = *state;
    brdffit_grid *g = (brdffit_grid *)&g;
    brdffit_error err;
    brdffit_axes bad = *brdffit_axes_default();
    brdffit_allocator no_free = {NULL, NULL, NULL};
    assert_int_equal(brdffit_load_merl_buffer(NULL, f->image, FX_MERL_SIZE, NULL, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_load_merl_buffer(&g, NULL, FX_MERL_SIZE, NULL, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_null(g);
    assert_int_equal(brdffit_load_merl(&g, NULL, NULL, NULL, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_load_merl(NULL, f->path, NULL, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_load_merl(&g, f->path, NULL, &no_free, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    bad.theta_o = NULL;
    assert_int_equal(brdffit_load_merl_buffer(&g, f->image, FX_MERL_SIZE, &bad, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    bad = *brdffit_axes_default();
    bad.n_phi_o = 0;
    assert_int_equal(brdffit_load_merl_buffer(&g, f->image, FX_MERL_SIZE, &bad, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    bad.n_phi_o = (size_t)1 << 40;
    assert_int_equal(brdffit_load_merl_buffer(&g, f->image, FX_MERL_SIZE, &bad, NULL, &err),
                     BRDFFIT_E_TOO_LARGE);
}

/* ---- allocation failures ------------------------------------------------------------------------ */

typedef struct oom_case {
    const unsigned char *image;
    const char *path;
    const brdffit_axes *axes;
} oom_case;

static void check_oom(const oom_case *k)
{
    size_t n;
    for (n = 1;; n++) {
        counting_alloc ca;
        brdffit_grid *g = (brdffit_grid *)&g;
        brdffit_status st;
        counting_alloc_init(&ca, n);
        st = k->path != NULL
                 ? brdffit_load_merl(&g, k->path, k->axes, &ca.hook, NULL)
                 : brdffit_load_merl_buffer(&g, k->image, FX_MERL_SIZE, k->axes, &ca.hook, NULL);
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

static void test_allocation_failures(void **state)
{
    fixture *f = *state;
    unsigned char *img = fx_merl_image(sparse, 90, 90, 180);
    char path[512];
    oom_case k;
    fx_tempdir_path(&f->dir, file_names[1], path, sizeof path);
    assert_true(fx_write_file(path, img, FX_MERL_SIZE));
    k.image = img, k.path = NULL, k.axes = NULL;
    check_oom(&k);
    k.axes = brdffit_axes_default();
    check_oom(&k);
    k.path = path;
    check_oom(&k);
    k.axes = NULL;
    check_oom(&k);
    free(img);
}

/* Bad axes are refused before the file is opened: with a missing file the
 * call still reports the axes, with the status brdffit_grid_create_regular()
 * gives them. */
static void test_axes_checked_before_reading(void **state)
{
    static const double ok[2] = {0.0, 0.5}, outside[2] = {0.0, 2.0}, repeated[2] = {0.5, 0.5};
    fixture *f = *state;
    brdffit_axes axes = {ok, 2, ok, 2, ok, 2};
    brdffit_grid *g = (brdffit_grid *)&g;
    brdffit_error err;
    char path[512];
    fx_tempdir_path(&f->dir, "absent.binary", path, sizeof path);
    assert_int_equal(brdffit_load_merl(&g, path, &axes, NULL, &err), BRDFFIT_E_IO);
    axes.theta_o = outside;
    assert_int_equal(brdffit_load_merl(&g, path, &axes, NULL, &err), BRDFFIT_E_RANGE);
    assert_null(g);
    assert_non_null(strstr(err.message, "theta_o[1]"));
    axes.theta_o = ok;
    axes.phi_o = repeated;
    assert_int_equal(brdffit_load_merl(&g, path, &axes, NULL, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "phi_o is not strictly increasing"));
    axes.phi_o = ok;
    axes.theta_i = outside;
    assert_int_equal(brdffit_load_merl_buffer(&g, f->image, 3, &axes, NULL, &err),
                     BRDFFIT_E_RANGE);
    assert_non_null(strstr(err.message, "theta_i[1]"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scattered_from_file_and_buffer),
        cmocka_unit_test(test_regular_default_axes),
        cmocka_unit_test(test_regular_known_directions),
        cmocka_unit_test(test_format_errors),
        cmocka_unit_test(test_value_errors),
        cmocka_unit_test(test_no_data),
        cmocka_unit_test(test_file_errors),
        cmocka_unit_test(test_null_arguments),
        cmocka_unit_test(test_axes_checked_before_reading),
        cmocka_unit_test(test_allocation_failures),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
