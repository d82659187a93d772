/* The lanes of the fused loop (pass_fused.c): the sums of one run of
 * samples in LANES = 8 lanes each, sample i of a run in lane i mod 8. Two
 * implementations of the same arithmetic: with the GNU C vector
 * extensions (gcc, clang), whose 8-double vectors the compiler keeps in
 * registers (one zmm each with AVX-512, two ymm halves with AVX2 or the
 * baseline), and in plain C for other compilers and as the reference of
 * tests/test_fused.c. Each comes in two families: with fused multiply-add
 * (fma = 1: the AVX-512 and AVX2 versions, and the plain one with fma()
 * of math.h) and without (fma = 0: the baseline and the plain one). Within
 * a family every version computes the same operations per lane, so the
 * same bits. Included by pass_fused.c only. Not installed. */
#ifndef BRDFFIT_FIT_PASS_LANES_H
#define BRDFFIT_FIT_PASS_LANES_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "core/core.h"
#include "fit/pass.h"
#include "fit/pass_fused.h"

#define LANES 8
/* lobes of the lobe form or the microfacet form (models/basis.h) the loop
 * runs: 0, 1 or 2 (the microfacet form 1 or 2) */
#define MAX_LOBES 2
/* lanes of sums with NE functions of the extended basis (the lobe form
 * 1 + 2 nl, the microfacet form 1 + 3 nl, Ward's 3, the Ashikhmin-Shirley
 * shader form 5) and L = 1 + nl linear ones, in blocks: block 0 the Gram
 * matrix of the basis (its upper triangle row by row), block 1 + c channel
 * c's sums. NORMAL: G (NE (NE + 1) / 2), then per channel [cost_c, H_c
 * (NE)]; VARPRO: G (L (L + 1) / 2), then per channel [b_c (L), rr_c];
 * COST: per channel [cost_c]. At most 52 (two microfacet lobes on 3
 * channels). */
#define MAX_SUMS 64
/* functions of the largest extended basis (two microfacet lobes) */
#define MAX_EXT (1 + 3 * MAX_LOBES)
#define INV_PI (1.0 / BF_PI)
/* the Ashikhmin-Shirley shader form's diffuse constant (kernel_ashikhmin.c) */
#define ASF_KD (28.0 / (23.0 * BF_PI))
/* the lobe form's g (models/basis.h, bf_lobe_g): read (Ashikhmin-Shirley),
 * 1 (Blinn-Phong), or 1 where x > X_RV_LIVE (Phong: the grid's log_rv is
 * BF_LOG_RV_NONE where r.v <= 0) */
#define G_READ 0
#define G_ONE 1
#define G_RV 2
#define X_RV_LIVE (-900.0)
/* samples of a run whose basis the vector sweeps hold in a buffer at once
 * (a multiple of LANES; the buffer, at most 11 rows of it, stays in the
 * first-level cache) */
#define SWEEP_BLOCK 128

/* One run's inputs: contiguous samples whose weights are w[i] * wf. The
 * lobe form: x and g shared by the lobes (NULL without lobes; g unread
 * unless G_READ), ns, k, dk per lobe. The microfacet form (mf =
 * BF_MF_GGX or BF_MF_CT): the dot products dot[0..3] = n.h, n.l, n.v, h.v
 * of the grid's geometry, the roughness r per lobe with its
 * parameter-only factors, and the shared F0. The Ashikhmin-Shirley shader
 * form (BF_MF_AS_FRESNEL): one lobe of the lobe form (x, g, ns, k, dk;
 * nsl = ns log2(e)),
 * the dot products and Rs in f0. The measured values m[c] and the colours
 * cd, cs are in the grid's scaled units (bf_grid_fscale(): every value
 * times a power of two), so that they fit single precision whatever the
 * data's units; cdpi = cd / pi. */
typedef struct lobe_in {
    const float *w, *g, *m[3];
    const double *x, *dot[4];
    double wf;
    double ns[MAX_LOBES], nsl[MAX_LOBES], k[MAX_LOBES], dk[MAX_LOBES];
    double cd[3], cdpi[3], cs[MAX_LOBES][3];
    /* GGX: r2 = a^2, two_r = 2 / a, four_r = 4 a, m2_r = -2 a; CT: r2 =
     * 1 / m^2, two_r = 2 / m (the expressions of kernel_microfacet.c);
     * Ward: r2 = 1 / a^2, two_r = 2 / a, four_r = r2 / (4 pi) (those of
     * kernel_ward.c) */
    double r2[MAX_LOBES], two_r[MAX_LOBES], four_r[MAX_LOBES], m2_r[MAX_LOBES], f0;
} lobe_in;

/* whether the form has the shared F0 (GGX, Cook-Torrance; not Ward's) */
static inline int has_f0(int mf)
{
    return mf == BF_MF_GGX || mf == BF_MF_CT;
}

/* the Ashikhmin-Shirley shader form: Rs in place of F0 and a diffuse
 * B_0 = (1 - Rs) fd of the sample in place of 1/pi */
static inline int is_asf(int mf)
{
    return mf == BF_MF_AS_FRESNEL;
}

/* whether the run reads x and g (the lobe form with lobes, the
 * Ashikhmin-Shirley shader form) and the dot products (the microfacet
 * form) */
static inline int reads_lobe(size_t nl, int mf)
{
    return (nl > 0 && mf == BF_MF_NONE) || is_asf(mf);
}

static inline size_t n_ext(size_t nl, int mf)
{
    return is_asf(mf) ? 5 : has_f0(mf) ? 1 + 3 * nl : 1 + 2 * nl;
}

/* the basis functions of the pass's sums: NE for NORMAL, L otherwise */
static inline size_t n_basis(bf_pass_kind kind, size_t nl, int mf)
{
    return kind == BF_PASS_NORMAL ? n_ext(nl, mf) : 1 + nl;
}

/* sums of the Gram block and of one channel's block */
static inline size_t gram_sums(bf_pass_kind kind, size_t nl, int mf)
{
    const size_t ne = n_basis(kind, nl, mf);
    return kind == BF_PASS_COST ? 0 : ne * (ne + 1) / 2;
}

static inline size_t channel_sums(bf_pass_kind kind, size_t nl, int mf)
{
    return kind == BF_PASS_COST ? 1 : 1 + n_basis(kind, nl, mf);
}

/* the first sum of block blk and the sums of the pass */
static inline size_t block_first(bf_pass_kind kind, size_t nl, int mf, size_t blk)
{
    return blk == 0 ? 0 : gram_sums(kind, nl, mf) + (blk - 1) * channel_sums(kind, nl, mf);
}

static inline size_t sums_of(bf_pass_kind kind, size_t nc, size_t nl, int mf)
{
    return block_first(kind, nl, mf, 1 + nc);
}

/* A run's samples beyond the last multiple of LANES, padded to LANES
 * with weight 0 (x = g = m = 0 and the dot products 1, so every padded
 * term is finite and its weighted value an exact 0): *t reads them from b
 * at offset 0. */
typedef struct tail_buf {
    float w[LANES], g[LANES], m[3][LANES];
    double x[LANES], dot[4][LANES];
} tail_buf;

static inline void pad_tail(const lobe_in *in, size_t i, size_t n, size_t nc, size_t nl, int mf,
                            int gk, tail_buf *b, lobe_in *t)
{
    size_t l, c, k;
    memset(b, 0, offsetof(tail_buf, dot));
    /* the dot products only for the microfacet form (mf is a constant) */
    if (mf != BF_MF_NONE)
        for (k = 0; k < 4; k++)
            for (l = 0; l < LANES; l++) b->dot[k][l] = 1.0;
    *t = *in;
    for (l = 0; i + l < n; l++) {
        b->w[l] = in->w[i + l];
        if (reads_lobe(nl, mf)) {
            b->x[l] = in->x[i + l];
            if (gk == G_READ) b->g[l] = in->g[i + l];
        }
        if (mf != BF_MF_NONE)
            for (k = 0; k < 4; k++) b->dot[k][l] = in->dot[k][i + l];
        for (c = 0; c < nc; c++) b->m[c][l] = in->m[c][i + l];
    }
    t->w = b->w;
    t->x = b->x;
    t->g = b->g;
    if (mf != BF_MF_NONE)
        for (k = 0; k < 4; k++) t->dot[k] = b->dot[k];
    for (c = 0; c < nc; c++) t->m[c] = b->m[c];
}

/* The exponential of the fused loop, e^y for y <= 0 (every argument of
 * the lobes is: ns > 0 times x <= 0, or minus a square), in the
 * operations of both families: bf_exp()'s reduction and scaling
 * (core/fastmath.h) from t = y log2(e) + 1.5 2^52, whose low bits hold
 * k = round(y / ln 2), and the Taylor polynomial of degree 11 in
 * Estrin's scheme (a chain of 5 dependent operations rather than
 * Horner's 11): truncation below 7e-15 relative, far below the
 * single-precision inputs' 6e-8. e^y is 0 below y = -708 (the
 * arithmetic of those lanes, finite or not, is masked off, so no clamp
 * lies on the chain). The lobe form takes t from x and ns log2(e) rather
 * than from y, one multiplication shorter: k may then differ from
 * round(y / ln 2) by one where y / ln 2 lies next to a half, which moves r
 * by ln 2 within the polynomial's accuracy. */
#define EXP_LO (-708.0)
#define EXP_LOG2E 1.4426950408889634
#define EXP_LN2_HI 6.93147180369123816490e-01
#define EXP_LN2_LO 1.90821492927058770002e-10
#define EXP_SHIFTER 6755399441055744.0 /* 1.5 * 2^52 */
#define EXP_C11 (1.0 / 39916800.0)
#define EXP_C10 (1.0 / 3628800.0)
#define EXP_C9 (1.0 / 362880.0)
#define EXP_C8 (1.0 / 40320.0)
#define EXP_C7 (1.0 / 5040.0)
#define EXP_C6 (1.0 / 720.0)
#define EXP_C5 (1.0 / 120.0)
#define EXP_C4 (1.0 / 24.0)
#define EXP_C3 (1.0 / 6.0)
#define EXP_C2 0.5

#if defined(__GNUC__) || defined(__clang__)
/* The helpers take and return vectors; they are static and inlined, so
 * no call crosses an ABI boundary (gcc and clang warn about the vector
 * ABI). */
#pragma GCC diagnostic ignored "-Wpsabi"
#define BF_LANES_VECTOR 1
/* 8-wide vectors with fused multiply-add (AVX-512), 4-wide ones with it
 * (AVX2) and without (the baseline: two xmm each), each running the lanes
 * of a run: the 4-wide sweeps run lanes 0-3, then lanes 4-7. The
 * AVX-512 and AVX2 ones are compiled for their instruction sets. */
#if BF_FUSED_HAVE_ISA
#include <immintrin.h>
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx512f,fma"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx512f,fma")
#endif
#define VW 8
#define VFMA 1
#define VSUFFIX w8
#include "fit/pass_lanes_vec.h"
#undef VW
#undef VFMA
#undef VSUFFIX
#if defined(__clang__)
#pragma clang attribute pop
#pragma clang attribute push(__attribute__((target("avx2,fma"))), apply_to = function)
#else
#pragma GCC pop_options
#pragma GCC push_options
#pragma GCC target("avx2,fma")
#endif
#define VW 4
#define VFMA 1
#define VSUFFIX w4f
#include "fit/pass_lanes_vec.h"
#undef VW
#undef VFMA
#undef VSUFFIX
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
#endif /* BF_FUSED_HAVE_ISA */
#define VW 4
#define VFMA 0
#define VSUFFIX w4
#include "fit/pass_lanes_vec.h"
#undef VW
#undef VFMA
#undef VSUFFIX
#endif

/* ---- the plain C version of the same arithmetic ---------------------------- */

typedef double lanes_t[LANES];

typedef struct sums_t {
    lanes_t v[MAX_SUMS];
} sums_t;

/* a b + c, rounded once (fma = 1) or twice */
static inline double madd(double a, double b, double c, int fma_)
{
    return fma_ ? fma(a, b, c) : a * b + c;
}

static inline double lane_exp_t(double y, double t, int fma_)
{
    double k, r, r2, r4, r8, q0, q1, q2, q3, q4, q5, p, scale;
    uint64_t bits;
    k = t - EXP_SHIFTER;
    r = madd(-k, EXP_LN2_HI, y, fma_);
    r = madd(-k, EXP_LN2_LO, r, fma_);
    r2 = r * r;
    r4 = r2 * r2;
    r8 = r4 * r4;
    q0 = r + 1.0;
    q1 = madd(EXP_C3, r, EXP_C2, fma_);
    q2 = madd(EXP_C5, r, EXP_C4, fma_);
    q3 = madd(EXP_C7, r, EXP_C6, fma_);
    q4 = madd(EXP_C9, r, EXP_C8, fma_);
    q5 = madd(EXP_C11, r, EXP_C10, fma_);
    q0 = madd(q1, r2, q0, fma_);
    q2 = madd(q3, r2, q2, fma_);
    q4 = madd(q5, r2, q4, fma_);
    q0 = madd(q2, r4, q0, fma_);
    p = madd(q4, r8, q0, fma_);
    memcpy(&bits, &t, sizeof bits);
    bits = (bits + 1023u) << 52;
    memcpy(&scale, &bits, sizeof scale);
    return y >= EXP_LO ? p * scale : 0.0;
}

static inline double lane_exp(double y, int fma_)
{
    return lane_exp_t(y, madd(y, EXP_LOG2E, EXP_SHIFTER, fma_), fma_);
}

/* The lane's weighted basis u = w (1/pi, B_1 .. B_nl, dB_1 .. dB_nl) (the
 * derivatives only for NORMAL) and the lobes' values b: the lobe form,
 * B_q = e_q k_q g with e_q = exp(ns_q x), the factors of e_q formed
 * apart from it (so that they lie off its chain). */
static inline void lane_basis(const lobe_in *in, size_t j, size_t nl, int gk, int derivs, double w,
                              double *u, double *b, int fma_)
{
    size_t q;
    u[0] = w * INV_PI;
    if (nl == 0) return;
    {
        const double x = in->x[j];
        const double g = gk == G_READ ? (double)in->g[j] : gk == G_ONE || x > X_RV_LIVE ? 1.0 : 0.0;
        const double gw = g * w;
        for (q = 0; q < nl; q++) {
            const double e =
                lane_exp_t(in->ns[q] * x, madd(x, in->nsl[q], EXP_SHIFTER, fma_), fma_);
            b[q] = e * (in->k[q] * g);
            u[1 + q] = e * (in->k[q] * gw);
            if (derivs) u[1 + nl + q] = e * (madd(in->k[q], x, in->dk[q], fma_) * gw);
        }
    }
}

/* The microfacet form: u = w (1/pi, B_q, dB_q/dr_q, dB_q/dF0) in the
 * order of models/basis.h (Ward's: w (1/pi, B_1, dB_1/da); the
 * Ashikhmin-Shirley shader form's: w (B_0, B_1, dB_1/dns, dB_0/dRs,
 * dB_1/dRs), its B_0 into *bd) and b = B_q, with the expressions of
 * kernel_microfacet.c (ggx_geometry(), ggx_lobe(), ct_geometry(),
 * ct_lobe()), kernel_ward.c (ward_basis_common()) and kernel_ashikhmin.c
 * (as_lobe(), asf_basis()). */
static inline void lane_mf_basis(const lobe_in *in, size_t j, size_t nl, int mf, int derivs,
                                 double w, double *u, double *b, double *bd, int fma_)
{
    const double nh = in->dot[0][j], nl_ = in->dot[1][j], nv = in->dot[2][j];
    const double hv1 = 1.0 - in->dot[3][j], hv2 = hv1 * hv1, f5 = hv2 * hv2 * hv1;
    const double fr = madd(1.0 - in->f0, f5, in->f0, fma_), omf = 1.0 - f5;
    size_t q;
    u[0] = w * INV_PI;
    if (mf == BF_MF_GGX) {
        const double t = (1.0 - nh) * (1.0 + nh), c2 = nh * nh;
        const double w4 = 1.0 / (4.0 * nl_ * nv);
        const double tl = (1.0 - nl_) * (1.0 + nl_) / (nl_ * nl_);
        const double tv = (1.0 - nv) * (1.0 + nv) / (nv * nv);
        for (q = 0; q < nl; q++) {
            const double a2 = in->r2[q], iq = 1.0 / madd(a2, c2, t, fma_);
            const double d = a2 * iq * iq / BF_PI;
            const double sl = sqrt(madd(a2, tl, 1.0, fma_)), sv = sqrt(madd(a2, tv, 1.0, fma_));
            const double r = 1.0 / ((sl + sv) * sl * sv);
            const double gg = 2.0 * sl * sv * r;
            const double dgs = d * gg * w4;
            b[q] = dgs * fr;
            u[1 + q] = w * b[q];
            if (derivs) {
                const double dd = d * (in->two_r[q] - in->four_r[q] * c2 * iq);
                const double dg = in->m2_r[q] * madd(tl, sv, tv * sl, fma_) * sl * sv * r * r;
                u[1 + nl + q] = w * (madd(dd, gg, d * dg, fma_) * w4 * fr);
                u[1 + 2 * nl + q] = w * (dgs * omf);
            }
        }
    } else if (is_asf(mf)) {
        const double x = in->x[j];
        const double p = lane_exp_t(in->ns[0] * x, madd(x, in->nsl[0], EXP_SHIFTER, fma_), fma_) *
                         (double)in->g[j];
        const double ol = 1.0 - 0.5 * nl_, ol2 = ol * ol, ov = 1.0 - 0.5 * nv, ov2 = ov * ov;
        const double fd = ASF_KD * (1.0 - ol2 * ol2 * ol) * (1.0 - ov2 * ov2 * ov);
        const double lobe = in->k[0] * p;
        (void)nh;
        *bd = (1.0 - in->f0) * fd;
        b[0] = lobe * fr;
        u[0] = w * *bd;
        u[1] = w * b[0];
        if (derivs) {
            u[2] = w * ((madd(in->k[0], x, in->dk[0], fma_) * p) * fr);
            u[3] = w * -fd;
            u[4] = w * (lobe * omf);
        }
    } else if (mf == BF_MF_WARD || mf == BF_MF_WARD_DUER) {
        const double inv_n = mf == BF_MF_WARD_DUER ? in->four_r[0] / (nl_ * nv)
                                                   : in->four_r[0] / sqrt(nl_ * nv);
        const double x = (1.0 - nh) * (1.0 + nh) / (nh * nh) * in->r2[0];
        (void)fr;
        (void)omf;
        b[0] = lane_exp(-x, fma_) * inv_n;
        u[1] = w * b[0];
        if (derivs) u[2] = w * (b[0] * in->two_r[0] * (x - 1.0));
    } else {
        const double c2 = nh * nh;
        const double mn = nl_ < nv ? nl_ : nv, gx = 2.0 * nh * mn / in->dot[3][j];
        const double gg = 1.0 < gx ? 1.0 : gx;
        const double t = (1.0 - nh) * (1.0 + nh) / (nh * nh);
        const double wc = gg / (4.0 * BF_PI * c2 * c2 * nl_ * nv);
        for (q = 0; q < nl; q++) {
            const double x = t * in->r2[q];
            const double dgs = lane_exp(-x, fma_) * in->r2[q] * wc;
            b[q] = dgs * fr;
            u[1 + q] = w * b[q];
            if (derivs) {
                u[1 + nl + q] = w * (b[q] * in->two_r[q] * (x - 1.0));
                u[1 + 2 * nl + q] = w * (dgs * omf);
            }
        }
    }
}

/* d_c = w (value_c - measured_c), in the order of the basis route (B_0
 * = bd for the Ashikhmin-Shirley shader form, else 1/pi) */
static inline double lane_residual(const lobe_in *in, size_t j, size_t c, size_t nl, int mf,
                                   double bd, const double *b, double w, int fma_)
{
    double d = is_asf(mf) ? madd(in->cd[c], bd, -(double)in->m[c][j], fma_)
                          : in->cdpi[c] - (double)in->m[c][j];
    size_t q;
    for (q = 0; q < nl; q++) d = madd(in->cs[q][c], b[q], d, fma_);
    return d * w;
}

/* The sums of one group of LANES samples from i, in the blocks' layout,
 * of u = w (1/pi, B_1 ..) (the extended basis for NORMAL), the residuals
 * d_c (NORMAL, COST) and the weighted values w m_c (VARPRO). */
static inline void group(const lobe_in *in, size_t i, size_t nc, size_t nl, int mf, int gk,
                         bf_pass_kind kind, sums_t *s, int fma_)
{
    const size_t ne = n_basis(kind, nl, mf), cs = channel_sums(kind, nl, mf);
    size_t l, c, a, e, t;
    for (l = 0; l < LANES; l++) {
        const double w = (double)in->w[i + l] * in->wf;
        double u[MAX_EXT], b[MAX_LOBES], bd = INV_PI;
        if (mf != BF_MF_NONE)
            lane_mf_basis(in, i + l, nl, mf, kind == BF_PASS_NORMAL, w, u, b, &bd, fma_);
        else
            lane_basis(in, i + l, nl, gk, kind == BF_PASS_NORMAL, w, u, b, fma_);
        t = 0;
        if (kind != BF_PASS_COST)
            for (a = 0; a < ne; a++)
                for (e = a; e < ne; e++) {
                    s->v[t][l] = madd(u[a], u[e], s->v[t][l], fma_);
                    t++;
                }
        for (c = 0; c < nc; c++) {
            const size_t f = t + c * cs;
            if (kind == BF_PASS_VARPRO) {
                const double r = w * (double)in->m[c][i + l];
                for (a = 0; a < ne; a++) s->v[f + a][l] = madd(u[a], r, s->v[f + a][l], fma_);
                s->v[f + ne][l] = madd(r, r, s->v[f + ne][l], fma_);
            } else {
                const double d = lane_residual(in, i + l, c, nl, mf, bd, b, w, fma_);
                s->v[f][l] = madd(d, d, s->v[f][l], fma_);
                if (kind == BF_PASS_NORMAL)
                    for (a = 0; a < ne; a++)
                        s->v[f + 1 + a][l] = madd(u[a], d, s->v[f + 1 + a][l], fma_);
            }
        }
    }
}

/* The sweep over one run with nc and kind constant after inlining. */
static inline void sweep_plain(const lobe_in *in, size_t n, size_t nc, size_t nl, int mf, int gk,
                               bf_pass_kind kind, double *acc, int fma_)
{
    sums_t a;
    const size_t bytes = sums_of(kind, nc, nl, mf) * LANES * sizeof(double);
    size_t i = 0;
    memcpy(&a, acc, bytes);
    for (; i + LANES <= n; i += LANES) group(in, i, nc, nl, mf, gk, kind, &a, fma_);
    if (i < n) {
        tail_buf b;
        lobe_in t;
        pad_tail(in, i, n, nc, nl, mf, gk, &b, &t);
        group(&t, 0, nc, nl, mf, gk, kind, &a, fma_);
    }
    memcpy(acc, &a, bytes);
}

#endif /* BRDFFIT_FIT_PASS_LANES_H */
