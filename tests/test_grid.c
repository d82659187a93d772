/* The measurement grid: creation from memory, validation, accessors,
 * derived geometry, the derived grids, allocation failures. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "grid/grid_internal.h"
#include "grid_fixtures.h"
#include "test_support.h"

#define PI 3.14159265358979323846

static const double ti_deg[] = {0.0, 20.0, 55.0};
static const double to_deg[] = {0.0, 10.0, 40.0, 90.0};
static const double po_deg[] = {
    0.0,
    60.0,
    150.0,
    180.0,
};

static void small_axes(fx_axes *a)
{
    fx_axes_set(a, ti_deg, 3, to_deg, 4, po_deg, 4);
}

static brdffit_grid *make_regular(const fx_axes *a, size_t nc, const unsigned char *mask,
                                  const brdffit_allocator *alloc)
{
    double *v = fx_values(&a->axes, nc);
    brdffit_grid *g = NULL;
    assert_non_null(v);
    assert_int_equal(brdffit_grid_create_regular(&g, &a->axes, nc, v, mask, alloc, NULL),
                     BRDFFIT_OK);
    free(v);
    return g;
}

/* ---- default axes -------------------------------------------------------- */

static void test_axes_default(void **state)
{
    const brdffit_axes *a = brdffit_axes_default();
    size_t k;
    (void)state;
    assert_non_null(a);
    assert_int_equal(a->n_theta_i, 19);
    assert_int_equal(a->n_theta_o, 37);
    assert_int_equal(a->n_phi_o, 36);
    for (k = 0; k < 19; k++) assert_true(a->theta_i[k] == DEG(5.0 * k));
    for (k = 0; k < 37; k++) assert_true(a->theta_o[k] == DEG(2.5 * k));
    for (k = 0; k < 36; k++) assert_close(a->phi_o[k], k * PI / 35.0, 1e-15);
    assert_true(a->theta_i[18] <= PI / 2 && a->theta_o[36] <= PI / 2 && a->phi_o[35] <= PI);
    assert_true(brdffit_axes_default() == a);
}

/* ---- regular grids -------------------------------------------------------- */

static void check_regular_contents(const brdffit_grid *g, const fx_axes *a, size_t nc)
{
    size_t n = 3 * 4 * 4, s, c, k, count;
    const double *x, *vals;
    double ti, pi_, to, po;
    assert_int_equal(brdffit_grid_get_kind(g), BRDFFIT_GRID_REGULAR);
    assert_int_equal(brdffit_grid_sample_count(g), n);
    assert_int_equal(brdffit_grid_channel_count(g), nc);
    for (k = 0; k < 3; k++) {
        assert_int_equal(brdffit_grid_axis(g, (brdffit_axis)k, &x, &count), BRDFFIT_OK);
        assert_int_equal(count, k == 0 ? 3 : 4);
        assert_memory_equal(x, a->rad[k], count * sizeof(double));
    }
    for (s = 0; s < n; s++) {
        size_t i = s / 16, j = s / 4 % 4, kk = s % 4;
        assert_int_equal(brdffit_grid_sample_angles(g, s, &ti, &pi_, &to, &po), BRDFFIT_OK);
        assert_true(ti == a->rad[0][i] && to == a->rad[1][j] && po == a->rad[2][kk]);
        assert_true(pi_ == PI);
        for (c = 0; c < nc; c++) {
            assert_int_equal(brdffit_grid_values(g, c, &vals), BRDFFIT_OK);
            assert_true(vals[s] == fx_value(ti, to, po, c));
        }
    }
}

static void test_create_regular(void **state)
{
    fx_axes a;
    size_t nc;
    (void)state;
    small_axes(&a);
    for (nc = 1; nc <= 7; nc += 2) {
        brdffit_grid *g = make_regular(&a, nc, NULL, NULL);
        check_regular_contents(g, &a, nc);
        assert_int_equal(brdffit_grid_missing_count(g), 0);
        assert_int_equal(brdffit_grid_is_missing(g, 0, 0), 0);
        assert_null(g->missing);
        brdffit_grid_destroy(g);
    }
}

static void test_create_regular_copies_input(void **state)
{
    fx_axes a;
    double *v;
    brdffit_grid *g = NULL;
    const double *vals;
    (void)state;
    small_axes(&a);
    v = fx_values(&a.axes, 2);
    assert_int_equal(brdffit_grid_create_regular(&g, &a.axes, 2, v, NULL, NULL, NULL), BRDFFIT_OK);
    /* scribble over the caller's arrays: the grid must not notice */
    memset(v, 0, 48 * 2 * sizeof(double));
    a.rad[0][1] = 1.0;
    fx_axes_set(&a, ti_deg, 3, to_deg, 4, po_deg, 4);
    check_regular_contents(g, &a, 2);
    assert_int_equal(brdffit_grid_values(g, 1, &vals), BRDFFIT_OK);
    free(v);
    brdffit_grid_destroy(g);
}

static void test_create_regular_missing(void **state)
{
    fx_axes a;
    double *v;
    unsigned char mask[48 * 3] = {0};
    brdffit_grid *g = NULL;
    const double *vals;
    size_t s, c;
    (void)state;
    small_axes(&a);
    v = fx_values(&a.axes, 3);
    /* masked values may hold anything, even NaN or negative numbers */
    mask[5 * 3 + 1] = 1, v[5 * 3 + 1] = NAN;
    mask[7 * 3 + 0] = 1, v[7 * 3 + 0] = -4.0;
    mask[7 * 3 + 2] = 7, v[7 * 3 + 2] = INFINITY;
    mask[47 * 3 + 2] = 1;
    assert_int_equal(brdffit_grid_create_regular(&g, &a.axes, 3, v, mask, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_grid_missing_count(g), 4);
    for (s = 0; s < 48; s++)
        for (c = 0; c < 3; c++) {
            int miss = mask[s * 3 + c] != 0;
            assert_int_equal(brdffit_grid_is_missing(g, s, c), miss);
            assert_int_equal(brdffit_grid_values(g, c, &vals), BRDFFIT_OK);
            if (miss)
                assert_true(vals[s] == 0.0);
            else
                assert_true(vals[s] == v[s * 3 + c]);
        }
    assert_int_equal(brdffit_grid_is_missing(g, 48, 0), 0);
    assert_int_equal(brdffit_grid_is_missing(g, 5, 3), 0);
    free(v);
    brdffit_grid_destroy(g);
}

static void test_create_regular_mask_without_missing(void **state)
{
    fx_axes a;
    unsigned char mask[48] = {0};
    brdffit_grid *g;
    (void)state;
    small_axes(&a);
    g = make_regular(&a, 1, mask, NULL);
    assert_int_equal(brdffit_grid_missing_count(g), 0);
    assert_null(g->missing);
    brdffit_grid_destroy(g);
}

static brdffit_status try_regular(const brdffit_axes *axes, size_t nc, const double *v,
                                  brdffit_error *err)
{
    brdffit_grid *g = (brdffit_grid *)&g; /* must be reset to NULL on failure */
    brdffit_status st;
    memset(err, 0, sizeof *err);
    st = brdffit_grid_create_regular(&g, axes, nc, v, NULL, NULL, err);
    if (st != BRDFFIT_OK) {
        assert_null(g);
        assert_int_equal(err->status, st);
        assert_true(strlen(err->message) > 0);
    }
    brdffit_grid_destroy(g);
    return st;
}

static void test_create_regular_errors(void **state)
{
    fx_axes a;
    brdffit_axes ax;
    brdffit_error err;
    brdffit_allocator bad = {NULL, NULL, NULL};
    double *v;
    double bad_ti[3];
    brdffit_grid *g = NULL;
    (void)state;
    small_axes(&a);
    v = fx_values(&a.axes, 2);
    assert_int_equal(brdffit_grid_create_regular(NULL, &a.axes, 2, v, NULL, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(try_regular(NULL, 2, v, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(try_regular(&a.axes, 2, NULL, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(try_regular(&a.axes, 0, v, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_grid_create_regular(&g, &a.axes, 2, v, NULL, &bad, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_null(g);
    ax = a.axes, ax.theta_o = NULL;
    assert_int_equal(try_regular(&ax, 2, v, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "theta_o"));
    ax = a.axes, ax.n_phi_o = 0;
    assert_int_equal(try_regular(&ax, 2, v, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "phi_o"));
    /* unsorted, repeated, out of range, not finite */
    memcpy(bad_ti, a.rad[0], sizeof bad_ti);
    ax = a.axes, ax.theta_i = bad_ti;
    bad_ti[2] = bad_ti[1];
    assert_int_equal(try_regular(&ax, 2, v, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "theta_i"));
    bad_ti[2] = bad_ti[1] / 2;
    assert_int_equal(try_regular(&ax, 2, v, &err), BRDFFIT_E_INVALID_ARGUMENT);
    bad_ti[2] = PI / 2 + 1e-12;
    assert_int_equal(try_regular(&ax, 2, v, &err), BRDFFIT_E_RANGE);
    assert_non_null(strstr(err.message, "theta_i[2]"));
    bad_ti[2] = NAN;
    assert_int_equal(try_regular(&ax, 2, v, &err), BRDFFIT_E_RANGE);
    bad_ti[0] = -1e-300, bad_ti[2] = a.rad[0][2];
    assert_int_equal(try_regular(&ax, 2, v, &err), BRDFFIT_E_RANGE);
    a.rad[2][3] = PI + 1e-12;
    assert_int_equal(try_regular(&a.axes, 2, v, &err), BRDFFIT_E_RANGE);
    assert_non_null(strstr(err.message, "phi_o[3]"));
    a.rad[2][3] = PI;
    assert_int_equal(try_regular(&a.axes, 2, v, &err), BRDFFIT_OK);
    /* values */
    v[9 * 2 + 1] = NAN;
    assert_int_equal(try_regular(&a.axes, 2, v, &err), BRDFFIT_E_RANGE);
    assert_non_null(strstr(err.message, "sample 9, channel 1"));
    v[9 * 2 + 1] = INFINITY;
    assert_int_equal(try_regular(&a.axes, 2, v, &err), BRDFFIT_E_RANGE);
    v[9 * 2 + 1] = -1e-9; /* negative values are data (measurement noise) */
    assert_int_equal(try_regular(&a.axes, 2, v, &err), BRDFFIT_OK);
    v[9 * 2 + 1] = -0.0;
    assert_int_equal(try_regular(&a.axes, 2, v, &err), BRDFFIT_OK);
    /* sizes that overflow are refused before any array is read */
    ax = a.axes, ax.n_theta_i = SIZE_MAX / 2;
    assert_int_equal(try_regular(&ax, 2, v, &err), BRDFFIT_E_TOO_LARGE);
    assert_int_equal(try_regular(&a.axes, SIZE_MAX / 8, v, &err), BRDFFIT_E_TOO_LARGE);
    free(v);
}

/* ---- scattered grids ------------------------------------------------------- */

enum { NS = 7 };
/* max(theta_i, theta_o): 50, 10, 50, 0, 90, 10, 30 (degrees) */
static const double s_ti[NS] = {50, 10, 20, 0, 90, 5, 30};
static const double s_pi[NS] = {0, -90, 200, 45, 180, -360, 359};
static const double s_to[NS] = {40, 10, 50, 0, 90, 10, 0};
static const double s_po[NS] = {180, 90, -45, 30, 0, 270, 10};
/* stable order by max theta */
static const size_t s_order[NS] = {3, 1, 5, 6, 0, 2, 4};

typedef struct scat {
    double ti[NS], pi_[NS], to[NS], po[NS], v[NS * 3], w[NS];
} scat;

static void scat_init(scat *x)
{
    size_t s, c;
    for (s = 0; s < NS; s++) {
        x->ti[s] = DEG(s_ti[s]), x->pi_[s] = DEG(s_pi[s]);
        x->to[s] = DEG(s_to[s]), x->po[s] = DEG(s_po[s]);
        x->w[s] = 0.5 + (double)s;
        for (c = 0; c < 3; c++) x->v[s * 3 + c] = 1.0 + (double)(10 * s + c);
    }
}

static void assert_same_direction(double t1, double p1, double t2, double p2)
{
    double a[3], b[3];
    fx_dir(t1, p1, a);
    fx_dir(t2, p2, b);
    assert_close(a[0], b[0], 1e-12);
    assert_close(a[1], b[1], 1e-12);
    assert_close(a[2], b[2], 1e-12);
    assert_close(t1, t2, 1e-12);
}

static void test_create_scattered(void **state)
{
    scat x;
    brdffit_grid *g = NULL;
    unsigned char mask[NS * 3] = {0};
    const double *vals;
    size_t s, c;
    (void)state;
    scat_init(&x);
    mask[2 * 3 + 1] = 1, x.v[2 * 3 + 1] = NAN;
    assert_int_equal(brdffit_grid_create_scattered(&g, NS, x.ti, x.pi_, x.to, x.po, 3, x.v, mask,
                                                   x.w, NULL, NULL),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_grid_get_kind(g), BRDFFIT_GRID_SCATTERED);
    assert_int_equal(brdffit_grid_sample_count(g), NS);
    assert_int_equal(brdffit_grid_channel_count(g), 3);
    assert_int_equal(brdffit_grid_missing_count(g), 1);
    assert_int_equal(brdffit_grid_axis(g, BRDFFIT_AXIS_THETA_I, &vals, &s), BRDFFIT_E_UNSUPPORTED);
    for (s = 0; s < NS; s++) {
        size_t src = s_order[s];
        double ti, pi_, to, po;
        assert_int_equal(brdffit_grid_sample_angles(g, s, &ti, &pi_, &to, &po), BRDFFIT_OK);
        assert_same_direction(ti, pi_, x.ti[src], x.pi_[src]);
        assert_same_direction(to, po, x.to[src], x.po[src]);
        assert_true(g->max_theta[s] == fmax(x.ti[src], x.to[src]));
        if (s > 0) assert_true(g->max_theta[s] >= g->max_theta[s - 1]);
        assert_true(g->sample_weight[s] == x.w[src]);
        for (c = 0; c < 3; c++) {
            assert_int_equal(brdffit_grid_values(g, c, &vals), BRDFFIT_OK);
            if (src == 2 && c == 1) {
                assert_true(vals[s] == 0.0);
                assert_int_equal(brdffit_grid_is_missing(g, s, c), 1);
            } else {
                assert_true(vals[s] == x.v[src * 3 + c]);
                assert_int_equal(brdffit_grid_is_missing(g, s, c), 0);
            }
        }
    }
    brdffit_grid_destroy(g);
}

static void test_create_scattered_sorts_large_input(void **state)
{
    enum { N = 5000 };
    double *ti = malloc(4 * N * sizeof(double)), *v = malloc(N * sizeof(double));
    brdffit_grid *g = NULL;
    const double *vals;
    uint32_t seed = 7;
    size_t s;
    (void)state;
    for (s = 0; s < N; s++) {
        seed = seed * 1664525u + 1013904223u;
        ti[s] = DEG((double)(seed >> 24) * 90.0 / 255.0); /* many ties */
        ti[N + s] = 0.0;
        ti[2 * N + s] = DEG((double)(seed >> 16 & 0xff) * 90.0 / 255.0);
        ti[3 * N + s] = 1.0;
        v[s] = (double)s; /* the value identifies the input position */
    }
    assert_int_equal(brdffit_grid_create_scattered(&g, N, ti, ti + N, ti + 2 * N, ti + 3 * N, 1, v,
                                                   NULL, NULL, NULL, NULL),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_grid_values(g, 0, &vals), BRDFFIT_OK);
    assert_null(g->sample_weight);
    for (s = 0; s < N; s++) {
        size_t src = (size_t)vals[s];
        assert_true(g->max_theta[s] == fmax(ti[src], ti[2 * N + src]));
        if (s == 0) continue;
        assert_true(g->max_theta[s] >= g->max_theta[s - 1]);
        if (g->max_theta[s] == g->max_theta[s - 1]) assert_true(vals[s] > vals[s - 1]);
    }
    brdffit_grid_destroy(g);
    free(ti);
    free(v);
}

static brdffit_status try_scattered(const scat *x, size_t n, const double *w, brdffit_error *err)
{
    brdffit_grid *g = (brdffit_grid *)&g;
    brdffit_status st;
    memset(err, 0, sizeof *err);
    st = brdffit_grid_create_scattered(&g, n, x->ti, x->pi_, x->to, x->po, 3, x->v, NULL, w, NULL,
                                       err);
    if (st != BRDFFIT_OK) {
        assert_null(g);
        assert_int_equal(err->status, st);
    }
    brdffit_grid_destroy(g);
    return st;
}

static void test_create_scattered_errors(void **state)
{
    scat x;
    brdffit_error err;
    brdffit_grid *g = NULL;
    (void)state;
    scat_init(&x);
    assert_int_equal(try_scattered(&x, 0, NULL, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_grid_create_scattered(&g, NS, NULL, x.pi_, x.to, x.po, 3, x.v, NULL,
                                                   NULL, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_grid_create_scattered(&g, NS, x.ti, x.pi_, x.to, NULL, 3, x.v, NULL,
                                                   NULL, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_grid_create_scattered(&g, NS, x.ti, x.pi_, x.to, x.po, 0, x.v, NULL,
                                                   NULL, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_grid_create_scattered(NULL, NS, x.ti, x.pi_, x.to, x.po, 3, x.v, NULL,
                                                   NULL, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    x.to[3] = PI / 2 + 1e-9;
    assert_int_equal(try_scattered(&x, NS, NULL, &err), BRDFFIT_E_RANGE);
    assert_non_null(strstr(err.message, "theta_o of sample 3"));
    x.to[3] = -1e-9;
    assert_int_equal(try_scattered(&x, NS, NULL, &err), BRDFFIT_E_RANGE);
    x.to[3] = 0.0;
    x.pi_[4] = 2 * PI + 1e-9;
    assert_int_equal(try_scattered(&x, NS, NULL, &err), BRDFFIT_E_RANGE);
    assert_non_null(strstr(err.message, "phi_i of sample 4"));
    x.pi_[4] = -2 * PI;
    assert_int_equal(try_scattered(&x, NS, NULL, &err), BRDFFIT_OK);
    x.po[1] = NAN;
    assert_int_equal(try_scattered(&x, NS, NULL, &err), BRDFFIT_E_RANGE);
    x.po[1] = 0.0;
    x.w[6] = -1.0;
    assert_int_equal(try_scattered(&x, NS, x.w, &err), BRDFFIT_E_RANGE);
    assert_non_null(strstr(err.message, "weight of sample 6"));
    x.w[6] = INFINITY;
    assert_int_equal(try_scattered(&x, NS, x.w, &err), BRDFFIT_E_RANGE);
    x.w[6] = NAN;
    assert_int_equal(try_scattered(&x, NS, x.w, &err), BRDFFIT_E_RANGE);
    x.w[6] = 0.0;
    assert_int_equal(try_scattered(&x, NS, x.w, &err), BRDFFIT_OK);
    x.v[2] = -INFINITY;
    assert_int_equal(try_scattered(&x, NS, NULL, &err), BRDFFIT_E_RANGE);
    assert_non_null(strstr(err.message, "sample 0, channel 2"));
    x.v[2] = -3.0;
    assert_int_equal(try_scattered(&x, NS, NULL, &err), BRDFFIT_OK);
    x.v[2] = 1.0;
    assert_int_equal(try_scattered(&x, SIZE_MAX / 4, NULL, &err), BRDFFIT_E_TOO_LARGE);
}

/* ---- derived geometry ----------------------------------------------------------- */

static void check_geometry_finite(const brdffit_grid *g)
{
    const bf_geometry *geo = &g->geo;
    size_t s;
    for (s = 0; s < g->n_samples; s++) {
        const double *arr[12] = {geo->lx, geo->ly, geo->lz, geo->vx, geo->vy,     geo->vz,
                                 geo->nl, geo->nv, geo->nh, geo->hv, geo->log_nh, geo->rv};
        size_t k;
        for (k = 0; k < 12; k++) assert_true(isfinite(arr[k][s]));
        for (k = 6; k < 10; k++) assert_true(arr[k][s] >= 1e-4 && arr[k][s] <= 1.0);
        assert_true(geo->log_nh[s] <= 0.0);
        assert_true(geo->rv[s] >= -1.0 && geo->rv[s] <= 1.0);
        assert_close(geo->lx[s] * geo->lx[s] + geo->ly[s] * geo->ly[s] + geo->lz[s] * geo->lz[s],
                     1.0, 1e-14);
    }
}

static void test_geometry_finite_at_grazing(void **state)
{
    static const double t[] = {0.0, 45.0, 89.0, 90.0};
    static const double p[] = {0.0, 90.0, 179.0, 180.0};
    fx_axes a;
    brdffit_grid *g;
    scat x;
    size_t s;
    (void)state;
    fx_axes_set(&a, t, 4, t, 4, p, 4);
    g = make_regular(&a, 1, NULL, NULL);
    check_geometry_finite(g);
    /* theta_i = theta_o = 90, phi_o = 0: light and view exactly opposite */
    s = (3 * 4 + 3) * 4 + 0;
    assert_true(g->geo.nh[s] == 1.0 && g->geo.log_nh[s] == 0.0);
    assert_true(g->geo.hv[s] == 1e-4 && g->geo.nl[s] == 1e-4 && g->geo.nv[s] == 1e-4);
    /* theta_i = theta_o = 90, phi_o = 180: the same direction */
    s = (3 * 4 + 3) * 4 + 3;
    assert_close(g->geo.hv[s], 1.0, 1e-15);
    assert_true(g->geo.nh[s] == 1e-4);
    brdffit_grid_destroy(g);
    /* scattered: grazing pairs at opposite and equal azimuths */
    scat_init(&x);
    for (s = 0; s < NS; s++) x.ti[s] = x.to[s] = PI / 2, x.pi_[s] = DEG(37.0 * s);
    for (s = 0; s < NS; s++) x.po[s] = x.pi_[s] + (s % 2 ? PI : 0.0) - (s > 3 ? 2 * PI : 0.0);
    assert_int_equal(brdffit_grid_create_scattered(&g, NS, x.ti, x.pi_, x.to, x.po, 3, x.v, NULL,
                                                   NULL, NULL, NULL),
                     BRDFFIT_OK);
    check_geometry_finite(g);
    brdffit_grid_destroy(g);
}

static void test_geometry_matches_directions(void **state)
{
    fx_axes a;
    brdffit_grid *g;
    size_t s;
    (void)state;
    small_axes(&a);
    g = make_regular(&a, 1, NULL, NULL);
    for (s = 0; s < g->n_samples; s++) {
        double ti, pi_, to, po, l[3], v[3], h[3], len;
        brdffit_grid_sample_angles(g, s, &ti, &pi_, &to, &po);
        fx_dir(ti, pi_, l);
        fx_dir(to, po, v);
        assert_close(l[0], -sin(ti), 1e-15); /* light at azimuth pi */
        assert_close(g->geo.lx[s], l[0], 1e-15);
        assert_close(g->geo.vy[s], v[1], 1e-15);
        assert_close(g->geo.rv[s], -l[0] * v[0] - l[1] * v[1] + l[2] * v[2], 1e-14);
        h[0] = l[0] + v[0], h[1] = l[1] + v[1], h[2] = l[2] + v[2];
        len = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
        if (len < 1e-6) continue;
        assert_close(g->geo.nh[s], fmax(h[2] / len, 1e-4), 1e-14);
    }
    brdffit_grid_destroy(g);
}

static void test_geometry_mirror_cosine_bounded(void **state)
{
    enum { N = 2000 };
    double *a = malloc(5 * N * sizeof(double));
    brdffit_grid *g = NULL;
    size_t s;
    (void)state;
    /* view exactly in the mirror direction: r.v = 1 up to rounding */
    for (s = 0; s < N; s++) {
        a[s] = a[2 * N + s] = DEG(90.0 * s / N);
        a[N + s] = 0.37 * (double)(s % 16) - 3.0;
        a[3 * N + s] = a[N + s] + PI;
        a[4 * N + s] = 1.0;
    }
    assert_int_equal(brdffit_grid_create_scattered(&g, N, a, a + N, a + 2 * N, a + 3 * N, 1,
                                                   a + 4 * N, NULL, NULL, NULL, NULL),
                     BRDFFIT_OK);
    for (s = 0; s < N; s++) {
        assert_true(g->geo.rv[s] <= 1.0 && g->geo.rv[s] >= -1.0);
        assert_close(g->geo.rv[s], 1.0, 1e-14);
    }
    brdffit_grid_destroy(g);
    free(a);
}

/* ---- accessors and handles -------------------------------------------------------- */

static void test_accessor_arguments(void **state)
{
    fx_axes a;
    brdffit_grid *g;
    const double *vals;
    size_t n;
    double t;
    (void)state;
    small_axes(&a);
    g = make_regular(&a, 2, NULL, NULL);
    assert_int_equal(brdffit_grid_axis(g, (brdffit_axis)3, &vals, &n), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_grid_axis(g, BRDFFIT_AXIS_PHI_O, NULL, &n),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_grid_axis(g, BRDFFIT_AXIS_PHI_O, &vals, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_grid_values(g, 2, &vals), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_grid_values(g, 0, NULL), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_grid_sample_angles(g, 48, &t, NULL, NULL, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_grid_sample_angles(g, 47, NULL, NULL, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_grid_sample_angles(g, 47, NULL, NULL, NULL, &t), BRDFFIT_OK);
    assert_true(t == PI);
    brdffit_grid_destroy(g);
    /* NULL handles */
    assert_int_equal(brdffit_grid_get_kind(NULL), 0);
    assert_int_equal(brdffit_grid_sample_count(NULL), 0);
    assert_int_equal(brdffit_grid_channel_count(NULL), 0);
    assert_int_equal(brdffit_grid_missing_count(NULL), 0);
    assert_int_equal(brdffit_grid_is_missing(NULL, 0, 0), 0);
    assert_int_equal(brdffit_grid_active_count(NULL, 1.0), 0);
    assert_int_equal(brdffit_grid_axis(NULL, BRDFFIT_AXIS_THETA_I, &vals, &n),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_grid_values(NULL, 0, &vals), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_grid_sample_angles(NULL, 0, &t, &t, &t, &t),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(bf_grid_ok(NULL), 0);
    brdffit_grid_destroy(NULL);
}

/* An allocator that never returns memory before the test ends, so that a
 * destroyed handle can still be inspected. */
typedef struct deferred {
    void *blocks[64];
    size_t n;
} deferred;

static void *deferred_alloc(size_t size, void *ctx)
{
    (void)ctx;
    return malloc(size);
}

static void deferred_free(void *ptr, void *ctx)
{
    deferred *d = ctx;
    d->blocks[d->n++] = ptr;
}

static void test_destroyed_handle(void **state)
{
    deferred d = {{0}, 0};
    brdffit_allocator hook = {deferred_alloc, deferred_free, &d};
    fx_axes a;
    brdffit_grid *g, *m = NULL;
    brdffit_error err;
    double w[48], out[2];
    const double *vals;
    size_t k;
    (void)state;
    small_axes(&a);
    g = make_regular(&a, 2, NULL, &hook);
    assert_int_equal(bf_grid_ok(g), 1);
    brdffit_grid_destroy(g);
    assert_true(d.n > 0);
    assert_int_equal(bf_grid_ok(g), 0);
    assert_int_equal(brdffit_grid_sample_count(g), 0);
    assert_int_equal(brdffit_grid_get_kind(g), 0);
    assert_int_equal(brdffit_grid_values(g, 0, &vals), BRDFFIT_E_BAD_HANDLE);
    assert_int_equal(brdffit_grid_weights(g, 1.0, 3, w, &err), BRDFFIT_E_BAD_HANDLE);
    assert_int_equal(brdffit_grid_eval(g, 0, 0, 0, 0, out, &err), BRDFFIT_E_BAD_HANDLE);
    assert_int_equal(brdffit_grid_channel_mean(&m, g, NULL, &err), BRDFFIT_E_BAD_HANDLE);
    assert_null(m);
    k = d.n;
    brdffit_grid_destroy(g); /* a second destroy is detected and ignored */
    assert_int_equal(d.n, k);
    for (k = 0; k < d.n; k++) free(d.blocks[k]);
}

/* ---- channel mean and clear coat ------------------------------------------------------- */

static void test_channel_mean(void **state)
{
    fx_axes a;
    double *v;
    unsigned char mask[48 * 3] = {0};
    brdffit_grid *g = NULL, *m = NULL;
    const double *mv;
    double w1[48], w2[48];
    size_t s;
    (void)state;
    small_axes(&a);
    v = fx_values(&a.axes, 3);
    mask[4 * 3 + 0] = 1;                                     /* one channel missing */
    mask[9 * 3 + 0] = mask[9 * 3 + 1] = mask[9 * 3 + 2] = 1; /* all missing */
    assert_int_equal(brdffit_grid_create_regular(&g, &a.axes, 3, v, mask, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_grid_channel_mean(&m, g, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_grid_channel_count(m), 1);
    assert_int_equal(brdffit_grid_sample_count(m), 48);
    assert_int_equal(brdffit_grid_missing_count(m), 1);
    assert_int_equal(brdffit_grid_values(m, 0, &mv), BRDFFIT_OK);
    for (s = 0; s < 48; s++) {
        double expect = (v[s * 3] + v[s * 3 + 1] + v[s * 3 + 2]) / 3.0;
        if (s == 4) expect = (v[s * 3 + 1] + v[s * 3 + 2]) / 2.0;
        if (s == 9) {
            assert_int_equal(brdffit_grid_is_missing(m, s, 0), 1);
            assert_true(mv[s] == 0.0);
            continue;
        }
        assert_int_equal(brdffit_grid_is_missing(m, s, 0), 0);
        assert_close(mv[s], expect, 1e-15);
    }
    /* the shape carries over: same weights, same interpolation nodes */
    assert_int_equal(brdffit_grid_weights(g, 1.2, 3, w1, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_grid_weights(m, 1.2, 3, w2, NULL), BRDFFIT_OK);
    assert_memory_equal(w1, w2, sizeof w1);
    assert_memory_equal(g->geo.block, m->geo.block, 48 * 12 * sizeof(double));
    brdffit_grid_destroy(m);
    brdffit_grid_destroy(g);
    /* overflow-safe: the mean of huge values stays finite */
    for (s = 0; s < 48 * 3; s++) v[s] = 1.5e308;
    assert_int_equal(brdffit_grid_create_regular(&g, &a.axes, 3, v, NULL, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_grid_channel_mean(&m, g, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_grid_values(m, 0, &mv), BRDFFIT_OK);
    assert_close(mv[0], 1.5e308, 1e-15);
    brdffit_grid_destroy(m);
    brdffit_grid_destroy(g);
    free(v);
}

static void test_channel_mean_scattered(void **state)
{
    scat x;
    brdffit_grid *g = NULL, *m = NULL;
    const double *mv, *gv[3];
    double w1[NS], w2[NS];
    size_t s, c;
    (void)state;
    scat_init(&x);
    assert_int_equal(brdffit_grid_create_scattered(&g, NS, x.ti, x.pi_, x.to, x.po, 3, x.v, NULL,
                                                   x.w, NULL, NULL),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_grid_channel_mean(&m, g, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_grid_get_kind(m), BRDFFIT_GRID_SCATTERED);
    assert_int_equal(brdffit_grid_values(m, 0, &mv), BRDFFIT_OK);
    for (c = 0; c < 3; c++) brdffit_grid_values(g, c, &gv[c]);
    for (s = 0; s < NS; s++) assert_close(mv[s], (gv[0][s] + gv[1][s] + gv[2][s]) / 3, 1e-15);
    assert_int_equal(brdffit_grid_weights(g, 1.0, 3, w1, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_grid_weights(m, 1.0, 3, w2, NULL), BRDFFIT_OK);
    assert_memory_equal(w1, w2, sizeof w1);
    assert_int_equal(brdffit_grid_active_count(m, 0.5), brdffit_grid_active_count(g, 0.5));
    brdffit_grid_destroy(m);
    brdffit_grid_destroy(g);
}

static double coat(double value, double theta_i, double r0)
{
    double c = fmax(cos(theta_i), 1e-4);
    double f = r0 + (1.0 - r0) * pow(1.0 - c, 5.0);
    return value / (1.0 - f);
}

static void test_clearcoat(void **state)
{
    static const double t[] = {0.0, 30.0, 60.0, 89.9, 90.0};
    fx_axes a;
    double *v;
    unsigned char mask[5 * 5 * 4 * 2] = {0};
    brdffit_grid *g = NULL, *cc = NULL;
    brdffit_error err;
    const double *cv, *gv;
    size_t s, c;
    (void)state;
    fx_axes_set(&a, t, 5, t, 5, po_deg, 4);
    v = fx_values(&a.axes, 2);
    mask[17] = 1;
    assert_int_equal(brdffit_grid_create_regular(&g, &a.axes, 2, v, mask, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_grid_clearcoat(&cc, g, 0.04, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_grid_missing_count(cc), 1);
    for (c = 0; c < 2; c++) {
        brdffit_grid_values(cc, c, &cv);
        brdffit_grid_values(g, c, &gv);
        for (s = 0; s < 100; s++) {
            double ti;
            brdffit_grid_sample_angles(g, s, &ti, NULL, NULL, NULL);
            if (s * 2 + c == 17) {
                assert_int_equal(brdffit_grid_is_missing(cc, s, c), 1);
                assert_true(cv[s] == 0.0);
                continue;
            }
            assert_close(cv[s], coat(gv[s], ti, 0.04), 1e-11);
            assert_true(cv[s] > gv[s]);
        }
    }
    brdffit_grid_destroy(cc);
    /* r0 = 0 at normal incidence leaves the value alone */
    assert_int_equal(brdffit_grid_clearcoat(&cc, g, 0.0, NULL, NULL), BRDFFIT_OK);
    brdffit_grid_values(cc, 0, &cv);
    brdffit_grid_values(g, 0, &gv);
    assert_true(cv[0] == gv[0]);
    brdffit_grid_destroy(cc);
    /* arguments */
    assert_int_equal(brdffit_grid_clearcoat(&cc, g, -0.01, NULL, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "r0"));
    assert_int_equal(brdffit_grid_clearcoat(&cc, g, 1.0, NULL, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_grid_clearcoat(&cc, g, NAN, NULL, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_grid_clearcoat(&cc, NULL, 0.1, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_grid_clearcoat(NULL, g, 0.1, NULL, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_null(cc);
    brdffit_grid_destroy(g);
    /* a compensated value that overflows is refused */
    for (s = 0; s < 200; s++) v[s] = 1e308;
    assert_int_equal(brdffit_grid_create_regular(&g, &a.axes, 2, v, NULL, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_grid_clearcoat(&cc, g, 0.5, NULL, &err), BRDFFIT_E_RANGE);
    assert_null(cc);
    brdffit_grid_destroy(g);
    free(v);
}

static void test_clearcoat_scattered(void **state)
{
    scat x;
    brdffit_grid *g = NULL, *cc = NULL;
    const double *cv, *gv;
    size_t s;
    (void)state;
    scat_init(&x);
    assert_int_equal(brdffit_grid_create_scattered(&g, NS, x.ti, x.pi_, x.to, x.po, 3, x.v, NULL,
                                                   NULL, NULL, NULL),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_grid_clearcoat(&cc, g, 0.2, NULL, NULL), BRDFFIT_OK);
    brdffit_grid_values(cc, 2, &cv);
    brdffit_grid_values(g, 2, &gv);
    for (s = 0; s < NS; s++) assert_close(cv[s], coat(gv[s], x.ti[s_order[s]], 0.2), 1e-11);
    brdffit_grid_destroy(cc);
    brdffit_grid_destroy(g);
}

/* ---- allocation failures --------------------------------------------------------------- */

typedef brdffit_status (*make_fn)(brdffit_grid **out, const brdffit_allocator *a, const void *ctx);

/* Fail the Nth allocation for N = 1, 2, ... until the call succeeds. */
static void check_oom(make_fn fn, const void *ctx)
{
    size_t n;
    for (n = 1;; n++) {
        counting_alloc ca;
        brdffit_grid *g = (brdffit_grid *)&g;
        brdffit_status st;
        counting_alloc_init(&ca, n);
        st = fn(&g, &ca.hook, ctx);
        if (st == BRDFFIT_OK) {
            assert_true(ca.allocs < n); /* no failure was injected */
            assert_true(ca.live > 0);
            brdffit_grid_destroy(g);
            assert_int_equal(ca.live, 0);
            assert_true(n > 1);
            return;
        }
        assert_int_equal(st, BRDFFIT_E_OUT_OF_MEMORY);
        assert_null(g);
        assert_int_equal(ca.live, 0);
        assert_true(n < 100);
    }
}

static brdffit_status oom_regular(brdffit_grid **out, const brdffit_allocator *a, const void *ctx)
{
    const fx_axes *ax = ctx;
    unsigned char mask[48 * 2] = {0};
    double *v = fx_values(&ax->axes, 2);
    brdffit_status st;
    mask[3] = 1;
    st = brdffit_grid_create_regular(out, &ax->axes, 2, v, mask, a, NULL);
    free(v);
    return st;
}

static brdffit_status oom_scattered(brdffit_grid **out, const brdffit_allocator *a, const void *ctx)
{
    const scat *x = ctx;
    unsigned char mask[NS * 3] = {0};
    mask[4] = 1;
    return brdffit_grid_create_scattered(out, NS, x->ti, x->pi_, x->to, x->po, 3, x->v, mask, x->w,
                                         a, NULL);
}

static brdffit_status oom_mean(brdffit_grid **out, const brdffit_allocator *a, const void *ctx)
{
    return brdffit_grid_channel_mean(out, ctx, a, NULL);
}

static brdffit_status oom_coat(brdffit_grid **out, const brdffit_allocator *a, const void *ctx)
{
    return brdffit_grid_clearcoat(out, ctx, 0.05, a, NULL);
}

static void test_allocation_failures(void **state)
{
    fx_axes a;
    scat x;
    brdffit_grid *g = NULL, *sg = NULL;
    (void)state;
    small_axes(&a);
    scat_init(&x);
    check_oom(oom_regular, &a);
    check_oom(oom_scattered, &x);
    assert_int_equal(oom_regular(&g, NULL, &a), BRDFFIT_OK);
    assert_int_equal(oom_scattered(&sg, NULL, &x), BRDFFIT_OK);
    check_oom(oom_mean, g);
    check_oom(oom_mean, sg);
    check_oom(oom_coat, g);
    check_oom(oom_coat, sg);
    brdffit_grid_destroy(g);
    brdffit_grid_destroy(sg);
}

static void test_every_allocation_goes_through_the_hook(void **state)
{
    counting_alloc ca;
    fx_axes a;
    brdffit_grid *g, *m = NULL;
    double w[48];
    (void)state;
    small_axes(&a);
    counting_alloc_init(&ca, 0);
    g = make_regular(&a, 3, NULL, &ca.hook);
    assert_true(ca.live >= 3);
    assert_true(ca.live_bytes >= 48 * 3 * sizeof(double) + 48 * 12 * sizeof(double));
    /* derived grids and weights use the given / the grid's allocator */
    assert_int_equal(brdffit_grid_channel_mean(&m, g, &ca.hook, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_grid_weights(g, 1.0, 3, w, NULL), BRDFFIT_OK);
    brdffit_grid_destroy(m);
    brdffit_grid_destroy(g);
    assert_int_equal(ca.live, 0);
    assert_int_equal(ca.live_bytes, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_axes_default),
        cmocka_unit_test(test_create_regular),
        cmocka_unit_test(test_create_regular_copies_input),
        cmocka_unit_test(test_create_regular_missing),
        cmocka_unit_test(test_create_regular_mask_without_missing),
        cmocka_unit_test(test_create_regular_errors),
        cmocka_unit_test(test_create_scattered),
        cmocka_unit_test(test_create_scattered_sorts_large_input),
        cmocka_unit_test(test_create_scattered_errors),
        cmocka_unit_test(test_geometry_finite_at_grazing),
        cmocka_unit_test(test_geometry_matches_directions),
        cmocka_unit_test(test_geometry_mirror_cosine_bounded),
        cmocka_unit_test(test_accessor_arguments),
        cmocka_unit_test(test_destroyed_handle),
        cmocka_unit_test(test_channel_mean),
        cmocka_unit_test(test_channel_mean_scattered),
        cmocka_unit_test(test_clearcoat),
        cmocka_unit_test(test_clearcoat_scattered),
        cmocka_unit_test(test_allocation_failures),
        cmocka_unit_test(test_every_allocation_goes_through_the_hook),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
