/* Fit the simplified Ashikhmin-Shirley model to a CSV measurement and print
 * the parameters, the error number and the renderer form.
 *
 *     fit_file FILE.csv
 */
#include <stdio.h>

#include <brdffit/brdffit.h>

int main(int argc, char **argv)
{
    brdffit_grid *grid = NULL;
    brdffit_model *model = NULL;
    brdffit_fit *fit = NULL;
    brdffit_error err;
    double p[7], rs, cd[3], cs[3], e;
    int rc = 1;

    if (argc != 2) {
        fprintf(stderr, "usage: fit_file FILE.csv\n");
        return 2;
    }
    if (brdffit_load_csv(&grid, argv[1], NULL, &err) != BRDFFIT_OK) {
        fprintf(stderr, "fit_file: %s: %s\n", argv[1], err.message);
        return 1;
    }
    if (brdffit_grid_channel_count(grid) != 3) {
        fprintf(stderr, "fit_file: %s: expected three channels\n", argv[1]);
        goto done;
    }
    if (brdffit_model_create(&model, "ashikhmin-shirley", NULL, &err) != BRDFFIT_OK ||
        brdffit_fit_create(&fit, grid, model, NULL, &err) != BRDFFIT_OK) {
        fprintf(stderr, "fit_file: %s\n", err.message);
        goto done;
    }
    if (brdffit_fit_run(fit) != BRDFFIT_OK) {
        fprintf(stderr, "fit_file: %s: %s\n", argv[1], brdffit_fit_message(fit));
        goto done;
    }
    brdffit_fit_params(fit, p); /* ns, cd[3], cs[3] */
    brdffit_fit_error(fit, BRDFFIT_METRIC_RMS, BRDFFIT_ALL_CHANNELS, &e);
    printf("ns = %g  cd = (%g %g %g)  cs = (%g %g %g)  e = %g\n", p[0], p[1], p[2], p[3], p[4],
           p[5], p[6], e);
    if (brdffit_fit_shader(fit, &rs, cd, cs) == BRDFFIT_OK)
        printf("shader: Rs = %g  cd = (%g %g %g)  cs = (%g %g %g)\n", rs, cd[0], cd[1], cd[2],
               cs[0], cs[1], cs[2]);
    rc = 0;
done:
    brdffit_fit_destroy(fit);
    brdffit_model_destroy(model);
    brdffit_grid_destroy(grid);
    return rc;
}
