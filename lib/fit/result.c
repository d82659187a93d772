/* The result of a run and the fit's messages: see result.h. */
#include "fit/result.h"

#include <stdarg.h>
#include <stdio.h>

#include "core/core.h"

brdffit_status bf_say(char *message, brdffit_status status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(message, BF_FIT_MESSAGE_SIZE, fmt, ap);
    va_end(ap);
    return status;
}

brdffit_status bf_result_keep_report(bf_result *r, const brdffit_optimizer *opt,
                                     const brdffit_allocator *a)
{
    size_t n;
    bf_free(a, r->history);
    r->history = NULL;
    r->history_len = 0;
    r->stop = BRDFFIT_STOP_CANCELLED;
    r->iterations = 0;
    if (opt == NULL) return BRDFFIT_OK; /* cancelled before any LM run */
    n = brdffit_optimizer_history(opt, NULL, NULL);
    r->stop = brdffit_optimizer_stop_reason(opt);
    r->iterations = brdffit_optimizer_iterations(opt);
    if (n == 0) return BRDFFIT_OK;
    r->history = bf_calloc(a, 2 * n, sizeof(double));
    if (r->history == NULL) return BRDFFIT_E_OUT_OF_MEMORY;
    brdffit_optimizer_history(opt, r->history, r->history + n);
    r->history_len = n;
    return BRDFFIT_OK;
}
