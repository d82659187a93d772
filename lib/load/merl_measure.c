/* The measure of a MERL cell in light x view space; the derivation is in
 * docs/measure.md.
 *
 * With the Rusinkiewicz half/difference angles,
 *     d(omega_i) d(omega_o) = 4 cos(theta_d) sin(theta_h) sin(theta_d)
 *                             d(theta_h) d(phi_h) d(theta_d) d(phi_d),
 * so in u = cos(theta_h) and s = sin(theta_d)^2 a cell's measure is
 *     16 pi * 1/2 * integral over the cell of L(u, s) du ds,
 * 16 pi = 4 (the Jacobian) x 2 pi (phi_h) x 2 (phi_d and phi_d + pi), and
 * L the length of the cell's phi_d interval where both directions lie
 * above the horizon: l_z, v_z = cos(theta_d) cos(theta_h) -+ sin(theta_d)
 * cos(phi_d) sin(theta_h), both > 0 when |cos(phi_d)| < cot(theta_h)
 * cot(theta_d). Cells the horizon does not cut have L = their phi_d width
 * and a closed form; the others are integrated by a tensor Gauss-Legendre
 * rule in (u, s). */
#include <math.h>

#include "core/core.h"
#include "core/quadrature.h"
#include "load/merl_measure.h"

#define N_TH 90
#define N_TD 90
#define N_PD 180
#define FACTOR (16.0 * BF_PI)

void bf_merl_measure_init(bf_merl_measure *m)
{
    bf_gauss_legendre(BF_MERL_MEASURE_POINTS, m->x, m->w);
}

/* Cell edges: theta_h = (i / 90)^2 pi/2, theta_d = j / 90 pi/2, phi_d = k / 180 pi. */
static double edge_h(size_t i)
{
    double t = (double)i / N_TH;
    return t * t * BF_HALF_PI;
}

static double edge_d(size_t j)
{
    return (double)j / N_TD * BF_HALF_PI;
}

static double edge_p(size_t k)
{
    return (double)k / N_PD * BF_PI;
}

/* Length of [p0, p1] (within [0, pi]) where |cos(phi)| < cot(theta_h)
 * cot(theta_d), given u = cos(theta_h) and s = sin(theta_d)^2. */
static double above_length(double u, double s, double p0, double p1)
{
    double num = u * sqrt(fmax(1.0 - s, 0.0)), den = sqrt(fmax((1.0 - u * u) * s, 0.0));
    double a, lo, hi;
    if (num >= den) return p1 - p0; /* cot cot >= 1: every phi_d */
    a = acos(num / den);            /* the allowed phi_d are (a, pi - a) */
    lo = fmax(p0, a);
    hi = fmin(p1, BF_PI - a);
    return hi > lo ? hi - lo : 0.0;
}

/* sin(theta_d)^2 where cot(theta_h) cot(theta_d) = c, for u = cos(theta_h). */
static double s_at(double u, double c)
{
    double q = u * u + c * c * (1.0 - u * u);
    return q > 0.0 ? u * u / q : 1.0;
}

/* cos(theta_h) where cot(theta_h) cot(theta_d) = c, for s = sin(theta_d)^2. */
static double u_at(double s, double c)
{
    double q = 1.0 - s * (1.0 - c * c);
    return q > 0.0 ? sqrt(s * c * c / q) : 1.0;
}

static void sort(double *x, size_t n)
{
    size_t a, b;
    for (a = 1; a < n; a++) /* insertion sort of a handful of numbers */
        for (b = a; b > 0 && x[b] < x[b - 1]; b--) {
            double t = x[b];
            x[b] = x[b - 1];
            x[b - 1] = t;
        }
}

/* The cell's data: its (u, s) ranges, its phi_d edges and the three values
 * of cot(theta_h) cot(theta_d) where the integrand has a kink. */
typedef struct cell {
    const bf_merl_measure *m;
    double u0, u1, s0, s1, p0, p1, c[3];
} cell;

/* Integral over s in [s0, s1] of above_length(u, s), split where the
 * allowed phi_d interval meets the cell's edges or vanishes, so the rule
 * sees a smooth integrand on every piece. */
static double s_integral(const cell *k, double u)
{
    double cut[5] = {k->s0, s_at(u, k->c[0]), s_at(u, k->c[1]), s_at(u, k->c[2]), k->s1};
    double sum = 0.0;
    size_t i, b;
    sort(cut, 5);
    for (i = 0; i + 1 < 5; i++) {
        double lo = fmax(cut[i], k->s0), hi = fmin(cut[i + 1], k->s1), piece = 0.0;
        if (!(hi > lo)) continue;
        for (b = 0; b < BF_MERL_MEASURE_POINTS; b++)
            piece += k->m->w[b] *
                     above_length(u, 0.5 * (lo + hi) + 0.5 * (hi - lo) * k->m->x[b], k->p0, k->p1);
        sum += 0.5 * (hi - lo) * piece;
    }
    return sum;
}

/* The same over u, split where a kink of the s integrand crosses s0 or s1. */
static double cut_cell(const cell *k)
{
    double cut[8], sum = 0.0;
    size_t i, b, n = 0;
    cut[n++] = k->u0;
    cut[n++] = k->u1;
    for (i = 0; i < 3; i++) {
        cut[n++] = u_at(k->s0, k->c[i]);
        cut[n++] = u_at(k->s1, k->c[i]);
    }
    sort(cut, n);
    for (i = 0; i + 1 < n; i++) {
        double lo = fmax(cut[i], k->u0), hi = fmin(cut[i + 1], k->u1), piece = 0.0;
        if (!(hi > lo)) continue;
        for (b = 0; b < BF_MERL_MEASURE_POINTS; b++)
            piece += k->m->w[b] * s_integral(k, 0.5 * (lo + hi) + 0.5 * (hi - lo) * k->m->x[b]);
        sum += 0.5 * (hi - lo) * piece;
    }
    return FACTOR * 0.5 * sum;
}

double bf_merl_cell_measure(const bf_merl_measure *m, size_t ih, size_t id, size_t ip)
{
    double h0 = edge_h(ih), h1 = edge_h(ih + 1), d0 = edge_d(id), d1 = edge_d(id + 1);
    double p0 = edge_p(ip), p1 = edge_p(ip + 1);
    double cos_max = fmax(fabs(cos(p0)), fabs(cos(p1)));
    /* cos(theta_h) - cos(theta_h') and sin^2 - sin^2 without cancellation */
    double du = 2.0 * sin(0.5 * (h0 + h1)) * sin(0.5 * (h1 - h0));
    double ds = sin(d1 + d0) * sin(d1 - d0);
    if (cos(h1) * cos(d1) > sin(h1) * sin(d1) * cos_max) /* the cell's worst corner is above */
        return FACTOR * 0.5 * du * ds * (p1 - p0);
    {
        cell k = {m, cos(h1), cos(h0), 0.0, 0.0, p0, p1, {fabs(cos(p0)), fabs(cos(p1)), 1.0}};
        k.s0 = sin(d0) * sin(d0), k.s1 = sin(d1) * sin(d1);
        return cut_cell(&k);
    }
}
