/* The evidence for the fit objectives (docs/fitting.md, Choosing the
 * objective): for every built-in model and objective, the auto fit's look
 * error (brdffit_model_log_error over the cap) and the PSNR of the model's
 * rendered spheres against the measurement's (the preview's three
 * spheres, lights 0, 30 and 60 degrees from the view, 140 pixels, default
 * picture options), on the bundled sample (data/sample-carpaint.csv) and
 * on data generated from two other models (ggx-2 and ward-duer with 5 %
 * noise, the default axes); then the auto fit times per objective on the
 * bundled sample at cap 90 degrees (75,924 rows), median of repeated runs,
 * squares in the same run.
 *
 *   bench_look [--smoke] [--times] [--repeats=N] [--filter=MODEL]
 *
 * --filter=MODEL runs one model, any built-in one (the times too);
 * --times runs the times alone, without the look tables.
 *
 * Prints a table (markdown rows) on stdout. --smoke fits one model on the
 * generated data once and checks the figures are finite. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <brdffit/brdffit.h>

#ifndef BENCH_SOURCE_DIR
#define BENCH_SOURCE_DIR "."
#endif

#define PI 3.14159265358979323846
#define NOBJ 4
#define SPHERE 140
#define MAXV 64


static double now(void)
{
    struct timespec ts;
    timespec_get(&ts, TIME_UTC);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* PSNR (dB) of the model's spheres against the measured ones over the
 * three lights, every pixel and channel. */
static double sphere_psnr(const brdffit_grid *grid, const brdffit_model *model, const double *p)
{
    static unsigned char a[SPHERE * SPHERE * 3], b[SPHERE * SPHERE * 3];
    static const double light_deg[3] = {0.0, 30.0, 60.0};
    size_t nc = brdffit_grid_channel_count(grid), k, i;
    double se = 0.0, count = 0.0;
    for (k = 0; k < 3; k++) {
        double t = light_deg[k] * PI / 180.0;
        if (brdffit_image_sphere_measured(a, 3 * SPHERE, SPHERE, grid, t, 0.0, NULL, NULL, NULL) !=
                BRDFFIT_OK ||
            brdffit_image_sphere_model(b, 3 * SPHERE, SPHERE, model, p, nc, t, 0.0, NULL, NULL,
                                       NULL) != BRDFFIT_OK)
            return NAN;
        for (i = 0; i < sizeof a; i++) {
            double d = (double)a[i] - (double)b[i];
            se += d * d;
            count += 1.0;
        }
    }
    if (se == 0.0) return INFINITY;
    return 10.0 * log10(255.0 * 255.0 / (se / count));
}

typedef struct outcome {
    double look, psnr, ms;
    unsigned warnings;
    int ok;
} outcome;

static outcome fit_one(const brdffit_grid *grid, const brdffit_model *model, int objective,
                       double cap)
{
    outcome o = {NAN, NAN, NAN, 0, 0};
    brdffit_fit *fit = NULL;
    double p[MAXV], t0;
    if (brdffit_fit_create(&fit, grid, model, NULL, NULL) != BRDFFIT_OK) return o;
    brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, objective);
    brdffit_fit_set(fit, BRDFFIT_FIT_CAP, cap);
    t0 = now();
    if (brdffit_fit_run(fit) == BRDFFIT_OK && brdffit_fit_params(fit, p) == BRDFFIT_OK) {
        o.ms = 1e3 * (now() - t0);
        o.ok = 1;
        o.warnings = brdffit_fit_warnings(fit);
        brdffit_model_log_error(model, grid, p, BRDFFIT_DEFAULT_CAP, BRDFFIT_ALL_CHANNELS, &o.look,
                                NULL);
        o.psnr = sphere_psnr(grid, model, p);
    }
    brdffit_fit_destroy(fit);
    return o;
}

/* Data from a built-in model with per-parameter values (shared parameters
 * take v[k][0]), times 1 + noise N(0, 1) (a fixed generator), on the
 * default axes. */
static brdffit_grid *generated(const char *name, const double v[][3], double noise)
{
    const brdffit_axes *ax = brdffit_axes_default();
    size_t n = ax->n_theta_i * ax->n_theta_o * ax->n_phi_o, s, c, k, i, j, l;
    brdffit_model *model = NULL;
    brdffit_grid *grid = NULL;
    double p[MAXV], *ti = malloc(n * sizeof *ti), *pi = malloc(n * sizeof *pi);
    double *to = malloc(n * sizeof *to), *po = malloc(n * sizeof *po);
    double *vals = malloc(3 * n * sizeof *vals), *inter = malloc(3 * n * sizeof *inter);
    unsigned long long state = 88172645463325252ULL;
    if (!ti || !pi || !to || !po || !vals || !inter ||
        brdffit_model_create(&model, name, NULL, NULL))
        goto done;
    for (k = 0; k < brdffit_model_param_count(model); k++) {
        int per = (brdffit_model_param(model, k)->flags & BRDFFIT_PARAM_PER_CHANNEL) != 0;
        for (c = 0; c < (per ? 3u : 1u); c++) p[brdffit_model_vector_index(model, k, c, 3)] = v[k][c];
    }
    for (i = 0, s = 0; i < ax->n_theta_i; i++)
        for (j = 0; j < ax->n_theta_o; j++)
            for (l = 0; l < ax->n_phi_o; l++, s++) {
                ti[s] = ax->theta_i[i];
                pi[s] = PI;
                to[s] = ax->theta_o[j];
                po[s] = ax->phi_o[l];
            }
    if (brdffit_model_eval_angles(model, n, ti, pi, to, po, 3, p, vals, NULL, NULL) != BRDFFIT_OK)
        goto done;
    for (s = 0; s < 3 * n; s++) {
        double u1, u2;
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        u1 = ((double)(state >> 11) + 0.5) * 0x1.0p-53;
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        u2 = (double)(state >> 11) * 0x1.0p-53;
        /* planar (channel c at c n + s) to interleaved (s 3 + c) */
        inter[(s % n) * 3 + s / n] =
            fmax(0.0, vals[s] * (1.0 + noise * sqrt(-2.0 * log(u1)) * cos(2.0 * PI * u2)));
    }
    if (brdffit_grid_create_regular(&grid, ax, 3, inter, NULL, NULL, NULL) != BRDFFIT_OK)
        grid = NULL;
done:
    brdffit_model_destroy(model);
    free(ti);
    free(pi);
    free(to);
    free(po);
    free(vals);
    free(inter);
    return grid;
}

static void table(const char *label, const brdffit_grid *grid, const char *filter, int smoke)
{
    size_t m;
    printf("\n%s: look error / sphere PSNR (dB), auto fit, cap 75 deg\n\n", label);
    printf("| model | squares | log | cube-root | relative |\n|---|---|---|---|---|\n");
    for (m = 0; m < brdffit_model_builtin_count(); m++) {
        const char *name = brdffit_model_builtin_name(m);
        brdffit_model *model = NULL;
        int o;
        if (filter && strcmp(filter, name) != 0) continue;
        if (brdffit_model_create(&model, name, NULL, NULL) != BRDFFIT_OK) continue;
        printf("| %s |", name);
        for (o = 0; o < NOBJ; o++) {
            outcome r = fit_one(grid, model, o, BRDFFIT_DEFAULT_CAP);
            if (!r.ok) printf(" failed |");
            else printf(" %.4f / %.1f%s |", r.look, r.psnr, r.warnings ? "*" : "");
            fflush(stdout);
            if (smoke && !(r.ok && isfinite(r.look) && r.psnr > 0.0)) exit(1);
        }
        printf("\n");
        brdffit_model_destroy(model);
        if (smoke) break;
    }
}

static void times(const brdffit_grid *grid, size_t repeats, const char *filter)
{
    static const char *const fixed[] = {"ashikhmin-shirley", "ggx", "ggx-2"};
    const char *const *models = filter ? &filter : fixed; /* --filter times any model */
    size_t n_models = filter ? 1 : sizeof fixed / sizeof fixed[0], i, r;
    printf("\nauto fit time per objective, bundled sample at cap 90 deg (75,924 rows), "
           "median of %zu runs, 1 thread\n\n| model | squares | log | cube-root | relative |\n"
           "|---|---|---|---|---|\n",
           repeats);
    for (i = 0; i < n_models; i++) {
        brdffit_model *model = NULL;
        double med[NOBJ];
        int o;
        if (brdffit_model_create(&model, models[i], NULL, NULL) != BRDFFIT_OK) continue;
        for (o = 0; o < NOBJ; o++) {
            double t[64];
            for (r = 0; r < repeats; r++) t[r] = fit_one(grid, model, o, PI / 2.0).ms;
            qsort(t, repeats, sizeof *t, cmp);
            med[o] = t[repeats / 2];
        }
        printf("| %s | %.0f ms | %.0f ms (%.2fx) | %.0f ms (%.2fx) | %.0f ms (%.2fx) |\n",
               models[i], med[0], med[1], med[1] / med[0], med[2], med[2] / med[0], med[3],
               med[3] / med[0]);
        brdffit_model_destroy(model);
    }
}

int main(int argc, char **argv)
{
    static const double ggx2[6][3] = {{0.3}, {0.05}, {0.04}, {0.3, 0.2, 0.1},
                                      {0.5, 0.4, 0.3}, {3.0, 2.5, 2.0}};
    static const double ward[3][3] = {{0.12}, {0.25, 0.12, 0.05}, {0.3, 0.3, 0.3}};
    const char *filter = NULL;
    size_t repeats = 5;
    int smoke = 0, times_only = 0, i;
    brdffit_grid *sample = NULL, *g1, *g2;
    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--smoke") == 0) smoke = 1;
        else if (strcmp(argv[i], "--times") == 0)
            times_only = 1;
        else if (strncmp(argv[i], "--repeats=", 10) == 0) repeats = (size_t)atoi(argv[i] + 10);
        else if (strncmp(argv[i], "--filter=", 9) == 0) filter = argv[i] + 9;
        else {
            fprintf(stderr, "usage: %s [--smoke] [--times] [--repeats=N] [--filter=MODEL]\n",
                    argv[0]);
            return 2;
        }
    }
    if (repeats < 1 || repeats > 64) repeats = 5;
    g1 = generated("ggx-2", ggx2, 0.05);
    g2 = generated("ward-duer", ward, 0.05);
    if (g1 == NULL || g2 == NULL) return 1;
    if (smoke) {
        table("ggx-2 data", g1, "ashikhmin-shirley", 1);
    } else {
        if (brdffit_load_csv(&sample, BENCH_SOURCE_DIR "/data/sample-carpaint.csv", NULL, NULL) !=
            BRDFFIT_OK) {
            fprintf(stderr, "cannot load the bundled sample\n");
            return 1;
        }
        if (!times_only) {
            table("bundled sample (data/sample-carpaint.csv)", sample, filter, 0);
            table("ggx-2 data, 5 % noise", g1, filter, 0);
            table("ward-duer data, 5 % noise", g2, filter, 0);
        }
        times(sample, repeats, filter);
        brdffit_grid_destroy(sample);
    }
    brdffit_grid_destroy(g1);
    brdffit_grid_destroy(g2);
    return 0;
}
