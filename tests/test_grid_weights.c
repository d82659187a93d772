/* Residual weights against closed-form solid angles, the angle cap, and the
 * streaming weight plan. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "grid/grid_internal.h"
#include "grid_fixtures.h"
#include "test_support.h"

#define PI 3.14159265358979323846

static brdffit_grid *make_grid(const fx_axes *a, const brdffit_allocator *alloc)
{
    double *v = fx_values(&a->axes, 1);
    brdffit_grid *g = NULL;
    assert_int_equal(brdffit_grid_create_regular(&g, &a->axes, 1, v, NULL, alloc, NULL),
                     BRDFFIT_OK);
    free(v);
    return g;
}

/* The thesis layout in degrees: theta 0..90 (steps 5 and 2.5), phi 0..180 in 35 steps. */
static void full_axes(fx_axes *a)
{
    double ti[19], to[37], po[36];
    size_t k;
    for (k = 0; k < 19; k++) ti[k] = 5.0 * k;
    for (k = 0; k < 37; k++) to[k] = 2.5 * k;
    for (k = 0; k < 36; k++) po[k] = 180.0 * k / 35.0;
    fx_axes_set(a, ti, 19, to, 37, po, 36);
}

/* Solid angle of a cell from its edges in degrees. */
static double cell(double t_lo, double t_hi, double p_lo, double p_hi)
{
    return DEG(p_hi - p_lo) * (cos(DEG(t_lo)) - cos(DEG(t_hi)));
}

/* Full axes, uniform steps: the cell of (theta_o, phi_o) for a cap that lies
 * on an axis value or below the next midpoint. */
static double uniform_cell(double to, double po, double cap_deg)
{
    double dp = 180.0 / 35.0;
    return cell(fmax(0.0, to - 1.25), fmin(cap_deg, to + 1.25), fmax(0.0, po - dp / 2),
                fmin(180.0, po + dp / 2));
}

static void check_full_axes_cap(const brdffit_grid *g, const fx_axes *a, double cap_deg)
{
    double *w = malloc(19 * 37 * 36 * sizeof(double)), norm = PI * (1.0 - cos(DEG(cap_deg)));
    double row_sum = 0.0;
    size_t s, n_active = 0;
    assert_int_equal(brdffit_grid_weights(g, DEG(cap_deg), BRDFFIT_WEIGHT_SOLID_ANGLE, w, NULL),
                     BRDFFIT_OK);
    for (s = 0; s < 19 * 37 * 36; s++) {
        size_t i = s / (37 * 36), j = s / 36 % 37, k = s % 36;
        double ti = a->deg[0][i], to = a->deg[1][j], po = a->deg[2][k];
        if (ti > cap_deg || to > cap_deg) {
            assert_true(w[s] == 0.0);
            continue;
        }
        n_active++;
        /* w = cell / (pi (1 - cos cap)): the cells sum to exactly that */
        assert_close(w[s] * norm, uniform_cell(to, po, cap_deg), 1e-12);
        if (i == 0) row_sum += w[s];
    }
    assert_close(row_sum, 1.0, 1e-12);
    assert_int_equal(n_active, brdffit_grid_active_count(g, DEG(cap_deg)));
    free(w);
}

static void test_solid_angle_full_axes(void **state)
{
    static const double caps[] = {75.0, 90.0, 45.0, 2.5, 76.0, 30.2, 11.0};
    fx_axes a;
    brdffit_grid *g;
    size_t k;
    (void)state;
    full_axes(&a);
    g = make_grid(&a, NULL);
    for (k = 0; k < sizeof caps / sizeof caps[0]; k++) check_full_axes_cap(g, &a, caps[k]);
    brdffit_grid_destroy(g);
}

static void test_halves_and_quarters(void **state)
{
    fx_axes a;
    brdffit_grid *g;
    double *w = malloc(19 * 37 * 36 * sizeof(double));
    size_t j75 = 30, row = 37 * 36;
    (void)state;
    full_axes(&a);
    g = make_grid(&a, NULL);
    assert_int_equal(brdffit_grid_weights(g, DEG(75.0), BRDFFIT_WEIGHT_SOLID_ANGLE, w, NULL),
                     BRDFFIT_OK);
    /* phi border cells are half as wide as their neighbours */
    assert_close(w[row + 10 * 36 + 0], w[row + 10 * 36 + 1] / 2, 1e-12);
    assert_close(w[row + 10 * 36 + 35], w[row + 10 * 36 + 34] / 2, 1e-12);
    /* the cap row (theta_o = 75) reaches only from 73.75 to 75 */
    assert_close(w[row + j75 * 36 + 7],
                 w[row + 29 * 36 + 7] * (cos(DEG(73.75)) - cos(DEG(75.0))) /
                     (cos(DEG(71.25)) - cos(DEG(73.75))),
                 1e-12);
    /* corner (theta_o = cap, phi_o = 0): a quarter of the cell area ratio */
    assert_close(w[row + j75 * 36 + 0], w[row + j75 * 36 + 1] / 2, 1e-12);
    assert_close(w[row + j75 * 36 + 0] / w[row + 29 * 36 + 1],
                 0.5 * (cos(DEG(73.75)) - cos(DEG(75.0))) / (cos(DEG(71.25)) - cos(DEG(73.75))),
                 1e-12);
    /* the pole cell: a cap of half width */
    assert_close(w[row + 5],
                 cell(0.0, 1.25, 180.0 * 4.5 / 35, 180.0 * 5.5 / 35) / (PI * (1 - cos(DEG(75.0)))),
                 1e-12);
    free(w);
    brdffit_grid_destroy(g);
}

static void test_cap_above_midpoint(void **state)
{
    fx_axes a;
    brdffit_grid *g;
    double *w = malloc(19 * 37 * 36 * sizeof(double));
    double norm = PI * (1.0 - cos(DEG(76.25))); /* the last cell stops at the midpoint */
    (void)state;
    full_axes(&a);
    g = make_grid(&a, NULL);
    assert_int_equal(brdffit_grid_weights(g, DEG(77.0), BRDFFIT_WEIGHT_SOLID_ANGLE, w, NULL),
                     BRDFFIT_OK);
    assert_close(w[30 * 36 + 3] * norm, uniform_cell(75.0, 180.0 * 3 / 35, 76.25), 1e-12);
    assert_close(w[10 * 36 + 3] * norm, uniform_cell(25.0, 180.0 * 3 / 35, 76.25), 1e-12);
    assert_true(w[31 * 36 + 3] == 0.0);
    free(w);
    brdffit_grid_destroy(g);
}

static void test_uneven_axes(void **state)
{
    static const double ti[] = {0.0, 30.0, 60.0};
    static const double to[] = {0.0, 10.0, 15.0, 40.0, 60.0, 90.0};
    static const double po[] = {0.0, 30.0, 45.0, 120.0, 180.0};
    static const double t_edges[5] = {0.0, 5.0, 12.5, 27.5, 50.0};
    static const double p_edges[6] = {0.0, 15.0, 37.5, 82.5, 150.0, 180.0};
    fx_axes a;
    brdffit_grid *g;
    double w[3 * 6 * 5], wc[3 * 6 * 5], norm = PI * (1.0 - cos(DEG(50.0)));
    size_t s;
    (void)state;
    fx_axes_set(&a, ti, 3, to, 6, po, 5);
    g = make_grid(&a, NULL);
    assert_int_equal(brdffit_grid_weights(g, DEG(50.0), BRDFFIT_WEIGHT_SOLID_ANGLE, w, NULL),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_grid_weights(g, DEG(50.0), BRDFFIT_WEIGHT_DEFAULT, wc, NULL),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_grid_active_count(g, DEG(50.0)), 2 * 4 * 5);
    for (s = 0; s < 90; s++) {
        size_t i = s / 30, j = s / 5 % 6, k = s % 5;
        if (i > 1 || j > 3) {
            assert_true(w[s] == 0.0 && wc[s] == 0.0);
            continue;
        }
        assert_close(w[s] * norm, cell(t_edges[j], t_edges[j + 1], p_edges[k], p_edges[k + 1]),
                     1e-12);
        assert_close(wc[s], w[s] * cos(DEG(ti[i])), 1e-12);
    }
    brdffit_grid_destroy(g);
}

static void test_flags(void **state)
{
    fx_axes a;
    brdffit_grid *g;
    double *w = malloc(19 * 37 * 36 * sizeof(double));
    double *ws = malloc(19 * 37 * 36 * sizeof(double));
    size_t s;
    (void)state;
    full_axes(&a);
    g = make_grid(&a, NULL);
    assert_int_equal(brdffit_grid_weights(g, DEG(60.0), BRDFFIT_WEIGHT_NONE, w, NULL), BRDFFIT_OK);
    for (s = 0; s < 19 * 37 * 36; s++) {
        int active = s / (37 * 36) <= 12 && s / 36 % 37 <= 24;
        assert_true(w[s] == (active ? 1.0 : 0.0));
    }
    assert_int_equal(brdffit_grid_weights(g, DEG(90.0), BRDFFIT_WEIGHT_COSINE, w, NULL),
                     BRDFFIT_OK);
    for (s = 0; s < 19 * 37 * 36; s++) assert_close(w[s], cos(DEG(5.0 * (s / (37 * 36)))), 1e-15);
    assert_true(w[18 * 37 * 36] >= 0.0);
    assert_int_equal(brdffit_grid_weights(g, DEG(60.0), BRDFFIT_WEIGHT_SOLID_ANGLE, ws, NULL),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_grid_weights(g, DEG(60.0), BRDFFIT_WEIGHT_DEFAULT, w, NULL),
                     BRDFFIT_OK);
    for (s = 0; s < 19 * 37 * 36; s++)
        assert_close(w[s], ws[s] * cos(DEG(5.0 * (s / (37 * 36)))), 1e-14);
    free(w);
    free(ws);
    brdffit_grid_destroy(g);
}

static void test_cap_tolerance_and_errors(void **state)
{
    fx_axes a;
    brdffit_grid *g;
    brdffit_error err;
    double *w = malloc(19 * 37 * 36 * sizeof(double));
    (void)state;
    full_axes(&a);
    g = make_grid(&a, NULL);
    /* theta <= cap + 1e-9 counts as inside */
    assert_int_equal(brdffit_grid_active_count(g, DEG(75.0) - 5e-10), 16 * 31 * 36);
    assert_int_equal(brdffit_grid_active_count(g, DEG(75.0) - 2e-9), 15 * 30 * 36);
    assert_int_equal(brdffit_grid_active_count(g, PI / 2), 19 * 37 * 36);
    assert_int_equal(brdffit_grid_active_count(g, 0.0), 36);
    assert_int_equal(brdffit_grid_active_count(g, -0.1), 0);
    assert_int_equal(brdffit_grid_active_count(g, PI / 2 + 1e-12), 0);
    assert_int_equal(brdffit_grid_active_count(g, NAN), 0);
    /* bad arguments */
    assert_int_equal(brdffit_grid_weights(g, -1e-12, 3, w, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "cap"));
    assert_int_equal(brdffit_grid_weights(g, 1.6, 3, w, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_grid_weights(g, NAN, 3, w, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_grid_weights(g, 1.0, 4, w, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "flags"));
    assert_int_equal(brdffit_grid_weights(g, 1.0, 3, NULL, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_grid_weights(NULL, 1.0, 3, w, &err), BRDFFIT_E_INVALID_ARGUMENT);
    /* cap 0: one view direction, no solid angle */
    memset(&err, 0, sizeof err);
    assert_int_equal(brdffit_grid_weights(g, 0.0, 3, w, &err), BRDFFIT_E_NO_DATA);
    assert_int_equal(err.status, BRDFFIT_E_NO_DATA);
    assert_non_null(strstr(err.message, "solid angle"));
    assert_int_equal(brdffit_grid_weights(g, 0.0, BRDFFIT_WEIGHT_COSINE, w, &err), BRDFFIT_OK);
    assert_true(w[0] == 1.0 && w[36] == 0.0 && w[37 * 36] == 0.0);
    brdffit_grid_destroy(g);
    free(w);
}

static void test_cap_below_first_axis_value(void **state)
{
    static const double t[] = {10.0, 20.0};
    static const double p[] = {0.0, 180.0};
    fx_axes a;
    brdffit_grid *g;
    brdffit_error err;
    double w[8];
    (void)state;
    fx_axes_set(&a, t, 2, t, 2, p, 2);
    g = make_grid(&a, NULL);
    assert_int_equal(brdffit_grid_active_count(g, DEG(5.0)), 0);
    assert_int_equal(brdffit_grid_weights(g, DEG(5.0), 0, w, &err), BRDFFIT_E_NO_DATA);
    assert_non_null(strstr(err.message, "cap"));
    /* theta cells start at the first axis value: [10, 15] and [15, 20] */
    assert_int_equal(brdffit_grid_weights(g, DEG(90.0), 1, w, &err), BRDFFIT_OK);
    assert_close(w[0] * (PI * (cos(DEG(10.0)) - cos(DEG(20.0)))), cell(10, 15, 0, 90), 1e-12);
    assert_close(w[3] * (PI * (cos(DEG(10.0)) - cos(DEG(20.0)))), cell(15, 20, 90, 180), 1e-12);
    brdffit_grid_destroy(g);
}

/* ---- scattered grids --------------------------------------------------------------- */

enum { NS = 6 };

static brdffit_grid *make_scattered(const double *weights)
{
    static const double ti[NS] = {10, 80, 30, 0, 60, 45};
    static const double to[NS] = {5, 20, 30, 70, 10, 89};
    double r_ti[NS], r_to[NS], p[NS], v[NS];
    brdffit_grid *g = NULL;
    size_t s;
    for (s = 0; s < NS; s++) {
        r_ti[s] = DEG(ti[s]), r_to[s] = DEG(to[s]), p[s] = 0.3 * s, v[s] = 1.0;
    }
    assert_int_equal(
        brdffit_grid_create_scattered(&g, NS, r_ti, p, r_to, p, 1, v, NULL, weights, NULL, NULL),
        BRDFFIT_OK);
    return g;
}

static void test_scattered_weights(void **state)
{
    /* stored order by max theta: (10,5) (30,30) (60,10) (0,70) (80,20) (45,89) */
    static const double cos_ti[NS] = {10, 30, 60, 0, 80, 45};
    static const double given[NS] = {1.0, 2.0, 3.0, 4.0, 5.0, 6.0}; /* input order */
    static const double stored_w[NS] = {1.0, 3.0, 5.0, 4.0, 2.0, 6.0};
    brdffit_grid *g = make_scattered(NULL), *gw = make_scattered(given);
    double w[NS];
    brdffit_error err;
    size_t s;
    (void)state;
    assert_int_equal(brdffit_grid_active_count(g, DEG(70.0)), 4);
    assert_int_equal(brdffit_grid_weights(g, DEG(70.0), BRDFFIT_WEIGHT_SOLID_ANGLE, w, NULL),
                     BRDFFIT_OK);
    for (s = 0; s < NS; s++) assert_close(w[s], s < 4 ? 0.25 : 0.0, 1e-15);
    assert_int_equal(brdffit_grid_weights(g, DEG(70.0), BRDFFIT_WEIGHT_DEFAULT, w, NULL),
                     BRDFFIT_OK);
    for (s = 0; s < NS; s++) assert_close(w[s], s < 4 ? 0.25 * cos(DEG(cos_ti[s])) : 0.0, 1e-15);
    assert_int_equal(brdffit_grid_weights(g, DEG(90.0), BRDFFIT_WEIGHT_COSINE, w, NULL),
                     BRDFFIT_OK);
    for (s = 0; s < NS; s++) assert_close(w[s], cos(DEG(cos_ti[s])), 1e-15);
    /* given weights, normalised by the sum of the active ones */
    assert_int_equal(brdffit_grid_weights(gw, DEG(70.0), BRDFFIT_WEIGHT_SOLID_ANGLE, w, NULL),
                     BRDFFIT_OK);
    for (s = 0; s < NS; s++) assert_close(w[s], s < 4 ? stored_w[s] / 13.0 : 0.0, 1e-15);
    assert_int_equal(brdffit_grid_weights(gw, DEG(90.0), BRDFFIT_WEIGHT_DEFAULT, w, NULL),
                     BRDFFIT_OK);
    for (s = 0; s < NS; s++) assert_close(w[s], stored_w[s] / 21.0 * cos(DEG(cos_ti[s])), 1e-15);
    assert_int_equal(brdffit_grid_weights(g, DEG(4.0), 3, w, &err), BRDFFIT_E_NO_DATA);
    assert_int_equal(brdffit_grid_active_count(g, DEG(4.0)), 0);
    assert_int_equal(brdffit_grid_active_count(g, DEG(10.0)), 1);
    brdffit_grid_destroy(g);
    brdffit_grid_destroy(gw);
}

static void test_scattered_zero_weights(void **state)
{
    static const double zero_first[NS] = {0, 1, 0, 1, 1, 1};
    brdffit_grid *g = make_scattered(zero_first);
    double w[NS];
    brdffit_error err;
    (void)state;
    /* only the first stored sample is active and its weight is 0 */
    assert_int_equal(brdffit_grid_weights(g, DEG(10.0), 1, w, &err), BRDFFIT_E_NO_DATA);
    assert_non_null(strstr(err.message, "weight"));
    assert_int_equal(brdffit_grid_weights(g, DEG(10.0), BRDFFIT_WEIGHT_COSINE, w, &err),
                     BRDFFIT_OK);
    brdffit_grid_destroy(g);
}

/* The plan's base form (bf_weight_plan_base()): for the weightings with
 * the solid angle, every chunk in one or two pieces of consecutive
 * samples whose base weight times the piece's factor is the chunk's
 * weight to single precision (relative 2^-24; 0 where it is 0); none for
 * the others. */
static void check_base(const bf_weight_plan *plan, unsigned flags)
{
    size_t c, t, k;
    double chunk[BF_CHUNK];
    bf_weight_piece piece[2];
    int has = flags == BRDFFIT_WEIGHT_DEFAULT || flags == BRDFFIT_WEIGHT_SOLID_ANGLE;
    assert_int_equal(plan->base != NULL, has);
    for (c = 0; c < plan->n_chunks; c++) {
        size_t first = 0, count = 0, np = bf_weight_plan_base(plan, c, piece), at;
        bf_weight_plan_chunk(plan, c, &first, &count, chunk);
        if (!has) {
            assert_int_equal(np, 0);
            continue;
        }
        assert_true(np == 1 || np == 2);
        for (k = 0, at = first; k < np; at += piece[k].count, k++) {
            assert_int_equal(piece[k].first, at);
            assert_true(piece[k].count > 0 && isfinite(piece[k].factor));
            for (t = 0; t < piece[k].count; t++) {
                double w = chunk[at - first + t], bw = plan->base[at + t] * piece[k].factor;
                if (!(fabs(bw - w) <= 0x1p-24 * w)) {
                    print_error("chunk %zu sample %zu: base %.17g x %.17g = %.17g, weight %.17g\n",
                                c, at + t, (double)plan->base[at + t], piece[k].factor, bw, w);
                    fail();
                }
            }
        }
        assert_int_equal(at, first + count);
    }
}

/* Weights are finite for every grid the loaders accept: solid angles or
 * given weights so small that their sum is subnormal, or so large that it
 * overflows, are scaled before they are summed. */
static void expect_normalised(const brdffit_grid *g, const double *want, double tol)
{
    size_t n = brdffit_grid_sample_count(g), s;
    double w[8], sum = 0.0;
    assert_true(n <= 8);
    assert_int_equal(brdffit_grid_weights(g, DEG(90.0), BRDFFIT_WEIGHT_SOLID_ANGLE, w, NULL),
                     BRDFFIT_OK);
    for (s = 0; s < n; s++) {
        assert_true(isfinite(w[s]) && w[s] >= 0.0);
        if (want != NULL) assert_close(w[s], want[s], tol);
        sum += w[s];
    }
    assert_close(sum, 1.0, 1e-15);
    /* the base form too, where the plan has one (a factor in the double
     * range) */
    {
        bf_weight_plan plan;
        assert_int_equal(
            bf_weight_plan_init(&plan, g, DEG(90.0), BRDFFIT_WEIGHT_SOLID_ANGLE, &g->alloc, NULL),
            BRDFFIT_OK);
        if (plan.base != NULL) check_base(&plan, BRDFFIT_WEIGHT_SOLID_ANGLE);
        bf_weight_plan_free(&plan, &g->alloc);
    }
}

static void test_tiny_and_huge_weights(void **state)
{
    static const char csv[] = "theta_i,theta_o,phi_o,r\n0,0,0,0.1\n0,0,1e-320,0.1\n"
                              "0,30,0,0.1\n0,30,1e-320,0.1\n";
    static const double ti[2] = {0.1, 0.2}, p[2] = {0.0, 0.0}, v[2] = {1.0, 1.0};
    static const double tiny[2] = {0.0, 1e-320}, huge[2] = {1e308, 1e308}, zero[2] = {0, 0};
    static const double tiny_w[2] = {0.0, 1.0}, huge_w[2] = {0.5, 0.5};
    brdffit_grid *g = NULL;
    brdffit_error err;
    double w[2];
    (void)state;
    assert_int_equal(brdffit_load_csv_buffer(&g, csv, sizeof csv - 1, NULL, &err), BRDFFIT_OK);
    expect_normalised(g, NULL, 0.0);
    brdffit_grid_destroy(g);
    assert_int_equal(brdffit_grid_create_scattered(&g, 2, ti, p, ti, p, 1, v, NULL, tiny, NULL,
                                                   NULL),
                     BRDFFIT_OK);
    expect_normalised(g, tiny_w, 0.0);
    brdffit_grid_destroy(g);
    assert_int_equal(brdffit_grid_create_scattered(&g, 2, ti, p, ti, p, 1, v, NULL, huge, NULL,
                                                   NULL),
                     BRDFFIT_OK);
    expect_normalised(g, huge_w, 0.0);
    brdffit_grid_destroy(g);
    assert_int_equal(brdffit_grid_create_scattered(&g, 2, ti, p, ti, p, 1, v, NULL, zero, NULL,
                                                   NULL),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_grid_weights(g, DEG(90.0), BRDFFIT_WEIGHT_SOLID_ANGLE, w, &err),
                     BRDFFIT_E_NO_DATA);
    assert_non_null(strstr(err.message, "weight"));
    brdffit_grid_destroy(g);
}

/* ---- the weight plan --------------------------------------------------------------------- */

static void check_plan(const brdffit_grid *g, double cap, unsigned flags)
{
    size_t n = brdffit_grid_sample_count(g), c, t, covered = 0;
    double *w = malloc(n * sizeof(double)), chunk[BF_CHUNK];
    unsigned char *seen = calloc(n, 1);
    bf_weight_plan plan;
    counting_alloc ca;
    counting_alloc_init(&ca, 0);
    assert_int_equal(brdffit_grid_weights(g, cap, flags, w, NULL), BRDFFIT_OK);
    assert_int_equal(bf_weight_plan_init(&plan, g, cap, flags, &ca.hook, NULL), BRDFFIT_OK);
    /* only per-axis arrays, never per-sample memory */
    assert_true(ca.peak_bytes <= (g->n_axis[0] + g->n_axis[1] + g->n_axis[2]) * sizeof(double));
    assert_int_equal(plan.n_active, brdffit_grid_active_count(g, cap));
    for (c = plan.n_chunks; c-- > 0;) { /* any order: chunks are independent */
        size_t first = 0, count = 0;
        bf_weight_plan_chunk(&plan, c, &first, &count, chunk);
        assert_true(count >= 1 && count <= BF_CHUNK);
        assert_true(first + count <= n);
        for (t = 0; t < count; t++) {
            assert_int_equal(seen[first + t], 0);
            seen[first + t] = 1;
            assert_true(chunk[t] == w[first + t]);
        }
        covered += count;
    }
    assert_int_equal(covered, plan.n_active);
    for (t = 0; t < n; t++) {
        if (seen[t]) continue;
        assert_true(w[t] == 0.0); /* everything outside the chunks is beyond the cap */
    }
    check_base(&plan, flags);
    bf_weight_plan_free(&plan, &ca.hook);
    assert_int_equal(ca.live, 0);
    free(w);
    free(seen);
}

static void test_weight_plan(void **state)
{
    /* 75: the last active view row's cells cut at the cap; 76: cut between
     * axis values */
    static const double caps[] = {75.0, 90.0, 10.0, 2.5, 52.0, 76.0};
    fx_axes a;
    brdffit_grid *g, *s1, *s2;
    size_t k;
    unsigned f;
    double *ti = malloc(2000 * 4 * sizeof(double)), *v = malloc(2000 * sizeof(double));
    (void)state;
    full_axes(&a);
    g = make_grid(&a, NULL);
    for (k = 0; k < 2000; k++) {
        ti[k] = DEG(fmod(k * 7.3, 90.0)), ti[2000 + k] = fmod(0.1 * k, 6.0);
        ti[4000 + k] = DEG(fmod(k * 3.1, 90.0)), ti[6000 + k] = -fmod(0.05 * k, 6.0);
        v[k] = 1.0;
    }
    assert_int_equal(brdffit_grid_create_scattered(&s1, 2000, ti, ti + 2000, ti + 4000, ti + 6000,
                                                   1, v, NULL, NULL, NULL, NULL),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_grid_create_scattered(&s2, 2000, ti, ti + 2000, ti + 4000, ti + 6000,
                                                   1, v, NULL, v, NULL, NULL),
                     BRDFFIT_OK);
    for (k = 0; k < sizeof caps / sizeof caps[0]; k++)
        for (f = 0; f < 4; f++) {
            check_plan(g, DEG(caps[k]), f);
            check_plan(s1, DEG(caps[k]), f);
            check_plan(s2, DEG(caps[k]), f);
        }
    brdffit_grid_destroy(g);
    brdffit_grid_destroy(s1);
    brdffit_grid_destroy(s2);
    free(ti);
    free(v);
}

static void test_weight_plan_chunk_layout(void **state)
{
    fx_axes a;
    brdffit_grid *g;
    bf_weight_plan plan;
    double chunk[BF_CHUNK];
    size_t first, count, per_row = (1116 + BF_CHUNK - 1) / BF_CHUNK;
    (void)state;
    full_axes(&a);
    g = make_grid(&a, NULL);
    /* cap 75: 16 theta_i rows of 31 x 36 = 1116 active samples each, cut
     * into chunks of at most BF_CHUNK samples */
    assert_int_equal(bf_weight_plan_init(&plan, g, DEG(75.0), 3, &g->alloc, NULL), BRDFFIT_OK);
    assert_int_equal(plan.n_ti_act, 16);
    assert_int_equal(plan.n_to_act, 31);
    assert_int_equal(plan.chunks_per_ti, per_row);
    assert_int_equal(plan.n_chunks, 16 * per_row);
    assert_int_equal(plan.n_active, 16 * 1116);
    /* the last chunk of the first row holds the rest of that row */
    bf_weight_plan_chunk(&plan, per_row - 1, &first, &count, chunk);
    assert_int_equal(first, (per_row - 1) * BF_CHUNK);
    assert_int_equal(count, 1116 - (per_row - 1) * BF_CHUNK);
    /* the next starts the second row, past its inactive theta_o values */
    bf_weight_plan_chunk(&plan, per_row, &first, &count, chunk);
    assert_int_equal(first, 37 * 36);
    assert_int_equal(count, BF_CHUNK);
    bf_weight_plan_free(&plan, &g->alloc);
    brdffit_grid_destroy(g);
}

static void test_weights_out_of_memory(void **state)
{
    counting_alloc ca;
    fx_axes a;
    brdffit_grid *g;
    double w[19 * 37 * 36];
    (void)state;
    full_axes(&a);
    counting_alloc_init(&ca, 0);
    g = make_grid(&a, &ca.hook);
    ca.fail_at = ca.allocs + 1;
    assert_int_equal(brdffit_grid_weights(g, 1.0, 3, w, NULL), BRDFFIT_E_OUT_OF_MEMORY);
    assert_int_equal(brdffit_grid_weights(g, 1.0, 3, w, NULL), BRDFFIT_OK);
    brdffit_grid_destroy(g);
    assert_int_equal(ca.live, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_solid_angle_full_axes),
        cmocka_unit_test(test_halves_and_quarters),
        cmocka_unit_test(test_cap_above_midpoint),
        cmocka_unit_test(test_uneven_axes),
        cmocka_unit_test(test_flags),
        cmocka_unit_test(test_cap_tolerance_and_errors),
        cmocka_unit_test(test_cap_below_first_axis_value),
        cmocka_unit_test(test_scattered_weights),
        cmocka_unit_test(test_scattered_zero_weights),
        cmocka_unit_test(test_tiny_and_huge_weights),
        cmocka_unit_test(test_weight_plan),
        cmocka_unit_test(test_weight_plan_chunk_layout),
        cmocka_unit_test(test_weights_out_of_memory),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
