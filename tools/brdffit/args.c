/* Option parsing by hand: --name VALUE, --name=VALUE, flags, "--", and
 * strict number parsing. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

void cli_args_init(cli_args *a, int argc, char **argv, const cli_option *options)
{
    a->argc = argc;
    a->argv = argv;
    a->index = 0;
    a->only_positional = 0;
    a->options = options;
}

static const cli_option *find_option(const cli_option *options, const char *name, size_t len)
{
    for (; options->name != NULL; options++)
        if (strlen(options->name) == len && strncmp(options->name, name, len) == 0) return options;
    return NULL;
}

/* An option argument "--name" or "--name=value". */
static int option(cli_args *a, const char *arg, const char **name, const char **value)
{
    const char *eq = strchr(arg, '=');
    size_t len = eq != NULL ? (size_t)(eq - arg) : strlen(arg);
    const cli_option *o = find_option(a->options, arg, len);
    if (o == NULL) {
        cli_error(NULL, "unknown option --%.*s (see --help)", (int)len, arg);
        return -1;
    }
    *name = o->name;
    *value = NULL;
    if (!o->takes_value) {
        if (eq == NULL) return 1;
        cli_error(NULL, "option --%s takes no value", o->name);
        return -1;
    }
    if (eq != NULL) {
        *value = eq + 1;
        return 1;
    }
    if (a->index >= a->argc) {
        cli_error(NULL, "option --%s needs a value", o->name);
        return -1;
    }
    *value = a->argv[a->index++];
    return 1;
}

int cli_next(cli_args *a, const char **name, const char **value)
{
    const char *arg;
    for (;;) {
        if (a->index >= a->argc) return 0;
        arg = a->argv[a->index++];
        if (!a->only_positional && strcmp(arg, "--") == 0) {
            a->only_positional = 1;
            continue;
        }
        break;
    }
    if (!a->only_positional && strcmp(arg, "-h") == 0 && find_option(a->options, "help", 4))
        return option(a, "help", name, value);
    if (a->only_positional || strncmp(arg, "--", 2) != 0 || arg[2] == '\0') {
        if (!a->only_positional && arg[0] == '-' && arg[1] != '\0') {
            cli_error(NULL, "unknown option %s (see --help)", arg);
            return -1;
        }
        *name = NULL;
        *value = arg;
        return 1;
    }
    return option(a, arg + 2, name, value);
}

int cli_parse_double(const char *s, double *out)
{
    char *end;
    double x;
    if (s == NULL || *s == '\0') return 0;
    errno = 0;
    x = strtod(s, &end);
    if (*end != '\0' || errno == ERANGE || x != x) return 0;
    *out = x;
    return 1;
}

int cli_parse_size(const char *s, size_t *out)
{
    char *end;
    unsigned long long x;
    if (s == NULL || *s < '0' || *s > '9') return 0;
    errno = 0;
    x = strtoull(s, &end, 10);
    if (*end != '\0' || errno == ERANGE || x > (unsigned long long)(size_t)-1) return 0;
    *out = (size_t)x;
    return 1;
}
