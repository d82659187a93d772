/* Generator of lib/models/albedo_tables.c: the directional albedo of the
 * built-in specular lobes with colour 1, tabulated over their sharpness
 * parameter, from the library's own quadrature (brdffit_model_albedo(),
 * default quality). The cheap energy bound of BRDFFIT_FIT_PLAUSIBLE 1
 * (lib/models/lobes.c) reads these tables.
 *
 * Build and run against a build of the library (it prints the C file):
 *
 *   cc -O2 -std=c11 -Iinclude -IBUILD/include -Ilib scripts/gen_albedo_tables.c BUILD/libbrdffit.a -lm \
 *      -lpthread -o /tmp/gen_albedo_tables && /tmp/gen_albedo_tables > lib/models/albedo_tables.c
 *
 * For each lobe and each node s of the sharpness parameter (PER_DECADE
 * nodes per decade over the parameter's declared range, logarithmically
 * spaced) it writes the albedo at the incidence angles BF_ALBEDO_ANGLES_DEG
 * with the lobe's Fresnel parameter at 1 (column 0) and at 0 (column 1);
 * the lobe is linear in that parameter, so the two columns give every
 * value of it. A lobe without a Fresnel parameter has equal columns. It
 * also evaluates the albedo at the middle of every cell and writes, per
 * cell and column, by how much it exceeds there the linear interpolation
 * of the nodes (relative to the column's largest value over the angles):
 * the bound adds twice that (models/lobes.h).
 *
 * Lafortune's lobe depends on n and cz alike. It is m^n max(0, a.v)^n, m
 * its largest base and a its axis (docs/models.md, Directional albedo),
 * so one table of H(n, c), the albedo of the lobe max(0, a.v)^n about an
 * axis of polar cosine c, serves every cz: ln H at PER_DECADE nodes per
 * decade of n over its declared range and of c from C_LO to 1, from a
 * one-dimensional integral (axial_albedo() below), with per cell the
 * largest excess of ln H over the bilinear interpolation at 21 points of
 * the cell (its quarter points and edge points). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "brdffit/brdffit.h"
#include "core/quadrature.h"
#include "models/lobes.h"

#define PI 3.14159265358979323846
#define PER_DECADE 8
#define C_LO 1e-6 /* the axial table's smallest axis cosine */
#define N_ANGLES BF_ALBEDO_ANGLES
static const double ANGLES_DEG[N_ANGLES] = BF_ALBEDO_ANGLES_DEG;

typedef struct lobe_spec {
    const char *table; /* C name of the table */
    const char *model; /* the one-lobe model it is taken from */
    size_t shape;      /* declared index of the sharpness parameter */
    long fresnel;      /* declared index of the Fresnel parameter, or -1 */
    size_t colour;     /* declared index of the lobe's colour */
} lobe_spec;

static const lobe_spec SPECS[] = {
    {"bf_albedo_phong", "phong", 0, -1, 2},
    {"bf_albedo_blinn_phong", "blinn-phong", 0, -1, 2},
    {"bf_albedo_ashikhmin", "ashikhmin-shirley-fresnel", 0, 1, 3},
    {"bf_albedo_cook_torrance", "cook-torrance", 0, 1, 3},
    {"bf_albedo_ggx", "ggx", 0, 1, 3},
    {"bf_albedo_ward", "ward", 0, -1, 2},
    {"bf_albedo_ward_duer", "ward-duer", 0, -1, 2},
};

/* The albedo at sharpness x into a[f][t], for f = 0 (Fresnel 1) and 1 (0). */
static int albedo(brdffit_model *m, const lobe_spec *s, double x, double a[2][N_ANGLES])
{
    double v[8], angles[N_ANGLES];
    size_t k, f, t;
    for (t = 0; t < N_ANGLES; t++) angles[t] = ANGLES_DEG[t] * PI / 180.0;
    for (k = 0; k < brdffit_model_param_count(m); k++) v[k] = 0.0;
    v[s->shape] = x;
    v[s->colour] = 1.0;
    for (f = 0; f < 2; f++) {
        if (s->fresnel >= 0) v[s->fresnel] = f == 0 ? 1.0 : 0.0;
        if (brdffit_model_albedo(m, v, 1, angles, N_ANGLES, 0, a[f], NULL) != BRDFFIT_OK) return 1;
    }
    return 0;
}

/* excess[2 i + f]: by how much the albedo at the middle of cell i (in
 * log10 of the sharpness) exceeds the linear interpolation of its nodes,
 * at most over the angles, relative to the interpolation's largest value
 * over the angles; column f. */
static int midpoint_excess(brdffit_model *m, const lobe_spec *s, double lo, size_t n,
                           double (*a)[2][N_ANGLES], double *excess)
{
    double mid[2][N_ANGLES];
    size_t i, f, t;
    for (i = 0; i + 1 < n; i++) {
        if (albedo(m, s, pow(10.0, lo + ((double)i + 0.5) / PER_DECADE), mid) != 0) return 1;
        for (f = 0; f < 2; f++) {
            double top = 0.0, over = 0.0;
            for (t = 0; t < N_ANGLES; t++) {
                double lin = 0.5 * (a[i][f][t] + a[i + 1][f][t]);
                top = fmax(top, lin);
                over = fmax(over, mid[f][t] - lin);
            }
            excess[2 * i + f] = top > 0.0 ? over / top : 0.0;
        }
    }
    return 0;
}

static void print_array(const char *name, const char *suffix, const double *v, size_t n,
                        size_t per_line, int digits)
{
    size_t i;
    printf("static const double %s_%s[%zu] = {", name, suffix, n);
    for (i = 0; i < n; i++) printf("%s %.*e,", i % per_line == 0 ? "\n   " : "", digits, v[i]);
    printf("\n};\n");
}

static int emit(const lobe_spec *s)
{
    static double a[2048][2][N_ANGLES], excess[4096];
    brdffit_model *m = NULL;
    const brdffit_param_info *info;
    double lo, hi, worst = 0.0;
    size_t n, i;
    if (brdffit_model_create(&m, s->model, NULL, NULL) != BRDFFIT_OK) return 1;
    info = brdffit_model_param(m, s->shape);
    lo = floor(log10(info->lower) * PER_DECADE + 0.5) / PER_DECADE;
    hi = floor(log10(info->upper) * PER_DECADE + 0.5) / PER_DECADE;
    n = (size_t)((hi - lo) * PER_DECADE + 0.5) + 1;
    for (i = 0; i < n; i++)
        if (albedo(m, s, pow(10.0, lo + (double)i / PER_DECADE), a[i]) != 0) return 1;
    if (midpoint_excess(m, s, lo, n, a, excess) != 0) return 1;
    for (i = 0; i < 2 * (n - 1); i++) worst = fmax(worst, excess[i]);
    printf("\n/* %s: %s \"%s\", 10^%g .. 10^%g;\n * largest midpoint excess %.3g */\n", s->table,
           s->model, info->name, lo, hi, worst);
    print_array(s->table, "values", &a[0][0][0], n * 2 * N_ANGLES, N_ANGLES, 7);
    print_array(s->table, "excess", excess, 2 * (n - 1), 6, 7);
    printf("const bf_albedo_table %s = {\n    %.17g, %d, %zu, %s_values, %s_excess};\n", s->table,
           lo, PER_DECADE, n, s->table, s->table);
    brdffit_model_destroy(m);
    return 0;
}

/* ---- Lafortune's lobe ---------------------------------------------------- */

/* The integrand of the clipped part below at phi (sin phi, cos phi given
 * accurately near both ends). */
static double clipped(double n, double c, double s, double sp, double cp)
{
    double x = fmin(c * sp / sqrt(1.0 - s * s * sp * sp), 1.0);
    return exp(n * log(sp)) * cp * (c * sp * (PI - acos(x)) + cp);
}

/* H(n, c): the albedo of the lobe max(0, a.v)^n about the unit axis a at
 * polar cosine c, the integral over the upper hemisphere of v of
 * max(0, a.v)^n v_z. With v at angle g from a and azimuth p about it,
 * v_z = c cos g - s sin g cos p (s = sin of a's polar angle); for each g
 * the integral over p of max(0, v_z) is 2 pi c cos g while the circle
 * stays above the horizon (cos g >= s) and 2 (A (pi - p0) + sqrt(B^2 -
 * A^2)) below it, A = c cos g, B = s sin g, p0 = acos(A / B). Then, with
 * t = cos g = s sin(phi) in the second part,
 *
 *   H = 2 pi c (1 - s^(n+2)) / (n + 2)
 *     + 2 s^(n+2) int_0^(pi/2) sin^n(phi) cos(phi) (c sin(phi) (pi - acos x) + cos(phi)) dphi,
 *   x = c sin(phi) / sqrt(1 - s^2 sin^2(phi)).
 *
 * The integral takes 8-point Gauss-Legendre panels halving towards both
 * ends (sin^n(phi) is a spike at pi/2 for large n, a cusp at 0 for small
 * n): exact to about 1e-10. */
static double axial_albedo(double n, double c)
{
    const double s = sqrt(fmax(0.0, 1.0 - c * c));
    const double sn2 = s > 0.0 ? exp((n + 2.0) * log(s)) : 0.0;
    double x[8], w[8], sum = 0.0;
    int end, k, j;
    bf_gauss_legendre(8, x, w);
    for (end = 0; end < 2 && s > 0.0; end++) {
        double hi = PI / 4.0; /* distance from the end */
        for (k = 0; k < 60; k++) {
            double lo = k == 59 ? 0.0 : 0.5 * hi, mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
            for (j = 0; j < 8; j++) {
                double d = mid + half * x[j]; /* phi = d (end 0) or pi/2 - d (end 1) */
                sum += w[j] * half *
                       (end == 0 ? clipped(n, c, s, sin(d), cos(d))
                                 : clipped(n, c, s, cos(d), sin(d)));
            }
            hi = lo;
        }
    }
    return 2.0 * PI * c * (1.0 - sn2) / (n + 2.0) + 2.0 * sn2 * sum;
}

/* The bilinear interpolation of ln H inside cell (i, j) at (u, v). */
static double bilinear(const double *h, size_t nc, size_t i, size_t j, double u, double v)
{
    return (1.0 - u) * ((1.0 - v) * h[i * nc + j] + v * h[i * nc + j + 1]) +
           u * ((1.0 - v) * h[(i + 1) * nc + j] + v * h[(i + 1) * nc + j + 1]);
}

static int emit_axial(void)
{
    static double h[128 * 64], excess[128 * 64];
    brdffit_model *m = NULL;
    const brdffit_param_info *info;
    double lo, hi, clo = log10(C_LO), worst = 0.0, edge = 0.0, quad = 0.0;
    size_t n, nc = (size_t)(-clo * PER_DECADE + 0.5) + 1, i, j, a, b;
    if (brdffit_model_create(&m, "lafortune", NULL, NULL) != BRDFFIT_OK) return 1;
    info = brdffit_model_param(m, 0);
    lo = floor(log10(info->lower) * PER_DECADE + 0.5) / PER_DECADE;
    hi = floor(log10(info->upper) * PER_DECADE + 0.5) / PER_DECADE;
    n = (size_t)((hi - lo) * PER_DECADE + 0.5) + 1;
    if (n > 128 || nc > 64) return 1;
    for (i = 0; i < n; i++) {
        double x = pow(10.0, lo + (double)i / PER_DECADE), zero = axial_albedo(x, 0.0);
        for (j = 0; j < nc; j++) {
            h[i * nc + j] = log(axial_albedo(x, pow(10.0, clo + (double)j / PER_DECADE)));
            /* H grows with c: the first node bounds every c below it */
            if (j > 0 && !(h[i * nc + j] >= h[i * nc + j - 1])) {
                fprintf(stderr, "lafortune: H(%g, c) falls at node %zu\n", x, j);
                return 1;
            }
        }
        if (!(log(zero) <= h[i * nc])) {
            fprintf(stderr, "lafortune: H(%g, 0) exceeds the first node\n", x);
            return 1;
        }
        edge = fmax(edge, exp(h[i * nc]) / zero - 1.0);
    }
    for (i = 0; i + 1 < n; i++)
        for (j = 0; j + 1 < nc; j++) {
            double over = 0.0;
            for (a = 0; a <= 4; a++)
                for (b = 0; b <= 4; b++) {
                    double u = 0.25 * (double)a, v = 0.25 * (double)b, truth;
                    if ((a == 0 || a == 4) && (b == 0 || b == 4)) continue; /* nodes */
                    truth = log(axial_albedo(pow(10.0, lo + ((double)i + u) / PER_DECADE),
                                             pow(10.0, clo + ((double)j + v) / PER_DECADE)));
                    over = fmax(over, truth - bilinear(h, nc, i, j, u, v));
                }
            excess[i * (nc - 1) + j] = over;
            worst = fmax(worst, over);
        }
    /* the library's quadrature agrees with H where it is accurate: the lobe
     * with cz = 1 is the mirror lobe (r.v)^n at theta_i = theta_a, for
     * n >= 10 and theta_i up to 85 degrees */
    for (i = 0; i < n; i++) {
        double x = pow(10.0, lo + (double)i / PER_DECADE), v[4] = {0.0, 1.0, 0.0, 1.0};
        double angles[N_ANGLES], lib[N_ANGLES];
        size_t t;
        if (x < 10.0) continue;
        v[0] = x;
        for (t = 0; t < N_ANGLES; t++) angles[t] = ANGLES_DEG[t] * PI / 180.0;
        if (brdffit_model_albedo(m, v, 1, angles, N_ANGLES, 0, lib, NULL) != BRDFFIT_OK) return 1;
        for (t = 0; t < N_ANGLES; t++)
            quad = fmax(quad, fabs(lib[t] / axial_albedo(x, cos(angles[t])) - 1.0));
    }
    printf("\n/* bf_albedo_lafortune: ln H of lafortune's axial lobe, \"%s\" 10^%g .. 10^%g,\n"
           " * axis cosine 10^%g .. 1; largest excess over the interpolation %.3g;\n"
           " * H(n, 10^%g) exceeds H(n, 0) by at most %.3g; the library's quadrature\n"
           " * (cz = 1, n >= 10, theta_i <= 85 deg) agrees to %.3g */\n",
           info->name, lo, hi, clo, worst, clo, edge, quad);
    print_array("bf_albedo_lafortune", "log_h", h, n * nc, 4, 12);
    print_array("bf_albedo_lafortune", "excess", excess, (n - 1) * (nc - 1), 6, 7);
    printf("const bf_axial_table bf_albedo_lafortune = {\n    %.17g, %d, %zu, %.17g, %d, %zu,\n"
           "    bf_albedo_lafortune_log_h, bf_albedo_lafortune_excess};\n",
           lo, PER_DECADE, n, clo, PER_DECADE, nc);
    brdffit_model_destroy(m);
    return 0;
}

int main(void)
{
    size_t i;
    printf("/* GENERATED by scripts/gen_albedo_tables.c (see there how to run it): do not\n"
           " * edit. Directional albedo of the built-in specular lobes with colour 1,\n"
           " * over their sharpness parameter; the layout is in models/lobes.h. */\n"
           "#include \"models/lobes.h\"\n");
    for (i = 0; i < sizeof SPECS / sizeof SPECS[0]; i++)
        if (emit(&SPECS[i]) != 0) {
            fprintf(stderr, "gen_albedo_tables: %s failed\n", SPECS[i].model);
            return 1;
        }
    if (emit_axial() != 0) {
        fprintf(stderr, "gen_albedo_tables: lafortune failed\n");
        return 1;
    }
    return 0;
}
