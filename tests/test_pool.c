/* The helper threads of a fit run (lib/fit/pool.c): every task of every
 * run exactly once, whatever the number of helpers, also across many
 * consecutive runs, and the calling thread always takes task 0. */
#include <pthread.h>
#include <string.h>

#include "fit/pool.h"
#include "test_support.h"

#define MAX_TASKS 16

typedef struct tally {
    pthread_mutex_t mutex;
    unsigned count[MAX_TASKS];
    pthread_t task0;
} tally;

static void count_task(void *arg, size_t task)
{
    tally *t = arg;
    pthread_mutex_lock(&t->mutex);
    t->count[task]++;
    if (task == 0) t->task0 = pthread_self();
    pthread_mutex_unlock(&t->mutex);
}

static void run_and_check(bf_pool *pool, size_t n_tasks)
{
    tally t;
    size_t k;
    memset(&t, 0, sizeof t);
    assert_int_equal(pthread_mutex_init(&t.mutex, NULL), 0);
    bf_pool_run(pool, count_task, &t, n_tasks);
    for (k = 0; k < MAX_TASKS; k++) assert_int_equal(t.count[k], k < n_tasks ? 1u : 0u);
    if (n_tasks > 0) assert_true(pthread_equal(t.task0, pthread_self()));
    pthread_mutex_destroy(&t.mutex);
}

static void test_every_task_once(void **state)
{
    static const size_t helpers[] = {0, 1, 3, 7};
    size_t h, n, round;
    (void)state;
    for (h = 0; h < sizeof helpers / sizeof helpers[0]; h++) {
        bf_pool pool;
        bf_pool_start(&pool, helpers[h]);
        assert_true(pool.n_helpers <= helpers[h]);
        for (round = 0; round < 50; round++)
            for (n = 0; n <= MAX_TASKS; n++) run_and_check(&pool, n);
        bf_pool_stop(&pool);
        assert_int_equal(pool.n_helpers, 0);
        bf_pool_stop(&pool); /* stopping twice is harmless */
    }
}

static void test_no_pool(void **state)
{
    (void)state;
    run_and_check(NULL, 0);
    run_and_check(NULL, 1);
    run_and_check(NULL, MAX_TASKS);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_task_once),
        cmocka_unit_test(test_no_pool),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
