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
