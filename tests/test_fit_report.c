/* The fit's report beyond its parameters: brdffit_fit_converged() and its
 * classification (limits, stalls, the callback), the labelled stages of
 * every pipeline (brdffit_fit_stage_info()) and the whole history
 * (brdffit_fit_history_all()), checked against the final LM run's own
 * report and against what each pipeline is documented to run. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit_fixtures.h"
#include "test_support.h"

#define MAXV 32
#define NC 3

static const double AS[3][8] = {{120.0}, {0.30, 0.20, 0.10}, {0.40, 0.35, 0.30}};

typedef struct fixture {
    brdffit_model *model;
    brdffit_grid *grid;
    brdffit_fit *fit;
} fixture;

static void setup(fixture *f, const char *model, const double values[][8])
{
    double p[MAXV];
    memset(f, 0, sizeof *f);
    assert_int_equal(brdffit_model_create(&f->model, model, NULL, NULL), BRDFFIT_OK);
    fx_vector(f->model, NC, values, p);
    f->grid = fx_grid_from_model(f->model, p, NC, NULL, 0.0, 1);
    assert_non_null(f->grid);
    assert_int_equal(brdffit_fit_create(&f->fit, f->grid, f->model, NULL, NULL), BRDFFIT_OK);
}

static void teardown(fixture *f)
{
    brdffit_fit_destroy(f->fit);
    brdffit_grid_destroy(f->grid);
    brdffit_model_destroy(f->model);
}

static void run_pipeline(fixture *f, brdffit_pipeline pipeline)
{
    assert_int_equal(brdffit_fit_set(f->fit, BRDFFIT_FIT_PIPELINE, (double)pipeline), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_run(f->fit), BRDFFIT_OK);
}

/* The whole history, with its stage numbers. */
typedef struct history {
    size_t n;
    double cost[8192], lambda[8192];
    size_t stage[8192];
} history;

static void read_history(const brdffit_fit *fit, history *h)
{
    h->n = brdffit_fit_history_all(fit, NULL, NULL, NULL);
    assert_true(h->n > 0 && h->n <= 8192);
    assert_int_equal(brdffit_fit_history_all(fit, h->cost, h->lambda, h->stage), h->n);
}

static brdffit_fit_stage stage_of(const brdffit_fit *fit, size_t i)
{
    brdffit_fit_stage s;
    memset(&s, 0xa5, sizeof s);
    assert_int_equal(brdffit_fit_stage_info(fit, i, &s, sizeof s), BRDFFIT_OK);
    return s;
}

/* The stages tile the history in order, every entry labelled with its own
 * stage; an LM stage has iterations + 1 entries, the scan one per
 * evaluation. */
static void check_tiling(const brdffit_fit *fit, const history *h)
{
    size_t n_stages = brdffit_fit_stage_count(fit), i, e, next = 0;
    for (i = 0; i < n_stages; i++) {
        brdffit_fit_stage s = stage_of(fit, i);
        assert_int_equal(s.first, next);
        if (s.kind == BRDFFIT_STAGE_SCAN)
            assert_int_equal(s.length, s.evaluations);
        else
            assert_int_equal(s.length, s.iterations + 1);
        for (e = s.first; e < s.first + s.length; e++) {
            assert_int_equal(h->stage[e], i);
            assert_true(isfinite(h->cost[e]) && h->cost[e] >= 0.0);
        }
        next += s.length;
    }
    assert_int_equal(next, h->n);
}

/* The final LM run's report (brdffit_fit_stop_reason(), _iterations(),
 * _history()) is the one of stage `final`. */
static void check_final(const brdffit_fit *fit, const history *h, size_t final)
{
    brdffit_fit_stage s = stage_of(fit, final);
    double cost[1024], lambda[1024];
    size_t n = brdffit_fit_history(fit, cost, lambda), i;
    assert_int_equal(brdffit_fit_stop_reason(fit), s.stop);
    assert_int_equal(brdffit_fit_iterations(fit), s.iterations);
    assert_int_equal(n, s.length);
    for (i = 0; i < n; i++) {
        assert_true(cost[i] == h->cost[s.first + i]);
        assert_true(lambda[i] == h->lambda[s.first + i]);
    }
}

static void test_joint_report(void **state)
{
    fixture f;
    history *h = calloc(1, sizeof *h);
    brdffit_fit_stage s;
    (void)state;
    setup(&f, "ashikhmin-shirley", AS);
    run_pipeline(&f, BRDFFIT_PIPELINE_JOINT);
    assert_int_equal(brdffit_fit_converged(f.fit), 1);
    assert_int_equal(brdffit_fit_stage_count(f.fit), 1);
    s = stage_of(f.fit, 0);
    assert_int_equal(s.kind, BRDFFIT_STAGE_JOINT);
    assert_int_equal(s.index, 0);
    assert_int_equal(s.converged, 1);
    assert_int_equal(s.kept, 1);
    assert_true(s.evaluations >= s.iterations);
    read_history(f.fit, h);
    check_tiling(f.fit, h);
    check_final(f.fit, h, 0);
    free(h);
    teardown(&f);
}

/* Auto: the scan (its entries the lowest cost so far: never rising), then
 * one polish per competing candidate, exactly one kept: the lowest final
 * cost, whose report is the fit's. */
static void test_auto_report(void **state)
{
    fixture f;
    history *h = calloc(1, sizeof *h);
    size_t n_stages, i, e, kept = 0, kept_stage = 0;
    double best = HUGE_VAL, fit_cost;
    brdffit_fit_stage s;
    (void)state;
    setup(&f, "ashikhmin-shirley", AS);
    run_pipeline(&f, BRDFFIT_PIPELINE_AUTO);
    assert_int_equal(brdffit_fit_converged(f.fit), 1);
    n_stages = brdffit_fit_stage_count(f.fit);
    assert_true(n_stages >= 2);
    read_history(f.fit, h);
    check_tiling(f.fit, h);
    s = stage_of(f.fit, 0);
    assert_int_equal(s.kind, BRDFFIT_STAGE_SCAN);
    assert_int_equal(s.kept, 0);
    assert_int_equal(s.stop, BRDFFIT_STOP_NONE);
    assert_true(s.evaluations >= 19); /* 2 per decade over 1e-3 .. 1e6, and any refinement */
    for (e = 1; e < s.length; e++) {
        assert_true(h->cost[e] <= h->cost[e - 1]);
        assert_true(h->lambda[e] == 0.0);
    }
    for (i = 1; i < n_stages; i++) {
        brdffit_fit_stage p = stage_of(f.fit, i);
        double final = h->cost[p.first + p.length - 1];
        assert_int_equal(p.kind, BRDFFIT_STAGE_POLISH);
        assert_int_equal(p.index, i - 1);
        if (final < best) best = final;
        if (p.kept) {
            kept++;
            kept_stage = i;
        }
    }
    assert_int_equal(kept, 1);
    assert_true(
        h->cost[stage_of(f.fit, kept_stage).first + stage_of(f.fit, kept_stage).length - 1] ==
        best);
    assert_int_equal(brdffit_fit_error(f.fit, BRDFFIT_METRIC_COST, BRDFFIT_ALL_CHANNELS, &fit_cost),
                     BRDFFIT_OK);
    assert_close(fit_cost, best, 1e-9);
    check_final(f.fit, h, kept_stage);
    free(h);
    teardown(&f);
}

/* Two-stage: the mean stage, then one stage per channel in order, all
 * kept; the fit's report is the last channel's. */
static void test_two_stage_report(void **state)
{
    fixture f;
    history *h = calloc(1, sizeof *h);
    size_t c;
    brdffit_fit_stage s;
    (void)state;
    setup(&f, "ashikhmin-shirley", AS);
    run_pipeline(&f, BRDFFIT_PIPELINE_TWO_STAGE);
    assert_int_equal(brdffit_fit_converged(f.fit), 1);
    assert_int_equal(brdffit_fit_stage_count(f.fit), 1 + NC);
    read_history(f.fit, h);
    check_tiling(f.fit, h);
    s = stage_of(f.fit, 0);
    assert_int_equal(s.kind, BRDFFIT_STAGE_MEAN);
    assert_int_equal(s.kept, 1);
    for (c = 0; c < NC; c++) {
        s = stage_of(f.fit, 1 + c);
        assert_int_equal(s.kind, BRDFFIT_STAGE_CHANNEL);
        assert_int_equal(s.index, c);
        assert_int_equal(s.kept, 1);
        assert_int_equal(s.converged, 1);
    }
    check_final(f.fit, h, NC);
    free(h);
    teardown(&f);
}

/* One iteration from the default start is not enough: the iteration limit
 * is reported as not converged, by every pipeline. */
static void test_iteration_limit_not_converged(void **state)
{
    static const brdffit_pipeline pipelines[] = {BRDFFIT_PIPELINE_AUTO, BRDFFIT_PIPELINE_JOINT,
                                                 BRDFFIT_PIPELINE_TWO_STAGE};
    fixture f;
    size_t p;
    (void)state;
    setup(&f, "ashikhmin-shirley", AS);
    assert_int_equal(brdffit_fit_set(f.fit, BRDFFIT_FIT_MAX_ITERATIONS, 1), BRDFFIT_OK);
    for (p = 0; p < 3; p++) {
        run_pipeline(&f, pipelines[p]);
        assert_int_equal(brdffit_fit_stop_reason(f.fit), BRDFFIT_STOP_MAX_ITERATIONS);
        assert_int_equal(brdffit_fit_converged(f.fit), 0);
    }
    /* and the same fit with its limit back converges */
    assert_int_equal(brdffit_fit_set(f.fit, BRDFFIT_FIT_MAX_ITERATIONS, 200), BRDFFIT_OK);
    run_pipeline(&f, BRDFFIT_PIPELINE_JOINT);
    assert_int_equal(brdffit_fit_converged(f.fit), 1);
    teardown(&f);
}

/* The callback stops the joint run at its second iteration. */
static int stop_second(const brdffit_iteration *it, void *user)
{
    int *calls = user;
    (void)it;
    return ++*calls == 2;
}

static void test_callback_stop_not_converged(void **state)
{
    fixture f;
    int calls = 0;
    (void)state;
    setup(&f, "ashikhmin-shirley", AS);
    assert_int_equal(brdffit_fit_set_callback(f.fit, stop_second, &calls), BRDFFIT_OK);
    run_pipeline(&f, BRDFFIT_PIPELINE_JOINT);
    assert_int_equal(brdffit_fit_stop_reason(f.fit), BRDFFIT_STOP_CALLBACK);
    assert_int_equal(brdffit_fit_converged(f.fit), 0);
    assert_int_equal(stage_of(f.fit, 0).converged, 0);
    teardown(&f);
}

/* Stops the LM run that makes call number `at` of the callback. */
typedef struct stop_at {
    int calls, at;
} stop_at;

static int stop_at_call(const brdffit_iteration *it, void *user)
{
    stop_at *s = user;
    (void)it;
    return ++s->calls == s->at;
}

/* Two-stage whose first channel stage alone is stopped by the callback:
 * the final run (the last channel's) converged, so the fit's stop reason
 * says so, but the answer holds channel 0's unconverged colours: not
 * converged. */
static void test_two_stage_judges_every_kept_stage(void **state)
{
    fixture f;
    stop_at s = {0, 0};
    brdffit_fit_stage st;
    (void)state;
    setup(&f, "ashikhmin-shirley", AS);
    run_pipeline(&f, BRDFFIT_PIPELINE_TWO_STAGE);
    s.at = (int)stage_of(f.fit, 0).iterations + 1; /* channel 0's first iteration */
    assert_int_equal(brdffit_fit_set_callback(f.fit, stop_at_call, &s), BRDFFIT_OK);
    run_pipeline(&f, BRDFFIT_PIPELINE_TWO_STAGE);
    st = stage_of(f.fit, 1);
    assert_int_equal(st.kind, BRDFFIT_STAGE_CHANNEL);
    assert_int_equal(st.stop, BRDFFIT_STOP_CALLBACK);
    assert_int_equal(st.kept, 1);
    assert_int_equal(stage_of(f.fit, 0).converged, 1);
    assert_int_equal(stage_of(f.fit, NC).converged, 1);
    assert_true(brdffit_fit_stop_reason(f.fit) != BRDFFIT_STOP_CALLBACK);
    assert_int_equal(brdffit_fit_converged(f.fit), 0);
    teardown(&f);
}

/* A cancel before the run: auto returns its start point unpolished, with
 * no stage run, cancelled and not converged. */
static void test_cancelled_auto_not_converged(void **state)
{
    fixture f;
    (void)state;
    setup(&f, "ashikhmin-shirley", AS);
    brdffit_fit_cancel(f.fit);
    run_pipeline(&f, BRDFFIT_PIPELINE_AUTO);
    assert_int_equal(brdffit_fit_stop_reason(f.fit), BRDFFIT_STOP_CANCELLED);
    assert_int_equal(brdffit_fit_converged(f.fit), 0);
    assert_int_equal(brdffit_fit_stage_count(f.fit), 0);
    /* the request was consumed: the next run converges */
    run_pipeline(&f, BRDFFIT_PIPELINE_AUTO);
    assert_int_equal(brdffit_fit_converged(f.fit), 1);
    teardown(&f);
}

/* value = c x, whatever k: the data cannot tell k and the run stalls. */
static brdffit_status idle_eval(const brdffit_batch *b, const double *p, size_t nc, double *values,
                                double *jac, void *user)
{
    size_t s, c, n = b->n;
    (void)user;
    for (s = 0; s < n; s++)
        for (c = 0; c < nc; c++) {
            values[c * n + s] = p[1 + c] * b->nv[s];
            if (jac != NULL) {
                jac[c * n + s] = 0.0;
                jac[(nc + c) * n + s] = b->nv[s];
            }
        }
    return BRDFFIT_OK;
}

static void test_stall_not_converged(void **state)
{
    const brdffit_param_info params[] = {
        {"k", 0, 0.0, 10.0, 1.0},
        {"cd", BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR, 0.0, HUGE_VAL, 0.1},
    };
    const double v[2][8] = {{1.0}, {0.30, 0.20, 0.10}};
    brdffit_model_def def = BRDFFIT_MODEL_DEF_INIT;
    fixture f;
    double p[MAXV];
    (void)state;
    memset(&f, 0, sizeof f);
    def.name = "idle";
    def.n_params = 2;
    def.params = params;
    def.eval = idle_eval;
    assert_int_equal(brdffit_model_create_custom(&f.model, &def, NULL, NULL), BRDFFIT_OK);
    fx_vector(f.model, NC, v, p);
    f.grid = fx_grid_from_model(f.model, p, NC, NULL, 0.0, 1);
    assert_non_null(f.grid);
    assert_int_equal(brdffit_fit_create(&f.fit, f.grid, f.model, NULL, NULL), BRDFFIT_OK);
    run_pipeline(&f, BRDFFIT_PIPELINE_JOINT);
    assert_int_equal(brdffit_fit_stop_reason(f.fit), BRDFFIT_STOP_STALLED);
    assert_int_equal(brdffit_fit_converged(f.fit), 0);
    teardown(&f);
}

/* Before a run, after a failed one, and bad arguments. */
static void test_report_before_and_misuse(void **state)
{
    fixture f;
    brdffit_fit_stage s;
    double cost;
    size_t stage;
    (void)state;
    setup(&f, "ashikhmin-shirley", AS);
    assert_int_equal(brdffit_fit_converged(f.fit), 0);
    assert_int_equal(brdffit_fit_stage_count(f.fit), 0);
    assert_int_equal(brdffit_fit_history_all(f.fit, &cost, NULL, &stage), 0);
    assert_int_equal(brdffit_fit_stage_info(f.fit, 0, &s, sizeof s), BRDFFIT_E_NOT_READY);
    run_pipeline(&f, BRDFFIT_PIPELINE_JOINT);
    assert_int_equal(brdffit_fit_stage_info(f.fit, 1, &s, sizeof s), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_stage_info(f.fit, 0, NULL, sizeof s), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_stage_info(f.fit, 0, &s, BRDFFIT_FIT_STAGE_SIZE_V1 - 1),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_stage_info(NULL, 0, &s, sizeof s), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_stage_info(f.fit, 0, &s, BRDFFIT_FIT_STAGE_SIZE_V1), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_converged(NULL), 0);
    assert_int_equal(brdffit_fit_stage_count(NULL), 0);
    assert_int_equal(brdffit_fit_history_all(NULL, NULL, NULL, NULL), 0);
    /* a failed run leaves no result: a cap of 0 leaves no sample */
    assert_int_equal(brdffit_fit_set(f.fit, BRDFFIT_FIT_CAP, 0.0), BRDFFIT_OK);
    assert_int_not_equal(brdffit_fit_run(f.fit), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_converged(f.fit), 0);
    assert_int_equal(brdffit_fit_stage_count(f.fit), 0);
    teardown(&f);
}

static void test_stage_names(void **state)
{
    (void)state;
    assert_string_equal(brdffit_fit_stage_name(BRDFFIT_STAGE_SCAN), "scan");
    assert_string_equal(brdffit_fit_stage_name(BRDFFIT_STAGE_POLISH), "polish");
    assert_string_equal(brdffit_fit_stage_name(BRDFFIT_STAGE_JOINT), "joint");
    assert_string_equal(brdffit_fit_stage_name(BRDFFIT_STAGE_MEAN), "mean");
    assert_string_equal(brdffit_fit_stage_name(BRDFFIT_STAGE_CHANNEL), "channel");
    assert_null(brdffit_fit_stage_name((brdffit_fit_stage_kind)5));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_joint_report),
        cmocka_unit_test(test_auto_report),
        cmocka_unit_test(test_two_stage_report),
        cmocka_unit_test(test_iteration_limit_not_converged),
        cmocka_unit_test(test_callback_stop_not_converged),
        cmocka_unit_test(test_stall_not_converged),
        cmocka_unit_test(test_two_stage_judges_every_kept_stage),
        cmocka_unit_test(test_cancelled_auto_not_converged),
        cmocka_unit_test(test_report_before_and_misuse),
        cmocka_unit_test(test_stage_names),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
