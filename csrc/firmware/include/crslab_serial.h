/* crslab: the one serial port both framework generations print through (SCI-A to Tera Term).
 * serial_printf formats as the lab's framework generation does (Gen A: the course's small
 * printf, which truncates; Gen B: TI's rounding vsprintf) and queues the characters on the
 * board's serial line (csrc/firmware/serial_format.h, csrc/board/serial_line.h). Returns how many
 * characters the transmit ring took. No printf format attribute: Gen A knows %b, C does not. */
#ifndef CRSLAB_SERIAL_H
#define CRSLAB_SERIAL_H

#include <stdint.h>

struct crs_serial_port {
    uint32_t id;
};
int serial_printf(struct crs_serial_port *port, char *fmt, ...);

#endif
