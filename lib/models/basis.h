/* The basis form of the built-in models, as the rest of the library sees
 * it (the fit's basis pass). Not installed.
 *
 * A built-in model is value_c(s) = sum over linear parameters m of
 * p_{m,c} B_m(s; theta), theta its shared shape parameters, declared first,
 * then the per-channel linear colours (docs/models.md). A kernel computes
 * the basis functions B_m and their derivatives dB_m/dtheta_k for a block of
 * samples; the caller combines them with the colours. The kernel itself is
 * opaque: read it through the functions below. */
#ifndef BRDFFIT_MODELS_BASIS_H
#define BRDFFIT_MODELS_BASIS_H

#include <stddef.h>

#include "brdffit/model.h"

/* Samples per basis block (the buffers live on the stack). */
#define BF_KERNEL_BLOCK 64
#define BF_KERNEL_MAX_SHAPE 3
#define BF_KERNEL_MAX_LINEAR 3

/* Basis values b[m][i] and derivatives db[k][m][i] of one block. Entries
 * whose (k, m) pair is not in the kernel's dependency mask are never read. */
typedef struct bf_basis {
    double b[BF_KERNEL_MAX_LINEAR][BF_KERNEL_BLOCK];
    double db[BF_KERNEL_MAX_SHAPE][BF_KERNEL_MAX_LINEAR][BF_KERNEL_BLOCK];
} bf_basis;

typedef struct bf_kernel bf_kernel;

/* The shape of a kernel's basis. */
typedef struct bf_basis_form {
    size_t n_shape;                    /* K <= BF_KERNEL_MAX_SHAPE */
    size_t n_linear;                   /* L <= BF_KERNEL_MAX_LINEAR */
    unsigned dep[BF_KERNEL_MAX_SHAPE]; /* bit m set: B_m depends on shape k */
} bf_basis_form;

/* The model's kernel when every parameter of the model belongs to its
 * basis form (K shape parameters, then L linear ones), else NULL (user
 * models). */
const bf_kernel *bf_model_basis(const brdffit_model *m);

/* Whether model m, which has no basis form, is affine in its one
 * per-channel colour c: value_c(s) = A(s; theta) c_c + B(s; theta) with A
 * and B free of every colour, theta its shared parameters (the glTF and
 * OpenPBR models). If so, the colour's declared index into *colour. */
int bf_model_affine(const brdffit_model *m, size_t *colour);

/* The form of kernel k. */
void bf_kernel_form(const bf_kernel *k, bf_basis_form *out);

/* The lobe form of a kernel, for the fit's fused passes
 * (fit/pass_fused.c): B_0 = 1/pi and one lobe per shape parameter s,
 * B_{1+s} = k_s P_s, dB_{1+s}/dtheta_s = (dk_s + k_s x) P_s with
 * P_s = exp(theta_s x) g, where x and g are per-sample arrays of the
 * grid's geometry that do not depend on the parameters (the same for
 * every lobe of the kernel). Lambert (K = 0) is the form without lobes. */
typedef enum bf_lobe_x { BF_LOBE_X_LOG_NH, BF_LOBE_X_LOG_RV } bf_lobe_x;
typedef enum bf_lobe_g {
    BF_LOBE_G_ONE,         /* g = 1 */
    BF_LOBE_G_AS,          /* g = 1 / (8 pi h.v max(n.l, n.v)) */
    BF_LOBE_G_RV_POSITIVE  /* g = 1 where r.v > 0, else 0 */
} bf_lobe_g;
typedef struct bf_lobe {
    bf_lobe_x x;
    bf_lobe_g g;
    double k, dk; /* at the shape parameter theta_0 */
} bf_lobe;

/* Whether kernel k has the lobe form (K lobes, L = K + 1); if so and
 * K > 0, the constants of a lobe at its shape parameter theta into *out
 * (x and g are the same for every theta). The fused pass computes the same
 * expressions as the kernel, so the same basis bits. */
int bf_kernel_lobe(const bf_kernel *k, double theta, bf_lobe *out);

/* The microfacet form of a kernel, for the fit's fused passes too: nl = 1
 * or 2 lobes, shape parameters (r_1 .. r_nl, F0) with one roughness per
 * lobe and a Fresnel F0 shared by the lobes, linear ones (cd, cs_1 ..
 * cs_nl), B_0 = 1/pi and B_q = D_q G_q F / (4 (n.l)(n.v)) of the family's
 * microfacet distribution D and shadowing G (kernel_microfacet.c), with
 * F = F0 + (1 - F0) (1 - h.v)^5. Its extended basis (fit/pass_basis.c) is
 * (1/pi, B_1 .. B_nl, dB_1/dr_1 .. dB_nl/dr_nl, dB_1/dF0 .. dB_nl/dF0). */
typedef enum bf_microfacet {
    BF_MF_NONE,     /* not of the microfacet form */
    BF_MF_GGX,      /* Trowbridge-Reitz D, height-correlated Smith G */
    BF_MF_CT,       /* Beckmann D, V-cavity G (Cook-Torrance) */
    /* Ward's isotropic lobe in the same frame, one lobe and no F0: shape
     * (a), B_1 = exp(-tan^2 theta_h / a^2) / (4 pi a^2 N), extended basis
     * (1/pi, B_1, dB_1/da) (kernel_ward.c) */
    BF_MF_WARD,      /* N = sqrt((n.l)(n.v)) */
    BF_MF_WARD_DUER, /* N = (n.l)(n.v) */
    /* Ashikhmin-Shirley's shader form (kernel_ashikhmin.c), one lobe with
     * Rs in place of F0 and a diffuse that depends on it: shape (ns, Rs),
     * linear (cd, cs), B_0 = (1 - Rs) fd, B_1 = (ns + 1) P F with P =
     * exp(ns ln n.h) / (8 pi h.v max(n.l, n.v)) as in the lobe form, fd =
     * 28 / (23 pi) (1 - (1 - n.l / 2)^5) (1 - (1 - n.v / 2)^5) and F = Rs +
     * (1 - Rs) (1 - h.v)^5; extended basis (B_0, B_1, dB_1/dns, dB_0/dRs
     * = -fd, dB_1/dRs = (ns + 1) P (1 - (1 - h.v)^5)) */
    BF_MF_AS_FRESNEL
} bf_microfacet;

/* The microfacet family of kernel k (BF_MF_NONE: not of the form); its
 * lobes are n_shape - 1 (n_shape for Ward's; one for
 * BF_MF_AS_FRESNEL). The fused pass computes the
 * kernel's expressions, so the same basis bits. */
bf_microfacet bf_kernel_microfacet(const bf_kernel *k);

/* Fill the basis of samples [first, first + count) of the batch
 * (count <= BF_KERNEL_BLOCK) at the shape parameters `shape` (the first K
 * entries of the parameter vector). */
void bf_kernel_basis(const bf_kernel *k, const brdffit_batch *batch, size_t first, size_t count,
                     const double *shape, bf_basis *out);

#endif /* BRDFFIT_MODELS_BASIS_H */
