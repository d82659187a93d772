/* The values derived from a grid, computed here only: channel values with
 * their presence, the channel mean, the clear-coat divisor, the rows of a
 * fit; used by the derived grids of grid.c and by the fit's passes alike.
 * Also what other layers read of a grid, through functions rather than its
 * fields. See grid_internal.h. */
#include <math.h>
#include <string.h>

#include "core/core.h"
#include "grid/grid_internal.h"

int bf_grid_has_missing(const brdffit_grid *g)
{
    return g->missing != NULL;
}

void bf_grid_batch(const brdffit_grid *g, size_t first, size_t count, brdffit_batch *out)
{
    bf_geometry_batch(&g->geo, first, count, out);
}

void bf_grid_load_channel(const brdffit_grid *g, size_t c, size_t first, size_t n, double *meas,
                          double *present)
{
    const double *v = g->values + c * g->n_samples + first;
    size_t s;
    memcpy(meas, v, n * sizeof *meas);
    if (g->missing == NULL) {
        for (s = 0; s < n; s++) present[s] = 1.0;
        return;
    }
    for (s = 0; s < n; s++) present[s] = g->missing[c * g->n_samples + first + s] ? 0.0 : 1.0;
}

size_t bf_grid_sample_mean(const brdffit_grid *g, size_t s, double *mean)
{
    size_t c, n = 0;
    double sum = 0.0;
    for (c = 0; c < g->n_channels; c++) {
        if (g->missing != NULL && g->missing[c * g->n_samples + s]) continue;
        sum += g->values[c * g->n_samples + s];
        n++;
    }
    if (n > 0 && !isfinite(sum)) { /* overflow: average the scaled values */
        double top = 0.0;
        sum = 0.0;
        for (c = 0; c < g->n_channels; c++)
            if (g->missing == NULL || !g->missing[c * g->n_samples + s]) {
                sum += g->values[c * g->n_samples + s] / (double)n;
                top = fmax(top, g->values[c * g->n_samples + s]);
            }
        /* values near DBL_MAX: the rounded quotients may sum past it; the
         * mean never lies above the largest value */
        *mean = fmin(sum, top);
        return n;
    }
    *mean = n > 0 ? sum / (double)n : 0.0;
    return n;
}

void bf_grid_load_mean(const brdffit_grid *g, size_t first, size_t n, double *meas,
                       double *present)
{
    size_t s, c;
    if (g->missing != NULL) {
        for (s = 0; s < n; s++)
            present[s] = bf_grid_sample_mean(g, first + s, &meas[s]) ? 1.0 : 0.0;
        return;
    }
    /* Nothing missing: bf_grid_sample_mean's sums in the same order, one
     * channel row at a time (so the loops vectorise), and the sample's own
     * call where a sum overflows. */
    for (s = 0; s < n; s++) meas[s] = 0.0;
    for (c = 0; c < g->n_channels; c++) {
        const double *v = g->values + c * g->n_samples + first;
        for (s = 0; s < n; s++) meas[s] += v[s];
    }
    for (s = 0; s < n; s++) {
        present[s] = 1.0;
        if (isfinite(meas[s])) meas[s] /= (double)g->n_channels;
        else bf_grid_sample_mean(g, first + s, &meas[s]);
    }
}

double bf_grid_largest_value(const brdffit_grid *g, size_t first, size_t n)
{
    double top = 0.0;
    size_t c, s;
    for (c = 0; c < g->n_channels; c++)
        for (s = first; s < first + n; s++) top = fmax(top, g->values[c * g->n_samples + s]);
    return top;
}

/* Present values of the selected channel (see bf_grid_count_rows) for
 * samples [first, first + n) into present. */
static void load_present(const brdffit_grid *g, size_t channel, size_t first, size_t n,
                         double *meas, double *present)
{
    if (channel == BF_GRID_MEAN) bf_grid_load_mean(g, first, n, meas, present);
    else bf_grid_load_channel(g, channel, first, n, meas, present);
}

/* Rows of the selected channel(s), counting stops once `limit` is passed. */
static size_t count_rows(const bf_weight_plan *plan, size_t channel, size_t limit)
{
    const brdffit_grid *g = plan->grid;
    double w[BF_CHUNK], meas[BF_CHUNK], present[BF_CHUNK];
    size_t ci, first, n, c, s, count = 0;
    size_t c0 = channel == BF_GRID_EVERY_CHANNEL ? 0 : channel;
    size_t c1 = channel == BF_GRID_EVERY_CHANNEL ? g->n_channels : c0 + 1;
    for (ci = 0; ci < plan->n_chunks && count <= limit; ci++) {
        bf_weight_plan_chunk(plan, ci, &first, &n, w);
        for (c = c0; c < c1; c++) {
            load_present(g, channel == BF_GRID_MEAN ? BF_GRID_MEAN : c, first, n, meas, present);
            for (s = 0; s < n; s++) count += present[s] != 0.0 && w[s] != 0.0;
        }
    }
    return count;
}

size_t bf_grid_count_rows(const bf_weight_plan *plan, size_t channel)
{
    return count_rows(plan, channel, (size_t)-1);
}

int bf_grid_has_rows(const bf_weight_plan *plan)
{
    return count_rows(plan, BF_GRID_EVERY_CHANNEL, 0) > 0;
}
