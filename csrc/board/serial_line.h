/* The board's serial lines (docs/framework.md section 6): bytes queued into a port's transmit ring move
 * into the SCI's hardware FIFO and shift register, and leave one after another at the baud rate.
 * Every port has one (SerialA's carries serial_printf to Tera Term; SerialB's and SerialC's the
 * replies to the host, csrc/board/host_ports.h), and the host's bytes come in on a line of the same
 * kind. Internal to the board; not read by cffi.
 *
 * All of a tick's serial_printf calls happen at the start of its millisecond; the interrupt moves
 * characters from the ring into the FIFO only after a call has finished queueing (and then at
 * once), so one call finds the ring holding everything queued and not yet moved out of it. What
 * does not fit is dropped, the line ends included. A character belongs to the tick during whose
 * millisecond its last bit leaves. */
#ifndef CRSLAB_SERIAL_LINE_H
#define CRSLAB_SERIAL_LINE_H

#include <stdint.h>

#include "board.h"

/* The most characters that can leave a line in one tick (11 or 12 at 115200 baud). */
enum { CRS_LINE_MAX_CHARS_PER_TICK = 12 };

/* Line time units per tick and per character (see crs_serial_line). */
int64_t crs_line_units_per_tick(void);
int64_t crs_line_units_per_char(void);
/* The tick during whose millisecond line time `t` (> 0) falls: ((k ms, k+1 ms] is tick k's). */
int64_t crs_line_tick(int64_t t);

/* Queue n characters at the start of tick `tick` onto `line`, whose transmit ring holds
 * ring_chars; returns how many the ring took (the first ones; the rest are dropped). */
uint32_t crs_line_queue(crs_serial_line *line, uint32_t ring_chars, int64_t tick, const char *data,
                        uint32_t n);
/* The same at line time `start` (the first character starts leaving then, or after what is
 * queued). The caller has taken every character that left before `start`. */
uint32_t crs_line_queue_at(crs_serial_line *line, uint32_t ring_chars, int64_t start, const char *data,
                           uint32_t n);

/* Take the characters that fully leave `line` during tick `tick` into dst (room for
 * CRS_LINE_MAX_CHARS_PER_TICK); returns how many. */
uint32_t crs_line_take(crs_serial_line *line, int64_t tick, char *dst);
/* Take the characters that have fully left by line time `until`, at most `room`, into dst. */
uint32_t crs_line_take_until(crs_serial_line *line, int64_t until, char *dst, uint32_t room);

/* SerialA: move the characters that fully leave during tick `tick` from sh's line to
 * sh->serial, marked with that tick. */
void crs_line_send(crs_shared *sh, int64_t tick);

#endif
