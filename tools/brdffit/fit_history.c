/* brdffit fit: whether the fit converged, its stages and its whole
 * history (brdffit_fit_stage_info(), brdffit_fit_history_all()), kept
 * with the result and written into its JSON object. */
#include <stdlib.h>
#include <string.h>

#include "fit_result.h"

int fit_history_collect(const brdffit_fit *fit, fit_result *r)
{
    size_t i, n = brdffit_fit_history_all(fit, NULL, NULL, NULL);
    r->converged = brdffit_fit_converged(fit);
    r->n_stages = brdffit_fit_stage_count(fit);
    r->stages = calloc(r->n_stages + 1, sizeof *r->stages);
    r->history = calloc(2 * n + 1, sizeof *r->history);
    if (r->stages == NULL || r->history == NULL) return -1;
    r->lambdas = r->history + n;
    r->n_history = brdffit_fit_history_all(fit, r->history, r->lambdas, NULL);
    for (i = 0; i < r->n_stages; i++)
        if (brdffit_fit_stage_info(fit, i, &r->stages[i], sizeof r->stages[i]) != BRDFFIT_OK)
            return -1;
    return 0;
}

static void json_numbers(cli_buf *b, const double *v, size_t n)
{
    size_t i;
    cli_buf_puts(b, "[");
    for (i = 0; i < n; i++) {
        if (i) cli_buf_puts(b, ", ");
        cli_buf_json_number(b, v[i]);
    }
    cli_buf_puts(b, "]");
}

static void json_stage(cli_buf *b, const fit_result *r, const brdffit_fit_stage *s)
{
    size_t first = s->first, end = s->first + s->length;
    if (end > r->n_history || first > end) first = end = 0; /* the library's tiling: never */
    cli_buf_puts(b, "{\"stage\": ");
    cli_buf_json_string(b, brdffit_fit_stage_name(s->kind));
    cli_buf_printf(b, ", \"index\": %zu, \"kept\": %s, \"converged\": %s, \"stop\": ", s->index,
                   s->kept ? "true" : "false", s->converged ? "true" : "false");
    cli_buf_json_string(b, cli_stop_token(s->stop));
    cli_buf_printf(b, ", \"iterations\": %zu, \"evaluations\": %zu, \"cost\": ", s->iterations,
                   s->evaluations);
    json_numbers(b, r->history + first, end - first);
    cli_buf_puts(b, ", \"lambda\": ");
    json_numbers(b, r->lambdas + first, end - first);
    cli_buf_puts(b, "}");
}

void fit_history_json(cli_buf *b, const fit_result *r)
{
    size_t i;
    cli_buf_printf(b, ", \"converged\": %s, \"stages\": [", r->converged ? "true" : "false");
    for (i = 0; i < r->n_stages; i++) {
        if (i) cli_buf_puts(b, ", ");
        json_stage(b, r, &r->stages[i]);
    }
    cli_buf_puts(b, "]");
}
