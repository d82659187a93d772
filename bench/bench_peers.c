/* bench_peers: the joint fit of the simplified Ashikhmin-Shirley model
 * (ns + 3 cd + 3 cs = 7 parameters) from the thesis's starts (ns = 25,
 * cd = cs = 0.2) on P1 and P2, by libbrdffit (BRDFFIT_PIPELINE_JOINT) and by
 * libbrdffit under its two other damping policies (Marquardt's and the
 * thesis's; rows for their iteration and evaluation counts, not for the
 * speed targets), and by two general least-squares libraries given the
 * callback a user would write:
 *   GSL      gsl_multifit_nlinear, trust region with trs_lm and the Cholesky
 *            solver (default scaling);
 *   MINPACK  cminpack's lmder;
 *   Ceres    its Levenberg-Marquardt (bench_ceres.cc, dense QR; function
 *            tolerance 1e-12, parameter tolerance 1e-10, gradient test
 *            off), when built; its evaluations are the callback's calls,
 *            each with the residuals (at accepted points also the
 *            Jacobian).
 * The callback: the active samples at libbrdffit's default cap (75 deg),
 * rows stacked per channel, r = w cos(theta_i) (R - M) / sum w with the
 * solid-angle weights computed here from the axes (and checked against
 * brdffit_grid_weights()), M evaluated row by row with pow(), and the
 * analytic Jacobian (4.29). The peers work on ns itself, without bounds;
 * the geometry (n.h, h.v, max(n.l, n.v)) is computed once before timing,
 * as libbrdffit's grid holds it.
 *
 * Stopping: libbrdffit's fit settings (xtol 1e-10 on the step, ftol 1e-13
 * on the relative cost reduction with the cost lookahead, gtol 1e-13;
 * lib/fit/stage.c); GSL xtol 1e-10 with its
 * absolute gradient test switched off (it compares against max(cost, 1),
 * far above these costs); MINPACK ftol 1e-12, xtol 1e-10, gtol 0.
 * Every final cost is recomputed as sum r^2 by the same code, so the
 * comparison does not depend on a solver's convention (GSL reports
 * 0.5 sum r^2). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "datasets.h"
#include "harness.h"
#include "naive.h"

#ifdef BENCH_HAVE_GSL
#include <gsl/gsl_errno.h>
#include <gsl/gsl_multifit_nlinear.h>
#endif
#ifdef BENCH_HAVE_CMINPACK
#include <cminpack.h>
#endif
#ifdef BENCH_HAVE_CERES
#include "bench_ceres.h"
#endif

#define PEER_PI 3.14159265358979323846
#define NP 7 /* ns, cd (3), cs (3) */
#define NC 3
#define PEER_REPEATS 11
#define CAP_TOL 1e-9

/* ---- the user's problem -------------------------------------------------------- */

typedef struct peer_problem {
    size_t n;             /* active samples */
    size_t rows;          /* n * NC */
    double *nh, *hv, *mx; /* n each: clamped n.h, h.v, max(n.l, n.v) */
    double *w;            /* n: residual weight factor */
    double *meas;         /* NC * n: [c * n + s] */
    double *block;
} peer_problem;

/* Residual row c * n + s: w (R - M). */
static void residuals(const peer_problem *pp, const double *x, double *f)
{
    double ns = x[0];
    size_t s, c;
    for (c = 0; c < NC; c++)
        for (s = 0; s < pp->n; s++) {
            double lobe = (ns + 1.0) * pow(pp->nh[s], ns) / (8.0 * PEER_PI * pp->hv[s] * pp->mx[s]);
            double m = x[1 + c] / PEER_PI + x[4 + c] * lobe;
            f[c * pp->n + s] = pp->w[s] * (pp->meas[c * pp->n + s] - m);
        }
}

/* d r / d x of row c * n + s into row[0 .. NP) (4.29). */
static void jacobian_row(const peer_problem *pp, const double *x, size_t c, size_t s, double *row)
{
    double ns = x[0], p = pow(pp->nh[s], ns), den = 8.0 * PEER_PI * pp->hv[s] * pp->mx[s];
    size_t k;
    for (k = 0; k < NP; k++) row[k] = 0.0;
    row[0] = -pp->w[s] * x[4 + c] * (p + (ns + 1.0) * p * log(pp->nh[s])) / den;
    row[1 + c] = -pp->w[s] / PEER_PI;
    row[4 + c] = -pp->w[s] * (ns + 1.0) * p / den;
}

static double sum_squares(const double *f, size_t n)
{
    double s = 0.0;
    size_t i;
    for (i = 0; i < n; i++) s += f[i] * f[i];
    return s;
}

/* sum r^2 at x, by the callback's own code. */
static double peer_cost(const peer_problem *pp, const double *x)
{
    double *f = malloc(pp->rows * sizeof *f), c = NAN;
    if (f == NULL) return c;
    residuals(pp, x, f);
    c = sum_squares(f, pp->rows);
    free(f);
    return c;
}

/* ---- weights, computed here from the axes (docs/definitions.md, Weights) ---------------------- */

static size_t axis_active(const double *x, size_t n, double cap)
{
    size_t i = 0;
    while (i < n && x[i] <= cap + CAP_TOL) i++;
    return i;
}

/* Polar extent of view cell j of the a active values (the last one cut at the cap). */
static void polar_cell(const double *x, size_t n, size_t a, size_t j, double cap, double *lo,
                       double *hi)
{
    *lo = j == 0 ? x[0] : 0.5 * (x[j - 1] + x[j]);
    *hi = j + 1 < n ? 0.5 * (x[j] + x[j + 1]) : x[j];
    if (j + 1 == a && *hi > cap) *hi = cap;
}

static double phi_width(const double *x, size_t n, size_t k)
{
    double lo = k == 0 ? x[0] : 0.5 * (x[k - 1] + x[k]);
    double hi = k + 1 == n ? x[k] : 0.5 * (x[k] + x[k + 1]);
    return hi - lo;
}

typedef struct axes_view {
    const double *ti, *to, *po;
    size_t n_ti, n_to, n_po, a_ti, a_to;
} axes_view;

static void view_axes(const brdffit_grid *g, double cap, axes_view *ax)
{
    brdffit_grid_axis(g, BRDFFIT_AXIS_THETA_I, &ax->ti, &ax->n_ti);
    brdffit_grid_axis(g, BRDFFIT_AXIS_THETA_O, &ax->to, &ax->n_to);
    brdffit_grid_axis(g, BRDFFIT_AXIS_PHI_O, &ax->po, &ax->n_po);
    ax->a_ti = axis_active(ax->ti, ax->n_ti, cap);
    ax->a_to = axis_active(ax->to, ax->n_to, cap);
}

/* w[t] for the active samples t in (i, j, k) order: solid angle of the view
 * cell times cos theta_i, over the sum of the view cells' solid angles. */
static void user_weights(const axes_view *ax, double cap, double *w)
{
    double sum = 0.0, lo, hi;
    size_t i, j, k, t = 0;
    for (j = 0; j < ax->a_to; j++)
        for (k = 0; k < ax->n_po; k++) {
            polar_cell(ax->to, ax->n_to, ax->a_to, j, cap, &lo, &hi);
            sum += phi_width(ax->po, ax->n_po, k) * (cos(lo) - cos(hi));
        }
    for (i = 0; i < ax->a_ti; i++)
        for (j = 0; j < ax->a_to; j++)
            for (k = 0; k < ax->n_po; k++, t++) {
                polar_cell(ax->to, ax->n_to, ax->a_to, j, cap, &lo, &hi);
                w[t] = cos(ax->ti[i]) * phi_width(ax->po, ax->n_po, k) * (cos(lo) - cos(hi)) / sum;
            }
}

/* Largest relative difference between our weights and the library's. */
static double compare_weights(const brdffit_grid *g, const axes_view *ax, const double *w)
{
    size_t n = brdffit_grid_sample_count(g), i, j, k, t = 0;
    double *lib = malloc(n * sizeof *lib), worst = 0.0, scale = 0.0;
    if (lib == NULL || brdffit_grid_weights(g, BRDFFIT_DEFAULT_CAP, BRDFFIT_WEIGHT_DEFAULT, lib,
                                            NULL) != BRDFFIT_OK) {
        free(lib);
        return HUGE_VAL;
    }
    for (i = 0; i < ax->a_ti; i++)
        for (j = 0; j < ax->a_to; j++)
            for (k = 0; k < ax->n_po; k++, t++) {
                size_t s = (i * ax->n_to + j) * ax->n_po + k;
                worst = fmax(worst, fabs(lib[s] - w[t]));
                scale = fmax(scale, fabs(lib[s]));
            }
    free(lib);
    return worst / scale;
}

static void fill_geometry(peer_problem *pp, const brdffit_grid *g, const axes_view *ax)
{
    size_t i, j, k, c, t = 0;
    for (i = 0; i < ax->a_ti; i++)
        for (j = 0; j < ax->a_to; j++)
            for (k = 0; k < ax->n_po; k++, t++) {
                size_t s = (i * ax->n_to + j) * ax->n_po + k;
                naive_geom geo;
                naive_geometry(ax->ti[i], PEER_PI, ax->to[j], ax->po[k], &geo);
                pp->nh[t] = geo.nh;
                pp->hv[t] = geo.hv;
                pp->mx[t] = fmax(geo.nl, geo.nv);
                for (c = 0; c < NC; c++) {
                    const double *v;
                    brdffit_grid_values(g, c, &v);
                    pp->meas[c * pp->n + t] = v[s];
                }
            }
}

static int problem_init(peer_problem *pp, const brdffit_grid *g, double *weight_diff)
{
    axes_view ax;
    size_t n;
    memset(pp, 0, sizeof *pp);
    view_axes(g, BRDFFIT_DEFAULT_CAP, &ax);
    n = ax.a_ti * ax.a_to * ax.n_po;
    pp->block = malloc(n * (4 + NC) * sizeof *pp->block);
    if (pp->block == NULL) return 0;
    pp->n = n;
    pp->rows = n * NC;
    pp->nh = pp->block, pp->hv = pp->block + n, pp->mx = pp->block + 2 * n;
    pp->w = pp->block + 3 * n, pp->meas = pp->block + 4 * n;
    user_weights(&ax, BRDFFIT_DEFAULT_CAP, pp->w);
    *weight_diff = compare_weights(g, &ax, pp->w);
    fill_geometry(pp, g, &ax);
    return 1;
}

/* ---- solvers ------------------------------------------------------------------------ */

typedef struct solver_result {
    int ok;
    char message[256];
    double x[NP];
    double cost;        /* sum r^2 recomputed by peer_cost() */
    size_t iterations;  /* solver iterations (Jacobian evaluations for MINPACK) */
    size_t evaluations; /* residual evaluations */
} solver_result;

typedef struct solver_ctx {
    const peer_problem *pp;
    const brdffit_grid *grid;
    const brdffit_model *model;
    const double *start;
    solver_result res;
} solver_ctx;

/* The joint fit under `damping` (NULL: the default policy). */
static int run_policy(solver_ctx *sc, const brdffit_damping *damping)
{
    bd_fit_job job;
    bd_fit_result r;
    memset(&job, 0, sizeof job);
    job.grid = sc->grid;
    job.model = sc->model;
    job.pipeline = BRDFFIT_PIPELINE_JOINT;
    job.start = sc->start;
    job.threads = 1;
    job.damping = damping;
    sc->res.ok = bd_fit_run(&job, &r) == BRDFFIT_OK;
    snprintf(sc->res.message, sizeof sc->res.message, "%s", r.message);
    memcpy(sc->res.x, r.params, NP * sizeof(double));
    sc->res.cost = r.cost; /* the library's own figure; compared with peer_cost() below */
    sc->res.iterations = r.iterations;
    sc->res.evaluations = r.passes;
    return !sc->res.ok;
}

static int run_libbrdffit(void *arg)
{
    return run_policy(arg, NULL);
}

static int run_marquardt(void *arg)
{
    return run_policy(arg, brdffit_damping_marquardt());
}

static int run_thesis(void *arg)
{
    return run_policy(arg, brdffit_damping_thesis());
}

#ifdef BENCH_HAVE_GSL
static int gsl_f(const gsl_vector *x, void *params, gsl_vector *f)
{
    residuals(params, x->data, f->data);
    return GSL_SUCCESS;
}

static int gsl_df(const gsl_vector *x, void *params, gsl_matrix *J)
{
    const peer_problem *pp = params;
    size_t c, s;
    for (c = 0; c < NC; c++)
        for (s = 0; s < pp->n; s++)
            jacobian_row(pp, x->data, c, s, J->data + (c * pp->n + s) * J->tda);
    return GSL_SUCCESS;
}

static int run_gsl(void *arg)
{
    solver_ctx *sc = arg;
    gsl_multifit_nlinear_fdf fdf;
    gsl_multifit_nlinear_parameters par = gsl_multifit_nlinear_default_parameters();
    gsl_multifit_nlinear_workspace *w;
    gsl_vector_const_view x0 = gsl_vector_const_view_array(sc->start, NP);
    int info = 0, status;
    memset(&fdf, 0, sizeof fdf);
    fdf.f = gsl_f;
    fdf.df = gsl_df;
    fdf.n = sc->pp->rows;
    fdf.p = NP;
    fdf.params = (void *)sc->pp;
    par.trs = gsl_multifit_nlinear_trs_lm;
    par.solver = gsl_multifit_nlinear_solver_cholesky;
    w = gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &par, fdf.n, fdf.p);
    if (w == NULL) return 1;
    gsl_multifit_nlinear_init(&x0.vector, &fdf, w);
    status = gsl_multifit_nlinear_driver(200, 1e-10, 1e-300, 0.0, NULL, NULL, &info, w);
    /* GSL_ENOPROG: no step could lower the cost any more, i.e. converged to rounding */
    sc->res.ok = status == GSL_SUCCESS || status == GSL_ENOPROG;
    snprintf(sc->res.message, sizeof sc->res.message, "%s (info %d)", gsl_strerror(status), info);
    memcpy(sc->res.x, gsl_multifit_nlinear_position(w)->data, NP * sizeof(double));
    sc->res.iterations = gsl_multifit_nlinear_niter(w);
    sc->res.evaluations = fdf.nevalf;
    gsl_multifit_nlinear_free(w);
    return !sc->res.ok;
}
#endif

#ifdef BENCH_HAVE_CMINPACK
static int minpack_fcn(void *p, int m, int n, const double *x, double *fvec, double *fjac,
                       int ldfjac, int iflag)
{
    const peer_problem *pp = p;
    double row[NP];
    size_t c, s, k;
    (void)m;
    (void)n;
    if (iflag == 1) residuals(pp, x, fvec);
    if (iflag != 2) return 0;
    for (c = 0; c < NC; c++)
        for (s = 0; s < pp->n; s++) {
            size_t i = c * pp->n + s;
            jacobian_row(pp, x, c, s, row);
            for (k = 0; k < NP; k++) fjac[k * (size_t)ldfjac + i] = row[k];
        }
    return 0;
}

static int run_minpack(void *arg)
{
    solver_ctx *sc = arg;
    int m = (int)sc->pp->rows, n = NP, info, nfev = 0, njev = 0, ipvt[NP];
    double x[NP], diag[NP], qtf[NP], wa1[NP], wa2[NP], wa3[NP];
    double *fvec = malloc((size_t)m * sizeof *fvec), *wa4 = malloc((size_t)m * sizeof *wa4);
    double *fjac = malloc((size_t)m * NP * sizeof *fjac);
    if (fvec == NULL || wa4 == NULL || fjac == NULL) {
        free(fvec), free(wa4), free(fjac);
        return 1;
    }
    memcpy(x, sc->start, sizeof x);
    info = lmder(minpack_fcn, (void *)sc->pp, m, n, x, fvec, fjac, m, 1e-12, 1e-10, 0.0, 1000, diag,
                 1, 100.0, 0, &nfev, &njev, ipvt, qtf, wa1, wa2, wa3, wa4);
    sc->res.ok = info >= 1 && info <= 4;
    snprintf(sc->res.message, sizeof sc->res.message, "lmder info %d", info);
    memcpy(sc->res.x, x, sizeof x);
    sc->res.iterations = (size_t)njev;
    sc->res.evaluations = (size_t)nfev;
    free(fvec), free(wa4), free(fjac);
    return !sc->res.ok;
}
#endif

#ifdef BENCH_HAVE_CERES
/* The user's callback in libbrdffit's residual form, counting its calls
 * (each computes the residuals; those with jac also the Jacobian). */
typedef struct ceres_user {
    const peer_problem *pp;
    size_t calls;
} ceres_user;

static brdffit_status ceres_fn(const double *x, double *r, double *jac, void *user)
{
    ceres_user *cu = user;
    const peer_problem *pp = cu->pp;
    size_t c, s;
    cu->calls++;
    residuals(pp, x, r);
    if (jac == NULL) return BRDFFIT_OK;
    for (c = 0; c < NC; c++)
        for (s = 0; s < pp->n; s++) jacobian_row(pp, x, c, s, jac + (c * pp->n + s) * NP);
    return BRDFFIT_OK;
}

static int run_ceres(void *arg)
{
    static const bench_ceres_settings settings = {200, 1e-12, 1e-300, 1e-10};
    solver_ctx *sc = arg;
    ceres_user cu = {sc->pp, 0};
    bench_ceres_result res = {0, 0};
    double x[NP];
    memcpy(x, sc->start, sizeof x);
    sc->res.ok = bench_ceres_solve(ceres_fn, &cu, NP, sc->pp->rows, &settings, x, &res) == 0 &&
                 res.converged;
    snprintf(sc->res.message, sizeof sc->res.message, "ceres converged %d", res.converged);
    memcpy(sc->res.x, x, sizeof x);
    sc->res.iterations = res.iterations;
    sc->res.evaluations = cu.calls;
    return !sc->res.ok;
}
#endif

/* ---- reporting -------------------------------------------------------------------------- */

typedef struct peer {
    const char *name;
    bh_run_fn run; /* NULL: not built */
    int own;       /* 1: libbrdffit itself, under one of its damping policies */
} peer;

/* The default policy (Nielsen) first: every ratio is against it. The other
 * two policies are rows for their iteration and evaluation counts; the
 * speed targets are against the peers only. */
static const peer peers[] = {
    {"libbrdffit", run_libbrdffit, 1},
    {"marquardt", run_marquardt, 1},
    {"thesis", run_thesis, 1},
#ifdef BENCH_HAVE_GSL
    {"gsl", run_gsl, 0},
#else
    {"gsl", NULL, 0},
#endif
#ifdef BENCH_HAVE_CMINPACK
    {"minpack", run_minpack, 0},
#else
    {"minpack", NULL, 0},
#endif
#ifdef BENCH_HAVE_CERES
    {"ceres", run_ceres, 0},
#else
    {"ceres", NULL, 0},
#endif
};

#define N_PEERS (sizeof peers / sizeof peers[0])

typedef struct outcome {
    int have;
    bh_stats st;
    solver_result res;
    double rel_diff; /* final cost vs libbrdffit's */
} outcome;

/* |a - b| relative to the larger, costs below 1e-12 of the start cost
 * counting as zero (the noise-free P1 ends there: at rounding level for
 * the peers, near 1e-17 of the start cost for libbrdffit, whose fused
 * passes read single-precision inputs). */
static double relative_diff(double a, double b, double start_cost)
{
    const double zero = 1e-12 * start_cost;
    if (fabs(a) <= zero && fabs(b) <= zero) return 0.0;
    return fabs(a - b) / fmax(fmax(fabs(a), fabs(b)), zero);
}

static void table_row(bh_output *out, bd_dataset d, const char *name, const outcome *o,
                      const outcome *lib)
{
    if (!o->have) {
        bh_table(out, "%-4s %-11s skipped (not found at configure time)\n", bd_name(d), name);
        return;
    }
    bh_table(out, "%-4s %-11s %6zu %6zu %14.9e %9.2e %10.3f %9.3f %9.3f %9.3f %8.1fx  %.4f\n",
             bd_name(d), name, o->res.iterations, o->res.evaluations, o->res.cost, o->rel_diff,
             o->st.median_ns / 1e6, o->st.min_ns / 1e6, o->st.max_ns / 1e6,
             o->st.median_cpu_ns / 1e6, o->st.median_ns / lib->st.median_ns, o->res.x[0]);
}

/* ratio_vs_X = median time of X / median time of this solver (> 1: this one is faster). */
static void json_row(bh_output *out, bd_dataset d, const char *name, const outcome *o,
                     const outcome *all, size_t rows)
{
    const outcome *lib = &all[0];
    bh_record r;
    char full[96];
    size_t p;
    snprintf(full, sizeof full, "joint/%s/%s", bd_name(d), name);
    bh_rec_begin(&r, out, full);
    bh_rec_str(&r, "solver", name);
    bh_rec_str(&r, "data", bd_name(d));
    bh_rec_bool(&r, "skipped", !o->have);
    if (o->have) {
        bh_rec_stats(&r, &o->st, rows);
        bh_rec_int(&r, "iterations", o->res.iterations);
        bh_rec_int(&r, "evaluations", o->res.evaluations);
        bh_rec_num(&r, "cost", o->res.cost);
        bh_rec_num(&r, "rel_cost_diff_vs_libbrdffit", o->rel_diff);
        bh_rec_num(&r, "ns_fitted", o->res.x[0]);
        if (o != lib) bh_rec_num(&r, "ratio_vs_libbrdffit", lib->st.median_ns / o->st.median_ns);
    }
    for (p = 1; o == lib && p < N_PEERS; p++) {
        char key[48];
        snprintf(key, sizeof key, "ratio_vs_%s", peers[p].name);
        bh_rec_num(&r, key, all[p].have ? all[p].st.median_ns / o->st.median_ns : NAN);
    }
    bh_rec_end(&r, out);
}

typedef struct worst {
    double ratio[N_PEERS];     /* smallest peer / libbrdffit time ratio over the data sets */
    double ratio_cpu[N_PEERS]; /* the same from CPU times */
    double diff[N_PEERS];      /* largest relative cost difference */
} worst;

static void run_peer(bh_output *out, solver_ctx *sc, size_t p, outcome *o)
{
    size_t reps = bh_repeats(out->opt, PEER_REPEATS);
    memset(o, 0, sizeof *o);
    if (peers[p].run == NULL) return;
    memset(&sc->res, 0, sizeof sc->res);
    if (bh_measure(peers[p].run, sc, out->opt->smoke ? 0 : 1, reps, &o->st) != 0) {
        bh_fail(out, "%s did not converge: %s", peers[p].name, sc->res.message);
        return;
    }
    o->have = 1;
    o->res = sc->res;
}

/* The library's cost through the callback's code must equal its own figure:
 * both sides minimise the same sum. */
static void check_same_problem(bh_output *out, const peer_problem *pp, outcome *lib,
                               double start_cost)
{
    double mine = peer_cost(pp, lib->res.x);
    if (!(relative_diff(mine, lib->res.cost, start_cost) < 1e-9))
        bh_fail(out, "libbrdffit's cost %.17g differs from the callback's sum r^2 %.17g",
                lib->res.cost, mine);
    lib->res.cost = mine;
}

static void run_dataset(bh_output *out, const brdffit_model *model, bd_dataset d, worst *wo)
{
    brdffit_grid *grid = NULL;
    peer_problem pp;
    solver_ctx sc;
    outcome o[N_PEERS];
    double start[BD_MAX_PARAMS], wdiff, c0;
    char label[32];
    size_t p;
    snprintf(label, sizeof label, "joint/%s", bd_name(d));
    if (!bh_selected(out->opt, label)) return;
    if (bd_default_grid(&grid, d, BD_SEED, NULL, NULL) != BRDFFIT_OK ||
        !problem_init(&pp, grid, &wdiff)) {
        bh_fail(out, "setting up %s", bd_name(d));
        brdffit_grid_destroy(grid);
        return;
    }
    if (!(wdiff < 1e-12)) bh_fail(out, "weights differ from brdffit_grid_weights() by %g", wdiff);
    bd_thesis_start(model, NC, start);
    c0 = peer_cost(&pp, start);
    sc.pp = &pp, sc.grid = grid, sc.model = model, sc.start = start;
    for (p = 0; p < N_PEERS; p++) {
        run_peer(out, &sc, p, &o[p]);
        if (!o[p].have) continue;
        if (p == 0)
            check_same_problem(out, &pp, &o[0], c0);
        else
            o[p].res.cost = peer_cost(&pp, o[p].res.x);
        o[p].rel_diff = o[0].have ? relative_diff(o[p].res.cost, o[0].res.cost, c0) : NAN;
        if (p > 0 && o[p].have && !(o[p].rel_diff < 1e-6))
            bh_fail(out, "%s on %s: final cost differs from libbrdffit's by %.3g relative",
                    peers[p].name, bd_name(d), o[p].rel_diff);
    }
    bh_table(out,
             "%-4s (%zu rows, weights match brdffit_grid_weights() to %.1e, start cost "
             "%.6e)\n",
             bd_name(d), pp.rows, wdiff, c0);
    for (p = 0; p < N_PEERS && o[0].have; p++) {
        table_row(out, d, peers[p].name, &o[p], &o[0]);
        json_row(out, d, peers[p].name, &o[p], o, pp.rows);
        if (!o[p].have) continue;
        wo->ratio[p] = fmin(wo->ratio[p], o[p].st.median_ns / o[0].st.median_ns);
        wo->ratio_cpu[p] = fmin(wo->ratio_cpu[p], o[p].st.median_cpu_ns / o[0].st.median_cpu_ns);
        wo->diff[p] = fmax(wo->diff[p], o[p].rel_diff);
    }
    free(pp.block);
    brdffit_grid_destroy(grid);
}

static void report_targets(bh_output *out, const worst *wo)
{
    char measured[64], what[96];
    size_t p;
    bh_table(out, "\n");
    for (p = 1; p < N_PEERS; p++) {
        if (peers[p].own) continue;
        if (peers[p].run == NULL) {
            bh_table(out, "target: joint fit vs %s: skipped\n", peers[p].name);
            continue;
        }
        snprintf(what, sizeof what, "joint fit %s / libbrdffit time (worse of P1, P2)",
                 peers[p].name);
        snprintf(measured, sizeof measured, "%.1fx (cpu %.1fx)", wo->ratio[p], wo->ratio_cpu[p]);
        bh_target(out, what, measured, ">= 10x", wo->ratio[p] >= 10.0);
        snprintf(what, sizeof what, "same final cost as %s (relative, worse of P1, P2)",
                 peers[p].name);
        snprintf(measured, sizeof measured, "%.1e", wo->diff[p]);
        bh_target(out, what, measured, "<= 1e-9", wo->diff[p] <= 1e-9);
    }
}

int main(int argc, char **argv)
{
    bh_options opt;
    bh_output out;
    brdffit_model *model = NULL;
    worst wo;
    size_t p;
    int code;
    if (!bh_parse_args(argc, argv,
                       "The joint fit under each damping policy, against GSL and MINPACK.", &opt,
                       &code))
        return code;
    if (!bh_output_open(&out, &opt, "joint fit of ashikhmin-shirley vs GSL and MINPACK (cap 75)"))
        return 1;
#ifdef BENCH_HAVE_GSL
    gsl_set_error_handler_off();
#endif
    for (p = 0; p < N_PEERS; p++) wo.ratio[p] = wo.ratio_cpu[p] = HUGE_VAL, wo.diff[p] = 0.0;
    bh_table(&out,
             "start ns = 25, cd = cs = 0.2; %zu timed runs each; cost = sum r^2; "
             "ratio = solver time / libbrdffit time\n",
             bh_repeats(&opt, PEER_REPEATS));
    bh_table(&out, "%-4s %-11s %6s %6s %15s %9s %10s %9s %9s %9s %9s  %s\n", "data", "solver",
             "iters", "evals", "final cost", "rel diff", "median ms", "min ms", "max ms", "cpu ms",
             "ratio", "ns");
    if (brdffit_model_create(&model, "ashikhmin-shirley", NULL, NULL) == BRDFFIT_OK) {
        run_dataset(&out, model, BD_P1, &wo);
        run_dataset(&out, model, BD_P2, &wo);
    } else {
        bh_fail(&out, "creating the model");
    }
    if (opt.filter == NULL) report_targets(&out, &wo);
    brdffit_model_destroy(model);
    return bh_output_close(&out);
}
