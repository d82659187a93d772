/* The NIST StRD nonlinear regression models with analytic gradients, and
 * the published starts, certified parameters and residual sums of
 * squares. Each model returns f(b; x); the residual is f - y. */
#include "nist_problems.h"

#include <math.h>

#define PI 3.14159265358979323846

/* b1 (1 - exp(-b2 x)): Misra1a, BoxBOD. */
static double m_misra1a(const double *b, const double *x, double *g)
{
    double e = exp(-b[1] * x[0]);
    if (g) {
        g[0] = 1.0 - e;
        g[1] = b[0] * x[0] * e;
    }
    return b[0] * (1.0 - e);
}

/* exp(-b1 x) / (b2 + b3 x): Chwirut1, Chwirut2. */
static double m_chwirut(const double *b, const double *x, double *g)
{
    double d = b[1] + b[2] * x[0], f = exp(-b[0] * x[0]) / d;
    if (g) {
        g[0] = -x[0] * f;
        g[1] = -f / d;
        g[2] = -x[0] * f / d;
    }
    return f;
}

/* b1 exp(-b2 x) + b3 exp(-b4 x) + b5 exp(-b6 x): Lanczos1-3. */
static double m_lanczos(const double *b, const double *x, double *g)
{
    double f = 0.0;
    int k;
    for (k = 0; k < 3; k++) {
        double e = exp(-b[2 * k + 1] * x[0]);
        f += b[2 * k] * e;
        if (g) {
            g[2 * k] = e;
            g[2 * k + 1] = -x[0] * b[2 * k] * e;
        }
    }
    return f;
}

/* One Gaussian a exp(-(x - c)^2 / w^2) into g[0..2]. */
static double gaussian(double a, double c, double w, double x, double *g)
{
    double u = (x - c) / w, e = exp(-u * u);
    if (g) {
        g[0] = e;
        g[1] = a * e * 2.0 * u / w;
        g[2] = a * e * 2.0 * u * u / w;
    }
    return a * e;
}

/* b1 exp(-b2 x) + two Gaussians: Gauss1-3. */
static double m_gauss(const double *b, const double *x, double *g)
{
    double e = exp(-b[1] * x[0]);
    if (g) {
        g[0] = e;
        g[1] = -x[0] * b[0] * e;
    }
    return b[0] * e + gaussian(b[2], b[3], b[4], x[0], g ? g + 2 : NULL) +
           gaussian(b[5], b[6], b[7], x[0], g ? g + 5 : NULL);
}

/* b1 x^b2: DanWood. */
static double m_danwood(const double *b, const double *x, double *g)
{
    double p = pow(x[0], b[1]);
    if (g) {
        g[0] = p;
        g[1] = b[0] * p * log(x[0]);
    }
    return b[0] * p;
}

/* b1 (1 - (1 + b2 x / 2)^-2): Misra1b. */
static double m_misra1b(const double *b, const double *x, double *g)
{
    double u = 1.0 + 0.5 * b[1] * x[0];
    if (g) {
        g[0] = 1.0 - 1.0 / (u * u);
        g[1] = b[0] * x[0] / (u * u * u);
    }
    return b[0] * (1.0 - 1.0 / (u * u));
}

/* (b1 + b2 x + ... ) / (1 + b[m] x + ...): numerator of m terms, denominator
 * of m - 1 (Kirby2: m = 3; Hahn1, Thurber: m = 4). */
static double rational(const double *b, double x, double *g, int m)
{
    double num = 0.0, den = 1.0, xk = 1.0, f;
    int k;
    for (k = 0; k < m; k++, xk *= x) num += b[k] * xk;
    for (k = 1, xk = x; k < m; k++, xk *= x) den += b[m + k - 1] * xk;
    f = num / den;
    if (g) {
        for (k = 0, xk = 1.0; k < m; k++, xk *= x) g[k] = xk / den;
        for (k = 1, xk = x; k < m; k++, xk *= x) g[m + k - 1] = -f * xk / den;
    }
    return f;
}

static double m_kirby2(const double *b, const double *x, double *g)
{
    return rational(b, x[0], g, 3);
}

static double m_cubic(const double *b, const double *x, double *g)
{
    return rational(b, x[0], g, 4);
}

/* log y = b1 - b2 x1 exp(-b3 x2): Nelson. */
static double m_nelson(const double *b, const double *x, double *g)
{
    double e = exp(-b[2] * x[1]);
    if (g) {
        g[0] = 1.0;
        g[1] = -x[0] * e;
        g[2] = b[1] * x[0] * x[1] * e;
    }
    return b[0] - b[1] * x[0] * e;
}

/* b1 + b2 exp(-x b4) + b3 exp(-x b5): MGH17 (Osborne 1). */
static double m_mgh17(const double *b, const double *x, double *g)
{
    double e4 = exp(-x[0] * b[3]), e5 = exp(-x[0] * b[4]);
    if (g) {
        g[0] = 1.0;
        g[1] = e4;
        g[2] = e5;
        g[3] = -x[0] * b[1] * e4;
        g[4] = -x[0] * b[2] * e5;
    }
    return b[0] + b[1] * e4 + b[2] * e5;
}

/* b1 (1 - (1 + 2 b2 x)^-1/2): Misra1c. */
static double m_misra1c(const double *b, const double *x, double *g)
{
    double s = sqrt(1.0 + 2.0 * b[1] * x[0]);
    if (g) {
        g[0] = 1.0 - 1.0 / s;
        g[1] = b[0] * x[0] / (s * s * s);
    }
    return b[0] * (1.0 - 1.0 / s);
}

/* b1 b2 x / (1 + b2 x): Misra1d. */
static double m_misra1d(const double *b, const double *x, double *g)
{
    double d = 1.0 + b[1] * x[0];
    if (g) {
        g[0] = b[1] * x[0] / d;
        g[1] = b[0] * x[0] / (d * d);
    }
    return b[0] * b[1] * x[0] / d;
}

/* b1 - b2 x - arctan(b3 / (x - b4)) / pi: Roszman1. */
static double m_roszman1(const double *b, const double *x, double *g)
{
    double d = x[0] - b[3], q = d * d + b[2] * b[2];
    if (g) {
        g[0] = 1.0;
        g[1] = -x[0];
        g[2] = -d / q / PI;
        g[3] = -b[2] / q / PI;
    }
    return b[0] - b[1] * x[0] - atan(b[2] / d) / PI;
}

/* a cos(2 pi x / p) + c sin(2 pi x / p), and its derivatives in p, a, c. */
static double cycle(double p, double a, double c, double x, double *g)
{
    double t = 2.0 * PI * x / p, ct = cos(t), st = sin(t);
    if (g) {
        g[0] = (a * st - c * ct) * t / p;
        g[1] = ct;
        g[2] = st;
    }
    return a * ct + c * st;
}

/* b1 + the annual cycle (b2, b3) + two cycles of periods b4 and b7: ENSO. */
static double m_enso(const double *b, const double *x, double *g)
{
    double t = 2.0 * PI * x[0] / 12.0;
    if (g) {
        g[0] = 1.0;
        g[1] = cos(t);
        g[2] = sin(t);
    }
    return b[0] + b[1] * cos(t) + b[2] * sin(t) + cycle(b[3], b[4], b[5], x[0], g ? g + 3 : NULL) +
           cycle(b[6], b[7], b[8], x[0], g ? g + 6 : NULL);
}

/* b1 (x^2 + x b2) / (x^2 + x b3 + b4): MGH09 (Kowalik and Osborne). */
static double m_mgh09(const double *b, const double *x, double *g)
{
    double n = x[0] * x[0] + x[0] * b[1], d = x[0] * x[0] + x[0] * b[2] + b[3];
    double f = b[0] * n / d;
    if (g) {
        g[0] = n / d;
        g[1] = b[0] * x[0] / d;
        g[2] = -f * x[0] / d;
        g[3] = -f / d;
    }
    return f;
}

/* b1 / (1 + exp(b2 - b3 x)): Rat42. */
static double m_rat42(const double *b, const double *x, double *g)
{
    double e = exp(b[1] - b[2] * x[0]), w = 1.0 + e;
    if (g) {
        g[0] = 1.0 / w;
        g[1] = -b[0] * e / (w * w);
        g[2] = b[0] * x[0] * e / (w * w);
    }
    return b[0] / w;
}

/* b1 exp(b2 / (x + b3)): MGH10 (Meyer). */
static double m_mgh10(const double *b, const double *x, double *g)
{
    double d = x[0] + b[2], e = exp(b[1] / d);
    if (g) {
        g[0] = e;
        g[1] = b[0] * e / d;
        g[2] = -b[0] * e * b[1] / (d * d);
    }
    return b[0] * e;
}

/* (b1 / b2) exp(-((x - b3) / b2)^2 / 2): Eckerle4. */
static double m_eckerle4(const double *b, const double *x, double *g)
{
    double z = (x[0] - b[2]) / b[1], e = exp(-0.5 * z * z), f = b[0] / b[1] * e;
    if (g) {
        g[0] = e / b[1];
        g[1] = f * (z * z - 1.0) / b[1];
        g[2] = f * z / b[1];
    }
    return f;
}

/* b1 / (1 + exp(b2 - b3 x))^(1 / b4): Rat43. */
static double m_rat43(const double *b, const double *x, double *g)
{
    double e = exp(b[1] - b[2] * x[0]), w = 1.0 + e, f = b[0] * pow(w, -1.0 / b[3]);
    if (g) {
        g[0] = pow(w, -1.0 / b[3]);
        g[1] = -f * e / (b[3] * w);
        g[2] = f * e * x[0] / (b[3] * w);
        g[3] = f * log(w) / (b[3] * b[3]);
    }
    return f;
}

/* b1 (b2 + x)^(-1 / b3): Bennett5. */
static double m_bennett5(const double *b, const double *x, double *g)
{
    double u = b[1] + x[0], f = b[0] * pow(u, -1.0 / b[2]);
    if (g) {
        g[0] = pow(u, -1.0 / b[2]);
        g[1] = -f / (b[2] * u);
        g[2] = f * log(u) / (b[2] * b[2]);
    }
    return f;
}

#define N(a, stride) (sizeof(a) / sizeof(a[0]) / (stride))

/* clang-format off */
static const nist_problem problems[] = {
    /* lower difficulty */
    {"Misra1a", 2, N(nist_misra1a_data, 2), nist_misra1a_data, 2, 0, m_misra1a,
     {{500, 1e-4}, {250, 5e-4}}, {2.3894212918E+02, 5.5015643181E-04}, 1.2455138894E-01},
    {"Chwirut2", 3, N(nist_chwirut2_data, 2), nist_chwirut2_data, 2, 0, m_chwirut,
     {{0.1, 0.01, 0.02}, {0.15, 0.008, 0.010}},
     {1.6657666537E-01, 5.1653291286E-03, 1.2150007096E-02}, 5.1304802941E+02},
    {"Chwirut1", 3, N(nist_chwirut1_data, 2), nist_chwirut1_data, 2, 0, m_chwirut,
     {{0.1, 0.01, 0.02}, {0.15, 0.008, 0.010}},
     {1.9027818370E-01, 6.1314004477E-03, 1.0530908399E-02}, 2.3844771393E+03},
    {"Lanczos3", 6, N(nist_lanczos3_data, 2), nist_lanczos3_data, 2, 0, m_lanczos,
     {{1.2, 0.3, 5.6, 5.5, 6.5, 7.6}, {0.5, 0.7, 3.6, 4.2, 4, 6.3}},
     {8.6816414977E-02, 9.5498101505E-01, 8.4400777463E-01, 2.9515951832E+00, 1.5825685901E+00,
      4.9863565084E+00},
     1.6117193594E-08},
    {"Gauss1", 8, N(nist_gauss1_y, 1), nist_gauss1_y, 1, 0, m_gauss,
     {{97, 0.009, 100, 65, 20, 70, 178, 16.5}, {94, 0.0105, 99, 63, 25, 71, 180, 20}},
     {9.8778210871E+01, 1.0497276517E-02, 1.0048990633E+02, 6.7481111276E+01, 2.3129773360E+01,
      7.1994503004E+01, 1.7899805021E+02, 1.8389389025E+01},
     1.3158222432E+03},
    {"Gauss2", 8, N(nist_gauss2_y, 1), nist_gauss2_y, 1, 0, m_gauss,
     {{96, 0.009, 103, 106, 18, 72, 151, 18}, {98, 0.0105, 103, 105, 20, 73, 150, 20}},
     {9.9018328406E+01, 1.0994945399E-02, 1.0188022528E+02, 1.0703095519E+02, 2.3578584029E+01,
      7.2045589471E+01, 1.5327010194E+02, 1.9525972636E+01},
     1.2475282092E+03},
    {"DanWood", 2, N(nist_danwood_data, 2), nist_danwood_data, 2, 0, m_danwood,
     {{1, 5}, {0.7, 4}}, {7.6886226176E-01, 3.8604055871E+00}, 4.3173084083E-03},
    {"Misra1b", 2, N(nist_misra1a_data, 2), nist_misra1a_data, 2, 0, m_misra1b,
     {{500, 1e-4}, {300, 2e-4}}, {3.3799746163E+02, 3.9039091287E-04}, 7.5464681533E-02},
    /* average difficulty */
    {"Kirby2", 5, N(nist_kirby2_data, 2), nist_kirby2_data, 2, 0, m_kirby2,
     {{2, -0.1, 0.003, -0.001, 1e-5}, {1.5, -0.15, 0.0025, -0.0015, 2e-5}},
     {1.6745063063E+00, -1.3927397867E-01, 2.5961181191E-03, -1.7241811870E-03,
      2.1664802578E-05},
     3.9050739624E+00},
    {"Hahn1", 7, N(nist_hahn1_data, 2), nist_hahn1_data, 2, 0, m_cubic,
     {{10, -1, 0.05, -1e-5, -0.05, 0.001, -1e-6}, {1, -0.1, 0.005, -1e-6, -0.005, 1e-4, -1e-7}},
     {1.0776351733E+00, -1.2269296921E-01, 4.0863750610E-03, -1.4262662514E-06,
      -5.7609940901E-03, 2.4053735503E-04, -1.2314450199E-07},
     1.5324382854E+00},
    {"Nelson", 3, N(nist_nelson_data, 3), nist_nelson_data, 3, 1, m_nelson,
     {{2, 1e-4, -0.01}, {2.5, 5e-9, -0.05}},
     {2.5906836021E+00, 5.6177717026E-09, -5.7701013174E-02}, 3.7976833176E+00},
    {"MGH17", 5, N(nist_mgh17_data, 2), nist_mgh17_data, 2, 0, m_mgh17,
     {{50, 150, -100, 1, 2}, {0.5, 1.5, -1, 0.01, 0.02}},
     {3.7541005211E-01, 1.9358469127E+00, -1.4646871366E+00, 1.2867534640E-02,
      2.2122699662E-02},
     5.4648946975E-05},
    {"Lanczos1", 6, N(nist_lanczos1_data, 2), nist_lanczos1_data, 2, 0, m_lanczos,
     {{1.2, 0.3, 5.6, 5.5, 6.5, 7.6}, {0.5, 0.7, 3.6, 4.2, 4, 6.3}},
     {9.5100000027E-02, 1.0000000001E+00, 8.6070000013E-01, 3.0000000002E+00, 1.5575999998E+00,
      5.0000000001E+00},
     1.4307867721E-25},
    {"Lanczos2", 6, N(nist_lanczos2_data, 2), nist_lanczos2_data, 2, 0, m_lanczos,
     {{1.2, 0.3, 5.6, 5.5, 6.5, 7.6}, {0.5, 0.7, 3.6, 4.2, 4, 6.3}},
     {9.6251029939E-02, 1.0057332849E+00, 8.6424689056E-01, 3.0078283915E+00, 1.5529016879E+00,
      5.0028798100E+00},
     2.2299428125E-11},
    {"Gauss3", 8, N(nist_gauss3_y, 1), nist_gauss3_y, 1, 0, m_gauss,
     {{94.9, 0.009, 90.1, 113, 20, 73.8, 140, 20}, {96, 0.0096, 80, 110, 25, 74, 139, 25}},
     {9.8940368970E+01, 1.0945879335E-02, 1.0069553078E+02, 1.1163619459E+02, 2.3300500029E+01,
      7.3705031418E+01, 1.4776164251E+02, 1.9668221230E+01},
     1.2444846360E+03},
    {"Misra1c", 2, N(nist_misra1a_data, 2), nist_misra1a_data, 2, 0, m_misra1c,
     {{500, 1e-4}, {600, 2e-4}}, {6.3642725809E+02, 2.0813627256E-04}, 4.0966836971E-02},
    {"Misra1d", 2, N(nist_misra1a_data, 2), nist_misra1a_data, 2, 0, m_misra1d,
     {{500, 1e-4}, {450, 3e-4}}, {4.3736970754E+02, 3.0227324449E-04}, 5.6419295283E-02},
    {"Roszman1", 4, N(nist_roszman1_data, 2), nist_roszman1_data, 2, 0, m_roszman1,
     {{0.1, -1e-5, 1000, -100}, {0.2, -5e-6, 1200, -150}},
     {2.0196866396E-01, -6.1953516256E-06, 1.2044556708E+03, -1.8134269537E+02},
     4.9484847331E-04},
    {"ENSO", 9, N(nist_enso_y, 1), nist_enso_y, 1, 0, m_enso,
     {{11, 3, 0.5, 40, -0.7, -1.3, 25, -0.3, 1.4}, {10, 3, 0.5, 44, -1.5, 0.5, 26, -0.1, 1.5}},
     {1.0510749193E+01, 3.0762128085E+00, 5.3280138227E-01, 4.4311088700E+01, -1.6231428586E+00,
      5.2554493756E-01, 2.6887614440E+01, 2.1232288488E-01, 1.4966870418E+00},
     7.8853978668E+02},
    /* higher difficulty */
    {"MGH09", 4, N(nist_mgh09_data, 2), nist_mgh09_data, 2, 0, m_mgh09,
     {{25, 39, 41.5, 39}, {0.25, 0.39, 0.415, 0.39}},
     {1.9280693458E-01, 1.9128232873E-01, 1.2305650693E-01, 1.3606233068E-01}, 3.0750560385E-04},
    {"Thurber", 7, N(nist_thurber_data, 2), nist_thurber_data, 2, 0, m_cubic,
     {{1000, 1000, 400, 40, 0.7, 0.3, 0.03}, {1300, 1500, 500, 75, 1, 0.4, 0.05}},
     {1.2881396800E+03, 1.4910792535E+03, 5.8323836877E+02, 7.5416644291E+01, 9.6629502864E-01,
      3.9797285797E-01, 4.9727297349E-02},
     5.6427082397E+03},
    {"BoxBOD", 2, N(nist_boxbod_data, 2), nist_boxbod_data, 2, 0, m_misra1a,
     {{1, 1}, {100, 0.75}}, {2.1380940889E+02, 5.4723748542E-01}, 1.1680088766E+03},
    {"Rat42", 3, N(nist_rat42_data, 2), nist_rat42_data, 2, 0, m_rat42,
     {{100, 1, 0.1}, {75, 2.5, 0.07}}, {7.2462237576E+01, 2.6180768402E+00, 6.7359200066E-02},
     8.0565229338E+00},
    {"MGH10", 3, N(nist_mgh10_data, 2), nist_mgh10_data, 2, 0, m_mgh10,
     {{2, 400000, 25000}, {0.02, 4000, 250}},
     {5.6096364710E-03, 6.1813463463E+03, 3.4522363462E+02}, 8.7945855171E+01},
    {"Eckerle4", 3, N(nist_eckerle4_data, 2), nist_eckerle4_data, 2, 0, m_eckerle4,
     {{1, 10, 500}, {1.5, 5, 450}}, {1.5543827178E+00, 4.0888321754E+00, 4.5154121844E+02},
     1.4635887487E-03},
    {"Rat43", 4, N(nist_rat43_data, 2), nist_rat43_data, 2, 0, m_rat43,
     {{100, 10, 1, 1}, {700, 5, 0.75, 1.3}},
     {6.9964151270E+02, 5.2771253025E+00, 7.5962938329E-01, 1.2792483859E+00}, 8.7864049080E+03},
    {"Bennett5", 3, N(nist_bennett5_data, 2), nist_bennett5_data, 2, 0, m_bennett5,
     {{-2000, 50, 0.8}, {-1500, 45, 0.85}},
     {-2.5235058043E+03, 4.6736564644E+01, 9.3218483193E-01}, 5.2404744073E-04},
};
/* clang-format on */

const nist_problem *nist_problems(size_t *count)
{
    *count = sizeof problems / sizeof problems[0];
    return problems;
}

double nist_response(const nist_problem *p, size_t i, double x[2])
{
    const double *row = p->data + i * p->stride;
    x[0] = p->stride == 1 ? (double)(i + 1) : row[1];
    x[1] = p->stride == 3 ? row[2] : 0.0;
    return p->log_response ? log(row[0]) : row[0];
}

brdffit_status nist_residuals(const double *b, double *r, double *jac, void *user)
{
    const nist_problem *p = user;
    size_t i;
    for (i = 0; i < p->n_obs; i++) {
        double x[2], y = nist_response(p, i, x);
        r[i] = p->model(b, x, jac ? jac + i * p->n_params : NULL) - y;
    }
    return BRDFFIT_OK;
}

double nist_lre(double value, double certified)
{
    double err = fabs(value - certified);
    double lre;
    if (certified != 0.0) err /= fabs(certified);
    if (!(err == err)) return 0.0;
    if (err == 0.0) return 15.0;
    lre = -log10(err);
    return lre > 15.0 ? 15.0 : (lre < 0.0 ? 0.0 : lre);
}
