/* bench_scale: large inputs and many fits.
 *
 * 1. A MERL-sized scattered set: a synthetic MERL binary (90 x 90 x 180
 *    cells, the P2 reflectance of datasets.h with 1 % noise at every cell
 *    centre) built in memory and loaded with brdffit_load_merl_buffer(axes
 *    NULL), which keeps one sample per cell with light and view above the
 *    horizon (about 1.11 million, 3 channels), exactly as for a real file.
 *    The grid's memory comes from a counting allocator. Then one auto fit
 *    of "ashikhmin-shirley" on 1 and 2 threads (BRDFFIT_FIT_THREADS).
 * 2. Fits per second: a batch of 100 default grids (P2, one noise seed
 *    each), auto fits of "ashikhmin-shirley", on 1 and 2 pthreads; each
 *    thread fits its own share of the grids, one fit handle at a time with
 *    BRDFFIT_FIT_THREADS = 1.
 * --smoke replaces the MERL set by 20,000 random directions and the batch
 * by 4 grids. */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "datasets.h"
#include "harness.h"

#define SC_PI 3.14159265358979323846
#define MERL_TH 90
#define MERL_TD 90
#define MERL_PD 180
#define MERL_CELLS ((size_t)MERL_TH * MERL_TD * MERL_PD)
#define MERL_HEADER 12
#define BATCH 100
#define BATCH_SMOKE 4
#define SMOKE_SAMPLES 20000
#define MERL_FIT_REPEATS 5
#define BATCH_REPEATS 3
#define MAX_THREADS 2

static const double merl_scale[3] = {1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};

/* ---- a synthetic MERL file ---------------------------------------------------- */

/* Light and view at the centre of cell (ih, id, ip), phi_h = 0
 * (docs/definitions.md, MERL files). */
static void cell_directions(size_t ih, size_t id, size_t ip, double l[3], double v[3])
{
    double u = (ih + 0.5) / MERL_TH, th = u * u * SC_PI / 2.0;
    double td = (id + 0.5) / MERL_TD * SC_PI / 2.0, pd = (ip + 0.5) / MERL_PD * SC_PI;
    double dx = sin(td) * cos(pd), dy = sin(td) * sin(pd), dz = cos(td);
    l[0] = dx * cos(th) + dz * sin(th), l[1] = dy, l[2] = -dx * sin(th) + dz * cos(th);
    v[0] = -dx * cos(th) + dz * sin(th), v[1] = -dy, v[2] = dx * sin(th) + dz * cos(th);
}

static void put_le32(unsigned char *p, uint32_t x)
{
    int k;
    for (k = 0; k < 4; k++) p[k] = (unsigned char)(x >> (8 * k));
}

static void put_le64(unsigned char *p, double d)
{
    uint64_t x;
    int k;
    memcpy(&x, &d, sizeof x);
    for (k = 0; k < 8; k++) p[k] = (unsigned char)(x >> (8 * k));
}

typedef struct cells {
    size_t n;
    uint32_t *index; /* cell of each kept direction pair */
    double *angles;  /* 4 n: theta_i, phi_i, theta_o, phi_o */
} cells;

static double polar(const double d[3])
{
    return atan2(sqrt(d[0] * d[0] + d[1] * d[1]), d[2]);
}

/* Every cell with light and view above the horizon, with its angles. */
static int above_horizon(cells *cs)
{
    size_t cell, n = 0;
    cs->index = malloc(MERL_CELLS * sizeof *cs->index);
    cs->angles = malloc(4 * MERL_CELLS * sizeof *cs->angles);
    if (cs->index == NULL || cs->angles == NULL) return 0;
    for (cell = 0; cell < MERL_CELLS; cell++) {
        double l[3], v[3];
        cell_directions(cell / MERL_PD / MERL_TD, cell / MERL_PD % MERL_TD, cell % MERL_PD, l, v);
        if (!(l[2] > 0.0 && v[2] > 0.0)) continue;
        cs->index[n] = (uint32_t)cell;
        cs->angles[n] = polar(l), cs->angles[MERL_CELLS + n] = atan2(l[1], l[0]);
        cs->angles[2 * MERL_CELLS + n] = polar(v),
                                    cs->angles[3 * MERL_CELLS + n] = atan2(v[1], v[0]);
        n++;
    }
    cs->n = n;
    return 1;
}

/* The file's bytes: header, then red, green and blue blocks of raw values
 * (value / channel scale); cells below the horizon hold 0. */
static unsigned char *merl_bytes(const cells *cs, const double *values, size_t *size)
{
    unsigned char *data;
    size_t t, c;
    *size = MERL_HEADER + 3 * MERL_CELLS * sizeof(double);
    data = calloc(*size, 1);
    if (data == NULL) return NULL;
    put_le32(data, MERL_TH), put_le32(data + 4, MERL_TD), put_le32(data + 8, MERL_PD);
    for (t = 0; t < cs->n; t++)
        for (c = 0; c < 3; c++)
            put_le64(data + MERL_HEADER + (c * MERL_CELLS + cs->index[t]) * sizeof(double),
                     values[t * 3 + c] / merl_scale[c]);
    return data;
}

static unsigned char *synthetic_merl(size_t *size, brdffit_error *err)
{
    cells cs = {0, NULL, NULL};
    double *values = NULL;
    unsigned char *data = NULL;
    if (above_horizon(&cs) && (values = malloc(cs.n * 3 * sizeof *values)) != NULL) {
        const double *a = cs.angles;
        if (bd_generate(BD_P2, BD_SEED, cs.n, a, a + MERL_CELLS, a + 2 * MERL_CELLS,
                        a + 3 * MERL_CELLS, values, err) == BRDFFIT_OK)
            data = merl_bytes(&cs, values, size);
    }
    free(values);
    free(cs.index);
    free(cs.angles);
    return data;
}

/* ---- the smoke set: random directions --------------------------------------------- */

static brdffit_status random_scattered(brdffit_grid **out, size_t n, const brdffit_allocator *a,
                                       brdffit_error *err)
{
    double *ang = malloc(4 * n * sizeof *ang), *values = malloc(3 * n * sizeof *values);
    brdffit_status st = BRDFFIT_E_OUT_OF_MEMORY;
    bh_rng rng;
    size_t s;
    bh_rng_seed(&rng, BD_SEED);
    if (ang != NULL && values != NULL) {
        for (s = 0; s < 4 * n; s++)
            ang[s] = (s / n) % 2 == 0 ? acos(bh_rng_uniform(&rng) * 0.999)
                                      : SC_PI * (2.0 * bh_rng_uniform(&rng) - 1.0);
        st = bd_generate(BD_P2, BD_SEED, n, ang, ang + n, ang + 2 * n, ang + 3 * n, values, err);
    }
    if (st == BRDFFIT_OK)
        st = brdffit_grid_create_scattered(out, n, ang, ang + n, ang + 2 * n, ang + 3 * n, 3,
                                           values, NULL, NULL, a, err);
    free(ang);
    free(values);
    return st;
}

/* ---- the large fit ----------------------------------------------------------------- */

typedef struct big {
    brdffit_grid *grid;
    bh_counter counter;
    double load_ms;
    size_t grid_bytes, load_peak;
} big;

static int load_big(bh_output *out, big *b)
{
    brdffit_allocator a;
    brdffit_error err;
    brdffit_status st;
    uint64_t t0;
    bh_counter_init(&b->counter);
    a = bh_counter_allocator(&b->counter);
    t0 = bh_now_ns();
    if (out->opt->smoke) {
        st = random_scattered(&b->grid, SMOKE_SAMPLES, &a, &err);
    } else {
        size_t size = 0;
        unsigned char *data = synthetic_merl(&size, &err);
        t0 = bh_now_ns();
        st = data ? brdffit_load_merl_buffer(&b->grid, data, size, NULL, &a, &err)
                  : BRDFFIT_E_OUT_OF_MEMORY;
        free(data);
    }
    b->load_ms = (double)(bh_now_ns() - t0) / 1e6;
    b->grid_bytes = atomic_load(&b->counter.live);
    b->load_peak = atomic_load(&b->counter.peak);
    if (st != BRDFFIT_OK) bh_fail(out, "building the large grid: %s", err.message);
    return st == BRDFFIT_OK;
}

typedef struct big_fit {
    bd_fit_job job;
    bd_fit_result res;
} big_fit;

static int run_big_fit(void *ctx)
{
    big_fit *bf = ctx;
    return bd_fit_run(&bf->job, &bf->res) != BRDFFIT_OK;
}

static int fit_big(bh_output *out, const big *b, const brdffit_model *model, size_t threads,
                   bh_stats *st, bd_fit_result *res)
{
    big_fit bf;
    memset(&bf, 0, sizeof bf);
    bf.job.grid = b->grid;
    bf.job.model = model;
    bf.job.pipeline = BRDFFIT_PIPELINE_AUTO;
    bf.job.threads = threads;
    if (bh_measure(run_big_fit, &bf, out->opt->smoke ? 0 : 1,
                   bh_repeats(out->opt, MERL_FIT_REPEATS), st) != 0) {
        bh_fail(out, "large fit on %zu threads: %s", threads, bf.res.message);
        return 0;
    }
    *res = bf.res;
    return 1;
}

static void big_record(bh_output *out, size_t threads, const bh_stats *st, const bd_fit_result *res,
                       size_t rows, double speedup)
{
    bh_record r;
    char name[64];
    bh_table(out, "  %7zu %10.1f %9.1f %9.1f %9.1f %6zu %5zu %13.6e %9.3f %8.2fx\n", threads,
             st->median_ns / 1e6, st->min_ns / 1e6, st->max_ns / 1e6, st->median_cpu_ns / 1e6,
             res->passes, res->iterations, res->cost, res->params[0], speedup);
    snprintf(name, sizeof name, "merl_fit/threads%zu", threads);
    bh_rec_begin(&r, out, name);
    bh_rec_int(&r, "threads", threads);
    bh_rec_stats(&r, st, rows);
    bh_rec_int(&r, "passes", res->passes);
    bh_rec_int(&r, "iterations", res->iterations);
    bh_rec_num(&r, "cost", res->cost);
    bh_rec_num(&r, "ns_fitted", res->params[0]);
    bh_rec_num(&r, "speedup_vs_1_thread", speedup);
    bh_rec_end(&r, out);
}

typedef struct scale_summary {
    double fit1_ms, fit1_cpu_ms, speedup, grid_mb;
    int have_fit;
} scale_summary;

static void big_section(bh_output *out, const brdffit_model *model, scale_summary *sm)
{
    big b;
    bh_stats st[MAX_THREADS];
    bd_fit_result res[MAX_THREADS];
    bh_record r;
    size_t t, n, active;
    memset(&b, 0, sizeof b);
    if (!load_big(out, &b)) return;
    n = brdffit_grid_sample_count(b.grid);
    active = brdffit_grid_active_count(b.grid, BRDFFIT_DEFAULT_CAP);
    sm->grid_mb = (double)b.grid_bytes / 1e6;
    bh_table(out, "%s: %zu samples x 3 channels, %zu inside the 75 deg cap (%zu rows)\n",
             out->opt->smoke ? "random scattered set" : "MERL-sized scattered set", n, active,
             active * 3);
    bh_table(out, "  loaded in %.0f ms; grid memory %.1f MB live, %.1f MB peak while loading\n",
             b.load_ms, b.grid_bytes / 1e6, b.load_peak / 1e6);
    bh_rec_begin(&r, out, "merl_grid");
    bh_rec_int(&r, "grid_samples", n);
    bh_rec_int(&r, "active_samples", active);
    bh_rec_int(&r, "grid_bytes", b.grid_bytes);
    bh_rec_int(&r, "load_peak_bytes", b.load_peak);
    bh_rec_num(&r, "load_ms", b.load_ms);
    bh_rec_end(&r, out);
    bh_table(out, "  auto fit of ashikhmin-shirley, %zu timed runs each:\n",
             bh_repeats(out->opt, MERL_FIT_REPEATS));
    bh_table(out, "  %7s %10s %9s %9s %9s %6s %5s %13s %9s %9s\n", "threads", "median ms", "min ms",
             "max ms", "cpu ms", "passes", "iters", "cost", "ns", "speed-up");
    for (t = 0; t < MAX_THREADS; t++) {
        if (!fit_big(out, &b, model, t + 1, &st[t], &res[t])) break;
        big_record(out, t + 1, &st[t], &res[t], active * 3, st[0].median_ns / st[t].median_ns);
    }
    if (t == MAX_THREADS) {
        sm->have_fit = 1;
        sm->fit1_ms = st[0].median_ns / 1e6;
        sm->fit1_cpu_ms = st[0].median_cpu_ns / 1e6;
        sm->speedup = st[0].median_ns / st[1].median_ns;
        if (!(fabs(res[1].params[0] / res[0].params[0] - 1.0) < 1e-6))
            bh_fail(out, "1 and 2 threads fitted ns = %.9g and %.9g", res[0].params[0],
                    res[1].params[0]);
    }
    brdffit_grid_destroy(b.grid);
    if (atomic_load(&b.counter.live) != 0) bh_fail(out, "the large grid leaked memory");
}

/* ---- the batch --------------------------------------------------------------------------- */

typedef struct batch {
    brdffit_grid **grids;
    size_t n;
    const brdffit_model *model;
} batch;

typedef struct batch_worker {
    const batch *b;
    size_t first, step;
    int failed;
} batch_worker;

static void *batch_thread(void *arg)
{
    batch_worker *w = arg;
    size_t i;
    for (i = w->first; i < w->b->n && !w->failed; i += w->step) {
        bd_fit_job job;
        bd_fit_result res;
        memset(&job, 0, sizeof job);
        job.grid = w->b->grids[i];
        job.model = w->b->model;
        job.pipeline = BRDFFIT_PIPELINE_AUTO;
        job.threads = 1;
        w->failed = bd_fit_run(&job, &res) != BRDFFIT_OK;
    }
    return NULL;
}

typedef struct batch_run {
    const batch *b;
    size_t threads;
} batch_run;

static int run_batch(void *ctx)
{
    batch_run *br = ctx;
    batch_worker w[MAX_THREADS];
    pthread_t tid[MAX_THREADS];
    int created[MAX_THREADS] = {0}, failed = 0;
    size_t t;
    memset(w, 0, sizeof w);
    for (t = 0; t < br->threads; t++) w[t].b = br->b, w[t].first = t, w[t].step = br->threads;
    for (t = 1; t < br->threads; t++)
        created[t] = pthread_create(&tid[t], NULL, batch_thread, &w[t]) == 0;
    batch_thread(&w[0]);
    for (t = 1; t < br->threads; t++) {
        if (created[t])
            pthread_join(tid[t], NULL);
        else
            batch_thread(&w[t]); /* could not start a thread: do its share here */
    }
    for (t = 0; t < br->threads; t++) failed |= w[t].failed;
    return failed;
}

static int make_batch(bh_output *out, batch *b, size_t n)
{
    size_t i;
    brdffit_error err;
    b->grids = calloc(n, sizeof *b->grids);
    b->n = n;
    if (b->grids == NULL) return 0;
    for (i = 0; i < n; i++)
        if (bd_default_grid(&b->grids[i], BD_P2, BD_SEED + i, NULL, &err) != BRDFFIT_OK) {
            bh_fail(out, "creating batch grid %zu: %s", i, err.message);
            return 0;
        }
    return 1;
}

static void free_batch(batch *b)
{
    size_t i;
    for (i = 0; b->grids != NULL && i < b->n; i++) brdffit_grid_destroy(b->grids[i]);
    free(b->grids);
}

static void batch_section(bh_output *out, const brdffit_model *model)
{
    batch b = {NULL, 0, model};
    bh_stats st[MAX_THREADS];
    size_t t, n = out->opt->smoke ? BATCH_SMOKE : BATCH;
    bh_table(out,
             "\nbatch of %zu default grids (P2, one seed each), auto fits of "
             "ashikhmin-shirley, %zu timed batches:\n",
             n, bh_repeats(out->opt, BATCH_REPEATS));
    bh_table(out, "  %7s %10s %9s %9s %9s %9s %9s\n", "threads", "median s", "min s", "max s",
             "cpu s", "fits/s", "speed-up");
    if (make_batch(out, &b, n))
        for (t = 0; t < MAX_THREADS; t++) {
            batch_run br = {&b, t + 1};
            bh_record r;
            char name[64];
            double fps, speedup;
            if (bh_measure(run_batch, &br, 0, bh_repeats(out->opt, BATCH_REPEATS), &st[t]) != 0) {
                bh_fail(out, "a batch fit on %zu threads failed", t + 1);
                break;
            }
            fps = (double)n / (st[t].median_ns / 1e9);
            speedup = st[0].median_ns / st[t].median_ns;
            bh_table(out, "  %7zu %10.3f %9.3f %9.3f %9.3f %9.1f %8.2fx\n", t + 1,
                     st[t].median_ns / 1e9, st[t].min_ns / 1e9, st[t].max_ns / 1e9,
                     st[t].median_cpu_ns / 1e9, fps, speedup);
            snprintf(name, sizeof name, "batch/threads%zu", t + 1);
            bh_rec_begin(&r, out, name);
            bh_rec_int(&r, "threads", t + 1);
            bh_rec_int(&r, "fits", n);
            bh_rec_stats(&r, &st[t], 0);
            bh_rec_num(&r, "fits_per_second", fps);
            bh_rec_num(&r, "speedup_vs_1_thread", speedup);
            bh_rec_end(&r, out);
        }
    free_batch(&b);
}

static void report_targets(bh_output *out, const scale_summary *sm)
{
    char m[64];
    bh_table(out, "\n");
    snprintf(m, sizeof m, "%.0f ms (cpu %.0f)", sm->fit1_ms, sm->fit1_cpu_ms);
    bh_target(out, "MERL-sized auto fit, 1 thread, median", m, "< 300 ms",
              sm->have_fit && sm->fit1_ms < 300.0);
    bh_target(out, "MERL-sized auto fit, 1 thread, median (issue 16)", m, "< 120 ms",
              sm->have_fit && sm->fit1_ms < 120.0);
    snprintf(m, sizeof m, "%.2fx", sm->speedup);
    bh_target(out, "MERL-sized auto fit, speed-up on 2 threads", m, ">= 1.7x",
              sm->have_fit && sm->speedup >= 1.7);
    bh_target(out, "MERL-sized auto fit, speed-up on 2 threads (issue 16)", m, ">= 1.8x",
              sm->have_fit && sm->speedup >= 1.8);
    snprintf(m, sizeof m, "%.1f MB", sm->grid_mb);
    bh_target(out, "MERL-sized grid memory (live after loading)", m, "< 200 MB",
              sm->grid_mb < 200.0);
}

int main(int argc, char **argv)
{
    bh_options opt;
    bh_output out;
    brdffit_model *model = NULL;
    scale_summary sm;
    int code;
    if (!bh_parse_args(argc, argv, "A MERL-sized fit on 1 and 2 threads; fits per second.", &opt,
                       &code))
        return code;
    if (!bh_output_open(&out, &opt, "large inputs and batches")) return 1;
    memset(&sm, 0, sizeof sm);
    if (brdffit_model_create(&model, "ashikhmin-shirley", NULL, NULL) != BRDFFIT_OK) {
        bh_fail(&out, "creating the model");
        return bh_output_close(&out);
    }
    if (bh_selected(&opt, "merl")) big_section(&out, model, &sm);
    if (bh_selected(&opt, "batch")) batch_section(&out, model);
    if (opt.filter == NULL) report_targets(&out, &sm);
    brdffit_model_destroy(model);
    return bh_output_close(&out);
}
