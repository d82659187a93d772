/* curve_fit: fit a Gaussian peak on a sloping baseline with libbrdffit's
 * Levenberg-Marquardt optimizer, using a damping policy written here.
 *
 *   y(t) = h exp(-(t - c)^2 / (2 w^2)) + b0 + b1 t
 *
 * The data are made from known parameters plus deterministic noise; the
 * program prints the fit, its standard errors and the cost per iteration,
 * and exits with 0 when every parameter lies within five standard errors
 * of the value the data were made from. */
#include <math.h>
#include <stdio.h>

#include "brdffit/brdffit.h"

enum { N_POINTS = 120, N_PARAMS = 5 };

typedef struct data {
    double t[N_POINTS], y[N_POINTS];
} data;

static const double truth[N_PARAMS] = {3.0, 4.2, 0.6, 0.5, 0.05};
static const char *const names[N_PARAMS] = {"height", "centre", "width", "base", "slope"};
static const double noise = 0.03;

static double model(const double *p, double t)
{
    double u = (t - p[1]) / p[2];
    return p[0] * exp(-0.5 * u * u) + p[3] + p[4] * t;
}

/* Roughly normal noise with unit variance from a small linear congruential
 * generator: the same numbers on every platform. */
static double noise_sample(unsigned long long *s)
{
    double sum = 0.0;
    int k;
    for (k = 0; k < 12; k++) {
        *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
        sum += (double)(*s >> 11) / 9007199254740992.0;
    }
    return sum - 6.0;
}

static void make_data(data *d)
{
    unsigned long long s = 2017;
    int i;
    for (i = 0; i < N_POINTS; i++) {
        d->t[i] = 10.0 * i / (N_POINTS - 1);
        d->y[i] = model(truth, d->t[i]) + noise * noise_sample(&s);
    }
}

/* Residuals r_i = y(t_i) - y_i and, when asked, the Jacobian. */
static brdffit_status residuals(const double *p, double *r, double *jac, void *user)
{
    const data *d = user;
    int i;
    if (!(p[2] != 0.0)) return BRDFFIT_E_MODEL_FAILED; /* zero width: undefined */
    for (i = 0; i < N_POINTS; i++) {
        double t = d->t[i], u = (t - p[1]) / p[2], e = exp(-0.5 * u * u);
        double *row = jac ? jac + i * N_PARAMS : NULL;
        r[i] = p[0] * e + p[3] + p[4] * t - d->y[i];
        if (row == NULL) continue;
        row[0] = e;
        row[1] = p[0] * e * u / p[2];
        row[2] = p[0] * e * u * u / p[2];
        row[3] = 1.0;
        row[4] = t;
    }
    return BRDFFIT_OK;
}

/* A damping policy in the spirit of a trust region: shrink lambda after a
 * step the linear model predicted well (rho > 3/4), grow it after a poor
 * one (rho < 1/4), and grow it faster with every rejection in a row. */
typedef struct trust_state {
    int rejections; /* in a row */
} trust_state;

static void trust_init(void *state, double *lambda, void *user)
{
    (void)state;
    (void)user;
    *lambda = 1e-2;
}

static void trust_accept(void *state, double rho, double *lambda, void *user)
{
    trust_state *s = state;
    (void)user;
    s->rejections = 0;
    if (rho > 0.75)
        *lambda /= 3.0;
    else if (rho < 0.25)
        *lambda *= 2.0;
}

static void trust_reject(void *state, double rho, double *lambda, void *user)
{
    trust_state *s = state;
    (void)rho;
    (void)user;
    s->rejections++;
    *lambda *= 2.0 * s->rejections;
}

static int print_iteration(const brdffit_iteration *it, void *user)
{
    (void)user;
    printf("  %3zu  %-8s cost %-12.6g lambda %-10.3g rho %.3g\n", it->iteration,
           it->accepted ? "accepted" : "rejected", it->cost, it->lambda, it->rho);
    return 0;
}

static int report(brdffit_optimizer *opt, const double *p)
{
    double se[N_PARAMS];
    int j, ok = 1;
    brdffit_stop_reason why = brdffit_optimizer_stop_reason(opt);
    printf("stopped: %s after %zu iterations, %zu evaluations\n", brdffit_stop_reason_string(why),
           brdffit_optimizer_iterations(opt), brdffit_optimizer_evaluations(opt));
    printf("cost: %.6g -> %.6g (last improvement at iteration %zu)\n",
           brdffit_optimizer_initial_cost(opt), brdffit_optimizer_final_cost(opt),
           brdffit_optimizer_last_improvement(opt));
    printf("condition number of J^T J: %.3g\n", brdffit_optimizer_condition(opt));
    if (brdffit_optimizer_std_errors(opt, se) != BRDFFIT_OK) return 0;
    printf("%-8s %12s %12s %12s\n", "param", "fit", "std. error", "truth");
    for (j = 0; j < N_PARAMS; j++) {
        printf("%-8s %12.6f %12.6f %12.6f\n", names[j], p[j], se[j], truth[j]);
        if (!(fabs(p[j] - truth[j]) <= 5.0 * se[j])) ok = 0;
    }
    return ok && why != BRDFFIT_STOP_MAX_ITERATIONS && why != BRDFFIT_STOP_MAX_EVALUATIONS;
}

int main(void)
{
    static data d;
    brdffit_optimizer *opt = NULL;
    brdffit_error err;
    brdffit_damping policy = BRDFFIT_DAMPING_INIT;
    double p[N_PARAMS] = {2.0, 5.0, 1.0, 0.0, 0.0}; /* a rough first guess */
    const double lower[N_PARAMS] = {0.0, 0.0, 0.05, -HUGE_VAL, -HUGE_VAL};
    const double upper[N_PARAMS] = {HUGE_VAL, 10.0, 5.0, HUGE_VAL, HUGE_VAL};
    brdffit_status st;
    int ok;

    make_data(&d);
    policy.name = "trust";
    policy.state_size = sizeof(trust_state);
    policy.init = trust_init;
    policy.accept = trust_accept;
    policy.reject = trust_reject;

    if (brdffit_optimizer_create(&opt, N_PARAMS, NULL, &err) != BRDFFIT_OK) {
        fprintf(stderr, "curve_fit: %s\n", err.message);
        return 1;
    }
    st = brdffit_optimizer_set_residuals(opt, N_POINTS, residuals, &d);
    if (st == BRDFFIT_OK) st = brdffit_optimizer_set_damping(opt, &policy);
    if (st == BRDFFIT_OK) st = brdffit_optimizer_set_bounds(opt, lower, upper);
    if (st == BRDFFIT_OK) st = brdffit_optimizer_set_callback(opt, print_iteration, NULL);
    if (st == BRDFFIT_OK) {
        printf("fitting %d points with the '%s' damping policy\n", N_POINTS, policy.name);
        st = brdffit_optimizer_run(opt, p);
    }
    if (st != BRDFFIT_OK) {
        fprintf(stderr, "curve_fit: %s: %s\n", brdffit_status_name(st),
                brdffit_optimizer_message(opt));
        brdffit_optimizer_destroy(opt);
        return 1;
    }
    ok = report(opt, p);
    brdffit_optimizer_destroy(opt);
    printf("%s\n", ok ? "fit recovers the parameters" : "FIT FAILED");
    return ok ? 0 : 1;
}
