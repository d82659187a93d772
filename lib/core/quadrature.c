/* Gauss-Legendre rules: the roots of the Legendre polynomial P_n found by
 * Newton's method from the asymptotic first guesses
 * cos(pi (k + 3/4) / (n + 1/2)), P_n and P_n' from the three-term
 * recurrence; weights 2 / ((1 - x^2) P_n'(x)^2). */
#include <math.h>

#include "core/core.h"
#include "core/quadrature.h"

/* P_n(x) and P_n'(x). */
static void legendre(size_t n, double x, double *p, double *dp)
{
    double p0 = 1.0, p1 = x;
    size_t k;
    for (k = 2; k <= n; k++) {
        double p2 = ((double)(2 * k - 1) * x * p1 - (double)(k - 1) * p0) / (double)k;
        p0 = p1;
        p1 = p2;
    }
    *p = n == 0 ? 1.0 : p1;
    *dp = (double)n * (x * p1 - p0) / (x * x - 1.0);
}

void bf_gauss_legendre(size_t n, double *x, double *w)
{
    size_t k, it;
    for (k = 0; k < (n + 1) / 2; k++) {
        double r = cos(BF_PI * ((double)k + 0.75) / ((double)n + 0.5)), p = 0.0, dp = 1.0;
        for (it = 0; it < 100; it++) {
            double step;
            legendre(n, r, &p, &dp);
            step = p / dp;
            r -= step;
            if (fabs(step) < 1e-16) break;
        }
        legendre(n, r, &p, &dp);
        x[n - 1 - k] = r;
        x[k] = -r;
        w[k] = w[n - 1 - k] = 2.0 / ((1.0 - r * r) * dp * dp);
    }
    if (n % 2 == 1) x[n / 2] = 0.0; /* the middle root, exactly */
}
