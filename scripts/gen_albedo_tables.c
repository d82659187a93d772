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
 * the bound adds twice that (models/lobes.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "brdffit/brdffit.h"
#include "models/lobes.h"

#define PER_DECADE 8
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
    for (t = 0; t < N_ANGLES; t++) angles[t] = ANGLES_DEG[t] * 3.14159265358979323846 / 180.0;
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
                        size_t per_line)
{
    size_t i;
    printf("static const double %s_%s[%zu] = {", name, suffix, n);
    for (i = 0; i < n; i++) printf("%s %.7e,", i % per_line == 0 ? "\n   " : "", v[i]);
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
    print_array(s->table, "values", &a[0][0][0], n * 2 * N_ANGLES, N_ANGLES);
    print_array(s->table, "excess", excess, 2 * (n - 1), 6);
    printf("const bf_albedo_table %s = {\n    %.17g, %d, %zu, %s_values, %s_excess};\n", s->table,
           lo, PER_DECADE, n, s->table, s->table);
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
    return 0;
}
