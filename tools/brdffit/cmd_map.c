/* brdffit map FILE: fit a model to every texel of a texel map in one file
 * (map.h) with brdffit_fit_many(), and write the parameter map as CSV. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fit_result.h"
#include "map.h"

#define PI 3.14159265358979323846

static const char map_help[] =
    "usage: brdffit map [OPTIONS] FILE\n"
    "\n"
    "Fit a model to every texel of a texel map (a CSV file whose first column,\n"
    "texel, names the texel of each row; docs/formats.md) and write the\n"
    "parameter map: one CSV row per texel.\n"
    "\n"
    "  --out OUT.csv         the parameter map (written whole or not at all);\n"
    "                        default: standard output\n"
    "  --model NAME          model to fit (brdffit models); default ashikhmin-shirley\n"
    "  --pipeline P          auto (default), joint or two-stage\n"
    "  --objective O         cube-root (default), log, relative or squares\n"
    "  --start LIST          start values, NAME=VALUE or NAME=V1:V2:V3, comma-separated\n"
    "  --cap DEG             angle cap in degrees, (0, 90]; default 75\n"
    "  --no-solid-angle      do not weight residuals by the solid angle of the cell\n"
    "  --no-cosine           do not weight residuals by cos theta_i\n"
    "  --clearcoat R0        divide the data by 1 - F(theta_i), Schlick F with R0\n"
    "  --max-iterations N    iteration limit of each Levenberg-Marquardt run\n"
    "  --threads N           threads fitting texels, 1 to 64; default 1\n"
    "\n"
    "A texel that cannot be fitted gets empty parameter fields and its status;\n"
    "the others are still fitted. The summary goes to standard error.\n"
    "Exit status: 0 when every texel was fitted, 1 when some failed or the\n"
    "file cannot be read, 2 for usage errors.\n";

typedef struct map_opts {
    const char *model_name, *start_text, *out;
    brdffit_pipeline pipeline;
    brdffit_objective objective;
    double cap, clearcoat;
    unsigned weighting;
    size_t threads, max_iterations;
} map_opts;

typedef struct map_result {
    const map_data *m;
    const brdffit_model *model;
    size_t n_vec;
    brdffit_many_out out;
} map_result;

/* --- options ------------------------------------------------------------------ */

static int option_value(map_opts *o, const char *name, const char *value)
{
    double x = 0.0;
    if (strcmp(name, "model") == 0) o->model_name = value;
    else if (strcmp(name, "start") == 0) o->start_text = value;
    else if (strcmp(name, "out") == 0) o->out = value;
    else if (strcmp(name, "objective") == 0) {
        if (!cli_parse_objective(value, &o->objective))
            return cli_usage_error("map", "--objective is squares, log, cube-root or relative");
    } else if (strcmp(name, "pipeline") == 0) {
        if (strcmp(value, "auto") == 0) o->pipeline = BRDFFIT_PIPELINE_AUTO;
        else if (strcmp(value, "joint") == 0) o->pipeline = BRDFFIT_PIPELINE_JOINT;
        else if (strcmp(value, "two-stage") == 0) o->pipeline = BRDFFIT_PIPELINE_TWO_STAGE;
        else return cli_usage_error("map", "--pipeline is auto, joint or two-stage");
    } else if (strcmp(name, "cap") == 0) {
        if (!cli_parse_double(value, &x) || !(x > 0.0 && x <= 90.0))
            return cli_usage_error("map", "--cap needs degrees in (0, 90], not \"%s\"", value);
        o->cap = x * PI / 180.0;
    } else if (strcmp(name, "clearcoat") == 0) {
        if (!cli_parse_double(value, &o->clearcoat) || !(o->clearcoat >= 0.0) ||
            !(o->clearcoat < 1.0))
            return cli_usage_error("map", "--clearcoat needs a number in [0, 1)");
    } else if (strcmp(name, "threads") == 0) {
        if (!cli_parse_size(value, &o->threads) || o->threads < 1 || o->threads > 64)
            return cli_usage_error("map", "--threads needs a count from 1 to 64");
    } else if (strcmp(name, "max-iterations") == 0) {
        if (!cli_parse_size(value, &o->max_iterations) || o->max_iterations < 1 ||
            o->max_iterations > 1000000)
            return cli_usage_error("map", "--max-iterations needs a count from 1 to 1000000");
    }
    return 0;
}

/* The file name, or NULL after --help (*rc 0) or a usage error (*rc 2). */
static const char *parse_options(map_opts *o, int argc, char **argv, int *rc)
{
    static const cli_option options[] = {
        {"help", 0},     {"out", 1},      {"model", 1},          {"pipeline", 1},
        {"objective", 1}, {"start", 1},   {"cap", 1},            {"no-solid-angle", 0},
        {"no-cosine", 0}, {"clearcoat", 1}, {"max-iterations", 1}, {"threads", 1},
        {NULL, 0}};
    cli_args a;
    const char *name, *value, *file = NULL;
    int r;
    *rc = CLI_USAGE;
    cli_args_init(&a, argc, argv, options);
    while ((r = cli_next(&a, &name, &value)) > 0) {
        if (name == NULL) {
            if (file != NULL) {
                cli_usage_error("map", "one texel map at a time");
                return NULL;
            }
            file = value;
        } else if (strcmp(name, "help") == 0) {
            fputs(map_help, stdout);
            *rc = CLI_OK;
            return NULL;
        } else if (strcmp(name, "no-solid-angle") == 0) {
            o->weighting &= ~(unsigned)BRDFFIT_WEIGHT_SOLID_ANGLE;
        } else if (strcmp(name, "no-cosine") == 0) {
            o->weighting &= ~(unsigned)BRDFFIT_WEIGHT_COSINE;
        } else if (value != NULL && option_value(o, name, value) != 0) {
            return NULL;
        }
    }
    if (r < 0) return NULL;
    if (file == NULL) cli_usage_error("map", "no texel map given");
    return file;
}

/* --- the fit --------------------------------------------------------------------- */

static int configure(brdffit_fit *fit, const map_opts *o, const brdffit_model *model,
                     size_t nc, char *msg, size_t msg_size)
{
    cli_assign_list start = {0, NULL};
    double *vec = NULL;
    int rc = 0;
    if (brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, (double)o->pipeline) ||
        brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, (double)o->objective) ||
        brdffit_fit_set(fit, BRDFFIT_FIT_CAP, o->cap) ||
        brdffit_fit_set(fit, BRDFFIT_FIT_WEIGHTING, (double)o->weighting) ||
        brdffit_fit_set(fit, BRDFFIT_FIT_CLEARCOAT, o->clearcoat) ||
        brdffit_fit_set(fit, BRDFFIT_FIT_THREADS, (double)o->threads) ||
        (o->max_iterations > 0 &&
         brdffit_fit_set(fit, BRDFFIT_FIT_MAX_ITERATIONS, (double)o->max_iterations))) {
        cli_format(msg, msg_size, "%s", brdffit_fit_message(fit));
        return -1;
    }
    if (o->start_text == NULL) return 0;
    vec = malloc(brdffit_fit_param_count(fit) * sizeof *vec);
    if (vec == NULL) {
        cli_format(msg, msg_size, "out of memory");
        rc = -1;
    } else if (cli_assign_parse(&start, model, o->start_text, msg, msg_size) != 0 ||
               cli_assign_vector(&start, model, nc, vec, msg, msg_size) != 0) {
        rc = -1;
    } else if (brdffit_fit_set_start(fit, vec) != BRDFFIT_OK) {
        cli_format(msg, msg_size, "--start: %s", brdffit_fit_message(fit));
        rc = -1;
    }
    cli_assign_free(&start);
    free(vec);
    return rc;
}

static int alloc_out(map_result *r, size_t n)
{
    brdffit_many_out *o = &r->out;
    memset(o, 0, sizeof *o);
    o->struct_size = sizeof *o;
    o->status = calloc(n, sizeof *o->status);
    o->params = calloc(n * r->n_vec, sizeof *o->params);
    o->std_errors = calloc(n * r->n_vec, sizeof *o->std_errors);
    o->cost = calloc(n, sizeof(double));
    o->rms = calloc(n, sizeof(double));
    o->ngan = calloc(n, sizeof(double));
    o->stop = calloc(n, sizeof *o->stop);
    o->iterations = calloc(n, sizeof *o->iterations);
    o->warnings = calloc(n, sizeof *o->warnings);
    return o->status && o->params && o->std_errors && o->cost && o->rms && o->ngan && o->stop &&
           o->iterations && o->warnings;
}

static void free_out(brdffit_many_out *o)
{
    free(o->status), free(o->params), free(o->std_errors), free(o->cost), free(o->rms);
    free(o->ngan), free(o->stop), free(o->iterations), free(o->warnings);
}

/* --- the parameter map ------------------------------------------------------------- */

static void names(cli_buf *b, const brdffit_model *model, size_t nc, const char *prefix)
{
    size_t k, c;
    for (k = 0; k < brdffit_model_param_count(model); k++) {
        const brdffit_param_info *p = brdffit_model_param(model, k);
        if (!(p->flags & BRDFFIT_PARAM_PER_CHANNEL)) cli_buf_printf(b, ",%s%s", prefix, p->name);
        else
            for (c = 0; c < nc; c++) cli_buf_printf(b, ",%s%s_%zu", prefix, p->name, c);
    }
}

static void number(cli_buf *b, double x)
{
    if (isfinite(x)) cli_buf_printf(b, ",%.17g", x);
    else cli_buf_puts(b, ",");
}

/* Declaration order, channel by channel, as `brdffit fit --csv`. */
static void vector(cli_buf *b, const map_result *r, const double *v)
{
    size_t k, c, nc = r->m->n_channels;
    for (k = 0; k < brdffit_model_param_count(r->model); k++) {
        int per = (brdffit_model_param(r->model, k)->flags & BRDFFIT_PARAM_PER_CHANNEL) != 0;
        for (c = 0; c < (per ? nc : 1); c++)
            number(b, v[brdffit_model_vector_index(r->model, k, c, nc)]);
    }
}

static void row(cli_buf *b, const map_result *r, size_t t)
{
    const brdffit_many_out *o = &r->out;
    unsigned bit;
    int first = 1;
    cli_buf_csv_field(b, r->m->texel[t]);
    vector(b, r, o->params + t * r->n_vec);
    vector(b, r, o->std_errors + t * r->n_vec);
    number(b, o->rms[t]);
    number(b, o->ngan[t]);
    number(b, o->cost[t]);
    cli_buf_printf(b, ",%zu,%s,%s,", o->iterations[t], cli_stop_token(o->stop[t]),
                   o->status[t] == BRDFFIT_OK ? "ok" : brdffit_status_name(o->status[t]));
    for (bit = 1; bit != 0; bit <<= 1)
        if (o->warnings[t] & bit) {
            cli_buf_printf(b, "%s%s", first ? "" : ";", brdffit_warning_name(bit));
            first = 0;
        }
    cli_buf_puts(b, "\n");
}

static int write_map(FILE *f, void *ctx, char *msg, size_t msg_size)
{
    const map_result *r = ctx;
    cli_buf b;
    size_t t;
    int rc = 0;
    cli_buf_init(&b);
    cli_buf_puts(&b, "texel");
    names(&b, r->model, r->m->n_channels, "");
    names(&b, r->model, r->m->n_channels, "se_");
    cli_buf_puts(&b, ",rms,ngan,cost,iterations,stop,status,warnings\n");
    for (t = 0; t < r->m->n_texels; t++) row(&b, r, t);
    if (b.failed) {
        cli_format(msg, msg_size, "out of memory");
        rc = -1;
    } else if (fwrite(b.data, 1, b.len, f) != b.len) {
        cli_format(msg, msg_size, "write error");
        rc = -1;
    }
    cli_buf_free(&b);
    return rc;
}

/* Per-texel failures on stderr; returns how many failed. */
static size_t report_failures(const char *path, const map_result *r)
{
    size_t t, failed = 0;
    for (t = 0; t < r->m->n_texels; t++)
        if (r->out.status[t] != BRDFFIT_OK) {
            if (failed++ < 20)
                cli_error(path, "texel \"%s\": %s", r->m->texel[t],
                          brdffit_status_string(r->out.status[t]));
        }
    if (failed > 20) cli_error(path, "... %zu texels failed in all", failed);
    return failed;
}

static int fit_map(const char *path, const map_opts *o, map_data *m, brdffit_model *model)
{
    char msg[CLI_MSG_SIZE];
    brdffit_fit *fit = NULL;
    map_result r;
    double t0, ms;
    size_t failed;
    int rc = CLI_FAILED;
    r.m = m, r.model = model, r.n_vec = brdffit_model_vector_size(model, m->n_channels);
    memset(&r.out, 0, sizeof r.out);
    if (brdffit_fit_create(&fit, m->grid, model, NULL, NULL) != BRDFFIT_OK || !alloc_out(&r, m->n_texels)) {
        cli_error(path, "out of memory");
    } else if (configure(fit, o, model, m->n_channels, msg, sizeof msg) != 0) {
        cli_error(path, "%s", msg);
    } else {
        t0 = cli_now_ms();
        if (brdffit_fit_many(fit, m->n_texels, m->values, m->missing, &r.out, NULL, NULL) != 0) {
            cli_error(path, "%s", brdffit_fit_message(fit));
        } else {
            ms = cli_now_ms() - t0;
            failed = report_failures(path, &r);
            fprintf(stderr,
                    "brdffit: %s: %zu texels of %zu samples x %zu channels, %zu fitted, %zu "
                    "failed, %.1f ms (%.0f fits/s, %zu threads)\n",
                    path, m->n_texels, m->n_samples, m->n_channels, m->n_texels - failed, failed,
                    ms, ms > 0.0 ? 1e3 * (double)m->n_texels / ms : 0.0, o->threads);
            rc = failed > 0 ? CLI_FAILED : CLI_OK;
            if (o->out != NULL ? cli_write_atomic(o->out, write_map, &r, msg, sizeof msg) != 0
                               : write_map(stdout, &r, msg, sizeof msg) != 0) {
                cli_error(o->out, "%s", msg);
                rc = CLI_FAILED;
            }
        }
    }
    free_out(&r.out);
    brdffit_fit_destroy(fit);
    return rc;
}

int cli_cmd_map(int argc, char **argv)
{
    map_opts o = {"ashikhmin-shirley",
                  NULL,
                  NULL,
                  BRDFFIT_PIPELINE_AUTO,
                  CLI_DEFAULT_OBJECTIVE,
                  BRDFFIT_DEFAULT_CAP,
                  0.0,
                  BRDFFIT_WEIGHT_DEFAULT,
                  1,
                  0};
    char msg[CLI_MSG_SIZE];
    brdffit_model *model = NULL;
    brdffit_error err;
    map_data m;
    int rc;
    const char *path = parse_options(&o, argc, argv, &rc);
    if (path == NULL) return rc;
    if (brdffit_model_create(&model, o.model_name, NULL, &err) != BRDFFIT_OK)
        return cli_usage_error("map", "%s", err.message);
    if (map_read(path, &m, msg, sizeof msg) != 0) {
        cli_error(path, "%s", msg);
        brdffit_model_destroy(model);
        return CLI_FAILED;
    }
    rc = fit_map(path, &o, &m, model);
    map_free(&m);
    brdffit_model_destroy(model);
    return rc;
}
