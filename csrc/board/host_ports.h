/* The host ports: SerialB (the course's Simulink model) and SerialC (its MATLAB scripts), as the
 * framework's receive interrupts and command code handle them (docs/framework.md section 8; the
 * bytes in docs/host-tools.md, "The protocols byte by byte"). Internal to the board; not read by cffi.
 *
 * Time: what the host sent between two chunks goes onto the port's receive line at the start of
 * the next tick to run and arrives at the baud rate (11.52 bytes per ms). A byte whose last bit
 * arrives during tick k's millisecond is received at that moment of line time, after tick k's
 * lab() and before tick k+1's, like every other change from outside (never inside lab()); what it
 * makes the board send is queued then into the port's transmit ring and leaves at the baud rate
 * right away (or after what is still on the line); what the ring cannot take is dropped, as on the
 * board. */
#ifndef CRSLAB_HOST_PORTS_H
#define CRSLAB_HOST_PORTS_H

#include <stdint.h>

#include "board.h"

/* The ports' work for tick `tick`, after its lab(): take the inbox onto the receive lines, receive
 * what arrives during the tick, answer, and move what leaves during the tick to out[]. */
void crs_host_ports_tick(crs_board *board, int64_t tick);

/* 1 when a port's out[] is more than half full (the reader should take it). */
int crs_host_ports_full(const crs_shared *sh);

#endif
