/* Allocation failures, in one place, for every public function that
 * allocates: the Nth allocation fails for N = 1, 2, ... until the call
 * succeeds. Every failure must return exactly BRDFFIT_E_OUT_OF_MEMORY,
 * leave no output behind, leak nothing (the counting allocator has no live
 * block once the objects made are destroyed), and leave the handle it
 * worked on usable: the same call on the same handle, with the allocator
 * no longer failing, succeeds and gives exactly the result of a call that
 * never saw a failure. A function documented to allocate nothing is swept
 * too, and must not call the allocator.
 *
 * The number of allocation points of each sweep is printed at the end. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit_fixtures.h"
#include "grid_fixtures.h"
#include "optim_problems.h"
#include "rgl_writer.h"
#include "test_support.h"

/* ---- the sweep ------------------------------------------------------------------------------ */

/* One function under test. ctx holds its inputs, its output and the
 * reference output made without the failing allocator. */
typedef struct sweep_ops {
    const char *name;
    /* NULL, or make the handles the call works on, through ca (which does
     * not fail while setup runs). */
    void (*setup)(void *ctx, counting_alloc *ca);
    /* The call; ca is the allocator for everything it makes. On failure it
     * checks that no output was left behind and the message. */
    brdffit_status (*call)(void *ctx, counting_alloc *ca);
    /* After a success: compare the output with the reference. */
    void (*check)(void *ctx);
    /* Destroy what setup and call made (outputs may be NULL). */
    void (*teardown)(void *ctx);
    int allocates; /* 0: the call must not allocate at all */
} sweep_ops;

#define SWEEP_MAX 500
#define MAX_RECORDS 64

static struct {
    const char *name;
    size_t points;
} records[MAX_RECORDS];
static size_t n_records;

static void record(const char *name, size_t points)
{
    if (n_records < MAX_RECORDS) {
        records[n_records].name = name;
        records[n_records].points = points;
        n_records++;
    }
}

/* Runs the sweep and returns the number of allocation points covered. */
static size_t sweep(const sweep_ops *ops, void *ctx)
{
    size_t n;
    for (n = 1; n <= SWEEP_MAX; n++) {
        counting_alloc ca;
        size_t base;
        brdffit_status st;
        counting_alloc_init(&ca, 0);
        if (ops->setup != NULL) ops->setup(ctx, &ca);
        base = ca.allocs;
        ca.fail_at = base + n;
        st = ops->call(ctx, &ca);
        ca.fail_at = 0;
        if (st == BRDFFIT_OK) {
            if (ca.allocs - base != n - 1)
                fail_msg("%s: %zu allocations on success after %zu points", ops->name,
                         ca.allocs - base, n - 1);
            ops->check(ctx);
            ops->teardown(ctx);
            assert_int_equal(ca.live, 0);
            if (ops->allocates && n == 1) fail_msg("%s: made no allocation", ops->name);
            record(ops->name, n - 1);
            return n - 1;
        }
        if (!ops->allocates) fail_msg("%s: failed with %s", ops->name, brdffit_status_name(st));
        if (st != BRDFFIT_E_OUT_OF_MEMORY)
            fail_msg("%s: allocation %zu failed, returned %s", ops->name, n,
                     brdffit_status_name(st));
        st = ops->call(ctx, &ca);
        if (st != BRDFFIT_OK)
            fail_msg("%s: after allocation %zu failed, the retry returned %s", ops->name, n,
                     brdffit_status_name(st));
        ops->check(ctx);
        ops->teardown(ctx);
        if (ca.live != 0) fail_msg("%s: %zu blocks leaked at point %zu", ops->name, ca.live, n);
    }
    fail_msg("%s: still failing after %d allocations", ops->name, SWEEP_MAX);
    return 0;
}

/* A creation function's failure: no object, and the error record filled. */
static void check_create_failure(brdffit_status st, const void *out, const brdffit_error *err)
{
    if (st == BRDFFIT_OK) return;
    assert_null(out);
    assert_int_equal(err->status, st);
    assert_true(err->message[0] != '\0');
}

/* ---- grids ---------------------------------------------------------------------------------- */

static void assert_grids_equal(const brdffit_grid *a, const brdffit_grid *b)
{
    size_t n = brdffit_grid_sample_count(b), nc = brdffit_grid_channel_count(b), c, s;
    assert_non_null(a);
    assert_int_equal(brdffit_grid_get_kind(a), brdffit_grid_get_kind(b));
    assert_int_equal(brdffit_grid_sample_count(a), n);
    assert_int_equal(brdffit_grid_channel_count(a), nc);
    assert_int_equal(brdffit_grid_missing_count(a), brdffit_grid_missing_count(b));
    for (c = 0; c < nc; c++) {
        const double *va, *vb;
        assert_int_equal(brdffit_grid_values(a, c, &va), BRDFFIT_OK);
        assert_int_equal(brdffit_grid_values(b, c, &vb), BRDFFIT_OK);
        assert_memory_equal(va, vb, n * sizeof *va);
        for (s = 0; s < n; s++)
            assert_int_equal(brdffit_grid_is_missing(a, s, c), brdffit_grid_is_missing(b, s, c));
    }
    for (s = 0; s < n; s++) {
        double ta[4], tb[4];
        assert_int_equal(brdffit_grid_sample_angles(a, s, &ta[0], &ta[1], &ta[2], &ta[3]),
                         BRDFFIT_OK);
        assert_int_equal(brdffit_grid_sample_angles(b, s, &tb[0], &tb[1], &tb[2], &tb[3]),
                         BRDFFIT_OK);
        assert_memory_equal(ta, tb, sizeof ta);
    }
}

/* Inputs shared by every sweep, made once. */
#define N_SCATTERED 40
typedef struct inputs {
    fx_tempdir dir;
    char csv_path[512], merl_path[512], astm_path[512], rgl_path[512];
    fx_axes axes;        /* 6 x 8 x 7, for the fits too */
    fx_axes merl_axes;   /* resampling axes of the MERL loads */
    double *values;      /* 3 channels over axes */
    unsigned char *mask; /* some values missing */
    char *csv;           /* the grid with its missing values as CSV text */
    char *csv_scattered; /* a scattered CSV text */
    unsigned char *merl; /* a complete MERL file image, mostly unmeasured */
    char *astm;          /* an ASTM E1392 text */
    unsigned char *rgl;  /* a small RGL .bsdf file */
    size_t rgl_size;
    double ti[N_SCATTERED], pi[N_SCATTERED], to[N_SCATTERED], po[N_SCATTERED];
    double sc_values[2 * N_SCATTERED], sc_weights[N_SCATTERED];
    brdffit_grid *regular;   /* from values, no mask */
    brdffit_grid *scattered; /* from the scattered arrays */
    brdffit_grid *fit_grid;  /* ashikhmin-shirley data over axes */
    brdffit_model *model;    /* ashikhmin-shirley */
} inputs;

static const char *const file_names[] = {"grid.csv", "merl.binary", "scan.astm", "m.bsdf"};

static const char astm_text[] = "SOURCE \"sweep\"\nNUM_POINTS 4\n"
                                "VARS theta_i,phi_i,theta_s,phi_s,R,G\n"
                                "10,0,20,180,0.5,-0.01\n30,0,40,90,0.125,nan\n"
                                "0,0,0,0,1,2\n60,0,-10,45,0.75,0.5\n";

static double rgl_material(const double wi[3], const double wo[3], size_t c)
{
    (void)wi;
    return 0.1 + 0.05 * (double)c + 0.2 * wo[2];
}

static unsigned char *make_rgl(size_t *size)
{
    fx_rgl_spec sp;
    memset(&sp, 0, sizeof sp);
    sp.n_theta = 2, sp.n_phi = 1, sp.theta_i[1] = 0.5;
    sp.nx = 4, sp.ny = 3, sp.nc = 3, sp.rgb = 1, sp.jacobian = 1, sp.brdf = rgl_material;
    return fx_rgl_file(&sp, size);
}

/* Measured only in a band of cells, so the scattered grid stays small. */
static double merl_sparse(double theta_h, double theta_d, double phi_d, int channel)
{
    if (theta_d > 0.5 || phi_d > 0.2) return -1.0;
    return 0.2 + 0.1 * channel + cos(theta_h) + 0.01 * phi_d;
}

static char *scattered_csv(void)
{
    static const char text[] = "# scattered\ntheta_i,phi_i,theta_o,phi_o,r,g\n"
                               "10,180,20,0,0.5,0.25\n"
                               "30,180,40,90,0.125,nan\n"
                               "0,0,0,0,1,2\n"
                               "60,-90,10,45,0.75,0.5\n"
                               "85,170,85,350,0.01,0\n";
    char *s = malloc(sizeof text);
    if (s != NULL) memcpy(s, text, sizeof text);
    return s;
}

static void make_scattered_arrays(inputs *in)
{
    size_t s;
    for (s = 0; s < N_SCATTERED; s++) {
        in->ti[s] = DEG(2.0 * (double)s);
        in->pi[s] = DEG(180.0 - 3.0 * (double)s);
        in->to[s] = DEG(85.0 - 2.0 * (double)s);
        in->po[s] = DEG(7.0 * (double)s);
        in->sc_values[2 * s] = 0.1 + 0.01 * (double)s;
        in->sc_values[2 * s + 1] = 0.3;
        in->sc_weights[s] = 1.0 + (double)(s % 3);
    }
}

static int group_setup(void **state)
{
    static const double ti[] = {0, 15, 30, 45, 60, 75};
    static const double to[] = {0, 10, 20, 30, 40, 50, 60, 70};
    static const double po[] = {0, 30, 60, 90, 120, 150, 180};
    static const double mti[] = {0, 40, 80}, mto[] = {5, 45}, mpo[] = {0, 90, 180};
    static const double as_params[5] = {120.0, 0.3, 0.2, 0.5, 0.4}; /* ns, cd, cs */
    inputs *in = calloc(1, sizeof *in);
    size_t n, k;
    assert_non_null(in);
    fx_axes_set(&in->axes, ti, 6, to, 8, po, 7);
    fx_axes_set(&in->merl_axes, mti, 3, mto, 2, mpo, 3);
    n = 6 * 8 * 7 * 3;
    in->values = fx_values(&in->axes.axes, 3);
    in->mask = calloc(n, 1);
    assert_non_null(in->values);
    assert_non_null(in->mask);
    for (k = 0; k < n; k += 17) in->mask[k] = 1;
    in->csv = fx_csv_regular(&in->axes, 3, in->values, in->mask, "nan", 1);
    in->csv_scattered = scattered_csv();
    in->merl = fx_merl_image(merl_sparse, 90, 90, 180);
    assert_non_null(in->csv);
    assert_non_null(in->csv_scattered);
    assert_non_null(in->merl);
    assert_true(fx_tempdir_make(&in->dir));
    fx_tempdir_path(&in->dir, file_names[0], in->csv_path, sizeof in->csv_path);
    fx_tempdir_path(&in->dir, file_names[1], in->merl_path, sizeof in->merl_path);
    assert_true(fx_write_file(in->csv_path, in->csv, strlen(in->csv)));
    assert_true(fx_write_file(in->merl_path, in->merl, FX_MERL_SIZE));
    in->astm = malloc(sizeof astm_text);
    in->rgl = make_rgl(&in->rgl_size);
    assert_non_null(in->astm);
    assert_non_null(in->rgl);
    memcpy(in->astm, astm_text, sizeof astm_text);
    fx_tempdir_path(&in->dir, file_names[2], in->astm_path, sizeof in->astm_path);
    fx_tempdir_path(&in->dir, file_names[3], in->rgl_path, sizeof in->rgl_path);
    assert_true(fx_write_file(in->astm_path, in->astm, strlen(in->astm)));
    assert_true(fx_write_file(in->rgl_path, in->rgl, in->rgl_size));
    make_scattered_arrays(in);
    assert_int_equal(
        brdffit_grid_create_regular(&in->regular, &in->axes.axes, 3, in->values, NULL, NULL, NULL),
        BRDFFIT_OK);
    assert_int_equal(brdffit_grid_create_scattered(&in->scattered, N_SCATTERED, in->ti, in->pi,
                                                   in->to, in->po, 2, in->sc_values, NULL,
                                                   in->sc_weights, NULL, NULL),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_model_create(&in->model, "ashikhmin-shirley", NULL, NULL), BRDFFIT_OK);
    in->fit_grid = fx_grid_from_model(in->model, as_params, 2, &in->axes.axes, 0.02, 7);
    assert_non_null(in->fit_grid);
    *state = in;
    return 0;
}

static int group_teardown(void **state)
{
    inputs *in = *state;
    size_t k;
    fx_tempdir_remove(&in->dir, file_names, 4);
    brdffit_grid_destroy(in->regular);
    brdffit_grid_destroy(in->scattered);
    brdffit_grid_destroy(in->fit_grid);
    brdffit_model_destroy(in->model);
    free(in->values);
    free(in->mask);
    free(in->csv);
    free(in->csv_scattered);
    free(in->merl);
    free(in->astm);
    free(in->rgl);
    free(in);
    printf("allocation-failure points per function:\n");
    for (k = 0; k < n_records; k++) printf("  %-52s %4zu\n", records[k].name, records[k].points);
    return 0;
}

/* ---- calls that make a grid: loaders, constructors, derived grids ------------------------- */

typedef brdffit_status (*make_fn)(const void *spec, brdffit_grid **out,
                                  const brdffit_allocator *a, brdffit_error *err);

/* One call to sweep: `make` with `spec`, its result and the reference made
 * without a failing allocator. */
typedef struct make_job {
    make_fn make;
    const void *spec;
    brdffit_grid *out, *ref;
    brdffit_error err;
} make_job;

static brdffit_status make_call(void *ctx, counting_alloc *ca)
{
    make_job *j = ctx;
    brdffit_status st = j->make(j->spec, &j->out, &ca->hook, &j->err);
    check_create_failure(st, j->out, &j->err);
    return st;
}

static void make_check(void *ctx)
{
    make_job *j = ctx;
    assert_grids_equal(j->out, j->ref);
}

static void make_teardown(void *ctx)
{
    make_job *j = ctx;
    brdffit_grid_destroy(j->out);
    j->out = NULL;
}

static void run_make(const char *name, make_fn make, const void *spec)
{
    make_job j;
    sweep_ops ops = {name, NULL, make_call, make_check, make_teardown, 1};
    memset(&j, 0, sizeof j);
    j.make = make;
    j.spec = spec;
    assert_int_equal(make(spec, &j.ref, NULL, &j.err), BRDFFIT_OK);
    sweep(&ops, &j);
    brdffit_grid_destroy(j.ref);
}

/* ---- loaders -------------------------------------------------------------------------------- */

typedef enum load_kind {
    LOAD_CSV,
    LOAD_CSV_BUFFER,
    LOAD_MERL,
    LOAD_MERL_BUFFER,
    LOAD_ASTM,
    LOAD_ASTM_BUFFER,
    LOAD_RGL,
    LOAD_RGL_BUFFER
} load_kind;

typedef struct load_spec {
    load_kind kind;
    const char *path;
    const void *data;
    size_t size;
    const brdffit_axes *axes;
} load_spec;

static brdffit_status load_with(const void *spec, brdffit_grid **out, const brdffit_allocator *a,
                                brdffit_error *err)
{
    const load_spec *k = spec;
    switch (k->kind) {
    case LOAD_CSV: return brdffit_load_csv(out, k->path, a, err);
    case LOAD_CSV_BUFFER: return brdffit_load_csv_buffer(out, k->data, k->size, a, err);
    case LOAD_MERL: return brdffit_load_merl(out, k->path, k->axes, a, err);
    case LOAD_MERL_BUFFER: return brdffit_load_merl_buffer(out, k->data, k->size, k->axes, a, err);
    case LOAD_ASTM: return brdffit_load_astm(out, k->path, a, err);
    case LOAD_ASTM_BUFFER: return brdffit_load_astm_buffer(out, k->data, k->size, a, err);
    case LOAD_RGL: return brdffit_load_rgl(out, k->path, k->axes, a, err);
    case LOAD_RGL_BUFFER: return brdffit_load_rgl_buffer(out, k->data, k->size, k->axes, a, err);
    }
    return BRDFFIT_E_INVALID_ARGUMENT;
}

static void test_loaders(void **state)
{
    inputs *in = *state;
    load_spec k;
    memset(&k, 0, sizeof k);
    k.kind = LOAD_CSV, k.path = in->csv_path;
    run_make("brdffit_load_csv (grid form, missing values)", load_with, &k);
    k.kind = LOAD_CSV_BUFFER, k.data = in->csv, k.size = strlen(in->csv);
    run_make("brdffit_load_csv_buffer (grid form, missing values)", load_with, &k);
    k.data = in->csv_scattered, k.size = strlen(in->csv_scattered);
    run_make("brdffit_load_csv_buffer (scattered form)", load_with, &k);
    k.kind = LOAD_MERL, k.path = in->merl_path, k.axes = &in->merl_axes.axes;
    run_make("brdffit_load_merl (resampled)", load_with, &k);
    k.kind = LOAD_MERL_BUFFER, k.data = in->merl, k.size = FX_MERL_SIZE, k.axes = NULL;
    run_make("brdffit_load_merl_buffer (scattered)", load_with, &k);
    k.axes = &in->merl_axes.axes;
    run_make("brdffit_load_merl_buffer (resampled)", load_with, &k);
    k.kind = LOAD_ASTM, k.path = in->astm_path, k.axes = NULL;
    run_make("brdffit_load_astm", load_with, &k);
    k.kind = LOAD_ASTM_BUFFER, k.data = in->astm, k.size = strlen(in->astm);
    run_make("brdffit_load_astm_buffer", load_with, &k);
    k.kind = LOAD_RGL, k.path = in->rgl_path;
    run_make("brdffit_load_rgl (as measured)", load_with, &k);
    k.kind = LOAD_RGL_BUFFER, k.data = in->rgl, k.size = in->rgl_size;
    run_make("brdffit_load_rgl_buffer (as measured)", load_with, &k);
    k.axes = &in->merl_axes.axes;
    run_make("brdffit_load_rgl_buffer (resampled)", load_with, &k);
}

/* ---- grid creation and derived grids -------------------------------------------------------- */

typedef enum grid_kind { MAKE_REGULAR, MAKE_SCATTERED, MAKE_MEAN, MAKE_CLEARCOAT } grid_kind;

typedef struct grid_spec {
    const inputs *in;
    grid_kind kind;
    const unsigned char *mask;
    const double *weights;
    const brdffit_grid *src;
} grid_spec;

static brdffit_status make_with(const void *spec, brdffit_grid **out, const brdffit_allocator *a,
                                brdffit_error *err)
{
    const grid_spec *k = spec;
    const inputs *in = k->in;
    switch (k->kind) {
    case MAKE_REGULAR:
        return brdffit_grid_create_regular(out, &in->axes.axes, 3, in->values, k->mask, a, err);
    case MAKE_SCATTERED:
        return brdffit_grid_create_scattered(out, N_SCATTERED, in->ti, in->pi, in->to, in->po, 2,
                                             in->sc_values, k->mask, k->weights, a, err);
    case MAKE_MEAN: return brdffit_grid_channel_mean(out, k->src, a, err);
    case MAKE_CLEARCOAT: return brdffit_grid_clearcoat(out, k->src, 0.04, a, err);
    }
    return BRDFFIT_E_INVALID_ARGUMENT;
}

static void test_grids(void **state)
{
    inputs *in = *state;
    unsigned char sc_mask[2 * N_SCATTERED] = {0};
    grid_spec k;
    memset(&k, 0, sizeof k);
    k.in = in;
    sc_mask[3] = sc_mask[10] = 1;
    k.kind = MAKE_REGULAR;
    run_make("brdffit_grid_create_regular", make_with, &k);
    k.mask = in->mask;
    run_make("brdffit_grid_create_regular (missing values)", make_with, &k);
    k.kind = MAKE_SCATTERED, k.mask = NULL;
    run_make("brdffit_grid_create_scattered", make_with, &k);
    k.mask = sc_mask, k.weights = in->sc_weights;
    run_make("brdffit_grid_create_scattered (missing, weights)", make_with, &k);
    k.kind = MAKE_MEAN, k.src = in->regular;
    run_make("brdffit_grid_channel_mean (regular)", make_with, &k);
    k.src = in->scattered;
    run_make("brdffit_grid_channel_mean (scattered, weights)", make_with, &k);
    k.kind = MAKE_CLEARCOAT, k.src = in->regular;
    run_make("brdffit_grid_clearcoat (regular)", make_with, &k);
    k.src = in->scattered;
    run_make("brdffit_grid_clearcoat (scattered, weights)", make_with, &k);
}

/* brdffit_grid_weights allocates through the grid's own allocator. */
typedef struct weights_ctx {
    grid_spec make;
    unsigned flags;
    brdffit_grid *grid;
    double out[6 * 8 * 7], ref[6 * 8 * 7];
    brdffit_error err;
} weights_ctx;

static void weights_setup(void *ctx, counting_alloc *ca)
{
    weights_ctx *k = ctx;
    assert_int_equal(make_with(&k->make, &k->grid, &ca->hook, &k->err), BRDFFIT_OK);
}

static brdffit_status weights_call(void *ctx, counting_alloc *ca)
{
    weights_ctx *k = ctx;
    brdffit_status st;
    (void)ca;
    st = brdffit_grid_weights(k->grid, DEG(65.0), k->flags, k->out, &k->err);
    if (st != BRDFFIT_OK) assert_int_equal(k->err.status, st);
    return st;
}

static void weights_check(void *ctx)
{
    weights_ctx *k = ctx;
    assert_memory_equal(k->out, k->ref, brdffit_grid_sample_count(k->grid) * sizeof(double));
}

static void weights_teardown(void *ctx)
{
    weights_ctx *k = ctx;
    brdffit_grid_destroy(k->grid);
    k->grid = NULL;
}

static void run_weights(const char *name, weights_ctx *k, int allocates)
{
    sweep_ops ops = {name, weights_setup, weights_call, weights_check, weights_teardown, allocates};
    brdffit_grid *g = NULL;
    assert_int_equal(make_with(&k->make, &g, NULL, &k->err), BRDFFIT_OK);
    assert_int_equal(brdffit_grid_weights(g, DEG(65.0), k->flags, k->ref, NULL), BRDFFIT_OK);
    brdffit_grid_destroy(g);
    sweep(&ops, k);
}

static void test_grid_weights(void **state)
{
    inputs *in = *state;
    weights_ctx k;
    memset(&k, 0, sizeof k);
    k.make.in = in;
    k.make.kind = MAKE_REGULAR;
    k.flags = BRDFFIT_WEIGHT_DEFAULT;
    run_weights("brdffit_grid_weights (regular)", &k, 1);
    k.make.kind = MAKE_SCATTERED, k.make.weights = in->sc_weights;
    run_weights("brdffit_grid_weights (scattered)", &k, 0);
}

/* ---- models --------------------------------------------------------------------------------- */

static int destroyed;

static void count_destroy(void *user)
{
    (void)user;
    destroyed++;
}

static brdffit_status lambert_eval(const brdffit_batch *b, const double *params, size_t nc,
                                   double *values, double *jac, void *user)
{
    size_t s, c;
    (void)user;
    for (c = 0; c < nc; c++)
        for (s = 0; s < b->n; s++) {
            values[c * b->n + s] = params[c] / 3.14159265358979323846;
            if (jac != NULL) jac[c * b->n + s] = 1.0 / 3.14159265358979323846;
        }
    return BRDFFIT_OK;
}

typedef struct model_ctx {
    int custom;
    brdffit_model *out;
    brdffit_error err;
} model_ctx;

static const brdffit_param_info custom_params[] = {
    {"albedo", BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR, 0.0, 1.0, 0.5}};

static brdffit_status model_call(void *ctx, counting_alloc *ca)
{
    model_ctx *k = ctx;
    brdffit_status st;
    if (k->custom) {
        brdffit_model_def def = BRDFFIT_MODEL_DEF_INIT;
        def.name = "my-lambert";
        def.n_params = 1;
        def.params = custom_params;
        def.eval = lambert_eval;
        def.destroy = count_destroy;
        st = brdffit_model_create_custom(&k->out, &def, &ca->hook, &k->err);
        if (st != BRDFFIT_OK) assert_int_equal(destroyed, 0);
    } else {
        st = brdffit_model_create(&k->out, "ggx-2", &ca->hook, &k->err);
    }
    check_create_failure(st, k->out, &k->err);
    return st;
}

static void model_check(void *ctx)
{
    model_ctx *k = ctx;
    const brdffit_param_info *p = brdffit_model_param(k->out, 0);
    assert_non_null(p);
    assert_string_equal(brdffit_model_name(k->out), k->custom ? "my-lambert" : "ggx-2");
    assert_string_equal(p->name, k->custom ? "albedo" : "a1");
}

static void model_teardown(void *ctx)
{
    model_ctx *k = ctx;
    if (k->out != NULL) {
        brdffit_model_destroy(k->out);
        if (k->custom) assert_int_equal(destroyed, 1);
    }
    destroyed = 0;
    k->out = NULL;
}

static void test_model_create(void **state)
{
    model_ctx k;
    sweep_ops ops = {"brdffit_model_create", NULL, model_call, model_check, model_teardown, 1};
    (void)state;
    memset(&k, 0, sizeof k);
    sweep(&ops, &k);
    ops.name = "brdffit_model_create_custom";
    k.custom = 1;
    sweep(&ops, &k);
}

/* Evaluation and the Jacobian check allocate through the model's allocator. */
typedef enum eval_kind { EVAL_ANGLES, EVAL_GRID, EVAL_CHECK, EVAL_ALBEDO, EVAL_LOG } eval_kind;

#define EVAL_N 12
typedef struct eval_ctx {
    const inputs *in;
    eval_kind kind;
    brdffit_model *model;
    double params[5];
    double values[2 * EVAL_N], jac[3 * 2 * EVAL_N], ref[2 * EVAL_N], ref_jac[3 * 2 * EVAL_N];
    brdffit_jacobian_report report, ref_report;
    brdffit_error err;
} eval_ctx;

static void eval_setup(void *ctx, counting_alloc *ca)
{
    eval_ctx *k = ctx;
    assert_int_equal(brdffit_model_create(&k->model, "ashikhmin-shirley", &ca->hook, NULL),
                     BRDFFIT_OK);
}

static brdffit_status eval_with(eval_ctx *k, const brdffit_model *m, double *values, double *jac,
                                brdffit_jacobian_report *report)
{
    const inputs *in = k->in;
    switch (k->kind) {
    case EVAL_ANGLES:
        return brdffit_model_eval_angles(m, EVAL_N, in->ti, in->pi, in->to, in->po, 2, k->params,
                                         values, jac, &k->err);
    case EVAL_GRID:
        return brdffit_model_eval_grid(m, in->scattered, 3, EVAL_N, k->params, values, jac,
                                       &k->err);
    case EVAL_CHECK:
        report->struct_size = sizeof *report;
        return brdffit_model_check_jacobian(m, in->scattered, k->params, report, &k->err);
    case EVAL_ALBEDO:
        return brdffit_model_albedo(m, k->params, 2, in->ti, 2, 0, values, &k->err);
    case EVAL_LOG:
        return brdffit_model_log_error(m, in->scattered, k->params, 1.0, (size_t)-1, values,
                                       &k->err);
    }
    return BRDFFIT_E_INVALID_ARGUMENT;
}

static brdffit_status eval_call(void *ctx, counting_alloc *ca)
{
    eval_ctx *k = ctx;
    brdffit_status st;
    (void)ca;
    st = eval_with(k, k->model, k->values, k->jac, &k->report);
    if (st != BRDFFIT_OK) assert_int_equal(k->err.status, st);
    return st;
}

static void eval_check(void *ctx)
{
    eval_ctx *k = ctx;
    if (k->kind == EVAL_CHECK) {
        assert_memory_equal(&k->report, &k->ref_report, sizeof k->report);
        return;
    }
    assert_memory_equal(k->values, k->ref, sizeof k->values);
    assert_memory_equal(k->jac, k->ref_jac, sizeof k->jac);
}

static void eval_teardown(void *ctx)
{
    eval_ctx *k = ctx;
    brdffit_model_destroy(k->model);
    k->model = NULL;
}

static void run_eval(const char *name, eval_ctx *k, int allocates)
{
    sweep_ops ops = {name, eval_setup, eval_call, eval_check, eval_teardown, allocates};
    assert_int_equal(eval_with(k, k->in->model, k->ref, k->ref_jac, &k->ref_report), BRDFFIT_OK);
    sweep(&ops, k);
}

static void test_model_eval(void **state)
{
    eval_ctx k;
    memset(&k, 0, sizeof k);
    k.in = *state;
    k.params[0] = 80.0, k.params[1] = 0.3, k.params[2] = 0.2;
    k.params[3] = 0.6, k.params[4] = 0.5;
    k.kind = EVAL_ANGLES;
    run_eval("brdffit_model_eval_angles", &k, 1);
    k.kind = EVAL_GRID;
    run_eval("brdffit_model_eval_grid", &k, 0);
    k.kind = EVAL_CHECK;
    run_eval("brdffit_model_check_jacobian", &k, 1);
    k.kind = EVAL_ALBEDO;
    run_eval("brdffit_model_albedo", &k, 1);
    k.kind = EVAL_LOG;
    run_eval("brdffit_model_log_error", &k, 1);
}

/* ---- the optimizer -------------------------------------------------------------------------- */

typedef enum optim_kind {
    OPT_CREATE,
    OPT_SET_RESIDUALS,
    OPT_SET_NORMAL,
    OPT_SET_DAMPING,
    OPT_RUN_RESIDUALS,
    OPT_RUN_NORMAL
} optim_kind;

typedef struct optim_ctx {
    optim_kind kind;
    optim_fit_data data;
    optim_normal_adapter adapter;
    brdffit_optimizer *opt;
    double x[3], ref[3], se[3], ref_se[3];
    brdffit_error err;
} optim_ctx;

static const double exp_start[3] = {1.0, 1.0, 0.0};

static void state_init(void *state, double *lambda, void *user)
{
    (void)user;
    memset(state, 0, 64);
    *lambda = 1e-3;
}

static void state_accept(void *state, double rho, double *lambda, void *user)
{
    (void)state, (void)rho, (void)user;
    *lambda *= 0.5;
}

static void state_reject(void *state, double rho, double *lambda, void *user)
{
    (void)state, (void)rho, (void)user;
    *lambda *= 4.0;
}

static const brdffit_damping *stateful_policy(void)
{
    static const brdffit_damping policy = {
        sizeof(brdffit_damping), "stateful", 64, state_init, state_accept, state_reject, NULL};
    return &policy;
}

/* Give the problem in the form the kind uses. */
static brdffit_status set_problem(optim_ctx *k, brdffit_optimizer *opt)
{
    if (k->kind == OPT_SET_NORMAL || k->kind == OPT_RUN_NORMAL) {
        optim_normal_adapter_init(&k->adapter, optim_exp_fit, &k->data, k->data.n, 3);
        return brdffit_optimizer_set_normal(opt, k->data.n, optim_normal_adapter_fn, &k->adapter);
    }
    return brdffit_optimizer_set_residuals(opt, k->data.n, optim_exp_fit, &k->data);
}

static void optim_setup(void *ctx, counting_alloc *ca)
{
    optim_ctx *k = ctx;
    assert_int_equal(brdffit_optimizer_create(&k->opt, 3, &ca->hook, NULL), BRDFFIT_OK);
    if (k->kind == OPT_RUN_RESIDUALS || k->kind == OPT_RUN_NORMAL)
        assert_int_equal(set_problem(k, k->opt), BRDFFIT_OK);
}

/* Run from the standard start; the result goes to x and se. */
static brdffit_status optim_run(optim_ctx *k, brdffit_optimizer *opt, double *x, double *se)
{
    brdffit_status st;
    memcpy(x, exp_start, sizeof exp_start);
    st = brdffit_optimizer_run(opt, x);
    if (st == BRDFFIT_OK)
        assert_int_equal(brdffit_optimizer_std_errors(opt, se), BRDFFIT_OK);
    else
        assert_memory_equal(x, exp_start, sizeof exp_start);
    (void)k;
    return st;
}

static brdffit_status optim_call(void *ctx, counting_alloc *ca)
{
    optim_ctx *k = ctx;
    brdffit_status st;
    switch (k->kind) {
    case OPT_CREATE:
        st = brdffit_optimizer_create(&k->opt, 3, &ca->hook, &k->err);
        check_create_failure(st, k->opt, &k->err);
        return st;
    case OPT_SET_RESIDUALS:
    case OPT_SET_NORMAL: st = set_problem(k, k->opt); break;
    case OPT_SET_DAMPING: st = brdffit_optimizer_set_damping(k->opt, stateful_policy()); break;
    default: st = optim_run(k, k->opt, k->x, k->se); break;
    }
    if (st != BRDFFIT_OK) assert_true(brdffit_optimizer_message(k->opt)[0] != '\0');
    return st;
}

/* After set_* the optimizer must run as one that never saw a failure. */
static void optim_check(void *ctx)
{
    optim_ctx *k = ctx;
    if (k->kind == OPT_CREATE) {
        assert_int_equal(brdffit_optimizer_param_count(k->opt), 3);
        return;
    }
    if (k->kind == OPT_SET_RESIDUALS || k->kind == OPT_SET_NORMAL || k->kind == OPT_SET_DAMPING) {
        if (k->kind == OPT_SET_DAMPING) assert_int_equal(set_problem(k, k->opt), BRDFFIT_OK);
        assert_int_equal(optim_run(k, k->opt, k->x, k->se), BRDFFIT_OK);
    }
    assert_memory_equal(k->x, k->ref, sizeof k->x);
    assert_memory_equal(k->se, k->ref_se, sizeof k->se);
}

static void optim_teardown(void *ctx)
{
    optim_ctx *k = ctx;
    brdffit_optimizer_destroy(k->opt);
    k->opt = NULL;
}

static void run_optim(const char *name, optim_ctx *k, int allocates)
{
    sweep_ops ops = {name,           k->kind == OPT_CREATE ? NULL : optim_setup,
                     optim_call,     optim_check,
                     optim_teardown, allocates};
    brdffit_optimizer *opt = NULL;
    assert_int_equal(brdffit_optimizer_create(&opt, 3, NULL, NULL), BRDFFIT_OK);
    if (k->kind == OPT_SET_DAMPING)
        assert_int_equal(brdffit_optimizer_set_damping(opt, stateful_policy()), BRDFFIT_OK);
    assert_int_equal(set_problem(k, opt), BRDFFIT_OK);
    assert_int_equal(optim_run(k, opt, k->ref, k->ref_se), BRDFFIT_OK);
    assert_close(k->ref[0], k->data.truth[0], 0.2);
    brdffit_optimizer_destroy(opt);
    sweep(&ops, k);
}

static void test_optimizer(void **state)
{
    optim_ctx k;
    (void)state;
    memset(&k, 0, sizeof k);
    optim_make_exp_data(&k.data);
    k.kind = OPT_CREATE;
    run_optim("brdffit_optimizer_create", &k, 1);
    k.kind = OPT_SET_RESIDUALS;
    run_optim("brdffit_optimizer_set_residuals", &k, 1);
    k.kind = OPT_SET_NORMAL;
    run_optim("brdffit_optimizer_set_normal", &k, 0);
    k.kind = OPT_SET_DAMPING;
    run_optim("brdffit_optimizer_set_damping (64 bytes of state)", &k, 1);
    k.kind = OPT_RUN_RESIDUALS;
    run_optim("brdffit_optimizer_run (residual form)", &k, 1);
    k.kind = OPT_RUN_NORMAL;
    run_optim("brdffit_optimizer_run (normal form)", &k, 1);
}

/* ---- fits ----------------------------------------------------------------------------------- */

#define FIT_MAX 16
typedef struct fit_result {
    double params[FIT_MAX], se[FIT_MAX], errors[3];
    size_t iterations;
    brdffit_stop_reason stop;
} fit_result;

typedef struct fit_ctx {
    const inputs *in;
    int create_only;
    brdffit_pipeline pipeline;
    brdffit_objective objective;
    double threads, clearcoat;
    brdffit_fit *fit;
    fit_result ref;
    brdffit_error err;
} fit_ctx;

static void fit_configure(const fit_ctx *k, brdffit_fit *fit)
{
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, k->pipeline), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_THREADS, k->threads), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_CLEARCOAT, k->clearcoat), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, k->objective), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_MAX_ITERATIONS, 40), BRDFFIT_OK);
}

static void fit_read(const brdffit_fit *fit, fit_result *r)
{
    size_t m;
    memset(r, 0, sizeof *r);
    assert_true(brdffit_fit_param_count(fit) <= FIT_MAX);
    assert_int_equal(brdffit_fit_params(fit, r->params), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_std_errors(fit, r->se), BRDFFIT_OK);
    for (m = 0; m < 3; m++)
        assert_int_equal(
            brdffit_fit_error(fit, (brdffit_fit_metric)m, BRDFFIT_ALL_CHANNELS, &r->errors[m]),
            BRDFFIT_OK);
    r->iterations = brdffit_fit_iterations(fit);
    r->stop = brdffit_fit_stop_reason(fit);
}

static void fit_setup(void *ctx, counting_alloc *ca)
{
    fit_ctx *k = ctx;
    assert_int_equal(brdffit_fit_create(&k->fit, k->in->fit_grid, k->in->model, &ca->hook, NULL),
                     BRDFFIT_OK);
    fit_configure(k, k->fit);
}

static brdffit_status fit_call(void *ctx, counting_alloc *ca)
{
    fit_ctx *k = ctx;
    brdffit_status st;
    if (k->create_only) {
        st = brdffit_fit_create(&k->fit, k->in->fit_grid, k->in->model, &ca->hook, &k->err);
        check_create_failure(st, k->fit, &k->err);
        return st;
    }
    st = brdffit_fit_run(k->fit);
    if (st != BRDFFIT_OK) {
        double p[FIT_MAX];
        assert_true(brdffit_fit_message(k->fit)[0] != '\0');
        assert_int_equal(brdffit_fit_params(k->fit, p), BRDFFIT_E_NOT_READY);
    }
    return st;
}

static void fit_check(void *ctx)
{
    fit_ctx *k = ctx;
    fit_result r;
    if (k->create_only) {
        assert_int_equal(brdffit_fit_param_count(k->fit), 5);
        return;
    }
    fit_read(k->fit, &r);
    assert_memory_equal(&r, &k->ref, sizeof r);
}

static void fit_teardown(void *ctx)
{
    fit_ctx *k = ctx;
    brdffit_fit_destroy(k->fit);
    k->fit = NULL;
}

static void run_fit(const char *name, fit_ctx *k)
{
    sweep_ops ops = {name, k->create_only ? NULL : fit_setup, fit_call, fit_check, fit_teardown, 1};
    brdffit_fit *fit = NULL;
    assert_int_equal(brdffit_fit_create(&fit, k->in->fit_grid, k->in->model, NULL, NULL),
                     BRDFFIT_OK);
    fit_configure(k, fit);
    assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
    fit_read(fit, &k->ref);
    brdffit_fit_destroy(fit);
    assert_close(k->ref.params[0], 120.0, 0.2); /* the data's exponent */
    sweep(&ops, k);
}

static void test_fit(void **state)
{
    static const struct {
        const char *name;
        brdffit_pipeline pipeline;
        brdffit_objective objective;
        double threads, clearcoat;
    } runs[] = {
        {"brdffit_fit_run (auto, 1 thread)", BRDFFIT_PIPELINE_AUTO, BRDFFIT_OBJECTIVE_SQUARES, 1,
         0},
        {"brdffit_fit_run (auto, 2 threads)", BRDFFIT_PIPELINE_AUTO, BRDFFIT_OBJECTIVE_SQUARES, 2,
         0},
        {"brdffit_fit_run (joint, 1 thread)", BRDFFIT_PIPELINE_JOINT, BRDFFIT_OBJECTIVE_SQUARES, 1,
         0},
        {"brdffit_fit_run (joint, 2 threads)", BRDFFIT_PIPELINE_JOINT, BRDFFIT_OBJECTIVE_SQUARES, 2,
         0},
        {"brdffit_fit_run (two-stage, 1 thread)", BRDFFIT_PIPELINE_TWO_STAGE,
         BRDFFIT_OBJECTIVE_SQUARES, 1, 0},
        {"brdffit_fit_run (two-stage, 2 threads)", BRDFFIT_PIPELINE_TWO_STAGE,
         BRDFFIT_OBJECTIVE_SQUARES, 2, 0},
        {"brdffit_fit_run (auto, clear coat, 2 threads)", BRDFFIT_PIPELINE_AUTO,
         BRDFFIT_OBJECTIVE_SQUARES, 2, 0.04},
        /* the profile's colour passes and their shape cache */
        {"brdffit_fit_run (auto, cube root, 2 threads)", BRDFFIT_PIPELINE_AUTO,
         BRDFFIT_OBJECTIVE_CUBE_ROOT, 2, 0},
    };
    fit_ctx k;
    size_t r;
    memset(&k, 0, sizeof k);
    k.in = *state;
    k.create_only = 1;
    k.threads = 1;
    run_fit("brdffit_fit_create", &k);
    k.create_only = 0;
    for (r = 0; r < sizeof runs / sizeof runs[0]; r++) {
        k.pipeline = runs[r].pipeline;
        k.objective = runs[r].objective;
        k.threads = runs[r].threads;
        k.clearcoat = runs[r].clearcoat;
        run_fit(runs[r].name, &k);
    }
}

/* ---- pictures ------------------------------------------------------------------------------- */

typedef enum image_kind { IMG_TEXTURE, IMG_SPHERE_MEASURED, IMG_SPHERE_MODEL } image_kind;

#define SPHERE 24
typedef struct image_ctx {
    const inputs *in;
    image_kind kind;
    brdffit_texture_kind texture;
    double params[5];
    size_t width, height;
    unsigned char *pixels, *ref;
    brdffit_error err;
} image_ctx;

static brdffit_status draw(image_ctx *k, unsigned char *px, const brdffit_allocator *a)
{
    const inputs *in = k->in;
    switch (k->kind) {
    case IMG_TEXTURE:
        return brdffit_image_texture(px, 3 * k->width, k->texture, in->fit_grid, in->model,
                                     k->params, NULL, a, &k->err);
    case IMG_SPHERE_MEASURED:
        return brdffit_image_sphere_measured(px, 3 * SPHERE, SPHERE, in->fit_grid, 0.4, 0.5, NULL,
                                             a, &k->err);
    case IMG_SPHERE_MODEL:
        return brdffit_image_sphere_model(px, 3 * SPHERE, SPHERE, in->model, k->params, 2, 0.4, 0.5,
                                          NULL, a, &k->err);
    }
    return BRDFFIT_E_INVALID_ARGUMENT;
}

static brdffit_status image_call(void *ctx, counting_alloc *ca)
{
    image_ctx *k = ctx;
    brdffit_status st = draw(k, k->pixels, &ca->hook);
    if (st != BRDFFIT_OK) assert_int_equal(k->err.status, st);
    return st;
}

static void image_check(void *ctx)
{
    image_ctx *k = ctx;
    assert_memory_equal(k->pixels, k->ref, 3 * k->width * k->height);
}

static void image_teardown(void *ctx)
{
    (void)ctx;
}

static void run_image(const char *name, image_ctx *k)
{
    sweep_ops ops = {name, NULL, image_call, image_check, image_teardown, 1};
    if (k->kind == IMG_TEXTURE)
        assert_int_equal(
            brdffit_image_texture_size(k->in->fit_grid, NULL, &k->width, &k->height, NULL),
            BRDFFIT_OK);
    else
        k->width = k->height = SPHERE;
    k->pixels = calloc(3 * k->width * k->height, 1);
    k->ref = calloc(3 * k->width * k->height, 1);
    assert_non_null(k->pixels);
    assert_non_null(k->ref);
    assert_int_equal(draw(k, k->ref, NULL), BRDFFIT_OK);
    sweep(&ops, k);
    free(k->pixels);
    free(k->ref);
}

static void test_images(void **state)
{
    image_ctx k;
    memset(&k, 0, sizeof k);
    k.in = *state;
    k.params[0] = 100.0, k.params[1] = 0.3, k.params[2] = 0.2;
    k.params[3] = 0.5, k.params[4] = 0.4;
    k.kind = IMG_TEXTURE;
    k.texture = BRDFFIT_TEXTURE_MEASURED;
    run_image("brdffit_image_texture (measured)", &k);
    k.texture = BRDFFIT_TEXTURE_MODEL;
    run_image("brdffit_image_texture (model)", &k);
    k.texture = BRDFFIT_TEXTURE_DIFFERENCE;
    run_image("brdffit_image_texture (difference)", &k);
    k.kind = IMG_SPHERE_MEASURED;
    run_image("brdffit_image_sphere_measured", &k);
    k.kind = IMG_SPHERE_MODEL;
    run_image("brdffit_image_sphere_model", &k);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_loaders),      cmocka_unit_test(test_grids),
        cmocka_unit_test(test_grid_weights), cmocka_unit_test(test_model_create),
        cmocka_unit_test(test_model_eval),   cmocka_unit_test(test_optimizer),
        cmocka_unit_test(test_fit),          cmocka_unit_test(test_images),
    };
    return cmocka_run_group_tests(tests, group_setup, group_teardown);
}
