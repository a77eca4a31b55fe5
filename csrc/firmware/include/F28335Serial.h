/* crslab host stand-in for F28335Serial.h of the Gen B "me446 starter" framework (C2000Ware,
 * no RTOS): the clocks, the three serial ports and their functions, and (through buffer.h) the
 * device header. Gen B lab files define PI, TWOPI, HALFPI, GRAV and `int UARTprint` themselves;
 * the idle loop runs printing() when UARTprint is 1. Only SerialA is emulated (serial_printf to
 * Tera Term); the other ports carry the Simulink and MATLAB protocols inside the board, so their
 * objects and functions are declared for the lab to name, not defined. */
#ifndef CRSLAB_F28335SERIAL_H
#define CRSLAB_F28335SERIAL_H

#include "buffer.h"
#include "crslab_serial.h"

/* Clocks in kHz and Hz, with the framework's settings (PLL 0xA on a 30 MHz oscillator: 150 MHz;
 * high-speed peripheral clock /2, low-speed /4) */
#define PLL 0xA
#define OSCCLK_KHZ 30000L
#define SYSCLKOUT_KHZ (OSCCLK_KHZ * PLL / 2)
#define HISPCLK_KHZ (SYSCLKOUT_KHZ / 2)
#define HISPCLK_HZ (HISPCLK_KHZ * 1000L)
#define LSPCLK_KHZ (SYSCLKOUT_KHZ / 4)
#define LSPCLK_HZ (LSPCLK_KHZ * 1000L)

/* The three ports share crslab's serial port object (`struct serialSCIA_s` names it too). */
#define serialSCIA_s crs_serial_port
#define serialSCIB_s crs_serial_port
#define serialSCIC_s crs_serial_port
typedef struct crs_serial_port serialSCIA_t;
typedef struct crs_serial_port serialSCIB_t;
typedef struct crs_serial_port serialSCIC_t;
extern serialSCIA_t SerialA; /* real buffer: 136 bytes */
extern serialSCIB_t SerialB; /* the Simulink link: declared only */
extern serialSCIC_t SerialC; /* the MATLAB link: declared only */

uint16_t init_serialSCIA(serialSCIA_t *s, Uint32 baud);
void uninit_serialSCIA(serialSCIA_t *s);
uint16_t serial_sendSCIA(serialSCIA_t *s, char *data, Uint16 len);
uint16_t init_serialSCIB(serialSCIB_t *s, Uint32 baud);
void uninit_serialSCIB(serialSCIB_t *s);
uint16_t serial_sendSCIB(serialSCIB_t *s, char *data, Uint16 len);
uint16_t init_serialSCIC(serialSCIC_t *s, Uint32 baud);
void uninit_serialSCIC(serialSCIC_t *s);
uint16_t serial_sendSCIC(serialSCIC_t *s, char *data, Uint16 len);
void TXAINT_data_sent(void);
void TXBINT_data_sent(void);
void TXCINT_data_sent(void);
void RXAINT_recv_ready(void);
void RXBINT_recv_ready(void);
void RXCINT_recv_ready(void);

/* The framework's entry, which 2024-style labs call from their own main(). */
void mains_code(void);

#endif
