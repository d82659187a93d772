/* brdffit fit --gltf / --mtlx in the records: which model each export
 * holds, whether it was refitted (export_refit.c) and that model's error
 * figures on the data. docs/formats.md describes the keys and columns. */
#include "fit_result.h"

#include <math.h>

static const char *const formats[2] = {"gltf", "mtlx"};

static int any_asked(const fit_result *r)
{
    return r->exports[0].asked || r->exports[1].asked;
}

void fit_exports_json(cli_buf *b, const fit_result *r)
{
    size_t k, n = 0;
    if (!any_asked(r)) return;
    cli_buf_puts(b, ", \"exports\": [");
    for (k = 0; k < 2; k++) {
        const fit_export *e = &r->exports[k];
        if (!e->written) continue;
        cli_buf_printf(b, "%s{\"format\": \"%s\", \"file\": ", n++ ? ", " : "", formats[k]);
        cli_buf_json_string(b, e->file);
        cli_buf_puts(b, ", \"model\": ");
        cli_buf_json_string(b, e->model);
        cli_buf_printf(b, ", \"refit\": %s, \"rms\": ", e->refit ? "true" : "false");
        cli_buf_json_number(b, e->rms);
        cli_buf_puts(b, ", \"ngan\": ");
        cli_buf_json_number(b, e->ngan);
        cli_buf_puts(b, ", \"cost\": ");
        cli_buf_json_number(b, e->cost);
        cli_buf_puts(b, "}");
    }
    cli_buf_puts(b, "]");
}

void fit_exports_csv_header(cli_buf *b, const fit_result *r)
{
    size_t k;
    for (k = 0; k < 2; k++)
        if (r->exports[k].asked)
            cli_buf_printf(b, ",%s_file,%s_model,%s_refit,%s_rms,%s_ngan,%s_cost", formats[k],
                           formats[k], formats[k], formats[k], formats[k], formats[k]);
}

static void csv_number(cli_buf *b, double x)
{
    if (isfinite(x))
        cli_buf_printf(b, ",%.17g", x);
    else
        cli_buf_puts(b, ",");
}

void fit_exports_csv_row(cli_buf *b, const fit_result *r)
{
    size_t k;
    for (k = 0; k < 2; k++) {
        const fit_export *e = &r->exports[k];
        if (!e->asked) continue;
        if (!e->written) {
            cli_buf_puts(b, ",,,,,,");
            continue;
        }
        cli_buf_puts(b, ",");
        cli_buf_csv_field(b, e->file);
        cli_buf_puts(b, ",");
        cli_buf_csv_field(b, e->model);
        cli_buf_printf(b, ",%d", e->refit ? 1 : 0);
        csv_number(b, e->rms);
        csv_number(b, e->ngan);
        csv_number(b, e->cost);
    }
}
