/* The run's data summary: see summary.h. One sweep over the chunks of the
 * weight plans (the residual plan and the solid-angle one have the same
 * chunks: they depend on the grid and the cap alone) serves up to GROUP
 * channels; it reads each chunk's weights of both plans once, makes the
 * three sums' weights of each sample from them (shared by the channels),
 * and reads each channel's values in place, once for the largest value
 * and the weighted sums and once for the deviations (a clear coat's
 * compensated values are made once per chunk and channel; without one
 * nothing is divided). The three sums of a channel are added side by
 * side in the lanes of one vector, each in sample order. The mean's
 * error takes each chunk's weighted mean and squared deviation about the
 * chunk's own mean and merges them into the running totals by Chan,
 * Golub and LeVeque's update (The American Statistician 37(3), 1983), so
 * nothing cancels. Values that do not count in a sum (a weight 0, a
 * missing value) add exact zeros: without missing values, a finite
 * value times its weight 0 is one; with missing values, or where a
 * compensated value overflows, masked_moments() puts the value 0 there
 * instead. The fit's threads take contiguous blocks of chunks, merged in
 * block order, as the passes do. */
#include "fit/summary.h"

#include <math.h>
#include <string.h>

#include "core/core.h"
#include "fit/pool.h"
#include "fit/stage.h"

/* Channels served by one sweep. */
#define GROUP 8

/* The mean's three sums (summary.h): E's numerator, e's, the cost. */
enum { E_SUM, PLAIN_SUM, COST_SUM, N_SUMS };

/* The three sums side by side in the lanes of a vector, one AVX2
 * register or two of the baseline's (GNU C vector extensions, as
 * many_scan.c's; without fused multiply-adds, as BF_VECTOR_CLONES
 * promises). Each lane adds in sample order, as a scalar sum would. The
 * fourth lane of a chunk's weights counts its samples of the residual
 * plan; its sums are not used. */
#define LANES 4
typedef double lanes __attribute__((vector_size(LANES * sizeof(double))));

/* Weighted count, mean and squared deviation about the mean. */
typedef struct moments {
    double w, mean, m2;
} moments;

/* Fold a chunk's moments b into the running moments a. */
static void merge(moments *a, const moments *b)
{
    double w = a->w + b->w, delta;
    if (!(b->w > 0.0)) return;
    delta = b->mean - a->mean;
    a->mean += delta * (b->w / w);
    a->m2 += b->m2 + delta * delta * (a->w * b->w / w);
    a->w = w;
}

/* A block of chunks' sweep over the channels c0 .. c0 + nc - 1
 * (nc <= GROUP): the moments of each channel and sum, the largest value,
 * and the counts (of samples with c0 = 0 only). */
typedef struct block {
    const bf_run *run;
    size_t c0, nc, chunk_begin, chunk_end;
    moments out[GROUP * N_SUMS]; /* channel c's sum k at c N_SUMS + k */
    double top;
    size_t on[2], rows[2];
} block;

/* A chunk's weights, which every channel without a missing value shares:
 * a value counts in the solid-angle plan's sums (E's and e's) where that
 * plan's weight is non-zero, in the cost where the residual weight is. */
typedef struct chunk {
    lanes a[BF_CHUNK];      /* the sums' weights of sample s (a zero where it does not count) */
    lanes a_total;          /* each lane's weights added in sample order */
    size_t first, n, on[2]; /* on: samples with a non-zero weight, of each plan */
    double w[2][BF_CHUNK];  /* the plans' weights ([0] the residual plan) */
    double dv[BF_CHUNK];    /* the clear-coat divisors (with a coat only) */
} chunk;

/* The sums' moments m[k] from the lanes' weight totals w, weighted sums
 * s1 and weights a and values r of the n samples (squared deviations
 * about the mean s1 / w, where w > 0). r NULL: every lane's value is
 * y[s]. */
static void lane_moments(const lanes *a, const lanes *w, const lanes *s1, const lanes *r,
                         const double *y, size_t n, moments *m)
{
    lanes mean = {0.0, 0.0, 0.0, 0.0}, m2 = mean;
    size_t s, k;
    for (k = 0; k < N_SUMS; k++)
        if ((*w)[k] > 0.0) mean[k] = (*s1)[k] / (*w)[k];
    for (s = 0; s < n; s++) {
        lanes d = (r != NULL ? r[s] : (lanes){y[s], y[s], y[s], y[s]}) - mean;
        m2 += a[s] * d * d;
    }
    for (k = 0; k < N_SUMS; k++) {
        m[k].w = (*w)[k];
        m[k].mean = mean[k];
        m[k].m2 = (*w)[k] > 0.0 ? m2[k] : 0.0;
    }
}

/* The sums' moments of one channel's values y of the chunk, with the
 * chunk's weights, and the largest of its measured values v and *top
 * into *top. Every value enters every sum, also where its weight is 0: a
 * finite value then adds a zero (x + 0 = x, and a sum starting at +0
 * never becomes -0), the same bits as the value 0 masked_moments() puts
 * there. Returns 0 if a value is not finite (the weighted sums are then
 * not finite either), and m is not to be used. */
static int shared_moments(const chunk *ch, const double *v, const double *y, double *top,
                          moments *m)
{
    lanes s1 = {0.0, 0.0, 0.0, 0.0};
    double t = *top;
    size_t s;
    for (s = 0; s < ch->n; s++) {
        t = v[s] > t ? v[s] : t;
        s1 += ch->a[s] * y[s];
    }
    *top = t;
    if (!(isfinite(s1[E_SUM]) && isfinite(s1[PLAIN_SUM]) && isfinite(s1[COST_SUM]))) return 0;
    lane_moments(ch->a, &ch->a_total, &s1, NULL, y, ch->n, m);
    return 1;
}

/* The same moments from values that count only where pres (NULL: every
 * value present) and the sum's plan weight are non-zero, and are 0
 * elsewhere: with missing values, and where shared_moments() met a value
 * that is not finite (an overflowing clear-coat compensation). */
static void masked_moments(const chunk *ch, const double *y, const double *pres, moments *m)
{
    lanes a[BF_CHUNK], r[BF_CHUNK], zero = {0.0, 0.0, 0.0, 0.0}, w = zero, s1 = zero;
    size_t s;
    for (s = 0; s < ch->n; s++) {
        const int here = pres == NULL || pres[s] != 0.0;
        const double on = here && ch->w[0][s] != 0.0 ? y[s] : 0.0;
        const double on_sa = here && ch->w[1][s] != 0.0 ? y[s] : 0.0;
        a[s] = here ? ch->a[s] : zero;
        r[s] = (lanes){on_sa, on_sa, on, 0.0};
        w += a[s];
        s1 += a[s] * r[s];
    }
    lane_moments(a, &w, &s1, r, y, ch->n, m);
}

/* Chunk ci: the weights of both plans and the geometry once, then the
 * group's channels one by one, their values read in place (divided by
 * the coat's divisors into a copy with a clear coat). */
BF_VECTOR_CLONES static void sweep_chunk(block *b, size_t ci)
{
    const brdffit_fit *fit = b->run->fit;
    const int coat = fit->clearcoat > 0.0, missing = bf_grid_has_missing(fit->grid);
    chunk ch;
    moments m[N_SUMS];
    lanes total;
    double y[BF_CHUNK], meas[BF_CHUNK], pres[BF_CHUNK];
    size_t c, s, k;
    brdffit_batch batch;
    bf_weight_plan_chunk(&b->run->plan, ci, &ch.first, &ch.n, ch.w[0]);
    bf_weight_plan_chunk(&b->run->plan_sa, ci, &ch.first, &ch.n, ch.w[1]);
    bf_grid_batch(fit->grid, ch.first, ch.n, &batch);
    /* the sums' weights of each sample: E's w cos^2, e's 1, the cost's
     * w^2, and 1 in the spare lane where the residual weight counts;
     * weights are >= 0 (> 0 is != 0), and one of 0 makes its products
     * zeros, of either sign, which add as the +0 of a selection would */
    total = (lanes){0.0, 0.0, 0.0, 0.0};
    for (s = 0; s < ch.n; s++) {
        const double cz = batch.lz[s] > 0.0 ? batch.lz[s] : 0.0, w0 = ch.w[0][s], w1 = ch.w[1][s];
        const lanes as = {w1 * cz * cz, w1 > 0.0 ? 1.0 : 0.0, w0 * w0, w0 > 0.0 ? 1.0 : 0.0};
        ch.a[s] = as;
        total += as;
    }
    ch.a_total = total;
    /* whole numbers up to BF_CHUNK: exact */
    ch.on[0] = (size_t)total[N_SUMS];
    ch.on[1] = (size_t)total[PLAIN_SUM];
    /* a compensated value is the measured one divided by it */
    if (coat)
        for (s = 0; s < ch.n; s++) ch.dv[s] = bf_grid_coat_divisor(fit->clearcoat, batch.lz[s]);
    if (b->c0 == 0) {
        b->on[0] += ch.on[0];
        b->on[1] += ch.on[1];
    }
    for (c = 0; c < b->nc; c++) {
        const double *v = bf_grid_values(fit->grid, b->c0 + c) + ch.first, *yc = v;
        if (coat) {
            for (s = 0; s < ch.n; s++) y[s] = v[s] / ch.dv[s];
            yc = y;
        }
        if (missing) {
            for (s = 0; s < ch.n; s++) b->top = v[s] > b->top ? v[s] : b->top;
            bf_grid_load_channel(fit->grid, b->c0 + c, ch.first, ch.n, meas, pres);
            for (s = 0; s < ch.n; s++) {
                b->rows[0] += pres[s] != 0.0 && ch.w[0][s] != 0.0;
                b->rows[1] += pres[s] != 0.0 && ch.w[1][s] != 0.0;
            }
            masked_moments(&ch, yc, pres, m);
        } else {
            b->rows[0] += ch.on[0];
            b->rows[1] += ch.on[1];
            if (!shared_moments(&ch, v, yc, &b->top, m)) masked_moments(&ch, yc, NULL, m);
        }
        for (k = 0; k < N_SUMS; k++) merge(&b->out[c * N_SUMS + k], &m[k]);
    }
}

static void block_task(void *arg, size_t t)
{
    block *b = (block *)arg + t;
    size_t ci;
    memset(b->out, 0, sizeof b->out);
    b->top = 0.0;
    b->on[0] = b->on[1] = b->rows[0] = b->rows[1] = 0;
    for (ci = b->chunk_begin; ci < b->chunk_end; ci++) sweep_chunk(b, ci);
}

/* The sweep over the whole plan, on the fit's threads, into blocks[0]. */
static void sweep(bf_run *run, size_t c0, size_t nc, block *blocks)
{
    size_t n_chunks = run->plan.n_chunks, t, k, j;
    size_t threads = run->fit->threads < 1 ? 1 : run->fit->threads;
    if (threads > BF_POOL_MAX + 1) threads = BF_POOL_MAX + 1;
    if (threads > n_chunks) threads = n_chunks ? n_chunks : 1;
    for (t = 0; t < threads; t++) {
        blocks[t].run = run;
        blocks[t].c0 = c0;
        blocks[t].nc = nc;
        blocks[t].chunk_begin = n_chunks * t / threads;
        blocks[t].chunk_end = n_chunks * (t + 1) / threads;
    }
    bf_pool_run(&run->pool, block_task, blocks, threads);
    for (t = 1; t < threads; t++) {
        for (j = 0; j < nc * N_SUMS; j++) merge(&blocks[0].out[j], &blocks[t].out[j]);
        blocks[0].top = blocks[t].top > blocks[0].top ? blocks[t].top : blocks[0].top;
        for (k = 0; k < 2; k++) {
            blocks[0].on[k] += blocks[t].on[k];
            blocks[0].rows[k] += blocks[t].rows[k];
        }
    }
}

/* Sum k's squared deviations over the nc channels of a sweep. */
static double total(const moments *m, size_t k, size_t nc)
{
    double t = 0.0;
    size_t c;
    for (c = 0; c < nc; c++)
        if (m[c * N_SUMS + k].w > 0.0) t += m[c * N_SUMS + k].m2;
    return t;
}

void bf_summary_make(bf_run *run)
{
    block b[BF_POOL_MAX + 1];
    bf_summary *sum = &run->summary;
    size_t c0, nc, k;
    memset(sum, 0, sizeof *sum);
    for (c0 = 0; c0 < run->fit->nc; c0 += nc) {
        nc = run->fit->nc - c0 < GROUP ? run->fit->nc - c0 : GROUP;
        sweep(run, c0, nc, b);
        sum->mean_error += total(b[0].out, E_SUM, nc);
        sum->mean_plain += total(b[0].out, PLAIN_SUM, nc);
        sum->mean_cost += total(b[0].out, COST_SUM, nc);
        sum->top = b[0].top > sum->top ? b[0].top : sum->top;
        for (k = 0; k < 2; k++) {
            sum->on[k] += b[0].on[k];
            sum->rows[k] += b[0].rows[k];
        }
    }
}

size_t bf_summary_rows(const bf_run *run, const bf_problem *pb)
{
    size_t k = pb->plan == &run->plan_sa, rows;
    if (pb->plan != &run->plan && pb->plan != &run->plan_sa) k = 2;
    if (k < 2 && pb->source == BF_SOURCE_CHANNELS && pb->nc == run->fit->nc)
        return run->summary.rows[k];
    if (k < 2 && pb->source != BF_SOURCE_CHANNELS && !bf_grid_has_missing(run->fit->grid))
        return pb->nc * run->summary.on[k];
    bf_count_rows(pb, &rows, NULL);
    return rows;
}
