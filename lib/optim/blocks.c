/* Covariance and standard errors of a block-structured J^T J, in time
 * linear in the number of blocks.
 *
 * In a fit of many channels the colours of two channels never meet in a
 * residual: J^T J over the analysed set C has an arrow structure. Taking
 * out the few parameters that meet every other one (the hubs: the shared
 * shape) leaves small blocks (one per channel) that touch only themselves
 * and the hubs. With M = S A S scaled to unit diagonal (analysis.c), D the
 * block-diagonal part, B the block-hub coupling and X = D^-1 B, the
 * inverse is
 *
 *     M^-1 = [ D^-1 + X T X^T   -X T ]     T = (M_HH - B^T X)^-1,
 *            [ -T X^T             T  ]
 *
 * computed from Cholesky factors of the blocks and of the hubs' Schur
 * complement. The dense path takes the pseudo-inverse of M, dropping the
 * eigenvalues at or below BF_LINALG_RTOL of the largest; it equals M^-1
 * when it drops none, which holds when 1 / trace(M^-1), a lower bound of
 * the smallest eigenvalue, exceeds BF_LINALG_RTOL times an upper bound of
 * the largest (Gershgorin's) with a margin. Without the structure, or
 * without that proof, the caller takes the dense path. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "core/linalg.h"
#include "optim/optim_internal.h"

#define BF_BLOCKS_MIN 128   /* below this many analysed parameters: dense */
#define BF_BLOCK_MAX 16     /* largest block */
#define BF_HUB_MAX 32       /* most hubs */
#define BF_BLOCK_MARGIN 100 /* on the proof that no eigenvalue is dropped */

#define DEAD SIZE_MAX      /* zero diagonal: not determined */
#define HUB (SIZE_MAX - 1) /* a hub */
#define UNSEEN (SIZE_MAX - 2)

typedef struct blocks {
    const brdffit_optimizer *opt;
    size_t n, n_rest, h; /* |C|; order[0, n_rest) blocks, then h hubs */
    double *X;           /* n_rest x h, by position */
    double *Y;           /* n_rest x h: X T */
    double *Dinv;        /* n_rest x BF_BLOCK_MAX: row t holds D^-1 (t, block) */
    double *T;           /* h x h */
    double *tmp;         /* 2 BF_BLOCK_MAX^2 + 2 BF_HUB_MAX^2 + BF_HUB_MAX */
} blocks;

/* M(a, b) by position in C. */
static double entry(const blocks *bk, size_t a, size_t b)
{
    const bf_optim_work *w = &bk->opt->w;
    size_t p = bk->opt->n_params;
    return w->jtj[w->free_idx[a] * p + w->free_idx[b]] * w->scale[a] * w->scale[b];
}

static int linked(const blocks *bk, size_t a, size_t b)
{
    const bf_optim_work *w = &bk->opt->w;
    return a != b && w->jtj[w->free_idx[a] * bk->opt->n_params + w->free_idx[b]] != 0.0;
}

/* Hubs: parameters linked to more than a block member can be. */
static int mark_hubs(blocks *bk)
{
    size_t *group = bk->opt->w.group, a, b;
    bk->h = 0;
    for (a = 0; a < bk->n; a++) {
        size_t degree = 0;
        if (group[a] == DEAD) continue;
        for (b = 0; b < bk->n; b++) degree += group[b] != DEAD && linked(bk, a, b);
        if (degree < BF_BLOCK_MAX + BF_HUB_MAX) continue;
        group[a] = HUB;
        if (++bk->h > BF_HUB_MAX) return 0;
    }
    return 1;
}

/* The connected components of the others (breadth first, into order;
 * group holds each one's first position), then the hubs. */
static int find_blocks(blocks *bk)
{
    const bf_optim_work *w = &bk->opt->w;
    size_t a, b, q, t = 0;
    for (a = 0; a < bk->n; a++) w->group[a] = w->scale[a] > 0.0 ? UNSEEN : DEAD;
    if (!mark_hubs(bk)) return 0;
    for (a = 0; a < bk->n; a++) {
        size_t start = t;
        if (w->group[a] != UNSEEN) continue;
        w->order[t++] = a;
        w->group[a] = start;
        for (q = start; q < t; q++)
            for (b = 0; b < bk->n; b++) {
                if (w->group[b] != UNSEEN || !linked(bk, w->order[q], b)) continue;
                if (t - start == BF_BLOCK_MAX) return 0;
                w->order[t++] = b;
                w->group[b] = start;
            }
    }
    bk->n_rest = t;
    for (a = 0; a < bk->n; a++)
        if (w->group[a] == HUB) w->order[t++] = a;
    for (q = 0; q < t; q++) w->pos[w->order[q]] = q;
    return 1;
}

/* Size of the block starting at position bs. */
static size_t block_size(const blocks *bk, size_t bs)
{
    const bf_optim_work *w = &bk->opt->w;
    size_t k = 1;
    while (bs + k < bk->n_rest && w->group[w->order[bs + k]] == bs) k++;
    return k;
}

/* x = L^-T L^-1 e_j (k values), L from bf_cholesky(). */
static void solve_unit(const double *l, size_t k, size_t j, double *x)
{
    memset(x, 0, k * sizeof *x);
    x[j] = 1.0;
    bf_cholesky_solve(l, k, x);
}

/* One block: its inverse into Dinv, X = D^-1 B into X, and B^T X taken
 * from the Schur complement in T. 0 when the block is not positive definite. */
static int factor_block(blocks *bk, size_t bs, size_t k)
{
    const size_t *order = bk->opt->w.order, h = bk->h;
    double *l = bk->tmp, *x = l + BF_BLOCK_MAX * BF_BLOCK_MAX;
    size_t i, j, c;
    for (i = 0; i < k; i++)
        for (j = 0; j < k; j++) l[i * k + j] = entry(bk, order[bs + i], order[bs + j]);
    if (!bf_cholesky(l, k, 0.0)) return 0;
    for (j = 0; j < k; j++) {
        solve_unit(l, k, j, x);
        for (i = 0; i < k; i++) bk->Dinv[(bs + i) * BF_BLOCK_MAX + j] = x[i];
    }
    for (c = 0; c < h; c++) {
        for (i = 0; i < k; i++) x[i] = entry(bk, order[bs + i], order[bk->n_rest + c]);
        bf_cholesky_solve(l, k, x);
        for (i = 0; i < k; i++) bk->X[(bs + i) * h + c] = x[i];
    }
    for (i = 0; i < k; i++)
        for (c = 0; c < h; c++) {
            double bic = entry(bk, order[bs + i], order[bk->n_rest + c]);
            for (j = 0; j < h; j++) bk->T[c * h + j] -= bic * bk->X[(bs + i) * h + j];
        }
    return 1;
}

/* T = (M_HH - sum B^T X)^-1 and Y = X T; 0 when not positive definite. */
static int factor_all(blocks *bk)
{
    const size_t *order = bk->opt->w.order, h = bk->h;
    double *l = bk->tmp + 2 * BF_BLOCK_MAX * BF_BLOCK_MAX, *x = l + h * h;
    size_t bs, k, i, j, c;
    for (i = 0; i < h; i++)
        for (j = 0; j < h; j++)
            bk->T[i * h + j] = entry(bk, order[bk->n_rest + i], order[bk->n_rest + j]);
    for (bs = 0; bs < bk->n_rest; bs += k) {
        k = block_size(bk, bs);
        if (!factor_block(bk, bs, k)) return 0;
    }
    memcpy(l, bk->T, h * h * sizeof *l);
    if (!bf_cholesky(l, h, 0.0)) return 0;
    for (j = 0; j < h; j++) {
        solve_unit(l, h, j, x);
        for (i = 0; i < h; i++) bk->T[i * h + j] = x[i];
    }
    for (i = 0; i < bk->n_rest; i++)
        for (c = 0; c < h; c++) {
            double s = 0.0;
            for (j = 0; j < h; j++) s += bk->X[i * h + j] * bk->T[j * h + c];
            bk->Y[i * h + c] = s;
        }
    return 1;
}

/* (M^-1)(t, u) by positions in order. */
static double inverse(const blocks *bk, size_t t, size_t u)
{
    const bf_optim_work *w = &bk->opt->w;
    size_t h = bk->h, r = bk->n_rest, bs;
    if (t >= r && u >= r) return bk->T[(t - r) * h + (u - r)];
    if (u >= r) return -bk->Y[t * h + (u - r)];
    if (t >= r) return -bk->Y[u * h + (t - r)];
    bs = w->group[w->order[t]];
    return (bs == w->group[w->order[u]] ? bk->Dinv[t * BF_BLOCK_MAX + (u - bs)] : 0.0) +
           bf_dot(bk->Y + t * h, bk->X + u * h, h);
}

/* Gershgorin's bound on the largest eigenvalue of M over the live set. */
static double largest_bound(const blocks *bk)
{
    const bf_optim_work *w = &bk->opt->w;
    size_t t, u, live = bk->n_rest + bk->h;
    double top = 0.0;
    for (t = 0; t < live; t++) {
        size_t a = w->order[t], bs = w->group[a], k = bs == HUB ? 0 : block_size(bk, bs);
        double sum = 0.0;
        if (bs == HUB)
            for (u = 0; u < bk->n; u++) sum += w->group[u] != DEAD ? fabs(entry(bk, a, u)) : 0.0;
        else {
            for (u = 0; u < k; u++) sum += fabs(entry(bk, a, w->order[bs + u]));
            for (u = bk->n_rest; u < live; u++) sum += fabs(entry(bk, a, w->order[u]));
        }
        top = fmax(top, sum);
    }
    return fmin(top, (double)live);
}

/* Whether the dense pseudo-inverse would drop no eigenvalue of the live set. */
static int proven(const blocks *bk)
{
    size_t t, live = bk->n_rest + bk->h;
    double trace = 0.0;
    for (t = 0; t < live; t++) {
        double d = inverse(bk, t, t);
        if (!(d > 0.0) || !isfinite(d)) return 0;
        trace += d;
    }
    return trace * largest_bound(bk) * BF_LINALG_RTOL * BF_BLOCK_MARGIN < 1.0;
}

/* Set up and factor; held (by position in C) marks the parameters the
 * data do not determine, as the dense path does. */
static int prepare(blocks *bk, const brdffit_optimizer *opt)
{
    const bf_optim_work *w = &opt->w;
    size_t a, p = opt->n_params;
    if (opt->res.sandwich) return 0;
    bk->opt = opt;
    bk->n = 0;
    for (a = 0; a < p; a++)
        if (w->analysed[a]) w->free_idx[bk->n++] = a;
    if (bk->n <= BF_BLOCKS_MIN) return 0;
    for (a = 0; a < bk->n; a++) {
        double ajj = w->jtj[w->free_idx[a] * p + w->free_idx[a]];
        w->scale[a] = ajj > 0.0 ? 1.0 / sqrt(ajj) : 0.0;
    }
    bk->X = w->v;
    bk->Y = w->jtj_new;
    bk->Dinv = w->meat;
    bk->T = w->m;
    bk->tmp = w->m + BF_HUB_MAX * BF_HUB_MAX;
    if (!find_blocks(bk) || !factor_all(bk) || !proven(bk)) return 0;
    for (a = 0; a < bk->n; a++)
        w->held[a] = w->scale[a] == 0.0 || bf_optim_vanished(opt, w->free_idx[a]);
    return 1;
}

int bf_blocks_std_errors(const brdffit_optimizer *opt, double *se)
{
    const bf_optim_work *w = &opt->w;
    blocks bk;
    size_t a;
    double f;
    if (!prepare(&bk, opt)) return 0;
    f = sqrt(bf_optim_classic_factor(opt, bk.n));
    for (a = 0; a < bk.n; a++)
        se[w->free_idx[a]] = w->held[a] ? HUGE_VAL
                                        : f * w->scale[a] *
                                              sqrt(fmax(inverse(&bk, w->pos[a], w->pos[a]), 0.0));
    return 1;
}

int bf_blocks_covariance(const brdffit_optimizer *opt, double *cov)
{
    const bf_optim_work *w = &opt->w;
    size_t a, b, p = opt->n_params;
    blocks bk;
    double f;
    if (!prepare(&bk, opt)) return 0;
    f = bf_optim_classic_factor(opt, bk.n);
    for (a = 0; a < bk.n; a++) {
        double *crow = cov + w->free_idx[a] * p;
        if (w->held[a]) {
            crow[w->free_idx[a]] = HUGE_VAL;
            continue;
        }
        for (b = 0; b < bk.n; b++)
            if (!w->held[b])
                crow[w->free_idx[b]] =
                    f * w->scale[a] * inverse(&bk, w->pos[a], w->pos[b]) * w->scale[b];
    }
    return 1;
}
