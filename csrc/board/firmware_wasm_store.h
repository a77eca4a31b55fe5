/* One board's WebAssembly store (crs_wasm), and what the files of the WebAssembly port give each
 * other:
 *   firmware_wasm.c           a board's store: its instance, the board's imports, the calls into it
 *   firmware_wasm_api.c       wasmtime's C library, loaded by path (wasmtime_api.h)
 *   firmware_wasm_engine.c    the process's engine and its compiled modules (one per firmware)
 *   firmware_wasm_watchdog.c  the watchdog thread: interrupts per store
 *   firmware_wasm_wasi.c      WASI, as the C library asks for it: answered or refused
 * Internal to the board; not read by cffi. */
#ifndef CRSLAB_FIRMWARE_WASM_STORE_H
#define CRSLAB_FIRMWARE_WASM_STORE_H

#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "board.h"
#include "firmware_wasm.h"
#include "wasmtime_api.h"

typedef struct crs_wasm_module crs_wasm_module; /* a compiled module (firmware_wasm_engine.c) */

/* A board's firmware: its store, its instance, and what it may take of the worker. */
typedef struct {
    crs_board *board;
    wasmtime_store_t *store;
    wasmtime_context_t *ctx;
    wasmtime_linker_t *linker;
    crs_wasm_module *shared;     /* the compiled module (shared) */
    wasmtime_module_t *module;   /* its wasmtime module */
    int64_t deadline_ns;         /* a call running longer is interrupted: hung (0: never) */
    int64_t call_ns;             /* a shared worker's: a call using more CPU time ends the run (0: never) */
    int64_t chunk_ns;            /* a shared worker's: a chunk ends at the first tick after it used
                                    this much CPU time (0: at its end tick) */
    int64_t chunk_cpu_ns;        /* the CPU time of the worker's thread as the current chunk began */
    atomic_int cut;              /* set by the watchdog: the chunk had its share (crs_fw_chunk_over) */
    uint64_t call_fuel;          /* the fuel each call starts with: the most it may cost plus one
                                    (CRS_WASM_FUEL when it may cost anything) */
    atomic_int interrupt;        /* CRS_FW_TRAP_* the running call ends with, set by the watchdog
                                    before it bumps the epoch (0: none) */
    wasmtime_instance_t instance;
    wasmtime_memory_t memory;
    uint8_t *base;               /* the firmware's memory: it grows (its heap) up to the board's limit, */
    uint64_t size;               /* in place: it never moves, so the board's pointers into it hold */
    wasmtime_func_t lab, printing;
} crs_wasm;

/* The fuel of a call that may cost anything: it never runs out, fuel only counts instructions. */
#define CRS_WASM_FUEL ((uint64_t)1 << 62)

/* ---- firmware_wasm.c: a board's store ---- */

/* `len` bytes at firmware address `addr`, or NULL when they do not all lie in its memory (as large
 * as its heap has grown it). */
uint8_t *crs_wasm_span(crs_wasm *w, uint64_t addr, uint64_t len);
/* The board of the firmware that called a host function. */
crs_wasm *crs_wasm_of_caller(wasmtime_caller_t *caller);
/* Note in board->trap that the firmware stopped: `kind` (CRS_FW_TRAP_*) and `text` say why (the
 * text may quote the firmware). */
void crs_wasm_note(crs_wasm *w, int32_t kind, const char *text);
/* Note that a call went past what a worker its boards share gives one (CRS_FW_TRAP_TOO_COSTLY,
 * CRS_FW_TRAP_TOO_LONG): the text's first line is the limit ("5000000 instructions", "20 ms"). */
void crs_wasm_note_over(crs_wasm *w, int32_t kind);
/* A trap of the board's own making, noted (crs_wasm_note): what a host function returns to end the
 * call. */
wasm_trap_t *crs_wasm_trap(crs_wasm *w, int32_t kind, const char *text);
/* Charge the running call `units` of fuel for the work a host function does for it (what it walks):
 * NULL, or, when that is more than the call may still cost, the trap that ends it
 * (CRS_FW_TRAP_TOO_COSTLY). */
wasm_trap_t *crs_wasm_charge(crs_wasm *w, uint64_t units);
/* The firmware could not be loaded: board->trap says `what` (and wasmtime's `detail`). */
void crs_wasm_load_failed(crs_board *board, const char *what, const char *detail, size_t detail_len);
/* The same with wasmtime's error `err` (deleted) as the detail. */
void crs_wasm_take_error(crs_board *board, const char *what, wasmtime_error_t *err);

static inline uint32_t crs_wasm_load_u32(const uint8_t *p)
{
    uint32_t v;
    memcpy(&v, p, sizeof v);
    return v;
}

static inline void crs_wasm_store_u32(uint8_t *p, uint32_t v) { memcpy(p, &v, sizeof v); }

/* ---- firmware_wasm_engine.c: the engine and its compiled modules ---- */

/* The process's engine (NULL until the first load). */
wasm_engine_t *crs_wasm_engine(void);
/* Create the process's engine with the board's limits on the first load; 0, or -1 with board->trap
 * saying why (a later load asking for other limits is refused). */
int crs_wasm_engine_for(crs_board *board, const crs_wasm_options *o);
/* The compiled module for `o` (one per distinct module_key, shared and counted), or NULL with
 * board->trap saying why. */
crs_wasm_module *crs_wasm_module_for(crs_board *board, const crs_wasm_options *o);
wasmtime_module_t *crs_wasm_module_of(const crs_wasm_module *m);
int32_t crs_wasm_module_users(const crs_wasm_module *m);
/* A board no longer uses `m`: kept while CRS_WASM_IDLE_MODULES others no board uses are newer. */
void crs_wasm_module_release(crs_wasm_module *m);

/* ---- firmware_wasm_watchdog.c: interrupts per store ---- */

/* The CPU time the calling thread has used (ns). */
int64_t crs_thread_cpu_ns(void);
/* Start the process's watchdog thread (once; again in a forked child): 0, or -1. */
int crs_watchdog_start(void);
/* The firmware of `w` may run from now on, in the calling thread (until crs_watchdog_end): the
 * watchdog times its calls and its chunk. */
void crs_watchdog_begin(crs_wasm *w);
void crs_watchdog_end(void);
/* A store's epoch-deadline callback (data: its crs_wasm), for every epoch its calls reach: ends the
 * call when the watchdog said why in this store (a hang, a call too long for a shared worker, the
 * crslab process's stop), else lets it go on to the next epoch (an epoch meant for another store). */
wasmtime_error_t *crs_watchdog_on_epoch(wasmtime_context_t *context, void *data, uint64_t *delta, uint8_t *kind);

/* ---- firmware_wasm_wasi.c: WASI ---- */

/* Define the WASI function `name` (of wasi_snapshot_preview1, type `ft`) in w's linker: answered
 * or refused as the board does; 0, or -1 with the load failure noted. */
int crs_wasi_define(crs_wasm *w, const wasm_byte_vec_t *module, const wasm_byte_vec_t *name,
                    const wasm_functype_t *ft);

#endif
