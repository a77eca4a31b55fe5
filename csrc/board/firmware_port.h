/* The board's side of the firmware (csrc/firmware: the lab file linked with the framework's
 * stand-ins): how a tick calls it, and what its serial_printf hands the board. Internal to the
 * board; not read by cffi.
 *
 * One implementation per build of the board: firmware_wasm.c (crslab's default: the firmware is a
 * WebAssembly module that wasmtime runs inside this process, compiled into crslab._core) and
 * firmware_native.c (the firmware linked natively into one shared object with the board: crslab
 * debug, --sanitize, --native). Both set board->fw (where the firmware's variables are), count what
 * each lab() call costs and mark the phase the board is in for the watchdog. */
#ifndef CRSLAB_FIRMWARE_PORT_H
#define CRSLAB_FIRMWARE_PORT_H

#include <stdint.h>

#include "board.h"

/* lab() once, with this tick's encoder angles and the last tick's safety flag; the torques land
 * in board->fw.tau. *print is 1 when the lab asked for printing(). Returns 0, or CRS_RUN_TRAPPED
 * with board->trap filled. */
int crs_fw_call_lab(crs_board *board, int32_t *print);
/* printing() once: 0, or CRS_RUN_TRAPPED. */
int crs_fw_call_printing(crs_board *board);
/* At the start of every tick: 1 to end the chunk before it (crslab debug's --break-when holds;
 * only a native firmware runs under a debugger), else 0. */
int crs_fw_tick_begins(crs_board *board);

/* Before and after each chunk of ticks (crs_board_run): the WebAssembly port arms this board's
 * store and its watchdog (interrupts per store); the native port does nothing. */
void crs_fw_chunk_begins(crs_board *board);
void crs_fw_chunk_ends(crs_board *board);
/* After each tick: 1 when the chunk has had its share of a worker its boards share (the
 * WebAssembly port's crs_wasm_options.chunk_ns; the chunk ends, CRS_RUN_CUT), else 0. */
int crs_fw_chunk_over(crs_board *board);

/* What the firmware's serial_printf sends (firmware.h: crs_board_serial_send): `formatted`
 * characters, the first of them at `chars` (`available` of them readable). Queues them on SerialA's
 * line and returns how many the transmit ring took; a line that overflows the generation's
 * format buffer is noted (board->overflow_tick) instead and nothing is queued. */
int32_t crs_board_serial_out(crs_board *board, const char *chars, uint32_t available, uint32_t formatted);

/* Count what one lab() call cost (in board->config.cost_unit) into the run's totals, its maximum and the
 * calls over board->budget (the first few ticks of which are kept). */
void crs_board_lab_cost(crs_board *board, int64_t cost);

#endif
