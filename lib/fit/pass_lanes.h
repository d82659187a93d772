/* The lanes of the fused loop (pass_fused.c): the sums of one chunk in
 * LANES = 8 lanes each, sample i of a chunk in lane i mod 8. Two
 * implementations of the same arithmetic: with the GNU C vector
 * extensions (gcc, clang), whose 8-double vectors the compiler keeps in
 * registers (one zmm each with AVX-512, two ymm with AVX2, four xmm on the
 * baseline), and in plain C for other compilers. Included by pass_fused.c
 * only. Not installed. */
#ifndef BRDFFIT_FIT_PASS_LANES_H
#define BRDFFIT_FIT_PASS_LANES_H

#include <stddef.h>
#include <string.h>

#include "core/core.h"
#include "core/fastmath.h"
#include "fit/pass.h"

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

static size_t sums_of(bf_pass_kind kind, size_t nc)
{
    return kind == BF_PASS_NORMAL ? 7 + 3 * nc : kind == BF_PASS_VARPRO ? 3 + 3 * nc : 1;
}

/* A chunk's samples beyond the last multiple of LANES, padded to LANES
 * with weight 0 (x = g = m = 0 too, so every padded term is an exact 0):
 * *t reads them from b at offset 0. */
typedef struct tail_buf {
    double w[LANES], x[LANES], g[LANES], m[3][LANES];
} tail_buf;

static inline void pad_tail(const lobe_in *in, size_t i, size_t n, size_t nc, tail_buf *b,
                            lobe_in *t)
{
    size_t l, c;
    memset(b, 0, sizeof *b);
    *t = *in;
    for (l = 0; i + l < n; l++) {
        b->w[l] = in->w[i + l];
        b->x[l] = in->x[i + l];
        b->g[l] = in->g[i + l];
        for (c = 0; c < nc; c++) b->m[c][l] = in->m[c][i + l];
    }
    t->w = b->w;
    t->x = b->x;
    t->g = b->g;
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

/* NORMAL: sums [cost, G00 G01 G02 G11 G12 G22, H_c0 H_c1 H_c2 ...]. */
static inline void normal_group(const lobe_in *in, size_t i, size_t nc, sums_t *s)
{
    size_t l, c;
    for (l = 0; l < LANES; l++) {
        const double w = in->w[i + l], x = in->x[i + l];
        const double p = bf_exp(in->ns * x) * in->g[i + l];
        const double b1 = in->k * p, db1 = (in->dk + in->k * x) * p;
        const double u0 = w * INV_PI, u1 = w * b1, u2 = w * db1;
        s->v[1][l] += u0 * u0;
        s->v[2][l] += u0 * u1;
        s->v[3][l] += u0 * u2;
        s->v[4][l] += u1 * u1;
        s->v[5][l] += u1 * u2;
        s->v[6][l] += u2 * u2;
        for (c = 0; c < nc; c++) {
            const double d = ((-in->m[c][i + l] + in->cd[c] * INV_PI) + in->cs[c] * b1) * w;
            s->v[0][l] += d * d;
            s->v[7 + 3 * c][l] += u0 * d;
            s->v[8 + 3 * c][l] += u1 * d;
            s->v[9 + 3 * c][l] += u2 * d;
        }
    }
}

/* COST: [cost]. */
static inline void cost_group(const lobe_in *in, size_t i, size_t nc, sums_t *s)
{
    size_t l, c;
    for (l = 0; l < LANES; l++) {
        const double w = in->w[i + l];
        const double b1 = in->k * (bf_exp(in->ns * in->x[i + l]) * in->g[i + l]);
        for (c = 0; c < nc; c++) {
            const double d = ((-in->m[c][i + l] + in->cd[c] * INV_PI) + in->cs[c] * b1) * w;
            s->v[0][l] += d * d;
        }
    }
}

/* VARPRO: [G00 G01 G11, b_c0 b_c1 ..., rr_c ...] of u = w (1/pi, k P) and
 * the weighted values w m_c. */
static inline void varpro_group(const lobe_in *in, size_t i, size_t nc, sums_t *s)
{
    size_t l, c;
    for (l = 0; l < LANES; l++) {
        const double w = in->w[i + l];
        const double b1 = in->k * (bf_exp(in->ns * in->x[i + l]) * in->g[i + l]);
        const double u0 = w * INV_PI, u1 = w * b1;
        s->v[0][l] += u0 * u0;
        s->v[1][l] += u0 * u1;
        s->v[2][l] += u1 * u1;
        for (c = 0; c < nc; c++) {
            const double r = w * in->m[c][i + l];
            s->v[3 + 2 * c][l] += u0 * r;
            s->v[4 + 2 * c][l] += u1 * r;
            s->v[3 + 2 * nc + c][l] += r * r;
        }
    }
}

static inline void group(const lobe_in *in, size_t i, size_t nc, bf_pass_kind kind, sums_t *s)
{
    if (kind == BF_PASS_NORMAL) normal_group(in, i, nc, s);
    else if (kind == BF_PASS_COST) cost_group(in, i, nc, s);
    else varpro_group(in, i, nc, s);
}


/* The sweep over one chunk with nc and kind constant after inlining; the
 * lanes live in locals for the whole chunk. */
static inline void sweep_plain(const lobe_in *in, size_t n, size_t nc, bf_pass_kind kind, double *acc)
{
    sums_t a;
    const size_t bytes = sums_of(kind, nc) * LANES * sizeof(double);
    size_t i = 0;
    memcpy(&a, acc, bytes);
    for (; i + LANES <= n; i += LANES) group(in, i, nc, kind, &a);
    if (i < n) {
        tail_buf b;
        lobe_in t;
        pad_tail(in, i, n, nc, &b, &t);
        group(&t, 0, nc, kind, &a);
    }
    memcpy(acc, &a, bytes);
}

#endif /* BRDFFIT_FIT_PASS_LANES_H */
