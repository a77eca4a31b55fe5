/* crslab host stand-in for coecsl.h of the Gen A "CRSRobot" framework (DSP/BIOS era):
 * constants, the serial port, the printing SWI, and the device registers.
 * PI, TWOPI, HALFPI and GRAV use the exact token strings of the real header, so a lab that also
 * #defines them (as Gen B files do) gets an identical, silent redefinition. */
#ifndef CRSLAB_COECSL_H
#define CRSLAB_COECSL_H

#define CRSLAB_FRAMEWORK_GEN_A 1 /* its older DSP2833x_Device.h: no <stdbool.h>, <stddef.h> */
#include "DSP2833x_Device.h"
#include "crslab_serial.h"
#include "tistdtypes.h"

#include <stdarg.h>

#define PI 3.1415926535897932384626433832795
#define TWOPI 6.283185307179586476925286766559
#define HALFPI 1.5707963267948966192313216916398
#define GRAV 9.81

/* The serial driver (28335_serial.h, which coecsl.h reaches). Only SerialA is emulated
 * (serial_printf to Tera Term); SerialB and SerialC and the driver's other functions are
 * declared for the lab to name, not defined. `struct serial_s` names the port too. */
#define serial_s crs_serial_port
typedef struct crs_serial_port serial_t;
typedef int err_t;
extern serial_t SerialA; /* real buffer: 2048 bytes */
extern serial_t SerialB;
extern serial_t SerialC;
err_t init_serial(serial_t *s, Uint32 baud, void (*got_func)(serial_t *s, char data));
void uninit_serial(serial_t *s);
Uint16 serial_send(serial_t *s, char *data, Uint16 len);
void UART_LCDPrintfLine(unsigned char line, char *format, ...);
void UART_LCDvPrintfLine(unsigned char line, char *format, va_list ap);

/* DSP/BIOS software interrupt: SWI_post(&SWI_printf) makes the framework run printing() once,
 * after lab() returns; several posts in one tick run it once. */
typedef struct {
    int posted;
} SWI_Obj;
typedef SWI_Obj *SWI_Handle;
extern SWI_Obj SWI_printf;
void SWI_post(SWI_Handle swi);

#endif
