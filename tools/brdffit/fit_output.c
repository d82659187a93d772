/* brdffit fit: the summary, JSON and CSV forms of a result. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fit_result.h"

void fit_result_free(fit_result *r)
{
    free(r->params);
    free(r->se);
    free(r->cov);
    r->cov = NULL;
    free(r->shader_cd);
    free(r->shader_cs);
    free(r->stages);
    free(r->history);
    free(r->held);
    r->held = NULL;
    r->params = r->se = r->shader_cd = r->shader_cs = r->history = r->lambdas = NULL;
    r->stages = NULL;
}

static const char *const covariance_names[] = {"classic", "sandwich"};

#define N_NAMES(names) (sizeof names / sizeof *names)

/* The index of `name` among n names, or n. */
static size_t name_index(const char *const *names, size_t n, const char *name)
{
    size_t k = 0;
    while (k < n && strcmp(name, names[k]) != 0) k++;
    return k;
}

const char *cli_covariance_name(int covariance)
{
    return covariance >= 0 && (size_t)covariance < N_NAMES(covariance_names)
               ? covariance_names[covariance]
               : "unknown";
}

int cli_parse_covariance(const char *name, int *out)
{
    size_t k = name_index(covariance_names, N_NAMES(covariance_names), name);
    if (k == N_NAMES(covariance_names)) return 0;
    *out = (int)k;
    return 1;
}

const char *cli_stop_token(brdffit_stop_reason reason)
{
    switch (reason) {
    case BRDFFIT_STOP_NONE: return "none";
    case BRDFFIT_STOP_GRADIENT: return "gradient";
    case BRDFFIT_STOP_STEP: return "step";
    case BRDFFIT_STOP_COST: return "cost";
    case BRDFFIT_STOP_MAX_ITERATIONS: return "max-iterations";
    case BRDFFIT_STOP_MAX_EVALUATIONS: return "max-evaluations";
    case BRDFFIT_STOP_CANCELLED: return "cancelled";
    case BRDFFIT_STOP_CALLBACK: return "callback";
    case BRDFFIT_STOP_ZERO_COST: return "zero-cost";
    case BRDFFIT_STOP_STALLED: return "stalled";
    }
    return "unknown";
}

static const char *const objective_names[] = {"squares", "log", "cube-root", "relative"};

const char *cli_objective_name(brdffit_objective objective)
{
    return (size_t)objective < N_NAMES(objective_names) ? objective_names[objective] : "unknown";
}

int cli_parse_objective(const char *name, brdffit_objective *out)
{
    size_t k = name_index(objective_names, N_NAMES(objective_names), name);
    if (k == N_NAMES(objective_names)) return 0;
    *out = (brdffit_objective)k;
    return 1;
}

const char *cli_pipeline_name(brdffit_pipeline p)
{
    switch (p) {
    case BRDFFIT_PIPELINE_AUTO: return "auto";
    case BRDFFIT_PIPELINE_JOINT: return "joint";
    case BRDFFIT_PIPELINE_TWO_STAGE: return "two-stage";
    }
    return "unknown";
}

/* Entries of parameter k in the vector: 1 shared, or one per channel. */
static size_t param_width(const fit_result *r, size_t k)
{
    const brdffit_param_info *p = brdffit_model_param(r->model, k);
    return p->flags & BRDFFIT_PARAM_PER_CHANNEL ? r->n_channels : 1;
}

static double param_at(const fit_result *r, const double *v, size_t k, size_t c)
{
    return v[brdffit_model_vector_index(r->model, k, c, r->n_channels)];
}

void cli_weighting_names(cli_buf *b, unsigned weighting, const char *sep)
{
    int sa = (weighting & BRDFFIT_WEIGHT_SOLID_ANGLE) != 0;
    int cos = (weighting & BRDFFIT_WEIGHT_COSINE) != 0;
    if (sa) cli_buf_puts(b, "solid-angle");
    if (sa && cos) cli_buf_puts(b, sep);
    if (cos) cli_buf_puts(b, "cosine");
    if (!sa && !cos) cli_buf_puts(b, "none");
}

/* Degrees, rounded to 1e-9 deg so that 75 deg reads back as 75. */
static double degrees(double rad)
{
    return floor(rad * 180.0 / 3.14159265358979323846 * 1e9 + 0.5) / 1e9;
}

/* --- summary ------------------------------------------------------------------ */

/* One line with cap, weighting, clear coat and plausibility when any is
 * not the default. */
static void summary_settings(cli_buf *b, const fit_result *r)
{
    if (fabs(degrees(r->cap) - 75.0) < 1e-9 && r->weighting == BRDFFIT_WEIGHT_DEFAULT &&
        r->clearcoat == 0.0 && r->plausible == 1)
        return;
    cli_buf_printf(b, "  %-12scap %.6g deg, weighting ", "settings", degrees(r->cap));
    cli_weighting_names(b, r->weighting, " and ");
    if (r->clearcoat > 0.0)
        cli_buf_printf(b, ", clear coat R0 %.6g", r->clearcoat);
    else
        cli_buf_puts(b, ", no clear coat");
    if (r->plausible != 1) cli_buf_printf(b, ", plausibility %d", r->plausible);
    cli_buf_puts(b, "\n");
}

static void summary_param(cli_buf *b, const fit_result *r, size_t k)
{
    size_t c, n = param_width(r, k);
    /* names of 12 characters or more ("clearcoatRoughness") still get a space */
    int held = r->held != NULL && r->held[k];
    cli_buf_printf(b, "  %-11s ", brdffit_model_param(r->model, k)->name);
    for (c = 0; c < n; c++) {
        cli_buf_printf(b, "%s%.6g", c ? ", " : "", param_at(r, r->params, k, c));
        if (!held) cli_buf_printf(b, " +- %.2g", param_at(r, r->se, k, c));
    }
    cli_buf_puts(b, held ? " (held)\n" : "\n");
}

static void summary_list(cli_buf *b, const double *v, size_t n)
{
    size_t c;
    for (c = 0; c < n; c++) cli_buf_printf(b, " %.6g", v[c]);
}

void fit_summary(cli_buf *b, const fit_result *r)
{
    size_t k, n_decl = brdffit_model_param_count(r->model);
    cli_buf_printf(b, "%s\n", r->path);
    cli_buf_printf(b, "  %-12s%s, %zu channel%s, %zu samples, %zu inside the cap\n", "data",
                   r->source, r->n_channels, r->n_channels == 1 ? "" : "s", r->n_samples,
                   r->n_active);
    cli_buf_printf(b, "  %-12s%s, pipeline %s", "model", brdffit_model_name(r->model),
                   cli_pipeline_name(r->pipeline));
    if (r->objective != CLI_DEFAULT_OBJECTIVE)
        cli_buf_printf(b, ", objective %s", cli_objective_name(r->objective));
    if (r->covariance != 0) cli_buf_printf(b, ", %s errors", cli_covariance_name(r->covariance));
    cli_buf_puts(b, "\n");
    summary_settings(b, r);
    for (k = 0; k < n_decl; k++) summary_param(b, r, k);
    cli_buf_printf(b, "  %-12s", "shader");
    if (r->has_shader) {
        cli_buf_printf(b, "Rs %.6g; cd", r->rs);
        summary_list(b, r->shader_cd, r->n_channels);
        cli_buf_puts(b, "; cs");
        summary_list(b, r->shader_cs, r->n_channels);
        cli_buf_puts(b, "\n");
    } else
        cli_buf_puts(b, "none (needs colours cd and cs with max(cs) < 1)\n");
    cli_buf_printf(b, "  %-12se %.6g, E %.6g, cost %.6g\n", "errors", r->rms, r->ngan, r->cost);
    cli_buf_printf(b, "  %-12s%zu (%s), %s\n", "iterations", r->iterations,
                   brdffit_stop_reason_string(r->stop),
                   r->converged ? "converged" : "not converged");
    for (k = 0; k < r->n_warnings; k++)
        cli_buf_printf(b, "  %-12s%s: %s\n", k == 0 ? "warnings" : "",
                       brdffit_warning_name(r->warnings[k].bit), r->warnings[k].text);
    cli_buf_printf(b, "  %-12s%.0f ms\n", "fit time", r->fit_ms);
}

void fit_warnings_report(const fit_result *r)
{
    size_t k;
    for (k = 0; k < r->n_warnings; k++)
        cli_error(r->path, "warning: %s (%s)", r->warnings[k].text,
                  brdffit_warning_name(r->warnings[k].bit));
}

/* --- JSON -------------------------------------------------------------------------- */

static void json_array(cli_buf *b, const double *v, size_t n)
{
    size_t c;
    cli_buf_puts(b, "[");
    for (c = 0; c < n; c++) {
        if (c) cli_buf_puts(b, ", ");
        cli_buf_json_number(b, v[c]);
    }
    cli_buf_puts(b, "]");
}

/* {"name": x, "name": [..], ...} of a parameter vector. */
static void json_params(cli_buf *b, const fit_result *r, const double *v)
{
    size_t k, c, n_decl = brdffit_model_param_count(r->model);
    cli_buf_puts(b, "{");
    for (k = 0; k < n_decl; k++) {
        const brdffit_param_info *p = brdffit_model_param(r->model, k);
        if (k) cli_buf_puts(b, ", ");
        cli_buf_json_string(b, p->name);
        cli_buf_puts(b, ": ");
        if (!(p->flags & BRDFFIT_PARAM_PER_CHANNEL)) {
            cli_buf_json_number(b, param_at(r, v, k, 0));
            continue;
        }
        cli_buf_puts(b, "[");
        for (c = 0; c < r->n_channels; c++) {
            if (c) cli_buf_puts(b, ", ");
            cli_buf_json_number(b, param_at(r, v, k, c));
        }
        cli_buf_puts(b, "]");
    }
    cli_buf_puts(b, "}");
}

/* The name of every entry of the parameter vector, in its order: NAME for
 * a shared parameter, NAME_C for channel C's (as the CSV columns). */
static void json_vector_names(cli_buf *b, const fit_result *r)
{
    size_t i, k, c, n_decl = brdffit_model_param_count(r->model);
    cli_buf_puts(b, "[");
    for (i = 0; i < r->n_params; i++) {
        int found = 0;
        if (i) cli_buf_puts(b, ", ");
        for (k = 0; k < n_decl && !found; k++)
            for (c = 0; c < param_width(r, k) && !found; c++) {
                const char *name = brdffit_model_param(r->model, k)->name;
                char label[96];
                if (brdffit_model_vector_index(r->model, k, c, r->n_channels) != i) continue;
                found = 1;
                if (!(brdffit_model_param(r->model, k)->flags & BRDFFIT_PARAM_PER_CHANNEL))
                    cli_format(label, sizeof label, "%s", name);
                else
                    cli_format(label, sizeof label, "%s_%zu", name, c);
                cli_buf_json_string(b, label);
            }
        if (!found) cli_buf_puts(b, "null");
    }
    cli_buf_puts(b, "]");
}

/* A variance the correlation can divide by: neither 0 (held, at a bound)
 * nor HUGE_VAL (not determined). */
static int usable_variance(double v)
{
    return v > 0.0 && isfinite(v);
}

/* "correlation": {"names": [...], "matrix": [[...], ...]} of the
 * covariance, null entries for parameters without a usable variance; null
 * when the fit kept no covariance. */
static void json_correlation(cli_buf *b, const fit_result *r)
{
    size_t i, j, p = r->n_params;
    cli_buf_puts(b, ", \"correlation\": ");
    if (r->cov == NULL) {
        cli_buf_puts(b, "null");
        return;
    }
    cli_buf_puts(b, "{\"names\": ");
    json_vector_names(b, r);
    cli_buf_puts(b, ", \"matrix\": [");
    for (i = 0; i < p; i++) {
        double vi = r->cov[i * p + i];
        cli_buf_puts(b, i ? ", [" : "[");
        for (j = 0; j < p; j++) {
            double vj = r->cov[j * p + j], x;
            if (j) cli_buf_puts(b, ", ");
            if (!usable_variance(vi) || !usable_variance(vj)) {
                cli_buf_puts(b, "null");
                continue;
            }
            x = i == j ? 1.0 : r->cov[i * p + j] / (sqrt(vi) * sqrt(vj));
            cli_buf_json_number(b, x > 1.0 ? 1.0 : x < -1.0 ? -1.0 : x);
        }
        cli_buf_puts(b, "]");
    }
    cli_buf_puts(b, "]}");
}

static void json_failure(cli_buf *b, const fit_result *r)
{
    cli_buf_puts(b, "{\"file\": ");
    cli_buf_json_string(b, r->path);
    cli_buf_puts(b, ", \"error\": {\"status\": ");
    cli_buf_json_string(b, brdffit_status_name(r->status));
    cli_buf_puts(b, ", \"message\": ");
    cli_buf_json_string(b, r->error);
    cli_buf_puts(b, "}}\n");
}

/* "held": [NAME, ...]: the parameters the fit held */
static void json_held(cli_buf *b, const fit_result *r)
{
    size_t k, n = 0;
    cli_buf_puts(b, ", \"held\": [");
    for (k = 0; r->held != NULL && k < brdffit_model_param_count(r->model); k++) {
        if (!r->held[k]) continue;
        if (n++) cli_buf_puts(b, ", ");
        cli_buf_json_string(b, brdffit_model_param(r->model, k)->name);
    }
    cli_buf_puts(b, "]");
}

/* "warnings": [{"name": ..., "text": ...}, ...] */
static void json_warnings(cli_buf *b, const fit_result *r)
{
    size_t k;
    cli_buf_puts(b, ", \"warnings\": [");
    for (k = 0; k < r->n_warnings; k++) {
        cli_buf_puts(b, k ? ", {\"name\": " : "{\"name\": ");
        cli_buf_json_string(b, brdffit_warning_name(r->warnings[k].bit));
        cli_buf_puts(b, ", \"text\": ");
        cli_buf_json_string(b, r->warnings[k].text);
        cli_buf_puts(b, "}");
    }
    cli_buf_puts(b, "]");
}

void fit_json(cli_buf *b, const fit_result *r)
{
    if (!r->fitted) {
        json_failure(b, r);
        return;
    }
    cli_buf_puts(b, "{\"file\": ");
    cli_buf_json_string(b, r->path);
    cli_buf_puts(b, ", \"model\": ");
    cli_buf_json_string(b, brdffit_model_name(r->model));
    cli_buf_puts(b, ", \"pipeline\": ");
    cli_buf_json_string(b, cli_pipeline_name(r->pipeline));
    cli_buf_printf(b, ", \"channels\": %zu, \"params\": ", r->n_channels);
    json_params(b, r, r->params);
    cli_buf_puts(b, ", \"shader\": ");
    if (r->has_shader) {
        cli_buf_puts(b, "{\"Rs\": ");
        cli_buf_json_number(b, r->rs);
        cli_buf_puts(b, ", \"cd\": ");
        json_array(b, r->shader_cd, r->n_channels);
        cli_buf_puts(b, ", \"cs\": ");
        json_array(b, r->shader_cs, r->n_channels);
        cli_buf_puts(b, "}");
    } else
        cli_buf_puts(b, "null");
    cli_buf_puts(b, ", \"errors\": {\"rms\": ");
    cli_buf_json_number(b, r->rms);
    cli_buf_puts(b, ", \"ngan\": ");
    cli_buf_json_number(b, r->ngan);
    cli_buf_puts(b, ", \"cost\": ");
    cli_buf_json_number(b, r->cost);
    cli_buf_printf(b, "}, \"iterations\": %zu, \"stop\": ", r->iterations);
    cli_buf_json_string(b, cli_stop_token(r->stop));
    cli_buf_puts(b, ", \"fit_ms\": ");
    cli_buf_json_number(b, r->fit_ms);
    cli_buf_puts(b, ", \"std_errors\": ");
    json_params(b, r, r->se);
    cli_buf_puts(b, ", \"std_errors_estimator\": ");
    cli_buf_json_string(b, cli_covariance_name(r->covariance));
    json_correlation(b, r);
    cli_buf_puts(b, ", \"source\": ");
    cli_buf_json_string(b, r->source);
    cli_buf_printf(b, ", \"samples\": %zu, \"active_samples\": %zu", r->n_samples, r->n_active);
    json_warnings(b, r);
    json_held(b, r);
    fit_history_json(b, r);
    cli_buf_puts(b, ", \"objective\": ");
    cli_buf_json_string(b, cli_objective_name(r->objective));
    cli_buf_puts(b, ", \"cap_deg\": ");
    cli_buf_json_number(b, degrees(r->cap));
    cli_buf_puts(b, ", \"weighting\": [");
    if (r->weighting & BRDFFIT_WEIGHT_SOLID_ANGLE) cli_buf_puts(b, "\"solid-angle\"");
    if ((r->weighting & BRDFFIT_WEIGHT_SOLID_ANGLE) && (r->weighting & BRDFFIT_WEIGHT_COSINE))
        cli_buf_puts(b, ", ");
    if (r->weighting & BRDFFIT_WEIGHT_COSINE) cli_buf_puts(b, "\"cosine\"");
    cli_buf_puts(b, "], \"clearcoat_r0\": ");
    cli_buf_json_number(b, r->clearcoat);
    cli_buf_printf(b, ", \"max_iterations\": %zu, \"plausible\": %d", r->max_iterations,
                   r->plausible);
    fit_exports_json(b, r);
    cli_buf_puts(b, "}\n");
}

/* --- CSV ------------------------------------------------------------------------ */

static int has_shader_columns(const fit_result *r)
{
    size_t k;
    return brdffit_model_param_find(r->model, "cd", &k) == BRDFFIT_OK &&
           brdffit_model_param_find(r->model, "cs", &k) == BRDFFIT_OK;
}

/* Column names of a parameter vector, each with a prefix. */
static void csv_param_names(cli_buf *b, const fit_result *r, const char *prefix)
{
    size_t k, c, n_decl = brdffit_model_param_count(r->model);
    for (k = 0; k < n_decl; k++) {
        const char *name = brdffit_model_param(r->model, k)->name;
        if (!(brdffit_model_param(r->model, k)->flags & BRDFFIT_PARAM_PER_CHANNEL))
            cli_buf_printf(b, ",%s%s", prefix, name);
        else
            for (c = 0; c < r->n_channels; c++) cli_buf_printf(b, ",%s%s_%zu", prefix, name, c);
    }
}

void fit_csv_header(cli_buf *b, const fit_result *r)
{
    size_t c;
    cli_buf_puts(b, "file,model,pipeline,channels");
    csv_param_names(b, r, "");
    csv_param_names(b, r, "se_");
    if (has_shader_columns(r)) {
        cli_buf_puts(b, ",shader_Rs");
        for (c = 0; c < r->n_channels; c++) cli_buf_printf(b, ",shader_cd_%zu", c);
        for (c = 0; c < r->n_channels; c++) cli_buf_printf(b, ",shader_cs_%zu", c);
    }
    cli_buf_puts(b, ",rms,ngan,cost,iterations,stop,fit_ms,warnings");
    cli_buf_puts(b, ",objective,cap_deg,weighting,clearcoat_r0,max_iterations,plausible,converged");
    fit_exports_csv_header(b, r);
}

static void csv_number(cli_buf *b, double x)
{
    if (isfinite(x))
        cli_buf_printf(b, ",%.17g", x);
    else
        cli_buf_puts(b, ",");
}

static void csv_vector(cli_buf *b, const double *v, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++) csv_number(b, v[i]);
}

/* The vector in declaration order (the library's layout is that order). */
static void csv_params(cli_buf *b, const fit_result *r, const double *v)
{
    size_t k, c, n_decl = brdffit_model_param_count(r->model);
    for (k = 0; k < n_decl; k++)
        for (c = 0; c < param_width(r, k); c++) csv_number(b, param_at(r, v, k, c));
}

void fit_csv_row(cli_buf *b, const fit_result *r)
{
    size_t c;
    cli_buf_csv_field(b, r->path);
    cli_buf_puts(b, ",");
    cli_buf_csv_field(b, brdffit_model_name(r->model));
    cli_buf_printf(b, ",%s,%zu", cli_pipeline_name(r->pipeline), r->n_channels);
    csv_params(b, r, r->params);
    csv_params(b, r, r->se);
    if (has_shader_columns(r) && r->has_shader) {
        csv_number(b, r->rs);
        csv_vector(b, r->shader_cd, r->n_channels);
        csv_vector(b, r->shader_cs, r->n_channels);
    } else if (has_shader_columns(r))
        for (c = 0; c < 1 + 2 * r->n_channels; c++) cli_buf_puts(b, ",");
    csv_number(b, r->rms);
    csv_number(b, r->ngan);
    csv_number(b, r->cost);
    cli_buf_printf(b, ",%zu,%s", r->iterations, cli_stop_token(r->stop));
    csv_number(b, r->fit_ms);
    cli_buf_puts(b, ",");
    for (c = 0; c < r->n_warnings; c++)
        cli_buf_printf(b, "%s%s", c ? ";" : "", brdffit_warning_name(r->warnings[c].bit));
    cli_buf_printf(b, ",%s", cli_objective_name(r->objective));
    csv_number(b, degrees(r->cap));
    cli_buf_puts(b, ",");
    cli_weighting_names(b, r->weighting, ";");
    csv_number(b, r->clearcoat);
    cli_buf_printf(b, ",%zu,%d", r->max_iterations, r->plausible);
    cli_buf_printf(b, ",%d", r->converged ? 1 : 0);
    fit_exports_csv_row(b, r);
    cli_buf_puts(b, "\n");
}
