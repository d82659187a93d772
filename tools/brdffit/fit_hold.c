/* brdffit fit: the options that change what the fit may move and how:
 * --fix NAME=VALUE (held at a value), --free NAME (let a parameter the
 * model holds by default move), --damping POLICY. */
#include <stdlib.h>
#include <string.h>

#include "fit_result.h"

void fit_holds_free(fit_holds *h)
{
    cli_assign_free(&h->fix);
    free(h->free_params);
    h->free_params = NULL;
    h->n_free = 0;
}

/* --free "NAME,NAME,...": the declared indices. */
static int parse_free(fit_holds *h, const brdffit_model *model, const char *text, char *msg,
                      size_t msg_size)
{
    size_t n = 1, len;
    const char *p = text;
    for (; *p != '\0'; p++) n += *p == ',';
    h->free_params = calloc(n, sizeof *h->free_params);
    if (h->free_params == NULL) {
        cli_format(msg, msg_size, "out of memory");
        return -1;
    }
    for (p = text; n > 0; p += len + 1, n--) {
        char name[128];
        len = strcspn(p, ",");
        cli_format(name, sizeof name, "%.*s", (int)(len < 127 ? len : 127), p);
        if (len >= sizeof name ||
            brdffit_model_param_find(model, name, &h->free_params[h->n_free]) != BRDFFIT_OK) {
            cli_format(msg, msg_size, "model %s has no parameter \"%s\"", brdffit_model_name(model),
                       name);
            return -1;
        }
        h->n_free++;
    }
    return 0;
}

int fit_holds_parse(fit_holds *h, const brdffit_model *model, const char *fix,
                    const char *free_text, char *msg, size_t msg_size)
{
    size_t i, j;
    char why[CLI_MSG_SIZE];
    memset(h, 0, sizeof *h);
    if (fix != NULL && cli_assign_parse(&h->fix, model, fix, why, sizeof why) != 0) {
        cli_format(msg, msg_size, "--fix: %s", why);
        return -1;
    }
    if (free_text != NULL && parse_free(h, model, free_text, why, sizeof why) != 0) {
        cli_format(msg, msg_size, "--free: %s", why);
        fit_holds_free(h);
        return -1;
    }
    for (i = 0; i < h->fix.count; i++)
        for (j = 0; j < h->n_free; j++)
            if (h->fix.items[i].param == h->free_params[j]) {
                cli_format(msg, msg_size, "%s is both held (--fix) and freed (--free)",
                           brdffit_model_param(model, h->free_params[j])->name);
                fit_holds_free(h);
                return -1;
            }
    return 0;
}

int fit_holds_apply(const fit_holds *h, const cli_assign_list *start, brdffit_fit *fit,
                    const brdffit_model *model, size_t n_channels, char *msg, size_t msg_size)
{
    size_t n = brdffit_model_vector_size(model, n_channels), i;
    brdffit_status st = BRDFFIT_OK;
    double *v;
    int rc = 0;
    for (i = 0; i < h->n_free && st == BRDFFIT_OK; i++)
        st = brdffit_fit_set_fixed(fit, h->free_params[i], 0);
    for (i = 0; i < h->fix.count && st == BRDFFIT_OK; i++)
        st = brdffit_fit_set_fixed(fit, h->fix.items[i].param, 1);
    if (st != BRDFFIT_OK) {
        cli_format(msg, msg_size, "%s", brdffit_fit_message(fit));
        return -1;
    }
    if (start->count == 0 && h->fix.count == 0) return 0;
    v = malloc(n * sizeof *v);
    if (v == NULL) {
        cli_format(msg, msg_size, "out of memory");
        return -1;
    }
    if (cli_assign_vector(start, model, n_channels, v, msg, msg_size) != 0 ||
        cli_assign_apply(&h->fix, model, n_channels, v, msg, msg_size) != 0)
        rc = -1;
    else if (brdffit_fit_set_start(fit, v) != BRDFFIT_OK) {
        cli_format(msg, msg_size, "%s", brdffit_fit_message(fit));
        rc = -1;
    }
    free(v);
    return rc;
}

unsigned char *fit_holds_held(const fit_holds *h, const brdffit_model *model)
{
    size_t n = brdffit_model_param_count(model), k;
    unsigned char *held = calloc(n + 1, 1);
    if (held == NULL) return NULL;
    for (k = 0; k < n; k++)
        held[k] = (brdffit_model_param(model, k)->flags & BRDFFIT_PARAM_FIXED) != 0;
    for (k = 0; k < h->n_free; k++) held[h->free_params[k]] = 0;
    for (k = 0; k < h->fix.count; k++) held[h->fix.items[k].param] = 1;
    return held;
}

int cli_parse_damping(const char *name, const brdffit_damping **out)
{
    if (strcmp(name, "nielsen") == 0)
        *out = brdffit_damping_nielsen();
    else if (strcmp(name, "marquardt") == 0)
        *out = brdffit_damping_marquardt();
    else if (strcmp(name, "thesis") == 0)
        *out = brdffit_damping_thesis();
    else
        return 0;
    return 1;
}
