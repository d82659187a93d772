/* The fused inner loop (pass_fused.h): one sweep per chunk for the models
 * of the one-lobe form of models/basis.h,
 *
 *     value_c = cd_c / pi + cs_c k P,  P = exp(ns x) g,
 *     dB_1 / dns = (dk + k x) P,
 *
 * with x and g read from the grid's geometry (precomputed once per grid:
 * ln n.h or ln r.v, and 1 / (8 pi h.v max(n.l, n.v)) for
 * Ashikhmin-Shirley), and for the models of its microfacet form (GGX and
 * Cook-Torrance, one lobe or two sharing F0),
 *
 *     value_c = cd_c / pi + sum_q cs_qc B_q,  B_q = D_q G_q F / (4 n.l n.v),
 *
 * with the extended basis (1/pi, B_q, dB_q/dr_q, dB_q/dF0) computed in
 * the lanes from the grid's dot products: the per-sample geometry (tan^2,
 * 1 / (4 n.l n.v), (1 - h.v)^5, the V-cavity G) once per group of lanes
 * and shared by the lobes, the parameter-only factors (a^2, 2 / a, 4 a,
 * -2 a; 1 / m^2, 2 / m) once per chunk; and Ward's lobes (Ward,
 * Ward-Duer) alike, without F0; and ashikhmin-shirley-fresnel in the
 * same form, Rs in F0's place and its diffuse (1 - Rs) fd in 1/pi's, fd
 * and (1 - h.v)^5 once per group of lanes. Both take the weights of the chunk
 * as the driver computed them and the measured values in place. Per
 * sample the loop evaluates the basis once and adds every sum of the pass
 * (NORMAL on 3 channels and one lobe of the lobe form: the cost, the 6
 * entries of the Gram matrix G of the weighted basis u = w (1/pi, k P,
 * (dk + k x) P) and the 9 of H = u d_c) into local accumulators. The
 * values of B and d are the same expressions as the kernel's and the
 * basis route's (kernel_ashikhmin.c, kernel_lambert_phong.c,
 * kernel_microfacet.c, pass_basis.c), so only the order of the sums
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
static inline void sweep_impl(const lobe_in *in, size_t n, size_t nc, size_t nl, int mf,
                              bf_pass_kind kind, double *acc, int width)
{
#if BF_LANES_VECTOR
    if (width == 8) {
        sweep_w8(in, n, nc, nl, mf, kind, acc);
        return;
    }
    if (width == 4) {
        sweep_w4(in, n, nc, nl, mf, kind, acc);
        return;
    }
#endif
    (void)width;
    sweep_plain(in, n, nc, nl, mf, kind, acc);
}

/* kind made a constant for the compiler */
static inline void sweep_kind(const lobe_in *in, size_t n, size_t nc, size_t nl, int mf,
                              bf_pass_kind kind, double *acc, int width)
{
    if (kind == BF_PASS_NORMAL) sweep_impl(in, n, nc, nl, mf, BF_PASS_NORMAL, acc, width);
    else if (kind == BF_PASS_COST) sweep_impl(in, n, nc, nl, mf, BF_PASS_COST, acc, width);
    else sweep_impl(in, n, nc, nl, mf, BF_PASS_VARPRO, acc, width);
}

/* the lobes and the form too */
static inline void sweep_lobes(const lobe_in *in, size_t n, size_t nc, size_t nl, int mf,
                               bf_pass_kind kind, double *acc, int width)
{
    if (mf == BF_MF_GGX) {
        if (nl == 1) sweep_kind(in, n, nc, 1, BF_MF_GGX, kind, acc, width);
        else sweep_kind(in, n, nc, 2, BF_MF_GGX, kind, acc, width);
    } else if (mf == BF_MF_CT) {
        if (nl == 1) sweep_kind(in, n, nc, 1, BF_MF_CT, kind, acc, width);
        else sweep_kind(in, n, nc, 2, BF_MF_CT, kind, acc, width);
    } else if (mf == BF_MF_WARD) {
        sweep_kind(in, n, nc, 1, BF_MF_WARD, kind, acc, width);
    } else if (mf == BF_MF_WARD_DUER) {
        sweep_kind(in, n, nc, 1, BF_MF_WARD_DUER, kind, acc, width);
    } else if (mf == BF_MF_AS_FRESNEL) {
        sweep_kind(in, n, nc, 1, BF_MF_AS_FRESNEL, kind, acc, width);
    } else {
        if (nl == 1) sweep_kind(in, n, nc, 1, BF_MF_NONE, kind, acc, width);
        else if (nl == 2) sweep_kind(in, n, nc, 2, BF_MF_NONE, kind, acc, width);
        else sweep_kind(in, n, nc, 0, BF_MF_NONE, kind, acc, width);
    }
}

/* nc too */
static inline void sweep_any(const lobe_in *in, size_t n, size_t nc, size_t nl, int mf,
                             bf_pass_kind kind, double *acc, int width)
{
    if (nc == 3) sweep_lobes(in, n, 3, nl, mf, kind, acc, width);
    else sweep_lobes(in, n, 1, nl, mf, kind, acc, width);
}

#if defined(__GNUC__) || defined(__clang__)
#define BF_FLATTEN __attribute__((flatten))
#else
#define BF_FLATTEN
#endif

/* The versions, chosen per problem (bf_problem.isa). */
#if BF_FUSED_HAVE_ISA
__attribute__((target("avx512f"))) BF_FLATTEN static void
sweep_avx512(const lobe_in *in, size_t n, size_t nc, size_t nl, int mf,
             bf_pass_kind kind, double *acc)
{
    sweep_any(in, n, nc, nl, mf, kind, acc, 8);
}

__attribute__((target("avx2"))) BF_FLATTEN static void
sweep_avx2(const lobe_in *in, size_t n, size_t nc, size_t nl, int mf,
             bf_pass_kind kind, double *acc)
{
    sweep_any(in, n, nc, nl, mf, kind, acc, 4);
}
#endif

BF_FLATTEN static void sweep_base(const lobe_in *in, size_t n, size_t nc, size_t nl, int mf,
                                  bf_pass_kind kind, double *acc)
{
    sweep_any(in, n, nc, nl, mf, kind, acc, 4);
}

BF_FLATTEN static void sweep_plain_c(const lobe_in *in, size_t n, size_t nc, size_t nl,
                                     int mf, bf_pass_kind kind, double *acc)
{
    sweep_any(in, n, nc, nl, mf, kind, acc, 0);
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
    pb->lobe = 0;
    pb->mf = BF_MF_NONE;
    if (pb->kernel == NULL) return;
    if (bf_kernel_lobe(pb->kernel, 1.0, &lobe)) {
        bf_basis_form f;
        bf_kernel_form(pb->kernel, &f);
        pb->lobe = 1 + (int)f.n_shape;
    } else if (bf_kernel_microfacet(pb->kernel) != BF_MF_NONE) {
        /* shape parameters: a roughness per lobe, then F0 (Ward's: none;
         * the Ashikhmin-Shirley shader form: ns, then Rs) */
        bf_basis_form f;
        bf_kernel_form(pb->kernel, &f);
        pb->mf = (int)bf_kernel_microfacet(pb->kernel);
        pb->lobe = (int)f.n_shape + (has_f0(pb->mf) || is_asf(pb->mf) ? 0 : 1);
    }
}

/* Lobes of the problem's kernel (the lobe form: one per shape parameter;
 * the microfacet form: one per roughness);
 * read per chunk, so from pb rather than from the kernel. */
static size_t lobes_of(const bf_problem *pb)
{
    return (size_t)pb->lobe - 1;
}

int bf_fused_serves(const bf_problem *pb, bf_pass_kind kind)
{
    return pb->lobe > 0 && kind != BF_PASS_METRICS && kind != BF_PASS_SANDWICH &&
           (pb->objective == BRDFFIT_OBJECTIVE_SQUARES || kind == BF_PASS_VARPRO) &&
           (pb->nc == 1 || pb->nc == 3) && lobes_of(pb) <= MAX_LOBES &&
           (pb->mf == BF_MF_NONE || lobes_of(pb) >= 1) &&
           (has_f0(pb->mf) || pb->mf == BF_MF_NONE || lobes_of(pb) == 1);
}

int bf_fused_in_place(const bf_problem *pb, bf_pass_kind kind)
{
    return bf_fused_serves(pb, kind) && pb->source == BF_SOURCE_CHANNELS && !(pb->clearcoat > 0.0);
}

size_t bf_fused_acc_size(const bf_problem *pb, bf_pass_kind kind)
{
    return sums_of(kind, pb->nc, lobes_of(pb), pb->mf) * LANES;
}

/* The chunk's inputs: lobe constants, colours, geometry and values. */
static void fill_in(const bf_problem *pb, bf_pass_kind kind, const double *params,
                    const bf_scratch *sc, size_t n, size_t nl, lobe_in *in, double *g_local)
{
    const bf_geometry *geo = bf_grid_geometry(pb->grid);
    const size_t first = sc->first, nc = pb->nc;
    const int in_place = bf_fused_in_place(pb, kind);
    bf_lobe lobe = {BF_LOBE_X_LOG_NH, BF_LOBE_G_ONE, 0.0, 0.0};
    size_t c, i, q;
    if (is_asf(pb->mf)) {
        /* shape (ns, Rs), then (cd, cs); the lobe's constants those of
         * kernel_ashikhmin.c's as_lobe(): k = ns + 1, dk = 1 */
        const double ns = params[pb->vindex[0]];
        in->ns[0] = ns;
        in->k[0] = ns + 1.0;
        in->dk[0] = 1.0;
        in->f0 = params[pb->vindex[nc]];
        in->w = sc->w;
        in->x = geo->log_nh + first;
        in->g = geo->as_g + first;
        in->dot[0] = geo->nh + first;
        in->dot[1] = geo->nl + first;
        in->dot[2] = geo->nv + first;
        in->dot[3] = geo->hv + first;
        for (c = 0; c < nc; c++) {
            in->cd[c] = params[pb->vindex[2 * nc + c]];
            in->cs[0][c] = params[pb->vindex[3 * nc + c]];
            in->m[c] = in_place ? bf_grid_values(pb->grid, c) + first : sc->meas + c * n;
        }
        return;
    }
    if (pb->mf != BF_MF_NONE) {
        /* shape (r_1 .. r_nl, F0; Ward's: a), then (cd, cs_1 .. cs_nl) */
        const size_t K = nl + (has_f0(pb->mf) ? 1 : 0);
        for (q = 0; q < nl; q++) {
            const double r = params[pb->vindex[q * nc]];
            in->r2[q] = pb->mf == BF_MF_GGX ? r * r : 1.0 / (r * r);
            in->two_r[q] = 2.0 / r;
            in->four_r[q] = pb->mf == BF_MF_GGX || pb->mf == BF_MF_CT ? 4.0 * r
                                                                       : in->r2[q] / (4.0 * BF_PI);
            in->m2_r[q] = -2.0 * r;
        }
        in->f0 = has_f0(pb->mf) ? params[pb->vindex[nl * nc]] : 0.0;
        in->w = sc->w;
        in->x = in->g = NULL;
        in->dot[0] = geo->nh + first;
        in->dot[1] = geo->nl + first;
        in->dot[2] = geo->nv + first;
        in->dot[3] = geo->hv + first;
        for (c = 0; c < nc; c++) {
            in->cd[c] = params[pb->vindex[K * nc + c]];
            for (q = 0; q < nl; q++) in->cs[q][c] = params[pb->vindex[(K + 1 + q) * nc + c]];
            in->m[c] = in_place ? bf_grid_values(pb->grid, c) + first : sc->meas + c * n;
        }
        return;
    }
    for (q = 0; q < nl; q++) {
        const double ns = params[pb->vindex[q * nc]];
        bf_kernel_lobe(pb->kernel, ns, &lobe);
        in->ns[q] = ns;
        in->k[q] = lobe.k;
        in->dk[q] = lobe.dk;
    }
    in->w = sc->w;
    in->x = in->g = NULL;
    for (i = 0; i < 4; i++) in->dot[i] = NULL;
    if (nl > 0) {
        in->x = (lobe.x == BF_LOBE_X_LOG_NH ? geo->log_nh : geo->log_rv) + first;
        if (lobe.g == BF_LOBE_G_AS) {
            in->g = geo->as_g + first;
        } else {
            const double *rv = geo->rv + first;
            int one = lobe.g == BF_LOBE_G_ONE;
            for (i = 0; i < n; i++) g_local[i] = one || rv[i] > 0.0 ? 1.0 : 0.0;
            in->g = g_local;
        }
    }
    for (c = 0; c < nc; c++) {
        in->cd[c] = params[pb->vindex[nl * nc + c]];
        for (q = 0; q < nl; q++) in->cs[q][c] = params[pb->vindex[(nl + 1 + q) * nc + c]];
        in->m[c] = in_place ? bf_grid_values(pb->grid, c) + first : sc->meas + c * n;
    }
}

void bf_fused_chunk(const bf_problem *pb, bf_pass_kind kind, const double *params,
                    bf_scratch *sc, size_t n)
{
    double g_local[BF_CHUNK];
    const size_t nl = lobes_of(pb);
    lobe_in in;
    fill_in(pb, kind, params, sc, n, nl, &in, g_local);
#if BF_FUSED_HAVE_ISA
    if (pb->isa == BF_ISA_AVX512) {
        sweep_avx512(&in, n, pb->nc, nl, pb->mf, kind, sc->acc);
        return;
    }
    if (pb->isa == BF_ISA_AVX2) {
        sweep_avx2(&in, n, pb->nc, nl, pb->mf, kind, sc->acc);
        return;
    }
#endif
    if (pb->isa == BF_ISA_PLAIN) sweep_plain_c(&in, n, pb->nc, nl, pb->mf, kind, sc->acc);
    else sweep_base(&in, n, pb->nc, nl, pb->mf, kind, sc->acc);
}

/* Lanes reduced in the fixed order of the file comment. */
static double lane_sum(const double *a)
{
    return ((a[0] + a[1]) + (a[2] + a[3])) + ((a[4] + a[5]) + (a[6] + a[7]));
}

/* The upper triangle of an ne x ne Gram matrix from sums t0, t0 + 1, ..
 * (row by row), into G[a * ne + b]. */
static void reduce_gram(const double *lanes, size_t t0, size_t ne, double *G)
{
    size_t a, b, t = t0;
    for (a = 0; a < ne; a++)
        for (b = a; b < ne; b++) G[a * ne + b] = lane_sum(lanes + t++ * LANES);
}

void bf_fused_reduce(const bf_problem *pb, bf_pass_kind kind, const double *lanes,
                     double *basis_acc)
{
    const size_t nc = pb->nc, nl = lobes_of(pb), ne = n_ext(nl, pb->mf), L = 1 + nl;
    size_t t;
    if (kind == BF_PASS_COST) {
        basis_acc[0] = lane_sum(lanes);
    } else if (kind == BF_PASS_NORMAL) {
        const size_t ng = ne * (ne + 1) / 2;
        double *G = basis_acc + 1, *H = basis_acc + 1 + ne * ne;
        memset(basis_acc, 0, (1 + ne * ne + nc * ne) * sizeof *basis_acc);
        basis_acc[0] = lane_sum(lanes);
        reduce_gram(lanes, 1, ne, G);
        for (t = 0; t < nc * ne; t++) H[t] = lane_sum(lanes + (1 + ng + t) * LANES);
    } else {
        const size_t ng = L * (L + 1) / 2;
        double *G = basis_acc, *b = basis_acc + L * L;
        memset(basis_acc, 0, (L * L + nc * (L + 1)) * sizeof *basis_acc);
        reduce_gram(lanes, 0, L, G);
        /* b (nc x L) and then rr (nc): the same order as the sums */
        for (t = 0; t < nc * (L + 1); t++) b[t] = lane_sum(lanes + (ng + t) * LANES);
    }
}
