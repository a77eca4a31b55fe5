/* What a debugger sees and stops on (crslab debug, docs/debugging.md). Nothing here changes
 * what a lab computes: the tick is copied where gdb can read it, a condition is evaluated
 * between ticks, and floating-point traps only turn a NaN- or Inf-making operation of lab()
 * into a stop at its line. */
#define _GNU_SOURCE /* feenableexcept */

#include <fenv.h>
#include <stddef.h>

#include "debug.h"

volatile int64_t crs_tick = -1;

/* Defined by a lab built with crslab debug --break-when (crslab/lab/build.py compiles the lab
 * file and this function as one translation unit): the condition, over the lab's globals and
 * the error flag the coming lab() call receives. */
extern int crs_debug_condition(int error) __attribute__((weak));

int crs_debug_tick_begins(crs_board *board)
{
    crs_tick = board->tick;
    if (!board->config.debug.break_when || crs_debug_condition == NULL) return 0;
    if (board->tick < board->config.startup_ticks || !(board->fw.symbols & CRS_LAB_HAS_LAB)) {
        return 0; /* no lab() call this tick */
    }
    if (!crs_debug_condition(board->safety_flag)) return 0;
    board->config.debug.break_when = 0; /* once: the debugger takes over from here */
    return 1;
}

void crs_debug_break(int64_t tick) { crs_tick = tick; }

void crs_debug_fp_traps(int on)
{
#if defined(__GLIBC__)
    const int kinds = FE_INVALID | FE_DIVBYZERO | FE_OVERFLOW;
    if (on) {
        feclearexcept(kinds); /* a flag left raised would trap at once */
        feenableexcept(kinds);
    } else {
        fedisableexcept(kinds);
    }
#else
    (void)on; /* no trap control outside glibc: --strict still names the tick */
#endif
}
