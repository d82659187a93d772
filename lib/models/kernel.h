/* The built-in model kernels (docs/models.md). Not installed.
 *
 * Every built-in model but the glTF and OpenPBR ones (kernel_gltf.c,
 * kernel_openpbr.c: affine in their colour, bf_builtin.affine) has the form
 *
 *     value_c(s) = sum over linear parameters m of p_{m,c} * B_m(s; theta)
 *
 * where theta are the shared shape parameters (exponents, roughness, Fresnel
 * terms) and p_{m,c} the per-channel linear colours. A kernel only computes
 * the basis functions B_m and their derivatives dB_m/dtheta_k for a block of
 * samples; bf_kernel_run() turns them into values and a Jacobian for every
 * channel with plain multiply-adds, so no transcendental function is ever
 * evaluated per channel.
 *
 * Built-in models declare their shape parameters first, then their linear
 * (per-channel) parameters, so the parameter vector is
 * [theta_0 .. theta_{K-1}, p_{0,0} .. p_{0,C-1}, p_{1,0} ..]. */
#ifndef BRDFFIT_MODELS_KERNEL_H
#define BRDFFIT_MODELS_KERNEL_H

#include <stddef.h>

#include "brdffit/model.h"
#include "models/basis.h"

/* Fill the basis of samples [first, first + count) of the batch
 * (count <= BF_KERNEL_BLOCK) for the shape parameters `shape`. */
typedef void (*bf_basis_fn)(const brdffit_batch *batch, size_t first, size_t count,
                            const double *shape, bf_basis *out);

/* The lobe form's constants of one lobe at its shape parameter theta
 * (basis.h); a kernel without shape parameters (Lambert) has one that is
 * never called. */
typedef void (*bf_lobe_fn)(double theta, bf_lobe *out);

struct bf_kernel {
    size_t n_shape;                    /* K <= BF_KERNEL_MAX_SHAPE */
    size_t n_linear;                   /* L <= BF_KERNEL_MAX_LINEAR */
    unsigned dep[BF_KERNEL_MAX_SHAPE]; /* bit m set: B_m depends on shape k */
    bf_basis_fn basis;
    bf_lobe_fn lobe;                   /* NULL: not of the lobe form */
    bf_microfacet mf;                  /* the microfacet form's family, or BF_MF_NONE */
};

/* Evaluate a kernel over a batch with the layouts of brdffit_model_eval_fn. */
brdffit_status bf_kernel_run(const bf_kernel *k, const brdffit_batch *batch, const double *params,
                             size_t n_channels, double *values, double *jacobian);

/* A built-in model: its name, its parameters and its evaluation callback. */
typedef struct bf_builtin {
    const char *name;
    size_t n_params;
    const brdffit_param_info *params;
    brdffit_model_eval_fn eval;
    const bf_kernel *kernel; /* the basis form, for the fit's fused passes; NULL
                              * for a model that has none (the glTF ones) */
    size_t affine;           /* 1 + the declared index of the one per-channel
                              * colour c a model without a basis form is affine
                              * in (value_c = A c_c + B, A and B free of every
                              * colour: the glTF and OpenPBR models); 0 for the
                              * others (models/basis.h, bf_model_affine()) */
} bf_builtin;

/* Branch-free min and max for finite arguments (compile to minsd/maxsd and
 * vectorise, unlike fmin/fmax with their NaN rules). */
static inline double bf_min(double a, double b)
{
    return a < b ? a : b;
}

static inline double bf_max(double a, double b)
{
    return a > b ? a : b;
}

/* The GGX lobe of glTF's BRDF at one sample (kernel_gltf.c), shared with
 * the OpenPBR models (kernel_openpbr.c): S = D Vis with GGX D and
 * height-correlated Smith Vis, alpha = roughness^2; dS/d(roughness); and
 * Schlick's (1 - h.v)^5. */
typedef struct bf_ggx_lobe {
    double s, ds, f5;
} bf_ggx_lobe;

bf_ggx_lobe bf_ggx_shape(double nl, double nv, double nh, double hv, double roughness);

/* Parameter ranges shared by the built-in models. */
#define BF_EXP_LO 1e-3
#define BF_EXP_HI 1e6
#define BF_ROUGH_LO 1e-4
#define BF_ROUGH_HI 1.0

/* kernel_lambert_phong.c */
extern const bf_builtin bf_builtin_lambert;
extern const bf_builtin bf_builtin_phong;
extern const bf_builtin bf_builtin_blinn_phong;
/* kernel_ashikhmin.c */
extern const bf_builtin bf_builtin_ashikhmin_shirley;
extern const bf_builtin bf_builtin_ashikhmin_shirley_fresnel;
extern const bf_builtin bf_builtin_ashikhmin_shirley_2;
/* kernel_microfacet.c */
extern const bf_builtin bf_builtin_cook_torrance;
extern const bf_builtin bf_builtin_ggx;
extern const bf_builtin bf_builtin_cook_torrance_2;
extern const bf_builtin bf_builtin_ggx_2;
/* kernel_ward.c */
extern const bf_builtin bf_builtin_ward;
extern const bf_builtin bf_builtin_ward_duer;
/* kernel_lafortune.c */
extern const bf_builtin bf_builtin_lafortune;
/* kernel_gltf.c */
extern const bf_builtin bf_builtin_gltf;
extern const bf_builtin bf_builtin_gltf_clearcoat;

/* kernel_openpbr.c */
extern const bf_builtin bf_builtin_openpbr;
extern const bf_builtin bf_builtin_openpbr_coat;

#endif /* BRDFFIT_MODELS_KERNEL_H */
