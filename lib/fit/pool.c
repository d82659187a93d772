/* The helper threads of one fit run: see pool.h. */
#include "fit/pool.h"

#include <string.h>

static void *helper_main(void *arg)
{
    bf_pool_slot *slot = arg;
    bf_pool *pool = slot->pool;
    unsigned long seen = 0;
    pthread_mutex_lock(&pool->mutex);
    for (;;) {
        size_t task = slot->index + 1;
        while (!pool->stop && pool->generation == seen) pthread_cond_wait(&pool->wake, &pool->mutex);
        if (pool->stop) break;
        seen = pool->generation;
        if (task >= pool->n_tasks) continue;
        pthread_mutex_unlock(&pool->mutex);
        pool->fn(pool->arg, task);
        pthread_mutex_lock(&pool->mutex);
        if (--pool->pending == 0) pthread_cond_signal(&pool->done);
    }
    pthread_mutex_unlock(&pool->mutex);
    return NULL;
}

static int init_sync(bf_pool *pool)
{
    if (pthread_mutex_init(&pool->mutex, NULL) != 0) return 0;
    if (pthread_cond_init(&pool->wake, NULL) != 0) {
        pthread_mutex_destroy(&pool->mutex);
        return 0;
    }
    if (pthread_cond_init(&pool->done, NULL) != 0) {
        pthread_cond_destroy(&pool->wake);
        pthread_mutex_destroy(&pool->mutex);
        return 0;
    }
    return 1;
}

void bf_pool_start(bf_pool *pool, size_t helpers)
{
    size_t h;
    memset(pool, 0, sizeof *pool);
    if (helpers == 0 || !init_sync(pool)) return;
    pool->ready = 1;
    if (helpers > BF_POOL_MAX) helpers = BF_POOL_MAX;
    for (h = 0; h < helpers; h++) {
        pool->slot[h].pool = pool;
        pool->slot[h].index = h;
        if (pthread_create(&pool->tid[h], NULL, helper_main, &pool->slot[h]) != 0) break;
        pool->n_helpers = h + 1;
    }
}

void bf_pool_run(bf_pool *pool, bf_task_fn fn, void *arg, size_t n_tasks)
{
    size_t given = 0, t;
    if (pool != NULL && n_tasks > 1)
        given = n_tasks - 1 < pool->n_helpers ? n_tasks - 1 : pool->n_helpers;
    if (given > 0) {
        pthread_mutex_lock(&pool->mutex);
        pool->fn = fn;
        pool->arg = arg;
        pool->n_tasks = n_tasks;
        pool->pending = given;
        pool->generation++;
        pthread_cond_broadcast(&pool->wake);
        pthread_mutex_unlock(&pool->mutex);
    }
    if (n_tasks > 0) fn(arg, 0);
    for (t = given + 1; t < n_tasks; t++) fn(arg, t);
    if (given == 0) return;
    pthread_mutex_lock(&pool->mutex);
    while (pool->pending > 0) pthread_cond_wait(&pool->done, &pool->mutex);
    pthread_mutex_unlock(&pool->mutex);
}

void bf_pool_stop(bf_pool *pool)
{
    size_t h;
    if (!pool->ready) return;
    pthread_mutex_lock(&pool->mutex);
    pool->stop = 1;
    pthread_cond_broadcast(&pool->wake);
    pthread_mutex_unlock(&pool->mutex);
    for (h = 0; h < pool->n_helpers; h++) pthread_join(pool->tid[h], NULL);
    pthread_cond_destroy(&pool->done);
    pthread_cond_destroy(&pool->wake);
    pthread_mutex_destroy(&pool->mutex);
    pool->ready = 0;
    pool->n_helpers = 0;
}
