/* What other layers read of a grid, through functions rather than its
 * fields: channel values with their presence, the channel mean, the
 * clear-coat divisor and the geometry of a run of samples. See
 * grid_internal.h. */
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

void bf_grid_load_mean(const brdffit_grid *g, size_t first, size_t n, double *meas,
                       double *present)
{
    size_t s, c;
    for (s = 0; s < n; s++) {
        double sum = 0.0, count = 0.0;
        for (c = 0; c < g->n_channels; c++) {
            size_t at = c * g->n_samples + first + s;
            if (g->missing != NULL && g->missing[at]) continue;
            sum += g->values[at];
            count += 1.0;
        }
        meas[s] = count > 0.0 ? sum / count : 0.0;
        present[s] = count > 0.0 ? 1.0 : 0.0;
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

double bf_grid_coat_factor(double r0, double cos_i)
{
    double c = cos_i < BF_DOT_FLOOR ? BF_DOT_FLOOR : (cos_i > 1.0 ? 1.0 : cos_i);
    double m = 1.0 - c, m5 = m * m * m * m * m;
    return 1.0 / ((1.0 - r0) * (1.0 - m5));
}

/* Present values of the selected channel (see bf_grid_count_rows) for
 * samples [first, first + n) into present. */
static void load_present(const brdffit_grid *g, size_t channel, size_t first, size_t n,
                         double *meas, double *present)
{
    if (channel == BF_GRID_MEAN) bf_grid_load_mean(g, first, n, meas, present);
    else bf_grid_load_channel(g, channel, first, n, meas, present);
}

size_t bf_grid_count_rows(const bf_weight_plan *plan, size_t channel)
{
    const brdffit_grid *g = plan->grid;
    double w[BF_CHUNK], meas[BF_CHUNK], present[BF_CHUNK];
    size_t ci, first, n, c, s, count = 0;
    size_t c0 = channel == BF_GRID_EVERY_CHANNEL ? 0 : channel;
    size_t c1 = channel == BF_GRID_EVERY_CHANNEL ? g->n_channels : c0 + 1;
    for (ci = 0; ci < plan->n_chunks; ci++) {
        bf_weight_plan_chunk(plan, ci, &first, &n, w);
        for (c = c0; c < c1; c++) {
            load_present(g, channel == BF_GRID_MEAN ? BF_GRID_MEAN : c, first, n, meas, present);
            for (s = 0; s < n; s++) count += present[s] != 0.0 && w[s] != 0.0;
        }
    }
    return count;
}
