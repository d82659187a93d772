/* What a fit run needs of the data alone, made once per run in one sweep
 * over the weight plans' chunks: the largest value inside the cap (the
 * scale check), the row counts (the no-data checks and every stage's
 * optimizer), and the error of the best constant value per channel (the
 * baseline of the verdict's "no better than the mean" warning). None of
 * it depends on the parameters. Not installed. */
#ifndef BRDFFIT_FIT_SUMMARY_H
#define BRDFFIT_FIT_SUMMARY_H

#include <stddef.h>

struct bf_run;
struct bf_problem;

typedef struct bf_summary {
    double top; /* largest value of any channel inside the cap (missing ones 0), >= 0 */
    /* [0] of run->plan, [1] of run->plan_sa: */
    size_t on[2];   /* samples with a non-zero weight */
    size_t rows[2]; /* of them, the present values summed over the channels */
    /* the mean's error: the sum over channels c of
     * min over mu of sum_s a_s cos^2(theta_i) (R_cs - mu)^2 over the
     * active, present samples, a_s the solid-angle weight (the numerator
     * of E with the model replaced by the best constant) in mean_error;
     * the same unweighted (e's sum) in mean_plain; weighted by the fit's
     * residual weights (the squares objective's cost) in mean_cost */
    double mean_error, mean_plain, mean_cost;
} bf_summary;

/* Into run->summary, on the run's pool (started, with the helpers of its
 * passes), from run->plan and run->plan_sa. */
void bf_summary_make(struct bf_run *run);

/* The rows of a stage's problem pb (bf_count_rows()), from run->summary
 * where it holds them (every channel, or no value missing), else
 * counted. */
size_t bf_summary_rows(const struct bf_run *run, const struct bf_problem *pb);

#endif
