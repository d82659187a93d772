/* The damped step with bounds and fixed parameters (an active-set,
 * projected Levenberg-Marquardt step):
 *
 * 1. Held: fixed parameters, and parameters on a bound whose gradient
 *    points out of the box.
 * 2. Solve (A + lambda D) delta = -g over the others (A = J^T J,
 *    g = J^T r), equilibrated to unit diagonal, by Cholesky, or by the
 *    eigen-decomposition pseudo-inverse when Cholesky fails or its pivots
 *    show bad conditioning.
 * 3. A parameter on a bound whose delta still points out of the box is
 *    held too, and step 2 is repeated (at most once per parameter).
 * 4. trial = projection of x + t delta onto the box; the predicted
 *    reduction is that of the model for the step actually taken. */
#include <math.h>
#include <string.h>

#include "core/linalg.h"
#include "optim/optim_internal.h"

int bf_optim_on_bound(const brdffit_optimizer *opt, size_t j, const double *x)
{
    return x[j] <= opt->w.lower[j] || x[j] >= opt->w.upper[j];
}

/* How stale the remembered scaling is: the smallest ratio of a free
 * parameter's entry of D to its diag(J^T J) when every one exceeds
 * BF_SCALE_RESET (the problem's scale as a whole has changed since, as on
 * the way from a far start, not one parameter's, as one passing through
 * zero), else 0. */
static double staleness(const bf_optim_work *w, size_t p)
{
    size_t j;
    double least = HUGE_VAL;
    int any = 0;
    for (j = 0; j < p; j++) {
        double a = w->jtj[j * p + j];
        if (w->fixed[j]) continue;
        if (!(w->d[j] > BF_SCALE_RESET * a)) return 0.0;
        if (a > 0.0) least = fmin(least, w->d[j] / a);
        any = 1;
    }
    return any ? least : 0.0;
}

/* Marquardt's D: diag(J^T J) at the current point, floored at DIAG_FLOOR
 * times the largest its column had in the attempt; or with the scale
 * memory its running maximum, which needs no floor. Each entry depends on
 * its own column only, so rescaling a parameter scales its entry alone
 * and the step does not depend on the parameters' units. When the memory
 * is stale (staleness()) every entry is divided by the same factor, the
 * least stale one's, so that the entries keep their ratios. */
static void marquardt_scaling(brdffit_optimizer *opt, int set_d0)
{
    const bf_optim_work *w = &opt->w;
    size_t j, p = opt->n_params;
    double stale = set_d0 || !opt->settings.scale_memory ? 0.0 : staleness(w, p);
    for (j = 0; j < p; j++) {
        double a = w->jtj[j * p + j];
        if (!opt->settings.scale_memory)
            w->d[j] = fmax(a, fmax(opt->settings.diag_floor * w->amax[j], BF_SCALE_ABS_FLOOR));
        else if (set_d0)
            w->d[j] = fmax(a, BF_SCALE_ABS_FLOOR);
        else if (stale > 0.0)
            w->d[j] = fmax(fmax(a, w->d[j] / stale), BF_SCALE_ABS_FLOOR);
        else
            w->d[j] = fmax(w->d[j], a);
    }
}

void bf_optim_update_scaling(brdffit_optimizer *opt, int set_d0)
{
    const bf_optim_work *w = &opt->w;
    size_t j, p = opt->n_params;
    double dmax = 0.0;
    bf_optim_forget_step(opt);
    for (j = 0; j < p; j++) {
        double a = w->jtj[j * p + j];
        w->amax[j] = set_d0 ? a : fmax(w->amax[j], a);
        if (!w->fixed[j] && a > dmax) dmax = a;
    }
    if (opt->settings.marquardt) {
        marquardt_scaling(opt, set_d0);
        return;
    }
    if (!set_d0) return;
    dmax = fmax(dmax, BF_SCALE_ABS_FLOOR);
    for (j = 0; j < p; j++) w->d[j] = dmax;
}

/* Held at the start of a step: fixed, or on a bound with the descent
 * direction -g pointing out of the box. */
static void init_held(brdffit_optimizer *opt)
{
    bf_optim_work *w = &opt->w;
    size_t j;
    for (j = 0; j < opt->n_params; j++) {
        double x = w->x[j], g = w->g[j];
        w->held[j] = w->fixed[j] || (x <= w->lower[j] && g > 0.0) || (x >= w->upper[j] && g < 0.0);
    }
}

static size_t gather_free(bf_optim_work *w, size_t p)
{
    size_t j, nf = 0;
    for (j = 0; j < p; j++)
        if (!w->held[j]) w->free_idx[nf++] = j;
    return nf;
}

/* Parameter j's diagonal of A + lambda D, the only place lambda enters
 * the step. */
static double damped(const bf_optim_work *w, size_t p, size_t j, double lambda)
{
    return w->jtj[j * p + j] + lambda * w->d[j];
}

int bf_optim_same_damping(const brdffit_optimizer *opt, double l1, double l2)
{
    const bf_optim_work *w = &opt->w;
    size_t j, p = opt->n_params;
    if (l1 == l2) return 1;
    for (j = 0; j < p; j++)
        if (!w->fixed[j] && !(damped(w, p, j, l1) == damped(w, p, j, l2))) return 0;
    return 1;
}

/* Equilibration factors of A + lambda D over the free set. A parameter
 * whose damped diagonal is zero or overflows gets factor 0: no step. */
static void equilibrate(brdffit_optimizer *opt, size_t nf, double lambda)
{
    bf_optim_work *w = &opt->w;
    size_t a, p = opt->n_params;
    for (a = 0; a < nf; a++) {
        size_t j = w->free_idx[a];
        double mjj = damped(w, p, j, lambda);
        w->scale[a] = mjj > 0.0 && isfinite(mjj) ? 1.0 / sqrt(mjj) : 0.0;
    }
}

/* m = S (A + lambda D) S over the free set; unit diagonal by construction.
 * With lower, the lower triangle and the diagonal only (all Cholesky reads). */
static void build_scaled(brdffit_optimizer *opt, size_t nf, int lower)
{
    bf_optim_work *w = &opt->w;
    size_t a, b, p = opt->n_params;
    for (a = 0; a < nf; a++) {
        const double *arow = w->jtj + w->free_idx[a] * p;
        double *mrow = w->m + a * nf;
        size_t end = lower ? a : nf;
        for (b = 0; b < end; b++) mrow[b] = arow[w->free_idx[b]] * w->scale[a] * w->scale[b];
        mrow[a] = 1.0;
    }
}

static int stop_requested(const void *ctx)
{
    return bf_optim_stopped(ctx);
}

/* delta (nf values) = -(A + lambda D)^-1 g over the free set; 0 (no step)
 * when a cancel stopped the solve. */
static void solve_reduced(brdffit_optimizer *opt, size_t nf, double lambda, int *fallback,
                          double *pivot)
{
    bf_optim_work *w = &opt->w;
    const bf_stop stop = {stop_requested, opt};
    size_t a;
    int factored;
    equilibrate(opt, nf, lambda);
    build_scaled(opt, nf, 1);
    for (a = 0; a < nf; a++) w->delta[a] = -w->g[w->free_idx[a]] * w->scale[a];
    factored = bf_cholesky_until(w->m, nf, BF_LINALG_RTOL, &stop);
    *pivot = 0.0;
    if (factored == 1) {
        *pivot = HUGE_VAL;
        for (a = 0; a < nf; a++) *pivot = fmin(*pivot, w->m[a * nf + a] * w->m[a * nf + a]);
        bf_cholesky_solve(w->m, nf, w->delta);
    } else if (factored == 0) {
        *fallback = 1;
        build_scaled(opt, nf, 0);
        if (bf_sym_eigen_until(w->m, nf, w->w, w->v, &stop) >= 0)
            bf_eigen_pinv_solve(w->w, w->v, nf, BF_LINALG_RTOL, w->delta, w->delta, w->tmp);
        else
            factored = -1;
    }
    for (a = 0; a < nf; a++) w->delta[a] = factored < 0 ? 0.0 : w->delta[a] * w->scale[a];
}

/* Hold free parameters on a bound whose delta points out of the box.
 * Returns whether any was added. */
static int hold_outward(bf_optim_work *w, size_t nf)
{
    size_t a;
    int changed = 0;
    for (a = 0; a < nf; a++) {
        size_t j = w->free_idx[a];
        double x = w->x[j], dj = w->delta[a];
        if ((x <= w->lower[j] && dj < 0.0) || (x >= w->upper[j] && dj > 0.0)) {
            w->held[j] = 1;
            changed = 1;
        }
    }
    return changed;
}

/* Shorten delta, keeping its direction, so that no parameter changes by
 * more than bound times its scale (the largest magnitude it has had in
 * the run). A parameter that has only ever been 0 has no scale and sets
 * no bound. */
static int bound_step(bf_optim_work *w, size_t nf, double bound)
{
    size_t a;
    double r = 0.0;
    for (a = 0; a < nf; a++) {
        double s = w->xscale[w->free_idx[a]];
        if (s > 0.0 && fabs(w->delta[a]) > r * s) r = fabs(w->delta[a]) / s;
    }
    if (!(r > bound)) return 0;
    for (a = 0; a < nf; a++) w->delta[a] *= bound / r;
    return 1;
}

/* trial = P(x + t delta), step = trial - x. Returns whether the
 * projection moved a value. */
static int project_trial(bf_optim_work *w, size_t p, size_t nf, double t)
{
    size_t a, j;
    int clipped = 0;
    memcpy(w->trial, w->x, p * sizeof *w->trial);
    for (a = 0; a < nf; a++) {
        double v;
        j = w->free_idx[a];
        v = w->x[j] + t * w->delta[a];
        if (v < w->lower[j]) v = w->lower[j], clipped = 1;
        if (v > w->upper[j]) v = w->upper[j], clipped = 1;
        w->trial[j] = v;
    }
    for (j = 0; j < p; j++) w->step[j] = w->trial[j] - w->x[j];
    return clipped;
}

/* Predicted reduction of the linear model for step s:
 * cost - |r + J s|^2 = -(2 g.s + s.A s). */
static double predicted_reduction(const bf_optim_work *w, size_t p)
{
    double gs = 0.0, sas = 0.0;
    size_t j, k;
    for (j = 0; j < p; j++) {
        const double *row = w->jtj + j * p;
        double sj = w->step[j], as = 0.0;
        if (sj == 0.0) continue;
        gs += w->g[j] * sj;
        for (k = 0; k < p; k++)
            if (w->step[k] != 0.0) as += row[k] * w->step[k];
        sas += sj * as;
    }
    return -(2.0 * gs + sas);
}

void bf_optim_forget_step(brdffit_optimizer *opt)
{
    opt->memo.valid = 0;
}

void bf_optim_step_only(brdffit_optimizer *opt, double lambda, double t, double bound, int *bounded,
                        int *fallback)
{
    bf_optim_work *w = &opt->w;
    bf_step_memo *memo = &opt->memo;
    size_t p = opt->n_params, nf;
    double pivot = 0.0;
    int used_fallback = 0, rounds = 0, clipped;
    if (memo->valid && memo->t == t && memo->bound == bound &&
        bf_optim_same_damping(opt, memo->lambda, lambda)) {
        *bounded = memo->bounded;
        if (memo->fallback) *fallback = 1;
        return;
    }
    init_held(opt);
    for (;;) {
        nf = gather_free(w, p);
        if (nf == 0) break;
        solve_reduced(opt, nf, lambda, &used_fallback, &pivot);
        rounds++;
        if (!hold_outward(w, nf)) break;
    }
    *bounded = nf > 0 && bound_step(w, nf, bound);
    clipped = project_trial(w, p, nf, t);
    if (used_fallback) *fallback = 1;
    memo->pivot = rounds == 1 && !*bounded && !clipped && !used_fallback ? pivot : 0.0;
    memo->lambda = lambda;
    memo->t = t;
    memo->bound = bound;
    memo->bounded = *bounded;
    memo->fallback = used_fallback;
    memo->valid = !bf_optim_stopped(opt); /* a cancelled solve left no step */
}

double bf_optim_step(brdffit_optimizer *opt, double lambda, double t, double bound, int *bounded,
                     int *fallback)
{
    bf_optim_step_only(opt, lambda, t, bound, bounded, fallback);
    return predicted_reduction(&opt->w, opt->n_params);
}
