/* brdffit info FILE: what a measurement holds. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"

#define RAD2DEG (180.0 / 3.14159265358979323846)

static const char info_help[] =
    "usage: brdffit info FILE\n"
    "\n"
    "Summarise a measurement (CSV, MERL binary resampled onto the default axes,\n"
    "ASTM E1392, or RGL .bsdf as measured; the format is told from the content):\n"
    "its form (regular or scattered), the axes of a regular grid, the range of\n"
    "every angle in degrees, channels, samples, missing values, the value range\n"
    "and negative values of each channel, and the samples inside and outside the\n"
    "default 75 deg angle cap.\n";

/* An axis: count, range, and the step when evenly spaced (else the list). */
static void print_axis(const char *label, const double *v, size_t n)
{
    double step = n > 1 ? (v[n - 1] - v[0]) / (double)(n - 1) : 0.0;
    size_t i;
    int even = 1;
    for (i = 1; i < n; i++)
        if (fabs(v[i] - v[i - 1] - step) > 1e-9 * (1.0 + fabs(step))) even = 0;
    printf("%-10s %zu value%s, %g .. %g deg", label, n, n == 1 ? "" : "s", v[0] * RAD2DEG,
           v[n - 1] * RAD2DEG);
    if (n > 1 && even)
        printf(", step %g\n", step * RAD2DEG);
    else if (n > 1) {
        printf(":");
        for (i = 0; i < n; i++) printf(" %g", v[i] * RAD2DEG);
        printf("\n");
    } else
        printf("\n");
}

static void print_axes(const brdffit_grid *g)
{
    static const char *const labels[3] = {"theta_i", "theta_o", "phi_o"};
    static const brdffit_axis axes[3] = {BRDFFIT_AXIS_THETA_I, BRDFFIT_AXIS_THETA_O,
                                         BRDFFIT_AXIS_PHI_O};
    size_t k;
    for (k = 0; k < 3; k++) {
        const double *v;
        size_t n;
        if (brdffit_grid_axis(g, axes[k], &v, &n) == BRDFFIT_OK) print_axis(labels[k], v, n);
    }
}

/* The range of each of the four angles over every sample, in degrees. */
static void print_angles(const brdffit_grid *g)
{
    static const char *const names[4] = {"theta_i", "phi_i", "theta_o", "phi_o"};
    double lo[4] = {0}, hi[4] = {0}, a[4];
    size_t s, k, n = brdffit_grid_sample_count(g);
    for (s = 0; s < n; s++) {
        if (brdffit_grid_sample_angles(g, s, &a[0], &a[1], &a[2], &a[3]) != BRDFFIT_OK) return;
        for (k = 0; k < 4; k++) {
            if (s == 0 || a[k] < lo[k]) lo[k] = a[k];
            if (s == 0 || a[k] > hi[k]) hi[k] = a[k];
        }
    }
    printf("%-10s", "angles");
    for (k = 0; k < 4; k++)
        printf("%s %s %g .. %g", k == 0 ? "" : ",", names[k], lo[k] * RAD2DEG, hi[k] * RAD2DEG);
    printf(" deg\n");
}

/* Smallest and largest present value of one channel, and how many of them
 * are negative. */
static int channel_range(const brdffit_grid *g, size_t c, double *lo, double *hi,
                         size_t *negative)
{
    const double *v;
    size_t s, n = brdffit_grid_sample_count(g);
    int any = 0;
    *negative = 0;
    if (brdffit_grid_values(g, c, &v) != BRDFFIT_OK) return 0;
    for (s = 0; s < n; s++) {
        if (brdffit_grid_is_missing(g, s, c)) continue;
        if (!any || v[s] < *lo) *lo = v[s];
        if (!any || v[s] > *hi) *hi = v[s];
        *negative += v[s] < 0.0;
        any = 1;
    }
    return any;
}

static void print_values(const brdffit_grid *g)
{
    size_t c, nc = brdffit_grid_channel_count(g);
    for (c = 0; c < nc; c++) {
        double lo = 0.0, hi = 0.0;
        size_t neg = 0;
        char label[32];
        cli_format(label, sizeof label, "channel %zu", c);
        if (channel_range(g, c, &lo, &hi, &neg))
            printf("%-10s %g .. %g (1/sr), %zu negative\n", label, lo, hi, neg);
        else
            printf("%-10s all missing\n", label);
    }
}

static void print_summary(const brdffit_grid *g, const char *path, const char *what)
{
    size_t n = brdffit_grid_sample_count(g), nc = brdffit_grid_channel_count(g);
    size_t in_cap = brdffit_grid_active_count(g, BRDFFIT_DEFAULT_CAP);
    printf("%-10s %s\n", "file", path);
    printf("%-10s %s\n", "format", what);
    printf("%-10s %s\n", "form",
           brdffit_grid_get_kind(g) == BRDFFIT_GRID_REGULAR ? "regular" : "scattered");
    if (brdffit_grid_get_kind(g) == BRDFFIT_GRID_REGULAR) print_axes(g);
    print_angles(g);
    printf("%-10s %zu\n", "channels", nc);
    printf("%-10s %zu (%zu values)\n", "samples", n, n * nc);
    printf("%-10s %zu values\n", "missing", brdffit_grid_missing_count(g));
    print_values(g);
    printf("%-10s %zu samples with theta_i, theta_o <= 75 deg; %zu outside (%.1f %%)\n",
           "in cap", in_cap, n - in_cap, 100.0 * (double)(n - in_cap) / (double)n);
}

int cli_cmd_info(int argc, char **argv)
{
    static const cli_option options[] = {{"help", 0}, {NULL, 0}};
    cli_args a;
    const char *name, *value, *path = NULL, *what;
    brdffit_grid *g = NULL;
    char msg[CLI_MSG_SIZE];
    int r;
    cli_args_init(&a, argc, argv, options);
    while ((r = cli_next(&a, &name, &value)) > 0) {
        if (name != NULL) {
            fputs(info_help, stdout);
            return CLI_OK;
        }
        if (path != NULL) return cli_usage_error("info", "give one FILE");
        path = value;
    }
    if (r < 0) return CLI_USAGE;
    if (path == NULL) return cli_usage_error("info", "no FILE given");
    if (cli_load(path, &g, &what, msg, sizeof msg) != BRDFFIT_OK) {
        cli_error(path, "%s", msg);
        return CLI_FAILED;
    }
    print_summary(g, path, what);
    brdffit_grid_destroy(g);
    return CLI_OK;
}
