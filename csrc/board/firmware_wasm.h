/* The WebAssembly firmware's port (firmware_wasm.c and the firmware_wasm_*.c beside it: see
 * firmware_wasm_store.h): the firmware is a WebAssembly module (built by crslab/lab/firmware.py)
 * that wasmtime runs inside the worker, on its own memory, with the board's few functions as its
 * only imports. A worker may hold many boards: one engine per process, one compiled module per
 * distinct firmware (shared by every board running it), a store and an instance per board, and a
 * deadline per store. Compiled into crslab._core; read by cffi with board.h. */
#ifndef CRSLAB_FIRMWARE_WASM_H
#define CRSLAB_FIRMWARE_WASM_H

#include <stddef.h>
#include <stdint.h>

#include "board.h"

typedef struct {
    const char *libwasmtime;      /* path of the wasmtime C library (the `wasmtime` package's) */
    const uint8_t *wasm;          /* the firmware module's bytes */
    uint64_t wasm_len;
    uint64_t memory_bytes;        /* the most memory the firmware may have, bytes */
    uint64_t stack_bytes;         /* the most native stack its calls may use, bytes */
    const uint8_t *compiled;      /* wasmtime's compilation of this module for this board, kept
                                     between runs in crslab's build cache (read and its seal checked
                                     by crslab); NULL: compile anew */
    uint64_t compiled_len;
    int32_t compiled_fd;          /* a module compiled anew is written here (a private file crslab
                                     seals and renames into the cache); -1: kept nowhere */
    const char *module_key;       /* the module's digest (at most 95 characters): boards loading the
                                     same key share one compiled module; NULL or "": not shared */
    uint64_t deadline_ns;         /* a firmware call (a constructor, lab(), printing()) running
                                     longer is interrupted (CRS_FW_TRAP_INTERRUPT); 0: never */
    /* what one board may take of a worker its boards share (a server's run host); 0: no limit */
    uint64_t call_instructions;   /* the most one call may cost: more ends it (CRS_FW_TRAP_TOO_COSTLY) */
    uint64_t call_ns;             /* the longest one call may run: longer ends it (CRS_FW_TRAP_TOO_LONG) */
    uint64_t chunk_ns;            /* a chunk ends at the first tick after this long (CRS_RUN_CUT) */
} crs_wasm_options;

enum {
    CRS_WASM_IDLE_MODULES = 8,        /* compiled modules a worker keeps that no board uses (the
                                         last used): past them the oldest is freed */
    CRS_WATCH_PERIOD_NS = 5000000     /* how often the watchdog looks at the running call: a call is
                                         ended within this of its limit */
};

/* Load the firmware for board->config.generation into a store of its own, run its constructors (phase
 * CRS_PHASE_LOADING) and point board->fw at its variables. The first load of a process creates its
 * engine (with this memory and stack; later loads must ask for the same) and its watchdog thread.
 * `wasm` may be NULL when the process holds the module already (crs_fw_wasm_module_held).
 * Returns 0; else CRS_RUN_TRAPPED with board->trap saying why (CRS_FW_TRAP_LOAD: the module is not a firmware this board can run, or it asks for more than the
 * board gives; any other kind: a constructor stopped). */
int crs_fw_wasm_load(crs_board *board, const crs_wasm_options *options);
/* Load wasmtime's C library (`libwasmtime`, its path) into this process now, so that the processes
 * it forks later start with it loaded (crslab's fork servers); 0, or -1 when it cannot be loaded. */
int crs_fw_wasm_preload(const char *libwasmtime);
/* Compile the firmware `options->wasm` for boards with `options->memory_bytes` and `stack_bytes` (as
 * crs_fw_wasm_load's engine would) and write it to `options->compiled_fd` (a private file crslab
 * then seals and renames into its build cache, where a later load finds it): a lab's first run
 * then compiles nothing in the worker its neighbours share. No board, store or watchdog: an engine of its own, deleted before it returns (the process
 * holds nothing of wasmtime's afterwards but its loaded library). Returns 0; else -1 with `error`
 * (`error_size` bytes) saying why. */
int crs_fw_wasm_compile(const crs_wasm_options *options, char *error, size_t error_size);
/* Free the firmware's store (board->firmware is NULL afterwards); its compiled module is kept while
 * no more than CRS_WASM_IDLE_MODULES modules no board uses are newer. */
void crs_fw_wasm_unload(crs_board *board);
/* The compiled modules this process holds now (one per distinct module_key in use, and up to
 * CRS_WASM_IDLE_MODULES no board uses). */
int32_t crs_fw_wasm_module_count(void);
/* 1 when this process holds the compiled module of `module_key` now (a load of it reads no file). */
int32_t crs_fw_wasm_module_held(const char *module_key);
/* How many boards share the compiled module of board's firmware (0: none loaded). */
int32_t crs_fw_wasm_module_refs(const crs_board *board);
/* The firmware's memory: its first byte, and its size in *size (0 when none is loaded). */
uint8_t *crs_fw_wasm_memory(crs_board *board, uint64_t *size);
/* The address in the firmware's memory of the variable the module exports as `name` (the build
 * exports every global of the lab file that has one), or 0. */
uint32_t crs_fw_wasm_variable(crs_board *board, const char *name);

#endif
