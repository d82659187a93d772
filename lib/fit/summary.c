/* The run's data summary: see summary.h. One sweep over the chunks of the
 * weight plans (the residual plan and the solid-angle one have the same
 * chunks: they depend on the grid and the cap alone) serves up to GROUP
 * channels; it reads each chunk's weights of both plans and each
 * channel's values once for every figure. The mean's error takes each
 * chunk's weighted mean and squared deviation about the chunk's own mean
 * and merges them into the running totals by Chan, Golub and LeVeque's
 * update (The American Statistician 37(3), 1983), so nothing cancels. The
 * fit's threads take contiguous blocks of chunks, merged in block order,
 * as the passes do. */
#include "fit/summary.h"

#include <string.h>

#include "core/core.h"
#include "fit/pool.h"
#include "fit/stage.h"

/* Channels served by one sweep. */
#define GROUP 8

/* The mean's three sums (summary.h): E's numerator, e's, the cost. */
enum { E_SUM, PLAIN_SUM, COST_SUM, N_SUMS };

/* Channels whose sums one loop adds side by side, and the sums. */
#define LANES 4
#define J_LANES (LANES * N_SUMS)

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

/* A chunk's weights and values for LANES channels side by side: a value
 * counts in the solid-angle plan's sums (E's and e's) where that plan's
 * weight is non-zero and the value present, in the cost where the
 * residual weight is; elsewhere it and its weight are 0. */
typedef struct chunk {
    size_t first, n, on[2];      /* on: samples with a non-zero weight, of each plan */
    double w[2][BF_CHUNK];       /* the plans' weights ([0] the residual plan) */
    double aw[N_SUMS][BF_CHUNK]; /* sum k's weight of a present value */
    double dv[BF_CHUNK];         /* the clear-coat divisors (1 without) */
    double a[BF_CHUNK][J_LANES]; /* sum k's weight in lane l at k LANES + l */
    double r[BF_CHUNK][J_LANES]; /* and its value */
} chunk;

/* The sums' moments of the chunk, m[k LANES + l]. Each sum is added up in
 * sample order, as a sum alone would be (the same bits); side by side,
 * their additions overlap and vectorise. */
BF_VECTOR_CLONES static void chunk_moments(const chunk *ch, moments *m)
{
    double w[J_LANES] = {0.0}, s1[J_LANES] = {0.0}, mean[J_LANES] = {0.0}, m2[J_LANES] = {0.0};
    size_t s, j;
    for (s = 0; s < ch->n; s++)
        for (j = 0; j < J_LANES; j++) {
            w[j] += ch->a[s][j];
            s1[j] += ch->a[s][j] * ch->r[s][j];
        }
    for (j = 0; j < J_LANES; j++)
        if (w[j] > 0.0) mean[j] = s1[j] / w[j];
    for (s = 0; s < ch->n; s++)
        for (j = 0; j < J_LANES; j++) {
            double d = ch->r[s][j] - mean[j];
            m2[j] += ch->a[s][j] * d * d;
        }
    for (j = 0; j < J_LANES; j++) {
        m[j].w = w[j];
        m[j].mean = mean[j];
        m[j].m2 = w[j] > 0.0 ? m2[j] : 0.0;
    }
}

/* Fill ch->r (and ch->a with missing values; without, sweep_chunk() fills
 * it once for every lane) for the channels c0 .. c0 + nc - 1
 * (nc <= LANES), counting their rows and largest value into b. Lanes
 * without a channel hold values 0 (their moments are not used). */
BF_VECTOR_CLONES static void fill_lanes(block *b, chunk *ch, size_t c0, size_t nc, int missing)
{
    const brdffit_grid *g = b->run->fit->grid;
    double meas[BF_CHUNK], pres[BF_CHUNK];
    size_t l, s, k, n = ch->n;
    for (l = nc; l < LANES; l++)
        for (s = 0; s < n; s++)
            for (k = 0; k < N_SUMS; k++) {
                ch->r[s][k * LANES + l] = 0.0;
                if (missing) ch->a[s][k * LANES + l] = 0.0;
            }
    for (l = 0; l < nc; l++) {
        const double *v = bf_grid_values(g, c0 + l) + ch->first;
        double top = b->top;
        if (!missing) {
            for (s = 0; s < n; s++) {
                double x = v[s], y = x / ch->dv[s];
                top = x > top ? x : top;
                ch->r[s][E_SUM * LANES + l] = ch->r[s][PLAIN_SUM * LANES + l] =
                    ch->w[1][s] != 0.0 ? y : 0.0;
                ch->r[s][COST_SUM * LANES + l] = ch->w[0][s] != 0.0 ? y : 0.0;
            }
            b->rows[0] += ch->on[0];
            b->rows[1] += ch->on[1];
            b->top = top;
            continue;
        }
        bf_grid_load_channel(g, c0 + l, ch->first, n, meas, pres);
        for (s = 0; s < n; s++) {
            const int here = pres[s] != 0.0;
            const int on = here && ch->w[0][s] != 0.0, on_sa = here && ch->w[1][s] != 0.0;
            double x = v[s], y = x / ch->dv[s];
            top = x > top ? x : top;
            b->rows[0] += (size_t)on;
            b->rows[1] += (size_t)on_sa;
            for (k = 0; k < N_SUMS; k++) ch->a[s][k * LANES + l] = here ? ch->aw[k][s] : 0.0;
            ch->r[s][E_SUM * LANES + l] = ch->r[s][PLAIN_SUM * LANES + l] = on_sa ? y : 0.0;
            ch->r[s][COST_SUM * LANES + l] = on ? y : 0.0;
        }
        b->top = top;
    }
}

/* Chunk ci: the weights of both plans and the geometry once, then the
 * group's channels, LANES at a time. */
BF_VECTOR_CLONES static void sweep_chunk(block *b, size_t ci)
{
    const brdffit_fit *fit = b->run->fit;
    const int coat = fit->clearcoat > 0.0, missing = bf_grid_has_missing(fit->grid);
    chunk ch;
    moments m[J_LANES];
    size_t c, s, k, l;
    brdffit_batch batch;
    bf_weight_plan_chunk(&b->run->plan, ci, &ch.first, &ch.n, ch.w[0]);
    bf_weight_plan_chunk(&b->run->plan_sa, ci, &ch.first, &ch.n, ch.w[1]);
    bf_grid_batch(fit->grid, ch.first, ch.n, &batch);
    ch.on[0] = ch.on[1] = 0;
    for (s = 0; s < ch.n; s++) {
        double cz = batch.lz[s] > 0.0 ? batch.lz[s] : 0.0;
        ch.aw[E_SUM][s] = ch.w[1][s] != 0.0 ? ch.w[1][s] * cz * cz : 0.0;
        ch.aw[PLAIN_SUM][s] = ch.w[1][s] != 0.0 ? 1.0 : 0.0;
        ch.aw[COST_SUM][s] = ch.w[0][s] != 0.0 ? ch.w[0][s] * ch.w[0][s] : 0.0;
        /* a compensated value is the measured one divided by it; x / 1 is x */
        ch.dv[s] = coat ? bf_grid_coat_divisor(fit->clearcoat, batch.lz[s]) : 1.0;
        ch.on[0] += ch.w[0][s] != 0.0;
        ch.on[1] += ch.w[1][s] != 0.0;
    }
    if (b->c0 == 0) {
        b->on[0] += ch.on[0];
        b->on[1] += ch.on[1];
    }
    if (!missing)
        for (s = 0; s < ch.n; s++)
            for (k = 0; k < N_SUMS; k++)
                for (l = 0; l < LANES; l++) ch.a[s][k * LANES + l] = ch.aw[k][s];
    for (c = 0; c < b->nc; c += LANES) {
        size_t nl = b->nc - c < LANES ? b->nc - c : LANES;
        fill_lanes(b, &ch, b->c0 + c, nl, missing);
        chunk_moments(&ch, m);
        for (l = 0; l < nl; l++)
            for (k = 0; k < N_SUMS; k++) merge(&b->out[(c + l) * N_SUMS + k], &m[k * LANES + l]);
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
