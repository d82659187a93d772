/* The fused inner loop (pass_fused.h): one sweep per run of samples for
 * the models of the one-lobe form of models/basis.h,
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
 * -2 a; 1 / m^2, 2 / m) once per pass; and Ward's lobes (Ward,
 * Ward-Duer) alike, without F0; and ashikhmin-shirley-fresnel in the
 * same form, Rs in F0's place and its diffuse (1 - Rs) fd in 1/pi's, fd
 * and (1 - h.v)^5 once per group of lanes.
 *
 * What a pass reads per sample, in place: the grid's base weight (the
 * weight plan's, bf_weight_plan_base(), times a factor per run of
 * samples), its lobe geometry g, its measured values times a power of two
 * (bf_grid_fvalues()), all three in single precision, and the logarithm
 * x and the dot products in double (grid_internal.h). So a pass streams
 * 28 bytes per sample of Ashikhmin-Shirley on 3 channels, where the
 * double inputs and the weights computed per chunk took 56 on a scattered
 * grid; the sums, every product and the exponential are in double. Each
 * rounded input is within 2^-24 of its double, so the loop's sums agree
 * with the unfused basis route's (double inputs) to about 1e-7 relative
 * (test_fused.c checks 1e-6 of the largest entry), and fits of noise-free
 * data end within 1e-7 of the truth rather than at rounding level.
 *
 * A run (the weight plan's pieces of one factor, joined while their
 * samples follow each other, at most a thread's block of chunks) is swept
 * SWEEP_BLOCK samples at a time in two phases (pass_lanes_vec.h): the
 * weighted basis of every sample into a buffer, whose lanes have no
 * dependence from one group to the next so that the processor overlaps
 * their long chains (the exponential's), then the sums from the buffer,
 * short chains into the accumulators, which stay in registers: all of
 * them with AVX-512, one block of them at a time (the Gram matrix, then
 * each channel's) with 16 registers.
 *
 * Summation order, fixed whatever the instruction set: every sum has
 * LANES = 8 lanes; sample i of a run goes to lane i mod 8, in sample
 * order (a run's last samples beyond a multiple of 8 are run as a group
 * padded with weight 0, which adds exact zeros); a thread's lanes run over
 * its block of chunks in order, the driver adds the blocks' lanes in block
 * order (pass.c) and the lanes are then reduced as ((l0 + l1) + (l2 +
 * l3)) + ((l4 + l5) + (l6 + l7)), the channels' costs in channel order.
 * The versions compute the same operations per lane in two families: with
 * fused multiply-add (the AVX-512 and AVX2 versions, and the plain C one
 * with fma() as their reference) and without (the baseline and the plain
 * C one; ISO C mode for gcc, FP_CONTRACT off for clang), so within a
 * family they give the same bits, and the families agree to rounding;
 * test_fused.c checks both on what the machine runs. Views (grid/view.c)
 * hold the single-precision values too, so the fits of a batch give the
 * bits of single fits; the channel mean and the clear-coat compensation
 * are loaded by the driver, rounded alike and swept chunk by chunk. */
#ifdef __clang__
#pragma STDC FP_CONTRACT OFF
#endif

#include "fit/pass_fused.h"

#include <string.h>

#include "core/core.h"
#include "fit/pass_lanes.h"
#include "models/basis.h"

/* The forms the loop runs (lobes, microfacet family, the lobe form's g):
 * Lambert; Ashikhmin-Shirley, Blinn-Phong, Phong; the two-lobe
 * Ashikhmin-Shirley; GGX and Cook-Torrance with one lobe and two; Ward,
 * Ward-Duer; the Ashikhmin-Shirley shader form. Each (version, form,
 * kind, channels) is a function of its own with every choice a constant,
 * flattened alone (one function holding them all takes the compiler
 * minutes). */
#define FORMS(X, V)                      \
    X(V, 0, 0, BF_MF_NONE, G_ONE)        \
    X(V, 1, 1, BF_MF_NONE, G_READ)       \
    X(V, 2, 1, BF_MF_NONE, G_ONE)        \
    X(V, 3, 1, BF_MF_NONE, G_RV)         \
    X(V, 4, 2, BF_MF_NONE, G_READ)       \
    X(V, 5, 1, BF_MF_GGX, G_READ)        \
    X(V, 6, 2, BF_MF_GGX, G_READ)        \
    X(V, 7, 1, BF_MF_CT, G_READ)         \
    X(V, 8, 2, BF_MF_CT, G_READ)         \
    X(V, 9, 1, BF_MF_WARD, G_READ)       \
    X(V, 10, 1, BF_MF_WARD_DUER, G_READ) \
    X(V, 11, 1, BF_MF_AS_FRESNEL, G_READ)
#define N_FORMS 12

typedef void (*sweep_fn)(const lobe_in *in, size_t n, double *acc);

#if defined(__GNUC__) || defined(__clang__)
#define BF_FLATTEN __attribute__((flatten))
#else
#define BF_FLATTEN
#endif

/* The versions' sweeps: VCALL(in, n, nc, nl, mf, gk, kind, acc). */
#if BF_LANES_VECTOR
#if BF_FUSED_HAVE_ISA
#define CALL_avx512(in, n, nc, nl, mf, gk, kind, acc) sweep_w8(in, n, nc, nl, mf, gk, kind, acc)
#define TARGET_avx512 __attribute__((target("avx512f,fma")))
#define CALL_avx2(in, n, nc, nl, mf, gk, kind, acc) sweep_w4f(in, n, nc, nl, mf, gk, kind, acc)
#define TARGET_avx2 __attribute__((target("avx2,fma")))
#endif
#define CALL_base(in, n, nc, nl, mf, gk, kind, acc) sweep_w4(in, n, nc, nl, mf, gk, kind, acc)
#else
#define CALL_base(in, n, nc, nl, mf, gk, kind, acc) sweep_plain(in, n, nc, nl, mf, gk, kind, acc, 0)
#endif
#define TARGET_base
#define CALL_plain(in, n, nc, nl, mf, gk, kind, acc) \
    sweep_plain(in, n, nc, nl, mf, gk, kind, acc, 0)
#define TARGET_plain
#define CALL_plainfma(in, n, nc, nl, mf, gk, kind, acc) \
    sweep_plain(in, n, nc, nl, mf, gk, kind, acc, 1)
#define TARGET_plainfma

/* One function per form, kind and channel count of version V. */
#define SWEEP_DEF(V, F, NL, MF, GK, K, KIND, NC)                                                \
    TARGET_##V BF_FLATTEN static void sweep_##V##_##F##_##K##_##NC(const lobe_in *in, size_t n, \
                                                                   double *acc)                 \
    {                                                                                           \
        CALL_##V(in, n, NC, NL, MF, GK, KIND, acc);                                             \
    }
#define SWEEP_DEFS(V, F, NL, MF, GK)                  \
    SWEEP_DEF(V, F, NL, MF, GK, 0, BF_PASS_COST, 1)   \
    SWEEP_DEF(V, F, NL, MF, GK, 0, BF_PASS_COST, 3)   \
    SWEEP_DEF(V, F, NL, MF, GK, 1, BF_PASS_NORMAL, 1) \
    SWEEP_DEF(V, F, NL, MF, GK, 1, BF_PASS_NORMAL, 3) \
    SWEEP_DEF(V, F, NL, MF, GK, 2, BF_PASS_VARPRO, 1) \
    SWEEP_DEF(V, F, NL, MF, GK, 2, BF_PASS_VARPRO, 3)
#define SWEEP_ROW(V, F, NL, MF, GK)                  \
    {{sweep_##V##_##F##_0_1, sweep_##V##_##F##_0_3}, \
     {sweep_##V##_##F##_1_1, sweep_##V##_##F##_1_3}, \
     {sweep_##V##_##F##_2_1, sweep_##V##_##F##_2_3}},
/* the table of version V: [form][COST, NORMAL, VARPRO][1 or 3 channels] */
#define SWEEP_TABLE(V)   \
    FORMS(SWEEP_DEFS, V) \
    static const sweep_fn sweeps_##V[N_FORMS][3][2] = {FORMS(SWEEP_ROW, V)};

#if BF_FUSED_HAVE_ISA && BF_LANES_VECTOR
SWEEP_TABLE(avx512)
SWEEP_TABLE(avx2)
#endif
SWEEP_TABLE(base)
SWEEP_TABLE(plain)
SWEEP_TABLE(plainfma)

/* The problem's form (FORMS), -1 when the loop does not run it. */
static int form_of(const bf_problem *pb, size_t nl, int gk)
{
    switch (pb->mf) {
    case BF_MF_NONE:
        if (nl == 0) return 0;
        if (nl == 1) return gk == G_READ ? 1 : gk == G_ONE ? 2 : 3;
        return nl == 2 && gk == G_READ ? 4 : -1;
    case BF_MF_GGX: return nl == 1 ? 5 : nl == 2 ? 6 : -1;
    case BF_MF_CT: return nl == 1 ? 7 : nl == 2 ? 8 : -1;
    case BF_MF_WARD: return nl == 1 ? 9 : -1;
    case BF_MF_WARD_DUER: return nl == 1 ? 10 : -1;
    case BF_MF_AS_FRESNEL: return nl == 1 ? 11 : -1;
    default: return -1;
    }
}

unsigned bf_fused_best_isa(void)
{
#if BF_FUSED_HAVE_ISA
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("fma")) return BF_ISA_AVX512;
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return BF_ISA_AVX2;
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

/* The lobe form's g of the problem's kernel (G_READ: its x and g are the
 * Ashikhmin-Shirley ones). */
static int g_kind(const bf_problem *pb)
{
    bf_lobe lobe;
    if (pb->mf != BF_MF_NONE || lobes_of(pb) == 0) return G_READ;
    bf_kernel_lobe(pb->kernel, 1.0, &lobe);
    return lobe.g == BF_LOBE_G_AS ? G_READ : lobe.g == BF_LOBE_G_ONE ? G_ONE : G_RV;
}

int bf_fused_serves_any(const bf_problem *pb, bf_pass_kind kind)
{
    return pb->lobe > 0 && kind != BF_PASS_METRICS && kind != BF_PASS_SANDWICH &&
           pb->plan->base != NULL &&
           (pb->objective == BRDFFIT_OBJECTIVE_SQUARES || kind == BF_PASS_VARPRO) &&
           (pb->nc == 1 || pb->nc == 3) && form_of(pb, lobes_of(pb), g_kind(pb)) >= 0;
}

int bf_fused_serves(const bf_problem *pb, bf_pass_kind kind)
{
    return bf_fused_serves_any(pb, kind) && bf_grid_fscale(pb->grid) > 0.0;
}

int bf_fused_in_place(const bf_problem *pb, bf_pass_kind kind)
{
    return bf_fused_serves(pb, kind) && pb->source == BF_SOURCE_CHANNELS &&
           !(pb->clearcoat > 0.0) && bf_grid_fvalues(pb->grid, 0) != NULL;
}

size_t bf_fused_acc_size(const bf_problem *pb, bf_pass_kind kind)
{
    return sums_of(kind, pb->nc, lobes_of(pb), pb->mf) * LANES;
}

/* A pass's constants of the run inputs: lobe constants and colours (in
 * the grid's scaled units); the arrays are set per run (set_run()). */
static void fill_constants(const bf_problem *pb, const double *params, size_t nl, lobe_in *in)
{
    const size_t nc = pb->nc;
    const double scale = bf_grid_fscale(pb->grid);
    size_t c, q, k0 = nl; /* declared index of cd */
    memset(in, 0, sizeof *in);
    if (is_asf(pb->mf)) {
        /* shape (ns, Rs), then (cd, cs); the lobe's constants those of
         * kernel_ashikhmin.c's as_lobe(): k = ns + 1, dk = 1 */
        const double ns = params[pb->vindex[0]];
        in->ns[0] = ns;
        in->nsl[0] = ns * EXP_LOG2E;
        in->k[0] = ns + 1.0;
        in->dk[0] = 1.0;
        in->f0 = params[pb->vindex[nc]];
        k0 = 2;
    } else if (pb->mf != BF_MF_NONE) {
        /* shape (r_1 .. r_nl, F0; Ward's: a), then (cd, cs_1 .. cs_nl) */
        for (q = 0; q < nl; q++) {
            const double r = params[pb->vindex[q * nc]];
            in->r2[q] = pb->mf == BF_MF_GGX ? r * r : 1.0 / (r * r);
            in->two_r[q] = 2.0 / r;
            in->four_r[q] = pb->mf == BF_MF_GGX || pb->mf == BF_MF_CT ? 4.0 * r
                                                                       : in->r2[q] / (4.0 * BF_PI);
            in->m2_r[q] = -2.0 * r;
        }
        in->f0 = has_f0(pb->mf) ? params[pb->vindex[nl * nc]] : 0.0;
        k0 = nl + (has_f0(pb->mf) ? 1 : 0);
    } else {
        for (q = 0; q < nl; q++) {
            bf_lobe lobe;
            const double ns = params[pb->vindex[q * nc]];
            bf_kernel_lobe(pb->kernel, ns, &lobe);
            in->ns[q] = ns;
            in->nsl[q] = ns * EXP_LOG2E;
            in->k[q] = lobe.k;
            in->dk[q] = lobe.dk;
        }
    }
    for (c = 0; c < nc; c++) {
        in->cd[c] = params[pb->vindex[k0 * nc + c]] * scale;
        in->cdpi[c] = in->cd[c] * INV_PI;
        for (q = 0; q < nl; q++) in->cs[q][c] = params[pb->vindex[(k0 + 1 + q) * nc + c]] * scale;
    }
}

/* The arrays of the run of samples from `first` (weights base * wf, values
 * m[c] + offset). */
static void set_run(const bf_problem *pb, lobe_in *in, size_t nl, size_t first, double wf,
                    const float *const *m, size_t offset)
{
    const bf_geometry *geo = bf_grid_geometry(pb->grid);
    size_t c;
    in->w = pb->plan->base + first;
    in->wf = wf;
    in->x = NULL;
    in->g = NULL;
    if (reads_lobe(nl, pb->mf)) {
        bf_lobe lobe = {BF_LOBE_X_LOG_NH, BF_LOBE_G_AS, 0.0, 0.0};
        if (pb->mf == BF_MF_NONE) bf_kernel_lobe(pb->kernel, 1.0, &lobe);
        in->x = (lobe.x == BF_LOBE_X_LOG_NH ? geo->log_nh : geo->log_rv) + first;
        in->g = geo->as_g + first;
    }
    if (pb->mf != BF_MF_NONE) {
        in->dot[0] = geo->nh + first;
        in->dot[1] = geo->nl + first;
        in->dot[2] = geo->nv + first;
        in->dot[3] = geo->hv + first;
    }
    for (c = 0; c < pb->nc; c++) in->m[c] = m[c] + offset;
}

/* The problem's sweep of this kind in its version of the loop. */
static sweep_fn sweep_of(const bf_problem *pb, bf_pass_kind kind)
{
    const int f = form_of(pb, lobes_of(pb), g_kind(pb));
    const int k = kind == BF_PASS_COST ? 0 : kind == BF_PASS_NORMAL ? 1 : 2, c = pb->nc == 3;
#if BF_FUSED_HAVE_ISA && BF_LANES_VECTOR
    if (pb->isa == BF_ISA_AVX512) return sweeps_avx512[f][k][c];
    if (pb->isa == BF_ISA_AVX2) return sweeps_avx2[f][k][c];
#endif
    if (pb->isa == BF_ISA_PLAIN) return sweeps_plain[f][k][c];
    if (pb->isa == BF_ISA_PLAIN_FMA) return sweeps_plainfma[f][k][c];
    return sweeps_base[f][k][c];
}

/* Sweep the run (nothing when it is empty). */
static void flush_run(const bf_problem *pb, sweep_fn sweep, lobe_in *in, size_t nl,
                      const float *const *m, const bf_weight_piece *run, double *acc)
{
    if (run->count == 0) return;
    set_run(pb, in, nl, run->first, run->factor, m, run->first);
    sweep(in, run->count, acc);
}

int bf_fused_block(const bf_problem *pb, bf_pass_kind kind, const double *params, bf_scratch *sc,
                   size_t c0, size_t c1)
{
    const size_t nl = lobes_of(pb);
    const float *m[3];
    bf_weight_piece run = {0, 0, 0.0}, piece[2];
    lobe_in in;
    sweep_fn sweep;
    size_t ci, k, c, np;
    if (!bf_fused_in_place(pb, kind)) return 0;
    sweep = sweep_of(pb, kind);
    fill_constants(pb, params, nl, &in);
    for (c = 0; c < pb->nc; c++) m[c] = bf_grid_fvalues(pb->grid, c);
    /* the chunks' pieces joined into runs of contiguous samples with one
     * factor, each swept at once */
    for (ci = c0; ci < c1; ci++) {
        np = bf_weight_plan_base(pb->plan, ci, piece);
        for (k = 0; k < np; k++) {
            if (run.count > 0 && piece[k].first == run.first + run.count &&
                piece[k].factor == run.factor) {
                run.count += piece[k].count;
                continue;
            }
            flush_run(pb, sweep, &in, nl, m, &run, sc->acc);
            run = piece[k];
        }
    }
    flush_run(pb, sweep, &in, nl, m, &run, sc->acc);
    return 1;
}

void bf_fused_chunk(const bf_problem *pb, bf_pass_kind kind, const double *params,
                    bf_scratch *sc, size_t n)
{
    const size_t nl = lobes_of(pb), nc = pb->nc;
    const double scale = bf_grid_fscale(pb->grid);
    float *fm = (float *)(void *)sc->vals; /* nc * BF_CHUNK floats */
    const float *m[3];
    bf_weight_piece piece[2];
    lobe_in in;
    const sweep_fn sweep = sweep_of(pb, kind);
    size_t np, k, c, i;
    fill_constants(pb, params, nl, &in);
    /* the loaded values, scaled, in single precision */
    for (c = 0; c < nc; c++) {
        for (i = 0; i < n; i++) fm[c * n + i] = (float)(sc->meas[c * n + i] * scale);
        m[c] = fm + c * n;
    }
    np = bf_weight_plan_base(pb->plan, sc->chunk, piece);
    for (k = 0; k < np; k++) {
        set_run(pb, &in, nl, piece[k].first, piece[k].factor, m, piece[k].first - sc->first);
        sweep(&in, piece[k].count, sc->acc);
    }
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
    const size_t nc = pb->nc, nl = lobes_of(pb), ne = n_basis(kind, nl, pb->mf);
    const size_t ng = gram_sums(kind, nl, pb->mf), cs = channel_sums(kind, nl, pb->mf);
    /* back from the grid's scaled units (exact: a power of two) */
    const double unit = 1.0 / bf_grid_fscale(pb->grid), unit2 = unit * unit;
    size_t c, a;
    if (kind == BF_PASS_COST) {
        double cost = 0.0;
        for (c = 0; c < nc; c++) cost += lane_sum(lanes + c * LANES);
        basis_acc[0] = cost * unit2;
    } else if (kind == BF_PASS_NORMAL) {
        double *G = basis_acc + 1, *H = basis_acc + 1 + ne * ne, cost = 0.0;
        memset(basis_acc, 0, (1 + ne * ne + nc * ne) * sizeof *basis_acc);
        reduce_gram(lanes, 0, ne, G);
        for (c = 0; c < nc; c++) {
            const double *ch = lanes + (ng + c * cs) * LANES;
            cost += lane_sum(ch);
            for (a = 0; a < ne; a++) H[c * ne + a] = lane_sum(ch + (1 + a) * LANES) * unit;
        }
        basis_acc[0] = cost * unit2;
    } else {
        double *G = basis_acc, *b = basis_acc + ne * ne, *rr = b + nc * ne;
        memset(basis_acc, 0, (ne * ne + nc * (ne + 1)) * sizeof *basis_acc);
        reduce_gram(lanes, 0, ne, G);
        for (c = 0; c < nc; c++) {
            const double *ch = lanes + (ng + c * cs) * LANES;
            for (a = 0; a < ne; a++) b[c * ne + a] = lane_sum(ch + a * LANES) * unit;
            rr[c] = lane_sum(ch + ne * LANES) * unit2;
        }
    }
}
