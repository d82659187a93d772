/* brdffit fit FILE...: fit a model to every file, files in parallel, and
 * report in the order the files were given. */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "export_gltf.h"
#include "fit_result.h"

#define PI 3.14159265358979323846

static const char fit_help[] =
    "usage: brdffit fit [OPTIONS] FILE...\n"
    "\n"
    "Fit a model to each measurement (CSV, or MERL .binary resampled onto the\n"
    "default axes) and print the result.\n"
    "\n"
    "  --model NAME          model to fit (brdffit models); default ashikhmin-shirley\n"
    "  --pipeline P          auto (default: global search, no start values), joint\n"
    "                        or two-stage (the thesis's method with --objective\n"
    "                        squares, from start values)\n"
    "  --objective O         cube-root (default: the best rendered match), log,\n"
    "                        relative or squares (the thesis's weighted squares;\n"
    "                        docs/fitting.md)\n"
    "  --start LIST          start values, NAME=VALUE (all channels) or\n"
    "                        NAME=V1:V2:V3 (one per channel), comma-separated\n"
    "  --cap DEG             angle cap in degrees, (0, 90]; default 75\n"
    "  --no-solid-angle      do not weight residuals by the solid angle of the cell\n"
    "  --no-cosine           do not weight residuals by cos theta_i\n"
    "  --clearcoat R0        divide the data by 1 - F(theta_i), Schlick F with R0\n"
    "  --fix LIST            hold parameters at values, NAME=VALUE or\n"
    "                        NAME=V1:V2:V3, comma-separated (every pipeline)\n"
    "  --free LIST           let parameters the model holds by default (F0) move,\n"
    "                        NAME,NAME,...\n"
    "  --plausible N         auto's energy bounds: 0 none, 1 (default) cd <= 1 and\n"
    "                        each lobe's albedo <= 1 (tabulated), 2 every term's\n"
    "                        albedo <= 1 by the integral (slower)\n"
    "  --damping POLICY      Levenberg-Marquardt damping: nielsen (default),\n"
    "                        marquardt or thesis\n"
    "  --max-iterations N    iteration limit of each Levenberg-Marquardt run\n"
    "  --errors E            standard errors: classic (default: one noise level for\n"
    "                        every weighted residual) or sandwich (HC3: any noise\n"
    "                        per value, e.g. multiplicative; docs/fitting.md)\n"
    "  --threads N           files fitted in parallel (one file: threads of the fit)\n"
    "  --json                one JSON object per file on stdout, one per line\n"
    "  --csv OUT             append one row per fitted file to OUT (header when new)\n"
    "  --preview OUT.png     write a picture of the fit; with several files OUT\n"
    "                        must contain %s, replaced by each file's base name\n"
    "  --report OUT.html     write one self-contained HTML page per file: settings,\n"
    "                        parameters, warnings and the preview (%s as above)\n"
    "  --gain G              brightness of the preview textures; default 3\n"
    "  --gamma G             gamma of the preview pictures; default 2.2\n"
    "  --strict              a fit with warnings (parameter at a bound, albedo\n"
    "                        above 1, iteration limit, ...) counts as failed\n"
    "  --gltf OUT.gltf       write the fitted material on a sphere as a glTF 2.0\n"
    "                        asset (%s as for --preview); other models than gltf\n"
    "                        and gltf-clearcoat are refitted with one of them\n"
    "  --mtlx OUT.mtlx       write the material as a MaterialX document with an\n"
    "                        open_pbr_surface (%s likewise); other models than the\n"
    "                        glTF and OpenPBR ones are refitted with openpbr(-coat)\n"
    "  --mtlx-shader S       the MaterialX shader: open_pbr_surface (default),\n"
    "                        standard_surface, or both\n"
    "\n"
    "Warnings about a fit go to standard error, and into the summary and JSON.\n"
    "Exit status: 0 when every file was fitted, 1 when some failed (or, with\n"
    "--strict, has warnings), 2 for usage errors.\n";

typedef struct fit_opts {
    const char *model_name, *start_text, *csv_path, *preview, *gltf, *mtlx, *report;
    const char *fix_text, *free_text;
    const brdffit_damping *damping; /* NULL: the library's default */
    brdffit_pipeline pipeline;
    brdffit_objective objective;
    double cap, clearcoat, gain, gamma;
    unsigned weighting, mtlx_shaders;
    size_t threads, max_iterations, plausible;
    int covariance; /* BRDFFIT_FIT_COVARIANCE */
    int json, strict;
} fit_opts;

/* Shared by the workers; the mutex guards next, done and n_done. */
typedef struct fit_run {
    const fit_opts *opts;
    const brdffit_model *model;
    const cli_assign_list *start;
    const fit_holds *holds;
    char **files;
    size_t n_files, next, n_done;
    fit_result *results;
    int *done;
    pthread_mutex_t lock;
    pthread_cond_t cond;
} fit_run;

/* --- one file ---------------------------------------------------------------- */

static int fail(fit_result *r, brdffit_status st, const char *msg)
{
    r->status = st;
    cli_format(r->error, sizeof r->error, "%s", msg);
    return -1;
}

static int configure(brdffit_fit *fit, const fit_run *run, fit_result *r)
{
    const fit_opts *o = run->opts;
    char msg[CLI_MSG_SIZE];
    brdffit_status st = BRDFFIT_OK;
    double threads = run->n_files == 1 ? (double)(o->threads > 64 ? 64 : o->threads) : 1.0;
    if ((st = brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, (double)o->pipeline)) != BRDFFIT_OK ||
        (st = brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, (double)o->objective)) != BRDFFIT_OK ||
        (st = brdffit_fit_set(fit, BRDFFIT_FIT_COVARIANCE, (double)o->covariance)) != BRDFFIT_OK ||
        (st = brdffit_fit_set(fit, BRDFFIT_FIT_PLAUSIBLE, (double)o->plausible)) != BRDFFIT_OK ||
        (st = brdffit_fit_set(fit, BRDFFIT_FIT_CAP, o->cap)) != BRDFFIT_OK ||
        (st = brdffit_fit_set(fit, BRDFFIT_FIT_WEIGHTING, (double)o->weighting)) != BRDFFIT_OK ||
        (st = brdffit_fit_set(fit, BRDFFIT_FIT_CLEARCOAT, o->clearcoat)) != BRDFFIT_OK ||
        (st = brdffit_fit_set(fit, BRDFFIT_FIT_THREADS, threads)) != BRDFFIT_OK ||
        (st = brdffit_fit_set_damping(fit, o->damping)) != BRDFFIT_OK ||
        (o->max_iterations > 0 && (st = brdffit_fit_set(fit, BRDFFIT_FIT_MAX_ITERATIONS,
                                                        (double)o->max_iterations)) != BRDFFIT_OK))
        return fail(r, st, brdffit_fit_message(fit));
    if (fit_holds_apply(run->holds, run->start, fit, run->model, r->n_channels, msg, sizeof msg))
        return fail(r, BRDFFIT_E_INVALID_ARGUMENT, msg);
    return 0;
}

static void collect_warnings(const brdffit_fit *fit, fit_result *r)
{
    unsigned all = brdffit_fit_warnings(fit), bit;
    r->n_warnings = 0;
    for (bit = 1; bit != 0 && r->n_warnings < CLI_MAX_WARNINGS; bit <<= 1) {
        fit_warning *w = &r->warnings[r->n_warnings];
        if (!(all & bit)) continue;
        w->bit = bit;
        if (brdffit_fit_warning_text(fit, bit, w->text, sizeof w->text) != BRDFFIT_OK)
            w->text[0] = '\0';
        r->n_warnings++;
    }
}

/* The settings the fit ran with, as the library holds them. */
static void collect_settings(const brdffit_fit *fit, fit_result *r)
{
    double v = 0.0;
    if (brdffit_fit_get(fit, BRDFFIT_FIT_CAP, &r->cap) != BRDFFIT_OK) r->cap = 0.0;
    if (brdffit_fit_get(fit, BRDFFIT_FIT_WEIGHTING, &v) == BRDFFIT_OK) r->weighting = (unsigned)v;
    if (brdffit_fit_get(fit, BRDFFIT_FIT_CLEARCOAT, &r->clearcoat) != BRDFFIT_OK)
        r->clearcoat = 0.0;
    if (brdffit_fit_get(fit, BRDFFIT_FIT_MAX_ITERATIONS, &v) == BRDFFIT_OK)
        r->max_iterations = (size_t)v;
    if (brdffit_fit_get(fit, BRDFFIT_FIT_PLAUSIBLE, &v) == BRDFFIT_OK) r->plausible = (int)v;
    if (brdffit_fit_get(fit, BRDFFIT_FIT_COVARIANCE, &v) == BRDFFIT_OK) r->covariance = (int)v;
}

/* The covariance for the JSON record's correlation (only --json shows it);
 * left NULL when the fit keeps none (BRDFFIT_E_TOO_LARGE). */
static int collect_covariance(const brdffit_fit *fit, fit_result *r)
{
    brdffit_status st;
    if (r->n_params > BRDFFIT_FIT_MAX_PARAMS) return 0;
    r->cov = malloc(r->n_params * r->n_params * sizeof(double));
    if (r->cov == NULL) return fail(r, BRDFFIT_E_OUT_OF_MEMORY, "out of memory");
    st = brdffit_fit_covariance(fit, r->cov);
    if (st == BRDFFIT_OK) return 0;
    free(r->cov);
    r->cov = NULL;
    return st == BRDFFIT_E_TOO_LARGE ? 0 : fail(r, st, brdffit_fit_message(fit));
}

static int collect(brdffit_fit *fit, const fit_run *run, fit_result *r)
{
    size_t nc = r->n_channels;
    r->params = calloc(r->n_params, sizeof(double));
    r->se = calloc(r->n_params, sizeof(double));
    r->shader_cd = calloc(nc, sizeof(double));
    r->shader_cs = calloc(nc, sizeof(double));
    if (r->params == NULL || r->se == NULL || r->shader_cd == NULL || r->shader_cs == NULL)
        return fail(r, BRDFFIT_E_OUT_OF_MEMORY, "out of memory");
    if (brdffit_fit_params(fit, r->params) != BRDFFIT_OK ||
        brdffit_fit_std_errors(fit, r->se) != BRDFFIT_OK ||
        brdffit_fit_error(fit, BRDFFIT_METRIC_RMS, BRDFFIT_ALL_CHANNELS, &r->rms) != BRDFFIT_OK ||
        brdffit_fit_error(fit, BRDFFIT_METRIC_NGAN, BRDFFIT_ALL_CHANNELS, &r->ngan) != BRDFFIT_OK ||
        brdffit_fit_error(fit, BRDFFIT_METRIC_COST, BRDFFIT_ALL_CHANNELS, &r->cost) != BRDFFIT_OK)
        return fail(r, BRDFFIT_E_NOT_READY, brdffit_fit_message(fit));
    r->has_shader = brdffit_fit_shader(fit, &r->rs, r->shader_cd, r->shader_cs) == BRDFFIT_OK;
    r->iterations = brdffit_fit_iterations(fit);
    r->stop = brdffit_fit_stop_reason(fit);
    if (fit_history_collect(fit, r) != 0) return fail(r, BRDFFIT_E_OUT_OF_MEMORY, "out of memory");
    if (run->opts->json && collect_covariance(fit, r) != 0) return -1;
    r->held = fit_holds_held(run->holds, run->model);
    if (r->held == NULL) return fail(r, BRDFFIT_E_OUT_OF_MEMORY, "out of memory");
    collect_warnings(fit, r);
    collect_settings(fit, r);
    r->fitted = 1;
    return 0;
}

/* --report: the page with the preview's PNG bytes. */
static void write_report(const cli_preview_input *in, const fit_run *run, fit_result *r)
{
    char msg[CLI_MSG_SIZE], full[CLI_MSG_SIZE + 300];
    char *name = cli_preview_name(run->opts->report, r->path);
    cli_buf png;
    cli_buf_init(&png);
    if (name == NULL) {
        fail(r, BRDFFIT_E_OUT_OF_MEMORY, "report: out of memory");
        return;
    }
    if (cli_preview_png(in, &png, msg, sizeof msg) != 0 ||
        cli_report_write(name, r, &png, msg, sizeof msg) != 0) {
        cli_format(full, sizeof full, "report %s: %s", name, msg);
        fail(r, BRDFFIT_E_IO, full);
    }
    cli_buf_free(&png);
    free(name);
}

/* --preview and --report. */
static void write_preview(const brdffit_grid *grid, const fit_run *run, fit_result *r)
{
    cli_preview_input in;
    char msg[CLI_MSG_SIZE], title[CLI_MSG_SIZE], base[128];
    char *name = run->opts->preview != NULL ? cli_preview_name(run->opts->preview, r->path)
                                            : NULL;
    if (name == NULL && run->opts->preview != NULL) {
        fail(r, BRDFFIT_E_OUT_OF_MEMORY, "preview: out of memory");
        return;
    }
    in.grid = grid;
    in.model = run->model;
    in.params = r->params;
    in.history = r->history;
    in.n_history = r->n_history;
    in.stages = r->stages;
    in.n_stages = r->n_stages;
    in.gain = run->opts->gain;
    in.gamma = run->opts->gamma;
    in.rms = r->rms;
    in.ngan = r->ngan;
    in.cost = r->cost;
    in.cap = run->opts->cap;
    cli_base_name(r->path, base, sizeof base);
    cli_format(title, sizeof title, "%s: %s, %s pipeline, %s objective, %zu iterations, stop: %s",
               base, brdffit_model_name(run->model), cli_pipeline_name(r->pipeline),
               cli_objective_name(r->objective), r->iterations, cli_stop_token(r->stop));
    in.title = title;
    if (name != NULL && cli_preview_write(&in, name, msg, sizeof msg) != 0) {
        char full[CLI_MSG_SIZE + 300];
        cli_format(full, sizeof full, "preview %s: %s", name, msg);
        fail(r, BRDFFIT_E_IO, full);
    }
    if (run->opts->report != NULL) write_report(&in, run, r);
    free(name);
}

/* The note of a refit export, on standard error (one line) and in the file. */
static void refit_note(const fit_run *run, const fit_result *r, const cli_refit *rf, int mtlx,
                       char *note, size_t size)
{
    cli_format(note, size,
               "the %s export holds %s refitted to the data (auto, e %.6g, E %.6g): the "
               "fitted model %s is not %s",
               mtlx ? "MaterialX" : "glTF", brdffit_model_name(rf->model), rf->rms, rf->ngan,
               brdffit_model_name(run->model), mtlx ? "a MaterialX shader's BRDF" : "glTF's BRDF");
    fprintf(stderr, "brdffit: %s: note: %s\n", r->path, note);
}

/* What the records say of a written export (export_record.c). */
static void record_export(fit_export *e, const char *file, const brdffit_model *model,
                          const cli_refit *rf, const fit_result *r)
{
    e->written = 1;
    e->refit = rf != NULL;
    cli_format(e->file, sizeof e->file, "%s", file);
    cli_format(e->model, sizeof e->model, "%s", brdffit_model_name(model));
    e->rms = rf ? rf->rms : r->rms;
    e->ngan = rf ? rf->ngan : r->ngan;
    e->cost = rf ? rf->cost : r->cost;
}

/* --gltf or --mtlx (`mtlx`): the file named by `pattern` for this input;
 * a model that is not the export's own is refitted first (export_refit.c). */
static void write_export(const fit_run *run, const brdffit_grid *grid, const brdffit_fit *fit,
                         fit_result *r, const char *pattern, int mtlx)
{
    char msg[CLI_MSG_SIZE], full[CLI_MSG_SIZE + 300], base[128], note[CLI_MSG_SIZE];
    char *name = cli_preview_name(pattern, r->path);
    const char *what = mtlx ? "MaterialX" : "glTF";
    const brdffit_model *model = run->model;
    const double *params = r->params;
    cli_refit rf = {NULL, NULL, 0.0, 0.0, 0.0};
    int rc = 0, refit = !cli_export_native(brdffit_model_name(model), mtlx);
    cli_base_name(r->path, base, sizeof base);
    if (name == NULL) {
        cli_format(full, sizeof full, "%s: out of memory", what);
        fail(r, BRDFFIT_E_OUT_OF_MEMORY, full);
        return;
    }
    if (refit) {
        rc = cli_export_refit(grid, fit, cli_export_target(brdffit_model_name(model), mtlx), &rf,
                              msg, sizeof msg);
        if (rc == 0) {
            refit_note(run, r, &rf, mtlx, note, sizeof note);
            model = rf.model;
            params = rf.params;
        }
    }
    if (rc == 0)
        rc = mtlx ? cli_mtlx_export(name, model, params, r->n_channels, base,
                                    run->opts->mtlx_shaders, refit ? note : NULL, msg, sizeof msg)
                  : cli_gltf_export(name, model, params, r->n_channels, base, refit ? note : NULL,
                                    msg, sizeof msg);
    if (rc != 0) {
        cli_format(full, sizeof full, "%s %s: %s", what, name, msg);
        fail(r, BRDFFIT_E_IO, full);
    } else
        record_export(&r->exports[mtlx], name, model, refit ? &rf : NULL, r);
    cli_refit_free(&rf);
    free(name);
}

static void fit_one(const fit_run *run, fit_result *r)
{
    brdffit_grid *grid = NULL;
    brdffit_fit *fit = NULL;
    brdffit_error err;
    brdffit_status st;
    char msg[CLI_MSG_SIZE];
    double t0;
    r->exports[0].asked = run->opts->gltf != NULL;
    r->exports[1].asked = run->opts->mtlx != NULL;
    if ((st = cli_load(r->path, &grid, &r->source, msg, sizeof msg)) != BRDFFIT_OK) {
        fail(r, st, msg);
        return;
    }
    r->n_channels = brdffit_grid_channel_count(grid);
    r->n_samples = brdffit_grid_sample_count(grid);
    r->n_active = brdffit_grid_active_count(grid, run->opts->cap);
    r->n_params = brdffit_model_vector_size(run->model, r->n_channels);
    if ((st = brdffit_fit_create(&fit, grid, run->model, NULL, &err)) != BRDFFIT_OK)
        fail(r, st, err.message);
    else if (configure(fit, run, r) == 0) {
        t0 = cli_now_ms();
        st = brdffit_fit_run(fit);
        r->fit_ms = cli_now_ms() - t0;
        if (st != BRDFFIT_OK)
            fail(r, st, brdffit_fit_message(fit));
        else if (collect(fit, run, r) == 0 && (run->opts->preview != NULL || run->opts->report != NULL))
            write_preview(grid, run, r);
        if (r->fitted && run->opts->gltf != NULL)
            write_export(run, grid, fit, r, run->opts->gltf, 0);
        if (r->fitted && run->opts->mtlx != NULL)
            write_export(run, grid, fit, r, run->opts->mtlx, 1);
    }
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
}

static void *worker(void *arg)
{
    fit_run *run = arg;
    for (;;) {
        size_t i;
        pthread_mutex_lock(&run->lock);
        i = run->next < run->n_files ? run->next++ : run->n_files;
        pthread_mutex_unlock(&run->lock);
        if (i == run->n_files) return NULL;
        fit_one(run, &run->results[i]);
        pthread_mutex_lock(&run->lock);
        run->done[i] = 1;
        run->n_done++;
        pthread_cond_broadcast(&run->cond);
        pthread_mutex_unlock(&run->lock);
    }
}

/* --- output, in file order ---------------------------------------------------- */

static void progress(const fit_run *run, size_t n_done, int clear)
{
    enum { WIDTH = 30 };
    char bar[WIDTH + 1];
    size_t i, filled = run->n_files ? n_done * WIDTH / run->n_files : 0;
    if (clear) {
        fprintf(stderr, "\r%*s\r", WIDTH + 40, "");
        return;
    }
    for (i = 0; i < WIDTH; i++) bar[i] = i < filled ? '#' : '.';
    bar[WIDTH] = '\0';
    fprintf(stderr, "\r[%s] %zu/%zu files", bar, n_done, run->n_files);
    fflush(stderr);
}

static int output(const fit_run *run, fit_result *r, int show_progress)
{
    char msg[CLI_MSG_SIZE];
    cli_buf b;
    int ok = r->fitted && r->error[0] == '\0' && !(run->opts->strict && r->n_warnings > 0);
    cli_buf_init(&b);
    if (show_progress) progress(run, 0, 1);
    if (r->error[0] != '\0') cli_error(r->path, "%s", r->error);
    fit_warnings_report(r);
    if (r->n_samples > 0 && (r->n_samples - r->n_active) * 4 > r->n_samples)
        cli_error(r->path,
                  "warning: the %g deg angle cap leaves out %zu of the %zu samples (%.0f %%); "
                  "--cap 90 fits them all",
                  run->opts->cap * 180.0 / PI, r->n_samples - r->n_active, r->n_samples,
                  100.0 * (double)(r->n_samples - r->n_active) / (double)r->n_samples);
    if (run->opts->json)
        fit_json(&b, r);
    else if (r->fitted)
        fit_summary(&b, r);
    if (b.len > 0) fwrite(b.data, 1, b.len, stdout);
    fflush(stdout);
    if (r->fitted && run->opts->csv_path != NULL) {
        cli_buf header, row;
        cli_buf_init(&header);
        cli_buf_init(&row);
        fit_csv_header(&header, r);
        fit_csv_row(&row, r);
        if (header.failed || row.failed) {
            cli_error(run->opts->csv_path, "out of memory");
            ok = 0;
        } else if (cli_append(run->opts->csv_path, header.data, row.data, row.len, msg,
                              sizeof msg) != 0) {
            cli_error(run->opts->csv_path, "%s (row of %s not written)", msg, r->path);
            ok = 0;
        }
        cli_buf_free(&header);
        cli_buf_free(&row);
    }
    cli_buf_free(&b);
    return ok;
}

static size_t start_workers(fit_run *run, pthread_t *threads, size_t n)
{
    size_t started = 0;
    while (started < n && pthread_create(&threads[started], NULL, worker, run) == 0) started++;
    return started;
}

static int run_all(fit_run *run)
{
    size_t n_threads = run->opts->threads < run->n_files ? run->opts->threads : run->n_files;
    pthread_t *threads = calloc(n_threads, sizeof(pthread_t));
    size_t started = threads != NULL ? start_workers(run, threads, n_threads) : 0, i;
    int all_ok = 1, show = run->n_files > 1 && isatty(fileno(stderr));
    if (started == 0) worker(run); /* no thread could be started: fit here */
    for (i = 0; i < run->n_files; i++) {
        pthread_mutex_lock(&run->lock);
        while (!run->done[i]) {
            if (show) progress(run, run->n_done, 0);
            pthread_cond_wait(&run->cond, &run->lock);
        }
        pthread_mutex_unlock(&run->lock);
        all_ok &= output(run, &run->results[i], show);
        fit_result_free(&run->results[i]);
        if (show && i + 1 < run->n_files) progress(run, run->n_done, 0);
    }
    if (show) progress(run, 0, 1);
    for (i = 0; i < started; i++) pthread_join(threads[i], NULL);
    free(threads);
    return all_ok ? CLI_OK : CLI_FAILED;
}

/* --- options ------------------------------------------------------------------ */

static int parse_pipeline(const char *s, brdffit_pipeline *p)
{
    if (strcmp(s, "auto") == 0)
        *p = BRDFFIT_PIPELINE_AUTO;
    else if (strcmp(s, "joint") == 0)
        *p = BRDFFIT_PIPELINE_JOINT;
    else if (strcmp(s, "two-stage") == 0)
        *p = BRDFFIT_PIPELINE_TWO_STAGE;
    else
        return 0;
    return 1;
}

/* A number in [lo, hi], or in [lo, hi) with hi_open. */
static int number_option(const char *name, const char *value, double lo, double hi, int hi_open,
                         double *out)
{
    double x;
    if (!cli_parse_double(value, &x) || !(x >= lo) || (hi_open ? !(x < hi) : !(x <= hi)))
        return cli_usage_error("fit", "--%s needs a number in [%g, %g%s, not \"%s\"", name, lo, hi,
                               hi_open ? ")" : "]", value);
    *out = x;
    return 0;
}

static int option_value(fit_opts *o, const char *name, const char *value)
{
    double x = 0.0;
    if (strcmp(name, "model") == 0)
        o->model_name = value;
    else if (strcmp(name, "start") == 0)
        o->start_text = value;
    else if (strcmp(name, "csv") == 0)
        o->csv_path = value;
    else if (strcmp(name, "preview") == 0)
        o->preview = value;
    else if (strcmp(name, "report") == 0)
        o->report = value;
    else if (strcmp(name, "gltf") == 0)
        o->gltf = value;
    else if (strcmp(name, "mtlx") == 0)
        o->mtlx = value;
    else if (strcmp(name, "fix") == 0)
        o->fix_text = value;
    else if (strcmp(name, "free") == 0)
        o->free_text = value;
    else if (strcmp(name, "damping") == 0) {
        if (!cli_parse_damping(value, &o->damping))
            return cli_usage_error("fit", "--damping is nielsen, marquardt or thesis");
    } else if (strcmp(name, "mtlx-shader") == 0) {
        if (strcmp(value, "open_pbr_surface") == 0)
            o->mtlx_shaders = CLI_MTLX_OPENPBR;
        else if (strcmp(value, "standard_surface") == 0)
            o->mtlx_shaders = CLI_MTLX_STANDARD;
        else if (strcmp(value, "both") == 0)
            o->mtlx_shaders = CLI_MTLX_OPENPBR | CLI_MTLX_STANDARD;
        else
            return cli_usage_error("fit", "--mtlx-shader is open_pbr_surface, standard_surface "
                                          "or both");
    } else if (strcmp(name, "errors") == 0) {
        if (!cli_parse_covariance(value, &o->covariance))
            return cli_usage_error("fit", "--errors is classic or sandwich, not \"%s\"", value);
    } else if (strcmp(name, "objective") == 0) {
        if (!cli_parse_objective(value, &o->objective))
            return cli_usage_error("fit", "--objective is squares, log, cube-root or relative");
    } else if (strcmp(name, "pipeline") == 0) {
        if (!parse_pipeline(value, &o->pipeline))
            return cli_usage_error("fit", "--pipeline is auto, joint or two-stage");
    } else if (strcmp(name, "cap") == 0) {
        if (!cli_parse_double(value, &x) || !(x > 0.0 && x <= 90.0))
            return cli_usage_error("fit", "--cap needs degrees in (0, 90], not \"%s\"", value);
        o->cap = x * PI / 180.0;
    } else if (strcmp(name, "clearcoat") == 0)
        return number_option(name, value, 0.0, 1.0, 1, &o->clearcoat);
    else if (strcmp(name, "gain") == 0)
        return number_option(name, value, 0.0, 1e6, 0, &o->gain);
    else if (strcmp(name, "gamma") == 0)
        return number_option(name, value, 0.1, 10.0, 0, &o->gamma);
    else if (strcmp(name, "threads") == 0) {
        if (!cli_parse_size(value, &o->threads) || o->threads < 1 || o->threads > 256)
            return cli_usage_error("fit", "--threads needs a count from 1 to 256");
    } else if (strcmp(name, "plausible") == 0) {
        if (!cli_parse_size(value, &o->plausible) || o->plausible > 2)
            return cli_usage_error("fit", "--plausible is 0, 1 or 2");
    } else if (strcmp(name, "max-iterations") == 0) {
        if (!cli_parse_size(value, &o->max_iterations) || o->max_iterations < 1 ||
            o->max_iterations > 1000000)
            return cli_usage_error("fit", "--max-iterations needs a count from 1 to 1000000");
    }
    return 0;
}

static int option_flag(fit_opts *o, const char *name)
{
    if (strcmp(name, "help") == 0) {
        fputs(fit_help, stdout);
        return -1;
    }
    if (strcmp(name, "json") == 0)
        o->json = 1;
    else if (strcmp(name, "strict") == 0)
        o->strict = 1;
    else if (strcmp(name, "no-solid-angle") == 0)
        o->weighting &= ~(unsigned)BRDFFIT_WEIGHT_SOLID_ANGLE;
    else if (strcmp(name, "no-cosine") == 0)
        o->weighting &= ~(unsigned)BRDFFIT_WEIGHT_COSINE;
    return 0;
}

/* Collect the files into argv's front; returns their number, or -1 (help
 * printed: exit 0) or -2 (usage error printed). */
static int parse_options(fit_opts *o, int argc, char **argv)
{
    static const cli_option options[] = {{"help", 0},      {"model", 1},     {"pipeline", 1},
                                         {"start", 1},     {"cap", 1},       {"no-solid-angle", 0},
                                         {"no-cosine", 0}, {"clearcoat", 1}, {"max-iterations", 1}, {"plausible", 1},
                                         {"threads", 1},   {"json", 0},      {"csv", 1},
                                         {"preview", 1},   {"gain", 1},      {"gamma", 1},
                                         {"strict", 0},    {"gltf", 1},      {"mtlx", 1},
                                         {"objective", 1}, {"report", 1},  {"fix", 1},
                                         {"free", 1},      {"damping", 1}, {"mtlx-shader", 1},
                                         {"errors", 1},
                                         {NULL, 0}};
    cli_args a;
    const char *name, *value;
    int r, n_files = 0;
    cli_args_init(&a, argc, argv, options);
    while ((r = cli_next(&a, &name, &value)) > 0) {
        if (name == NULL)
            argv[n_files++] = (char *)value;
        else if (value != NULL ? option_value(o, name, value) != 0
                               : (r = option_flag(o, name)) != 0)
            return r < 0 ? -1 : -2;
    }
    return r < 0 ? -2 : n_files;
}

/* Every output named from a pattern: one name per input, none an input. */
static int output_names_check(const fit_opts *o, char **files, size_t n_files)
{
    const char *const option[4] = {"preview", "gltf", "mtlx", "report"};
    const char *const pattern[4] = {o->preview, o->gltf, o->mtlx, o->report};
    size_t i;
    int rc = 0;
    for (i = 0; i < 4 && rc == 0; i++)
        if (pattern[i] != NULL) rc = cli_output_names_check(option[i], pattern[i], files, n_files);
    return rc;
}

static int check_options(const fit_opts *o, char **files, int n_files)
{
    if (n_files == 0) return cli_usage_error("fit", "no FILE given");
    if (o->preview != NULL && !cli_png_available())
        return cli_usage_error("fit", "--preview is not available: brdffit was built without "
                                      "cairo");
    if (o->preview != NULL && n_files > 1 && strstr(o->preview, "%s") == NULL)
        return cli_usage_error("fit", "--preview with several files needs %%s in its name");
    if (o->report != NULL && !cli_png_available())
        return cli_usage_error("fit", "--report is not available: brdffit was built without "
                                      "cairo");
    if (o->report != NULL && n_files > 1 && strstr(o->report, "%s") == NULL)
        return cli_usage_error("fit", "--report with several files needs %%s in its name");
    if (o->gltf != NULL && n_files > 1 && strstr(o->gltf, "%s") == NULL)
        return cli_usage_error("fit", "--gltf with several files needs %%s in its name");
    if (o->mtlx != NULL && n_files > 1 && strstr(o->mtlx, "%s") == NULL)
        return cli_usage_error("fit", "--mtlx with several files needs %%s in its name");
    return output_names_check(o, files, (size_t)n_files);
}

static int fit_files(const fit_opts *o, char **files, size_t n_files)
{
    brdffit_model *model = NULL;
    brdffit_error err;
    cli_assign_list start = {0, NULL};
    fit_holds holds;
    char msg[CLI_MSG_SIZE];
    fit_run run;
    int rc;
    size_t i;
    if (brdffit_model_create(&model, o->model_name, NULL, &err) != BRDFFIT_OK)
        return cli_usage_error("fit", "--model: %s", err.message);
    if (o->start_text != NULL &&
        cli_assign_parse(&start, model, o->start_text, msg, sizeof msg) != 0) {
        brdffit_model_destroy(model);
        return cli_usage_error("fit", "--start: %s", msg);
    }
    if (fit_holds_parse(&holds, model, o->fix_text, o->free_text, msg, sizeof msg) != 0) {
        cli_assign_free(&start);
        brdffit_model_destroy(model);
        return cli_usage_error("fit", "%s", msg);
    }
    memset(&run, 0, sizeof run);
    run.opts = o;
    run.model = model;
    run.start = &start;
    run.holds = &holds;
    run.files = files;
    run.n_files = n_files;
    run.results = calloc(n_files, sizeof(fit_result));
    run.done = calloc(n_files, sizeof(int));
    if (run.results == NULL || run.done == NULL) {
        cli_error(NULL, "out of memory");
        rc = CLI_FAILED;
    } else {
        for (i = 0; i < n_files; i++) {
            run.results[i].path = files[i];
            run.results[i].source = "";
            run.results[i].model = model;
            run.results[i].pipeline = o->pipeline;
            run.results[i].objective = o->objective;
        }
        pthread_mutex_init(&run.lock, NULL);
        pthread_cond_init(&run.cond, NULL);
        rc = run_all(&run);
        pthread_cond_destroy(&run.cond);
        pthread_mutex_destroy(&run.lock);
    }
    free(run.results);
    free(run.done);
    cli_assign_free(&start);
    fit_holds_free(&holds);
    brdffit_model_destroy(model);
    return rc;
}

int cli_cmd_fit(int argc, char **argv)
{
    fit_opts o;
    int n_files, rc;
    memset(&o, 0, sizeof o);
    o.model_name = "ashikhmin-shirley";
    o.pipeline = BRDFFIT_PIPELINE_AUTO;
    o.objective = CLI_DEFAULT_OBJECTIVE;
    o.cap = BRDFFIT_DEFAULT_CAP;
    o.weighting = BRDFFIT_WEIGHT_DEFAULT;
    o.gain = 3.0;
    o.gamma = 2.2;
    o.threads = 1;
    o.plausible = 1;
    n_files = parse_options(&o, argc, argv);
    if (n_files == -1) return CLI_OK;
    if (n_files < 0) return CLI_USAGE;
    if ((rc = check_options(&o, argv, n_files)) != 0) return rc;
    rc = fit_files(&o, argv, (size_t)n_files);
    if (o.preview != NULL || o.report != NULL) cli_preview_cleanup();
    return rc;
}
