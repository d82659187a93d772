/* Branch-free elementary functions that the compiler can vectorise inside
 * the model kernels' sample loops (a call into libm would keep every such
 * loop scalar). Accurate to about one unit in the last place over the whole
 * double range; results are the same on every machine. Not installed. */
#ifndef BRDFFIT_FASTMATH_H
#define BRDFFIT_FASTMATH_H

#include <stdint.h>
#include <string.h>

/* e^x for finite x, to about one unit in the last place. Results below
 * e^-708 (about 3e-308, the edge of the normal range) are flushed to 0 and
 * arguments above 709 are clamped to 709 (e^709 ~ 8e307): the kernels never
 * need more. Only arithmetic and 64-bit integer adds and shifts, so sample
 * loops calling it vectorise. */
static inline double bf_exp(double x)
{
    const double log2e = 1.4426950408889634, ln2_hi = 6.93147180369123816490e-01,
                 ln2_lo = 1.90821492927058770002e-10, shifter = 6755399441055744.0; /* 1.5 * 2^52 */
    double t, k, r, p, scale, keep = x >= -708.0 ? 1.0 : 0.0;
    uint64_t bits;
    x = x < -708.0 ? -708.0 : (x > 709.0 ? 709.0 : x);
    t = x * log2e + shifter; /* the low mantissa bits of t now hold round(x / ln 2) */
    k = t - shifter;
    r = (x - k * ln2_hi) - k * ln2_lo;
    /* e^r for |r| <= ln2 / 2: Taylor to degree 13 (truncation < 1e-17) */
    p = 1.0 / 6227020800.0;
    p = p * r + 1.0 / 479001600.0;
    p = p * r + 1.0 / 39916800.0;
    p = p * r + 1.0 / 3628800.0;
    p = p * r + 1.0 / 362880.0;
    p = p * r + 1.0 / 40320.0;
    p = p * r + 1.0 / 5040.0;
    p = p * r + 1.0 / 720.0;
    p = p * r + 1.0 / 120.0;
    p = p * r + 1.0 / 24.0;
    p = p * r + 1.0 / 6.0;
    p = p * r + 0.5;
    p = p * r + 1.0;
    p = p * r + 1.0;
    /* 2^k: k + 1023 into the exponent field (the low bits of t are k plus a
     * multiple of 4096, which the shift drops) */
    memcpy(&bits, &t, sizeof bits);
    bits = (bits + 1023u) << 52;
    memcpy(&scale, &bits, sizeof scale);
    return p * scale * keep;
}

#endif
