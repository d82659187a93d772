/* A writer of small RGL .bsdf tensor files from an analytic BRDF, for the
 * loader tests. Its warp is chosen so that the format's piecewise warp is
 * exact and has a closed form written here independently of the library:
 * the VNDF of light b is (1 + A_b x)(1 + B y), which bilinear
 * interpolation reproduces, so the warp of the unit square is the inverse
 * of two quadratic CDFs. */
#ifndef BRDFFIT_RGL_WRITER_H
#define BRDFFIT_RGL_WRITER_H

#include <stddef.h>

/* f_r (1/sr) of channel c for light wi and view wo (unit vectors). */
typedef double (*fx_brdf_fn)(const double wi[3], const double wo[3], size_t c);

typedef struct fx_rgl_spec {
    size_t n_theta, n_phi;   /* light directions */
    double theta_i[16];      /* radians */
    double phi_i[4];         /* radians */
    size_t nx, ny;           /* samples per light */
    size_t nc;               /* channels */
    int rgb;                 /* 1: an "rgb" field (nc = 3); 0: "spectra" + "wavelengths" */
    int jacobian;            /* the jacobian flag */
    fx_brdf_fn brdf;
} fx_rgl_spec;

/* The file (malloc'ed; *size receives its length). */
unsigned char *fx_rgl_file(const fx_rgl_spec *spec, size_t *size);

/* The closed-form warp of light (phi index a, theta index b): the uniform
 * point s (clamped as the format does) to u, and its density. */
double fx_rgl_warp(const fx_rgl_spec *spec, size_t b, const double s[2], double u[2]);
/* Its inverse: u to s. */
void fx_rgl_warp_inverse(const fx_rgl_spec *spec, size_t b, const double u[2], double s[2]);
/* The NDF and sigma fields' functions (linear, so stored exactly). */
double fx_rgl_ndf(const double u[2]);
double fx_rgl_sigma(const double u[2]);
/* The microfacet normal of u for the light azimuth phi_i (isotropic). */
void fx_rgl_normal(const double u[2], double phi_i, double m[3]);

#endif /* BRDFFIT_RGL_WRITER_H */
