/* The optimizer's stop requests: its own cancel flag and the watched one
 * (optim/watch.h). */
#include "optim/watch.h"

#include "optim/optim_internal.h"

void bf_optim_watch(brdffit_optimizer *opt, const atomic_int *flag)
{
    if (bf_optim_check_handle(opt) == BRDFFIT_OK) opt->watch = flag;
}

int bf_optim_watched_stop(const brdffit_optimizer *opt)
{
    return opt->watch != NULL && atomic_load(opt->watch) != 0;
}

int bf_optim_stopped(const brdffit_optimizer *opt)
{
    return atomic_load(&opt->cancel) != 0 || bf_optim_watched_stop(opt);
}
