/* The helper threads of one fit run: started once when the run begins and
 * reused by every pass, so a pass costs a wake-up instead of a thread
 * creation. Each pass hands out one task per block of samples; which thread
 * runs a task never changes what it computes, so results do not depend on
 * how many helpers could be started. Not installed. */
#ifndef BRDFFIT_FIT_POOL_H
#define BRDFFIT_FIT_POOL_H

#include <pthread.h>
#include <stddef.h>

#define BF_POOL_MAX 63

typedef void (*bf_task_fn)(void *arg, size_t task);

typedef struct bf_pool bf_pool;

typedef struct bf_pool_slot {
    bf_pool *pool;
    size_t index; /* runs task index + 1 */
} bf_pool_slot;

struct bf_pool {
    pthread_mutex_t mutex;
    pthread_cond_t wake, done;
    pthread_t tid[BF_POOL_MAX];
    bf_pool_slot slot[BF_POOL_MAX];
    size_t n_helpers;        /* helper threads running */
    unsigned long generation;/* one per bf_pool_run with work for helpers */
    size_t pending;          /* helper tasks of this generation not finished */
    int stop;
    bf_task_fn fn;
    void *arg;
    size_t n_tasks;
    int ready;               /* mutex and conditions initialised */
};

/* Start up to `helpers` threads (at most BF_POOL_MAX); fewer when the
 * system refuses, none on failure to set up the synchronisation. Never
 * fails: the calling thread runs whatever no helper takes. */
void bf_pool_start(bf_pool *pool, size_t helpers);

/* Run fn(arg, t) for t = 0 .. n_tasks - 1 and return when all are done:
 * task 0 and the tasks beyond the helpers on the calling thread, task t
 * on helper t - 1. */
void bf_pool_run(bf_pool *pool, bf_task_fn fn, void *arg, size_t n_tasks);

/* Stop and join the helpers. */
void bf_pool_stop(bf_pool *pool);

#endif /* BRDFFIT_FIT_POOL_H */
