/* The worker pool (src/pool.c): every run does all of its shared work
 * exactly once and returns only when every worker that came in has left,
 * with more threads than cores and with workers put to sleep between runs,
 * so that some come late or not at all. */
#define _GNU_SOURCE  /* nanosleep; sched_getcpu, sched_setaffinity (Linux) */
#include "util.h"
#include "pool.h"

#include <sched.h>
#include <signal.h>
#include <stdatomic.h>
#include <time.h>
#include <unistd.h>

typedef struct run {
    atomic_int next, items_done, inside, joined;
    int        n;
    int        wait;  /* the caller's part waits (up to 2 s) for a worker to come in */
    atomic_int worker_cpu, caller_cpu;  /* where a worker and the caller ran the job (Linux), else -1 */
} run;

static int cpu_now(void) {
#ifdef __linux__
    return sched_getcpu();
#else
    return -1;
#endif
}

static atomic_int sink;  /* the items' busy work goes somewhere */

static void nap_us(long us) {
    struct timespec ts = {0, us * 1000};
    nanosleep(&ts, NULL);
}

static void job(void *vp, int index) {
    run *r = vp;
    atomic_fetch_add(&r->inside, 1);
    if (index > 0) atomic_fetch_add(&r->joined, 1), atomic_store(&r->worker_cpu, cpu_now());
    for (int i; (i = atomic_fetch_add(&r->next, 1)) < r->n;) {
        for (int k = 0; k < 300; k++) atomic_store_explicit(&sink, k, memory_order_relaxed);
        atomic_fetch_add(&r->items_done, 1);
    }
    for (int ms = 0; index == 0 && r->wait && atomic_load(&r->joined) == 0 && ms < 2000; ms++) nap_us(1000);
    if (index == 0) atomic_store(&r->caller_cpu, cpu_now());
    atomic_fetch_sub(&r->inside, 1);
}

static double process_cpu_ms(void) {
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec / 1e6;
}

/* A worker that comes in burns 2 ms of its own processor time; the caller
 * waits (up to 2 s) for one to come in and finish. */
typedef struct busy { atomic_int joined, done; } busy;
static void busy_job(void *vp, int index) {
    busy *b = vp;
    if (index > 0) {
        atomic_store(&b->joined, 1);
        double t0 = ew_pool_thread_cpu_ms();
        while (ew_pool_thread_cpu_ms() - t0 < 2.0) atomic_store_explicit(&sink, 1, memory_order_relaxed);
        atomic_store(&b->done, 1);
        return;
    }
    for (int ms = 0; !atomic_load(&b->done) && ms < 2000; ms++) nap_us(1000);
}

/* A pool that loses track of its workers can hang instead of failing. */
static void hung(int sig) {
    (void)sig;
    static const char msg[] = "FAIL test_pool: still running after 120 s (the pool hung)\n";
    if (write(2, msg, sizeof msg - 1) < 0) _exit(2);
    _exit(1);
}

int main(void) {
    signal(SIGALRM, hung);
    alarm(120);
    const int counts[] = {1, 2, 4, 8};
    for (int c = 0; c < 4; c++) {
        int threads = counts[c];
        ew_pool *p = ew_pool_create(threads);
        CHECK(p != NULL && ew_pool_threads(p) == threads, "a pool of %d threads", threads);
        if (!p) continue;
        long joined = 0, bad_items = 0, still_inside = 0, too_many = 0;
        const int runs = 3000;
        for (int k = 0; k < runs; k++) {
            /* Now and then the workers fall asleep (past the pool's spin)
             * and the next run starts with or without a wake-up call. */
            if (k % 200 == 199) {
                nap_us(2000);
                if (k % 400 == 399) ew_pool_wake(p);
            }
            run r = {0};
            r.n = k % 61;
            ew_pool_run(p, job, &r);
            bad_items += atomic_load(&r.items_done) != r.n;
            still_inside += atomic_load(&r.inside) != 0;
            too_many += atomic_load(&r.joined) > threads - 1;
            joined += atomic_load(&r.joined);
        }
        CHECK(bad_items == 0, "%d threads: %ld runs did not do their items exactly once", threads, bad_items);
        CHECK(still_inside == 0, "%d threads: %ld runs returned with a worker still in the job", threads,
              still_inside);
        CHECK(too_many == 0, "%d threads: %ld runs had more workers than the pool", threads, too_many);
        /* Runs this short may all end before a worker is scheduled (another
         * test busy on the other core): one more run whose caller waits for
         * a worker shows that they do come in. */
        run last = {.n = 1, .wait = threads > 1};
        ew_pool_run(p, job, &last);
        CHECK(atomic_load(&last.items_done) == 1 && atomic_load(&last.inside) == 0, "%d threads: the waiting run",
              threads);
        joined += atomic_load(&last.joined);
        if (threads == 1)
            CHECK(joined == 0, "a pool of one thread has no workers (%ld joined)", joined);
        else
            CHECK(joined > 0, "%d threads: no worker took part in %d runs nor in one that waited 2 s", threads, runs);
        printf("%d threads: workers took part %ld times in %d runs (at most %ld)\n", threads, joined, runs + 1,
               (long)(runs + 1) * (threads - 1));
        ew_pool_free(p);
    }
#ifdef __linux__
    /* Frames spaced out, as in the viewer: the workers sleep between them,
     * and the kernel tends to wake a worker on the processor of the thread
     * that wakes it (on a virtual machine nearly always).  A worker must
     * not stay there, polling, while the caller has the frame to run. */
    if (ew_pool_cores() >= 2) {
        ew_pool *p = ew_pool_create(2);
        int frames = 0, apart = 0;
        for (int k = 0; p && k < 20; k++) {
            nap_us(20000);  /* past the pool's polling: the worker sleeps */
            ew_pool_wake(p);
            run r = {.n = 1, .wait = 1};
            atomic_store(&r.worker_cpu, -1);
            ew_pool_run(p, job, &r);
            int w = atomic_load(&r.worker_cpu), c = atomic_load(&r.caller_cpu);
            frames += w >= 0 && c >= 0;
            apart += w >= 0 && c >= 0 && w != c;
        }
        CHECK(p && frames >= 15 && apart >= frames * 3 / 4,
              "a woken worker leaves the caller's processor: apart in %d of %d frames", apart, frames);
        printf("frames spaced out: the worker ran on another processor than the caller in %d of %d\n", apart,
               frames);
        ew_pool_free(p);
    }
    /* "One thread per core" counts the processors the process may use. */
    cpu_set_t was, one;
    if (sched_getaffinity(0, sizeof was, &was) == 0) {
        CPU_ZERO(&one);
        CPU_SET(cpu_now(), &one);
        if (sched_setaffinity(0, sizeof one, &one) == 0) {
            CHECK(ew_pool_cores() == 1, "bound to one processor, ew_pool_cores() is %d", ew_pool_cores());
            sched_setaffinity(0, sizeof was, &was);
        }
        CHECK(ew_pool_cores() == CPU_COUNT(&was), "ew_pool_cores() %d, the process's processors %d",
              ew_pool_cores(), CPU_COUNT(&was));
    }
#endif
    /* The end of a frame (ew_pool_rest): the workers sleep at once, where
     * they polled 0.6-4.8 ms after each frame before; a viewer spacing its
     * frames 16 ms apart burnt a third of a core on it. */
    if (ew_pool_cores() >= 2) {
        ew_pool *p = ew_pool_create(2);
        double idle_cpu = 0;
        for (int k = 0; p && k < 10; k++) {
            ew_pool_wake(p);  /* a frame starts: the worker polls for its first job */
            run r = {.n = 20};
            ew_pool_run(p, job, &r);
            ew_pool_rest(p);
            double c0 = process_cpu_ms();
            nap_us(20000);
            idle_cpu += process_cpu_ms() - c0;
        }
        CHECK(p && idle_cpu < 2.0, "after ew_pool_rest the workers sleep: %.2f ms of processor time in 10 pauses of 20 ms",
              idle_cpu);
        printf("processor time in 10 pauses of 20 ms after ew_pool_rest: %.3f ms\n", idle_cpu);
        /* The workers' time inside jobs is counted (not the caller's). */
        double w0 = ew_pool_work_ms(p);
        busy b = {0};
        ew_pool_run(p, busy_job, &b);
        nap_us(20000);  /* the worker adds its time after leaving the job */
        double w = ew_pool_work_ms(p) - w0;
        CHECK(!atomic_load(&b.joined) || (w >= 1.5 && w < 1000),
              "a worker's 2 ms of processor time in a job counted as %.3f ms", w);
        CHECK(ew_pool_work_ms(NULL) == 0, "no pool: no workers' time");
        /* The run's busy time: the caller's (it waited for the worker's
         * 2 ms) and the worker's, summed; at most twice its wall time. */
        double wall, busy_ms;
        ew_pool_last_run(p, &wall, &busy_ms);
        CHECK(wall >= 2.0 && busy_ms <= 2 * wall + 1e-6 && (!atomic_load(&b.joined) || busy_ms >= 3.5),
              "the last run: wall %.3f ms, busy %.3f ms, a worker in: %d", wall, busy_ms, atomic_load(&b.joined));
        ew_pool_last_run(NULL, &wall, &busy_ms);
        CHECK(wall == 0 && busy_ms == 0, "no pool: no run");
        ew_pool_free(p);
    }
    /* NULL: the caller alone. */
    run r = {0};
    r.n = 10;
    ew_pool_run(NULL, job, &r);
    CHECK(atomic_load(&r.items_done) == 10 && atomic_load(&r.joined) == 0, "no pool: the caller's part only");
    return ew_t_finish();
}
