/* Worker pool (internal, pool.c): the threads that render bands of a frame. */
#ifndef EW_POOL_H
#define EW_POOL_H

#define EW_MAX_THREADS 16
#define EW_BANDS_PER_THREAD 4
#define EW_MAX_BANDS (EW_MAX_THREADS * EW_BANDS_PER_THREAD)

typedef struct ew_pool ew_pool;
ew_pool *ew_pool_create(int threads);
void     ew_pool_free(ew_pool *p);
int      ew_pool_threads(const ew_pool *p);
/* Runs job(ctx, i) for every thread index i, 0 on the caller; waits for all. */
void     ew_pool_run(ew_pool *p, void (*job)(void *ctx, int index), void *ctx);
/* Gets sleeping workers polling for a while (a frame's serial front end is
 * starting), so the first parallel phase does not wait on a kernel wake-up. */
void     ew_pool_wake(ew_pool *p);

#endif
