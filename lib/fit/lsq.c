#include "fit/lsq.h"

#include "core/linalg.h"

#include <math.h>
#include <string.h>

/* Solve A x = y for symmetric positive definite A (n x n, row-major); 0
 * when A is too badly conditioned to trust (the caller then tries other
 * active sets). */
static int chol_solve(size_t n, const double *A, const double *y, double *x)
{
    double L[BF_LSQ_MAX * BF_LSQ_MAX];
    memcpy(L, A, n * n * sizeof *L);
    if (!bf_cholesky(L, n, 1e-13)) return 0;
    memcpy(x, y, n * sizeof *x);
    bf_cholesky_solve(L, n, x);
    return 1;
}

static double objective(size_t K, const double *G, const double *b, const double *c)
{
    double f = 0.0;
    size_t i, j;
    for (i = 0; i < K; i++) {
        double gi = 0.0;
        for (j = 0; j < K; j++) gi += G[i * K + j] * c[j];
        f += c[i] * gi - 2.0 * b[i] * c[i];
    }
    return f;
}

/* One assignment: state[i] 0 = free, 1 = at lower, 2 = at upper. Returns 0
 * when infeasible or singular. */
static int try_assignment(size_t K, const double *G, const double *b, const double *lower,
                          const double *upper, const int *state, double *c)
{
    double A[BF_LSQ_MAX * BF_LSQ_MAX], y[BF_LSQ_MAX], x[BF_LSQ_MAX];
    size_t idx[BF_LSQ_MAX], nf = 0, i, j;
    for (i = 0; i < K; i++) {
        if (state[i] == 1) c[i] = lower[i];
        else if (state[i] == 2) c[i] = upper[i];
        else idx[nf++] = i;
        if (state[i] != 0 && !isfinite(c[i])) return 0;
    }
    for (i = 0; i < nf; i++) {
        double sum = b[idx[i]];
        for (j = 0; j < K; j++)
            if (state[j] != 0) sum -= G[idx[i] * K + j] * c[j];
        y[i] = sum;
        for (j = 0; j < nf; j++) A[i * nf + j] = G[idx[i] * K + idx[j]];
    }
    if (nf > 0 && !chol_solve(nf, A, y, x)) return 0;
    for (i = 0; i < nf; i++) {
        if (x[i] < lower[idx[i]] || x[i] > upper[idx[i]]) return 0;
        c[idx[i]] = x[i];
    }
    return 1;
}

/* Every assignment, the best kept; with free_first, the first (every
 * variable free) alone when it is feasible. */
static double enumerate(size_t K, const double *G, const double *b, const double *lower,
                        const double *upper, double *c, int free_first)
{
    int state[BF_LSQ_MAX];
    double trial[BF_LSQ_MAX], best = HUGE_VAL;
    size_t i, total = 1, code;
    for (i = 0; i < K; i++) total *= 3;
    for (code = 0; code < total; code++) {
        size_t rest = code;
        double f;
        for (i = 0; i < K; i++) {
            state[i] = (int)(rest % 3);
            rest /= 3;
        }
        if (!try_assignment(K, G, b, lower, upper, state, trial)) continue;
        f = objective(K, G, b, trial);
        if (f < best) {
            best = f;
            memcpy(c, trial, K * sizeof *c);
        }
        if (code == 0 && free_first) break;
    }
    return best;
}

static double clampd(double x, double lo, double hi)
{
    return x < lo ? lo : (x > hi ? hi : x);
}

/* Projected Gauss-Seidel with a small ridge; converges for positive
 * semi-definite G. */
static double gauss_seidel(size_t K, const double *G, const double *b, const double *lower,
                           const double *upper, double *c)
{
    size_t i, j, sweep;
    double trace = 0.0;
    for (i = 0; i < K; i++) trace += G[i * K + i];
    for (i = 0; i < K; i++) c[i] = clampd(0.0, lower[i], upper[i]);
    for (sweep = 0; sweep < 10000; sweep++) {
        double change = 0.0, size = 0.0;
        for (i = 0; i < K; i++) {
            double diag = G[i * K + i] + 1e-14 * trace + 1e-300, sum = b[i], old = c[i];
            for (j = 0; j < K; j++)
                if (j != i) sum -= G[i * K + j] * c[j];
            c[i] = clampd(sum / diag, lower[i], upper[i]);
            change = fmax(change, fabs(c[i] - old));
            size = fmax(size, fabs(c[i]));
        }
        if (change <= 1e-15 * size) break;
    }
    return objective(K, G, b, c);
}

/* The bounded minimum of two variables in closed form into c and its
 * objective into *f, when G is safely positive definite (else 0): the
 * unconstrained minimiser when it lies inside the bounds; otherwise the
 * minimum lies on the box's boundary, and on each edge (one variable at a
 * finite bound) it is the other's one-dimensional minimiser clamped into
 * its bounds (the problem is strictly convex). */
static int bounded_pair(const double *G, const double *b, const double *lower,
                        const double *upper, double *c, double *f)
{
    double det = G[0] * G[3] - G[1] * G[2], t[2];
    size_t i, side;
    if (!(det > 1e-12 * G[0] * G[3])) return 0;
    c[0] = (G[3] * b[0] - G[1] * b[1]) / det;
    c[1] = (G[0] * b[1] - G[2] * b[0]) / det;
    if (c[0] >= lower[0] && c[0] <= upper[0] && c[1] >= lower[1] && c[1] <= upper[1]) {
        *f = objective(2, G, b, c);
        return 1;
    }
    *f = HUGE_VAL;
    for (i = 0; i < 2; i++)
        for (side = 0; side < 2; side++) {
            size_t j = 1 - i;
            double v;
            t[i] = side ? upper[i] : lower[i];
            if (!isfinite(t[i])) continue;
            t[j] = clampd((b[j] - G[j * 2 + i] * t[i]) / G[j * 2 + j], lower[j], upper[j]);
            v = objective(2, G, b, t);
            if (v < *f) {
                *f = v;
                c[0] = t[0];
                c[1] = t[1];
            }
        }
    return *f < HUGE_VAL;
}

/* Solve in Jacobi-scaled variables c = D c', D = diag(G)^(-1/2), so that
 * bases of very different magnitude (a constant diffuse term next to a
 * sharp lobe) do not spoil the conditioning. A variable whose basis is zero
 * has no effect and is set to the bound nearest 0. */
static double bounded_lsq(size_t K, const double *G, const double *b, const double *lower,
                          const double *upper, double *c, int free_first)
{
    double Gs[BF_LSQ_MAX * BF_LSQ_MAX], bs[BF_LSQ_MAX], lo[BF_LSQ_MAX], hi[BF_LSQ_MAX];
    double d[BF_LSQ_MAX], cs[BF_LSQ_MAX], f = HUGE_VAL;
    size_t i, j;
    if (K == 0) return 0.0;
    for (i = 0; i < K; i++) d[i] = G[i * K + i] > 0.0 ? 1.0 / sqrt(G[i * K + i]) : 0.0;
    for (i = 0; i < K; i++) {
        for (j = 0; j < K; j++) Gs[i * K + j] = d[i] * d[j] * G[i * K + j];
        if (d[i] == 0.0) Gs[i * K + i] = 1.0; /* no effect: any value, pinned below */
        bs[i] = d[i] * b[i];
        lo[i] = d[i] > 0.0 ? lower[i] / d[i] : clampd(0.0, lower[i], upper[i]);
        hi[i] = d[i] > 0.0 ? upper[i] / d[i] : lo[i];
    }
    if (free_first && K == 2 && bounded_pair(Gs, bs, lo, hi, cs, &f)) {
        /* done in closed form */
    } else if (K <= 6) {
        f = enumerate(K, Gs, bs, lo, hi, cs, free_first);
    }
    if (!(f < HUGE_VAL)) f = gauss_seidel(K, Gs, bs, lo, hi, cs);
    for (i = 0; i < K; i++) c[i] = d[i] > 0.0 ? d[i] * cs[i] : lo[i];
    return f;
}

double bf_bounded_lsq(size_t K, const double *G, const double *b, const double *lower,
                      const double *upper, double *c)
{
    return bounded_lsq(K, G, b, lower, upper, c, 0);
}

double bf_bounded_lsq_quick(size_t K, const double *G, const double *b, const double *lower,
                            const double *upper, double *c)
{
    return bounded_lsq(K, G, b, lower, upper, c, 1);
}
