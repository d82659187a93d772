/* The RGL .bsdf loader's parts: the file's fields (rgl.c), its
 * marginal-conditional warp (rgl_warp.c) and the two grid forms
 * (rgl_grid.c). Not installed. */
#ifndef BRDFFIT_RGL_INTERNAL_H
#define BRDFFIT_RGL_INTERNAL_H

#include "brdffit/grid.h"
#include "load/tensor_internal.h"

/* A 2D density on [0, 1]^2 given at nx x ny nodes and interpolated
 * bilinearly, one per slice (a light direction of the file), with the
 * normalised density and its conditional (per row) and marginal CDFs. */
typedef struct bf_warp {
    size_t nx, ny, n_slices;
    double *data; /* n_slices * ny * nx; owns the block */
    double *cond; /* n_slices * ny * nx */
    double *marg; /* n_slices * ny */
} bf_warp;

/* Up to four slices and their weights: the light parameters (phi_i,
 * theta_i) interpolated linearly between the file's values. */
typedef struct bf_corners {
    size_t slice[4];
    double w[4];
} bf_corners;

brdffit_status bf_warp_build(bf_warp *w, const bf_tensor_field *f, size_t n_slices,
                             const brdffit_allocator *a, brdffit_error *err);
void bf_warp_free(bf_warp *w, const brdffit_allocator *a);
/* The warp of slice `slice` at the uniform point s: u, and the density. */
double bf_warp_sample(const bf_warp *w, size_t slice, const double s[2], double u[2]);
/* The inverse, with the slices of c interpolated: s, and the density. */
double bf_warp_invert(const bf_warp *w, const bf_corners *c, const double u[2], double s[2]);
/* Bilinear interpolation of the float32 field f over an nx x ny block
 * starting at element base, at pos in [0, 1]^2 (clamped). */
double bf_bilinear(const bf_tensor_field *f, size_t base, size_t nx, size_t ny,
                   const double pos[2]);

/* A checked RGL file. */
typedef struct rgl_file {
    bf_tensor t;
    const bf_tensor_field *theta_i, *phi_i, *ndf, *sigma, *vndf, *values;
    size_t n_phi, n_theta, nc, nx, ny;
    int jacobian, isotropic, reduction;
    bf_warp warp;
} rgl_file;

/* The cosine of the view below which a sample is dropped (marked
 * missing when resampled): the file stores f_r cos theta_o. */
#define BF_RGL_MIN_COS 1e-6

brdffit_status bf_rgl_open(rgl_file *f, const unsigned char *data, size_t size,
                           const brdffit_allocator *a, brdffit_error *err);
void bf_rgl_close(rgl_file *f, const brdffit_allocator *a);
brdffit_status bf_rgl_scattered(brdffit_grid **out, const rgl_file *f,
                                const brdffit_allocator *a, brdffit_error *err);
brdffit_status bf_rgl_regular(brdffit_grid **out, const rgl_file *f, const brdffit_axes *axes,
                              const brdffit_allocator *a, brdffit_error *err);

#endif /* BRDFFIT_RGL_INTERNAL_H */
