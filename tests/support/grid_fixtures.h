/* Helpers for the grid and loader tests: small grids from known functions,
 * a CSV writer, a MERL writer with an independent half/difference angle
 * computation, and temporary directories. */
#ifndef BRDFFIT_GRID_FIXTURES_H
#define BRDFFIT_GRID_FIXTURES_H

#include <stddef.h>

#include "brdffit/brdffit.h"

/* A smooth positive test function of a regular sample and a channel. */
double fx_value(double theta_i, double theta_o, double phi_o, size_t channel);

/* Interleaved values of fx_value() over the axes (caller frees with free()). */
double *fx_values(const brdffit_axes *axes, size_t n_channels);

/* Degree axes, converted with DEG() into the radian arrays of *axes. */
typedef struct fx_axes {
    double deg[3][64];
    double rad[3][64];
    brdffit_axes axes;
} fx_axes;
void fx_axes_set(fx_axes *a, const double *ti, size_t n_ti, const double *to, size_t n_to,
                 const double *po, size_t n_po);

/* CSV text (malloc'ed, NUL-terminated) of a regular grid given by degree
 * axes and interleaved values; missing values (mask may be NULL) are
 * written as `missing_text`. Numbers use %.17g. Rows are written in a
 * shuffled order when `shuffle` is non-zero. */
char *fx_csv_regular(const fx_axes *a, size_t n_channels, const double *values,
                     const unsigned char *mask, const char *missing_text, int shuffle);

/* A temporary directory; paths inside it; cleanup removes the listed files. */
typedef struct fx_tempdir {
    char path[256];
} fx_tempdir;
int fx_tempdir_make(fx_tempdir *t);
void fx_tempdir_path(const fx_tempdir *t, const char *name, char *out, size_t size);
int fx_write_file(const char *path, const void *data, size_t size);
void fx_tempdir_remove(fx_tempdir *t, const char *const *names, size_t n_names);

/* MERL files. */
#define FX_MERL_CELLS ((size_t)90 * 90 * 180)
#define FX_MERL_SIZE ((size_t)12 + 3 * FX_MERL_CELLS * 8)
/* Value function at the centre angles of a cell; negative = unmeasured. */
typedef double (*fx_merl_fn)(double theta_h, double theta_d, double phi_d, int channel);
/* A complete MERL file image (malloc'ed, FX_MERL_SIZE bytes) with the
 * given header dimensions. */
unsigned char *fx_merl_image(fx_merl_fn fn, int d0, int d1, int d2);
void fx_put_le32(unsigned char *p, int v);
void fx_put_le64(unsigned char *p, double v);
/* Centre angles of MERL cell indices. */
double fx_merl_theta_h(size_t ih);
double fx_merl_theta_d(size_t id);
double fx_merl_phi_d(size_t ip);
/* Half/difference angles of a direction pair, computed by projecting l on
 * the axes of the half-vector frame (an independent route from the
 * library's rotations); phi_d folded into [0, pi). */
void fx_half_diff(const double l[3], const double v[3], double *theta_h, double *theta_d,
                  double *phi_d);
/* Fractional MERL index coordinates of half/difference angles. */
void fx_merl_coords(double theta_h, double theta_d, double phi_d, double pos[3]);
/* Unit vector of (theta, phi). */
void fx_dir(double theta, double phi, double out[3]);

#endif
