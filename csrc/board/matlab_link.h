/* SerialC's receiver: the course's MATLAB variable protocol (matlab_link.c). Internal to the board;
 * not read by cffi. */
#ifndef CRSLAB_MATLAB_LINK_H
#define CRSLAB_MATLAB_LINK_H

#include <stdint.h>

#include "board.h"

/* One byte arriving on SerialC (the receive interrupt), its last bit at line time `now`
 * (csrc/board/serial_line.h). */
void crs_matlab_receive(crs_board *board, int64_t now, uint8_t byte);

#endif
