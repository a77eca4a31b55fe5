/* crslab host stand-in for F28335Serial.h of the Gen B "me446 starter" framework (C2000Ware,
 * no RTOS): the serial port and the device types. Gen B lab files define PI, TWOPI, HALFPI,
 * GRAV and `int UARTprint` themselves; the idle loop runs printing() when UARTprint is 1. */
#ifndef CRSLAB_F28335SERIAL_H
#define CRSLAB_F28335SERIAL_H

#include "DSP2833x_Device.h"
#include "crslab_serial.h"

typedef struct crs_serial_port serialSCIA_t;
extern serialSCIA_t SerialA; /* real buffer: 136 bytes */

/* The framework's entry, which 2024-style labs call from their own main(). */
void mains_code(void);

#endif
