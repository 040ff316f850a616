/* Worker pool (internal, pool.c): the threads that render bands of a frame. */
#ifndef EW_POOL_H
#define EW_POOL_H

#include "edgewise_lab.h"  /* EW_BANDS_PER_THREAD, EW_DRAW_ITEMS_PER_THREAD */

#define EW_MAX_THREADS 64
#define EW_MAX_BANDS (EW_MAX_THREADS * EW_BANDS_PER_THREAD)
#define EW_MAX_ITEMS (EW_MAX_THREADS * EW_DRAW_ITEMS_PER_THREAD)

typedef struct ew_pool ew_pool;
ew_pool *ew_pool_create(int threads);
void     ew_pool_free(ew_pool *p);
int      ew_pool_threads(const ew_pool *p);
/* The processors this process may run on (its affinity, as `taskset` or a
 * container sets it), at least 1: what "one thread per core" means. */
int      ew_pool_cores(void);
/* Runs job(ctx, 0) on the caller and job(ctx, i) on each worker i that
 * comes in before the caller's own call returns, and waits for those: a
 * worker asleep or off its core meanwhile is not waited for.  So a job
 * shares its work out (atomic counters) and must not count on any index
 * but 0 running.  A pool of one thread (no workers) runs job(ctx, 0) on
 * the caller, as does p == NULL. */
void     ew_pool_run(ew_pool *p, void (*job)(void *ctx, int index), void *ctx);
/* Wall time (ms) spent inside ew_pool_run since the pool was made, call to
 * return: the frame's parallel sections, whatever calls them; everything
 * else a frame does is serial (ew_stats.ms_serial).  0 for NULL. */
double   ew_pool_parallel_ms(const ew_pool *p);
/* The last ew_pool_run's wall time, call to return, and its busy time:
 * the time the caller and each worker that came in spent inside the job,
 * summed (ms).  busy / wall is how many threads the run kept busy on
 * average (at most the pool's threads); busy on N threads over busy on
 * one is the extra work N threads do in that run.  0 and 0 for NULL or
 * before the first run. */
void     ew_pool_last_run(const ew_pool *p, double *wall_ms, double *busy_ms);
/* Gets sleeping workers polling for a while (a frame's serial front end is
 * starting), so the first parallel phase does not wait on a kernel wake-up. */
void     ew_pool_wake(ew_pool *p);
/* The frame is over: workers stop polling and sleep (until the next
 * ew_pool_wake or job), at once unless frames come back to back (then
 * after 0.1 ms at most), so nothing is burnt between spaced frames. */
void     ew_pool_rest(ew_pool *p);
/* Processor time (ms) the workers spent inside jobs since the pool was
 * made, all workers together (not the caller's: ew_pool_thread_cpu_ms
 * times that); 0 for NULL or one thread.  A worker adds a job's time just
 * after the caller stops waiting for it, so a read may miss the last one. */
double   ew_pool_work_ms(const ew_pool *p);
/* The calling thread's processor time in ms (0 where there is no such clock). */
double   ew_pool_thread_cpu_ms(void);

#endif
