/* A small persistent worker pool: ew_pool_run(pool, job, ctx) runs
 * job(ctx, i) for i = 0..threads-1, index 0 on the calling thread, and
 * returns when all are done.  Threads are created once per renderer, so a
 * frame pays two condition-variable handoffs per phase, not thread starts. */
#include "ew_render.h"

#include <pthread.h>
#include <stdlib.h>

struct ew_pool {
    int              threads;     /* including the caller */
    pthread_t       *tid;
    pthread_mutex_t  mu;
    pthread_cond_t   start, done;
    unsigned         generation;
    int              pending;
    int              quit;
    void           (*job)(void *ctx, int index);
    void            *ctx;
};

typedef struct worker_arg { ew_pool *p; int index; } worker_arg;

static void *worker(void *vp) {
    worker_arg *wa = vp;
    ew_pool *p = wa->p;
    int index = wa->index;
    free(wa);
    unsigned seen = 0;
    pthread_mutex_lock(&p->mu);
    for (;;) {
        while (p->generation == seen && !p->quit) pthread_cond_wait(&p->start, &p->mu);
        if (p->quit) break;
        seen = p->generation;
        void (*job)(void *, int) = p->job;
        void *ctx = p->ctx;
        pthread_mutex_unlock(&p->mu);
        job(ctx, index);
        pthread_mutex_lock(&p->mu);
        if (--p->pending == 0) pthread_cond_signal(&p->done);
    }
    pthread_mutex_unlock(&p->mu);
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

void ew_pool_run(ew_pool *p, void (*job)(void *ctx, int index), void *ctx) {
    if (!p || p->threads == 1) {
        job(ctx, 0);
        return;
    }
    pthread_mutex_lock(&p->mu);
    p->job = job, p->ctx = ctx;
    p->pending = p->threads - 1;
    p->generation++;
    pthread_cond_broadcast(&p->start);
    pthread_mutex_unlock(&p->mu);
    job(ctx, 0);
    pthread_mutex_lock(&p->mu);
    while (p->pending > 0) pthread_cond_wait(&p->done, &p->mu);
    pthread_mutex_unlock(&p->mu);
}

void ew_pool_free(ew_pool *p) {
    if (!p) return;
    pthread_mutex_lock(&p->mu);
    p->quit = 1;
    pthread_cond_broadcast(&p->start);
    pthread_mutex_unlock(&p->mu);
    for (int i = 1; i < p->threads; i++) pthread_join(p->tid[i], NULL);
    pthread_mutex_destroy(&p->mu);
    pthread_cond_destroy(&p->start);
    pthread_cond_destroy(&p->done);
    free(p->tid);
    free(p);
}
