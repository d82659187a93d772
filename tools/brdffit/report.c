/* brdffit fit --report: one self-contained HTML page per fitted file, with
 * the settings, the parameters with their standard errors, the renderer
 * form, the error figures, the warnings and the preview picture embedded
 * as a PNG data URL. Written atomically, like every output. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fit_result.h"

/* Text with &, <, >, " escaped. */
static void esc(cli_buf *b, const char *s)
{
    for (; *s != '\0'; s++) {
        switch (*s) {
        case '&': cli_buf_puts(b, "&amp;"); break;
        case '<': cli_buf_puts(b, "&lt;"); break;
        case '>': cli_buf_puts(b, "&gt;"); break;
        case '"': cli_buf_puts(b, "&quot;"); break;
        default: cli_buf_write(b, s, 1);
        }
    }
}

static void base64(cli_buf *b, const unsigned char *p, size_t n)
{
    static const char digits[] =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    size_t i;
    for (i = 0; i < n; i += 3) {
        unsigned long v = (unsigned long)p[i] << 16;
        char q[4];
        if (i + 1 < n) v |= (unsigned long)p[i + 1] << 8;
        if (i + 2 < n) v |= p[i + 2];
        q[0] = digits[v >> 18 & 63];
        q[1] = digits[v >> 12 & 63];
        q[2] = i + 1 < n ? digits[v >> 6 & 63] : '=';
        q[3] = i + 2 < n ? digits[v & 63] : '=';
        cli_buf_write(b, q, 4);
    }
}

static void row(cli_buf *b, const char *name, const char *value)
{
    cli_buf_puts(b, "<tr><th>");
    esc(b, name);
    cli_buf_puts(b, "</th><td>");
    esc(b, value);
    cli_buf_puts(b, "</td></tr>\n");
}

static void settings(cli_buf *b, const fit_result *r)
{
    char t[128];
    cli_buf w;
    cli_buf_puts(b, "<h2>Settings</h2>\n<table>\n");
    row(b, "model", brdffit_model_name(r->model));
    row(b, "pipeline", cli_pipeline_name(r->pipeline));
    row(b, "objective", cli_objective_name(r->objective));
    cli_format(t, sizeof t, "%.6g deg", r->cap * 180.0 / 3.14159265358979323846);
    row(b, "angle cap", t);
    cli_buf_init(&w);
    cli_weighting_names(&w, r->weighting, " and ");
    row(b, "weighting", w.failed || w.data == NULL ? "" : w.data);
    cli_buf_free(&w);
    if (r->clearcoat > 0.0)
        cli_format(t, sizeof t, "R0 %.6g", r->clearcoat);
    else
        cli_format(t, sizeof t, "none");
    row(b, "clear coat", t);
    cli_format(t, sizeof t, "%zu", r->max_iterations);
    row(b, "iteration limit", t);
    row(b, "standard errors", cli_covariance_name(r->covariance));
    cli_format(t, sizeof t, "%s, %zu channel%s, %zu samples, %zu inside the cap", r->source,
               r->n_channels, r->n_channels == 1 ? "" : "s", r->n_samples, r->n_active);
    row(b, "data", t);
    cli_buf_puts(b, "</table>\n");
}

static void params(cli_buf *b, const fit_result *r)
{
    size_t k, c, n_decl = brdffit_model_param_count(r->model);
    cli_buf_puts(b, "<h2>Parameters</h2>\n<table>\n<tr><th>parameter</th><th>channel</th>"
                    "<th>value</th><th>standard error</th></tr>\n");
    for (k = 0; k < n_decl; k++) {
        const brdffit_param_info *p = brdffit_model_param(r->model, k);
        size_t n = p->flags & BRDFFIT_PARAM_PER_CHANNEL ? r->n_channels : 1;
        for (c = 0; c < n; c++) {
            size_t i = brdffit_model_vector_index(r->model, k, c, r->n_channels);
            cli_buf_puts(b, "<tr><th>");
            esc(b, p->name);
            if (n > 1)
                cli_buf_printf(b, "</th><td>%zu</td>", c);
            else
                cli_buf_puts(b, "</th><td>all</td>");
            cli_buf_printf(b, "<td>%.6g</td><td>%.2g</td></tr>\n", r->params[i], r->se[i]);
        }
    }
    cli_buf_puts(b, "</table>\n");
}

static void figures(cli_buf *b, const fit_result *r)
{
    char t[160];
    size_t c;
    cli_buf_puts(b, "<h2>Result</h2>\n<table>\n");
    cli_format(t, sizeof t, "%.6g", r->rms);
    row(b, "e (root of the summed squared differences)", t);
    cli_format(t, sizeof t, "%.6g", r->ngan);
    row(b, "E (Ngan et al. error)", t);
    cli_format(t, sizeof t, "%.6g", r->cost);
    row(b, "cost", t);
    cli_format(t, sizeof t, "%zu (%s)", r->iterations, brdffit_stop_reason_string(r->stop));
    row(b, "iterations", t);
    cli_format(t, sizeof t, "%.0f ms", r->fit_ms);
    row(b, "fit time", t);
    cli_buf_puts(b, "<tr><th>renderer form</th><td>");
    if (r->has_shader) {
        cli_buf_printf(b, "Rs %.6g; cd", r->rs);
        for (c = 0; c < r->n_channels; c++) cli_buf_printf(b, " %.6g", r->shader_cd[c]);
        cli_buf_puts(b, "; cs");
        for (c = 0; c < r->n_channels; c++) cli_buf_printf(b, " %.6g", r->shader_cs[c]);
    } else
        cli_buf_puts(b, "none (needs colours cd and cs with max(cs) &lt; 1)");
    cli_buf_puts(b, "</td></tr>\n</table>\n");
}

static void warnings(cli_buf *b, const fit_result *r)
{
    size_t k, out = r->n_samples - r->n_active;
    cli_buf_puts(b, "<h2>Warnings</h2>\n");
    if (r->n_warnings == 0 && out == 0) {
        cli_buf_puts(b, "<p>none</p>\n");
        return;
    }
    cli_buf_puts(b, "<ul>\n");
    for (k = 0; k < r->n_warnings; k++) {
        cli_buf_puts(b, "<li><code>");
        esc(b, brdffit_warning_name(r->warnings[k].bit));
        cli_buf_puts(b, "</code>: ");
        esc(b, r->warnings[k].text);
        cli_buf_puts(b, "</li>\n");
    }
    if (out > 0)
        cli_buf_printf(b, "<li>the angle cap leaves out %zu of the %zu samples (%.0f %%)</li>\n",
                       out, r->n_samples, 100.0 * (double)out / (double)r->n_samples);
    cli_buf_puts(b, "</ul>\n");
}

/* The preview, its size read from the PNG header. */
static void picture(cli_buf *b, const fit_result *r, const cli_buf *png)
{
    const unsigned char *p = (const unsigned char *)png->data;
    unsigned long w = 0, h = 0;
    int i;
    if (png->data == NULL || png->len < 24) return;
    for (i = 0; i < 4; i++) {
        w = w << 8 | p[16 + i];
        h = h << 8 | p[20 + i];
    }
    cli_buf_printf(b, "<h2>Preview</h2>\n<p><img width=\"%lu\" height=\"%lu\" alt=\"preview of ",
                   w, h);
    esc(b, r->path);
    cli_buf_puts(b, "\" src=\"data:image/png;base64,");
    base64(b, p, png->len);
    cli_buf_puts(b, "\"></p>\n");
}

static void page(cli_buf *b, const fit_result *r, const cli_buf *png)
{
    cli_buf_puts(b, "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
                    "<title>brdffit: ");
    esc(b, r->path);
    cli_buf_puts(b, "</title>\n<style>\n"
                    "body { font-family: sans-serif; background: #181818; color: #ddd; "
                    "margin: 1.5em; }\n"
                    "table { border-collapse: collapse; margin-bottom: 1em; }\n"
                    "th, td { text-align: left; padding: 0.15em 0.8em 0.15em 0; "
                    "border-bottom: 1px solid #333; }\n"
                    "th { font-weight: normal; color: #aaa; }\n"
                    "img { max-width: 100%; height: auto; }\n"
                    "</style>\n</head>\n<body>\n<h1>");
    esc(b, r->path);
    cli_buf_puts(b, "</h1>\n");
    settings(b, r);
    params(b, r);
    figures(b, r);
    warnings(b, r);
    picture(b, r, png);
    cli_buf_puts(b, "<p>Written by brdffit " BRDFFIT_CLI_VERSION ".</p>\n</body>\n</html>\n");
}

static int write_page(FILE *f, void *ctx, char *msg, size_t msg_size)
{
    const cli_buf *html = ctx;
    if (fwrite(html->data, 1, html->len, f) == html->len) return 0;
    cli_format(msg, msg_size, "write failed");
    return -1;
}

int cli_report_write(const char *path, const fit_result *r, const cli_buf *png, char *msg,
                     size_t msg_size)
{
    cli_buf html;
    int rc;
    cli_buf_init(&html);
    page(&html, r, png);
    if (html.failed || html.data == NULL) {
        cli_buf_free(&html);
        cli_format(msg, msg_size, "out of memory");
        return -1;
    }
    rc = cli_write_atomic(path, write_page, &html, msg, msg_size);
    cli_buf_free(&html);
    return rc;
}
