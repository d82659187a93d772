/* The built-in models' Jacobians against finite differences at random
 * parameter sets over the whole default grid, the linear-parameter
 * contract, finiteness over the extremes of every parameter range, and the
 * dot-product floor inside the default angle cap. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "grid/grid_internal.h"
#include "model_fixtures.h"
#include "test_support.h"

/* Random parameter sets per model, and the worst relative error allowed
 * (metric of brdffit_model_check_jacobian()). */
#define N_SETS 20
#define JACOBIAN_TOLERANCE 1e-6
#define NC 3

typedef struct fixture {
    brdffit_grid *grid; /* default axes, NC channels */
} fixture;

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    if (f == NULL) return -1;
    f->grid = mf_default_grid(NC);
    if (f->grid == NULL) return -1;
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    brdffit_grid_destroy(f->grid);
    free(f);
    return 0;
}

static brdffit_model *create(const char *name)
{
    brdffit_model *m = NULL;
    assert_int_equal(brdffit_model_create(&m, name, NULL, NULL), BRDFFIT_OK);
    return m;
}

/* ---- Jacobians at random parameter sets ------------------------------------ */

static void check_model_jacobian(const fixture *f, const char *name, uint64_t seed)
{
    brdffit_model *m = create(name);
    double x[32], worst_lib = 0.0, worst_own = 0.0, worst_raw = 0.0;
    uint64_t rng = seed;
    /* BRDFFIT_TEST_QUICK (the valgrind runs): the first 3 sets only */
    size_t set, n_sets = test_quick() ? 3 : N_SETS;
    assert_true(brdffit_model_vector_size(m, NC) <= 32);
    for (set = 0; set < n_sets; set++) {
        brdffit_jacobian_report r;
        brdffit_error err;
        double own, raw;
        memset(&r, 0, sizeof r);
        r.struct_size = sizeof r;
        mf_random_params(m, NC, &rng, x);
        if (brdffit_model_check_jacobian(m, f->grid, x, &r, &err) != BRDFFIT_OK)
            fail_msg("%s: %s", name, err.message);
        own = mf_independent_jacobian_error(m, f->grid, x, &raw);
        assert_true(own >= 0.0);
        if (r.worst_error > JACOBIAN_TOLERANCE || own > JACOBIAN_TOLERANCE)
            fail_msg("%s set %zu: library check %.3g (param %s, channel %zu, sample %zu, "
                     "analytic %.17g, numeric %.17g), independent check %.3g",
                     name, set, r.worst_error, brdffit_model_param(m, r.param)->name, r.channel,
                     r.sample, r.analytic, r.numeric, own);
        worst_lib = fmax(worst_lib, r.worst_error);
        worst_own = fmax(worst_own, own);
        worst_raw = fmax(worst_raw, raw);
    }
    print_message("%-26s worst relative error over %zu sets: check_jacobian %.2e, "
                  "independent %.2e, plain (resolvable entries) %.2e\n",
                  name, n_sets, worst_lib, worst_own, worst_raw);
    brdffit_model_destroy(m);
}

#define JACOBIAN_TEST(fn, name, seed)             \
    static void fn(void **state)                  \
    {                                             \
        check_model_jacobian(*state, name, seed); \
    }

JACOBIAN_TEST(test_jacobian_lambert, "lambert", 1)
JACOBIAN_TEST(test_jacobian_phong, "phong", 2)
JACOBIAN_TEST(test_jacobian_blinn_phong, "blinn-phong", 3)
JACOBIAN_TEST(test_jacobian_as, "ashikhmin-shirley", 4)
JACOBIAN_TEST(test_jacobian_as_fresnel, "ashikhmin-shirley-fresnel", 5)
JACOBIAN_TEST(test_jacobian_as2, "ashikhmin-shirley-2", 6)
JACOBIAN_TEST(test_jacobian_ct, "cook-torrance", 7)
JACOBIAN_TEST(test_jacobian_ct2, "cook-torrance-2", 8)
JACOBIAN_TEST(test_jacobian_ggx, "ggx", 9)
JACOBIAN_TEST(test_jacobian_ggx2, "ggx-2", 10)
JACOBIAN_TEST(test_jacobian_ward, "ward", 11)
JACOBIAN_TEST(test_jacobian_ward_duer, "ward-duer", 12)
JACOBIAN_TEST(test_jacobian_lafortune, "lafortune", 13)
JACOBIAN_TEST(test_jacobian_gltf, "gltf", 14)
JACOBIAN_TEST(test_jacobian_gltf_clearcoat, "gltf-clearcoat", 15)
JACOBIAN_TEST(test_jacobian_openpbr, "openpbr", 16)
JACOBIAN_TEST(test_jacobian_openpbr_coat, "openpbr-coat", 17)

/* Every built-in model has a Jacobian test above. */
static void test_jacobian_tests_cover_all_models(void **state)
{
    (void)state;
    assert_int_equal(brdffit_model_builtin_count(), 17);
}

/* At the bounds of the shape parameters the check's stencil is one-sided. */
static void test_jacobian_at_bounds(void **state)
{
    const fixture *f = *state;
    brdffit_model *m = create("ashikhmin-shirley-fresnel");
    double x[2 + 2 * NC];
    brdffit_jacobian_report r;
    size_t c;
    x[0] = 20.0;
    x[1] = 0.0; /* Rs at its lower bound */
    for (c = 0; c < NC; c++) {
        x[2 + c] = 0.3;
        x[2 + NC + c] = 0.0; /* colours at their lower bound */
    }
    r.struct_size = sizeof r;
    assert_int_equal(brdffit_model_check_jacobian(m, f->grid, x, &r, NULL), BRDFFIT_OK);
    assert_true(r.worst_error < JACOBIAN_TOLERANCE);
    x[1] = 1.0; /* upper bound */
    x[2 + NC] = 0.5;
    assert_int_equal(brdffit_model_check_jacobian(m, f->grid, x, &r, NULL), BRDFFIT_OK);
    assert_true(r.worst_error < JACOBIAN_TOLERANCE);
    brdffit_model_destroy(m);
}

/* ---- the linear-parameter contract ------------------------------------------ */

/* value = sum over LINEAR parameters of parameter * derivative, for every
 * built-in model with LINEAR parameters (all but the glTF and OpenPBR ones). */
static void test_linear_contract(void **state)
{
    const fixture *f = *state;
    const size_t n = brdffit_grid_sample_count(f->grid);
    double *v = malloc(NC * n * sizeof(double)), *jac = malloc(6 * NC * n * sizeof(double));
    uint64_t rng = 99;
    size_t i, k, c, s;
    assert_non_null(v);
    assert_non_null(jac);
    for (i = 0; i < brdffit_model_builtin_count(); i++) {
        brdffit_model *m = create(brdffit_model_builtin_name(i));
        double x[32];
        if (strncmp(brdffit_model_name(m), "gltf", 4) == 0 ||
            strncmp(brdffit_model_name(m), "openpbr", 7) == 0) { /* test_gltf_affine */
            brdffit_model_destroy(m);
            continue;
        }
        assert_true(brdffit_model_param_count(m) <= 6);
        mf_random_params(m, NC, &rng, x);
        assert_int_equal(brdffit_model_eval_grid(m, f->grid, 0, n, x, v, jac, NULL), BRDFFIT_OK);
        for (c = 0; c < NC; c++) {
            for (s = 0; s < n; s++) {
                double sum = 0.0;
                for (k = 0; k < brdffit_model_param_count(m); k++) {
                    if (!(brdffit_model_param(m, k)->flags & BRDFFIT_PARAM_LINEAR)) continue;
                    sum += x[brdffit_model_vector_index(m, k, c, NC)] * jac[(k * NC + c) * n + s];
                }
                assert_close(sum, v[c * n + s], 1e-12);
            }
        }
        brdffit_model_destroy(m);
    }
    free(v);
    free(jac);
}

/* The glTF models are affine, not linear, in baseColor: value - b dvalue/db
 * is the same for b = 0 and any other b (the colourless specular part),
 * and it is not 0, which is why baseColor is not flagged LINEAR. */
static void check_affine(const fixture *f, const char *name, const double *shape, size_t n_shape)
{
    const size_t n = brdffit_grid_sample_count(f->grid);
    const double colour[NC] = {0.8, 0.5, 0.1};
    double *v = malloc(2 * NC * n * sizeof(double)), *jac = malloc(7 * NC * n * sizeof(double));
    double x[8], rest_max = 0.0;
    brdffit_model *m = create(name);
    size_t c, s, k;
    assert_non_null(v);
    assert_non_null(jac);
    assert_int_equal(brdffit_model_param_find(m, "baseColor", &k), BRDFFIT_OK);
    assert_int_equal(k, n_shape);
    memcpy(x, shape, n_shape * sizeof(double));
    memcpy(x + n_shape, colour, sizeof colour);
    assert_int_equal(brdffit_model_eval_grid(m, f->grid, 0, n, x, v, jac, NULL), BRDFFIT_OK);
    memset(x + n_shape, 0, sizeof colour);
    assert_int_equal(brdffit_model_eval_grid(m, f->grid, 0, n, x, v + NC * n, NULL, NULL),
                     BRDFFIT_OK);
    for (c = 0; c < NC; c++) {
        for (s = 0; s < n; s++) {
            const double rest = v[c * n + s] - colour[c] * jac[(n_shape * NC + c) * n + s];
            assert_close(rest, v[NC * n + c * n + s], 1e-12);
            rest_max = fmax(rest_max, rest);
        }
    }
    assert_true(rest_max > 1e-3);
    brdffit_model_destroy(m);
    free(v);
    free(jac);
}

static void test_gltf_affine(void **state)
{
    check_affine(*state, "gltf", (const double[]){0.3, 0.4}, 2);
    check_affine(*state, "gltf-clearcoat", (const double[]){0.3, 0.4, 0.7, 0.05}, 4);
}

/* ---- extremes --------------------------------------------------------------- */

/* Value j of `count` test points across [lower, upper]: both bounds and
 * points in between (geometric for log-scale parameters). */
static double sweep_value(const brdffit_param_info *p, size_t j, size_t count)
{
    const double t = (double)j / (double)(count - 1);
    if (p->flags & BRDFFIT_PARAM_LOG_SCALE)
        return j + 1 == count ? p->upper : exp(log(p->lower) + t * (log(p->upper) - log(p->lower)));
    return j + 1 == count ? p->upper : p->lower + t * (p->upper - p->lower);
}

static int all_finite(const double *x, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        if (!isfinite(x[i])) return 0;
    return 1;
}

/* Every model, every combination of shape parameters at 5 points of their
 * range (both ends included; BRDFFIT_TEST_QUICK: 3, both ends and the
 * middle), colours 0, 1 and 1000 in the three channels, every sample of
 * the 0..90 degree grid: values and Jacobian finite. */
static void test_extremes_finite(void **state)
{
    const fixture *f = *state;
    const size_t n = brdffit_grid_sample_count(f->grid), points = test_quick() ? 3 : 5;
    const double colours[NC] = {0.0, 1.0, 1000.0};
    double *v = malloc(NC * n * sizeof(double)), *jac = malloc(6 * NC * n * sizeof(double));
    size_t i, combos = 0;
    assert_non_null(v);
    assert_non_null(jac);
    for (i = 0; i < brdffit_model_builtin_count(); i++) {
        brdffit_model *m = create(brdffit_model_builtin_name(i));
        const size_t np = brdffit_model_param_count(m);
        size_t n_shape = 0, total = 1, combo, k, c;
        for (k = 0; k < np; k++)
            if (!(brdffit_model_param(m, k)->flags & BRDFFIT_PARAM_PER_CHANNEL)) n_shape++;
        for (k = 0; k < n_shape; k++) total *= points;
        for (combo = 0; combo < total; combo++) {
            double x[32];
            size_t digits = combo;
            brdffit_error err;
            for (k = 0; k < np; k++) {
                const brdffit_param_info *p = brdffit_model_param(m, k);
                if (p->flags & BRDFFIT_PARAM_PER_CHANNEL) {
                    for (c = 0; c < NC; c++)
                        x[brdffit_model_vector_index(m, k, c, NC)] = colours[c];
                } else {
                    x[brdffit_model_vector_index(m, k, 0, NC)] =
                        sweep_value(p, digits % points, points);
                    digits /= points;
                }
            }
            if (brdffit_model_eval_grid(m, f->grid, 0, n, x, v, jac, &err) != BRDFFIT_OK)
                fail_msg("%s combination %zu: %s", brdffit_model_name(m), combo, err.message);
            assert_true(all_finite(v, NC * n));
            assert_true(all_finite(jac, np * NC * n));
            combos++;
        }
        brdffit_model_destroy(m);
    }
    print_message("extremes: %zu parameter combinations x %zu samples finite\n", combos, n);
    free(v);
    free(jac);
}

/* ---- the dot-product floor inside the default cap ---------------------------- */

/* Count samples of the default grid where the 1e-4 floor of n.l, n.v, n.h
 * or h.v is active, from the grid's own geometry and, independently, from
 * the angles; inside the 75 degree cap there are none. */
static void test_clamp_inside_default_cap(void **state)
{
    const fixture *f = *state;
    const brdffit_grid *g = f->grid;
    const size_t n = brdffit_grid_sample_count(g);
    size_t s, inside = 0, all = 0, inside_own = 0, active = 0, below_90 = 0;
    for (s = 0; s < n; s++) {
        double ti, pi, to, po, l[3], v[3], h[3], len, raw[4];
        int clamped_lib, clamped_own = 0, in_cap, q;
        assert_int_equal(brdffit_grid_sample_angles(g, s, &ti, &pi, &to, &po), BRDFFIT_OK);
        in_cap = ti <= BRDFFIT_DEFAULT_CAP && to <= BRDFFIT_DEFAULT_CAP;
        clamped_lib = g->geo.nl[s] <= 1e-4 || g->geo.nv[s] <= 1e-4 || g->geo.nh[s] <= 1e-4 ||
                      g->geo.hv[s] <= 1e-4;
        l[0] = sin(ti) * cos(pi);
        l[1] = sin(ti) * sin(pi);
        l[2] = cos(ti);
        v[0] = sin(to) * cos(po);
        v[1] = sin(to) * sin(po);
        v[2] = cos(to);
        for (q = 0; q < 3; q++) h[q] = l[q] + v[q];
        len = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
        raw[0] = l[2];
        raw[1] = v[2];
        raw[2] = len > 1e-12 ? h[2] / len : 1.0;
        raw[3] = len > 1e-12 ? (h[0] * v[0] + h[1] * v[1] + h[2] * v[2]) / len : 1.0;
        for (q = 0; q < 4; q++) clamped_own |= raw[q] < 1e-4;
        all += clamped_lib;
        below_90 += clamped_lib && ti < DEG(90.0) - 1e-9 && to < DEG(90.0) - 1e-9;
        inside += clamped_lib && in_cap;
        inside_own += clamped_own && in_cap;
        active += in_cap;
    }
    print_message("dot-product floor active: %zu of %zu samples (0..90 deg), %zu of %zu inside "
                  "the 75 deg cap\n",
                  all, n, inside, active);
    assert_int_equal(inside, 0);
    assert_int_equal(inside_own, 0);
    assert_int_equal(below_90, 0); /* only samples at 90 degrees reach it */
    assert_true(all > 0); /* the grid does reach grazing angles */
    assert_int_equal(active, brdffit_grid_active_count(g, BRDFFIT_DEFAULT_CAP));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_jacobian_tests_cover_all_models),
        cmocka_unit_test(test_jacobian_lambert),
        cmocka_unit_test(test_jacobian_phong),
        cmocka_unit_test(test_jacobian_blinn_phong),
        cmocka_unit_test(test_jacobian_as),
        cmocka_unit_test(test_jacobian_as_fresnel),
        cmocka_unit_test(test_jacobian_as2),
        cmocka_unit_test(test_jacobian_ct),
        cmocka_unit_test(test_jacobian_ct2),
        cmocka_unit_test(test_jacobian_ggx),
        cmocka_unit_test(test_jacobian_ggx2),
        cmocka_unit_test(test_jacobian_ward),
        cmocka_unit_test(test_jacobian_ward_duer),
        cmocka_unit_test(test_jacobian_lafortune),
        cmocka_unit_test(test_jacobian_gltf),
        cmocka_unit_test(test_jacobian_gltf_clearcoat),
        cmocka_unit_test(test_jacobian_openpbr),
        cmocka_unit_test(test_jacobian_openpbr_coat),
        cmocka_unit_test(test_jacobian_at_bounds),
        cmocka_unit_test(test_linear_contract),
        cmocka_unit_test(test_gltf_affine),
        cmocka_unit_test(test_extremes_finite),
        cmocka_unit_test(test_clamp_inside_default_cap),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
