/* The benchmark harness: command-line options shared by every bench
 * program, timing with warm-up and repeats (median / min / max), the
 * machine description, a counting allocator for the library's allocator
 * hook, a deterministic random generator, and the two outputs (a table for
 * people on stdout, JSON lines for scripts). */
#ifndef BRDFFIT_BENCH_HARNESS_H
#define BRDFFIT_BENCH_HARNESS_H

#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include <brdffit/brdffit.h>

/* Return the status of a call that fails. */
#define BH_TRY(expr)                             \
    do {                                         \
        brdffit_status bh_st_ = (expr);          \
        if (bh_st_ != BRDFFIT_OK) return bh_st_; \
    } while (0)

/* Fill err (status BRDFFIT_E_INVALID_ARGUMENT) with a message of the bench
 * itself and return that status. */
brdffit_status bh_error(brdffit_error *err, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* ---- options ------------------------------------------------------------ */

typedef struct bh_options {
    const char *program;   /* argv[0] without the directory */
    int smoke;             /* --smoke: one tiny iteration, checks only */
    int json_only;         /* --json: JSON lines on stdout instead of the table */
    const char *json_path; /* --json=FILE: JSON lines appended to FILE, table on stdout */
    size_t repeats;        /* --repeats=N: override the program's repeat counts (0 = keep) */
    const char *filter;    /* --filter=TEXT: only measurements whose name contains TEXT */
} bh_options;

/* Parse the common options; prints usage and returns 0 for --help or an
 * unknown option (*exit_code tells which), 1 to go on. */
int bh_parse_args(int argc, char **argv, const char *summary, bh_options *opt, int *exit_code);

/* Repeats to use: the override, else `normal` (1 in smoke mode). */
size_t bh_repeats(const bh_options *opt, size_t normal);

/* Whether a measurement called `name` is selected by --filter. */
int bh_selected(const bh_options *opt, const char *name);

/* ---- timing ----------------------------------------------------------------- */

typedef struct bh_stats {
    size_t samples;                   /* timed runs */
    double median_ns, min_ns, max_ns; /* wall clock, CLOCK_MONOTONIC */
    double median_cpu_ns;             /* CPU time of the process (all threads), median */
} bh_stats;

/* One run of the thing being measured; returns 0 on success. */
typedef int (*bh_run_fn)(void *ctx);

/* CLOCK_MONOTONIC in nanoseconds. */
uint64_t bh_now_ns(void);
/* CPU time of the process (CLOCK_PROCESS_CPUTIME_ID) in nanoseconds. */
uint64_t bh_cpu_ns(void);

/* `warmup` untimed runs, then `repeats` (>= 1) timed ones. Returns the
 * first non-zero result of `fn`, or 0. */
int bh_measure(bh_run_fn fn, void *ctx, size_t warmup, size_t repeats, bh_stats *out);

/* Median / min / max of n timings (sorted in place). */
void bh_stats_from(double *ns, size_t n, bh_stats *out);

/* ---- the machine ------------------------------------------------------------ */

/* "model name" of /proc/cpuinfo, or "unknown". */
void bh_cpu_model(char *buf, size_t size);
/* The compiler that built the bench (and, with bench.sh, the library). */
const char *bh_compiler(void);
/* Online processors. */
long bh_cpu_count(void);
/* The 1-minute load average (/proc/loadavg), or -1. */
double bh_load_average(void);

/* ---- counting allocator ------------------------------------------------------ */

/* Bytes live and peak, allocation calls and bytes ever requested. Safe to
 * share between threads. */
typedef struct bh_counter {
    atomic_size_t live, peak, total, calls;
} bh_counter;

void bh_counter_init(bh_counter *c);
/* Restart the peak at the bytes live now. */
void bh_counter_reset_peak(bh_counter *c);
/* An allocator hook counting into c. */
brdffit_allocator bh_counter_allocator(bh_counter *c);

/* ---- random numbers ---------------------------------------------------------- */

typedef struct bh_rng {
    uint64_t state;
} bh_rng;

void bh_rng_seed(bh_rng *r, uint64_t seed);
/* Uniform in [0, 1). */
double bh_rng_uniform(bh_rng *r);
/* Standard normal (Box-Muller). */
double bh_rng_normal(bh_rng *r);

/* ---- output --------------------------------------------------------------------- */

typedef struct bh_output {
    const bh_options *opt;
    FILE *table; /* NULL with --json */
    FILE *json;  /* NULL without --json */
    int failed;  /* a check failed: the program exits non-zero */
} bh_output;

/* Open the outputs and print the header (program, CPU, compiler, library
 * version) to both. Returns 0 when the JSON file cannot be opened. */
int bh_output_open(bh_output *out, const bh_options *opt, const char *title);
/* Close; returns the program's exit code (1 if a check failed). */
int bh_output_close(bh_output *out);
/* printf to the table (no-op with --json). */
void bh_table(bh_output *out, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
/* Report a failed check on stderr and remember it. */
void bh_fail(bh_output *out, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* One JSON object, built field by field. */
typedef struct bh_record {
    char buf[2048];
    size_t len;
} bh_record;

void bh_rec_begin(bh_record *r, const bh_output *out, const char *name);
void bh_rec_str(bh_record *r, const char *key, const char *value);
/* A number; NaN and infinities become null. */
void bh_rec_num(bh_record *r, const char *key, double value);
void bh_rec_int(bh_record *r, const char *key, size_t value);
void bh_rec_bool(bh_record *r, const char *key, int value);
/* samples, rows, median_ns, min_ns, max_ns, ns_per_row (null for rows 0),
 * median_cpu_ns. */
void bh_rec_stats(bh_record *r, const bh_stats *s, size_t rows);
void bh_rec_end(bh_record *r, bh_output *out);

/* A target line: table "target: <what>: <measured> (<limit>) met|MISSED" and
 * a JSON record {"name":"target", ...}. */
void bh_target(bh_output *out, const char *what, const char *measured, const char *limit, int met);

#endif /* BRDFFIT_BENCH_HARNESS_H */
