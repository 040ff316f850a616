/* A small persistent worker pool: ew_pool_run(pool, job, ctx) runs
 * job(ctx, 0) on the calling thread and job(ctx, i) on each worker that
 * joins before the caller's own call returns, and returns when those are
 * done.  The jobs share their work through atomic counters, so a worker
 * still asleep when the caller has finished everything is not waited for:
 * it would only find nothing left, after a kernel wake-up (20-100 us on a
 * busy machine).  Threads are created once per renderer.  A frame has a
 * few short phases, so both sides spin briefly before they sleep on a
 * condition variable: a wake-up through the kernel costs more than a phase
 * at small frame sizes.  ew_pool_wake, called as a frame starts, has
 * sleeping workers poll through the serial front end; ew_pool_rest, called
 * as it ends, sends them to sleep (at once unless frames come back to
 * back), so polling never outlasts a frame: a viewer spacing its frames
 * 16 ms apart burnt a third of a core on workers polling 0.6-4.8 ms. */
#define _GNU_SOURCE  /* sched_getcpu, sched_setaffinity (Linux) */
#include "pool.h"
#include "ew_util.h"

#include <pthread.h>
#include <sched.h>
#include <time.h>
#include <stdatomic.h>
#include <limits.h>
#include <stdlib.h>
#include <unistd.h>

/* Polling is bounded by time, not by a count of pause instructions (whose
 * latency differs tenfold between processors: 20000 of them took 0.57 ms
 * here and would take 0.05 ms on older cores).  Long enough to bridge the
 * serial steps between a frame's phases (0.1-0.6 ms at 1080p), short
 * enough that an idle renderer sleeps at once. */
#define SPIN_MS 0.6
#define WAKE_MS (8 * SPIN_MS)  /* after ew_pool_wake: long enough for a front end */
/* After a frame, workers poll on only while frames come back to back (the
 * last one started within LINGER_MS of the end of the one before), and
 * then for LINGER_MS at most: a renderer drawing frame after frame keeps
 * its workers (a kernel wake-up costs the caller 10-20 us a frame here,
 * 3-5% of a 640x480 frame on two threads), one that spaces its frames
 * burns nothing between them. */
#define LINGER_MS 0.1

/* A worker's processor time inside jobs, on a cache line of its own: the
 * worker writes it, ew_pool_work_ms reads it between runs. */
typedef struct worker_clock {
    _Alignas(64) _Atomic long long ns;
} worker_clock;

/* This thread's processor time in nanoseconds (0 where there is no such clock). */
static long long thread_cpu_ns(void) {
#ifdef CLOCK_THREAD_CPUTIME_ID
    struct timespec t;
    if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t) == 0) return (long long)t.tv_sec * 1000000000LL + t.tv_nsec;
#endif
    return 0;
}

struct ew_pool {
    int              threads;     /* including the caller */
    pthread_t       *tid;
    pthread_mutex_t  mu;
    pthread_cond_t   start, done;
    atomic_uint      generation;  /* bumped to start a job */
    atomic_uint      wakes;       /* bumped by ew_pool_wake */
    atomic_int       resting;     /* set by ew_pool_rest, cleared by ew_pool_wake: no polling */
    atomic_int       linger;      /* 1: frames come back to back, poll LINGER_MS after one */
    double           rest_ms;     /* when the last frame ended (ew_pool_rest), 0 before */
    /* The job's door: its generation << 32, OPEN while the caller runs its
     * own part, and the workers that came in; then how many have finished. */
    _Atomic uint64_t entry;
    atomic_int       finished;
    /* The run's busy time in ns: each worker that came in adds its time
     * inside the job before it counts itself finished, so the caller reads
     * the whole sum once all are. */
    _Atomic long long busy_ns;
    double           last_wall_ms, last_busy_ms;  /* the last run's (ew_pool_last_run) */
    atomic_int       quit;
    atomic_int       caller_cpu;  /* where the caller was when it last woke the workers, -1 unknown */
    void           (*job)(void *ctx, int index);
    void            *ctx;
    double           run_ms;      /* time inside ew_pool_run (the caller's thread only) */
    worker_clock    *work;        /* per worker (index 1..): its processor time inside jobs */
};

/* wake_after: a sleeper is woken after the mutex is let go, not while it
 * is held.  Its state is changed under the mutex, so a sleeper that tested
 * the old state is already waiting and is woken; one that tests later sees
 * the new state.  Woken under the mutex, a sleeper that came round before
 * the unlock found it taken and slept again on it, and the unlock paid a
 * second kernel wake.  On a 2-vCPU virtual machine the caller's wake of a
 * sleeping worker that may wake on the caller's processor took 15-21 us
 * under the mutex, 12-14 us after it; once the worker keeps off that
 * processor (leave_caller_cpu) 11-16 us either way. */
typedef struct worker_arg { ew_pool *p; int index; } worker_arg;

/* A worker woken from its sleep is placed by the kernel, and on a virtual
 * machine that is nearly always the waking thread's own processor: an idle
 * virtual processor looks preempted, so the scheduler passes it over (93 to
 * 98 wakes in 100 here, with the other processor idle).  There the worker
 * polls for its first job while the caller, which has the frame to run, waits
 * for its turn: 0.5-1.2 ms a frame whenever frames are spaced out, as in
 * the viewer, more than a whole frame at 1080p.  So a worker that wakes
 * where the caller is moves itself off that processor: its set becomes the
 * one it started with less the caller's, until it finds the caller elsewhere. */
typedef struct cpus {
#ifdef __linux__
    cpu_set_t start;  /* the worker's processors when it started */
    int       ok;
#endif
} cpus;

static void cpus_init(cpus *c) {
#ifdef __linux__
    c->ok = sched_getaffinity(0, sizeof c->start, &c->start) == 0;
#else
    (void)c;
#endif
}

static int this_cpu(void) {
#ifdef __linux__
    return sched_getcpu();
#else
    return -1;
#endif
}

static void leave_caller_cpu(const cpus *c, int caller) {
#ifdef __linux__
    if (!c->ok || caller < 0 || caller >= CPU_SETSIZE || this_cpu() != caller) return;
    cpu_set_t set = c->start;
    CPU_CLR(caller, &set);
    if (CPU_COUNT(&set) > 0) (void)sched_setaffinity(0, sizeof set, &set);  /* a failure changes nothing */
#else
    (void)c, (void)caller;
#endif
}

static inline void relax(void) {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
}

/* Polls until done(arg) or ms milliseconds have passed (the clock is read
 * every 64 rounds); returns done(arg). */
static int spin_until(int (*done)(void *), void *arg, double ms) {
    double end = ew_now_ms() + ms;
    for (int k = 1;; k++) {
        if (done(arg)) return 1;
        relax();
        if ((k & 63) == 0 && ew_now_ms() > end) return done(arg);
    }
}

typedef struct gen_wait { ew_pool *p; unsigned seen, woken; } gen_wait;
/* A job to run, or a reason to stop polling (the frame ended, the pool closes). */
static int job_posted(void *a) {
    gen_wait *g = a;
    return atomic_load(&g->p->generation) != g->seen || atomic_load(&g->p->quit) || atomic_load(&g->p->resting);
}
/* A job, the pool closing or the next frame's wake (the frame's end ignored). */
static int job_or_wake(void *a) {
    gen_wait *g = a;
    return atomic_load(&g->p->generation) != g->seen || atomic_load(&g->p->quit) ||
           atomic_load(&g->p->wakes) != g->woken;
}
#define OPEN ((uint64_t)1 << 31)
#define JOINED(e) ((int)((e) & (OPEN - 1)))

/* Comes in to job generation g if its caller is still at it. */
static int join(ew_pool *p, unsigned g) {
    uint64_t e = atomic_load(&p->entry);
    while ((unsigned)(e >> 32) == g && (e & OPEN))
        if (atomic_compare_exchange_weak(&p->entry, &e, e + 1)) return 1;
    return 0;
}

typedef struct done_wait { ew_pool *p; int joined; } done_wait;
static int all_done(void *a) {
    done_wait *d = a;
    return atomic_load(&d->p->finished) >= d->joined;
}

static void *worker(void *vp) {
    worker_arg *wa = vp;
    ew_pool *p = wa->p;
    int index = wa->index;
    free(wa);
    unsigned seen = 0, woken = 0;
    double spin = SPIN_MS;
    cpus own;
    cpus_init(&own);
    for (;;) {
        gen_wait gw = {p, seen, woken};
        spin_until(job_posted, &gw, spin);
        unsigned g = atomic_load(&p->generation);
        spin = SPIN_MS;
        /* The frame is over: poll a little longer only for back-to-back frames. */
        if (g == seen && atomic_load(&p->resting) && atomic_load(&p->linger) && spin_until(job_or_wake, &gw, LINGER_MS)) {
            g = atomic_load(&p->generation);
            if (g == seen && atomic_load(&p->wakes) != woken) {  /* the next frame is starting */
                woken = atomic_load(&p->wakes);
                spin = WAKE_MS;
                continue;
            }
        }
        if (g == seen && !atomic_load(&p->quit)) {
            pthread_mutex_lock(&p->mu);
            while ((g = atomic_load(&p->generation)) == seen && atomic_load(&p->wakes) == woken &&
                   !atomic_load(&p->quit))
                pthread_cond_wait(&p->start, &p->mu);
            pthread_mutex_unlock(&p->mu);
            leave_caller_cpu(&own, atomic_load(&p->caller_cpu));
            if (g == seen && atomic_load(&p->wakes) != woken) {  /* a frame is starting */
                woken = atomic_load(&p->wakes);
                spin = WAKE_MS;
                continue;
            }
        }
        if (atomic_load(&p->quit)) break;
        seen = g;
        woken = atomic_load(&p->wakes);  /* a wake before this job is used up */
        /* The processor clock is a system call, where the kernel may switch
         * threads (with more threads than processors it does): read before
         * coming in and after leaving, never while holding items the caller
         * waits for.  So a job's time may land after the caller has read
         * the sum, and count in the next frame's. */
        long long c0 = thread_cpu_ns();
        if (!join(p, g)) continue;  /* too late: the caller has done it all */
        const double t0 = ew_now_ms();
        p->job(p->ctx, index);  /* job and ctx were set before the bump */
        atomic_fetch_add_explicit(&p->busy_ns, (long long)((ew_now_ms() - t0) * 1e6), memory_order_relaxed);
        int f = atomic_fetch_add(&p->finished, 1) + 1;  /* publishes the add above */
        uint64_t e = atomic_load(&p->entry);
        if (!(e & OPEN) && f == JOINED(e)) {  /* the last one the caller waits for */
            pthread_mutex_lock(&p->mu);  /* the caller checks, or waits (wake_after) */
            pthread_mutex_unlock(&p->mu);
            pthread_cond_signal(&p->done);
        }
        atomic_fetch_add_explicit(&p->work[index].ns, thread_cpu_ns() - c0, memory_order_relaxed);
    }
    return NULL;
}

ew_pool *ew_pool_create(int threads) {
    ew_pool *p = calloc(1, sizeof *p);
    if (!p) return NULL;
    p->threads = 1;
    atomic_init(&p->busy_ns, 0);
    atomic_store(&p->caller_cpu, -1);
    pthread_mutex_init(&p->mu, NULL);
    pthread_cond_init(&p->start, NULL);
    pthread_cond_init(&p->done, NULL);
    p->tid = calloc((size_t)threads, sizeof(pthread_t));
    p->work = aligned_alloc(_Alignof(worker_clock), sizeof(worker_clock) * (size_t)(threads > 0 ? threads : 1));
    if (!p->tid || !p->work) {
        ew_pool_free(p);
        return NULL;
    }
    for (int i = 0; i < threads; i++) atomic_init(&p->work[i].ns, 0);
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

int ew_pool_cores(void) {
#ifdef __linux__
    cpu_set_t set;
    if (sched_getaffinity(0, sizeof set, &set) == 0 && CPU_COUNT(&set) > 0) return CPU_COUNT(&set);
#endif
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (int)(n < INT_MAX ? n : INT_MAX) : 1;
}

void ew_pool_wake(ew_pool *p) {
    if (!p || p->threads == 1) return;
    atomic_store(&p->caller_cpu, this_cpu());
    atomic_store(&p->linger, p->rest_ms > 0 && ew_now_ms() - p->rest_ms < LINGER_MS);
    atomic_store(&p->resting, 0);
    pthread_mutex_lock(&p->mu);
    atomic_fetch_add(&p->wakes, 1);
    pthread_mutex_unlock(&p->mu);
    pthread_cond_broadcast(&p->start);  /* after the unlock (wake_after) */
}

/* No lock or broadcast: a polling worker sees the flag within a round and
 * sleeps (after LINGER_MS if frames come back to back); one already
 * asleep stays so. */
void ew_pool_rest(ew_pool *p) {
    if (!p || p->threads == 1) return;
    atomic_store(&p->resting, 1);
    p->rest_ms = ew_now_ms();
}

double ew_pool_parallel_ms(const ew_pool *p) { return p ? p->run_ms : 0; }

double ew_pool_work_ms(const ew_pool *p) {
    long long ns = 0;
    for (int i = 1; p && i < p->threads; i++) ns += atomic_load_explicit(&p->work[i].ns, memory_order_relaxed);
    return (double)ns / 1e6;
}

double ew_pool_thread_cpu_ms(void) { return (double)thread_cpu_ns() / 1e6; }

/* Returns the time the threads spent inside job, summed (ms). */
static double run_job(ew_pool *p, void (*job)(void *ctx, int index), void *ctx) {
    if (p->threads == 1) {
        const double t0 = ew_now_ms();
        job(ctx, 0);
        return ew_now_ms() - t0;
    }
    p->job = job, p->ctx = ctx;
    unsigned g = atomic_load(&p->generation) + 1;
    atomic_store(&p->finished, 0);
    atomic_store_explicit(&p->busy_ns, 0, memory_order_relaxed);  /* published with the generation */
    atomic_store(&p->entry, (uint64_t)g << 32 | OPEN);
    atomic_store(&p->caller_cpu, this_cpu());
    pthread_mutex_lock(&p->mu);
    atomic_store(&p->generation, g);  /* publishes job, ctx and the open door */
    pthread_mutex_unlock(&p->mu);
    pthread_cond_broadcast(&p->start);  /* after the unlock (wake_after) */
    const double t0 = ew_now_ms();
    job(ctx, 0);
    const double own = ew_now_ms() - t0;
    done_wait d = {p, JOINED(atomic_fetch_and(&p->entry, ~OPEN))};  /* no one comes in after this */
    if (!spin_until(all_done, &d, SPIN_MS)) {
        pthread_mutex_lock(&p->mu);
        while (!all_done(&d)) pthread_cond_wait(&p->done, &p->mu);
        pthread_mutex_unlock(&p->mu);
    }
    return own + (double)atomic_load_explicit(&p->busy_ns, memory_order_relaxed) / 1e6;
}

void ew_pool_run(ew_pool *p, void (*job)(void *ctx, int index), void *ctx) {
    if (!p) {
        job(ctx, 0);
        return;
    }
    double t0 = ew_now_ms();
    p->last_busy_ms = run_job(p, job, ctx);
    p->last_wall_ms = ew_now_ms() - t0;
    p->run_ms += p->last_wall_ms;
}

void ew_pool_last_run(const ew_pool *p, double *wall_ms, double *busy_ms) {
    *wall_ms = p ? p->last_wall_ms : 0;
    *busy_ms = p ? p->last_busy_ms : 0;
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
    free(p->work);
    free(p);
}
