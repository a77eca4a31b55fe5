/* The store's helpers (firmware_wasm_store.h): what the board's store, its engine, its WASI calls
 * and its watchdog each need to note a failure or a trap on a board, to reach the firmware's memory
 * and to charge a call for what a host function walks. They call nothing of those files: each of
 * them calls down to these, never back up. */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <string.h>

#include "board_io.h"
#include "firmware_wasm_store.h"

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
