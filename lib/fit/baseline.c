/* The mean's error: see baseline.h. One sweep over the chunks of a weight
 * plan serves up to GROUP channels and, for the solid-angle plan, both of
 * its sums (E's and e's). Each chunk's weighted mean and squared deviation
 * are taken about the chunk's own mean and merged into the running totals
 * by Chan, Golub and LeVeque's update (The American Statistician 37(3),
 * 1983), so nothing cancels and the data are read once per group. The
 * fit's threads take contiguous blocks of chunks, merged in block order,
 * as the passes do. */
#include "fit/baseline.h"

#include <string.h>

#include "core/core.h"
#include "fit/pool.h"

/* Channels served by one sweep. */
#define GROUP 8

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

/* The moments of r[0..n) under the weights a[0..n) (0 = left out). */
static moments chunk_moments(const double *a, const double *r, size_t n)
{
    moments m = {0.0, 0.0, 0.0};
    double s1 = 0.0;
    size_t s;
    for (s = 0; s < n; s++) {
        m.w += a[s];
        s1 += a[s] * r[s];
    }
    if (!(m.w > 0.0)) return m;
    m.mean = s1 / m.w;
    for (s = 0; s < n; s++) {
        double d = r[s] - m.mean;
        m.m2 += a[s] * d * d;
    }
    return m;
}

/* A block of chunks' sweep: the plan, the channels c0 .. c0 + nc - 1
 * (nc <= GROUP) and, with squares set, each sample weighted by its plan
 * weight squared (the squares cost) into out[0]; otherwise by
 * a cos^2(theta_i) (E's numerator) into out[0] and by 1 (e's sum) into
 * out[1]. Present, active samples only. */
typedef struct block {
    const bf_run *run;
    const bf_weight_plan *plan;
    int squares;
    size_t c0, nc, chunk_begin, chunk_end;
    moments out[2][GROUP];
} block;

static void sweep_chunk(block *b, size_t ci)
{
    const brdffit_fit *fit = b->run->fit;
    double w[BF_CHUNK], meas[BF_CHUNK], pres[BF_CHUNK], a0[BF_CHUNK], a1[BF_CHUNK];
    size_t c, s, first, n;
    brdffit_batch batch;
    bf_weight_plan_chunk(b->plan, ci, &first, &n, w);
    bf_grid_batch(fit->grid, first, n, &batch);
    for (c = 0; c < b->nc; c++) {
        moments m;
        bf_grid_load_channel(fit->grid, b->c0 + c, first, n, meas, pres);
        for (s = 0; s < n; s++) {
            double cz = batch.lz[s] > 0.0 ? batch.lz[s] : 0.0;
            int on = w[s] != 0.0 && pres[s] != 0.0;
            if (on && fit->clearcoat > 0.0)
                meas[s] /= bf_grid_coat_divisor(fit->clearcoat, batch.lz[s]);
            if (!on) meas[s] = 0.0;
            a0[s] = !on ? 0.0 : b->squares ? w[s] * w[s] : w[s] * cz * cz;
            a1[s] = on ? 1.0 : 0.0;
        }
        m = chunk_moments(a0, meas, n);
        merge(&b->out[0][c], &m);
        if (b->squares) continue;
        m = chunk_moments(a1, meas, n);
        merge(&b->out[1][c], &m);
    }
}

static void block_task(void *arg, size_t t)
{
    block *b = (block *)arg + t;
    size_t ci;
    memset(b->out, 0, sizeof b->out);
    for (ci = b->chunk_begin; ci < b->chunk_end; ci++) sweep_chunk(b, ci);
}

/* The sweep over the whole plan, on the fit's threads, into blocks[0].out. */
static void sweep(bf_run *run, const bf_weight_plan *plan, int squares, size_t c0, size_t nc,
                  block *blocks)
{
    size_t threads = run->fit->threads < 1 ? 1 : run->fit->threads, t, k, c;
    if (threads > BF_POOL_MAX + 1) threads = BF_POOL_MAX + 1;
    if (threads > plan->n_chunks) threads = plan->n_chunks ? plan->n_chunks : 1;
    for (t = 0; t < threads; t++) {
        blocks[t].run = run;
        blocks[t].plan = plan;
        blocks[t].squares = squares;
        blocks[t].c0 = c0;
        blocks[t].nc = nc;
        blocks[t].chunk_begin = plan->n_chunks * t / threads;
        blocks[t].chunk_end = plan->n_chunks * (t + 1) / threads;
    }
    bf_pool_run(&run->pool, block_task, blocks, threads);
    for (t = 1; t < threads; t++)
        for (k = 0; k < 2; k++)
            for (c = 0; c < nc; c++) merge(&blocks[0].out[k][c], &blocks[t].out[k][c]);
}

static double total(const moments *m, size_t nc)
{
    double t = 0.0;
    size_t c;
    for (c = 0; c < nc; c++)
        if (m[c].w > 0.0) t += m[c].m2;
    return t;
}

void bf_baseline_mean_error(bf_run *run)
{
    block b[BF_POOL_MAX + 1];
    bf_result *res = run->result;
    size_t c0, nc;
    res->mean_error = res->mean_plain = res->mean_cost = 0.0;
    for (c0 = 0; c0 < run->fit->nc; c0 += nc) {
        nc = run->fit->nc - c0 < GROUP ? run->fit->nc - c0 : GROUP;
        sweep(run, &run->plan_sa, 0, c0, nc, b);
        res->mean_error += total(b[0].out[0], nc);
        res->mean_plain += total(b[0].out[1], nc);
        sweep(run, &run->plan, 1, c0, nc, b);
        res->mean_cost += total(b[0].out[0], nc);
    }
}
