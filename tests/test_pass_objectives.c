/* The basis route under the objectives other than the squares
 * (lib/fit/pass_basis.c): its COST and NORMAL passes, which transform each
 * channel's rows and keep one Gram matrix per channel, agree with the
 * generic route (the model's own Jacobian, row by row) to 1e-11 of the
 * largest entry, for models of the lobe form, the microfacet form, the
 * Fresnel shader form and Lafortune's basis form, on three channels, on the
 * channel mean, and with a clear coat; and the objective is really applied
 * (its cost is not the squares'). And the objective's row functions
 * (bf_objective_terms(), _rows() and _slopes(): compiled in AVX-512, AVX2
 * and baseline versions, one picked when the library is loaded) give bit
 * for bit what the same formulas give in this file's plain loops, for
 * values of every kind: whichever version this machine runs (the test
 * prints it) agrees with the plain C. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/fastmath.h"
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

/* The model values of the row test: values near and far from the
 * measured ones, negative, zero, subnormal, below and above delta. */
static double row_value(const double *meas, size_t s)
{
    switch (s % 8) {
    case 0: return meas[s] * (1.0 + 0.01 * (double)(s % 5));
    case 1: return -meas[s];
    case 2: return 0.0;
    case 3: return 1e-310 * (double)(1 + s % 3);
    case 4: return 1e-4 * meas[s]; /* below delta = 1e-3 for values below 10 */
    case 5: return 1e300;
    case 6: return meas[s] * 3.0;
    default: return 1e-200;
    }
}

static int same_bits(const double *a, const double *b, size_t n, const char *what)
{
    size_t i;
    for (i = 0; i < n; i++)
        if (memcmp(&a[i], &b[i], sizeof a[i]) != 0) {
            printf("%s, row %zu: library %a, plain C %a\n", what, i, a[i], b[i]);
            return 0;
        }
    return 1;
}

static void test_row_functions_match_plain_c(void **state)
{
    static const brdffit_objective objectives[] = {
        BRDFFIT_OBJECTIVE_LOG, BRDFFIT_OBJECTIVE_CUBE_ROOT, BRDFFIT_OBJECTIVE_RELATIVE};
    size_t o, m, i;
    (void)state;
#if defined(__GNUC__) && defined(__x86_64__)
    __builtin_cpu_init();
    printf("this machine runs the %s version of the row functions\n",
           __builtin_cpu_supports("avx512f") ? "AVX-512"
           : __builtin_cpu_supports("avx2") ? "AVX2"
                                            : "baseline");
#endif
    for (o = 0; o < sizeof objectives / sizeof objectives[0]; o++) {
        setup s;
        const bf_problem *pb;
        size_t ns, n;
        double *buf;
        setup_init(&s, "ashikhmin-shirley", 3, BF_SOURCE_CHANNELS, 0.0, objectives[o]);
        pb = &s.pb;
        ns = pb->grid->n_samples;
        n = ns < 203 ? ns : 203; /* every vector width's tail */
        buf = calloc(9 * n, sizeof *buf);
        assert_non_null(buf);
        for (m = 0; m < pb->nc; m++) {
            const double *meas = bf_grid_values(pb->grid, m), *lz = pb->grid->geo.lz;
            const double *tm = pb->terms + m * ns, *tc = pb->terms + pb->nc * ns;
            double *val = buf, *rd = buf + n, *rw = buf + 2 * n, *prd = buf + 3 * n;
            double *prw = buf + 4 * n, *sw = buf + 5 * n, *psw = buf + 6 * n;
            double *ltm = buf + 7 * n, *ltc = buf + 8 * n;
            const double root_delta = bf_cbrt(pb->delta);
            const double floor_slope = 1.0 / (3.0 * root_delta * root_delta);
            for (i = 0; i < n; i++) {
                val[i] = row_value(meas, i);
                rw[i] = prw[i] = sw[i] = psw[i] = i % 7 == 3 ? 0.0 : 0.5 + 0.001 * (double)i;
            }
            bf_objective_rows(pb, m, 0, meas, val, lz, n, rd, rw);
            bf_objective_slopes(pb, m, 0, meas, lz, n, sw);
            bf_objective_terms(pb, meas, lz, n, ltm, ltc);
            for (i = 0; i < n; i++) {
                double c = lz[i] > 0.0 ? lz[i] : 0.0, on = prw[i] != 0.0 ? 1.0 : 0.0;
                if (objectives[o] == BRDFFIT_OBJECTIVE_LOG) {
                    double cv = on * c * val[i];
                    prd[i] = prw[i] * (bf_log1p(cv) - tm[i]);
                    prw[i] *= c / (1.0 + cv);
                    psw[i] *= c / (1.0 + (psw[i] != 0.0 ? c * meas[i] : 0.0));
                    assert_true(memcmp(&ltm[i], &tm[i], sizeof tm[i]) == 0);
                } else if (objectives[o] == BRDFFIT_OBJECTIVE_CUBE_ROOT) {
                    double v = on * val[i], a = v < 0.0 ? -v : v, y = bf_rcbrt(a), y2 = y * y;
                    double tv = a * y2, cc = tc[i], sv = cc > 0.0 ? fabs(tm[i]) / cc : 0.0;
                    double t = sv > root_delta ? sv : root_delta;
                    prd[i] = prw[i] * ((v < 0.0 ? -cc : cc) * tv - tm[i]);
                    prw[i] *= cc * (tv > root_delta ? y2 * (1.0 / 3.0) : floor_slope);
                    psw[i] *= cc / (3.0 * t * t);
                    assert_true(memcmp(&ltm[i], &tm[i], sizeof tm[i]) == 0);
                    assert_true(memcmp(&ltc[i], &tc[i], sizeof tc[i]) == 0);
                } else {
                    prd[i] = prw[i] * (val[i] - meas[i]) * tm[i];
                    prw[i] *= tm[i];
                    psw[i] *= tm[i];
                }
            }
            if (!same_bits(rd, prd, n, objective_names[objectives[o]]) ||
                !same_bits(rw, prw, n, objective_names[objectives[o]]) ||
                !same_bits(sw, psw, n, objective_names[objectives[o]]))
                fail();
        }
        free(buf);
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
        cmocka_unit_test(test_row_functions_match_plain_c),
        cmocka_unit_test(test_lobe_form),
        cmocka_unit_test(test_microfacet_form),
        cmocka_unit_test(test_lafortune_and_clear_coat),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
