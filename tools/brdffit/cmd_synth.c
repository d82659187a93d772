/* brdffit synth: a synthetic measurement from a model, written as CSV in
 * the grid form of docs/definitions.md, CSV measurements. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

#define PI 3.14159265358979323846
#define CHUNK 4096
#define MAX_SAMPLES 50000000

static const char synth_help[] =
    "usage: brdffit synth --model NAME [--params NAME=VALUE,...] --out FILE.csv\n"
    "                     [--channels N] [--noise SIGMA [--seed S]]\n"
    "                     [--axes TI_STEP,TO_STEP,N_PHI]\n"
    "\n"
    "Write the values of a model on a regular grid as CSV (grid form, angles in\n"
    "degrees, values with 17 significant digits).\n"
    "\n"
    "  --model NAME      a built-in model (brdffit models); default ashikhmin-shirley\n"
    "  --params LIST     NAME=VALUE sets a parameter (all channels of a per-channel\n"
    "                    one), NAME=V1:V2:V3 one value per channel; parameters not\n"
    "                    given keep their default start values\n"
    "  --channels N      channels, default 3 (named r,g,b; otherwise c1..cN)\n"
    "  --noise SIGMA     multiply every value by 1 + SIGMA * g, g standard normal,\n"
    "                    and clamp at 0; default 0 (no noise)\n"
    "  --seed S          seed of the noise, default 1\n"
    "  --axes A,B,N      theta_i = 0, A, 2A, ... <= 90 deg; theta_o = 0, B, ... <= 90\n"
    "                    deg; N azimuths from 0 to 180 deg; default 5,2.5,36 (the\n"
    "                    thesis's layout)\n"
    "  --out FILE        the CSV file, written completely or not at all\n";

typedef struct synth_job {
    const brdffit_model *model;
    const double *params;
    size_t n_channels;
    double *deg[3]; /* axes, degrees */
    size_t n[3];
    double noise;
    uint64_t rng;
    size_t seed;
} synth_job;

/* splitmix64: small, fast, and the same stream on every platform. */
static double uniform(uint64_t *state)
{
    uint64_t z = (*state += UINT64_C(0x9e3779b97f4a7c15));
    z = (z ^ (z >> 30)) * UINT64_C(0xbf58476d1ce4e5b9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94d049bb133111eb);
    z ^= z >> 31;
    return ((double)(z >> 11) + 0.5) / 9007199254740992.0; /* (0, 1) */
}

static double gauss(uint64_t *state)
{
    double u = uniform(state), v = uniform(state);
    return sqrt(-2.0 * log(u)) * cos(2.0 * PI * v);
}

/* "NAME=V" or "NAME=V1:V2:..." for every parameter, space-separated. */
static void write_params(FILE *f, const synth_job *job)
{
    size_t k, c, n_decl = brdffit_model_param_count(job->model);
    for (k = 0; k < n_decl; k++) {
        const brdffit_param_info *p = brdffit_model_param(job->model, k);
        size_t n = p->flags & BRDFFIT_PARAM_PER_CHANNEL ? job->n_channels : 1;
        fprintf(f, "%s%s=", k ? "," : "", p->name);
        for (c = 0; c < n; c++) {
            char num[32];
            cli_shortest(
                num, sizeof num,
                job->params[brdffit_model_vector_index(job->model, k, c, job->n_channels)]);
            fprintf(f, "%s%s", c ? ":" : "", num);
        }
    }
}

static void write_header(FILE *f, const synth_job *job)
{
    size_t c;
    fprintf(f, "# SYNTHETIC DATA written by brdffit synth %s: model %s, params ",
            BRDFFIT_CLI_VERSION, brdffit_model_name(job->model));
    write_params(f, job);
    if (job->noise > 0.0) fprintf(f, ", noise %g (relative), seed %zu", job->noise, job->seed);
    fprintf(f, "\n# angles in degrees, light at azimuth 180 deg, values in 1/sr\n");
    fprintf(f, "theta_i,theta_o,phi_o");
    for (c = 0; c < job->n_channels; c++) {
        if (job->n_channels == 3)
            fprintf(f, ",%c", "rgb"[c]);
        else
            fprintf(f, ",c%zu", c + 1);
    }
    fprintf(f, "\n");
}

typedef struct chunk {
    double ti[CHUNK], pi_[CHUNK], to[CHUNK], po[CHUNK];
    double *values;
} chunk;

static void chunk_angles(chunk *ch, const synth_job *job, size_t first, size_t count)
{
    size_t s;
    for (s = 0; s < count; s++) {
        size_t i = first + s, k = i % job->n[2], j = i / job->n[2] % job->n[1];
        i /= job->n[2] * job->n[1];
        ch->ti[s] = job->deg[0][i] * PI / 180.0;
        ch->pi_[s] = PI;
        ch->to[s] = job->deg[1][j] * PI / 180.0;
        ch->po[s] = job->deg[2][k] * PI / 180.0;
    }
}

static void write_rows(FILE *f, const chunk *ch, synth_job *job, size_t first, size_t count)
{
    size_t s, c;
    for (s = 0; s < count; s++) {
        size_t i = first + s, k = i % job->n[2], j = i / job->n[2] % job->n[1];
        i /= job->n[2] * job->n[1];
        fprintf(f, "%.17g,%.17g,%.17g", job->deg[0][i], job->deg[1][j], job->deg[2][k]);
        for (c = 0; c < job->n_channels; c++) {
            double v = ch->values[c * count + s];
            if (job->noise > 0.0) v *= 1.0 + job->noise * gauss(&job->rng);
            fprintf(f, ",%.17g", v > 0.0 ? v : 0.0);
        }
        fputc('\n', f);
    }
}

static int write_csv(FILE *f, void *ctx, char *msg, size_t msg_size)
{
    synth_job *job = ctx;
    size_t n = job->n[0] * job->n[1] * job->n[2], first;
    chunk *ch = malloc(sizeof *ch);
    int rc = 0;
    if (ch == NULL || (ch->values = malloc(CHUNK * job->n_channels * sizeof(double))) == NULL) {
        free(ch);
        cli_format(msg, msg_size, "out of memory");
        return -1;
    }
    write_header(f, job);
    for (first = 0; first < n && rc == 0; first += CHUNK) {
        size_t count = n - first < CHUNK ? n - first : CHUNK;
        brdffit_error err;
        chunk_angles(ch, job, first, count);
        if (brdffit_model_eval_angles(job->model, count, ch->ti, ch->pi_, ch->to, ch->po,
                                      job->n_channels, job->params, ch->values, NULL,
                                      &err) != BRDFFIT_OK) {
            cli_format(msg, msg_size, "%s", err.message);
            rc = -1;
        } else
            write_rows(f, ch, job, first, count);
    }
    free(ch->values);
    free(ch);
    return rc;
}

/* Values of the polar axis 0, step, 2 step, ... <= 90 deg, as a double so
 * that a tiny step gives a huge count (or inf) to check, never a size_t
 * conversion out of range. */
static double polar_count(double step)
{
    return floor(90.0 / step + 1e-9) + 1.0;
}

/* The axis of polar_count(step) values; n is within the sample limit. */
static size_t polar_axis(double step, double **out)
{
    size_t n = (size_t)polar_count(step), k;
    *out = malloc(n * sizeof(double));
    if (*out == NULL) return 0;
    for (k = 0; k < n; k++) (*out)[k] = (double)k * step;
    return n;
}

static size_t azimuth_axis(size_t n, double **out)
{
    size_t k;
    *out = malloc(n * sizeof(double));
    if (*out == NULL) return 0;
    for (k = 0; k < n; k++) (*out)[k] = n > 1 ? 180.0 * (double)k / (double)(n - 1) : 0.0;
    return n;
}

/* "A,B,N" with 0 < A, B <= 90 and 1 <= N <= 100000. */
static int parse_axes(const char *text, double *ti_step, double *to_step, size_t *n_phi)
{
    char buf[128], *b, *c;
    if (strlen(text) >= sizeof buf) return 0;
    strcpy(buf, text);
    b = strchr(buf, ',');
    if (b == NULL || (c = strchr(b + 1, ',')) == NULL) return 0;
    *b++ = '\0';
    *c++ = '\0';
    return cli_parse_double(buf, ti_step) && cli_parse_double(b, to_step) &&
           cli_parse_size(c, n_phi) && *ti_step > 0.0 && *ti_step <= 90.0 && *to_step > 0.0 &&
           *to_step <= 90.0 && *n_phi >= 1 && *n_phi <= 100000;
}

typedef struct synth_opts {
    const char *model, *params, *out;
    size_t channels;
    double noise, ti_step, to_step;
    size_t n_phi, seed;
} synth_opts;

static int parse_options(synth_opts *o, int argc, char **argv)
{
    static const cli_option options[] = {{"help", 0},     {"model", 1}, {"params", 1},
                                         {"channels", 1}, {"noise", 1}, {"seed", 1},
                                         {"axes", 1},     {"out", 1},   {NULL, 0}};
    cli_args a;
    const char *name, *value;
    int r;
    cli_args_init(&a, argc, argv, options);
    while ((r = cli_next(&a, &name, &value)) > 0) {
        if (name == NULL) return cli_usage_error("synth", "unexpected argument \"%s\"", value);
        if (strcmp(name, "help") == 0) {
            fputs(synth_help, stdout);
            return -1;
        }
        if (strcmp(name, "model") == 0)
            o->model = value;
        else if (strcmp(name, "params") == 0)
            o->params = value;
        else if (strcmp(name, "out") == 0)
            o->out = value;
        else if (strcmp(name, "channels") == 0) {
            if (!cli_parse_size(value, &o->channels) || o->channels < 1 || o->channels > 1000)
                return cli_usage_error("synth", "--channels needs a count from 1 to 1000");
        } else if (strcmp(name, "noise") == 0) {
            if (!cli_parse_double(value, &o->noise) || !(o->noise >= 0.0) || o->noise > 10.0)
                return cli_usage_error("synth", "--noise needs a number from 0 to 10");
        } else if (strcmp(name, "seed") == 0) {
            if (!cli_parse_size(value, &o->seed))
                return cli_usage_error("synth", "--seed needs a non-negative integer");
        } else if (!parse_axes(value, &o->ti_step, &o->to_step, &o->n_phi))
            return cli_usage_error("synth", "--axes needs TI_STEP,TO_STEP,N_PHI (steps in "
                                            "(0, 90] deg, 1 <= N_PHI <= 100000)");
    }
    if (r < 0) return CLI_USAGE;
    if (o->out == NULL) return cli_usage_error("synth", "--out FILE is required");
    return 0;
}

static int build_axes(synth_job *job, const synth_opts *o)
{
    /* The sample count first, in doubles (inf for absurd steps): nothing is
     * allocated for axes beyond the limit. */
    if (!(polar_count(o->ti_step) * polar_count(o->to_step) * (double)o->n_phi <= MAX_SAMPLES))
        return cli_usage_error("synth", "--axes gives more than %d samples", MAX_SAMPLES);
    job->n[0] = polar_axis(o->ti_step, &job->deg[0]);
    job->n[1] = polar_axis(o->to_step, &job->deg[1]);
    job->n[2] = azimuth_axis(o->n_phi, &job->deg[2]);
    if (job->n[0] == 0 || job->n[1] == 0 || job->n[2] == 0) {
        cli_error(NULL, "out of memory");
        return -1;
    }
    return 0;
}

static int run(synth_job *job, const synth_opts *o)
{
    cli_assign_list list = {0, NULL};
    char msg[CLI_MSG_SIZE];
    double *params;
    int rc = CLI_FAILED;
    size_t np = brdffit_model_vector_size(job->model, o->channels);
    if (o->params != NULL && cli_assign_parse(&list, job->model, o->params, msg, sizeof msg) != 0)
        return cli_usage_error("synth", "--params: %s", msg);
    params = malloc(np * sizeof(double));
    if (params == NULL)
        cli_error(NULL, "out of memory");
    else if (cli_assign_vector(&list, job->model, o->channels, params, msg, sizeof msg) != 0)
        rc = cli_usage_error("synth", "--params: %s", msg);
    else {
        job->params = params;
        if (cli_write_atomic(o->out, write_csv, job, msg, sizeof msg) == 0)
            rc = CLI_OK;
        else
            cli_error(o->out, "%s", msg);
    }
    free(params);
    cli_assign_free(&list);
    return rc;
}

int cli_cmd_synth(int argc, char **argv)
{
    synth_opts o = {"ashikhmin-shirley", NULL, NULL, 3, 0.0, 5.0, 2.5, 36, 1};
    synth_job job;
    brdffit_model *model = NULL;
    brdffit_error err;
    int rc = parse_options(&o, argc, argv);
    if (rc != 0) return rc < 0 ? CLI_OK : rc;
    if (brdffit_model_create(&model, o.model, NULL, &err) != BRDFFIT_OK)
        return cli_usage_error("synth", "--model: %s", err.message);
    memset(&job, 0, sizeof job);
    job.model = model;
    job.n_channels = o.channels;
    job.noise = o.noise;
    job.rng = (uint64_t)o.seed;
    job.seed = o.seed;
    rc = build_axes(&job, &o);
    if (rc == 0)
        rc = run(&job, &o);
    else if (rc < 0)
        rc = CLI_FAILED;
    free(job.deg[0]);
    free(job.deg[1]);
    free(job.deg[2]);
    brdffit_model_destroy(model);
    return rc;
}
