/* Internal to the board: the lab file's symbols (weak: a lab may lack some) and the hooks the
 * loop uses to run printing and update the LEDs. Not read by cffi. */
#ifndef CRSLAB_BOARD_H
#define CRSLAB_BOARD_H

#include <stdint.h>

#include "sim.h"

/* Defined by the lab file. */
extern void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
                float *tau3, int error) __attribute__((weak));
extern void printing(void) __attribute__((weak));
extern int UARTprint __attribute__((weak));
extern float offset_Enc2_rad __attribute__((weak));
extern float offset_Enc3_rad __attribute__((weak));
extern float Simulink_PlotVar1 __attribute__((weak));
extern float Simulink_PlotVar2 __attribute__((weak));
extern float Simulink_PlotVar3 __attribute__((weak));
extern float Simulink_PlotVar4 __attribute__((weak));

/* The framework's own globals: what Simulink sent (csrc/sim/simulink_inputs.c) and Gen A's
 * matlabLock (csrc/sim/matlab_link.c). */
extern int SIMU_Var1_fromSIMU_16bit, SIMU_Var2_fromSIMU_16bit, SIMU_Var3_fromSIMU_16bit,
    SIMU_Var4_fromSIMU_16bit, SIMU_Var5_fromSIMU_16bit, SIMU_Var6_fromSIMU_16bit,
    SIMU_Var7_fromSIMU_16bit;
extern float matlabLock;

/* The board the serial port writes into (set by crs_sim_run). */
void crs_board_attach(crs_sim *sim);
/* The framework objects as at power-up: LEDs at CRS_LEDS_AT_START, nothing posted. */
void crs_board_reset(void);
/* After lab(): run printing() once if it was requested this tick (SWI post or UARTprint). */
void crs_board_after_lab(crs_sim *sim);
/* Apply the GPIO SET/CLEAR/TOGGLE writes of this tick; returns the LED bits. */
uint32_t crs_board_update_gpio(void);
/* CLOCK_MONOTONIC in ns. */
int64_t crs_now_ns(void);

#endif
