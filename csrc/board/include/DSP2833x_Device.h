/* crslab host stand-in for TI's DSP2833x_Device.h: integer types, interrupt and protected-
 * register macros (no-ops on a host), and the GPIO data registers the labs toggle LEDs with. */
#ifndef CRSLAB_DSP2833X_DEVICE_H
#define CRSLAB_DSP2833X_DEVICE_H

#include <stdint.h>

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

#endif
