/* SerialB's receiver: the course's Simulink model's 5 ms packets (simulink_link.c). Internal to the
 * board; not read by cffi. */
#ifndef CRSLAB_SIMULINK_LINK_H
#define CRSLAB_SIMULINK_LINK_H

#include <stdint.h>

#include "board.h"

/* One byte arriving on SerialB (the receive interrupt), its last bit at line time `now`
 * (csrc/board/serial_line.h). */
void crs_simulink_receive(crs_board *board, int64_t now, uint8_t byte);

/* What a Simulink_PlotVar is sent as: the C long of 10000 * value, multiplied in single precision
 * and truncated toward zero. Beyond the long's range C leaves it undefined: saturated here, as the
 * C28x FPU's conversion does; a NaN is sent as 0 (crslab's choice). */
int32_t crs_simulink_scaled(float value);

#endif
