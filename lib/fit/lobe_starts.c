/* Auto's further starts for two interchangeable lobes: see lobe_starts.h. */
#include "fit/lobe_starts.h"

#include <math.h>
#include <string.h>

#include "fit/plausible.h"
#include "fit/profile_gn.h"
#include "models/lobes.h"

/* A line point is kept when its profile cost is below (1 + this) times
 * the best polish's. */
#define LINE_SLACK 0.01
/* The split lobes' shapes: the lobe's times and divided by this. */
#define SPLIT_FACTOR 1.1
/* The best polish is degenerate when a lobe's colour is below this
 * fraction of the other's, or their shapes within MERGED of each other. */
#define FAINT 1e-3
#define MERGED 1.5
/* A coat is degenerate when its weight is below this times its lower
 * bound. */
#define COAT_FAINT 2.0

/* Vector entry of declared parameter k (channel c for a colour). */
static size_t entry(const bf_stage *st, size_t k, size_t c)
{
    return st->vindex[k * st->pb.nc + c];
}

/* The scan dimension over entry e, or sc->nd. */
static size_t scan_dim(const bf_scan *sc, size_t e)
{
    size_t d;
    for (d = 0; d < sc->nd && sc->dims[d].entry != e; d++) continue;
    return d;
}

/* Lobe l's colour summed over the channels at p. */
static double colour_sum(const bf_stage *st, const bf_lobe_desc *lobe, const double *p)
{
    double s = 0.0;
    size_t c;
    for (c = 0; c < st->pb.nc; c++) s += p[entry(st, lobe->colour, c)];
    return s;
}

/* The profile at `at` with entry e at natural x: its colours into st->p,
 * its cost into *cost. */
static brdffit_status profile_with(bf_stage *st, const double *at, size_t e, double x, double *cost)
{
    memcpy(st->p, at, st->n * sizeof *st->p);
    st->p[e] = x;
    BF_RETURN_IF_ERROR(bf_plausible_bounds(st, 1));
    return bf_profile_point(st, at, 1, cost);
}

/* Lobe l's line (lobe_starts.h): its lowest kept point into start and its
 * cost into *lowest when below *lowest. */
static brdffit_status line(bf_stage *st, const bf_scan *sc, const bf_lobes *lobes, size_t l,
                           const double *at, double *lowest, double *start)
{
    const bf_scan_dim *dim = &sc->dims[scan_dim(sc, entry(st, lobes->lobe[l].shape, 0))];
    double step = bf_scan_coord(dim, 1) - bf_scan_coord(dim, 0), here, cost;
    size_t e = dim->entry, i;
    here = dim->log ? log(at[e]) : at[e];
    for (i = 0; i + 1 < 2 * dim->count && !st->run->cancelled; i++) {
        double u = 0.5 * (bf_scan_coord(dim, i / 2) + bf_scan_coord(dim, (i + 1) / 2));
        if (fabs(u - here) < step) continue;
        BF_RETURN_IF_ERROR(profile_with(st, at, e, bf_stage_natural(st, e, u), &cost));
        if (cost < *lowest && colour_sum(st, &lobes->lobe[0], st->p) > 0.0 &&
            colour_sum(st, &lobes->lobe[1], st->p) > 0.0) {
            *lowest = cost;
            memcpy(start, st->p, st->n * sizeof *start);
        }
    }
    return BRDFFIT_OK;
}

/* The split (lobe_starts.h) into start. */
static brdffit_status split(bf_stage *st, const bf_lobes *lobes, const double *at, double *start)
{
    size_t big = colour_sum(st, &lobes->lobe[0], at) >= colour_sum(st, &lobes->lobe[1], at) ? 0 : 1;
    size_t a = entry(st, lobes->lobe[big].shape, 0), b = entry(st, lobes->lobe[1 - big].shape, 0);
    double s = at[a], cost;
    memcpy(start, at, st->n * sizeof *start);
    start[a] = fmin(fmax(s * SPLIT_FACTOR, st->lower[a]), st->upper[a]);
    BF_RETURN_IF_ERROR(profile_with(
        st, start, b, fmin(fmax(s / SPLIT_FACTOR, st->lower[b]), st->upper[b]), &cost));
    memcpy(start, st->p, st->n * sizeof *start);
    return BRDFFIT_OK;
}

/* Whether `at` is degenerate (lobe_starts.h). */
static int degenerate(const bf_stage *st, const bf_lobes *lobes, const double *at)
{
    double c0 = colour_sum(st, &lobes->lobe[0], at), c1 = colour_sum(st, &lobes->lobe[1], at);
    double s0 = at[entry(st, lobes->lobe[0].shape, 0)], s1 = at[entry(st, lobes->lobe[1].shape, 0)];
    if (!(c0 > FAINT * c1) || !(c1 > FAINT * c0)) return 1;
    return s0 > 0.0 && s1 > 0.0 && fmax(s0, s1) < MERGED * fmin(s0, s1);
}

size_t bf_coat_faint(const bf_stage *st, const double *at)
{
    const bf_coat *coat = bf_model_coat(st->pb.model);
    size_t w, s, b;
    if (coat == NULL) return st->n;
    w = entry(st, coat->weight, 0);
    s = entry(st, coat->shape, 0);
    b = entry(st, coat->base_shape, 0);
    if (st->fixed[w] || st->fixed[s] || st->fixed[b]) return st->n;
    return at[w] <= COAT_FAINT * st->lower[w] ? s : st->n;
}

/* The coat's start (lobe_starts.h) into start, *n counting it. */
static brdffit_status coat_start(bf_stage *st, const bf_coat *coat, const double *at, double *start,
                                 size_t *n)
{
    size_t w = entry(st, coat->weight, 0), s = entry(st, coat->shape, 0);
    size_t b = entry(st, coat->base_shape, 0);
    double cost;
    if (bf_coat_faint(st, at) == st->n) return BRDFFIT_OK;
    memcpy(start, at, st->n * sizeof *start);
    start[w] = st->upper[w];
    start[s] = at[b];
    BF_RETURN_IF_ERROR(profile_with(st, start, b, st->upper[b], &cost));
    memcpy(start, st->p, st->n * sizeof *start);
    (*n)++;
    return BRDFFIT_OK;
}

brdffit_status bf_lobe_starts(bf_stage *st, const bf_scan *sc, const double *at, double cost,
                              double *starts, size_t *n)
{
    const bf_lobes *lobes = bf_model_lobes(st->pb.model);
    const bf_coat *coat = bf_model_coat(st->pb.model);
    double lowest = cost * (1.0 + LINE_SLACK);
    size_t l;
    *n = 0;
    if (coat != NULL) return coat_start(st, coat, at, starts, n);
    if (lobes == NULL || lobes->n != 2 || !lobes->interchangeable) return BRDFFIT_OK;
    for (l = 0; l < 2; l++)
        if (scan_dim(sc, entry(st, lobes->lobe[l].shape, 0)) == sc->nd) return BRDFFIT_OK;
    if (!degenerate(st, lobes, at)) return BRDFFIT_OK;
    for (l = 0; l < 2; l++) BF_RETURN_IF_ERROR(line(st, sc, lobes, l, at, &lowest, starts));
    if (lowest < cost * (1.0 + LINE_SLACK)) (*n)++;
    if (st->run->cancelled) return BRDFFIT_OK;
    BF_RETURN_IF_ERROR(split(st, lobes, at, starts + *n * st->n));
    (*n)++;
    return BRDFFIT_OK;
}
