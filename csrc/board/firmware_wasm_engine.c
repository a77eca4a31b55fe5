/* The process's wasmtime engine and the firmware modules it compiled (firmware_wasm_store.h).
 *
 * One engine per process, created with the board's limits by the first load (every board of a
 * process has the same: a later load asking for others is refused). One compiled module per
 * distinct firmware (keyed by the module's digest, crs_wasm_options.module_key), shared by every
 * board running it and counted; a module no board uses is kept (a page that runs its lab again
 * loads nothing) while fewer than CRS_WASM_IDLE_MODULES others no board uses were used since, and
 * freed after that: a worker that ran a thousand labs holds the modules of the labs it runs now
 * and of the last few, not of every one. A module is loaded from its compilation kept in crslab's
 * build cache when there is one (the bytes crslab read and checked the seal of: the board opens no
 * file of the cache; written by the first board that compiled it, or by crs_fw_wasm_compile: a
 * lab's first compile, with an engine of its own made alike, to a private file crslab made, which
 * crslab seals and renames into place), else compiled. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "firmware_wasm_store.h"

struct crs_wasm_module {
    char key[96];                /* the module's digest (crs_wasm_options.module_key) */
    wasmtime_module_t *module;
    int32_t users;               /* boards using it */
    uint64_t used;               /* when a board last took or left it (the count of those so far) */
    struct crs_wasm_module *next;
};

static wasm_engine_t *engine;
static uint64_t engine_memory_bytes, engine_stack_bytes;
static crs_wasm_module *modules;
static uint64_t uses; /* modules taken or left by boards so far: each one's `used` */

/* A process forked from one that ran firmware (a benchmark's in-process run, then its workers)
 * has no use for the parent's engine and modules: it makes its own on its first load (what the
 * parent's were is left alone: it is the parent's). */
static void forget_after_fork(void)
{
    engine = NULL;
    modules = NULL;
    uses = 0;
}

wasm_engine_t *crs_wasm_engine(void) { return engine; }

/* The engine configuration of every board, for the memory and stack of `o`: the process's engine
 * (crs_wasm_engine_for) and crs_fw_wasm_compile's are made alike, so a module one compiled the
 * other loads. */
static wasm_config_t *engine_config(const crs_wasm_options *o)
{
    const crs_wasmtime_api *api = &crs_wasmtime;
    wasm_config_t *config = api->config_new();
    api->config_consume_fuel_set(config, true);
    api->config_epoch_interruption_set(config, true);
    api->config_parallel_compilation_set(config, false); /* the worker compiles in its main thread */
    api->config_wasm_threads_set(config, false);
    api->config_max_wasm_stack_set(config, (size_t)o->stack_bytes);
    /* the memory grows (the lab's heap) up to the board's limit, within one reservation, so it never
     * moves and needs no more address space than that (bounds are checked explicitly): a memory
     * limit on the worker holds */
    api->config_memory_reservation_set(config, o->memory_bytes);
    api->config_memory_reservation_for_growth_set(config, 0);
    api->config_memory_guard_size_set(config, 0);
    api->config_memory_may_move_set(config, false);
    return config;
}

int crs_wasm_engine_for(crs_board *board, const crs_wasm_options *o)
{
    static int fork_handled;
    if (!fork_handled) {
        if (pthread_atfork(NULL, NULL, forget_after_fork) != 0) {
            crs_wasm_load_failed(board, "the board cannot prepare its engine", NULL, 0);
            return -1;
        }
        fork_handled = 1;
    }
    if (engine != NULL) {
        if (o->memory_bytes == engine_memory_bytes && o->stack_bytes == engine_stack_bytes) return 0;
        crs_wasm_load_failed(board, "this worker's boards have other memory or stack limits", NULL, 0);
        return -1;
    }
    engine = crs_wasmtime.engine_new_with_config(engine_config(o));
    if (engine == NULL) {
        crs_wasm_load_failed(board, "wasmtime cannot start", NULL, 0);
        return -1;
    }
    engine_memory_bytes = o->memory_bytes;
    engine_stack_bytes = o->stack_bytes;
    return 0;
}

/* The module as wasmtime compiled it for this engine, from `bytes` (kept in crslab's build cache
 * from this firmware's compilation, read and its seal checked by crslab: these very bytes), or NULL
 * when there are none or wasmtime refuses them (another wasmtime or another configuration: their
 * header says so), and it is compiled anew. */
static wasmtime_module_t *load_compiled(const uint8_t *bytes, uint64_t len)
{
    if (bytes == NULL || len == 0) return NULL;
    wasmtime_module_t *module = NULL;
    wasmtime_error_t *err = crs_wasmtime.module_deserialize(engine, bytes, (size_t)len, &module);
    if (err == NULL) return module;
    crs_wasmtime.error_delete(err);
    return NULL;
}

/* Write the compiled module to `fd` (a private file crslab made, which it then seals and renames
 * into place for the next run of the same firmware); the board opens no file of the cache. 0, or -1
 * when it was not written whole (a cache: crslab keeps nothing and the next run compiles again). */
static int keep_compiled(const wasmtime_module_t *module, int fd)
{
    wasm_byte_vec_t bytes = {0, NULL};
    wasmtime_error_t *err = crs_wasmtime.module_serialize((wasmtime_module_t *)module, &bytes);
    if (err != NULL) {
        crs_wasmtime.error_delete(err);
        return -1;
    }
    size_t done = 0;
    while (done < bytes.size) {
        const ssize_t n = write(fd, (const char *)bytes.data + done, bytes.size - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        done += (size_t)n;
    }
    const int whole = done == bytes.size ? 0 : -1;
    crs_wasmtime.byte_vec_delete(&bytes);
    return whole;
}

int crs_fw_wasm_compile(const crs_wasm_options *o, char *error, size_t error_size)
{
    const crs_wasmtime_api *api = &crs_wasmtime;
    if (crs_wasmtime_load(o->libwasmtime, error, error_size) != 0) return -1;
    if (o->compiled_fd < 0) {
        snprintf(error, error_size, "there is no place to keep the compiled module");
        return -1;
    }
    wasm_engine_t *own = api->engine_new_with_config(engine_config(o));
    if (own == NULL) {
        snprintf(error, error_size, "wasmtime cannot start");
        return -1;
    }
    wasmtime_module_t *module = NULL;
    wasmtime_error_t *err = api->module_new(own, o->wasm, (size_t)o->wasm_len, &module);
    int code = 0;
    if (err != NULL) {
        wasm_byte_vec_t m = {0, NULL};
        api->error_message(err, &m);
        snprintf(error, error_size, "not a WebAssembly module wasmtime can run: %.*s", (int)m.size,
                 m.data != NULL ? m.data : "");
        api->byte_vec_delete(&m);
        api->error_delete(err);
        code = -1;
    } else {
        if (keep_compiled(module, o->compiled_fd) != 0) {
            snprintf(error, error_size, "the compiled module could not be written");
            code = -1;
        }
        api->module_delete(module);
    }
    api->engine_delete(own);
    return code;
}

static void unlink_module(crs_wasm_module *m)
{
    for (crs_wasm_module **p = &modules; *p != NULL; p = &(*p)->next) {
        if (*p == m) {
            *p = m->next;
            return;
        }
    }
}

crs_wasm_module *crs_wasm_module_for(crs_board *board, const crs_wasm_options *o)
{
    const char *key = o->module_key != NULL ? o->module_key : "";
    if (key[0] != '\0') {
        for (crs_wasm_module *m = modules; m != NULL; m = m->next) {
            if (strcmp(m->key, key) == 0) {
                m->users++;
                m->used = ++uses;
                return m;
            }
        }
    }
    crs_wasm_module *m = calloc(1, sizeof *m);
    if (m == NULL) {
        crs_wasm_load_failed(board, "out of memory", NULL, 0);
        return NULL;
    }
    snprintf(m->key, sizeof m->key, "%s", key);
    m->module = load_compiled(o->compiled, o->compiled_len);
    if (m->module == NULL) {
        if (o->wasm == NULL) {
            crs_wasm_load_failed(board, "the firmware's bytes were not given", NULL, 0);
            free(m);
            return NULL;
        }
        wasmtime_error_t *err = crs_wasmtime.module_new(engine, o->wasm, (size_t)o->wasm_len, &m->module);
        if (err != NULL) {
            crs_wasm_take_error(board, "not a WebAssembly module wasmtime can run", err);
            free(m);
            return NULL;
        }
        if (o->compiled_fd >= 0) (void)keep_compiled(m->module, o->compiled_fd);
    }
    m->users = 1;
    m->used = ++uses;
    m->next = modules;
    modules = m;
    return m;
}

wasmtime_module_t *crs_wasm_module_of(const crs_wasm_module *m) { return m->module; }

int32_t crs_wasm_module_users(const crs_wasm_module *m) { return m != NULL ? m->users : 0; }

void crs_wasm_module_release(crs_wasm_module *m)
{
    if (m == NULL) return;
    m->used = ++uses;
    if (--m->users > 0) return;
    if (m->key[0] == '\0') { /* not shared: nobody can take it again */
        unlink_module(m);
        crs_wasmtime.module_delete(m->module);
        free(m);
        return;
    }
    for (;;) { /* free the least recently used of the modules no board uses, past the number kept */
        int32_t idle = 0;
        crs_wasm_module *oldest = NULL;
        for (crs_wasm_module *i = modules; i != NULL; i = i->next) {
            if (i->users > 0) continue;
            idle++;
            if (oldest == NULL || i->used < oldest->used) oldest = i;
        }
        if (idle <= CRS_WASM_IDLE_MODULES) return;
        unlink_module(oldest);
        crs_wasmtime.module_delete(oldest->module);
        free(oldest);
    }
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
