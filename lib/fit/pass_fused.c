/* The fused inner loop (pass_fused.h): one sweep per chunk for the models
 * of the one-lobe form of models/basis.h,
 *
 *     value_c = cd_c / pi + cs_c k P,  P = exp(ns x) g,
 *     dB_1 / dns = (dk + k x) P,
 *
 * with x and g read from the grid's geometry (precomputed once per grid:
 * ln n.h or ln r.v, and 1 / (8 pi h.v max(n.l, n.v)) for
 * Ashikhmin-Shirley), the weights of the chunk as the driver computed
 * them and the measured values in place. Per sample it evaluates the
 * basis once and adds every sum of the pass (NORMAL on 3 channels: the
 * cost, the 6 entries of the Gram matrix G of the weighted basis
 * u = w (1/pi, k P, (dk + k x) P) and the 9 of H = u d_c) into local
 * accumulators. The values of B and d are the same expressions as the
 * kernel's and the basis route's (kernel_ashikhmin.c,
 * kernel_lambert_phong.c, pass_basis.c), so only the order of the sums
 * differs from that route.
 *
 * Summation order, fixed whatever the instruction set: every sum has
 * LANES = 8 lanes; sample i of a chunk goes to lane i mod 8, in sample
 * order (a chunk's last samples beyond a multiple of 8 are run as a
 * group padded with weight 0, which adds exact zeros); a thread's lanes
 * run over its block of chunks in chunk order, the driver adds the
 * blocks' lanes in block order (pass.c) and the lanes are then reduced as
 * ((l0 + l1) + (l2 + l3)) + ((l4 + l5) + (l6 + l7)). The AVX-512, AVX2 and
 * baseline versions below compute the same operations per lane (no fused
 * multiply-add: ISO C mode for gcc, FP_CONTRACT off for clang), so they
 * give the same bits; test_fused.c checks it on what the machine runs. */
#ifdef __clang__
#pragma STDC FP_CONTRACT OFF
#endif

#include "fit/pass_fused.h"

#include <string.h>

#include "core/core.h"
#include "core/fastmath.h"
#include "models/basis.h"

#define LANES 8
/* lanes of sums: NORMAL 7 + 3 nc, VARPRO 3 + 3 nc, COST 1 */
#define MAX_SUMS 16
#define INV_PI (1.0 / BF_PI)

typedef double lanes_t[LANES];

/* One chunk's inputs. */
typedef struct lobe_in {
    const double *w, *x, *g, *m[3];
    double ns, k, dk, cd[3], cs[3];
} lobe_in;

/* NORMAL: sums [cost, G00 G01 G02 G11 G12 G22, H_c0 H_c1 H_c2 ...]. */
static inline void normal_group(const lobe_in *in, size_t i, size_t nc, lanes_t *a)
{
    size_t l, c;
    for (l = 0; l < LANES; l++) {
        const double w = in->w[i + l], x = in->x[i + l];
        const double p = bf_exp(in->ns * x) * in->g[i + l];
        const double b1 = in->k * p, db1 = (in->dk + in->k * x) * p;
        const double u0 = w * INV_PI, u1 = w * b1, u2 = w * db1;
        a[1][l] += u0 * u0;
        a[2][l] += u0 * u1;
        a[3][l] += u0 * u2;
        a[4][l] += u1 * u1;
        a[5][l] += u1 * u2;
        a[6][l] += u2 * u2;
        for (c = 0; c < nc; c++) {
            const double d = ((-in->m[c][i + l] + in->cd[c] * INV_PI) + in->cs[c] * b1) * w;
            a[0][l] += d * d;
            a[7 + 3 * c][l] += u0 * d;
            a[8 + 3 * c][l] += u1 * d;
            a[9 + 3 * c][l] += u2 * d;
        }
    }
}

/* COST: [cost]. */
static inline void cost_group(const lobe_in *in, size_t i, size_t nc, lanes_t *a)
{
    size_t l, c;
    for (l = 0; l < LANES; l++) {
        const double w = in->w[i + l];
        const double b1 = in->k * (bf_exp(in->ns * in->x[i + l]) * in->g[i + l]);
        for (c = 0; c < nc; c++) {
            const double d = ((-in->m[c][i + l] + in->cd[c] * INV_PI) + in->cs[c] * b1) * w;
            a[0][l] += d * d;
        }
    }
}

/* VARPRO: [G00 G01 G11, b_c0 b_c1 ..., rr_c ...] of u = w (1/pi, k P) and
 * the weighted values w m_c. */
static inline void varpro_group(const lobe_in *in, size_t i, size_t nc, lanes_t *a)
{
    size_t l, c;
    for (l = 0; l < LANES; l++) {
        const double w = in->w[i + l];
        const double b1 = in->k * (bf_exp(in->ns * in->x[i + l]) * in->g[i + l]);
        const double u0 = w * INV_PI, u1 = w * b1;
        a[0][l] += u0 * u0;
        a[1][l] += u0 * u1;
        a[2][l] += u1 * u1;
        for (c = 0; c < nc; c++) {
            const double r = w * in->m[c][i + l];
            a[3 + 2 * c][l] += u0 * r;
            a[4 + 2 * c][l] += u1 * r;
            a[3 + 2 * nc + c][l] += r * r;
        }
    }
}

static inline void group(const lobe_in *in, size_t i, size_t nc, bf_pass_kind kind, lanes_t *a)
{
    if (kind == BF_PASS_NORMAL) normal_group(in, i, nc, a);
    else if (kind == BF_PASS_COST) cost_group(in, i, nc, a);
    else varpro_group(in, i, nc, a);
}

/* The chunk's samples beyond the last multiple of LANES, padded with
 * weight 0 (x = g = m = 0 too, so every padded term is an exact 0). */
static inline void tail(const lobe_in *in, size_t i, size_t n, size_t nc, bf_pass_kind kind,
                        lanes_t *a)
{
    double w[LANES] = {0.0}, x[LANES] = {0.0}, g[LANES] = {0.0}, m[3][LANES] = {{0.0}};
    lobe_in t = *in;
    size_t l, c;
    for (l = 0; i + l < n; l++) {
        w[l] = in->w[i + l];
        x[l] = in->x[i + l];
        g[l] = in->g[i + l];
        for (c = 0; c < nc; c++) m[c][l] = in->m[c][i + l];
    }
    t.w = w;
    t.x = x;
    t.g = g;
    for (c = 0; c < nc; c++) t.m[c] = m[c];
    group(&t, 0, nc, kind, a);
}

static size_t sums_of(bf_pass_kind kind, size_t nc)
{
    return kind == BF_PASS_NORMAL ? 7 + 3 * nc : kind == BF_PASS_VARPRO ? 3 + 3 * nc : 1;
}

/* The sweep over one chunk with nc and kind constant after inlining; the
 * lanes live in locals for the whole chunk. */
static inline void sweep(const lobe_in *in, size_t n, size_t nc, bf_pass_kind kind, double *acc)
{
    lanes_t a[MAX_SUMS];
    const size_t bytes = sums_of(kind, nc) * sizeof(lanes_t);
    size_t i = 0;
    memcpy(a, acc, bytes);
    for (; i + LANES <= n; i += LANES) group(in, i, nc, kind, a);
    if (i < n) tail(in, i, n, nc, kind, a);
    memcpy(acc, a, bytes);
}

static inline void sweep_any(const lobe_in *in, size_t n, size_t nc, bf_pass_kind kind,
                             double *acc)
{
    if (nc == 3) {
        if (kind == BF_PASS_NORMAL) sweep(in, n, 3, BF_PASS_NORMAL, acc);
        else if (kind == BF_PASS_COST) sweep(in, n, 3, BF_PASS_COST, acc);
        else sweep(in, n, 3, BF_PASS_VARPRO, acc);
    } else {
        if (kind == BF_PASS_NORMAL) sweep(in, n, 1, BF_PASS_NORMAL, acc);
        else if (kind == BF_PASS_COST) sweep(in, n, 1, BF_PASS_COST, acc);
        else sweep(in, n, 1, BF_PASS_VARPRO, acc);
    }
}

/* The three versions, chosen per problem (bf_problem.isa). */
#if BF_FUSED_HAVE_ISA
__attribute__((target("avx512f"), flatten)) static void
sweep_avx512(const lobe_in *in, size_t n, size_t nc, bf_pass_kind kind, double *acc)
{
    sweep_any(in, n, nc, kind, acc);
}

__attribute__((target("avx2"), flatten)) static void
sweep_avx2(const lobe_in *in, size_t n, size_t nc, bf_pass_kind kind, double *acc)
{
    sweep_any(in, n, nc, kind, acc);
}
#endif

#if defined(__GNUC__)
__attribute__((flatten))
#endif
static void sweep_base(const lobe_in *in, size_t n, size_t nc, bf_pass_kind kind, double *acc)
{
    sweep_any(in, n, nc, kind, acc);
}

unsigned bf_fused_best_isa(void)
{
#if BF_FUSED_HAVE_ISA
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f")) return BF_ISA_AVX512;
    if (__builtin_cpu_supports("avx2")) return BF_ISA_AVX2;
#endif
    return BF_ISA_BASE;
}

int bf_fused_serves(const bf_problem *pb, bf_pass_kind kind)
{
    bf_lobe lobe;
    if (kind == BF_PASS_METRICS || (pb->nc != 1 && pb->nc != 3)) return 0;
    return bf_kernel_lobe(pb->kernel, 1.0, &lobe);
}

int bf_fused_in_place(const bf_problem *pb, bf_pass_kind kind)
{
    return bf_fused_serves(pb, kind) && pb->source == BF_SOURCE_CHANNELS && !(pb->clearcoat > 0.0);
}

size_t bf_fused_acc_size(const bf_problem *pb, bf_pass_kind kind)
{
    return sums_of(kind, pb->nc) * LANES;
}

/* The chunk's inputs: lobe constants, colours, geometry and values. */
static void fill_in(const bf_problem *pb, bf_pass_kind kind, const double *params,
                    const bf_scratch *sc, size_t n, lobe_in *in, double *g_local)
{
    const bf_geometry *geo = bf_grid_geometry(pb->grid);
    const size_t first = sc->first, nc = pb->nc;
    bf_lobe lobe;
    size_t c, i;
    bf_kernel_lobe(pb->kernel, params[0], &lobe);
    in->ns = params[0];
    in->k = lobe.k;
    in->dk = lobe.dk;
    in->w = sc->w;
    in->x = (lobe.x == BF_LOBE_X_LOG_NH ? geo->log_nh : geo->log_rv) + first;
    if (lobe.g == BF_LOBE_G_AS) {
        in->g = geo->as_g + first;
    } else {
        const double *rv = geo->rv + first;
        int one = lobe.g == BF_LOBE_G_ONE;
        for (i = 0; i < n; i++) g_local[i] = one || rv[i] > 0.0 ? 1.0 : 0.0;
        in->g = g_local;
    }
    for (c = 0; c < nc; c++) {
        in->cd[c] = params[pb->vindex[1 * nc + c]];
        in->cs[c] = params[pb->vindex[2 * nc + c]];
        in->m[c] = bf_fused_in_place(pb, kind) ? bf_grid_values(pb->grid, c) + first
                                               : sc->meas + c * n;
    }
}

void bf_fused_chunk(const bf_problem *pb, bf_pass_kind kind, const double *params,
                    bf_scratch *sc, size_t n)
{
    double g_local[BF_CHUNK];
    lobe_in in;
    fill_in(pb, kind, params, sc, n, &in, g_local);
#if BF_FUSED_HAVE_ISA
    if (pb->isa == BF_ISA_AVX512) {
        sweep_avx512(&in, n, pb->nc, kind, sc->acc);
        return;
    }
    if (pb->isa == BF_ISA_AVX2) {
        sweep_avx2(&in, n, pb->nc, kind, sc->acc);
        return;
    }
#endif
    sweep_base(&in, n, pb->nc, kind, sc->acc);
}

/* Lanes reduced in the fixed order of the file comment. */
static double lane_sum(const double *a)
{
    return ((a[0] + a[1]) + (a[2] + a[3])) + ((a[4] + a[5]) + (a[6] + a[7]));
}

void bf_fused_reduce(const bf_problem *pb, bf_pass_kind kind, const double *lanes,
                     double *basis_acc)
{
    /* sum index -> basis layout: NORMAL NE = 3, VARPRO L = 2 */
    static const size_t g_normal[6] = {0, 1, 2, 4, 5, 8}, g_varpro[3] = {0, 1, 3};
    const size_t nc = pb->nc;
    size_t t, c;
    if (kind == BF_PASS_COST) {
        basis_acc[0] = lane_sum(lanes);
    } else if (kind == BF_PASS_NORMAL) {
        double *G = basis_acc + 1, *H = basis_acc + 1 + 9;
        memset(basis_acc, 0, (1 + 9 + 3 * nc) * sizeof *basis_acc);
        basis_acc[0] = lane_sum(lanes);
        for (t = 0; t < 6; t++) G[g_normal[t]] = lane_sum(lanes + (1 + t) * LANES);
        for (t = 0; t < 3 * nc; t++) H[t] = lane_sum(lanes + (7 + t) * LANES);
    } else {
        double *G = basis_acc, *b = basis_acc + 4, *rr = b + 2 * nc;
        memset(basis_acc, 0, (4 + 3 * nc) * sizeof *basis_acc);
        for (t = 0; t < 3; t++) G[g_varpro[t]] = lane_sum(lanes + t * LANES);
        for (c = 0; c < nc; c++) {
            b[2 * c] = lane_sum(lanes + (3 + 2 * c) * LANES);
            b[2 * c + 1] = lane_sum(lanes + (4 + 2 * c) * LANES);
            rr[c] = lane_sum(lanes + (3 + 2 * nc + c) * LANES);
        }
    }
}
