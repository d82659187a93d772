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

/* One export of the fit (--gltf or --mtlx) as the records state it. */
typedef struct fit_export {
    int asked;             /* the option was given */
    int written;           /* the file was written */
    int refit;             /* it holds another model refitted to the data */
    char file[256];        /* the file written */
    char model[64];        /* the model whose parameters it holds */
    double rms, ngan, cost; /* that model's error figures on the data */
} fit_export;

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
    int plausible;           /* BRDFFIT_FIT_PLAUSIBLE */
    int covariance;          /* BRDFFIT_FIT_COVARIANCE: 0 classic, 1 sandwich */
    int fitted;               /* the fit produced parameters */
    brdffit_status status;    /* the failure when not fitted */
    char error[CLI_MSG_SIZE]; /* why the file failed ("" when it did not) */
    size_t n_channels, n_samples, n_active, n_params;
    double *params, *se; /* n_params each */
    double *cov;         /* n_params^2, row-major; NULL: BRDFFIT_E_TOO_LARGE */
    unsigned char *held; /* per declared parameter: held by the fit */
    int has_shader;
    double rs, *shader_cd, *shader_cs; /* n_channels each */
    double rms, ngan, cost;
    size_t iterations;
    brdffit_stop_reason stop;
    double fit_ms;
    fit_warning warnings[CLI_MAX_WARNINGS];
    size_t n_warnings;
    int converged;                /* brdffit_fit_converged() */
    brdffit_fit_stage *stages;    /* n_stages: brdffit_fit_stage_info() */
    size_t n_stages;
    double *history, *lambdas;    /* n_history each: brdffit_fit_history_all() */
    size_t n_history;
    fit_export exports[2];        /* [0] --gltf, [1] --mtlx */
} fit_result;

void fit_result_free(fit_result *r);

/* --- fit_history.c: the stages and the whole history --------------------- */

/* Copy the fit's converged flag, stages and history into r; -1 when out of
 * memory. */
int fit_history_collect(const brdffit_fit *fit, fit_result *r);
/* ', "converged": B, "stages": [{...}, ...]' for the JSON object. */
void fit_history_json(cli_buf *b, const fit_result *r);

/* --- fit_hold.c: --fix, --free, --damping -------------------------------- */

typedef struct fit_holds {
    cli_assign_list fix;  /* --fix NAME=VALUE,...: held at these values */
    size_t *free_params;  /* --free NAME,...: declared indices let free */
    size_t n_free;
} fit_holds;

/* Parse --fix and --free (either may be NULL) against the model; a name in
 * both is an error. -1 with the message in msg. */
int fit_holds_parse(fit_holds *h, const brdffit_model *model, const char *fix,
                    const char *free_text, char *msg, size_t msg_size);
void fit_holds_free(fit_holds *h);
/* Free and hold the parameters, and set the start values (--start, then
 * the held values on top) when either list has any. */
int fit_holds_apply(const fit_holds *h, const cli_assign_list *start, brdffit_fit *fit,
                    const brdffit_model *model, size_t n_channels, char *msg, size_t msg_size);
/* Per declared parameter, whether the fit holds it (the model's default
 * with the lists applied); malloc'd, NULL when out of memory. */
unsigned char *fit_holds_held(const fit_holds *h, const brdffit_model *model);
/* "nielsen", "marquardt" or "thesis"; 0 for another name. */
int cli_parse_damping(const char *name, const brdffit_damping **out);

/* The objective of a fit without --objective: the library's default. */
#define CLI_DEFAULT_OBJECTIVE BRDFFIT_OBJECTIVE_CUBE_ROOT

/* The objective's name on the command line and in JSON ("squares", "log",
 * "cube-root", "relative"), and back; 0 for an unknown name. */
const char *cli_objective_name(brdffit_objective objective);
int cli_parse_objective(const char *name, brdffit_objective *out);

/* The standard-error estimator's name (--errors, JSON "std_errors_estimator"):
 * "classic" or "sandwich" for BRDFFIT_FIT_COVARIANCE 0 and 1, and back; 0
 * for an unknown name. */
const char *cli_covariance_name(int covariance);
int cli_parse_covariance(const char *name, int *out);

/* The weighting flags as JSON and CSV name them: "solid-angle;cosine",
 * "solid-angle", "cosine" or "none" (`sep` between two names). */
void cli_weighting_names(cli_buf *b, unsigned weighting, const char *sep);

/* The readable summary, the JSON object (one line, with '\n'), and the
 * CSV header and row (without '\n' for the header, with it for the row). */
void fit_summary(cli_buf *b, const fit_result *r);
void fit_json(cli_buf *b, const fit_result *r);
void fit_csv_header(cli_buf *b, const fit_result *r);
void fit_csv_row(cli_buf *b, const fit_result *r);

/* export_record.c: the exports in the records, appended to the JSON object
 * (', "exports": [...]' before its closing brace) and the CSV header and
 * row, only when --gltf or --mtlx was given. */
void fit_exports_json(cli_buf *b, const fit_result *r);
void fit_exports_csv_header(cli_buf *b, const fit_result *r);
void fit_exports_csv_row(cli_buf *b, const fit_result *r);

/* report.c: the HTML page of a fitted result with the PNG bytes of its
 * preview (png->len 0: no picture), written atomically. */
int cli_report_write(const char *path, const fit_result *r, const cli_buf *png, char *msg,
                     size_t msg_size);

/* The warnings of a fitted result, one "brdffit: FILE: warning: ..." line
 * each, on standard error. */
void fit_warnings_report(const fit_result *r);

#endif /* BRDFFIT_CLI_FIT_RESULT_H */
