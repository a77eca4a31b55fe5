/* Internal to the board: what the loop does with the framework's objects that live in the
 * firmware (the GPIO registers) and the clock. Not read by cffi. */
#ifndef CRSLAB_BOARD_IO_H
#define CRSLAB_BOARD_IO_H

#include <stdint.h>

#include "board.h"

/* Apply the GPIO SET/CLEAR/TOGGLE writes of this tick to the firmware's registers; returns the
 * LED bits (bit 0 GPIO34, bit 1 GPIO60). */
uint32_t crs_board_update_gpio(crs_board *board);
/* Before a firmware is loaded: 0 when board->generation is a row of generations.c that can run;
 * else CRS_RUN_TRAPPED, with board->trap (CRS_FW_TRAP_LOAD) saying which generation and why. The
 * board reads the row of board->generation only after this said 0. */
int crs_board_check_generation(crs_board *board);
/* CLOCK_MONOTONIC in ns. */
int64_t crs_now_ns(void);

#endif
