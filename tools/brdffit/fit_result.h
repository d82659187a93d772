/* brdffit fit: the result of fitting one file, and its output forms. */
#ifndef BRDFFIT_CLI_FIT_RESULT_H
#define BRDFFIT_CLI_FIT_RESULT_H

#include "cli.h"

/* Room for every warning bit the library defines, and more. */
#define CLI_MAX_WARNINGS 16

typedef struct fit_warning {
    unsigned bit;   /* one brdffit_warning */
    char text[256]; /* brdffit_fit_warning_text() */
} fit_warning;

typedef struct fit_result {
    const char *path;
    const char *source; /* what cli_load() said about the file */
    const brdffit_model *model;
    brdffit_pipeline pipeline;
    brdffit_objective objective;
    /* the other settings that shaped the fit, read back from it */
    double cap;              /* radians */
    unsigned weighting;      /* brdffit_weighting flags */
    double clearcoat;        /* Schlick R0; 0 = no compensation */
    size_t max_iterations;   /* of each LM run */
    int fitted;               /* the fit produced parameters */
    brdffit_status status;    /* the failure when not fitted */
    char error[CLI_MSG_SIZE]; /* why the file failed ("" when it did not) */
    size_t n_channels, n_samples, n_active, n_params;
    double *params, *se; /* n_params each */
    int has_shader;
    double rs, *shader_cd, *shader_cs; /* n_channels each */
    double rms, ngan, cost;
    size_t iterations;
    brdffit_stop_reason stop;
    double fit_ms;
    fit_warning warnings[CLI_MAX_WARNINGS];
    size_t n_warnings;
} fit_result;

void fit_result_free(fit_result *r);

/* The objective's name on the command line and in JSON ("squares", "log",
 * "cube-root", "relative"), and back; 0 for an unknown name. */
const char *cli_objective_name(brdffit_objective objective);
int cli_parse_objective(const char *name, brdffit_objective *out);

/* The weighting flags as JSON and CSV name them: "solid-angle;cosine",
 * "solid-angle", "cosine" or "none" (`sep` between two names). */
void cli_weighting_names(cli_buf *b, unsigned weighting, const char *sep);

/* The readable summary, the JSON object (one line, with '\n'), and the
 * CSV header and row (without '\n' for the header, with it for the row). */
void fit_summary(cli_buf *b, const fit_result *r);
void fit_json(cli_buf *b, const fit_result *r);
void fit_csv_header(cli_buf *b, const fit_result *r);
void fit_csv_row(cli_buf *b, const fit_result *r);

/* report.c: the HTML page of a fitted result with the PNG bytes of its
 * preview (png->len 0: no picture), written atomically. */
int cli_report_write(const char *path, const fit_result *r, const cli_buf *png, char *msg,
                     size_t msg_size);

/* The warnings of a fitted result, one "brdffit: FILE: warning: ..." line
 * each, on standard error. */
void fit_warnings_report(const fit_result *r);

#endif /* BRDFFIT_CLI_FIT_RESULT_H */
