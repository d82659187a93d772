/* Do the fit's standard errors mean what they say? Data generated from
 * known Ashikhmin-Shirley parameters on a small grid (384 samples, one
 * channel), with fixed-seed noise: over DRAWS draws, the interval
 * estimate +- standard error of every free parameter must cover the true
 * value in 60 to 76 % of the draws (68 % expected) for the covariance
 * estimator the documentation recommends for the noise
 * (brdffit_fit_covariance()): the classic one for additive noise of one
 * level with uniform weights, the sandwich for multiplicative noise (and
 * for weights that do not follow the noise). The classic one under
 * multiplicative noise misses that range. Also: brdffit_fit_covariance()
 * agrees with the standard errors in every pipeline and objective, the
 * sandwich's meat equals the optimizer's own residual-form sandwich of
 * the same rows, held and undetermined parameters have the documented
 * rows, two-stage has its documented block structure, and bad input gets
 * its exact error code. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit_fixtures.h"
#include "test_support.h"

#define DRAWS 300
#define N_TI 8
#define N_TO 6
#define N_PO 8
#define N_SAMPLES (N_TI * N_TO * N_PO)
#define ADDITIVE 0.01       /* sd of the additive noise */
#define MULTIPLICATIVE 0.02 /* relative sd of the multiplicative noise */
#define MAXV 16

static const double PI = 3.14159265358979323846;

/* The geometry: theta_i 0 .. 70 deg every 10, theta_o 5 .. 65 every 12,
 * phi_o over half the circle; the directions as arrays for the model. */
typedef struct setup {
    double ti[N_TI], to[N_TO], po[N_PO];
    brdffit_axes axes;
    double ati[N_SAMPLES], api[N_SAMPLES], ato[N_SAMPLES], apo[N_SAMPLES];
    brdffit_model *model;
    size_t nc, nv;
    double truth[MAXV];
    double *clean; /* N_SAMPLES * nc interleaved values of the truth */
} setup;

static void setup_make(setup *s, const char *model, const double values[][8], size_t nc)
{
    size_t i, j, k, n = 0, c;
    double *planar;
    for (i = 0; i < N_TI; i++) s->ti[i] = (10.0 * (double)i) * PI / 180.0;
    for (i = 0; i < N_TO; i++) s->to[i] = (5.0 + 12.0 * (double)i) * PI / 180.0;
    for (i = 0; i < N_PO; i++) s->po[i] = (double)i * PI / (double)N_PO;
    s->axes.theta_i = s->ti;
    s->axes.n_theta_i = N_TI;
    s->axes.theta_o = s->to;
    s->axes.n_theta_o = N_TO;
    s->axes.phi_o = s->po;
    s->axes.n_phi_o = N_PO;
    for (i = 0; i < N_TI; i++)
        for (j = 0; j < N_TO; j++)
            for (k = 0; k < N_PO; k++, n++) {
                s->ati[n] = s->ti[i];
                s->api[n] = PI;
                s->ato[n] = s->to[j];
                s->apo[n] = s->po[k];
            }
    s->model = NULL;
    assert_int_equal(brdffit_model_create(&s->model, model, NULL, NULL), BRDFFIT_OK);
    s->nc = nc;
    s->nv = brdffit_model_vector_size(s->model, nc);
    assert_true(s->nv <= MAXV);
    fx_vector(s->model, nc, values, s->truth);
    planar = malloc(N_SAMPLES * nc * sizeof *planar);
    s->clean = malloc(N_SAMPLES * nc * sizeof *s->clean);
    assert_non_null(planar);
    assert_non_null(s->clean);
    assert_int_equal(brdffit_model_eval_angles(s->model, N_SAMPLES, s->ati, s->api, s->ato, s->apo,
                                               nc, s->truth, planar, NULL, NULL),
                     BRDFFIT_OK);
    for (n = 0; n < N_SAMPLES; n++)
        for (c = 0; c < nc; c++) s->clean[n * nc + c] = planar[c * N_SAMPLES + n];
    free(planar);
}

static void setup_free(setup *s)
{
    brdffit_model_destroy(s->model);
    free(s->clean);
}

/* Noisy values of the truth into values (N_SAMPLES * nc): additive of sd
 * ADDITIVE, or multiplicative value * (1 + MULTIPLICATIVE g), g standard
 * normal. */
static void noisy_values(const setup *s, int multiplicative, uint64_t *state, double *values)
{
    size_t i;
    for (i = 0; i < N_SAMPLES * s->nc; i++) {
        double g = fx_normal(state);
        values[i] =
            multiplicative ? s->clean[i] * (1.0 + MULTIPLICATIVE * g) : s->clean[i] + ADDITIVE * g;
    }
}

static brdffit_grid *make_grid(const setup *s, const double *values)
{
    brdffit_grid *grid = NULL;
    assert_int_equal(brdffit_grid_create_regular(&grid, &s->axes, s->nc, values, NULL, NULL, NULL),
                     BRDFFIT_OK);
    return grid;
}

/* The fit's options. */
typedef struct options {
    int pipeline;
    unsigned weighting;
    int objective;
    int sandwich;
} options;

/* A fit of the grid from the truth. */
static brdffit_fit *make_fit(const setup *s, const brdffit_grid *grid, const options *o)
{
    brdffit_fit *fit = NULL;
    assert_int_equal(brdffit_fit_create(&fit, grid, s->model, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, o->pipeline), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_WEIGHTING, o->weighting), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, o->objective), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_COVARIANCE, o->sandwich), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set_start(fit, s->truth), BRDFFIT_OK);
    return fit;
}

/* The covariance agrees with the standard errors as fit.h says: symmetric,
 * never NaN, diagonal = se^2 (HUGE_VAL and 0 exactly), 0 off the diagonal
 * in the rows of se 0 or HUGE_VAL, correlations within [-1, 1]. Returns
 * the number of entries with a positive finite standard error. */
static size_t check_consistent(const brdffit_fit *fit, const char *what)
{
    size_t n = brdffit_fit_param_count(fit), a, b, determined = 0;
    double se[MAXV], cov[MAXV * MAXV];
    assert_true(n <= MAXV);
    assert_int_equal(brdffit_fit_std_errors(fit, se), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_covariance(fit, cov), BRDFFIT_OK);
    for (a = 0; a < n; a++) {
        double d = cov[a * n + a];
        int finite = se[a] > 0.0 && se[a] < HUGE_VAL;
        if (finite ? !(fabs(sqrt(d) - se[a]) <= 1e-12 * se[a]) : d != se[a])
            print_error("%s: entry %zu: se %.17g, variance %.17g\n", what, a, se[a], d);
        if (finite)
            assert_true(fabs(sqrt(d) - se[a]) <= 1e-12 * se[a]);
        else
            assert_true(d == se[a]);
        determined += finite;
        for (b = 0; b < n; b++) {
            int other = se[b] > 0.0 && se[b] < HUGE_VAL;
            assert_false(isnan(cov[a * n + b]));
            assert_true(cov[a * n + b] == cov[b * n + a]);
            if (a != b && !finite) assert_true(cov[a * n + b] == 0.0);
            if (a != b && finite && other)
                assert_true(fabs(cov[a * n + b]) <= se[a] * se[b] * (1.0 + 1e-9));
        }
    }
    return determined;
}

/* Coverage of each entry's interval over DRAWS draws into cover; the
 * largest distance of a coverage from 0.68 is returned. */
static double coverage(const setup *s, int multiplicative, const options *o, double *cover)
{
    static const char *const objectives[] = {"squares", "log", "cube-root", "relative"};
    uint64_t state = multiplicative ? 20261202u : 14u;
    size_t hits[MAXV] = {0}, d, e;
    double values[N_SAMPLES], worst = 0.0;
    assert_int_equal(s->nc, 1);
    for (d = 0; d < DRAWS; d++) {
        brdffit_grid *grid;
        brdffit_fit *fit;
        double p[MAXV], se[MAXV];
        noisy_values(s, multiplicative, &state, values);
        grid = make_grid(s, values);
        fit = make_fit(s, grid, o);
        assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_params(fit, p), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_std_errors(fit, se), BRDFFIT_OK);
        if (d < 3) assert_int_equal(check_consistent(fit, "coverage"), s->nv);
        for (e = 0; e < s->nv; e++) {
            assert_true(se[e] > 0.0 && se[e] < HUGE_VAL);
            if (fabs(p[e] - s->truth[e]) <= se[e]) hits[e]++;
        }
        brdffit_fit_destroy(fit);
        brdffit_grid_destroy(grid);
    }
    printf("%s noise, %s objective, weighting %u, %s: coverage",
           multiplicative ? "multiplicative" : "additive", objectives[o->objective], o->weighting,
           o->sandwich ? "sandwich" : "classic");
    for (e = 0; e < s->nv; e++) {
        cover[e] = (double)hits[e] / DRAWS;
        worst = fmax(worst, fabs(cover[e] - 0.68));
        printf(" %s %.3f", brdffit_model_param(s->model, e)->name, cover[e]);
    }
    printf("\n");
    return worst;
}

/* Every entry's coverage within [0.60, 0.76]; the largest distance from
 * 0.68 returned. */
static double expect_calibrated(const setup *s, int multiplicative, const options *o)
{
    double cover[MAXV], worst = coverage(s, multiplicative, o, cover);
    size_t e;
    for (e = 0; e < s->nv; e++) {
        if (!(cover[e] >= 0.60 && cover[e] <= 0.76))
            print_error("%s: coverage %.3f outside [0.60, 0.76]\n",
                        brdffit_model_param(s->model, e)->name, cover[e]);
        assert_true(cover[e] >= 0.60 && cover[e] <= 0.76);
    }
    return worst;
}

/* Some entry's coverage outside [0.60, 0.76], and the worst distance from
 * 0.68 larger than `better` (another estimator's on the same draws). */
static void expect_miscalibrated(const setup *s, int multiplicative, const options *o,
                                 double better)
{
    double cover[MAXV], worst = coverage(s, multiplicative, o, cover);
    size_t e, outside = 0;
    for (e = 0; e < s->nv; e++) outside += !(cover[e] >= 0.60 && cover[e] <= 0.76);
    assert_true(outside > 0);
    assert_true(worst > better);
}

/* One channel: shape ns (log scale), colours cd and cs. */
static const double AS1[3][8] = {{40.0}, {0.3}, {0.4}};

/* Additive noise of one level, uniform weights, the squares objective:
 * the classic covariance's assumption holds; the sandwich holds too. */
static void test_additive_classic(void **state)
{
    setup s;
    const options classic = {BRDFFIT_PIPELINE_JOINT, BRDFFIT_WEIGHT_NONE, 0, 0};
    const options sandwich = {BRDFFIT_PIPELINE_JOINT, BRDFFIT_WEIGHT_NONE, 0, 1};
    (void)state;
    setup_make(&s, "ashikhmin-shirley", AS1, 1);
    expect_calibrated(&s, 0, &classic);
    expect_calibrated(&s, 0, &sandwich);
    setup_free(&s);
}

/* Multiplicative noise: the sandwich covers, with uniform and with the
 * default weights; the classic covariance does not. */
static void test_multiplicative_sandwich(void **state)
{
    setup s;
    const options classic = {BRDFFIT_PIPELINE_JOINT, BRDFFIT_WEIGHT_NONE, 0, 0};
    const options sandwich = {BRDFFIT_PIPELINE_JOINT, BRDFFIT_WEIGHT_NONE, 0, 1};
    const options weighted = {BRDFFIT_PIPELINE_JOINT, BRDFFIT_WEIGHT_DEFAULT, 0, 1};
    double best;
    (void)state;
    setup_make(&s, "ashikhmin-shirley", AS1, 1);
    best = expect_calibrated(&s, 1, &sandwich);
    expect_calibrated(&s, 1, &weighted);
    expect_miscalibrated(&s, 1, &classic, best);
    setup_free(&s);
}

/* Additive noise of one level under the default (solid-angle and cosine)
 * weights: the weighted residuals' spread varies, so the classic
 * covariance misses and the sandwich covers. */
static void test_weights_need_sandwich(void **state)
{
    setup s;
    const options classic = {BRDFFIT_PIPELINE_JOINT, BRDFFIT_WEIGHT_DEFAULT, 0, 0};
    const options sandwich = {BRDFFIT_PIPELINE_JOINT, BRDFFIT_WEIGHT_DEFAULT, 0, 1};
    double best;
    (void)state;
    setup_make(&s, "ashikhmin-shirley", AS1, 1);
    best = expect_calibrated(&s, 0, &sandwich);
    expect_miscalibrated(&s, 0, &classic, best);
    setup_free(&s);
}

/* The other objectives under multiplicative noise: the sandwich of their
 * own residuals covers for log and cube root; the relative objective's
 * residuals (M - R) / |R| have one spread, so its classic covariance
 * covers too. */
static void test_objectives(void **state)
{
    setup s;
    const options log_sandwich = {BRDFFIT_PIPELINE_JOINT, BRDFFIT_WEIGHT_NONE,
                                  BRDFFIT_OBJECTIVE_LOG, 1};
    const options cbrt_sandwich = {BRDFFIT_PIPELINE_JOINT, BRDFFIT_WEIGHT_NONE,
                                   BRDFFIT_OBJECTIVE_CUBE_ROOT, 1};
    const options relative_classic = {BRDFFIT_PIPELINE_JOINT, BRDFFIT_WEIGHT_NONE,
                                      BRDFFIT_OBJECTIVE_RELATIVE, 0};
    const options relative_sandwich = {BRDFFIT_PIPELINE_JOINT, BRDFFIT_WEIGHT_NONE,
                                       BRDFFIT_OBJECTIVE_RELATIVE, 1};
    (void)state;
    setup_make(&s, "ashikhmin-shirley", AS1, 1);
    expect_calibrated(&s, 1, &log_sandwich);
    expect_calibrated(&s, 1, &cbrt_sandwich);
    expect_calibrated(&s, 1, &relative_classic);
    expect_calibrated(&s, 1, &relative_sandwich);
    setup_free(&s);
}

/* ---- the sandwich against the optimizer's own ------------------------------ */

typedef struct rows {
    const setup *s;
    const double *values;
} rows;

/* r = M - R over every sample (all inside the default cap, uniform
 * weights), natural parameters, the model's own Jacobian. */
static brdffit_status model_rows(const double *x, double *r, double *jac, void *user)
{
    const rows *rw = user;
    const setup *s = rw->s;
    double vals[N_SAMPLES], J[3 * N_SAMPLES];
    size_t i, k;
    brdffit_status st = brdffit_model_eval_angles(s->model, N_SAMPLES, s->ati, s->api, s->ato,
                                                  s->apo, 1, x, vals, jac ? J : NULL, NULL);
    if (st != BRDFFIT_OK) return st;
    for (i = 0; i < N_SAMPLES; i++) {
        r[i] = vals[i] - rw->values[i];
        if (jac)
            for (k = 0; k < 3; k++) jac[i * 3 + k] = J[k * N_SAMPLES + i];
    }
    return BRDFFIT_OK;
}

/* The fit's covariance (normal equations over passes, ns in log space,
 * the meat from the per-row pass) equals the optimizer's over the same
 * rows in residual form (natural space, its own HC3), classic and
 * sandwich alike: the leverages and the delta method are invariant under
 * the change of variables. */
static void test_against_optimizer(void **state)
{
    setup s;
    uint64_t seed = 99;
    double values[N_SAMPLES];
    int sandwich;
    (void)state;
    setup_make(&s, "ashikhmin-shirley", AS1, 1);
    assert_int_equal(s.nv, 3);
    noisy_values(&s, 1, &seed, values);
    for (sandwich = 0; sandwich < 2; sandwich++) {
        const options o = {BRDFFIT_PIPELINE_JOINT, BRDFFIT_WEIGHT_NONE, 0, sandwich};
        brdffit_grid *grid = make_grid(&s, values);
        brdffit_fit *fit = make_fit(&s, grid, &o);
        brdffit_optimizer *opt = NULL;
        rows rw = {&s, values};
        double p[3], x[3], fcov[9], ocov[9];
        size_t a, b;
        assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_params(fit, p), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_covariance(fit, fcov), BRDFFIT_OK);
        assert_int_equal(brdffit_optimizer_create(&opt, 3, NULL, NULL), BRDFFIT_OK);
        assert_int_equal(brdffit_optimizer_set_residuals(opt, N_SAMPLES, model_rows, &rw),
                         BRDFFIT_OK);
        assert_int_equal(brdffit_optimizer_set(opt, BRDFFIT_OPT_COVARIANCE, sandwich), BRDFFIT_OK);
        memcpy(x, p, sizeof x);
        assert_int_equal(brdffit_optimizer_run(opt, x), BRDFFIT_OK);
        assert_int_equal(brdffit_optimizer_covariance(opt, ocov), BRDFFIT_OK);
        for (a = 0; a < 3; a++) assert_true(fabs(x[a] - p[a]) <= 1e-7 * fabs(p[a]));
        for (a = 0; a < 3; a++)
            for (b = 0; b < 3; b++) {
                double scale = sqrt(ocov[a * 3 + a] * ocov[b * 3 + b]);
                if (!(fabs(fcov[a * 3 + b] - ocov[a * 3 + b]) <= 1e-6 * scale))
                    print_error("%s: cov[%zu][%zu] fit %.12g optimizer %.12g\n",
                                sandwich ? "sandwich" : "classic", a, b, fcov[a * 3 + b],
                                ocov[a * 3 + b]);
                assert_true(fabs(fcov[a * 3 + b] - ocov[a * 3 + b]) <= 1e-6 * scale);
            }
        brdffit_optimizer_destroy(opt);
        brdffit_fit_destroy(fit);
        brdffit_grid_destroy(grid);
    }
    setup_free(&s);
}

/* ---- structure of the matrix ------------------------------------------------ */

static const double AS3[3][8] = {{40.0}, {0.30, 0.20, 0.10}, {0.40, 0.35, 0.30}};

/* Every pipeline, objective and estimator: consistent with the standard
 * errors, every entry determined; joint and auto couple the channels'
 * colours (through the shared shape), two-stage's blocks are apart; the
 * sandwich differs from the classic covariance. */
static void test_pipelines(void **state)
{
    static const int pipelines[] = {BRDFFIT_PIPELINE_AUTO, BRDFFIT_PIPELINE_JOINT,
                                    BRDFFIT_PIPELINE_TWO_STAGE};
    setup s;
    uint64_t seed = 5;
    double values[N_SAMPLES * 3];
    size_t pl, a, b;
    int obj, est;
    (void)state;
    setup_make(&s, "ashikhmin-shirley", AS3, 3);
    noisy_values(&s, 1, &seed, values);
    for (pl = 0; pl < 3; pl++)
        for (obj = 0; obj < 4; obj++) {
            double cov[2][MAXV * MAXV];
            for (est = 0; est < 2; est++) {
                const options o = {pipelines[pl], BRDFFIT_WEIGHT_DEFAULT, obj, est};
                brdffit_grid *grid = make_grid(&s, values);
                brdffit_fit *fit = make_fit(&s, grid, &o);
                size_t n = s.nv, cross = 0;
                assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
                assert_int_equal(check_consistent(fit, "pipelines"), n);
                assert_int_equal(brdffit_fit_covariance(fit, cov[est]), BRDFFIT_OK);
                for (a = 0; a < n; a++)
                    for (b = 0; b < n; b++) {
                        size_t ka = 0, kb = 0, ca = 0, cb = 0, k, c;
                        for (k = 0; k < 3; k++)
                            for (c = 0; c < 3; c++) {
                                if (brdffit_model_vector_index(s.model, k, c, 3) == a)
                                    ka = k, ca = c;
                                if (brdffit_model_vector_index(s.model, k, c, 3) == b)
                                    kb = k, cb = c;
                            }
                        /* colours of two different channels, or shape and colour */
                        if ((ka > 0 && kb > 0 && ca != cb) || ((ka == 0) != (kb == 0))) {
                            if (pipelines[pl] == BRDFFIT_PIPELINE_TWO_STAGE)
                                assert_true(cov[est][a * n + b] == 0.0);
                            else
                                cross += cov[est][a * n + b] != 0.0;
                        }
                    }
                if (pipelines[pl] != BRDFFIT_PIPELINE_TWO_STAGE) assert_true(cross > 0);
                brdffit_fit_destroy(fit);
                brdffit_grid_destroy(grid);
            }
            assert_true(memcmp(cov[0], cov[1], s.nv * s.nv * sizeof(double)) != 0);
        }
    setup_free(&s);
}

/* A held parameter and one at a bound: 0 rows and columns; a parameter
 * the data do not determine (ns with cs held at 0): HUGE_VAL on the
 * diagonal, 0 beside it; both estimators. */
static void test_held_bound_undetermined(void **state)
{
    setup s;
    uint64_t seed = 8;
    double values[N_SAMPLES], start[MAXV], cov[MAXV * MAXV], se[MAXV];
    size_t i, k_cd = 0, k_cs = 0, e_cd, e_cs, e_ns;
    int est;
    (void)state;
    setup_make(&s, "ashikhmin-shirley", AS1, 1);
    assert_int_equal(brdffit_model_param_find(s.model, "cd", &k_cd), BRDFFIT_OK);
    assert_int_equal(brdffit_model_param_find(s.model, "cs", &k_cs), BRDFFIT_OK);
    e_cd = brdffit_model_vector_index(s.model, k_cd, 0, 1);
    e_cs = brdffit_model_vector_index(s.model, k_cs, 0, 1);
    e_ns = brdffit_model_vector_index(s.model, 0, 0, 1);
    for (est = 0; est < 2; est++) {
        const options o = {BRDFFIT_PIPELINE_JOINT, BRDFFIT_WEIGHT_NONE, 0, est};
        brdffit_grid *grid;
        brdffit_fit *fit;
        /* cd held */
        noisy_values(&s, 1, &seed, values);
        grid = make_grid(&s, values);
        fit = make_fit(&s, grid, &o);
        assert_int_equal(brdffit_fit_set_fixed(fit, k_cd, 1), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
        assert_int_equal(check_consistent(fit, "held"), 2);
        assert_int_equal(brdffit_fit_std_errors(fit, se), BRDFFIT_OK);
        assert_true(se[e_cd] == 0.0);
        brdffit_fit_destroy(fit);
        brdffit_grid_destroy(grid);
        /* cd at its bound 0: the data lie below the specular lobe alone */
        for (i = 0; i < N_SAMPLES; i++) values[i] -= 0.3 / PI + 0.02;
        grid = make_grid(&s, values);
        fit = make_fit(&s, grid, &o);
        assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_params(fit, start), BRDFFIT_OK);
        assert_true(start[e_cd] == 0.0);
        assert_int_equal(check_consistent(fit, "bound"), 2);
        assert_int_equal(brdffit_fit_covariance(fit, cov), BRDFFIT_OK);
        for (i = 0; i < 3; i++) assert_true(cov[e_cd * 3 + i] == 0.0 && cov[i * 3 + e_cd] == 0.0);
        brdffit_fit_destroy(fit);
        brdffit_grid_destroy(grid);
        /* cs held at 0: nothing depends on ns */
        noisy_values(&s, 0, &seed, values);
        grid = make_grid(&s, values);
        fit = make_fit(&s, grid, &o);
        memcpy(start, s.truth, sizeof start);
        start[e_cs] = 0.0;
        assert_int_equal(brdffit_fit_set_start(fit, start), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_set_fixed(fit, k_cs, 1), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
        assert_int_equal(check_consistent(fit, "undetermined"), 1);
        assert_int_equal(brdffit_fit_covariance(fit, cov), BRDFFIT_OK);
        assert_true(cov[e_ns * 3 + e_ns] == HUGE_VAL);
        assert_true(cov[e_cs * 3 + e_cs] == 0.0);
        assert_true(cov[e_cd * 3 + e_cd] > 0.0 && cov[e_cd * 3 + e_cd] < HUGE_VAL);
        brdffit_fit_destroy(fit);
        brdffit_grid_destroy(grid);
    }
    setup_free(&s);
}

/* Bad input, each with its exact code. */
static void test_bad_input(void **state)
{
    setup s;
    uint64_t seed = 3;
    double values[N_SAMPLES], cov[MAXV * MAXV], v = -1.0;
    const options o = {BRDFFIT_PIPELINE_JOINT, BRDFFIT_WEIGHT_NONE, 0, 0};
    brdffit_grid *grid;
    brdffit_fit *fit;
    (void)state;
    setup_make(&s, "ashikhmin-shirley", AS1, 1);
    noisy_values(&s, 0, &seed, values);
    grid = make_grid(&s, values);
    fit = make_fit(&s, grid, &o);
    assert_int_equal(brdffit_fit_covariance(NULL, cov), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_covariance(fit, NULL), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_covariance(fit, cov), BRDFFIT_E_NOT_READY);
    assert_int_equal(brdffit_fit_get(fit, BRDFFIT_FIT_COVARIANCE, &v), BRDFFIT_OK);
    assert_true(v == 0.0);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_COVARIANCE, 2), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_COVARIANCE, -1), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_COVARIANCE, 0.5), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_COVARIANCE, NAN), BRDFFIT_E_INVALID_ARGUMENT);
    assert_non_null(strstr(brdffit_fit_message(fit), "out of range"));
    assert_int_equal(brdffit_fit_get(fit, BRDFFIT_FIT_COVARIANCE, &v), BRDFFIT_OK);
    assert_true(v == 0.0);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_COVARIANCE, 1), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_get(fit, BRDFFIT_FIT_COVARIANCE, &v), BRDFFIT_OK);
    assert_true(v == 1.0);
    /* a failed run leaves no result */
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_CAP, 0.0), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_run(fit), BRDFFIT_E_NO_DATA);
    assert_int_equal(brdffit_fit_covariance(fit, cov), BRDFFIT_E_NOT_READY);
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    setup_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_additive_classic),
        cmocka_unit_test(test_multiplicative_sandwich),
        cmocka_unit_test(test_weights_need_sandwich),
        cmocka_unit_test(test_objectives),
        cmocka_unit_test(test_against_optimizer),
        cmocka_unit_test(test_pipelines),
        cmocka_unit_test(test_held_bound_undetermined),
        cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
