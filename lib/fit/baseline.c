/* The mean's error: see baseline.h. One pass over the chunks of the
 * solid-angle plan with the sums S0 = sum a c^2, S1 = sum a c^2 R and
 * S2 = sum a c^2 R^2 per channel; the best constant leaves
 * S2 - S1^2 / S0, taken about the mean so that nothing cancels. */
#include "fit/baseline.h"

#include <math.h>

#include "core/core.h"

/* Weighted mean of channel c (pass 1) or weighted squared deviation from
 * `mu` (pass 2), over chunk ci. */
static void chunk_sums(const bf_run *run, size_t ci, size_t c, int plain, double mu, double *s0,
                       double *s1)
{
    const brdffit_fit *fit = run->fit;
    double w[BF_CHUNK], meas[BF_CHUNK], pres[BF_CHUNK];
    size_t first, n, s;
    brdffit_batch batch;
    bf_weight_plan_chunk(plain == 2 ? &run->plan : &run->plan_sa, ci, &first, &n, w);
    bf_grid_batch(fit->grid, first, n, &batch);
    bf_grid_load_channel(fit->grid, c, first, n, meas, pres);
    for (s = 0; s < n; s++) {
        double cz = batch.lz[s] > 0.0 ? batch.lz[s] : 0.0, r = meas[s], a;
        if (w[s] == 0.0 || pres[s] == 0.0) continue;
        if (fit->clearcoat > 0.0) r /= bf_grid_coat_divisor(fit->clearcoat, batch.lz[s]);
        a = plain == 2 ? w[s] * w[s] : (plain ? 1.0 : w[s] * cz * cz);
        *s0 += a;
        *s1 += isnan(mu) ? a * r : a * (r - mu) * (r - mu);
    }
}

/* The sum over channels of the best constant's squared error, weighted
 * as E's numerator (plain 0), unweighted as e's (1) or by the fit's
 * residual weights as the squares cost (2). */
static double mean_error(const bf_run *run, int plain)
{
    size_t c, ci, chunks = plain == 2 ? run->plan.n_chunks : run->plan_sa.n_chunks;
    double total = 0.0;
    for (c = 0; c < run->fit->nc; c++) {
        double s0 = 0.0, s1 = 0.0, dev = 0.0, mu;
        for (ci = 0; ci < chunks; ci++) chunk_sums(run, ci, c, plain, NAN, &s0, &s1);
        if (!(s0 > 0.0)) continue;
        mu = s1 / s0;
        for (s0 = 0.0, ci = 0; ci < chunks; ci++) chunk_sums(run, ci, c, plain, mu, &s0, &dev);
        total += dev;
    }
    return total;
}

void bf_baseline_mean_error(bf_run *run)
{
    run->result->mean_error = mean_error(run, 0);
    run->result->mean_plain = mean_error(run, 1);
    run->result->mean_cost = mean_error(run, 2);
}
