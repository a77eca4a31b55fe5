/* The board's serial transmit line (crs-facts section 7): serial_printf queues characters into the
 * transmit ring, the TX interrupt moves them into the SCI's hardware FIFO and shift register, and
 * they leave one after another at the baud rate. Internal to the board; not read by cffi.
 *
 * All of a tick's serial_printf calls happen at the start of its millisecond; the interrupt moves
 * characters from the ring into the FIFO only after a call has finished queueing (and then at
 * once), so one call finds the ring holding everything queued and not yet moved out of it. What
 * does not fit is dropped, the line ends included. A character belongs to the tick during whose
 * millisecond its last bit leaves. */
#ifndef CRSLAB_SERIAL_LINE_H
#define CRSLAB_SERIAL_LINE_H

#include <stdint.h>

#include "sim.h"

/* Line time units per tick and per character (see crs_serial_line). */
int64_t crs_line_units_per_tick(void);
int64_t crs_line_units_per_char(void);

/* Queue one serial_printf's n characters at tick `tick` into the line of sh, whose transmit ring
 * holds ring_chars; returns how many the ring took (the first ones; the rest are dropped). When it
 * took any, the call is recorded in sh's print marks (its tick and how many characters it has on
 * the line). */
uint32_t crs_line_queue(crs_shared *sh, uint32_t ring_chars, int64_t tick, const char *data, uint32_t n);

/* Move the characters that fully leave during tick `tick` from the line to sh->serial, marked
 * with that tick. */
void crs_line_send(crs_shared *sh, int64_t tick);

#endif
