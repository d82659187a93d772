/* The generic route of a pass (pass_route.h): any model, through its
 * evaluation callback, with the model's Jacobian per channel. Serves every
 * problem and every kind of pass. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/core.h"
#include "core/fastmath.h"
#include "core/linalg.h"
#include "fit/pass_route.h"
#include "models/models.h"

static int wants_jacobian(bf_pass_kind kind)
{
    return kind == BF_PASS_NORMAL || kind == BF_PASS_VARPRO || kind == BF_PASS_SANDWICH;
}

static int generic_serves(const bf_problem *pb)
{
    (void)pb;
    return 1;
}

/* Room for the Jacobian: n_params * nc * BF_CHUNK doubles. */
static size_t generic_scratch_size(const bf_problem *pb)
{
    return pb->ly.n_params * pb->nc * BF_CHUNK;
}

/* Where a chunk's measured values are: model channel m's at
 * meas + m * stride and its presence at pres + m * stride (pres NULL:
 * every value present). The driver's scratch, or the grid's own values
 * when the route reads them in place (bf_generic_in_place()). */
typedef struct measured {
    const double *meas, *pres;
    size_t stride;
} measured;

/* The measured values the driver loaded into the scratch. */
static measured in_scratch(const bf_scratch *sc, size_t n)
{
    measured in;
    in.meas = sc->meas;
    in.pres = sc->pres;
    in.stride = n;
    return in;
}

int bf_generic_in_place(const bf_problem *pb, bf_pass_kind kind)
{
    return kind == BF_PASS_METRICS && !bf_grid_has_missing(pb->grid) && !(pb->clearcoat > 0.0) &&
           pb->source != BF_SOURCE_MEAN;
}

/* The chunk's measured values for a pass of this kind: in place in the
 * grid when the driver left them unloaded, else the scratch; the presence
 * left out on a grid without missing values (each factor would be 1). */
static measured chunk_measured(const bf_problem *pb, bf_pass_kind kind, const bf_scratch *sc,
                               size_t first, size_t n)
{
    measured in = in_scratch(sc, n);
    if (kind != BF_PASS_METRICS) return in;
    if (bf_generic_in_place(pb, kind)) {
        size_t c = pb->source == BF_SOURCE_ONE_CHANNEL ? pb->source_channel : 0;
        in.meas = bf_grid_values(pb->grid, c) + first;
        in.stride = pb->grid->n_samples;
    }
    if (!bf_grid_has_missing(pb->grid)) in.pres = NULL;
    return in;
}

/* Row weights w * present of channel m into rw (w where every value is
 * present: w * 1 is w). */
static void row_weights(const bf_scratch *sc, const measured *in, size_t m, size_t n,
                        double *restrict rw)
{
    const double *restrict pres;
    size_t s;
    if (in->pres == NULL) {
        memcpy(rw, sc->w, n * sizeof *rw);
        return;
    }
    pres = in->pres + m * in->stride;
    for (s = 0; s < n; s++) rw[s] = sc->w[s] * pres[s];
}

/* Weighted residuals rd = rw * (value - measured) of channel m. */
static void weighted_residuals(const bf_scratch *sc, const measured *in, size_t m, size_t n,
                               double *restrict rd)
{
    const double *restrict meas = in->meas + m * in->stride, *restrict val = sc->vals + m * n;
    const double *restrict rw = sc->ww;
    size_t s;
    for (s = 0; s < n; s++) rd[s] = rw[s] * (val[s] - meas[s]);
}

/* bf_objective_terms() of pass_route.h. */
BF_WIDE_CLONES
void bf_objective_terms(const bf_problem *pb, const double *restrict meas,
                        const double *restrict lz, size_t n, double *restrict tm,
                        double *restrict tc)
{
    const double delta = pb->delta;
    size_t s;
    switch (pb->objective) {
    case BRDFFIT_OBJECTIVE_LOG:
        for (s = 0; s < n; s++) tm[s] = bf_log1p((lz[s] > 0.0 ? lz[s] : 0.0) * meas[s]);
        return;
    case BRDFFIT_OBJECTIVE_CUBE_ROOT:
        for (s = 0; s < n; s++) tm[s] = bf_cbrt((lz[s] > 0.0 ? lz[s] : 0.0) * meas[s]);
        if (tc != NULL)
            for (s = 0; s < n; s++) tc[s] = bf_cbrt(lz[s] > 0.0 ? lz[s] : 0.0);
        return;
    case BRDFFIT_OBJECTIVE_RELATIVE:
        for (s = 0; s < n; s++) tm[s] = 1.0 / (fabs(meas[s]) + delta);
        return;
    case BRDFFIT_OBJECTIVE_SQUARES: break;
    }
}

/* bf_objective_rows() of pass_route.h: one branch-free loop per
 * objective, with the vectorisable cube root and logarithm of
 * core/fastmath.h, so the loops vectorise; what depends on the measured
 * value and the geometry alone comes from the problem's terms. */
BF_WIDE_CLONES
void bf_objective_rows(const bf_problem *pb, size_t m, size_t first, const double *restrict meas,
                       const double *restrict val, const double *restrict lz, size_t n,
                       double *restrict rd, double *restrict rw)
{
    const size_t ns = pb->grid->n_samples;
    const double *restrict tm = pb->terms + m * ns + first;
    size_t s;
    switch (pb->objective) {
    case BRDFFIT_OBJECTIVE_LOG:
        for (s = 0; s < n; s++) {
            double c = lz[s] > 0.0 ? lz[s] : 0.0, on = rw[s] != 0.0 ? 1.0 : 0.0;
            double cv = on * c * val[s];
            rd[s] = rw[s] * (bf_log1p(cv) - tm[s]);
            rw[s] *= c / (1.0 + cv);
        }
        return;
    case BRDFFIT_OBJECTIVE_CUBE_ROOT: {
        /* cbrt(c R) as cbrt(c) cbrt(|R|) with R's sign, and the slope's pole
         * at R = 0 floored at |R| = delta: cbrt is monotonic, so the floor
         * is t = max(cbrt |R|, cbrt delta). With y = |R|^(-1/3) from
         * bf_rcbrt(), cbrt |R| = |R| y^2 and 1 / (3 t^2) = y^2 / 3 above
         * the floor: no division per row. */
        const double root_delta = bf_cbrt(pb->delta);
        const double floor_slope = 1.0 / (3.0 * root_delta * root_delta);
        const double *restrict tc = pb->terms + pb->nc * ns + first;
        for (s = 0; s < n; s++) {
            double on = rw[s] != 0.0 ? 1.0 : 0.0, cc = tc[s];
            double v = on * val[s], a = v < 0.0 ? -v : v, y = bf_rcbrt(a), y2 = y * y;
            double tv = a * y2, slope = tv > root_delta ? y2 * (1.0 / 3.0) : floor_slope;
            rd[s] = rw[s] * ((v < 0.0 ? -cc : cc) * tv - tm[s]);
            rw[s] *= cc * slope;
        }
        return;
    }
    case BRDFFIT_OBJECTIVE_RELATIVE:
        for (s = 0; s < n; s++) {
            rd[s] = rw[s] * (val[s] - meas[s]) * tm[s];
            rw[s] *= tm[s];
        }
        return;
    case BRDFFIT_OBJECTIVE_SQUARES: break;
    }
    for (s = 0; s < n; s++) rd[s] = rw[s] * (val[s] - meas[s]);
}

/* bf_objective_slopes() of pass_route.h: the row factors of
 * bf_objective_rows() with val = meas; cube-root's cbrt |R| as
 * |cbrt(c R)| / cbrt(c) from the terms. */
BF_WIDE_CLONES
void bf_objective_slopes(const bf_problem *pb, size_t m, size_t first, const double *restrict meas,
                         const double *restrict lz, size_t n, double *restrict rw)
{
    const size_t ns = pb->grid->n_samples;
    const double *restrict tm = pb->terms + m * ns + first;
    size_t s;
    switch (pb->objective) {
    case BRDFFIT_OBJECTIVE_LOG:
        for (s = 0; s < n; s++) {
            double c = lz[s] > 0.0 ? lz[s] : 0.0, cv = rw[s] != 0.0 ? c * meas[s] : 0.0;
            rw[s] *= c / (1.0 + cv);
        }
        return;
    case BRDFFIT_OBJECTIVE_CUBE_ROOT: {
        const double root_delta = bf_cbrt(pb->delta);
        const double *restrict tc = pb->terms + pb->nc * ns + first;
        for (s = 0; s < n; s++) {
            double cc = tc[s], tv = cc > 0.0 ? fabs(tm[s]) / cc : 0.0;
            double t = tv > root_delta ? tv : root_delta;
            rw[s] *= cc / (3.0 * t * t);
        }
        return;
    }
    case BRDFFIT_OBJECTIVE_RELATIVE:
        for (s = 0; s < n; s++) rw[s] *= tm[s];
        return;
    case BRDFFIT_OBJECTIVE_SQUARES: break;
    }
}

/* The rows of channel m: weighted residuals into sc->d and row factors
 * into sc->ww, squares exactly as ever, other objectives transformed. */
static void channel_rows(const bf_problem *pb, bf_scratch *sc, const measured *in, size_t m,
                         const double *lz, size_t n)
{
    const size_t first = (size_t)(lz - pb->grid->geo.lz);
    row_weights(sc, in, m, n, sc->ww);
    if (pb->objective == BRDFFIT_OBJECTIVE_SQUARES)
        weighted_residuals(sc, in, m, n, sc->d);
    else
        bf_objective_rows(pb, m, first, in->meas + m * in->stride, sc->vals + m * n, lz, n, sc->d,
                          sc->ww);
}

static void scale_rows(double *restrict x, const double *restrict rw, size_t n)
{
    size_t s;
    for (s = 0; s < n; s++) x[s] *= rw[s];
}

/* J^T J (upper triangle) and J^T r of channel m's weighted rows. */
static void normal_channel(const bf_problem *pb, const double *jac, size_t m, size_t n,
                           const double *d, double *jtr, double *jtj)
{
    size_t nv = pb->ly.n_vec, np = pb->ly.n_params, nc = pb->nc, k, l;
    for (k = 0; k < np; k++) {
        const double *jk = jac + (k * nc + m) * n;
        size_t a = pb->vindex[k * nc + m];
        jtr[a] += bf_dot(jk, d, n);
        for (l = k; l < np; l++) {
            size_t b = pb->vindex[l * nc + m];
            size_t lo = a < b ? a : b, hi = a < b ? b : a;
            jtj[lo * nv + hi] += bf_dot(jk, jac + (l * nc + m) * n, n);
        }
    }
}

/* J^T J, J^T r and the cost of the weighted rows: every Jacobian column is
 * scaled by the row weight in place, then all sums are plain dot products. */
static void accumulate_normal(const bf_problem *pb, bf_scratch *sc, double *jac, const double *lz,
                              size_t n)
{
    const measured in = in_scratch(sc, n);
    size_t np = pb->ly.n_params, nc = pb->nc, m, k;
    for (m = 0; m < nc; m++) {
        channel_rows(pb, sc, &in, m, lz, n);
        sc->acc[0] += bf_dot(sc->d, sc->d, n);
        for (k = 0; k < np; k++) scale_rows(jac + (k * nc + m) * n, sc->ww, n);
        normal_channel(pb, jac, m, n, sc->d, sc->acc + 1, sc->acc + 1 + pb->ly.n_vec);
    }
}

/* The measured values of channel m less the model's colour-free offset
 * B = value - sum_q p_q dvalue/dp_q of a model affine in its colours
 * (layout.h), into rm: the offset moves to the right-hand side as held
 * colours do (varpro.c). */
static void remove_offset(const bf_problem *pb, const bf_scratch *sc, const double *jac,
                          const double *params, size_t m, size_t n, double *restrict rm)
{
    const double *restrict meas = sc->meas + m * n, *restrict val = sc->vals + m * n;
    size_t K = pb->ly.n_linear, nc = pb->nc, q, s;
    for (s = 0; s < n; s++) rm[s] = meas[s] - val[s];
    for (q = 0; q < K; q++) {
        const double p = params[pb->vindex[pb->ly.linear[q] * nc + m]];
        const double *restrict bq = jac + (pb->ly.linear[q] * nc + m) * n;
        for (s = 0; s < n; s++) rm[s] += p * bq[s];
    }
}

/* Gram matrix of the weighted linear columns and their products with the
 * weighted measurement (less the offset of an affine model). */
static void accumulate_varpro(const bf_problem *pb, bf_scratch *sc, double *jac,
                              const double *params, size_t n)
{
    size_t K = pb->ly.n_linear, stride = 1 + K + K * K, nc = pb->nc, m, q, r;
    const size_t *lin = pb->ly.linear;
    for (m = 0; m < nc; m++) {
        double *acc = sc->acc + m * stride, *b = acc + 1, *G = acc + 1 + K;
        const measured in = in_scratch(sc, n);
        double *rm = sc->d;
        row_weights(sc, &in, m, n, sc->ww);
        if (pb->ly.offset)
            remove_offset(pb, sc, jac, params, m, n, rm);
        else
            memcpy(rm, sc->meas + m * n, n * sizeof *rm);
        scale_rows(rm, sc->ww, n);
        acc[0] += bf_dot(rm, rm, n);
        for (q = 0; q < K; q++) scale_rows(jac + (lin[q] * nc + m) * n, sc->ww, n);
        for (q = 0; q < K; q++) {
            const double *bq = jac + (lin[q] * nc + m) * n;
            b[q] += bf_dot(bq, rm, n);
            for (r = q; r < K; r++) G[q * K + r] += bf_dot(bq, jac + (lin[r] * nc + m) * n, n);
        }
    }
}

/* The sandwich's meat (pass.h, SANDWICH): each row's leverage
 * h = J_i B J_i^T from its Jacobian (weighted rows, as NORMAL's) and its
 * residual's HC3 weight (r / (1 - h))^2, the floor of 1 - h as the
 * optimizer's (analysis.c); upper triangle, mirrored by the driver. */
static void accumulate_sandwich(const bf_problem *pb, bf_scratch *sc, double *jac, const double *lz,
                                size_t n)
{
    size_t nv = pb->ly.n_vec, np = pb->ly.n_params, nc = pb->nc, m, k, l, s;
    const double *B = pb->bread;
    const measured in = in_scratch(sc, n);
    double *meat = sc->acc;
    for (m = 0; m < nc; m++) {
        const size_t *at = pb->vindex + m; /* at[k * nc]: entry of declared k */
        const double *col = jac + m * n;   /* col[k * nc * n + s]: J of declared k, row s */
        channel_rows(pb, sc, &in, m, lz, n);
        for (k = 0; k < np; k++) scale_rows(jac + (k * nc + m) * n, sc->ww, n);
        for (s = 0; s < n; s++) {
            double h = 0.0, q, r2;
            if (sc->d[s] == 0.0) continue; /* no weight, no value, or an exact fit */
            for (k = 0; k < np; k++) {
                const double *bk = B + at[k * nc] * nv;
                double t = 0.0;
                for (l = 0; l < np; l++) t += bk[at[l * nc]] * col[l * nc * n + s];
                h += col[k * nc * n + s] * t;
            }
            q = fmax(1.0 - h, 1e-8);
            r2 = sc->d[s] * sc->d[s] / (q * q);
            for (k = 0; k < np; k++) {
                double jk = r2 * col[k * nc * n + s];
                for (l = k; l < np; l++) {
                    size_t a = at[k * nc], b = at[l * nc];
                    size_t lo = a < b ? a : b, hi = a < b ? b : a;
                    meat[lo * nv + hi] += jk * col[l * nc * n + s];
                }
            }
        }
    }
}

static void accumulate_cost(const bf_problem *pb, bf_scratch *sc, const double *lz, size_t n)
{
    const measured in = in_scratch(sc, n);
    size_t m;
    for (m = 0; m < pb->nc; m++) {
        channel_rows(pb, sc, &in, m, lz, n);
        sc->acc[0] += bf_dot(sc->d, sc->d, n);
    }
}

/* One channel's sums of the error figures (pass.h, METRICS) where every
 * value is present: metrics_with_presence()'s without its presence
 * factors (each 1, and x * 1 is x) and with the per-sample factors
 * sac = wsa c^2 and w2 = w^2 formed once for all channels; the products
 * associate as there, so every bit is kept. acc[3] under squares only
 * (the other objectives' cost comes from their rows). */
static void metrics_present(const double *restrict meas, const double *restrict val,
                            const double *restrict wsa, const double *restrict sac,
                            const double *restrict w2, size_t n, int squares, double *acc)
{
    double a0 = acc[0], a1 = acc[1], a2 = acc[2], a3 = acc[3];
    size_t s;
    for (s = 0; s < n; s++) {
        double d = val[s] - meas[s];
        a0 += d * d;
        a1 += sac[s] * d * d;
        a2 += wsa[s];
        if (squares) a3 += w2[s] * d * d;
    }
    acc[0] = a0;
    acc[1] = a1;
    acc[2] = a2;
    acc[3] = a3;
}

/* One channel's sums of the error figures with each row's presence
 * factor pres (1 or 0), c = max(lz, 0). */
static void metrics_with_presence(const double *restrict meas, const double *restrict val,
                                  const double *restrict pres, const double *restrict wsa,
                                  const double *restrict w, const double *restrict lz, size_t n,
                                  int squares, double *acc)
{
    double a0 = acc[0], a1 = acc[1], a2 = acc[2], a3 = acc[3];
    size_t s;
    for (s = 0; s < n; s++) {
        double d = val[s] - meas[s], c = lz[s] > 0.0 ? lz[s] : 0.0;
        a0 += pres[s] * d * d;
        a1 += pres[s] * wsa[s] * c * c * d * d;
        a2 += pres[s] * wsa[s];
        if (squares) a3 += pres[s] * w[s] * w[s] * d * d;
    }
    acc[0] = a0;
    acc[1] = a1;
    acc[2] = a2;
    acc[3] = a3;
}

/* The error figures' sums of the chunk, acc[4 m ..] for channel m; the
 * sums run in sample order within each of them, from the value they had. */
static void accumulate_metrics(const bf_problem *pb, bf_scratch *sc, const measured *in,
                               const double *lz, size_t n)
{
    const int squares = pb->objective == BRDFFIT_OBJECTIVE_SQUARES;
    double sac[BF_CHUNK], w2[BF_CHUNK];
    size_t m, s;
    if (in->pres == NULL)
        for (s = 0; s < n; s++) {
            double c = lz[s] > 0.0 ? lz[s] : 0.0;
            sac[s] = sc->wsa[s] * c * c;
            w2[s] = sc->w[s] * sc->w[s];
        }
    for (m = 0; m < pb->nc; m++) {
        const double *meas = in->meas + m * in->stride, *val = sc->vals + m * n;
        double *acc = sc->acc + 4 * m;
        if (in->pres == NULL)
            metrics_present(meas, val, sc->wsa, sac, w2, n, squares, acc);
        else
            metrics_with_presence(meas, val, in->pres + m * in->stride, sc->wsa, sc->w, lz, n,
                                  squares, acc);
        if (!squares) {
            /* the objective's cost in place of the squares */
            channel_rows(pb, sc, in, m, lz, n);
            acc[3] += bf_dot(sc->d, sc->d, n);
        }
    }
}

/* ---- non-finite numbers, named ------------------------------------------------ */

/* Index of the first non-finite of x[0 .. n), or n. */
static size_t first_nonfinite(const double *x, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        if (!isfinite(x[i])) break;
    return i;
}

/* Where model channel m's values come from, for messages. */
static void channel_name(const bf_problem *pb, size_t m, char *out, size_t size)
{
    if (pb->source == BF_SOURCE_MEAN)
        snprintf(out, size, " of the channel mean");
    else
        snprintf(out, size, ", channel %zu",
                 pb->source == BF_SOURCE_ONE_CHANNEL ? pb->source_channel : m);
}

/* NaN or Inf among the model's values or derivatives of the chunk from
 * sample `first`: BRDFFIT_E_NONFINITE naming the model, the sample, the
 * channel and (for a derivative) the parameter. */
static brdffit_status check_outputs(const bf_problem *pb, size_t first, size_t n,
                                    const double *vals, const double *jac, brdffit_error *err)
{
    const char *model = brdffit_model_name(pb->model);
    size_t nc = pb->nc, per = nc * n, i;
    char where[48];
    /* one branch-free sweep; the first culprit is looked for only when
     * there is one */
    if (bf_all_finite(vals, per) && (jac == NULL || bf_all_finite(jac, per * pb->ly.n_params)))
        return BRDFFIT_OK;
    if ((i = first_nonfinite(vals, per)) < per) {
        channel_name(pb, i / n, where, sizeof where);
        return bf_fail(err, BRDFFIT_E_NONFINITE,
                       "model \"%s\" gave a non-finite value (%g) at sample %zu%s", model, vals[i],
                       first + i % n, where);
    }
    if (jac == NULL || (i = first_nonfinite(jac, per * pb->ly.n_params)) == per * pb->ly.n_params)
        return BRDFFIT_OK;
    channel_name(pb, i % per / n, where, sizeof where);
    return bf_fail(err, BRDFFIT_E_NONFINITE,
                   "model \"%s\" gave a non-finite derivative (%g) with respect to \"%s\" at "
                   "sample %zu%s",
                   model, jac[i], brdffit_model_param(pb->model, i / per)->name, first + i % n,
                   where);
}

/* The sums of a pass overflowed in this chunk although the model's outputs
 * are finite: name the first sample whose weighted residual squared is not
 * finite, or the chunk. */
static brdffit_status overflow(const bf_problem *pb, bf_scratch *sc, const measured *in,
                               const brdffit_batch *batch, size_t first, brdffit_error *err)
{
    size_t m, s, n = batch->n;
    char where[48];
    for (m = 0; m < pb->nc; m++) {
        channel_rows(pb, sc, in, m, batch->lz, n);
        for (s = 0; s < n; s++) {
            if (isfinite(sc->d[s] * sc->d[s])) continue;
            channel_name(pb, m, where, sizeof where);
            return bf_fail(err, BRDFFIT_E_NONFINITE,
                           "the residual of model \"%s\" at sample %zu%s (model %g, measured "
                           "%g) overflows when squared",
                           brdffit_model_name(pb->model), first + s, where, sc->vals[m * n + s],
                           in->meas[m * in->stride + s]);
        }
    }
    return bf_fail(err, BRDFFIT_E_NONFINITE,
                   "the sums of model \"%s\" overflow in the %zu samples from sample %zu",
                   brdffit_model_name(pb->model), n, first);
}

/* Whether the chunk's sums are still finite (the cost sums, one per
 * channel at most: cheap against the pass). */
static int sums_finite(const bf_problem *pb, bf_pass_kind kind, const double *acc)
{
    size_t K = pb->ly.n_linear, m;
    if (kind == BF_PASS_COST || kind == BF_PASS_NORMAL) return isfinite(acc[0]);
    if (kind == BF_PASS_SANDWICH) return 1; /* the driver checks the whole sum */
    for (m = 0; m < pb->nc; m++) {
        const double *a = kind == BF_PASS_METRICS ? acc + 4 * m : acc + m * (1 + K + K * K);
        if (!isfinite(a[0]) || (kind == BF_PASS_METRICS && !isfinite(a[3]))) return 0;
    }
    return 1;
}

static brdffit_status generic_chunk(const bf_problem *pb, bf_pass_kind kind, const double *params,
                                    bf_scratch *sc, const brdffit_batch *batch, brdffit_error *err)
{
    double *jac = wants_jacobian(kind) ? sc->own : NULL;
    size_t n = batch->n, first = (size_t)(batch->lz - pb->grid->geo.lz);
    const measured in = chunk_measured(pb, kind, sc, first, n);
    brdffit_status status = bf_model_eval(pb->model, batch, params, pb->nc, sc->vals, jac, err);
    if (status != BRDFFIT_OK) return status;
    BF_RETURN_IF_ERROR(check_outputs(pb, first, n, sc->vals, jac, err));
    switch (kind) {
    case BF_PASS_COST: accumulate_cost(pb, sc, batch->lz, n); break;
    case BF_PASS_NORMAL: accumulate_normal(pb, sc, jac, batch->lz, n); break;
    case BF_PASS_VARPRO: accumulate_varpro(pb, sc, jac, params, n); break;
    case BF_PASS_METRICS: accumulate_metrics(pb, sc, &in, batch->lz, n); break;
    case BF_PASS_SANDWICH: accumulate_sandwich(pb, sc, jac, batch->lz, n); break;
    case BF_PASS_SHAPE:
    case BF_PASS_COLOUR_COST:
    case BF_PASS_COLOUR_NORMAL:
    case BF_PASS_COLOUR_VARPRO: break; /* the colour route's (pass.c never sends them) */
    }
    return sums_finite(pb, kind, sc->acc) ? BRDFFIT_OK : overflow(pb, sc, &in, batch, first, err);
}

static void generic_finish(const bf_problem *pb, bf_pass_kind kind, const double *params,
                           const double *part, double *acc)
{
    (void)params;
    memcpy(acc, part, bf_pass_acc_size(pb, kind) * sizeof *acc);
}

const bf_route bf_route_generic = {(1u << BF_PASS_COST) | (1u << BF_PASS_NORMAL) |
                                       (1u << BF_PASS_VARPRO) | (1u << BF_PASS_METRICS) |
                                       (1u << BF_PASS_SANDWICH),
                                   generic_serves,
                                   bf_pass_acc_size,
                                   generic_scratch_size,
                                   generic_chunk,
                                   generic_finish,
                                   NULL};
