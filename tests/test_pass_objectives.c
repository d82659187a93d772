/* The basis route under the objectives other than the squares
 * (lib/fit/pass_basis.c): its COST and NORMAL passes, which transform each
 * channel's rows and keep one Gram matrix per channel, agree with the
 * generic route (the model's own Jacobian, row by row) to 1e-11 of the
 * largest entry, for models of the lobe form, the microfacet form, the
 * Fresnel shader form and Lafortune's basis form, on three channels, on the
 * channel mean, and with a clear coat; and the objective is really applied
 * (its cost is not the squares'). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit/pass.h"
#include "fit/pass_route.h"
#include "pass_fixtures.h"
#include "test_support.h"

#define DEG2RAD (3.14159265358979323846 / 180.0)
#define MAX_ACC 512

typedef struct setup {
    brdffit_grid *grid;
    brdffit_model *model;
    bf_weight_plan plan;
    bf_problem pb;
    size_t vindex[64];
    double params[32];
    double *work, *terms;
} setup;

static void setup_init(setup *s, const char *model, size_t nc, bf_source source, double coat,
                       brdffit_objective objective)
{
    bf_problem *pb = &s->pb;
    size_t size;
    memset(s, 0, sizeof *s);
    s->grid = fx_pass_grid(3);
    assert_int_equal(brdffit_model_create(&s->model, model, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(bf_weight_plan_init(&s->plan, s->grid, 80.0 * DEG2RAD,
                                         BRDFFIT_WEIGHT_DEFAULT, &s->grid->alloc, NULL),
                     BRDFFIT_OK);
    fx_pass_problem(pb, s->grid, s->model, &s->plan, nc, source, coat);
    pb->objective = objective;
    pb->delta = 1e-3;
    assert_true(pb->ly.n_vec <= 32 && brdffit_model_param_count(s->model) * nc <= 64);
    bf_layout_entries(&pb->ly, s->model, s->vindex, NULL);
    pb->vindex = s->vindex;
    bf_pass_prepare(pb);
    assert_true(pb->route == &bf_route_basis);
    fx_pass_start(pb, s->params);
    /* room for either route */
    size = bf_pass_work_size(pb);
    pb->route = &bf_route_generic;
    if (bf_pass_work_size(pb) > size) size = bf_pass_work_size(pb);
    pb->route = &bf_route_basis;
    s->work = calloc(size, sizeof(double));
    assert_non_null(s->work);
    pb->work = s->work;
    s->terms = calloc(bf_pass_terms_size(pb), sizeof(double));
    assert_non_null(s->terms);
    bf_pass_terms(pb, s->terms);
    pb->terms = s->terms;
}

static void setup_free(setup *s)
{
    free(s->work);
    free(s->terms);
    bf_weight_plan_free(&s->plan, &s->grid->alloc);
    brdffit_model_destroy(s->model);
    brdffit_grid_destroy(s->grid);
}

static void run(setup *s, const bf_route *route, bf_pass_kind kind, double *acc)
{
    brdffit_error err;
    s->pb.route = route;
    memset(acc, 0, MAX_ACC * sizeof *acc);
    assert_true(bf_pass_acc_size(&s->pb, kind) <= MAX_ACC);
    assert_int_equal(bf_pass(&s->pb, kind, s->params, acc, &err), BRDFFIT_OK);
    s->pb.route = &bf_route_basis;
}

static const char *const objective_names[] = {"squares", "log", "cube-root", "relative"};

static void check_case(const char *model, size_t nc, bf_source source, double coat)
{
    static const bf_pass_kind kinds[] = {BF_PASS_COST, BF_PASS_NORMAL};
    static const brdffit_objective objectives[] = {
        BRDFFIT_OBJECTIVE_LOG, BRDFFIT_OBJECTIVE_CUBE_ROOT, BRDFFIT_OBJECTIVE_RELATIVE};
    double basis[MAX_ACC], generic[MAX_ACC], squares[MAX_ACC];
    size_t o, k, i, n;
    for (o = 0; o < sizeof objectives / sizeof objectives[0]; o++) {
        setup s;
        setup_init(&s, model, nc, source, coat, objectives[o]);
        for (k = 0; k < sizeof kinds / sizeof kinds[0]; k++) {
            double top = 0.0;
            n = bf_pass_acc_size(&s.pb, kinds[k]);
            run(&s, &bf_route_basis, kinds[k], basis);
            run(&s, &bf_route_generic, kinds[k], generic);
            for (i = 0; i < n; i++) top = fmax(top, fabs(generic[i]));
            assert_true(top > 0.0);
            for (i = 0; i < n; i++)
                if (!(fabs(basis[i] - generic[i]) <= 1e-11 * top)) {
                    printf("%s, %s, kind %d, entry %zu: basis %.17g generic %.17g\n", model,
                           objective_names[objectives[o]], (int)kinds[k], i, basis[i],
                           generic[i]);
                    fail();
                }
        }
        /* the objective is applied: its cost is not the squares' */
        s.pb.objective = BRDFFIT_OBJECTIVE_SQUARES;
        s.pb.terms = NULL;
        run(&s, &bf_route_basis, BF_PASS_COST, squares);
        s.pb.objective = objectives[o];
        s.pb.terms = s.terms;
        run(&s, &bf_route_basis, BF_PASS_COST, basis);
        assert_true(fabs(basis[0] - squares[0]) > 1e-6 * squares[0]);
        setup_free(&s);
    }
}

static void test_lobe_form(void **state)
{
    (void)state;
    check_case("ashikhmin-shirley", 3, BF_SOURCE_CHANNELS, 0.0);
    check_case("ashikhmin-shirley-2", 3, BF_SOURCE_CHANNELS, 0.0);
    check_case("blinn-phong", 1, BF_SOURCE_MEAN, 0.0);
}

static void test_microfacet_form(void **state)
{
    (void)state;
    check_case("ggx", 3, BF_SOURCE_CHANNELS, 0.0);
    check_case("cook-torrance-2", 3, BF_SOURCE_CHANNELS, 0.0);
    check_case("ashikhmin-shirley-fresnel", 3, BF_SOURCE_CHANNELS, 0.0);
}

static void test_lafortune_and_clear_coat(void **state)
{
    (void)state;
    check_case("lafortune", 3, BF_SOURCE_CHANNELS, 0.0);
    check_case("ashikhmin-shirley", 3, BF_SOURCE_CHANNELS, 0.04);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lobe_form),
        cmocka_unit_test(test_microfacet_form),
        cmocka_unit_test(test_lafortune_and_clear_coat),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
