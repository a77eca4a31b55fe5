/* The watchdog: interrupts per store (firmware_wasm_store.h).
 *
 * A thread of the worker looks every CRS_WATCH_PERIOD_NS at the board whose firmware may run now
 * (the tick and the phase its board wrote into its shared block: only the board writes them) and
 * times its current call: on the wall clock against its board's deadline (a call past it hung), and
 * in the CPU time of the thread running it against what a worker its boards share gives one call
 * (crs_wasm.call_ns) and one chunk (crs_wasm.chunk_ns: the chunk then ends at its next tick,
 * crs_fw_chunk_over). CPU time, not wall time: what a run takes of the worker is what it used,
 * however busy the machine (a call that waited for a core meanwhile used nothing). It ends the
 * call past a limit, or when the crslab process asked the board to stop (crs_shared.stop: the
 * page's Stop, a page that closed): it says why in the store (crs_wasm.interrupt) and bumps the
 * engine's epoch. A store's call that reaches an epoch, at its next loop iteration or call, goes
 * to its epoch callback (crs_watchdog_on_epoch): the running store's ends with the reason said in
 * it; any other store (its next call after an epoch it did not run in) was told nothing, and goes
 * on. One guard, the store's own reason: no state a firmware can write takes part. */
#define _POSIX_C_SOURCE 200809L

#include <pthread.h>
#include <stdio.h>
#include <time.h>

#include "board_io.h"
#include "firmware_wasm_store.h"

static pthread_mutex_t watch_lock = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t watch_wake = PTHREAD_COND_INITIALIZER;
static crs_wasm *watch_running; /* the board whose firmware may run now (NULL: none) */
static clockid_t watch_cpu;     /* the CPU-time clock of the thread running it */
static int watch_started;

static int64_t cpu_ns(clockid_t clock)
{
    struct timespec ts;
    if (clock_gettime(clock, &ts) != 0) return 0;
    return (int64_t)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

int64_t crs_thread_cpu_ns(void) { return cpu_ns(CLOCK_THREAD_CPUTIME_ID); }

void crs_watchdog_begin(crs_wasm *w)
{
    clockid_t clock;
    if (pthread_getcpuclockid(pthread_self(), &clock) != 0) clock = CLOCK_MONOTONIC;
    pthread_mutex_lock(&watch_lock);
    watch_running = w;
    watch_cpu = clock;
    pthread_cond_signal(&watch_wake);
    pthread_mutex_unlock(&watch_lock);
}

void crs_watchdog_end(void)
{
    pthread_mutex_lock(&watch_lock);
    watch_running = NULL;
    pthread_mutex_unlock(&watch_lock);
}

/* Why the running call of `w` must end now (CRS_FW_TRAP_*), after `ran_ns` of the wall clock and
 * `used_ns` of CPU time; 0: it goes on. */
static int32_t why_end(const crs_wasm *w, const volatile crs_shared *sh, int64_t ran_ns, int64_t used_ns)
{
    if (sh->stop) return CRS_FW_TRAP_STOPPED;
    if (w->deadline_ns > 0 && ran_ns > w->deadline_ns) return CRS_FW_TRAP_INTERRUPT;
    if (w->call_ns > 0 && used_ns > w->call_ns) return CRS_FW_TRAP_TOO_LONG;
    return 0;
}

static void *watchdog(void *unused)
{
    (void)unused;
    const crs_wasm *seen = NULL;
    int64_t seen_tick = -1, since_ns = 0, since_cpu_ns = 0;
    int32_t seen_phase = -1, fired = 0;
    pthread_mutex_lock(&watch_lock);
    for (;;) {
        while (watch_running == NULL) {
            seen = NULL;
            pthread_cond_wait(&watch_wake, &watch_lock);
        }
        crs_wasm *w = watch_running;
        /* the tick and phase its board is in (written by the board, in the worker's main thread) */
        const volatile crs_shared *sh = w->board->shared;
        const int64_t tick = sh->tick;
        const int32_t phase = sh->phase;
        const int64_t now = crs_now_ns(), cpu = cpu_ns(watch_cpu);
        if (w->chunk_ns > 0 && cpu - w->chunk_cpu_ns >= w->chunk_ns) atomic_store(&w->cut, 1);
        const int calling = phase == CRS_PHASE_LAB || phase == CRS_PHASE_PRINTING || phase == CRS_PHASE_LOADING;
        if (!calling || w != seen || tick != seen_tick || phase != seen_phase) {
            seen = w, seen_tick = tick, seen_phase = calling ? phase : -1, since_ns = now, fired = 0;
            since_cpu_ns = cpu;
        }
        if (calling && !fired) {
            const int32_t why = why_end(w, sh, now - since_ns, cpu - since_cpu_ns);
            if (why != 0) {
                atomic_store(&w->interrupt, why);
                crs_wasmtime.engine_increment_epoch(crs_wasm_engine()); /* every store's next check: only w's ends */
                fired = 1;
            }
        }
        pthread_mutex_unlock(&watch_lock);
        const struct timespec period = {0, CRS_WATCH_PERIOD_NS};
        nanosleep(&period, NULL);
        pthread_mutex_lock(&watch_lock);
    }
    return NULL;
}

wasmtime_error_t *crs_watchdog_on_epoch(wasmtime_context_t *context, void *data, uint64_t *delta, uint8_t *kind)
{
    (void)context;
    crs_wasm *w = data;
    *delta = 1;
    *kind = WASMTIME_UPDATE_DEADLINE_CONTINUE;
    const int32_t why = atomic_exchange(&w->interrupt, 0);
    if (why == 0) return NULL; /* an epoch meant for another store's call: go on */
    if (why == CRS_FW_TRAP_TOO_LONG) { /* board->trap says why; the call ends with wasmtime's error */
        crs_wasm_note_over(w, why);
    } else {
        crs_wasm_note(w, why, "");
    }
    return crs_wasmtime.error_new(why == CRS_FW_TRAP_STOPPED ? "stopped" : "interrupted");
}

/* A process forked from one that ran firmware has no watchdog thread: it starts its own. */
static void forget_after_fork(void)
{
    pthread_mutex_init(&watch_lock, NULL);
    pthread_cond_init(&watch_wake, NULL);
    watch_running = NULL;
    watch_started = 0;
}

int crs_watchdog_start(void)
{
    static int fork_handled;
    if (!fork_handled) {
        if (pthread_atfork(NULL, NULL, forget_after_fork) != 0) return -1;
        fork_handled = 1;
    }
    if (watch_started) return 0;
    pthread_t thread;
    pthread_attr_t attr;
    pthread_attr_init(&attr);
    pthread_attr_setdetachstate(&attr, PTHREAD_CREATE_DETACHED);
    const int failed = pthread_create(&thread, &attr, watchdog, NULL);
    pthread_attr_destroy(&attr);
    if (failed) return -1;
    watch_started = 1;
    return 0;
}
