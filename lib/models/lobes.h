/* The specular lobes of the built-in models, as the rest of the library
 * sees them: which parameters make each lobe, which one measures its
 * sharpness and in which direction, and a cheap upper bound on its
 * directional albedo (the fit's plausibility, fit/plausible.c, and the
 * canonical lobe order, fit/canonical.c). Not installed. */
#ifndef BRDFFIT_MODELS_LOBES_H
#define BRDFFIT_MODELS_LOBES_H

#include <stddef.h>

#include "brdffit/model.h"

/* Incidence angles of the tables and of the bound (degrees): those of the
 * full bound of BRDFFIT_FIT_PLAUSIBLE 2 (fit/plausible.c). */
#define BF_ALBEDO_ANGLES 6
#define BF_ALBEDO_ANGLES_DEG              \
    {                                     \
        0.0, 30.0, 50.0, 65.0, 75.0, 85.0 \
    }

/* The albedo of a lobe with colour 1 at n nodes of its sharpness parameter
 * s, s_i = 10^(log10_lo + i / per_decade): values[(2 i + f) * 6 + t] at
 * incidence angle t with the lobe's Fresnel parameter at 1 (f = 0) and at 0
 * (f = 1); the lobe is linear in it. Generated offline
 * (scripts/gen_albedo_tables.c; lib/models/albedo_tables.c). */
typedef struct bf_albedo_table {
    double log10_lo;
    int per_decade;
    size_t n;
    const double *values;
    const double *excess; /* excess[2 i + f], cell i from node i to i + 1: see the generator */
} bf_albedo_table;

/* The albedo of a lobe max(0, a.v)^n about a unit axis a at polar angle
 * theta_a, H(n, c) with c = cos(theta_a), over n and c: ln H at
 * n_i = 10^(log10_lo + i / per_decade) and c_j = 10^(log10_c_lo + j /
 * c_per_decade), log_h[i * n_c + j]; H grows with c, and c_0 lies so low
 * that H(n, c_0) exceeds H(n, 0) by less than 0.2 %. Lafortune's lobe is
 * such a lobe times a power of its largest base (docs/models.md,
 * Directional albedo). Generated offline from a one-dimensional integral
 * of H (scripts/gen_albedo_tables.c; lib/models/albedo_tables.c). */
typedef struct bf_axial_table {
    double log10_lo;
    int per_decade;
    size_t n;
    double log10_c_lo;
    int c_per_decade;
    size_t n_c;
    const double *log_h;
    const double *excess; /* excess[i * (n_c - 1) + j], cell (i, j): see the generator */
} bf_axial_table;

#define BF_NO_PARAM ((size_t)-1)

/* One specular lobe: declared parameter indices. */
typedef struct bf_lobe_desc {
    size_t colour;      /* its linear colour */
    size_t shape;       /* the parameter measuring its sharpness */
    int sharper_larger; /* 1: larger is sharper (an exponent); 0: smaller (a roughness) */
    size_t fresnel;     /* the bound's second parameter: a Fresnel parameter the lobe is
                         * linear in (F0, Rs) with `albedo`, Lafortune's cz with `axial`;
                         * or BF_NO_PARAM */
    const bf_albedo_table *albedo; /* its tabulated albedo over its sharpness, or NULL */
    const bf_axial_table *axial;   /* Lafortune's lobe: the albedo of its axial form, or NULL */
} bf_lobe_desc;

/* The lobes of a model. */
typedef struct bf_lobes {
    size_t n;            /* 1 or 2 */
    int interchangeable; /* two lobes that are the same function of their own parameters */
    bf_lobe_desc lobe[2];
} bf_lobes;

/* The lobes of a built-in model with specular lobes of a linear colour;
 * NULL for the others and for user models. */
const bf_lobes *bf_model_lobes(const brdffit_model *m);

/* A coat over a base lobe, both roughnesses (larger is broader): declared
 * indices of the coat's weight, the coat's roughness and the base's. */
typedef struct bf_coat {
    size_t weight;
    size_t shape;
    size_t base_shape;
} bf_coat;

/* The coat of a built-in model with one (gltf-clearcoat, openpbr-coat);
 * NULL for the others and for user models. */
const bf_coat *bf_model_coat(const brdffit_model *m);

/* An upper bound on the largest directional albedo over the angles above
 * of the lobe with colour 1 at sharpness `shape` and second parameter
 * `fresnel` (its `fresnel` member; 1 without one).
 * With `albedo`: the largest over the angles of the interpolation, linear
 * in log10(shape) and in F = `fresnel`, of the two table nodes around
 * `shape`, times 1 + 10^-3 (the quadrature's error), plus twice the
 * cell's midpoint excess of each column times that column's largest
 * interpolated value, weighted F and 1 - F (the interpolation's error).
 * With `axial` (Lafortune's lobe, n = `shape`, cz = `fresnel`): the
 * largest over the angles of m^n H(n, c), m = sqrt(1 - (1 - cz^2)
 * cos^2 theta_i) the lobe's largest base and c = cz cos(theta_i) / m the
 * cosine of its axis, H from the table: ln H interpolated bilinearly in
 * log10 n and log10 c (c below the table taken at its first node, H
 * growing with c), plus twice the cell's largest excess of ln H over the
 * interpolation, plus ln(1 + 10^-3).
 * 0 when the lobe has no table or a parameter lies outside the table's
 * range. Pure; thread-safe. */
double bf_lobe_albedo_bound(const bf_lobe_desc *lobe, double shape, double fresnel);

/* The tables (albedo_tables.c). */
extern const bf_albedo_table bf_albedo_phong, bf_albedo_blinn_phong, bf_albedo_ashikhmin,
    bf_albedo_cook_torrance, bf_albedo_ggx, bf_albedo_ward, bf_albedo_ward_duer;
extern const bf_axial_table bf_albedo_lafortune;

#endif /* BRDFFIT_MODELS_LOBES_H */
