/* crslab: the one serial port both framework generations print through (SCI-A to Tera Term).
 * serial_printf formats like printf and appends the bytes to the board's transcript. */
#ifndef CRSLAB_SERIAL_H
#define CRSLAB_SERIAL_H

#include <stdint.h>

struct crs_serial_port {
    uint32_t id;
};
int serial_printf(struct crs_serial_port *port, char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

#endif
