/* WASI, as the C library the firmware is linked with asks for it (firmware_wasm_store.h): its
 * imports of wasi_snapshot_preview1 are answered here, the board's way. stdout and stderr (printf,
 * puts: on the real board they go to CCS's console, not Tera Term) are counted and dropped, exit()
 * ends the run, and everything else (files, the clock, the environment, random bytes, sockets) is
 * refused and named: the firmware stops with the words a diagnosis uses. Every argument is read out
 * of the firmware's memory through crs_wasm_span, bounded; what a call walks is charged to it as
 * fuel (crs_wasm_charge). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "firmware_wasm_store.h"

enum { WASI_EBADF = 8, WASI_EFAULT = 21, WASI_ESPIPE = 70 };
enum { CONSOLE_FDS = 3, ROOT_FD = 3 }; /* stdin, stdout, stderr; "/" (so a file's name reaches path_open) */

typedef wasm_trap_t *(*wasi_call)(crs_wasm *w, wasmtime_val_raw_t *a, size_t n, const char *name);

static wasm_trap_t *refuse(crs_wasm *w, const char *what)
{
    char text[CRS_FW_TRAP_TEXT];
    snprintf(text, sizeof text, "%s", what);
    return crs_wasm_trap(w, CRS_FW_TRAP_REFUSED, text);
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
    const uint8_t *vec = crs_wasm_span(w, iovs, (uint64_t)count * 8);
    uint8_t *written = crs_wasm_span(w, (uint32_t)a[3].i32, 4);
    if (vec == NULL || written == NULL) {
        a[0].i32 = WASI_EFAULT;
        return NULL;
    }
    wasm_trap_t *over = crs_wasm_charge(w, count); /* the board walks every iovec: one instruction each */
    if (over != NULL) return over;
    uint64_t total = 0;
    for (uint32_t i = 0; i < count; ++i) total += crs_wasm_load_u32(vec + 8 * (uint64_t)i + 4);
    if (total > UINT32_MAX) total = UINT32_MAX;
    w->board->console_bytes += (int64_t)total; /* CCS's console: counted, not shown */
    crs_wasm_store_u32(written, (uint32_t)total);
    a[0].i32 = 0;
    return NULL;
}

static wasm_trap_t *wasi_fd_fdstat_get(crs_wasm *w, wasmtime_val_raw_t *a, size_t n, const char *name)
{
    (void)name;
    if (n < 2) return refuse(w, "use a file");
    const uint32_t fd = (uint32_t)a[0].i32;
    uint8_t *stat = crs_wasm_span(w, (uint32_t)a[1].i32, 24);
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
    uint8_t *out = n >= 2 ? crs_wasm_span(w, (uint32_t)a[1].i32, 8) : NULL;
    if ((uint32_t)a[0].i32 != ROOT_FD) {
        a[0].i32 = WASI_EBADF; /* the only folder the C library finds is "/": every path reaches path_open */
        return NULL;
    }
    if (out == NULL) {
        a[0].i32 = WASI_EFAULT;
        return NULL;
    }
    memset(out, 0, 8);
    crs_wasm_store_u32(out + 4, 1); /* a directory whose name is one character long */
    a[0].i32 = 0;
    return NULL;
}

static wasm_trap_t *wasi_fd_prestat_dir_name(crs_wasm *w, wasmtime_val_raw_t *a, size_t n, const char *name)
{
    (void)name;
    uint8_t *out = n >= 3 && (uint32_t)a[2].i32 >= 1 ? crs_wasm_span(w, (uint32_t)a[1].i32, 1) : NULL;
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
    const uint8_t *p = crs_wasm_span(w, path, len);
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
    const uint8_t *p = n >= 4 ? crs_wasm_span(w, (uint32_t)a[2].i32, len) : NULL;
    if (p == NULL) return refuse(w, "look up a file (stat)");
    snprintf(text, sizeof text, "look up /%.*s (stat)", (int)len, (const char *)p);
    return refuse(w, text);
}

static wasm_trap_t *wasi_proc_exit(crs_wasm *w, wasmtime_val_raw_t *a, size_t n, const char *name)
{
    (void)name;
    w->board->trap.exit_code = n >= 1 ? a[0].i32 : 0;
    return crs_wasm_trap(w, CRS_FW_TRAP_EXIT, "exit");
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
    crs_wasm *w = crs_wasm_of_caller(caller);
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
    return refuse(crs_wasm_of_caller(caller), text);
}

static void free_name(void *name) { free(name); }

static int same(const wasm_byte_vec_t *v, const char *s)
{
    return v->size == strlen(s) && memcmp(v->data, s, v->size) == 0;
}

int crs_wasi_define(crs_wasm *w, const wasm_byte_vec_t *module, const wasm_byte_vec_t *name,
                    const wasm_functype_t *ft)
{
    wasmtime_func_unchecked_callback_t callback = NULL;
    void *env = NULL;
    void (*finalizer)(void *) = NULL;
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
            crs_wasm_load_failed(w->board, "out of memory", NULL, 0);
            return -1;
        }
        memcpy(kept, name->data, name->size);
        callback = wasi_other;
        env = kept;
        finalizer = free_name;
    }
    wasmtime_error_t *err = crs_wasmtime.linker_define_func_unchecked(w->linker, module->data, module->size,
                                                                      name->data, name->size, ft, callback,
                                                                      env, finalizer);
    if (err != NULL) {
        crs_wasm_take_error(w->board, "the board cannot give the firmware its imports", err);
        return -1;
    }
    return 0;
}
