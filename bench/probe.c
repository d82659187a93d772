/* The probe loop of probe.h. Its last n mod 8 samples are left out (at
 * most 7 of the 25,308). */
#include "probe.h"

#include <stdlib.h>
#include <string.h>

#include "grid/grid_internal.h"

#define PI 3.14159265358979323846

int probe_init(probe_data *pd, const brdffit_grid *grid, double cap, const size_t *first,
               const size_t *count, size_t n_blocks, const double *params, const size_t *vindex)
{
    size_t n_all = brdffit_grid_sample_count(grid), b, s, c, t = 0;
    const bf_geometry *geo = bf_grid_geometry(grid);
    double *w = malloc(n_all * sizeof *w);
    memset(pd, 0, sizeof *pd);
    for (b = 0; b < n_blocks; b++) pd->n += count[b];
    pd->store = calloc(6 * pd->n + 8, sizeof(double));
    if (w == NULL || pd->store == NULL ||
        brdffit_grid_weights(grid, cap, BRDFFIT_WEIGHT_DEFAULT, w, NULL) != BRDFFIT_OK) {
        free(w);
        probe_free(pd);
        return 0;
    }
    pd->w = pd->store;
    pd->x = pd->w + pd->n;
    pd->g = pd->x + pd->n;
    for (c = 0; c < 3; c++) pd->m[c] = pd->g + (1 + c) * pd->n;
    for (b = 0; b < n_blocks; b++)
        for (s = first[b]; s < first[b] + count[b]; s++, t++) {
            pd->w[t] = w[s];
            pd->x[t] = geo->log_nh[s];
            pd->g[t] = geo->as_g[s];
            for (c = 0; c < 3; c++) pd->m[c][t] = bf_grid_values(grid, c)[s];
        }
    free(w);
    pd->ns = params[0];
    pd->k = params[0] + 1.0;
    pd->dk = 1.0;
    for (c = 0; c < 3; c++) {
        pd->cd[c] = params[vindex[3 + c]];
        pd->cs[c] = params[vindex[6 + c]];
    }
    return 1;
}

void probe_free(probe_data *pd)
{
    free(pd->store);
    memset(pd, 0, sizeof *pd);
}

#if defined(__GNUC__) && defined(__x86_64__)
#pragma GCC diagnostic ignored "-Wpsabi"

/* One body per vector width W (8 doubles for AVX-512, 4 for AVX2), so
 * that each clone keeps its 16 accumulators in registers (16 ymm or 32
 * zmm): 8-lane vectors split into two ymm halves would need 32. The
 * exponential is bf_exp() on W lanes without its range guards (arguments
 * here lie in [-709, 0]), so the floor is not flattered by work the probe
 * skips. */
#define PROBE_BODY(NAME, W, TARGET)                                                              \
    typedef double NAME##_v __attribute__((vector_size(8 * (W))));                               \
    typedef unsigned long long NAME##_u __attribute__((vector_size(8 * (W))));                   \
    __attribute__((target(TARGET))) static inline NAME##_v NAME##_ld(const double *p)            \
    {                                                                                            \
        NAME##_v v;                                                                              \
        memcpy(&v, p, sizeof v);                                                                 \
        return v;                                                                                \
    }                                                                                            \
    __attribute__((target(TARGET))) static inline NAME##_v NAME##_sp(double x)                   \
    {                                                                                            \
        return (NAME##_v){0} + x;                                                                \
    }                                                                                            \
    __attribute__((target(TARGET))) static inline NAME##_v NAME##_exp(NAME##_v x)                \
    {                                                                                            \
        const NAME##_v shifter = NAME##_sp(6755399441055744.0);                                  \
        NAME##_v t = x * NAME##_sp(1.4426950408889634) + shifter, k = t - shifter, p;            \
        NAME##_v r = (x - k * NAME##_sp(6.93147180369123816490e-01)) -                           \
                     k * NAME##_sp(1.90821492927058770002e-10);                                  \
        int i;                                                                                   \
        p = NAME##_sp(exp_coef[0]);                                                              \
        for (i = 1; i < 14; i++) p = p * r + NAME##_sp(exp_coef[i]);                             \
        return p * (NAME##_v)(((NAME##_u)t + 1023u) << 52);                                      \
    }                                                                                            \
    __attribute__((target(TARGET), flatten)) static void NAME(const probe_data *pd, double *out) \
    {                                                                                            \
        NAME##_v s[PROBE_SUMS];                                                                  \
        size_t i, c, j;                                                                          \
        for (j = 0; j < PROBE_SUMS; j++) s[j] = NAME##_sp(0.0);                                  \
        for (i = 0; i + (W) <= pd->n - pd->n % 8; i += (W)) {                                    \
            const NAME##_v w = NAME##_ld(pd->w + i), x = NAME##_ld(pd->x + i);                   \
            const NAME##_v p = NAME##_exp(NAME##_sp(pd->ns) * x) * NAME##_ld(pd->g + i);         \
            const NAME##_v b1 = NAME##_sp(pd->k) * p, u0 = w * NAME##_sp(1.0 / PI), u1 = w * b1; \
            const NAME##_v u2 = w * ((NAME##_sp(pd->dk) + NAME##_sp(pd->k) * x) * p);            \
            s[1] += u0 * u0, s[2] += u0 * u1, s[3] += u0 * u2;                                   \
            s[4] += u1 * u1, s[5] += u1 * u2, s[6] += u2 * u2;                                   \
            for (c = 0; c < 3; c++) {                                                            \
                const NAME##_v d = ((NAME##_sp(pd->cd[c] / PI) - NAME##_ld(pd->m[c] + i)) +      \
                                    NAME##_sp(pd->cs[c]) * b1) *                                 \
                                   w;                                                            \
                s[0] += d * d;                                                                   \
                s[7 + 3 * c] += u0 * d, s[8 + 3 * c] += u1 * d, s[9 + 3 * c] += u2 * d;          \
            }                                                                                    \
        }                                                                                        \
        for (j = 0; j < PROBE_SUMS; j++) {                                                       \
            double t = 0.0;                                                                      \
            for (c = 0; c < (W); c++) t += s[j][c];                                              \
            out[j] = t;                                                                          \
        }                                                                                        \
    }

static const double exp_coef[14] = {1.0 / 6227020800.0,
                                    1.0 / 479001600.0,
                                    1.0 / 39916800.0,
                                    1.0 / 3628800.0,
                                    1.0 / 362880.0,
                                    1.0 / 40320.0,
                                    1.0 / 5040.0,
                                    1.0 / 720.0,
                                    1.0 / 120.0,
                                    1.0 / 24.0,
                                    1.0 / 6.0,
                                    0.5,
                                    1.0,
                                    1.0};

PROBE_BODY(body512, 8, "avx512f,fma")
PROBE_BODY(body256, 4, "avx2,fma")
PROBE_BODY(body128, 2, "sse2")

void probe_normal(const probe_data *pd, int avx512, double *out)
{
    __builtin_cpu_init();
    if (avx512 && __builtin_cpu_supports("avx512f"))
        body512(pd, out);
    else if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))
        body256(pd, out);
    else
        body128(pd, out);
}
#else
void probe_normal(const probe_data *pd, int avx512, double *out)
{
    (void)pd;
    (void)avx512;
    memset(out, 0, PROBE_SUMS * sizeof *out);
}
#endif
