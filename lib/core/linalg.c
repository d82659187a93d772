/* Dense symmetric linear algebra: Cholesky with a conditioning check,
 * cyclic Jacobi eigen-decomposition, pseudo-inverses. See linalg.h. */
#include "core/linalg.h"

#include "core/core.h"

#include <float.h>
#include <math.h>

enum { BF_JACOBI_MAX_SWEEPS = 64 };

BF_VECTOR_CLONES
double bf_dot(const double *restrict a, const double *restrict b, size_t n)
{
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    size_t k = 0;
    for (; k + 4 <= n; k += 4) {
        s0 += a[k] * b[k];
        s1 += a[k + 1] * b[k + 1];
        s2 += a[k + 2] * b[k + 2];
        s3 += a[k + 3] * b[k + 3];
    }
    for (; k < n; k++) s0 += a[k] * b[k];
    return (s0 + s1) + (s2 + s3);
}

static int stop_asked(const bf_stop *stop)
{
    return stop != NULL && stop->fn(stop->ctx);
}

int bf_cholesky(double *a, size_t n, double rtol)
{
    return bf_cholesky_until(a, n, rtol, NULL) == 1;
}

int bf_cholesky_until(double *a, size_t n, double rtol, const bf_stop *stop)
{
    double dmin = HUGE_VAL, dmax = 0.0;
    size_t i, j;
    for (j = 0; j < n; j++) {
        double *rj = a + j * n;
        if (stop != NULL && j % 16 == 0 && stop_asked(stop)) return -1;
        double d = rj[j] - bf_dot(rj, rj, j), ljj;
        if (!(d > 0.0) || !isfinite(d)) return 0;
        if (d < dmin) dmin = d;
        if (d > dmax) dmax = d;
        ljj = sqrt(d);
        rj[j] = ljj;
        for (i = j + 1; i < n; i++) {
            double *ri = a + i * n;
            ri[j] = (ri[j] - bf_dot(ri, rj, j)) / ljj;
        }
    }
    return n == 0 || dmin >= rtol * dmax;
}

void bf_cholesky_solve(const double *l, size_t n, double *b)
{
    size_t i, k;
    for (i = 0; i < n; i++) { /* L y = b */
        const double *ri = l + i * n;
        b[i] = (b[i] - bf_dot(ri, b, i)) / ri[i];
    }
    for (i = n; i-- > 0;) { /* L^T x = y */
        double s = b[i];
        for (k = i + 1; k < n; k++) s -= l[k * n + i] * b[k];
        b[i] = s / l[i * n + i];
    }
}

/* tan of the rotation angle that zeroes a_pq. */
static double jacobi_tan(double app, double aqq, double apq)
{
    double theta = (aqq - app) / (2.0 * apq);
    if (fabs(theta) > 1e150) return 0.5 / theta;
    return (theta >= 0.0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
}

static void jacobi_rotate(double *a, size_t n, double *v, size_t p, size_t q)
{
    double apq = a[p * n + q];
    double t = jacobi_tan(a[p * n + p], a[q * n + q], apq);
    double c = 1.0 / sqrt(t * t + 1.0), s = t * c;
    size_t k;
    for (k = 0; k < n; k++) {
        double akp, akq;
        if (k == p || k == q) continue;
        akp = a[k * n + p];
        akq = a[k * n + q];
        a[k * n + p] = a[p * n + k] = c * akp - s * akq;
        a[k * n + q] = a[q * n + k] = s * akp + c * akq;
    }
    a[p * n + p] -= t * apq;
    a[q * n + q] += t * apq;
    a[p * n + q] = a[q * n + p] = 0.0;
    if (v == NULL) return;
    for (k = 0; k < n; k++) {
        double vkp = v[k * n + p], vkq = v[k * n + q];
        v[k * n + p] = c * vkp - s * vkq;
        v[k * n + q] = s * vkp + c * vkq;
    }
}

/* One cyclic sweep; returns the number of rotations made. An element too
 * small to change either diagonal entry in floating point is set to 0.
 * *stopped is set when `stop` asks to give up (checked once per row). */
static size_t jacobi_sweep(double *a, size_t n, double *v, const bf_stop *stop, int *stopped)
{
    size_t p, q, rotations = 0;
    for (p = 0; p + 1 < n; p++) {
        if (stop_asked(stop)) {
            *stopped = 1;
            return rotations;
        }
        for (q = p + 1; q < n; q++) {
            double apq = a[p * n + q];
            double scale = sqrt(fabs(a[p * n + p])) * sqrt(fabs(a[q * n + q]));
            if (apq == 0.0) continue;
            if (fabs(apq) <= 0.5 * DBL_EPSILON * scale) {
                a[p * n + q] = a[q * n + p] = 0.0;
                continue;
            }
            jacobi_rotate(a, n, v, p, q);
            rotations++;
        }
    }
    return rotations;
}

int bf_sym_eigen(double *a, size_t n, double *w, double *v)
{
    return bf_sym_eigen_until(a, n, w, v, NULL);
}

int bf_sym_eigen_until(double *a, size_t n, double *w, double *v, const bf_stop *stop)
{
    size_t i, sweep;
    int converged = 0, stopped = 0;
    if (v != NULL) {
        for (i = 0; i < n * n; i++) v[i] = 0.0;
        for (i = 0; i < n; i++) v[i * n + i] = 1.0;
    }
    for (sweep = 0; sweep < BF_JACOBI_MAX_SWEEPS && !converged && !stopped; sweep++)
        converged = jacobi_sweep(a, n, v, stop, &stopped) == 0 && !stopped;
    if (stopped) return -1;
    for (i = 0; i < n; i++) w[i] = a[i * n + i];
    return converged;
}

static double eigen_threshold(const double *w, size_t n, double rtol)
{
    double wmax = 0.0;
    size_t k;
    for (k = 0; k < n; k++)
        if (w[k] > wmax) wmax = w[k];
    return rtol * wmax;
}

void bf_eigen_pinv_solve(const double *w, const double *v, size_t n, double rtol, const double *b,
                         double *x, double *tmp)
{
    double thr = eigen_threshold(w, n, rtol);
    size_t i, k;
    for (k = 0; k < n; k++) {
        double s = 0.0;
        if (w[k] > thr) {
            for (i = 0; i < n; i++) s += v[i * n + k] * b[i];
            s /= w[k];
        }
        tmp[k] = s;
    }
    for (i = 0; i < n; i++) {
        double s = 0.0;
        for (k = 0; k < n; k++) s += v[i * n + k] * tmp[k];
        x[i] = s;
    }
}

int bf_eigen_pinv(const double *w, const double *v, size_t n, double rtol, double *out,
                  const bf_stop *stop)
{
    double thr = eigen_threshold(w, n, rtol);
    size_t i, j, k;
    for (i = 0; i < n; i++) {
        if (stop_asked(stop)) return 0;
        for (j = i; j < n; j++) {
            double s = 0.0;
            for (k = 0; k < n; k++)
                if (w[k] > thr) s += v[i * n + k] * v[j * n + k] / w[k];
            out[i * n + j] = out[j * n + i] = s;
        }
    }
    return 1;
}

double bf_eigen_condition(const double *w, size_t n)
{
    double wmin = HUGE_VAL, wmax = -HUGE_VAL;
    size_t k;
    if (n == 0) return 1.0;
    for (k = 0; k < n; k++) {
        if (w[k] < wmin) wmin = w[k];
        if (w[k] > wmax) wmax = w[k];
    }
    if (!(wmin > 0.0)) return HUGE_VAL;
    return wmax / wmin;
}
