/* For debuggers (crslab debug, csrc/board/debug.c; the native board only): the tick being run,
 * which gdb shows; the check at the start of every tick (1: stop for --break-when); the function
 * gdb breaks on when crslab asks for a stop (it then stops at the next lab() call); floating-point
 * traps on (1) or off (0). Read by cffi (ABI mode) with board.h. */
#ifndef CRSLAB_DEBUG_H
#define CRSLAB_DEBUG_H

#include <stdint.h>

#include "board.h"

extern volatile int64_t crs_tick;
int crs_debug_tick_begins(crs_board *board);
void crs_debug_break(int64_t tick);
void crs_debug_fp_traps(int on);

#endif
