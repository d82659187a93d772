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
#include "fit/pass_lanes.h"
#include "models/basis.h"

/* width 8 or 4: the vector sweeps; 0: the plain C one */
static inline void sweep_impl(const lobe_in *in, size_t n, size_t nc, bf_pass_kind kind,
                              double *acc, int width)
{
#if BF_LANES_VECTOR
    if (width == 8) {
        sweep_w8(in, n, nc, kind, acc);
        return;
    }
    if (width == 4) {
        sweep_w4(in, n, nc, kind, acc);
        return;
    }
#endif
    (void)width;
    sweep_plain(in, n, nc, kind, acc);
}

/* nc and kind made constants for the compiler */
static inline void sweep_any(const lobe_in *in, size_t n, size_t nc, bf_pass_kind kind,
                             double *acc, int width)
{
    if (nc == 3) {
        if (kind == BF_PASS_NORMAL) sweep_impl(in, n, 3, BF_PASS_NORMAL, acc, width);
        else if (kind == BF_PASS_COST) sweep_impl(in, n, 3, BF_PASS_COST, acc, width);
        else sweep_impl(in, n, 3, BF_PASS_VARPRO, acc, width);
    } else {
        if (kind == BF_PASS_NORMAL) sweep_impl(in, n, 1, BF_PASS_NORMAL, acc, width);
        else if (kind == BF_PASS_COST) sweep_impl(in, n, 1, BF_PASS_COST, acc, width);
        else sweep_impl(in, n, 1, BF_PASS_VARPRO, acc, width);
    }
}

#if defined(__GNUC__) || defined(__clang__)
#define BF_FLATTEN __attribute__((flatten))
#else
#define BF_FLATTEN
#endif

/* The versions, chosen per problem (bf_problem.isa). */
#if BF_FUSED_HAVE_ISA
__attribute__((target("avx512f"))) BF_FLATTEN static void
sweep_avx512(const lobe_in *in, size_t n, size_t nc, bf_pass_kind kind, double *acc)
{
    sweep_any(in, n, nc, kind, acc, 8);
}

__attribute__((target("avx2"))) BF_FLATTEN static void
sweep_avx2(const lobe_in *in, size_t n, size_t nc, bf_pass_kind kind, double *acc)
{
    sweep_any(in, n, nc, kind, acc, 4);
}
#endif

BF_FLATTEN static void sweep_base(const lobe_in *in, size_t n, size_t nc, bf_pass_kind kind,
                                  double *acc)
{
    sweep_any(in, n, nc, kind, acc, 4);
}

BF_FLATTEN static void sweep_plain_c(const lobe_in *in, size_t n, size_t nc, bf_pass_kind kind,
                                     double *acc)
{
    sweep_any(in, n, nc, kind, acc, 0);
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

void bf_fused_prepare(bf_problem *pb)
{
    bf_lobe lobe;
    pb->isa = bf_fused_best_isa();
    pb->lobe = pb->kernel != NULL && bf_kernel_lobe(pb->kernel, 1.0, &lobe);
}

int bf_fused_serves(const bf_problem *pb, bf_pass_kind kind)
{
    return pb->lobe && kind != BF_PASS_METRICS && (pb->nc == 1 || pb->nc == 3);
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
    const int in_place = bf_fused_in_place(pb, kind);
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
        in->m[c] = in_place ? bf_grid_values(pb->grid, c) + first : sc->meas + c * n;
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
    if (pb->isa == BF_ISA_PLAIN) sweep_plain_c(&in, n, pb->nc, kind, sc->acc);
    else sweep_base(&in, n, pb->nc, kind, sc->acc);
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
