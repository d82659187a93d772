/* What the items of a batch share (lib/fit/many_scan.h): the cached chunk
 * weights equal the computed ones bit for bit; the scan basis has one
 * point per grid point of auto's scan and keeps a column that no shape
 * parameter moves once; and at every grid point an item's VARPRO sums from
 * the basis equal a VARPRO pass's to rounding (1e-12 of the Cauchy-Schwarz
 * scale of each sum; 1e-6 where the pass reads the Ashikhmin-Shirley lobe
 * geometry in single precision), for the lobe form (one scan dimension), the
 * microfacet form, Ashikhmin-Shirley's shader form (two dimensions), a
 * clear coat and the cube-root objective's weights; the point's cheap
 * plausibility bounds are those computed there, and the basis handed to
 * the colour steps is the kernel's. An item with a
 * missing value, and a grid point past the basis, take the pass. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fit/many_scan.h"
#include "fit/plausible.h"
#include "fit/run.h"
#include "fit/scan.h"
#include "fit_fixtures.h"
#include "test_support.h"

#define NC 3

typedef struct setup {
    brdffit_grid *grid;
    brdffit_model *model;
    brdffit_fit *fit;
    bf_batch batch;
    bf_run run;
    bf_result res;
    char message[BF_FIT_MESSAGE_SIZE];
    bf_stage st;
} setup;

/* A fit of `name` on a small regular grid (noisy Ashikhmin-Shirley values) with the batch's shared state, and
 * auto's stage over it as a run sets it up. */
static void set_up(setup *s, const char *name, double coat, brdffit_objective objective)
{
    static const double p[7] = {120.0, 0.2, 0.15, 0.1, 0.05, 0.06, 0.07};
    double ti[9], to[13], po[12];
    brdffit_axes axes = fx_small_axes(ti, to, po);
    memset(s, 0, sizeof *s);
    s->grid = fx_grid_from_named("ashikhmin-shirley", p, NC, &axes, 0.02, 5);
    assert_non_null(s->grid);
    assert_int_equal(brdffit_model_create(&s->model, name, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_create(&s->fit, s->grid, s->model, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(s->fit, BRDFFIT_FIT_CLEARCOAT, coat), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(s->fit, BRDFFIT_FIT_OBJECTIVE, (double)objective), 0);
    assert_int_equal(bf_batch_init(&s->batch, s->fit), BRDFFIT_OK);
    assert_true(s->batch.has_plans);
    assert_true(s->batch.n_points > 0);
    assert_ptr_equal(s->fit->batch, &s->batch);
    s->fit->batch_work = calloc(s->batch.work_size, sizeof(double));
    assert_non_null(s->fit->batch_work);
    s->res.message = s->message;
    s->run.fit = s->fit;
    s->run.result = &s->res;
    assert_true(bf_batch_plans(s->fit, &s->run.plan, &s->run.plan_sa));
    bf_pool_start(&s->run.pool, 0);
    assert_int_equal(bf_stage_init(&s->st, &s->run, NC, BF_SOURCE_CHANNELS, 0, 0), BRDFFIT_OK);
}

static void tear_down(setup *s)
{
    bf_stage_free(&s->st);
    bf_pool_stop(&s->run.pool);
    free(s->fit->batch_work);
    s->fit->batch_work = NULL;
    s->fit->batch = NULL;
    bf_batch_free(&s->batch, &s->fit->alloc);
    brdffit_fit_destroy(s->fit);
    brdffit_model_destroy(s->model);
    brdffit_grid_destroy(s->grid);
}

/* The sums of channel block a (from the basis) against b (a pass):
 * [r^T W r, b (L), G (L x L)], each within tol of its scale. */
static void assert_sums_close(const double *a, const double *b, size_t L, double tol)
{
    size_t q, r;
    const double *G = b + 1 + L;
    assert_true(fabs(a[0] - b[0]) <= tol * fabs(b[0]));
    for (q = 0; q < L; q++) {
        double scale = sqrt(fabs(b[0]) * fabs(G[q * L + q]));
        assert_true(fabs(a[1 + q] - b[1 + q]) <= tol * scale);
        for (r = 0; r < L; r++) {
            double sg = sqrt(fabs(G[q * L + q]) * fabs(G[r * L + r]));
            assert_true(fabs(a[1 + L + q * L + r] - G[q * L + r]) <= tol * sg);
        }
    }
}

/* The basis the batch hands the colour steps at a grid point (st->p set
 * there) is the kernel's, bit for bit, on every row of the plan. */
static void check_point_basis(const bf_stage *st, size_t flat, size_t L)
{
    const size_t *col;
    size_t stride, n_rows, ci, i, q, first, n, k;
    const double *basis = bf_batch_point_basis(st, flat, &col, &stride, &n_rows);
    double w[BF_CHUNK], shape[BF_KERNEL_MAX_SHAPE];
    bf_basis_form form;
    assert_non_null(basis);
    assert_int_equal(n_rows, st->pb.plan->n_chunks * BF_CHUNK);
    bf_kernel_form(st->pb.kernel, &form);
    for (k = 0; k < form.n_shape; k++) shape[k] = st->p[st->vindex[k * st->pb.nc]];
    for (ci = 0; ci < st->pb.plan->n_chunks; ci++) {
        brdffit_batch geo;
        bf_basis bb;
        bf_weight_plan_chunk(st->pb.plan, ci, &first, &n, w);
        bf_grid_batch(st->pb.grid, first, n, &geo);
        bf_kernel_basis(st->pb.kernel, &geo, 0, n, shape, &bb);
        for (i = 0; i < n; i++)
            for (q = 0; q < L; q++)
                assert_memory_equal(&basis[(ci * BF_CHUNK + i) * stride + col[q]], &bb.b[q][i],
                                    sizeof(double));
    }
}

/* Every grid point: the basis's sums against a VARPRO pass's, within tol.
 * The batch weighs and rounds the values as the fused loop, which takes
 * these passes, does (s->batch.single), so the sums agree to rounding
 * (1e-12) but for the Ashikhmin-Shirley lobe geometry g, which the loop
 * reads in single precision and the batch's basis, the kernel's, holds in
 * double (1e-6, the loop's bound against double inputs: test_fused.c).
 * Returns the number of points. */
static size_t check_points(setup *s, double tol)
{
    bf_stage *st = &s->st;
    bf_scan sc;
    double u[BF_MAX_DIMS];
    size_t P = bf_scan_layout(st, &sc), n_acc = bf_pass_acc_size(&st->pb, BF_PASS_VARPRO), j, m;
    size_t L = s->batch.L, stride = 1 + L + L * L;
    double *table = malloc(n_acc * sizeof *table), *upper = malloc(3 * st->n * sizeof *upper);
    assert_non_null(table);
    assert_non_null(upper);
    assert_int_equal(P, s->batch.n_points);
    assert_int_equal(n_acc, NC * stride);
    assert_true(s->batch.single);
    for (j = 0; j < P; j++) {
        bf_scan_grid_point(&sc, j, u);
        bf_scan_set_point(st, &sc, u);
        /* the point's cheap plausibility bounds, as computed there */
        assert_true(bf_batch_scan_bounds(st, j));
        memcpy(upper, st->lower, 2 * st->n * sizeof *upper);
        memcpy(upper + 2 * st->n, st->oupper, st->n * sizeof *upper);
        assert_int_equal(bf_plausible_bounds(st, 0), BRDFFIT_OK);
        assert_memory_equal(upper, st->lower, 2 * st->n * sizeof *upper);
        assert_memory_equal(upper + 2 * st->n, st->oupper, st->n * sizeof *upper);
        check_point_basis(st, j, L);
        assert_true(bf_batch_scan_sums(st, j));
        memcpy(table, st->acc, n_acc * sizeof *table);
        assert_int_equal(bf_stage_pass(st, BF_PASS_VARPRO), BRDFFIT_OK);
        for (m = 0; m < NC; m++) assert_sums_close(table + m * stride, st->acc + m * stride, L, tol);
    }
    assert_false(bf_batch_scan_sums(st, P)); /* past the basis: the pass */
    free(table), free(upper);
    return P;
}

/* The cached weights of both plans equal a plan's computed ones. */
static void test_cached_weights(void **state)
{
    setup s;
    bf_weight_plan plan, plan_sa, *own[2] = {&plan, &plan_sa};
    const bf_weight_plan *shared[2];
    brdffit_error err;
    double w1[BF_CHUNK], w2[BF_CHUNK];
    size_t k, ci, f1, f2, n1, n2;
    (void)state;
    set_up(&s, "ashikhmin-shirley", 0.0, BRDFFIT_OBJECTIVE_SQUARES);
    shared[0] = &s.run.plan;
    shared[1] = &s.run.plan_sa;
    assert_int_equal(bf_run_plans(s.fit, &plan, &plan_sa, &err), BRDFFIT_OK);
    for (k = 0; k < 2; k++) {
        assert_non_null(shared[k]->cached);
        assert_null(own[k]->cached);
        assert_int_equal(shared[k]->n_chunks, own[k]->n_chunks);
        for (ci = 0; ci < own[k]->n_chunks; ci++) {
            bf_weight_plan_chunk(shared[k], ci, &f1, &n1, w1);
            bf_weight_plan_chunk(own[k], ci, &f2, &n2, w2);
            assert_int_equal(f1, f2);
            assert_int_equal(n1, n2);
            assert_memory_equal(w1, w2, n1 * sizeof *w1);
        }
    }
    bf_weight_plan_free(&plan, &s.fit->alloc);
    bf_weight_plan_free(&plan_sa, &s.fit->alloc);
    tear_down(&s);
}

/* One shape parameter (ns, two points per decade over 1e-3 .. 1e6): the
 * constant diffuse column is kept once. */
static void test_lobe_form(void **state)
{
    setup s;
    (void)state;
    set_up(&s, "ashikhmin-shirley", 0.0, BRDFFIT_OBJECTIVE_SQUARES);
    assert_int_equal(check_points(&s, 1e-6), 19);
    assert_int_equal(s.batch.L, 2);
    assert_int_equal(s.batch.n_cols, 19 + 1);
    assert_true(s.batch.has_bounds);
    tear_down(&s);
}

static void test_microfacet_and_coat(void **state)
{
    setup s;
    (void)state;
    set_up(&s, "ggx", 0.04, BRDFFIT_OBJECTIVE_SQUARES);
    check_points(&s, 1e-12); /* the loop reads the dot products in double */
    tear_down(&s);
}

/* Two shape parameters (ns and Rs): the diffuse column moves with Rs
 * alone, so it is kept once per Rs. */
static void test_two_dimensions(void **state)
{
    setup s;
    bf_scan sc;
    size_t P;
    (void)state;
    set_up(&s, "ashikhmin-shirley-fresnel", 0.0, BRDFFIT_OBJECTIVE_SQUARES);
    P = check_points(&s, 1e-6);
    bf_scan_layout(&s.st, &sc);
    assert_int_equal(sc.nd, 2);
    assert_true(s.batch.n_cols < P * s.batch.L);
    assert_true(s.batch.n_cols >= P);
    tear_down(&s);
}

/* The cube-root objective weighs VARPRO by the solid angle alone. */
static void test_cube_root_weights(void **state)
{
    setup s;
    (void)state;
    set_up(&s, "ashikhmin-shirley", 0.0, BRDFFIT_OBJECTIVE_CUBE_ROOT);
    check_points(&s, 1e-6);
    tear_down(&s);
}

/* A fit whose grid (a view, as the batch's items have) has a missing
 * value takes the pass; without one, the basis. */
static void test_missing_takes_the_pass(void **state)
{
    setup s;
    brdffit_grid view;
    const brdffit_grid *kept;
    size_t n;
    double *values, *store;
    unsigned char *missing, *mask;
    (void)state;
    set_up(&s, "ashikhmin-shirley", 0.0, BRDFFIT_OBJECTIVE_SQUARES);
    n = brdffit_grid_sample_count(s.grid) * NC;
    values = calloc(n, sizeof *values);
    store = calloc(n, BF_GRID_VIEW_BYTES); /* the view's doubles and floats */
    missing = calloc(2 * n, 1);
    assert_non_null(values);
    assert_non_null(store);
    assert_non_null(missing);
    mask = missing + n;
    kept = s.fit->grid;
    bf_grid_view_init(&view, kept, store);
    s.fit->grid = &view;
    missing[5] = 1;
    assert_int_equal(bf_grid_view_set(&view, values, missing, mask, NULL), BRDFFIT_OK);
    assert_false(bf_batch_scan_sums(&s.st, 0));
    assert_int_equal(bf_grid_view_set(&view, values, NULL, mask, NULL), BRDFFIT_OK);
    s.st.run->batch_ready = 0; /* another item */
    assert_true(bf_batch_scan_sums(&s.st, 0));
    s.fit->grid = kept;
    free(values), free(store), free(missing);
    tear_down(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cached_weights),      cmocka_unit_test(test_lobe_form),
        cmocka_unit_test(test_microfacet_and_coat), cmocka_unit_test(test_two_dimensions),
        cmocka_unit_test(test_cube_root_weights),   cmocka_unit_test(test_missing_takes_the_pass),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
