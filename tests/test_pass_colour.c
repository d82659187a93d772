/* The colour route of auto's profile (lib/fit/pass_colour.c): after one
 * SHAPE pass at a shape, its COLOUR_COST and COLOUR_NORMAL agree with the
 * problem's own COST and the colour block of its NORMAL (the basis route
 * for the models in basis form, the generic route for the affine glTF and
 * OpenPBR models and on a grid with missing values) to 1e-11 of the largest
 * entry (1e-6 against a pass that the fused loop takes, whose inputs are
 * in single precision: test_fused.c), under every objective, on three channels, the channel mean, one
 * channel and with a clear coat. COLOUR_VARPRO is VARPRO under the squares
 * objective and, under the others, the sums of the objective linearised at
 * the measured values: NORMAL's colour block where the model reproduces
 * the data exactly, and under the relative objective (linear in the
 * colours) on any data. A cache filled at another shape, or colours other
 * than NORMAL's, fail the comparison. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit/pass.h"
#include "fit/pass_fused.h"
#include "fit/pass_route.h"
#include "fit_fixtures.h"
#include "grid_fixtures.h"
#include "pass_fixtures.h"
#include "test_support.h"

#define DEG2RAD (3.14159265358979323846 / 180.0)
#define MAX_ACC 1024
#define TOL 1e-11
/* against a pass the fused loop takes: its single-precision inputs'
 * bound (test_fused.c) */
#define TOL_FUSED 1e-6

static const char *const objective_names[] = {"squares", "log", "cube-root", "relative"};
static const brdffit_objective objectives[] = {BRDFFIT_OBJECTIVE_SQUARES, BRDFFIT_OBJECTIVE_LOG,
                                               BRDFFIT_OBJECTIVE_CUBE_ROOT,
                                               BRDFFIT_OBJECTIVE_RELATIVE};
#define NOBJ (sizeof objectives / sizeof objectives[0])

typedef enum data_kind { DATA_PLAIN, DATA_MISSING, DATA_EXACT } data_kind;

typedef struct setup {
    const char *model_name;
    brdffit_grid *grid;
    brdffit_model *model;
    bf_weight_plan plan;
    bf_problem pb;
    size_t vindex[64];
    double params[32];
    double *work, *terms, *shape;
} setup;

/* The default axes with fx_value() measurements on 3 channels, every 5th
 * value of channel 1 and every 7th of channel 2 missing. */
static brdffit_grid *missing_grid(void)
{
    const brdffit_axes *axes = brdffit_axes_default();
    const size_t n = axes->n_theta_i * axes->n_theta_o * axes->n_phi_o;
    double *v = fx_values(axes, 3);
    unsigned char *missing = calloc(3 * n, 1);
    brdffit_grid *g = NULL;
    size_t s;
    assert_non_null(v);
    assert_non_null(missing);
    for (s = 0; s < n; s++) missing[3 * s + 1] = s % 5 == 0, missing[3 * s + 2] = s % 7 == 0;
    assert_int_equal(brdffit_grid_create_regular(&g, axes, 3, v, missing, NULL, NULL), BRDFFIT_OK);
    free(v);
    free(missing);
    return g;
}

static void setup_init(setup *s, const char *model, size_t nc, bf_source source, double coat,
                       brdffit_objective objective, data_kind data)
{
    bf_problem *pb = &s->pb;
    memset(s, 0, sizeof *s);
    s->model_name = model;
    assert_int_equal(brdffit_model_create(&s->model, model, NULL, NULL), BRDFFIT_OK);
    fx_pass_problem(pb, NULL, s->model, &s->plan, nc, source, coat);
    assert_true(pb->ly.n_vec <= 32 && brdffit_model_param_count(s->model) * nc <= 64);
    bf_layout_entries(&pb->ly, s->model, s->vindex, NULL);
    pb->vindex = s->vindex;
    fx_pass_start(pb, s->params);
    if (data == DATA_EXACT) /* the model at the start values, exactly */
        s->grid = fx_grid_from_model(s->model, s->params, nc, NULL, 0.0, 1);
    else
        s->grid = data == DATA_MISSING ? missing_grid() : fx_pass_grid(3);
    assert_non_null(s->grid);
    pb->grid = s->grid;
    assert_int_equal(bf_weight_plan_init(&s->plan, s->grid, 80.0 * DEG2RAD, BRDFFIT_WEIGHT_DEFAULT,
                                         &s->grid->alloc, NULL),
                     BRDFFIT_OK);
    pb->objective = objective;
    pb->delta = 1e-3;
    pb->colour = 1;
    bf_pass_prepare(pb);
    assert_true(bf_pass_shape_size(pb) > 0);
    s->work = calloc(bf_pass_work_size(pb), sizeof(double));
    s->shape = calloc(bf_pass_shape_size(pb), sizeof(double));
    assert_non_null(s->work);
    assert_non_null(s->shape);
    pb->work = s->work;
    pb->shape = s->shape;
    if (bf_pass_terms_size(pb) > 0) {
        s->terms = calloc(bf_pass_terms_size(pb), sizeof(double));
        assert_non_null(s->terms);
        bf_pass_terms(pb, s->terms);
        pb->terms = s->terms;
    }
}

static void setup_free(setup *s)
{
    free(s->work);
    free(s->terms);
    free(s->shape);
    bf_weight_plan_free(&s->plan, &s->grid->alloc);
    brdffit_model_destroy(s->model);
    brdffit_grid_destroy(s->grid);
}

static void pass(setup *s, bf_pass_kind kind, const double *params, double *acc)
{
    brdffit_error err;
    memset(acc, 0, MAX_ACC * sizeof *acc);
    assert_true(bf_pass_acc_size(&s->pb, kind) <= MAX_ACC);
    assert_int_equal(bf_pass(&s->pb, kind, params, acc, &err), BRDFFIT_OK);
}

/* Vector entry of colour q of channel m. */
static size_t colour_entry(const setup *s, size_t q, size_t m)
{
    return s->vindex[s->pb.ly.linear[q] * s->pb.nc + m];
}

/* The largest difference of COLOUR_NORMAL's blocks from NORMAL's colour
 * entries (total cost, J^T r, J^T J), relative to the largest entry of
 * NORMAL's; `top` receives that entry. */
static double normal_mismatch(setup *s, const double *normal, const double *colour, double *top)
{
    const size_t n = s->pb.ly.n_vec, K = s->pb.ly.n_linear, stride = 1 + K + K * K;
    size_t m, q, r;
    double worst = 0.0, cost = 0.0;
    *top = 0.0;
    for (m = 0; m < s->pb.nc; m++)
        for (q = 0; q < K; q++) {
            size_t e = colour_entry(s, q, m);
            *top = fmax(*top, fabs(normal[1 + e]));
            for (r = 0; r < K; r++)
                *top = fmax(*top, fabs(normal[1 + n + e * n + colour_entry(s, r, m)]));
        }
    for (m = 0; m < s->pb.nc; m++) {
        const double *b = colour + m * stride;
        cost += b[0];
        for (q = 0; q < K; q++) {
            size_t e = colour_entry(s, q, m);
            worst = fmax(worst, fabs(b[1 + q] - normal[1 + e]));
            for (r = 0; r < K; r++)
                worst = fmax(worst, fabs(b[1 + K + q * K + r] -
                                         normal[1 + n + e * n + colour_entry(s, r, m)]));
        }
    }
    assert_true(*top > 0.0);
    worst /= *top;
    return fmax(worst, fabs(cost - normal[0]) / normal[0]);
}

/* The tolerance against the problem's own pass of this kind. */
static double tol_of(const setup *s, bf_pass_kind kind)
{
    return bf_fused_serves(&s->pb, kind) ? TOL_FUSED : TOL;
}

static void report(const setup *s, const char *what, double mismatch)
{
    printf("%s, %s, nc %zu, source %d: %s off by %.3g\n", s->model_name,
           objective_names[s->pb.objective], s->pb.nc, (int)s->pb.source, what, mismatch);
}

/* COLOUR_COST and COLOUR_NORMAL against COST and NORMAL at the cache's
 * shape; then at other colours; then a cache of another shape must not
 * pass. */
static void check_normal(setup *s)
{
    static double normal[MAX_ACC], colour[MAX_ACC], other[32];
    const size_t n = s->pb.ly.n_vec;
    double top, mismatch;
    size_t m, q;
    pass(s, BF_PASS_SHAPE, s->params, colour);
    pass(s, BF_PASS_NORMAL, s->params, normal);
    pass(s, BF_PASS_COLOUR_NORMAL, s->params, colour);
    if (!((mismatch = normal_mismatch(s, normal, colour, &top)) <= tol_of(s, BF_PASS_NORMAL))) {
        report(s, "COLOUR_NORMAL", mismatch);
        fail();
    }
    pass(s, BF_PASS_COST, s->params, normal);
    pass(s, BF_PASS_COLOUR_COST, s->params, colour);
    if (!(fabs(colour[0] - normal[0]) <= tol_of(s, BF_PASS_COST) * normal[0])) {
        report(s, "COLOUR_COST", fabs(colour[0] - normal[0]) / normal[0]);
        fail();
    }
    /* other colours, the same cache */
    memcpy(other, s->params, n * sizeof *other);
    for (m = 0; m < s->pb.nc; m++)
        for (q = 0; q < s->pb.ly.n_linear; q++)
            other[colour_entry(s, q, m)] *= 1.7 - 0.3 * (double)q;
    pass(s, BF_PASS_NORMAL, other, normal);
    pass(s, BF_PASS_COLOUR_NORMAL, other, colour);
    if (!((mismatch = normal_mismatch(s, normal, colour, &top)) <= tol_of(s, BF_PASS_NORMAL))) {
        report(s, "COLOUR_NORMAL at other colours", mismatch);
        fail();
    }
    /* NORMAL at params against the colour pass at other colours, and the
     * colour pass against a cache of another shape: both must differ */
    pass(s, BF_PASS_NORMAL, s->params, normal);
    assert_true(normal_mismatch(s, normal, colour, &top) > 1e-3);
    memcpy(other, s->params, n * sizeof *other);
    other[s->vindex[0]] *= 1.3; /* the first parameter, a shape parameter */
    pass(s, BF_PASS_SHAPE, other, colour);
    pass(s, BF_PASS_COLOUR_NORMAL, s->params, colour);
    assert_true(normal_mismatch(s, normal, colour, &top) > 1e-6);
}

/* COLOUR_VARPRO under the squares objective: VARPRO itself. */
static void check_varpro_squares(setup *s)
{
    static double varpro[MAX_ACC], colour[MAX_ACC];
    const size_t na = bf_pass_acc_size(&s->pb, BF_PASS_VARPRO);
    double top = 0.0, worst = 0.0;
    size_t i;
    assert_int_equal(bf_pass_acc_size(&s->pb, BF_PASS_COLOUR_VARPRO), na);
    pass(s, BF_PASS_SHAPE, s->params, colour);
    pass(s, BF_PASS_VARPRO, s->params, varpro);
    pass(s, BF_PASS_COLOUR_VARPRO, s->params, colour);
    for (i = 0; i < na; i++) top = fmax(top, fabs(varpro[i]));
    for (i = 0; i < na; i++) worst = fmax(worst, fabs(colour[i] - varpro[i]) / top);
    if (!(worst <= tol_of(s, BF_PASS_VARPRO))) {
        report(s, "COLOUR_VARPRO", worst);
        fail();
    }
}

/* COLOUR_VARPRO [r0, b, G] per channel against NORMAL's colour block at
 * params: G = J^T J, b = G c - J^T r (the rows f (M - R) with f the
 * objective's row factor, the same at M and at R where the model fits the
 * data exactly or the objective is linear in M); `zero_cost` also checks
 * r0 against the cost at colours 0 (the relative objective). */
static void check_varpro_linearised(setup *s, int zero_cost)
{
    static double normal[MAX_ACC], colour[MAX_ACC], zero[32], cost0[MAX_ACC];
    const size_t n = s->pb.ly.n_vec, K = s->pb.ly.n_linear, stride = 1 + K + K * K;
    double top = 0.0, worst = 0.0, r0 = 0.0;
    size_t m, q, r;
    pass(s, BF_PASS_SHAPE, s->params, colour);
    pass(s, BF_PASS_NORMAL, s->params, normal);
    pass(s, BF_PASS_COLOUR_VARPRO, s->params, colour);
    for (m = 0; m < s->pb.nc; m++) {
        const double *acc = colour + m * stride;
        double gc[BF_KERNEL_MAX_LINEAR];
        r0 += acc[0];
        for (q = 0; q < K; q++) {
            size_t e = colour_entry(s, q, m);
            gc[q] = -normal[1 + e];
            for (r = 0; r < K; r++) {
                size_t f = colour_entry(s, r, m);
                gc[q] += normal[1 + n + e * n + f] * s->params[f];
                top = fmax(top, fabs(normal[1 + n + e * n + f]));
                worst = fmax(worst, fabs(acc[1 + K + q * K + r] - normal[1 + n + e * n + f]));
            }
        }
        for (q = 0; q < K; q++) {
            top = fmax(top, fabs(gc[q]));
            worst = fmax(worst, fabs(acc[1 + q] - gc[q]));
        }
    }
    worst /= top;
    if (!(worst <= tol_of(s, BF_PASS_NORMAL))) {
        report(s, "COLOUR_VARPRO (linearised)", worst);
        fail();
    }
    if (!zero_cost) return;
    memcpy(zero, s->params, n * sizeof *zero);
    for (m = 0; m < s->pb.nc; m++)
        for (q = 0; q < K; q++) zero[colour_entry(s, q, m)] = 0.0;
    pass(s, BF_PASS_COST, zero, cost0);
    if (!(fabs(r0 - cost0[0]) <= tol_of(s, BF_PASS_COST) * cost0[0])) {
        report(s, "COLOUR_VARPRO's r0", fabs(r0 - cost0[0]) / cost0[0]);
        fail();
    }
}

/* Every check of one model, channel source and coat on the plain data,
 * under every objective. */
static void check_case(const char *model, size_t nc, bf_source source, double coat)
{
    size_t o;
    for (o = 0; o < NOBJ; o++) {
        setup s;
        setup_init(&s, model, nc, source, coat, objectives[o], DATA_PLAIN);
        if (source == BF_SOURCE_ONE_CHANNEL) s.pb.source_channel = 2;
        check_normal(&s);
        if (objectives[o] == BRDFFIT_OBJECTIVE_SQUARES) check_varpro_squares(&s);
        if (objectives[o] == BRDFFIT_OBJECTIVE_RELATIVE) check_varpro_linearised(&s, 1);
        setup_free(&s);
    }
}

/* The linearised COLOUR_VARPRO on data the model reproduces, and the
 * colour passes on a grid with missing values (the generic route's). */
static void check_exact_and_missing(const char *model)
{
    size_t o;
    for (o = 0; o < NOBJ; o++) {
        setup s;
        setup_init(&s, model, 3, BF_SOURCE_CHANNELS, 0.0, objectives[o], DATA_EXACT);
        check_varpro_linearised(&s, 0);
        setup_free(&s);
        setup_init(&s, model, 3, BF_SOURCE_CHANNELS, 0.0, objectives[o], DATA_MISSING);
        assert_true(s.pb.route == &bf_route_generic);
        check_normal(&s);
        if (objectives[o] == BRDFFIT_OBJECTIVE_SQUARES) check_varpro_squares(&s);
        if (objectives[o] == BRDFFIT_OBJECTIVE_RELATIVE) check_varpro_linearised(&s, 1);
        setup_free(&s);
    }
}

static void test_basis_form(void **state)
{
    (void)state;
    check_case("ashikhmin-shirley", 3, BF_SOURCE_CHANNELS, 0.0);
    check_case("ashikhmin-shirley-2", 3, BF_SOURCE_CHANNELS, 0.0);
    check_case("ggx", 3, BF_SOURCE_CHANNELS, 0.04);
    check_case("lafortune", 1, BF_SOURCE_MEAN, 0.0);
    check_case("cook-torrance-2", 1, BF_SOURCE_ONE_CHANNEL, 0.0);
}

static void test_affine(void **state)
{
    (void)state;
    check_case("gltf", 3, BF_SOURCE_CHANNELS, 0.0);
    check_case("gltf-clearcoat", 3, BF_SOURCE_CHANNELS, 0.04);
    check_case("openpbr", 1, BF_SOURCE_MEAN, 0.0);
    check_case("openpbr-coat", 3, BF_SOURCE_CHANNELS, 0.0);
}

static void test_exact_data_and_missing_values(void **state)
{
    (void)state;
    check_exact_and_missing("ashikhmin-shirley");
    check_exact_and_missing("gltf-clearcoat");
}

/* A user model, linear in its one colour: value = a. */
static brdffit_status user_eval(const brdffit_batch *batch, const double *params, size_t nc,
                                double *values, double *jacobian, void *user)
{
    size_t c, s;
    (void)user;
    for (c = 0; c < nc; c++)
        for (s = 0; s < batch->n; s++) {
            values[c * batch->n + s] = params[c];
            if (jacobian != NULL) jacobian[c * batch->n + s] = 1.0;
        }
    return BRDFFIT_OK;
}

/* A user model has no colour form, so no cache. */
static void test_no_cache(void **state)
{
    static const brdffit_param_info params[] = {
        {"a", BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR, 0.0, 1.0, 0.5}};
    brdffit_model_def def = BRDFFIT_MODEL_DEF_INIT;
    brdffit_model *model = NULL;
    brdffit_grid *grid = fx_pass_grid(3);
    bf_weight_plan plan;
    bf_problem pb;
    (void)state;
    def.name = "user";
    def.n_params = 1;
    def.params = params;
    def.eval = user_eval;
    assert_int_equal(bf_weight_plan_init(&plan, grid, 80.0 * DEG2RAD, BRDFFIT_WEIGHT_DEFAULT,
                                         &grid->alloc, NULL),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_model_create_custom(&model, &def, NULL, NULL), BRDFFIT_OK);
    fx_pass_problem(&pb, grid, model, &plan, 3, BF_SOURCE_CHANNELS, 0.0);
    bf_pass_prepare(&pb);
    assert_int_equal(bf_pass_shape_size(&pb), 0);
    brdffit_model_destroy(model);
    bf_weight_plan_free(&plan, &grid->alloc);
    brdffit_grid_destroy(grid);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_basis_form),
        cmocka_unit_test(test_affine),
        cmocka_unit_test(test_exact_data_and_missing_values),
        cmocka_unit_test(test_no_cache),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
