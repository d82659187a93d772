/* brdffit: fit analytic BRDF models to measured reflectance from the
 * command line. Dispatches to the subcommands (docs/cli.md). */
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"

static void usage(FILE *out)
{
    fputs("usage: brdffit COMMAND [OPTIONS] [ARGS]\n"
          "\n"
          "Fit analytic BRDF models to measured reflectance.\n"
          "\n"
          "commands:\n"
          "  fit FILE...      fit a model to measurements (CSV or MERL .binary)\n"
          "  map FILE         fit every texel of a texel map, write a parameter map\n"
          "  models           list the built-in models and their parameters\n"
          "  info FILE        summarise a measurement\n"
          "  synth            write a synthetic measurement from a model as CSV\n"
          "\n"
          "options:\n"
          "  -h, --help       this text; `brdffit COMMAND --help` for a command\n"
          "  --version        the version of the command and of the library\n"
          "\n"
          "Exit status: 0 success, 1 some file failed, 2 usage error.\n",
          out);
}

static int version(void)
{
    printf("brdffit %s (libbrdffit %s, PNG preview %s)\n", BRDFFIT_CLI_VERSION,
           brdffit_version_string(), cli_png_available() ? "yes" : "no");
    return CLI_OK;
}

static int dispatch(int argc, char **argv)
{
    const char *cmd = argc > 1 ? argv[1] : NULL;
    if (cmd == NULL) {
        usage(stderr);
        return CLI_USAGE;
    }
    if (strcmp(cmd, "-h") == 0 || strcmp(cmd, "--help") == 0 || strcmp(cmd, "help") == 0) {
        usage(stdout);
        return CLI_OK;
    }
    if (strcmp(cmd, "--version") == 0) return version();
    if (strcmp(cmd, "fit") == 0) return cli_cmd_fit(argc - 2, argv + 2);
    if (strcmp(cmd, "map") == 0) return cli_cmd_map(argc - 2, argv + 2);
    if (strcmp(cmd, "models") == 0) return cli_cmd_models(argc - 2, argv + 2);
    if (strcmp(cmd, "info") == 0) return cli_cmd_info(argc - 2, argv + 2);
    if (strcmp(cmd, "synth") == 0) return cli_cmd_synth(argc - 2, argv + 2);
    return cli_usage_error(NULL, "unknown command \"%s\"", cmd);
}

/* Output that could not be written (a full disk, > /dev/full, a closed
 * pipe) is a failure of the command, not a success. */
int main(int argc, char **argv)
{
    int rc = dispatch(argc, argv);
    errno = 0;
    if (fflush(stdout) != 0 || ferror(stdout) || fclose(stdout) != 0) {
        cli_error(NULL, "cannot write the standard output: %s",
                  errno != 0 ? strerror(errno) : "write error");
        return rc != CLI_OK ? rc : CLI_FAILED;
    }
    return rc;
}
