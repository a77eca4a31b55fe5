/* The native firmware's port (firmware_native.c): the firmware linked into one shared object with
 * the board, for crslab debug, --sanitize and --native. Read by cffi (ABI mode, with board.h). */
#ifndef CRSLAB_FIRMWARE_NATIVE_H
#define CRSLAB_FIRMWARE_NATIVE_H

#include "board.h"

/* Start the firmware linked with this board for board->generation and point board->fw at its
 * variables; the board of this process is `board` from now on (serial_printf reaches it). Returns 0;
 * else CRS_RUN_TRAPPED with board->trap (CRS_FW_TRAP_LOAD) saying why: no row of generations.c has
 * that id, or its row cannot run. */
int crs_fw_native_attach(crs_board *board);

#endif
