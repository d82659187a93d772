/* Auto's further starts for a model of two interchangeable lobes or of a
 * coat over a base lobe (models/lobes.h), from its best polish. On data one lobe fits, the
 * scan's minima polish into a flat valley where one lobe's colour is 0
 * and its shape free, or into two lobes of one width sharing the
 * channels, while the optimum can lie elsewhere: two lobes of nearly one
 * width each taking some channels, or a broad or sharp lobe of small
 * colour beside the main one. A coat's polishes can all end with the
 * coat at its lower weight while the optimum is a full coat over a
 * broader base. Not installed. */
#ifndef BRDFFIT_FIT_LOBE_STARTS_H
#define BRDFFIT_FIT_LOBE_STARTS_H

#include "fit/scan.h"

/* At most this many starts. */
#define BF_LOBE_STARTS 2

/* From `at` (the best polish, st->n natural values, of cost `cost`),
 * the points LM should polish too, into starts (BF_LOBE_STARTS * st->n
 * doubles), their number into *n: 0 for any other model, when either
 * lobe's shape is held, or unless `at` is degenerate: one lobe's colour
 * (summed over the channels) below 1e-3 of the other's, or the two shapes
 * within a factor 1.5 of each other (on data two distinct lobes fit, the
 * scan's minima find them); for a coat, unless bf_coat_faint(). The
 * starts for two lobes:
 * - a line: each lobe's shape in turn over its scan range at twice the
 *   scan's density, the other's held at `at`, every colour solved by the
 *   profile (profile_gn.h); points within one scan step of the lobe's own
 *   shape are left out (the polish's basin), and so are points where
 *   either lobe's colour is 0 in every channel; the lowest point when its
 *   profile cost is within 1 % of `cost`;
 * - a split: the lobe of larger colour (summed over the channels) split
 *   into two of its shape times 1.1 and divided by 1.1, the colours
 *   solved by the profile.
 * For a coat, one: the coat at its upper weight with the base's
 * roughness at `at`, the base at its upper (broadest) roughness, the
 * colours solved by the profile. */
brdffit_status bf_lobe_starts(bf_stage *st, const bf_scan *sc, const double *at, double cost,
                              double *starts, size_t *n);

/* For a model with a coat whose weight and both roughnesses are free, at
 * `at` (st->n natural values) with the coat's weight at most twice its
 * lower bound, where the coat's roughness is all but undetermined: the
 * coat roughness's entry; else st->n. */
size_t bf_coat_faint(const bf_stage *st, const double *at);

#endif
