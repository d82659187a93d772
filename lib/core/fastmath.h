/* Branch-free elementary functions that the compiler can vectorise inside
 * the model kernels' sample loops (a call into libm would keep every such
 * loop scalar). Accurate to a few units in the last place over the whole
 * double range (tests/test_fastmath.c); results are the same on every
 * machine. Not installed. */
#ifndef BRDFFIT_FASTMATH_H
#define BRDFFIT_FASTMATH_H

#include <math.h>
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

/* x^(-1/3) for x >= 0, to about one unit in the last place (x y^2, the
 * cube root, to about four), without a division: a first guess from the
 * high word of the bits (a constant minus a third of it, the constant
 * tuned for the smallest largest error, 3.4 %), then two steps
 * y (1 - h)^(-1/3) with h = 1 - x y^3 and the power's series to h^3
 * (relative errors ~2e-5, then below rounding); x y^3 is formed as
 * (x y) y^2, so no product leaves the normal range. Arguments below
 * 2^-1000 (subnormals) are scaled by 2^162 and the result by 2^54, those
 * above 2^1000 the other way; 0 gives a finite y (so x * y * y is 0
 * there); NaN for NaN or an infinity. Vectorises, like the others here. */
static inline double bf_rcbrt(double x)
{
    const double tiny = 0x1p-1000;
    double a = x, y, scale, h;
    uint64_t bits;
    uint32_t hi;
    int small = a < tiny, big = a > 0x1p1000, k;
    a = small ? a * 0x1p162 : (big ? a * 0x1p-162 : a);
    scale = small ? 0x1p54 : (big ? 0x1p-54 : 1.0);
    a = a > tiny ? a : tiny;
    memcpy(&bits, &a, sizeof bits);
    hi = 0x553ef0fdu - (uint32_t)(bits >> 32) / 3u;
    bits = (uint64_t)hi << 32;
    memcpy(&y, &bits, sizeof y);
    for (k = 0; k < 2; k++) {
        double y2 = y * y, ya = y * a;
        h = 1.0 - ya * y2;
        h = h * ((1.0 / 3.0 + h * (2.0 / 9.0)) + (h * h) * (14.0 / 81.0));
        y = y + y * h;
    }
    return y * scale + (x - x);
}

/* The real cube root of finite x, to at most a few units in the last place;
 * NaN for NaN or an infinity (x - x carries it): |x| y^2 with y =
 * bf_rcbrt(|x|), then one Newton step c - (c - |x| / c^2) / 3 rounding it
 * off. 0 gives 0. Vectorises. */
static inline double bf_cbrt(double x)
{
    double a = x < 0.0 ? -x : x, y = bf_rcbrt(a), c = a * (y * y);
    c = a > 0.0 ? c - (c - a / (c * c)) / 3.0 : 0.0;
    return (x < 0.0 ? -c : c) + (x - x);
}

/* ln x for x > 0 to about one unit in the last place; -HUGE_VAL at 0 and
 * NaN below 0 or for NaN, as ln() of libm; +inf gives NaN (x - x). The
 * mantissa m in [sqrt(1/2), sqrt(2)) and exponent k from the bits, then
 * ln m = 2 atanh(s), s = (m - 1) / (m + 1), |s| <= 0.1716, by its series to
 * s^23 (truncation below 1e-18 relative). Subnormals are scaled by 2^60
 * first. Only arithmetic, selects and integer ops: loops vectorise. */
static inline double bf_log(double x)
{
    const double ln2_hi = 6.93147180369123816490e-01, ln2_lo = 1.90821492927058770002e-10;
    double a = x, m, f, s, z, p, k;
    uint64_t bits;
    int32_t e;
    int small = a < 0x1p-1000;
    a = small ? a * 0x1p60 : a;
    a = a > 0x1p-1070 ? a : 1.0; /* 0 and below: any positive value, replaced at the end */
    memcpy(&bits, &a, sizeof bits);
    /* shift the mantissa's range to [sqrt(1/2), sqrt(2)) before splitting */
    bits += 0x3ff0000000000000ULL - 0x3fe6a09e667f3bcdULL;
    e = (int32_t)(uint32_t)(bits >> 52) - 1023;
    bits = (bits & 0x000fffffffffffffULL) + 0x3fe6a09e667f3bcdULL;
    memcpy(&m, &bits, sizeof m);
    k = (double)e - (small ? 60.0 : 0.0);
    f = m - 1.0;
    s = f / (2.0 + f);
    z = s * s;
    p = 2.0 / 23.0;
    p = p * z + 2.0 / 21.0;
    p = p * z + 2.0 / 19.0;
    p = p * z + 2.0 / 17.0;
    p = p * z + 2.0 / 15.0;
    p = p * z + 2.0 / 13.0;
    p = p * z + 2.0 / 11.0;
    p = p * z + 2.0 / 9.0;
    p = p * z + 2.0 / 7.0;
    p = p * z + 2.0 / 5.0;
    p = p * z + 2.0 / 3.0;
    /* ln m = f - s f + s (2/3 z + ...) * z ... written as f - s (f - p z) */
    p = k * ln2_hi + (f - (s * (f - p * z) - k * ln2_lo));
    p = x > 0.0 ? p : (x == 0.0 ? -HUGE_VAL : NAN);
    return p + (x - x);
}

/* ln(1 + x) for x > -1, to a few units in the last place also for tiny x:
 * ln w with w = 1 + x rounded, corrected by the rounding error of w
 * ((w - 1) - x) / w. -HUGE_VAL at -1 and NaN below. Vectorises. */
static inline double bf_log1p(double x)
{
    double w = 1.0 + x, u = w - 1.0, fix = (u - x) / (w != 0.0 ? w : 1.0);
    return bf_log(w) - (w > 0.0 ? fix : 0.0);
}

#endif
