/* Output names made from a pattern (--preview, --gltf, --mtlx): one per
 * input, never shared, never an input. */
#include <stdlib.h>
#include <string.h>

#include "cli.h"

char *cli_preview_name(const char *pattern, const char *path)
{
    char base[256], *out, *q;
    const char *p;
    size_t n = strlen(pattern) + 1;
    cli_base_name(path, base, sizeof base);
    for (p = strstr(pattern, "%s"); p != NULL; p = strstr(p + 2, "%s")) n += strlen(base);
    out = malloc(n);
    if (out == NULL) return NULL;
    for (p = pattern, q = out; *p != '\0';) {
        if (p[0] == '%' && p[1] == 's') {
            strcpy(q, base);
            q += strlen(base);
            p += 2;
        } else
            *q++ = *p++;
    }
    *q = '\0';
    return out;
}

/* The first clash of name i with an earlier name or with any input. */
static int clash(const char *option, char **names, char **files, size_t n_files, size_t i)
{
    size_t j;
    for (j = 0; j < i; j++)
        if (strcmp(names[i], names[j]) == 0)
            return cli_usage_error("fit",
                                   "--%s: %s and %s would both write %s (same base name); "
                                   "rename one, or fit them in separate runs",
                                   option, files[j], files[i], names[i]);
    for (j = 0; j < n_files; j++)
        if (strcmp(names[i], files[j]) == 0)
            return cli_usage_error("fit", "--%s: the output of %s would overwrite the input %s",
                                   option, files[i], files[j]);
    return 0;
}

int cli_output_names_check(const char *option, const char *pattern, char **files,
                           size_t n_files)
{
    char **names = calloc(n_files, sizeof *names);
    size_t i;
    int rc = 0;
    if (names == NULL) rc = -1;
    for (i = 0; names != NULL && i < n_files && rc == 0; i++) {
        names[i] = cli_preview_name(pattern, files[i]);
        rc = names[i] == NULL ? -1 : clash(option, names, files, n_files, i);
    }
    if (rc < 0) cli_error(NULL, "out of memory");
    for (i = 0; names != NULL && i < n_files; i++) free(names[i]);
    free(names);
    return rc < 0 ? CLI_FAILED : rc;
}
