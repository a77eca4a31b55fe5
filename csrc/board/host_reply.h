/* The board's replies on the host ports, as the framework's command code queues them: into the
 * port's transmit ring, which leaves at the baud rate (host_ports.h). Called by the receivers
 * (matlab_link.c, simulink_link.c); internal to the board; not read by cffi. */
#ifndef CRSLAB_HOST_REPLY_H
#define CRSLAB_HOST_REPLY_H

#include <stdint.h>

#include "board.h"

/* Queue a reply on host port `port` (CRS_HOST_PORT_*) at line time `now`; what its transmit ring
 * cannot take is dropped and counted. */
void crs_host_reply(crs_board *board, int port, int64_t now, const char *data, uint32_t n);

#endif
