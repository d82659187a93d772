/* Parameter assignments "NAME=v,NAME=v1:v2:v3" (--start, --fix, synth --params). */
#include <stdlib.h>
#include <string.h>

#include "cli.h"

void cli_assign_free(cli_assign_list *list)
{
    size_t i;
    for (i = 0; i < list->count; i++) free(list->items[i].values);
    free(list->items);
    list->items = NULL;
    list->count = 0;
}

/* Values "v1:v2:..." of one assignment; the text is modified. */
static int parse_values(cli_assign *a, char *text, char *msg, size_t msg_size)
{
    size_t n = 1, i = 0;
    char *p, *next;
    for (p = text; *p != '\0'; p++) n += *p == ':';
    a->values = malloc(n * sizeof(double));
    if (a->values == NULL) {
        cli_format(msg, msg_size, "out of memory");
        return -1;
    }
    for (p = text; p != NULL; p = next, i++) {
        next = strchr(p, ':');
        if (next != NULL) *next++ = '\0';
        if (!cli_parse_double(p, &a->values[i])) {
            cli_format(msg, msg_size, "\"%s\" is not a number", p);
            return -1;
        }
    }
    a->n_values = n;
    return 0;
}

static int parse_one(cli_assign *a, const brdffit_model *model, char *item, char *msg,
                     size_t msg_size)
{
    char *eq = strchr(item, '=');
    const brdffit_param_info *info;
    if (eq == NULL) {
        cli_format(msg, msg_size, "\"%s\" is not NAME=VALUE", item);
        return -1;
    }
    *eq = '\0';
    if (brdffit_model_param_find(model, item, &a->param) != BRDFFIT_OK) {
        cli_format(msg, msg_size, "model %s has no parameter \"%s\"", brdffit_model_name(model),
                   item);
        return -1;
    }
    if (parse_values(a, eq + 1, msg, msg_size) != 0) return -1;
    info = brdffit_model_param(model, a->param);
    if (a->n_values > 1 && !(info->flags & BRDFFIT_PARAM_PER_CHANNEL)) {
        cli_format(msg, msg_size, "parameter %s is shared by all channels: give one value",
                   info->name);
        return -1;
    }
    return 0;
}

int cli_assign_parse(cli_assign_list *list, const brdffit_model *model, const char *text, char *msg,
                     size_t msg_size)
{
    size_t n = 1;
    const char *p;
    char *copy, *item, *next;
    int rc = 0;
    list->count = 0;
    list->items = NULL;
    for (p = text; *p != '\0'; p++) n += *p == ',';
    copy = malloc(strlen(text) + 1);
    list->items = calloc(n, sizeof(cli_assign));
    if (copy == NULL || list->items == NULL) {
        free(copy);
        cli_format(msg, msg_size, "out of memory");
        return -1;
    }
    strcpy(copy, text);
    for (item = copy; item != NULL && rc == 0; item = next) {
        next = strchr(item, ',');
        if (next != NULL) *next++ = '\0';
        rc = parse_one(&list->items[list->count++], model, item, msg, msg_size);
    }
    free(copy);
    if (rc != 0) cli_assign_free(list);
    return rc;
}

int cli_assign_vector(const cli_assign_list *list, const brdffit_model *model, size_t n_channels,
                      double *params, char *msg, size_t msg_size)
{
    if (brdffit_model_default_params(model, n_channels, params) != BRDFFIT_OK) {
        cli_format(msg, msg_size, "cannot set up the parameters of model %s",
                   brdffit_model_name(model));
        return -1;
    }
    return cli_assign_apply(list, model, n_channels, params, msg, msg_size);
}

int cli_assign_apply(const cli_assign_list *list, const brdffit_model *model, size_t n_channels,
                     double *params, char *msg, size_t msg_size)
{
    size_t i, c;
    for (i = 0; i < list->count; i++) {
        const cli_assign *a = &list->items[i];
        const brdffit_param_info *info = brdffit_model_param(model, a->param);
        size_t n = info->flags & BRDFFIT_PARAM_PER_CHANNEL ? n_channels : 1;
        if (a->n_values != 1 && a->n_values != n) {
            cli_format(msg, msg_size, "parameter %s has %zu values, the data %zu channels",
                       info->name, a->n_values, n_channels);
            return -1;
        }
        for (c = 0; c < n; c++)
            params[brdffit_model_vector_index(model, a->param, c, n_channels)] =
                a->values[a->n_values == 1 ? 0 : c];
    }
    return 0;
}
