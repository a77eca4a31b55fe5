/* crslab host stand-in for TI's DSP2833x_Device.h: the device selection, integer types,
 * interrupt and protected-register macros (no-ops on a host), the interrupt mask and bit
 * constants, the GPIO data registers the labs toggle LEDs with, and the other peripherals' names
 * (crslab_peripherals.h). Gen B's copy (C2000Ware 4.01, as the course ships it) also includes
 * <stdbool.h>, <stddef.h> and <stdint.h>, so a Gen B lab uses bool, size_t and uint16_t without
 * including them; Gen A's older copy does not (coecsl.h says which generation includes it). */
#ifndef CRSLAB_DSP2833X_DEVICE_H
#define CRSLAB_DSP2833X_DEVICE_H

#include <stdint.h> /* the stand-ins' own types, both generations */
#ifndef CRSLAB_FRAMEWORK_GEN_A
#include <stdbool.h>
#include <stddef.h>
#endif

#define TARGET 1
#define DSP28_28335 TARGET
#define DSP28_28334 0
#define DSP28_28333 0
#define DSP28_28332 0

/* TI compiler keywords a lab may write; nothing on a host */
#ifndef __interrupt
#define __interrupt
#endif
#ifndef cregister
#define cregister
#endif
extern volatile unsigned int IFR; /* the CPU's interrupt flag and enable registers */
extern volatile unsigned int IER;

#define M_INT1 0x0001
#define M_INT2 0x0002
#define M_INT3 0x0004
#define M_INT4 0x0008
#define M_INT5 0x0010
#define M_INT6 0x0020
#define M_INT7 0x0040
#define M_INT8 0x0080
#define M_INT9 0x0100
#define M_INT10 0x0200
#define M_INT11 0x0400
#define M_INT12 0x0800
#define M_INT13 0x1000
#define M_INT14 0x2000
#define M_DLOG 0x4000
#define M_RTOS 0x8000

#define BIT0 0x0001
#define BIT1 0x0002
#define BIT2 0x0004
#define BIT3 0x0008
#define BIT4 0x0010
#define BIT5 0x0020
#define BIT6 0x0040
#define BIT7 0x0080
#define BIT8 0x0100
#define BIT9 0x0200
#define BIT10 0x0400
#define BIT11 0x0800
#define BIT12 0x1000
#define BIT13 0x2000
#define BIT14 0x4000
#define BIT15 0x8000

/* the F28335's peripherals, all present */
#define DSP28_EPWM1 1
#define DSP28_EPWM2 1
#define DSP28_EPWM3 1
#define DSP28_EPWM4 1
#define DSP28_EPWM5 1
#define DSP28_EPWM6 1
#define DSP28_ECAP1 1
#define DSP28_ECAP2 1
#define DSP28_ECAP3 1
#define DSP28_ECAP4 1
#define DSP28_ECAP5 1
#define DSP28_ECAP6 1
#define DSP28_EQEP1 1
#define DSP28_EQEP2 1
#define DSP28_ECANA 1
#define DSP28_ECANB 1
#define DSP28_MCBSPA 1
#define DSP28_MCBSPB 1
#define DSP28_SPIA 1
#define DSP28_SCIA 1
#define DSP28_SCIB 1
#define DSP28_SCIC 1
#define DSP28_I2CA 1

#ifndef DSP28_DATA_TYPES
#define DSP28_DATA_TYPES
typedef int16_t int16;
typedef int32_t int32;
typedef int64_t int64;
typedef uint16_t Uint16;
typedef uint32_t Uint32;
typedef uint64_t Uint64;
typedef float float32;
typedef long double float64;
#endif

#define EALLOW ((void)0)
#define EDIS ((void)0)
#define EINT ((void)0)
#define DINT ((void)0)
#define ERTM ((void)0)
#define DRTM ((void)0)
#define ESTOP0 ((void)0)

/* GPIO32..GPIO63 as one 32-bit register, one bit each (GPIO34: control-card LED; GPIO60: the
 * e-stop box LED, active low). SET, CLEAR and TOGGLE are write-only on the chip: the board
 * applies them to GPBDAT after every lab() call and clears them. */
struct CRS_GPB_BITS {
    uint32_t GPIO32 : 1, GPIO33 : 1, GPIO34 : 1, GPIO35 : 1, GPIO36 : 1, GPIO37 : 1, GPIO38 : 1,
        GPIO39 : 1, GPIO40 : 1, GPIO41 : 1, GPIO42 : 1, GPIO43 : 1, GPIO44 : 1, GPIO45 : 1,
        GPIO46 : 1, GPIO47 : 1, GPIO48 : 1, GPIO49 : 1, GPIO50 : 1, GPIO51 : 1, GPIO52 : 1,
        GPIO53 : 1, GPIO54 : 1, GPIO55 : 1, GPIO56 : 1, GPIO57 : 1, GPIO58 : 1, GPIO59 : 1,
        GPIO60 : 1, GPIO61 : 1, GPIO62 : 1, GPIO63 : 1;
};
union CRS_GPB_REG {
    uint32_t all;
    struct CRS_GPB_BITS bit;
};
struct CRS_GPA_BITS {
    uint32_t GPIO0 : 1, GPIO1 : 1, GPIO2 : 1, GPIO3 : 1, GPIO4 : 1, GPIO5 : 1, GPIO6 : 1,
        GPIO7 : 1, GPIO8 : 1, GPIO9 : 1, GPIO10 : 1, GPIO11 : 1, GPIO12 : 1, GPIO13 : 1,
        GPIO14 : 1, GPIO15 : 1, GPIO16 : 1, GPIO17 : 1, GPIO18 : 1, GPIO19 : 1, GPIO20 : 1,
        GPIO21 : 1, GPIO22 : 1, GPIO23 : 1, GPIO24 : 1, GPIO25 : 1, GPIO26 : 1, GPIO27 : 1,
        GPIO28 : 1, GPIO29 : 1, GPIO30 : 1, GPIO31 : 1;
};
union CRS_GPA_REG {
    uint32_t all;
    struct CRS_GPA_BITS bit;
};
struct GPIO_DATA_REGS {
    union CRS_GPA_REG GPADAT, GPASET, GPACLEAR, GPATOGGLE;
    union CRS_GPB_REG GPBDAT, GPBSET, GPBCLEAR, GPBTOGGLE;
};
extern volatile struct GPIO_DATA_REGS GpioDataRegs;

#include "crslab_peripherals.h"

#endif
