/* bench_certified: the optimizer against MINPACK, GSL and (when built)
 * Ceres on certified problems: the 27 NIST StRD nonlinear regression
 * problems from both certified starts (54 runs) and the 35 least-squares
 * problems of Moré, Garbow and Hillstrom (1981) from x0, 10 x0 and
 * 100 x0 (105 runs), the problems of tests/support (nist_problems.c,
 * optim_problems.c) with their analytic Jacobians; then the same runs in
 * changed coordinates (optim_changed in optim_problems.h), whose answers
 * should not change: "mixed", the first parameter in units that make its
 * certified value (StRD) or its start (MGH) 1e6; "zero" (StRD), every
 * parameter shifted by the midpoint of its start and its certified value,
 * so that each changes sign on the way.
 *
 * One success criterion for every solver, judged on the point it
 * returns, whatever it reports: StRD, every parameter's log relative
 * error against NIST's certified value (in the coordinates of the run)
 * at least 6; MGH, the final cost
 * (sum r^2, recomputed here) within 1e-6 relative of one of the paper's
 * minima (below 1e-10 for a zero minimum). "Elsewhere" counts the runs
 * a solver reported as converged that did not meet it (other stationary
 * points, or worse).
 *
 * Evaluations are counted by the callback itself for every solver: f,
 * the calls for residuals alone, and J, those for the Jacobian (with the
 * residuals for libbrdffit and Ceres, alone for MINPACK and GSL).
 *
 * Settings, the same budget for all (libbrdffit's default limits):
 * libbrdffit its defaults (10000 iterations, 24000 evaluations), and
 * once more with BRDFFIT_OPT_STEP_CONTROL 1 ("lib+control", not a peer);
 * MINPACK lmder ftol 1e-15, xtol 1e-10, gtol 0, at most 24000
 * evaluations, its own scaling (mode 1); GSL gsl_multifit_nlinear with
 * the trust-region subproblems lm, lmaccel and ddogleg, Moré's scaling
 * (its default), Cholesky, xtol 1e-10, gtol and ftol off, 10000
 * iterations; Ceres (bench_ceres.cc) its Levenberg-Marquardt with
 * function, gradient and parameter tolerances 1e-15, 1e-15, 1e-10 and
 * 10000 iterations. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "nist_problems.h"
#include "optim_problems.h"

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

#define MAX_P 12
#define MAX_M 256

/* ---- one problem, counted ------------------------------------------------------- */

/* The sets of runs: the problems in their own coordinates, then in
 * changed ones. */
enum { SET_STRD, SET_MGH, SET_STRD_MIXED, SET_STRD_ZERO, SET_MGH_MIXED, N_SETS };
static const char *const set_names[N_SETS] = {"StRD", "MGH", "StRD-mixed", "StRD-zero",
                                              "MGH-mixed"};

typedef struct cproblem {
    const char *name;
    int start; /* StRD: 1 or 2; MGH: the factor of x0 */
    int set;   /* SET_*; the StRD sets are judged by LRE, the MGH ones by cost */
    const nist_problem *nist;
    const optim_problem *mgh;
    optim_changed changed; /* the coordinates of the run */
    brdffit_residual_fn fn;
    void *user;
    size_t n, m;
    double x0[MAX_P];
    double target[MAX_P];    /* StRD: the certified values in the run's coordinates */
    size_t f_calls, j_calls; /* counted by the callbacks */
} cproblem;

static int strd_set(int set)
{
    return set == SET_STRD || set == SET_STRD_MIXED || set == SET_STRD_ZERO;
}

typedef struct run_result {
    int ran;       /* the solver ran (it may have failed) */
    int converged; /* it said so */
    double x[MAX_P];
    size_t iterations;
} run_result;

static brdffit_status counted(const double *x, double *r, double *jac, void *user)
{
    cproblem *cp = user;
    if (jac != NULL)
        cp->j_calls++;
    else
        cp->f_calls++;
    return cp->fn(x, r, jac, cp->user);
}

static double cost_at(const cproblem *cp, const double *x)
{
    double r[MAX_M], c = 0.0;
    size_t i;
    if (cp->fn(x, r, NULL, cp->user) != BRDFFIT_OK) return HUGE_VAL;
    for (i = 0; i < cp->m; i++) c += r[i] * r[i];
    return isfinite(c) ? c : HUGE_VAL;
}

static int solved(const cproblem *cp, const double *x)
{
    size_t j;
    for (j = 0; j < cp->n; j++)
        if (!isfinite(x[j])) return 0;
    if (strd_set(cp->set)) {
        for (j = 0; j < cp->n; j++)
            if (!(nist_lre(x[j], cp->target[j]) >= 6.0)) return 0;
        return 1;
    }
    return optim_mgh_solved(cp->mgh, cost_at(cp, x));
}

/* ---- the solvers ------------------------------------------------------------------ */

static void run_optimizer(cproblem *cp, run_result *rr, int step_control)
{
    brdffit_optimizer *opt = NULL;
    if (brdffit_optimizer_create(&opt, cp->n, NULL, NULL) != BRDFFIT_OK) return;
    memcpy(rr->x, cp->x0, cp->n * sizeof *rr->x);
    if (brdffit_optimizer_set(opt, BRDFFIT_OPT_STEP_CONTROL, step_control) == BRDFFIT_OK &&
        brdffit_optimizer_set_residuals(opt, cp->m, counted, cp) == BRDFFIT_OK &&
        brdffit_optimizer_run(opt, rr->x) == BRDFFIT_OK) {
        rr->converged = brdffit_optimizer_converged(opt);
        rr->iterations = brdffit_optimizer_iterations(opt);
    }
    rr->ran = 1;
    brdffit_optimizer_destroy(opt);
}

static void run_libbrdffit(cproblem *cp, run_result *rr)
{
    run_optimizer(cp, rr, 0);
}

/* BRDFFIT_OPT_STEP_CONTROL 1: Moré's rules on top of the policy. */
static void run_step_control(cproblem *cp, run_result *rr)
{
    run_optimizer(cp, rr, 1);
}

#ifdef BENCH_HAVE_CMINPACK
static int minpack_fcn(void *p, int m, int n, const double *x, double *fvec, double *fjac,
                       int ldfjac, int iflag)
{
    cproblem *cp = p;
    double jac[MAX_M * MAX_P];
    size_t i, j;
    (void)m;
    (void)n;
    if (iflag == 0) return 0;
    if (iflag == 1) return counted(x, fvec, NULL, cp) == BRDFFIT_OK ? 0 : -1;
    {
        double r[MAX_M];
        cp->j_calls++;
        if (cp->fn(x, r, jac, cp->user) != BRDFFIT_OK) return -1;
    }
    for (i = 0; i < cp->m; i++)
        for (j = 0; j < cp->n; j++) fjac[j * (size_t)ldfjac + i] = jac[i * cp->n + j];
    return 0;
}

static void run_minpack(cproblem *cp, run_result *rr)
{
    int m = (int)cp->m, n = (int)cp->n, info, nfev = 0, njev = 0, ipvt[MAX_P];
    double fvec[MAX_M], fjac[MAX_M * MAX_P], diag[MAX_P], qtf[MAX_P];
    double wa1[MAX_P], wa2[MAX_P], wa3[MAX_P], wa4[MAX_M];
    memcpy(rr->x, cp->x0, cp->n * sizeof *rr->x);
    info = lmder(minpack_fcn, cp, m, n, rr->x, fvec, fjac, m, 1e-15, 1e-10, 0.0, 24000, diag, 1,
                 100.0, 0, &nfev, &njev, ipvt, qtf, wa1, wa2, wa3, wa4);
    rr->ran = 1;
    rr->converged = info >= 1 && info <= 4;
    rr->iterations = (size_t)njev;
}
#endif

#ifdef BENCH_HAVE_GSL
static int gsl_f(const gsl_vector *x, void *params, gsl_vector *f)
{
    return counted(x->data, f->data, NULL, params) == BRDFFIT_OK ? GSL_SUCCESS : GSL_EDOM;
}

static int gsl_df(const gsl_vector *x, void *params, gsl_matrix *J)
{
    cproblem *cp = params;
    double r[MAX_M], jac[MAX_M * MAX_P];
    size_t i, j;
    cp->j_calls++;
    if (cp->fn(x->data, r, jac, cp->user) != BRDFFIT_OK) return GSL_EDOM;
    for (i = 0; i < cp->m; i++)
        for (j = 0; j < cp->n; j++) gsl_matrix_set(J, i, j, jac[i * cp->n + j]);
    return GSL_SUCCESS;
}

static void run_gsl(cproblem *cp, run_result *rr, const gsl_multifit_nlinear_trs *trs)
{
    gsl_multifit_nlinear_fdf fdf;
    gsl_multifit_nlinear_parameters par = gsl_multifit_nlinear_default_parameters();
    gsl_multifit_nlinear_workspace *w;
    gsl_vector_view x0 = gsl_vector_view_array(rr->x, cp->n);
    int info = 0, status;
    memcpy(rr->x, cp->x0, cp->n * sizeof *rr->x);
    memset(&fdf, 0, sizeof fdf);
    fdf.f = gsl_f;
    fdf.df = gsl_df;
    fdf.n = cp->m;
    fdf.p = cp->n;
    fdf.params = cp;
    par.trs = trs;
    par.solver = gsl_multifit_nlinear_solver_cholesky;
    w = gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &par, fdf.n, fdf.p);
    if (w == NULL) return;
    rr->ran = 1;
    if (gsl_multifit_nlinear_init(&x0.vector, &fdf, w) == GSL_SUCCESS) {
        status = gsl_multifit_nlinear_driver(10000, 1e-10, 1e-300, 1e-300, NULL, NULL, &info, w);
        rr->converged = status == GSL_SUCCESS;
        memcpy(rr->x, gsl_multifit_nlinear_position(w)->data, cp->n * sizeof *rr->x);
        rr->iterations = gsl_multifit_nlinear_niter(w);
    }
    gsl_multifit_nlinear_free(w);
}

static void run_gsl_lm(cproblem *cp, run_result *rr)
{
    run_gsl(cp, rr, gsl_multifit_nlinear_trs_lm);
}

static void run_gsl_lmaccel(cproblem *cp, run_result *rr)
{
    run_gsl(cp, rr, gsl_multifit_nlinear_trs_lmaccel);
}

static void run_gsl_ddogleg(cproblem *cp, run_result *rr)
{
    run_gsl(cp, rr, gsl_multifit_nlinear_trs_ddogleg);
}
#endif

#ifdef BENCH_HAVE_CERES
static void run_ceres(cproblem *cp, run_result *rr)
{
    static const bench_ceres_settings settings = {10000, 1e-15, 1e-15, 1e-10};
    bench_ceres_result res = {0, 0};
    memcpy(rr->x, cp->x0, cp->n * sizeof *rr->x);
    if (bench_ceres_solve(counted, cp, cp->n, cp->m, &settings, rr->x, &res) != 0) return;
    rr->ran = 1;
    rr->converged = res.converged;
    rr->iterations = res.iterations;
}
#endif

typedef void (*solver_fn)(cproblem *cp, run_result *rr);

typedef struct solver {
    const char *name;
    solver_fn run; /* NULL: not built */
} solver;

/* libbrdffit's rows first: the default, then with the step control; the
 * peers after them (OWN_ROWS). */
#define OWN_ROWS 2
static const solver solvers[] = {
    {"libbrdffit", run_libbrdffit},
    {"lib+control", run_step_control},
#ifdef BENCH_HAVE_CMINPACK
    {"minpack", run_minpack},
#else
    {"minpack", NULL},
#endif
#ifdef BENCH_HAVE_GSL
    {"gsl-lm", run_gsl_lm},
    {"gsl-lmaccel", run_gsl_lmaccel},
    {"gsl-ddogleg", run_gsl_ddogleg},
#else
    {"gsl-lm", NULL},
    {"gsl-lmaccel", NULL},
    {"gsl-ddogleg", NULL},
#endif
#ifdef BENCH_HAVE_CERES
    {"ceres", run_ceres},
#else
    {"ceres", NULL},
#endif
};

#define N_SOLVERS (sizeof solvers / sizeof solvers[0])

/* ---- the runs -------------------------------------------------------------------------- */

typedef struct totals {
    size_t solved[N_SETS], runs[N_SETS], wrong[N_SETS]; /* per set */
    size_t f_calls[N_SETS], j_calls[N_SETS], iterations[N_SETS];
} totals;

static void run_all(bh_output *out, cproblem *cp, totals *tot)
{
    size_t s;
    int set = cp->set;
    double best = HUGE_VAL;
    char line[1024];
    size_t len;
    len =
        (size_t)snprintf(line, sizeof line, "%-10s %-22s %4d", set_names[set], cp->name, cp->start);
    for (s = 0; s < N_SOLVERS; s++) {
        run_result rr;
        int ok;
        if (solvers[s].run == NULL) continue;
        memset(&rr, 0, sizeof rr);
        cp->f_calls = cp->j_calls = 0;
        solvers[s].run(cp, &rr);
        ok = rr.ran && solved(cp, rr.x);
        if (rr.ran) best = fmin(best, cost_at(cp, rr.x));
        tot[s].runs[set]++;
        tot[s].solved[set] += (size_t)ok;
        tot[s].wrong[set] += (size_t)(!ok && rr.converged);
        tot[s].f_calls[set] += cp->f_calls;
        tot[s].j_calls[set] += cp->j_calls;
        tot[s].iterations[set] += rr.iterations;
        if (len < sizeof line)
            len +=
                (size_t)snprintf(line + len, sizeof line - len, " | %c%c %5zu %5zu", ok ? 'S' : '-',
                                 rr.converged ? 'c' : ' ', cp->f_calls, cp->j_calls);
    }
    if (!out->opt->smoke) bh_table(out, "%s | %.12e\n", line, best);
}

/* The run's coordinates: the identity for SET_STRD and SET_MGH. Sets
 * cp->fn, cp->user, cp->x0 and cp->target from the problem's start b0
 * and certified values cert (NULL for MGH). */
static void set_coordinates(cproblem *cp, brdffit_residual_fn fn, void *user, const double *b0,
                            const double *cert)
{
    optim_changed_init(&cp->changed, fn, user, cp->m, cp->n);
    if (cp->set == SET_STRD_MIXED) optim_changed_mixed(&cp->changed, cert[0]);
    if (cp->set == SET_MGH_MIXED) optim_changed_mixed(&cp->changed, b0[0]);
    if (cp->set == SET_STRD_ZERO) optim_changed_through_zero(&cp->changed, b0, cert);
    cp->fn = optim_changed_fn;
    cp->user = &cp->changed;
    optim_changed_from_problem(&cp->changed, b0, cp->x0);
    if (cert != NULL) optim_changed_from_problem(&cp->changed, cert, cp->target);
}

static void strd_runs(bh_output *out, totals *tot, int set)
{
    size_t n, k, s;
    const nist_problem *ps = nist_problems(&n);
    for (k = 0; k < n && (!out->opt->smoke || k < 2); k++) {
        for (s = 0; s < 2; s++) {
            cproblem cp;
            memset(&cp, 0, sizeof cp);
            cp.name = ps[k].name;
            cp.start = (int)s + 1;
            cp.set = set;
            cp.nist = &ps[k];
            cp.n = ps[k].n_params;
            cp.m = ps[k].n_obs;
            if (cp.m > MAX_M || cp.n > MAX_P) {
                bh_fail(out, "%s: %zu rows, %zu parameters: too many", cp.name, cp.m, cp.n);
                continue;
            }
            set_coordinates(&cp, nist_residuals, (void *)&ps[k], ps[k].start[s], ps[k].certified);
            run_all(out, &cp, tot);
        }
    }
}

static void mgh_runs(bh_output *out, totals *tot, int set)
{
    static const int factor[3] = {1, 10, 100};
    size_t n, k, f, j;
    const optim_problem *pbs = optim_mgh_set(&n);
    for (k = 0; k < n && (!out->opt->smoke || k < 4); k++) {
        for (f = 0; f < 3; f++) {
            cproblem cp;
            double b0[MAX_P];
            memset(&cp, 0, sizeof cp);
            cp.name = pbs[k].name;
            cp.start = factor[f];
            cp.set = set;
            cp.mgh = &pbs[k];
            cp.n = pbs[k].n_params;
            cp.m = pbs[k].n_rows;
            for (j = 0; j < cp.n; j++) b0[j] = factor[f] * pbs[k].x0[j];
            set_coordinates(&cp, pbs[k].fn, (void *)&pbs[k], b0, NULL);
            run_all(out, &cp, tot);
        }
    }
}

static void header(bh_output *out)
{
    char line[1024];
    size_t s, len = (size_t)snprintf(line, sizeof line, "%-10s %-22s %4s", "set", "problem", "x0");
    for (s = 0; s < N_SOLVERS; s++)
        if (solvers[s].run != NULL && len < sizeof line)
            len += (size_t)snprintf(line + len, sizeof line - len, " | %-14s", solvers[s].name);
    bh_table(out,
             "per run: S solved, c reported converged, then f and J evaluations; the lowest "
             "final cost of all\n%s | best cost\n",
             line);
}

static void summary(bh_output *out, const totals *tot)
{
    size_t s, k;
    bh_table(out, "\n%-12s %-10s %7s %6s %9s %9s %9s %9s\n", "solver", "set", "solved", "runs",
             "elsewhere", "f evals", "J evals", "iters");
    for (s = 0; s < N_SOLVERS; s++) {
        if (solvers[s].run == NULL) {
            bh_table(out, "%-12s skipped (not found at configure time)\n", solvers[s].name);
            continue;
        }
        for (k = 0; k < N_SETS; k++) {
            bh_record r;
            char name[64];
            bh_table(out, "%-12s %-10s %7zu %6zu %9zu %9zu %9zu %9zu\n", solvers[s].name,
                     set_names[k], tot[s].solved[k], tot[s].runs[k], tot[s].wrong[k],
                     tot[s].f_calls[k], tot[s].j_calls[k], tot[s].iterations[k]);
            snprintf(name, sizeof name, "certified/%s/%s", set_names[k], solvers[s].name);
            bh_rec_begin(&r, out, name);
            bh_rec_int(&r, "solved", tot[s].solved[k]);
            bh_rec_int(&r, "runs", tot[s].runs[k]);
            bh_rec_int(&r, "converged_elsewhere", tot[s].wrong[k]);
            bh_rec_int(&r, "f_evaluations", tot[s].f_calls[k]);
            bh_rec_int(&r, "j_evaluations", tot[s].j_calls[k]);
            bh_rec_int(&r, "iterations", tot[s].iterations[k]);
            bh_rec_end(&r, out);
        }
    }
}

/* Every set: libbrdffit's default solves at least as many runs as the
 * best peer. */
static void report_targets(bh_output *out, const totals *tot)
{
    size_t s, k;
    for (k = 0; k < N_SETS; k++) {
        size_t best = 0, mine = tot[0].solved[k];
        char what[64], measured[64], limit[64];
        for (s = OWN_ROWS; s < N_SOLVERS; s++)
            if (solvers[s].run != NULL && tot[s].solved[k] > best) best = tot[s].solved[k];
        snprintf(what, sizeof what, "%s runs solved", set_names[k]);
        snprintf(measured, sizeof measured, "%zu", mine);
        snprintf(limit, sizeof limit, ">= %zu (the best peer)", best);
        bh_target(out, what, measured, limit, mine >= best);
    }
}

int main(int argc, char **argv)
{
    bh_options opt;
    bh_output out;
    totals tot[N_SOLVERS];
    int code;
    if (!bh_parse_args(argc, argv,
                       "The optimizer against MINPACK, GSL and Ceres on NIST StRD and MGH.", &opt,
                       &code))
        return code;
    if (!bh_output_open(&out, &opt,
                        "certified problems: StRD 54 runs, MGH 105 runs, in their own and in "
                        "changed coordinates"))
        return 1;
#ifdef BENCH_HAVE_GSL
    gsl_set_error_handler_off();
#endif
    memset(tot, 0, sizeof tot);
    header(&out);
    strd_runs(&out, tot, SET_STRD);
    mgh_runs(&out, tot, SET_MGH);
    strd_runs(&out, tot, SET_STRD_MIXED);
    strd_runs(&out, tot, SET_STRD_ZERO);
    mgh_runs(&out, tot, SET_MGH_MIXED);
    summary(&out, tot);
    if (!opt.smoke) report_targets(&out, tot);
    return bh_output_close(&out);
}
