/* The basis route of a pass (pass_route.h): models in basis form.
 *
 * A built-in model is value_c = sum_m p_{m,c} B_m(theta) (models/basis.h),
 * so every Jacobian entry of channel c's row is one of the functions
 *
 *     E = { B_m } and { dB_m / dtheta_s : B_m depends on theta_s },
 *
 * possibly times a colour p_{m,c}. With one row weight w per sample for
 * every channel (no missing values), J^T J is a small combination of the
 * channel-independent sums G_ab = sum w^2 E_a E_b, and J^T r of
 * H_ca = sum w^2 E_a d_c, d_c = value_c - measured_c. So a pass computes
 * each basis function once per sample, NE (NE + 1) / 2 + nc (NE + 1) dot
 * products per block, and never expands the Jacobian per channel. The cost
 * and J^T r are still sums of directly computed residuals: nothing cancels
 * near an exact fit.
 *
 * Under an objective other than the squares (brdffit_objective) COST and
 * NORMAL transform each channel's rows (bf_objective_rows()): the residual
 * r_c = w T(value_c, measured_c) and the row factor f_c = w dT/dvalue_c,
 * which differs per channel. Channel c's Jacobian row is f_c times the
 * extended basis (times a colour), so the sums become per channel,
 * G_cab = sum f_c^2 E_a E_b and H_ca = sum f_c E_a r_c, nc (NE (NE + 1) / 2
 * + NE + 1) dot products per block; VARPRO stays the squares of values. */
#include <string.h>

#include "core/core.h"
#include "core/linalg.h"
#include "fit/pass_fused.h"
#include "fit/pass_route.h"
#include "models/basis.h"

/* The extended basis of a kernel: E_a for a < L is B_a; the others are the
 * derivatives, in (shape, linear) order. ext[s][m] is the index of
 * dB_m/dtheta_s, or -1 when B_m does not depend on theta_s. */
typedef struct ebasis {
    size_t L, K, NE;
    int ext[BF_KERNEL_MAX_SHAPE][BF_KERNEL_MAX_LINEAR];
} ebasis;

static void ebasis_of(const bf_kernel *k, ebasis *eb)
{
    bf_basis_form f;
    size_t s, m, next;
    bf_kernel_form(k, &f);
    next = f.n_linear;
    eb->L = f.n_linear;
    eb->K = f.n_shape;
    for (s = 0; s < BF_KERNEL_MAX_SHAPE; s++)
        for (m = 0; m < BF_KERNEL_MAX_LINEAR; m++)
            eb->ext[s][m] = (s < eb->K && m < eb->L && (f.dep[s] & (1u << m))) ? (int)next++ : -1;
    eb->NE = next;
}

/* A model in basis form and no missing values: then every channel's rows
 * share one set of weights. */
static int basis_serves(const bf_problem *pb)
{
    return pb->kernel != NULL && !bf_grid_has_missing(pb->grid);
}

int bf_basis_in_place(const bf_problem *pb, bf_pass_kind kind)
{
    return bf_fused_in_place(pb, kind);
}

/* Whether COST and NORMAL transform their rows (see the file comment). */
static int transformed(const bf_problem *pb)
{
    return pb->objective != BRDFFIT_OBJECTIVE_SQUARES;
}

/* Gram matrices of NORMAL: one shared by the channels, or one per channel
 * when the rows are transformed. */
static size_t gram_count(const bf_problem *pb)
{
    return transformed(pb) ? pb->nc : 1;
}

static size_t basis_acc_size(const bf_problem *pb, bf_pass_kind kind)
{
    ebasis eb;
    if (bf_fused_serves(pb, kind)) return bf_fused_acc_size(pb, kind);
    ebasis_of(pb->kernel, &eb);
    switch (kind) {
    case BF_PASS_COST: return 1;
    case BF_PASS_NORMAL: return 1 + gram_count(pb) * eb.NE * eb.NE + pb->nc * eb.NE;
    case BF_PASS_VARPRO: return eb.L * eb.L + pb->nc * (eb.L + 1);
    case BF_PASS_METRICS:
    case BF_PASS_SANDWICH: break; /* the generic route's */
    case BF_PASS_SHAPE:
    case BF_PASS_COLOUR_COST:
    case BF_PASS_COLOUR_NORMAL:
    case BF_PASS_COLOUR_VARPRO: break; /* the colour route's */
    }
    return 0;
}

static size_t basis_scratch_size(const bf_problem *pb)
{
    /* the basis block, the weighted functions u_a = w E_a (at most
     * L (1 + K) of them), one residual block, and the values and row
     * factors of transformed rows */
    if (bf_fused_serves(pb, BF_PASS_NORMAL)) return 0; /* the fused loop needs none */
    return sizeof(bf_basis) / sizeof(double) +
           (BF_KERNEL_MAX_LINEAR * (1 + BF_KERNEL_MAX_SHAPE) + 3) * BF_KERNEL_BLOCK;
}

/* Colour p_{m,c} of the parameter vector. */
static double colour(const bf_problem *pb, const double *params, size_t K, size_t m, size_t c)
{
    return params[pb->vindex[(K + m) * pb->nc + c]];
}

/* d~ = w (value - measured) of channel c over a block. */
static void residuals(const bf_problem *pb, const double *params, const ebasis *eb,
                      const bf_basis *bs, const bf_scratch *sc, size_t n, size_t off, size_t count,
                      size_t c, double *restrict dw)
{
    const double *restrict meas = sc->meas + c * n + off, *restrict w = sc->w + off;
    size_t m, i;
    for (i = 0; i < count; i++) dw[i] = -meas[i];
    for (m = 0; m < eb->L; m++) {
        const double p = colour(pb, params, eb->K, m, c);
        const double *restrict b = bs->b[m];
        for (i = 0; i < count; i++) dw[i] += p * b[i];
    }
    for (i = 0; i < count; i++) dw[i] *= w[i];
}

/* Channel c's transformed rows over a block (see the file comment): the
 * residuals into dw, the row factors into f, the model's values into val. */
static void transformed_rows(const bf_problem *pb, const double *params, const ebasis *eb,
                             const bf_basis *bs, const bf_scratch *sc, const double *lz, size_t n,
                             size_t off, size_t count, size_t c, double *restrict val,
                             double *restrict f, double *restrict dw)
{
    size_t m, i;
    for (i = 0; i < count; i++) val[i] = 0.0;
    for (m = 0; m < eb->L; m++) {
        const double p = colour(pb, params, eb->K, m, c);
        const double *restrict b = bs->b[m];
        for (i = 0; i < count; i++) val[i] += p * b[i];
    }
    memcpy(f, sc->w + off, count * sizeof *f);
    bf_objective_rows(pb, c, sc->first + off, sc->meas + c * n + off, val, lz + off, count, dw, f);
}

/* u_a = w E_a for every function of the extended basis. */
static void weighted_basis(const ebasis *eb, const bf_basis *bs, const double *restrict w,
                           size_t count, double *u)
{
    size_t s, m, i;
    for (m = 0; m < eb->L; m++)
        for (i = 0; i < count; i++) u[m * BF_KERNEL_BLOCK + i] = w[i] * bs->b[m][i];
    for (s = 0; s < eb->K; s++)
        for (m = 0; m < eb->L; m++) {
            double *restrict ua;
            if (eb->ext[s][m] < 0) continue;
            ua = u + (size_t)eb->ext[s][m] * BF_KERNEL_BLOCK;
            for (i = 0; i < count; i++) ua[i] = w[i] * bs->db[s][m][i];
        }
}

static void block_normal(const bf_problem *pb, const double *params, const ebasis *eb,
                         const bf_basis *bs, const bf_scratch *sc, size_t n, size_t off,
                         size_t count, double *u, double *dw)
{
    double *acc = sc->acc, *G = acc + 1, *H = acc + 1 + eb->NE * eb->NE;
    size_t a, b, c;
    weighted_basis(eb, bs, sc->w + off, count, u);
    for (a = 0; a < eb->NE; a++)
        for (b = a; b < eb->NE; b++)
            G[a * eb->NE + b] +=
                bf_dot(u + a * BF_KERNEL_BLOCK, u + b * BF_KERNEL_BLOCK, count);
    for (c = 0; c < pb->nc; c++) {
        residuals(pb, params, eb, bs, sc, n, off, count, c, dw);
        acc[0] += bf_dot(dw, dw, count);
        for (a = 0; a < eb->NE; a++)
            H[c * eb->NE + a] += bf_dot(u + a * BF_KERNEL_BLOCK, dw, count);
    }
}

/* NORMAL of transformed rows: per-channel G_c and H_c. */
static void block_normal_transformed(const bf_problem *pb, const double *params,
                                     const ebasis *eb, const bf_basis *bs, const bf_scratch *sc,
                                     const double *lz, size_t n, size_t off, size_t count,
                                     double *u, double *dw)
{
    const size_t NE = eb->NE;
    double *acc = sc->acc, *H = acc + 1 + pb->nc * NE * NE;
    double *val = dw + BF_KERNEL_BLOCK, *f = val + BF_KERNEL_BLOCK;
    size_t a, b, c;
    for (c = 0; c < pb->nc; c++) {
        double *G = acc + 1 + c * NE * NE;
        transformed_rows(pb, params, eb, bs, sc, lz, n, off, count, c, val, f, dw);
        acc[0] += bf_dot(dw, dw, count);
        weighted_basis(eb, bs, f, count, u);
        for (a = 0; a < NE; a++) {
            for (b = a; b < NE; b++)
                G[a * NE + b] += bf_dot(u + a * BF_KERNEL_BLOCK, u + b * BF_KERNEL_BLOCK, count);
            H[c * NE + a] += bf_dot(u + a * BF_KERNEL_BLOCK, dw, count);
        }
    }
}

static void block_cost(const bf_problem *pb, const double *params, const ebasis *eb,
                       const bf_basis *bs, const bf_scratch *sc, const double *lz, size_t n,
                       size_t off, size_t count, double *dw)
{
    double *val = dw + BF_KERNEL_BLOCK, *f = val + BF_KERNEL_BLOCK;
    size_t c;
    for (c = 0; c < pb->nc; c++) {
        if (transformed(pb))
            transformed_rows(pb, params, eb, bs, sc, lz, n, off, count, c, val, f, dw);
        else
            residuals(pb, params, eb, bs, sc, n, off, count, c, dw);
        sc->acc[0] += bf_dot(dw, dw, count);
    }
}

static void block_varpro(const bf_problem *pb, const ebasis *eb, const bf_basis *bs,
                         const bf_scratch *sc, size_t n, size_t off, size_t count, double *u,
                         double *rw)
{
    double *G = sc->acc, *bvec = sc->acc + eb->L * eb->L, *rr = bvec + pb->nc * eb->L;
    const double *restrict w = sc->w + off;
    size_t a, b, c, i;
    weighted_basis(eb, bs, w, count, u);
    for (a = 0; a < eb->L; a++)
        for (b = a; b < eb->L; b++)
            G[a * eb->L + b] +=
                bf_dot(u + a * BF_KERNEL_BLOCK, u + b * BF_KERNEL_BLOCK, count);
    for (c = 0; c < pb->nc; c++) {
        const double *restrict meas = sc->meas + c * n + off;
        for (i = 0; i < count; i++) rw[i] = w[i] * meas[i];
        rr[c] += bf_dot(rw, rw, count);
        for (a = 0; a < eb->L; a++)
            bvec[c * eb->L + a] += bf_dot(u + a * BF_KERNEL_BLOCK, rw, count);
    }
}

BF_VECTOR_CLONES
static brdffit_status basis_chunk(const bf_problem *pb, bf_pass_kind kind, const double *params,
                                  bf_scratch *sc, const brdffit_batch *batch, brdffit_error *err)
{
    const bf_kernel *k = pb->kernel;
    double *work = sc->own;
    bf_basis *bs = (bf_basis *)(void *)work;
    double *u = work + sizeof(bf_basis) / sizeof(double);
    double *dw = u + BF_KERNEL_MAX_LINEAR * (1 + BF_KERNEL_MAX_SHAPE) * BF_KERNEL_BLOCK;
    size_t n = batch->n, off, count;
    ebasis eb;
    (void)err; /* a kernel never fails */
    if (bf_fused_serves(pb, kind)) {
        bf_fused_chunk(pb, kind, params, sc, n);
        return BRDFFIT_OK;
    }
    ebasis_of(k, &eb);
    for (off = 0; off < n; off += count) {
        count = n - off < BF_KERNEL_BLOCK ? n - off : BF_KERNEL_BLOCK;
        bf_kernel_basis(k, batch, off, count, params, bs);
        if (kind == BF_PASS_NORMAL && transformed(pb))
            block_normal_transformed(pb, params, &eb, bs, sc, batch->lz, n, off, count, u, dw);
        else if (kind == BF_PASS_NORMAL)
            block_normal(pb, params, &eb, bs, sc, n, off, count, u, dw);
        else if (kind == BF_PASS_COST)
            block_cost(pb, params, &eb, bs, sc, batch->lz, n, off, count, dw);
        else block_varpro(pb, &eb, bs, sc, n, off, count, u, dw);
    }
    return BRDFFIT_OK;
}

static double sym(const double *G, size_t NE, size_t a, size_t b)
{
    return a <= b ? G[a * NE + b] : G[b * NE + a];
}

/* J^T J and J^T r in the vector layout from G and H (see the file comment;
 * G is channel c's own when the rows are transformed). */
static void finish_normal(const bf_problem *pb, const double *params, const ebasis *eb,
                          const double *bacc, double *acc)
{
    const size_t nv = pb->ly.n_vec, nc = pb->nc, K = eb->K, L = eb->L, NE = eb->NE;
    const size_t ng = gram_count(pb);
    const double *H = bacc + 1 + ng * NE * NE;
    double *jtr = acc + 1, *jtj = acc + 1 + nv;
    size_t s, t, m, q, c;
    memset(acc, 0, (1 + nv + nv * nv) * sizeof *acc);
    acc[0] = bacc[0];
    for (c = 0; c < nc; c++) {
        const double *G = bacc + 1 + (ng > 1 ? c : 0) * NE * NE;
        for (m = 0; m < L; m++) {
            size_t im = pb->vindex[(K + m) * nc + c];
            jtr[im] = H[c * NE + m];
            for (q = 0; q < L; q++) jtj[im * nv + pb->vindex[(K + q) * nc + c]] = sym(G, NE, m, q);
        }
        for (s = 0; s < K; s++) {
            size_t is = pb->vindex[s * nc];
            for (m = 0; m < L; m++) {
                double pm;
                if (eb->ext[s][m] < 0) continue;
                pm = colour(pb, params, K, m, c);
                jtr[is] += pm * H[c * NE + (size_t)eb->ext[s][m]];
                for (q = 0; q < L; q++) {
                    double v = pm * sym(G, NE, (size_t)eb->ext[s][m], q);
                    size_t iq = pb->vindex[(K + q) * nc + c];
                    jtj[is * nv + iq] += v;
                    jtj[iq * nv + is] += v;
                }
                for (t = 0; t < K; t++)
                    for (q = 0; q < L; q++) {
                        if (eb->ext[t][q] < 0) continue;
                        jtj[is * nv + pb->vindex[t * nc]] +=
                            pm * colour(pb, params, K, q, c) *
                            sym(G, NE, (size_t)eb->ext[s][m], (size_t)eb->ext[t][q]);
                    }
            }
        }
    }
}

/* Per-channel [R^T W R, b, G] of pass.h from the shared Gram matrix. */
static void finish_varpro(const bf_problem *pb, const ebasis *eb, const double *bacc, double *acc)
{
    const size_t L = eb->L, stride = 1 + L + L * L;
    const double *G = bacc, *bvec = bacc + L * L, *rr = bvec + pb->nc * L;
    size_t c, a, b;
    for (c = 0; c < pb->nc; c++) {
        double *out = acc + c * stride;
        out[0] = rr[c];
        for (a = 0; a < L; a++) {
            out[1 + a] = bvec[c * L + a];
            for (b = 0; b < L; b++) out[1 + L + a * L + b] = sym(G, L, a, b);
        }
    }
}

static void basis_finish(const bf_problem *pb, bf_pass_kind kind, const double *params,
                         const double *basis_acc, double *acc)
{
    double reduced[BF_FUSED_REDUCED_MAX];
    ebasis eb;
    ebasis_of(pb->kernel, &eb);
    if (bf_fused_serves(pb, kind)) {
        bf_fused_reduce(pb, kind, basis_acc, reduced);
        basis_acc = reduced;
    }
    if (kind == BF_PASS_NORMAL) finish_normal(pb, params, &eb, basis_acc, acc);
    else if (kind == BF_PASS_VARPRO) finish_varpro(pb, &eb, basis_acc, acc);
    else acc[0] = basis_acc[0];
}

/* METRICS is left to the generic route. */
const bf_route bf_route_basis = {(1u << BF_PASS_COST) | (1u << BF_PASS_NORMAL) |
                                     (1u << BF_PASS_VARPRO),
                                 basis_serves,
                                 basis_acc_size,
                                 basis_scratch_size,
                                 basis_chunk,
                                 basis_finish,
                                 bf_fused_block};
