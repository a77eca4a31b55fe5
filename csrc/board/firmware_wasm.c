/* The WebAssembly firmware's port (firmware_port.h, firmware_wasm.h).
 *
 * The firmware module runs in a wasmtime store of its own inside the worker: it computes on its own
 * linear memory (fixed in size when it was linked, crslab/lab/firmware.py) and can reach nothing
 * else. Its only imports are the board's: `board.serial_send` (serial_printf), and the WASI calls
 * the C library may make, answered here: stdout and stderr (printf, puts: on the real board they
 * go to CCS's console, not Tera Term) are counted and dropped, exit() ends the run, and everything
 * else (files, the clock, the environment, random bytes, sockets) is refused and named.
 *
 * A worker may hold many boards (crs_board), each with its own firmware: they share one wasmtime
 * engine (per process) and one compiled module per distinct firmware (refcounted, by the module's
 * digest), and each has a store and an instance of its own, so what one firmware does (a trap, a
 * hang) ends its own board only.
 *
 * What each lab() call costs is counted in WebAssembly instructions (wasmtime's fuel), which does
 * not depend on the host's load. A call that does not return is stopped by epoch interruption, per
 * store: a watchdog thread in the worker looks at the board whose firmware is running (the tick and
 * the phase its board wrote into its shared block; only the board writes them) and, once one call
 * has run past that board's deadline, bumps the engine's epoch; only the running store has a
 * deadline of the current epoch (each store's is set again before its board runs a chunk), so only
 * its call traps, at its next loop iteration or call, and its board reports it. No state a firmware
 * can write takes part. Everything read out of the firmware's memory is bounded by its size. */
#define _POSIX_C_SOURCE 200809L

#include "firmware_wasm.h"

#include <dlfcn.h>
#include <pthread.h>
#include <time.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "board_io.h"
#include "firmware_port.h"
#include "wasmtime_api.h"

/* ---- the wasmtime library ------------------------------------------------------------------ */

static crs_wasmtime_api api; /* filled once per process */
static int api_loaded;

#define LOAD_SYMBOL(field, symbol)                                                  \
    do {                                                                            \
        void *f = dlsym(lib, #symbol);                                              \
        if (f == NULL) {                                                            \
            snprintf(error, cap, "%s lacks %s: not the wasmtime crslab needs", path, #symbol); \
            return -1;                                                              \
        }                                                                           \
        memcpy(&api.field, &f, sizeof f);                                           \
    } while (0)

int crs_wasmtime_api_load(crs_wasmtime_api *out, const char *path, char *error, size_t cap)
{
    if (api_loaded) {
        *out = api;
        return 0;
    }
    void *lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (lib == NULL) {
        snprintf(error, cap, "cannot load wasmtime (%s)", dlerror());
        return -1;
    }
    LOAD_SYMBOL(config_new, wasm_config_new);
    LOAD_SYMBOL(config_consume_fuel_set, wasmtime_config_consume_fuel_set);
    LOAD_SYMBOL(config_epoch_interruption_set, wasmtime_config_epoch_interruption_set);
    LOAD_SYMBOL(config_parallel_compilation_set, wasmtime_config_parallel_compilation_set);
    LOAD_SYMBOL(config_max_wasm_stack_set, wasmtime_config_max_wasm_stack_set);
    LOAD_SYMBOL(config_memory_reservation_set, wasmtime_config_memory_reservation_set);
    LOAD_SYMBOL(config_memory_guard_size_set, wasmtime_config_memory_guard_size_set);
    LOAD_SYMBOL(config_memory_reservation_for_growth_set, wasmtime_config_memory_reservation_for_growth_set);
    LOAD_SYMBOL(config_memory_may_move_set, wasmtime_config_memory_may_move_set);
    LOAD_SYMBOL(config_wasm_threads_set, wasmtime_config_wasm_threads_set);
    LOAD_SYMBOL(engine_new_with_config, wasm_engine_new_with_config);
    LOAD_SYMBOL(engine_delete, wasm_engine_delete);
    LOAD_SYMBOL(engine_increment_epoch, wasmtime_engine_increment_epoch);
    LOAD_SYMBOL(module_new, wasmtime_module_new);
    LOAD_SYMBOL(module_delete, wasmtime_module_delete);
    LOAD_SYMBOL(module_serialize, wasmtime_module_serialize);
    LOAD_SYMBOL(module_deserialize_file, wasmtime_module_deserialize_file);
    LOAD_SYMBOL(module_imports, wasmtime_module_imports);
    LOAD_SYMBOL(importtype_vec_delete, wasm_importtype_vec_delete);
    LOAD_SYMBOL(importtype_module, wasm_importtype_module);
    LOAD_SYMBOL(importtype_name, wasm_importtype_name);
    LOAD_SYMBOL(importtype_type, wasm_importtype_type);
    LOAD_SYMBOL(externtype_kind, wasm_externtype_kind);
    LOAD_SYMBOL(externtype_as_functype_const, wasm_externtype_as_functype_const);
    LOAD_SYMBOL(store_new, wasmtime_store_new);
    LOAD_SYMBOL(store_delete, wasmtime_store_delete);
    LOAD_SYMBOL(store_context, wasmtime_store_context);
    LOAD_SYMBOL(store_limiter, wasmtime_store_limiter);
    LOAD_SYMBOL(context_get_data, wasmtime_context_get_data);
    LOAD_SYMBOL(context_set_fuel, wasmtime_context_set_fuel);
    LOAD_SYMBOL(context_get_fuel, wasmtime_context_get_fuel);
    LOAD_SYMBOL(context_set_epoch_deadline, wasmtime_context_set_epoch_deadline);
    LOAD_SYMBOL(linker_new, wasmtime_linker_new);
    LOAD_SYMBOL(linker_delete, wasmtime_linker_delete);
    LOAD_SYMBOL(linker_define_func_unchecked, wasmtime_linker_define_func_unchecked);
    LOAD_SYMBOL(linker_instantiate, wasmtime_linker_instantiate);
    LOAD_SYMBOL(instance_export_get, wasmtime_instance_export_get);
    LOAD_SYMBOL(global_get, wasmtime_global_get);
    LOAD_SYMBOL(func_call_unchecked, wasmtime_func_call_unchecked);
    LOAD_SYMBOL(caller_context, wasmtime_caller_context);
    LOAD_SYMBOL(memory_data, wasmtime_memory_data);
    LOAD_SYMBOL(memory_data_size, wasmtime_memory_data_size);
    LOAD_SYMBOL(trap_new, wasmtime_trap_new);
    LOAD_SYMBOL(trap_code, wasmtime_trap_code);
    LOAD_SYMBOL(trap_message, wasm_trap_message);
    LOAD_SYMBOL(trap_delete, wasm_trap_delete);
    LOAD_SYMBOL(trap_trace, wasm_trap_trace);
    LOAD_SYMBOL(frame_vec_delete, wasm_frame_vec_delete);
    LOAD_SYMBOL(frame_func_name, wasmtime_frame_func_name);
    LOAD_SYMBOL(frame_module_offset, wasm_frame_module_offset);
    LOAD_SYMBOL(error_message, wasmtime_error_message);
    LOAD_SYMBOL(error_delete, wasmtime_error_delete);
    LOAD_SYMBOL(error_exit_status, wasmtime_error_exit_status);
    LOAD_SYMBOL(byte_vec_delete, wasm_byte_vec_delete);
    api_loaded = 1;
    *out = api;
    return 0;
}

/* ---- one loaded firmware --------------------------------------------------------------------- */

/* A compiled module, shared by every board running the same firmware in this process. */
typedef struct crs_wasm_module {
    char key[96];                /* the module's digest (crs_wasm_options.module_key) */
    wasmtime_module_t *module;
    int32_t refs;                /* boards using it */
    struct crs_wasm_module *next;
} crs_wasm_module;

typedef struct {
    crs_board *board;
    wasmtime_store_t *store;
    wasmtime_context_t *ctx;
    wasmtime_linker_t *linker;
    crs_wasm_module *shared;     /* the compiled module (shared) */
    wasmtime_module_t *module;   /* shared->module */
    int64_t deadline_ns;         /* a call running longer is interrupted; 0: never */
    wasmtime_instance_t instance;
    wasmtime_memory_t memory;
    uint8_t *base;               /* the firmware's memory: it grows (its heap) up to the board's limit, */
    uint64_t size;               /* in place: it never moves, so the board's pointers into it hold */
    wasmtime_func_t lab, printing;
    uint64_t fuel_left;          /* fuel after the last call */
} crs_wasm;

/* The process's engine (created by the first load, kept until the process ends), the modules it
 * compiled, and its limits (every board of a process has the same: a later load asking for others
 * is refused). */
static wasm_engine_t *engine;
static uint64_t engine_memory_bytes, engine_stack_bytes;
static crs_wasm_module *modules;

/* ---- the watchdog: interrupts per store ------------------------------------------------------ */

enum { WATCH_PERIOD_NS = 10000000 }; /* how often it looks: a hang is stopped within a deadline + 10 ms */

static pthread_mutex_t watch_lock = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t watch_wake = PTHREAD_COND_INITIALIZER;
static crs_wasm *watch_running;   /* the board whose firmware may run now (NULL: none) */
static int watch_started;

static int64_t watch_now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

static void *watchdog(void *unused);

/* The firmware of `w` may run from now on (until watch_end): its store's deadline is the next
 * epoch, and the watchdog times its calls. */
static void watch_begin(crs_wasm *w)
{
    pthread_mutex_lock(&watch_lock);
    api.context_set_epoch_deadline(w->ctx, 1); /* this store's deadline: the next epoch */
    watch_running = w;
    pthread_cond_signal(&watch_wake);
    pthread_mutex_unlock(&watch_lock);
}

static void watch_end(void)
{
    pthread_mutex_lock(&watch_lock);
    watch_running = NULL;
    pthread_mutex_unlock(&watch_lock);
}

static void *watchdog(void *unused)
{
    (void)unused;
    const crs_wasm *seen = NULL;
    int64_t seen_tick = -1, since_ns = 0;
    int32_t seen_phase = -1, fired = 0;
    pthread_mutex_lock(&watch_lock);
    for (;;) {
        while (watch_running == NULL) {
            seen = NULL;
            pthread_cond_wait(&watch_wake, &watch_lock);
        }
        const crs_wasm *w = watch_running;
        /* the tick and phase its board is in (written by the board, in the worker's main thread) */
        const volatile crs_shared *sh = w->board->shared;
        const int64_t tick = sh->tick;
        const int32_t phase = sh->phase;
        const int64_t now = watch_now_ns();
        const int calling = phase == CRS_PHASE_LAB || phase == CRS_PHASE_PRINTING || phase == CRS_PHASE_LOADING;
        if (!calling || w != seen || tick != seen_tick || phase != seen_phase) {
            seen = w, seen_tick = tick, seen_phase = calling ? phase : -1, since_ns = now, fired = 0;
        } else if (w->deadline_ns > 0 && !fired && now - since_ns > w->deadline_ns) {
            api.engine_increment_epoch(engine); /* only the running store's deadline is this epoch */
            fired = 1;
        }
        pthread_mutex_unlock(&watch_lock);
        const struct timespec period = {0, WATCH_PERIOD_NS};
        nanosleep(&period, NULL);
        pthread_mutex_lock(&watch_lock);
    }
    return NULL;
}

/* A process forked from one that ran firmware (a benchmark's in-process run, then its workers)
 * has neither the watchdog thread nor a use for the parent's engine and modules: it starts its own
 * on its first load (what the parent's were is left alone: it is the parent's). */
static void forget_after_fork(void)
{
    pthread_mutex_init(&watch_lock, NULL);
    pthread_cond_init(&watch_wake, NULL);
    watch_running = NULL;
    watch_started = 0;
    engine = NULL;
    modules = NULL;
}

static int watch_start(void)
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

static const uint64_t FUEL = (uint64_t)1 << 62; /* never runs out: fuel only counts instructions */
enum { WASI_EBADF = 8, WASI_EFAULT = 21, WASI_ESPIPE = 70 };
enum { CONSOLE_FDS = 3, ROOT_FD = 3 }; /* stdin, stdout, stderr; "/" (so a file's name reaches path_open) */

static void set_text(crs_fw_trap *t, const char *text)
{
    snprintf(t->text, sizeof t->text, "%s", text);
}

static void load_failed(crs_board *board, const char *what, const char *detail, size_t detail_len)
{
    crs_fw_trap *t = &board->trap;
    t->kind = CRS_FW_TRAP_LOAD;
    t->phase = CRS_PHASE_LOADING;
    t->tick = board->tick;
    snprintf(t->text, sizeof t->text, "%s%s%.*s", what, detail_len ? ": " : "", (int)detail_len,
             detail != NULL ? detail : "");
}

static void take_error(crs_board *board, const char *what, wasmtime_error_t *err)
{
    wasm_byte_vec_t m = {0, NULL};
    api.error_message(err, &m);
    load_failed(board, what, m.data, m.size);
    api.byte_vec_delete(&m);
    api.error_delete(err);
}

/* `len` bytes at firmware address `addr`, or NULL when they do not all lie in its memory (as large
 * as its heap has grown it). */
static uint8_t *span(crs_wasm *w, uint64_t addr, uint64_t len)
{
    if (addr > w->size || len > w->size - addr) w->size = api.memory_data_size(w->ctx, &w->memory);
    return addr <= w->size && len <= w->size - addr ? w->base + addr : NULL;
}

static uint32_t load_u32(const uint8_t *p)
{
    uint32_t v;
    memcpy(&v, p, sizeof v);
    return v;
}

static void store_u32(uint8_t *p, uint32_t v) { memcpy(p, &v, sizeof v); }

static crs_wasm *of_caller(wasmtime_caller_t *caller)
{
    return api.context_get_data(api.caller_context(caller));
}

/* A trap of the board's own making: `kind` and `text` say why (the text may quote the firmware). */
static wasm_trap_t *board_trap(crs_wasm *w, int32_t kind, const char *text)
{
    crs_fw_trap *t = &w->board->trap;
    t->kind = kind;
    t->phase = w->board->shared != NULL ? w->board->shared->phase : CRS_PHASE_LOADING;
    t->tick = w->board->tick;
    set_text(t, text);
    return api.trap_new(text, strlen(text));
}

/* ---- imports: the board's serial port ------------------------------------------------------- */

static wasm_trap_t *board_serial_send(void *env, wasmtime_caller_t *caller, wasmtime_val_raw_t *a, size_t n)
{
    (void)env;
    crs_wasm *w = of_caller(caller);
    if (n < 3) return board_trap(w, CRS_FW_TRAP_OTHER, "the firmware called board.serial_send wrongly");
    const uint64_t chars = (uint32_t)a[1].i32, formatted = (uint32_t)a[2].i32;
    const uint64_t available = chars < w->size ? (w->size - chars < formatted ? w->size - chars : formatted) : 0;
    a[0].i32 = crs_board_serial_out(w->board, (const char *)w->base + (chars < w->size ? chars : 0),
                                    (uint32_t)available, (uint32_t)formatted);
    return NULL;
}

static wasm_trap_t *board_fault(void *env, wasmtime_caller_t *caller, wasmtime_val_raw_t *a, size_t n)
{
    (void)env;
    crs_wasm *w = of_caller(caller);
    const int32_t kind = n >= 1 ? a[0].i32 : CRS_FW_TRAP_OTHER;
    const int known = kind == CRS_FW_TRAP_NULL || kind == CRS_FW_TRAP_DIVIDE || kind == CRS_FW_TRAP_OVERFLOW;
    w->board->trap.line = n >= 2 && a[1].i32 > 0 ? a[1].i32 : 0;
    return board_trap(w, known ? kind : CRS_FW_TRAP_OTHER, "");
}

/* ---- imports: WASI, as the C library asks for it -------------------------------------------- */

typedef wasm_trap_t *(*wasi_call)(crs_wasm *w, wasmtime_val_raw_t *a, size_t n, const char *name);

static wasm_trap_t *refuse(crs_wasm *w, const char *what)
{
    char text[CRS_FW_TRAP_TEXT];
    snprintf(text, sizeof text, "%s", what);
    return board_trap(w, CRS_FW_TRAP_REFUSED, text);
}

static wasm_trap_t *wasi_fd_write(crs_wasm *w, wasmtime_val_raw_t *a, size_t n, const char *name)
{
    (void)name;
    if (n < 4) return refuse(w, "write to a file");
    const uint32_t fd = (uint32_t)a[0].i32, iovs = (uint32_t)a[1].i32, count = (uint32_t)a[2].i32;
    if (fd != 1 && fd != 2) {
        char text[96];
        snprintf(text, sizeof text, "write to descriptor %u (a file or a pipe: the board has none)", fd);
        return refuse(w, text);
    }
    const uint8_t *vec = span(w, iovs, (uint64_t)count * 8);
    uint8_t *written = span(w, (uint32_t)a[3].i32, 4);
    if (vec == NULL || written == NULL) {
        a[0].i32 = WASI_EFAULT;
        return NULL;
    }
    uint64_t total = 0;
    for (uint32_t i = 0; i < count; ++i) total += load_u32(vec + 8 * (uint64_t)i + 4);
    if (total > UINT32_MAX) total = UINT32_MAX;
    w->board->console_bytes += (int64_t)total; /* CCS's console: counted, not shown */
    store_u32(written, (uint32_t)total);
    a[0].i32 = 0;
    return NULL;
}

static wasm_trap_t *wasi_fd_fdstat_get(crs_wasm *w, wasmtime_val_raw_t *a, size_t n, const char *name)
{
    (void)name;
    if (n < 2) return refuse(w, "use a file");
    const uint32_t fd = (uint32_t)a[0].i32;
    uint8_t *stat = span(w, (uint32_t)a[1].i32, 24);
    if (fd > ROOT_FD) {
        a[0].i32 = WASI_EBADF;
        return NULL;
    }
    if (stat == NULL) {
        a[0].i32 = WASI_EFAULT;
        return NULL;
    }
    memset(stat, 0, 24);
    stat[0] = fd == ROOT_FD ? 3 : 2; /* a directory; a character device (the console) */
    memset(stat + 8, 0xFF, 16);      /* every right: what is refused is refused when it is tried */
    a[0].i32 = 0;
    return NULL;
}

static wasm_trap_t *wasi_fd_seek(crs_wasm *w, wasmtime_val_raw_t *a, size_t n, const char *name)
{
    (void)w, (void)n, (void)name;
    a[0].i32 = (uint32_t)a[0].i32 <= ROOT_FD ? WASI_ESPIPE : WASI_EBADF;
    return NULL;
}

static wasm_trap_t *wasi_fd_console(crs_wasm *w, wasmtime_val_raw_t *a, size_t n, const char *name)
{
    (void)w, (void)n, (void)name; /* fd_close, fd_fdstat_set_flags on the console: nothing to do */
    a[0].i32 = (uint32_t)a[0].i32 <= ROOT_FD ? 0 : WASI_EBADF;
    return NULL;
}

static wasm_trap_t *wasi_fd_prestat_get(crs_wasm *w, wasmtime_val_raw_t *a, size_t n, const char *name)
{
    (void)name;
    uint8_t *out = n >= 2 ? span(w, (uint32_t)a[1].i32, 8) : NULL;
    if ((uint32_t)a[0].i32 != ROOT_FD) {
        a[0].i32 = WASI_EBADF; /* the only folder the C library finds is "/": every path reaches path_open */
        return NULL;
    }
    if (out == NULL) {
        a[0].i32 = WASI_EFAULT;
        return NULL;
    }
    memset(out, 0, 8);
    store_u32(out + 4, 1); /* a directory whose name is one character long */
    a[0].i32 = 0;
    return NULL;
}

static wasm_trap_t *wasi_fd_prestat_dir_name(crs_wasm *w, wasmtime_val_raw_t *a, size_t n, const char *name)
{
    (void)name;
    uint8_t *out = n >= 3 && (uint32_t)a[2].i32 >= 1 ? span(w, (uint32_t)a[1].i32, 1) : NULL;
    if ((uint32_t)a[0].i32 != ROOT_FD || out == NULL) {
        a[0].i32 = WASI_EBADF;
        return NULL;
    }
    out[0] = '/';
    a[0].i32 = 0;
    return NULL;
}

enum { WASI_RIGHT_FD_WRITE = 1 << 6, WASI_O_CREAT = 1, WASI_O_TRUNC = 8 };

static wasm_trap_t *wasi_path_open(crs_wasm *w, wasmtime_val_raw_t *a, size_t n, const char *name)
{
    (void)name;
    if (n < 9) return refuse(w, "open a file");
    const uint32_t path = (uint32_t)a[2].i32, path_len = (uint32_t)a[3].i32, oflags = (uint32_t)a[4].i32;
    const int writing = (oflags & (WASI_O_CREAT | WASI_O_TRUNC)) || (a[5].i64 & WASI_RIGHT_FD_WRITE);
    char shown[512];
    const uint32_t len = path_len < 400 ? path_len : 400;
    const uint8_t *p = span(w, path, len);
    char text[CRS_FW_TRAP_TEXT];
    if (p == NULL) {
        snprintf(text, sizeof text, "open a file (its name lies outside its memory) for %s",
                 writing ? "writing" : "reading");
    } else {
        memcpy(shown, p, len);
        shown[len] = '\0';
        snprintf(text, sizeof text, "open /%s%s for %s", shown, len < path_len ? "..." : "",
                 writing ? "writing" : "reading");
    }
    return refuse(w, text);
}

/* path_filestat_get(fd, flags, path, path_len, buf): stat() of a path, an existence oracle. */
static wasm_trap_t *wasi_path_filestat_get(crs_wasm *w, wasmtime_val_raw_t *a, size_t n, const char *name)
{
    (void)name;
    char text[CRS_FW_TRAP_TEXT];
    const uint32_t len = n >= 4 ? ((uint32_t)a[3].i32 < 400 ? (uint32_t)a[3].i32 : 400) : 0;
    const uint8_t *p = n >= 4 ? span(w, (uint32_t)a[2].i32, len) : NULL;
    if (p == NULL) return refuse(w, "look up a file (stat)");
    snprintf(text, sizeof text, "look up /%.*s (stat)", (int)len, (const char *)p);
    return refuse(w, text);
}

static wasm_trap_t *wasi_proc_exit(crs_wasm *w, wasmtime_val_raw_t *a, size_t n, const char *name)
{
    (void)name;
    w->board->trap.exit_code = n >= 1 ? a[0].i32 : 0;
    return board_trap(w, CRS_FW_TRAP_EXIT, "exit");
}

static wasm_trap_t *wasi_zero(crs_wasm *w, wasmtime_val_raw_t *a, size_t n, const char *name)
{
    (void)w, (void)n, (void)name; /* sched_yield: nothing else runs */
    a[0].i32 = 0;
    return NULL;
}

static const struct {
    const char *name;
    wasi_call call;     /* NULL: refused with `refusal` */
    const char *refusal;
} WASI_CALLS[] = {
    {"fd_write", wasi_fd_write, NULL},
    {"fd_fdstat_get", wasi_fd_fdstat_get, NULL},
    {"fd_seek", wasi_fd_seek, NULL},
    {"fd_close", wasi_fd_console, NULL},
    {"fd_fdstat_set_flags", wasi_fd_console, NULL},
    {"fd_prestat_get", wasi_fd_prestat_get, NULL},
    {"fd_prestat_dir_name", wasi_fd_prestat_dir_name, NULL},
    {"path_open", wasi_path_open, NULL},
    {"path_filestat_get", wasi_path_filestat_get, NULL},
    {"proc_exit", wasi_proc_exit, NULL},
    {"sched_yield", wasi_zero, NULL},
    {"fd_read", NULL, "read from the console or a file (scanf, getchar, fread)"},
    {"fd_pread", NULL, "read a file"},
    {"fd_pwrite", NULL, "write to a file"},
    {"environ_get", NULL, "read the environment (getenv)"},
    {"environ_sizes_get", NULL, "read the environment (getenv)"},
    {"args_get", NULL, "read the command line"},
    {"args_sizes_get", NULL, "read the command line"},
    {"clock_time_get", NULL, "read the host's clock (time, clock, clock_gettime)"},
    {"clock_res_get", NULL, "read the host's clock (time, clock, clock_gettime)"},
    {"random_get", NULL, "read random bytes from the host (getentropy, arc4random)"},
    {"poll_oneoff", NULL, "wait on the host (sleep, usleep, poll)"},
    {"proc_raise", NULL, "raise a signal (raise, kill)"},
};

static wasm_trap_t *wasi_dispatch(void *env, wasmtime_caller_t *caller, wasmtime_val_raw_t *a, size_t n)
{
    crs_wasm *w = of_caller(caller);
    const size_t calls = sizeof WASI_CALLS / sizeof WASI_CALLS[0];
    const uintptr_t i = (uintptr_t)env;
    if (i < calls) {
        if (WASI_CALLS[i].call != NULL) return WASI_CALLS[i].call(w, a, n, WASI_CALLS[i].name);
        return refuse(w, WASI_CALLS[i].refusal);
    }
    return NULL; /* not reached: every other WASI name is defined with wasi_other */
}

static wasm_trap_t *wasi_other(void *env, wasmtime_caller_t *caller, wasmtime_val_raw_t *a, size_t n)
{
    (void)a, (void)n;
    const char *name = env; /* the import's name, kept by the store's lifetime: see define_imports */
    char text[200];
    if (strncmp(name, "sock_", 5) == 0) {
        snprintf(text, sizeof text, "use the network (%.60s)", name);
    } else if (strncmp(name, "path_", 5) == 0) {
        snprintf(text, sizeof text, "look up or change files (%.60s)", name);
    } else if (strncmp(name, "fd_", 3) == 0) {
        snprintf(text, sizeof text, "use a file (%.60s)", name);
    } else {
        snprintf(text, sizeof text, "call the host (WASI's %.60s)", name);
    }
    return refuse(of_caller(caller), text);
}

static int same(const wasm_byte_vec_t *v, const char *s)
{
    return v->size == strlen(s) && memcmp(v->data, s, v->size) == 0;
}

static void free_name(void *name) { free(name); }

/* Define every import of the module in the linker: the board's, and WASI's as the C library asks;
 * 0, or -1 with the load failure noted. */
static int define_imports(crs_wasm *w)
{
    crs_board *board = w->board;
    wasm_importtype_vec_t imports = {0, NULL};
    api.module_imports(w->module, &imports);
    int ok = 0;
    for (size_t k = 0; k < imports.size && ok == 0; ++k) {
        const wasm_importtype_t *it = imports.data[k];
        const wasm_byte_vec_t *mod = api.importtype_module(it), *name = api.importtype_name(it);
        const wasm_externtype_t *type = api.importtype_type(it);
        char shown[160];
        snprintf(shown, sizeof shown, "%.*s.%.*s", (int)(mod->size < 60 ? mod->size : 60), mod->data,
                 (int)(name->size < 60 ? name->size : 60), name->data);
        if (api.externtype_kind(type) != WASM_EXTERN_FUNC) {
            load_failed(board, "the firmware imports something other than a function", shown, strlen(shown));
            ok = -1;
            break;
        }
        const wasm_functype_t *ft = api.externtype_as_functype_const(type);
        wasmtime_func_unchecked_callback_t callback = NULL;
        void *env = NULL;
        void (*finalizer)(void *) = NULL;
        if (same(mod, "board") && same(name, "serial_send")) {
            callback = board_serial_send;
        } else if (same(mod, "board") && same(name, "fault")) {
            callback = board_fault;

        } else if (same(mod, "wasi_snapshot_preview1")) {
            const size_t calls = sizeof WASI_CALLS / sizeof WASI_CALLS[0];
            for (size_t i = 0; i < calls && callback == NULL; ++i) {
                if (same(name, WASI_CALLS[i].name)) {
                    callback = wasi_dispatch;
                    env = (void *)(uintptr_t)i;
                }
            }
            if (callback == NULL) {
                char *kept = calloc(1, name->size + 1);
                if (kept == NULL) {
                    load_failed(board, "out of memory", NULL, 0);
                    ok = -1;
                    break;
                }
                memcpy(kept, name->data, name->size);
                callback = wasi_other;
                env = kept;
                finalizer = free_name;
            }
        } else {
            load_failed(board, "the firmware imports a function the board does not give", shown, strlen(shown));
            ok = -1;
            break;
        }
        wasmtime_error_t *err = api.linker_define_func_unchecked(w->linker, mod->data, mod->size, name->data,
                                                                 name->size, ft, callback, env, finalizer);
        if (err != NULL) {
            take_error(board, "the board cannot give the firmware its imports", err);
            ok = -1;
        }
    }
    api.importtype_vec_delete(&imports);
    return ok;
}

/* ---- calls into the firmware ---------------------------------------------------------------- */

static int32_t kind_of(uint8_t code)
{
    switch (code) {
    case WASMTIME_TRAP_CODE_STACK_OVERFLOW: return CRS_FW_TRAP_STACK;
    case WASMTIME_TRAP_CODE_MEMORY_OUT_OF_BOUNDS:
    case WASMTIME_TRAP_CODE_HEAP_MISALIGNED: return CRS_FW_TRAP_MEMORY;
    case WASMTIME_TRAP_CODE_TABLE_OUT_OF_BOUNDS:
    case WASMTIME_TRAP_CODE_INDIRECT_CALL_TO_NULL:
    case WASMTIME_TRAP_CODE_BAD_SIGNATURE: return CRS_FW_TRAP_CALL;
    case WASMTIME_TRAP_CODE_INTEGER_OVERFLOW: return CRS_FW_TRAP_OVERFLOW;
    case WASMTIME_TRAP_CODE_INTEGER_DIVISION_BY_ZERO: return CRS_FW_TRAP_DIVIDE;
    case WASMTIME_TRAP_CODE_BAD_CONVERSION_TO_INTEGER: return CRS_FW_TRAP_CONVERSION;
    case WASMTIME_TRAP_CODE_UNREACHABLE_CODE_REACHED: return CRS_FW_TRAP_UNREACHABLE;
    case WASMTIME_TRAP_CODE_INTERRUPT: return CRS_FW_TRAP_INTERRUPT;
    default: return CRS_FW_TRAP_OTHER;
    }
}

/* Append wasmtime's message (what happened and the firmware's backtrace, with the lab's file and
 * line when the firmware carries its debug information) to t->text, after a newline. */
static void append_message(crs_fw_trap *t, const wasm_byte_vec_t *m)
{
    size_t used = strlen(t->text);
    if (m->data == NULL || used + 2 >= sizeof t->text) return;
    snprintf(t->text + used, sizeof t->text - used, "%s%.*s", used ? "\n" : "",
             (int)(m->size < sizeof t->text ? m->size : sizeof t->text - 1), m->data);
}

/* Call `f`; 0, or CRS_RUN_TRAPPED with board->trap saying how it stopped. */
static int call(crs_wasm *w, const wasmtime_func_t *f, wasmtime_val_raw_t *args, size_t n, int32_t phase)
{
    wasm_trap_t *trap = NULL;
    wasmtime_error_t *err = api.func_call_unchecked(w->ctx, f, args, n, &trap);
    if (err == NULL && trap == NULL) return 0;
    crs_board *board = w->board;
    crs_fw_trap *t = &board->trap;
    if (t->kind == CRS_FW_TRAP_NONE) { /* not one of the board's own */
        uint8_t code = 0;
        if (trap != NULL) {
            t->kind = api.trap_code(trap, &code) ? kind_of(code) : CRS_FW_TRAP_OTHER;
        } else {
            int status = 0;
            t->kind = api.error_exit_status(err, &status) ? CRS_FW_TRAP_EXIT : CRS_FW_TRAP_OTHER;
            t->exit_code = status;
        }
    }
    wasm_byte_vec_t m = {0, NULL};
    if (trap != NULL) {
        api.trap_message(trap, &m);
    } else {
        api.error_message(err, &m);
    }
    append_message(t, &m);
    if (m.data != NULL) api.byte_vec_delete(&m);
    t->phase = phase;
    t->tick = board->tick;
    if (trap != NULL) api.trap_delete(trap);
    if (err != NULL) api.error_delete(err);
    return CRS_RUN_TRAPPED;
}

static void take_fuel(crs_wasm *w, int64_t *cost)
{
    uint64_t left = w->fuel_left;
    wasmtime_error_t *err = api.context_get_fuel(w->ctx, &left);
    if (err != NULL) api.error_delete(err);
    *cost = (int64_t)(w->fuel_left - left);
    w->fuel_left = left;
}

int crs_fw_call_lab(crs_board *board, int32_t *print)
{
    crs_wasm *w = board->firmware;
    crs_shared *sh = board->shared;
    wasmtime_val_raw_t a[4];
    a[0].f32 = (float)board->enc_rad[0];
    a[1].f32 = (float)board->enc_rad[1];
    a[2].f32 = (float)board->enc_rad[2];
    a[3].i32 = board->safety_flag;
    board->lab_calls++;
    sh->phase = CRS_PHASE_LAB;
    const int code = call(w, &w->lab, a, 4, CRS_PHASE_LAB);
    int64_t cost = 0;
    take_fuel(w, &cost);
    crs_board_lab_cost(board, cost);
    if (code) return code;
    *print = a[0].i32 != 0;
    return 0;
}

int crs_fw_tick_begins(crs_board *board)
{
    (void)board; /* no debugger runs a WebAssembly firmware: crslab debug builds it natively */
    return 0;
}

int crs_fw_call_printing(crs_board *board)
{
    crs_wasm *w = board->firmware;
    wasmtime_val_raw_t a[1];
    board->shared->phase = CRS_PHASE_PRINTING;
    const int code = call(w, &w->printing, a, 0, CRS_PHASE_PRINTING);
    int64_t cost = 0;
    take_fuel(w, &cost);
    return code;
}

/* ---- loading --------------------------------------------------------------------------------- */

static int export_func(crs_wasm *w, const char *name, wasmtime_func_t *out)
{
    wasmtime_extern_t e;
    if (!api.instance_export_get(w->ctx, &w->instance, name, strlen(name), &e) || e.kind != WASMTIME_EXTERN_FUNC) {
        return -1;
    }
    *out = e.of.func;
    return 0;
}

/* A host pointer to `bytes` at firmware address `addr` aligned to `align`, or NULL. */
static void *view(crs_wasm *w, uint32_t addr, uint64_t bytes, uint32_t align)
{
    if (addr == 0 || addr % align != 0) return NULL;
    return span(w, addr, bytes);
}

/* The firmware's table (firmware.h: crs_fw_table, 32-bit addresses in WebAssembly). */
enum {
    T_TAU = 0, T_OFFSET2 = 1, T_OFFSET3 = 2, T_PLOT = 3, T_GPIO = 7, T_SIMULINK = 8, T_MATLAB_LOCK = 15,
    T_SYMBOLS = 16, T_WORDS = 18
};

static int read_table(crs_wasm *w, uint32_t address)
{
    crs_board *board = w->board;
    const uint8_t *t = span(w, address, 4 * T_WORDS);
    if (t == NULL) return -1;
    uint32_t word[T_WORDS];
    for (int i = 0; i < T_WORDS; ++i) word[i] = load_u32(t + 4 * i);
    crs_fw_view *v = &board->fw;
    memset(v, 0, sizeof *v);
    v->tau = view(w, word[T_TAU], 3 * sizeof(float), 4);
    v->offset_enc2 = view(w, word[T_OFFSET2], sizeof(float), 4);
    v->offset_enc3 = view(w, word[T_OFFSET3], sizeof(float), 4);
    for (int i = 0; i < 4; ++i) v->plot[i] = view(w, word[T_PLOT + i], sizeof(float), 4);
    v->gpio = view(w, word[T_GPIO], 8 * sizeof(uint32_t), 4);
    for (int i = 0; i < 7; ++i) v->simulink_input[i] = view(w, word[T_SIMULINK + i], sizeof(int32_t), 4);
    v->matlab_lock = view(w, word[T_MATLAB_LOCK], sizeof(float), 4);
    v->symbols = (int32_t)word[T_SYMBOLS];
    return v->tau != NULL && v->gpio != NULL ? 0 : -1;
}

int crs_fw_wasm_preload(const char *libwasmtime)
{
    char error[256];
    return crs_wasmtime_api_load(&api, libwasmtime, error, sizeof error) == 0 ? 0 : -1;
}

/* The module as wasmtime compiled it for this engine, from `path` (crslab's build cache, written by
 * keep_compiled from this firmware's bytes), or NULL when there is none or wasmtime refuses it
 * (another wasmtime or another configuration: its header says so), and it is compiled anew. */
static wasmtime_module_t *load_compiled(const char *path)
{
    if (access(path, R_OK) != 0) return NULL;
    wasmtime_module_t *module = NULL;
    wasmtime_error_t *err = api.module_deserialize_file(engine, path, &module);
    if (err == NULL) return module;
    api.error_delete(err);
    return NULL;
}

/* Keep the compiled module at `path` for the next run of the same firmware (written whole to a
 * file of its own, then renamed into place: a run reading it never sees half of it). A cache:
 * when it cannot be written, the next run compiles again. */
static void keep_compiled(const wasmtime_module_t *module, const char *path)
{
    wasm_byte_vec_t bytes = {0, NULL};
    wasmtime_error_t *err = api.module_serialize((wasmtime_module_t *)module, &bytes);
    if (err != NULL) {
        api.error_delete(err);
        return;
    }
    char partial[4096];
    const int n = snprintf(partial, sizeof partial, "%s.%ld.partial", path, (long)getpid());
    if (n > 0 && (size_t)n < sizeof partial) {
        FILE *f = fopen(partial, "wb");
        if (f != NULL) {
            const int whole = fwrite(bytes.data, 1, bytes.size, f) == bytes.size;
            if (fclose(f) == 0 && whole && rename(partial, path) == 0) partial[0] = '\0';
            if (partial[0] != '\0') remove(partial);
        }
    }
    api.byte_vec_delete(&bytes);
}

/* The engine configuration of every board, for the memory and stack of `o`: the process's engine
 * (engine_for) and crs_fw_wasm_compile's are made alike, so a module one compiled the other loads. */
static wasm_config_t *engine_config(const crs_wasm_options *o)
{
    wasm_config_t *config = api.config_new();
    api.config_consume_fuel_set(config, true);
    api.config_epoch_interruption_set(config, true);
    api.config_parallel_compilation_set(config, false); /* the worker compiles in its main thread */
    api.config_wasm_threads_set(config, false);
    api.config_max_wasm_stack_set(config, (size_t)o->stack_bytes);
    /* the memory grows (the lab's heap) up to the board's limit, within one reservation, so it never
     * moves and needs no more address space than that (bounds are checked explicitly): a memory
     * limit on the worker holds */
    api.config_memory_reservation_set(config, o->memory_bytes);
    api.config_memory_reservation_for_growth_set(config, 0);
    api.config_memory_guard_size_set(config, 0);
    api.config_memory_may_move_set(config, false);
    return config;
}

int crs_fw_wasm_compile(const crs_wasm_options *o, char *error, size_t error_size)
{
    if (crs_wasmtime_api_load(&api, o->libwasmtime, error, error_size) != 0) return -1;
    if (o->compiled_path == NULL) {
        snprintf(error, error_size, "there is no place to keep the compiled module");
        return -1;
    }
    wasm_engine_t *own = api.engine_new_with_config(engine_config(o));
    if (own == NULL) {
        snprintf(error, error_size, "wasmtime cannot start");
        return -1;
    }
    wasmtime_module_t *module = NULL;
    wasmtime_error_t *err = api.module_new(own, o->wasm, (size_t)o->wasm_len, &module);
    int code = 0;
    if (err != NULL) {
        wasm_byte_vec_t m = {0, NULL};
        api.error_message(err, &m);
        snprintf(error, error_size, "not a WebAssembly module wasmtime can run: %.*s", (int)m.size,
                 m.data != NULL ? m.data : "");
        api.byte_vec_delete(&m);
        api.error_delete(err);
        code = -1;
    } else {
        keep_compiled(module, o->compiled_path);
        api.module_delete(module);
        if (access(o->compiled_path, R_OK) != 0) {
            snprintf(error, error_size, "the compiled module could not be kept at %s", o->compiled_path);
            code = -1;
        }
    }
    api.engine_delete(own);
    return code;
}

/* The process's engine, created with the board's limits by the first load; 0, or -1 with
 * board->trap saying why. */
static int engine_for(crs_board *board, const crs_wasm_options *o)
{
    if (engine != NULL) {
        if (o->memory_bytes == engine_memory_bytes && o->stack_bytes == engine_stack_bytes) return 0;
        load_failed(board, "this worker's boards have other memory or stack limits", NULL, 0);
        return -1;
    }
    wasm_config_t *config = engine_config(o);
    engine = api.engine_new_with_config(config);
    if (engine == NULL) {
        load_failed(board, "wasmtime cannot start", NULL, 0);
        return -1;
    }
    engine_memory_bytes = o->memory_bytes;
    engine_stack_bytes = o->stack_bytes;
    return 0;
}

/* The compiled module for `o` (one per distinct module_key, shared and counted), or NULL with
 * board->trap saying why. */
static crs_wasm_module *module_for(crs_board *board, const crs_wasm_options *o)
{
    const char *key = o->module_key != NULL ? o->module_key : "";
    if (key[0] != '\0') {
        for (crs_wasm_module *m = modules; m != NULL; m = m->next) {
            if (strcmp(m->key, key) == 0) {
                m->refs++;
                return m;
            }
        }
    }
    crs_wasm_module *m = calloc(1, sizeof *m);
    if (m == NULL) {
        load_failed(board, "out of memory", NULL, 0);
        return NULL;
    }
    snprintf(m->key, sizeof m->key, "%s", key);
    if (o->compiled_path != NULL) m->module = load_compiled(o->compiled_path);
    if (m->module == NULL) {
        wasmtime_error_t *err = api.module_new(engine, o->wasm, (size_t)o->wasm_len, &m->module);
        if (err != NULL) {
            take_error(board, "not a WebAssembly module wasmtime can run", err);
            free(m);
            return NULL;
        }
        if (o->compiled_path != NULL) keep_compiled(m->module, o->compiled_path);
    }
    m->refs = 1;
    m->next = modules;
    modules = m;
    return m;
}

static void module_release(crs_wasm_module *m)
{
    if (m == NULL || --m->refs > 0) return;
    for (crs_wasm_module **p = &modules; *p != NULL; p = &(*p)->next) {
        if (*p == m) {
            *p = m->next;
            break;
        }
    }
    api.module_delete(m->module);
    free(m);
}

int32_t crs_fw_wasm_module_count(void)
{
    int32_t n = 0;
    for (const crs_wasm_module *m = modules; m != NULL; m = m->next) ++n;
    return n;
}

int32_t crs_fw_wasm_module_held(const char *module_key)
{
    if (module_key == NULL || module_key[0] == '\0') return 0;
    for (const crs_wasm_module *m = modules; m != NULL; m = m->next) {
        if (strcmp(m->key, module_key) == 0) return 1;
    }
    return 0;
}

int32_t crs_fw_wasm_module_refs(const crs_board *board)
{
    const crs_wasm *w = board->firmware;
    return w != NULL && w->shared != NULL ? w->shared->refs : 0;
}

/* Instantiate the module in the store of `w` and run its constructors and crs_fw_start; 0, or
 * CRS_RUN_TRAPPED with board->trap saying why. */
static int start_firmware(crs_wasm *w)
{
    crs_board *board = w->board;
    char error[256];
    wasm_trap_t *trap = NULL;
    wasmtime_error_t *err = api.linker_instantiate(w->linker, w->ctx, w->module, &w->instance, &trap);
    if (err != NULL) {
        take_error(board, "the firmware cannot be started", err);
        return CRS_RUN_TRAPPED;
    }
    if (trap != NULL) {
        wasm_byte_vec_t m = {0, NULL};
        api.trap_message(trap, &m);
        load_failed(board, "the firmware stopped while it was started", m.data, m.size);
        api.byte_vec_delete(&m);
        api.trap_delete(trap);
        return CRS_RUN_TRAPPED;
    }
    wasmtime_extern_t memory;
    if (!api.instance_export_get(w->ctx, &w->instance, "memory", 6, &memory) || memory.kind != WASMTIME_EXTERN_MEMORY) {
        load_failed(board, "the firmware exports no memory", NULL, 0);
        return CRS_RUN_TRAPPED;
    }
    w->memory = memory.of.memory;
    w->base = api.memory_data(w->ctx, &w->memory);
    w->size = api.memory_data_size(w->ctx, &w->memory);
    wasmtime_func_t start;
    if (export_func(w, "crs_fw_start", &start) != 0 || export_func(w, "crs_fw_lab", &w->lab) != 0
        || export_func(w, "crs_fw_printing", &w->printing) != 0) {
        load_failed(board, "not a crslab firmware (crs_fw_start, crs_fw_lab or crs_fw_printing is missing)", NULL, 0);
        return CRS_RUN_TRAPPED;
    }
    board->config.cost_unit = CRS_COST_INSTRUCTIONS;
    wasmtime_func_t initialize;
    wasmtime_val_raw_t a[1];
    if (export_func(w, "_initialize", &initialize) == 0) { /* the C library's and the lab's constructors */
        if (call(w, &initialize, a, 0, CRS_PHASE_LOADING) != 0) return CRS_RUN_TRAPPED;
    }
    a[0].i32 = board->config.generation;
    if (call(w, &start, a, 1, CRS_PHASE_LOADING) != 0) return CRS_RUN_TRAPPED;
    int64_t cost = 0;
    take_fuel(w, &cost); /* the constructors' cost is not lab()'s */
    if (a[0].i32 == 0) {
        snprintf(error, sizeof error, "the firmware cannot run framework generation %d (its generations.c "
                 "is not the board's)", (int)board->config.generation);
        load_failed(board, error, NULL, 0);
        return CRS_RUN_TRAPPED;
    }
    if (read_table(w, (uint32_t)a[0].i32) != 0) {
        load_failed(board, "the firmware's table of the framework's variables is not in its memory", NULL, 0);
        return CRS_RUN_TRAPPED;
    }
    return 0;
}

int crs_fw_wasm_load(crs_board *board, const crs_wasm_options *o)
{
    char error[256];
    memset(&board->trap, 0, sizeof board->trap);
    if (crs_board_check_generation(board) != 0) return CRS_RUN_TRAPPED;
    if (crs_wasmtime_api_load(&api, o->libwasmtime, error, sizeof error) != 0) {
        load_failed(board, error, NULL, 0);
        return CRS_RUN_TRAPPED;
    }
    if (watch_start() != 0) {
        load_failed(board, "the board cannot start its watchdog", NULL, 0);
        return CRS_RUN_TRAPPED;
    }
    if (engine_for(board, o) != 0) return CRS_RUN_TRAPPED;
    crs_wasm *w = calloc(1, sizeof *w);
    if (w == NULL) {
        load_failed(board, "out of memory", NULL, 0);
        return CRS_RUN_TRAPPED;
    }
    w->board = board;
    w->deadline_ns = (int64_t)o->deadline_ns;
    board->firmware = w;
    w->shared = module_for(board, o);
    if (w->shared == NULL) return CRS_RUN_TRAPPED;
    w->module = w->shared->module;
    w->store = api.store_new(engine, w, NULL);
    w->ctx = api.store_context(w->store);
    api.store_limiter(w->store, (int64_t)o->memory_bytes, 100000, 1, 1, 1);
    w->fuel_left = FUEL;
    wasmtime_error_t *err = api.context_set_fuel(w->ctx, FUEL);
    if (err != NULL) {
        take_error(board, "wasmtime cannot count the firmware's instructions", err);
        return CRS_RUN_TRAPPED;
    }
    w->linker = api.linker_new(engine);
    if (define_imports(w) != 0) return CRS_RUN_TRAPPED;
    watch_begin(w); /* the constructors are timed as lab() is */
    const int code = start_firmware(w);
    watch_end();
    return code;
}

void crs_fw_wasm_unload(crs_board *board)
{
    crs_wasm *w = board->firmware;
    if (w == NULL) return;
    if (w->store != NULL) api.store_delete(w->store);
    if (w->linker != NULL) api.linker_delete(w->linker);
    module_release(w->shared);
    free(w);
    board->firmware = NULL;
    memset(&board->fw, 0, sizeof board->fw);
}

void crs_fw_chunk_begins(crs_board *board)
{
    if (board->firmware != NULL) watch_begin(board->firmware);
}

void crs_fw_chunk_ends(crs_board *board)
{
    (void)board;
    watch_end();
}

uint8_t *crs_fw_wasm_memory(crs_board *board, uint64_t *size)
{
    const crs_wasm *w = board->firmware;
    *size = w != NULL ? w->size : 0;
    return w != NULL ? w->base : NULL;
}

uint32_t crs_fw_wasm_variable(crs_board *board, const char *name)
{
    crs_wasm *w = board->firmware;
    wasmtime_extern_t e;
    if (w == NULL || !api.instance_export_get(w->ctx, &w->instance, name, strlen(name), &e)
        || e.kind != WASMTIME_EXTERN_GLOBAL) {
        return 0;
    }
    wasmtime_val_t v;
    api.global_get(w->ctx, &e.of.global, &v);
    return v.kind == WASMTIME_I32 ? (uint32_t)v.of.i32 : 0;
}
