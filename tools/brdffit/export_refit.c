/* brdffit fit --gltf / --mtlx of a model that is not the export's own BRDF:
 * the export's model fitted to the same data with the same settings (auto
 * pipeline, no start values), so that the file holds a renderer's material
 * fitted in the renderer's own lobes rather than a conversion. docs/cli.md
 * says which model each export takes. */
#include "export_gltf.h"

#include <stdlib.h>
#include <string.h>

int cli_export_native(const char *model_name, int mtlx)
{
    if (cli_gltf_exportable(model_name)) return 1;
    return mtlx && strncmp(model_name, "openpbr", 7) == 0;
}

const char *cli_export_target(const char *model_name, int mtlx)
{
    const size_t n = strlen(model_name);
    const int two = (n > 2 && strcmp(model_name + n - 2, "-2") == 0) ||
                    (n > 5 && strcmp(model_name + n - 5, "-coat") == 0);
    if (mtlx) return two ? "openpbr-coat" : "openpbr";
    return two ? CLI_GLTF_COAT_MODEL : CLI_GLTF_MODEL;
}

/* The fitted run's data settings, then the auto pipeline. */
static brdffit_status copy_settings(const brdffit_fit *from, brdffit_fit *to)
{
    static const brdffit_fit_setting kept[] = {BRDFFIT_FIT_CAP, BRDFFIT_FIT_WEIGHTING,
                                               BRDFFIT_FIT_CLEARCOAT, BRDFFIT_FIT_THREADS,
                                               BRDFFIT_FIT_MAX_ITERATIONS, BRDFFIT_FIT_OBJECTIVE};
    brdffit_status st = BRDFFIT_OK;
    size_t i;
    for (i = 0; i < sizeof kept / sizeof kept[0] && st == BRDFFIT_OK; i++) {
        double v;
        st = brdffit_fit_get(from, kept[i], &v);
        if (st == BRDFFIT_OK) st = brdffit_fit_set(to, kept[i], v);
    }
    if (st == BRDFFIT_OK) st = brdffit_fit_set(to, BRDFFIT_FIT_PIPELINE, BRDFFIT_PIPELINE_AUTO);
    return st;
}

int cli_export_refit(const brdffit_grid *grid, const brdffit_fit *fitted, const char *target,
                     cli_refit *out, char *msg, size_t msg_size)
{
    brdffit_fit *fit = NULL;
    brdffit_error err;
    brdffit_status st;
    memset(out, 0, sizeof *out);
    if (brdffit_model_create(&out->model, target, NULL, &err) != BRDFFIT_OK) {
        cli_format(msg, msg_size, "%s", err.message);
        return -1;
    }
    out->params = malloc(brdffit_model_vector_size(out->model, brdffit_grid_channel_count(grid)) *
                         sizeof(double));
    if (out->params == NULL) {
        cli_format(msg, msg_size, "out of memory");
    } else if ((st = brdffit_fit_create(&fit, grid, out->model, NULL, &err)) != BRDFFIT_OK) {
        cli_format(msg, msg_size, "refit with %s: %s", target, err.message);
    } else if (copy_settings(fitted, fit) != BRDFFIT_OK || brdffit_fit_run(fit) != BRDFFIT_OK ||
               brdffit_fit_params(fit, out->params) != BRDFFIT_OK ||
               brdffit_fit_error(fit, BRDFFIT_METRIC_RMS, BRDFFIT_ALL_CHANNELS, &out->rms) !=
                   BRDFFIT_OK ||
               brdffit_fit_error(fit, BRDFFIT_METRIC_NGAN, BRDFFIT_ALL_CHANNELS, &out->ngan) !=
                   BRDFFIT_OK ||
               brdffit_fit_error(fit, BRDFFIT_METRIC_COST, BRDFFIT_ALL_CHANNELS, &out->cost) !=
                   BRDFFIT_OK) {
        cli_format(msg, msg_size, "refit with %s: %s", target, brdffit_fit_message(fit));
    } else {
        brdffit_fit_destroy(fit);
        return 0;
    }
    brdffit_fit_destroy(fit);
    cli_refit_free(out);
    return -1;
}

void cli_refit_free(cli_refit *r)
{
    free(r->params);
    brdffit_model_destroy(r->model);
    r->params = NULL;
    r->model = NULL;
}
