/* A small persistent worker pool: ew_pool_run(pool, job, ctx) runs
 * job(ctx, i) for i = 0..threads-1, index 0 on the calling thread, and
 * returns when all are done.  Threads are created once per renderer.  A
 * frame has a few short phases, so both sides spin briefly before they
 * sleep on a condition variable: a wake-up through the kernel costs more
 * than a phase at small frame sizes.  ew_pool_wake, called as a frame
 * starts, has sleeping workers poll through the serial front end. */
#include "renderer.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>

#define SPIN_ROUNDS 20000  /* about 50-100 microseconds of polling */
#define WAKE_ROUNDS (8 * SPIN_ROUNDS)  /* after ew_pool_wake: long enough for a front end */

struct ew_pool {
    int              threads;     /* including the caller */
    pthread_t       *tid;
    pthread_mutex_t  mu;
    pthread_cond_t   start, done;
    atomic_uint      generation;  /* bumped to start a job */
    atomic_uint      wakes;       /* bumped by ew_pool_wake */
    atomic_int       pending;     /* workers still running it */
    atomic_int       quit;
    void           (*job)(void *ctx, int index);
    void            *ctx;
};

typedef struct worker_arg { ew_pool *p; int index; } worker_arg;

static inline void relax(void) {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
}

static void *worker(void *vp) {
    worker_arg *wa = vp;
    ew_pool *p = wa->p;
    int index = wa->index;
    free(wa);
    unsigned seen = 0, woken = 0;
    int rounds = SPIN_ROUNDS;
    for (;;) {
        unsigned g = atomic_load(&p->generation);
        for (int k = 0; k < rounds && g == seen && !atomic_load(&p->quit); k++) {
            relax();
            g = atomic_load(&p->generation);
        }
        rounds = SPIN_ROUNDS;
        if (g == seen && !atomic_load(&p->quit)) {
            pthread_mutex_lock(&p->mu);
            while ((g = atomic_load(&p->generation)) == seen && atomic_load(&p->wakes) == woken &&
                   !atomic_load(&p->quit))
                pthread_cond_wait(&p->start, &p->mu);
            pthread_mutex_unlock(&p->mu);
            if (g == seen && atomic_load(&p->wakes) != woken) {  /* a frame is starting */
                woken = atomic_load(&p->wakes);
                rounds = WAKE_ROUNDS;
                continue;
            }
        }
        if (atomic_load(&p->quit)) break;
        seen = g;
        woken = atomic_load(&p->wakes);  /* a wake before this job is used up */
        p->job(p->ctx, index);  /* job and ctx were set before the bump */
        if (atomic_fetch_sub(&p->pending, 1) == 1) {
            pthread_mutex_lock(&p->mu);
            pthread_cond_signal(&p->done);
            pthread_mutex_unlock(&p->mu);
        }
    }
    return NULL;
}

ew_pool *ew_pool_create(int threads) {
    ew_pool *p = calloc(1, sizeof *p);
    if (!p) return NULL;
    p->threads = 1;
    pthread_mutex_init(&p->mu, NULL);
    pthread_cond_init(&p->start, NULL);
    pthread_cond_init(&p->done, NULL);
    p->tid = calloc((size_t)threads, sizeof(pthread_t));
    if (!p->tid) {
        ew_pool_free(p);
        return NULL;
    }
    for (int i = 1; i < threads; i++) {
        worker_arg *wa = malloc(sizeof *wa);
        if (!wa) break;
        wa->p = p, wa->index = i;
        if (pthread_create(&p->tid[i], NULL, worker, wa) != 0) {
            free(wa);
            break;
        }
        p->threads = i + 1;
    }
    return p;
}

int ew_pool_threads(const ew_pool *p) { return p ? p->threads : 1; }

void ew_pool_wake(ew_pool *p) {
    if (!p || p->threads == 1) return;
    pthread_mutex_lock(&p->mu);
    atomic_fetch_add(&p->wakes, 1);
    pthread_cond_broadcast(&p->start);
    pthread_mutex_unlock(&p->mu);
}

void ew_pool_run(ew_pool *p, void (*job)(void *ctx, int index), void *ctx) {
    if (!p || p->threads == 1) {
        job(ctx, 0);
        return;
    }
    p->job = job, p->ctx = ctx;
    atomic_store(&p->pending, p->threads - 1);
    pthread_mutex_lock(&p->mu);
    atomic_fetch_add(&p->generation, 1);  /* publishes job and ctx */
    pthread_cond_broadcast(&p->start);
    pthread_mutex_unlock(&p->mu);
    job(ctx, 0);
    for (int k = 0; k < SPIN_ROUNDS && atomic_load(&p->pending) > 0; k++) relax();
    if (atomic_load(&p->pending) > 0) {
        pthread_mutex_lock(&p->mu);
        while (atomic_load(&p->pending) > 0) pthread_cond_wait(&p->done, &p->mu);
        pthread_mutex_unlock(&p->mu);
    }
}

void ew_pool_free(ew_pool *p) {
    if (!p) return;
    pthread_mutex_lock(&p->mu);
    atomic_store(&p->quit, 1);
    pthread_cond_broadcast(&p->start);
    pthread_mutex_unlock(&p->mu);
    for (int i = 1; i < p->threads; i++) pthread_join(p->tid[i], NULL);
    pthread_mutex_destroy(&p->mu);
    pthread_cond_destroy(&p->start);
    pthread_cond_destroy(&p->done);
    free(p->tid);
    free(p);
}
