/* The WebAssembly firmware's port (firmware_port.h, firmware_wasm.h): a board's store.
 *
 * The firmware module runs in a wasmtime store of its own inside the worker: it computes on its own
 * linear memory (fixed in size when it was linked, crslab/lab/firmware.py) and can reach nothing
 * else. Its only imports are the board's: `board.serial_send` (serial_printf) and `board.fault`
 * (here), and the WASI calls the C library may make (firmware_wasm_wasi.c).
 *
 * A worker may hold many boards (crs_board), each with its own firmware: they share one wasmtime
 * engine (per process) and one compiled module per distinct firmware (firmware_wasm_engine.c), and
 * each has a store and an instance of its own, so what one firmware does (a trap, a hang) ends its
 * own board only.
 *
 * What each call costs is counted in WebAssembly instructions (wasmtime's fuel), which does not
 * depend on the host's load; what a host function walks for it is charged too (crs_wasm_charge). A
 * call that does not return is stopped per store by the watchdog (firmware_wasm_watchdog.c). In a
 * worker whose boards share it (crs_wasm_options: a server's run host), each call may cost at most
 * call_instructions and run at most call_ns, and a chunk ends at the first tick after chunk_ns
 * (crs_fw_chunk_over): no board holds the worker longer than that, whatever its firmware does.
 * Everything read out of the firmware's memory is bounded by its size. */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "board_io.h"
#include "firmware_port.h"
#include "firmware_wasm_store.h"

/* ---- the store's helpers (firmware_wasm_store.h) --------------------------------------------- */

void crs_wasm_load_failed(crs_board *board, const char *what, const char *detail, size_t detail_len)
{
    crs_fw_trap *t = &board->trap;
    t->kind = CRS_FW_TRAP_LOAD;
    t->phase = CRS_PHASE_LOADING;
    t->tick = board->tick;
    snprintf(t->text, sizeof t->text, "%s%s%.*s", what, detail_len ? ": " : "", (int)detail_len,
             detail != NULL ? detail : "");
}

void crs_wasm_take_error(crs_board *board, const char *what, wasmtime_error_t *err)
{
    wasm_byte_vec_t m = {0, NULL};
    crs_wasmtime.error_message(err, &m);
    crs_wasm_load_failed(board, what, m.data, m.size);
    crs_wasmtime.byte_vec_delete(&m);
    crs_wasmtime.error_delete(err);
}

uint8_t *crs_wasm_span(crs_wasm *w, uint64_t addr, uint64_t len)
{
    if (addr > w->size || len > w->size - addr) w->size = crs_wasmtime.memory_data_size(w->ctx, &w->memory);
    return addr <= w->size && len <= w->size - addr ? w->base + addr : NULL;
}

crs_wasm *crs_wasm_of_caller(wasmtime_caller_t *caller)
{
    return crs_wasmtime.context_get_data(crs_wasmtime.caller_context(caller));
}

void crs_wasm_note(crs_wasm *w, int32_t kind, const char *text)
{
    crs_fw_trap *t = &w->board->trap;
    t->kind = kind;
    t->phase = w->board->shared != NULL ? w->board->shared->phase : CRS_PHASE_LOADING;
    t->tick = w->board->tick;
    snprintf(t->text, sizeof t->text, "%s", text);
}

void crs_wasm_note_over(crs_wasm *w, int32_t kind)
{
    char limit[64];
    if (kind == CRS_FW_TRAP_TOO_COSTLY) {
        snprintf(limit, sizeof limit, "%llu instructions", (unsigned long long)(w->call_fuel - 1));
    } else {
        snprintf(limit, sizeof limit, "%lld ms", (long long)(w->call_ns / 1000000));
    }
    crs_wasm_note(w, kind, limit);
}

wasm_trap_t *crs_wasm_trap(crs_wasm *w, int32_t kind, const char *text)
{
    crs_wasm_note(w, kind, text);
    return crs_wasmtime.trap_new(text, strlen(text));
}

wasm_trap_t *crs_wasm_charge(crs_wasm *w, uint64_t units)
{
    uint64_t left = 0;
    wasmtime_error_t *err = crs_wasmtime.context_get_fuel(w->ctx, &left);
    if (err == NULL && units >= left) {
        crs_wasm_note_over(w, CRS_FW_TRAP_TOO_COSTLY);
        return crs_wasmtime.trap_new(w->board->trap.text, strlen(w->board->trap.text));
    }
    if (err == NULL) err = crs_wasmtime.context_set_fuel(w->ctx, left - units);
    if (err != NULL) crs_wasmtime.error_delete(err);
    return NULL;
}

/* ---- imports: the board's serial port and its faults ------------------------------------------ */

static wasm_trap_t *board_serial_send(void *env, wasmtime_caller_t *caller, wasmtime_val_raw_t *a, size_t n)
{
    (void)env;
    crs_wasm *w = crs_wasm_of_caller(caller);
    if (n < 3) return crs_wasm_trap(w, CRS_FW_TRAP_OTHER, "the firmware called board.serial_send wrongly");
    const uint64_t chars = (uint32_t)a[1].i32, formatted = (uint32_t)a[2].i32;
    const uint64_t available = chars < w->size ? (w->size - chars < formatted ? w->size - chars : formatted) : 0;
    a[0].i32 = crs_board_serial_out(w->board, (const char *)w->base + (chars < w->size ? chars : 0),
                                    (uint32_t)available, (uint32_t)formatted);
    return NULL;
}

static wasm_trap_t *board_fault(void *env, wasmtime_caller_t *caller, wasmtime_val_raw_t *a, size_t n)
{
    (void)env;
    crs_wasm *w = crs_wasm_of_caller(caller);
    const int32_t kind = n >= 1 ? a[0].i32 : CRS_FW_TRAP_OTHER;
    const int known = kind == CRS_FW_TRAP_NULL || kind == CRS_FW_TRAP_DIVIDE || kind == CRS_FW_TRAP_OVERFLOW;
    w->board->trap.line = n >= 2 && a[1].i32 > 0 ? a[1].i32 : 0;
    return crs_wasm_trap(w, known ? kind : CRS_FW_TRAP_OTHER, "");
}

static int same(const wasm_byte_vec_t *v, const char *s)
{
    return v->size == strlen(s) && memcmp(v->data, s, v->size) == 0;
}

/* Define every import of the module in the linker: the board's, and WASI's as the C library asks;
 * 0, or -1 with the load failure noted. */
static int define_imports(crs_wasm *w)
{
    const crs_wasmtime_api *api = &crs_wasmtime;
    crs_board *board = w->board;
    wasm_importtype_vec_t imports = {0, NULL};
    api->module_imports(w->module, &imports);
    int ok = 0;
    for (size_t k = 0; k < imports.size && ok == 0; ++k) {
        const wasm_importtype_t *it = imports.data[k];
        const wasm_byte_vec_t *mod = api->importtype_module(it), *name = api->importtype_name(it);
        const wasm_externtype_t *type = api->importtype_type(it);
        char shown[160];
        snprintf(shown, sizeof shown, "%.*s.%.*s", (int)(mod->size < 60 ? mod->size : 60), mod->data,
                 (int)(name->size < 60 ? name->size : 60), name->data);
        if (api->externtype_kind(type) != WASM_EXTERN_FUNC) {
            crs_wasm_load_failed(board, "the firmware imports something other than a function", shown,
                                 strlen(shown));
            ok = -1;
            break;
        }
        const wasm_functype_t *ft = api->externtype_as_functype_const(type);
        if (same(mod, "wasi_snapshot_preview1")) {
            ok = crs_wasi_define(w, mod, name, ft);
            continue;
        }
        wasmtime_func_unchecked_callback_t callback = NULL;
        if (same(mod, "board") && same(name, "serial_send")) {
            callback = board_serial_send;
        } else if (same(mod, "board") && same(name, "fault")) {
            callback = board_fault;
        } else {
            crs_wasm_load_failed(board, "the firmware imports a function the board does not give", shown,
                                 strlen(shown));
            ok = -1;
            break;
        }
        wasmtime_error_t *err = api->linker_define_func_unchecked(w->linker, mod->data, mod->size, name->data,
                                                                  name->size, ft, callback, NULL, NULL);
        if (err != NULL) {
            crs_wasm_take_error(board, "the board cannot give the firmware its imports", err);
            ok = -1;
        }
    }
    api->importtype_vec_delete(&imports);
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
    case WASMTIME_TRAP_CODE_OUT_OF_FUEL: return CRS_FW_TRAP_TOO_COSTLY;
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

/* Call `f` with the fuel a call starts with; *cost is what it cost (instructions, the host's work
 * for it included). 0, or CRS_RUN_TRAPPED with board->trap saying how it stopped: a trap, the
 * watchdog, or (a shared worker's) all its fuel spent, whether wasmtime saw it run out or the call
 * returned on its last unit (wasmtime checks fuel where loops and calls begin). */
static int call(crs_wasm *w, const wasmtime_func_t *f, wasmtime_val_raw_t *args, size_t n, int32_t phase,
                int64_t *cost)
{
    const crs_wasmtime_api *api = &crs_wasmtime;
    wasmtime_error_t *err = api->context_set_fuel(w->ctx, w->call_fuel);
    if (err != NULL) api->error_delete(err);
    wasm_trap_t *trap = NULL;
    err = api->func_call_unchecked(w->ctx, f, args, n, &trap);
    uint64_t left = 0;
    wasmtime_error_t *fuel = api->context_get_fuel(w->ctx, &left);
    if (fuel != NULL) api->error_delete(fuel);
    *cost = (int64_t)(w->call_fuel - left);
    crs_board *board = w->board;
    crs_fw_trap *t = &board->trap;
    if (err == NULL && trap == NULL) {
        if (left > 0 || w->call_fuel == CRS_WASM_FUEL) return 0;
        crs_wasm_note_over(w, CRS_FW_TRAP_TOO_COSTLY); /* it returned on its last unit of fuel */
    } else if (t->kind == CRS_FW_TRAP_NONE) { /* not one of the board's own */
        uint8_t code = 0;
        if (trap != NULL) {
            t->kind = api->trap_code(trap, &code) ? kind_of(code) : CRS_FW_TRAP_OTHER;
            if (t->kind == CRS_FW_TRAP_TOO_COSTLY) crs_wasm_note_over(w, t->kind); /* it ran out of fuel */
        } else {
            int status = 0;
            t->kind = api->error_exit_status(err, &status) ? CRS_FW_TRAP_EXIT : CRS_FW_TRAP_OTHER;
            t->exit_code = status;
        }
    }
    wasm_byte_vec_t m = {0, NULL};
    if (trap != NULL) {
        api->trap_message(trap, &m);
    } else if (err != NULL) {
        api->error_message(err, &m);
    }
    append_message(t, &m);
    if (m.data != NULL) api->byte_vec_delete(&m);
    t->phase = phase;
    t->tick = board->tick;
    if (trap != NULL) api->trap_delete(trap);
    if (err != NULL) api->error_delete(err);
    return CRS_RUN_TRAPPED;
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
    int64_t cost = 0;
    const int code = call(w, &w->lab, a, 4, CRS_PHASE_LAB, &cost);
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
    int64_t cost = 0;
    return call(w, &w->printing, a, 0, CRS_PHASE_PRINTING, &cost);
}

/* ---- loading --------------------------------------------------------------------------------- */

static int export_func(crs_wasm *w, const char *name, wasmtime_func_t *out)
{
    wasmtime_extern_t e;
    if (!crs_wasmtime.instance_export_get(w->ctx, &w->instance, name, strlen(name), &e)
        || e.kind != WASMTIME_EXTERN_FUNC) {
        return -1;
    }
    *out = e.of.func;
    return 0;
}

/* A host pointer to `bytes` at firmware address `addr` aligned to `align`, or NULL. */
static void *view(crs_wasm *w, uint32_t addr, uint64_t bytes, uint32_t align)
{
    if (addr == 0 || addr % align != 0) return NULL;
    return crs_wasm_span(w, addr, bytes);
}

/* The firmware's table (firmware.h: crs_fw_table, 32-bit addresses in WebAssembly). */
enum {
    T_TAU = 0, T_OFFSET2 = 1, T_OFFSET3 = 2, T_PLOT = 3, T_GPIO = 7, T_SIMULINK = 8, T_MATLAB_LOCK = 15,
    T_SYMBOLS = 16, T_WORDS = 18
};

static int read_table(crs_wasm *w, uint32_t address)
{
    crs_board *board = w->board;
    const uint8_t *t = crs_wasm_span(w, address, 4 * T_WORDS);
    if (t == NULL) return -1;
    uint32_t word[T_WORDS];
    for (int i = 0; i < T_WORDS; ++i) word[i] = crs_wasm_load_u32(t + 4 * i);
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
    return crs_wasmtime_load(libwasmtime, error, sizeof error) == 0 ? 0 : -1;
}

int32_t crs_fw_wasm_module_refs(const crs_board *board)
{
    const crs_wasm *w = board->firmware;
    return w != NULL ? crs_wasm_module_users(w->shared) : 0;
}

/* Instantiate the module in the store of `w` and run its constructors and crs_fw_start; 0, or
 * CRS_RUN_TRAPPED with board->trap saying why. */
static int start_firmware(crs_wasm *w)
{
    const crs_wasmtime_api *api = &crs_wasmtime;
    crs_board *board = w->board;
    char error[256];
    wasm_trap_t *trap = NULL;
    wasmtime_error_t *err = api->linker_instantiate(w->linker, w->ctx, w->module, &w->instance, &trap);
    if (err != NULL) {
        crs_wasm_take_error(board, "the firmware cannot be started", err);
        return CRS_RUN_TRAPPED;
    }
    if (trap != NULL) {
        wasm_byte_vec_t m = {0, NULL};
        api->trap_message(trap, &m);
        crs_wasm_load_failed(board, "the firmware stopped while it was started", m.data, m.size);
        api->byte_vec_delete(&m);
        api->trap_delete(trap);
        return CRS_RUN_TRAPPED;
    }
    wasmtime_extern_t memory;
    if (!api->instance_export_get(w->ctx, &w->instance, "memory", 6, &memory)
        || memory.kind != WASMTIME_EXTERN_MEMORY) {
        crs_wasm_load_failed(board, "the firmware exports no memory", NULL, 0);
        return CRS_RUN_TRAPPED;
    }
    w->memory = memory.of.memory;
    w->base = api->memory_data(w->ctx, &w->memory);
    w->size = api->memory_data_size(w->ctx, &w->memory);
    wasmtime_func_t start;
    if (export_func(w, "crs_fw_start", &start) != 0 || export_func(w, "crs_fw_lab", &w->lab) != 0
        || export_func(w, "crs_fw_printing", &w->printing) != 0) {
        crs_wasm_load_failed(board, "not a crslab firmware (crs_fw_start, crs_fw_lab or crs_fw_printing is "
                             "missing)", NULL, 0);
        return CRS_RUN_TRAPPED;
    }
    board->config.cost_unit = CRS_COST_INSTRUCTIONS;
    wasmtime_func_t initialize;
    wasmtime_val_raw_t a[1];
    int64_t cost = 0; /* the constructors' cost is not lab()'s */
    if (export_func(w, "_initialize", &initialize) == 0) { /* the C library's and the lab's constructors */
        if (call(w, &initialize, a, 0, CRS_PHASE_LOADING, &cost) != 0) return CRS_RUN_TRAPPED;
    }
    a[0].i32 = board->config.generation;
    if (call(w, &start, a, 1, CRS_PHASE_LOADING, &cost) != 0) return CRS_RUN_TRAPPED;
    if (a[0].i32 == 0) {
        snprintf(error, sizeof error, "the firmware cannot run framework generation %d (its generations.c "
                 "is not the board's)", (int)board->config.generation);
        crs_wasm_load_failed(board, error, NULL, 0);
        return CRS_RUN_TRAPPED;
    }
    if (read_table(w, (uint32_t)a[0].i32) != 0) {
        crs_wasm_load_failed(board, "the firmware's table of the framework's variables is not in its memory",
                             NULL, 0);
        return CRS_RUN_TRAPPED;
    }
    return 0;
}

int crs_fw_wasm_load(crs_board *board, const crs_wasm_options *o)
{
    const crs_wasmtime_api *api = &crs_wasmtime;
    char error[256];
    memset(&board->trap, 0, sizeof board->trap);
    if (crs_board_check_generation(board) != 0) return CRS_RUN_TRAPPED;
    if (crs_wasmtime_load(o->libwasmtime, error, sizeof error) != 0) {
        crs_wasm_load_failed(board, error, NULL, 0);
        return CRS_RUN_TRAPPED;
    }
    if (crs_watchdog_start() != 0) {
        crs_wasm_load_failed(board, "the board cannot start its watchdog", NULL, 0);
        return CRS_RUN_TRAPPED;
    }
    if (crs_wasm_engine_for(board, o) != 0) return CRS_RUN_TRAPPED;
    crs_wasm *w = calloc(1, sizeof *w);
    if (w == NULL) {
        crs_wasm_load_failed(board, "out of memory", NULL, 0);
        return CRS_RUN_TRAPPED;
    }
    w->board = board;
    w->deadline_ns = (int64_t)o->deadline_ns;
    w->call_ns = (int64_t)o->call_ns;
    w->chunk_ns = (int64_t)o->chunk_ns;
    w->call_fuel = o->call_instructions > 0 && o->call_instructions < CRS_WASM_FUEL ? o->call_instructions + 1
                                                                                     : CRS_WASM_FUEL;
    board->firmware = w;
    w->shared = crs_wasm_module_for(board, o);
    if (w->shared == NULL) return CRS_RUN_TRAPPED;
    w->module = crs_wasm_module_of(w->shared);
    w->store = api->store_new(crs_wasm_engine(), w, NULL);
    w->ctx = api->store_context(w->store);
    api->store_limiter(w->store, (int64_t)o->memory_bytes, 100000, 1, 1, 1);
    api->store_epoch_deadline_callback(w->store, crs_watchdog_on_epoch, w, NULL);
    w->linker = api->linker_new(crs_wasm_engine());
    if (define_imports(w) != 0) return CRS_RUN_TRAPPED;
    crs_watchdog_begin(w); /* the constructors are timed as lab() is */
    const int code = start_firmware(w);
    crs_watchdog_end();
    return code;
}

void crs_fw_wasm_unload(crs_board *board)
{
    crs_wasm *w = board->firmware;
    if (w == NULL) return;
    if (w->store != NULL) crs_wasmtime.store_delete(w->store);
    if (w->linker != NULL) crs_wasmtime.linker_delete(w->linker);
    crs_wasm_module_release(w->shared);
    free(w);
    board->firmware = NULL;
    memset(&board->fw, 0, sizeof board->fw);
}

/* ---- chunks ---------------------------------------------------------------------------------- */

void crs_fw_chunk_begins(crs_board *board)
{
    crs_wasm *w = board->firmware;
    if (w == NULL) return;
    atomic_store(&w->cut, 0);
    if (w->chunk_ns > 0) w->chunk_cpu_ns = crs_thread_cpu_ns();
    crs_watchdog_begin(w);
}

void crs_fw_chunk_ends(crs_board *board)
{
    (void)board;
    crs_watchdog_end();
}

int crs_fw_chunk_over(crs_board *board)
{
    crs_wasm *w = board->firmware;
    return w != NULL && atomic_load_explicit(&w->cut, memory_order_relaxed);
}

/* ---- what the board reads of the firmware ---------------------------------------------------- */

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
    if (w == NULL || !crs_wasmtime.instance_export_get(w->ctx, &w->instance, name, strlen(name), &e)
        || e.kind != WASMTIME_EXTERN_GLOBAL) {
        return 0;
    }
    wasmtime_val_t v;
    crs_wasmtime.global_get(w->ctx, &e.of.global, &v);
    return v.kind == WASMTIME_I32 ? (uint32_t)v.of.i32 : 0;
}
