/* The solid-angle measure of MERL cells (docs/measure.md): the cells
 * partition the pairs of directions above the horizon, the Jacobian of the
 * half/difference angles against finite differences, cells the horizon
 * cuts against a brute-force count, the loader's weights, and a fit on
 * MERL-layout data that recovers known parameters. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "grid/grid_internal.h"
#include "grid_fixtures.h"
#include "load/merl_measure.h"
#include "test_support.h"

#define PI 3.14159265358979323846

static double edge_h(size_t i)
{
    double t = (double)i / 90.0;
    return t * t * PI / 2;
}

static double edge_d(size_t j)
{
    return (double)j / 90.0 * PI / 2;
}

static double edge_p(size_t k)
{
    return (double)k / 180.0 * PI;
}

/* Light and view of half/difference angles, by the test's own rotations:
 * h = Rz(ph) Ry(th) z, l = Rz(ph) Ry(th) d, v = Rz(ph) Ry(th) (-dx, -dy, dz). */
static void pair_of(const double a[4], double l[3], double v[3])
{
    double th = a[0], ph = a[1], td = a[2], pd = a[3];
    double d[2][3] = {{sin(td) * cos(pd), sin(td) * sin(pd), cos(td)},
                      {-sin(td) * cos(pd), -sin(td) * sin(pd), cos(td)}};
    double *out[2] = {l, v};
    int k;
    for (k = 0; k < 2; k++) {
        double x = d[k][0] * cos(th) + d[k][2] * sin(th), y = d[k][1];
        double z = -d[k][0] * sin(th) + d[k][2] * cos(th);
        out[k][0] = x * cos(ph) - y * sin(ph);
        out[k][1] = x * sin(ph) + y * cos(ph);
        out[k][2] = z;
    }
}

/* The 4-volume spanned by the columns of the 6 x 4 Jacobian of
 * (theta_h, phi_h, theta_d, phi_d) -> (l, v): sqrt(det(J^T J)). */
static double numeric_jacobian(const double a[4])
{
    double J[4][6], G[4][4], det = 1.0, h = 1e-6;
    int i, j, k;
    for (k = 0; k < 4; k++) {
        double ap[4], am[4], lp[3], vp[3], lm[3], vm[3];
        memcpy(ap, a, sizeof ap);
        memcpy(am, a, sizeof am);
        ap[k] += h, am[k] -= h;
        pair_of(ap, lp, vp);
        pair_of(am, lm, vm);
        for (i = 0; i < 3; i++) {
            J[k][i] = (lp[i] - lm[i]) / (2 * h);
            J[k][3 + i] = (vp[i] - vm[i]) / (2 * h);
        }
    }
    for (i = 0; i < 4; i++)
        for (j = 0; j < 4; j++) {
            G[i][j] = 0.0;
            for (k = 0; k < 6; k++) G[i][j] += J[i][k] * J[j][k];
        }
    for (k = 0; k < 4; k++) { /* Gaussian elimination; G is positive definite */
        det *= G[k][k];
        for (i = k + 1; i < 4; i++) {
            double f = G[i][k] / G[k][k];
            for (j = k; j < 4; j++) G[i][j] -= f * G[k][j];
        }
    }
    return sqrt(det);
}

static void test_jacobian_matches_finite_differences(void **state)
{
    static const double at[][4] = {
        {0.3, 0.0, 0.7, 0.4}, {1.2, 2.0, 0.2, 2.9}, {0.05, -1.0, 1.4, 1.0}, {0.8, 0.5, 0.9, 1.6}};
    size_t k;
    (void)state;
    for (k = 0; k < sizeof at / sizeof at[0]; k++) {
        const double *a = at[k];
        double want = 4.0 * cos(a[2]) * sin(a[0]) * sin(a[2]);
        assert_close(numeric_jacobian(a) / want, 1.0, 1e-7);
    }
}

/* A cell the horizon does not cut: the Jacobian at its centre times its
 * coordinate volume (2 pi in phi_h, twice for reciprocity) is its measure
 * to second order in the cell size. */
static void test_small_cell_against_jacobian(void **state)
{
    bf_merl_measure m;
    static const size_t cells[][3] = {{40, 10, 30}, {20, 50, 90}, {60, 20, 170}};
    size_t k;
    (void)state;
    bf_merl_measure_init(&m);
    for (k = 0; k < sizeof cells / sizeof cells[0]; k++) {
        size_t ih = cells[k][0], id = cells[k][1], ip = cells[k][2];
        double h0 = edge_h(ih), h1 = edge_h(ih + 1), d0 = edge_d(id), d1 = edge_d(id + 1);
        double p0 = edge_p(ip), p1 = edge_p(ip + 1);
        double a[4] = {0.5 * (h0 + h1), 0.3, 0.5 * (d0 + d1), 0.5 * (p0 + p1)};
        double want = numeric_jacobian(a) * (h1 - h0) * 2 * PI * (d1 - d0) * (p1 - p0) * 2;
        assert_close(bf_merl_cell_measure(&m, ih, id, ip) / want, 1.0, 2e-4);
    }
}

/* Every cell, above the horizon or not: together they cover each pair of
 * directions above the horizon once, (2 pi)^2 in all. */
static void test_cells_partition_the_hemisphere_pairs(void **state)
{
    bf_merl_measure m;
    size_t ih, id, ip;
    double sum = 0.0;
    (void)state;
    bf_merl_measure_init(&m);
    for (ih = 0; ih < 90; ih++)
        for (id = 0; id < 90; id++)
            for (ip = 0; ip < 180; ip++) sum += bf_merl_cell_measure(&m, ih, id, ip);
    print_message("sum over all cells %.12g, (2 pi)^2 = %.12g, relative %.2g\n", sum, 4 * PI * PI,
                  sum / (4 * PI * PI) - 1);
    assert_close(sum / (4 * PI * PI), 1.0, 1e-8);
}

/* A cut cell against a brute-force midpoint count of the pairs above the
 * horizon, with the Jacobian in closed form. */
static double brute_force_cell(size_t ih, size_t id, size_t ip, size_t n)
{
    double h0 = edge_h(ih), h1 = edge_h(ih + 1), d0 = edge_d(id), d1 = edge_d(id + 1);
    double p0 = edge_p(ip), p1 = edge_p(ip + 1), sum = 0.0;
    size_t a, b, c;
    for (a = 0; a < n; a++) {
        double th = h0 + (h1 - h0) * (a + 0.5) / n;
        for (b = 0; b < n; b++) {
            double td = d0 + (d1 - d0) * (b + 0.5) / n;
            double jac = 4.0 * cos(td) * sin(th) * sin(td);
            for (c = 0; c < n; c++) {
                double pd = p0 + (p1 - p0) * (c + 0.5) / n;
                double lz = cos(td) * cos(th) - sin(td) * cos(pd) * sin(th);
                double vz = cos(td) * cos(th) + sin(td) * cos(pd) * sin(th);
                if (lz > 0.0 && vz > 0.0) sum += jac;
            }
        }
    }
    return sum * (h1 - h0) * (d1 - d0) * (p1 - p0) / ((double)n * n * n) * 2 * PI * 2;
}

static void test_cut_cells_against_brute_force(void **state)
{
    bf_merl_measure m;
    static const size_t cells[][3] = {{89, 0, 0}, {89, 5, 80}, {70, 35, 5}, {89, 80, 89}};
    size_t k;
    (void)state;
    bf_merl_measure_init(&m);
    for (k = 0; k < sizeof cells / sizeof cells[0]; k++) {
        size_t ih = cells[k][0], id = cells[k][1], ip = cells[k][2];
        double got = bf_merl_cell_measure(&m, ih, id, ip), want = brute_force_cell(ih, id, ip, 300);
        double full = 16 * PI * 0.5 * (cos(edge_h(ih)) - cos(edge_h(ih + 1))) *
                      (pow(sin(edge_d(id + 1)), 2) - pow(sin(edge_d(id)), 2)) * PI / 180;
        print_message("cut cell (%zu, %zu, %zu): %.6g, brute force %.6g, uncut %.6g\n", ih, id, ip,
                      got, want, full);
        assert_true(got > 0.1 * full && got < 0.9 * full); /* the horizon cuts it */
        assert_close(got / want, 1.0, 2e-4);
    }
}

/* ---- the loader's weights ------------------------------------------------------ */

/* Every cell measured, with a highlight, so the recovery fit has a lobe. */
static const double as_ns = 120.0;
static const double as_cd[3] = {0.3, 0.2, 0.1}, as_cs[3] = {0.5, 0.8, 1.2};
static const double scale[3] = {1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};

/* The simplified Ashikhmin-Shirley model of docs/models.md at the cell
 * centre (phi_h = 0), in the file's raw units. */
static double ashikhmin(double th, double td, double pd, int c)
{
    double a[4] = {th, 0.0, td, pd}, l[3], v[3], nl, nv, value;
    pair_of(a, l, v);
    nl = fmax(l[2], 1e-4), nv = fmax(v[2], 1e-4);
    value = as_cd[c] / PI +
            (as_ns + 1) * pow(cos(th), as_ns) / (8 * PI * cos(td) * fmax(nl, nv)) * as_cs[c];
    return value / scale[c];
}

/* The group's state: the complete MERL-layout grid, loaded once for the
 * weights' test and the recovery fit. */
static int load_complete(void **state)
{
    unsigned char *img = fx_merl_image(ashikhmin, 90, 90, 180);
    brdffit_grid *g = NULL;
    brdffit_status st;
    if (img == NULL) return -1;
    st = brdffit_load_merl_buffer(&g, img, FX_MERL_SIZE, NULL, NULL, NULL);
    free(img);
    *state = g;
    return st == BRDFFIT_OK ? 0 : -1;
}

static int unload_complete(void **state)
{
    brdffit_grid_destroy(*state);
    return 0;
}

static size_t cell_of_sample(const brdffit_grid *g, size_t s, size_t idx[3])
{
    double ti, pi_, to, po, l[3], v[3], th, td, pd, pos[3];
    brdffit_grid_sample_angles(g, s, &ti, &pi_, &to, &po);
    fx_dir(ti, pi_, l);
    fx_dir(to, po, v);
    fx_half_diff(l, v, &th, &td, &pd);
    fx_merl_coords(th, td, pd, pos);
    idx[0] = (size_t)pos[0], idx[1] = (size_t)pos[1], idx[2] = (size_t)pos[2];
    return (idx[0] * 90 + idx[1]) * 180 + idx[2];
}

static void test_loader_weights(void **state)
{
    const brdffit_grid *g = *state;
    size_t n = brdffit_grid_sample_count(g), s, idx[3], lo = 0, hi = 0;
    double sum = 0.0, *w = malloc(n * sizeof(double)), ratio, want;
    double rest = 0.0;
    unsigned char *seen = calloc(FX_MERL_CELLS, 1);
    bf_merl_measure m;
    bf_merl_measure_init(&m);
    assert_non_null(g->sample_weight);
    for (s = 0; s < n; s++) {
        size_t cell = cell_of_sample(g, s, idx);
        /* each sample carries the measure of its own cell */
        assert_true(g->sample_weight[s] == bf_merl_cell_measure(&m, idx[0], idx[1], idx[2]));
        assert_int_equal(seen[cell], 0);
        seen[cell] = 1;
        sum += g->sample_weight[s];
    }
    for (s = 0; s < FX_MERL_CELLS; s++)
        if (!seen[s]) rest += bf_merl_cell_measure(&m, s / 180 / 90, s / 180 % 90, s % 180);
    free(seen);
    print_message("%zu samples, weights sum to %.12g sr^2 = (2 pi)^2 (1 %+.4g)\n", n, sum,
                  sum / (4 * PI * PI) - 1);
    /* the cells whose centre lies below the horizon are left out: they
     * hold the rest of the pairs above the horizon, below 1 % */
    assert_close((sum + rest) / (4 * PI * PI), 1.0, 1e-8);
    assert_true(rest > 0.0 && rest < 0.01 * 4 * PI * PI);
    /* the public weights are those measures normalised over the cap */
    assert_int_equal(brdffit_grid_weights(g, PI / 2, BRDFFIT_WEIGHT_SOLID_ANGLE, w, NULL),
                     BRDFFIT_OK);
    for (s = 0; s < n; s++) {
        assert_close(w[s] * sum / g->sample_weight[s], 1.0, 1e-12);
        if (w[s] < w[lo]) lo = s;
        if (w[s] > w[hi]) hi = s;
    }
    print_message("largest / smallest weight: %.3g\n", w[hi] / w[lo]);
    assert_true(w[hi] / w[lo] > 1e6);
    /* a highlight cell against a wide one, both uncut: the ratio of
     * (cos theta_h0 - cos theta_h1) */
    for (s = 0, lo = hi = n; s < n; s++) {
        size_t cell = cell_of_sample(g, s, idx);
        if (cell == (0 * 90 + 20) * 180 + 60) lo = s;
        if (cell == (60 * 90 + 20) * 180 + 60) hi = s;
    }
    assert_true(lo < n && hi < n);
    ratio = w[lo] / w[hi];
    want = (1 - cos(edge_h(1))) / (cos(edge_h(60)) - cos(edge_h(61)));
    print_message("highlight / wide cell: %.4g\n", ratio);
    assert_close(ratio / want, 1.0, 1e-9);
    assert_true(ratio < 1e-5);
    free(w);
}

static void test_fit_recovers_parameters(void **state)
{
    const brdffit_grid *g = *state;
    brdffit_model *model = NULL;
    brdffit_fit *fit = NULL;
    double p[7];
    size_t c;
    assert_int_equal(brdffit_model_create(&model, "ashikhmin-shirley", NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_create(&fit, g, model, NULL, NULL), BRDFFIT_OK);
    /* the truth's cs = 1.03 is above the lobe's albedo bound: recover it as it is */
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PLAUSIBLE, 0), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_params(fit, p), BRDFFIT_OK);
    print_message("fitted ns %.10g cd %.10g %.10g %.10g cs %.10g %.10g %.10g\n", p[0], p[1], p[2],
                  p[3], p[4], p[5], p[6]);
    assert_close(p[0] / as_ns, 1.0, 1e-6);
    for (c = 0; c < 3; c++) {
        assert_close(p[1 + c] / as_cd[c], 1.0, 1e-6);
        assert_close(p[4 + c] / as_cs[c], 1.0, 1e-6);
    }
    brdffit_fit_destroy(fit);
    brdffit_model_destroy(model);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_jacobian_matches_finite_differences),
        cmocka_unit_test(test_small_cell_against_jacobian),
        cmocka_unit_test(test_cells_partition_the_hemisphere_pairs),
        cmocka_unit_test(test_cut_cells_against_brute_force),
        cmocka_unit_test(test_loader_weights),
        cmocka_unit_test(test_fit_recovers_parameters),
    };
    return cmocka_run_group_tests(tests, load_complete, unload_complete);
}
