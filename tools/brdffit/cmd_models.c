/* brdffit models: the built-in models with their parameters. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"

static const char models_help[] =
    "usage: brdffit models\n"
    "\n"
    "List the built-in models: every parameter with whether it is shared by\n"
    "all channels or has one value per channel, its flags (linear: solved\n"
    "exactly by the auto pipeline; log: optimised on a log scale; fixed: held\n"
    "at its start value), its range and its default start value.\n";

static void print_bound(double x)
{
    if (isinf(x))
        printf("%s", x < 0 ? "-inf" : "inf");
    else
        printf("%g", x);
}

static void print_param(const brdffit_param_info *p)
{
    printf("    %-6s %-12s", p->name,
           p->flags & BRDFFIT_PARAM_PER_CHANNEL ? "per-channel" : "shared");
    printf(" %-14s", p->flags & BRDFFIT_PARAM_LINEAR
                         ? "linear"
                         : (p->flags & BRDFFIT_PARAM_LOG_SCALE ? "log" : "-"));
    printf(" [");
    print_bound(p->lower);
    printf(", ");
    print_bound(p->upper);
    printf("]  start %g%s\n", p->start, p->flags & BRDFFIT_PARAM_FIXED ? "  fixed" : "");
}

static int print_model(const char *name)
{
    brdffit_model *m = NULL;
    brdffit_error err;
    size_t i;
    if (brdffit_model_create(&m, name, NULL, &err) != BRDFFIT_OK) {
        cli_error(NULL, "model %s: %s", name, err.message);
        return -1;
    }
    printf("%s\n", name);
    for (i = 0; i < brdffit_model_param_count(m); i++) print_param(brdffit_model_param(m, i));
    brdffit_model_destroy(m);
    return 0;
}

int cli_cmd_models(int argc, char **argv)
{
    static const cli_option options[] = {{"help", 0}, {NULL, 0}};
    cli_args a;
    const char *name, *value;
    int r, failed = 0;
    size_t i;
    cli_args_init(&a, argc, argv, options);
    while ((r = cli_next(&a, &name, &value)) > 0) {
        if (name == NULL) return cli_usage_error("models", "unexpected argument \"%s\"", value);
        fputs(models_help, stdout);
        return CLI_OK;
    }
    if (r < 0) return CLI_USAGE;
    for (i = 0; i < brdffit_model_builtin_count(); i++)
        failed |= print_model(brdffit_model_builtin_name(i)) != 0;
    return failed ? CLI_FAILED : CLI_OK;
}
