/* The brdffit command: declarations shared by its source files. The
 * command uses the public API of libbrdffit only. */
#ifndef BRDFFIT_CLI_H
#define BRDFFIT_CLI_H

#include <stddef.h>
#include <stdio.h>

#include "brdffit/brdffit.h"

/* Exit statuses. */
enum { CLI_OK = 0, CLI_FAILED = 1, CLI_USAGE = 2 };

#define CLI_MSG_SIZE 512

/* --- args.c: hand-written option parsing ----------------------------------- */

/* One option of a subcommand: name without the leading "--", and whether
 * it takes a value ("--name VALUE" or "--name=VALUE"). */
typedef struct cli_option {
    const char *name;
    int takes_value;
} cli_option;

/* Walks argv. cli_next() returns 1 with *name set to the option (or NULL
 * for a positional argument, then *value is that argument) and *value to
 * its value (NULL for flags); 0 at the end; -1 after a usage error, which
 * it has printed. "--" ends the options. */
typedef struct cli_args {
    int argc, index, only_positional;
    char **argv;
    const cli_option *options;
} cli_args;

void cli_args_init(cli_args *a, int argc, char **argv, const cli_option *options);
int cli_next(cli_args *a, const char **name, const char **value);

/* Strict number parsing: the whole string must be the number. */
int cli_parse_double(const char *s, double *out);
int cli_parse_size(const char *s, size_t *out);

/* --- util.c -------------------------------------------------------------- */

/* "brdffit: FILE: message" (or "brdffit: message" for a NULL file) on one
 * line of stderr. */
void cli_error(const char *file, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* A usage error: the message, then a hint to --help; returns CLI_USAGE. */
int cli_usage_error(const char *command, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

void cli_format(char *buf, size_t size, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* The shortest %g form that reads back as x. */
void cli_shortest(char *buf, size_t size, double x);

/* Milliseconds on a monotonic clock. */
double cli_now_ms(void);

/* The file name without directories and without its last extension. */
void cli_base_name(const char *path, char *out, size_t size);

/* Write an output file (write.c). A regular file, or a new one, appears
 * complete or not at all: the writer fills a temporary file next to it,
 * which is then renamed over it, with the mode of the file it replaces
 * (0644 for a new one). A symbolic link stays a link: its target is
 * replaced the same way (a link to a missing file is refused). A device
 * or a FIFO is never replaced: it is written through (a FIFO without a
 * reader is refused). A directory is refused. The writer returns 0 on
 * success or fills msg. Returns 0 on success; on failure msg says why and
 * no temporary file is left behind. */
typedef int (*cli_writer)(FILE *f, void *ctx, char *msg, size_t msg_size);
int cli_write_atomic(const char *path, cli_writer writer, void *ctx, char *msg, size_t msg_size);

/* Append `size` bytes to `path` with one write(2) (O_APPEND), creating
 * the file when missing. When the file is empty or new, `header` (may be
 * NULL) is written first, in the same write. When the file is not empty
 * and `header` is given, its first line must equal the header. */
int cli_append(const char *path, const char *header, const char *data, size_t size, char *msg,
               size_t msg_size);

/* A growable string. */
typedef struct cli_buf {
    char *data;
    size_t len, cap;
    int failed; /* out of memory at some point */
} cli_buf;
void cli_buf_init(cli_buf *b);
void cli_buf_free(cli_buf *b);
void cli_buf_printf(cli_buf *b, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
void cli_buf_puts(cli_buf *b, const char *s);
void cli_buf_write(cli_buf *b, const char *data, size_t size);
/* A JSON string literal (quoted, escaped, invalid UTF-8 replaced). */
void cli_buf_json_string(cli_buf *b, const char *s);
/* A JSON number with %.17g, or null when not finite. */
void cli_buf_json_number(cli_buf *b, double x);
/* A CSV field, quoted when it holds a comma, quote or line break. */
void cli_buf_csv_field(cli_buf *b, const char *s);

/* --- load.c -------------------------------------------------------------- */

/* Load a measurement, reading the file once and telling its format from
 * its content: MERL binary (resampled onto the default axes), RGL .bsdf
 * (the samples as measured), ASTM E1392, else CSV. `what` receives a
 * short description of the source. On failure msg holds the library's
 * message (or why the file cannot be read). */
brdffit_status cli_load(const char *path, brdffit_grid **grid, const char **what, char *msg,
                        size_t msg_size);

/* --- params.c: NAME=VALUE,... lists ---------------------------------------- */

/* One assignment: parameter index, and 1 value (all channels) or one per
 * channel. */
typedef struct cli_assign {
    size_t param;
    size_t n_values;
    double *values;
} cli_assign;

typedef struct cli_assign_list {
    size_t count;
    cli_assign *items;
} cli_assign_list;

/* Parse "NAME=v,NAME=v1:v2:v3" against a model's parameter names. */
int cli_assign_parse(cli_assign_list *list, const brdffit_model *model, const char *text, char *msg,
                     size_t msg_size);
void cli_assign_free(cli_assign_list *list);
/* Fill a parameter vector for n_channels: model defaults, then the list. */
int cli_assign_vector(const cli_assign_list *list, const brdffit_model *model, size_t n_channels,
                      double *params, char *msg, size_t msg_size);
/* Write the list's values into a filled parameter vector for n_channels. */
int cli_assign_apply(const cli_assign_list *list, const brdffit_model *model, size_t n_channels,
                     double *params, char *msg, size_t msg_size);

/* --- preview*.c (cairo) ------------------------------------------------------ */

typedef struct cli_preview_input {
    const char *title; /* drawn at the top */
    const brdffit_grid *grid;
    const brdffit_model *model;
    const double *params;
    const double *history; /* brdffit_fit_history_all(): every stage in turn */
    size_t n_history;
    const brdffit_fit_stage *stages; /* n_stages: brdffit_fit_stage_info() */
    size_t n_stages;
    double gain, gamma;
    double rms, ngan, cost; /* e, E and the cost of the fit */
    double cap;             /* angle cap, radians */
} cli_preview_input;

/* Draws the preview and writes it as PNG, atomically (cli_write_atomic). */
int cli_preview_write(const cli_preview_input *in, const char *path, char *msg,
                      size_t msg_size);
/* Frees cairo's font caches once no picture is being drawn any more (so
 * that leak checkers see a clean exit). */
void cli_preview_cleanup(void);
/* Draws the preview and appends its PNG bytes to `out`. */
int cli_preview_png(const cli_preview_input *in, cli_buf *out, char *msg, size_t msg_size);
/* preview_name.c: the picture name of one input, every %s of the pattern
 * replaced by the input's base name (NULL when out of memory; free() it). */
char *cli_preview_name(const char *pattern, const char *path);
/* 0 when every input gets an output name of its own (from `pattern`, the
 * value of --`option`) that is not one of the inputs; otherwise prints a
 * usage error naming the clash and returns CLI_USAGE (CLI_FAILED when out
 * of memory). */
int cli_output_names_check(const char *option, const char *pattern, char **files,
                           size_t n_files);
/* 1 when the command was built with cairo (PNG previews). */
int cli_png_available(void);

/* --- subcommands ------------------------------------------------------------- */

int cli_cmd_fit(int argc, char **argv);
int cli_cmd_info(int argc, char **argv);
int cli_cmd_models(int argc, char **argv);
int cli_cmd_synth(int argc, char **argv);
int cli_cmd_map(int argc, char **argv);

/* Short token of a stop reason for JSON and CSV ("gradient", ...). */
const char *cli_stop_token(brdffit_stop_reason reason);
/* Name of a pipeline ("auto", "joint", "two-stage"). */
const char *cli_pipeline_name(brdffit_pipeline p);

#endif /* BRDFFIT_CLI_H */
