/* Writes the measurements of the command tests: an ASTM E1392 scan and an
 * RGL .bsdf file (tests/support/rgl_writer.c) of the same analytic,
 * reciprocal material, a Lambertian base and a Blinn-Phong lobe.
 *
 *   make_measurements ASTM_PATH RGL_PATH */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "rgl_writer.h"

#define PI 3.14159265358979323846

static double material(const double wi[3], const double wo[3], size_t c)
{
    static const double kd[3] = {0.15, 0.3, 0.45};
    double h[3] = {wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]};
    double len = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    return kd[c] / PI + 0.4 * 22.0 / (8.0 * PI) * pow(h[2] / len, 20.0);
}

static void dir(double t, double p, double d[3])
{
    d[0] = sin(t) * cos(p), d[1] = sin(t) * sin(p), d[2] = cos(t);
}

/* Light 0..80 step 10 at azimuth 0; view 0..88 step 4, azimuth 0..180 step 15. */
static int write_astm(const char *path)
{
    FILE *f = fopen(path, "w");
    int ti, to, po, n = 9 * 23 * 13;
    if (f == NULL) return 0;
    fprintf(f, "SOURCE \"libbrdffit command tests\"\nSAMPLE \"analytic\"\nNUM_POINTS %d\n", n);
    fprintf(f, "VARS theta_i,phi_i,theta_s,phi_s,R,G,B\n");
    for (ti = 0; ti <= 80; ti += 10)
        for (to = 0; to <= 88; to += 4)
            for (po = 0; po <= 180; po += 15) {
                double wi[3], wo[3];
                size_t c;
                dir(ti * PI / 180.0, 0.0, wi);
                dir(to * PI / 180.0, po * PI / 180.0, wo);
                fprintf(f, "%d,0,%d,%d", ti, to, po);
                for (c = 0; c < 3; c++) fprintf(f, ",%.9g", material(wi, wo, c));
                fprintf(f, "\n");
            }
    return fclose(f) == 0;
}

static int write_rgl(const char *path)
{
    fx_rgl_spec sp = {0};
    size_t k, size = 0;
    unsigned char *data;
    FILE *f;
    int ok;
    sp.n_theta = 9, sp.n_phi = 1;
    for (k = 0; k < 9; k++) sp.theta_i[k] = (double)k * 10.0 * PI / 180.0;
    sp.nx = sp.ny = 17, sp.nc = 3, sp.rgb = 1, sp.jacobian = 1, sp.brdf = material;
    data = fx_rgl_file(&sp, &size);
    f = data != NULL ? fopen(path, "wb") : NULL;
    ok = f != NULL && fwrite(data, 1, size, f) == size;
    if (f != NULL && fclose(f) != 0) ok = 0;
    free(data);
    return ok;
}

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: make_measurements ASTM_PATH RGL_PATH\n");
        return 2;
    }
    return write_astm(argv[1]) && write_rgl(argv[2]) ? 0 : 1;
}
