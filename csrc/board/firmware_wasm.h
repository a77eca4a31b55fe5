/* The WebAssembly firmware's port (firmware_wasm.c): the firmware is a WebAssembly module (built by
 * crslab/lab/firmware.py) that wasmtime runs inside the worker, on its own memory, with the board's
 * few functions as its only imports. Compiled into crslab._core; read by cffi with sim.h. */
#ifndef CRSLAB_FIRMWARE_WASM_H
#define CRSLAB_FIRMWARE_WASM_H

#include <stddef.h>
#include <stdint.h>

#include "sim.h"

typedef struct {
    const char *libwasmtime;      /* path of the wasmtime C library (the `wasmtime` package's) */
    const uint8_t *wasm;          /* the firmware module's bytes */
    uint64_t wasm_len;
    uint64_t memory_bytes;        /* the most memory the firmware may have, bytes */
    uint64_t stack_bytes;         /* the most native stack its calls may use, bytes */
    const char *compiled_path;    /* where wasmtime's compilation of this module for this board is
                                     kept between runs (crslab's build cache); NULL: compile anew */
} crs_wasm_options;

/* Load the firmware for sim->generation, run its constructors (phase CRS_PHASE_LOADING) and point
 * sim->fw at its variables. Returns 0; else CRS_RUN_TRAPPED with sim->trap saying why
 * (CRS_FW_TRAP_LOAD: the module is not a firmware this board can run, or it asks for more than the
 * board gives; any other kind: a constructor stopped). */
int crs_fw_wasm_load(crs_sim *sim, const crs_wasm_options *options);
/* Load wasmtime's C library (`libwasmtime`, its path) into this process now, so that the processes
 * it forks later start with it loaded (crslab's fork servers); 0, or -1 when it cannot be loaded. */
int crs_fw_wasm_preload(const char *libwasmtime);
/* Free the firmware (sim->firmware is NULL afterwards). */
void crs_fw_wasm_unload(crs_sim *sim);
/* The firmware's memory: its first byte, and its size in *size (0 when none is loaded). */
uint8_t *crs_fw_wasm_memory(crs_sim *sim, uint64_t *size);
/* The address in the firmware's memory of the variable the module exports as `name` (the build
 * exports every global of the lab file that has one), or 0. */
uint32_t crs_fw_wasm_variable(crs_sim *sim, const char *name);
/* Stop the firmware's running call at its next loop iteration or call (it traps with
 * CRS_FW_TRAP_INTERRUPT): async-signal-safe. */
void crs_fw_wasm_interrupt(void);
/* Make signal `signo` call crs_fw_wasm_interrupt (the crslab process sends it at a deadline);
 * 0, or -1 when the handler cannot be installed. */
int crs_fw_wasm_interrupt_on(int signo);

#endif
