/* The lanes of the fused loop (pass_fused.c): the sums of one chunk in
 * LANES = 8 lanes each, sample i of a chunk in lane i mod 8. Two
 * implementations of the same arithmetic: with the GNU C vector
 * extensions (gcc, clang), whose 8-double vectors the compiler keeps in
 * registers (one zmm each with AVX-512, two ymm with AVX2, four xmm on the
 * baseline), and in plain C for other compilers. Included by pass_fused.c
 * only. Not installed. */
#ifndef BRDFFIT_FIT_PASS_LANES_H
#define BRDFFIT_FIT_PASS_LANES_H

#include <math.h>
#include <stddef.h>
#include <string.h>

#include "core/core.h"
#include "core/fastmath.h"
#include "fit/pass.h"

#define LANES 8
/* lobes of the lobe form or the microfacet form (models/basis.h) the loop
 * runs: 0, 1 or 2 (the microfacet form 1 or 2) */
#define MAX_LOBES 2
/* lanes of sums with NE functions of the extended basis (the lobe form
 * 1 + 2 nl, the microfacet form 1 + 3 nl, Ward's 3, the Ashikhmin-Shirley
 * shader form 5) and L = 1 + nl linear ones:
 * NORMAL 1 + NE (NE + 1) / 2 + nc NE, VARPRO L (L + 1) / 2 + nc (L + 1),
 * COST 1; at most 50 (two microfacet lobes on 3 channels) */
#define MAX_SUMS 64
/* functions of the largest extended basis (two microfacet lobes) */
#define MAX_EXT (1 + 3 * MAX_LOBES)
#define INV_PI (1.0 / BF_PI)
/* the Ashikhmin-Shirley shader form's diffuse constant (kernel_ashikhmin.c) */
#define ASF_KD (28.0 / (23.0 * BF_PI))

typedef double lanes_t[LANES];

/* One chunk's inputs: nl lobes. The lobe form: x and g shared by the
 * lobes (NULL without lobes), ns, k, dk per lobe. The microfacet form
 * (mf = BF_MF_GGX or BF_MF_CT): the dot products dot[0..3] = n.h, n.l,
 * n.v, h.v of the grid's geometry, the roughness r per lobe with its
 * parameter-only factors, and the shared F0. The Ashikhmin-Shirley
 * shader form (BF_MF_AS_FRESNEL): one lobe of the lobe form (x, g, ns, k,
 * dk), the dot products and Rs in f0. */
typedef struct lobe_in {
    const double *w, *x, *g, *m[3], *dot[4];
    double ns[MAX_LOBES], k[MAX_LOBES], dk[MAX_LOBES], cd[3], cs[MAX_LOBES][3];
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

static inline size_t n_ext(size_t nl, int mf)
{
    return is_asf(mf) ? 5 : has_f0(mf) ? 1 + 3 * nl : 1 + 2 * nl;
}

static inline size_t sums_of(bf_pass_kind kind, size_t nc, size_t nl, int mf)
{
    const size_t ne = n_ext(nl, mf), l = 1 + nl;
    return kind == BF_PASS_NORMAL   ? 1 + ne * (ne + 1) / 2 + nc * ne
           : kind == BF_PASS_VARPRO ? l * (l + 1) / 2 + nc * (l + 1)
                                    : 1;
}

/* A chunk's samples beyond the last multiple of LANES, padded to LANES
 * with weight 0 (x = g = m = 0 and the dot products 1, so every padded
 * term is finite and its weighted value an exact 0): *t reads them from b
 * at offset 0. */
typedef struct tail_buf {
    double w[LANES], x[LANES], g[LANES], m[3][LANES], dot[4][LANES];
} tail_buf;

static inline void pad_tail(const lobe_in *in, size_t i, size_t n, size_t nc, size_t nl, int mf,
                            tail_buf *b, lobe_in *t)
{
    size_t l, c, k;
    /* the dot products only for the microfacet form (mf is a constant) */
    memset(b, 0, offsetof(tail_buf, dot));
    if (mf != BF_MF_NONE)
        for (k = 0; k < 4; k++)
            for (l = 0; l < LANES; l++) b->dot[k][l] = 1.0;
    *t = *in;
    for (l = 0; i + l < n; l++) {
        b->w[l] = in->w[i + l];
        if (nl > 0 && (mf == BF_MF_NONE || is_asf(mf))) {
            b->x[l] = in->x[i + l];
            b->g[l] = in->g[i + l];
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

#if defined(__GNUC__) || defined(__clang__)
/* The helpers take and return vectors; they are static and inlined, so
 * no call crosses an ABI boundary (gcc and clang warn about the vector
 * ABI). */
#pragma GCC diagnostic ignored "-Wpsabi"
#define BF_LANES_VECTOR 1
/* 8-wide vectors (one zmm each with AVX-512) and 4-wide ones (one ymm
 * with AVX2, two xmm on the baseline), each running the lanes of a
 * chunk: the 4-wide sweep runs lanes 0-3, then lanes 4-7. */
#define VW 8
#include "fit/pass_lanes_vec.h"
#undef VW
#define VW 4
#include "fit/pass_lanes_vec.h"
#undef VW
#endif

/* The plain C version of the same arithmetic, for compilers without the
 * vector extensions (and as a reference in test_fused.c's sense: every
 * version gives the same bits). */


typedef struct sums_t {
    lanes_t v[MAX_SUMS];
} sums_t;

/* The lane's weighted basis u = w (1/pi, B_1 .. B_nl, dB_1 .. dB_nl) (the
 * derivatives only for NORMAL) and the lobes' values b: the lobe form. */
static inline void lane_basis(const lobe_in *in, size_t j, size_t nl, int derivs, double *u,
                              double *b)
{
    const double w = in->w[j];
    size_t q;
    u[0] = w * INV_PI;
    for (q = 0; q < nl; q++) {
        const double x = in->x[j], p = bf_exp(in->ns[q] * x) * in->g[j];
        b[q] = in->k[q] * p;
        u[1 + q] = w * b[q];
        if (derivs) u[1 + nl + q] = w * ((in->dk[q] + in->k[q] * x) * p);
    }
}

/* The microfacet form: u = w (1/pi, B_q, dB_q/dr_q, dB_q/dF0) in the
 * order of models/basis.h (Ward's: w (1/pi, B_1, dB_1/da); the
 * Ashikhmin-Shirley shader form's: w (B_0, B_1, dB_1/dns, dB_0/dRs,
 * dB_1/dRs), its B_0 into *bd) and b = B_q, with the expressions of
 * kernel_microfacet.c (ggx_geometry(), ggx_lobe(), ct_geometry(),
 * ct_lobe()), kernel_ward.c (ward_basis_common()) and kernel_ashikhmin.c
 * (as_lobe(), asf_basis()) operation for operation. */
static inline void lane_mf_basis(const lobe_in *in, size_t j, size_t nl, int mf, int derivs,
                                 double *u, double *b, double *bd)
{
    const double w = in->w[j], nh = in->dot[0][j], nl_ = in->dot[1][j], nv = in->dot[2][j];
    const double hv1 = 1.0 - in->dot[3][j], hv2 = hv1 * hv1, f5 = hv2 * hv2 * hv1;
    const double fr = in->f0 + (1.0 - in->f0) * f5, omf = 1.0 - f5;
    size_t q;
    u[0] = w * INV_PI;
    if (mf == BF_MF_GGX) {
        const double t = (1.0 - nh) * (1.0 + nh), c2 = nh * nh;
        const double w4 = 1.0 / (4.0 * nl_ * nv);
        const double tl = (1.0 - nl_) * (1.0 + nl_) / (nl_ * nl_);
        const double tv = (1.0 - nv) * (1.0 + nv) / (nv * nv);
        for (q = 0; q < nl; q++) {
            const double a2 = in->r2[q], iq = 1.0 / (t + a2 * c2);
            const double d = a2 * iq * iq / BF_PI;
            const double sl = sqrt(1.0 + a2 * tl), sv = sqrt(1.0 + a2 * tv);
            const double r = 1.0 / ((sl + sv) * sl * sv);
            const double gg = 2.0 * sl * sv * r;
            const double dgs = d * gg * w4;
            b[q] = dgs * fr;
            u[1 + q] = w * b[q];
            if (derivs) {
                const double dd = d * (in->two_r[q] - in->four_r[q] * c2 * iq);
                const double dg = in->m2_r[q] * (tl * sv + tv * sl) * sl * sv * r * r;
                u[1 + nl + q] = w * ((dd * gg + d * dg) * w4 * fr);
                u[1 + 2 * nl + q] = w * (dgs * omf);
            }
        }
    } else if (is_asf(mf)) {
        const double x = in->x[j], p = bf_exp(in->ns[0] * x) * in->g[j];
        const double ol = 1.0 - 0.5 * nl_, ol2 = ol * ol, ov = 1.0 - 0.5 * nv, ov2 = ov * ov;
        const double fd = ASF_KD * (1.0 - ol2 * ol2 * ol) * (1.0 - ov2 * ov2 * ov);
        const double lobe = in->k[0] * p;
        (void)nh;
        *bd = (1.0 - in->f0) * fd;
        b[0] = lobe * fr;
        u[0] = w * *bd;
        u[1] = w * b[0];
        if (derivs) {
            u[2] = w * (((in->dk[0] + in->k[0] * x) * p) * fr);
            u[3] = w * -fd;
            u[4] = w * (lobe * omf);
        }
    } else if (mf == BF_MF_WARD || mf == BF_MF_WARD_DUER) {
        const double inv_n = mf == BF_MF_WARD_DUER ? in->four_r[0] / (nl_ * nv)
                                                   : in->four_r[0] / sqrt(nl_ * nv);
        const double x = (1.0 - nh) * (1.0 + nh) / (nh * nh) * in->r2[0];
        (void)fr;
        (void)omf;
        b[0] = bf_exp(-x) * inv_n;
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
            const double dgs = bf_exp(-x) * in->r2[q] * wc;
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
                                   double bd, const double *b)
{
    double d = -in->m[c][j] + (is_asf(mf) ? in->cd[c] * bd : in->cd[c] * INV_PI);
    size_t q;
    for (q = 0; q < nl; q++) d = d + in->cs[q][c] * b[q];
    return d * in->w[j];
}

/* NORMAL: sums [cost, G (upper, row by row), H_c (NE each)]; COST:
 * [cost]; VARPRO: [G (L x L upper), b_c (L each), rr_c] of u = w (1/pi,
 * B_1 ..) and the weighted values w m_c. */
static inline void group(const lobe_in *in, size_t i, size_t nc, size_t nl, int mf,
                         bf_pass_kind kind, sums_t *s)
{
    const size_t ne = kind == BF_PASS_NORMAL ? n_ext(nl, mf) : 1 + nl;
    const size_t ng = ne * (ne + 1) / 2;
    size_t l, c, a, e, t;
    for (l = 0; l < LANES; l++) {
        double u[MAX_EXT], b[MAX_LOBES], bd = INV_PI;
        if (mf != BF_MF_NONE)
            lane_mf_basis(in, i + l, nl, mf, kind == BF_PASS_NORMAL, u, b, &bd);
        else lane_basis(in, i + l, nl, kind == BF_PASS_NORMAL, u, b);
        t = kind == BF_PASS_NORMAL ? 1 : 0;
        if (kind != BF_PASS_COST)
            for (a = 0; a < ne; a++)
                for (e = a; e < ne; e++) s->v[t++][l] += u[a] * u[e];
        for (c = 0; c < nc; c++) {
            if (kind == BF_PASS_VARPRO) {
                const double r = in->w[i + l] * in->m[c][i + l];
                for (a = 0; a < ne; a++) s->v[ng + c * ne + a][l] += u[a] * r;
                s->v[ng + nc * ne + c][l] += r * r;
            } else {
                const double d = lane_residual(in, i + l, c, nl, mf, bd, b);
                s->v[0][l] += d * d;
                if (kind == BF_PASS_NORMAL)
                    for (a = 0; a < ne; a++) s->v[1 + ng + c * ne + a][l] += u[a] * d;
            }
        }
    }
}

/* The sweep over one chunk with nc and kind constant after inlining; the
 * lanes live in locals for the whole chunk. */
static inline void sweep_plain(const lobe_in *in, size_t n, size_t nc, size_t nl, int mf,
                               bf_pass_kind kind, double *acc)
{
    sums_t a;
    const size_t bytes = sums_of(kind, nc, nl, mf) * LANES * sizeof(double);
    size_t i = 0;
    memcpy(&a, acc, bytes);
    for (; i + LANES <= n; i += LANES) group(in, i, nc, nl, mf, kind, &a);
    if (i < n) {
        tail_buf b;
        lobe_in t;
        pad_tail(in, i, n, nc, nl, mf, &b, &t);
        group(&t, 0, nc, nl, mf, kind, &a);
    }
    memcpy(acc, &a, bytes);
}

#endif /* BRDFFIT_FIT_PASS_LANES_H */
