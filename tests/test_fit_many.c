/* brdffit_fit_many(): many value sets on one geometry. Every item's result
 * must equal, bit for bit, a fit with the prototype's options and one
 * thread on a grid made from the same directions and the item's values;
 * one and two threads must give the same arrays; bad items are reported
 * per item; cancelling and progress behave as documented; bad arguments
 * get their exact statuses; an allocation failure anywhere either fails
 * the call with BRDFFIT_E_OUT_OF_MEMORY or one item with it, never leaks
 * and never changes another item. Also run under ThreadSanitizer (label
 * tsan). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fit_fixtures.h"
#include "grid_fixtures.h"
#include "test_support.h"

#define NS 200 /* samples per texel */
#define NC 3
#define NV 7 /* ashikhmin-shirley: ns, cd[3], cs[3] */
#define MAX_ITEMS 700

typedef struct geometry {
    double ti[NS], pi[NS], to[NS], po[NS];
} geometry;

/* Scattered directions in no particular order (so the grid reorders them). */
static void make_geometry(geometry *g, uint64_t seed)
{
    size_t s;
    for (s = 0; s < NS; s++) {
        g->ti[s] = DEG(80.0) * fx_uniform(&seed);
        g->pi[s] = DEG(180.0);
        g->to[s] = DEG(80.0) * fx_uniform(&seed);
        g->po[s] = DEG(180.0) * fx_uniform(&seed);
    }
}

static brdffit_model *make_model(void)
{
    brdffit_model *m = NULL;
    assert_int_equal(brdffit_model_create(&m, "ashikhmin-shirley", NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_model_vector_size(m, NC), NV);
    return m;
}

/* Texel i's true parameters: ns from 20 to 2000, colours varying. */
static void truth(const brdffit_model *m, size_t i, double *p)
{
    double v[3][8];
    size_t c;
    memset(v, 0, sizeof v);
    v[0][0] = 20.0 * pow(100.0, (double)(i % 11) / 10.0);
    for (c = 0; c < NC; c++) {
        v[1][c] = 0.05 + 0.02 * (double)((i + c) % 7);
        v[2][c] = 0.02 + 0.01 * (double)((i * 3 + c) % 5);
    }
    fx_vector(m, NC, (const double(*)[8])v, p);
}

/* n items' values, interleaved per item in input order, with noise. */
static double *make_values(const brdffit_model *m, const geometry *g, size_t n, double noise)
{
    double *values = malloc(n * NS * NC * sizeof *values), p[NV], ch[NS * NC];
    uint64_t seed = 99;
    size_t i, s, c;
    assert_non_null(values);
    for (i = 0; i < n; i++) {
        double *x = values + i * NS * NC;
        truth(m, i, p);
        assert_int_equal(brdffit_model_eval_angles(m, NS, g->ti, g->pi, g->to, g->po, NC, p, ch,
                                                   NULL, NULL),
                         BRDFFIT_OK);
        /* per channel from the model, interleaved for the grid */
        for (s = 0; s < NS; s++)
            for (c = 0; c < NC; c++)
                x[s * NC + c] = ch[c * NS + s] * (1.0 + noise * fx_normal(&seed));
    }
    return values;
}

static brdffit_grid *scattered(const geometry *g, const double *values,
                               const unsigned char *missing, const brdffit_allocator *a)
{
    brdffit_grid *grid = NULL;
    assert_int_equal(brdffit_grid_create_scattered(&grid, NS, g->ti, g->pi, g->to, g->po, NC,
                                                   values, missing, NULL, a, NULL),
                     BRDFFIT_OK);
    return grid;
}

/* Result arrays of up to MAX_ITEMS items. */
typedef struct results {
    brdffit_status status[MAX_ITEMS];
    double params[MAX_ITEMS * NV], se[MAX_ITEMS * NV];
    double cost[MAX_ITEMS], rms[MAX_ITEMS], ngan[MAX_ITEMS];
    brdffit_stop_reason stop[MAX_ITEMS];
    size_t iterations[MAX_ITEMS];
    unsigned warnings[MAX_ITEMS];
    brdffit_many_out out;
} results;

static results *new_results(void)
{
    results *r = calloc(1, sizeof *r);
    assert_non_null(r);
    r->out.struct_size = sizeof r->out;
    r->out.status = r->status;
    r->out.params = r->params;
    r->out.std_errors = r->se;
    r->out.cost = r->cost;
    r->out.rms = r->rms;
    r->out.ngan = r->ngan;
    r->out.stop = r->stop;
    r->out.iterations = r->iterations;
    r->out.warnings = r->warnings;
    return r;
}

/* Options of the prototypes below, also applied to the single fits. */
typedef void (*options_fn)(brdffit_fit *fit);

static void auto_options(brdffit_fit *fit)
{
    (void)fit;
}

static void joint_options(brdffit_fit *fit)
{
    double start[NV] = {100.0, 0.1, 0.1, 0.1, 0.05, 0.05, 0.05};
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, BRDFFIT_PIPELINE_JOINT), 0);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_CAP, DEG(70.0)), 0);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_MAX_ITERATIONS, 7), 0);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, BRDFFIT_OBJECTIVE_RELATIVE), 0);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_WEIGHTING, BRDFFIT_WEIGHT_COSINE), 0);
    assert_int_equal(brdffit_fit_set_damping(fit, brdffit_damping_marquardt()), 0);
    assert_int_equal(brdffit_fit_set_start(fit, start), 0);
}

/* Auto with plausibility off and the sandwich errors: settings that change
 * the result of the bright items below. */
static void auto_unbounded_options(brdffit_fit *fit)
{
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PLAUSIBLE, 0), 0);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_COVARIANCE, 1), 0);
}

/* Auto settings that change what the batch's shared scan basis holds
 * (many_scan.h): the cube-root objective (VARPRO weighs by the solid
 * angle alone, and colour steps follow every scan point); a clear coat,
 * the cosine weighting and a smaller cap; a held colour (a constant of the
 * scan's colour solves). */
static void cube_root_options(brdffit_fit *fit)
{
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, BRDFFIT_OBJECTIVE_CUBE_ROOT), 0);
}

static void coat_options(brdffit_fit *fit)
{
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_CLEARCOAT, 0.04), 0);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_WEIGHTING, BRDFFIT_WEIGHT_COSINE), 0);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_CAP, DEG(60.0)), 0);
}

static void held_colour_options(brdffit_fit *fit)
{
    double start[NV] = {100.0, 0.1, 0.1, 0.1, 0.05, 0.05, 0.05};
    assert_int_equal(brdffit_fit_set_start(fit, start), 0);
    assert_int_equal(brdffit_fit_set_fixed(fit, 2, 1), 0); /* cs */
}

/* Item i fitted alone: a grid of its own, a fit with one thread. */
static void single_fit(const brdffit_model *m, const geometry *g, const double *values,
                       const unsigned char *missing, options_fn options, results *r, size_t i)
{
    brdffit_grid *grid = NULL;
    brdffit_fit *fit = NULL;
    brdffit_status st;
    st = brdffit_grid_create_scattered(&grid, NS, g->ti, g->pi, g->to, g->po, NC,
                                       values + i * NS * NC,
                                       missing ? missing + i * NS * NC : NULL, NULL, NULL, NULL);
    r->status[i] = st;
    if (st != BRDFFIT_OK) return;
    assert_int_equal(brdffit_fit_create(&fit, grid, m, NULL, NULL), BRDFFIT_OK);
    options(fit);
    st = r->status[i] = brdffit_fit_run(fit);
    if (st == BRDFFIT_OK) {
        assert_int_equal(brdffit_fit_params(fit, r->params + i * NV), 0);
        assert_int_equal(brdffit_fit_std_errors(fit, r->se + i * NV), 0);
        assert_int_equal(brdffit_fit_error(fit, BRDFFIT_METRIC_COST, BRDFFIT_ALL_CHANNELS,
                                           r->cost + i), 0);
        assert_int_equal(brdffit_fit_error(fit, BRDFFIT_METRIC_RMS, BRDFFIT_ALL_CHANNELS,
                                           r->rms + i), 0);
        assert_int_equal(brdffit_fit_error(fit, BRDFFIT_METRIC_NGAN, BRDFFIT_ALL_CHANNELS,
                                           r->ngan + i), 0);
        r->stop[i] = brdffit_fit_stop_reason(fit);
        r->iterations[i] = brdffit_fit_iterations(fit);
        r->warnings[i] = brdffit_fit_warnings(fit);
    }
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
}

/* Items a and b of two result sets are the same, bit for bit (the
 * standard errors when a asked for them); a failed item has NaN
 * everywhere. */
static void assert_same_item(const results *a, const results *b, size_t i)
{
    size_t k;
    assert_int_equal(a->status[i], b->status[i]);
    if (a->status[i] != BRDFFIT_OK) {
        for (k = 0; k < NV; k++) assert_true(isnan(a->params[i * NV + k]));
        assert_true(isnan(a->cost[i]) && isnan(a->rms[i]) && isnan(a->ngan[i]));
        assert_int_equal(a->stop[i], BRDFFIT_STOP_NONE);
        assert_int_equal(a->warnings[i], 0);
        return;
    }
    assert_memory_equal(a->params + i * NV, b->params + i * NV, NV * sizeof(double));
    if (a->out.std_errors != NULL)
        assert_memory_equal(a->se + i * NV, b->se + i * NV, NV * sizeof(double));
    assert_memory_equal(&a->cost[i], &b->cost[i], sizeof(double));
    assert_memory_equal(&a->rms[i], &b->rms[i], sizeof(double));
    assert_memory_equal(&a->ngan[i], &b->ngan[i], sizeof(double));
    assert_int_equal(a->stop[i], b->stop[i]);
    assert_int_equal(a->iterations[i], b->iterations[i]);
    assert_int_equal(a->warnings[i], b->warnings[i]);
}

static brdffit_fit *prototype(const brdffit_grid *grid, const brdffit_model *m, options_fn options,
                              size_t threads, const brdffit_allocator *a)
{
    brdffit_fit *fit = NULL;
    assert_int_equal(brdffit_fit_create(&fit, grid, m, a, NULL), BRDFFIT_OK);
    options(fit);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_THREADS, (double)threads), BRDFFIT_OK);
    return fit;
}

/* The batch against single fits, on 1 and 2 threads, with `options`; the
 * run on 2 threads asks for no standard errors (their computation is
 * skipped), which must leave everything else as it is. */
static void check_against_single(options_fn options, size_t n, const unsigned char *missing,
                                 double *values)
{
    geometry g;
    brdffit_model *m = make_model();
    brdffit_grid *grid;
    results *one = new_results(), *two = new_results(), *ref = new_results();
    brdffit_fit *p1, *p2;
    size_t i;
    make_geometry(&g, 7);
    if (values == NULL) values = make_values(m, &g, n, 0.02);
    grid = scattered(&g, values, NULL, NULL); /* item 0's values: not used by the batch */
    p1 = prototype(grid, m, options, 1, NULL);
    p2 = prototype(grid, m, options, 2, NULL);
    two->out.std_errors = NULL;
    assert_int_equal(brdffit_fit_many(p1, n, values, missing, &one->out, NULL, NULL), 0);
    assert_int_equal(brdffit_fit_many(p2, n, values, missing, &two->out, NULL, NULL), 0);
    assert_int_equal(one->out.n_run, n);
    assert_int_equal(two->out.n_run, n);
    for (i = 0; i < n; i++) {
        single_fit(m, &g, values, missing, options, ref, i);
        assert_same_item(one, ref, i);
        assert_same_item(two, ref, i);
    }
    brdffit_fit_destroy(p1);
    brdffit_fit_destroy(p2);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(m);
    free(values);
    free(one), free(two), free(ref);
}

/* The auto pipeline recovers each texel's parameters, and equals single fits. */
static void test_auto_equals_single_fits(void **state)
{
    geometry g;
    brdffit_model *m = make_model();
    double *values, p[NV];
    results *r = new_results();
    brdffit_grid *grid;
    brdffit_fit *fit;
    size_t i, k, n = 12;
    (void)state;
    make_geometry(&g, 7);
    values = make_values(m, &g, n, 0.0);
    grid = scattered(&g, values, NULL, NULL);
    fit = prototype(grid, m, auto_options, 2, NULL);
    assert_int_equal(brdffit_fit_many(fit, n, values, NULL, &r->out, NULL, NULL), BRDFFIT_OK);
    for (i = 0; i < n; i++) {
        assert_int_equal(r->status[i], BRDFFIT_OK);
        truth(m, i, p);
        for (k = 0; k < NV; k++) assert_close(r->params[i * NV + k], p[k], 1e-6);
    }
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(m);
    free(values);
    free(r);
    check_against_single(auto_options, 24, NULL, NULL);
}

static void test_joint_options_equal_single_fits(void **state)
{
    (void)state;
    check_against_single(joint_options, 9, NULL, NULL);
}

/* Items 8 times too bright (diffuse albedos above 1): the batch honours
 * the prototype's plausibility and covariance settings as single fits do,
 * and the settings matter here (plausibility on bounds cd <= 1). */
static void test_auto_settings_equal_single_fits(void **state)
{
    geometry g;
    brdffit_model *m = make_model();
    results *on = new_results(), *off = new_results();
    double *values;
    size_t i, n = 6, differ = 0;
    (void)state;
    make_geometry(&g, 7);
    values = make_values(m, &g, n, 0.02);
    for (i = 0; i < n * NS * NC; i++) values[i] *= 8.0;
    for (i = 0; i < n; i++) {
        single_fit(m, &g, values, NULL, auto_options, on, i);
        single_fit(m, &g, values, NULL, auto_unbounded_options, off, i);
        assert_int_equal(on->status[i], BRDFFIT_OK);
        assert_int_equal(off->status[i], BRDFFIT_OK);
        differ += memcmp(on->params + i * NV, off->params + i * NV, NV * sizeof(double)) != 0;
    }
    assert_true(differ > 0);
    brdffit_model_destroy(m);
    free(on), free(off);
    check_against_single(auto_unbounded_options, n, NULL, values); /* frees values */
}

/* The batch's scan takes its sums from the shared basis; the results
 * stay those of single fits bit for bit under these settings too. */
static void test_auto_variants_equal_single_fits(void **state)
{
    (void)state;
    check_against_single(cube_root_options, 6, NULL, NULL);
    check_against_single(coat_options, 8, NULL, NULL);
    check_against_single(held_colour_options, 8, NULL, NULL);
}

/* Missing values, a NaN, an item with nothing present, an item too large
 * to fit: reported per item; the others as single fits. */
static void test_bad_items(void **state)
{
    geometry g;
    brdffit_model *m = make_model();
    size_t n = 8, v;
    unsigned char *missing = calloc(n * NS * NC, 1);
    double *values;
    (void)state;
    make_geometry(&g, 7);
    values = make_values(m, &g, n, 0.02);
    assert_non_null(missing);
    missing[1 * NS * NC + 5] = 1; /* item 1: one value missing */
    missing[1 * NS * NC + 17] = 1;
    values[2 * NS * NC + 40] = NAN; /* item 2: not finite */
    for (v = 0; v < NS * NC; v++) missing[3 * NS * NC + v] = 1; /* item 3: nothing */
    for (v = 0; v < NS * NC; v++) values[5 * NS * NC + v] *= 1e105; /* item 5: too large */
    values[6 * NS * NC + 7] = INFINITY; /* item 6: infinite but missing: fine */
    missing[6 * NS * NC + 7] = 1;
    check_against_single(auto_options, n, missing, values); /* frees values */
    free(missing);
    brdffit_model_destroy(m);
}

/* The statuses of those bad items, exactly. */
static void test_bad_item_statuses(void **state)
{
    geometry g;
    brdffit_model *m = make_model();
    size_t n = 4, v;
    unsigned char *missing = calloc(n * NS * NC, 1);
    double *values;
    results *r = new_results();
    brdffit_grid *grid;
    brdffit_fit *fit;
    (void)state;
    make_geometry(&g, 7);
    values = make_values(m, &g, n, 0.02);
    values[1 * NS * NC + 40] = NAN;
    for (v = 0; v < NS * NC; v++) missing[2 * NS * NC + v] = 1;
    for (v = 0; v < NS * NC; v++) values[3 * NS * NC + v] *= 1e105;
    grid = scattered(&g, values, NULL, NULL);
    fit = prototype(grid, m, auto_options, 2, NULL);
    assert_int_equal(brdffit_fit_many(fit, n, values, missing, &r->out, NULL, NULL), 0);
    assert_int_equal(r->status[0], BRDFFIT_OK);
    assert_int_equal(r->status[1], BRDFFIT_E_RANGE);
    assert_int_equal(r->status[2], BRDFFIT_E_NO_DATA);
    assert_int_equal(r->status[3], BRDFFIT_E_RANGE);
    assert_int_equal(r->out.n_run, n);
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(m);
    free(values), free(missing), free(r);
}

/* A regular geometry: items equal fits of regular grids. */
static void test_regular_grid(void **state)
{
    static const double ti[] = {0, 20, 40, 60}, to[] = {0, 15, 30, 45, 60, 75},
                        po[] = {0, 30, 60, 90, 120, 150, 180};
    fx_axes ax;
    brdffit_model *m = make_model();
    size_t n = 3, ns = 4 * 6 * 7, i;
    double *values = malloc(n * ns * NC * sizeof *values), p[NV];
    brdffit_grid *grid = NULL, *one = NULL;
    brdffit_fit *fit, *single = NULL;
    results *r = new_results();
    (void)state;
    fx_axes_set(&ax, ti, 4, to, 6, po, 7);
    assert_non_null(values);
    for (i = 0; i < n; i++) {
        brdffit_grid *tmp;
        const double *ch;
        size_t s, c;
        truth(m, i + 3, p);
        tmp = fx_grid_from_named("ashikhmin-shirley", p, NC, &ax.axes, 0.01, 1 + i);
        assert_non_null(tmp);
        for (c = 0; c < NC; c++) {
            assert_int_equal(brdffit_grid_values(tmp, c, &ch), 0);
            for (s = 0; s < ns; s++) values[(i * ns + s) * NC + c] = ch[s];
        }
        brdffit_grid_destroy(tmp);
    }
    assert_int_equal(brdffit_grid_create_regular(&grid, &ax.axes, NC, values, NULL, NULL, NULL),
                     0);
    fit = prototype(grid, m, auto_options, 2, NULL);
    assert_int_equal(brdffit_fit_many(fit, n, values, NULL, &r->out, NULL, NULL), 0);
    for (i = 0; i < n; i++) {
        double q[NV];
        assert_int_equal(r->status[i], BRDFFIT_OK);
        assert_int_equal(brdffit_grid_create_regular(&one, &ax.axes, NC, values + i * ns * NC,
                                                     NULL, NULL, NULL),
                         0);
        assert_int_equal(brdffit_fit_create(&single, one, m, NULL, NULL), 0);
        assert_int_equal(brdffit_fit_run(single), 0);
        assert_int_equal(brdffit_fit_params(single, q), 0);
        assert_memory_equal(q, r->params + i * NV, sizeof q);
        brdffit_fit_destroy(single);
        brdffit_grid_destroy(one);
    }
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(m);
    free(values), free(r);
}

/* ---- progress and cancel ----------------------------------------------------------------- */

typedef struct progress_log {
    size_t calls, last, total, cancel_at;
    int monotonic;
    brdffit_fit *cancel_fit; /* cancel through brdffit_fit_cancel() instead */
} progress_log;

static int on_progress(void *user, size_t done, size_t total)
{
    progress_log *log = user;
    if (log->calls > 0 && done <= log->last) log->monotonic = 0;
    log->calls++;
    log->last = done;
    log->total = total;
    if (log->cancel_at != 0 && done >= log->cancel_at) {
        if (log->cancel_fit == NULL) return 1;
        brdffit_fit_cancel(log->cancel_fit);
    }
    return 0;
}

typedef struct batch_fixture {
    geometry g;
    brdffit_model *m;
    double *values;
    brdffit_grid *grid;
    size_t n;
} batch_fixture;

static void fixture_make(batch_fixture *f, size_t n)
{
    make_geometry(&f->g, 7);
    f->m = make_model();
    f->n = n;
    f->values = make_values(f->m, &f->g, n, 0.02);
    f->grid = scattered(&f->g, f->values, NULL, NULL);
}

static void fixture_free(batch_fixture *f)
{
    brdffit_grid_destroy(f->grid);
    brdffit_model_destroy(f->m);
    free(f->values);
}

static void test_progress(void **state)
{
    batch_fixture f;
    results *r = new_results();
    progress_log log;
    brdffit_fit *fit;
    (void)state;
    fixture_make(&f, 10);
    fit = prototype(f.grid, f.m, auto_options, 1, NULL);
    memset(&log, 0, sizeof log);
    log.monotonic = 1;
    assert_int_equal(brdffit_fit_many(fit, f.n, f.values, NULL, &r->out, on_progress, &log), 0);
    /* one thread, 10 items: every item reported, once each */
    assert_int_equal(log.calls, 10);
    assert_int_equal(log.last, 10);
    assert_int_equal(log.total, 10);
    assert_true(log.monotonic);
    brdffit_fit_destroy(fit);
    fit = prototype(f.grid, f.m, auto_options, 2, NULL);
    memset(&log, 0, sizeof log);
    log.monotonic = 1;
    assert_int_equal(brdffit_fit_many(fit, f.n, f.values, NULL, &r->out, on_progress, &log), 0);
    assert_true(log.calls >= 1 && log.calls <= 10);
    assert_int_equal(log.last, 10);
    assert_true(log.monotonic);
    brdffit_fit_destroy(fit);
    fixture_free(&f);
    free(r);
}

/* Cancel from the progress callback's return value or brdffit_fit_cancel(). */
static void check_cancel(size_t threads, int through_fit)
{
    batch_fixture f;
    results *r = new_results(), *ref = new_results();
    progress_log log;
    brdffit_fit *fit;
    size_t i, n = 600; /* progress every 3 items */
    fixture_make(&f, n);
    fit = prototype(f.grid, f.m, auto_options, threads, NULL);
    memset(&log, 0, sizeof log);
    log.cancel_at = 3;
    log.cancel_fit = through_fit ? fit : NULL;
    assert_int_equal(brdffit_fit_many(fit, n, f.values, NULL, &r->out, on_progress, &log), 0);
    /* one thread stops exactly there; with two, the other thread finishes
     * what it has begun and takes no new item once it sees the request,
     * however late the scheduler lets it see it: far fewer than all */
    if (threads == 1) assert_int_equal(r->out.n_run, 3);
    assert_true(r->out.n_run >= 3 && r->out.n_run < n / 2);
    for (i = 0; i < n; i++) {
        if (i < r->out.n_run) {
            single_fit(f.m, &f.g, f.values, NULL, auto_options, ref, i);
            assert_same_item(r, ref, i);
        } else {
            assert_int_equal(r->status[i], BRDFFIT_E_NOT_READY);
            assert_true(isnan(r->params[i * NV]) && isnan(r->cost[i]));
        }
    }
    /* the request was consumed: the next call runs every item */
    assert_int_equal(brdffit_fit_many(fit, 5, f.values, NULL, &r->out, NULL, NULL), 0);
    assert_int_equal(r->out.n_run, 5);
    brdffit_fit_destroy(fit);
    fixture_free(&f);
    free(r), free(ref);
}

static void test_cancel(void **state)
{
    (void)state;
    check_cancel(1, 0);
    check_cancel(1, 1);
    check_cancel(2, 0);
    check_cancel(2, 1);
}

/* ---- arguments ------------------------------------------------------------------------------ */

static void test_bad_arguments(void **state)
{
    batch_fixture f;
    results *r = new_results();
    brdffit_fit *fit;
    brdffit_many_out small;
    double before[NV], after[NV];
    (void)state;
    fixture_make(&f, 2);
    fit = prototype(f.grid, f.m, auto_options, 1, NULL);
    assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_params(fit, before), 0);
    assert_int_equal(brdffit_fit_many(NULL, 1, f.values, NULL, &r->out, NULL, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_many((brdffit_fit *)(void *)f.grid, 1, f.values, NULL, &r->out,
                                      NULL, NULL),
                     BRDFFIT_E_BAD_HANDLE);
    assert_int_equal(brdffit_fit_many(fit, 1, f.values, NULL, NULL, NULL, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_true(strlen(brdffit_fit_message(fit)) > 0);
    small = r->out;
    small.struct_size = sizeof(size_t);
    assert_int_equal(brdffit_fit_many(fit, 1, f.values, NULL, &small, NULL, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_many(fit, 1, NULL, NULL, &r->out, NULL, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_many(fit, SIZE_MAX / 16, f.values, NULL, &r->out, NULL, NULL),
                     BRDFFIT_E_TOO_LARGE);
    assert_non_null(strstr(brdffit_fit_message(fit), "too many"));
    r->out.n_run = 99;
    assert_int_equal(brdffit_fit_many(fit, 0, NULL, NULL, &r->out, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(r->out.n_run, 0);
    assert_string_equal(brdffit_fit_message(fit), "");
    /* every output may be NULL */
    memset(&small, 0, sizeof small);
    small.struct_size = sizeof small;
    assert_int_equal(brdffit_fit_many(fit, 2, f.values, NULL, &small, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(small.n_run, 2);
    /* the prototype's own result is untouched */
    assert_int_equal(brdffit_fit_params(fit, after), 0);
    assert_memory_equal(before, after, sizeof before);
    brdffit_fit_destroy(fit);
    fixture_free(&f);
    free(r);
}

/* ---- allocation failures --------------------------------------------------------------------- */

static void test_allocation_failures(void **state)
{
    batch_fixture f;
    results *ref = new_results(), *r = new_results();
    counting_alloc ca;
    brdffit_fit *fit;
    size_t n = 3, point, i, fatal = 0, per_item = 0;
    (void)state;
    fixture_make(&f, n);
    counting_alloc_init(&ca, 0);
    fit = prototype(f.grid, f.m, auto_options, 1, &ca.hook);
    assert_int_equal(brdffit_fit_many(fit, n, f.values, NULL, &ref->out, NULL, NULL), 0);
    for (point = 1; point < 1000; point++) {
        size_t base = ca.allocs, live = ca.live;
        brdffit_status st;
        ca.fail_at = base + point;
        st = brdffit_fit_many(fit, n, f.values, NULL, &r->out, NULL, NULL);
        ca.fail_at = 0;
        assert_int_equal(ca.live, live);
        if (st == BRDFFIT_E_OUT_OF_MEMORY) {
            fatal++;
            assert_non_null(strstr(brdffit_fit_message(fit), "out of memory"));
            continue;
        }
        assert_int_equal(st, BRDFFIT_OK);
        assert_int_equal(r->out.n_run, n);
        for (i = 0; i < n; i++) {
            if (r->status[i] == BRDFFIT_E_OUT_OF_MEMORY) {
                per_item++;
                assert_true(isnan(r->params[i * NV]));
            } else {
                assert_same_item(r, ref, i);
            }
        }
        if (ca.allocs - base < point) break; /* no failure was reached: swept */
    }
    assert_true(point < 1000);
    assert_true(fatal >= 3);    /* the workers array, the buffers, the private fit */
    assert_true(per_item >= 3); /* inside each item's run */
    brdffit_fit_destroy(fit);
    assert_int_equal(ca.live, 0);
    fixture_free(&f);
    free(ref), free(r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_auto_equals_single_fits),
        cmocka_unit_test(test_joint_options_equal_single_fits),
        cmocka_unit_test(test_auto_settings_equal_single_fits),
        cmocka_unit_test(test_auto_variants_equal_single_fits),
        cmocka_unit_test(test_bad_items),
        cmocka_unit_test(test_bad_item_statuses),
        cmocka_unit_test(test_regular_grid),
        cmocka_unit_test(test_progress),
        cmocka_unit_test(test_cancel),
        cmocka_unit_test(test_bad_arguments),
        cmocka_unit_test(test_allocation_failures),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
